r"""Smoothing the force histories: least-squares polynomials and a smoothing spline.

(Formerly ``pipeline.fit``, a name now given to the fitting of contact parameters,
:mod:`pipeline.fit`; the old imports ``from pipeline.fit import fit_window`` still work.)

The seed paper (Ciornei et al. 2017, doi:10.1051/matecconf/201711207005) fitted the
measured :math:`F_n(t)`, :math:`F_t(t)` with 4th-degree polynomials and integrated them into
percussions. Raw power-basis coefficients of microsecond times are hopelessly
ill-conditioned (a Vandermonde matrix of :math:`t \sim 10^{-3}` s, :math:`t^4 \sim 10^{-12}`),
so every polynomial here lives on the scaled domain

.. math::

    x = \frac{2t - (t_s + t_e)}{t_e - t_s} \in [-1, 1], \qquad
    F(t) = \sum_{k=0}^{d} c_k P_k(x),

with :math:`P_k` the Legendre polynomials, solved by a QR factorisation of the design
matrix (never the normal equations). The coefficients ``coef`` are in newtons; the curve is
also available as a :class:`numpy.polynomial.Legendre` with ``domain=[t_s, t_e]``
(:attr:`PolyFit.poly`), which evaluates, differentiates and integrates exactly in time units.

**End constraints** :math:`F(t_s) = F(t_e) = 0` (the pulse starts and ends at zero force)
are imposed exactly by the factorisation :math:`F = (1 - x^2)\,q(x)` with
:math:`q = \sum_{k=0}^{d-2} b_k P_k`; the free coefficients :math:`b` are fitted and mapped
linearly (:math:`c = T b`) to the Legendre coefficients of degree :math:`d`, and the
covariance with them (:math:`C_c = T C_b T^\top`, rank :math:`d-1`).

**Covariance** :math:`C = \hat\sigma^2 (A^\top A)^{-1} = \hat\sigma^2 R^{-1}R^{-\top}`,
:math:`\hat\sigma^2 = \mathrm{SS_{res}}/(n - p)` for :math:`p` free coefficients.

**Structure in the residuals** (Wald–Wolfowitz runs test on the residual signs): for
:math:`n_+` positive and :math:`n_-` negative residuals (a zero counts as positive) the
number of runs :math:`R` of equal signs has, for independent residuals, mean
:math:`\mu = 1 + 2n_+n_-/n` and variance
:math:`2n_+n_-(2n_+n_- - n)/(n^2(n-1))`. A curve the polynomial misses leaves long runs of
one sign, so the fit is flagged ``poor`` (and a :class:`~pipeline.errors.PoorFitWarning`
issued) when :math:`z = (R - \mu)/\sqrt{\mathrm{var}} < -2.326` — a one-sided test at
level α = 0.01. On independent white noise it fires 1.0 % of the time; on the residuals of
a least-squares quartic fitted to white noise, which are slightly anti-correlated, less
often: 0.05 %, 0.45 %, 0.5 %, 0.7 % for n = 30, 100, 300, 1000 samples (20 000 Monte-Carlo
records each; checked in ``tests/test_smooth.py``). It is not run (``runs_z`` NaN, not
flagged) with fewer than 10 samples or residuals at rounding level (RMS below 10⁻⁹ of
the largest |F|: nothing left to model).

**Batches** (:func:`fit_polynomials_batch`): records sharing one time grid share the design
matrix, so one QR serves every right-hand side; coefficients, covariances, RMS, R² and the
runs test are computed as arrays, no Python loop over records. :func:`fit_polynomial` is
the batch of one.

**Smoothing spline** (:func:`fit_spline`): the cubic smoothing spline of
:func:`scipy.interpolate.make_smoothing_spline` with the penalty chosen by generalised
cross-validation (its ``lam=None``; Craven & Wahba 1979), fitted on the same scaled
domain, with an exact antiderivative.

References
----------
A. Wald, J. Wolfowitz, "On a test whether two samples are from the same population",
Ann. Math. Stat. 11:147 (1940), doi:10.1214/aoms/1177731909.
P. Craven, G. Wahba, "Smoothing noisy data with spline functions", Numer. Math. 31:377
(1979), doi:10.1007/BF01404567.
G. H. Golub, C. F. Van Loan, Matrix Computations, 4th ed., Johns Hopkins (2013), §5.3
(least squares by QR).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.polynomial import legendre as L
from scipy import linalg, special

if TYPE_CHECKING:
    from scipy import interpolate

from ._json import json_ready
from .errors import InputError, PoorFitWarning
from .record import channel

__all__ = [
    "noise_level",
    "PolyFit",
    "PolyFitBatch",
    "SplineFit",
    "WindowFits",
    "fit_polynomial",
    "fit_polynomials_batch",
    "fit_spline",
    "fit_window",
    "runs_test",
    "RUNS_ALPHA",
]

#: One-sided level of the runs test that flags structured residuals.
RUNS_ALPHA = 0.01
_RUNS_Z = float(special.ndtri(RUNS_ALPHA))  # −2.326
_RUNS_MIN_N = 10
_ROUNDING = 1e-9


# ------------------------------------------------------------------ helpers
def _scale(t, t_start, t_end):
    return (2.0 * np.asarray(t, dtype=float) - (t_start + t_end)) / (t_end - t_start)


def _domain(t, t_start, t_end):
    t = np.asarray(t, dtype=float)
    if t.ndim != 1 or t.size < 2:
        raise InputError(f"a fit needs a 1-D time grid of at least 2 samples, got shape {t.shape}")
    if not np.all(np.isfinite(t)):
        raise InputError("the time grid has NaN or infinite values")
    t_start = float(t.min()) if t_start is None else float(t_start)
    t_end = float(t.max()) if t_end is None else float(t_end)
    if not t_end > t_start:
        raise InputError(f"the fit window must have t_end > t_start, got [{t_start}, {t_end}] s")
    tol = 1e-9 * (t_end - t_start)
    if t.min() < t_start - tol or t.max() > t_end + tol:
        raise InputError(
            f"samples from {t.min()!r} s to {t.max()!r} s lie outside the fit window "
            f"[{t_start!r}, {t_end!r}] s; cut the record to the window first"
        )
    return t, t_start, t_end


def _constraint_map(degree: int, end_constraints: bool) -> np.ndarray:
    """T (p × q): Legendre coefficients of degree ``degree`` from the q free coefficients."""
    p = degree + 1
    if not end_constraints:
        return np.eye(p)
    one_minus_x2 = L.poly2leg([1.0, 0.0, -1.0])  # (2/3)(P0 − P2)
    q = degree - 1
    T = np.zeros((p, q))
    for k in range(q):
        e = np.zeros(k + 1)
        e[k] = 1.0
        col = L.legmul(one_minus_x2, e)
        T[: col.size, k] = col
    return T


def _design(x, degree, end_constraints):
    if end_constraints:
        return (1.0 - x * x)[:, None] * L.legvander(x, degree - 2)
    return L.legvander(x, degree)


def runs_test(residuals, *, axis=-1):
    """Wald–Wolfowitz runs test on the signs of residuals (vectorised).

    Parameters
    ----------
    residuals : array_like
        Residuals [any unit], the samples along ``axis`` in time order.

    Returns
    -------
    numpy.ndarray
        z = (R − μ)/√var [-] per series (see module notes); strongly negative z means
        fewer sign changes than independent residuals would give. NaN where a series has
        fewer than 10 samples or only one sign.
    """
    r = np.moveaxis(np.asarray(residuals, dtype=float), axis, -1)
    n = r.shape[-1]
    pos = r >= 0
    n_pos = pos.sum(axis=-1).astype(float)
    n_neg = n - n_pos
    runs = 1.0 + np.count_nonzero(pos[..., 1:] != pos[..., :-1], axis=-1)
    two = 2.0 * n_pos * n_neg
    mu = 1.0 + two / n
    var = two * (two - n) / (n * n * (n - 1.0)) if n > 1 else np.zeros_like(two)
    with np.errstate(invalid="ignore", divide="ignore"):
        z = (runs - mu) / np.sqrt(var)
    bad = (n_pos == 0) | (n_neg == 0) | (var <= 0) | (n < _RUNS_MIN_N)
    return np.where(bad, np.nan, z)


# ------------------------------------------------------------------ results
@dataclass(frozen=True, eq=False)
class PolyFit:
    """A least-squares polynomial F(t) on [t_start, t_end] (see the module notes).

    Attributes
    ----------
    coef : numpy.ndarray, shape (degree + 1,)
        Legendre coefficients c_k [N] in the scaled variable x ∈ [−1, 1].
    cov : numpy.ndarray, shape (degree + 1, degree + 1)
        Covariance of ``coef`` [N²] (singular with end constraints).
    t_start, t_end : float
        The domain [s]; x = −1 at t_start, +1 at t_end.
    degree : int
        Polynomial degree.
    end_constraints : bool
        Whether F(t_start) = F(t_end) = 0 was imposed.
    n : int
        Samples fitted.
    dof : int
        Residual degrees of freedom n − (free coefficients).
    rms : float
        Residual RMS √(SS_res/n) [N].
    sigma : float
        Residual standard deviation √(SS_res/dof) [N] (NaN when dof = 0).
    r2 : float
        Coefficient of determination 1 − SS_res/SS_tot [-].
    runs_z : float
        Runs-test statistic of the residual signs [-] (NaN when not run).
    poor : bool
        True when the residuals show structure the polynomial misses (runs_z < −2.326).
    """

    coef: np.ndarray
    cov: np.ndarray
    t_start: float
    t_end: float
    degree: int
    end_constraints: bool
    n: int
    dof: int
    rms: float
    sigma: float
    r2: float
    runs_z: float
    poor: bool

    @property
    def poly(self) -> L.Legendre:
        """The curve as a :class:`numpy.polynomial.Legendre` in time [s] → force [N]."""
        return L.Legendre(self.coef, domain=[self.t_start, self.t_end])

    def __call__(self, t):
        """F(t) [N]."""
        return L.legval(_scale(t, self.t_start, self.t_end), self.coef)

    def derivative(self, t, m: int = 1):
        """d^mF/dt^m at ``t`` [N/s^m]."""
        c = L.legder(self.coef, m, scl=2.0 / (self.t_end - self.t_start))
        return L.legval(_scale(t, self.t_start, self.t_end), c)

    def _integ_matrix(self, t):
        # row i: the linear map coef → ∫_{t_start}^{t_i} F dt
        x = _scale(t, self.t_start, self.t_end)
        half = 0.5 * (self.t_end - self.t_start)
        p = self.degree + 1
        M = np.empty((np.size(x), p))
        for k in range(p):
            e = np.zeros(p)
            e[k] = 1.0
            M[:, k] = np.ravel(L.legval(x, L.legint(e, lbnd=-1.0, scl=half)))
        return M

    def antiderivative(self, t):
        """Exact ∫_{t_start}^{t} F dt' [N·s] (the percussion of seed eq. 3)."""
        x = _scale(t, self.t_start, self.t_end)
        c = L.legint(self.coef, lbnd=-1.0, scl=0.5 * (self.t_end - self.t_start))
        return L.legval(x, c)

    def antiderivative_std(self, t):
        """Standard error of :meth:`antiderivative` from ``cov`` [N·s]."""
        M = self._integ_matrix(t)
        var = np.einsum("ij,jk,ik->i", M, self.cov, M)
        return np.sqrt(np.maximum(var, 0.0)).reshape(np.shape(t))

    def std(self, t):
        """Standard error of the fitted curve F(t) from ``cov`` [N]."""
        V = L.legvander(_scale(np.ravel(t), self.t_start, self.t_end), self.degree)
        var = np.einsum("ij,jk,ik->i", V, self.cov, V)
        return np.sqrt(np.maximum(var, 0.0)).reshape(np.shape(t))

    def summary(self) -> dict:
        """JSON-ready dict (units in key names; NaN → None)."""
        return json_ready(
            {
                "model": "polynomial (Legendre basis on the scaled window)",
                "degree": self.degree,
                "end_constraints": self.end_constraints,
                "t_start_s": self.t_start,
                "t_end_s": self.t_end,
                "coef_N": self.coef.tolist(),
                "coef_stderr_N": np.sqrt(np.maximum(np.diag(self.cov), 0.0)).tolist(),
                "n": self.n,
                "dof": self.dof,
                "rms_N": self.rms,
                "sigma_N": self.sigma,
                "r2": self.r2,
                "runs_z": self.runs_z,
                "poor": self.poor,
            }
        )


