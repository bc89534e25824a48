"""Tests of the sensor model (pipeline.sensor_model.to_sensor) and the bundled GR-style samples.

Ground truth: the exact elastic Hertz pulse (pipeline.contact.hertz_pulse; Johnson,
Contact Mechanics 1985, doi:10.1017/CBO9781139171731, §11.4) and closed forms of linear
systems theory (Butterworth polynomials, ramp lag; statistics of a least-squares line).
"""

from __future__ import annotations

import hashlib
import json
import math
from pathlib import Path

import numpy as np
import pytest
from _rig import GR_RIG

from pipeline import InputError, Scene
from pipeline.contact import hertz_impact, hertz_pulse
from pipeline.record import make_record
from pipeline.sensor_model import SensorSaturationWarning, to_sensor

# Garland–Rogers-like scene (Garland & Rogers 2009): 25.4 mm steel ball on a 25.4 mm steel cap.
SCENE = Scene(
    **GR_RIG,
    speed=0.6,
    angle_deg=15.0,
)
IMPACT = hertz_impact(SCENE)
N_IDEAL = 2001
QUIET = dict(
    noise=0.0,
    offset=0.0,
    drift=0.0,
    crosstalk=0.0,
    bits=None,
    bandwidth=math.inf,
    full_scale=math.inf,
)


def ideal_record(ft_ratio=0.1):
    """Exact Hertz pulse on [0, t_c] as an ideal record; Ft a fixed fraction of Fn."""
    t = np.linspace(0.0, IMPACT.t_c, N_IDEAL)
    F = hertz_pulse(t, IMPACT)["F"]
    return make_record(
        t,
        {"Fn": F, "Ft": ft_ratio * F},
        attrs={
            "source": "hertz_pulse",
            "format": "test",
            "kind": "simulated",
            "e_n": 1.0,
            **SCENE.to_dict(),
        },
    )


@pytest.fixture(scope="module")
def ideal():
    return ideal_record()


# ------------------------------------------------------------------ determinism
def _t_tol(rec):
    """Rounding allowance on the time axis: 1e-9 of one sample period."""
    return 1e-9 * float(np.diff(rec.time.values[:2])[0])


def _same_samples(a, b, name):
    """Two records of the same seed hold the same samples. The random draws are
    bit-identical, but the filter's sums may round differently (SIMD order, alignment), and
    a value that lands on an ADC decision level can then flip by one step: allow one step
    of the converter, at no more than a few samples."""
    i = ("Fn", "Ft", "Fy").index(name)
    step = float(np.asarray(a.attrs["sensor_quantum"])[i]) if "sensor_quantum" in a.attrs else 0.0
    d = np.abs(a[name].values - b[name].values)
    scale = float(np.max(np.abs(a[name].values)))
    assert np.all(d <= 1.001 * step + 1e-12 * scale), name
    assert np.count_nonzero(d > 1e-12 * scale) <= 3, name


def test_same_seed_same_record_other_seed_differs(ideal):
    a = to_sensor(ideal, seed=7)
    b = to_sensor(ideal, seed=7)
    c = to_sensor(ideal, seed=8)
    for name in ("Fn", "Ft", "Fy"):
        _same_samples(a, b, name)
    np.testing.assert_allclose(a.time.values, b.time.values, rtol=0, atol=_t_tol(a))
    assert a.attrs == b.attrs
    assert a.sizes["time"] == c.sizes["time"]
    assert not np.array_equal(a.Fn.values, c.Fn.values)
    assert a.attrs["sensor_crosstalk_matrix"] != c.attrs["sensor_crosstalk_matrix"]
    assert a.attrs["sensor_phase"] != c.attrs["sensor_phase"]


def test_seed_none_is_recorded_and_reproduces(ideal):
    a = to_sensor(ideal, seed=None)
    b = to_sensor(ideal, seed=int(a.attrs["sensor_seed"]))
    _same_samples(a, b, "Fn")


def test_zeroing_noise_keeps_phase_and_crosstalk(ideal):
    """Draws come in a fixed order: the noise-free twin shares the phase and matrix."""
    a = to_sensor(ideal, seed=3)
    b = to_sensor(ideal, seed=3, noise=0.0)
    assert a.attrs["sensor_phase"] == b.attrs["sensor_phase"]
    assert a.attrs["sensor_crosstalk_matrix"] == b.attrs["sensor_crosstalk_matrix"]
    np.testing.assert_allclose(a.time.values, b.time.values, rtol=0, atol=_t_tol(a))


