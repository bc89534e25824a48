"""How every fit proceeds: lmfit drives, then the uncertainty, the bounds and the checks.

:func:`run_fit` is shared by :func:`pipeline.fit.fit_contact` and
:func:`pipeline.fit.fit_campaign`:

1. lmfit's Levenberg–Marquardt (:class:`lmfit.Minimizer`, ``leastsq`` with the Jacobian of
   :class:`pipeline.fit.engine.Problem` as ``Dfun``) from the starting values, inside bounds
   (E* within a factor 20 of its start, e in [0.1, 1], μ ≥ 0, ``kt_scale`` in [10⁻³, 10³]:
   a step along a direction the data do not bound stays finite; t0 from
   the first fitted sample to mid-contact);
2. the covariance at the optimum (:func:`pipeline.fit.uncertainty.covariance`);
3. the one-sided parameters: μ and ``kt_scale`` are pushed to 30× their value with the
   others refitted; where χ² barely moves, the data bound them only from below, and their
   profile gives the bound (:mod:`pipeline.fit.uncertainty`);
4. the block bootstrap, when asked for;
5. the checks: a fit is *poor* when χ²_ν exceeds 1 + 5·√(2/(N − k)) (five standard
   deviations of χ²_ν for a model that fits to the measured noise), when the runs test on a
   channel's residual signs gives z < −2.326 (α = 0.01, as :mod:`pipeline.smooth`), or when
   the minimiser did not converge; a poor fit is flagged and a
   :class:`~pipeline.errors.PoorFitWarning` names the reason.

A fit read for its χ² and values alone (``lean``: the fits of the verdict's tables of laws
and filter orders, :func:`pipeline.fit_contact`) skips what nothing reads of it — the misfit
test, the standard errors and correlations of lmfit's parameters, and the covariance
where no parameter may be one-sided (the values of a one-sided one come from its
interval) — and keeps every number it has as a full fit has it.
"""

from __future__ import annotations

import functools
import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import PoorFitWarning
from ..smooth import runs_test
from .engine import Problem
from .forward import UNITS
from .pulse import E_MIN
from .uncertainty import block_bootstrap, chi2_quantile, covariance_parts, profile

__all__ = [
    "run_fit",
    "base_name",
    "misfit",
    "misfit_part",
    "misfit_of",
    "Misfit",
    "MisfitPart",
    "MisfitParts",
    "MISFIT_Z",
]

#: lmder's ftol and xtol: χ² falls by less than 1e-6 of itself, ~10⁻³ in χ² units for a
#: thousand samples, which moves a parameter by well under 10⁻² of its standard error
_TOL = 1e-6
#: how far above its value a parameter is pushed to see whether the data bound it above
_PUSH = 30.0


@functools.cache
def _minimizer():
    """lmfit's Minimizer without its own error bars. :func:`run_fit` sets every varied
    parameter's ``stderr`` and ``correl`` from the fit's covariance
    (:func:`~pipeline.fit.uncertainty.covariance_parts`, which knows the priors and the
    nuisance parameters), so lmfit's — scaled by its χ²_ν and turned into ``uncertainties``
    variables, ~0.4 ms a fit, a tenth of an exact point fit — would be computed only to be
    overwritten. lmfit still drives the fit and keeps its covariance in ``result.covar``
    (unscaled). lmfit is imported on the first fit, not with the package."""
    import lmfit

    class Minimizer(lmfit.Minimizer):
        def _calculate_uncertainties_correlations(self):
            self.result.errorbars = True

    return Minimizer


