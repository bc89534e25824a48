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
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ..errors import PoorFitWarning
from ..smooth import runs_test
from .engine import Problem
from .forward import UNITS
from .pulse import E_MIN
from .uncertainty import block_bootstrap, chi2_quantile, covariance, profile

__all__ = ["run_fit", "base_name"]

_RUNS_Z = -2.326  # one-sided α = 0.01 (pipeline.smooth.RUNS_ALPHA)
#: lmder's ftol and xtol: χ² falls by less than 1e-6 of itself, ~10⁻³ in χ² units for a
#: thousand samples, which moves a parameter by well under 10⁻² of its standard error
_TOL = 1e-6
#: how far above its value a parameter is pushed to see whether the data bound it above
_PUSH = 30.0


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
    if name == "leak":
        return (-0.5, 0.5)
    if name == "time_base":
        return (-0.1, 0.1)
    if name == "bandwidth":
        return (value / 20.0, value * 20.0)
    if name == "t0":
        dur = data.window.duration
        return (data.channels[0].t[0], data.window.t_start + 0.5 * dur)
    raise KeyError(name)  # pragma: no cover


def run_fit(model, datas, design, init, vary, notes, *, n_boot=0, seed=0) -> dict:
    """Drive lmfit on a Problem, then the uncertainty and identifiability (shared)."""
    import lmfit

    names = design.names
    varied = [n in vary for n in names]
    problem = Problem(model, datas, design, varied)
    params = lmfit.Parameters()
    lower = np.full(len(names), -np.inf)
    upper = np.full(len(names), np.inf)
    for i, n in enumerate(names):
        lo, hi = _bounds(base_name(n), init[n], datas[_rec(n, len(datas))])
        lower[i], upper[i] = lo, hi
        v = float(np.clip(init[n], lo, hi)) if varied[i] else float(init[n])
        if varied[i] and not (lo < v < hi):  # start strictly inside the bounds
            v = lo + 1e-6 * (hi - lo) if v <= lo else hi - 1e-6 * (hi - lo)
        params.add(
            n,
            value=v,
            vary=varied[i],
            min=lo if varied[i] else -np.inf,
            max=hi if varied[i] else np.inf,
        )
    order = list(names)

    def theta_of(p):
        return np.array([p[n].value for n in order])

    def fcn(p):
        return problem.residual(theta_of(p)).copy()

    def dfun(p):
        return problem.jacobian(theta_of(p)).copy()  # lmfit scales it in place

    mini = lmfit.Minimizer(fcn, params, nan_policy="raise")
    res = mini.leastsq(Dfun=dfun, col_deriv=0, ftol=_TOL, xtol=_TOL, max_nfev=2000)
    theta = theta_of(res.params)
    r, J = problem.residual(theta), problem.jacobian(theta)
    chi2 = float(r @ r)
    n = problem.n_data
    k = int(sum(varied))
    nuisance = sum(d.n_nuisance for d in datas)
    redchi = chi2 / max(n - k - nuisance, 1)
    cov = covariance(J, redchi)
    vidx = np.flatnonzero(varied)
    # ---- one-sided parameters (μ, kt_scale): is χ² flat up to 30× the fitted value?
    profiles, lower_only = _one_sided(problem, theta, chi2, redchi, lower, upper, names, vidx)
    for nm in lower_only:
        notes.append(_why_lower_only(nm, model))
    # ---- bootstrap
    boot, blocks = None, {}
    if n_boot > 0:
        boot, blocks = block_bootstrap(
            problem, theta, r, J, n_boot=n_boot, seed=seed, lower=lower, upper=upper
        )
    # ---- parameters with their uncertainty, for lmfit's report
    for j, i in enumerate(vidx):
        par = res.params[names[i]]
        par.stderr = math.sqrt(cov[j, j]) if np.isfinite(cov[j, j]) else None
        par.correl = {}
        for jj, ii in enumerate(vidx):
            if ii != i and np.isfinite(cov[j, jj]) and par.stderr and cov[jj, jj] > 0:
                par.correl[names[ii]] = cov[j, jj] / math.sqrt(cov[j, j] * cov[jj, jj])
    # ---- poor fit?
    poor_reasons = []
    lim = 1.0 + 5.0 * math.sqrt(2.0 / max(n - k - nuisance, 1))
    if redchi > lim:
        poor_reasons.append(f"χ²_ν = {redchi:.3g} > {lim:.3g}")
    start = 0
    for d in datas:
        for c in d.channels:
            z = float(runs_test(r[start : start + c.t.size]))
            start += c.t.size
            if np.isfinite(z) and z < _RUNS_Z:
                poor_reasons.append(f"{c.name} residual signs run in long stretches (z = {z:.3g})")
    if not res.success:
        poor_reasons.append(f"the minimiser did not converge: {res.message}")
    poor = bool(poor_reasons)
    if poor:
        msg = (
            f"{model.name} fit of {datas[0].record.attrs.get('source', 'the record')}: "
            + "; ".join(poor_reasons)
            + " — the model misses structure in the record; try another model (select_model)"
        )
        notes.append(msg)
        warnings.warn(msg, PoorFitWarning, stacklevel=3)
    kwargs = dict(
        names=tuple(names),
        theta=theta,
        varied=tuple(varied),
        cov=cov,
        chi2=chi2,
        n_data=n,
        n_nuisance=nuisance,
        params=res.params,
        result=res,
        boot=boot,
        blocks=blocks,
        profiles=profiles,
        lower_only=tuple(lower_only),
        notes=tuple(notes),
        poor=poor,
        model=model,
        problem=problem,
    )
    return kwargs


