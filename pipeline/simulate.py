r"""Hertz–Mindlin simulation of an oblique impact: records with known truth.

Degrees of freedom (PHYSICS.md §1): the normal approach δ, the tangential velocity of the
centre v_t and the spin ω of the ball (and, for a free second sphere, its spin). With the
normal force :math:`F_n` (> 0 compressive) and the tangential force :math:`F_t` (> 0
opposing the initial slip)

.. math::

    m^*\ddot\delta = -F_n, \qquad m^*\dot v_t = -F_t, \qquad
    I_1\dot\omega_1 = F_t R_1, \qquad I_2\dot\omega_2 = F_t R_2,

    s = v_t - \omega_1 R_1 - \omega_2 R_2, \qquad
    \dot s = -F_t/m_t, \qquad
    \frac{1}{m_t} = \frac{1 + 1/\kappa_1}{m_1} + \frac{1 + 1/\kappa_2}{m_2}.

``v_t`` is the tangential velocity of ball 1's centre relative to ball 2's centre (or to
the target surface, which may move at ``scene.surface_speed``); both spins are counted
positive in the sense a positive :math:`F_t` produces (Pt > 0 spins the ball up). For a
fixed target (``target_mass = inf``) :math:`m^* = m`, :math:`m_t = m\kappa/(1+\kappa)`
and :math:`s(P_t) = v_{t0} - (1 + 1/\kappa)P_t/m` (PHYSICS.md §1). For two free spheres
the normal problem uses :math:`m^* = m_1 m_2/(m_1 + m_2)` and the slip uses :math:`m_t`
above (the second sphere's κ is ``target_kappa``, default the ball's). A movable flat
target (finite ``target_mass``, infinite ``target_radius``) is refused, as by
:func:`pipeline.rigid.sphere_on_plane`: its rotational term depends on where its centre of
mass lies, which the scene does not say.

The tangential axis points along the initial slip :math:`s_0 = v_{t0} - \omega_0 R`: if a
spin or a surface speed makes :math:`s_0 < 0`, every tangential output (``Ft``, ``slip``,
``vt``, ``spin``, ``omega``, ``Pt_final``) is reported on the flipped axis so that
``Ft > 0`` still opposes the initial slip (``attrs["tangential_axis_sign"] = -1``). This is
the convention API.md and PHYSICS.md §1 fix for the outputs: ``Pt > 0`` opposes the
INITIAL slip and ``omega`` is positive in the sense ``Pt > 0`` produces, so
:math:`\omega = \sigma\omega_0 + P_t R/I` with :math:`\sigma` = ``tangential_axis_sign``.
The scene's own inputs (``spin``, ``surface_speed``, the sense of :math:`v\sin\alpha`) are
on the scene's axis; multiply a reported value by σ to return to it. ``e_t`` is the same
on either axis; the rebound angles are measured on the scene's axis.

Equations are integrated in dimensionless form: δ/δ_max, t/t* with δ_max the elastic
Hertz maximum approach and t* = δ_max/v_n0 (:func:`pipeline.contact.hertz_impact`),
forces over m*·v_n0²/δ_max, so tolerances are relative to the problem's own scale
(the default 1e-9 means nanometres on a micrometre indentation).

Tangential models
-----------------
``"none"``
    Frictionless.
``"coulomb"``
    No tangential compliance: :math:`F_t = \mu F_n` while the contact point slides; when
    the slip reaches zero it sticks (for a sphere nothing drives it to slip again, so
    :math:`F_t = 0` from then on). This is the exact limit of a regularised law
    :math:`\mu F_n\tanh(s/v_{reg})` as :math:`v_{reg}\to 0`, handled with an event at
    s = 0 instead of a stiff regularisation; it reproduces Routh's broken line
    (PHYSICS.md §3) for any normal law.
``"mindlin"``
    Tangential spring :math:`k_t = 8G^*a` with the Coulomb cap and a displacement history,
    see :func:`pipeline.contact.mindlin_total` (``history="total"``, the default, as
    LAMMPS ``mindlin`` and LIGGGHTS ``tangential history``) and
    :func:`pipeline.contact.mindlin_incremental` (``history="incremental"``, as YADE
    ``MindlinPhys`` and LAMMPS ``mindlin/force``). The single-impact solver integrates
    the continuous-time limit of these rules exactly, switching between stick and slide
    at events.

Two paths:

- :func:`impact` — one scene, adaptive ``solve_ivp`` with events at every stick/slide
  switch and at separation; returns a record (``xarray.Dataset``).
- :func:`impact_outcomes` — thousands of scenes at once: a fixed-step RK4 in dimensionless
  time over numpy arrays (no per-scene Python loop), the elastic normal problem taken from
  the exact self-similar solution :func:`pipeline.contact.hertz_pulse`, Coulomb friction
  from Routh's closed form; returns :class:`ImpactOutcomes`.

References
----------
R. D. Mindlin, J. Appl. Mech. 16:259 (1949), doi:10.1115/1.4009973.
R. D. Mindlin, H. Deresiewicz, J. Appl. Mech. 20:327 (1953), doi:10.1115/1.4010702.
N. Maw, J. R. Barber, J. N. Fawcett, Wear 38:101 (1976), doi:10.1016/0043-1648(76)90201-7.
Y. C. Chung, J. Y. Ooi, Granular Matter 13:643 (2011), doi:10.1007/s10035-011-0277-0.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
import xarray as xr
from scipy import integrate, optimize

from . import contact
from .errors import InputError, PipelineWarning
from .record import make_record
from .scene import Scene
from .sensor_model import to_sensor

__all__ = [
    "impact",
    "TANGENTIAL_MODELS",
    "HISTORY_RULES",
    "default_normal",
    "to_sensor",
]

TANGENTIAL_MODELS = ("none", "coulomb", "mindlin")
HISTORY_RULES = ("total", "incremental")

_F_END = 1e-12  # separation: dimensionless Fn below this during restitution
_MAX_SEGMENTS = 400


def default_normal(e) -> str:
    """The default normal law for restitution ``e``: ``"hertz"`` if e == 1, else
    ``"hunt_crossley"`` (API.md)."""
    return "hertz" if float(e) == 1.0 else "hunt_crossley"


# ----------------------------------------------------------------------------- setup
def _check_models(tangential, history):
    if tangential not in TANGENTIAL_MODELS:
        raise InputError(
            f"unknown tangential model {tangential!r}; choose one of {TANGENTIAL_MODELS}"
        )
    if history not in HISTORY_RULES:
        raise InputError(f"unknown Mindlin history rule {history!r}; choose one of {HISTORY_RULES}")


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

    def fn(self, x, u):
        """Dimensionless normal force, zero out of contact."""
        x = np.asarray(x, dtype=float)
        f = self.law.force(
            x * self.dstar, np.asarray(u) * self.v0, self.param, self.K, self.m_eff, self.v0
        )
        return np.where(x > 0, f / self.fscale, 0.0)

    def kt(self, x):
        return self.kt_coef * np.sqrt(np.maximum(x, 0.0))


_law = contact._law  # name -> NormalLaw, InputError naming the choices


def _param(law, e, K, m_eff, v0, alpha=None, param=None):
    """The law's damping parameter: given, from a material constant, or calibrated to e."""
    if param is not None:
        return param
    if alpha is not None:
        return law.material_to_param(alpha, K, m_eff, v0)  # e.g. c = α·v0 (PHYSICS.md §4)
    return law.calibrate(e)


