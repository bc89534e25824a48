"""Plausibility before physics: a record against the scales its scene predicts.

The expected scales are closed forms of Hertz theory (Johnson, Contact Mechanics, CUP 1985,
§11.4, doi:10.1017/CBO9781139171731: t_c = 2.943·δ_max/v0, F_max = K·δ_max^{3/2}) and the
impulse bound m*·v_n0 ≤ Pn ≤ 2·m*·v_n0 (0 ≤ e ≤ 1). Records: the bundled synthetic
Garland–Rogers-style sample (simulator + sensor model, truth in its sidecar) with its
header's units changed — the values stay, only their label lies.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from pipeline import Scene
from pipeline.contact import hertz_impact
from pipeline.errors import (
    ContactTimeWarning,
    ImpulseWarning,
    PeakForceWarning,
    UnitMismatchError,
)
from pipeline.io import load
from pipeline.plausibility import check_plausible
from pipeline.report import scene_from_sidecar

SAMPLE = Path(__file__).resolve().parents[1] / "data_samples" / "gr_15deg_0.6ms.csv"
SCENE = scene_from_sidecar(SAMPLE)


def _relabel(tmp_path, name, header=None, time_factor=1.0, drop_rate=True):
    """The sample with its header changed and its time values scaled (text-exact)."""
    lines = SAMPLE.read_text(encoding="utf-8").splitlines()
    i = next(k for k, ln in enumerate(lines) if not ln.startswith("#"))
    head = [ln for ln in lines[:i] if not (drop_rate and ln.startswith("# sample rate"))]
    rows = lines[i + 1 :]
    if time_factor != 1.0:
        rows = [
            ",".join([repr(float(r.split(",")[0]) * time_factor), *r.split(",")[1:]]) for r in rows
        ]
    p = tmp_path / name
    p.write_text("\n".join([*head, header or lines[i], *rows]) + "\n", encoding="utf-8")
    return p


def test_the_sample_is_plausible():
    rec = load(SAMPLE)
    checks = check_plausible(rec, SCENE)
    hertz = hertz_impact(SCENE)
    assert checks.ok
    assert checks["contact_time"].expected == pytest.approx(hertz.t_c, rel=1e-12)
    assert checks["peak_force"].expected == pytest.approx(hertz.F_max, rel=1e-12)
    # Pn = (1 + e)·m*·v_n0 with the sidecar's e = 0.9, to the sensor's few per mille
    assert checks["impulse"].ratio == pytest.approx(1.9, rel=0.01)
    assert checks.summary()["impulse"]["status"] == "ok"


def test_times_in_microseconds_under_a_seconds_header(tmp_path):
    """e came out as 1.9e6 before: now the contact lasts 10⁶ × Hertz's t_c, and the error
    says the values are in µs."""
    p = _relabel(tmp_path, "us_as_s.csv", time_factor=1e6)
    with pytest.raises(UnitMismatchError, match="fit 'us', not 's'") as info:
        check_plausible(load(p), SCENE)
    assert info.value.quantity == "time" and info.value.suggested == "us"
    assert info.value.ratio == pytest.approx(1e6, rel=0.2)
    assert "us_as_s.csv" in str(info.value)


def test_forces_in_newtons_under_a_kilonewton_header(tmp_path):
    """e ≈ 1900 before: now the peak is 10³ × Hertz's and the error names N."""
    p = _relabel(tmp_path, "N_as_kN.csv", header="time [s],Fx [kN],Fy [kN],Fz [kN]")
    with pytest.raises(UnitMismatchError, match="fit 'N', not 'kN'") as info:
        check_plausible(load(p), SCENE)
    assert info.value.quantity == "force" and info.value.suggested == "N"


def test_a_scene_in_wrong_units_is_blamed_by_the_impulse():
    """Duration and peak barely move with the mass (t_c ∝ m^{2/5}), but a density given in
    g/cm³ read as kg/m³ makes m* 1000× too small and the impulse 1000× too large."""
    light = SCENE.replace(density=SCENE.density / 1000)
    with pytest.raises(UnitMismatchError) as info:
        check_plausible(load(SAMPLE), light.replace(E=None, nu=None))
    assert info.value.quantity == "impulse" and "scene's own units" in str(info.value)