@dataclass(frozen=True, eq=False)
class PolyFitBatch:
    """Least-squares polynomials of many records sharing one time grid.

    Attributes as :class:`PolyFit`, with a leading record axis: ``coef`` (n_records,
    degree + 1) [N], ``cov`` (n_records, degree + 1, degree + 1) [N²], ``rms``, ``sigma``
    [N], ``r2``, ``runs_z`` [-] and ``poor`` (bool) of shape (n_records,). ``batch[i]`` is
    the :class:`PolyFit` of record i.
    """

    coef: np.ndarray
    cov: np.ndarray
    t_start: float
    t_end: float
    degree: int
    end_constraints: bool
    n: int
    dof: int
    rms: np.ndarray
    sigma: np.ndarray
    r2: np.ndarray
    runs_z: np.ndarray
    poor: np.ndarray

    def __len__(self):
        return self.coef.shape[0]

    def __getitem__(self, i) -> PolyFit:
        return PolyFit(
            coef=self.coef[i],
            cov=self.cov[i],
            t_start=self.t_start,
            t_end=self.t_end,
            degree=self.degree,
            end_constraints=self.end_constraints,
            n=self.n,
            dof=self.dof,
            rms=float(self.rms[i]),
            sigma=float(self.sigma[i]),
            r2=float(self.r2[i]),
            runs_z=float(self.runs_z[i]),
            poor=bool(self.poor[i]),
        )

    def __call__(self, t):
        """F(t) [N] of every record: shape (n_records, len(t))."""
        V = L.legvander(_scale(np.ravel(t), self.t_start, self.t_end), self.degree)
        return self.coef @ V.T

    def antiderivative(self, t):
        """Exact ∫_{t_start}^{t} F dt' [N·s] of every record: shape (n_records, len(t))."""
        c = L.legint(self.coef.T, lbnd=-1.0, scl=0.5 * (self.t_end - self.t_start), axis=0)
        V = L.legvander(_scale(np.ravel(t), self.t_start, self.t_end), self.degree + 1)
        return c.T @ V.T


