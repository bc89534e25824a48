r"""The least-squares engine every fit shares: global parameters → records → weighted residuals.

A fit has *global* parameters θ (what lmfit varies: E*, e or α, μ or μ = a + b·v_t0,
``kt_scale``, t0, the systematics ...) and, for each record, the *local* parameters of its
forward model (:data:`pipeline.fit.forward.PARAMS`). A :class:`Design` maps one to the other
(the identity for one record; shared and per-record parameters for a campaign). The
residual is :math:`r = (y - m(\theta))/\sigma`, all channels of all records concatenated,
then one row :math:`(\theta_k - \theta_{k,0})/u_k` per parameter known to a standard
uncertainty :math:`u_k` (a Gaussian constraint: the systematics of
:func:`pipeline.fit_contact`), so that χ² is −2 ln of the posterior.

Jacobian: the derivatives with respect to the parameters that only scale, stretch, shift
or mix the pulse (:data:`pipeline.fit.forward.ANALYTIC`) in closed form, the others by
finite differences in the *local* parameters, all perturbed columns of all records
evaluated in one vectorised call of the forward model (columns that differ only in the
analytic parameters share one tangential solution), then the chain rule through the design,
:math:`\partial r/\partial\theta = \sum_l \partial r/\partial P_l\;\partial P_l/\partial\theta`.
lmfit's Levenberg–Marquardt (MINPACK ``lmder``) receives it as ``Dfun``, so a fit costs one
vectorised model call per iteration instead of one per parameter.

Many fits at once — bootstrap replicates, profile points — use :func:`gauss_newton_many`:
Gauss–Newton steps for B parameter vectors and data sets in one model call per iteration,
no Python loop over the replicates and no lmfit in that hot loop.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from .forward import ANALYTIC, PARAMS, ForwardModel

__all__ = ["Design", "Problem", "gauss_newton_many", "local_derivatives", "local_jacobians"]

_P = {name: i for i, name in enumerate(PARAMS)}
#: relative finite-difference step of the local parameters
_REL = 1e-6


class Design:
    """Global parameters → local parameters of each record (vectorised over rows of θ).

    Subclasses set ``names`` (all global parameters, fixed ones too), ``scale`` (a typical
    magnitude of each, for finite-difference steps) and implement :meth:`local`.
    """

    names: tuple = ()
    scale: np.ndarray
    #: ∂P/∂θ is the same at every θ (a design linear in θ): the Problem works out the
    #: chain rule's structure once
    constant_dlocal: bool = False

    def local(self, theta: np.ndarray) -> list:
        """θ, shape (B, p) → one (B, 6) array of local parameters per record."""
        raise NotImplementedError

    def dlocal(self, theta: np.ndarray, vary: np.ndarray) -> list:
        """∂P/∂θ_vary per record, shape (B, 6, n_vary), by forward differences of
        :meth:`local` (exact for the linear parts of a design)."""
        base = self.local(theta)
        out = [np.zeros(b.shape + (vary.size,)) for b in base]
        for j, k in enumerate(vary):
            step = 1e-7 * np.maximum(np.abs(theta[:, k]), self.scale[k])
            th = theta.copy()
            th[:, k] += step
            for o, b, p in zip(out, base, self.local(th), strict=True):
                # equal entries (an infinite bandwidth or resonance among them) do not move
                with np.errstate(invalid="ignore"):
                    o[:, :, j] = np.where(p == b, 0.0, p - b) / step[:, None]
        return out


class Problem:
    """A weighted least-squares problem over records (module notes).

    Parameters
    ----------
    model : ForwardModel
    datas : list of pipeline.fit.forward.RecordData
    design : Design
    vary : sequence of bool — which of ``design.names`` vary
    priors : dict, optional — {index into ``design.names``: (value, standard uncertainty)}
        of the parameters known to a tolerance (module notes); their rows follow the data
    """

    def __init__(self, model: ForwardModel, datas, design: Design, vary, priors=None):
        self.model, self.datas, self.design = model, list(datas), design
        self.vary = np.flatnonzero(np.asarray(vary, dtype=bool))
        self.y = np.concatenate([d.y() for d in self.datas])
        self.sizes = [d.n_data for d in self.datas]
        self.n_data = int(self.y.size)
        priors = dict(priors or {})
        self.prior_index = np.array(sorted(priors), dtype=int)
        self.prior_value = np.array([priors[k][0] for k in self.prior_index], dtype=float)
        self.prior_sigma = np.array([priors[k][1] for k in self.prior_index], dtype=float)
        self.n_calls = 0
        self._last = None
        self._dlocal = None  # (rows, the chain rule's structure) of a constant design
        self._prior_rows = None  # ∂(prior rows)/∂θ_vary, (priors, n_vary)
        self.solutions = None  # per record, of the last evaluation's rows (model's type)

    # ---------------------------------------------------------------- evaluation
    def evaluate(self, Theta, jacobian=False):
        """Residuals r (B, N) at the rows of Θ (B, p), and ∂r/∂θ_vary (B, N, n_vary).

        Local derivatives: E* and t0 analytic (they only stretch, scale and shift the
        pulse, :meth:`ForwardModel.predict`), the others by forward differences.
        """
        Theta = np.atleast_2d(np.asarray(Theta, dtype=float))
        Ps = self.design.local(Theta)
        self.n_calls += 1
        if not jacobian:
            res, self.solutions = self.model.residuals(self.datas, Ps)
            return self._with_priors(np.concatenate(res, axis=1), Theta), None
        dP, active, sels = self._chain(Theta)
        res, Ds, sols = local_derivatives(self.model, self.datas, Ps, active)
        self.solutions = sols
        J_all = [
            Dl[:, sel].transpose(0, 2, 1)
            if sel is not None
            else np.einsum("bln,blv->bnv", Dl, D[:, act, :])
            for Dl, act, D, sel in zip(Ds, active, dP, sels, strict=True)
        ]
        r = res[0] if len(res) == 1 else np.concatenate(res, axis=1)
        J = J_all[0] if len(J_all) == 1 else np.concatenate(J_all, axis=1)
        return self._with_priors(r, Theta, J)

    def _chain(self, Theta):
        """∂P/∂θ_vary per record at the rows of Θ, the local parameters each depends on, and
        each record's selection (:func:`_selection`: the places of the varied parameters
        among the active ones); kept for a design whose derivative is constant
        (:attr:`Design.constant_dlocal`), per number of rows."""
        B = Theta.shape[0]
        if self._dlocal is not None and self._dlocal[0] == B:
            return self._dlocal[1]
        dP = self.design.dlocal(Theta, self.vary)
        active = [np.flatnonzero(np.any(D != 0, axis=(0, 2))) for D in dP]
        sels = [_selection(D) for D in dP]
        sels = [
            None if sel is None else _gather(np.searchsorted(act, sel), len(act))
            for sel, act in zip(sels, active, strict=True)
        ]
        out = (dP, active, sels)
        if getattr(self.design, "constant_dlocal", False):  # a design of Design's duck type too
            self._dlocal = (B, out)
        return out

    @property
    def n_rows(self) -> int:
        """Rows of the residual: the data's, then one per prior."""
        return self.n_data + self.prior_index.size

    def _with_priors(self, r, Theta, J=None):
        """The residuals (and Jacobian) with the prior rows (θ_k − θ_k0)/u_k appended."""
        if not self.prior_index.size:
            return r if J is None else (r, J)
        pr = (Theta[:, self.prior_index] - self.prior_value) / self.prior_sigma
        r = np.concatenate([r, pr], axis=1)
        if J is None:
            return r
        if self._prior_rows is None:  # the same at every θ: worked out once
            Jp = np.zeros((self.prior_index.size, self.vary.size))
            col = {k: j for j, k in enumerate(self.vary)}
            for row, k in enumerate(self.prior_index):
                if k in col:
                    Jp[row, col[k]] = 1.0 / self.prior_sigma[row]
            self._prior_rows = Jp
        out = np.empty((J.shape[0], J.shape[1] + self.prior_index.size, J.shape[2]))
        out[:, : J.shape[1]] = J
        out[:, J.shape[1] :] = self._prior_rows
        return r, out

    def residual(self, theta):
        """Weighted residuals at θ; the Jacobian there is computed with them and kept for
        :meth:`jacobian` (Levenberg–Marquardt asks for it at accepted points)."""
        theta = np.asarray(theta, dtype=float)
        if self._last is None or not (self._last[0] == theta).all():
            r, J = self.evaluate(theta[None, :], jacobian=True)
            self._last = (theta.copy(), r[0], J[0], self.solutions)
        return self._last[1]

    def jacobian(self, theta):
        self.residual(theta)
        return self._last[2]

    def solution(self, theta):
        """The model's solution of each record at θ (kept from the last evaluation there)."""
        self.residual(theta)
        return self._last[3]

    def gain(self, theta):
        """K = (JᵀJ)⁻¹Jᵀ of the Jacobian at θ (:func:`_pseudo_inverse`), kept with it: the
        fit's covariance works it out (:meth:`keep_gain`), the dynamics' bounds reuse it."""
        self.residual(theta)
        if len(self._last) < 5:
            self._last += (_pseudo_inverse(self._last[2]),)
        return self._last[4]

    def keep_gain(self, theta, gain):
        """Keep ``gain``, K of the Jacobian at θ worked out elsewhere
        (:func:`pipeline.fit.uncertainty.covariance_parts`), for :meth:`gain` — where θ is
        the point the problem last evaluated (else there is nothing to keep it with)."""
        last = self._last
        if gain is not None and last is not None and (last[0] == np.asarray(theta)).all():
            self._last = last[:4] + (gain,)


