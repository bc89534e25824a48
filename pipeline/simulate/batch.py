"""Many impacts at once, fixed-step and vectorised: the batch integrator behind
:func:`pipeline.simulate.impact_outcomes` (``_batch_group``, one group of scenes with one
normal law), which also builds the outcome tables of :mod:`pipeline.simulate.table`, and
:func:`tangential_history`, the tangential model driven by given normal histories (what the
contact-parameter fits use)."""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from .. import contact
from ..errors import InputError, PipelineWarning
from ._common import (
    _check_models,
    _first_contact_mode,
    _unique,
)

__all__ = ["TangentialHistory", "tangential_history"]


def _calibrate_many(law, e):
    e = np.asarray(e, dtype=float)
    uniq, inv = _unique(e.ravel())
    try:
        p = np.asarray(law.calibrate(uniq), dtype=float)
        if p.shape != uniq.shape:
            raise ValueError
    except (TypeError, ValueError) as err:
        if isinstance(err, InputError):
            raise
        p = np.array([float(law.calibrate(float(x))) for x in uniq])
    return p[inv.reshape(e.shape)]


#: dimensionless elastic Hertz impact: δ_max = 1, v0 = 1, m* = 1 (so K = F_max = 5/4)
_UNIT_HERTZ = contact.HertzImpact(1.0, 1.25, contact.HERTZ_TC_CONSTANT, 1.25, 1.0, 1.0)


#: Largest ω_t·h (ω_t = √(λ·k_t) the dimensionless tangential frequency at full overlap)
#: at which the fixed-step RK4 keeps its stated error; beyond it (k_t ≳ 50× Mindlin's at
#: the default step) the tangential error grows to ~5e-4 in Pt/(m*·v0).
_MAX_OMEGA_H = 0.15


def _check_tangential_step(lam, ktc, h, where):
    """Warn where the tangential spring is too stiff for the fixed step ``h``."""
    wh = np.sqrt(np.asarray(lam, dtype=float) * np.asarray(ktc, dtype=float)) * h
    bad = wh > _MAX_OMEGA_H
    if np.any(bad):
        warnings.warn(
            f"{where}: {int(bad.sum())} of {bad.size} contacts have a tangential stiffness too "
            f"high for the fixed step (ω_t·h up to {float(np.max(wh)):.2g} > {_MAX_OMEGA_H}); "
            "their tangential outcome exceeds the stated error. Use more steps.",
            PipelineWarning,
            stacklevel=3,
        )


