r"""The tangential contact on a given normal pulse, solved piecewise without a time-step loop.

The fits evaluate the tangential model hundreds of times per record, for many parameter
sets at once (Jacobian columns, bootstrap replicates), so it must cost a few numpy calls,
not one Python iteration per time step. It is solved exactly where the physics allows and
with a 4th-order propagator elsewhere, on the nodes τ_j = j·h of a
:class:`~pipeline.fit.pulse.NormalPulse` (units δ*, δ*/v0, m*·v0²/δ*; docs/theory.md):

.. math::

    p' = f_t, \qquad s = s_0 - \lambda p, \qquad |f_t| \le \mu f,

with p = Pt/(m*·v0), s the slip over v0, λ = m*/m_t and :math:`k_t = k_c\sqrt{x}` the Mindlin
stiffness in these units, :math:`k_c = 6\,(G^*/E^*)\cdot` ``kt_scale`` (8·G*·a over
K·δ*^{1/2}: independent of speed, size and mass).

**Sliding** (:math:`f_t = \sigma\mu f`) is closed form: :math:`p = p_a + \sigma\mu
(P_n - P_{n,a})` with the exact :math:`P_n = 1 - u`.

**Sticking** is a linear system :math:`v' = A(\tau)v` with a traceless
:math:`A = [[0, a],[b, 0]]`: for the total-displacement rule (LAMMPS ``mindlin``, the
simulator's default; :func:`pipeline.contact.mindlin_total`) v = (ξ/δ*, s), a = 1,
:math:`b = -\lambda k_c\sqrt x`, :math:`f_t = k_c\sqrt{x}\,\xi`; for the incremental rule
(YADE, LAMMPS ``mindlin/force``; :func:`pipeline.contact.mindlin_incremental`)
v = (f_t, s), :math:`a = k_c\sqrt x`, b = −λ. Each step's propagator is the 4th-order
Magnus exponential :math:`\exp\Omega`, :math:`\Omega = \tfrac h2(A_1 + A_2) +
\tfrac{\sqrt3 h^2}{12}[A_2, A_1]` (two Gauss points), in closed form for a traceless 2×2
(:math:`e^\Omega = \cosh\theta\,I + \tfrac{\sinh\theta}{\theta}\Omega`,
:math:`\theta^2 = -\det\Omega`), and the fundamental matrix at every node is their prefix
product, taken in log2(n) vectorised passes (Hillis–Steele scan).

**Switches** are located, not stepped over: stick → slide where the spring force reaches the
Coulomb cap, slide → stick where the spring, left free, would fall back inside it
(:math:`\sigma\,\mathrm{d}f_{spring}/\mathrm{d}\tau < \mu f'`), each by regula falsi on
the interpolated pulse; the initial mode as in :func:`pipeline.simulate.impact`. The loop
runs over stick/slide segments (a handful per impact), for all parameter sets at once.
This is the continuous-time model :func:`pipeline.simulate.impact` integrates adaptively;
``tests/test_fit_contact.py`` checks the two against each other.

**Coulomb** friction without compliance is Routh's line on the pulse,
:math:`p = \min(\mu P_n, s_0/\lambda)` (docs/theory.md).

References
----------
W. Magnus, Commun. Pure Appl. Math. 7:649 (1954), doi:10.1002/cpa.3160070404;
A. Iserles, S. P. Nørsett, Phil. Trans. R. Soc. A 357:983 (1999),
doi:10.1098/rsta.1999.0361 (the 4th-order two-point Magnus integrator).
W. D. Hillis, G. L. Steele, Commun. ACM 29:1170 (1986), doi:10.1145/7902.7903 (the scan).
R. D. Mindlin, J. Appl. Mech. 16:259 (1949), doi:10.1115/1.4009973.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .pulse import NormalPulse

__all__ = ["TangentialResponse", "tangential_response", "TANGENTIAL_MODELS", "HISTORY_RULES"]

TANGENTIAL_MODELS = ("none", "coulomb", "mindlin")
HISTORY_RULES = ("total", "incremental")

_G1, _G2 = 0.5 - np.sqrt(3.0) / 6.0, 0.5 + np.sqrt(3.0) / 6.0  # Gauss–Legendre points
_MAGNUS_C = np.sqrt(3.0) / 12.0
_MAX_SEGMENTS = 64


@dataclass(frozen=True)
class TangentialResponse:
    """Tangential percussion and force on the pulse's nodes (dimensionless, see module).

    Attributes
    ----------
    p : numpy.ndarray, shape (M, n + 1) — Pt/(m*·v0)
    ft, dft : numpy.ndarray, shape (M, n + 1) — Ft/(m*·v0²/δ*) (> 0 opposing the initial
        slip) and its rate d ft/dτ (one-sided where the mode switches)
    slip_stops : numpy.ndarray of bool, shape (M,) — the slip s = s0 − λp reached zero
        (Routh's sticking regime); False: the contact slides throughout
    slide_share : numpy.ndarray, shape (M,) — share of the normal percussion delivered while
        the Coulomb cap held (μ acts), in [0, 1]
    segments : numpy.ndarray of int, shape (M,) — stick/slide segments
    """

    p: np.ndarray
    ft: np.ndarray
    dft: np.ndarray
    slip_stops: np.ndarray
    slide_share: np.ndarray
    segments: np.ndarray


def _hermite(theta, y0, d0, y1, d1, h):
    t2 = theta * theta
    t3 = t2 * theta
    return (
        (2 * t3 - 3 * t2 + 1) * y0
        + (t3 - 2 * t2 + theta) * h * d0
        + (3 * t2 - 2 * t3) * y1
        + (t3 - t2) * h * d1
    )


class _Pulse:
    """The normal pulse of M columns with interpolation at arbitrary τ (one per column)."""

    def __init__(self, pulse: NormalPulse):
        self.x, self.u, self.f, self.df = pulse.x, pulse.u, pulse.f, pulse.df
        self.qg = np.sqrt(pulse.xg)  # (M, 2, n): √x at each step's Gauss points
        self.n = pulse.n_steps
        self.h = pulse.tau_c / self.n  # (M,)
        self.tau_c = pulse.tau_c
        self.q = np.sqrt(self.x)
        self.pn = 1.0 - self.u
        self.rows = np.arange(self.x.shape[0])

    def at(self, rows, tau, what="xufdp"):
        """x, u, f, df, pn at τ (arrays of the rows' length; only those in ``what``: "x",
        "u", "f", "d", "p"), τ clipped to [0, τ_c]. Cubic Hermite in x, u, f (their rates
        are u, −f, df), linear in df."""
        h = self.h[rows]
        s = np.clip(tau / h, 0.0, self.n)
        j = np.minimum(s.astype(int), self.n - 1)
        th = s - j
        out = []
        if "x" in what:
            x = _hermite(
                th, self.x[rows, j], self.u[rows, j], self.x[rows, j + 1], self.u[rows, j + 1], h
            )
            out.append(np.maximum(x, 0.0))
        if "u" in what or "p" in what:
            u = _hermite(
                th, self.u[rows, j], -self.f[rows, j], self.u[rows, j + 1], -self.f[rows, j + 1], h
            )
            if "u" in what:
                out.append(u)
        if "f" in what:
            f = _hermite(
                th, self.f[rows, j], self.df[rows, j], self.f[rows, j + 1], self.df[rows, j + 1], h
            )
            out.append(np.maximum(f, 0.0))
        if "d" in what:
            out.append(self.df[rows, j] + th * (self.df[rows, j + 1] - self.df[rows, j]))
        if "p" in what:
            out.append(1.0 - u)
        return out

    def gauss_q(self, rows, t0, t1):
        """√x at the two Gauss points of [t0, t1] (within one step or less)."""
        return [np.sqrt(self.at(rows, t0 + g * (t1 - t0), "x")[0]) for g in (_G1, _G2)]


class _Stick:
    """Coefficients a(√x), b(√x) of the stick system v' = [[0, a], [b, 0]] v of one rule."""

    def __init__(self, history, lam, kc):
        self.total = history == "total"
        self.lam, self.kc = lam, kc

    def ab(self, q, rows):
        lam, kc = self.lam[rows], self.kc[rows]
        if self.total:  # v = (ξ, s): ξ' = s, s' = −λ·kc·√x·ξ
            return np.ones_like(q), -lam * kc * q
        return kc * q, -lam * np.ones_like(q)  # v = (ft, s): ft' = kc·√x·s, s' = −λ·ft

    def force(self, v1, q, rows):
        return self.kc[rows] * q * v1 if self.total else v1

    def dforce(self, v1, v2, q, u, rows):
        """d(spring force)/dτ: total kc(q'ξ + q s) with q' = u/(2q); incremental kc·q·s."""
        kc = self.kc[rows]
        if self.total:
            with np.errstate(divide="ignore", invalid="ignore"):
                qd = np.where(q > 0, u / (2.0 * np.where(q > 0, q, 1.0)), 0.0)
            return kc * (qd * v1 + q * v2)
        return kc * q * v2


def _expm(a, b, d):
    """exp([[d, a], [b, −d]]) as (m11, m12, m21, m22) (traceless 2×2, closed form)."""
    t2 = d * d + a * b
    r = np.sqrt(np.abs(t2))
    pos = t2 > 0
    # each branch only where it applies: a stiff spring's oscillatory r overflows cosh
    rh = np.where(pos, r, 0.0)
    C = np.where(pos, np.cosh(rh), np.cos(r))
    with np.errstate(invalid="ignore", divide="ignore"):
        S = np.where(r > 1e-8, np.where(pos, np.sinh(rh), np.sin(r)) / np.where(r > 0, r, 1), 1.0)
    S = np.where(r > 1e-8, S, 1.0 + t2 / 6.0)
    return C + S * d, S * a, S * b, C - S * d


def _magnus(stick, rows, q1, q2, dt):
    """4th-order Magnus propagator over dt with √x = q1, q2 at its Gauss points."""
    a1, b1 = stick.ab(q1, rows)
    a2, b2 = stick.ab(q2, rows)
    return _expm(
        0.5 * dt * (a1 + a2), 0.5 * dt * (b1 + b2), _MAGNUS_C * dt * dt * (a2 * b1 - a1 * b2)
    )


def _fundamental(pl: _Pulse, stick: _Stick):
    """Φ_j (from τ = 0 to τ_j) at every node, shape (M, n + 1) per entry (prefix scan)."""
    M, n = pl.x.shape[0], pl.n
    rows = pl.rows[:, None]
    cur = [np.empty((M, n + 1)) for _ in range(4)]
    steps = _magnus(stick, rows, pl.qg[:, 0], pl.qg[:, 1], pl.h[:, None])
    for c, v, one in zip(cur, steps, (1.0, 0.0, 0.0, 1.0), strict=True):
        c[:, 0] = one  # Φ_0 = I
        c[:, 1:] = v  # the step propagators M_j, becoming Φ_{j+1} = M_j···M_0
    k = 1
    while k < n:
        a11, a12, a21, a22 = (c[:, k + 1 :] for c in cur)
        b11, b12, b21, b22 = (c[:, 1 : n + 1 - k] for c in cur)
        p11 = a11 * b11 + a12 * b21
        p12 = a11 * b12 + a12 * b22
        p21 = a21 * b11 + a22 * b21
        p22 = a21 * b12 + a22 * b22
        a11[...], a12[...], a21[...], a22[...] = p11, p12, p21, p22
        k *= 2
    return cur


def _linear_root(lo, hi, g_lo, g_hi):
    """Where the line through (lo, g_lo), (hi, g_hi) crosses zero (g_lo ≤ 0 < g_hi)."""
    den = g_hi - g_lo
    with np.errstate(divide="ignore", invalid="ignore"):
        th = np.where(den > 0, -g_lo / np.where(den > 0, den, 1.0), 1.0)
    return lo + np.clip(th, 0.0, 1.0) * (hi - lo)


def tangential_response(
    pulse: NormalPulse,
    s0,
    lam,
    mu,
    kc,
    *,
    tangential: str = "mindlin",
    history: str = "total",
) -> TangentialResponse:
    """The tangential model of M impacts on their dimensionless normal pulses (module notes).

    Parameters
    ----------
    pulse : NormalPulse — M normal pulses (:func:`pipeline.fit.pulse.normal_pulse`)
    s0 : array_like, shape (M,) — initial slip over v0 [-], ≥ 0 (initial-slip axis)
    lam : array_like — m*/m_t [-] (3.5 for a solid sphere on a fixed target)
    mu : array_like — Coulomb friction coefficient [-]
    kc : array_like — Mindlin stiffness k_t/(K·√δ*·√x) = 6·(G*/E*)·kt_scale [-]
    tangential : {"mindlin", "coulomb", "none"}
    history : {"total", "incremental"} — Mindlin history rule

    Returns
    -------
    TangentialResponse
    """
    if tangential not in TANGENTIAL_MODELS:
        raise InputError(
            f"unknown tangential model {tangential!r}; choose one of {TANGENTIAL_MODELS}"
        )
    if history not in HISTORY_RULES:
        raise InputError(f"unknown Mindlin history rule {history!r}; choose one of {HISTORY_RULES}")
    M, J = pulse.x.shape
    s0, lam, mu, kc = (np.broadcast_to(np.asarray(a, dtype=float), (M,)) for a in (s0, lam, mu, kc))
    pn = pulse.pn
    pn_end = pn[:, -1]
    if tangential == "none":
        z = np.zeros((M, J))
        return TangentialResponse(z, z, z, np.zeros(M, bool), np.zeros(M), np.ones(M, int))
    if tangential == "coulomb":
        cap = (s0 / lam)[:, None]
        slide = mu[:, None] * pn < cap
        p = np.minimum(mu[:, None] * pn, cap)
        stops = mu * pn_end >= s0 / lam
        with np.errstate(divide="ignore", invalid="ignore"):
            share = np.where(stops, (s0 / lam) / np.maximum(mu * pn_end, 1e-300), 1.0)
        return TangentialResponse(
            p=p,
            ft=np.where(slide, mu[:, None] * pulse.f, 0.0),
            dft=np.where(slide, mu[:, None] * pulse.df, 0.0),
            slip_stops=stops,
            slide_share=np.clip(np.where(mu > 0, share, 0.0), 0.0, 1.0),
            segments=np.where(stops, 2, 1),
        )
    return _mindlin(pulse, s0, lam, mu, kc, history)


def _mindlin(pulse, s0, lam, mu, kc, history):
    pl = _Pulse(pulse)
    stick = _Stick(history, lam, kc)
    M, J = pl.x.shape
    h = pl.h
    nodes = np.arange(J)[None, :]
    tau = h[:, None] * nodes
    Phi = _fundamental(pl, stick)
    p_out, ft_out, dft_out = (np.zeros((M, J)) for _ in range(3))
    slide_pn = np.zeros(M)
    segments = np.zeros(M, dtype=int)

    # initial mode (as pipeline.simulate.impact): does the spring stay under the cap at
    # first contact? Trial force at node 1: total k·s0·τ, incremental (2/3)·k·s0·τ
    trial = kc * pl.q[:, 1] * s0 * h * (1.0 if stick.total else 2.0 / 3.0)
    mode = np.where((s0 <= 0) | (trial < mu * pl.f[:, 1]), 0, 1)  # 0 stick, ±1 slide
    mode = np.where(mu <= 0, 1, mode)
    t_a = np.zeros(M)  # start of the current segment
    p_a = np.zeros(M)
    v1 = np.zeros(M)  # stick state: ξ (total) or ft (incremental)
    v2 = s0.copy()  # slip s
    active = np.ones(M, dtype=bool)
    for _ in range(_MAX_SEGMENTS):
        if not active.any():
            break
        segments += active
        stick_rows = np.nonzero(active & (mode == 0))[0]
        slide_rows = np.nonzero(active & (mode != 0))[0]
        if stick_rows.size:
            _stick_segment(
                pl,
                stick,
                Phi,
                stick_rows,
                t_a,
                p_a,
                v1,
                v2,
                mode,
                active,
                s0,
                lam,
                mu,
                tau,
                nodes,
                p_out,
                ft_out,
                dft_out,
            )
        if slide_rows.size:
            _slide_segment(
                pl,
                stick,
                slide_rows,
                t_a,
                p_a,
                v1,
                v2,
                mode,
                active,
                s0,
                lam,
                mu,
                kc,
                tau,
                nodes,
                p_out,
                ft_out,
                dft_out,
                slide_pn,
            )
    ft_out[:, -1] = 0.0  # the last node: the contact has ended
    with np.errstate(divide="ignore", invalid="ignore"):
        share = np.clip(np.where(pl.pn[:, -1] > 0, slide_pn / pl.pn[:, -1], 0.0), 0.0, 1.0)
    slip_stops = np.any(s0[:, None] - lam[:, None] * p_out <= 0, axis=1)
    return TangentialResponse(
        p=p_out, ft=ft_out, dft=dft_out, slip_stops=slip_stops, slide_share=share, segments=segments
    )


def _stick_segment(
    pl,
    stick,
    Phi,
    r,
    t_a,
    p_a,
    v1,
    v2,
    mode,
    active,
    s0,
    lam,
    mu,
    tau,
    nodes,
    p_out,
    ft_out,
    dft_out,
):
    """Advance the rows ``r`` through one stick segment: v_j = Φ_j·Φ_{k+1}⁻¹·M_part·v_a."""
    n = pl.n
    hr = pl.h[r]
    k = np.minimum((t_a[r] / hr).astype(int), n - 1)
    t_k1 = (k + 1) * hr
    qg = pl.gauss_q(r, t_a[r], t_k1)
    Mp = _magnus(stick, r, qg[0], qg[1], t_k1 - t_a[r])
    w1 = Mp[0] * v1[r] + Mp[1] * v2[r]
    w2 = Mp[2] * v1[r] + Mp[3] * v2[r]
    P = [c[r, k + 1] for c in Phi]  # Φ_{k+1}, det 1: its inverse is [[d, −b], [−c, a]]
    c1 = P[3] * w1 - P[1] * w2
    c2 = P[0] * w2 - P[2] * w1
    V1 = Phi[0][r] * c1[:, None] + Phi[1][r] * c2[:, None]
    V2 = Phi[2][r] * c1[:, None] + Phi[3][r] * c2[:, None]
    q = pl.q[r]
    rr = r[:, None]
    F = stick.force(V1, q, rr)
    g = np.abs(F) - mu[rr] * pl.f[r]
    hit = (nodes > k[:, None]) & (g > 0)
    has = hit.any(axis=1)
    te = np.full(r.size, np.inf)
    ev = np.nonzero(has)[0]
    if ev.size:
        # the spring reaches the cap between nodes j − 1 and j (the trajectory extends
        # back past t_a, so node j − 1 is on it even when t_a lies beyond it)
        j = hit[ev].argmax(axis=1)
        re = r[ev]
        he = pl.h[re]
        te[ev] = np.maximum(
            _linear_root((j - 1) * he, j * he, np.minimum(g[ev, j - 1], 0.0), g[ev, j]), t_a[re]
        )
    own = (tau[r] >= t_a[rr]) & (tau[r] < te[:, None])
    ft_out[r] = np.where(own, F, ft_out[r])
    p_out[r] = np.where(own, (s0[rr] - V2) / lam[rr], p_out[r])
    dft_out[r] = np.where(own, stick.dforce(V1, V2, q, pl.u[r], rr), dft_out[r])
    done = ~has
    if ev.size:
        # the state at the switch: one partial step from the node before it
        jl = np.minimum((te[ev] / he).astype(int), n - 1)
        qg = pl.gauss_q(re, jl * he, te[ev])
        Mq = _magnus(stick, re, qg[0], qg[1], te[ev] - jl * he)
        a, b = V1[ev, jl], V2[ev, jl]
        xi, s = Mq[0] * a + Mq[1] * b, Mq[2] * a + Mq[3] * b
        x = pl.at(re, te[ev], "x")[0]
        mode[re] = np.where(stick.force(xi, np.sqrt(x), re) >= 0, 1, -1)
        t_a[re] = te[ev]
        p_a[re] = (s0[re] - s) / lam[re]
        done[ev] |= te[ev] >= pl.tau_c[re] * (1 - 1e-12)
    active[r[done]] = False


def _slide_segment(
    pl,
    stick,
    r,
    t_a,
    p_a,
    v1,
    v2,
    mode,
    active,
    s0,
    lam,
    mu,
    kc,
    tau,
    nodes,
    p_out,
    ft_out,
    dft_out,
    slide_pn,
):
    """Advance the rows ``r`` through one slide segment (closed form) to the release."""
    n = pl.n
    rr = r[:, None]
    sig = mode[r].astype(float)[:, None]
    mr = mu[rr]
    pn_a = pl.at(r, t_a[r], "p")[0]
    Pj = p_a[rr] + sig * mr * (pl.pn[r] - pn_a[:, None])
    # release: σ·d(free spring force)/dτ − μ·f' < 0 (module notes)
    x, f, df = pl.x[r], pl.f[r], pl.df[r]
    R = sig * kc[rr] * pl.q[r] * (s0[rr] - lam[rr] * Pj) - mr * df
    if stick.total:  # on the cap ξ = σμf/(kc√x): the term kc·q'·ξ = μ·f·u/(2x)
        with np.errstate(divide="ignore", invalid="ignore"):
            R = R + np.where(x > 0, mr * f * pl.u[r] / (2 * np.where(x > 0, x, 1.0)), 0.0)
    hit = (tau[r] > t_a[rr]) & (x > 0) & (R < 0) & (nodes < n)
    has = hit.any(axis=1) & (mu[r] > 0)
    tr = np.full(r.size, np.inf)
    ev = np.nonzero(has)[0]
    if ev.size:
        j = hit[ev].argmax(axis=1)
        re = r[ev]
        he = pl.h[re]
        # −R rises through zero between nodes j − 1 and j (closed form extends before t_a)
        tr[ev] = np.maximum(
            _linear_root((j - 1) * he, j * he, np.minimum(-R[ev, j - 1], 0.0), -R[ev, j]), t_a[re]
        )
    own = (tau[r] >= t_a[rr]) & (tau[r] < tr[:, None])
    ft_out[r] = np.where(own, sig * mr * f, ft_out[r])
    dft_out[r] = np.where(own, sig * mr * df, dft_out[r])
    p_out[r] = np.where(own, Pj, p_out[r])
    pn_b = pl.pn[r, -1].copy()
    if ev.size:
        x, f_, pn_ = pl.at(re, tr[ev], "xfp")
        pn_b[ev] = pn_
        pr = p_a[re] + sig[ev, 0] * mu[re] * (pn_ - pn_a[ev])
        cap = sig[ev, 0] * mu[re] * f_
        q = np.sqrt(x)
        with np.errstate(divide="ignore", invalid="ignore"):
            xi = np.where(q > 0, cap / (kc[re] * np.where(q > 0, q, 1.0)), 0.0)
        v1[re] = xi if stick.total else cap
        v2[re] = s0[re] - lam[re] * pr
        mode[re] = 0
        t_a[re] = tr[ev]
    slide_pn[r] += pn_b - pn_a
    active[r[~has]] = False
