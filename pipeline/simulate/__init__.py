r"""Hertz–Mindlin simulation of an oblique impact: records with known truth.

Degrees of freedom (docs/theory.md): the normal approach δ, the tangential velocity of the
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
and :math:`s(P_t) = v_{t0} - (1 + 1/\kappa)P_t/m` (docs/theory.md). For two free spheres
the normal problem uses :math:`m^* = m_1 m_2/(m_1 + m_2)` and the slip uses :math:`m_t`
above (the second sphere's κ is ``target_kappa``, default the ball's). A movable flat
target (finite ``target_mass``, infinite ``target_radius``) is refused, as by
:func:`pipeline.rigid.sphere_on_plane`: its rotational term depends on where its centre of
mass lies, which the scene does not say.

The tangential axis points along the initial slip :math:`s_0 = v_{t0} - \omega_0 R`: if a
spin or a surface speed makes :math:`s_0 < 0`, every tangential output (``Ft``, ``slip``,
``vt``, ``spin``, ``omega``, ``Pt_final``) is reported on the flipped axis so that
``Ft > 0`` still opposes the initial slip (``attrs["tangential_axis_sign"] = -1``). This is
the conventions of docs/theory.md fix for the outputs: ``Pt > 0`` opposes the
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
    (docs/theory.md) for any normal law.
``"mindlin"``
    Tangential spring :math:`k_t = 8G^*a` with the Coulomb cap and a displacement history,
    see :func:`pipeline.contact.mindlin_total` (``history="total"``, the default, as
    LAMMPS ``mindlin`` and LIGGGHTS ``tangential history``) and
    :func:`pipeline.contact.mindlin_incremental` (``history="incremental"``, as YADE
    ``MindlinPhys`` and LAMMPS ``mindlin/force``). The single-impact solver integrates
    the continuous-time limit of these rules exactly, switching between stick and slide
    at events.

Tangential damping (``tangential_damping=``, LAMMPS's x_γ,t): a dashpot on the slip in
parallel with the Mindlin spring, x_γ,t times the normal law's dashpot coefficient at the
same overlap, spring and dashpot capped together at μ·Fn (LAMMPS ``tangential mindlin``;
YADE's convention beside it in :mod:`pipeline.contact.tangential`). ``kt_scale`` scales the
spring (rough contacts are softer than 8·G*·a).

Three paths, one physics (they agree within their stated errors; ``tests/test_simulate.py``
sweeps every law, both history rules and both paths over 1–89° of Chung & Ooi's test 4):

- :func:`impact` — one scene, adaptive ``solve_ivp`` with events at every stick/slide
  switch and at separation; returns a record (``xarray.Dataset``).
- :func:`impact_outcomes` — thousands of scenes at once: a fixed-step RK4 in dimensionless
  time over numpy arrays (no per-scene Python loop), the normal problem integrated once
  per distinct damping parameter (every law is self-similar), Coulomb friction from Routh's
  closed form; returns :class:`ImpactOutcomes`.
- ``impact_outcomes(..., method="table")`` — the outcome read from a table of the
  dimensionless tangential problem (:mod:`pipeline.simulate.table`), built once per law,
  damping and stiffness group and cached, with a stated and tested interpolation error.

:mod:`pipeline.simulate.lammps` runs the same scenes in LAMMPS, where it is installed.

References
----------
R. D. Mindlin, J. Appl. Mech. 16:259 (1949), doi:10.1115/1.4009973.
R. D. Mindlin, H. Deresiewicz, J. Appl. Mech. 20:327 (1953), doi:10.1115/1.4010702.
N. Maw, J. R. Barber, J. N. Fawcett, Wear 38:101 (1976), doi:10.1016/0043-1648(76)90201-7.
Y. C. Chung, J. Y. Ooi, Granular Matter 13:643 (2011), doi:10.1007/s10035-011-0277-0.
"""

from __future__ import annotations

from ._common import HISTORY_RULES, TANGENTIAL_MODELS, default_normal
from .batch import TangentialHistory, tangential_history
from .outcomes import ImpactOutcomes, impact_outcomes
from .single import impact

__all__ = [
    "impact",
    "impact_outcomes",
    "tangential_history",
    "ImpactOutcomes",
    "TangentialHistory",
    "TANGENTIAL_MODELS",
    "HISTORY_RULES",
    "default_normal",
    "to_sensor",
]


def __getattr__(name):
    # the sensor model (scipy.signal) loads only when asked for
    if name == "to_sensor":
        from ..sensor_model import to_sensor

        return to_sensor
    raise AttributeError(f"module 'pipeline.simulate' has no attribute {name!r}")