# ------------------------------------------------------------- ideal sensor
def test_ideal_sensor_reproduces_the_exact_pulse(ideal):
    rate, pre, post = 2e6, 100e-6, 200e-6
    r = to_sensor(ideal, rate=rate, pre_trigger=pre, post_trigger=post, seed=11, **QUIET)
    t = r.time.values
    np.testing.assert_allclose(np.diff(t), 1.0 / rate, rtol=0, atol=1e-15)
    phase = r.attrs["sensor_phase"]
    assert 0.0 <= phase < 1.0 / rate
    assert t[0] == pytest.approx(-pre + phase, abs=1e-15)
    assert t[-1] <= IMPACT.t_c + post + phase and t[-1] > IMPACT.t_c + post - 1.0 / rate
    exact = hertz_pulse(t, IMPACT)["F"]
    # Linear interpolation of the 2001-point pulse: the worst error is at the t^{3/2}
    # start, ~0.1·F(dt) with dt = t_c/2000, i.e. ~3e-6·F_max; away from it dt²/8·|F''|
    # ~ 3e-7·F_max. Tolerance 1e-5·F_max (≈ 14 mN on 1.35 kN).
    tol = 1e-5 * IMPACT.F_max
    np.testing.assert_allclose(r.Fn.values, exact, rtol=0, atol=tol)
    np.testing.assert_allclose(r.Ft.values, 0.1 * exact, rtol=0, atol=tol)
    np.testing.assert_array_equal(r.Fy.values, 0.0)
    assert (r.Fn.values[t < 0] == 0).all() and (r.Fn.values[t > IMPACT.t_c] == 0).all()
    assert np.count_nonzero(t < 0) == pytest.approx(pre * rate, abs=1)


# ------------------------------------------------- baseline statistics
def test_noise_offset_drift_recovered_from_pre_trigger(ideal):
    noise = np.array([2.0, 1.0, 0.5])
    offset = np.array([5.0, -3.0, 1.5])
    drift = np.array([2.0e3, -1.0e3, 5.0e2])  # [N/s]: 10, −5, 2.5 N over the window
    rate, pre = 2e6, 5e-3  # 10 000 pre-trigger samples: 5 SE of the rms ≈ 3.5 %
    r = to_sensor(
        ideal, rate=rate, pre_trigger=pre, noise=noise, offset=offset, drift=drift, seed=2024
    )
    t = r.time.values
    pre_mask = t < 0  # the true force is zero before the contact (causal filter)
    tt = t[pre_mask] - t[0]
    n = tt.size
    assert n == pytest.approx(pre * rate, abs=1)
    q = np.asarray(r.attrs["sensor_quantum"])
    sxx = np.sum((tt - tt.mean()) ** 2)
    for i, name in enumerate(("Fn", "Ft", "Fy")):
        y = r[name].values[pre_mask]
        slope, intercept = np.polyfit(tt, y, 1)
        resid = y - (intercept + slope * tt)
        sigma = math.sqrt(noise[i] ** 2 + q[i] ** 2 / 12)  # white noise + rounding
        # Standard errors of a least-squares line with n points and noise sigma:
        se_slope = sigma / math.sqrt(sxx)
        se_intercept = sigma * math.sqrt(1.0 / n + tt.mean() ** 2 / sxx)
        se_sd = sigma / math.sqrt(2.0 * (n - 2))
        assert abs(slope - drift[i]) < 5 * se_slope, name
        assert abs(intercept - offset[i]) < 5 * se_intercept, name
        assert abs(resid.std(ddof=2) - sigma) < 5 * se_sd, name


# ------------------------------------------------------------- quantisation
def test_quantisation_step_is_full_scale_over_two_to_the_bits(ideal):
    bits, fs = 12, 4000.0  # ±2 kN, F_max 1.35 kN stays in range
    q = fs / 2**bits
    r = to_sensor(
        ideal, bits=bits, full_scale=fs, noise=0.0, offset=0.0, drift=0.0, crosstalk=0.0, seed=5
    )
    assert r.attrs["sensor_quantum"] == [q, q, q]
    codes = r.Fn.values / q
    np.testing.assert_allclose(codes, np.round(codes), rtol=0, atol=1e-9)
    levels = np.unique(r.Fn.values)
    assert np.min(np.diff(levels)) == pytest.approx(q, rel=1e-12)
    # rounding error of at most q/2 against the unquantised twin
    u = to_sensor(
        ideal, bits=None, full_scale=fs, noise=0.0, offset=0.0, drift=0.0, crosstalk=0.0, seed=5
    )
    assert np.max(np.abs(r.Fn.values - u.Fn.values)) <= q / 2 + 1e-9


