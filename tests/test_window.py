"""Contact window: start/end, baseline and noise on records with a known truth.

Ground truth is the exact elastic Hertz history (pipeline.contact.hertz_pulse; Johnson,
Contact Mechanics, CUP 1985, §11.4, doi:10.1017/CBO9781139171731) for a 25.4 mm steel ball
on a steel cap at 0.5 m/s (Garland & Rogers 2009 table: F_max ≈ 1.2 kN, t_c ≈ 101 µs), with
offset, drift, white noise and pre-/post-trigger samples added here with numpy.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.stats
import xarray as xr
from scipy import integrate

from pipeline.contact import hertz_impact, hertz_pulse
from pipeline.errors import (
    ClippedSignalError,
    InputError,
    MultipleImpactWarning,
    NoPulseError,
    SignFlipError,
    SpikeWarning,
    TriggerGlitchWarning,
    TruncatedPulseError,
)
from pipeline.record import make_record
from pipeline.scene import Scene
from pipeline.window import apply_window, default_threshold, find_contact

SCENE = Scene(
    radius=0.0127, density=7800.0, E=200e9, nu=0.3, target_E=200e9, target_nu=0.3, speed=0.5
)
IMPACT = hertz_impact(SCENE)
FS = 1e6  # sampling rate [Hz]: ~100 samples per contact (Garland & Rogers 2009)
T0 = 1.5e-3 + 0.37e-6  # true contact start, off the sample grid [s]
SIGMA_N, SIGMA_T = 2.0, 1.5  # white noise [N]
OFFSET_N, DRIFT_N = 15.0, 2.0e4  # [N], [N/s]
OFFSET_T, DRIFT_T = -3.0, -5.0e3


def sensor_record(seed=1, pulse=True, sigma_n=SIGMA_N, extra=None):
    """The Hertz pulse at T0 with offset, drift and noise; ``extra(t)`` adds a force [N]."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 3.1e-3, 1.0 / FS)
    F = hertz_pulse(t - T0, IMPACT)["F"] if pulse else np.zeros_like(t)
    if extra is not None:
        F = F + extra(t)
    Fn = F + OFFSET_N + DRIFT_N * t + rng.normal(0.0, sigma_n, t.size)
    Ft = 0.2 * F + OFFSET_T + DRIFT_T * t + rng.normal(0.0, SIGMA_T, t.size)
    return make_record(
        t, {"Fn": Fn, "Ft": Ft}, attrs={"source": "synthetic", "format": "test", "kind": "sensor"}
    )


def end_tolerance(sigma):
    """One sample period plus the time a Hertz start F = K(v0 t)^{3/2} needs to reach 3σ.

    Below ~σ the pulse cannot be told from noise; the window's ends stop at the last sample
    above σ and interpolate to zero, so they are off by the rise time to a few σ (late) or
    by noise samples above σ next to the edge (early, probability 0.16 per sample).
    """
    return 1.0 / FS + (3.0 * sigma / IMPACT.K) ** (2.0 / 3.0) / IMPACT.v0


def test_sensor_window_recovers_start_end_noise_and_impulse():
    rec = sensor_record()
    raw = rec.copy(deep=True)
    w = find_contact(rec)
    tol = end_tolerance(SIGMA_N)
    assert tol < 3.0 / FS  # the derived tolerance is about one to two samples here
    assert abs(w.t_start - T0) < tol
    assert abs(w.t_end - (T0 + IMPACT.t_c)) < tol
    for seed in (2, 3, 4):
        other = find_contact(sensor_record(seed))
        assert abs(other.t_start - T0) < tol
        assert abs(other.t_end - (T0 + IMPACT.t_c)) < tol
    assert w.noise["Fn"] == pytest.approx(SIGMA_N, rel=0.10)
    assert w.noise["Ft"] == pytest.approx(SIGMA_T, rel=0.10)
    # the baseline recovered: offset and drift of both channels
    assert w.baseline["Fn"](0.0) == pytest.approx(OFFSET_N, abs=0.5)
    assert w.baseline["Fn"].slope == pytest.approx(DRIFT_N, rel=0.05)
    assert w.baseline["Ft"].slope == pytest.approx(DRIFT_T, rel=0.2)
    # impulse after baseline removal: Pn(t_c) = 2·m*·v0 (docs/theory.md, Compliant contact)
    t = np.concatenate([[w.t_start], w.record["time"].values, [w.t_end]])
    Fn = np.concatenate([[0.0], w.record["Fn"].values, [0.0]])
    Pn = integrate.trapezoid(Fn, t)
    assert Pn == pytest.approx(2.0 * IMPACT.m_eff * IMPACT.v0, rel=0.01)
    # Ft = 0.2·Fn in the truth: its impulse follows once its own baseline is gone
    Pt = integrate.trapezoid(np.concatenate([[0.0], w.record["Ft"].values, [0.0]]), t)
    assert Pt == pytest.approx(0.2 * 2.0 * IMPACT.m_eff * IMPACT.v0, rel=0.03)
    # raw input untouched
    assert rec.identical(raw)
    assert w.n_samples == w.record.sizes["time"]
    assert w.record.attrs["baseline_removed"] == 1