def _gather(sel, n_active):
    """``sel`` as an index of the ``n_active`` active parameters: a slice of all of them
    where it picks each in order (a view of the derivatives, not a copy)."""
    return slice(None) if np.array_equal(sel, np.arange(n_active)) else sel


def _selection(D):
    """The local parameter each varied one is, where ∂P/∂θ (B, p_local, n_vary) only picks
    them out (0/1, one per column, alike in every row: one record's identity design), else
    None — the chain rule is then a gather, not a product."""
    nz = D[0] != 0
    if not (np.all(nz.sum(axis=0) == 1) and np.all(D[0][nz] == 1.0)):
        return None
    if D.shape[0] > 1 and not np.array_equal(D, np.broadcast_to(D[:1], D.shape)):
        return None
    return np.argmax(nz, axis=0)


def local_jacobians(model, datas, Ps, active):
    """Weighted residuals and their derivatives with respect to the local parameters, per
    record, in one vectorised call of the forward model.

    Parameters
    ----------
    model : ForwardModel
    datas : list of RecordData
    Ps : list of numpy.ndarray (B, len(PARAMS)) — each record's local parameters
    active : list of sequences of int — per record, the local parameters (indices into
        PARAMS) to differentiate: the :data:`~pipeline.fit.forward.ANALYTIC` ones in closed
        form, the others by forward differences

    Returns
    -------
    res : list of (B, n_i); Jl : list of (B, len(PARAMS), n_i) (zero outside ``active``);
    sols : list of the model's solutions of the B rows
    """
    res, Ds, sols = local_derivatives(model, datas, Ps, active)
    Jls = []
    for r, D, act in zip(res, Ds, active, strict=True):
        Jl = np.zeros((r.shape[0], len(PARAMS), r.shape[1]))
        Jl[:, act] = D
        Jls.append(Jl)
    return res, Jls, sols