def test_saturation_clips_to_end_codes_and_warns(ideal):
    bits, fs = 8, 1000.0  # ±500 N, below F_max ≈ 1.35 kN
    q = fs / 2**bits
    with pytest.warns(SensorSaturationWarning, match="clipped"):
        r = to_sensor(
            ideal, bits=bits, full_scale=fs, noise=0.0, offset=0.0, drift=0.0, crosstalk=0.0, seed=5
        )
    assert r.Fn.max() == pytest.approx((2 ** (bits - 1) - 1) * q)
    assert r.attrs["sensor_saturated"] > 0


# ------------------------------------------------------------------ filter
# Normalised Butterworth polynomials B_n(s) = 1 + a1·s + ...: a1 = 1, √2, 2, 1+√2+... ;
# for order 4, a1 = 2.6131259 (Williams & Taylor, Electronic Filter Design Handbook,
# 4th ed. 2006, Table 11-1). A low-pass 1/B_n(s/ωc) follows a ramp with the lag a1/ωc.
@pytest.mark.parametrize("order, a1", [(1, 1.0), (2, math.sqrt(2)), (3, 2.0), (4, 2.6131259)])
def test_causal_butterworth_lags_a_ramp_by_a1_over_omega(order, a1):
    slope, T, fc = 1.0e6, 200e-6, 50e3  # [N/s], [s], [Hz]
    t = np.linspace(0.0, T, 401)
    rec = make_record(t, {"Fn": slope * t}, attrs={"source": "ramp", "format": "test"})
    r = to_sensor(
        rec,
        bandwidth=fc,
        filter_order=order,
        noise=0.0,
        offset=0.0,
        drift=0.0,
        crosstalk=0.0,
        bits=None,
        full_scale=math.inf,
        pre_trigger=20e-6,
        post_trigger=0.0,
        seed=1,
    )
    lag = a1 / (2 * math.pi * fc)
    tt = r.time.values
    late = (tt > 120e-6) & (tt < T)  # transient decays as exp(−ζωc·t), ≥ 20 time constants
    np.testing.assert_allclose(
        r.Fn.values[late], slope * (tt[late] - lag), rtol=0, atol=1e-4 * slope * lag
    )
    # causality: nothing before the input starts
    assert np.all(r.Fn.values[tt < 0] == 0.0)


def test_default_filter_delays_hertz_pulse_by_its_group_delay(ideal):
    """Order-2 Butterworth at fc: output ≈ the pulse delayed by √2/(2π·fc)."""
    fc = 300e3
    r = to_sensor(ideal, filter_order=2, **{**QUIET, "bandwidth": fc}, seed=4)
    t = r.time.values
    lag = math.sqrt(2) / (2 * math.pi * fc)
    undelayed = hertz_pulse(t, IMPACT)["F"]
    delayed = hertz_pulse(t - lag, IMPACT)["F"]
    err_delayed = np.max(np.abs(r.Fn.values - delayed))
    err_undelayed = np.max(np.abs(r.Fn.values - undelayed))
    # the residual after the delay is the curvature term ~ F''/ωc², 1e-3·F_max at most
    assert err_delayed < 1e-3 * IMPACT.F_max
    assert err_undelayed > 10 * err_delayed


# --------------------------------------------------------------- cross-talk
def test_crosstalk_matrix_mixes_axes(ideal):
    C = np.array([[1.0, 0.03, -0.01], [0.02, 1.0, 0.015], [-0.025, 0.01, 1.0]])
    r = to_sensor(ideal, **{**QUIET, "crosstalk": C}, seed=9)
    t = r.time.values
    F = hertz_pulse(t, IMPACT)["F"]
    true = np.stack([F, 0.1 * F, 0.0 * F])
    tol = 2e-5 * IMPACT.F_max
    for i, name in enumerate(("Fn", "Ft", "Fy")):
        np.testing.assert_allclose(r[name].values, C[i] @ true, rtol=0, atol=tol)
    assert r.attrs["sensor_crosstalk_matrix"] == C.ravel().tolist()