# ------------------------------------------------------------------ fitting
def fit_polynomials_batch(
    t,
    F,
    *,
    degree: int = 4,
    end_constraints: bool = False,
    t_start: float | None = None,
    t_end: float | None = None,
    warn: bool = True,
) -> PolyFitBatch:
    """Least-squares polynomials of many records on one time grid: one QR for all.

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample instants shared by all records [s].
    F : array_like, shape (n_records, n) or (n,)
        Forces [N], one record per row.
    degree : int
        Polynomial degree (4: the seed paper's quartic).
    end_constraints : bool
        Impose F(t_start) = F(t_end) = 0 exactly (needs degree ≥ 2).
    t_start, t_end : float, optional
        The fit window [s] (default: the first and last sample). All samples must lie in
        it; with ``end_constraints`` the zeros are placed at these instants.
    warn : bool
        Issue one :class:`~pipeline.errors.PoorFitWarning` naming the records whose
        residuals show structure.

    Returns
    -------
    PolyFitBatch

    Raises
    ------
    InputError
        Bad degree, fewer samples than coefficients, samples outside the window,
        non-finite forces, or a force array not matching the time grid.
    """
    t, t_start, t_end = _domain(t, t_start, t_end)
    Y = np.asarray(F, dtype=float)
    if Y.ndim == 1:
        Y = Y[None, :]
    if Y.ndim != 2 or Y.shape[1] != t.size:
        raise InputError(f"forces of shape {np.shape(F)} do not match {t.size} time samples")
    if not np.all(np.isfinite(Y)):
        raise InputError("forces have NaN or infinite values; remove or repair those samples")
    degree = int(degree)
    if degree < (2 if end_constraints else 0):
        raise InputError(
            f"degree {degree} is too low"
            + (": end constraints need degree ≥ 2" if end_constraints else "")
        )
    T = _constraint_map(degree, end_constraints)
    q = T.shape[1]
    n = t.size
    if n < q:
        raise InputError(f"{n} samples cannot determine {q} coefficients; lower the degree")
    x = _scale(t, t_start, t_end)
    A = _design(x, degree, end_constraints)
    Q, R = np.linalg.qr(A)  # reduced QR: Q (n, q), R (q, q)
    b = linalg.solve_triangular(R, Q.T @ Y.T)  # (q, n_records)
    resid = Y - (A @ b).T  # (n_records, n)
    ss_res = np.einsum("ij,ij->i", resid, resid)
    ss_tot = np.einsum(
        "ij,ij->i", Y - Y.mean(axis=1, keepdims=True), Y - Y.mean(axis=1, keepdims=True)
    )
    dof = n - q
    with np.errstate(invalid="ignore", divide="ignore"):
        sigma2 = ss_res / dof if dof > 0 else np.full(ss_res.shape, np.nan)
        r2 = np.where(ss_tot > 0, 1.0 - ss_res / ss_tot, np.where(ss_res == 0, 1.0, np.nan))
    Rinv = linalg.solve_triangular(R, np.eye(q))
    G = T @ (Rinv @ Rinv.T) @ T.T  # (p, p): (AᵀA)⁻¹ mapped to Legendre coefficients
    cov = sigma2[:, None, None] * G[None, :, :]
    coef = (T @ b).T
    rms = np.sqrt(ss_res / n)
    z = runs_test(resid)
    scale = np.max(np.abs(Y), axis=1)
    z = np.where(rms <= _ROUNDING * scale, np.nan, z)
    poor = np.nan_to_num(z, nan=0.0) < _RUNS_Z
    if warn and poor.any():
        idx = np.flatnonzero(poor)
        which = (
            f"record {idx[0]}"
            if Y.shape[0] == 1
            else (f"{idx.size} of {Y.shape[0]} records (first: {idx[:5].tolist()})")
        )
        warnings.warn(
            f"degree-{degree} polynomial fit of {which}: the residuals show structure the "
            f"polynomial misses (runs test z = {np.nanmin(z[poor]):.2f} < {_RUNS_Z:.2f}, "
            f"one-sided α = {RUNS_ALPHA}); try a higher degree, end constraints or the "
            "smoothing spline",
            PoorFitWarning,
            stacklevel=3,
        )
    return PolyFitBatch(
        coef=coef,
        cov=cov,
        t_start=t_start,
        t_end=t_end,
        degree=degree,
        end_constraints=bool(end_constraints),
        n=n,
        dof=dof,
        rms=rms,
        sigma=np.sqrt(sigma2),
        r2=r2,
        runs_z=z,
        poor=poor,
    )