class _MindlinRK4:
    """Tangential state (Pt, and ξ or Ft) of N scenes, advanced by RK4 (dimensionless).

    The Coulomb cap is applied inside the stages and the discrete history rule after each
    step: where spring plus tangential dashpot exceed the cap, the spring is set so that
    their sum is on it — for the total rule ξ = (±μFn − η_t·s)/k_t
    (:func:`pipeline.contact.mindlin_total` with zero increment when η_t = 0), for the
    incremental rule Ft_spring = ±μFn − η_t·s (:func:`pipeline.contact.mindlin_incremental`);
    written out as clips here for speed. ``start`` (from :func:`._common._first_contact_mode`)
    marks contacts that begin sliding backwards: their spring starts on the lower cap.
    """

    #: a spring state beyond any cap: the first step's clip and projection put it on the cap
    _ON_LOWER_CAP = -1e300

    def __init__(self, s0, lam, mu, ktc, history, xg=0.0, start=None):
        self.s0, self.lam, self.mu, self.ktc, self.xg = s0, lam, mu, ktc, xg
        self.total = history == "total"
        n = s0.size
        self.p = np.zeros(n)
        self.z = np.zeros(n)
        if start is not None:
            self.z = np.where(np.asarray(start) < 0, self._ON_LOWER_CAP, 0.0)
        self.ft_min = np.zeros(n)
        self.ft_max = np.zeros(n)
        self.ratio_max = np.zeros(n)  # max |Ft|/(μ·Fn) at the step ends in contact

    def rhs(self, sq, fn, eta, p, z):
        cap = self.mu * fn
        s = self.s0 - self.lam * p
        damp = self.xg * eta * s
        if self.total:
            return np.clip(self.ktc * z * sq + damp, -cap, cap), s
        return np.clip(z + damp, -cap, cap), self.ktc * sq * s

    def step(self, h, stages, end):
        """``stages``: (√x, fn, η) at τ, τ+h/2 (twice, RK4 stages 2 and 3) and τ+h, η the
        normal dashpot coefficient (dimensionless); ``end``: the same at the end of the
        step (for the history rule)."""
        p, z = self.p, self.z
        (q1, f1, e1), (q2, f2, e2), (q3, f3, e3), (q4, f4, e4) = stages
        a1, b1 = self.rhs(q1, f1, e1, p, z)
        a2, b2 = self.rhs(q2, f2, e2, p + 0.5 * h * a1, z + 0.5 * h * b1)
        a3, b3 = self.rhs(q3, f3, e3, p + 0.5 * h * a2, z + 0.5 * h * b2)
        a4, b4 = self.rhs(q4, f4, e4, p + h * a3, z + h * b3)
        self.p = p + h / 6.0 * (a1 + 2.0 * (a2 + a3) + a4)
        z = z + h / 6.0 * (b1 + 2.0 * (b2 + b3) + b4)
        qe, fe, ee = end
        cap = self.mu * fe
        damp = self.xg * ee * (self.s0 - self.lam * self.p)
        if self.total:
            k = self.ktc * qe
            with np.errstate(divide="ignore", invalid="ignore"):
                hi = np.where(k > 0, (cap - damp) / k, 0.0)
                lo = np.where(k > 0, (-cap - damp) / k, 0.0)
            self.z = np.clip(z, lo, hi)
        else:
            self.z = np.clip(z, -cap - damp, cap - damp)
        np.minimum(self.ft_min, a4, out=self.ft_min)
        np.maximum(self.ft_max, a4, out=self.ft_max)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.abs(self.force(qe, fe, ee)) / cap
        np.maximum(self.ratio_max, np.where(cap > 0, ratio, 0.0), out=self.ratio_max)

    def force(self, q, fn, eta):
        """Ft of the current state at √x = ``q``, fn, η (the state is already on the cap)."""
        damp = self.xg * eta * (self.s0 - self.lam * self.p)
        return (self.ktc * q * self.z if self.total else self.z) + damp


@dataclass(frozen=True)
class TangentialHistory:
    """Tangential percussion and force of N impacts at the step ends (dimensionless).

    Attributes
    ----------
    p : numpy.ndarray, shape (n + 1, N) — Pt/(m*·v0) at τ_k = k·h
    ft : numpy.ndarray, shape (n + 1, N) — Ft/(m*·v0²/δ_max) at τ_k (> 0 opposing the
        initial slip)
    """

    p: np.ndarray
    ft: np.ndarray