def test_scalar_crosstalk_draws_bounded_off_diagonals(ideal):
    c = 0.03
    r = to_sensor(ideal, crosstalk=c, seed=12)
    M = np.array(r.attrs["sensor_crosstalk_matrix"]).reshape(3, 3)
    np.testing.assert_array_equal(np.diag(M), 1.0)
    off = M[~np.eye(3, dtype=bool)]
    assert np.all(np.abs(off) <= c) and np.all(off != 0)


# ------------------------------------------------------------------ attrs
def test_output_attrs_keep_truth_scene_and_parameters(ideal):
    r = to_sensor(ideal, seed=1)
    assert r.attrs["kind"] == "sensor" and r.attrs["format"] == "simulate.to_sensor"
    assert r.attrs["truth_e_n"] == 1.0 and r.attrs["truth_kind"] == "simulated"
    assert r.attrs["angle_deg"] == 15.0 and r.attrs["truth_angle_deg"] == 15.0
    for key in (
        "rate",
        "noise",
        "offset",
        "drift",
        "bits",
        "full_scale",
        "bandwidth",
        "filter_order",
        "crosstalk",
        "crosstalk_matrix",
        "pre_trigger",
        "post_trigger",
        "phase",
        "seed",
        "quantum",
    ):
        assert f"sensor_{key}" in r.attrs, key
    assert "Fy" in r and r.Fy.attrs["units"] == "N"


# ------------------------------------------------------------------ bad input
@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"rate": 0.0}, "rate"),
        ({"noise": -1.0}, "noise"),
        ({"noise": [1.0, 2.0]}, "noise"),
        ({"bits": 16, "full_scale": math.inf}, "full_scale"),
        ({"bits": 0.5}, "bits"),
        ({"crosstalk": np.eye(2)}, "crosstalk"),
        ({"phase": 1e-6, "rate": 2e6}, "phase"),
        ({"bandwidth": -5.0}, "bandwidth"),
        ({"seed": -3}, "seed"),
    ],
)
def test_bad_parameters_raise_input_error(ideal, kwargs, match):
    with pytest.raises(InputError, match=match):
        to_sensor(ideal, **kwargs)


# ============================================== bundled Garland–Rogers-style samples
ROOT = Path(__file__).resolve().parents[1]
GR_SIDECARS = sorted((ROOT / "data_samples").glob("gr_*.json"))
SIDECAR_KEYS = {
    "synthetic",
    "description",
    "file",
    "file_sha256",
    "columns",
    "generator",
    "seed",
    "scene",
    "friction_law",
    "model",
    "simulated_attrs",
    "outcome",
    "truth",
    "sensor",
}
OUTCOME_KEYS = {
    "e_n",
    "e_t",
    "omega",
    "t_contact",
    "E_initial",
    "E_final",
    "W_friction",
    "W_damping",
}
SENSOR_KEYS = {
    "rate",
    "noise",
    "offset",
    "drift",
    "bits",
    "full_scale",
    "quantum",
    "bandwidth",
    "filter_order",
    "oversample",
    "crosstalk_matrix",
    "pre_trigger",
    "post_trigger",
    "phase",
    "seed",
}


def _sidecar(path):
    return json.loads(path.read_text(encoding="utf-8"))


def _sensor_kwargs(sensor: dict) -> dict:
    """to_sensor arguments rebuilt from a sidecar's "sensor" block alone."""
    return {
        "rate": sensor["rate"],
        "noise": sensor["noise"],
        "offset": sensor["offset"],
        "drift": sensor["drift"],
        "bits": sensor["bits"] or None,
        "full_scale": [float(v) for v in sensor["full_scale"]],
        "bandwidth": float(sensor["bandwidth"]),
        "filter_order": sensor["filter_order"],
        "oversample": sensor["oversample"],
        "crosstalk": np.reshape(sensor["crosstalk_matrix"], (3, 3)),
        "pre_trigger": sensor["pre_trigger"],
        "post_trigger": sensor["post_trigger"],
        "phase": sensor["phase"],
        "seed": int(sensor["seed"]),
    }


def test_gr_samples_cover_the_requested_grid():
    """Issue 3 part 5: incidence 5°, 15°, 30°, 45° at two speeds or more."""
    scenes = [_sidecar(p)["scene"] for p in GR_SIDECARS]
    angles = {s["angle_deg"] for s in scenes}
    assert {5.0, 15.0, 30.0, 45.0} <= angles
    for a in (5.0, 15.0, 30.0, 45.0):
        assert len({s["speed"] for s in scenes if s["angle_deg"] == a}) >= 2
    for p in GR_SIDECARS:
        assert p.with_suffix(".csv").stat().st_size < 1_000_000