def _one_sided(problem, theta, chi2, redchi, lower, upper, names, vidx):
    """Profiles of μ and kt_scale where the data bound them only from below.

    Screen: each candidate held at 30× its value, the others refitted (all at once); where
    Δχ² stays under χ²₁(0.99) (scaled like the covariance) the parameter has no upper bound
    and its profile below the value gives the one-sided lower bound (module
    :mod:`pipeline.fit.uncertainty`).
    """
    cand = [i for i in vidx if base_name(names[i]) in ("mu", "kt_scale") and theta[i] > 0]
    if not cand:
        return {}, []
    scale = max(1.0, redchi)
    limit = chi2_quantile(0.99) * scale
    top = np.minimum(theta[cand] * _PUSH, upper[cand])
    pushed = np.repeat(theta[None, :], len(cand), axis=0)
    pushed[np.arange(len(cand)), cand] = top
    # χ² at the pushed value with the others held bounds the refitted one from above: below
    # the limit the parameter is certainly unbounded; far above it, certainly bounded
    d_top = np.einsum("bn,bn->b", *(2 * (problem.evaluate(pushed)[0],))) - chi2
    unsure = [j for j, d in enumerate(d_top) if limit <= d < 100 * limit]
    for j in unsure:
        i = cand[j]
        d_top[j] = profile(problem, theta, i, [top[j]], lower=lower, upper=upper, iters=3)[0] - chi2
    profiles, lower_only = {}, []
    for i, t, d in zip(cand, top, d_top, strict=True):
        if d >= limit:
            continue
        grid = np.concatenate([theta[i] * np.geomspace(1 / _PUSH, 1, 10), [t]])
        grid = np.clip(grid, max(lower[i], 1e-9), upper[i])
        dd = np.maximum(profile(problem, theta, i, grid[:-1], lower=lower, upper=upper) - chi2, 0)
        profiles[names[i]] = (grid, np.append(dd, max(d, 0.0)))
        lower_only.append(names[i])
    return profiles, lower_only


def base_name(name):
    """``kt_scale_3`` → ``kt_scale`` (a campaign's per-record parameter); names as given."""
    head, _, tail = name.rpartition("_")
    return head if tail.isdigit() and head in UNITS else name


def _rec(name, n_records):
    """Record index of a per-record campaign parameter ``<name>_<i>`` (0 otherwise)."""
    tail = name.rsplit("_", 1)[-1]
    return int(tail) if tail.isdigit() and int(tail) < n_records else 0


def _why_lower_only(name, model) -> str:
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