def _check_target(scene: Scene):
    """Refuse a movable flat target, as :func:`pipeline.rigid.sphere_on_plane` does."""
    if np.any(np.isfinite(np.asarray(scene.target_mass)) & np.isinf(scene.target_radius)):
        raise InputError(
            "a movable flat target (finite target_mass, target_radius = inf) is not a scene "
            "the simulator can take: its tangential inverse mass depends on where its centre "
            "of mass lies, which the scene does not say. Give target_radius for a free "
            "sphere, or leave target_mass = inf for a fixed target"
        )


def _setup(scene: Scene, normal, alpha=None, param=None, target_kappa=None) -> _Problem:
    _check_target(scene)
    for name in Scene.field_names():
        v = getattr(scene, name)
        if isinstance(v, np.ndarray) and v.size != 1:
            raise InputError(
                "impact() simulates one scene; use impact_outcomes() for arrays "
                f"(Scene.{name} has {v.size} values)"
            )
    law = _law(normal)
    if normal == "hertz" and scene.e < 1:
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
        8.0
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
        mu=float(scene.mu),
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
                ft = k * z
                dz = s
            else:
                ft = z
                dz = k * s
        else:
            ft = 0.0
        return [u, -fn, ft, dz, (fn - fel) * u, ft * s]

    return rhs


