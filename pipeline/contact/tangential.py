r"""Tangential contact: Mindlin's no-slip stiffness with a Coulomb cap and a history rule.

:math:`k_t = 8G^*a`, :math:`|F_t| \le \mu F_n` (Mindlin 1949; docs/theory.md). The DEM codes
keep different histories: the total displacement (LAMMPS ``mindlin``, LIGGGHTS
``tangential history``: :func:`mindlin_total`) or the force, incremented
(YADE ``MindlinPhys``, LAMMPS ``mindlin/force``: :func:`mindlin_incremental`).

Tangential damping. A dashpot on the slip s acts in parallel with the spring; the codes
scale it differently:

- LAMMPS (``pair granular`` / ``fix wall/gran granular ... tangential mindlin k_t x_γ,t μ``):
  η_t = x_γ,t·η_n, the normal law's dashpot coefficient at the same overlap
  (:attr:`pipeline.contact.NormalLaw.damping`), so F_t = k_t·ξ + x_γ,t·η_n(δ)·s, and
  spring plus dashpot together are capped at μ·|F_n| (F_n including its own dashpot);
  on the cap the stored displacement is reset so that their sum is exactly on it. This
  is what ``pipeline.simulate`` implements (``tangential_damping=`` x_γ,t).
- YADE (``Law2_ScGeom_MindlinPhys_Mindlin``, linear damping ``betan``, ``betas``):
  c_s = 2·β_s·√(m*·k_s) with the current tangential stiffness k_s = 8·G*·a, i.e. a fraction
  β_s of the tangential spring's critical damping (and c_n = 2·β_n·√(m*·k_n),
  k_n = 2·E*·a); the Coulomb cap applies to the spring force alone and the dashpot is
  dropped while the contact slides. With a Tsuji-type normal dashpot (YADE's ``en``/``es``
  inputs, its ``alpha``) the same coefficient is used for both directions, c_s = c_n,
  which is LAMMPS's x_γ,t = 1 (up to YADE's cap on the spring alone). A linear YADE
  damping maps to x_γ,t = (β_s/β_n)·√(k_s/k_n) = (β_s/β_n)·√(4·G*/E*) on a tangent-stiffness
  normal dashpot, again up to where the cap is applied.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .elastic import contact_radius

__all__ = [
    "mindlin_stiffness",
    "MindlinState",
    "mindlin_total",
    "mindlin_incremental",
]


# --------------------------------------------------------------------------- Mindlin
def mindlin_stiffness(delta, G_eff, R_eff):
    """Mindlin no-slip tangential stiffness k_t = 8·G*·a, a = √(R*·δ) [N/m].

    References
    ----------
    R. D. Mindlin, J. Appl. Mech. 16:259 (1949).
    """
    return 8.0 * G_eff * contact_radius(delta, R_eff)


@dataclass(frozen=True)
class MindlinState:
    """Tangential contact state after a Mindlin update (arrays broadcast together).

    Attributes
    ----------
    xi : numpy.ndarray
        Elastic tangential displacement [m]: the stored spring displacement of the total rule,
        Ft/k_t for the incremental rule.
    Ft : numpy.ndarray
        Tangential force [N], > 0 opposing positive ξ (docs/theory.md when ξ accumulates the
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
    against 0.714 for :func:`mindlin_incremental` (docs/theory.md), and 0.952 against
    0.893 at 5° (the often-quoted "0.89 vs 0.95" does not say which is which; an explicit DEM
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
