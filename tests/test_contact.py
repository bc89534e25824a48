"""Tests of pipeline.contact: Hertz closed forms and calibrated damped normal laws.

Ground truth comes from published numbers (docs/theory.md, Compliant contact; Chung & Ooi 2011,
with the papers cited at each
test) or from an independent, tightly toleranced ODE integration written here (solve_ivp of
the dimensionless equation of motion, not the library's helpers).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate, special
from scipy.integrate import solve_ivp

from pipeline import Scene, contact
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
        first_step=1e-10,
    )
    assert sol.status == 1, "the contact did not end inside the integration window"
    return -sol.y[1, -1]


# ------------------------------------------------------------------ Hunt–Crossley family
# docs/theory.md, Compliant contact table: the COR each paper's closed-form c(e) actually gives (3
# decimals).
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
    """docs/theory.md, Compliant contact: the COR each paper's c(e) gives, to the printed 3
    decimals."""
    closed, expected = CLOSED_FORM_TABLE[name]
    got = contact.cor_hunt_crossley_family(closed(np.array(TABLE_TARGETS)))
    np.testing.assert_allclose(got, expected, atol=5e-4 + 1e-9, rtol=0)
    assert contact.NORMAL_LAWS[name].closed_form is closed


def test_hc_exact_relation_holds():
    """c(1+e) = ln[(1+c)/(1−c·e)] (docs/theory.md, Compliant contact) at the calibrated pairs."""
    e = np.array([0.2, 0.35, 0.5, 0.8, 0.95])  # (small e: 1 − c·e → 0 makes the log ill-posed)
    c = contact.calibrate_hunt_crossley_family(e)
    np.testing.assert_allclose(c * (1 + e), np.log((1 + c) / (1 - c * e)), rtol=1e-13)


def test_hc_round_trip_whole_range():
    e = np.concatenate([np.linspace(1e-3, 1.0, 1001), 1 - np.geomspace(1e-14, 1e-2, 60)])
    c = contact.calibrate_hunt_crossley_family(e)
    assert np.all(np.diff(c[:1001]) < 0), "c(e) must fall monotonically"
    np.testing.assert_allclose(contact.cor_hunt_crossley_family(c), e, atol=1e-12, rtol=0)


def test_hc_newton_stops_at_two_adjacent_doubles(monkeypatch):
    """e(c) over the range of the calibration's table (c from 1e-4 to 1e3): every element's
    Newton iteration ends within a dozen steps, also where e lies in [0.5, 0.555) and the
    relative tolerance 2e-16 is below half an ulp (the bracket ends as two adjacent doubles,
    f of either sign by rounding) — before, those ran the 200 steps of the cap, each a pass
    over the array, and a first fit waited ~10 ms on them; the relation c(1+e) =
    ln[(1+c)/(1−c·e)] (docs/theory.md) holds at the result."""
    from pipeline.contact import damping

    calls = []
    phi = damping._phi_reduced
    monkeypatch.setattr(damping, "_phi_reduced", lambda x: calls.append(1) or phi(x))
    c = np.geomspace(1e-4, 1e3, 400)
    e = damping._hc_cor(c)
    assert np.any((e >= 0.5) & (e < 0.555))
    assert len(calls) <= 12
    ok = c * e < 1 - 1e-3  # where 1 − c·e keeps the digits of the log
    np.testing.assert_allclose(
        c[ok] * (1 + e[ok]), np.log((1 + c[ok]) / (1 - c[ok] * e[ok])), rtol=1e-12
    )


def test_hc_near_elastic_limit_series():
    """As c → 0 the exact relation gives e = 1 − 2c/3 + 4c²/9 + O(c³) (expand the energy
    integral in c); the old root-finders lost this to cancellation."""
    c = np.array([1e-12, 1e-9, 1e-6, 1e-5])
    e = contact.cor_hunt_crossley_family(c)
    # the truncated series is off by O(c³) < 1e-15 at c = 1e-5; e ≈ 1 is resolved to
    # 1.1e-16, so 4e-15 leaves room for the rounding of either side
    np.testing.assert_allclose(e, 1 - 2 * c / 3 + 4 * c**2 / 9, atol=4e-15, rtol=0)
    np.testing.assert_allclose(
        contact.calibrate_hunt_crossley_family(1 - 2 * c / 3 + 4 * c**2 / 9), c, rtol=1e-3
    )


def test_hc_heavy_damping_limit():
    """For c → ∞ the relation forces 1 − c·e → 0, i.e. e → 1/c."""
    c = np.array([50.0, 1e3, 1e6])
    np.testing.assert_allclose(contact.cor_hunt_crossley_family(c), 1 / c, rtol=1e-12)
    assert contact.cor_hunt_crossley_family(0.0) == 1.0
    assert contact.calibrate_hunt_crossley_family(1.0) == 0.0


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


# --------------------------------------------------------------------------- Hertz
# Chung & Ooi, Granular Matter 13:643 (2011), doi:10.1007/s10035-011-0277-0, tests 1 and 2
# (Chung & Ooi 2011): expected F_max [N], t_c [s], δ_max [m].
def _glass_pair(E, nu, rho):
    m = rho * 4.0 / 3.0 * math.pi * 0.01**3
    return Scene(
        radius=0.01,
        density=rho,
        E=E,
        nu=nu,
        target_E=E,
        target_nu=nu,
        target_radius=0.01,
        target_mass=m,
        speed=20.0,
    )  # ±10 m/s: 20 m/s relative


CHUNG_OOI = [
    ("test1 glass", _glass_pair(48e9, 0.20, 2800), 10.70e3, 40.3e-6, 274e-6),
    ("test1 limestone", _glass_pair(20e9, 0.25, 2500), 7.11e3, 54.2e-6, 368e-6),
    (
        "test2 Al alloy",
        Scene(radius=0.1, density=2699, E=70e9, nu=0.30, speed=0.2),
        11.37e3,
        732e-6,
        49.7e-6,
    ),
    (
        "test2 Mg alloy",
        Scene(radius=0.1, density=1800, E=40e9, nu=0.35, speed=0.2),
        7.23e3,
        767e-6,
        52.1e-6,
    ),
]


@pytest.mark.parametrize(
    ("label", "scene", "F_max", "t_c", "delta_max"), CHUNG_OOI, ids=[c[0] for c in CHUNG_OOI]
)
def test_hertz_impact_chung_ooi(label, scene, F_max, t_c, delta_max):
    h = contact.hertz_impact(scene)
    assert h.F_max == pytest.approx(F_max, rel=2e-3)
    assert h.t_c == pytest.approx(t_c, rel=2e-3)
    assert h.delta_max == pytest.approx(delta_max, rel=2e-3)


def test_hertz_tc_constant():
    """t_c·v0/δ_max = 2∫₀¹ du/√(1−u^{5/2}) (energy integral) = 0.8·B(2/5, 1/2) = 2.943275…"""
    quad, _ = integrate.quad(
        lambda u: 2.0 / math.sqrt(1.0 - u**2.5), 0.0, 1.0, epsabs=1e-13, epsrel=1e-13, limit=200
    )
    beta = math.gamma(0.4) * math.gamma(0.5) / math.gamma(0.9)
    assert contact.HERTZ_TC_CONSTANT == pytest.approx(quad, rel=1e-9)
    assert contact.HERTZ_TC_CONSTANT == pytest.approx(0.8 * beta, rel=1e-14)
    assert abs(contact.HERTZ_TC_CONSTANT - 2.943275) < 1e-6


def test_hertz_fmax_tc_product():
    """docs/theory.md, Compliant contact: F_max·t_c = 3.679·m*·v0, for any scene."""
    for _, scene, *_ in CHUNG_OOI:
        h = contact.hertz_impact(scene)
        assert h.F_max * h.t_c / (h.m_eff * h.v0) == pytest.approx(3.679, abs=5e-4)


# Garland & Rogers 2009 magnitudes (steel E = 210 GPa, ν = 0.3, on steel), to their printed digits.
@pytest.mark.parametrize(
    ("R", "m", "v0", "F", "tc", "dmax", "dF"),
    [
        (0.0127, 0.067, 0.2, 0.41e3, 121e-6, 8e-6, 5.0),
        (0.0127, 0.067, 0.5, 1.23e3, 101e-6, 17e-6, 5.0),
        (0.0127, 0.067, 1.0, 2.8e3, 88e-6, 30e-6, 50.0),
        (0.0254, 0.539, 0.2, 1.6e3, 242e-6, 17e-6, 50.0),
        (0.0254, 0.539, 0.5, 4.9e3, 202e-6, 34e-6, 50.0),
        (0.0254, 0.539, 1.0, 11.3e3, 176e-6, 60e-6, 50.0),
    ],
)
def test_hertz_garland_rogers_magnitudes(R, m, v0, F, tc, dmax, dF):
    s = Scene(radius=R, mass=m, E=210e9, nu=0.3, target_E=210e9, target_nu=0.3, speed=v0)
    h = contact.hertz_impact(s)
    assert abs(h.F_max - F) <= dF
    assert abs(h.t_c - tc) <= 0.5e-6
    # δ_max is printed to 1 µm: 8 µm is 2.5 % off at 8.2 µm, and the 50.8 mm / 0.2 m/s cell
    # reads 17 µm where Hertz gives 16.46 µm (a rounding slip in Garland & Rogers 2009): 3.5 %.
    assert h.delta_max == pytest.approx(dmax, rel=0.035)


def _steel_ball(v0=0.5):
    return Scene(
        radius=0.0127, mass=0.067, E=210e9, nu=0.3, target_E=210e9, target_nu=0.3, speed=v0
    )


def test_hertz_pulse_against_ode():
    """The exact pulse against solve_ivp of m*·δ̈ = −K·δ^{3/2} (δ_max ≈ 17 µm; absolute
    tolerances 1e-11·δ_max ≈ 0.2 pm and 1e-11·v0)."""
    h = contact.hertz_impact(_steel_ball(0.5))
    m, K, v0, dm = h.m_eff, h.K, h.v0, h.delta_max
    t = np.linspace(0.0, h.t_c, 401)

    def rhs(_, y):
        return [y[1], -K * max(y[0], 0.0) ** 1.5 / m]

    sol = solve_ivp(
        rhs,
        (0.0, h.t_c),
        [0.0, v0],
        method="DOP853",
        t_eval=t,
        rtol=1e-12,
        atol=[1e-11 * dm, 1e-11 * v0],
    )
    delta, ddot = sol.y
    pulse = contact.hertz_pulse(t, h)
    np.testing.assert_allclose(pulse["delta"], delta, rtol=0, atol=1e-8 * dm)
    np.testing.assert_allclose(pulse["delta_dot"], ddot, rtol=0, atol=1e-8 * v0)
    np.testing.assert_allclose(
        pulse["F"], K * np.maximum(delta, 0) ** 1.5, rtol=0, atol=1e-8 * h.F_max
    )
    np.testing.assert_allclose(pulse["Pn"], m * (v0 - ddot), rtol=0, atol=1e-8 * m * v0)
    # the ODE ends where it started, with the speed reversed, at t_c (0.8·B(2/5,1/2)·δ_max/v0)
    assert abs(delta[-1]) < 1e-7 * dm and ddot[-1] == pytest.approx(-v0, rel=1e-8)


def test_hertz_pulse_percussions():
    """docs/theory.md, Compliant contact: peak at t_c/2, Pn(t_c/2) = m*·v0, Pn(t_c) = 2·m*·v0, zero
    outside."""
    h = contact.hertz_impact(_steel_ball(1.0))
    p = contact.hertz_pulse(np.array([-1e-6, 0.0, h.t_c / 2, h.t_c, 2 * h.t_c]), h)
    assert p["Pn"][2] == pytest.approx(h.m_eff * h.v0, rel=1e-12)
    assert p["Pn"][3] == pytest.approx(2 * h.m_eff * h.v0, rel=1e-12)
    assert p["Pn"][4] == pytest.approx(2 * h.m_eff * h.v0, rel=1e-12)
    assert p["F"][2] == pytest.approx(h.F_max, rel=1e-12)
    assert p["F"][0] == p["F"][4] == p["Pn"][0] == 0.0
    assert p["delta"][2] == pytest.approx(h.delta_max, rel=1e-12)
    t = np.linspace(0, h.t_c, 2001)
    assert t[np.argmax(contact.hertz_pulse(t, h)["F"])] == pytest.approx(
        h.t_c / 2, abs=h.t_c / 2000
    )


# ---------------------------------------------------------- every damped normal law
# Dimensionless laws (length δ* = (m*v0²/K)^{2/5}, time δ*/v0), written here from the
# papers' equations, independently of the library: x'' = accel(x, x'; p).
ODE_ACCEL = {
    "hunt_crossley": lambda p: lambda x, v: -(x**1.5) * (1 + p * v),
    "lankarani_nikravesh": lambda p: lambda x, v: -(x**1.5) * (1 + p * v),
    "flores": lambda p: lambda x, v: -(x**1.5) * (1 + p * v),
    # F = Kδ^{3/2} + 2ζ√(m*·k)·δ̇, k = 1.5·K√δ (tangent) or K√δ (secant)
    "hertz_dashpot": lambda p: lambda x, v: -(x**1.5) - 2 * p * math.sqrt(1.5) * x**0.25 * v,
    "hertz_dashpot_secant": lambda p: lambda x, v: -(x**1.5) - 2 * p * x**0.25 * v,
    # F = K(δ^{3/2} + (3/2)·A·√δ·δ̇), γ = A·v0^{1/5}(K/m*)^{2/5}
    "viscoelastic": lambda p: lambda x, v: -(x**1.5) - 1.5 * p * np.sqrt(x) * v,
}
DAMPED = sorted(ODE_ACCEL)


def test_registry_covers_all_damped_laws():
    # Thornton's plastic law is checked against its closed forms in tests/test_plastic.py
    assert set(contact.NORMAL_LAWS) == set(DAMPED) | {"hertz", "thornton"}
    for name, law in contact.NORMAL_LAWS.items():
        assert law.name == name
        assert callable(law.force) and callable(law.calibrate) and callable(law.cor)
        assert callable(law.material_to_param) and law.material
        assert law.e_range[1] == 1.0


@pytest.mark.parametrize("name", DAMPED)
@pytest.mark.parametrize("e", E_SET)
def test_calibration_against_independent_ode(name, e):
    """Chung–Ooi test 3 (Chung & Ooi 2011): a damped law must return the requested e; here
    for every registered law, to 1e-5 (the brief asks 1e-3)."""
    law = contact.NORMAL_LAWS[name]
    p = law.calibrate(e)
    assert abs(_integrate_cor(ODE_ACCEL[name](p)) - e) < 1e-5
    assert law.cor(p) == pytest.approx(e, abs=1e-12)


@pytest.mark.parametrize("name", [*DAMPED, "thornton"])
def test_registered_force_in_physical_units(name):
    """m*·δ̈ = −force(δ, δ̇, param, K, m*, v0) for a 25.4 mm steel ball at 0.5 m/s (δ ≈ 17 µm),
    ended by the δ = 0 event only (the clipped force makes that the same rebound)."""
    law = contact.NORMAL_LAWS[name]
    h = contact.hertz_impact(_steel_ball(0.5))
    K, m, v0 = h.K, h.m_eff, h.v0
    p = law.calibrate(0.5)

    def rhs(_, y):
        return [y[1], -float(law.force(y[0], y[1], p, K, m, v0)) / m]

    def separated(_, y):
        return y[0]

    separated.terminal, separated.direction = True, -1
    sol = solve_ivp(
        rhs,
        (0.0, 20 * h.t_c),
        [0.0, v0],
        method="DOP853",
        rtol=1e-12,
        atol=[1e-12 * h.delta_max, 1e-12 * v0],
        events=separated,
        first_step=1e-6 * h.t_c,
    )
    assert sol.status == 1
    assert -sol.y[1, -1] / v0 == pytest.approx(0.5, abs=1e-5)


@pytest.mark.parametrize("name", DAMPED)
def test_library_dimensionless_rhs_matches(name):
    """The simulator's shared helper gives the calibrated e too."""
    p = contact.NORMAL_LAWS[name].calibrate(0.7)
    rhs, events = contact.dimensionless_normal_rhs(name, p)
    sol = solve_ivp(
        rhs,
        (0, 100),
        [0.0, 1.0],
        method="DOP853",
        rtol=1e-12,
        atol=1e-13,
        events=events,
        first_step=1e-6,
    )
    assert -sol.y[1, -1] == pytest.approx(0.7, abs=1e-6)