def fit_polynomial(
    t,
    F,
    *,
    degree: int = 4,
    end_constraints: bool = False,
    t_start: float | None = None,
    t_end: float | None = None,
    warn: bool = True,
) -> PolyFit:
    """Least-squares polynomial F(t) on a scaled domain (Legendre basis, QR).

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample instants [s].
    F : array_like, shape (n,)
        Force samples [N].
    degree : int
        Polynomial degree; 4 is the seed paper's choice.
    end_constraints : bool
        Impose F(t_start) = F(t_end) = 0 exactly (the factorisation (1 − x²)·q(x)).
    t_start, t_end : float, optional
        The fit window [s]; default the first and last sample.
    warn : bool
        Issue a :class:`~pipeline.errors.PoorFitWarning` when the residuals show structure.

    Returns
    -------
    PolyFit
        ``poor`` is True (and a warning was issued) when the runs test finds structure.

    Notes
    -----
    The batch of one: identical to ``fit_polynomials_batch(t, F[None], ...)[0]``.
    """
    F = np.asarray(F, dtype=float)
    if F.ndim != 1:
        raise InputError(
            f"fit_polynomial takes one record (1-D forces), got shape {F.shape}; "
            "use fit_polynomials_batch for many"
        )
    batch = fit_polynomials_batch(
        t,
        F[None, :],
        degree=degree,
        end_constraints=end_constraints,
        t_start=t_start,
        t_end=t_end,
        warn=False,
    )
    out = batch[0]
    if warn and out.poor:
        _warn_poor(out, "", stacklevel=3)
    return out


