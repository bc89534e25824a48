"""The contact normal turning over a curved target (pipeline.simulate.curved) and the
geometric flag of advise and the contact fit.

A ball sliding over a convex cap moves on a circle about the cap's centre: with a central
normal force and no friction its angular momentum about that centre and its energy are
conserved (Goldstein, *Classical Mechanics*, §3.1), so an elastic frictionless impact leaves
with the centre's speed across the line of centres unchanged and the same speed overall; the
line of centres turns by v_t·t_c/(R + R_cap) to first order; the first contact's frame sees
e_n fall by about tan α·θ ∝ v_t². LAMMPS (``fix wall/gran/region`` on a sphere, the same
contact law) integrates the same motion independently.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from pipeline import Scene, advise
from pipeline.errors import GeometryWarning, InputError
from pipeline.simulate import impact
from pipeline.simulate.curved import geometry_error, turning_outcomes

#: Garland & Rogers' steel ball (12.7 mm radius) on a steel cap.
GR = dict(radius=0.0127, density=7850.0, E=210e9, nu=0.29)
R = GR["radius"]


def _grazing(cap=0.05, **kw):
    return Scene(
        **{**GR, "speed": 2.0, "angle_deg": 75.0, "mu": 0.1, "e": 0.9, **kw}, target_radius=cap
    )


def _oblique(v_n, v_t, cap=0.05, **kw):
    """A scene with the given normal and tangential speeds [m/s]."""
    return Scene(
        **GR,
        speed=math.hypot(v_n, v_t),
        angle_deg=math.degrees(math.atan2(v_t, v_n)),
        target_radius=cap,
        **kw,
    )


def test_held_frame_is_the_simulator():
    """With r held infinite the turning equations are impact()'s: same e_n, e_t, ω to the
    integrations' tolerance (both 1e-9 relative or better on O(1) quantities)."""
    sc = _grazing()
    fixed = turning_outcomes(sc, "hertz_dashpot_secant")["fixed"]
    ref = impact(sc, normal="hertz_dashpot_secant", samples=51).attrs
    assert fixed["e_n"] == pytest.approx(ref["e_n"], abs=1e-7)
    assert fixed["e_t"] == pytest.approx(ref["e_t"], abs=1e-7)
    assert fixed["omega"] == pytest.approx(ref["omega"], rel=1e-6)
    assert fixed["theta"] == pytest.approx(0.0, abs=1e-12)  # dθ/dt held at 0


@pytest.mark.parametrize("v_t", [2.0, 0.5])
def test_frictionless_elastic_slide_conserves_energy_and_angular_momentum(v_t):
    """μ = 0, Hertz (no damping): r·w is conserved about the cap's centre and r returns to
    R + R_cap, so e_t on the frame at separation is exactly 1; the speed is conserved, so
    (e_n·v_n0)² + (e_t·v_t0)² = v0² on the first frame; the turn is v_t·t_c/(R + R_cap) to
    first order in δ/r (≈ 3e-4 here)."""
    sc = _oblique(0.5, v_t, mu=0.0, e=1.0)
    out = turning_outcomes(sc, "hertz")["turning"]
    assert out["e_t_local"] == pytest.approx(1.0, abs=1e-8)
    assert out["e_n_local"] == pytest.approx(1.0, abs=1e-7)
    speed2 = (out["e_n"] * 0.5) ** 2 + (out["e_t"] * v_t) ** 2
    assert speed2 == pytest.approx(0.5**2 + v_t**2, rel=1e-8)
    assert out["theta"] == pytest.approx(v_t * out["t_contact"] / (R + 0.05), rel=2e-3)
    # the first frame: the centre's tangential speed turns into normal speed
    th = out["theta"]
    assert out["e_n"] == pytest.approx(math.cos(th) - v_t / 0.5 * math.sin(th), abs=1e-7)


def test_the_change_grows_as_the_tangential_speed_squared():
    """Δe_n ≈ (v_t/v_n)·θ with θ ∝ v_t: a quarter of v_t gives a sixteenth (within the
    O(θ²) and δ/r corrections, ≤ 1 % here)."""
    d = [
        geometry_error(_oblique(0.5, v_t, mu=0.0, e=1.0), normal="hertz")["e_n"]
        for v_t in (2.0, 0.5)
    ]
    assert d[0] / d[1] == pytest.approx(16.0, rel=0.01)
    # and as t_c/(R + R_cap): a cap four times as large turns less (its t_c is a little
    # longer: R* is larger)
    scenes = [_oblique(0.5, 2.0, cap=c, mu=0.0, e=1.0) for c in (0.05, 0.2)]
    big = geometry_error(scenes[1], normal="hertz")["e_n"]
    t_c = [turning_outcomes(s, "hertz")["fixed"]["t_contact"] for s in scenes]
    expected = (t_c[0] / (R + 0.05)) / (t_c[1] / (R + 0.2))
    assert d[0] / big == pytest.approx(expected, rel=0.01)