def _bounds(name, value, data):
    if name == "E_eff":
        return (value / 20.0, value * 20.0)
    if name == "e":
        return (E_MIN, 1.0)
    if name == "alpha":
        return (0.0, math.inf)
    if name == "mu":
        return (0.0, math.inf)
    if name == "kt_scale":
        return (1e-3, 1e3)
    if name == "mu_a":
        return (-1.0, 5.0)
    if name == "mu_b":
        return (-math.inf, math.inf)
    if name in ("speed", "mass", "radius"):
        return (value / 3.0, value * 3.0)
    if name in ("gain_n", "gain_t"):
        return (0.5, 2.0)
    if name in ("leak", "leak_tn"):
        return (-0.5, 0.5)
    if name == "time_base":
        return (-0.1, 0.1)
    if name in ("bandwidth", "resonance"):
        return (value / 20.0, value * 20.0)
    if name == "damping_ratio":
        return (1e-3, 0.95)
    if name == "discharge":
        return (value / 100.0, value * 100.0)
    if name in ("shift_n", "shift_t"):
        return (-math.inf, math.inf)
    if name == "shift_at":
        w = data.window
        return (w.t_start - 0.25 * w.duration, w.t_end + 0.25 * w.duration)
    if name == "shift_width":
        step = float(np.median(np.diff(data.channels[0].t))) / max(data.oversample, 1)
        return (2.0 * step, 2.0 * data.window.duration)
    if name == "t0":
        w = data.window
        return t0_bounds(data.channels[0].t[0], w.t_start, w.duration)
    raise KeyError(name)  # pragma: no cover


def t0_bounds(t_first, t_start, duration) -> tuple:
    """The onset's bounds [s]: from the first fitted sample ``t_first`` to the middle of the
    contact window (``t_start``, ``duration`` [s])."""
    return (t_first, t_start + 0.5 * duration)