def _spring_ft(pb: _Problem, history, x, z):
    """Dimensionless Mindlin spring force of the stored state z (ξ or Ft), for scalars."""
    return pb.kts(x) * z if history == "total" else z


def _ft_of(pb, tangential, history, mode, y):
    """Dimensionless Ft for states y (shape (6, n)) in a mode."""
    x, u, z = y[0], y[1], y[3]
    if mode[0] == "slide":
        return mode[1] * pb.mu * pb.fn(x, u)
    if mode[0] == "stick" and tangential == "mindlin":
        return pb.kt(x) * z if history == "total" else z
    return np.zeros_like(x)


def _events(pb: _Problem, tangential, history, mode):
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
            x, u, z = y[0], y[1], y[3]
            if x <= 0:  # past separation: keep the sign, so a real crossing is found
                return -1.0
            return pb.mu * pb.fs(x, u) - abs(_spring_ft(pb, history, x, z))

        cap.terminal = True
        cap.direction = -1
        evs.append(cap)
    elif tangential == "mindlin" and kind == "slide":
        sig = mode[1]

        def release(tau, y):
            x, u, p = y[0], y[1], y[2]
            if x <= 0:
                return 1.0
            s = pb.s0 - pb.lam * p
            fn = pb.fs(x, u)
            rate = sig * pb.kts(x) * s - pb.mu * pb.fs_rate(x, u)
            if history == "total":
                rate += 0.5 * u / x * pb.mu * fn
            return rate

        release.terminal = True
        release.direction = -1
        evs.append(release)
    return evs


def _never(tau, y):
    return 1.0


_never.terminal = True
_never.direction = -1


def _initial_mode(pb: _Problem, tangential, history):
    if tangential == "none" or pb.mu == 0 or pb.s0 == 0:
        return ("free",) if tangential == "none" or pb.mu == 0 else ("stick",)
    if tangential == "coulomb":
        return ("slide", 1.0)
    # Mindlin: does the spring force stay under the cap as t → 0+? (δ ≈ v0 t)
    tau = 1e-8
    fn = pb.fs(tau, 1.0)
    k = pb.kts(tau)
    trial = k * pb.s0 * tau if history == "total" else 2.0 / 3.0 * k * pb.s0 * tau
    return ("stick",) if trial < pb.mu * fn else ("slide", 1.0)


