"""advise: the cheapest model within a tolerance, on scenes whose answer is known.

- Chung & Ooi (2011), test 4 (Granular Matter 13:643, doi:10.1007/s10035-011-0277-0;
  Chung & Ooi 2011): a 2.5 mm aluminium-oxide sphere at 3.9 m/s on a rigid wall, μ = 0.092,
  e = 0.98 — "rigid theory above 32.5°, compliance dominates below". 32.5° is Routh's
  sliding boundary tan α = 3.5·μ·(1+e) (seed eq. 6, Ciornei et al. 2017,
  doi:10.1051/matecconf/201711207005).
- Maw, Barber & Fawcett (Wear 38:101, 1976, doi:10.1016/0043-1648(76)90201-7): χ ≈ 1.44
  for a solid steel sphere (docs/theory.md, Compliant contact), χ = (1−ν)/(2−ν)·(1 + R²/k²).
- Derived here: above the sliding boundary a compliant contact slides from its first
  instant (ψ1 ≥ 2χ(1+e) > 2/3: the Mindlin spring meets the Coulomb cap at once), so
  Ft = μ·Fn at every instant in every model — the rigid answer is exact, and Coulomb
  friction on the compliant normal law reproduces the full model's Pt(t) exactly; without
  friction every model gives Pt = 0.
"""

from __future__ import annotations

import json
import math

import pytest

import pipeline
from pipeline import Scene
from pipeline.advice import LADDER, Advice, advise, mbf_groups
from pipeline.errors import InputError

CHUNG_OOI_4 = dict(radius=2.5e-3, density=4000.0, E=380e9, nu=0.23, speed=3.9, mu=0.092, e=0.98)
STEEL = dict(
    radius=0.0127,
    density=7850.0,
    E=210e9,
    nu=0.3,
    target_E=210e9,
    target_nu=0.3,
    target_radius=0.0254,
    speed=0.6,
    mu=0.131,
    e=0.9,
)


def test_sliding_75_degrees_is_rigid_and_exact():
    a = advise(Scene(angle_deg=75.0, **CHUNG_OOI_4))
    assert isinstance(a, Advice)
    assert a.model == "rigid" and a.normal is None and a.regime == "sliding"
    assert a.reason.startswith("sliding throughout")
    assert "rigid Coulomb is exact" in a.reason
    # exact up to the integrations behind the check (module notes: ~1e-6)
    for q in ("e_t", "omega", "Pt(Pn)"):
        assert a.errors[q]["rigid"] < 1e-6, q


def test_sticking_15_degrees_needs_mindlin():
    a = advise(Scene(angle_deg=15.0, **STEEL))
    assert a.model == "mindlin" and a.normal == "hunt_crossley" and a.regime == "sticking"
    assert "Mindlin's tangential compliance is needed" in a.reason
    # the rigid model's e_t is 5/7 (sticking, seed §3); compliance moves it by percents
    assert a.errors["e_t"]["rigid"] > 1e-2
    # Coulomb friction on the compliant normal law changes nothing Routh did not say
    assert a.errors["e_t"]["coulomb"] == pytest.approx(a.errors["e_t"]["rigid"], abs=1e-6)
    # a tolerance above the rigid model's worst error accepts it (the ladder is monotone)
    worst = max(a.errors[q]["rigid"] for q in a.quantities)
    assert advise(Scene(angle_deg=15.0, **STEEL), tol=1.01 * worst).model == "rigid"


@pytest.mark.parametrize("angle, model", [(33.0, "rigid"), (32.0, "mindlin")])
def test_chung_ooi_test4_boundary_at_32_5_degrees(angle, model):
    boundary = math.degrees(math.atan(3.5 * 0.092 * 1.98))
    assert boundary == pytest.approx(32.5, abs=0.05)
    assert advise(Scene(angle_deg=angle, **CHUNG_OOI_4)).model == model