def tangential_history(
    q,
    fn,
    h,
    s0,
    lam,
    mu,
    kt_coef,
    *,
    tangential="mindlin",
    history="total",
    eta=None,
    tangential_damping=0.0,
    start=None,
) -> TangentialHistory:
    """The tangential model of N impacts driven by given normal histories (dimensionless).

    The batch path's tangential integrator (RK4 with the Coulomb cap inside the stages and
    the discrete history rule after each step, as :func:`impact_outcomes` uses it) on
    normal histories the caller supplies — e.g. a fitted normal law's tabulated pulse.

    Parameters
    ----------
    q, fn : array_like, shape (2n + 1, N) or (2n + 1,)
        √x with x = δ/δ_max, and the normal force over m*·v0²/δ_max, at the half steps
        τ_j = j·h/2 of the dimensionless time τ = t·v0/δ_max (δ_max the scene's elastic
        Hertz maximum approach, v0 its normal approach speed); zero out of contact.
    h : float or array_like, shape (N,)
        Dimensionless step, one for all impacts or one per impact (column).
    s0 : array_like, shape (N,) — initial slip / v0, ≥ 0 (on the initial-slip axis)
    lam : array_like — m*/m_t (m_t the tangential effective mass)
    mu : array_like — Coulomb friction coefficient [-]
    kt_coef : array_like — k_t·δ_max²/(m*·v0²) per √x (k_t = 8·G*·a)
    tangential : {"mindlin", "coulomb", "none"}
    history : {"total", "incremental"}
    eta : array_like, shape like ``q``, optional
        The normal law's dashpot coefficient η_n(δ) over m*·v0/δ_max at the half steps
        (:attr:`pipeline.contact.NormalLaw.damping`); needed with ``tangential_damping``.
    tangential_damping : float or array_like
        LAMMPS's x_γ,t [-]: tangential dashpot = x_γ,t·η_n(δ) (see :func:`impact`).
    start : array_like of int, shape (N,), optional
        How each contact starts: 0 stick, +1 slide forward, −1 slide backward, as
        :func:`._common._first_contact_mode` finds from the law's behaviour as δ → 0 (only
        −1 changes anything: the spring then starts on the lower cap). Default: the
        discrete rule's own first step.

    Returns
    -------
    TangentialHistory
        Pt and Ft at τ_k = k·h, k = 0 … n.
    """
    _check_models(tangential, history)
    q = np.asarray(q, dtype=float)
    fn = np.asarray(fn, dtype=float)
    if q.shape != fn.shape or q.shape[0] % 2 != 1 or q.shape[0] < 3:
        raise InputError("q and fn need the same shape, (2n + 1, N) half-step values")
    q2, f2 = (a.reshape(a.shape[0], -1) for a in (q, fn))
    n, N = (q2.shape[0] - 1) // 2, q2.shape[1]
    s0, lam, mu, ktc, xg = (
        np.broadcast_to(np.asarray(a, dtype=float), (N,))
        for a in (s0, lam, mu, kt_coef, tangential_damping)
    )
    if eta is None:
        if np.any(xg != 0):
            raise InputError("tangential_damping needs the normal dashpot coefficient eta")
        e2 = np.zeros_like(q2)
    else:
        e2 = np.asarray(eta, dtype=float).reshape(q2.shape)
    p = np.zeros((n + 1, N))
    ft = np.zeros((n + 1, N))
    if tangential == "coulomb":  # Routh: Pt = min(μ·Pn, m_t·s0) (docs/theory.md), Pn by Simpson
        pn = np.concatenate(
            [np.zeros((1, N)), np.cumsum(h / 6.0 * (f2[:-2:2] + 4.0 * f2[1::2] + f2[2::2]), 0)]
        )
        p[...] = np.minimum(mu * pn, s0 / lam)
        ft[...] = np.where(mu * pn < s0 / lam, mu * f2[::2], 0.0)
    elif tangential == "mindlin":
        _check_tangential_step(lam, ktc, h, "tangential_history")
        tan = _MindlinRK4(s0.copy(), lam, mu, ktc, history, xg, start)
        for k in range(n):
            i = 2 * k
            mid = (q2[i + 1], f2[i + 1], e2[i + 1])
            end = (q2[i + 2], f2[i + 2], e2[i + 2])
            tan.step(h, ((q2[i], f2[i], e2[i]), mid, mid, end), end)
            p[k + 1] = tan.p
            ft[k + 1] = tan.force(*end)
    shape = (n + 1,) + q.shape[1:]
    return TangentialHistory(p=p.reshape(shape), ft=ft.reshape(shape))