def _warn_poor(fit: PolyFit, what: str, stacklevel: int):
    """The PoorFitWarning of one fit; ``what`` names the channel ("" when unknown)."""
    warnings.warn(
        f"{what}degree-{fit.degree} polynomial fit: the residuals show structure the "
        f"polynomial misses (runs test z = {fit.runs_z:.2f} < {_RUNS_Z:.2f}, one-sided α = "
        f"{RUNS_ALPHA}; residual RMS {fit.rms:.4g} N); try a higher degree, end "
        "constraints or the smoothing spline",
        PoorFitWarning,
        stacklevel=stacklevel,
    )


@dataclass(frozen=True, eq=False)
class SplineFit:
    """A cubic smoothing spline F(t) on [t_start, t_end], penalty chosen by GCV.

    Attributes
    ----------
    spline : scipy.interpolate.BSpline
        The spline in the scaled variable x = (2t − t_start − t_end)/(t_end − t_start) → F [N].
    t_start, t_end : float
        The domain [s] (also the origin of :meth:`antiderivative`).
    n : int
        Samples fitted.
    rms : float
        Residual RMS [N].
    r2 : float
        Coefficient of determination [-].
    lam : float or None
        The smoothing parameter given, or None when GCV chose it.
    """

    spline: interpolate.BSpline
    t_start: float
    t_end: float
    n: int
    rms: float
    r2: float
    lam: float | None = None

    def __call__(self, t):
        """F(t) [N]."""
        return self.spline(_scale(t, self.t_start, self.t_end))

    def derivative(self, t, m: int = 1):
        """d^mF/dt^m [N/s^m]."""
        dxdt = 2.0 / (self.t_end - self.t_start)
        return self.spline.derivative(m)(_scale(t, self.t_start, self.t_end)) * dxdt**m

    def antiderivative(self, t):
        """Exact ∫_{t_start}^{t} F dt' of the spline [N·s] (extrapolated outside the samples)."""
        anti = self.spline.antiderivative()
        half = 0.5 * (self.t_end - self.t_start)
        return (anti(_scale(t, self.t_start, self.t_end)) - anti(-1.0)) * half

    def summary(self) -> dict:
        """JSON-ready dict (units in key names; NaN → None)."""
        return json_ready(
            {
                "model": "cubic smoothing spline (GCV)" if self.lam is None else "smoothing spline",
                "t_start_s": self.t_start,
                "t_end_s": self.t_end,
                "n": self.n,
                "rms_N": self.rms,
                "r2": self.r2,
            }
        )


