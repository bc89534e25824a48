r"""Compliant contact: Hertz, damped normal laws and Mindlin tangential compliance.

Theory (PHYSICS.md §4; Johnson, *Contact Mechanics*, CUP 1985, §4.2 and §11.4):

.. math::

    F_n = K\,\delta^{3/2}, \qquad K = \tfrac43 E^*\sqrt{R^*}, \qquad a = \sqrt{R^*\delta}

An elastic impact at approach speed :math:`v_0` reaches

.. math::

    \delta_{max} = \left(\frac{15\,m^* v_0^2}{16\,E^*\sqrt{R^*}}\right)^{2/5}, \quad
    F_{max} = K\delta_{max}^{3/2}, \quad
    t_c = 0.8\,B(\tfrac25,\tfrac12)\,\frac{\delta_{max}}{v_0}
        = 2.943275\ldots\frac{\delta_{max}}{v_0}.

Damped laws of the Hunt–Crossley family share one force law
:math:`F = K\delta^{3/2}(1 + c\,\dot\delta/v_0)` whose coefficient of restitution depends on
``c`` alone through the exact energy integral :math:`c(1+e) = \ln[(1+c)/(1-ce)]`.

Genuinely different force shapes: the Hertz spring with a linear dashpot scaled by the
contact stiffness, :math:`F = K\delta^{3/2} + 2\zeta\sqrt{m^*k(\delta)}\,\dot\delta`
(Tsuji et al. 1992; tangent or secant k), whose COR depends on ζ alone, and the viscoelastic
law :math:`F = K(\delta^{3/2} + \tfrac32 A\sqrt\delta\,\dot\delta)` (Kuwabara & Kono 1987;
Brilliantov et al. 1996), whose COR depends on :math:`\gamma = A v_0^{1/5}(K/m^*)^{2/5}`.

All these laws are self-similar: in units δ* = (m*·v0²/K)^{2/5}, δ*/v0 the impact reads
x'' = −f(x, x'; p) with one dimensionless parameter p, so e(p) is computed once — exactly
from the energy integral for the Hunt–Crossley family, from a table of the dimensionless
ODE (solved once, stored below with the function that made it) for the others — and
calibration inverts it without integrating anything per call. No law is adhesive: every
force is clipped at F ≥ 0 and the contact ends when δ returns to zero (for the dashpot and
viscoelastic laws the force reaches zero first, at δ > 0; the ball then moves freely, so
its rebound speed is fixed at that instant).

Every normal law is a :class:`NormalLaw` in :data:`NORMAL_LAWS`: a vectorised force
function ``force(delta, delta_dot, param, K, m_eff, v0)`` [N], a calibration
``calibrate(e)`` returning the damping parameter that gives restitution ``e``, the COR a
parameter gives (``cor``), the paper's closed-form guess, and ``material_to_param``
mapping a speed-independent material constant (α [s/m], ζ [-], A [s]) to the parameter of
an impact at speed v0, so a campaign can hold the material fixed and let e vary with speed.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy import special

from .errors import InputError
from .scene import Scene

__all__ = [
    "HERTZ_TC_CONSTANT",
    "HertzImpact",
    "NormalLaw",
    "NORMAL_LAWS",
    "hertz_stiffness",
    "hertz",
    "hertz_impact",
    "hertz_pulse",
    "contact_radius",
    "hunt_crossley",
    "lankarani_nikravesh",
    "flores",
    "cor_hunt_crossley_family",
    "calibrate_hunt_crossley_family",
    "c_hunt_crossley",
    "c_lankarani_nikravesh",
    "c_flores",
    "cor_hunt_crossley_alpha",
    "alpha_hunt_crossley",
    "hertz_dashpot",
    "cor_hertz_dashpot",
    "calibrate_hertz_dashpot",
    "zeta_hertz_dashpot_dem",
    "kuwabara_kono",
    "kuwabara_kono_group",
    "cor_kuwabara_kono",
    "calibrate_kuwabara_kono",
    "gamma_schwager_poschel",
    "SCHWAGER_POSCHEL_C1",
    "SCHWAGER_POSCHEL_C2",
    "normal_cor",
    "dimensionless_normal_rhs",
    "mindlin_stiffness",
]

#: t_c·v0/δ_max for an elastic Hertz impact: 0.8·B(2/5, 1/2) = 2.9432756...
HERTZ_TC_CONSTANT = 0.8 * special.beta(0.4, 0.5)


# --------------------------------------------------------------------------- Hertz
def hertz_stiffness(E_eff, R_eff):
    """Hertz stiffness K = (4/3)·E*·√R* [N/m^1.5].

    Parameters
    ----------
    E_eff : float or array — effective modulus E* [Pa]
    R_eff : float or array — effective radius R* [m]
    """
    return 4.0 / 3.0 * np.asarray(E_eff) * np.sqrt(R_eff)


def hertz(delta, K):
    """Elastic Hertz force F = K·δ^{3/2} [N]; zero for δ ≤ 0.

    Parameters
    ----------
    delta : float or array — normal approach (overlap) [m]
    K : float or array — Hertz stiffness [N/m^1.5]
    """
    d = np.maximum(np.asarray(delta, dtype=float), 0.0)
    return K * d * np.sqrt(d)


def contact_radius(delta, R_eff):
    """Hertz contact radius a = √(R*·δ) [m]."""
    return np.sqrt(np.maximum(np.asarray(delta, dtype=float), 0.0) * R_eff)


@dataclass(frozen=True)
class HertzImpact:
    """Closed-form outcome of an elastic Hertz impact (all SI).

    Attributes
    ----------
    delta_max : maximum approach [m]
    F_max : peak force [N]
    t_c : contact duration [s]
    K : Hertz stiffness [N/m^1.5]
    v0 : normal approach speed [m/s]
    m_eff : effective mass [kg]
    """

    delta_max: float
    F_max: float
    t_c: float
    K: float
    v0: float
    m_eff: float

    @property
    def t_star(self):
        """Time scale δ_max/v0 [s]: t_c = 2.943·t_star."""
        return self.delta_max / self.v0


def hertz_impact(scene: Scene, v0=None) -> HertzImpact:
    """Maximum approach, peak force and duration of an elastic Hertz impact.

    Parameters
    ----------
    scene : Scene
        Needs ``E``, ``nu`` (and target constants); uses ``m_eff``, ``R_eff``, ``E_eff``.
    v0 : float, optional
        Normal approach speed [m/s]; default ``scene.v_n0``.

    Returns
    -------
    HertzImpact

    Notes
    -----
    δ_max = (15·m*·v0²/(16·E*·√R*))^{2/5}, F_max = K·δ_max^{3/2},
    t_c = 0.8·B(2/5, 1/2)·δ_max/v0 (Johnson 1985, eq. 11.24).

    References
    ----------
    K. L. Johnson, Contact Mechanics, Cambridge University Press (1985),
    doi:10.1017/CBO9781139171731. S. P. Timoshenko, J. N. Goodier, Theory of Elasticity (1970).
    """
    v0 = scene.v_n0 if v0 is None else v0
    v0 = np.asarray(v0, dtype=float)
    if np.any(v0 <= 0):
        raise InputError("hertz_impact needs a positive normal approach speed (angle < 90°)")
    E, R, m = scene.E_eff, scene.R_eff, scene.m_eff
    K = hertz_stiffness(E, R)
    delta_max = (15.0 * m * v0**2 / (16.0 * E * np.sqrt(R))) ** 0.4
    F_max = K * delta_max**1.5
    t_c = HERTZ_TC_CONSTANT * delta_max / v0
    return HertzImpact(*(_f(x) for x in (delta_max, F_max, t_c, K, v0, m)))


def _f(x):
    x = np.asarray(x, dtype=float)
    return float(x) if x.ndim == 0 else x


def hertz_pulse(t, impact: HertzImpact):
    """Exact elastic Hertz impact history: approach, force and normal percussion at ``t``.

    Parameters
    ----------
    t : array_like
        Time since first contact [s]; values outside [0, t_c] give zero force.
    impact : HertzImpact
        From :func:`hertz_impact`.

    Returns
    -------
    dict of numpy.ndarray
        ``delta`` [m], ``delta_dot`` [m/s], ``F`` [N], ``Pn`` [N·s] (normal percussion).

    Notes
    -----
    Energy conservation, ½m*δ̇² + (2/5)Kδ^{5/2} = ½m*v0², with u = (δ/δ_max)^{5/2} gives
    t = (2/5)·B(2/5, 1/2)·I_u(2/5, 1/2)·δ_max/v0 on the way in, I_u the regularised incomplete
    beta function; its inverse gives δ(t) exactly, and F = F_max·u^{3/5},
    Pn = m*·(v0 − δ̇). No ODE, no half-sine approximation.
    """
    t = np.asarray(t, dtype=float)
    half = impact.t_c / 2.0
    inside = (t >= 0) & (t <= impact.t_c)
    s = np.clip(np.where(t <= half, t, impact.t_c - t) / half, 0.0, 1.0)
    u = special.betaincinv(0.4, 0.5, s)
    sign = np.where(t <= half, 1.0, -1.0)
    delta = np.where(inside, impact.delta_max * u**0.4, 0.0)
    delta_dot = np.where(inside, sign * impact.v0 * np.sqrt(1.0 - u), 0.0)
    F = np.where(inside, impact.F_max * u**0.6, 0.0)
    Pn = impact.m_eff * np.where(
        t < 0, 0.0, np.where(inside, impact.v0 - delta_dot, 2.0 * impact.v0)
    )
    return {"delta": delta, "delta_dot": delta_dot, "F": F, "Pn": Pn}


# ------------------------------------------------------ Hunt–Crossley family
def hunt_crossley(delta, delta_dot, c, K, v0):
    """Hunt–Crossley force F = K·δ^{3/2}·(1 + c·δ̇/v0) [N], clipped at zero (no adhesion).

    Parameters
    ----------
    delta : approach [m]
    delta_dot : approach rate [m/s] (> 0 compressing)
    c : dimensionless damping [-] (``c = α·v0`` for a material constant α [s/m])
    K : Hertz stiffness [N/m^1.5]
    v0 : initial approach speed [m/s]

    Notes
    -----
    End of contact: δ̇ falls monotonically from v0 to −e·v0 and 1 − c·e > 0 (the exact
    relation of :func:`cor_hunt_crossley_family` requires c·e < 1), so the force stays
    positive until δ = 0: the clip never acts in a single impact and the contact ends at
    δ = 0.

    References
    ----------
    K. H. Hunt, F. R. E. Crossley, J. Appl. Mech. 42:440 (1975), doi:10.1115/1.3423596.
    """
    return np.maximum(hertz(delta, K) * (1.0 + c * np.asarray(delta_dot) / v0), 0.0)


#: Lankarani & Nikravesh (J. Mech. Des. 112:369, 1990) use the same force law.
lankarani_nikravesh = hunt_crossley
#: Flores et al. (Nonlinear Dyn. 65:161, 2011) use the same force law.
flores = hunt_crossley


def c_hunt_crossley(e):
    """Hunt & Crossley's closed-form damping guess c = 3(1−e)/2."""
    return 1.5 * (1.0 - np.asarray(e, dtype=float))


