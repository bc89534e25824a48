"""Tests of pipeline.Scene: validation, and derived properties against the hand formulas of
docs/theory.md, Sign conventions and §4 (effective two-body properties)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline import Scene
from pipeline.errors import InputError

STEEL = dict(E=210e9, nu=0.3, density=7800.0)


def base(**kw):
    d = dict(radius=0.0127, speed=1.0, **STEEL)
    d.update(kw)
    return Scene(**d)


# --------------------------------------------------------------------------- validation
BAD_FIELDS = [
    ("radius", 0.0),
    ("radius", -0.01),
    ("radius", math.inf),
    ("speed", -1.0),
    ("speed", math.inf),
    ("E", 0.0),
    ("E", -1e9),
    ("nu", -0.1),
    ("nu", 0.5),
    ("target_E", 0.0),
    ("target_nu", 0.5),
    ("target_nu", -0.01),
    ("target_radius", 0.0),
    ("target_radius", -1.0),
    ("target_mass", 0.0),
    ("angle_deg", -1.0),
    ("angle_deg", 90.0),
    ("mu", -0.1),
    ("mu", math.inf),
    ("e", -0.01),
    ("e", 1.01),
    ("kappa", 0.0),
    ("kappa", math.inf),
    ("spin", math.inf),
    ("surface_speed", -math.inf),
    ("density", 0.0),
    ("density", math.inf),
]


@pytest.mark.parametrize(("field", "value"), BAD_FIELDS)
def test_out_of_range_field_raises(field, value):
    kw = dict(radius=0.0127, speed=1.0, E=210e9, nu=0.3, density=7800.0)
    kw[field] = value
    with pytest.raises(InputError, match=f"Scene.{field}"):
        Scene(**kw)


@pytest.mark.parametrize("field", ["radius", "speed", "E", "mu", "angle_deg", "e"])
def test_nan_and_non_numbers_raise(field):
    with pytest.raises(InputError, match="NaN"):
        base(**{field: math.nan})
    with pytest.raises(InputError, match="number"):
        base(**{field: "fast"})


def test_edges_are_accepted():
    s = base(speed=0.0, nu=0.0, angle_deg=0.0, e=0.0, mu=0.0)
    assert s.e == 0.0
    assert base(e=1.0, angle_deg=89.9, nu=0.499).e == 1.0


def test_mass_or_density_required_and_consistent():
    with pytest.raises(InputError, match="density .* or its mass"):
        Scene(radius=0.01, speed=1.0)
    m = 7800.0 * 4.0 / 3.0 * math.pi * 0.01**3
    s = Scene(radius=0.01, speed=1.0, density=7800.0, mass=m)
    assert s.m == m
    with pytest.raises(InputError, match="disagrees with density"):
        Scene(radius=0.01, speed=1.0, density=7800.0, mass=1.05 * m)
    with pytest.raises(InputError, match="Scene.mass"):
        Scene(radius=0.01, speed=1.0, mass=-1.0)


def test_elastic_constants_needed_for_moduli():
    s = Scene(radius=0.01, speed=1.0, mass=0.03)
    with pytest.raises(InputError, match="elastic constants"):
        _ = s.E_eff
    with pytest.raises(InputError, match="elastic constants"):
        _ = s.G_eff


def test_validation_is_elementwise_for_arrays():
    with pytest.raises(InputError, match="Scene.nu"):
        base(nu=[0.2, 0.3, 0.6])
    with pytest.raises(InputError, match="Scene.angle_deg"):
        base(angle_deg=np.array([0.0, 95.0]))


# ------------------------------------------------------------------ derived properties
def test_mass_from_density():
    s = base()
    assert s.m == pytest.approx(7800.0 * 4.0 / 3.0 * math.pi * 0.0127**3, rel=1e-14)
    # rigid, fixed, flat target: m* = m, R* = R
    assert s.m_eff == pytest.approx(s.m, rel=1e-15)
    assert s.R_eff == pytest.approx(0.0127, rel=1e-15)


def test_effective_properties_two_spheres():
    """docs/theory.md, Compliant contact: 1/m* = 1/m1 + 1/m2, 1/R* = 1/R1 + 1/R2, 1/E* = Σ(1−ν²)/E,
    1/G* = Σ(2−ν)/G with G = E/(2(1+ν))."""
    s = Scene(
        radius=0.01,
        speed=2.0,
        mass=0.03,
        E=70e9,
        nu=0.3,
        target_radius=0.02,
        target_mass=0.06,
        target_E=200e9,
        target_nu=0.25,
    )
    assert s.m_eff == pytest.approx(0.02, rel=1e-14)  # 1/(1/0.03 + 1/0.06)
    assert s.R_eff == pytest.approx(0.02 / 3, rel=1e-14)  # 1/(1/0.01 + 1/0.02)
    e_star = 1.0 / ((1 - 0.09) / 70e9 + (1 - 0.0625) / 200e9)
    assert s.E_eff == pytest.approx(e_star, rel=1e-14)
    g1, g2 = 70e9 / 2.6, 200e9 / 2.5
    assert s.G_eff == pytest.approx(1.0 / (1.7 / g1 + 1.75 / g2), rel=1e-14)


def test_rigid_target_moduli():
    s = base()
    assert s.E_eff == pytest.approx(210e9 / (1 - 0.09), rel=1e-14)
    g = 210e9 / 2.6
    assert s.G_eff == pytest.approx(g / 1.7, rel=1e-14)


def test_target_cap_radius():
    """Garland–Rogers: ball on a spherical target cap; R* uses both radii (Garland & Rogers
    2009)."""
    s = base(radius=0.0254, target_radius=0.05)
    assert s.R_eff == pytest.approx(0.0254 * 0.05 / (0.0254 + 0.05), rel=1e-14)
    assert s.m_eff == pytest.approx(s.m, rel=1e-15)  # a fixed cap


def test_like_spheres_equal_halves():
    """Two identical spheres: R* = R/2, m* = m/2, E* = E/(2(1−ν²))."""
    m = 2800 * 4 / 3 * math.pi * 0.01**3
    s = Scene(
        radius=0.01,
        speed=20.0,
        density=2800,
        E=48e9,
        nu=0.2,
        target_E=48e9,
        target_nu=0.2,
        target_radius=0.01,
        target_mass=m,
    )
    assert s.R_eff == pytest.approx(0.005, rel=1e-14)
    assert s.m_eff == pytest.approx(m / 2, rel=1e-14)
    assert s.E_eff == pytest.approx(48e9 / (2 * 0.96), rel=1e-14)


def test_velocity_components():
    """docs/theory.md, Sign conventions: v_n0 = v·cos α, v_t0 = v·sin α − u, slip0 = v_t0 − ω·R."""
    s = base(speed=2.0, angle_deg=30.0, surface_speed=0.25, spin=10.0)
    assert s.v_n0 == pytest.approx(2.0 * math.sqrt(3) / 2, rel=1e-14)
    assert s.v_t0 == pytest.approx(1.0 - 0.25, rel=1e-14)
    assert s.slip0 == pytest.approx(0.75 - 10.0 * 0.0127, rel=1e-14)
    normal = base(speed=3.0)
    assert normal.v_n0 == 3.0 and normal.v_t0 == 0.0


def test_arrays_of_scenes_broadcast():
    s = base(
        speed=np.array([1.0, 2.0, 3.0]),
        angle_deg=np.array([0.0, 30.0, 60.0]),
        target_radius=[np.inf, 0.05, 0.1],
    )
    np.testing.assert_allclose(s.v_n0, [1.0, 2.0 * math.cos(math.pi / 6), 1.5], rtol=1e-14)
    np.testing.assert_allclose(s.v_t0, [0.0, 1.0, 3.0 * math.sin(math.pi / 3)], rtol=1e-14)
    np.testing.assert_allclose(s.R_eff, 1 / (1 / 0.0127 + 1 / np.array([np.inf, 0.05, 0.1])))
    assert np.shape(s.E_eff) == () and np.shape(s.m_eff) == ()
    e_arr = base(E=np.array([70e9, 210e9]))
    np.testing.assert_allclose(e_arr.E_eff, np.array([70e9, 210e9]) / 0.91, rtol=1e-14)


def test_replace_and_dict_round_trip():
    s = base(speed=[1.0, 2.0], mu=0.3)
    d = s.to_dict()
    assert d["speed"] == [1.0, 2.0] and "mass" not in d
    s2 = Scene.from_dict(d)
    np.testing.assert_array_equal(s2.speed, s.speed)
    assert s2.mu == 0.3
    with pytest.raises(InputError, match=r"unknown scene field 'raduis' \(did you mean 'radius'"):
        Scene.from_dict({**d, "raduis": 1})
    with pytest.raises(InputError, match="does not give speed"):
        Scene.from_dict({"radius": 0.01, "density": 7850.0})
    assert math.isinf(Scene.from_dict({**d, "target_E": "inf"}).target_E)
    with pytest.raises(InputError, match="Scene.mu"):
        s.replace(mu=-1.0)
    assert s.replace(mu=0.1).mu == 0.1 and s.mu == 0.3
    assert "surface_speed" in Scene.field_names()


def test_scene_is_frozen():
    s = base()
    with pytest.raises(AttributeError):
        s.radius = 1.0


def test_both_rigid_has_no_compliance():
    s = base(E=math.inf)  # rigid ball, rigid (default) target
    with pytest.raises(InputError, match="both rigid"):
        _ = s.E_eff
    with pytest.raises(InputError, match="both rigid"):
        _ = s.G_eff
    # a rigid ball on a compliant target is fine: E* = E_target/(1−ν_target²)
    s2 = base(E=math.inf, target_E=70e9, target_nu=0.3)
    assert s2.E_eff == pytest.approx(70e9 / 0.91, rel=1e-14)


# ------------------------------------------------------ unknown μ, e; types
def test_unknown_mu_and_e_are_refused_by_the_models_that_need_them():
    """A scene may leave μ and e unknown (None); a model needing them says which."""
    from pipeline.rigid import sphere_on_plane
    from pipeline.simulate import impact, impact_outcomes

    s = Scene(radius=0.0127, density=7850.0, E=210e9, nu=0.29, speed=0.6, angle_deg=15.0)
    unknown = s.replace(mu=None, e=None)
    assert "mu" not in unknown.to_dict() and "e" not in unknown.to_dict()
    with pytest.raises(InputError, match=r"Routh's rigid model needs mu, e"):
        sphere_on_plane(unknown)
    with pytest.raises(InputError, match=r"needs mu"):
        impact(unknown.replace(e=0.9))
    with pytest.raises(InputError, match=r"needs e"):
        impact(unknown, tangential="none")
    with pytest.raises(InputError, match=r"needs mu"):
        impact_outcomes([unknown.replace(e=0.9)] * 2)
    # frictionless with a given damping parameter needs neither
    rec = impact(unknown, normal="hunt_crossley", tangential="none", param=0.2, samples=11)
    assert 0 < rec.attrs["e_n"] < 1


@pytest.mark.parametrize("value", [True, False, np.bool_(True), "0.01", None])
def test_a_radius_must_be_a_number(value):
    """JSON's true is not a radius (it used to read as 1 m)."""
    with pytest.raises(InputError, match="radius"):
        Scene(radius=value, density=7850.0, speed=0.6)