@pytest.mark.parametrize("name", DAMPED)
@pytest.mark.parametrize("bad", [0.0, -0.5, 1.2, np.nan])
def test_unreachable_e_names_range(name, bad):
    with pytest.raises(InputError, match=r"\(0, 1\]"):
        contact.NORMAL_LAWS[name].calibrate(bad)


def test_hertz_refuses_damping():
    with pytest.raises(InputError, match="hunt_crossley"):
        contact.NORMAL_LAWS["hertz"].calibrate(0.9)
    assert contact.NORMAL_LAWS["hertz"].calibrate(1.0) == 0.0


@pytest.mark.parametrize("name", DAMPED)
def test_calibration_round_trip_and_monotone(name):
    law = contact.NORMAL_LAWS[name]
    e = np.concatenate(
        [[1e-9, 1e-6], np.linspace(0.001, 0.999, 999), 1 - np.geomspace(1e-12, 1e-4, 9)]
    )
    p = law.calibrate(e)
    assert p.shape == e.shape and np.all(np.diff(p[:1001]) < 0)
    np.testing.assert_allclose(law.cor(p), e, atol=1e-12, rtol=0)
    assert law.calibrate(1.0) == 0.0 and law.cor(0.0) == 1.0


def test_forces_clip_and_vanish_out_of_contact():
    K, m, v0 = 1e10, 0.07, 1.0
    d = np.array([-1e-6, 0.0, 1e-6, 1e-6])
    dd = np.array([1.0, 1.0, 0.0, -1e3])  # last: violent separation → unclipped F < 0
    for name in DAMPED:
        F = contact.NORMAL_LAWS[name].force(d, dd, 0.5, K, m, v0)
        assert F[0] == 0.0 and F[1] == 0.0 and F[3] == 0.0
        assert F[2] == pytest.approx(K * 1e-9, rel=1e-12)  # at rest: pure Hertz
    # tangent ζ and secant ζ·√1.5 are the same dashpot
    ft = contact.hertz_dashpot(2e-6, 0.3, 0.2, K, m, stiffness="tangent")
    fs = contact.hertz_dashpot(2e-6, 0.3, 0.2 * math.sqrt(1.5), K, m, stiffness="secant")
    assert ft == pytest.approx(fs, rel=1e-14)
    with pytest.raises(InputError, match="tangent"):
        contact.hertz_dashpot(1e-6, 0.1, 0.2, K, m, stiffness="chord")
    with pytest.raises(InputError, match="≥ 0"):
        contact.cor_hertz_dashpot(-0.1)