def fit_spline(
    t, F, *, t_start: float | None = None, t_end: float | None = None, lam: float | None = None
) -> SplineFit:
    """Cubic smoothing spline of F(t) (:func:`scipy.interpolate.make_smoothing_spline`).

    Parameters
    ----------
    t : array_like, shape (n,), n ≥ 5
        Strictly increasing sample instants [s].
    F : array_like, shape (n,)
        Force samples [N].
    t_start, t_end : float, optional
        The domain [s] used to scale time and as the origin of the antiderivative; default
        the first and last sample.
    lam : float, optional
        Penalty on the scaled domain; default None: chosen by generalised cross-validation.

    Returns
    -------
    SplineFit

    References
    ----------
    P. Craven, G. Wahba, Numer. Math. 31:377 (1979), doi:10.1007/BF01404567.
    """
    t, t_start, t_end = _domain(t, t_start, t_end)
    F = np.asarray(F, dtype=float)
    if F.shape != t.shape:
        raise InputError(f"forces of shape {F.shape} do not match {t.size} time samples")
    if t.size < 5:
        raise InputError(f"a smoothing spline needs at least 5 samples, got {t.size}")
    if np.any(np.diff(t) <= 0):
        raise InputError("a smoothing spline needs strictly increasing time samples")
    if not np.all(np.isfinite(F)):
        raise InputError("forces have NaN or infinite values; remove or repair those samples")
    from scipy import interpolate  # 0.1–0.4 s of import: only where a spline is fitted

    x = _scale(t, t_start, t_end)
    spl = interpolate.make_smoothing_spline(x, F, lam=lam)
    res = F - spl(x)
    ss_res = float(res @ res)
    ss_tot = float(((F - F.mean()) ** 2).sum())
    return SplineFit(
        spline=spl,
        t_start=t_start,
        t_end=t_end,
        n=int(t.size),
        rms=float(np.sqrt(ss_res / t.size)),
        r2=1.0 - ss_res / ss_tot if ss_tot > 0 else 1.0,
        lam=lam,
    )