# ------------------------------------------------------------------------ scene files
@pytest.mark.parametrize(
    "content,fragment",
    [
        (b'{"radius": 0.0127, "speed": 1', "not valid JSON"),
        (b"[0.0127, 1.0]", "must hold a JSON object {...}, not a list"),
        ('{"radius": 0.0127, "Speed": 1}'.encode("latin-1") + b"\xe9", "not UTF-8"),
        (b'{"radius": 0.0127, "radius": 0.02, "speed": 1, "mass": 0.1}', "appears twice"),
        (b'{"radius": true, "speed": 1, "mass": 0.1}', "Scene.radius must be a number"),
        (b'{"radius": 0.0127, "sped": 1, "mass": 0.1}', "did you mean 'speed'"),
        (b'{"radius": 0.0127, "mass": 0.1}', "does not give speed"),
        (b'{"scene": [1, 2]}', "'scene' must be an object"),
        (b"[" * 50000, "nests too deeply"),
    ],
)
def test_scene_file_errors_name_the_file(tmp_path, content, fragment):
    p = tmp_path / "s.json"
    p.write_bytes(content)
    with pytest.raises(InputError, match=fragment) as info:
        Scene.from_file(p)
    assert str(p) in str(info.value)


def test_scene_file_flat_or_sidecar(tmp_path):
    flat = tmp_path / "flat.json"
    flat.write_text('{"radius": 0.0127, "speed": 1.0, "density": 7800, "target_E": "inf"}')
    side = tmp_path / "side.json"
    side.write_text(
        '{"synthetic": true, "scene": {"radius": 0.0127, "speed": 1.0, "density": 7800}}'
    )
    assert (
        Scene.from_file(flat)
        == Scene.from_file(side)
        == Scene(radius=0.0127, speed=1.0, density=7800.0, mu=None, e=None)
    )  # μ and e a file leaves out are unknown, not 0 and 1
    with pytest.raises(InputError, match="is a directory"):
        Scene.from_file(tmp_path)
    with pytest.raises(InputError, match="no such scene file"):
        Scene.from_file(tmp_path / "missing.json")