def test_just_above_the_sliding_boundary_rigid_is_exact():
    # derived (module notes): sliding from the first instant in every model
    mu, e = 0.3, 0.7
    angle = math.degrees(math.atan(1.01 * 3.5 * mu * (1 + e)))
    s = Scene(angle_deg=angle, **{**STEEL, "mu": mu, "e": e})
    a = advise(s, tol=1e-5)
    psi1, chi, _ = mbf_groups(s)
    assert psi1 == pytest.approx(1.01 * 2 * chi * (1 + e), rel=1e-9)
    assert a.model == "rigid" and max(a.errors[q]["rigid"] for q in a.quantities) < 1e-6


def test_time_resolved_pt_in_gross_sliding_needs_coulomb_not_mindlin():
    # derived: Ft = μ·Fn at every instant in both compliant models, so Pt(t) agrees; the
    # rigid model has no time
    a = advise(Scene(angle_deg=75.0, **CHUNG_OOI_4), quantities=("e_t", "Pt(t)"))
    assert a.model == "coulomb" and a.normal == "hunt_crossley"
    assert a.errors["Pt(t)"]["rigid"] == math.inf
    assert a.errors["Pt(t)"]["coulomb"] < 1e-6
    assert "Pt(t) needs time" in a.reason


def test_frictionless_scene_is_rigid_with_zero_errors():
    a = advise(Scene(angle_deg=40.0, **{**STEEL, "mu": 0.0}))
    assert a.model == "rigid" and a.psi1 == math.inf
    assert "no friction impulse" in a.reason
    assert all(a.errors[q][m] == 0.0 for q in a.quantities for m in ("rigid", "coulomb"))


def test_mbf_groups_of_a_steel_sphere():
    # like materials: η = 2G*/E* = (1−ν)/(2−ν); solid sphere R²/k² = 5/2
    psi1, chi, eta = mbf_groups(Scene(angle_deg=20.0, **STEEL))
    assert eta == pytest.approx(0.7 / 1.7, rel=1e-12)
    assert chi == pytest.approx(0.7 / 1.7 * 3.5, rel=1e-12)
    # MBF's value for steel (docs/theory.md, Compliant contact)
    assert chi == pytest.approx(1.44, abs=0.005)
    assert psi1 == pytest.approx(2 * eta * math.tan(math.radians(20.0)) / 0.131, rel=1e-12)
    # a rigid target gives the same η: E* = E/(1−ν²), G* = G/(2−ν)
    rigid_target = {**STEEL, "target_E": math.inf}
    assert mbf_groups(Scene(angle_deg=20.0, **rigid_target))[2] == pytest.approx(eta, rel=1e-12)


def test_summary_is_strict_json_and_the_package_name_calls_advise():
    a = pipeline.advise(Scene(angle_deg=75.0, **CHUNG_OOI_4), quantities=("e_t", "Pt(t)"))
    d = json.loads(json.dumps(a.summary(), allow_nan=False))
    assert d["model"] == "coulomb" and d["errors"]["Pt(t)"]["rigid"] == "inf"
    assert d["quantities"] == ["e_t", "Pt(t)"] and LADDER.index(d["model"]) == 1


def test_bad_requests_raise_input_error():
    s = Scene(angle_deg=30.0, **STEEL)
    with pytest.raises(
        InputError, match=r"which need the ball's elastic constants: give Scene\(E="
    ):
        advise(Scene(radius=0.01, density=7800.0, speed=1.0, angle_deg=30.0, mu=0.1, e=0.9))
    with pytest.raises(InputError, match="tol = 0 must be a positive number"):
        advise(s, tol=0)
    with pytest.raises(InputError, match=r"quantities \['vt'\]: choose from"):
        advise(s, quantities=["vt"])
    with pytest.raises(InputError, match="needs mu"):
        advise(s.replace(mu=None))


def test_heavy_damping_sticks_where_rigid_theory_slides():
    # derived (module notes): near first contact the spring over the cap is 1.5·ψ1/(1 + c);
    # Hunt–Crossley at e = 0.01 has a large c, so at 45° (rigid: sliding, ψ1 ≈ 6.3 ≥
    # 2χ(1+e)) the contact sticks first and rigid theory is off
    s = Scene(angle_deg=45.0, **{**STEEL, "e": 0.01})
    a = advise(s)
    assert a.regime == "sliding" and a.model == "mindlin"
    assert a.reason.startswith("rigid theory slides throughout")
    assert a.errors["e_t"]["rigid"] > 1e-2