def run_fit(
    model, datas, design, init, vary, notes, *, n_boot=0, seed=0, priors=None, lean=False
) -> dict:
    """Drive lmfit on a Problem, then the uncertainty and identifiability (shared).

    ``priors`` maps a parameter name to (stated value, standard uncertainty): a Gaussian
    constraint, one residual row (:mod:`pipeline.fit.engine`). ``lean``: a fit read for its
    χ² and values alone (module notes): ``misfit`` None, lmfit's parameters without
    ``stderr``, and ``cov`` (with its parts) None where no parameter may be one-sided."""
    import lmfit

    names = design.names
    varied = [n in vary for n in names]
    priors = {n: priors[n] for n in names if n in (priors or {}) and n in vary}  # index order
    problem = Problem(
        model, datas, design, varied, {names.index(n): pr for n, pr in priors.items()}
    )
    params = []  # the varied ones (lmfit's Parameters built once, by the Minimizer); the
    # fixed stay in ``base``
    lower = np.full(len(names), -np.inf)  # the varied parameters' bounds (the fixed never move)
    upper = np.full(len(names), np.inf)
    base = np.array([float(init[n]) for n in names])
    for i, n in enumerate(names):
        if not varied[i]:
            continue
        lo, hi = _bounds(base_name(n), init[n], datas[_rec(n, len(datas))])
        lower[i], upper[i] = lo, hi
        v = min(max(float(init[n]), lo), hi)
        if not (lo < v < hi):  # start strictly inside the bounds
            v = lo + 1e-6 * (hi - lo) if v <= lo else hi - 1e-6 * (hi - lo)
        params.append(lmfit.Parameter(n, value=v, min=lo, max=hi))
    order = [names[i] for i in np.flatnonzero(varied)]
    where = np.flatnonzero(varied)

    def theta_of(p):
        th = base.copy()
        th[where] = [p[n].value for n in order]
        return th

    def finite(a, what):
        # lmfit's nan_policy="raise", checked here (its check converts and sums every
        # array it is handed, on each of a fit's dozen calls)
        if not np.isfinite(a).all():
            raise ValueError(
                f"{model.name} fit: the model's {what} hold NaN or infinite values; "
                "Levenberg–Marquardt cannot go on"
            )
        return a.copy()

    def fcn(p):
        return finite(problem.residual(theta_of(p)), "residuals")

    def dfun(p):
        return finite(problem.jacobian(theta_of(p)), "derivatives")  # lmfit scales it in place

    mini = _minimizer()(fcn, params, nan_policy="propagate")
    res = mini.leastsq(Dfun=dfun, col_deriv=0, ftol=_TOL, xtol=_TOL, max_nfev=2000)
    theta = theta_of(res.params)
    r, J = problem.residual(theta), problem.jacobian(theta)
    n = problem.n_data
    chi2 = float(r @ r)
    chi2_prior = float(r[n:] @ r[n:])
    k_free = int(sum(varied)) - len(priors)  # a constrained parameter brings its own row
    nuisance = sum(d.n_nuisance for d in datas)
    redchi = (chi2 - chi2_prior) / max(n - k_free - nuisance, 1)
    vidx = np.flatnonzero(varied)
    parts = cov = None
    if not lean or n_boot > 0 or _candidates(theta, names, vidx, priors):
        parts = covariance_parts(J, n, redchi)
        problem.keep_gain(theta, parts.gain)  # the dynamics' bounds take it up
        cov = parts.total
    # ---- one-sided parameters (μ, kt_scale, a free bandwidth): χ² flat up to 30× the value?
    profiles, lower_only, upper_only = _one_sided(
        problem, theta, chi2, redchi, lower, upper, names, vidx, set(priors), cov
    )
    for nm in lower_only:
        notes.append(_why_lower_only(nm, model))
    for nm in upper_only:
        notes.append(_why_upper_only(nm))
    # ---- bootstrap
    boot, blocks = None, {}
    if n_boot > 0:
        boot, blocks = block_bootstrap(
            problem, theta, r, J, n_boot=n_boot, seed=seed, lower=lower, upper=upper,
            gain=parts.gain,
        )  # fmt: skip
    # ---- parameters with their uncertainty, for lmfit's report (a lean fit has none)
    for j, i in enumerate(() if lean else vidx):
        par = res.params[names[i]]
        par.stderr = math.sqrt(cov[j, j]) if np.isfinite(cov[j, j]) else None
        par.correl = {}
        for jj, ii in enumerate(vidx):
            if ii != i and np.isfinite(cov[j, jj]) and par.stderr and cov[jj, jj] > 0:
                par.correl[names[ii]] = cov[j, jj] / math.sqrt(cov[j, j] * cov[jj, jj])
    # ---- does the model describe the data? (one test for every fit: misfit())
    check = None if lean else misfit(r[:n], datas, k_free)
    poor_reasons = [] if lean else list(check.reasons)
    if not res.success:
        poor_reasons.append(f"the minimiser did not converge: {res.message}")
    poor = bool(poor_reasons)
    if poor:
        msg = (
            f"{model.name} fit of {datas[0].record.attrs.get('source', 'the record')}: "
            + "; ".join(poor_reasons)
            + " — the model misses structure in the record (see the fit's verdict)"
        )
        notes.append(msg)
        warnings.warn(msg, PoorFitWarning, stacklevel=3)
    kwargs = dict(
        names=tuple(names),
        theta=theta,
        varied=tuple(varied),
        cov=cov,
        cov_stat=None if parts is None else parts.stat,
        sys_weights=None if parts is None else parts.prior_weights,
        priors=dict(priors),
        chi2=chi2,
        chi2_prior=chi2_prior,
        n_data=n,
        n_nuisance=nuisance,
        params=res.params,
        result=res,
        boot=boot,
        blocks=blocks,
        profiles=profiles,
        lower_only=tuple(lower_only),
        upper_only=tuple(upper_only),
        notes=tuple(notes),
        poor=poor,
        misfit=check,
        model=model,
        problem=problem,
    )
    return kwargs


@dataclass(frozen=True)
class Misfit:
    """Does a model describe a record's data? The one test every fit and ``select_model``
    use (:func:`misfit`).

    Attributes
    ----------
    redchi : float — χ²_ν of the (whitened) data residuals
    chi2_z : float — (χ²_ν − 1) over its standard deviation under a correct model
    runs_z : dict — runs-test z of each channel's residual signs (``"i:name"`` for record
        i's of a fit over many records; of :class:`MisfitParts`, a read-only mapping read
        from their array)
    reasons : tuple of str — what failed ("" when the model describes the data)
    """

    redchi: float
    chi2_z: float
    runs_z: dict
    reasons: tuple

    @property
    def ok(self) -> bool:
        return not self.reasons


