"""pipeline.analyse on records with known truth, and make reproduce's core.

Ground truth: the simulator (pipeline.simulate.impact) with a calibrated Hunt–Crossley
normal law (exact e, docs/theory.md, Compliant contact) and Routh's rigid solution (docs/theory.md,
Rigid bodies; seed eqs.
6–7, doi:10.1051/matecconf/201711207005).
"""

import json
import math
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from _rig import GR_RIG as STEEL

from pipeline import InputError, Scene, analyse
from pipeline.errors import PoorFitWarning
from pipeline.report import findings, reproduce, sample_files
from pipeline.simulate import impact, to_sensor

SAMPLES = Path(__file__).resolve().parent.parent / "data_samples"


def _analyse(record, scene, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PoorFitWarning)
        return analyse(record, scene, **kw)


@pytest.fixture(scope="module")
def sliding_sensor():
    """A sliding-regime (tan α > 3.5·μ·(1+e)) Coulomb impact seen through the sensor model."""
    scene = Scene(speed=0.5, angle_deg=60.0, mu=0.2, e=0.8, **STEEL)
    rec = to_sensor(impact(scene, tangential="coulomb"), seed=5, crosstalk=0.0)
    return scene, _analyse(rec, scene, n_boot=50)


def test_restitution_and_friction_recovered_through_the_sensor(sliding_sensor):
    scene, a = sliding_sensor
    assert a.rigid.regime == "sliding"
    # Poisson's e of the record vs the simulated e = 0.8 (exact calibration); the
    # sensor's noise (2 N on a ~1 kN pulse) and baseline removal allow ~0.5 %
    assert a.split.e_poisson == pytest.approx(0.8, abs=0.004)
    assert a.split.e_newton == pytest.approx(0.8, abs=0.004)
    # sliding throughout: Ft = μ·Fn at every instant, so the record's μ is the scene's
    assert a.mu_record == pytest.approx(0.2, rel=0.02)
    # the rigid end point E1: Pt_f = μ(1+e)·m·v_n0 (docs/theory.md, Rigid bodies)
    assert float(a.rigid.Pt_f) == pytest.approx(
        0.2 * 1.8 * scene.m * 0.5 * math.cos(math.radians(60.0)), rel=1e-12
    )
    assert abs(a.score["area"]) < 0.02 and abs(a.score["end_Pt"]) < 0.02


def test_rigid_parameters_from_the_record(sliding_sensor):
    scene, _ = sliding_sensor
    rec = to_sensor(impact(scene, tangential="coulomb"), seed=5, crosstalk=0.0)
    wrong = scene.replace(mu=0.5, e=0.3)  # the user's rigid guesses are off
    a = _analyse(rec, wrong, mu="record", e="record", n_boot=0)
    assert a.rigid_scene.mu == pytest.approx(0.2, rel=0.02)
    assert a.rigid_scene.e == pytest.approx(0.8, abs=0.004)
    a_bad = _analyse(rec, wrong, n_boot=0)  # the scene's guesses: far from the record
    assert a_bad.score["max_distance"] > 10 * a.score["max_distance"]
    with pytest.raises(InputError, match="mu="):
        _analyse(rec, scene, mu="guess")


def test_summary_is_strict_json_and_dataset_round_trips(tmp_path, sliding_sensor):
    _, a = sliding_sensor
    # the API: .summary() is JSON-ready as it stands (strict JSON: no NaN, no Infinity)
    text = json.dumps(a.summary(), allow_nan=False)
    back = json.loads(text)
    assert back["rigid"]["regime"] == "sliding"
    assert back["scene"]["target_mass"] == "inf"  # a fixed target, readable by Scene
    assert Scene.from_dict({k: float(v) for k, v in back["scene"].items()}) == a.scene
    assert back["score"]["total"]["area"]["value"] == pytest.approx(a.score["area"])
    ds = a.to_dataset()
    path = tmp_path / "analysis.nc"
    ds.to_netcdf(path, engine="h5netcdf")
    with xr.open_dataset(path, engine="h5netcdf") as back_ds:
        xr.testing.assert_identical(back_ds.load(), ds)
    assert ds["Pn_simpson"].attrs["units"] == "N s"
    assert json.loads(ds.attrs["summary_json"])["split"]["method"] == "momentum"