def test_window_does_not_fire_on_pure_noise():
    rec = sensor_record(pulse=False)
    with pytest.raises(InputError, match="no contact pulse found.*noise σ"):
        find_contact(rec)


def test_default_threshold_false_alarm_rate():
    # Bonferroni: P(max |z| > k over n samples) ≤ α; check by Monte Carlo on white noise.
    n, alpha = 1000, 0.05
    k = default_threshold(n, alpha)
    rng = np.random.default_rng(7)
    z = rng.normal(size=(4000, n))
    rate = np.mean(np.abs(z).max(axis=1) > k)
    assert rate < alpha
    assert rate > alpha / 2  # the bound is nearly tight for independent samples


def test_negative_pulse_is_refused():
    rec = sensor_record()
    flipped = rec.copy(deep=True)
    flipped["Fn"] = -flipped["Fn"]
    with pytest.raises(InputError, match="compressive"):
        find_contact(flipped)


def test_digitised_record_passes_through():
    t = np.linspace(0.0, IMPACT.t_c, 30)
    F = hertz_pulse(t, IMPACT)["F"]
    rec = make_record(
        t, {"Fn": F, "Ft": 0.1 * F}, attrs={"source": "x.csv", "format": "wpd", "kind": "digitised"}
    )
    w = find_contact(rec)
    assert (w.t_start, w.t_end) == (t[0], t[-1])
    np.testing.assert_array_equal(w.record["Fn"].values, F)
    assert w.record.attrs["baseline_removed"] == 0


def test_simulated_record_window_brackets_positive_force():
    h = 1e-6
    t = np.arange(-20e-6, IMPACT.t_c + 20e-6, h) + 0.3e-6
    F = hertz_pulse(t, IMPACT)["F"]
    rec = make_record(
        t,
        {"Fn": F, "Ft": 0 * F},
        attrs={"source": "sim", "format": "simulate", "kind": "simulated"},
    )
    w = find_contact(rec)
    assert -h < w.t_start <= 0.0
    assert IMPACT.t_c <= w.t_end < IMPACT.t_c + h
    assert w.record["Fn"].values[0] == 0.0 and w.record["Fn"].values[-1] == 0.0


def test_apply_window_to_the_raw_record_reproduces_the_window_record():
    rec = sensor_record(seed=3)
    w = find_contact(rec)
    again = apply_window(rec, w)
    np.testing.assert_array_equal(again["Fn"].values, w.record["Fn"].values)


def test_apply_window_subtracts_the_baselines_of_a_numpy_or_a_dask_record_alike():
    """The window's samples minus each channel's baseline line, the input untouched; a
    record whose variables are dask arrays (``.chunk()``) gives the same numbers."""
    pytest.importorskip("dask.array")
    rec = sensor_record(seed=4)
    raw = rec.copy(deep=True)
    w = find_contact(rec)
    t = rec["time"].values
    inside = (t >= w.t_start) & (t <= w.t_end)
    for record in (rec, rec.chunk({"time": 500})):
        out = apply_window(record, w)
        np.testing.assert_array_equal(out["time"].values, t[inside])
        for name in ("Fn", "Ft"):
            b = w.baseline[name]
            expected = rec[name].values[inside] - (b.offset + b.slope * (t[inside] - b.t_ref))
            np.testing.assert_allclose(out[name].values, expected, rtol=0, atol=1e-9)
            assert out[name].attrs == rec[name].attrs
        assert out.attrs["baseline_removed"] == 1
    xr.testing.assert_identical(rec, raw)