def c_lankarani_nikravesh(e):
    """Lankarani & Nikravesh's closed-form guess c = 3(1−e²)/4."""
    e = np.asarray(e, dtype=float)
    return 0.75 * (1.0 - e**2)


def c_flores(e):
    """Flores et al.'s closed-form guess c = 8(1−e)/(5e)."""
    e = np.asarray(e, dtype=float)
    return 8.0 * (1.0 - e) / (5.0 * e)


# Exact restitution of the Hunt–Crossley force law. With φ(x) = −ln(1−x) − x the energy
# integral c(1+e) = ln[(1+c)/(1−ce)] reads φ(c·e) = φ(−c); dividing by c² and writing
# Φ(x) = φ(x)/x² (Φ(0) = 1/2, increasing on (−∞, 1)) gives the well-conditioned form
#     e²·Φ(c·e) = Φ(−c),
# which keeps full precision as c → 0 (e → 1), where the original form cancels.
_PHI_TERMS = 22  # Σ_{k=2}^{23} x^{k−2}/k: truncation < 1e-19 for |x| < 0.1


@np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore")
def _phi_reduced(x):
    """Φ(x) = (−ln(1−x) − x)/x² and its derivative Φ'(x), for x < 1 (series near 0)."""
    x = np.asarray(x, dtype=float)
    small = np.abs(x) < 0.1
    xs = np.where(small, x, 0.0)
    s = np.zeros_like(xs)
    ds = np.zeros_like(xs)
    if np.any(small):
        for k in range(_PHI_TERMS + 1, 1, -1):  # Horner, highest power first
            s = s * xs + 1.0 / k
        for k in range(_PHI_TERMS + 1, 2, -1):
            ds = ds * xs + (k - 2.0) / k
    xl = np.where(small, 0.5, x)
    big = -np.log1p(-xl) - xl
    big_x2 = big / xl / xl
    phi = np.where(small, s, big_x2)
    dphi = np.where(small, ds, (1.0 / (1.0 - xl) - 2.0 * big_x2) / xl)
    return phi, dphi


def _newton_increasing(fun, x0, lo, hi, rtol=2e-16, maxiter=200):
    """Vectorised Newton for an increasing function, safeguarded by bisection.

    ``fun(x, mask) -> (f, f')`` is evaluated on the still-active elements; the root lies
    in (lo, hi) (f(lo) < 0 < f(hi)); iterates leaving the bracket are replaced by its
    midpoint, so every element converges.
    """
    x, lo, hi = (np.array(a, dtype=float, copy=True) for a in np.broadcast_arrays(x0, lo, hi))
    active = np.ones(x.shape, dtype=bool)
    for _ in range(maxiter):
        idx = np.nonzero(active)
        if idx[0].size == 0:
            break
        xa, la, ha = x[idx], lo[idx], hi[idx]
        f, df = fun(xa, idx)
        zero = f == 0
        la = np.where(f < 0, xa, la)
        ha = np.where(f > 0, xa, ha)
        with np.errstate(divide="ignore", invalid="ignore"):
            xn = xa - f / df
        converged = zero | (np.abs(xn - xa) <= rtol * np.abs(xa))  # step below resolution
        bad = ~((xn > la) & (xn < ha)) & ~converged
        xn = np.where(bad, 0.5 * (la + ha), np.where(converged, xa, xn))
        done = converged | (ha - la <= rtol * np.abs(ha))
        x[idx], lo[idx], hi[idx] = xn, la, ha
        active[idx] = ~done
    return x


@np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore")
def _hc_cor(c):
    """e(c) for c ≥ 0 (array): root of e·√Φ(c·e) = √Φ(−c) in (0, min(1, 1/c))."""
    c = np.asarray(c, dtype=float)
    out = np.ones_like(c)
    pos = c > 0
    if not np.any(pos):
        return out
    cp = c[pos]
    rhs = np.sqrt(_phi_reduced(-cp)[0])
    psi = np.where(cp < 0.1, cp * cp * rhs * rhs, cp - np.log1p(cp))  # ψ(c) = c − ln(1+c)
    # Lambert-W start: 1 − x = −W0(−exp(−1−ψ)), x = c·e (exact, ill-conditioned at ψ → 0)
    with np.errstate(under="ignore"):
        w = special.lambertw(-np.exp(-1.0 - psi)).real
    x0 = np.clip(1.0 + w, 0.0, 1.0)
    cs = np.minimum(cp, 1e-3)
    e0 = np.where(cp < 1e-3, 1.0 - 2.0 * cs / 3.0 + 4.0 * cs**2 / 9.0, x0 / cp)
    hi = np.minimum(1.0, 1.0 / cp)
    # ψ > 37: 1 − c·e < 1e-16, so e = 1/c to double precision
    saturated = psi > 37.0
    e0 = np.clip(e0, 0.0, hi)

    def q(e, idx):
        cc, r = cp[idx], rhs[idx]
        x = np.minimum(cc * e, np.nextafter(1.0, 0.0))
        p, dp = _phi_reduced(x)
        sp = np.sqrt(p)
        return e * sp - r, sp + e * cc * dp / (2.0 * sp)

    e = _newton_increasing(q, e0, 0.0, hi)
    out[pos] = np.where(saturated, 1.0 / cp, e)
    return out