# ------------------------------------------- speed dependence and material constants
def _physical_cor(force, K, m, v0, tc):
    def rhs(_, y):
        return [y[1], -float(force(y[0], y[1])) / m]

    def separated(_, y):
        return y[0]

    separated.terminal, separated.direction = True, -1
    dm = (m * v0**2 / K) ** 0.4
    sol = solve_ivp(
        rhs,
        (0.0, 50 * tc),
        [0.0, v0],
        method="DOP853",
        rtol=1e-12,
        atol=[1e-12 * dm, 1e-12 * v0],
        events=separated,
        first_step=1e-6 * tc,
    )
    assert sol.status == 1
    return -sol.y[1, -1] / v0


def test_dashpot_cor_is_speed_independent():
    """Self-similarity: the same ζ gives the same e for any v0, K, m* (two very different
    impacts), equal to cor_hertz_dashpot(ζ)."""
    zeta = 0.15
    out = []
    for scene in (_steel_ball(0.05), CHUNG_OOI[0][1]):
        h = contact.hertz_impact(scene)
        law = contact.NORMAL_LAWS["hertz_dashpot"]
        p = law.material_to_param(zeta, h.K, h.m_eff, h.v0)
        out.append(
            _physical_cor(
                lambda d, dd, p=p, h=h, law=law: law.force(d, dd, p, h.K, h.m_eff, h.v0),
                h.K,
                h.m_eff,
                h.v0,
                h.t_c,
            )
        )
    assert out[0] == pytest.approx(out[1], abs=1e-7)
    assert out[0] == pytest.approx(contact.cor_hertz_dashpot(zeta), abs=1e-7)