def local_derivatives(model, datas, Ps, active):
    """:func:`local_jacobians` with each record's derivatives with respect to its
    ``active`` local parameters only: (B, len(active_i), n_i), in the order of
    ``active_i`` (sorted)."""
    B = Ps[0].shape[0]
    cols, steps, plans = [], [], []
    for P, act in zip(Ps, active, strict=True):
        plan = _plan(tuple(map(int, act)))
        fd = plan[0]
        st = np.empty((B, len(fd)))
        # the base columns, then one block of them per parameter differenced, each moved
        # by its step in that parameter
        Q = np.concatenate([P] * (len(fd) + 1)) if fd else P
        for j, l in enumerate(fd):
            if l == _E:
                h = np.where(P[:, l] + 1e-6 > 1.0, -1e-6, 1e-6)
            else:
                h = _REL * np.maximum(np.abs(P[:, l]), 1e-3 if l == _MU else 1e-300)
            Q[B * (j + 1) : B * (j + 2), l] += h
            st[:, j] = h
        cols.append(Q)
        steps.append(st)
        plans.append(plan)
    analytic = [plan[1] for plan in plans]
    res, sols, ders = model.residuals(datas, cols, nderiv=[B] * len(cols), analytic=analytic)
    out_r, out_D = [], []
    for r, st, der, (*_, n_act, fd_at, an_at) in zip(res, steps, ders, plans, strict=True):
        base = r[:B]
        D = np.empty((B, n_act, r.shape[1]))
        for j, i in enumerate(fd_at):  # forward differences, column by column
            np.subtract(r[B * (j + 1) : B * (j + 2)], base, out=D[:, i])
            D[:, i] /= st[:, j, None]
        for dst, src in an_at:  # the analytic ones, in runs of adjacent places
            D[:, dst] = der[:, src]
        out_r.append(base)
        out_D.append(D)
    return out_r, out_D, [None if s is None else s.head(B) for s in sols]