def test_a_record_is_the_dataset_xarray_builds_from_the_same_arrays():
    """make_record builds its variables without xarray's probe for duck arrays: the Dataset
    is identical to the one xarray's own constructor makes (index, dtypes, attrs)."""
    t = np.arange(5) * 1e-6
    rec = make_record(
        t,
        {"Fn": [1, 2, 3, 4, 5], "Ft": np.zeros(5)},
        attrs={"source": "s", "format": "f", "kind": "digitised"},
        measured={"Fn": [1, 0, 1, 1, 0]},
        extra={"V": (np.ones(5), "V", "voltage")},
    )
    plain = xr.Dataset(
        {
            "Fn": ("time", np.arange(1.0, 6.0), {"units": "N", "long_name": rec.Fn.long_name}),
            "Ft": ("time", np.zeros(5), {"units": "N", "long_name": rec.Ft.long_name}),
            "Fn_measured": (
                "time",
                np.array([1, 0, 1, 1, 0], dtype=bool),
                {"long_name": "instants at which Fn was digitised"},
            ),
            "V": ("time", np.ones(5), {"units": "V", "long_name": "voltage"}),
        },
        coords={"time": ("time", t, {"units": "s", "long_name": "time"})},
        attrs={"source": "s", "format": "f", "kind": "digitised", "sha256": ""},
    )
    xr.testing.assert_identical(rec, plain)
    assert rec.indexes["time"].equals(plain.indexes["time"])
    assert rec.Fn_measured.dtype == bool and rec.Fn.dtype == np.float64


def ideal_hertz_record():
    """The exact Hertz pulse from first contact, densely sampled, Ft = 0.2·Fn (simulated)."""
    t = np.arange(-5, 2006) * (IMPACT.t_c / 2000)
    F = hertz_pulse(t, IMPACT)["F"]
    return make_record(
        t,
        {"Fn": F, "Ft": 0.2 * F, "Fy": 0.0 * F},
        attrs={"source": "hertz_pulse", "format": "test", "kind": "simulated"},
    )


def test_window_on_the_sensor_model_output():
    # the project's rig model (pipeline.sensor_model.to_sensor: cross-talk, causal
    # 300 kHz Butterworth, offset, drift, 2 N noise, 16-bit ADC) applied to the exact pulse
    from pipeline.sensor_model import SENSOR_DEFAULTS, to_sensor

    ideal = ideal_hertz_record()
    # 1 ms of baseline: the MAD noise estimate then has a s.e. of ≈1.17/√2000 ≈ 2.6 %
    rec = to_sensor(ideal, seed=5, pre_trigger=500e-6, post_trigger=500e-6)
    w = find_contact(rec)
    # the causal order-2 Butterworth delays the pulse by √2/(2π f_c) (sensor_model notes)
    delay = np.sqrt(2.0) / (2 * np.pi * SENSOR_DEFAULTS["bandwidth"])
    tol = (
        1.0 / SENSOR_DEFAULTS["rate"]
        + (3 * SENSOR_DEFAULTS["noise"] / IMPACT.K) ** (2 / 3) / IMPACT.v0
    )
    assert abs(w.t_start - delay) < tol
    assert abs(w.t_end - (IMPACT.t_c + delay)) < tol
    assert w.noise["Fn"] == pytest.approx(SENSOR_DEFAULTS["noise"], rel=0.10)
    tt = np.concatenate([[w.t_start], w.record["time"].values, [w.t_end]])
    Fn = np.concatenate([[0.0], w.record["Fn"].values, [0.0]])
    # cross-talk (±2 %) from Ft = 0.2·Fn into Fn bounds the impulse error at ~0.4 %
    assert integrate.trapezoid(Fn, tt) == pytest.approx(2 * IMPACT.m_eff * IMPACT.v0, rel=0.01)


def test_short_trigger_spans_still_give_the_window():
    """20 pre- and post-trigger samples around a ~100-sample pulse (a tight NI capture).

    The pulse fills ~70 % of the record, so a noise estimate over all samples would exceed
    the pulse; the window must still be found from the few baseline samples. With ~20
    baseline samples a single σ estimate scatters by ~1.67σ/√20 ≈ 0.4σ (MAD efficiency), so
    the noise is checked on the median over ten records. The baseline line rests on ~10
    samples per side, so its own error (≈ σ/√10 at each end) comes on top of the noise:
    the ends get twice the long-record tolerance.
    """
    tol = 2.0 * end_tolerance(SIGMA_N)
    noise = []
    for seed in range(10):
        rng = np.random.default_rng(seed)
        t = T0 - 20.0 / FS + np.arange(int(IMPACT.t_c * FS) + 41) / FS
        Fn = hertz_pulse(t - T0, IMPACT)["F"] + 3.0 + rng.normal(0.0, SIGMA_N, t.size)
        rec = make_record(
            t,
            {"Fn": Fn, "Ft": 0.1 * Fn},
            attrs={"source": "short", "format": "test", "kind": "sensor"},
        )
        w = find_contact(rec)
        assert abs(w.t_start - T0) < tol
        assert abs(w.t_end - (T0 + IMPACT.t_c)) < tol
        noise.append(w.noise["Fn"])
    assert np.median(noise) == pytest.approx(SIGMA_N, rel=0.25)