def test_flat_normal_or_movable_targets_turn_nothing():
    flat = geometry_error(_grazing(cap=math.inf))
    normal = geometry_error(_grazing(angle_deg=0.0))
    assert flat["e_n"] == flat["e_t"] == flat["theta"] == 0.0 and not flat["exceeds"]
    assert normal["e_n"] == 0.0 and not normal["exceeds"]
    with pytest.raises(InputError, match="fixed target"):
        turning_outcomes(_grazing(target_mass=1.0))


def _lammps_version():
    from pipeline.simulate.lammps import lammps_version

    return lammps_version()


@pytest.mark.skipif(_lammps_version() is None, reason="LAMMPS (lmp) is not installed")
def test_turning_normal_matches_lammps_on_a_cap():
    """LAMMPS 29 Sep 2021 (``fix wall/gran/region`` on a ``region sphere``, the secant
    Hertz dashpot and Mindlin, dt 1e-8 s) on 20 and 50 mm caps at 75°, 2 m/s: measured
    e_n 0.88304, 0.89161 against 0.88307, 0.89163 here (≤ 4e-5), while holding the frame
    (0.900) is 9e-3 to 1.7e-2 off."""
    from pipeline.simulate.lammps import run_lammps

    scenes = [_grazing(cap=c) for c in (0.02, 0.05)]
    lmp = run_lammps(scenes, dt=1e-8)
    for i, sc in enumerate(scenes):
        out = turning_outcomes(sc, "hertz_dashpot_secant")
        assert out["turning"]["e_n"] == pytest.approx(lmp.e_n[i], abs=1e-4)
        assert out["turning"]["e_t"] == pytest.approx(lmp.e_t[i], abs=1e-4)
        assert out["turning"]["omega"] == pytest.approx(lmp.omega[i], rel=1e-3)
        assert abs(out["fixed"]["e_n"] - lmp.e_n[i]) > 5e-3


def test_advise_names_the_turn_where_it_exceeds_the_tolerance():
    adv = advise(_grazing(), tol=1e-3)
    assert adv.geometry["exceeds"]
    assert adv.geometry["e_n"] > 5e-3
    assert "turning_outcomes" in adv.reason
    assert adv.summary()["geometry"]["e_n"] == pytest.approx(adv.geometry["e_n"])
    # a tenth of the tangential speed: the change falls a hundredfold, under the tolerance
    slow = advise(
        _oblique(2.0 * math.cos(math.radians(75)), 0.2 * math.sin(math.radians(75)), mu=0.1, e=0.9),
        tol=1e-3,
    )
    assert not slow.geometry["exceeds"] and "turning_outcomes" not in slow.reason
    assert advise(_grazing(cap=math.inf)).geometry is None


def test_fit_flags_the_turn_on_a_record_sliding_over_a_cap():
    """A record made with the line of centres turning (the misspecification suite's own
    integrator, a sensor with the first contact's axes): the fit names the geometry with a
    GeometryWarning, and says the forces fit (the residuals at the noise level: it is the
    parameters' reading the turn biases, not the model's match to the record); the same
    record told it lies on a flat target is not flagged so."""
    from benchmarks._misspec import CASES
    from pipeline.fit import fit_contact

    record, _, told = CASES["curved_grazing"].make(1)
    with pytest.warns(GeometryWarning, match="turns by"):
        fit = fit_contact(record, told["scene"], sensor=told["sensor"])
    assert "geometry" in fit.verdict["causes"] and not fit.verdict["ok"]
    g = fit.verdict["geometry"]
    assert g["exceeds"] and g["e_n"] > g["tol"]
    assert fit.misfit.ok  # the precondition: χ²_ν ≈ 1, no structure in the residuals
    words = fit.table().attrs["verdict"]
    assert "fits the record's forces to the noise level" in words, words
    assert "does not describe" not in words and "forces fit" in fit.report()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        flat = fit_contact(
            record, told["scene"].replace(target_radius=math.inf), sensor=told["sensor"]
        )
    assert "geometry" not in flat.verdict["causes"]
    assert not any(issubclass(w.category, GeometryWarning) for w in caught)
    assert np.isfinite(flat.values["E_eff"])
