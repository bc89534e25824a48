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

Every normal law is a :class:`NormalLaw` in :data:`NORMAL_LAWS`: a vectorised force
function ``force(delta, delta_dot, param, K, m_eff, v0)`` [N] and a calibration
``calibrate(e)`` returning the damping parameter that gives restitution ``e``.
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
        bad = ~((xn > la) & (xn < ha))
        xn = np.where(bad, 0.5 * (la + ha), xn)
        xn = np.where(zero, xa, xn)
        done = zero | (np.abs(xn - xa) <= rtol * np.abs(xn)) | (ha - la <= rtol * np.abs(ha))
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
}


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
    et al. (2011, 2013) use; on Chung & Ooi's test 4 it gives e_t ≈ 0.952 at 5° and
    0.698 at 10° (PHYSICS.md §4), against 0.893 and 0.714 for
    :func:`mindlin_incremental`.

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