def test_a_slow_digitiser_short_record_gives_the_window():
    """A 100 kHz capture (a general-purpose DAQ card): 10 pre- and 20 post-trigger samples
    around a ~10-sample contact, 41 samples in all. The first noise estimate must not rest
    on 4 end samples: the MAD of so few (about their own median) falls to a tenth of σ by
    chance, the noise then reads as a sensor's ring after the pulse and the window refused
    the record for want of baseline samples (3 of these 40 noise draws)."""
    from pipeline.sensor_model import SENSOR_DEFAULTS, to_sensor

    rate = 1e5
    ideal = ideal_hertz_record()
    delay = np.sqrt(2.0) / (2 * np.pi * SENSOR_DEFAULTS["bandwidth"])
    # end_tolerance at this rate, and two periods more: at 10 samples per contact a noise
    # sample above σ beside an end (chance 0.16 each) moves it by a whole period
    tol = 3.0 / rate + (3 * SENSOR_DEFAULTS["noise"] / IMPACT.K) ** (2 / 3) / IMPACT.v0
    for seed in range(40):
        rec = to_sensor(ideal, rate=rate, seed=seed)
        assert rec.sizes["time"] == 41
        w = find_contact(rec)
        assert abs(w.t_start - delay) < tol, seed
        assert abs(w.t_end - (IMPACT.t_c + delay)) < tol, seed


# --------------------------------------------------------------- what a careful eye refuses
def _with_fn(rec, fn):
    out = rec.copy(deep=True)
    out["Fn"] = ("time", fn, dict(rec["Fn"].attrs))
    return out


def _index(rec, t):
    return int(np.searchsorted(rec["time"].values, t))


@pytest.mark.parametrize(
    "cut,fragment",
    [
        (slice(None, _index_mid := int((T0 + 0.5 * IMPACT.t_c) * FS)), "runs past the end"),
        (slice(_index_mid, None), "starts inside the contact pulse"),
    ],
)
def test_a_pulse_cut_by_the_file_is_said_to_be_cut(cut, fragment):
    """A file ending (or starting) mid-pulse: its own error, naming the force at the cut —
    not 'flip the normal axis' (the old baseline through the two ends went through the
    pulse and turned it negative)."""
    rec = sensor_record().isel(time=cut)
    with pytest.raises(TruncatedPulseError, match=fragment) as info:
        find_contact(rec)
    assert "cut mid-pulse" in str(info.value)


@pytest.mark.parametrize("spike", [5000.0, -5000.0])
def test_a_trigger_glitch_is_reported_and_ignored(spike):
    """One sample of ±5 kN 1 ms before the impact: a warning naming it; the window and
    the noise are those of the clean record (the old code took the spike for the pulse:
    'no contact pulse found')."""
    clean = find_contact(sensor_record())
    rec = sensor_record()
    fn = rec["Fn"].values.copy()
    i = _index(rec, 0.5e-3)
    fn[i] += spike
    with pytest.warns(TriggerGlitchWarning, match=r"1 spike\(s\).*ignored") as caught:
        w = find_contact(_with_fn(rec, fn))
    assert caught[0].filename == __file__  # the caller's line, not one inside the window
    tol = end_tolerance(SIGMA_N)
    assert abs(w.t_start - clean.t_start) < tol and abs(w.t_end - clean.t_end) < tol
    assert w.noise["Fn"] == pytest.approx(clean.noise["Fn"], rel=0.02)
    ((t_glitch, value),) = w.glitches
    assert t_glitch == rec["time"].values[i]
    assert value == pytest.approx(spike, abs=10 * SIGMA_N)  # minus the baseline there


def test_a_record_of_noise_and_a_spike_has_no_pulse():
    rec = sensor_record(pulse=False)
    fn = rec["Fn"].values.copy()
    fn[1000] += 3000.0
    with pytest.raises(NoPulseError, match=r"only 1 spike\(s\)"):
        find_contact(_with_fn(rec, fn))


REBOUND = hertz_impact(SCENE.replace(speed=0.2))  # a slower second strike: ~40 % of F_max


def test_a_rebound_strike_after_the_contact_is_reported_and_left_out():
    gap = 30e-6
    t2 = T0 + IMPACT.t_c + gap
    rec = sensor_record(extra=lambda t: hertz_pulse(t - t2, REBOUND)["F"])
    with pytest.warns(MultipleImpactWarning, match=r"1 further pulse\(s\)") as info:
        w = find_contact(rec)
    assert "keeps to the first" in str(info[0].message)
    tol = end_tolerance(SIGMA_N)
    assert abs(w.t_start - T0) < tol and abs(w.t_end - (T0 + IMPACT.t_c)) < tol
    ((a, b, peak),) = w.other_pulses
    assert abs(a - t2) < end_tolerance(SIGMA_N) + 1 / FS
    assert peak == pytest.approx(REBOUND.F_max, rel=0.02)