def test_hunt_crossley_fixed_alpha_falls_with_speed():
    """F = Kδ^{3/2}(1 + α·δ̇) with α [s/m] fixed: e(v0) = e_HC(α·v0), falling with v0."""
    alpha = 0.4  # s/m
    law = contact.NORMAL_LAWS["hunt_crossley"]
    es = []
    for v0 in (0.2, 1.0, 3.0):
        h = contact.hertz_impact(_steel_ball(v0))
        e = _physical_cor(  # F ≥ 0: no adhesion
            lambda d, dd, h=h: max(h.K * max(d, 0) ** 1.5 * (1 + alpha * dd), 0.0),
            h.K,
            h.m_eff,
            v0,
            h.t_c,
        )
        assert e == pytest.approx(contact.cor_hunt_crossley_alpha(alpha, v0), abs=1e-7)
        assert law.material_to_param(alpha, h.K, h.m_eff, v0) == pytest.approx(alpha * v0)
        es.append(e)
    assert es[0] > es[1] > es[2]
    assert contact.alpha_hunt_crossley(es[1], 1.0) == pytest.approx(alpha, rel=1e-6)


def test_viscoelastic_fixed_material_time_falls_with_speed():
    """F = K(δ^{3/2} + 1.5·A·√δ·δ̇) with A [s] fixed: e depends on γ = A·v0^{1/5}(K/m*)^{2/5}
    (Brilliantov et al. 1996) and falls with speed."""
    A = 2e-7  # s
    law = contact.NORMAL_LAWS["viscoelastic"]
    es = []
    for v0 in (0.2, 1.0, 3.0):
        h = contact.hertz_impact(_steel_ball(v0))
        gamma = law.material_to_param(A, h.K, h.m_eff, v0)
        assert gamma == pytest.approx(A * v0**0.2 * (h.K / h.m_eff) ** 0.4, rel=1e-14)
        e = _physical_cor(
            lambda d, dd, h=h: max(
                h.K * (max(d, 0) ** 1.5 + 1.5 * A * math.sqrt(max(d, 0)) * dd), 0
            ),
            h.K,
            h.m_eff,
            v0,
            h.t_c,
        )
        assert e == pytest.approx(contact.cor_kuwabara_kono(gamma), abs=1e-7)
        es.append(e)
    assert es[0] > es[1] > es[2]