def test_factors_that_are_no_unit_warn_with_their_number():
    rec = load(SAMPLE)
    slow = SCENE.replace(speed=SCENE.speed / 6)  # Hertz: F ∝ v^{6/5}, t_c ∝ v^{-1/5}
    with pytest.warns(PeakForceWarning, match=r"ratio \d") as peak:
        with pytest.warns(ImpulseWarning, match="momentum"):
            checks = check_plausible(rec, slow)
    assert checks["peak_force"].status == "warning" and not checks.ok
    assert checks["peak_force"].ratio == pytest.approx(6**1.2, rel=0.05)
    assert checks["contact_time"].status == "ok"  # 6^0.2 = 1.43: inside 1/3…3
    assert "plausible 0.33 to 3" in str(peak[0].message)


def test_contact_time_warning():
    soft = SCENE.replace(E=SCENE.E / 1000, target_E=math.inf)  # t_c ∝ E*^{-2/5}: ~12×
    with pytest.warns(ContactTimeWarning):
        with pytest.warns(PeakForceWarning):
            check_plausible(load(SAMPLE), soft)


def test_hertz_checks_are_skipped_without_elastic_constants():
    checks = check_plausible(load(SAMPLE), SCENE.replace(E=None, nu=None))
    assert checks["contact_time"].status == "skipped"
    assert "no E and nu" in checks["contact_time"].note
    assert checks["impulse"].status == "ok"
    assert checks.summary()["peak_force"]["measured"] is None  # NaN in strict JSON


def test_zero_speed_scene_skips_everything_but_says_so():
    checks = check_plausible(load(SAMPLE), Scene(radius=0.0127, density=7850.0, speed=0.0))
    assert [c.status for c in checks.checks] == ["skipped", "skipped", "skipped"]
    assert np.isnan(checks["impulse"].ratio)


# ----------------------------------------------------------------------- after the physics
def _analyse(rec, scene):
    """``analyse`` without the quartic's PoorFitWarning (it cannot follow a Hertz pulse)."""
    import warnings

    from pipeline import analyse
    from pipeline.errors import PoorFitWarning

    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", category=PoorFitWarning)
        return analyse(rec, scene, n_boot=0)


def _coulomb_sliding():
    """A noise-free Coulomb impact that slides throughout: 60° > atan(3.5·μ·(1+e))."""
    from pipeline.simulate import impact

    scene = SCENE.replace(angle_deg=60.0, mu=0.1, e=0.9)
    return scene, impact(scene, tangential="coulomb")


def test_the_energy_ratio_is_routh_s_for_a_sliding_impact():
    """Routh, sliding throughout (docs/theory.md §3): v_n = e·v_n0, v_t = v_t0 −
    μ(1+e)·v_n0, ω = μ(1+e)·m·v_n0·R/I; the measured kinetic-energy ratio is that closed
    form, to the simulator's agreement with the broken line (~1e-3)."""
    scene, rec = _coulomb_sliding()
    a = _analyse(rec, scene)
    m, R, k = float(scene.m), scene.radius, scene.kappa
    vn0, vt0, mu, e = float(scene.v_n0), float(scene.v_t0), scene.mu, scene.e
    vt = vt0 - mu * (1 + e) * vn0
    w = mu * (1 + e) * m * vn0 * R / (k * m * R * R)
    ratio = (m * (e * vn0) ** 2 + m * vt**2 + k * m * R * R * w**2) / (m * (vn0**2 + vt0**2))
    energy = a.plausibility["energy"]
    assert energy.status == "ok" and energy.measured == pytest.approx(ratio, rel=2e-3)
    cone = a.plausibility["friction_cone"]  # Pt = μ·Pn while it slides
    assert cone.status == "ok" and cone.measured == pytest.approx(1.0, abs=5e-3)


def test_a_mu_below_the_record_s_breaks_the_friction_cone():
    """The same noise-free record against a scene whose μ is 20 % below the simulated one:
    Pt reaches 1.25·μ·Pn, beyond the 5 % floor (no cross-talk in a simulated record)."""
    from pipeline.errors import FrictionBoundWarning

    scene, rec = _coulomb_sliding()
    with pytest.warns(FrictionBoundWarning, match=r"reaches 1\.2\d·μ·Pn"):
        a = _analyse(rec, scene.replace(mu=0.08))
    assert a.plausibility["friction_cone"].status == "warning"
    assert a.plausibility["e_t_bound"].status == "ok"


def test_a_spinning_ball_may_leave_faster_along_the_surface():
    """e_t > 1 is no mistake for a ball spun against its slip before impact: the bound is
    skipped and says why."""
    scene, rec = _coulomb_sliding()
    a = _analyse(rec, scene.replace(spin=-50.0))
    assert a.plausibility["e_t_bound"].status == "skipped"
    assert "spins" in a.plausibility["e_t_bound"].note