def test_a_second_impact_merged_into_the_first_is_cut_at_the_dip():
    """The second strike begins at 0.8·t_c, before the first has ended: the force dips
    (to ~30 % of the smaller hump) and rises again. The window ends at the dip, so the
    analysis keeps to the first impact (its peak, not the sum of the two)."""
    t2 = T0 + 0.8 * IMPACT.t_c
    rec = sensor_record(extra=lambda t: hertz_pulse(t - t2, REBOUND)["F"])
    with pytest.warns(MultipleImpactWarning, match="the window ends at that dip"):
        w = find_contact(rec)
    truth = rec["time"].values
    both = hertz_pulse(truth - T0, IMPACT)["F"] + hertz_pulse(truth - t2, REBOUND)["F"]
    inside = (truth > T0 + 0.5 * IMPACT.t_c) & (truth < t2 + 0.5 * REBOUND.t_c)
    t_dip = truth[inside][np.argmin(both[inside])]
    assert abs(w.t_end - t_dip) <= 3 / FS  # the noisy minimum of a shallow valley
    assert w.peak == pytest.approx(IMPACT.F_max, rel=0.01)


WEAK = hertz_impact(SCENE.replace(speed=0.015))  # a grazing second touch: 1.5 % of F_max


@pytest.mark.parametrize("gap", [0.0, 2e-6, 20e-6, 2e-4])
def test_a_weak_second_strike_is_seen_however_close(gap):
    """A second strike of 1.5 % of the first's peak — under the 5 % that filter ringing may
    reach — still lasts longer than the first contact (t_c ∝ v^(-1/5)), so it is a second
    impact, at any gap after the force came back to the baseline."""
    t2 = T0 + IMPACT.t_c + gap
    rec = sensor_record(extra=lambda t: hertz_pulse(t - t2, WEAK)["F"])
    with pytest.warns(MultipleImpactWarning, match=r"1 further pulse\(s\)"):
        w = find_contact(rec)
    assert w.peak == pytest.approx(IMPACT.F_max, rel=0.01)
    assert w.duration < IMPACT.t_c + 2 * end_tolerance(SIGMA_N)


def _noise_free(kind, t, F):
    return make_record(
        t, {"Fn": F, "Ft": 0.1 * F}, attrs={"source": "synthetic", "format": "test", "kind": kind}
    )


@pytest.mark.parametrize("gap", [1e-7, 1e-6, 5e-5])
def test_a_second_strike_in_a_simulated_record_is_seen(gap):
    """Noise-free (simulated) records: the first ``Fn > 0`` run is the contact; Fn back to
    zero for one sample and up again is a second impact however soon (the window used to
    run to the last Fn > 0 of the record, both strikes in it)."""
    h = IMPACT.t_c / 1000
    t = np.arange(-5, 4000) * h
    t2 = IMPACT.t_c + gap
    F = hertz_pulse(t, IMPACT)["F"] + hertz_pulse(t - t2, REBOUND)["F"]
    with pytest.warns(MultipleImpactWarning, match="keeps to the first"):
        w = find_contact(_noise_free("simulated", t, F))
    assert abs(w.t_end - IMPACT.t_c) <= 2 * h and w.peak == pytest.approx(IMPACT.F_max, 1e-6)
    ((a, _, peak),) = w.other_pulses
    assert abs(a - t2) <= 2 * h and peak == pytest.approx(REBOUND.F_max, rel=1e-3)


def test_a_second_strike_in_a_digitised_record_is_seen():
    """A digitised curve: back within 2 % of the peak (the clicks' error) between two humps
    is a return to the baseline."""
    t = np.linspace(0.0, IMPACT.t_c, 25)
    t2 = np.linspace(0.0, REBOUND.t_c, 25)
    times = np.concatenate([t, [IMPACT.t_c + 1e-6], IMPACT.t_c + 2e-6 + t2])
    F = np.concatenate(
        [hertz_pulse(t, IMPACT)["F"], [0.01 * IMPACT.F_max], hertz_pulse(t2, REBOUND)["F"]]
    )
    with pytest.warns(MultipleImpactWarning, match=r"1 further pulse\(s\)"):
        w = find_contact(_noise_free("digitised", times, F))
    assert w.t_end == pytest.approx(IMPACT.t_c, abs=1e-12)  # its first point back at 0
    one = find_contact(_noise_free("digitised", t, hertz_pulse(t, IMPACT)["F"]))
    assert one.other_pulses == () and one.t_end == pytest.approx(IMPACT.t_c, abs=1e-12)


