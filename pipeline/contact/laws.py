"""The registry of named normal laws, :data:`NORMAL_LAWS`: force, calibration, closed form,
material constant and the normal damping coefficient each law implies."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .damping import (
    _dimensionless_normal_rhs,
    calibrate_hertz_dashpot,
    calibrate_hunt_crossley_family,
    calibrate_kuwabara_kono,
    cor_hertz_dashpot,
    cor_hunt_crossley_family,
    cor_kuwabara_kono,
)
from .elastic import _f, hertz
from .normal import (
    _dashpot_factor,
    _hertz_dashpot_raw,
    _viscoelastic_raw,
    c_flores,
    c_hunt_crossley,
    c_lankarani_nikravesh,
    gamma_schwager_poschel,
    hertz_dashpot,
    hunt_crossley,
    kuwabara_kono_group,
    zeta_hertz_dashpot_dem,
)
from .plastic import _law_force as _thornton_force
from .plastic import _no_damping as _thornton_damping
from .plastic import calibrate_thornton, cor_thornton

__all__ = [
    "NormalLaw",
    "NORMAL_LAWS",
    "normal_cor",
    "dimensionless_normal_rhs",
]


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
    damping : callable ``(delta, param, K, m_eff, v0) -> eta_n`` [N·s/m]
        The normal dashpot coefficient at approach δ [m]: every law here is linear in the
        approach rate, F = F_el(δ) + η_n(δ)·δ̇ before the no-adhesion clip. A tangential
        dashpot of ratio x_γ,t (LAMMPS's convention, :mod:`pipeline.contact.tangential`)
        has the coefficient x_γ,t·η_n(δ). Thornton's plastic law has no dashpot (its loss
        is plastic work): η_n = 0.

    Notes
    -----
    ``"thornton"`` (:mod:`pipeline.contact.plastic`) depends on the largest approach so far,
    not on the rate; in this signature, which describes one impact from approach speed v0
    at δ = 0, it loads while δ̇ ≥ 0 and unloads from that impact's own largest approach
    (closed form). Its parameter r = v_y/v0 plays the damping's part: the restitution is a
    function of r alone (:func:`pipeline.contact.cor_thornton`).
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
    damping: Callable | None = None


def _approach(delta):
    return np.maximum(np.asarray(delta, dtype=float), 0.0)


def _hc_damping(delta, c, K, m_eff, v0):
    """Hunt–Crossley family: η_n = c·K·δ^{3/2}/v0."""
    d = _approach(delta)
    return _f(np.asarray(c) * np.asarray(K) * d * np.sqrt(d) / np.asarray(v0))


def _no_damping(delta, param, K, m_eff, v0):
    return _f(np.zeros_like(_approach(delta)))


def _viscoelastic_damping(delta, gamma, K, m_eff, v0):
    """Viscoelastic law: η_n = (3/2)·K·A·√δ with A = γ·(m*/K)^{2/5}·v0^{−1/5}."""
    A = np.asarray(gamma) * (np.asarray(m_eff) / np.asarray(K)) ** 0.4 * np.asarray(v0) ** -0.2
    return _f(1.5 * np.asarray(K) * A * np.sqrt(_approach(delta)))


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

    def damping(delta, zeta, K, m_eff, v0):
        # η_n = 2ζ·√(m*·k(δ)), k = factor·K·√δ (tangent 3/2, secant 1)
        k = _dashpot_factor(stiffness) * np.asarray(K) * np.sqrt(_approach(delta))
        return _f(2.0 * np.asarray(zeta) * np.sqrt(np.asarray(m_eff) * k))

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
        damping=damping,
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
        damping=_hc_damping,
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
        damping=_no_damping,
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
        damping=_viscoelastic_damping,
    ),
    "thornton": NormalLaw(
        "thornton",
        _thornton_force,
        calibrate_thornton,
        None,
        "r = v_y/v0 [-] (yield speed over approach speed)",
        material_to_param=lambda v_y, K, m_eff, v0: _f(
            np.asarray(v_y, dtype=float) / np.asarray(v0, dtype=float)
        ),
        material="v_y [m/s] (yield speed; from the yield pressure by yield_velocity)",
        cor=cor_thornton,
        e_range=(0.0, 1.0),
        damping=_thornton_damping,
    ),
}


#: The same laws without the no-adhesion clip, in the law signature (for event functions).
_RAW_FORCES = {
    "hertz": lambda d, dd, p, K, m, v0: hertz(d, K),
    "hunt_crossley": lambda d, dd, c, K, m, v0: hertz(d, K) * (1.0 + c * np.asarray(dd) / v0),
    "hertz_dashpot": lambda d, dd, z, K, m, v0: _hertz_dashpot_raw(d, dd, z, K, m, "tangent"),
    "hertz_dashpot_secant": lambda d, dd, z, K, m, v0: _hertz_dashpot_raw(d, dd, z, K, m, "secant"),
    "viscoelastic": _viscoelastic_raw,
    "thornton": lambda d, dd, r, K, m, v0: _thornton_force(d, dd, r, K, m, v0, clip=False),
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