@pytest.mark.parametrize("path", GR_SIDECARS, ids=lambda p: p.stem)
def test_gr_sidecar_is_complete(path):
    meta = _sidecar(path)
    assert SIDECAR_KEYS <= set(meta), SIDECAR_KEYS - set(meta)
    assert meta["synthetic"] is True
    csv = path.with_suffix(".csv")
    assert meta["file"] == csv.name
    assert meta["file_sha256"] == hashlib.sha256(csv.read_bytes()).hexdigest()
    assert isinstance(meta["seed"], int) and meta["seed"] == meta["sensor"]["seed"]
    assert "make data" in meta["generator"]["command"] and meta["generator"]["version"]
    scene = Scene.from_dict(meta["scene"])
    assert math.isfinite(scene.target_radius) and math.isinf(scene.target_mass)
    law = meta["friction_law"]
    assert scene.mu == pytest.approx(law["a"] + law["b [s/m]"] * scene.v_t0, rel=1e-12)
    assert meta["model"]["normal"] and meta["model"]["tangential"] == "mindlin"
    assert math.isfinite(meta["model"]["damping_param"])
    assert OUTCOME_KEYS <= set(meta["outcome"])
    assert meta["outcome"]["e_n"] == pytest.approx(scene.e, abs=1e-3)
    assert SENSOR_KEYS <= set(meta["sensor"]), SENSOR_KEYS - set(meta["sensor"])


@pytest.mark.parametrize("path", GR_SIDECARS, ids=lambda p: p.stem)
def test_gr_sample_loads_and_matches_its_truth_within_the_noise(path):
    from pipeline.io import load
    from pipeline.simulate import impact

    meta = _sidecar(path)
    rec = load(path.with_suffix(".csv"))
    assert rec.attrs["format"] == "sensor_csv"
    scene = Scene.from_dict(meta["scene"])
    model = meta["model"]
    ideal = impact(
        scene, normal=model["normal"], tangential=model["tangential"], **model["impact_options"]
    )
    for key in ("e_n", "e_t", "omega", "t_contact"):
        assert ideal.attrs[key] == pytest.approx(meta["outcome"][key], rel=1e-6, abs=1e-9)

    s = meta["sensor"]
    noise = np.asarray(s["noise"])
    q = np.asarray(s["quantum"])
    t = rec.time.values

    # (1) Against the noise-free twin rebuilt from the sidecar alone: what is left is the
    # white noise plus two roundings, variance σ² + q²/6; its sample mean and standard
    # deviation must agree within 5 standard errors (n samples).
    twin = to_sensor(ideal, **{**_sensor_kwargs(s), "noise": 0.0})
    np.testing.assert_allclose(t, twin.time.values, rtol=0, atol=1e-15)
    n = t.size
    for i, name in enumerate(("Fn", "Ft", "Fy")):
        r = rec[name].values - twin[name].values
        sig = math.sqrt(noise[i] ** 2 + q[i] ** 2 / 6)
        assert abs(r.mean()) < 5 * sig / math.sqrt(n), name
        assert abs(r.std() - sig) < 5 * sig / math.sqrt(2 * n), name
        assert np.max(np.abs(r)) < 6 * sig, name

    # (2) Independently of to_sensor's internals: remove the stated baseline, undo nothing
    # else, and compare with the ideal forces mixed by the stated cross-talk matrix and
    # delayed by the order-2 Butterworth lag √2/(2π f_c) (linear systems theory). The
    # curvature residual of the delay approximation stays below 0.2 % of the peak.
    assert s["filter_order"] == 2
    lag = math.sqrt(2) / (2 * math.pi * float(s["bandwidth"]))
    C = np.reshape(s["crosstalk_matrix"], (3, 3))
    t_ideal = ideal.time.values
    true = np.stack(
        [
            np.interp(t - lag, t_ideal, ideal[c].values, left=0, right=0) if c in ideal else 0 * t
            for c in ("Fn", "Ft", "Fy")
        ]
    )
    expected = C @ true
    f_peak = meta["truth"]["Fn_max [N]"]
    for i, name in enumerate(("Fn", "Ft", "Fy")):
        baseline = s["offset"][i] + s["drift"][i] * (t - t[0])
        r = rec[name].values - baseline - expected[i]
        assert np.max(np.abs(r)) < 6 * noise[i] + 2e-3 * f_peak, name