def test_a_clipped_pulse_is_refused():
    """An ADC that saturates at 80 % of the peak: a flat top of ~30 samples at the
    channel's maximum, against a baseline whose noise (σ = 2 N) never repeats a value."""
    rec = sensor_record()
    fn = rec["Fn"].values.copy()
    top = 0.8 * IMPACT.F_max + OFFSET_N
    fn = np.minimum(fn, top)
    n_flat = int(np.count_nonzero(fn == top))
    assert n_flat > 10
    with pytest.raises(ClippedSignalError, match=f"{n_flat} consecutive samples") as info:
        find_contact(_with_fn(rec, fn))
    assert info.value.column == "Fn" and "saturated" in str(info.value)


def test_a_quantised_noise_free_top_is_not_clipping():
    """A noise-free record through a 16-bit ADC over 5 kN (step 0.076 N) repeats its top
    value a few times by right: the flat-run rule needs 10 % of the pulse there."""
    rec = sensor_record(sigma_n=0.0)
    q = 5000.0 / 2**16
    w = find_contact(_with_fn(rec, np.round(rec["Fn"].values / q) * q))
    assert abs(w.t_start - T0) < end_tolerance(q)


def test_a_digitised_curve_with_negative_fn_is_refused():
    t = np.linspace(0.0, IMPACT.t_c, 30)
    F = hertz_pulse(t, IMPACT)["F"]
    rec = make_record(
        t,
        {"Fn": -F, "Ft": 0.1 * F},
        attrs={"source": "fn.csv", "format": "wpd", "kind": "digitised"},
    )
    with pytest.raises(SignFlipError, match="fn.csv: the digitised Fn is all negative"):
        find_contact(rec)


def test_a_noise_free_quantised_baseline_takes_the_adc_rounding_as_its_noise():
    """A baseline sitting on one ADC level has zero MAD and zero spread; the noise is then
    the converter's rounding, q/√12 (a uniform error over one step), not 0 — which left no
    threshold and no samples 'outside the contact'."""
    from pipeline.contact import hertz_impact, hertz_pulse
    from pipeline.record import make_record
    from pipeline.scene import Scene

    hi = hertz_impact(Scene(radius=0.0127, density=7850.0, E=210e9, nu=0.29, speed=0.6))
    q = 5000.0 / 2**16  # a 16-bit converter over 5 kN
    t = np.arange(-200, 600) * hi.t_c / 200
    F = np.round(hertz_pulse(t, hi)["F"] / q) * q
    rec = make_record(t, {"Fn": F, "Ft": 0.1 * F}, attrs={"source": "q", "format": "t"})
    w = find_contact(rec)
    assert w.noise["Fn"] == pytest.approx(q / np.sqrt(12), rel=1e-6)
    assert w.t_start == pytest.approx(0.0, abs=3 * hi.t_c / 200)
    assert w.t_end == pytest.approx(hi.t_c, abs=3 * hi.t_c / 200)


def test_a_noise_free_sensor_record_finds_its_contact():
    """A noise-free, unquantised sensor record (simulator + filter, offset, drift and
    cross-talk of the sensor model) has residual baselines at rounding level; the contact
    must still be found where it is (it was refused as 'cut mid-pulse'): from first contact
    to t_c plus the filter's delay (order-2 Butterworth at 300 kHz: lag √2/(2π·f_c) ≈ 0.75 µs)."""
    from _rig import GR_RIG

    from pipeline.simulate import impact, to_sensor

    scene = Scene(**GR_RIG, speed=0.6, angle_deg=15.0, mu=0.13, e=0.9)
    ideal = impact(scene, samples=2001)
    w = find_contact(to_sensor(ideal, seed=3, noise=0.0, bits=None))
    dt = 0.5e-6  # the default 2 MHz
    assert w.t_start == pytest.approx(0.0, abs=2 * dt)
    assert w.t_end == pytest.approx(ideal.attrs["t_contact"], abs=4 * dt)


# ------------------------------------------------- the window against a slow reference
# The search shares its work (one spike scan for every channel, σ and lines reused where
# their samples did not change, the record cut only when read). Whatever it found, the
# window must be the fixed point of its own steps recomputed the plain way: each
# quadratic by numpy.polyfit, each median by numpy.median, each line by least squares,
# the run above σ sample by sample (the module notes give the steps).
def _neighbours_quadratic(y, i):
    """The least-squares quadratic through the six neighbours of sample ``i`` (offsets
    ±1…±3), at ``i``: what a spike there is repaired to."""
    off = np.array([-3, -2, -1, 1, 2, 3])
    return np.polyval(np.polyfit(off, y[i + off], 2), 0.0)


