r"""Damped normal force laws on the Hertz spring, and each paper's closed-form damping.

The Hunt–Crossley family (Hunt & Crossley, Lankarani & Nikravesh, Flores et al.) shares one
law :math:`F = K\delta^{3/2}(1 + c\,\dot\delta/v_0)`; the linear dashpot on Hertz (Tsuji
type) :math:`F = K\delta^{3/2} + 2\zeta\sqrt{m^*k(\delta)}\,\dot\delta` and the viscoelastic
law :math:`F = K(\delta^{3/2} + \tfrac32 A\sqrt\delta\,\dot\delta)` (Kuwabara & Kono;
Brilliantov et al.) have other shapes. Every force is clipped at F ≥ 0 (no adhesion).
The restitution each law gives and its calibration live in :mod:`pipeline.contact.damping`.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .elastic import _f, hertz

__all__ = [
    "hunt_crossley",
    "lankarani_nikravesh",
    "flores",
    "c_hunt_crossley",
    "c_lankarani_nikravesh",
    "c_flores",
    "hertz_dashpot",
    "zeta_hertz_dashpot_dem",
    "kuwabara_kono",
    "kuwabara_kono_group",
    "SCHWAGER_POSCHEL_C1",
    "SCHWAGER_POSCHEL_C2",
    "gamma_schwager_poschel",
]


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


def _dashpot_raw_canonical(delta, delta_dot, eta, K, m_eff, v0):
    # η = 2ζ√(k/(K√δ)): the secant form with ζ = η/2
    return _hertz_dashpot_raw(delta, delta_dot, 0.5 * eta, K, m_eff, "secant")


def _viscoelastic_raw(delta, delta_dot, gamma, K, m_eff, v0):
    A = np.asarray(gamma) * (np.asarray(m_eff) / np.asarray(K)) ** 0.4 * np.asarray(v0) ** -0.2
    return _kuwabara_kono_raw(delta, delta_dot, A, K)
