r"""Hertz's elastic contact and the exact elastic impact (docs/theory.md).

.. math::

    F_n = K\,\delta^{3/2}, \qquad K = \tfrac43 E^*\sqrt{R^*}, \qquad a = \sqrt{R^*\delta}

An elastic impact at approach speed :math:`v_0` reaches

.. math::

    \delta_{max} = \left(\frac{15\,m^* v_0^2}{16\,E^*\sqrt{R^*}}\right)^{2/5}, \quad
    F_{max} = K\delta_{max}^{3/2}, \quad
    t_c = 0.8\,B(\tfrac25,\tfrac12)\,\frac{\delta_{max}}{v_0}
        = 2.943275\ldots\frac{\delta_{max}}{v_0}.

References
----------
K. L. Johnson, Contact Mechanics, Cambridge University Press (1985),
doi:10.1017/CBO9781139171731.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..scene import Scene

__all__ = [
    "HERTZ_TC_CONSTANT",
    "hertz_stiffness",
    "hertz",
    "contact_radius",
    "HertzImpact",
    "hertz_impact",
    "hertz_pulse",
]


#: t_c·v0/δ_max for an elastic Hertz impact: 0.8·B(2/5, 1/2) = 2.94327518... (the value of
#: ``0.8 * scipy.special.beta(0.4, 0.5)`` written out, so that importing contact does not
#: load scipy.special)
HERTZ_TC_CONSTANT = 2.9432751843247047


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
    from scipy import special  # loaded on first use: importing contact stays light

    u = special.betaincinv(0.4, 0.5, s)
    sign = np.where(t <= half, 1.0, -1.0)
    delta = np.where(inside, impact.delta_max * u**0.4, 0.0)
    delta_dot = np.where(inside, sign * impact.v0 * np.sqrt(1.0 - u), 0.0)
    F = np.where(inside, impact.F_max * u**0.6, 0.0)
    Pn = impact.m_eff * np.where(
        t < 0, 0.0, np.where(inside, impact.v0 - delta_dot, 2.0 * impact.v0)
    )
    return {"delta": delta, "delta_dot": delta_dot, "F": F, "Pn": Pn}