def _solve(pb: _Problem, tangential, history, rtol, atol, method):
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
        evs = _events(pb, tangential, history, mode)
        sol = integrate.solve_ivp(
            _make_rhs(pb, tangential, history, mode),
            (tau0, tau_max),
            y,
            method=method,
            rtol=rtol,
            atol=atol_v,
            events=evs,
            dense_output=True,
        )
        if sol.status < 0:
            raise RuntimeError(f"impact integration failed: {sol.message}")
        if len(sol.t_events[2]):
            delta_max_tau = float(sol.t_events[2][0])
        segments.append((sol.t[0], sol.t[-1], sol.sol, mode))
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
            ft = _spring_ft(pb, history, y[0], y[3])
            mode = ("slide", 1.0 if ft >= 0 else -1.0)
        else:  # leave the cap: stick with the spring exactly at the cap
            sig = mode[1]
            fn = pb.fs(y[0], y[1])
            cap = sig * pb.mu * fn
            y[3] = cap / pb.kts(y[0]) if history == "total" else cap
            mode = ("stick",)
    raise RuntimeError(
        f"more than {_MAX_SEGMENTS} stick/slide switches; loosen the tolerance or check the scene"
    )


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
) -> xr.Dataset:
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
        ``stick_slip_segments``, the solver settings and the scene fields.

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
    normal_name = default_normal(scene.e) if normal is None else normal
    pb = _setup(scene, normal_name, alpha, param, target_kappa)
    atol = rtol if atol is None else atol
    segments, y_end, tau_dmax = _solve(pb, tangential, history, rtol, atol, method)
    tau_c = float(segments[-1][1])

    # ---- sample the dense solution
    n = int(samples)
    tau_s = np.linspace(0.0, tau_c, n)
    Y = np.empty((6, n))
    FT = np.empty(n)
    bounds = np.array([seg[1] for seg in segments])
    which = np.minimum(np.searchsorted(bounds, tau_s, side="left"), len(segments) - 1)
    for k, (_t0, _t1, sol, mode) in enumerate(segments):
        sel = which == k
        if np.any(sel):
            Y[:, sel] = sol(tau_s[sel])
            FT[sel] = _ft_of(pb, tangential, history, mode, Y[:, sel])
    Y[:, -1] = y_end
    FN = pb.fn(Y[0], Y[1])
    FN[0] = pb.fn(0.0, 1.0)
    FT[-1] = _ft_of(pb, tangential, history, segments[-1][3], y_end[:, None])[0]

    # ---- refine F_max and δ_max on the dense output
    def f_at(tau):
        k = min(int(np.searchsorted(bounds, tau, side="left")), len(segments) - 1)
        yy = segments[k][2](tau)
        return float(pb.fn(yy[0], yy[1]))

    i = int(np.argmax(FN))
    lo, hi_ = tau_s[max(i - 1, 0)], tau_s[min(i + 1, n - 1)]
    res = optimize.minimize_scalar(
        lambda t: -f_at(t), bounds=(lo, hi_), method="bounded", options={"xatol": 1e-12 * tau_c}
    )
    fmax = max(-res.fun, float(FN[i]))
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
        with np.errstate(divide="ignore", invalid="ignore"):
            xi = np.where(kt > 0, FT / np.where(kt > 0, kt, 1.0), 0.0) * pb.dstar
        extra["xi"] = (xi, "m", "elastic tangential displacement Ft/k_t")
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
    }
    if target_kappa is not None:
        attrs["target_kappa"] = float(target_kappa)
    if alpha is not None:
        attrs["alpha"] = float(alpha)
    attrs.update(scene.to_dict())
    return make_record(t, {"Fn": fn_N, "Ft": ft_N}, attrs=attrs, extra=extra)


# ----------------------------------------------------------------------------- batch
@dataclass(frozen=True)
class ImpactOutcomes:
    """Outcomes of many impacts (arrays shaped like the scenes).

    Attributes
    ----------
    e_n : normal restitution [-]
    e_t : tangential velocity of the centre after / before [-] (NaN when v_t0 = 0)
    omega : spin after impact [rad/s], > 0 in the sense Pt > 0 produces
    t_contact : contact duration [s]
    F_max : peak normal force [N]
    delta_max : maximum approach [m]
    Pn_final, Pt_final : normal and tangential percussion at separation [N·s]
    Ft_reverses : bool — the tangential force changed sign during contact
    normal : law name per scene; tangential, history : model names; n_steps : RK4 steps
    per elastic contact duration
    """

    e_n: np.ndarray
    e_t: np.ndarray
    omega: np.ndarray
    t_contact: np.ndarray
    F_max: np.ndarray
    delta_max: np.ndarray
    Pn_final: np.ndarray
    Pt_final: np.ndarray
    Ft_reverses: np.ndarray
    normal: np.ndarray
    tangential: str
    history: str
    n_steps: int

    _UNITS = {
        "e_n": "1",
        "e_t": "1",
        "omega": "rad/s",
        "t_contact": "s",
        "F_max": "N",
        "delta_max": "m",
        "Pn_final": "N s",
        "Pt_final": "N s",
        "Ft_reverses": "1",
    }

    def to_dataset(self) -> xr.Dataset:
        """The outcomes as an :class:`xarray.Dataset` on dimension ``scene`` (flattened)."""
        data = {
            k: ("scene", np.ravel(getattr(self, k)), {"units": u}) for k, u in self._UNITS.items()
        }
        data["normal"] = ("scene", np.ravel(self.normal).astype(str))
        return xr.Dataset(
            data,
            attrs={
                "tangential_model": self.tangential,
                "history_rule": self.history,
                "n_steps": self.n_steps,
                "generator": "pipeline.simulate.impact_outcomes",
            },
        )


