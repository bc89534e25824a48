r"""Uncertainty of fitted parameters: covariance, block bootstrap, profiles and bounds.

**Covariance.** :math:`C = (J^\top J)^{-1}\,\max(1, \chi^2_\nu)` with J the Jacobian of
the weighted residuals at the optimum: the weights come from the noise measured outside the
contact, so :math:`\chi^2_\nu \approx 1` for a model that fits; a fit worse than the noise
(structure left in the residuals) widens the intervals, a fit that looks better than the
noise does not narrow them. Its interval is :math:`\hat\theta \pm z\,\sigma`.

**Block bootstrap of residuals.** The residuals of a sensor record need not be independent
(a filter after the noise source correlates neighbours), and ignoring that makes intervals
too narrow. Replicates y* = model + σ·r*, with r* drawn as circular blocks of the weighted
residual series of each channel (Politis & Romano 1992), rescaled by √(N/(N − p)) for the
fitted degrees of freedom (Davison & Hinkley 1997, §6.2.3), are refitted all at once
(:func:`pipeline.fit.engine.gauss_newton_many`); the interval is the percentile interval of
the refits. The block length is chosen from the residuals' autocorrelation by the rule of
Politis & White (2004, with the correction of Patton, Politis & White 2009) for the
circular block bootstrap, :math:`b = (2\hat G^2/\hat D)^{1/3} N^{1/3}`, which is 1 (the
ordinary residual bootstrap) for white residuals.

**Profiles and identifiability.** Some parameters are bounded by the data on one side only:
μ in an impact that sticks throughout (any μ above the largest Ft/Fn the contact needed
gives the same forces), ``kt_scale`` in one that slides throughout (any stiffness above the
one that would stick). For those the fit profiles χ² (the others refitted at each point)
over a factor 30 each way; where χ² stays within :math:`\chi^2_1(0.99)` of its minimum up to
the largest value, the parameter is reported as not identifiable, with its lower bound at
the requested level (a one-sided bound: :math:`\Delta\chi^2 = z_{level}^2` scaled like the
covariance) and +inf as the upper end of its interval.

References
----------
D. N. Politis, J. P. Romano, "A circular block-resampling procedure for stationary data",
in *Exploring the Limits of Bootstrap*, Wiley (1992) 263–270.
D. N. Politis, H. White, Econometric Rev. 23:53 (2004), doi:10.1081/ETC-120028836;
A. Patton, D. N. Politis, H. White, Econometric Rev. 28:372 (2009),
doi:10.1080/07474930802459016.
A. C. Davison, D. V. Hinkley, *Bootstrap Methods and their Application*, CUP (1997),
doi:10.1017/CBO9780511802843.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import special

from .engine import Problem, _gain, _pseudo_inverse, _scaled_svd, gauss_newton_many

__all__ = [
    "covariance",
    "block_length",
    "block_bootstrap",
    "profile",
    "normal_interval",
    "percentile_interval",
    "one_sided_bound",
]


@dataclass(frozen=True)
class CovarianceParts:
    """The covariance of the varied parameters split by where the uncertainty comes from.

    The linearised estimator is δθ = K·r with K = (JᵀJ)⁻¹Jᵀ over every residual row: the
    data's and one per prior (a systematic). Rows are independent sources, so
    Cov = K Kᵀ = Σ_data rows + Σ_each prior row exactly (GUM §5.1 with uncorrelated
    inputs): ``stat`` is the data rows' part (scaled by max(1, χ²_ν) as the covariance),
    ``prior_weights`` the column of K of each prior row, whose square is that systematic's
    variance contribution to each parameter.

    Attributes
    ----------
    total : numpy.ndarray (p, p) — stat plus every systematic's part
    stat : numpy.ndarray (p, p)
    prior_weights : numpy.ndarray (p, n_priors) — ∂θ/∂(prior row), in parameter units per
        standard uncertainty of that input
    gain : numpy.ndarray (p, rows) — K itself (the bootstrap's linearised refits use it)
    """

    total: np.ndarray
    stat: np.ndarray
    prior_weights: np.ndarray
    gain: np.ndarray | None = None


def _null_directions(Vt, good):
    """Parameters with a part in the directions J leaves free (no finite variance)."""
    if np.all(good):
        return np.zeros(Vt.shape[1], bool)
    return np.abs(Vt[~good]).max(axis=0) > 1e-6


def covariance_parts(J, n_data, redchi) -> CovarianceParts:
    """:class:`CovarianceParts` of a Jacobian J whose first ``n_data`` rows are the data's
    and the rest one per prior (one SVD: K = (JᵀJ)⁻¹Jᵀ and the free directions)."""
    J = np.asarray(J, dtype=float)
    s, U, w, Vt, good = _scaled_svd(J)
    K = _gain(s, U, w, Vt, good)  # (p, rows)
    scale = max(1.0, float(redchi))
    Kd, Kp = K[:, :n_data], K[:, n_data:]
    stat = (Kd @ Kd.T) * scale
    total = stat + Kp @ Kp.T
    bad = _null_directions(Vt, good)
    if bad.any():  # directions the data and the priors leave free
        for m in (stat, total):
            m[bad, :] = np.nan
            m[:, bad] = np.nan
    return CovarianceParts(total, stat, Kp, K)


def covariance(J, redchi):
    """(JᵀJ)⁻¹·max(1, χ²_ν) by SVD of the column-scaled Jacobian; NaN rows where singular."""
    s, U, w, Vt, good = _scaled_svd(np.asarray(J, dtype=float))
    inv = (Vt[good].T / w[good] ** 2) @ Vt[good]
    cov = inv / np.outer(s, s) * max(1.0, float(redchi))
    null = _null_directions(Vt, good)
    cov[null, :] = np.nan
    cov[:, null] = np.nan
    return cov


def _acf(x, max_lag):
    x = np.asarray(x, dtype=float) - np.mean(x)
    n = x.size
    var = float(np.dot(x, x)) / n
    if var == 0:
        return np.zeros(max_lag + 1)
    return np.array([np.dot(x[: n - k], x[k:]) / n / var for k in range(max_lag + 1)])


def block_length(r) -> int:
    """Circular-block-bootstrap block length of a series (Politis–White rule, module notes)."""
    r = np.asarray(r, dtype=float)
    n = r.size
    if n < 10:
        return 1
    kn = max(5, int(math.ceil(math.sqrt(math.log10(n)))))
    max_lag = min(n - 1, max(2 * kn, int(math.ceil(math.sqrt(n))) + kn))
    rho = _acf(r, max_lag)
    c = 2.0 * math.sqrt(math.log10(n) / n)
    m_hat = max_lag - kn
    for m in range(0, max_lag - kn + 1):
        if np.all(np.abs(rho[m + 1 : m + 1 + kn]) < c):
            m_hat = m
            break
    M = 2 * m_hat
    if M == 0:
        return 1
    k = np.arange(-M, M + 1)
    s = np.abs(k) / M
    lam = np.where(s <= 0.5, 1.0, np.where(s <= 1.0, 2.0 * (1.0 - s), 0.0))
    acov = _acf(r, M) * np.var(r)
    R = acov[np.abs(k)]
    G = float(np.sum(lam * np.abs(k) * R))
    g0 = float(np.sum(lam * R))
    D = 4.0 / 3.0 * g0 * g0
    if D <= 0:
        return 1
    b = (2.0 * G * G / D) ** (1.0 / 3.0) * n ** (1.0 / 3.0)
    return int(min(max(1, math.ceil(b)), max(1, n // 3)))


#: Replicates resampled at a time by :func:`block_bootstrap`: a chunk's draws and resampled
#: residuals (~200 kB each for a thousand samples) stay in the cache and in memory already
#: mapped, where all 200 replicates' (1.6 MB each) land on fresh pages every fit (~0.8 ms of
#: page faults on a record of a thousand samples, more than the draws themselves).
_CHUNK = 25


def _circular_blocks(rng, r, b, B):
    """B circular-block resamples of the series r (block length b), shape (B, n)."""
    n = r.size
    nb = int(math.ceil(n / b))
    starts = rng.integers(0, n, size=(B, nb))
    if b == 1:  # white residuals: each draw is a sample (the same draws, no index arithmetic)
        return r[starts]
    # the series wrapped once, its windows of b samples (copied whole: gathering rows of a
    # contiguous array is several times faster than of the strided view): each draw
    # gathers whole blocks
    wrapped = np.concatenate([r, r[: b - 1]])
    windows = np.lib.stride_tricks.sliding_window_view(wrapped, b).copy()
    return windows.take(starts, axis=0).reshape(B, -1)[:, :n]


def block_bootstrap(
    problem: Problem, theta, r, J, *, n_boot, seed, lower, upper, iters=0, gain=None
):
    """Refits of block-bootstrap replicates of the weighted residuals ``r`` (module notes).

    Every replicate is refitted at once. By default (``iters=0``) the refit is the
    Gauss–Newton step from the optimum with the fit's Jacobian, θ* = θ̂ − K(r + Δy),
    K = (JᵀJ)⁻¹Jᵀ, clipped to the bounds: one matrix product for each channel's chunk of
    :data:`_CHUNK` replicates (drawn a chunk at a time, the same draws), no model
    evaluation. The replicates move the parameters by about their standard error, where
    the model is linear to far better than the noise: iterated refits
    (``iters`` > 0: simplified Gauss–Newton, :func:`pipeline.fit.engine.gauss_newton_many`,
    one vectorised model call per iteration) move no interval bound by more than ~1e-5 of
    its value on the bundled records, and a refit of each replicate alone by lmfit gives
    the same intervals (``tests/test_fit_contact.py``).

    Parameters
    ----------
    problem : Problem — the fitted problem
    theta : numpy.ndarray (p,) — the fitted parameters
    r : numpy.ndarray (N,) — weighted residuals at ``theta`` (records and channels in the
        problem's order; the prior rows last, which keep their centres)
    J : numpy.ndarray (N, n_vary) — their Jacobian
    n_boot : int — replicates; seed : int — of the resampling
    lower, upper : numpy.ndarray (p,) — bounds
    iters : int — Gauss–Newton iterations beyond the first step (0: the linearised refit)
    gain : numpy.ndarray (n_vary, N), optional — K = (JᵀJ)⁻¹Jᵀ where already computed
        (:func:`covariance_parts`)

    Returns
    -------
    Theta : numpy.ndarray (n_boot, p) — the refits; blocks : dict — block length per series
    """
    rng = np.random.default_rng(seed)
    n = problem.n_data  # the data's rows; the prior rows keep their centres
    p = problem.vary.size - problem.prior_index.size
    p += sum(d.n_nuisance for d in problem.datas)
    inflate = math.sqrt(n / max(n - p, 1))
    v = problem.vary
    if iters > 0:  # y* = model + σ·r*: in weighted units the data change by r* − r
        dy = np.zeros((n_boot, r.size))
    else:  # θ* = θ̂ − K·(inflate·r*, r_prior): the data rows' part summed channel by channel
        K = _pseudo_inverse(np.asarray(J, dtype=float)) if gain is None else gain
        step = np.zeros((n_boot, v.size))
    blocks, start = {}, 0
    for i, d in enumerate(problem.datas):
        for c in d.channels:
            cols = slice(start, start + c.t.size)
            seg = r[cols]
            b = block_length(seg)
            blocks[f"{i}:{c.name}"] = b
            seg0 = seg - seg.mean()
            Kc = None if iters > 0 else np.ascontiguousarray(K[:, cols].T)  # (samples, p)
            # the replicates a chunk at a time, in order: the same draws as all at once
            for lo in range(0, n_boot, _CHUNK):
                hi = min(lo + _CHUNK, n_boot)
                drawn = _circular_blocks(rng, seg0, b, hi - lo)
                if iters > 0:
                    dy[lo:hi, cols] = inflate * drawn - seg
                else:
                    step[lo:hi] += drawn @ Kc
            start += c.t.size
    Theta0 = np.repeat(np.asarray(theta, float)[None, :], n_boot, axis=0)
    if iters > 0:
        Theta, _ = gauss_newton_many(
            problem, Theta0, dy, lower=lower, upper=upper, iters=iters, jacobian=J, r0=r, tol=0.01
        )
        return Theta, blocks
    # the replicate's residuals at θ̂ are its data rows inflate·r* and the prior rows as
    # they are
    step = inflate * step + r[n:] @ K[:, n:].T
    Theta0[:, v] = np.clip(Theta0[:, v] - step, lower[v], upper[v])
    return Theta0, blocks


def profile(problem: Problem, theta, k, grid, *, lower, upper, iters=4):
    """χ² along parameter ``k`` (index into θ) held at each ``grid`` value, the others
    refitted (all grid points at once)."""
    Theta0 = np.repeat(np.asarray(theta, float)[None, :], len(grid), axis=0)
    Theta0[:, k] = grid
    freeze = np.zeros(Theta0.shape[1], dtype=bool)
    freeze[k] = True
    _, chi2 = gauss_newton_many(
        problem, Theta0, lower=lower, upper=upper, iters=iters, freeze=freeze
    )
    return chi2


def normal_interval(value, stderr, level):
    z = float(special.ndtri(0.5 + level / 2.0))
    return (value - z * stderr, value + z * stderr)


def percentile_interval(samples, level):
    s = np.asarray(samples, dtype=float)
    s = s[np.isfinite(s)]
    if s.size < 10:
        return (math.nan, math.nan)
    a = (1.0 - level) / 2.0
    lo, hi = np.quantile(s, [a, 1.0 - a])
    return (float(lo), float(hi))


def one_sided_bound(grid, dchi2, level, scale=1.0):
    """Smallest grid value whose Δχ²/scale is within z_level² (a one-sided lower bound)."""
    z2 = float(special.ndtri(level)) ** 2
    grid = np.asarray(grid, dtype=float)
    d = np.asarray(dchi2, dtype=float) / scale
    inside = d <= z2
    if not inside.any():
        return math.nan
    i = int(np.argmax(inside))
    if i == 0:
        return float(grid[0])
    # interpolate Δχ² linearly between the last point outside and the first inside
    g0, g1, d0, d1 = grid[i - 1], grid[i], d[i - 1], d[i]
    return float(g0 + (z2 - d0) * (g1 - g0) / (d1 - d0))


def chi2_quantile(level, df=1):
    """The ``level`` quantile of χ² with ``df`` degrees of freedom."""
    return float(special.chdtri(df, 1.0 - level))