#: One-sided z of each of the three tests (χ²_ν too high; Fn's, Ft's residual signs running
#: in long stretches): α = 0.005 each, at most 1.5 % false alarms in all on records the model
#: describes (measured: ``make bench``, misspec, the control).
MISFIT_Z = 2.576
#: Relative variance of a noise variance measured by the MAD: 2/(0.37·n), the MAD's
#: efficiency of 37 % under Gaussian noise (Hampel 1974).
_MAD_VAR = 2.0 / 0.37


def misfit(r, datas, k_free) -> Misfit:
    """The misfit test on weighted (whitened) data residuals ``r`` (records and channels in
    order) of a fit with ``k_free`` free parameters.

    χ²_ν is judged against its spread under a correct model: 2/ν from the residuals and the
    uncertainty of the measured noise levels themselves (each channel's σ from its samples
    outside the contact, ~5.4/n_noise in variance), so a record with few trigger samples is
    not called poor for its noise estimate; the signs of each channel's residuals by the
    runs test (Wald & Wolfowitz 1940). Either beyond :data:`MISFIT_Z` is a misfit.
    """
    parts, start = [], 0
    for d in datas:
        parts.append(misfit_part(r[start : start + d.n_data], d))
        start += d.n_data
    return misfit_of(parts, k_free, sum(d.n_nuisance for d in datas))


@dataclass(frozen=True)
class MisfitPart:
    """One record's share of the misfit test (:func:`misfit_part`), so that a fit over many
    records need not keep their residuals.

    Attributes
    ----------
    chi2 : float — the record's Σr²
    sizes : tuple of int — samples of each channel
    n_noise : tuple of int — samples each channel's σ was measured on (0: not measured)
    runs : tuple of (str, float) — each channel's name and runs-test z
    """

    chi2: float
    sizes: tuple
    n_noise: tuple
    runs: tuple


def misfit_part(r, data) -> MisfitPart:
    """The misfit test's share of one record with weighted residuals ``r`` (its channels in
    order)."""
    runs, start = [], 0
    for c in data.channels:
        runs.append((c.name, float(runs_test(r[start : start + c.t.size]))))
        start += c.t.size
    return MisfitPart(
        float(r @ r),
        tuple(c.t.size for c in data.channels),
        tuple(c.n_noise for c in data.channels),
        tuple(runs),
    )


class MisfitParts(Sequence):
    """Many records' shares of the misfit test as arrays, so that a fit over many records
    keeps no Python object a record (:func:`pipeline.fit.blocks.solve_blocks`): a sequence
    of :class:`MisfitPart`, made on access.

    Parameters
    ----------
    channels : tuple of str — the channels of every record, in order
    chi2 : numpy.ndarray (R,) — each record's Σr²
    sizes, n_noise : numpy.ndarray (R, C) of int — each channel's samples, and the samples
        its σ was measured on (0: not measured)
    runs : numpy.ndarray (R, C) — each channel's runs-test z
    """

    def __init__(self, channels, chi2, sizes, n_noise, runs):
        self.channels = tuple(channels)
        self.chi2, self.sizes, self.n_noise, self.runs = chi2, sizes, n_noise, runs

    @classmethod
    def empty(cls, n: int, channels) -> MisfitParts:
        """Room for ``n`` records' shares (:meth:`set` fills them)."""
        c = len(channels)
        ints = np.zeros((n, c), dtype=np.int32)
        return cls(channels, np.zeros(n), ints, ints.copy(), np.zeros((n, c)))

    def set(self, i, r, data) -> None:
        """Record ``i``'s share, of its weighted residuals ``r`` (:func:`misfit_part`)."""
        if tuple(c.name for c in data.channels) != self.channels:
            raise ValueError(f"record {i}'s channels are not {self.channels}")
        p = misfit_part(r, data)
        self.chi2[i], self.sizes[i], self.n_noise[i] = p.chi2, p.sizes, p.n_noise
        self.runs[i] = [z for _, z in p.runs]

    def put(self, a, parts: MisfitParts) -> None:
        """``parts`` (of records a, a + 1, ...) in their place."""
        b = a + len(parts)
        self.chi2[a:b], self.sizes[a:b] = parts.chi2, parts.sizes
        self.n_noise[a:b], self.runs[a:b] = parts.n_noise, parts.runs

    def __len__(self) -> int:
        return self.chi2.size

    def __getitem__(self, i) -> MisfitPart:
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(len(self)))]
        return MisfitPart(
            float(self.chi2[i]),
            tuple(int(x) for x in self.sizes[i]),
            tuple(int(x) for x in self.n_noise[i]),
            tuple(zip(self.channels, (float(z) for z in self.runs[i]), strict=True)),
        )


