r"""Compliant contact: Hertz, damped normal laws and Mindlin tangential compliance.

Theory (docs/theory.md; Johnson, *Contact Mechanics*, CUP 1985, §4.2 and §11.4):

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
And a plastic one: Thornton's elastic–perfectly-plastic law (Thornton 1997; Johnson §11.4
for the onset of yield), Hertz to the yield pressure p_y, linear beyond, elastic unloading
on an enlarged radius, whose COR depends on :math:`r = v_y/v_0` alone, in closed form
(:mod:`~pipeline.contact.plastic`).

All these laws are self-similar: in units δ* = (m*·v0²/K)^{2/5}, δ*/v0 the impact reads
x'' = −f(x, x'; p) with one dimensionless parameter p, so e(p) is computed once — exactly
from the energy integral for the Hunt–Crossley family, from a table of the dimensionless
ODE (solved once, stored below with the function that made it) for the others — and
calibration inverts it without integrating anything per call. No law is adhesive: every
force is clipped at F ≥ 0 and the contact ends when δ returns to zero (for the dashpot and
viscoelastic laws, and Thornton's, the force reaches zero first, at δ > 0; the ball then
moves freely, so its rebound speed is fixed at that instant).

Every normal law is a :class:`NormalLaw` in :data:`NORMAL_LAWS`: a vectorised force
function ``force(delta, delta_dot, param, K, m_eff, v0)`` [N], a calibration
``calibrate(e)`` returning the damping parameter that gives restitution ``e``, the COR a
parameter gives (``cor``), the paper's closed-form guess, and ``material_to_param``
mapping a speed-independent material constant (α [s/m], ζ [-], A [s], v_y [m/s]) to the parameter of
an impact at speed v0, so a campaign can hold the material fixed and let e vary with speed.

The package is split by concept; every name is re-exported here:

- :mod:`~pipeline.contact.elastic` — Hertz's law and the exact elastic impact;
- :mod:`~pipeline.contact.normal` — the damped normal force laws and each paper's
  closed-form damping;
- :mod:`~pipeline.contact.damping` — the restitution a damping parameter gives and the
  calibration of the damping to a requested e;
- :mod:`~pipeline.contact.plastic` — Thornton's elastic–perfectly-plastic law, its yield
  point, unloading curve and closed-form restitution;
- :mod:`~pipeline.contact.laws` — the registry :data:`NORMAL_LAWS`;
- :mod:`~pipeline.contact.tangential` — Mindlin's tangential spring, its history rules and
  the tangential dashpot.
"""

from __future__ import annotations

from . import damping, elastic, laws, normal, plastic, tangential
from .damping import *  # noqa: F403
from .elastic import *  # noqa: F403
from .laws import *  # noqa: F403
from .normal import *  # noqa: F403
from .plastic import *  # noqa: F403
from .tangential import *  # noqa: F403

__all__ = (
    elastic.__all__
    + normal.__all__
    + damping.__all__
    + plastic.__all__
    + laws.__all__
    + tangential.__all__
)

# private helpers other modules of the package use (pipeline.simulate, maintenance scripts)
from .damping import (  # noqa: E402, F401
    _dimensionless_normal_rhs,
    _print_cor_tables,
    _solve_normal_cor,
    _table_calibrate,
    _table_cor,
)
from .elastic import _f  # noqa: E402, F401
from .laws import _RAW_FORCES, _law  # noqa: E402, F401
from .normal import _hertz_dashpot_raw, _kuwabara_kono_raw, _viscoelastic_raw  # noqa: E402, F401