# ------------------------------------------------------------------ a window's channels
@dataclass(frozen=True, eq=False)
class WindowFits:
    """The fits of a contact window's force channels (None where a channel is absent).

    Attributes
    ----------
    Fn, Ft, Fy : PolyFit or SplineFit or None
        Fits of the normal, tangential and out-of-plane force [N] over the window.
    method : str
        ``"polynomial"`` or ``"spline"``.
    """

    Fn: PolyFit | SplineFit
    Ft: PolyFit | SplineFit | None = None
    Fy: PolyFit | SplineFit | None = None
    method: str = "polynomial"


def fit_window(
    window,
    *,
    method: str = "polynomial",
    degree: int = 4,
    end_constraints: bool = False,
    warn: bool = True,
) -> WindowFits:
    """Fit every force channel of a :class:`~pipeline.window.ContactWindow`.

    Parameters
    ----------
    window : pipeline.window.ContactWindow
        The window; its ``record`` (baseline removed) is fitted over [t_start, t_end],
        each channel on its own measured points (digitised records).
    method : {"polynomial", "spline"}
    degree, end_constraints, warn
        As in :func:`fit_polynomial` (ignored by the spline).

    Returns
    -------
    WindowFits
    """
    if method not in ("polynomial", "spline"):
        raise InputError(f"fit method {method!r} is unknown; use 'polynomial' or 'spline'")
    out = {}
    for name in ("Fn", "Ft", "Fy"):
        if name not in window.record:
            out[name] = None
            continue
        t, f = channel(window.record, name)
        if method == "spline":
            out[name] = fit_spline(t, f, t_start=window.t_start, t_end=window.t_end)
        else:
            out[name] = fit_polynomial(
                t,
                f,
                degree=degree,
                end_constraints=end_constraints,
                t_start=window.t_start,
                t_end=window.t_end,
                warn=False,
            )
            if warn and out[name].poor:
                _warn_poor(out[name], f"{name}: ", stacklevel=3)
    return WindowFits(method=method, **out)


def noise_level(window, fits, name) -> float:
    """Noise σ of channel ``name`` in the window [N], for the bootstrap.

    The window's baseline estimate where it made one (sensor records); else, for dense
    channels (≥ 50 samples), the robust second-difference estimate
    1.4826·median|Δ²F|/√6 (white noise of σ gives Δ²F of σ√6, the smooth pulse almost
    nothing); else (sparse, digitised) the RMS residual of the GCV smoothing spline,
    which follows the curve where a low-degree polynomial would leave its misfit in the
    residuals; with fewer than 5 samples the polynomial fit's residual standard deviation
    (NaN when the fit interpolates: no estimate).
    """
    sigma = float(window.noise.get(name, float("nan")))
    if np.isfinite(sigma):
        return sigma
    t, f = channel(window.record, name)
    if t.size >= 50:
        return float(1.4826 * np.median(np.abs(np.diff(f, 2))) / np.sqrt(6.0))
    if t.size >= 5:
        return float(fit_spline(t, f, t_start=window.t_start, t_end=window.t_end).rms)
    return float(getattr(fits, name).sigma)