# ------------------------------------------------------------------ yield
def test_yield_speed_of_steel_on_a_steel_flat_is_johnsons():
    """Johnson, Contact Mechanics (CUP 1985) §11.4, doi:10.1017/CBO9781139171731: a sphere
    striking a flat of its own material first yields at ρV_Y²/Y ≈ 26 (Y/E*)⁴ (the central
    pressure reaching 1.60 Y, §6.2; 26 is his rounding of (4/5π)(0.8π)⁵ = 25.5), about
    0.1 m/s for a medium-hard steel (Y = 1 GPa). At 0.6 m/s, 15° the impact is ~4× past it:
    the reason says so and the compliant models take Thornton's law."""
    flat = {**STEEL, "target_radius": math.inf, "e": 0.8}
    s = Scene(angle_deg=15.0, yield_strength=1e9, target_yield_strength=1e9, **flat)
    a = advise(s)
    E_eff = 210e9 / (2 * (1 - 0.3**2))
    assert 7850.0 * a.yield_speed**2 / 1e9 == pytest.approx(26 * (1e9 / E_eff) ** 4, rel=0.025)
    ratio = 0.6 * math.cos(math.radians(15.0)) / a.yield_speed
    assert 3.5 < ratio < 5.0
    assert a.normal == "thornton"
    assert "The impact yields" in a.reason and f"{ratio:.3g}× the speed of first yield" in a.reason
    assert json.loads(json.dumps(a.summary()))["yield_speed"] == pytest.approx(a.yield_speed)
    # a normal law the caller chose is kept, and the reason names the plastic one
    kept = advise(s, normal="hunt_crossley")
    assert kept.normal == "hunt_crossley" and "normal='thornton'" in kept.reason


def test_below_the_yield_speed_the_contact_stays_elastic():
    s = Scene(angle_deg=15.0, yield_strength=1e9, **{**STEEL, "speed": 0.05})
    a = advise(s)
    assert a.normal == "hunt_crossley" and a.yield_speed > 0.05
    assert "The contact stays elastic" in a.reason and "the target's not stated" in a.reason


def test_the_softer_body_yields_first_and_an_unstated_yield_says_nothing():
    soft_target = advise(
        Scene(angle_deg=15.0, yield_strength=2e9, target_yield_strength=0.4e9, **STEEL)
    )
    target_only = advise(Scene(angle_deg=15.0, target_yield_strength=0.4e9, **STEEL))
    assert soft_target.yield_speed == pytest.approx(target_only.yield_speed, rel=1e-12)
    assert "the target's Y = 400 MPa" in soft_target.reason
    # v_y ∝ Y^{5/2} at fixed E*, R*, m* (½m*v_y² ∝ δ_y^{5/2} ∝ p_0⁵)
    ball = advise(Scene(angle_deg=15.0, yield_strength=0.8e9, **STEEL)).yield_speed
    assert ball / target_only.yield_speed == pytest.approx(2.0**2.5, rel=1e-12)
    plain = advise(Scene(angle_deg=15.0, **STEEL))
    assert plain.yield_speed is None and "yield" not in plain.reason
    with pytest.raises(InputError, match="yield_strength"):
        Scene(yield_strength=-1.0, **STEEL)


def test_normal_incidence_with_friction_is_rigid():
    """At 0° there is no initial slip: Pt = 0 in every model (docs/theory.md), so the rigid
    model is exact whatever μ (it raised before: the simulator's rounding, ~1e-21 N of Ft,
    was refused as a force unit error)."""
    a = advise(Scene(angle_deg=0.0, **STEEL))
    assert a.model == "rigid" and a.normal is None
    assert abs(a.errors["omega"]["rigid"]) < 1e-12
    assert a.errors["Pt(Pn)"]["rigid"] < 1e-12