def _slow_mad_sigma(r):
    """σ of Gaussian noise from its median absolute deviation: MAD/Φ⁻¹(3/4) (Hampel 1974)."""
    return np.median(np.abs(r - np.median(r))) / scipy.stats.norm.ppf(0.75)


def _slow_outside(t, w, guard=0.25):
    """The samples the baseline rests on: outside the window widened by guard·duration on
    each side, the margin shortened to half a short trigger span (module notes, step 5)."""
    dur = w.t_end - w.t_start
    g_left = min(guard * dur, 0.5 * (w.t_start - t[0]))
    g_right = min(guard * dur, 0.5 * (t[-1] - w.t_end))
    return (t < w.t_start - g_left) | (t > w.t_end + g_right)


def _slow_line(t, y, out, w, t_ref):
    """The least-squares line through the samples ``out`` (both sides), else their mean."""
    both = np.sum(out & (t < w.t_start)) >= 4 and np.sum(out & (t > w.t_end)) >= 4
    if both:
        slope, offset = np.polyfit(t[out] - t_ref, y[out], 1)
        return lambda tt: offset + slope * (tt - t_ref)
    return lambda tt: np.mean(y[out]) + 0.0 * tt


def _slow_ends(t, r, sigma):
    """The stretch where r > σ around the largest r, and its ends (module notes, step 4)."""
    a = b = int(np.argmax(r))
    while a > 0 and r[a - 1] > sigma:
        a -= 1
    while b < r.size - 1 and r[b + 1] > sigma:
        b += 1
    t0 = t[a - 1] - r[a - 1] * (t[a] - t[a - 1]) / (r[a] - r[a - 1]) if r[a - 1] <= 0 else t[a - 1]
    t1 = t[b + 1] - r[b + 1] * (t[b] - t[b + 1]) / (r[b] - r[b + 1]) if r[b + 1] <= 0 else t[b + 1]
    return t0, t1


def _awkward(case):
    """A record that breaks an assumption, and the samples of Fn and Ft spiked in it."""
    rec = sensor_record(seed=21)
    t = rec["time"].values
    fn, ft = rec["Fn"].values.copy(), rec["Ft"].values.copy()
    spiked = {"Fn": [], "Ft": []}
    if case == "edge_spikes":  # on the first and last samples the scan judges, and mid-pulse
        for i, s in ((3, 60.0), (t.size - 4, -70.0), (_index(rec, T0 + 30e-6), 400.0)):
            fn[i] += s
            spiked["Fn"].append(i)
        ft[3] += 50.0
        spiked["Ft"].append(3)
    elif case == "zero_shift":  # the sensor's zero steps by 25 N after the pulse
        fn[t > T0 + IMPACT.t_c + 200e-6] += 25.0
    elif case == "drift":  # a curved drift on top of the linear one: 20 N over the record
        fn += 20.0 * (t / t[-1]) ** 2
    elif case == "no_pre_trigger":  # three samples before the pulse: a line on one side only
        keep = t >= T0 - 3.0 / FS
        t, fn, ft = t[keep], fn[keep], ft[keep]
    return make_record(
        t, {"Fn": fn, "Ft": ft}, attrs={"source": case, "format": "test", "kind": "sensor"}
    ), spiked