class _RunsZ(Mapping):
    """The runs-test z of many records' channels as :attr:`Misfit.runs_z` gives them
    (``"i:name"`` → z, record-major), read from a (R, C) array: no entry a channel kept."""

    def __init__(self, channels, runs):
        self._channels, self._runs = tuple(channels), runs

    def _key(self, i, c):
        return f"{i}:{self._channels[c]}"

    def __getitem__(self, key):
        i, _, name = str(key).partition(":")
        if i.isdigit() and int(i) < len(self._runs) and name in self._channels:
            c = self._channels.index(name)
            if self._key(int(i), c) == key:
                return float(self._runs[int(i), c])
        raise KeyError(key)

    def __iter__(self):
        R, C = self._runs.shape
        return (self._key(i, c) for i in range(R) for c in range(C))

    def __len__(self) -> int:
        return self._runs.size

    def __repr__(self):
        return f"<runs-test z of {len(self)} channels>"


#: Channels whose runs test failed named one by one in a misfit's reasons; beyond, a count.
_RUNS_LISTED = 4


def misfit_of(parts, k_free, nuisance) -> Misfit:
    """The misfit test (:func:`misfit`) from each record's :class:`MisfitPart` (or the
    records' :class:`MisfitParts`, without an object a record), with ``k_free`` free and
    ``nuisance`` baseline parameters."""
    if isinstance(parts, MisfitParts) and len(parts) > 1:
        return _misfit_of_arrays(parts, k_free, nuisance)
    n = sum(sum(p.sizes) for p in parts)
    nu = max(n - k_free - nuisance, 1)
    redchi = sum(p.chi2 for p in parts) / nu
    var = 2.0 / nu
    runs = {}
    for i, p in enumerate(parts):
        for size, n_noise, (name, z) in zip(p.sizes, p.n_noise, p.runs, strict=True):
            share = size / n
            if n_noise:
                var += share * share * _MAD_VAR / n_noise
            runs[name if len(parts) == 1 else f"{i}:{name}"] = z
    long = [(rz, key) for key, rz in runs.items() if np.isfinite(rz) and rz < -MISFIT_Z]
    return _misfit(redchi, var, runs, long)