@functools.cache
def _hc_table():
    """(e, ln c) on a grid, for Newton starting values (solved once, ~1 ms)."""
    c = np.geomspace(1e-4, 1e3, 400)
    return _hc_cor(c)[::-1], np.log(c)[::-1]


@np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore")
def _hc_calibrate(e):
    """c(e) for 0 < e ≤ 1 (array): root of e·√Φ(c·e) − √Φ(−c) in (0, 1/e)."""
    e = np.asarray(e, dtype=float)
    out = np.zeros_like(e)
    damped = e < 1
    if not np.any(damped):
        return out
    ed = e[damped]
    te, tlc = _hc_table()
    d = 1.0 - ed
    c0 = np.where(
        ed > te[-1],
        1.5 * d + 1.5 * d**2,
        np.where(ed < te[0], 1.0 / ed, np.exp(np.interp(ed, te, tlc))),
    )
    hi = 1.0 / ed
    # ψ(1/e) > 37: the root is 1/e to double precision (1 − c·e < 1e-16)
    saturated = (hi - np.log1p(hi)) > 37.0
    c0 = np.clip(c0, 0.0, hi)

    def r(c, idx):
        ee = ed[idx]
        x = np.minimum(c * ee, np.nextafter(1.0, 0.0))
        p, dp = _phi_reduced(x)
        pm, dpm = _phi_reduced(-c)
        sp, spm = np.sqrt(p), np.sqrt(pm)
        return ee * sp - spm, ee**2 * dp / (2.0 * sp) + dpm / (2.0 * spm)

    c = _newton_increasing(r, c0, 0.0, hi)
    out[damped] = np.where(saturated, hi, c)
    return out


def cor_hunt_crossley_family(c):
    r"""Exact coefficient of restitution of F = K·δ^{3/2}·(1 + c·δ̇/v0).

    Parameters
    ----------
    c : float or array_like
        Dimensionless damping [-], c ≥ 0. For a fixed material constant α [s/m] pass
        ``c = α·v0`` (see :func:`cor_hunt_crossley_alpha`).

    Returns
    -------
    float or numpy.ndarray
        Restitution e ∈ (0, 1] [-]; e = 1 for c = 0, e → 1/c as c → ∞.

    Notes
    -----
    The energy integral of the law (no ODE) gives, PHYSICS.md §4,

    .. math:: c\,(1+e) = \ln\frac{1+c}{1-c\,e}.

    With :math:`\Phi(x) = (-\ln(1-x) - x)/x^2` it reads :math:`e^2\,\Phi(ce) = \Phi(-c)`, which
    is solved by vectorised, bisection-safeguarded Newton iteration to double precision over
    the whole range (a power series for Φ near 0 keeps e → 1 exact).

    References
    ----------
    K. H. Hunt, F. R. E. Crossley, J. Appl. Mech. 42:440 (1975), doi:10.1115/1.3423596.
    """
    c_arr = np.asarray(c, dtype=float)
    if np.any(~(c_arr >= 0)) or np.any(~np.isfinite(c_arr)):
        raise InputError(f"Hunt–Crossley damping c must be finite and ≥ 0; got c = {c!r}")
    return _f(_hc_cor(c_arr))


def calibrate_hunt_crossley_family(e):
    r"""The damping c giving restitution e exactly (no ODE), for any e ∈ (0, 1].

    Parameters
    ----------
    e : float or array_like
        Requested coefficient of restitution [-], 0 < e ≤ 1.

    Returns
    -------
    float or numpy.ndarray
        c [-] with ``cor_hunt_crossley_family(c) == e`` to ~1e-15 (0 for e = 1; 1/e as e → 0).

    Raises
    ------
    InputError
        For e outside (0, 1] (e = 0 needs c = ∞).

    Notes
    -----
    Inverts :math:`e^2\,\Phi(ce) = \Phi(-c)` (see :func:`cor_hunt_crossley_family`) by
    bisection-safeguarded Newton iteration from a table of e(c) solved once.

    References
    ----------
    K. H. Hunt, F. R. E. Crossley, J. Appl. Mech. 42:440 (1975), doi:10.1115/1.3423596.
    """
    e_arr = np.asarray(e, dtype=float)
    if np.any(~((e_arr > 0) & (e_arr <= 1))):
        raise InputError(
            "Hunt–Crossley-type laws reach every e in the range (0, 1] (e = 0 would need "
            f"infinite damping); got e = {e!r}"
        )
    return _f(_hc_calibrate(e_arr))


def cor_hunt_crossley_alpha(alpha, v0):
    """Restitution of the Hunt–Crossley law with a fixed material constant α = c/v0.

    Parameters
    ----------
    alpha : float or array_like — damping constant α [s/m], ≥ 0
    v0 : float or array_like — normal approach speed [m/s], > 0

    Returns
    -------
    e [-]: ``cor_hunt_crossley_family(alpha * v0)``; falls as the speed rises.

    Notes
    -----
    Hunt & Crossley's force F = K·δ^{3/2}(1 + α·δ̇) has a speed-independent α [s/m];
    the dimensionless damping of an impact at v0 is c = α·v0.
    """
    return cor_hunt_crossley_family(np.asarray(alpha, dtype=float) * np.asarray(v0, dtype=float))


def alpha_hunt_crossley(e, v0):
    """The material constant α = c(e)/v0 [s/m] that gives restitution e at speed v0 [m/s].

    Inverse of :func:`cor_hunt_crossley_alpha`; e ∈ (0, 1], v0 > 0.
    """
    return _f(np.asarray(calibrate_hunt_crossley_family(e)) / np.asarray(v0, dtype=float))


# ------------------------------------------------------- Hertz + linear dashpot
_DASHPOT_STIFFNESS = {"tangent": 1.5, "secant": 1.0}  # k(δ) = factor·K·√δ


def _dashpot_factor(stiffness):
    try:
        return _DASHPOT_STIFFNESS[stiffness]
    except (KeyError, TypeError):
        raise InputError(
            f"stiffness must be 'tangent' (k = 2E*a) or 'secant' (k = (4/3)E*a); got {stiffness!r}"
        ) from None


def _hertz_dashpot_raw(delta, delta_dot, zeta, K, m_eff, stiffness="tangent"):
    d = np.maximum(np.asarray(delta, dtype=float), 0.0)
    k = _dashpot_factor(stiffness) * np.asarray(K) * np.sqrt(d)
    return K * d * np.sqrt(d) + 2.0 * np.asarray(zeta) * np.sqrt(m_eff * k) * delta_dot