def test_viscoelastic_schwager_poschel_series():
    """Schwager & Pöschel, Phys. Rev. E 57:650 (1998), doi:10.1103/PhysRevE.57.650:
    e = 1 − C1·(A α^{2/5} v^{1/5}) + C2·(…)², C1 = 1.15344, C2 = 0.79826, which in our group
    is 1 − 1.5·C1·γ + 2.25·C2·γ². C1 is the first-order energy integral
    ∫ x^{1/2} x'² dτ over the elastic pulse = 0.8·(5/4)^{3/5}·B(3/5, 3/2)."""
    c1 = 0.8 * 1.25**0.6 * special.beta(0.6, 1.5)
    assert c1 == pytest.approx(1.15344, abs=1e-5)
    g = np.array([1e-4, 1e-3, 3e-3])
    series = 1 - 1.5 * 1.15344 * g + 2.25 * 0.79826 * g**2
    # tolerance: the printed C1 (±5e-6) and the O(γ³) remainder
    assert np.all(np.abs(contact.cor_kuwabara_kono(g) - series) <= 1.5 * 1e-5 * g + 20 * g**3)
    # the two-term closed form inverts that series where it has a root
    np.testing.assert_allclose(contact.gamma_schwager_poschel(series), g, rtol=1e-10)
    assert np.isnan(contact.gamma_schwager_poschel(0.3))


