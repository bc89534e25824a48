r"""Compliant contact: Hertz, damped normal laws and Mindlin tangential compliance.

Theory (PHYSICS.md §4; Johnson, *Contact Mechanics*, CUP 1985, §4.2 and §11.4):

.. math::

    F_n = K\,\delta^{3/2}, \qquad K = \tfrac43 E^*\sqrt{R^*}, \qquad a = \sqrt{R^*\delta}

An elastic impact at approach speed :math:`v_0` reaches

.. math::

    \delta_{max} = \left(\frac{15\,m^* v_0^2}{16\,E^*\sqrt{R^*}}\right)^{2/5}, \quad
    F_{max} = K\delta_{max}^{3/2}, \quad
    t_c = 0.8\,B(\tfrac25,\tfrac12)\,\frac{\delta_{max}}{v_0} = 2.943275\ldots\frac{\delta_{max}}{v_0}.

Damped laws of the Hunt–Crossley family share one force law
:math:`F = K\delta^{3/2}(1 + c\,\dot\delta/v_0)` whose coefficient of restitution depends on
``c`` alone through the exact energy integral :math:`c(1+e) = \ln[(1+c)/(1-ce)]`.

Every normal law is a :class:`NormalLaw` in :data:`NORMAL_LAWS`: a vectorised force
function ``force(delta, delta_dot, param, K, m_eff, v0)`` [N] and a calibration
``calibrate(e)`` returning the damping parameter that gives restitution ``e``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy import optimize, special

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


def _cor_scalar(c):
    if c <= 0:
        return 1.0
    hi = min(1.0, 1.0 / c) * (1 - 1e-15)

    def g(e):
        return c * (1 + e) - np.log1p(c) + np.log1p(-c * e)

    return optimize.brentq(g, 0.0, hi, xtol=1e-15, rtol=1e-15)


def cor_hunt_crossley_family(c):
    """Exact coefficient of restitution of F = K·δ^{3/2}(1 + c·δ̇/v0).

    Solves c·(1+e) = ln[(1+c)/(1−c·e)] (PHYSICS.md §4) for e ∈ (0, 1].
    """
    return _f(np.vectorize(_cor_scalar, otypes=[float])(np.asarray(c, dtype=float)))


def _c_scalar(e):
    if e >= 1.0:
        return 0.0

    def h(c):
        return c * (1 + e) - np.log1p(c) + np.log1p(-c * e)

    hi = (1.0 / e) * (1 - 1e-15) if e > 0 else np.inf
    lo = 1e-12
    # h > 0 for small c and → −∞ at c → 1/e
    return optimize.brentq(h, lo, hi, xtol=1e-15, rtol=1e-15)


def calibrate_hunt_crossley_family(e):
    """The damping c giving restitution e exactly (no ODE), for any e ∈ (0, 1].

    Raises
    ------
    InputError
        For e outside (0, 1].
    """
    e_arr = np.asarray(e, dtype=float)
    if np.any((e_arr <= 0) | (e_arr > 1)):
        raise InputError(f"Hunt–Crossley-type laws reach every e in (0, 1]; got e = {e!r}")
    return _f(np.vectorize(_c_scalar, otypes=[float])(e_arr))


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
    """

    name: str
    force: Callable
    calibrate: Callable
    closed_form: Callable | None = None
    parameter: str = "c [-]"


def _hc_force(delta, delta_dot, c, K, m_eff, v0):
    return hunt_crossley(delta, delta_dot, c, K, v0)


def _hertz_force(delta, delta_dot, c, K, m_eff, v0):
    return hertz(delta, K)


def _hertz_calibrate(e):
    if np.any(np.asarray(e) != 1):
        raise InputError(f"the elastic 'hertz' law only reaches e = 1; got e = {e!r}. "
                         "Choose a damped law such as normal='hunt_crossley'.")
    return 0.0


NORMAL_LAWS: dict[str, NormalLaw] = {
    "hertz": NormalLaw("hertz", _hertz_force, _hertz_calibrate, None, "none"),
    "hunt_crossley": NormalLaw("hunt_crossley", _hc_force, calibrate_hunt_crossley_family,
                               c_hunt_crossley),
    "lankarani_nikravesh": NormalLaw("lankarani_nikravesh", _hc_force,
                                     calibrate_hunt_crossley_family, c_lankarani_nikravesh),
    "flores": NormalLaw("flores", _hc_force, calibrate_hunt_crossley_family, c_flores),
}


# --------------------------------------------------------------------------- Mindlin
def mindlin_stiffness(delta, G_eff, R_eff):
    """Mindlin no-slip tangential stiffness k_t = 8·G*·a, a = √(R*·δ) [N/m].

    References
    ----------
    R. D. Mindlin, J. Appl. Mech. 16:259 (1949).
    """
    return 8.0 * G_eff * contact_radius(delta, R_eff)