def hertz_dashpot(delta, delta_dot, zeta, K, m_eff, stiffness="tangent"):
    r"""Hertz spring with a linear dashpot scaled by the contact stiffness [N] (Tsuji type).

    Parameters
    ----------
    delta : float or array — normal approach (overlap) [m]
    delta_dot : float or array — approach rate [m/s] (> 0 compressing)
    zeta : float or array — damping ratio ζ [-], ≥ 0 (a material constant: the COR depends
        on ζ alone, not on speed, size or stiffness)
    K : float or array — Hertz stiffness (4/3)·E*·√R* [N/m^1.5]
    m_eff : float or array — effective mass m* [kg]
    stiffness : {"tangent", "secant"}
        Which contact stiffness k(δ) scales the dashpot (default ``"tangent"``).

    Returns
    -------
    F : numpy.ndarray or float — compressive normal force [N], ≥ 0; zero for δ ≤ 0.

    Notes
    -----
    .. math:: F = \max\left[0,\; K\delta^{3/2} + 2\zeta\sqrt{m^*\,k(\delta)}\;\dot\delta\right],

    tangent stiffness :math:`k = \mathrm{d}F/\mathrm{d}\delta = \tfrac32 K\sqrt\delta = 2E^*a`,
    secant stiffness :math:`k = F/\delta = K\sqrt\delta = \tfrac43 E^*a`. The DEM codes
    disagree: LIGGGHTS and EDEM scale their dashpot with the tangent stiffness
    :math:`S_n = 2E^*a`; Tsuji et al. (1992) write :math:`\eta = \alpha\sqrt{mK}\,\delta^{1/4}`,
    i.e. the secant one. The same ζ therefore means a dashpot √(3/2) ≈ 1.22 times stronger in
    the tangent convention (and a lower COR). The default is the tangent stiffness, because
    it is the stiffness of small oscillations about the current overlap, so ζ keeps its
    meaning of a damping ratio, and because it is what the most used codes implement.

    Self-similarity: with :math:`\delta = \delta^* x`, :math:`t = (\delta^*/v_0)\tau`,
    :math:`\delta^* = (m^* v_0^2/K)^{2/5}` the equation of motion becomes
    :math:`x'' = -x^{3/2} - 2\zeta\sqrt{\kappa}\,x^{1/4}x'` (κ = k/(K√δ) = 3/2 tangent,
    1 secant): no v0, K or m* is left, so the coefficient of restitution is a function of ζ alone
    (:func:`cor_hertz_dashpot`) and does not change with impact speed.

    End of contact: the force is clipped at zero (no adhesion). During restitution the
    dashpot term makes the unclipped force reach zero while δ > 0; from then on the force
    stays zero (δ falls at constant rate), so the ball separates with the speed it has
    when F first returns to zero — an event on δ = 0 with this clipped force gives the
    same rebound speed. (LIGGGHTS applies this clip only with ``limitForce on``.)

    References
    ----------
    Y. Tsuji, T. Tanaka, T. Ishida, Powder Technol. 71:239 (1992),
    doi:10.1016/0032-5910(92)88030-L.
    C. Thornton, S. J. Cummins, P. W. Cleary, Powder Technol. 233:30 (2013).
    LIGGGHTS-PUBLIC documentation, ``gran model hertz``.
    """
    raw = _hertz_dashpot_raw(delta, delta_dot, zeta, K, m_eff, stiffness)
    return _f(np.where(np.asarray(delta) > 0, np.maximum(raw, 0.0), 0.0))


def zeta_hertz_dashpot_dem(e, stiffness="tangent"):
    r"""The closed-form damping ratio DEM codes use for a Hertz dashpot [-].

    :math:`\zeta = \sqrt{5/6}\;(-\ln e)/\sqrt{\ln^2 e + \pi^2}` in the tangent-stiffness
    convention (LIGGGHTS ``gran model hertz``: :math:`\gamma_n = -2\sqrt{5/6}\,\beta
    \sqrt{S_n m^*}`, :math:`\beta = \ln e/\sqrt{\ln^2 e+\pi^2}`, :math:`S_n = 2E^*a`); it
    is the linear spring–dashpot result with a fitted factor, so it is only approximate
    for the Hertz law: compare :func:`cor_hertz_dashpot` of its output with e. For
    ``stiffness="secant"`` the same dashpot is expressed as ζ·√(3/2).

    Parameters
    ----------
    e : float or array — requested restitution [-], 0 < e ≤ 1
    stiffness : {"tangent", "secant"}
    """
    e = np.asarray(e, dtype=float)
    ln = np.log(e)
    zeta = np.sqrt(5.0 / 6.0) * (-ln) / np.sqrt(ln**2 + np.pi**2)
    return _f(zeta * np.sqrt(1.5 / _dashpot_factor(stiffness)))


def cor_hertz_dashpot(zeta, stiffness="tangent"):
    """Coefficient of restitution of :func:`hertz_dashpot` for damping ratio ζ [-].

    From a table of the dimensionless impact solved once (:func:`_solve_normal_cor`,
    1e-13 tolerances) and a cubic spline; accurate to ~1e-8 in e. Speed-independent.

    Parameters
    ----------
    zeta : float or array — damping ratio [-], ≥ 0
    stiffness : {"tangent", "secant"}
    """
    eta = 2.0 * np.sqrt(_dashpot_factor(stiffness)) * _nonneg(zeta, "zeta")
    return _f(_table_cor("dashpot", eta))


def calibrate_hertz_dashpot(e, stiffness="tangent"):
    """The damping ratio ζ [-] for which :func:`hertz_dashpot` rebounds with restitution e.

    No ODE per call: Newton iteration on the spline of a table solved once. Reaches every
    e ∈ (0, 1] (heavy damping drives e → 0 like 1/η², η = 2ζ√(k/K√δ)).

    Raises
    ------
    InputError
        For e outside (0, 1].
    """
    eta = _table_calibrate("dashpot", e, "the Hertz–dashpot law")
    return _f(eta / (2.0 * np.sqrt(_dashpot_factor(stiffness))))


# ------------------------------------------------------------ viscoelastic law
def kuwabara_kono(delta, delta_dot, A, K):
    r"""Viscoelastic (Kuwabara–Kono, Brilliantov et al.) normal force [N].

    Parameters
    ----------
    delta : float or array — normal approach [m]
    delta_dot : float or array — approach rate [m/s] (> 0 compressing)
    A : float or array — dissipative material time A [s], ≥ 0 (a function of the
        viscosities and elastic constants of the material)
    K : float or array — Hertz stiffness [N/m^1.5]

    Returns
    -------
    F : compressive normal force [N], ≥ 0; zero for δ ≤ 0.

    Notes
    -----
    .. math:: F = \max\left[0,\; K\left(\delta^{3/2} + \tfrac32 A\sqrt\delta\,\dot\delta
              \right)\right]

    In the units of :func:`hertz_dashpot` the motion reads
    :math:`x'' = -x^{3/2} - \tfrac32\gamma\sqrt{x}\,x'` with the one dimensionless group
    :math:`\gamma = A\,v_0^{1/5}(K/m^*)^{2/5}` (:func:`kuwabara_kono_group`); the COR falls
    with speed as :math:`e = 1 - \tfrac32 C_1\gamma + \tfrac94 C_2\gamma^2 \mp\ldots`
    (Schwager & Pöschel 1998, C1 = 1.15344, C2 = 0.79826). The force is clipped at zero and
    the contact ends as for :func:`hertz_dashpot` (the unclipped force reaches zero while
    δ > 0; the ball leaves with its speed at that instant).

    References
    ----------
    G. Kuwabara, K. Kono, Jpn. J. Appl. Phys. 26:1230 (1987), doi:10.1143/JJAP.26.1230.
    N. V. Brilliantov, F. Spahn, J.-M. Hertzsch, T. Pöschel, Phys. Rev. E 53:5382 (1996),
    doi:10.1103/PhysRevE.53.5382.
    T. Schwager, T. Pöschel, Phys. Rev. E 57:650 (1998), doi:10.1103/PhysRevE.57.650.
    """
    raw = _kuwabara_kono_raw(delta, delta_dot, A, K)
    return _f(np.where(np.asarray(delta) > 0, np.maximum(raw, 0.0), 0.0))


def _kuwabara_kono_raw(delta, delta_dot, A, K):
    d = np.maximum(np.asarray(delta, dtype=float), 0.0)
    return K * np.sqrt(d) * (d + 1.5 * np.asarray(A) * delta_dot)


def kuwabara_kono_group(A, K, m_eff, v0):
    """The dimensionless damping γ = A·v0^{1/5}·(K/m*)^{2/5} of the viscoelastic law [-].

    Parameters
    ----------
    A : material time [s]; K : Hertz stiffness [N/m^1.5]; m_eff : effective mass [kg];
    v0 : normal approach speed [m/s]
    """
    return _f(
        np.asarray(A, dtype=float)
        * np.asarray(v0, dtype=float) ** 0.2
        * (np.asarray(K, dtype=float) / np.asarray(m_eff, dtype=float)) ** 0.4
    )


#: Schwager & Pöschel (1998) series coefficients of e(γ) for the viscoelastic law; in the
#: group γ of :func:`kuwabara_kono_group`, e = 1 − 1.5·C1·γ + 2.25·C2·γ² ∓ ...
SCHWAGER_POSCHEL_C1 = 1.15344
SCHWAGER_POSCHEL_C2 = 0.79826