def _misfit_of_arrays(parts, k_free, nuisance) -> Misfit:
    """:func:`misfit_of` of :class:`MisfitParts`: the same sums in the same order, and only
    the channels whose signs run long named (their keys made for those alone)."""
    n = int(parts.sizes.sum())
    nu = max(n - k_free - nuisance, 1)
    redchi = sum(parts.chi2.tolist()) / nu
    var = 2.0 / nu
    sizes, noise = parts.sizes.ravel().tolist(), parts.n_noise.ravel().tolist()
    for size, n_noise in zip(sizes, noise, strict=True):  # record after record, as above
        if n_noise:
            share = size / n
            var += share * share * _MAD_VAR / n_noise
    runs = _RunsZ(parts.channels, parts.runs)
    with np.errstate(invalid="ignore"):
        flat = np.flatnonzero(np.isfinite(parts.runs) & (parts.runs < -MISFIT_Z))
    count = flat.size
    if count > _RUNS_LISTED:  # only the worst are named: the ties at the fourth too
        z = parts.runs.ravel()[flat]
        flat = flat[z <= np.partition(z, _RUNS_LISTED - 1)[_RUNS_LISTED - 1]]
    C = len(parts.channels)
    long = [(float(parts.runs.flat[k]), runs._key(k // C, k % C)) for k in flat]
    return _misfit(redchi, var, runs, long, count)


def _misfit(redchi, var, runs, long, count=None) -> Misfit:
    """The :class:`Misfit` of χ²_ν, the variance of its spread, every channel's runs z and
    ``long``: (z, key) of the channels whose signs run long (in their order; of ``count``
    such channels, the worst of them at least)."""
    count = len(long) if count is None else count
    z = (redchi - 1.0) / math.sqrt(var)
    reasons = []
    if z > MISFIT_Z:
        reasons.append(f"χ²_ν = {redchi:.3g} ({z:.1f} standard deviations above 1)")
    if count > _RUNS_LISTED:  # the worst, then how many more
        long = sorted(long)
    for rz, key in long[:_RUNS_LISTED]:
        reasons.append(f"{key} residual signs run in long stretches (z = {rz:.3g})")
    if count > _RUNS_LISTED:
        reasons.append(
            f"and {count - _RUNS_LISTED} more of the {len(runs)} channels' residual "
            "signs run in long stretches"
        )
    return Misfit(redchi, float(z), runs, tuple(reasons))


def _clearly_bounded(problem, theta, names, vidx, cov, limit) -> set:
    """The one-sided candidates the physics already shows bounded above, so the screen
    need not push them: μ where a tenth or more of the normal percussion is delivered at
    the Coulomb cap, ``kt_scale`` where the slip stops and a tenth or more is delivered
    sticking — each only where its linearised Δχ² at 30× its value (from the covariance)
    exceeds 100 times the limit, so that a noisy record is still screened. One record's
    fit only (a campaign's is always screened)."""
    if cov is None:
        return set()
    sols = problem.solution(theta)
    if len(sols) != 1 or sols[0] is None or getattr(sols[0], "tang", None) is None:
        return set()
    tang, k = sols[0].tang, int(sols[0].index[0])
    share, stops = float(tang.slide_share[k]), bool(tang.slip_stops[k])
    out = set()
    for j, i in enumerate(vidx):
        var = cov[j, j]
        if not (np.isfinite(var) and var > 0):
            continue
        steep = (theta[i] * (_PUSH - 1)) ** 2 / var > 100 * limit
        if names[i] == "mu" and share >= 0.1 and steep:
            out.add("mu")
        if names[i] == "kt_scale" and stops and share <= 0.9 and steep:
            out.add("kt_scale")
    return out


def _one_sided(problem, theta, chi2, redchi, lower, upper, names, vidx, constrained=(), cov=None):
    """Profiles of μ, kt_scale and a free bandwidth where the data bound them on one side
    only (a prior bounds a constrained one on both sides).

    Screen: each candidate held at 30× its value, the others refitted (all at once); where
    Δχ² stays under χ²₁(0.99) (scaled like the covariance) the parameter has no upper bound
    and its profile below the value gives the one-sided lower bound (module
    :mod:`pipeline.fit.uncertainty`). A candidate bounded above whose χ² is flat at the
    optimum (its covariance has no finite variance: a tangential spring whose stiffness
    matters only where a slip would stop, so a range of stiffnesses slides alike) is
    profiled both ways from a 30th of its value to 30×: where the profile stays under the
    limit at the bottom, the data bound it only from above; else its profile gives both
    ends of its interval.

    Returns
    -------
    (profiles, lower_only, upper_only) — {name: (grid, Δχ²)} and the two name lists; a
    profiled parameter in neither list has a two-sided profile interval
    """
    cand = _candidates(theta, names, vidx, constrained)
    if not cand:
        return {}, [], []
    scale = max(1.0, redchi)
    limit = chi2_quantile(0.99) * scale
    clear = _clearly_bounded(problem, theta, names, vidx, cov, limit)
    cand = [i for i in cand if names[i] not in clear]
    if not cand:
        return {}, [], []
    d_top = _pushed(problem, theta, chi2, cand, theta[cand] * _PUSH, lower, upper, limit)
    profiles, lower_only, upper_only = {}, [], []
    var = {i: cov[j, j] for j, i in enumerate(vidx)} if cov is not None else {}
    for i, d in zip(cand, d_top, strict=True):
        if d < limit or (np.isfinite(var.get(i, math.nan)) and var[i] > 0):
            continue
        grid = np.clip(theta[i] * np.geomspace(1 / _PUSH, _PUSH, 21), lower[i], upper[i])
        dd = np.maximum(profile(problem, theta, i, grid, lower=lower, upper=upper) - chi2, 0)
        if dd[0] < limit:  # flat down to a 30th: bounded only from above
            profiles[names[i]] = (grid[10:], dd[10:])
            upper_only.append(names[i])
        else:
            profiles[names[i]] = (grid, dd)
    for i, d in zip(cand, d_top, strict=True):
        if d >= limit:
            continue
        t = np.minimum(theta[i] * _PUSH, upper[i])
        grid = np.concatenate([theta[i] * np.geomspace(1 / _PUSH, 1, 10), [t]])
        grid = np.clip(grid, max(lower[i], 1e-9), upper[i])
        dd = np.maximum(profile(problem, theta, i, grid[:-1], lower=lower, upper=upper) - chi2, 0)
        profiles[names[i]] = (grid, np.append(dd, max(d, 0.0)))
        lower_only.append(names[i])
    return profiles, lower_only, upper_only


#: The parameters the data may bound on one side only (:func:`_one_sided`).
_ONE_SIDED = ("mu", "kt_scale", "bandwidth")


def _candidates(theta, names, vidx, constrained) -> list:
    """The varied parameters (indices into θ, in order) :func:`_one_sided` looks at: μ,
    ``kt_scale`` and a bandwidth above zero without a prior."""
    return [
        i
        for i in vidx
        if base_name(names[i]) in _ONE_SIDED and theta[i] > 0 and names[i] not in constrained
    ]


def _pushed(problem, theta, chi2, idx, targets, lower, upper, limit) -> np.ndarray:
    """Δχ² with parameter ``idx[j]`` held at ``targets[j]`` (clipped to its bounds): χ²
    with the others held bounds the refitted one from above, so below ``limit`` it
    certainly stays below, far above it (100×) certainly above; only the cases between
    are refitted (three iterations of the profile)."""
    idx = list(idx)
    targets = np.clip(targets, lower[idx], upper[idx])
    pushed = np.repeat(theta[None, :], len(idx), axis=0)
    pushed[np.arange(len(idx)), idx] = targets
    r = problem.evaluate(pushed)[0]
    d = np.einsum("bn,bn->b", r, r) - chi2
    for j in np.flatnonzero((d >= limit) & (d < 100 * limit)):
        prof = profile(problem, theta, idx[j], [targets[j]], lower=lower, upper=upper, iters=3)
        d[j] = prof[0] - chi2
    return d


def base_name(name):
    """``kt_scale_3`` → ``kt_scale`` (a campaign's per-record parameter); names as given."""
    head, _, tail = name.rpartition("_")
    return head if tail.isdigit() and head in UNITS else name


def _rec(name, n_records):
    """Record index of a per-record campaign parameter ``<name>_<i>`` (0 otherwise)."""
    tail = name.rsplit("_", 1)[-1]
    return int(tail) if tail.isdigit() and int(tail) < n_records else 0


def _why_upper_only(name) -> str:
    return (
        f"{name}: the data bound it only from above — the slip stops (if at all) only where "
        "the stiffness decides it, so any softer contact, sliding throughout, gives the same "
        "forces; its value is the one-sided upper bound"
    )


def _why_lower_only(name, model) -> str:
    if name == "bandwidth":
        return (
            "bandwidth: the record does not resolve the sensor's filter — any wider one gives "
            "the same samples; its value is the one-sided lower bound"
        )
    if name.startswith("mu"):
        return (
            f"{name}: the data bound it only from below — the contact never reaches the Coulomb "
            "cap where it matters (it sticks), so any larger μ gives the same forces; its value "
            "is the one-sided lower bound"
        )
    return (
        f"{name}: the data bound it only from below — the contact slides (or its tangential "
        "spring is never the limit), so any stiffer contact gives the same forces; its value "
        "is the one-sided lower bound"
    )
