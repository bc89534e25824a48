"""Tests of pipeline.contact: Hertz closed forms and calibrated damped normal laws.

Ground truth comes from published numbers (PHYSICS.md §4, §6, with the papers cited at each
test) or from an independent, tightly toleranced ODE integration written here (solve_ivp of
the dimensionless equation of motion, not the library's helpers).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pipeline import contact
from pipeline.errors import InputError

E_SET = [0.1, 0.3, 0.5, 0.7, 0.9, 0.98]


# --------------------------------------------------------------------------- helpers
def _integrate_cor(accel, tmax=60.0):
    """COR of the dimensionless impact x'' = accel(x, x'), x(0) = 0, x'(0) = 1.

    Units: length δ* = (m*·v0²/K)^{2/5}, time δ*/v0, so a Hertz law reads x'' = −x^{3/2}.
    The accelerations given here are the unclipped laws; the contact ends where the
    (compressive) force first returns to zero during restitution or at x = 0, whichever
    comes first (no adhesion). Tolerances: 1e-12 relative, 1e-13 of δ* absolute.
    """

    def rhs(t, y):
        return [y[1], accel(max(y[0], 0.0), y[1])]

    def separated(t, y):
        return y[0]

    separated.terminal, separated.direction = True, -1

    def force_zero(t, y):  # the compressive force −x'' reaches zero while restituting
        return -accel(max(y[0], 0.0), y[1]) if y[1] < 0 else 1.0

    force_zero.terminal, force_zero.direction = True, -1
    sol = solve_ivp(
        rhs,
        (0.0, tmax),
        [0.0, 1.0],
        method="DOP853",
        rtol=1e-12,
        atol=1e-13,
        events=[separated, force_zero],
        first_step=1e-6,
    )
    assert sol.status == 1, "the contact did not end inside the integration window"
    return -sol.y[1, -1]


# ------------------------------------------------------------------ Hunt–Crossley family
# PHYSICS.md §4 table: the COR each paper's closed-form c(e) actually gives (3 decimals).
# Hunt & Crossley, J. Appl. Mech. 42:440 (1975), doi:10.1115/1.3423596;
# Lankarani & Nikravesh, J. Mech. Des. 112:369 (1990), doi:10.1115/1.2912617;
# Flores et al., Nonlinear Dyn. 65:161 (2011), doi:10.1007/s11071-010-9911-5.
CLOSED_FORM_TABLE = {
    "hunt_crossley": (contact.c_hunt_crossley, [0.581, 0.663, 0.768, 0.909, 0.952]),
    "lankarani_nikravesh": (contact.c_lankarani_nikravesh, [0.684, 0.725, 0.796, 0.913, 0.954]),
    "flores": (contact.c_flores, [0.256, 0.470, 0.683, 0.894, 0.947]),
}
TABLE_TARGETS = [0.3, 0.5, 0.7, 0.9, 0.95]


@pytest.mark.parametrize("name", sorted(CLOSED_FORM_TABLE))
def test_closed_form_cor_table(name):
    """PHYSICS.md §4: the COR each paper's c(e) gives, to the printed 3 decimals."""
    closed, expected = CLOSED_FORM_TABLE[name]
    got = contact.cor_hunt_crossley_family(closed(np.array(TABLE_TARGETS)))
    np.testing.assert_allclose(got, expected, atol=5e-4 + 1e-9, rtol=0)
    assert contact.NORMAL_LAWS[name].closed_form is closed


def test_hc_exact_relation_holds():
    """c(1+e) = ln[(1+c)/(1−c·e)] (PHYSICS.md §4) at the calibrated pairs."""
    e = np.array([0.2, 0.35, 0.5, 0.8, 0.95])  # (small e: 1 − c·e → 0 makes the log ill-posed)
    c = contact.calibrate_hunt_crossley_family(e)
    np.testing.assert_allclose(c * (1 + e), np.log((1 + c) / (1 - c * e)), rtol=1e-13)


def test_hc_round_trip_whole_range():
    e = np.concatenate([np.linspace(1e-3, 1.0, 1001), 1 - np.geomspace(1e-14, 1e-2, 60)])
    c = contact.calibrate_hunt_crossley_family(e)
    assert np.all(np.diff(c[:1001]) < 0), "c(e) must fall monotonically"
    np.testing.assert_allclose(contact.cor_hunt_crossley_family(c), e, atol=1e-12, rtol=0)


def test_hc_near_elastic_limit_series():
    """As c → 0 the exact relation gives e = 1 − 2c/3 + 4c²/9 + O(c³) (expand the energy
    integral in c); the old root-finders lost this to cancellation."""
    c = np.array([1e-12, 1e-9, 1e-6, 1e-5])
    e = contact.cor_hunt_crossley_family(c)
    np.testing.assert_allclose(e, 1 - 2 * c / 3 + 4 * c**2 / 9, atol=1e-15, rtol=0)
    np.testing.assert_allclose(
        contact.calibrate_hunt_crossley_family(1 - 2 * c / 3 + 4 * c**2 / 9), c, rtol=1e-3
    )


def test_hc_heavy_damping_limit():
    """For c → ∞ the relation forces 1 − c·e → 0, i.e. e → 1/c."""
    c = np.array([50.0, 1e3, 1e6])
    np.testing.assert_allclose(contact.cor_hunt_crossley_family(c), 1 / c, rtol=1e-12)
    assert contact.cor_hunt_crossley_family(0.0) == 1.0
    assert contact.calibrate_hunt_crossley_family(1.0) == 0.0


@pytest.mark.parametrize("e", E_SET)
def test_hc_calibration_against_ode(e):
    """Integrate x'' = −x^{3/2}(1 + c·x') with the calibrated c: the rebound speed is e."""
    c = contact.calibrate_hunt_crossley_family(e)
    got = _integrate_cor(lambda x, v: -(x**1.5) * (1 + c * v))
    assert abs(got - e) < 1e-4


@pytest.mark.parametrize("bad", [0.0, -0.2, 1.01, np.nan])
def test_hc_unreachable_e_raises(bad):
    with pytest.raises(InputError, match=r"\(0, 1\]"):
        contact.calibrate_hunt_crossley_family(bad)


def test_hc_vectorised_shapes():
    e = np.array([[0.2, 0.6], [0.9, 1.0]])
    c = contact.calibrate_hunt_crossley_family(e)
    assert c.shape == e.shape
    assert isinstance(contact.calibrate_hunt_crossley_family(0.5), float)
    np.testing.assert_allclose(contact.cor_hunt_crossley_family(c), e, atol=1e-12)