def gamma_schwager_poschel(e):
    """Closed-form γ(e) from the two-term series of Schwager & Pöschel (1998) [-].

    Solves e = 1 − 1.5·C1·γ + 2.25·C2·γ² for its smaller root; the truncated series has
    no root for e < 0.5835 and NaN is returned there (use :func:`calibrate_kuwabara_kono`).

    References
    ----------
    T. Schwager, T. Pöschel, Phys. Rev. E 57:650 (1998), doi:10.1103/PhysRevE.57.650.
    """
    e = np.asarray(e, dtype=float)
    a, b = 2.25 * SCHWAGER_POSCHEL_C2, -1.5 * SCHWAGER_POSCHEL_C1
    disc = b * b - 4.0 * a * (1.0 - e)
    with np.errstate(invalid="ignore"):
        root = (2.0 * (1.0 - e)) / (-b + np.sqrt(disc))  # stable smaller root
    return _f(np.where(disc >= 0, root, np.nan))


def cor_kuwabara_kono(gamma):
    """Coefficient of restitution of the viscoelastic law for the group γ [-].

    Table of the dimensionless impact solved once + cubic spline (~1e-8 in e).
    For a fixed material time A use ``cor_kuwabara_kono(kuwabara_kono_group(A, K, m, v0))``.
    """
    return _f(_table_cor("viscoelastic", _nonneg(gamma, "gamma")))


def calibrate_kuwabara_kono(e):
    """The group γ [-] for which the viscoelastic law rebounds with restitution e ∈ (0, 1].

    No ODE per call (Newton on the spline of a table solved once); convert to the material
    time with ``A = γ·v0^{-1/5}·(m*/K)^{2/5}``.

    Raises
    ------
    InputError
        For e outside (0, 1].
    """
    return _f(_table_calibrate("viscoelastic", e, "the viscoelastic law"))


# ------------------------------------- the dimensionless normal impact, COR tables
def _nonneg(p, name):
    p = np.asarray(p, dtype=float)
    if np.any(~(p >= 0)) or np.any(~np.isfinite(p)):
        raise InputError(f"the damping parameter {name} must be finite and ≥ 0; got {p!r}")
    return p


def _dimensionless_normal_rhs(raw_force, param):
    """Right-hand side and end-of-contact events of one dimensionless normal impact.

    Units: length δ* = (m*·v0²/K)^{2/5}, time δ*/v0, so ``raw_force(x, x', param, 1, 1, 1)``
    is the dimensionless force (every law here is self-similar in these units; for the
    viscoelastic law ``param`` is the group γ, for the dashpot η = 2ζ·√(k/K√δ)). The state is
    y = (x, x'), x(0) = 0, x'(0) = 1. ``raw_force(delta, delta_dot, param, K, m_eff, v0)``
    is the law WITHOUT the no-adhesion clip; the right-hand side applies it (F ≥ 0, F = 0
    for x ≤ 0). Events (terminal, falling): x = 0, and the unclipped force reaching zero
    while restituting (x' < 0) — after which the clipped force stays zero, so the state
    then is the rebound.

    Returns
    -------
    rhs : callable ``(t, y) -> [x', x'']``
    events : list of two event callables for :func:`scipy.integrate.solve_ivp`
    """

    def force(x, v):
        return float(raw_force(max(x, 0.0), v, param, 1.0, 1.0, 1.0))

    def rhs(t, y):
        return [y[1], -max(force(y[0], y[1]), 0.0) if y[0] > 0 else 0.0]

    def separated(t, y):
        return y[0]

    def force_zero(t, y):
        return force(y[0], y[1]) if y[1] < 0 else 1.0

    for ev in (separated, force_zero):
        ev.terminal, ev.direction = True, -1
    return rhs, [separated, force_zero]


def _solve_normal_cor(raw_force, param, rtol=1e-13, atol=1e-14):
    """Rebound speed ratio of one dimensionless impact (DOP853, tolerances in δ* units)."""
    from scipy.integrate import solve_ivp

    rhs, events = _dimensionless_normal_rhs(raw_force, param)
    sol = solve_ivp(
        rhs,
        (0.0, 1e4),
        [0.0, 1.0],
        method="DOP853",
        rtol=rtol,
        atol=atol,
        events=events,
        first_step=1e-8,
    )
    if sol.status != 1:
        raise RuntimeError(f"dimensionless impact did not end (param = {param!r})")
    return -float(sol.y[1, -1])


def _dashpot_raw_canonical(delta, delta_dot, eta, K, m_eff, v0):
    # η = 2ζ√(k/(K√δ)): the secant form with ζ = η/2
    return _hertz_dashpot_raw(delta, delta_dot, 0.5 * eta, K, m_eff, "secant")


def _viscoelastic_raw(delta, delta_dot, gamma, K, m_eff, v0):
    A = np.asarray(gamma) * (np.asarray(m_eff) / np.asarray(K)) ** 0.4 * np.asarray(v0) ** -0.2
    return _kuwabara_kono_raw(delta, delta_dot, A, K)


#: Canonical dimensionless shapes: raw (unclipped) force in the law signature.
_SHAPES = {"dashpot": _dashpot_raw_canonical, "viscoelastic": _viscoelastic_raw}
#: Table nodes: the canonical parameter p = geomspace(1e-4, 1e4, 161) for every shape.
_TABLE_P = (1e-4, 1e4, 161)


def _solve_cor_table(shape):
    """Solve e(p) at the table nodes (the script behind the tables stored below, ~3 s).

    Regenerate with ``python -c "from pipeline.contact import _print_cor_tables as f; f()"``.
    """
    p = np.geomspace(*_TABLE_P)
    return np.array([_solve_normal_cor(_SHAPES[shape], pi) for pi in p])


def _print_cor_tables():  # pragma: no cover - maintenance script
    import sys
    import textwrap

    for shape in _SHAPES:
        e = _solve_cor_table(shape)
        body = textwrap.fill(" ".join(repr(float(x)) for x in e), 92)
        sys.stdout.write(f'    "{shape}": """\n{textwrap.indent(body, "    ")}\n    """,\n')


@functools.cache
def _table_spline(shape):
    from scipy.interpolate import CubicSpline

    s = np.log(np.geomspace(*_TABLE_P))
    e = np.array(_COR_TABLES[shape].split(), dtype=float)
    u = np.log(-np.log(e))  # ln(−ln e): ~ s + const for weak damping, smooth everywhere
    if e.shape != s.shape or not np.all(np.diff(u) > 0):
        raise RuntimeError(f"corrupt COR table for {shape!r}")  # pragma: no cover
    spline = CubicSpline(s, u)
    # heavy damping: e falls as a power of p (1/η² for the dashpot, γ^(−5/3) viscoelastic);
    # extrapolate ln e linearly in ln p with the end slope q = d ln e/d ln p
    q_hi = float(-np.exp(u[-1]) * spline(s[-1], 1))
    return s, u, spline, spline.derivative(), q_hi


def _table_cor(shape, p):
    p = np.asarray(p, dtype=float)
    s_n, u_n, spl, _, q_hi = _table_spline(shape)
    with np.errstate(divide="ignore"):
        s = np.log(p)
    # weak damping (below the first node): −ln e ∝ p, i.e. u = ln(−ln e) has slope 1
    u = np.where(s < s_n[0], u_n[0] + (s - s_n[0]), spl(np.clip(s, s_n[0], s_n[-1])))
    ln_e = np.where(s > s_n[-1], -np.exp(u_n[-1]) + q_hi * (s - s_n[-1]), -np.exp(u))
    return np.where(p > 0, np.exp(ln_e), 1.0)