def test_analyse_refuses_a_record_without_a_pulse():
    scene = Scene(speed=0.5, angle_deg=15.0, mu=0.2, e=0.8, **STEEL)
    rec = to_sensor(impact(scene, tangential="coulomb"), seed=1)
    rec = rec.assign(Fn=rec["Fn"] * 0 + np.random.default_rng(0).normal(0, 2, rec.sizes["time"]))
    with pytest.raises(InputError, match="no contact pulse"):
        _analyse(rec, scene)


def test_bundled_15deg_sample_shows_the_seeds_three_findings():
    """The synthetic 15° Garland–Rogers-style record (Mindlin tangential compliance)."""
    path = SAMPLES / "gr_15deg_0.6ms.csv"
    from pipeline.io import load
    from pipeline.report import scene_from_sidecar

    a = _analyse(load(path), scene_from_sidecar(path), n_boot=50)
    f = findings(a)
    assert f.close_in_compression and f.far_in_restitution and f.Pt_peaks_then_falls
    # the sidecar's truth: the record's restitution is the simulated e = 0.9
    truth = json.loads(path.with_suffix(".json").read_text())
    assert a.split.e_poisson == pytest.approx(truth["outcome"]["e_n"], abs=0.005)


def test_reproduce_writes_every_output(tmp_path):
    out = tmp_path / "reproduce"
    summary = reproduce(SAMPLES, out, n_boot=20)
    for name in (
        "fig4_percussion_plane.png",
        "fig6_disc_velocity.png",
        "fig8_forces.png",
        "fig9_percussion_plane.png",
        "summary.json",
        "report.md",
    ):
        assert (out / name).stat().st_size > 1000, name
    on_disk = json.loads((out / "summary.json").read_text())
    assert on_disk == summary
    assert len(on_disk["records"]) == len(sample_files(SAMPLES))
    assert all("error" not in r for r in on_disk["records"])
    assert all(
        on_disk["findings"][k]
        for k in ("close_in_compression", "far_in_restitution", "Pt_peaks_then_falls")
    )
    report = (out / "report.md").read_text()
    assert report.count("**holds**") == 3
    assert not list(out.glob(".*tmp"))  # atomic writes leave no temporaries


def test_reproduce_reports_a_broken_record_and_goes_on(tmp_path):
    samples = tmp_path / "samples"
    samples.mkdir()
    for name in ("gr_15deg_0.6ms.csv", "gr_15deg_0.6ms.json"):
        (samples / name).write_bytes((SAMPLES / name).read_bytes())
    (samples / "broken.csv").write_text("time [s],Fz [N]\n0.0,abc\n", encoding="utf-8")
    summary = reproduce(samples, tmp_path / "out", n_boot=0)
    bad = [r for r in summary["records"] if r["file"] == "broken.csv"]
    assert len(bad) == 1 and "broken.csv" in bad[0]["error"] and "line 2" in bad[0]["error"]
    assert (tmp_path / "out" / "report.md").exists()


def test_summary_json_keeps_infinite_scene_fields_readable(tmp_path):
    """A rigid (inf) target survives summary.json and reads back as the same Scene."""
    from pipeline._json import json_ready
    from pipeline.report import scene_from_sidecar

    scene = Scene(
        speed=0.5, angle_deg=15.0, mu=0.2, e=0.8, radius=0.0127, density=7850.0, E=210e9, nu=0.29
    )
    assert scene.target_E == math.inf
    side = tmp_path / "rec.json"
    side.write_text(json.dumps(json_ready({"scene": scene.to_dict()}), allow_nan=False))
    assert scene_from_sidecar(tmp_path / "rec.csv") == scene


def test_stages_are_reachable_from_the_package():
    import pipeline

    assert pipeline.io.load is not None and pipeline.rigid.sphere_on_plane is not None
    with pytest.raises(AttributeError):
        pipeline.no_such_stage  # noqa: B018