def _batch_group(law, elastic, param, s0, lam, mu, ktc, xg, tangential, history, n_steps):
    """Fixed-step RK4 over all scenes of one normal law (dimensionless).

    Every registered law is self-similar: in units δ* (the elastic δ_max), v0 and m* its
    force is ``law.force(x, u, param, K=5/4, m*=1, v0=1)`` (K·δ*^{5/2} = (5/4)·m*·v0²), so
    the normal problem is integrated once per distinct damping parameter."""
    N = s0.size
    TC = contact.HERTZ_TC_CONSTANT
    h = TC / n_steps
    total = history == "total"

    def mindlin(fn_of, eta_t_of):  # eta_t_of: the TANGENTIAL dashpot coefficient x_γ,t·η_n
        if tangential != "mindlin":
            return None
        start = _first_contact_mode(fn_of, eta_t_of, ktc, s0, mu, lam, total)
        _check_tangential_step(lam, ktc, h, "impact_outcomes")
        return _MindlinRK4(s0, lam, mu, ktc, history, xg, start)

    if elastic:
        # one universal normal solution for every scene (exact, contact.hertz_pulse)
        tau = np.arange(2 * n_steps + 1) * (h / 2)
        tau[-1] = TC
        pulse = contact.hertz_pulse(tau, _UNIT_HERTZ)
        qs, fs = np.sqrt(np.maximum(pulse["delta"], 0.0)), pulse["F"]
        tan = mindlin(lambda x, u: 1.25 * x**1.5, lambda x: 0.0)
        if tan is not None:
            for k in range(n_steps):
                mid = (qs[2 * k + 1], fs[2 * k + 1], 0.0)
                end = (qs[2 * k + 2], fs[2 * k + 2], 0.0)
                tan.step(h, ((qs[2 * k], fs[2 * k], 0.0), mid, mid, end), end)
        e_n = np.ones(N)
        tau_c = np.full(N, TC)
        f_max = np.full(N, 1.25)
        x_max = np.ones(N)
    else:
        param = np.broadcast_to(np.asarray(param, dtype=float), (N,))
        prm, inv = np.unique(param, return_inverse=True)
        M = prm.size

        def fn_of(x, u, idx=None):
            f = law.force(x, u, prm if idx is None else prm[idx], 1.25, 1.0, 1.0)
            return np.where(x > 0, f, 0.0)

        def g(a):
            return a[inv]

        def q(x):
            return g(np.sqrt(np.maximum(x, 0.0)))

        def eta_of(x):  # the normal dashpot coefficient over m*·v0/δ*, per scene
            eta = law.damping(np.maximum(x, 0.0), prm, 1.25, 1.0, 1.0)
            return g(np.where(x > 0, eta, 0.0))

        tan = mindlin(
            lambda x, u: g(fn_of(np.full(M, x), np.full(M, u))),
            lambda x: xg * eta_of(np.full(M, x)),
        )

        x = np.zeros(M)
        u = np.ones(M)
        tau_c = np.full(M, np.nan)
        f_max = np.zeros(M)
        x_max = np.zeros(M)
        f_prev2 = np.zeros(M)
        f_prev = np.zeros(M)
        x_prev2 = np.zeros(M)
        x_prev = np.zeros(M)
        done = np.zeros(M, dtype=bool)
        f1 = fn_of(x, u)
        for k in range(200 * n_steps):
            xa, ua = x + 0.5 * h * u, u - 0.5 * h * f1
            f2 = fn_of(xa, ua)
            xb, ub = x + 0.5 * h * ua, u - 0.5 * h * f2
            f3 = fn_of(xb, ub)
            xc, uc = x + h * ub, u - h * f3
            f4 = fn_of(xc, uc)
            xn = x + h / 6.0 * (u + 2.0 * (ua + ub) + uc)
            un = u - h / 6.0 * (f1 + 2.0 * (f2 + f3) + f4)
            fnew = fn_of(xn, un)
            if tan is not None:
                end = (q(xn), g(fnew), eta_of(xn))
                stages = ((x, f1), (xa, f2), (xb, f3), (xc, f4))
                tan.step(h, tuple((q(xs), g(fs), eta_of(xs)) for xs, fs in stages), end)
            # separation within this step: δ crosses 0, or Fn reaches 0 while restituting
            sep = ~done & (k > 0) & (un < 0) & ((xn <= 0) | (fnew <= 0))
            if np.any(sep):
                idx = np.nonzero(sep)[0]
                theta = _crossing(
                    x[idx],
                    u[idx],
                    xn[idx],
                    un[idx],
                    f1[idx],
                    fnew[idx],
                    h,
                    lambda xx, uu, i=idx: fn_of(xx, uu, i),
                )
                tau_c[sep] = (k + theta) * h
                done |= sep
            # peaks: parabola through the last three node values
            if k >= 2:
                for val, prev, prev2, best in (
                    (f1, f_prev, f_prev2, f_max),
                    (x, x_prev, x_prev2, x_max),
                ):
                    peak = (prev >= prev2) & (prev > val)
                    den = val - 2 * prev + prev2
                    with np.errstate(divide="ignore", invalid="ignore"):
                        ref = np.where(den < 0, prev - (val - prev2) ** 2 / (8 * den), prev)
                    best[...] = np.where(peak, np.maximum(best, ref), np.maximum(best, prev))
            f_prev2, f_prev = f_prev, f1
            x_prev2, x_prev = x_prev, x
            x, u, f1 = xn, un, fnew
            if done.all():
                break
        else:
            raise RuntimeError("impact_outcomes: some bodies did not separate")
        e_n, tau_c, f_max, x_max = g(-u), g(tau_c), g(f_max), g(x_max)
    ratio = np.full(N, np.nan)
    if tangential == "coulomb":
        p = np.minimum(mu * (1.0 + e_n), s0 / lam)  # Routh's broken line (docs/theory.md)
        reverses = np.zeros(N, dtype=bool)
    elif tangential == "none":
        p = np.zeros(N)
        reverses = np.zeros(N, dtype=bool)
    else:
        p = tan.p
        tiny = 1e-9 * np.maximum(mu, 1e-12)
        reverses = (tan.ft_min < -tiny) & (tan.ft_max > tiny)
        ratio = np.where(mu > 0, tan.ratio_max, np.nan)
    return {
        "e_n": e_n,
        "p": p,
        "tau_c": tau_c,
        "f_max": f_max,
        "x_max": x_max,
        "reverses": reverses,
        "ratio": ratio,
    }