def _table_calibrate(shape, e, label):
    e_arr = np.asarray(e, dtype=float)
    if np.any(~((e_arr > 0) & (e_arr <= 1))):
        raise InputError(
            f"{label} reaches every e in the range (0, 1] (e → 0 only as the damping → ∞); "
            f"got e = {e!r}"
        )
    s_n, u_n, spl, dspl, q_hi = _table_spline(shape)
    with np.errstate(divide="ignore"):
        ln_e = np.log(e_arr)
        ut = np.log(-ln_e)
    inside = (ut >= u_n[0]) & (ut <= u_n[-1])
    s = np.where(
        ut < u_n[0],
        s_n[0] + (ut - u_n[0]),
        np.where(ut > u_n[-1], s_n[-1] + (ln_e + np.exp(u_n[-1])) / q_hi, np.interp(ut, u_n, s_n)),
    )
    for _ in range(6):  # Newton on the spline itself: cor(calibrate(e)) == e to ~1e-14
        sc = np.clip(s, s_n[0], s_n[-1])
        s = np.where(inside, sc - (spl(sc) - ut) / dspl(sc), s)
    return np.where(e_arr < 1, np.exp(s), 0.0)


#: e(p) of the canonical dimensionless laws at p = geomspace(1e-4, 1e4, 161), solved by
#: :func:`_solve_cor_table` (DOP853, rtol 1e-13, atol 1e-14 δ*); tests re-solve nodes.
_COR_TABLES = {
    "dashpot": """
    0.9998595175739292 0.9998423780239517 0.9998231476239985 0.9998015713790579
    0.9997773632133938 0.9997502021850998 0.9997197282448592 0.9996855374750316
    0.9996471767576477 0.9996041377856478 0.9995558503649522 0.9995016748916017
    0.999440893922071 0.9993727027357182 0.9992961987500849 0.9992103696633979
    0.9991140801766576 0.9990060571189474 0.9988848727926106 0.9987489263340367
    0.998596422850073 0.9984253500828361 0.9982334523069974 0.9980182011606821
    0.9977767630470161 0.9975059627343366 0.9972022427310823 0.996861617976267
    0.9964796253343041 0.9960512674135278 0.995570949923979 0.9950324122660104
    0.9944286503443218 0.9937518310912861 0.9929931978792571 0.992142966053485
    0.9911902078360434 0.9901227257063316 0.988926913702603 0.9875876057714045
    0.9860879107020335 0.9844090332251977 0.9825300810899854 0.9804278583174006
    0.9780766452759534 0.9754479667173365 0.972510349923162 0.9692290758088261
    0.9655659273104199 0.961478940824196 0.9569221683827178 0.9518454605873836
    0.9461942829954005 0.939909581966908 0.9329277195719887 0.925180501399947 0.9165953256082725
    0.9070954863466445 0.896600669463774 0.885027682781299 0.87229146669099 0.858306432609383
    0.8429881760145753 0.826255606146203 0.8080335246438315 0.788255668897086 0.7668682112340289
    0.7438336709352713 0.7191351522794096 0.6927807676382128 0.6648080444809163
    0.6352880495192343 0.6043289027611355 0.5720783049926862 0.5387246772869454
    0.5044965225319332 0.469659677895919 0.4345122417263217 0.3993771289698085
    0.36459242695061495 0.3304999675772271 0.2974327717128379 0.26570221823924606
    0.2355859060184742 0.207317181472274 0.1810771845266704 0.15699003011890061
    0.135121422789851 0.1154806469146712 0.09802554047338993 0.08266979656183875
    0.0692917784956349 0.05774399376535926 0.04786243933847593 0.03947517865369581
    0.03240970339856557 0.026498834806792146 0.021585100840495326 0.017523668655906627
    0.014184008643429705 0.011450518508357559 0.009222350701144128 0.0074126741377984
    0.0059475718928250505 0.004764739264082863 0.0038121079492444317 0.003046486379612992
    0.002432275877113444 0.001940298080506617 0.0015467508815182579 0.0012322972093675218
    0.0009812824477942702 0.0007810710783436234 0.0006214904188352432 0.0004943683181747551
    0.0003931517880313402 0.00031259434869645146 0.0002485010406942571 0.00019752136894981222
    0.00015698178295965275 0.00012475055762754873 9.912908724848027e-05 7.87646169604983e-05
    6.258030966826793e-05 4.971928880083454e-05 3.949991997512822e-05 3.1380111365106455e-05
    2.4928838935242645e-05 1.9803450332590872e-05 1.5731585919794635e-05 1.2496784725833549e-05
    9.927028797530878e-06 7.885629478024772e-06 6.263978530312589e-06 4.975784410467931e-06
    3.952489568343358e-06 3.1396279447295517e-06 2.493929834488029e-06 1.9810212681783193e-06
    1.5735955346015867e-06 1.2499606466113855e-06 9.928850115853347e-07 7.886804427995442e-07
    6.264736144992185e-07 4.976272698203159e-07 3.952804162468932e-07 3.139830500288902e-07
    2.4940602166956104e-07 1.98110516457766e-07 1.5736495013189432e-07 1.2499953457556391e-07
    9.929073111349269e-08 7.886947747755205e-08 6.264828257092964e-08 4.9763318221220365e-08
    3.952842079678247e-08 3.1398547481339906e-08 2.494075835607145e-08 1.9811151768489044e-08
    1.573655924608642e-08 1.2499994675750483e-08
    """,
    "viscoelastic": """
    0.99982700070404 0.9998058940710878 0.999782212681718 0.9997556425334954 0.9997258313551687
    0.9996923839443782 0.9996548569472179 0.9996127529959592 0.9995655141523314 0.99951251452207
    0.999453052026643 0.9993863391301042 0.9993114924805645 0.9992275212881326 0.999133314301382
    0.9990276252267106 0.9989090563903023 0.9987760404531444 0.9986268199264711
    0.9984594242650754 0.9982716442275862 0.9980610032066594 0.9978247251804879
    0.9975596989009168 0.9972624379029116 0.9969290358700453 0.9965551168555241
    0.9961357798057233 0.9956655367901062 0.9951382442957872 0.9945470268932742
    0.9938841925376398 0.9931411387380173 0.9923082487799484 0.991374777186136
    0.9903287235856507 0.989156694180977 0.9878437501206819 0.9863732419833618
    0.9847266301328595 0.9828832904476174 0.9808203056639209 0.9785122428119873
    0.9759309179186522 0.9730451499100746 0.9698205067598678 0.9662190480973273
    0.9621990704171581 0.9577148627880946 0.9527164837154022 0.9471495727279757
    0.9409552138746554 0.9340698724602271 0.9264254310658298 0.9179493559132843
    0.9085650302540369 0.8981922964588946 0.8867482534478197 0.8741483593920546
    0.8603078907613135 0.845143806327138 0.8285770571504952 0.81053536914447 0.7909565017319148
    0.7697919528495416 0.7470110362849309 0.7226052023617299 0.6965924095950821
    0.6690212878178057 0.6399747701483156 0.6095728223111342 0.5779738763448946
    0.5453745933972027 0.5120076492898131 0.47813735972686966 0.4440531368784942
    0.41006097976515127 0.3764734221667396 0.3435985606563467 0.31172892746796577
    0.28113103011524065 0.25203633714639473 0.22463435004201388 0.19906818575532892
    0.17543283692811668 0.1537760173060815 0.13410127542416508 0.11637289730925618
    0.10052203192643439 0.08645346038335051 0.07405247926591516 0.06319146098766786
    0.05373576894087416 0.04554882386138914 0.03849622595318753 0.03244892613993193
    0.027285505494358105 0.02289366460464498 0.019171047149669492 0.01602552841097723
    0.013375094354409575 0.011147424433306302 0.009279274872047464 0.00771574150736378
    0.006409464115336258 0.005319818640812173 0.004412130446158872 0.0036569307801257
    0.0030292700518824585 0.002508094947023504 0.002075691640644231 0.001717194021656461
    0.001420153642469355 0.001174166778700183 0.0009705532915032228 0.0008020817545353995
    0.0006627353836727047 0.0005475135861165079 0.0004522643416494888 0.0003735430836797292
    0.0003084942214457513 0.00025475190859867725 0.00021035710463564796 0.00017368837602279569
    0.00014340425005140002 0.0001183952562136747 9.774407169987591e-05 8.069243480013583e-05
    6.661369916555766e-05 5.499008428118153e-05 4.539382989486867e-05 3.747159270054438e-05
    3.093153375568908e-05 2.5532636276790837e-05 2.107587182344424e-05 1.7396897007145236e-05
    1.4360017027210853e-05 1.1853197363653181e-05 9.78394225546659e-06 8.075889954389494e-06
    6.666000486365062e-06 5.502232970063406e-06 4.541627369782708e-06 3.748720716750731e-06
    3.094239232903762e-06 2.5540184438148365e-06 2.108111655458486e-06 1.7400540032418743e-06
    1.4362546586979043e-06 1.1854953018221741e-06 9.785160460748737e-07 8.07673491469283e-07
    6.66658641850213e-07 5.502639115250399e-07 4.5419088299305506e-07 3.7489157045593684e-07
    3.09437428396013e-07 2.554111951834804e-07 2.1081764033896715e-07 1.7400988091441402e-07
    1.4362856498558605e-07
    """,
}


