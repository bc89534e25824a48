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
the interpolated pulse; the initial mode as in :func:`pipeline.simulate.impact`. Where the
two conditions tie at one instant — a spring that reaches its cap at the contact's first
instant, where the cap is nil, or Thornton's cap letting go faster than the spring unloads —
the slide pushes as the spring does at the first node beyond the cap, and where a stick and
a slide in turn leave a column within :data:`_STALL` of a step of where it was, the slide
holds to the next node, so the solution moves on (its error there is of the order of the
step: ~1 % of the percussion at 64 steps, more at a stiff spring's let-go). The loop runs
over stick/slide segments (a handful per impact, a few tens for a stiff spring), for all
parameter sets at once, to at most 64: a far stiffer spring (kc ≳ 200, ``kt_scale`` ≳ 80)
sticks and slides again with every swing of its oscillation, and the contact left after the
64th segment keeps no tangential force.
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
_G12 = np.array([_G1, _G2])
_MAGNUS_C = np.sqrt(3.0) / 12.0
_EYE = np.eye(2)[:, :, None]  # Φ_0 = I, against the columns
_ENDS = np.arange(2)  # a step's two nodes
_MAX_SEGMENTS = 64
#: A stick and a slide that move a row on by less than this share of a step, in turn: a tie.
_STALL = 1e-3


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
    kink : numpy.ndarray of bool, shape (M, n + 1) or None — the steps j → j + 1 in which the
        mode switches (ft has a kink there): interpolated linearly, not by cubic Hermite,
        so the interpolant moves continuously as a switch crosses a node (the one-sided
        rates at a node would flip, and with them the cubic, by h·Δft')
    """

    p: np.ndarray
    ft: np.ndarray
    dft: np.ndarray
    slip_stops: np.ndarray
    slide_share: np.ndarray
    segments: np.ndarray
    kink: np.ndarray | None = None


class _Pulse:
    """The normal pulse of M columns with interpolation at arbitrary τ (one per column).

    Everything a segment needs that depends on the pulse alone is computed here once per
    solve, not once per segment.
    """

    def __init__(self, pulse: NormalPulse):
        x, u, f = pulse.x, pulse.u, pulse.f
        self.x, self.u, self.f, self.df = x, u, f, pulse.df
        self.qg = np.sqrt(pulse.xg)  # (M, 2, n): √x at each step's Gauss points
        self.n = pulse.n_steps
        self.h = pulse.tau_c / self.n  # (M,)
        self.tau_c = pulse.tau_c
        self.node = np.arange(self.n + 1)[None, :]
        self.tau = self.h[:, None] * self.node  # the nodes' τ (M, n + 1)
        self.q = np.sqrt(x)
        self.pn = 1.0 - u
        pos = x > 0
        # the total rule's d(spring force)/dτ terms, 0 where x = 0: q' = u/(2√x), and on
        # the cap (ξ = σμf/(kc√x)) kc·q'·ξ = σμ·f·u/(2x)
        self.qd = np.divide(u, 2.0 * self.q, out=np.zeros(x.shape), where=pos)
        self.fu_2x = np.divide(f * u, 2.0 * x, out=np.zeros(x.shape), where=pos)
        self.inner = pos  # x > 0 before the last node (where a slide may end)
        pos[:, -1] = False
        # x, u, f beside their rates u, −f, df at each node: one gather per side of a step
        # serves the three interpolants of :meth:`at` (a view of one (6, M, n + 1) block)
        self.table = np.array([x, u, f, u, -f, pulse.df]).transpose(1, 2, 0)

    def at(self, rows, tau, only_x=False):
        """x, u, f at τ (k, m) for the rows (k,) (an index array), each shaped like τ; τ
        clipped to [0, τ_c]. Cubic Hermite on the nodes (the rates of x, u, f are u, −f,
        df); x and f floored at 0. ``only_x``: x alone."""
        h = self.h[rows][:, None]
        s = np.minimum(np.maximum(tau / h, 0.0), self.n)
        j = np.minimum(s.astype(int), self.n - 1)
        th = s - j
        t2 = th * th
        t3 = t2 * th
        tab = self.table[..., ::3] if only_x else self.table  # x, u: x and its rate
        ends = tab[rows[:, None, None], j[..., None] + _ENDS]  # (k, m, 2, 2 or 6): one gather
        a, b = ends[..., 0, :], ends[..., 1, :]
        # the weights (float literals: no conversion per call); w0 = 2θ³ − 3θ² + 1 = 1 − w2
        # to the last bit
        w2 = 3.0 * t2 - 2.0 * t3
        w0, w1, w3 = 1.0 - w2, (t3 - 2.0 * t2 + th) * h, (t3 - t2) * h
        if only_x:
            return np.maximum(
                w0 * a[..., 0] + w1 * a[..., 1] + w2 * b[..., 0] + w3 * b[..., 1], 0.0
            )
        w0, w1, w2, w3 = w0[..., None], w1[..., None], w2[..., None], w3[..., None]
        y = w0 * a[..., :3] + w1 * a[..., 3:] + w2 * b[..., :3] + w3 * b[..., 3:]
        return np.maximum(y[..., 0], 0.0), y[..., 1], np.maximum(y[..., 2], 0.0)

    @staticmethod
    def gauss_points(t0, t1):
        """The two Gauss points of each [t0, t1], (k, 2)."""
        d = (t1 - t0)[:, None]
        return t0[:, None] + _G12 * d


def _column(a, M):
    """``a`` as a float array of shape (M,) (a scalar broadcast)."""
    a = np.asarray(a, dtype=float)
    return a if a.shape == (M,) else np.broadcast_to(a, (M,))


def _rows(r, M):
    """An index of the rows ``r`` (sorted, distinct) of M: a slice when it is every row, so
    that indexing gives views instead of copies (the common case: all columns in one mode)."""
    return slice(None) if r.size == M else r


class _Stick:
    """The stick system v' = [[0, a], [b, 0]] v of one rule (coefficients a(√x), b(√x)): its
    Magnus exponent, the spring force and its rate.

    ``rows`` indexes the columns (an index array, a slice, or either with a new axis).
    """

    def __init__(self, history, lam, kc):
        self.total = history == "total"
        self.lam, self.kc = lam, kc
        self.lam_kc = -lam * kc  # total rule: s' = −λ·kc·√x·ξ
        self.neg_lam = -lam

    def omega(self, q1, q2, dt, rows):
        """Magnus's Ω = ½dt(A_1 + A_2) + (√3/12)dt²[A_2, A_1] = [[d, a], [b, −d]] over dt, with
        √x = q1, q2 at its Gauss points: (a, b, d), for A_i = [[0, a_i], [b_i, 0]] (d =
        (√3/12)dt²(a_2·b_1 − a_1·b_2)); the rule's constant coefficient as a number."""
        c = _MAGNUS_C * dt * dt
        if self.total:  # v = (ξ, s): ξ' = s, s' = −λ·kc·√x·ξ (a = 1)
            lk = self.lam_kc[rows]
            b1, b2 = lk * q1, lk * q2
            return dt, 0.5 * dt * (b1 + b2), c * (b1 - b2)
        # v = (ft, s): ft' = kc·√x·s, s' = −λ·ft (b = −λ)
        kc, b = self.kc[rows], self.neg_lam[rows]
        a1, a2 = kc * q1, kc * q2
        return 0.5 * dt * (a1 + a2), dt * b, c * (a2 * b - a1 * b)

    def force(self, v1, q, rows):
        return self.kc[rows] * q * v1 if self.total else v1

    def dforce(self, v1, v2, q, qd, rows):
        """d(spring force)/dτ: total kc(q'ξ + q s) (q' = u/(2q), :attr:`_Pulse.qd`);
        incremental kc·q·s."""
        kc = self.kc[rows]
        if self.total:
            return kc * (qd * v1 + q * v2)
        return kc * q * v2


def _expm(a, b, d):
    """exp([[d, a], [b, −d]]) as (m11, m12, m21, m22) (traceless 2×2, closed form)."""
    t2 = d * d + a * b
    r = np.sqrt(np.abs(t2))
    pos = t2 > 0
    if pos.any():
        # each branch only where it applies: a stiff spring's oscillatory r overflows cosh
        rh = np.where(pos, r, 0.0)
        C = np.where(pos, np.cosh(rh), np.cos(r))
        Sr = np.where(pos, np.sinh(rh), np.sin(r))
    else:  # all oscillatory (the usual case): no hyperbolic branch to compute
        C, Sr = np.cos(r), np.sin(r)
    big = r > 1e-8
    if big.all():
        S = Sr / r
    else:  # sinh(θ)/θ → 1 + θ²/6
        S = np.where(big, Sr / np.where(big, r, 1.0), 1.0 + t2 / 6.0)
    Sd = S * d
    return C + Sd, S * a, S * b, C - Sd


def _magnus(stick, rows, q1, q2, dt):
    """4th-order Magnus propagator over dt with √x = q1, q2 at its Gauss points."""
    return _expm(*stick.omega(q1, q2, dt, rows))


def _fundamental(pl: _Pulse, stick: _Stick):
    """Φ_j (from τ = 0 to τ_j) at every node, shape (4, M, n + 1): its entries 11, 12, 21,
    22 (prefix scan)."""
    M, n = pl.x.shape[0], pl.n
    Phi = np.empty((2, 2, M, n + 1))
    Phi[..., 0] = _EYE
    steps = _magnus(stick, (slice(None), None), pl.qg[:, 0], pl.qg[:, 1], pl.h[:, None])
    flat = Phi.reshape(4, M, n + 1)
    for i, v in enumerate(steps):
        flat[i, :, 1:] = v  # the step propagators M_j, becoming Φ_{j+1} = M_j···M_0
    k = 1
    while k < n:
        A, B = Phi[..., k + 1 :], Phi[..., 1 : n + 1 - k]
        # the 2×2 products A·B node by node, (A·B)_ij = A_i1·B_1j + A_i2·B_2j: one einsum
        # (the same sums, in one call instead of three broadcast passes; A and B overlap,
        # so into a new array first)
        A[...] = np.einsum("ikml,kjml->ijml", A, B)
        k *= 2
    return flat


def _first_crossing(h, hit, g, t_from):
    """Where g (some rows, on the nodes; their steps ``h``) first rises through zero: by
    regula falsi between the first node marked in ``hit`` (never node 0; g > 0 there) and
    the one before it (g there taken as ≤ 0), not before ``t_from``.

    Returns the instants (inf for a row without a hit), the rows with one (bool), their
    positions among the rows, and each row's first hit (0 where there is none).
    """
    j = hit.argmax(axis=1)  # the first hit; 0 (node 0 is never one) where there is none
    has = j > 0
    ev = has.nonzero()[0]
    if ev.size == j.size:  # the usual case: a hit in every row, no copies of the rows
        return _root(g, j, h, t_from), has, ev, j
    t = np.full(j.size, np.inf)
    if ev.size:
        t[ev] = _root(g[ev], j[ev], h[ev], t_from[ev])
    return t, has, ev, j


def _root(g, j, h, t_from):
    """The root of g's line between nodes j − 1 and j of each row, not before t_from."""
    k = np.arange(j.size)
    g_lo = np.minimum(g[k, j - 1], 0.0)
    # the line's root between the nodes: −g_lo/(g_hi − g_lo) ∈ [0, 1] as g_hi > 0 ≥ g_lo
    return np.maximum((j - 1 - g_lo / (g[k, j] - g_lo)) * h, t_from)


def _put(a, R, where, v):
    """a[R] = v where ``where`` (rows ``R``: a slice of every row, or an index array)."""
    if isinstance(R, slice):
        np.copyto(a[R], v, where=where)
    else:
        a[R] = np.where(where, v, a[R])


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
    s0, lam, mu, kc = (_column(a, M) for a in (s0, lam, mu, kc))
    if tangential == "none":
        z = np.zeros((M, J))
        return TangentialResponse(z, z, z, np.zeros(M, bool), np.zeros(M), np.ones(M, int))
    if tangential == "coulomb":
        pn = pulse.pn
        pn_end = pn[:, -1]
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
    Phi = None  # the stick propagators, worked out for the first stick (never in gross slip)
    # initial mode (as pipeline.simulate.impact): does the spring stay under the cap at
    # first contact? Trial force at node 1: total k·s0·τ, incremental (2/3)·k·s0·τ
    trial = kc * pl.q[:, 1] * s0 * h * (1.0 if stick.total else 2.0 / 3.0)
    mode = np.where((s0 <= 0) | (trial < mu * pl.f[:, 1]), 0, 1)  # 0 stick, ±1 slide
    st = _State(
        s0=s0,
        lam=lam,
        mu=mu,
        kc=kc,
        mode=np.where(mu <= 0, 1, mode),
        t_a=np.zeros(M),
        p_a=np.zeros(M),
        pn_a=pl.pn[:, 0].copy(),  # 1 − u at τ = 0 (where the interpolant is u_0)
        v1=np.zeros(M),
        v2=s0.copy(),
        active=np.ones(M, dtype=bool),
        p=np.zeros((M, J)),
        ft=np.zeros((M, J)),
        dft=np.zeros((M, J)),
        slide_pn=np.zeros(M),
        kink=np.zeros((M, J), dtype=bool),
        may_stick=pl.inner if (mu > 0).all() else pl.inner & (mu > 0)[:, None],
        stalled=np.zeros(M, dtype=bool),
    )
    segments = np.zeros(M, dtype=int)
    seen = np.full((2, M), np.nan)  # each row's start two segments back and one back
    for _ in range(_MAX_SEGMENTS):
        # a row that moved on by next to nothing in two segments has stuck and slid in turn
        # without moving on
        st.stalled = st.t_a - seen[0] <= _STALL * pl.h
        seen[0] = seen[1]
        seen[1] = st.t_a
        sticking = st.mode == 0
        stick_rows = (st.active & sticking).nonzero()[0]
        slide_rows = (st.active & ~sticking).nonzero()[0]
        if not (stick_rows.size or slide_rows.size):
            break
        segments += st.active
        if stick_rows.size:
            Phi = _fundamental(pl, stick) if Phi is None else Phi
            _stick_segment(pl, stick, Phi, stick_rows, st)
        if slide_rows.size:
            _slide_segment(pl, stick, slide_rows, st)
    st.ft[:, -1] = 0.0  # the last node: the contact has ended
    pn_end = pl.pn[:, -1]
    share = np.divide(st.slide_pn, pn_end, out=np.zeros(M), where=pn_end > 0)
    share = np.minimum(np.maximum(share, 0.0), 1.0)
    slip_stops = lam * st.p.max(axis=1) >= s0  # s0 − λp ≤ 0 somewhere (λ > 0)
    return TangentialResponse(
        p=st.p,
        ft=st.ft,
        dft=st.dft,
        slip_stops=slip_stops,
        slide_share=share,
        segments=segments,
        kink=st.kink,
    )


@dataclass(eq=False)
class _State:
    """The M columns' parameters, their state at the start of the current segment and the
    solution so far; the segment functions advance it in place (internal).

    s0, lam, mu, kc : (M,) parameters; mode (M,) 0 stick, ±1 slide (the sign of the force);
    t_a, p_a, pn_a (M,) the segment's start τ, p and normal percussion; v1, v2 (M,) the
    stick state (ξ or ft, and the slip s); active (M,) the columns still in contact; p, ft,
    dft (M, J) the solution on the nodes; slide_pn (M,) the normal percussion delivered
    while sliding; kink (M, J) the steps holding a switch; may_stick (M, J) the nodes where
    a slide may end (x > 0 before the last node; never for μ = 0); stalled (M,) the rows
    moved on by less than :data:`_STALL` of a step in their last two segments.
    """

    s0: np.ndarray
    lam: np.ndarray
    mu: np.ndarray
    kc: np.ndarray
    mode: np.ndarray
    t_a: np.ndarray
    p_a: np.ndarray
    pn_a: np.ndarray
    v1: np.ndarray
    v2: np.ndarray
    active: np.ndarray
    p: np.ndarray
    ft: np.ndarray
    dft: np.ndarray
    slide_pn: np.ndarray
    kink: np.ndarray
    may_stick: np.ndarray
    stalled: np.ndarray

    def switch(self, rows, t, h):
        """Rows ``rows`` switch mode at τ = ``t``: the next segment starts there, and the
        step holding it is marked as a kink."""
        self.t_a[rows] = t
        j = np.minimum((t / h).astype(int), self.kink.shape[1] - 1)
        self.kink[rows, j] = True


def _stick_segment(pl, stick, Phi, r, st):
    """Advance the rows ``r`` through one stick segment: v_j = Φ_j·Φ_{k+1}⁻¹·M_part·v_a."""
    n = pl.n
    R = _rows(r, pl.x.shape[0])
    RC = (R, None)  # the rows as a column, against the nodes
    hr = pl.h[R]
    ta = st.t_a[r]  # a copy: t_a is updated below
    k = np.minimum((ta / hr).astype(int), n - 1)
    t_k1 = (k + 1) * hr
    qg = np.sqrt(pl.at(r, pl.gauss_points(ta, t_k1), only_x=True))
    Mp = _magnus(stick, R, qg[:, 0], qg[:, 1], t_k1 - ta)
    v1, v2 = st.v1[R], st.v2[R]
    w1 = Mp[0] * v1 + Mp[1] * v2
    w2 = Mp[2] * v1 + Mp[3] * v2
    P = Phi[:, r, k + 1]  # Φ_{k+1}, det 1: its inverse is [[d, −b], [−c, a]]
    c1 = (P[3] * w1 - P[1] * w2)[:, None]
    c2 = (P[0] * w2 - P[2] * w1)[:, None]
    Ph = Phi[:, R]
    V1 = Ph[0] * c1 + Ph[1] * c2
    V2 = Ph[2] * c1 + Ph[3] * c2
    q = pl.q[R]
    F = stick.force(V1, q, RC)
    g = np.abs(F) - st.mu[RC] * pl.f[R]
    # the spring reaches the cap (the trajectory extends back past t_a, so the node before
    # the first hit is on it even when t_a lies beyond it)
    hit = (pl.node > k[:, None]) & (g > 0)
    te, has, ev, first = _first_crossing(hr, hit, g, ta)
    tr = pl.tau[R]
    own = (tr >= ta[:, None]) & (tr < te[:, None])
    _put(st.ft, R, own, F)
    _put(st.p, R, own, (st.s0[RC] - V2) / st.lam[RC])
    _put(st.dft, R, own, stick.dforce(V1, V2, q, pl.qd[R], RC))
    done = ~has
    if ev.size:
        # the state at the switch: one partial step from the node before it
        re = r[ev]
        he = pl.h[re]
        t_e = te[ev]
        tl = np.minimum((t_e / he).astype(int), n - 1)
        tl_node = tl * he
        # x at the partial step's Gauss points and x, u at the switch: one interpolation
        pts = np.concatenate([pl.gauss_points(tl_node, t_e), t_e[:, None]], axis=1)
        x, u, f = pl.at(re, pts)
        qg = np.sqrt(x)
        Mq = _magnus(stick, re, qg[:, 0], qg[:, 1], t_e - tl_node)
        a, b = V1[ev, tl], V2[ev, tl]
        xi, s = Mq[0] * a + Mq[1] * b, Mq[2] * a + Mq[3] * b
        push = stick.force(xi, qg[:, 2], re)
        # at the contact's first instant the cap is nil and the spring's force there no
        # more than rounding, whose sign could send the slide against the slip — released
        # at once, over and over: there the slide pushes as the spring does at the first
        # node beyond the cap, where |F| > μ·f
        j = first[ev]
        nil = f[:, 2] <= 1e-9 * pl.f[re, j]
        st.mode[re] = np.where(np.where(nil, F[ev, j], push) >= 0, 1, -1)
        st.switch(re, t_e, he)
        st.p_a[re] = (st.s0[re] - s) / st.lam[re]
        st.pn_a[re] = 1.0 - u[:, 2]
        done[ev] |= t_e >= pl.tau_c[re] * (1 - 1e-12)
    st.active[r[done]] = False


def _slide_segment(pl, stick, r, st):
    """Advance the rows ``r`` through one slide segment (closed form) to the release."""
    R = _rows(r, pl.x.shape[0])
    RC = (R, None)  # the rows as a column, against the nodes
    sig = st.mode[r].astype(float)
    mr = st.mu[RC]
    smr = sig[:, None] * mr
    ta = st.t_a[r]  # a copy: t_a is updated below
    pn_s = st.pn_a[r]  # a copy, as ta
    Pj = st.p_a[RC] + smr * (pl.pn[R] - pn_s[:, None])
    # release: σ·d(free spring force)/dτ − μ·f' < 0 (module notes)
    f, df = pl.f[R], pl.df[R]
    Rl = (sig * st.kc[R])[:, None] * pl.q[R] * (st.s0[RC] - st.lam[RC] * Pj) - mr * df
    if stick.total:  # on the cap ξ = σμf/(kc√x): the term kc·q'·ξ = μ·f·u/(2x)
        Rl += mr * pl.fu_2x[R]
    tr = pl.tau[R]
    # −R rises through zero (the closed form extends before t_a)
    hit = (tr > ta[:, None]) & st.may_stick[R] & (Rl < 0)
    hr = pl.h[R]
    t_r, has, ev, first = _first_crossing(hr, hit, -Rl, ta)
    at_once = has & (t_r - ta <= _STALL * hr) & st.stalled[r]
    if at_once.any():
        # released where it began, once more: the spring's and the cap's rates tie there
        # (at the contact's first instant, where the spring's rate kc·s0 — ⅔ of it by the
        # incremental rule — and μ are as good as equal, or where the cap lets go as
        # Thornton's force does) and the steps' rounding sends stick and slide back and
        # forth without moving on; the slide holds to the first node past its start
        t_r = np.where(at_once, first * hr, t_r)
    own = (tr >= ta[:, None]) & (tr < t_r[:, None])
    _put(st.ft, R, own, smr * f)
    _put(st.dft, R, own, smr * df)
    _put(st.p, R, own, Pj)
    pn_b = pl.pn[r, -1]
    if ev.size:
        re = r[ev]
        t_e = t_r[ev]
        x, u, f_ = (y[:, 0] for y in pl.at(re, t_e[:, None]))
        pn_ = 1.0 - u
        pn_b[ev] = pn_
        sm = sig[ev] * st.mu[re]
        pr = st.p_a[re] + sm * (pn_ - pn_s[ev])
        cap = sm * f_
        if stick.total:  # the spring's ξ on the cap, cap/(kc√x) (0 where x = 0)
            q = np.sqrt(x)
            st.v1[re] = np.divide(cap, st.kc[re] * q, out=np.zeros(q.shape), where=q > 0)
        else:
            st.v1[re] = cap
        st.v2[re] = st.s0[re] - st.lam[re] * pr
        st.mode[re] = 0
        st.switch(re, t_e, pl.h[re])
    st.slide_pn[R] += pn_b - pn_s
    st.active[r[~has]] = False