_E, _MU = _P["e"], _P["mu"]


@functools.lru_cache(maxsize=256)
def _plan(act):
    """How :func:`local_derivatives` differentiates with respect to the local parameters
    ``act`` (a sorted tuple of indices into PARAMS), the same at every call: those by
    differences, the analytic ones' names, how many, the places of those by differences
    among ``act``, and the analytic ones' as runs of adjacent places (slices of D and of
    the model's derivatives: copies of blocks, not gathers)."""
    fd = tuple(l for l in act if PARAMS[l] not in ANALYTIC)
    an = tuple(PARAMS[l] for l in act if PARAMS[l] in ANALYTIC)
    place = {l: i for i, l in enumerate(act)}
    runs = []  # [first place in D, first analytic, how many]
    for i, a in enumerate(an):
        if runs and runs[-1][0] + runs[-1][2] == place[_P[a]]:
            runs[-1][2] += 1
        else:
            runs.append([place[_P[a]], i, 1])
    an_at = tuple((slice(d, d + k), slice(i, i + k)) for d, i, k in runs)
    return fd, an, len(place), tuple(place[l] for l in fd), an_at


def _solve_normal(J, r, damp):
    """Least-squares steps δ = argmin |J δ − r|² + damp·|D δ|² for a batch (B, N, p)."""
    scale = np.sqrt(np.einsum("bnp,bnp->bp", J, J))
    scale = np.where(scale > 0, scale, 1.0)
    Js = J / scale[:, None, :]
    A = np.einsum("bnp,bnq->bpq", Js, Js)
    A = A + damp * np.eye(A.shape[-1])[None]
    g = np.einsum("bnp,bn->bp", Js, r)
    try:
        d = np.linalg.solve(A, g[..., None])[..., 0]
    except np.linalg.LinAlgError:
        d = np.einsum("bpq,bq->bp", np.linalg.pinv(A), g)
    return d / scale