@dataclass(frozen=True)
class NormalLaw:
    """A normal contact law: its force, its calibration and the paper's closed form.

    Attributes
    ----------
    name : str
    force : callable ``(delta, delta_dot, param, K, m_eff, v0) -> F`` [N], vectorised
    calibrate : callable ``e -> param``, exact to ±0.001 in e at least
    closed_form : callable ``e -> param`` or None — the paper's own guess
    parameter : str — name and unit of the damping parameter
    material_to_param : callable ``(const, K, m_eff, v0) -> param``
        Maps the law's speed-independent material constant (see ``material``) to the
        damping parameter of an impact at approach speed v0 [m/s] (K [N/m^1.5], m_eff
        [kg]); so a campaign can hold the material fixed and let e vary with speed.
    material : str — name and unit of that material constant
    cor : callable ``param -> e`` or None — the restitution a parameter actually gives
    e_range : (float, float) — the closure of the reachable range of e
    """

    name: str
    force: Callable
    calibrate: Callable
    closed_form: Callable | None = None
    parameter: str = "c [-]"
    material_to_param: Callable | None = None
    material: str = ""
    cor: Callable | None = None
    e_range: tuple[float, float] = (0.0, 1.0)


def _hc_force(delta, delta_dot, c, K, m_eff, v0):
    return hunt_crossley(delta, delta_dot, c, K, v0)


def _hertz_force(delta, delta_dot, c, K, m_eff, v0):
    return hertz(delta, K)


def _hc_material_to_param(alpha, K, m_eff, v0):
    """Hunt–Crossley family: c = α·v0 (α [s/m])."""
    return _f(np.asarray(alpha, dtype=float) * np.asarray(v0, dtype=float))


def _dashpot_law(name, stiffness):
    def force(delta, delta_dot, zeta, K, m_eff, v0):
        return hertz_dashpot(delta, delta_dot, zeta, K, m_eff, stiffness)

    def calibrate(e):
        return calibrate_hertz_dashpot(e, stiffness)

    def closed_form(e):
        return zeta_hertz_dashpot_dem(e, stiffness)

    def cor(zeta):
        return cor_hertz_dashpot(zeta, stiffness)

    kind = "tangent stiffness 2E*a" if stiffness == "tangent" else "secant stiffness (4/3)E*a"
    return NormalLaw(
        name,
        force,
        calibrate,
        closed_form,
        f"zeta [-] ({kind})",
        material_to_param=lambda zeta, K, m_eff, v0: _f(np.asarray(zeta, dtype=float)),
        material="zeta [-] (speed-independent damping ratio)",
        cor=cor,
        e_range=(0.0, 1.0),
    )


def _viscoelastic_force(delta, delta_dot, gamma, K, m_eff, v0):
    raw = _viscoelastic_raw(delta, delta_dot, gamma, K, m_eff, v0)
    return _f(np.where(np.asarray(delta) > 0, np.maximum(raw, 0.0), 0.0))


def _hertz_calibrate(e):
    if np.any(np.asarray(e) != 1):
        raise InputError(
            f"the elastic 'hertz' law only reaches e = 1; got e = {e!r}. "
            "Choose a damped law such as normal='hunt_crossley'."
        )
    return 0.0


def _hc_law(name, closed_form):
    return NormalLaw(
        name,
        _hc_force,
        calibrate_hunt_crossley_family,
        closed_form,
        "c [-]",
        material_to_param=_hc_material_to_param,
        material="alpha [s/m] (c = alpha*v0)",
        cor=cor_hunt_crossley_family,
        e_range=(0.0, 1.0),
    )


NORMAL_LAWS: dict[str, NormalLaw] = {
    "hertz": NormalLaw(
        "hertz",
        _hertz_force,
        _hertz_calibrate,
        None,
        "none",
        material_to_param=lambda const, K, m_eff, v0: 0.0,
        material="none",
        cor=lambda p: _f(np.ones_like(np.asarray(p, dtype=float))),
        e_range=(1.0, 1.0),
    ),
    "hunt_crossley": _hc_law("hunt_crossley", c_hunt_crossley),
    "lankarani_nikravesh": _hc_law("lankarani_nikravesh", c_lankarani_nikravesh),
    "flores": _hc_law("flores", c_flores),
    "hertz_dashpot": _dashpot_law("hertz_dashpot", "tangent"),
    "hertz_dashpot_secant": _dashpot_law("hertz_dashpot_secant", "secant"),
    "viscoelastic": NormalLaw(
        "viscoelastic",
        _viscoelastic_force,
        calibrate_kuwabara_kono,
        gamma_schwager_poschel,
        "gamma = A*v0^(1/5)*(K/m*)^(2/5) [-]",
        material_to_param=kuwabara_kono_group,
        material="A [s] (material time of Kuwabara-Kono / Brilliantov)",
        cor=cor_kuwabara_kono,
        e_range=(0.0, 1.0),
    ),
}

#: The same laws without the no-adhesion clip, in the law signature (for event functions).
_RAW_FORCES = {
    "hertz": lambda d, dd, p, K, m, v0: hertz(d, K),
    "hunt_crossley": lambda d, dd, c, K, m, v0: hertz(d, K) * (1.0 + c * np.asarray(dd) / v0),
    "hertz_dashpot": lambda d, dd, z, K, m, v0: _hertz_dashpot_raw(d, dd, z, K, m, "tangent"),
    "hertz_dashpot_secant": lambda d, dd, z, K, m, v0: _hertz_dashpot_raw(d, dd, z, K, m, "secant"),
    "viscoelastic": _viscoelastic_raw,
}
_RAW_FORCES["lankarani_nikravesh"] = _RAW_FORCES["flores"] = _RAW_FORCES["hunt_crossley"]


def _law(name) -> NormalLaw:
    try:
        return NORMAL_LAWS[name]
    except (KeyError, TypeError):
        raise InputError(
            f"unknown normal law {name!r}; choose one of {', '.join(NORMAL_LAWS)}"
        ) from None


def normal_cor(law, param):
    """The coefficient of restitution a named law's damping parameter actually gives [-].

    Parameters
    ----------
    law : str — a key of :data:`NORMAL_LAWS`
    param : float or array — the law's dimensionless damping parameter

    Returns
    -------
    e [-], from the law's exact relation or its table (no ODE per call).
    """
    return _law(law).cor(param)


def dimensionless_normal_rhs(law, param):
    """Right-hand side and end-of-contact events of the dimensionless impact of ``law``.

    See :func:`_dimensionless_normal_rhs` (length δ* = (m*·v0²/K)^{2/5}, time δ*/v0,
    initial state (0, 1)); ``param`` is the law's dimensionless damping parameter.
    """
    _law(law)
    return _dimensionless_normal_rhs(_RAW_FORCES[law], param)


# --------------------------------------------------------------------------- Mindlin
def mindlin_stiffness(delta, G_eff, R_eff):
    """Mindlin no-slip tangential stiffness k_t = 8·G*·a, a = √(R*·δ) [N/m].

    References
    ----------
    R. D. Mindlin, J. Appl. Mech. 16:259 (1949).
    """
    return 8.0 * G_eff * contact_radius(delta, R_eff)


__all__ += ["MindlinState", "mindlin_total", "mindlin_incremental"]