def test_bootstrap_refinds_maximum_compression_by_the_split_method():
    """Each replicate's Pn_c follows the record's split method (closed forms, triangle pulse).

    F rises linearly to Fp at tp, then falls linearly to 0 at T: Pn(tp) = Fp·tp/2 (peak of
    Fn), and the mean of Pn over [0, T] is Pn(T) − (1/T)∫t·F dt = Fp·(2T − tp)/6 (closure).
    """
    from types import SimpleNamespace

    from pipeline.analysis import _boot_for

    T, tp, Fp = 1.0, 0.3, 2.0
    t = np.linspace(0.0, T, 2001)  # tp = 0.3 is a grid point
    Pn = np.where(t <= tp, Fp * t**2 / (2 * tp), Fp * T / 2 - Fp * (T - t) ** 2 / (2 * (T - tp)))
    scale = np.array([0.9, 1.0, 1.1])
    boot = {"trapezoid": (scale[:, None] * Pn, 0.1 * scale[:, None] * Pn)}
    perc = SimpleNamespace(time=t, t_start=0.0, t_end=T)
    expect = {
        "peak_force": Fp * tp / 2 * scale,
        "closure": Fp * (2 * T - tp) / 6 * scale,
        "momentum": np.full(3, 0.42),  # m*·v_n0 from the scene: not resampled
    }
    for method, want in expect.items():
        split = SimpleNamespace(source="trapezoid", method=method, Pn_c=0.42)
        Pn_b, Pt_b, Pn_c_b = _boot_for(split, boot, perc)
        assert Pn_b is boot["trapezoid"][0] and Pt_b is boot["trapezoid"][1]
        np.testing.assert_allclose(Pn_c_b, want, rtol=1e-6, err_msg=method)
    # no replicates of this source (n_boot = 0): no bootstrap
    assert _boot_for(SimpleNamespace(source="fit", method="closure", Pn_c=0.4), {}, perc) is None


def test_record_without_Ft_is_refused_up_front():
    scene = Scene(speed=0.5, angle_deg=15.0, mu=0.2, e=0.8, **STEEL)
    rec = impact(scene, tangential="coulomb").drop_vars("Ft")
    # the missing channel is named even when μ was to come from the record
    for mu in ("scene", "record"):
        with pytest.raises(InputError, match="no tangential channel Ft"):
            _analyse(rec, scene, mu=mu)
    with pytest.raises(InputError, match="source 'quartic' is unknown"):
        _analyse(impact(scene, tangential="coulomb"), scene, source="quartic")


def test_record_mu_in_the_sticking_regime():
    """Sticking regime (tan 15° = 0.27 < 3.5·μ·(1+e) = 1.9): the contact slides with
    Ft = μ·Fn only until corner A (a quarter of the compression impulse here, Pn_A = Pt_S/μ,
    docs/theory.md, Rigid bodies), then rolls with Ft = 0 (Coulomb law, rigid tangential contact).
    The
    record's μ is the sliding plateau, not the median over compression (which is 0)."""
    scene = Scene(speed=0.5, angle_deg=15.0, mu=0.3, e=0.8, **STEEL)
    rec = impact(scene, tangential="coulomb")
    a = _analyse(rec, scene.replace(mu=0.6), mu="record", n_boot=0)
    assert a.rigid.regime == "sticking"
    assert a.mu_record == pytest.approx(0.3, rel=0.01)
    assert a.rigid_scene.mu == a.mu_record