def gauss_newton_many(
    problem: Problem,
    Theta0,
    dy=None,
    *,
    lower=None,
    upper=None,
    iters=4,
    freeze=None,
    jacobian=None,
    r0=None,
    tol=1e-4,
):
    """Refit B parameter vectors at once (Gauss–Newton, one model call per iteration).

    Parameters
    ----------
    problem : Problem
    Theta0 : numpy.ndarray, shape (B, p) — starting values (fixed entries stay as given)
    dy : numpy.ndarray, shape (B, N), optional — weighted data changes (y* − y)/σ of each
        replicate (bootstrap); None: the problem's own data
    lower, upper : numpy.ndarray, shape (p,), optional — bounds (steps are clipped to them)
    iters : int — most iterations
    freeze : numpy.ndarray of bool, shape (p,), optional — parameters held at their start
        values (a profile)
    jacobian : numpy.ndarray, shape (N, n_vary), optional — a Jacobian shared by every row
        (the fit's, for replicates that start at its optimum): each iteration then costs one
        residual evaluation without derivatives (simplified Gauss–Newton, which converges
        to the same optimum); None: each row's own Jacobian, recomputed every iteration
    r0 : numpy.ndarray, shape (N,), optional — the residuals at ``Theta0`` when every row
        starts at the same point (the fit's optimum): saves the first model call
    tol : float — stop when every step is below ``tol`` of the parameter's scale (with
        ``jacobian``: of its standard error from that Jacobian)

    Returns
    -------
    Theta : numpy.ndarray (B, p), chi2 : numpy.ndarray (B,)
    """
    Theta = np.array(Theta0, dtype=float, copy=True)
    v = problem.vary
    p = Theta.shape[1]
    lo = np.full(p, -np.inf) if lower is None else np.asarray(lower, float)
    hi = np.full(p, np.inf) if upper is None else np.asarray(upper, float)
    free = np.ones(v.size, bool) if freeze is None else ~np.asarray(freeze, bool)[v]
    extra = 0.0 if dy is None else dy
    scale = np.maximum(np.abs(Theta[0, v]), problem.design.scale[v])
    if jacobian is not None:
        K = _pseudo_inverse(np.asarray(jacobian)[:, free])  # (n_free, N)
        scale = np.ones(v.size)
        scale[free] = np.sqrt(np.sum(K * K, axis=1))  # standard errors at unit noise
        r = (problem.evaluate(Theta)[0] if r0 is None else np.asarray(r0)[None, :]) + extra
    else:
        r, J = problem.evaluate(Theta, jacobian=True)
        r = r + extra
    chi2 = np.einsum("bn,bn->b", r, r)
    damp = np.full(Theta.shape[0], 1e-8)
    for _ in range(iters):
        step = np.zeros((Theta.shape[0], v.size))
        if jacobian is not None:
            step[:, free] = -r @ K.T
        else:
            step[:, free] = _solve_normal(J[:, :, free], -r, damp[:, None, None])
        trial = Theta.copy()
        trial[:, v] = np.clip(Theta[:, v] + step, lo[v], hi[v])
        if jacobian is not None:
            rt, Jt = problem.evaluate(trial)[0] + extra, None
        else:
            rt, Jt = problem.evaluate(trial, jacobian=True)
            rt = rt + extra
        ct = np.einsum("bn,bn->b", rt, rt)
        better = np.isfinite(ct) & (ct <= chi2 * (1 + 1e-12))
        Theta = np.where(better[:, None], trial, Theta)
        r = np.where(better[:, None], rt, r)
        if Jt is not None:
            J = np.where(better[:, None, None], Jt, J)
            damp = np.where(better, damp * 0.1, damp * 100.0)
        chi2 = np.where(better, ct, chi2)
        if np.all(np.abs(step) <= tol * scale):
            break
    return Theta, chi2


def _scaled_svd(J):
    """SVD of J with its columns scaled to unit norm (their units differ by up to 10¹⁵: Pa,
    s): (the scales, U, w, Vᵀ, the singular values kept — above 1e-10 of the largest)."""
    s = np.sqrt(np.einsum("ij,ij->j", J, J))  # no J² temporary
    s = np.where(s > 0, s, 1.0)
    U, w, Vt = np.linalg.svd(J / s, full_matrices=False)
    good = w > w.max() * 1e-10 if w.size else np.zeros(0, bool)
    return s, U, w, Vt, good


def _gain(s, U, w, Vt, good):
    """K = (JᵀJ)⁻¹Jᵀ from :func:`_scaled_svd`'s parts (rank-deficient directions dropped)."""
    return ((Vt[good].T / w[good]) @ U[:, good].T) / s[:, None]


def _pseudo_inverse(J):
    """(JᵀJ)⁻¹Jᵀ by SVD of the column-scaled J (rank-deficient directions dropped)."""
    return _gain(*_scaled_svd(J))


def chi2_of(r) -> float:
    return float(np.dot(r, r)) if np.all(np.isfinite(r)) else math.inf