@dataclass(frozen=True)
class MindlinState:
    """Tangential contact state after a Mindlin update (arrays broadcast together).

    Attributes
    ----------
    xi : numpy.ndarray
        Elastic tangential displacement [m]: the stored spring displacement of the total rule,
        Ft/k_t for the incremental rule.
    Ft : numpy.ndarray
        Tangential force [N], > 0 opposing positive ξ (PHYSICS.md §1 when ξ accumulates the
        slip measured along the initial slip).
    sliding : numpy.ndarray of bool
        True where the Coulomb cap |Ft| = μ·Fn was reached (the contact slides).
    """

    xi: np.ndarray
    Ft: np.ndarray
    sliding: np.ndarray


def _cap(Fn, mu):
    return np.asarray(mu, dtype=float) * np.maximum(np.asarray(Fn, dtype=float), 0.0)


def mindlin_total(xi, dxi, delta, Fn, mu, G_eff, R_eff) -> MindlinState:
    r"""One step of the Mindlin no-slip spring with Coulomb cap, TOTAL-displacement rule.

    The spring keeps the total tangential displacement ξ of the contact since it formed
    and the force follows the current stiffness, :math:`F_t = k_t(\delta)\,\xi`,
    :math:`k_t = 8G^*a`, :math:`a = \sqrt{R^*\delta}` (Mindlin 1949). Loading and
    unloading use the same rule: ξ ← ξ + Δξ; where :math:`|k_t\xi| > \mu F_n` the contact
    slides and ξ is rescaled onto the cap, :math:`\xi = \mathrm{sign}(\xi)\,\mu F_n/k_t`,
    so the force equals ±μ·Fn. As δ falls the same ξ carries less force (the spring
    "forgets" load with the contact area) and the cap μFn/k_t ∝ δ shrinks.
    This is the rule of LAMMPS ``pair granular ... tangential mindlin`` and of LIGGGHTS
    ``tangential_model history`` (Di Renzo & Di Maio 2004 "no-slip" model with Coulomb
    limit), not the full Mindlin–Deresiewicz (1953) annulus-of-slip theory that Thornton
    et al. (2011, 2013) use; on Chung & Ooi's test 4 it gives e_t ≈ 0.698 at 10°
    against 0.714 for :func:`mindlin_incremental` (PHYSICS.md §4), and 0.952 against
    0.893 at 5° (PHYSICS.md's "0.89 vs 0.95" does not say which is which; an explicit DEM
    loop with these per-step rules, ``tests/test_simulate.py``, gives this order).

    Parameters
    ----------
    xi : float or array — stored tangential displacement before the step [m]
    dxi : float or array — slip displacement over the step, s·dt [m]
    delta : float or array — normal approach at the end of the step [m]
    Fn : float or array — normal force at the end of the step [N] (> 0 compressive)
    mu : float or array — Coulomb friction coefficient [-]
    G_eff : float or array — effective shear modulus G* [Pa]
    R_eff : float or array — effective radius R* [m]

    Returns
    -------
    MindlinState
        ``xi`` after the step (rescaled where sliding), ``Ft`` [N], ``sliding``.

    Notes
    -----
    In continuous time the rule is the projected dynamics ξ̇ = s inside the cap and
    ξ = ±μFn/k_t on it while the slip pushes outward (used by
    :func:`pipeline.simulate.impact`). Where δ ≤ 0 (no contact) ξ and Ft are zero.

    The rule is not energy-consistent: at fixed ξ a change of k_t changes the stored
    energy ½k_t·ξ² without any work, so over an impact the tangential contact can return
    more energy than it received (net friction work ∫Ft·s dt < 0). Example: an alumina
    ball (Chung & Ooi test 4 scene) spinning at 100 rad/s that hits the wall normally leaves
    with |ω| ≈ 100.8 rad/s under this rule, 81.9 rad/s under :func:`mindlin_incremental`.

    References
    ----------
    R. D. Mindlin, J. Appl. Mech. 16:259 (1949), doi:10.1115/1.4009973.
    R. D. Mindlin, H. Deresiewicz, J. Appl. Mech. 20:327 (1953), doi:10.1115/1.4010702.
    A. Di Renzo, F. P. Di Maio, Chem. Eng. Sci. 59:525 (2004),
    doi:10.1016/j.ces.2003.09.037.
    C. Thornton, S. J. Cummins, P. W. Cleary, Powder Technol. 210:189 (2011),
    doi:10.1016/j.powtec.2011.01.013; Powder Technol. 233:30 (2013),
    doi:10.1016/j.powtec.2012.08.012.
    """
    k = mindlin_stiffness(delta, G_eff, R_eff)
    xi_new = np.asarray(xi, dtype=float) + np.asarray(dxi, dtype=float)
    trial = k * xi_new
    cap = _cap(Fn, mu)
    sliding = np.abs(trial) > cap
    Ft = np.clip(trial, -cap, cap)
    with np.errstate(divide="ignore", invalid="ignore"):
        xi_cap = np.where(k > 0, Ft / np.where(k > 0, k, 1.0), 0.0)
    xi_new = np.where(sliding, xi_cap, xi_new)
    in_contact = np.asarray(delta) > 0
    return MindlinState(
        xi=np.where(in_contact, xi_new, 0.0),
        Ft=np.where(in_contact, Ft, 0.0),
        sliding=sliding & in_contact,
    )


def mindlin_incremental(Ft, dxi, delta, Fn, mu, G_eff, R_eff) -> MindlinState:
    r"""One step of the Mindlin no-slip spring with Coulomb cap, INCREMENTAL rule.

    The force, not the displacement, is the history variable: each slip increment adds
    :math:`\Delta F_t = k_t(\delta)\,\Delta\xi` with the current stiffness
    :math:`k_t = 8G^*\sqrt{R^*\delta}` (Mindlin 1949), and the result is clipped to the
    Coulomb cap, :math:`|F_t| \le \mu F_n`. Loading and unloading use the same tangent
    stiffness, so a stuck contact keeps its force as δ falls until the shrinking cap
    μFn clips it. This is the rule of YADE's ``Law2_ScGeom_MindlinPhys_Mindlin`` and of
    LAMMPS ``tangential mindlin/force``; it simplifies the Mindlin–Deresiewicz (1953)
    loading/unloading history (no partial-slip annulus, no k_t reduction under partial
    slip — Thornton et al. 2011 discuss the consequences).

    Parameters
    ----------
    Ft : float or array — tangential force before the step [N] (> 0 opposing positive ξ)
    dxi : float or array — slip displacement over the step, s·dt [m]
    delta : float or array — normal approach at the end of the step [m]
    Fn : float or array — normal force at the end of the step [N]
    mu : float or array — Coulomb friction coefficient [-]
    G_eff : float or array — effective shear modulus G* [Pa]
    R_eff : float or array — effective radius R* [m]

    Returns
    -------
    MindlinState
        ``Ft`` after the step [N], ``xi`` = Ft/k_t [m], ``sliding``.

    References
    ----------
    R. D. Mindlin, J. Appl. Mech. 16:259 (1949), doi:10.1115/1.4009973.
    R. D. Mindlin, H. Deresiewicz, J. Appl. Mech. 20:327 (1953), doi:10.1115/1.4010702.
    A. Di Renzo, F. P. Di Maio, Chem. Eng. Sci. 59:525 (2004),
    doi:10.1016/j.ces.2003.09.037.
    C. Thornton, S. J. Cummins, P. W. Cleary, Powder Technol. 210:189 (2011),
    doi:10.1016/j.powtec.2011.01.013.
    """
    k = mindlin_stiffness(delta, G_eff, R_eff)
    trial = np.asarray(Ft, dtype=float) + k * np.asarray(dxi, dtype=float)
    cap = _cap(Fn, mu)
    sliding = np.abs(trial) > cap
    F = np.clip(trial, -cap, cap)
    in_contact = np.asarray(delta) > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        xi = np.where(k > 0, F / np.where(k > 0, k, 1.0), 0.0)
    return MindlinState(
        xi=np.where(in_contact, xi, 0.0),
        Ft=np.where(in_contact, F, 0.0),
        sliding=sliding & in_contact,
    )