def test_dashpot_weak_damping_energy_integral():
    """First order in the dashpot, 1 − e = η·∫x^{1/4}x'²dτ = η·0.4π√(5/4) over the elastic
    pulse (η = 2ζ√1.5 in the tangent convention)."""
    zeta = np.array([1e-6, 1e-5])
    eta = 2 * zeta * math.sqrt(1.5)
    np.testing.assert_allclose(
        1 - contact.cor_hertz_dashpot(zeta), eta * 0.4 * math.pi * math.sqrt(1.25), rtol=1e-4
    )


def test_closed_forms_describe_one_dashpot():
    """The DEM closed form ζ(e) = √(5/6)(−ln e)/√(ln²e + π²) is stated in the tangent
    convention; expressed in the secant one it must give the same dashpot and COR."""
    e = np.array([0.3, 0.6, 0.9])
    zt = contact.zeta_hertz_dashpot_dem(e)
    ln = np.log(e)
    np.testing.assert_allclose(zt, math.sqrt(5 / 6) * -ln / np.sqrt(ln**2 + math.pi**2), rtol=1e-14)
    zs = contact.zeta_hertz_dashpot_dem(e, stiffness="secant")
    np.testing.assert_allclose(
        contact.cor_hertz_dashpot(zs, "secant"),
        contact.cor_hertz_dashpot(zt, "tangent"),
        atol=1e-12,
    )