def _stack_scenes(scenes):
    if isinstance(scenes, Scene):
        return scenes
    scenes = list(scenes)
    if not scenes or not all(isinstance(s, Scene) for s in scenes):
        raise InputError("impact_outcomes() needs a Scene (array fields) or a list of Scenes")
    fields = {}
    for name in Scene.field_names():
        if name in ("density", "mass"):
            continue
        vals = [getattr(s, name) for s in scenes]
        if any(v is None for v in vals):
            if all(v is None for v in vals):
                continue
            raise InputError(f"Scene.{name} is given for some scenes but not others")
        fields[name] = np.array(vals, dtype=float)
    fields["mass"] = np.array([float(s.m) for s in scenes])
    return Scene(**fields)


def _calibrate_many(law, e):
    e = np.asarray(e, dtype=float)
    uniq, inv = np.unique(e, return_inverse=True)
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


#: laws whose dimensionless force depends on the damping parameter alone (F = K·δ^1.5·(1 +
#: c·δ̇/v0)): their normal problem is integrated once per distinct parameter value.
_SELF_SIMILAR = ("hunt_crossley", "lankarani_nikravesh", "flores")


class _MindlinRK4:
    """Tangential state (Pt, and ξ or Ft) of N scenes, advanced by RK4 (dimensionless).

    The Coulomb cap is applied inside the stages and the discrete history rule after each
    step: for the total rule ξ is clipped to ±μFn/k_t (:func:`pipeline.contact.mindlin_total`
    with zero increment), for the incremental rule Ft to ±μFn
    (:func:`pipeline.contact.mindlin_incremental`); written out as clips here for speed.
    """

    def __init__(self, s0, lam, mu, ktc, history):
        self.s0, self.lam, self.mu, self.ktc = s0, lam, mu, ktc
        self.total = history == "total"
        n = s0.size
        self.p = np.zeros(n)
        self.z = np.zeros(n)
        self.ft_min = np.zeros(n)
        self.ft_max = np.zeros(n)

    def rhs(self, sq, fn, p, z):
        cap = self.mu * fn
        s = self.s0 - self.lam * p
        if self.total:
            return np.clip(self.ktc * z * sq, -cap, cap), s
        return np.clip(z, -cap, cap), self.ktc * sq * s

    def step(self, h, stages, end):
        """``stages``: (√x, fn) at τ, τ+h/2 (twice, RK4 stages 2 and 3) and τ+h; ``end``: the
        same at the end of the step (for the history rule)."""
        p, z = self.p, self.z
        (q1, f1), (q2, f2), (q3, f3), (q4, f4) = stages
        a1, b1 = self.rhs(q1, f1, p, z)
        a2, b2 = self.rhs(q2, f2, p + 0.5 * h * a1, z + 0.5 * h * b1)
        a3, b3 = self.rhs(q3, f3, p + 0.5 * h * a2, z + 0.5 * h * b2)
        a4, b4 = self.rhs(q4, f4, p + h * a3, z + h * b3)
        self.p = p + h / 6.0 * (a1 + 2.0 * (a2 + a3) + a4)
        z = z + h / 6.0 * (b1 + 2.0 * (b2 + b3) + b4)
        qe, fe = end
        cap = self.mu * fe
        if self.total:
            k = self.ktc * qe
            with np.errstate(divide="ignore", invalid="ignore"):
                lim = np.where(k > 0, cap / k, 0.0)
            self.z = np.clip(z, -lim, lim)
        else:
            self.z = np.clip(z, -cap, cap)
        np.minimum(self.ft_min, a4, out=self.ft_min)
        np.maximum(self.ft_max, a4, out=self.ft_max)