def test_cli_analyse_prints_strict_json_and_logs_the_warnings(capsys, caplog):
    from pipeline.cli import main

    path = SAMPLES / "gr_15deg_0.6ms.csv"
    with caplog.at_level("WARNING", logger="pipeline"):
        assert main(["analyse", str(path), "--boot", "0", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)  # strict JSON: NaN or Infinity would fail
    assert out["rigid"]["regime"] == "sticking"
    # the quartics of the dense record are structured: said per channel, as a log line
    assert any(r.getMessage().startswith("PoorFitWarning: Fn: degree-4") for r in caplog.records)
    assert main(["analyse", str(SAMPLES / "no_such.csv")]) == 2


def test_fit_bootstrap_matches_the_fit_covariance_on_a_short_window():
    """Residual bootstrap of a sparse record (12 points, quartic: 7 residual dof).

    Least-squares theory (e.g. Draper & Smith, Applied Regression Analysis, 1998, §5.2):
    Var(∫F dt) = m·σ̂²(AᵀA)⁻¹·mᵀ, which PolyFit.antiderivative_std states. Resampling raw
    residuals would give (n − p)/n of it (std −24 % here); centred residuals inflated by
    √(n/dof) give it exactly in expectation (Davison & Hinkley 1997, §6.2.3). 4000
    replicates: relative s.e. of a std ≈ 1.1 %.
    """
    from pipeline.analysis import _bootstrap
    from pipeline.percussion import percussions
    from pipeline.record import make_record
    from pipeline.smooth import fit_window
    from pipeline.window import find_contact

    rng = np.random.default_rng(4)
    t = np.linspace(0.0, 1e-4, 12)
    x = t / 1e-4
    clean = 1e3 * x * (1 - x) * (1 + 0.5 * x)  # cubic pulse, inside the quartic's span
    rec = make_record(
        t,
        {"Fn": clean + rng.normal(0, 20.0, t.size), "Ft": 0.2 * clean + rng.normal(0, 5, t.size)},
        attrs={"source": "sparse", "format": "test", "kind": "digitised"},
    )
    win = find_contact(rec)
    fits = fit_window(win, degree=4, warn=False)
    perc = percussions(win, fits)
    boot = _bootstrap(win, perc, fits, 4000, 0)
    for k, name in enumerate(("Fn", "Ft")):
        want = float(getattr(fits, name).antiderivative_std(np.array([t[-1]]))[0])
        got = float(np.std(boot["fit"][k][:, -1], ddof=1))
        assert got == pytest.approx(want, rel=0.04), name
    # four points and a cubic: the fit interpolates, there is nothing to resample and no
    # noise estimate, so no replicates at all (the score's std is NaN, not a false 0)
    win4 = find_contact(rec.isel(time=slice(0, 12, 3)))
    fits4 = fit_window(win4, degree=3, warn=False)
    assert fits4.Fn.dof == 0
    assert _bootstrap(win4, percussions(win4, fits4), fits4, 50, 0) == {}


@pytest.mark.parametrize("surface_speed,spin", [(0.5, 0.0), (0.0, 60.0)])
def test_outcomes_of_a_slip_against_the_scene_axis(surface_speed, spin):
    """The seed's rotating disc running faster than the ball (v_t0 = v·sin α − u < 0), or a
    backspin past rolling (ω0·R > v_t0): the initial slip s0 = v_t0 − ω0·R is negative, and
    Pt, which opposes it, pushes the ball along +t. Sliding throughout (μ(1+e)·m·v_n0 <
    (2/7)·m·|s0|), Routh's end point gives (docs/theory.md) v_t = v_t0 + μ(1+e)·v_n0 on the
    scene's axis, ω = −ω0 + μ(1+e)·v_n0/(κR) on the slip's, and no energy gained (a
    warning is an error here: the old outcomes took Pt along −t and gained energy)."""
    scene = Scene(speed=0.5, angle_deg=15.0, mu=0.1, e=0.8, spin=spin,
                  surface_speed=surface_speed, **STEEL)  # fmt: skip
    assert scene.slip0 < 0
    a = _analyse(impact(scene, tangential="coulomb"), scene, n_boot=0)
    assert a.rigid.regime == "sliding"
    dv = 0.1 * 1.8 * scene.v_n0  # Pt_f/m
    v_t = scene.v_t0 + dv
    # the ideal record's percussions are exact to ~1e-6 of Pn; e by its calibration
    assert a.outcomes["e_t"] == pytest.approx(v_t / scene.v_t0, rel=1e-3)
    assert a.outcomes["omega"] == pytest.approx(-spin + dv / (0.4 * scene.radius), rel=1e-3)
    rebound = math.degrees(math.atan2(v_t, 0.8 * scene.v_n0))
    assert a.outcomes["rebound_deg"] == pytest.approx(rebound, abs=0.05)
    assert a.plausibility.summary()["energy"]["status"] == "ok"