@pytest.mark.parametrize("case", ["edge_spikes", "zero_shift", "drift", "no_pre_trigger"])
def test_the_window_is_the_fixed_point_of_its_steps_done_the_slow_way(case):
    rec, spiked = _awkward(case)
    raw = rec.copy(deep=True)
    with warnings.catch_warnings():  # the spikes are reported; here they are checked
        warnings.simplefilter("ignore", SpikeWarning)
        warnings.simplefilter("ignore", TriggerGlitchWarning)
        w = find_contact(rec)
    t = rec["time"].values
    tol = 2.0 * end_tolerance(SIGMA_N)  # the truth, for the records that keep both sides
    assert abs(w.t_start - T0) < tol and abs(w.t_end - (T0 + IMPACT.t_c)) < tol
    # the spikes planted, no others, each repaired to its neighbours' quadratic
    assert w.spike_indices() == {c: sorted(i) for c, i in spiked.items() if i}
    fixed = {}
    for c in ("Fn", "Ft"):
        y = rec[c].values.copy()
        for sp in (sp for sp in w.spikes if sp.channel == c):
            assert sp.repaired == pytest.approx(
                _neighbours_quadratic(y, sp.index), abs=1e-9 * np.ptp(y)
            )
            y[sp.index] = sp.repaired
        fixed[c] = y
    # lines, σ and ends from the window's own outside samples
    out = _slow_outside(t, w)
    t_ref = 0.5 * (t[0] + t[-1])
    lines = {c: _slow_line(t, fixed[c], out, w, t_ref) for c in fixed}
    for c, y in fixed.items():
        r = y - lines[c](t)
        scale = np.ptp(y)
        assert w.baseline[c](t) == pytest.approx(lines[c](t), abs=1e-9 * scale)
        sigma = max(_slow_mad_sigma(r[out]), 1e-6 * scale)
        assert w.noise[c] == pytest.approx(sigma, rel=1e-9)
    r = fixed["Fn"] - lines["Fn"](t)
    t0, t1 = _slow_ends(t, r, w.noise["Fn"])
    assert (w.t_start, w.t_end) == pytest.approx((t0, t1), abs=1e-9 / FS)
    inside = (t >= w.t_start) & (t <= w.t_end)
    assert w.n_samples == np.count_nonzero(inside)
    assert w.peak == pytest.approx(np.max(r[inside]), abs=1e-9 * np.ptp(r))
    # the record, cut when read: the repaired samples less their lines
    assert w.record.sizes["time"] == w.n_samples
    for c, y in fixed.items():
        np.testing.assert_allclose(
            w.record[c].values, (y - lines[c](t))[inside], rtol=0, atol=1e-9 * np.ptp(y)
        )
    xr.testing.assert_identical(rec, raw)


def test_the_runs_above_the_noise_are_those_a_loop_over_the_samples_finds():
    """_runs (vectorised) against a walk through the samples: each stretch beyond ±σ of one
    sign that holds a sample beyond ±k·σ, its largest sample and its count above k·σ."""
    from pipeline.window import _runs

    def slow(r, sigma, k):
        found = []
        for sign in (1, -1):
            s = sign * r
            i = 0
            while i < s.size:
                if s[i] > sigma:
                    j = i
                    while j + 1 < s.size and s[j + 1] > sigma:
                        j += 1
                    core = int(np.sum(s[i : j + 1] > k * sigma))
                    if core:
                        found.append((i, j, sign, i + int(np.argmax(s[i : j + 1])), core))
                    i = j + 1
                else:
                    i += 1
        return sorted(found)

    rng = np.random.default_rng(3)
    for _ in range(300):
        r = rng.normal(size=200)
        r[rng.integers(0, 200, 6)] += rng.choice([-9.0, 9.0], 6)  # spikes, at the ends too
        r[:2] += rng.choice([0.0, 7.0])
        r[80:120] += rng.choice([0.0, 12.0])  # a pulse
        got = [(x.a, x.b, x.sign, x.peak, x.core) for x in _runs(r, 1.0, 4.0)]
        assert got == slow(r, 1.0, 4.0)


def test_the_medians_the_window_takes_are_numpys():
    """The window's medians (one selection at the middle, or a sort of a short row) are
    numpy.median's to the last bit: odd and even counts either side of the sort's limit,
    tied values, signed zeros, a NaN (the median is then NaN), one value per row."""
    from pipeline.window import _median, _row_medians

    rng = np.random.default_rng(11)
    for n in (1, 2, 3, 8, 99, 255, 256, 257, 258, 1000, 1001):
        for case in ("normal", "tied", "zeros", "nan"):
            a = rng.normal(size=(3, n))
            if case == "tied":
                a = np.round(2.0 * a) / 2.0
            elif case == "zeros":
                a = np.where(rng.random((3, n)) < 0.5, 0.0, -0.0) + np.round(a) * (n > 8)
            elif case == "nan":
                a[1, rng.integers(n)] = np.nan
            want = np.median(a, axis=1)
            assert np.array_equal(_row_medians(a), want, equal_nan=True), (n, case)
            for row, m in zip(a, want, strict=True):
                got = _median(row)
                assert (np.isnan(got) and np.isnan(m)) or got == m, (n, case)


def test_a_window_copied_or_pickled_carries_its_cut_record():
    import copy
    import dataclasses
    import pickle

    rec = sensor_record(seed=5)
    w = find_contact(rec)
    for other in (pickle.loads(pickle.dumps(find_contact(rec))), copy.deepcopy(find_contact(rec))):
        assert other == w
        xr.testing.assert_identical(other.record, w.record)
    assert dataclasses.replace(w, record=None).record is None
    assert apply_window(rec, w).sizes["time"] == w.n_samples
