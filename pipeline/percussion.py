r"""Percussions, the instant of maximum compression and the coefficients of restitution.

The percussions (seed eq. 3; docs/theory.md) are the running impulses of the contact forces,

.. math::

    P_n(t) = \int_{t_s}^{t} F_n\,dt', \qquad P_t(t) = \int_{t_s}^{t} F_t\,dt',

computed three ways on one time grid so that each result can be cross-checked
(:func:`percussions`): the exact antiderivative of a fitted curve (:mod:`pipeline.smooth`),
the cumulative trapezoid rule and the cumulative Simpson rule
(:func:`scipy.integrate.cumulative_simpson`) on the raw samples. The raw samples are padded
with F = 0 at the window's ends when these fall between samples (the pulse starts and ends
at zero force). :attr:`Percussions.disagreement_n` is the largest spread of the three.

**Maximum compression** (:func:`compression_split`) is where the normal relative velocity

.. math::

    v_n(t) = v_{n0} - P_n(t)/m^*

vanishes, i.e. :math:`P_n(t_c) = m^* v_{n0}` (docs/theory.md), when the scene gives the
effective mass and the approach speed (``method="momentum"``). Without them the approach
obtained by integrating :math:`F_n/m^*` twice,
:math:`\delta(t) = v_{n0}(t - t_s) - \frac{1}{m^*}\int_{t_s}^{t} P_n\,dt'`, still fixes the
split if the bodies separate where they met, :math:`\delta(t_e) = 0` (no permanent
indentation — true of Hertz and of the Hunt–Crossley family, whose force vanishes only at
δ = 0): then

.. math::

    m^* v_{n0} = \frac{1}{t_e - t_s}\int_{t_s}^{t_e} P_n\,dt = \overline{P_n},

and maximum compression is where :math:`P_n = \overline{P_n}` (``method="closure"``). This
needs neither mass nor speed; it gives :math:`v_{n0} = \overline{P_n}/m^*` when the mass
alone is known. A permanent set :math:`\delta_p > 0` biases it low by
:math:`m^*\delta_p/(t_e - t_s)`. ``method="peak_force"`` (on request only) takes the peak
of :math:`F_n` — exact for elastic contact, early for damped contact, where the force
peaks before maximum compression — and warns. ``method="auto"`` (default) uses
``momentum`` when mass and speed are known and the record reaches :math:`m^* v_{n0}`,
otherwise ``closure`` (with a :class:`~pipeline.errors.PipelineWarning` when the record's
impulse falls short of :math:`m^* v_{n0}`, i.e. contradicts the scene).

**Coefficients of restitution** (seed eqs. 1–2; docs/theory.md):

- Poisson (:func:`restitution_poisson`): :math:`e_P = (P_{nf} - P_{nc})/P_{nc}`;
- Newton (:func:`restitution_newton`), when :math:`m^*` and :math:`v_{n0}` are given:
  :math:`v_n'' = P_{nf}/m^* - v_{n0}`, :math:`e_N = v_n''/v_{n0}`;
- Stronge (:func:`restitution_energetic`): :math:`e_*^2 = -W_r/W_c`, with the work of
  :math:`F_n` on the approach velocity :math:`W = \int F_n v_n\,dt`. Since
  :math:`dP_n = F_n\,dt`, :math:`W(P) = v_{n0}P - P^2/(2m^*)` exactly
  (:func:`normal_work`), so no quadrature is needed; the phases split at
  :math:`v_n = 0`.

For a sphere on a plane (contact normal through the centre of mass) the three coincide
(docs/theory.md); they differ here only if the split is not at :math:`v_n = 0`.

**What the record can resolve** (:func:`resolution`). Every way of computing percussions
above fails, silently, once the record itself is too coarse; the stability maps
(``benchmarks/bench_stability.py``, docs/stability.md) chart where. :func:`resolution`
checks a windowed record against those regions and flags (a :class:`ResolutionWarning`)
each one it is in, with the number that tripped it:

- *sparse sampling*: fewer than :data:`MIN_SAMPLES_PER_CONTACT` samples of a channel over
  the contact;
- *noise*: white noise σ (the window's estimate) propagates into a percussion from the
  samples with the quadrature weights :math:`w_i`, :math:`\mathrm{sd}(P_f) = \sigma
  \sqrt{\sum_i w_i^2}` (≈ σ·Δt·√n); flagged when three of it exceed ``tol`` of the
  percussion's scale (unflagged, fewer than 0.3 % of records miss by ``tol`` from noise);
- *coarse ADC*: a raw channel whose values lie on a grid of step q (an ADC's quantum,
  or a file's printed resolution) with q above :data:`MAX_ADC_STEP` of the channel's
  peak force and above the noise σ (noise of at least one step dithers the quantiser:
  its error is then noise-like, part of σ, and the noise check covers it);
- *filter bandwidth*: where the record states its bandwidth f_c (attribute
  ``sensor_bandwidth`` [Hz], as :func:`pipeline.sensor_model.to_sensor` writes it),
  f_c·(contact duration) below :data:`MIN_BANDWIDTH_PRODUCT`: the low-pass smears the
  pulse and its tangential reversal;
- *curved baseline*: a parabola fitted by least squares to the residuals of the window's
  linear baseline outside the contact, integrated over the contact, predicts what the
  line leaves in the percussions; flagged when that exceeds a third of ``tol`` and three
  of its own standard errors (a linear drift is removed exactly; a curved one is not).

One check concerns the fitted curve alone: where the fit's percussion departs from the
Simpson integral of the samples by more than half of ``tol`` (and by more than three noise
standard deviations, which the samples' integral carries and the fit smooths away), the
fit misses the pulse; it is flagged as a poor fit (``fit_flags``, a
:class:`~pipeline.errors.PoorFitWarning`), the samples' integrals are not.

References
----------
F.-C. Ciornei et al., MATEC Web Conf. 112:07005 (2017), doi:10.1051/matecconf/201711207005.
W. J. Stronge, "Rigid body collisions with friction", Proc. R. Soc. A 431:169 (1990),
doi:10.1098/rspa.1990.0125.
Y. Wang, M. T. Mason, J. Appl. Mech. 59:635 (1992), doi:10.1115/1.2893771.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import pandas as pd
import xarray as xr
from scipy import integrate, optimize

from ._json import json_ready
from .errors import InputError, PipelineWarning, PoorFitWarning
from .record import adc_step, channel, time_variable
from .smooth import fit_window
from .window import ContactWindow

__all__ = [
    "estimate_mu",
    "mu_plateau",
    "Percussions",
    "CompressionSplit",
    "Resolution",
    "ResolutionWarning",
    "percussions",
    "resolution",
    "cumulative_percussion",
    "compression_split",
    "normal_work",
    "restitution_poisson",
    "restitution_newton",
    "restitution_energetic",
    "SOURCES",
    "METHODS",
    "RESOLUTION_TOL",
    "MIN_SAMPLES_PER_CONTACT",
    "MAX_ADC_STEP",
    "MIN_BANDWIDTH_PRODUCT",
]

#: Where a percussion comes from: the fitted curve or the raw samples.
SOURCES = ("fit", "trapezoid", "simpson")
#: How the instant of maximum compression is found.
METHODS = ("auto", "momentum", "closure", "peak_force")

_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(5)

#: Relative error of a percussion above which :func:`resolution` flags the record [-].
RESOLUTION_TOL = 0.02
#: Fewest samples of a channel over the contact (stability map "noise × sampling rate").
MIN_SAMPLES_PER_CONTACT = 20
#: Largest undithered ADC step over the channel's peak force [-] (map "ADC resolution").
MAX_ADC_STEP = 0.02
#: Smallest bandwidth × contact duration f_c·t_c [-] (map "bandwidth × contact duration").
MIN_BANDWIDTH_PRODUCT = 3.0


class ResolutionWarning(PipelineWarning):
    """The record is too sparse, noisy, coarse or smeared for percussions within tolerance."""


# ------------------------------------------------------------------ coefficients
def restitution_poisson(Pn_c, Pn_f):
    """Poisson's (kinetic) coefficient e_P = (Pn_f − Pn_c)/Pn_c [-] (seed eq. 2).

    Parameters
    ----------
    Pn_c : float or array — normal percussion at maximum compression [N·s]
    Pn_f : float or array — normal percussion at the end of contact [N·s]
    """
    Pn_c = np.asarray(Pn_c, dtype=float)
    return (np.asarray(Pn_f, dtype=float) - Pn_c) / Pn_c


def restitution_newton(Pn_f, m, v_n0):
    """Newton's (kinematic) coefficient e_N = −v_n''/v_n' [-] (seed eq. 1).

    Parameters
    ----------
    Pn_f : float or array — total normal percussion [N·s]
    m : float or array — effective mass m* [kg]
    v_n0 : float or array — normal approach speed before impact [m/s] (> 0)

    Notes
    -----
    Rebound speed v_n'' = Pn_f/m* − v_n0 (momentum balance along the normal), so
    e_N = Pn_f/(m*·v_n0) − 1.
    """
    v_n0 = np.asarray(v_n0, dtype=float)
    return (np.asarray(Pn_f, dtype=float) / np.asarray(m, dtype=float) - v_n0) / v_n0


def normal_work(P, m, v_n0):
    """Work of Fn on the normal approach velocity up to percussion P [J].

    W(P) = ∫ Fn·v_n dt = v_n0·P − P²/(2m*), exact because dPn = Fn·dt and
    v_n = v_n0 − Pn/m*.

    Parameters
    ----------
    P : float or array — normal percussion [N·s]
    m : float or array — effective mass [kg]
    v_n0 : float or array — approach speed [m/s]
    """
    P = np.asarray(P, dtype=float)
    return np.asarray(v_n0, dtype=float) * P - P * P / (2.0 * np.asarray(m, dtype=float))


def restitution_energetic(Pn_f, m, v_n0):
    """Stronge's energetic coefficient e* = √(−W_r/W_c) [-].

    Parameters
    ----------
    Pn_f : float or array — total normal percussion [N·s]
    m : float or array — effective mass [kg]
    v_n0 : float or array — approach speed [m/s]

    Notes
    -----
    Compression ends where v_n = 0, at P = m*·v_n0: W_c = W(m*v_n0) = m*v_n0²/2,
    W_r = W(Pn_f) − W_c (:func:`normal_work`). For a sphere this equals |e_N|.
    NaN when W_r > 0 (the record would create energy).

    References
    ----------
    W. J. Stronge, Proc. R. Soc. A 431:169 (1990), doi:10.1098/rspa.1990.0125.
    """
    m = np.asarray(m, dtype=float)
    v_n0 = np.asarray(v_n0, dtype=float)
    W_c = normal_work(m * v_n0, m, v_n0)
    W_r = normal_work(Pn_f, m, v_n0) - W_c
    with np.errstate(invalid="ignore"):
        return np.sqrt(-W_r / W_c)


# ------------------------------------------------------------------ percussions
def cumulative_percussion(
    t, F, *, method: str = "trapezoid", t_start=None, t_end=None
) -> xr.DataArray:
    """Running impulse of raw force samples [N·s], zero at the first instant returned.

    Parameters
    ----------
    t : array_like, shape (n,)
        Strictly increasing instants [s].
    F : array_like, shape (n,)
        Force samples [N].
    method : {"trapezoid", "simpson"}
        Cumulative trapezoid rule, or :func:`scipy.integrate.cumulative_simpson`
        (non-uniform spacing allowed).
    t_start, t_end : float, optional
        Window ends [s]; where they lie outside the samples, a sample F = 0 is added there
        (the pulse starts and ends at zero force).

    Returns
    -------
    xarray.DataArray
        ∫ F dt' from the first instant [N·s] (``attrs["units"] = "N s"``) on the coordinate
        ``time`` [s]: the samples plus any padded ends.
    """
    t = np.asarray(t, dtype=float)
    F = np.asarray(F, dtype=float)
    if method not in ("trapezoid", "simpson"):
        raise InputError(f"integration method {method!r} is unknown; use 'trapezoid' or 'simpson'")
    t, F = _pad(t, F, t_start, t_end)
    P = _cumulative(t, F, method)
    return xr.DataArray(
        time_variable(P, {"units": "N s", "long_name": f"percussion ({method})"}),
        coords={"time": time_variable(pd.Index(t), {"units": "s"})},
        dims="time",
        name="P",
    )


def _pad(t, F, t_start, t_end):
    """``t`` and ``F`` (..., n) with a sample F = 0 added at a window end outside the samples."""
    span = t[-1] - t[0]
    tiny = 1e-9 * span
    zero = np.zeros(F.shape[:-1] + (1,))
    if t_start is not None and t_start < t[0] - tiny:
        t = np.concatenate([[t_start], t])
        F = np.concatenate([zero, F], axis=-1)
    if t_end is not None and t_end > t[-1] + tiny:
        t = np.concatenate([t, [t_end]])
        F = np.concatenate([F, zero], axis=-1)
    return t, F


def _cumulative(t, F, method):
    """Cumulative integral of F (..., n) on ``t`` along the last axis, zero at t[0]."""
    if method == "simpson" and t.size >= 3:
        return integrate.cumulative_simpson(F, x=t, axis=-1, initial=0.0)
    return integrate.cumulative_trapezoid(F, x=t, axis=-1, initial=0.0)


@dataclass(frozen=True, eq=False)
class Percussions:
    """Normal and tangential percussions on one time grid, three ways (all SI).

    Attributes
    ----------
    time : numpy.ndarray
        The grid [s]: t_start, the window's sample instants, t_end.
    Pn_fit, Pn_trapezoid, Pn_simpson : numpy.ndarray
        Normal percussion [N·s] from the fitted curve's exact antiderivative and from the
        raw samples by the cumulative trapezoid and Simpson rules.
    Pt_fit, Pt_trapezoid, Pt_simpson : numpy.ndarray or None
        Tangential percussion [N·s] likewise (None without an Ft channel).
    t_start, t_end : float
        The window [s]; every percussion is zero at t_start.
    disagreement_n, disagreement_t : float
        Largest spread max − min of the three percussions over the grid [N·s].
    fit_n, fit_t : PolyFit or SplineFit
        The fitted curves (callables with ``antiderivative``).
    """

    time: np.ndarray
    Pn_fit: np.ndarray
    Pn_trapezoid: np.ndarray
    Pn_simpson: np.ndarray
    t_start: float
    t_end: float
    disagreement_n: float
    fit_n: object
    Pt_fit: np.ndarray | None = None
    Pt_trapezoid: np.ndarray | None = None
    Pt_simpson: np.ndarray | None = None
    disagreement_t: float = float("nan")
    fit_t: object = None

    def Pn(self, source: str = "fit") -> np.ndarray:
        """Normal percussion [N·s] from ``source`` (``fit``, ``trapezoid``, ``simpson``)."""
        return getattr(self, f"Pn_{_check_source(source)}")

    def Pt(self, source: str = "fit") -> np.ndarray | None:
        """Tangential percussion [N·s] from ``source`` (None without an Ft channel)."""
        return getattr(self, f"Pt_{_check_source(source)}")

    @property
    def Pn_total(self) -> float:
        """Total normal percussion Pn(t_end) from the fit [N·s]."""
        return float(self.Pn_fit[-1])

    @property
    def Pt_total(self) -> float:
        """Total tangential percussion Pt(t_end) from the fit [N·s] (NaN without Ft)."""
        return float("nan") if self.Pt_fit is None else float(self.Pt_fit[-1])

    def to_dataset(self) -> xr.Dataset:
        """The percussions as an :class:`xarray.Dataset` on ``time`` (units in attrs)."""
        data = {}
        for comp, name in (("n", "normal"), ("t", "tangential")):
            for src in SOURCES:
                v = getattr(self, f"P{comp}_{src}")
                if v is not None:
                    data[f"P{comp}_{src}"] = (
                        "time",
                        v,
                        {
                            "units": "N s",
                            "long_name": f"{name} percussion ({src})",
                        },
                    )
        return xr.Dataset(
            data,
            coords={"time": ("time", self.time, {"units": "s", "long_name": "time"})},
            attrs={
                "t_start": self.t_start,
                "t_end": self.t_end,
                "disagreement_n": self.disagreement_n,
                "disagreement_t": self.disagreement_t,
                "disagreement_units": "N s",
            },
        )

    def summary(self) -> dict:
        """JSON-ready dict (units in key names; NaN → None)."""
        return json_ready(
            {
                "t_start_s": self.t_start,
                "t_end_s": self.t_end,
                "Pn_total_Ns": {s: float(self.Pn(s)[-1]) for s in SOURCES},
                "Pt_total_Ns": (
                    None if self.Pt_fit is None else {s: float(self.Pt(s)[-1]) for s in SOURCES}
                ),
                "disagreement_n_Ns": self.disagreement_n,
                "disagreement_t_Ns": self.disagreement_t,
            }
        )


def _check_source(source):
    if source not in SOURCES:
        raise InputError(f"percussion source {source!r} is unknown; use one of {SOURCES}")
    return source


def _raw_on_grid(t, F, grid, t_start, t_end, method):
    """Percussion [N·s] of raw samples F (..., n) at instants ``t``, on the grid ``grid``.

    The samples are padded with F = 0 at the window ends (:func:`_pad`) and integrated
    cumulatively; a channel sampled off the grid (digitised records) is put on it by linear
    interpolation, held constant outside the channel's own span.
    """
    tp, Fp = _pad(t, np.asarray(F, dtype=float), t_start, t_end)
    P = _cumulative(tp, Fp, method)
    if tp.size == grid.size and np.array_equal(tp, grid):
        return P
    flat = P.reshape(-1, tp.size)
    out = np.stack([np.interp(grid, tp, row) for row in flat])
    return out.reshape(P.shape[:-1] + (grid.size,))


def percussions(window, fits=None, *, t_start=None, t_end=None) -> Percussions:
    """Pn(t), Pt(t) of a contact window from the fit and from the raw samples.

    Parameters
    ----------
    window : pipeline.window.ContactWindow or xarray.Dataset
        The contact window, or a windowed record (baseline removed) whose attrs
        ``window_t_start``/``window_t_end`` (else its first/last instant) give the window.
    fits : pipeline.smooth.WindowFits, optional
        Fitted curves of the channels. Default: the GCV smoothing spline of each channel
        (:func:`pipeline.smooth.fit_window` with ``method="spline"``).
    t_start, t_end : float, optional
        Override the window ends [s].

    Returns
    -------
    Percussions
    """
    record = getattr(window, "record", window)
    if not isinstance(record, xr.Dataset):
        raise InputError("percussions needs a ContactWindow or a windowed record")
    t_all = record["time"].values
    ts = t_start if t_start is not None else getattr(window, "t_start", None)
    te = t_end if t_end is not None else getattr(window, "t_end", None)
    ts = float(record.attrs.get("window_t_start", t_all[0]) if ts is None else ts)
    te = float(record.attrs.get("window_t_end", t_all[-1]) if te is None else te)
    if not te > ts:
        raise InputError(f"the window must have t_end > t_start, got [{ts}, {te}] s")
    if fits is None:
        cw = (
            window
            if isinstance(window, ContactWindow)
            else ContactWindow(
                t_start=ts, t_end=te, kind=record.attrs.get("kind", ""), record=record
            )
        )
        fits = fit_window(cw, method="spline")
    grid, _ = _pad(t_all, np.zeros_like(t_all), ts, te)
    out = {}
    for comp, name in (("n", "Fn"), ("t", "Ft")):
        fitc = getattr(fits, name, None)
        if name not in record or fitc is None:
            continue
        t, f = channel(record, name)
        if t.size < 2:
            raise InputError(f"{name} has fewer than 2 samples in the window")
        P_fit = np.asarray(fitc.antiderivative(grid), dtype=float)
        P_tr = _raw_on_grid(t, f, grid, ts, te, "trapezoid")
        P_si = _raw_on_grid(t, f, grid, ts, te, "simpson")
        stack = np.vstack([P_fit, P_tr, P_si])
        out[f"P{comp}_fit"] = P_fit
        out[f"P{comp}_trapezoid"] = P_tr
        out[f"P{comp}_simpson"] = P_si
        out[f"disagreement_{comp}"] = float(np.max(stack.max(axis=0) - stack.min(axis=0)))
        out[f"fit_{comp}"] = fitc
    if "Pn_fit" not in out:
        raise InputError("percussions needs an Fn channel and its fit")
    return Percussions(time=grid, t_start=ts, t_end=te, **out)


# ------------------------------------------------------------------ compression split
@dataclass(frozen=True)
class CompressionSplit:
    """The compression/restitution split of an impact and its restitution coefficients.

    Attributes
    ----------
    t_c : float
        Instant of maximum compression [s].
    Pn_c, Pn_f : float
        Normal percussion at t_c and at the end of contact [N·s].
    Pt_c, Pt_f : float
        Tangential percussion at t_c and at the end [N·s] (NaN without Ft).
    method : str
        ``momentum``, ``closure`` or ``peak_force`` (module notes).
    source : str
        The percussion used: ``fit``, ``trapezoid`` or ``simpson``.
    m : float
        Effective mass used [kg] (NaN when unknown).
    v_n0 : float
        Approach speed [m/s]: given, or estimated by ``closure`` from the mass (NaN when
        neither is known).
    v_n0_given : bool
        Whether ``v_n0`` came from the caller (True) or was estimated (False).
    e_poisson : float
        (Pn_f − Pn_c)/Pn_c [-].
    e_newton : float
        Pn_f/(m·v_n0) − 1 [-]; NaN unless mass and speed were given.
    e_energetic : float
        Stronge's e* [-] with the phases split at v_n = 0; from mass and speed when given,
        else with m·v_n0 = Pn_c.
    W_c, W_r : float
        Work of Fn in compression and restitution [J] (NaN when the mass is unknown).
    """

    t_c: float
    Pn_c: float
    Pn_f: float
    Pt_c: float
    Pt_f: float
    method: str
    source: str
    m: float
    v_n0: float
    v_n0_given: bool
    e_poisson: float
    e_newton: float
    e_energetic: float
    W_c: float
    W_r: float

    def summary(self) -> dict:
        """JSON-ready dict (units in key names; NaN → None)."""
        return json_ready(
            {
                "t_c_s": self.t_c,
                "Pn_c_Ns": self.Pn_c,
                "Pn_f_Ns": self.Pn_f,
                "Pt_c_Ns": self.Pt_c,
                "Pt_f_Ns": self.Pt_f,
                "method": self.method,
                "source": self.source,
                "m_kg": self.m,
                "v_n0_m_per_s": self.v_n0,
                "v_n0_given": self.v_n0_given,
                "e_poisson": self.e_poisson,
                "e_newton": self.e_newton,
                "e_energetic": self.e_energetic,
                "W_c_J": self.W_c,
                "W_r_J": self.W_r,
            }
        )


def _mean_percussion(perc: Percussions, source: str) -> float:
    """(1/(t_e − t_s))·∫ Pn dt over the window [N·s]."""
    D = perc.t_end - perc.t_start
    if source != "fit":
        return float(integrate.trapezoid(perc.Pn(source), perc.time) / D)
    # composite 5-point Gauss–Legendre on each grid interval: exact for the antiderivative
    # of a polynomial of degree ≤ 8 and of a cubic spline with knots at the samples
    # (error O(h¹⁰) per interval beyond that)
    a, b = perc.time[:-1], perc.time[1:]
    half = 0.5 * (b - a)
    nodes = (0.5 * (a + b))[:, None] + half[:, None] * _GAUSS_X[None, :]
    vals = np.asarray(perc.fit_n.antiderivative(nodes.ravel())).reshape(nodes.shape)
    return float(np.sum(half[:, None] * _GAUSS_W[None, :] * vals) / D)


def _crossing_time(perc: Percussions, source: str, level: float) -> float:
    """First instant where Pn(t) reaches ``level`` (fit: Brent on the exact antiderivative)."""
    P = perc.Pn(source)
    above = np.flatnonzero(P >= level)
    if above.size == 0:
        raise InputError(f"the normal percussion never reaches {level:.6g} N·s")
    i = int(above[0])
    if i == 0:
        return float(perc.time[0])
    t0, t1 = perc.time[i - 1], perc.time[i]
    if source == "fit":

        def g(t):
            return float(perc.fit_n.antiderivative(t)) - level

        if g(t0) < 0 <= g(t1):
            return float(optimize.brentq(g, t0, t1, xtol=1e-15 * max(abs(t1), 1e-300), rtol=1e-14))
    return float(t0 + (level - P[i - 1]) * (t1 - t0) / (P[i] - P[i - 1]))


def _peak_time(perc: Percussions, source: str) -> float:
    if source == "fit":
        tt = np.linspace(perc.t_start, perc.t_end, 4001)
        F = np.asarray(perc.fit_n(tt))
        i = int(np.argmax(F))
        lo, hi = tt[max(i - 1, 0)], tt[min(i + 1, tt.size - 1)]
        res = optimize.minimize_scalar(
            lambda s: -float(perc.fit_n(s)),
            bounds=(lo, hi),
            method="bounded",
            options={"xatol": 1e-12 * (hi - lo)},
        )
        return float(res.x)
    # raw samples: the peak of the finite-difference force dPn/dt
    F = np.gradient(perc.Pn(source), perc.time)
    return float(perc.time[int(np.argmax(F))])


def _value_at(perc: Percussions, comp: str, source: str, t: float) -> float:
    P = getattr(perc, f"P{comp}_{source}")
    if P is None:
        return float("nan")
    if source == "fit":
        fitc = perc.fit_n if comp == "n" else perc.fit_t
        return float(fitc.antiderivative(t))
    return float(np.interp(t, perc.time, P))


def compression_split(
    perc: Percussions, scene=None, *, m=None, v_n0=None, method: str = "auto", source: str = "fit"
) -> CompressionSplit:
    """Split the impact at maximum compression and compute the restitution coefficients.

    Parameters
    ----------
    perc : Percussions
        From :func:`percussions`.
    scene : pipeline.Scene, optional
        Supplies ``m = scene.m_eff`` [kg] and ``v_n0 = scene.v_n0`` [m/s].
    m : float, optional
        Effective mass [kg]; overrides the scene's.
    v_n0 : float, optional
        Normal approach speed [m/s]; overrides the scene's.
    method : {"auto", "momentum", "closure", "peak_force"}
        How to find maximum compression (module notes). ``auto``: ``momentum`` with mass
        and speed, else ``closure``.
    source : {"fit", "trapezoid", "simpson"}
        Which percussion to use.

    Returns
    -------
    CompressionSplit

    Raises
    ------
    InputError
        Unknown method or source; ``momentum`` without mass and speed or on a record whose
        impulse never reaches m*·v_n0.

    Warns
    -----
    PipelineWarning
        ``auto`` falling back to ``closure`` because the record's impulse contradicts the
        scene; ``peak_force`` (a biased estimate for damped contacts).
    """
    if method not in METHODS:
        raise InputError(f"method {method!r} is unknown; use one of {METHODS}")
    _check_source(source)
    if scene is not None:
        m = scene.m_eff if m is None else m
        v_n0 = scene.v_n0 if v_n0 is None else v_n0
    m = float("nan") if m is None else float(m)
    v_given = v_n0 is not None
    v = float(v_n0) if v_given else float("nan")
    if np.isfinite(m) and m <= 0:
        raise InputError(f"the effective mass must be positive, got {m} kg")
    if v_given and not v > 0:
        raise InputError(f"the approach speed must be positive, got {v} m/s")
    P = perc.Pn(source)
    Pn_f = float(P[-1])
    known = np.isfinite(m) and v_given
    if method == "momentum" and not known:
        raise InputError(
            "method='momentum' needs the effective mass and the approach speed "
            "(give a scene, or m= and v_n0=)"
        )
    if method == "auto":
        if known and Pn_f > m * v:
            method = "momentum"
        else:
            if known:
                warnings.warn(
                    f"the record's normal impulse {Pn_f:.6g} N·s does not exceed m*·v_n0 = "
                    f"{m * v:.6g} N·s from the scene, so maximum compression is never "
                    "reached; using the closure estimate (mean Pn) instead — check the "
                    "scene's mass and speed or the force calibration",
                    PipelineWarning,
                    stacklevel=2,
                )
            method = "closure"
    if method == "momentum":
        Pn_c = m * v
        t_c = _crossing_time(perc, source, Pn_c)
    elif method == "closure":
        Pn_c = _mean_percussion(perc, source)
        t_c = _crossing_time(perc, source, Pn_c)
        if not v_given and np.isfinite(m):
            v = Pn_c / m
    else:  # peak_force
        warnings.warn(
            "maximum compression taken at the peak of Fn: exact for elastic contact, but a "
            "damped contact's force peaks before maximum compression, which biases e_P "
            "upward; give the mass and approach speed (momentum) or use method='closure'",
            PipelineWarning,
            stacklevel=2,
        )
        t_c = _peak_time(perc, source)
        Pn_c = _value_at(perc, "n", source, t_c)
    e_p = float(restitution_poisson(Pn_c, Pn_f))
    e_n = float(restitution_newton(Pn_f, m, v)) if known else float("nan")
    # Stronge: phases split at v_n = 0, i.e. at P = m·v_n0 (= Pn_c when m·v is unknown)
    mv = m * v if (np.isfinite(m) and np.isfinite(v)) else Pn_c
    e_star = float(restitution_energetic(Pn_f, 1.0, mv))  # W scales as 1/m: e* is m-free
    if np.isfinite(m):
        W_c = float(normal_work(mv, m, mv / m))
        W_r = float(normal_work(Pn_f, m, mv / m)) - W_c
    else:
        W_c = W_r = float("nan")
    return CompressionSplit(
        t_c=float(t_c),
        Pn_c=float(Pn_c),
        Pn_f=Pn_f,
        Pt_c=_value_at(perc, "t", source, t_c),
        Pt_f=float("nan") if perc.Pt(source) is None else float(perc.Pt(source)[-1]),
        method=method,
        source=source,
        m=m,
        v_n0=v,
        v_n0_given=v_given,
        e_poisson=e_p,
        e_newton=e_n,
        e_energetic=e_star,
        W_c=W_c,
        W_r=W_r,
    )


# ------------------------------------------------------------------ what the record resolves
@dataclass(frozen=True)
class Resolution:
    """How far a windowed record's sampling, noise, ADC, bandwidth and baseline limit its
    percussions (module notes; the thresholds come from the stability maps).

    Every relative error is over the channel's percussion scale (:func:`resolution`'s
    ``scale``: in :func:`pipeline.analyse`, the deviation score's P_ref and Pt_ref).

    Attributes
    ----------
    n_samples : dict
        Samples of each channel inside the contact window.
    noise_error : dict
        Standard deviation of each channel's final percussion from the window's white
        noise, relative [-] (NaN where the noise is unknown).
    adc_step : dict
        Step of the grid the raw values lie on [N] (0 where none was found or no raw
        record was given).
    adc_error : dict
        ``adc_step`` over the channel's peak |F| in the window [-].
    bandwidth_product : float
        Stated bandwidth × contact duration f_c·(t_e − t_s) [-] (NaN when not stated).
    baseline_error : dict
        Percussion the window's linear baseline leaves under the pulse when the baseline
        is curved (parabola fitted outside the contact), relative [-] (NaN when no
        baseline was fitted).
    fit_departure : dict
        Largest |P_fit − P_simpson| over the contact, relative [-] (module notes).
    flags : dict
        ``{region: message}`` for every failure region the record is in (empty: none);
        these limit every way of computing the percussions.
    fit_flags : dict
        ``{region: message}`` that concern the fitted curve's percussions alone.
    tol : float
        The relative tolerance of the checks [-].
    """

    n_samples: dict
    noise_error: dict
    adc_step: dict
    adc_error: dict
    bandwidth_product: float
    baseline_error: dict
    fit_departure: dict
    flags: dict
    fit_flags: dict
    tol: float

    @property
    def ok(self) -> bool:
        """True when the record is in no failure region."""
        return not self.flags

    def summary(self) -> dict:
        """JSON-ready dict (NaN → None)."""
        return json_ready(
            {
                "n_samples": self.n_samples,
                "noise_error": self.noise_error,
                "adc_step_N": self.adc_step,
                "adc_error": self.adc_error,
                "bandwidth_product": self.bandwidth_product,
                "baseline_error": self.baseline_error,
                "fit_departure": self.fit_departure,
                "flags": self.flags,
                "fit_flags": self.fit_flags,
                "tol": self.tol,
            }
        )


def _trapezoid_weights(t):
    """Weights w_i of the trapezoid rule on the instants ``t``: ∫F dt ≈ Σ w_i F_i [s]."""
    w = np.zeros(t.size)
    dt = np.diff(t)
    w[:-1] += 0.5 * dt
    w[1:] += 0.5 * dt
    return w


def resolution(
    window,
    perc: Percussions,
    *,
    record=None,
    scale=None,
    tol: float = RESOLUTION_TOL,
    warn: bool = True,
) -> Resolution:
    """Check a windowed record against the failure regions of the percussions.

    Parameters
    ----------
    window : pipeline.window.ContactWindow
        The contact window (its noise estimates and baselines are used).
    perc : Percussions
        The percussions of that window (:func:`percussions`).
    record : xarray.Dataset, optional
        The raw record the window was cut from (for the ADC step and the baseline check);
        without it those checks are skipped.
    scale : (float, float), optional
        The normal and tangential percussion scales [N·s] the errors are relative to
        (:func:`pipeline.analyse` passes the deviation score's P_ref and Pt_ref); default
        each channel's largest |P| from the samples.
    tol : float
        Relative error of a percussion that the record must stay within [-].
    warn : bool
        Issue one :class:`ResolutionWarning` listing every region the record is in, and a
        :class:`~pipeline.errors.PoorFitWarning` for ``fit_flags``.

    Returns
    -------
    Resolution

    Notes
    -----
    See the module notes for each check. :data:`MIN_SAMPLES_PER_CONTACT`,
    :data:`MAX_ADC_STEP` and :data:`MIN_BANDWIDTH_PRODUCT` are where the stability maps
    (docs/stability.md) measured the percussions' error crossing ``RESOLUTION_TOL``.
    """
    rec = window.record
    ts, te = perc.t_start, perc.t_end
    n, noise_err, step, adc_err, base_err, depart = {}, {}, {}, {}, {}, {}
    base_z = {}
    for i, (c, comp) in enumerate((("Fn", "n"), ("Ft", "t"))):
        P = getattr(perc, f"P{comp}_trapezoid")
        if P is None or c not in rec:
            continue
        ref = float(np.max(np.abs(P))) if scale is None else float(scale[i])
        t, f = channel(rec, c)
        n[c] = int(t.size)
        sigma = float(window.noise.get(c, float("nan")))
        tp, _ = _pad(t, f, ts, te)
        w = _trapezoid_weights(tp)[np.isin(tp, t)]  # the padded ends carry no noise
        with np.errstate(invalid="ignore", divide="ignore"):
            noise_err[c] = float(sigma * np.sqrt(np.sum(w * w)) / ref)
        peak = float(np.max(np.abs(f)))
        raw = channel(record, c)[1] if record is not None and c in record else ()
        step[c] = adc_step(raw)
        adc_err[c] = step[c] / peak if peak > 0 else float("nan")
        dP, se = _baseline_left(record, window, c)
        base_err[c] = abs(dP) / ref
        diff = getattr(perc, f"P{comp}_fit") - getattr(perc, f"P{comp}_simpson")
        depart[c] = float(np.max(np.abs(diff)) / ref)
        base_z[c] = abs(dP) / se if se > 0 else float("nan")
    flags = {}
    low = {c: k for c, k in n.items() if k < MIN_SAMPLES_PER_CONTACT}
    if low:
        flags["sparse sampling"] = (
            ", ".join(f"{c} has {k} samples" for c, k in low.items())
            + f" over the contact; below {MIN_SAMPLES_PER_CONTACT} the percussions' maximum "
            f"and end are off by more than {tol:g} whatever the method"
        )
    loud = {c: v for c, v in noise_err.items() if 3.0 * v > tol}
    if loud:
        flags["noise"] = (
            ", ".join(f"{c}: sd(P_f) = {v:.2g}" for c, v in loud.items())
            + f" of its scale from the white noise (σ·√Σw²); three of it exceed tol = {tol:g}"
        )
    coarse = {
        c: v
        for c, v in adc_err.items()
        if v > MAX_ADC_STEP and not float(window.noise.get(c, 0.0)) >= step[c]
    }
    if coarse:
        flags["coarse ADC"] = (
            ", ".join(
                f"{c} steps by {step[c]:.4g} N = {v:.2g} of its peak" for c, v in coarse.items()
            )
            + f", above {MAX_ADC_STEP:g} and above the noise: the quantisation alone moves the "
            f"percussions by more than {tol:g}"
        )
    fc = float(rec.attrs.get("sensor_bandwidth", float("nan")))
    product = fc * (te - ts) if np.isfinite(fc) else float("nan")
    if product < MIN_BANDWIDTH_PRODUCT:
        flags["filter bandwidth"] = (
            f"the stated bandwidth {fc:.4g} Hz times the contact duration {te - ts:.4g} s is "
            f"{product:.3g} < {MIN_BANDWIDTH_PRODUCT:g}: the low-pass smears the pulse and its "
            "tangential reversal"
        )
    curved = {c: v for c, v in base_err.items() if 3.0 * v > tol and base_z[c] > 3.0}
    if curved:
        flags["curved baseline"] = (
            ", ".join(f"{c}: {v:.2g} of its scale" for c, v in curved.items())
            + " left under the pulse by the linear baseline (a parabola fitted outside the "
            f"contact, {max(base_z[c] for c in curved):.3g} standard errors); three of it "
            f"exceed tol = {tol:g}"
        )
    fit_flags = {}
    off = {
        c: v
        for c, v in depart.items()
        if v > 0.5 * tol and not v <= 3.0 * noise_err.get(c, float("nan"))
    }
    if off:
        fit_flags["fit off the samples"] = (
            ", ".join(f"{c}: {v:.2g}" for c, v in off.items())
            + f" of its scale between the fit's percussion and the samples' Simpson integral, "
            f"above tol/2 = {0.5 * tol:g} and three noise standard deviations: the fitted "
            "curve misses the pulse; use the samples' integrals (source='simpson')"
        )
    if warn and flags:
        warnings.warn(
            "the record limits its percussions: "
            + "; ".join(f"{k}: {v}" for k, v in flags.items())
            + " (docs/stability.md names each region)",
            ResolutionWarning,
            stacklevel=2,
        )
    if warn and fit_flags:
        warnings.warn(
            f"fitted curve: {fit_flags['fit off the samples']}", PoorFitWarning, stacklevel=2
        )
    return Resolution(
        n_samples=n,
        noise_error=noise_err,
        adc_step=step,
        adc_error=adc_err,
        bandwidth_product=product,
        baseline_error=base_err,
        fit_departure=depart,
        flags=flags,
        fit_flags=fit_flags,
        tol=float(tol),
    )


def _baseline_left(record, window, name) -> tuple[float, float]:
    """What the window's linear baseline leaves in the channel's percussion [N·s], and its
    standard error: a parabola fitted by least squares to the raw channel minus that line
    outside the contact ± a quarter of its duration (where the line was fitted),
    integrated over the contact. (NaN, NaN) without a raw record or a fitted baseline."""
    nan = (float("nan"), float("nan"))
    base = window.baseline.get(name)
    if record is None or base is None or name not in record:
        return nan
    if base.offset == 0 and base.slope == 0:  # nothing fitted (digitised, simulated)
        return nan
    t, f = channel(record, name)
    ts, te = window.t_start, window.t_end
    g = 0.25 * (te - ts)
    out = (t < ts - g) | (t > te + g)
    if np.count_nonzero(out) < 10:
        return nan
    mid, half = 0.5 * (t[0] + t[-1]), 0.5 * (t[-1] - t[0])
    A = np.polynomial.legendre.legvander((t[out] - mid) / half, 2)
    coef, *_ = np.linalg.lstsq(A, (f - base(t))[out], rcond=None)
    resid = (f - base(t))[out] - A @ coef
    s2 = float(resid @ resid) / max(A.shape[0] - 3, 1)
    # ∫ over the contact of each Legendre term, exactly (Gauss–Legendre, 3 points)
    x, wq = np.polynomial.legendre.leggauss(3)
    tq = 0.5 * (ts + te) + 0.5 * (te - ts) * x
    v = (0.5 * (te - ts) * wq) @ np.polynomial.legendre.legvander((tq - mid) / half, 2)
    dP = float(v @ coef)
    se = float(np.sqrt(s2 * (v @ np.linalg.solve(A.T @ A, v))))
    return dP, se


def estimate_mu(window, t_c: float, *, level: float = 0.3, band: float = 0.1) -> float:
    """Friction coefficient from the record: Ft/Fn where the ball slides in compression [-].

    While the contact slides, Coulomb's law holds with equality, Ft/Fn = μ; once it sticks
    (the sticking regime, after corner A — often early in compression, docs/theory.md) or
    micro-slips, Ft/Fn < μ. So μ is the upper plateau of the ratio: over the samples before
    maximum compression ``t_c`` [s] where Fn exceeds ``level`` of its peak, the median of the
    ratios within ``band`` (relative) of their 95th percentile. For a record that slides
    throughout this is the median of nearly every ratio (a cut 10 % under the top removes
    only noise beyond a few σ); for a sticking record it skips the stuck samples. Returns
    NaN without an Ft channel or without such samples; needs some sliding samples above the
    level (a contact that sticks almost at once gives an estimate below μ).
    """
    rec = window.record
    if "Ft" not in rec:
        return float("nan")
    return mu_plateau(*channel(rec, "Fn"), *channel(rec, "Ft"), t_c, level=level, band=band)


def mu_plateau(t_n, f_n, t_t, f_t, t_c: float, *, level: float = 0.3, band: float = 0.1) -> float:
    """:func:`estimate_mu` on a contact's samples already cut and less their baselines:
    Fn at instants ``t_n`` [s], Ft at ``t_t`` [s] (forces [N]), maximum compression at
    ``t_c`` [s]. NaN without a sample before ``t_c`` above ``level`` of Fn's peak."""
    fn_at = f_n if t_n is t_t or np.array_equal(t_n, t_t) else np.interp(t_t, t_n, f_n)
    sel = (t_t <= t_c) & (fn_at > level * np.max(f_n))
    if not sel.any():
        return float("nan")
    r = f_t[sel] / fn_at[sel]
    top = float(np.quantile(r, 0.95))
    if top > 0:
        r = r[r >= (1.0 - band) * top]
    return float(np.median(r))