def _batch_group(
    law, elastic, param, K, m_eff, v0, dstar, s0, lam, mu, ktc, tangential, history, n_steps
):
    """Fixed-step RK4 over all scenes of one normal law (dimensionless)."""
    N = s0.size
    TC = contact.HERTZ_TC_CONSTANT
    h = TC / n_steps
    tan = _MindlinRK4(s0, lam, mu, ktc, history) if tangential == "mindlin" else None
    if elastic:
        # one universal normal solution for every scene (exact, contact.hertz_pulse)
        tau = np.arange(2 * n_steps + 1) * (h / 2)
        tau[-1] = TC
        pulse = contact.hertz_pulse(tau, _UNIT_HERTZ)
        qs, fs = np.sqrt(np.maximum(pulse["delta"], 0.0)), pulse["F"]
        if tan is not None:
            for k in range(n_steps):
                mid = (qs[2 * k + 1], fs[2 * k + 1])
                end = (qs[2 * k + 2], fs[2 * k + 2])
                tan.step(h, ((qs[2 * k], fs[2 * k]), mid, mid, end), end)
        e_n = np.ones(N)
        tau_c = np.full(N, TC)
        f_max = np.full(N, 1.25)
        x_max = np.ones(N)
    else:
        param = np.broadcast_to(np.asarray(param, dtype=float), (N,))
        if law.name in _SELF_SIMILAR:
            prm, inv = np.unique(param, return_inverse=True)
            Kn, mn, vn, dn = 1.25, 1.0, 1.0, 1.0  # dimensionless: δ* = v0 = m* = 1
        else:
            prm, inv = param, None
            Kn, mn, vn, dn = K, m_eff, v0, dstar
        fsc = mn * vn**2 / dn
        M = prm.size

        def fn_of(x, u, idx=None):
            if idx is None:
                f = law.force(x * dn, u * vn, prm, Kn, mn, vn) / fsc
            else:  # a subset of the scenes
                sub = [np.broadcast_to(a, (M,))[idx] for a in (prm, Kn, mn, vn, dn, fsc)]
                f = law.force(x * sub[4], u * sub[3], sub[0], sub[1], sub[2], sub[3]) / sub[5]
            return np.where(x > 0, f, 0.0)

        def g(a):
            return a if inv is None else a[inv]

        def q(x):
            return g(np.sqrt(np.maximum(x, 0.0)))

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
                end = (q(xn), g(fnew))
                tan.step(h, ((q(x), g(f1)), (q(xa), g(f2)), (q(xb), g(f3)), (q(xc), g(f4))), end)
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
    if tangential == "coulomb":
        p = np.minimum(mu * (1.0 + e_n), s0 / lam)  # Routh's broken line (PHYSICS.md §3)
        reverses = np.zeros(N, dtype=bool)
    elif tangential == "none":
        p = np.zeros(N)
        reverses = np.zeros(N, dtype=bool)
    else:
        p = tan.p
        tiny = 1e-9 * np.maximum(mu, 1e-12)
        reverses = (tan.ft_min < -tiny) & (tan.ft_max > tiny)
    return {
        "e_n": e_n,
        "p": p,
        "tau_c": tau_c,
        "f_max": f_max,
        "x_max": x_max,
        "reverses": reverses,
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


def impact_outcomes(
    scenes,
    normal=None,
    tangential="mindlin",
    *,
    history="total",
    n_steps=400,
    alpha=None,
    param=None,
    target_kappa=None,
) -> ImpactOutcomes:
    """Outcomes of many oblique impacts at once (vectorised, no per-scene loop).

    Parameters
    ----------
    scenes : Scene or sequence of Scene
        A Scene whose fields are arrays (broadcast together) or a list of scalar Scenes.
    normal : str, optional
        Normal law for all scenes; default per scene ``"hertz"`` if e == 1 else
        ``"hunt_crossley"``.
    tangential : {"mindlin", "coulomb", "none"}
    history : {"total", "incremental"}
        Mindlin history rule.
    n_steps : int
        RK4 steps per elastic contact duration (t_c = 2.943·t*); damped contacts, which
        last longer, take proportionally more.
    alpha, param, target_kappa
        As in :func:`impact`.

    Returns
    -------
    ImpactOutcomes

    Notes
    -----
    Every scene is integrated in its own dimensionless time τ = t·v_n0/δ_max with the same
    step, so the loop runs over time steps only. For the elastic Hertz law the normal
    problem is one universal function of τ (:func:`pipeline.contact.hertz_pulse`, exact),
    so only the tangential state (Pt, ξ or Ft) is integrated, by RK4 with the Coulomb cap
    applied inside the stages and the discrete history rule
    (:func:`pipeline.contact.mindlin_total` / :func:`~pipeline.contact.mindlin_incremental`)
    after each step: the LAMMPS/YADE update with an RK4 predictor. In these variables the
    tangential problem depends only on s0/(μ·v_n0), m*/m_t and G*/E* (the groups of Maw,
    Barber & Fawcett 1976). Coulomb friction needs no integration: Pt = min(μ·Pn,
    m_t·s0) exactly.

    Stated error (against :func:`impact` at rtol 1e-13; ``benchmarks/bench_simulate.py``):
    at the default n_steps = 400, for the elastic Hertz and Hunt–Crossley-family laws,
    |Δe_t| < 2e-5 (total rule ≈ 2e-6), |Δe_n| < 1e-6, relative F_max and t_contact < 1e-5;
    e_t errors fall roughly as n_steps⁻² (total rule) and n_steps⁻¹·⁵ (incremental: the
    stick/slip kinks). The error is one of Pt (|ΔPt| ≲ 2e-5·m*·v_n0 on those scenes; up to
    ~5e-5·m*·v_n0 for the incremental rule with heavy damping, e ≈ 0.2, and μ ≈ 1, where the
    longer contact holds more stick/slip switches); e_t = 1 − Pt/(m*·v_t0)
    magnifies it where v_t0 ≪ v_n0 or the initial slip is mostly spin. Laws whose damping
    grows as δ^{1/4} at first contact (linear dashpot on Hertz, viscoelastic) are not
    smooth there and converge more slowly: at n_steps = 400 and e ≥ 0.05,
    |Δe_n|, |Δe_t| < 1e-4, relative t_contact < 5e-4 and F_max < 1e-3 (the peak force of
    a heavily damped dashpot comes right after first contact).
    Scenes whose damping is too stiff for the explicit fixed step (e.g. an absurd material
    constant) come back as NaN with a :class:`~pipeline.errors.PipelineWarning`.
    """
    _check_models(tangential, history)
    if int(n_steps) < 4:
        raise InputError("n_steps must be at least 4")
    n_steps = int(n_steps)
    sc = _stack_scenes(scenes)
    _check_target(sc)
    hi = contact.hertz_impact(sc)
    arrs = np.broadcast_arrays(
        *(
            np.asarray(a, dtype=float)
            for a in (
                hi.delta_max,
                hi.K,
                hi.m_eff,
                hi.v0,
                sc.m,
                sc.target_mass,
                sc.kappa,
                sc.radius,
                sc.target_radius,
                sc.v_t0,
                sc.spin,
                sc.mu,
                sc.e,
                sc.G_eff,
                sc.R_eff,
            )
        )
    )
    shape = arrs[0].shape
    (dstar, K, m_eff, v0, m1, m2, k1, R1, R2, vt0, spin, mu, e, G, Rs) = (
        a.ravel().copy() for a in arrs
    )
    k2 = (
        k1
        if target_kappa is None
        else np.broadcast_to(np.asarray(target_kappa, dtype=float), shape).ravel()
    )
    with np.errstate(divide="ignore"):
        inv_m2 = np.where(np.isinf(m2), 0.0, 1.0 / m2)
    lam = m_eff * ((1 + 1 / k1) / m1 + (1 + 1 / k2) * inv_m2)
    slip0 = vt0 - spin * R1
    sign = np.where(slip0 < 0, -1.0, 1.0)
    s0 = np.abs(slip0) / v0
    ktc = 8.0 * G * np.sqrt(Rs * dstar) * dstar**2 / (m_eff * v0**2)
    if normal is None:
        names = np.where(e == 1.0, "hertz", "hunt_crossley")
    else:
        _law(normal)
        names = np.full(e.shape, normal, dtype=object)
    names = names.astype(object)
    if normal == "hertz" and np.any(e < 1):
        raise InputError("the elastic 'hertz' law cannot give e < 1; choose a damped law")
    out = {k: np.empty(e.size) for k in ("e_n", "p", "tau_c", "f_max", "x_max")}
    out["reverses"] = np.zeros(e.size, dtype=bool)
    for name in sorted(set(names)):
        law = _law(name)
        idx = np.nonzero(names == name)[0]
        elastic = name == "hertz"
        if param is not None:
            prm = np.broadcast_to(np.asarray(param, dtype=float), shape).ravel()[idx]
        elif alpha is not None:
            prm = np.asarray(
                _param(
                    law,
                    None,
                    K[idx],
                    m_eff[idx],
                    v0[idx],
                    alpha=np.broadcast_to(alpha, shape).ravel()[idx],
                )
            )
        else:
            prm = _calibrate_many(law, e[idx])
        res = _batch_group(
            law,
            elastic,
            prm,
            K[idx],
            m_eff[idx],
            v0[idx],
            dstar[idx],
            s0[idx],
            lam[idx],
            mu[idx],
            ktc[idx],
            tangential,
            history,
            n_steps,
        )
        for k in out:
            out[k][idx] = res["reverses" if k == "reverses" else k]
    # an explicit fixed step cannot follow a contact whose damping is too stiff for it:
    # such outcomes are unphysical (e_n outside [0, 1], non-finite) — flag, never return them
    bad = ~np.isfinite(out["e_n"]) | (out["e_n"] > 1 + 1e-6) | (out["e_n"] < 0)
    bad |= ~np.isfinite(out["p"]) | ~np.isfinite(out["tau_c"])
    if np.any(bad):
        warnings.warn(
            f"impact_outcomes: {int(bad.sum())} of {bad.size} scenes are too stiffly damped "
            f"for n_steps = {n_steps} (explicit RK4 unstable); their outcomes are NaN. "
            "Raise n_steps or use impact() for them.",
            PipelineWarning,
            stacklevel=2,
        )
        for k in ("e_n", "p", "tau_c", "f_max", "x_max"):
            out[k] = np.where(bad, np.nan, out[k])
    tstar = dstar / v0
    Pt = out["p"] * m_eff * v0
    vt0s = sign * vt0
    with np.errstate(divide="ignore", invalid="ignore"):
        e_t = np.where(vt0s != 0, (vt0s - out["p"] * v0) / np.where(vt0s != 0, vt0s, 1.0), np.nan)
    omega = sign * spin + Pt / (k1 * m1 * R1)

    def r(a):
        return np.asarray(a).reshape(shape)

    return ImpactOutcomes(
        e_n=r(out["e_n"]),
        e_t=r(e_t),
        omega=r(omega),
        t_contact=r(out["tau_c"] * tstar),
        F_max=r(out["f_max"] * m_eff * v0**2 / dstar),
        delta_max=r(out["x_max"] * dstar),
        Pn_final=r((1 + out["e_n"]) * m_eff * v0),
        Pt_final=r(Pt),
        Ft_reverses=r(out["reverses"]),
        normal=r(names),
        tangential=tangential,
        history=history,
        n_steps=n_steps,
    )
