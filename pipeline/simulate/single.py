"""One impact, integrated adaptively: :func:`impact` (see :mod:`pipeline.simulate`)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .. import contact
from ..errors import InputError
from ..scene import Scene
from ._common import (
    _SELF_SIMILAR,
    _check_kt_scale,
    _check_models,
    _check_tangential_damping,
    _check_target,
    _first_contact_mode,
    _law,
    _param,
    _release_rate,
    default_normal,
)

if TYPE_CHECKING:
    import xarray

__all__ = ["impact"]

_F_END = 1e-12  # separation: dimensionless Fn below this during restitution
_MAX_SEGMENTS = 400
#: largest step in τ = t·v0/δ_max (the elastic contact lasts 2.94): events are sign changes
#: between steps, and a loose rtol otherwise lets one step hide a stick-slip excursion
_MAX_STEP = 0.05


@dataclass(frozen=True)
class _Problem:
    """Dimensionless constants of one impact (internal)."""

    law: contact.NormalLaw
    param: object
    K: float
    m_eff: float
    v0: float  # normal approach speed [m/s]
    dstar: float  # elastic δ_max [m]
    tstar: float  # δ_max / v0 [s]
    fscale: float  # m*·v0²/δ_max [N]
    kel: float  # elastic Fn / fscale = kel·x^1.5
    kt_coef: float  # k_t·δ*²/(m* v0²) = kt_coef·√x
    mu: float
    lam: float  # m*/m_t
    s0: float  # |initial slip| / v0
    vt0: float  # initial v_t / v0 on the slip axis
    spin0: float  # initial spin [rad/s] on the slip axis
    sign: float  # +1, or −1 if the initial slip is against the scene's t axis
    R1: float
    m1: float
    kappa1: float
    m2: float
    kappa2: float
    R2: float
    hc_c: float | None = None  # c of a Hertz / Hunt–Crossley-family law (fast scalar path)
    xg: float = 0.0  # tangential dashpot / normal dashpot at the same overlap (LAMMPS x_γ,t)

    def fs(self, x, u):
        """Dimensionless normal force for scalars (float)."""
        if x <= 0:
            return 0.0
        if self.hc_c is not None:
            return max(self.kel * x * math.sqrt(x) * (1.0 + self.hc_c * u), 0.0)
        return float(self.fn(x, u))

    def fs_raw(self, x, u):
        """Dimensionless normal force WITHOUT the no-adhesion clip, for scalars, x > 0."""
        if self.hc_c is not None:
            return self.kel * x * math.sqrt(x) * (1.0 + self.hc_c * u)
        raw = contact._RAW_FORCES.get(self.law.name, self.law.force)
        F = raw(x * self.dstar, u * self.v0, self.param, self.K, self.m_eff, self.v0)
        return float(F) / self.fscale

    def fs_rate(self, x, u):
        """d(fn)/dτ along the trajectory for scalars, x > 0: central difference of the
        UNCLIPPED law with a step that keeps x ± h·u > 0. (Differencing the clipped force
        across F = 0, where a dashpot law lets go, halves the rate and made the slide →
        stick event chatter.)"""
        h = 1e-7 * min(1.0, 0.5 * x / abs(u)) if u != 0 else 1e-7
        f = self.fs(x, u)
        return (self.fs_raw(x + h * u, u - h * f) - self.fs_raw(x - h * u, u + h * f)) / (2 * h)

    def kts(self, x):
        return self.kt_coef * math.sqrt(x) if x > 0 else 0.0

    def etas(self, x):
        """Tangential dashpot coefficient x_γ,t·η_n(δ) over m*·v0/δ*, for scalars."""
        if self.xg == 0.0 or x <= 0:
            return 0.0
        if self.hc_c is not None:
            return self.xg * self.kel * self.hc_c * x * math.sqrt(x)
        eta = self.law.damping(x * self.dstar, self.param, self.K, self.m_eff, self.v0)
        return self.xg * float(eta) * self.dstar / (self.m_eff * self.v0)

    def etas_rate(self, x, u):
        """d(etas)/dτ along the trajectory (central difference keeping x ± h·u > 0)."""
        if self.xg == 0.0 or x <= 0:
            return 0.0
        h = 1e-7 * min(1.0, 0.5 * x / abs(u)) if u != 0 else 1e-7
        return (self.etas(x + h * u) - self.etas(x - h * u)) / (2 * h)

    def eta(self, x):
        """Tangential dashpot coefficient (dimensionless) for arrays."""
        x = np.asarray(x, dtype=float)
        if self.xg == 0.0:
            return np.zeros_like(x)
        eta = self.law.damping(
            np.maximum(x, 0.0) * self.dstar, self.param, self.K, self.m_eff, self.v0
        )
        return np.where(x > 0, self.xg * eta * self.dstar / (self.m_eff * self.v0), 0.0)

    def fn(self, x, u):
        """Dimensionless normal force, zero out of contact."""
        x = np.asarray(x, dtype=float)
        f = self.law.force(
            x * self.dstar, np.asarray(u) * self.v0, self.param, self.K, self.m_eff, self.v0
        )
        return np.where(x > 0, f / self.fscale, 0.0)

    def kt(self, x):
        return self.kt_coef * np.sqrt(np.maximum(x, 0.0))


def _setup(
    scene: Scene,
    normal,
    alpha=None,
    param=None,
    target_kappa=None,
    tangential_damping=0.0,
    kt_scale=1.0,
) -> _Problem:
    _check_target(scene)
    for name in Scene.field_names():
        v = getattr(scene, name)
        if isinstance(v, np.ndarray) and v.size != 1:
            raise InputError(
                "impact() simulates one scene; use impact_outcomes() for arrays "
                f"(Scene.{name} has {v.size} values)"
            )
    law = _law(normal)
    if param is None and alpha is None:
        scene.require("e", why="calibrating the normal law's damping")
    if normal == "hertz" and scene.e is not None and scene.e < 1:
        raise InputError(
            f"the elastic 'hertz' law cannot give e = {scene.e}; choose a damped "
            "law, e.g. normal='hunt_crossley'"
        )
    hi = contact.hertz_impact(scene)
    v0 = hi.v0
    p = _param(law, scene.e, hi.K, hi.m_eff, v0, alpha, param)
    m1 = float(scene.m)
    m2 = float(scene.target_mass)
    k1 = float(scene.kappa)
    k2 = k1 if target_kappa is None else float(target_kappa)
    R1, R2 = float(scene.radius), float(scene.target_radius)
    # m*/m_t with 1/m_t = (1+1/κ1)/m1 + (1+1/κ2)/m2; a fixed target (m2 = inf) adds nothing
    lam = hi.m_eff * ((1 + 1 / k1) / m1 + (0.0 if math.isinf(m2) else (1 + 1 / k2) / m2))
    vt0 = float(scene.v_t0)
    spin = float(scene.spin)
    s0 = vt0 - spin * R1
    sign = -1.0 if s0 < 0 else 1.0
    fscale = hi.m_eff * v0**2 / hi.delta_max
    # k_t·δ*²/(m*·v0²) = kt_coef·√(δ/δ*), k_t = 8·G*·√(R*·δ) (contact.mindlin_stiffness)
    kt_coef = (
        kt_scale
        * 8.0
        * scene.G_eff
        * math.sqrt(scene.R_eff * hi.delta_max)
        * hi.delta_max**2
        / (hi.m_eff * v0**2)
    )
    return _Problem(
        law=law,
        param=p,
        K=hi.K,
        m_eff=hi.m_eff,
        v0=v0,
        dstar=hi.delta_max,
        tstar=hi.t_star,
        fscale=fscale,
        kel=hi.K * hi.delta_max**2.5 / (hi.m_eff * v0**2),
        kt_coef=kt_coef,
        mu=0.0 if scene.mu is None else float(scene.mu),  # None: frictionless model
        lam=lam,
        s0=abs(s0) / v0,
        vt0=sign * vt0 / v0,
        spin0=sign * spin,
        sign=sign,
        R1=R1,
        m1=m1,
        kappa1=k1,
        m2=m2,
        kappa2=k2,
        R2=R2,
        hc_c=_hc_c(law, p),
        xg=float(tangential_damping),
    )


def _hc_c(law, p):
    if law.name == "hertz":
        return 0.0
    if law.name in _SELF_SIMILAR and np.size(p) == 1:
        return float(np.asarray(p, dtype=float).ravel()[0])
    return None


# ----------------------------------------------------------------------------- single
# State y = [x, u, p, z, Wd, Wf]: x = δ/δ*, u = δ̇/v0, p = Pt/(m* v0), z = ξ/δ* (total rule)
# or Ft/fscale (incremental rule), Wd, Wf = damping and friction work / (m* v0²).
# Modes: ("free",) no friction; ("slide", σ) Ft = σ μ Fn; ("stick",) Coulomb: Ft = 0,
# Mindlin: Ft from the spring.


def _make_rhs(pb: _Problem, tangential, history, mode):
    kind = mode[0]
    sig = mode[1] if kind == "slide" else 0.0

    def rhs(tau, y):
        x, u, p, z = y[0], y[1], y[2], y[3]
        fn = pb.fs(x, u)
        fel = pb.kel * max(x, 0.0) ** 1.5
        s = pb.s0 - pb.lam * p
        dz = 0.0
        if kind == "slide":
            ft = sig * pb.mu * fn
        elif kind == "stick" and tangential == "mindlin":
            k = pb.kts(x)
            if history == "total":
                ft = k * z + pb.etas(x) * s
                dz = s
            else:
                ft = z + pb.etas(x) * s
                dz = k * s
        else:
            ft = 0.0
        return [u, -fn, ft, dz, (fn - fel) * u, ft * s]

    return rhs


def _spring_ft(pb: _Problem, history, x, z):
    """Dimensionless Mindlin spring force of the stored state z (ξ or Ft), for scalars."""
    return pb.kts(x) * z if history == "total" else z


def _stick_ft(pb: _Problem, history, y):
    """Dimensionless Ft of a sticking Mindlin contact: spring + tangential dashpot (scalars)."""
    x, p, z = y[0], y[2], y[3]
    return _spring_ft(pb, history, x, z) + pb.etas(x) * (pb.s0 - pb.lam * p)


def _ft_of(pb, tangential, history, mode, y):
    """Dimensionless Ft for states y (shape (6, n)) in a mode."""
    x, u, z = y[0], y[1], y[3]
    if mode[0] == "slide":
        return mode[1] * pb.mu * pb.fn(x, u)
    if mode[0] == "stick" and tangential == "mindlin":
        spring = pb.kt(x) * z if history == "total" else z
        return spring + pb.eta(x) * (pb.s0 - pb.lam * y[2])
    return np.zeros_like(x)


def _events(pb: _Problem, tangential, history, mode, tau0=0.0):
    def sep_x(tau, y):
        return y[0]

    def sep_f(tau, y):
        return pb.fs(y[0], y[1]) - _F_END if y[1] < 0 else 1.0

    sep_x.terminal = sep_f.terminal = True
    sep_x.direction = sep_f.direction = -1

    def max_comp(tau, y):
        return y[1]

    max_comp.terminal = False
    max_comp.direction = -1
    # Hertz and Hunt–Crossley forces stay positive until δ = 0: end exactly there; other
    # laws (dashpots) may let go earlier, when Fn falls to zero (threshold _F_END)
    evs = [sep_x, sep_f if pb.hc_c is None else _never, max_comp]
    kind = mode[0]
    if tangential == "coulomb" and kind == "slide":

        def stop(tau, y):
            return mode[1] * (pb.s0 - pb.lam * y[2])

        stop.terminal = True
        stop.direction = -1
        evs.append(stop)
    elif tangential == "mindlin" and kind == "stick":

        def cap(tau, y):
            x, u = y[0], y[1]
            if x <= 0:  # first contact: under the cap; past separation: keep the sign
                return 1.0 if u > 0 else -1.0
            if tau <= tau0:  # a stick that begins on the cap (released from sliding)
                return 1.0  # begins inside it: rounding must not hide the next crossing
            return pb.mu * pb.fs(x, u) - abs(_stick_ft(pb, history, y))

        cap.terminal = True
        cap.direction = -1
        evs.append(cap)
    elif tangential == "mindlin" and kind == "slide":
        sig = mode[1]

        def release(tau, y):
            return _release_rate_at(pb, history, sig, y[0], y[1], y[2]) if y[0] > 0 else 1.0

        release.terminal = True
        release.direction = -1
        evs.append(release)
    return evs


def _release_rate_at(pb: _Problem, history, sig, x, u, p):
    """Release rate (:func:`._common._release_rate`) of the scalar state (x > 0)."""
    return _release_rate(
        sig,
        x,
        u,
        pb.s0 - pb.lam * p,
        pb.fs(x, u),
        pb.fs_rate(x, u),
        pb.kts(x),
        pb.etas(x),
        pb.etas_rate(x, u),
        pb.mu,
        pb.lam,
        history == "total",
    )


def _never(tau, y):
    return 1.0


_never.terminal = True
_never.direction = -1


def _initial_mode(pb: _Problem, tangential, history):
    if tangential == "none" or pb.mu == 0 or pb.s0 == 0:
        return ("free",) if tangential == "none" or pb.mu == 0 else ("stick",)
    if tangential == "coulomb":
        return ("slide", 1.0)
    # Mindlin: stick, or slide forward or backward (_first_contact_mode)
    mode = _first_contact_mode(pb.fs, pb.etas, pb.kt_coef, pb.s0, pb.mu, pb.lam, history == "total")
    return ("stick",) if mode == 0 else ("slide", float(mode))


def _solve(pb: _Problem, tangential, history, rtol, atol, method):
    from scipy.integrate import solve_ivp  # loaded on first use

    ps = max(pb.mu * 2.0, pb.s0 / pb.lam, 1e-3)
    zs = ps if history == "incremental" else max(pb.mu, 1e-3)
    scale = np.array([1.0, 1.0, ps, zs, 1.0, max(1.0, ps * pb.s0)])
    atol_v = atol * scale
    y = np.zeros(6)
    y[1] = 1.0
    tau0 = 0.0
    mode = _initial_mode(pb, tangential, history)
    segments = []
    tau_max = 1e4
    delta_max_tau = None
    for _ in range(_MAX_SEGMENTS):
        evs = _events(pb, tangential, history, mode, tau0)
        sol = solve_ivp(
            _make_rhs(pb, tangential, history, mode),
            (tau0, tau_max),
            y,
            method=method,
            rtol=rtol,
            atol=atol_v,
            events=evs,
            dense_output=True,
            max_step=_MAX_STEP,
        )
        if sol.status < 0:
            raise RuntimeError(f"impact integration failed: {sol.message}")
        if len(sol.t_events[2]):
            delta_max_tau = float(sol.t_events[2][0])
        segments.append((sol.t[0], sol.t[-1], sol.sol, mode, sol.t))
        if sol.status == 0:
            raise RuntimeError("the bodies did not separate; check the normal law's parameter")
        t_end = sol.t[-1]
        fired = [k for k, te in enumerate(sol.t_events) if len(te) and te[-1] == t_end and k != 2]
        y = sol.y[:, -1].copy()
        if 0 in fired or 1 in fired:
            return segments, y, delta_max_tau
        tau0 = t_end
        kind = mode[0]
        if tangential == "coulomb":
            mode = ("stick",)
        elif kind == "stick":  # spring reached the cap: slide in the direction of Ft
            ft = _stick_ft(pb, history, y)
            mode = ("slide", 1.0 if ft >= 0 else -1.0)
        else:  # leave the cap: stick with spring + dashpot exactly at the cap
            sig = mode[1]
            fn = pb.fs(y[0], y[1])
            spring = sig * pb.mu * fn - pb.etas(y[0]) * (pb.s0 - pb.lam * y[2])
            if history == "incremental":
                y[3] = spring
            else:
                y[3] = spring / pb.kts(y[0]) if y[0] > 0 else 0.0
            mode = ("stick",)
    raise RuntimeError(
        f"more than {_MAX_SEGMENTS} stick/slide switches; loosen the tolerance or check the scene"
    )


def _golden_max(f, lo, hi, xtol):
    """max of a unimodal f on [lo, hi] by golden-section search (to xtol in the argument)."""
    g = 0.5 * (math.sqrt(5.0) - 1.0)
    a, b = lo, hi
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = f(c), f(d)
    while b - a > xtol:
        if fc > fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = f(d)
    return max(fc, fd)


def _friction_ratio(pb: _Problem, tangential, history, segments):
    """max |Ft|/(μ·Fn) over the accepted steps in contact (NaN without friction)."""
    if tangential == "none" or pb.mu == 0:
        return math.nan
    worst = 0.0
    for _t0, _t1, sol, mode, ts in segments:
        y = sol(ts)
        fn = pb.fn(y[0], y[1])
        ft = _ft_of(pb, tangential, history, mode, y)
        inside = (y[0] > 0) & (fn > 0)
        if np.any(inside):
            worst = max(worst, float(np.max(np.abs(ft[inside]) / (pb.mu * fn[inside]))))
    return worst


def impact(
    scene: Scene,
    normal=None,
    tangential="mindlin",
    *,
    history="total",
    samples=2001,
    pad=0.0,
    rtol=1e-9,
    atol=None,
    method="DOP853",
    alpha=None,
    param=None,
    target_kappa=None,
    tangential_damping=0.0,
    kt_scale=1.0,
) -> xarray.Dataset:
    """Simulate one oblique impact and return its dense force record.

    Parameters
    ----------
    scene : Scene
        One impact (scalar fields); needs ``E`` and ``nu``.
    normal : str, optional
        A name in :data:`pipeline.contact.NORMAL_LAWS`. Default ``"hertz"`` if
        ``scene.e == 1`` else ``"hunt_crossley"``. ``"hertz"`` with ``scene.e < 1``
        raises :class:`InputError`.
    tangential : {"mindlin", "coulomb", "none"}
        Tangential model (module notes).
    history : {"total", "incremental"}
        Mindlin displacement-history rule (:func:`pipeline.contact.mindlin_total`,
        :func:`pipeline.contact.mindlin_incremental`).
    samples : int
        Number of samples over the contact [0, t_contact] (default 2001).
    pad : float
        Zero-force padding before and after the contact, as a fraction of t_contact
        (sampled at the same interval).
    rtol, atol : float
        Tolerances of the dimensionless integration (δ/δ_max, velocities/v_n0); ``atol``
        defaults to ``rtol``.
    method : str
        ``solve_ivp`` method (default ``"DOP853"``).
    alpha : float, optional
        Fixed material damping constant (e.g. α [s/m] with c = α·v0 for the Hunt–Crossley
        family) instead of calibrating to ``scene.e``; ``e_n`` then follows from the
        simulation.
    param : optional
        The law's damping parameter itself (bypasses calibration).
    target_kappa : float, optional
        I/(m·R²) of a free second sphere (default: the ball's ``kappa``).
    tangential_damping : float
        LAMMPS's x_γ,t [-] (≥ 0, default 0): a tangential dashpot whose coefficient is this
        multiple of the normal law's dashpot coefficient η_n(δ) at the same overlap
        (:attr:`pipeline.contact.NormalLaw.damping`), acting on the slip in parallel with
        the Mindlin spring; spring plus dashpot are capped together at μ·Fn, as in LAMMPS
        ``tangential mindlin`` (:mod:`pipeline.contact.tangential`, where YADE's
        convention is given beside it). Only with ``tangential="mindlin"``; zero for the
        elastic ``"hertz"`` law, which has no normal dashpot.
    kt_scale : float
        Tangential stiffness as a multiple of Mindlin's 8·G*·a [-] (> 0, default 1): real,
        rough contacts are softer.

    Returns
    -------
    xarray.Dataset
        Record (:mod:`pipeline.record`, kind ``"simulated"``) with ``Fn``, ``Ft`` [N] and
        ``delta`` [m], ``slip`` [m/s], ``vt`` [m/s], ``spin`` [rad/s] (and ``xi`` [m], the
        elastic tangential displacement Ft/k_t, for Mindlin); ``attrs``: ``e_n``, ``e_t``
        (tangential velocity of the centre after/before), ``omega`` [rad/s] (spin after
        impact, positive in the sense Pt > 0 produces: on the initial-slip axis, module
        notes), ``t_contact`` [s], ``F_max`` [N], ``delta_max`` [m], ``rebound_angle_deg`` (centre)
        and ``rebound_angle_contact_deg`` (contact point), ``E_initial``, ``E_final``,
        ``W_friction``, ``W_damping`` [J] (kinetic energies in the centre-of-mass frame
        of the target surface; W_friction = ∫Ft·s dt, W_damping = ∫(Fn − Kδ^{3/2})·δ̇ dt
        + (2/5)·K·δ_sep^{5/2}, the last term the elastic energy a law that lets go at
        δ_sep > 0 leaves in the contact (dashpot, viscoelastic; zero for the Hunt–Crossley
        family), so E_initial − E_final = W_friction + W_damping; W_friction can be slightly
        negative under the total-displacement rule, which is not energy-consistent —
        :func:`pipeline.contact.mindlin_total`), ``Pn_final``, ``Pt_final`` [N·s],
        ``damping_param``, ``damping_param_name``, ``normal_model``,
        ``tangential_model``, ``history_rule``, ``tangential_axis_sign``,
        ``stick_slip_segments``, ``tangential_damping``, ``friction_ratio_max`` (the largest
        |Ft|/(μ·Fn) over the solver's accepted steps in contact: ≤ 1 up to rounding, Coulomb's
        law holds), the solver settings and the scene fields.

    Raises
    ------
    InputError
        Unknown model names, an array scene, missing elastic constants, ``"hertz"`` with
        e < 1, or an e the law cannot reach.
    """
    _check_models(tangential, history)
    if int(samples) < 3:
        raise InputError("samples must be at least 3")
    if not isinstance(scene, Scene):
        raise InputError("impact() needs a pipeline.Scene")
    if tangential != "none":
        scene.require("mu", why=f"the {tangential!r} tangential model")
    if normal is None:
        scene.require("e", why="choosing the default normal law")
    normal_name = default_normal(scene.e) if normal is None else normal
    xg = _check_tangential_damping(tangential_damping, tangential)
    pb = _setup(scene, normal_name, alpha, param, target_kappa, xg, _check_kt_scale(kt_scale))
    atol = rtol if atol is None else atol
    segments, y_end, tau_dmax = _solve(pb, tangential, history, rtol, atol, method)
    friction_ratio = _friction_ratio(pb, tangential, history, segments)
    tau_c = float(segments[-1][1])

    # ---- sample the dense solution
    n = int(samples)
    tau_s = np.linspace(0.0, tau_c, n)
    Y = np.empty((6, n))
    FT = np.empty(n)
    bounds = np.array([seg[1] for seg in segments])
    which = np.minimum(np.searchsorted(bounds, tau_s, side="left"), len(segments) - 1)
    for k, (_t0, _t1, sol, mode, _ts) in enumerate(segments):
        sel = which == k
        if np.any(sel):
            Y[:, sel] = sol(tau_s[sel])
            FT[sel] = _ft_of(pb, tangential, history, mode, Y[:, sel])
    Y[:, -1] = y_end
    FN = pb.fn(Y[0], Y[1])
    FN[0] = pb.fn(0.0, 1.0)
    FT[-1] = _ft_of(pb, tangential, history, segments[-1][3], y_end[:, None])[0]
    if np.max(np.abs(FT)) <= 1e-12 * np.max(np.abs(FN)):
        # no tangential force beyond the integration's resolution (no initial slip, as at
        # normal incidence): the interpolants' rounding, ~1e-24 of Fn, is not a force
        FT[:] = 0.0

    # ---- refine F_max and δ_max on the dense output
    def f_at(tau):
        k = min(int(np.searchsorted(bounds, tau, side="left")), len(segments) - 1)
        yy = segments[k][2](tau)
        return float(pb.fn(yy[0], yy[1]))

    i = int(np.argmax(FN))
    lo, hi_ = tau_s[max(i - 1, 0)], tau_s[min(i + 1, n - 1)]
    fmax = max(_golden_max(f_at, lo, hi_, 1e-12 * tau_c), float(FN[i]))
    if tau_dmax is not None:
        k = min(int(np.searchsorted(bounds, tau_dmax, side="left")), len(segments) - 1)
        xmax = float(segments[k][2](tau_dmax)[0])
    else:
        xmax = float(np.max(Y[0]))

    # ---- outcome
    v0, m = pb.v0, pb.m_eff
    u_end, p_end = y_end[1], y_end[2]
    e_n = -u_end
    Pt = p_end * m * v0
    vt_after = (pb.vt0 - p_end) * v0
    vt_before = pb.vt0 * v0
    e_t = vt_after / vt_before if vt_before != 0 else math.nan
    I1 = pb.kappa1 * pb.m1 * pb.R1**2
    omega = pb.spin0 + Pt * pb.R1 / I1
    inv_I2 = 0.0 if math.isinf(pb.m2) or math.isinf(pb.R2) else 1.0 / (pb.kappa2 * pb.m2 * pb.R2**2)
    omega2 = Pt * pb.R2 * inv_I2 if inv_I2 else 0.0
    slip_after = vt_after - omega * pb.R1 - omega2 * pb.R2
    vn_after = e_n * v0

    def kin(vn, vt, w1, w2):
        e = 0.5 * m * (vn**2 + vt**2) + 0.5 * I1 * w1**2
        return e + (0.5 * w2**2 / inv_I2 if inv_I2 else 0.0)

    E_i = kin(v0, vt_before, pb.spin0, 0.0)
    E_f = kin(vn_after, vt_after, omega, omega2)

    # ---- record
    t = tau_s * pb.tstar
    fn_N = FN * pb.fscale
    ft_N = FT * pb.fscale
    p_s = Y[2]
    vt = (pb.vt0 - p_s) * v0
    spin_s = pb.spin0 + p_s * m * v0 * pb.R1 / I1
    spin2_s = p_s * m * v0 * pb.R2 * inv_I2 if inv_I2 else 0.0 * p_s
    slip = vt - spin_s * pb.R1 - spin2_s * (pb.R2 if inv_I2 else 0.0)
    extra = {
        "delta": (Y[0] * pb.dstar, "m", "normal approach (overlap)"),
        "slip": (slip, "m/s", "slip velocity of the contact point (> 0 along the initial slip)"),
        "vt": (vt, "m/s", "tangential velocity of the centre relative to the target"),
        "spin": (spin_s, "rad/s", "ball spin (> 0 in the sense Ft > 0 produces)"),
    }
    if tangential == "mindlin":
        kt = pb.kt(Y[0])
        spring = FT - pb.eta(Y[0]) * (pb.s0 - pb.lam * Y[2])
        with np.errstate(divide="ignore", invalid="ignore"):
            xi = np.where(kt > 0, spring / np.where(kt > 0, kt, 1.0), 0.0) * pb.dstar
        extra["xi"] = (xi, "m", "elastic tangential displacement (Ft - dashpot)/k_t")
    if pad > 0:
        dt = t[1] - t[0]
        npad = int(math.ceil(pad * t[-1] / dt))
        before = -dt * np.arange(npad, 0, -1)
        after = t[-1] + dt * np.arange(1, npad + 1)
        t = np.concatenate([before, t, after])

        def padded(a, lead, tail):
            return np.concatenate([np.full(npad, lead), a, np.full(npad, tail)])

        fn_N = padded(fn_N, 0.0, 0.0)
        ft_N = padded(ft_N, 0.0, 0.0)
        # out of contact δ and ξ are 0 (δ < 0 is no contact); velocities and spin keep their
        # values before and after the impact
        contact_vars = ("delta", "xi")
        extra = {
            k: (
                padded(v[0], 0.0, 0.0) if k in contact_vars else padded(v[0], v[0][0], v[0][-1]),
                v[1],
                v[2],
            )
            for k, v in extra.items()
        }
    # a law that lets go at δ > 0 (dashpot, viscoelastic) strands the elastic energy
    # (2/5)·K·δ^{5/2} in the contact: the clipped force never returns it, so it is lost
    x_sep = max(float(y_end[0]), 0.0)
    W_d = (y_end[4] + 0.4 * pb.kel * x_sep**2.5) * m * v0**2
    W_f = y_end[5] * m * v0**2
    attrs = {
        "source": f"pipeline.simulate.impact normal={normal_name} tangential={tangential}"
        + (f" history={history}" if tangential == "mindlin" else ""),
        "sha256": "",
        "format": "simulate.impact",
        "kind": "simulated",
        "normal_model": normal_name,
        "tangential_model": tangential,
        "history_rule": history if tangential == "mindlin" else "",
        "damping_param": float(np.asarray(pb.param, dtype=float).ravel()[0])
        if np.size(pb.param)
        else 0.0,
        "damping_param_name": pb.law.parameter,
        "e_n": float(e_n),
        "e_t": float(e_t),
        "omega": float(omega),
        "t_contact": float(tau_c * pb.tstar),
        "F_max": float(fmax * pb.fscale),
        "delta_max": float(xmax * pb.dstar),
        "Pn_final": float((1.0 + e_n) * m * v0),
        "Pt_final": float(Pt),
        "rebound_angle_deg": float(math.degrees(math.atan2(pb.sign * vt_after, vn_after))),
        "rebound_angle_contact_deg": float(
            math.degrees(math.atan2(pb.sign * slip_after, vn_after))
        ),
        "E_initial": float(E_i),
        "E_final": float(E_f),
        "W_friction": float(W_f),
        "W_damping": float(W_d),
        "tangential_axis_sign": float(pb.sign),
        "rtol": float(rtol),
        "atol": float(atol),
        "method": method,
        "stick_slip_segments": len(segments),
        "tangential_damping": xg,
        "kt_scale": float(kt_scale),
        "friction_ratio_max": friction_ratio,
    }
    if target_kappa is not None:
        attrs["target_kappa"] = float(target_kappa)
    if alpha is not None:
        attrs["alpha"] = float(alpha)
    attrs.update(scene.to_dict())
    from ..record import make_record  # xarray: loaded on first use

    return make_record(t, {"Fn": fn_N, "Ft": ft_N}, attrs=attrs, extra=extra)