def test_normal_cor_dispatch():
    assert contact.normal_cor("hunt_crossley", 0.0) == 1.0
    assert contact.normal_cor(
        "viscoelastic", contact.calibrate_kuwabara_kono(0.4)
    ) == pytest.approx(0.4)
    with pytest.raises(InputError, match="unknown normal law"):
        contact.normal_cor("nope", 0.1)


@pytest.mark.parametrize(
    ("name", "p"),
    [(n, p) for n in ("hertz_dashpot_secant", "viscoelastic") for p in (1e-6, 1e-4, 0.37, 3e3)],
)
def test_tabulated_cor_against_ode(name, p):
    """The stored tables, their spline and the weak-damping extrapolation (p = 1e-6 lies
    below the first node) against an independent integration, to 1e-8."""
    e = contact.NORMAL_LAWS[name].cor(p)
    assert abs(_integrate_cor(ODE_ACCEL[name](p)) - e) < 1e-8


@pytest.mark.parametrize("name", ["hertz_dashpot_secant", "viscoelastic"])
def test_tabulated_cor_heavy_damping_extrapolation(name):
    """Beyond the last node (p = 1e4) the table extrapolates; e is tiny there but still right
    to 1 % relative."""
    p = 3e4
    e = contact.NORMAL_LAWS[name].cor(p)
    assert _integrate_cor(ODE_ACCEL[name](p)) == pytest.approx(e, rel=1e-2)