def _hermite(theta, y0, d0, y1, d1, h):
    t2, t3 = theta**2, theta**3
    return (
        (2 * t3 - 3 * t2 + 1) * y0
        + (t3 - 2 * t2 + theta) * h * d0
        + (-2 * t3 + 3 * t2) * y1
        + (t3 - t2) * h * d1
    )


def _crossing(x0, u0, x1, u1, f0, f1, h, fn):
    """Fraction θ ∈ (0, 1] of the step where the contact ends: the root of the cubic Hermite
    interpolant of δ, or — when the force law lets go while δ > 0 — the first θ where
    ``fn`` of the Hermite-interpolated state (δ, δ̇) reaches zero (bisection, 40 halvings)."""
    theta = np.where(x1 < x0, x0 / np.where(x0 - x1 > 0, x0 - x1, 1.0), 1.0)
    theta = np.clip(theta, 0.0, 1.0)
    for _ in range(8):  # Newton on the Hermite cubic of δ(θ)
        t2 = theta**2
        val = _hermite(theta, x0, u0, x1, u1, h)
        der = (
            (6 * t2 - 6 * theta) * x0
            + (3 * t2 - 4 * theta + 1) * h * u0
            + (-6 * t2 + 6 * theta) * x1
            + (3 * t2 - 2 * theta) * h * u1
        )
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.where(der < 0, val / der, 0.0)
        theta = np.clip(theta - step, 0.0, 1.0)
    by_force = x1 > 0  # the force reached zero before δ did
    if np.any(by_force):
        lo = np.zeros(x0.shape)
        hi = np.ones(x0.shape)
        for _ in range(40):
            mid = 0.5 * (lo + hi)
            xm = _hermite(mid, x0, u0, x1, u1, h)
            um = _hermite(mid, u0, -f0, u1, -f1, h)
            pos = fn(xm, um) > 0
            lo = np.where(pos, mid, lo)
            hi = np.where(pos, hi, mid)
        theta = np.where(by_force, hi, theta)
    return theta
