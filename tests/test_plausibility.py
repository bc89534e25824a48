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