# --------------------------------------------------------------------------- Mindlin
@pytest.mark.parametrize("nu", [0.0, 0.23, 0.3, 0.45])
def test_mindlin_to_hertz_tangent_stiffness_ratio_like_materials(nu):
    """docs/theory.md, Compliant contact (Mindlin 1949; Johnson 1985 §7.2): for like materials
    k_t/k_n = 2(1−ν)/(2−ν), k_t = 8·G*·a, k_n = dF/dδ = (3/2)·K·√δ = 2·E*·a."""
    E, R1, R2, delta = 210e9, 0.0127, 0.0254, 7e-6
    s = Scene(
        radius=R1, mass=0.067, E=E, nu=nu, target_E=E, target_nu=nu, target_radius=R2, speed=1.0
    )
    kt = contact.mindlin_stiffness(delta, s.G_eff, s.R_eff)
    K = contact.hertz_stiffness(s.E_eff, s.R_eff)
    kn = 1.5 * K * math.sqrt(delta)
    assert kt / kn == pytest.approx(2 * (1 - nu) / (2 - nu), rel=1e-12)
    a = contact.contact_radius(delta, s.R_eff)
    assert a == pytest.approx(math.sqrt(delta * R1 * R2 / (R1 + R2)), rel=1e-14)
    assert kn == pytest.approx(2 * s.E_eff * a, rel=1e-12)


@pytest.mark.parametrize("name", sorted(contact.NORMAL_LAWS))
def test_normal_damping_coefficient_is_the_rate_term_of_the_law(name):
    """NormalLaw.damping is η_n(δ) in F = F_el(δ) + η_n(δ)·δ̇ (before the no-adhesion clip),
    written here from each paper's law: Hunt–Crossley η = c·K·δ^{3/2}/v0, the Hertz dashpot
    η = 2ζ√(m*·k) with k = (3/2)K√δ (tangent) or K√δ (secant), the viscoelastic law
    η = (3/2)·K·A·√δ with A = γ·(m*/K)^{2/5}·v0^{−1/5}; zero for elastic Hertz. The
    tangential dashpot of LAMMPS's x_γ,t is x_γ,t times this coefficient."""
    K, m, v0 = 2.7e10, 2.6e-4, 3.9
    d = np.array([1e-8, 1e-6, 6e-6])
    law = contact.NORMAL_LAWS[name]
    p = 0.0 if name == "hertz" else float(law.calibrate(0.6))
    expected = {
        "hertz": 0.0 * d,
        "hunt_crossley": p * K * d**1.5 / v0,
        "lankarani_nikravesh": p * K * d**1.5 / v0,
        "flores": p * K * d**1.5 / v0,
        "hertz_dashpot": 2 * p * np.sqrt(m * 1.5 * K * np.sqrt(d)),
        "hertz_dashpot_secant": 2 * p * np.sqrt(m * K * np.sqrt(d)),
        "viscoelastic": 1.5 * K * p * (m / K) ** 0.4 * v0**-0.2 * np.sqrt(d),
        # Thornton 1997: no dashpot, the loss is plastic work (the force is rate-free)
        "thornton": 0.0 * d,
    }[name]
    eta = law.damping(d, p, K, m, v0)
    np.testing.assert_allclose(eta, expected, rtol=1e-14, atol=0.0)
    # and it is the δ̇-coefficient of the registered force where the force is positive
    dd = 0.05 * v0
    F1 = law.force(d, dd, p, K, m, v0)
    F0 = law.force(d, 0.0, p, K, m, v0)
    np.testing.assert_allclose((F1 - F0) / dd, expected, rtol=1e-9, atol=1e-12 * K * 1e-9)
