"""A real rig's sensor: the mounted mode, the piezo's discharge, a shifted zero and spikes.

Ground truth: closed forms of linear systems (the damped oscillator's impulse response —
ringing at ω_d = ω_n√(1 − ζ²), logarithmic decrement 2πζ/√(1 − ζ²), unit area; the
first-order high-pass's exponential decay and its exact inverse F = F_m + (1/τ)∫F_m, and the
impulse deficit (T − t̄)/τ it leaves to first order; Harris & Piersol, *Shock and Vibration
Handbook*, 5th ed. 2002, ch. 2 and 12), scipy's continuous-time simulation
(:func:`scipy.signal.lsim`, exact for inputs linear between samples) as an independent path
to the chain the fits model, and records made by the misspecification suite's generator
(benchmarks/_misspec.py: its own impact integration and a bilinear sensor chain), whose
truth the fits must hold.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from _rig import GR_RIG
from scipy import signal

from benchmarks import _misspec as M
from pipeline import InputError, Scene, analyse
from pipeline.contact import hertz_impact, hertz_pulse
from pipeline.errors import (
    MultipleImpactWarning,
    PipelineWarning,
    SensorDynamicsWarning,
    SpikeWarning,
    TruncatedPulseError,
)
from pipeline.fit import fit_contact
from pipeline.fit.sensor import DEFAULT_DAMPING, sensor_spec
from pipeline.record import make_record
from pipeline.sensor_model import foh_filter, sensor_zpk, to_sensor
from pipeline.simulate import impact
from pipeline.window import find_contact, find_spikes


# ---------------------------------------------------------------- the chain, closed forms
def _impulse(n, dt):
    """A unit-area triangle one step wide on each side of sample 1 (piecewise linear: the
    hold is exact for it) — an impulse to the resolution of ``dt``."""
    u = np.zeros(n)
    u[1] = 1.0 / dt
    return u


def test_mode_rings_at_omega_d_with_its_logarithmic_decrement_and_keeps_the_area():
    # damped oscillator ω_n²/(s² + 2ζω_n s + ω_n²): impulse response
    # ω_n/√(1−ζ²)·e^{−ζω_n t}·sin(ω_d t) — zeros every π/ω_d, successive maxima in the
    # ratio e^{δ}, δ = 2πζ/√(1−ζ²) (Harris & Piersol 2002, ch. 2), and H(0) = 1
    fn, zeta, dt = 100e3, 0.05, 2e-9
    wn = 2 * math.pi * fn
    wd = wn * math.sqrt(1 - zeta**2)
    y = foh_filter(*sensor_zpk(resonance=fn, damping_ratio=zeta), dt)(_impulse(80_000, dt))
    t = np.arange(y.size) * dt - dt
    i = np.flatnonzero(np.diff(np.signbit(y)))
    crossings = t[i] - y[i] * dt / (y[i + 1] - y[i])  # linear between the samples
    assert np.diff(crossings[1:9]) == pytest.approx(math.pi / wd, rel=1e-4)
    peaks = [i for i in range(1, y.size - 1) if y[i - 1] < y[i] >= y[i + 1] and y[i] > 0]
    ratios = np.log(y[peaks[:-1]] / y[peaks[1:]])
    assert ratios[:6] == pytest.approx(2 * math.pi * zeta / math.sqrt(1 - zeta**2), rel=1e-4)
    tail = foh_filter(*sensor_zpk(resonance=fn, damping_ratio=zeta), 1e-7)(_impulse(20_000, 1e-7))
    assert np.sum(tail) * 1e-7 == pytest.approx(1.0, abs=1e-9)  # the percussion is kept


def _series(blocks):
    """State space of transfer functions (num, den) in series (well conditioned)."""
    A, B, C, D = (np.atleast_2d(x) for x in signal.tf2ss(*blocks[0]))
    for num, den in blocks[1:]:
        A2, B2, C2, D2 = (np.atleast_2d(x) for x in signal.tf2ss(num, den))
        n1, n2 = A.shape[0], A2.shape[0]
        A = np.block([[A, np.zeros((n1, n2))], [B2 @ C, A2]])
        B, C, D = np.vstack([B, B2 @ D]), np.hstack([D2 @ C, C2]), D2 @ D
    return A, B, C, D


def test_the_chain_equals_scipys_continuous_simulation():
    # low-pass (2nd-order Butterworth, 200 kHz) · mode (150 kHz, ζ = 0.05) · discharge
    # (τ = 0.2 ms), driven by a piecewise-linear input: scipy.signal.lsim integrates the
    # analogue system exactly for such an input, by another route (matrix exponentials of
    # the series state space)
    wc, wn, zeta, tau = 2 * math.pi * 200e3, 2 * math.pi * 150e3, 0.05, 2e-4
    blocks = [
        ([wc * wc], [1, math.sqrt(2) * wc, wc * wc]),
        ([wn * wn], [1, 2 * zeta * wn, wn * wn]),
        ([1.0, 0.0], [1.0, 1.0 / tau]),
    ]
    dt = 0.25e-6
    u = np.concatenate([[0.0], np.cumsum(np.random.default_rng(1).standard_normal(3999))])
    t = np.arange(u.size) * dt
    _, expected, _ = signal.lsim(_series(blocks), u, t, interp=True)
    z, p, k = sensor_zpk(200e3, 2, 150e3, zeta, tau)
    got = foh_filter(z, p, k, dt)(u)
    assert np.max(np.abs(got - expected)) < 1e-9 * np.max(np.abs(expected))


def test_discharge_decays_and_is_inverted_exactly():
    # s/(s + 1/τ): a constant force decays as e^{−t/τ}; the measured F_m gives back the
    # force by F = F_m + (1/τ)∫F_m; over [0, T] the measured integral falls short of the
    # impulse by (T − t̄)/τ to first order (t̄ the pulse's centroid)
    tau, dt = 1e-3, 1e-8
    chain = foh_filter(*sensor_zpk(discharge=tau), dt)
    t = np.arange(300_000) * dt
    step = np.minimum(t / dt, 1.0)  # a force switched on over one step
    assert chain(step)[1000::10_000] == pytest.approx(np.exp(-t[1000::10_000] / tau), rel=1e-4)
    imp = hertz_impact(Scene(**GR_RIG, speed=0.6))
    F = hertz_pulse(t - 10e-6, imp)["F"]
    Fm = chain(F)
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (Fm[1:] + Fm[:-1])) * dt])
    assert np.max(np.abs(Fm + integral / tau - F)) < 1e-6 * F.max()
    P = np.sum(F) * dt
    t_bar = np.sum(F * t) * dt / P
    T = t[-1]
    deficit = 1.0 - np.sum(Fm) * dt / P
    assert deficit == pytest.approx((T - t_bar) / tau, rel=(T / tau) * 1.0)  # O((T/τ)²)


def test_to_sensor_rings_after_the_pulse_and_keeps_the_percussion():
    imp = hertz_impact(Scene(**GR_RIG, speed=0.6))
    t = np.linspace(0.0, imp.t_c, 2001)
    F = hertz_pulse(t, imp)["F"]
    ideal = make_record(
        t, {"Fn": F}, attrs={"source": "hertz", "format": "test", "kind": "simulated"}
    )
    fn, zeta = 40e3, 0.03
    quiet = dict(noise=0.0, offset=0.0, drift=0.0, crosstalk=0.0, bits=None, full_scale=math.inf)
    rec = to_sensor(ideal, rate=10e6, resonance=fn, damping_ratio=zeta, post_trigger=600e-6,
                    phase=0.0, **quiet)  # fmt: skip
    tt, y = rec["time"].values, rec["Fn"].values
    assert np.trapezoid(y, tt) == pytest.approx(np.trapezoid(F, t), rel=1e-4)
    after = tt > imp.t_c + 100e-6
    crossings = tt[after][1:][np.diff(np.signbit(y[after])) != 0]
    wd = 2 * math.pi * fn * math.sqrt(1 - zeta**2)
    assert np.median(np.diff(crossings)) == pytest.approx(math.pi / wd, rel=2e-3)
    assert rec.attrs["sensor_resonance"] == fn and rec.attrs["sensor_damping_ratio"] == zeta


# ---------------------------------------------------------------- what the fits are told
def test_a_record_decoupled_when_loaded_has_no_crosstalk_left_to_model():
    matrix = [[1, 0.02, 0], [0.01, 1, 0], [0, 0, 1]]
    attrs = {"source": "x", "format": "t", "sensor_crosstalk_matrix": matrix}
    record = make_record(np.arange(50) * 1e-6, {"Fn": np.zeros(50)}, attrs=attrs)
    decoupled = make_record(
        np.arange(50) * 1e-6, {"Fn": np.zeros(50)}, attrs={**attrs, "decouple_source": "array"}
    )
    assert sensor_spec(record).crosstalk.tolist() == matrix
    stated = {"crosstalk_matrix": matrix}
    for spec in (sensor_spec(decoupled), sensor_spec(decoupled, stated)):
        assert spec.crosstalk is None and "decoupled when loaded" in spec.notes[-1]
    assert sensor_spec(record, stated).crosstalk.tolist() == matrix


def test_sensor_spec_reads_the_mode_and_the_discharge():
    blank = make_record(
        np.arange(50) * 1e-6, {"Fn": np.zeros(50)}, attrs={"source": "x", "format": "t"}
    )
    spec = sensor_spec(blank, {"bandwidth": 2e5, "resonance": 1.5e5, "discharge": 0.2e-3})
    assert (spec.resonance, spec.discharge, spec.damping_ratio) == (1.5e5, 0.2e-3, DEFAULT_DAMPING)
    assert not spec.damping_stated and any("damping ratio is not stated" in n for n in spec.notes)
    assert spec.ring_time() == pytest.approx(37.0 * 0.2e-3)  # the slowest pole: the discharge
    with pytest.raises(InputError, match=r"damping_ratio = 1\.5 must lie in \(0, 1\)"):
        sensor_spec(blank, {"resonance": 1e5, "damping_ratio": 1.5})
    with pytest.raises(InputError, match=r"resonance = -1\.0 Hz must be positive"):
        sensor_spec(blank, {"resonance": -1.0})
    meta = make_record(
        np.arange(50) * 1e-6,
        {"Fn": np.zeros(50)},
        attrs={"source": "x", "format": "t", "meta_resonance": "150 kHz",
               "meta_damping ratio": "0.04", "meta_discharge": "2 ms"},
    )  # fmt: skip
    spec = sensor_spec(meta)
    assert (spec.resonance, spec.damping_ratio, spec.discharge) == (150e3, 0.04, 2e-3)


# ---------------------------------------------------------------- fits on another generator
def _fit(case, seed, stated=(), **kw):
    """Fit a generator record as told, the truth of ``stated`` (sensor fields) told too."""
    rec, truth, told = M.CASES[case].make(seed)
    kw.setdefault("systematics", told["systematics"])
    sensor = {**told["sensor"], **{k: truth[k] for k in stated}}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fit = fit_contact(rec, told["scene"], sensor=sensor, n_boot=0, **kw)
    return fit, truth, [w.category for w in caught]


def _holds(fit, truth, names=("E_eff", "e", "mu")):
    ci = fit.ci()
    return {n: ci[n][0] <= truth[n] <= ci[n][1] for n in names}


def test_a_stated_mode_is_a_systematic_and_the_parameters_hold():
    fit, truth, warned = _fit("resonance_stated", 1)
    assert "resonance" in fit.priors and "resonance" in fit.budget["E_eff"]
    assert "sensor_dynamics" not in fit.verdict["causes"]
    assert all(_holds(fit, truth).values())


def test_a_stated_discharge_is_a_systematic():
    fit, truth, warned = _fit("discharge", 5, stated=("discharge",))
    assert fit.priors["discharge"] == pytest.approx((truth["discharge"], 0.1 * truth["discharge"]))
    assert "sensor_dynamics" not in fit.verdict["causes"]
    assert fit.values["discharge"] == pytest.approx(truth["discharge"], rel=0.05)
    assert all(_holds(fit, truth).values())


def test_an_unstated_mode_is_found_in_its_ringing_and_fitted():
    fit, truth, warned = _fit("resonance_near", 1)
    assert "sensor_dynamics" in fit.verdict["causes"] and SensorDynamicsWarning in warned
    assert fit.values["resonance"] == pytest.approx(truth["resonance"], rel=0.01)
    assert fit.values["damping_ratio"] == pytest.approx(truth["damping_ratio"], rel=0.2)
    assert "f_n = " in fit.verdict["messages"]["sensor_dynamics"]
    assert all(_holds(fit, truth).values())


def test_an_unstated_discharge_is_found_in_its_undershoot_and_fitted():
    fit, truth, warned = _fit("discharge", 5)  # τ = 12 contact times
    assert "sensor_dynamics" in fit.verdict["causes"] and SensorDynamicsWarning in warned
    assert fit.values["discharge"] == pytest.approx(truth["discharge"], rel=0.05)
    assert all(_holds(fit, truth).values())


def test_a_zero_shift_is_fitted_where_the_record_shows_one():
    fit, truth, warned = _fit("zero_shift", 3)
    assert "sensor_dynamics" in fit.verdict["causes"]
    assert fit.values["shift_n"] == pytest.approx(truth["zero_shift"], rel=0.1)
    assert "zero shifts by" in fit.verdict["messages"]["sensor_dynamics"]
    assert all(_holds(fit, truth).values())


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_record_without_them_grows_no_mode_and_bounds_it(seed):
    fit, truth, warned = _fit("control", seed, systematics=None)
    assert not {"sensor_dynamics", "spikes"} & set(fit.verdict["causes"])
    assert not {"resonance", "discharge", "shift_n"} & set(fit.vary)
    assert {"resonance", "discharge"} <= set(fit.budget["E_eff"])  # bounded, not fitted
    assert fit.dynamics["bounds"]["resonance"] > 1.0 / truth["t_contact"]


def test_noise_after_a_sparse_pulse_is_no_undamped_mode():
    """At 100 kHz (11 samples per contact, 20 after it) the screen's best "ring" in one
    draw of white noise did not decay at all (ζ = 0, the search's bound): a mode no
    transducer has, and the fit ended in a division by zero. Noise is no mode: the fit
    holds the truth and fits none."""
    scene = Scene(radius=0.0127, density=7850.0, E=210e9, nu=0.29, target_E=210e9,
                  target_nu=0.29, target_radius=0.0254, speed=0.6, angle_deg=15.0, mu=0.13,
                  e=0.9)  # fmt: skip
    rec = to_sensor(impact(scene, "hunt_crossley", "mindlin"), rate=1e5, seed=12)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)  # a sparse record: poor-fit notes
        fit = fit_contact(rec, scene.replace(mu=None, e=None), n_boot=0)
    assert not {"resonance", "damping_ratio"} & set(fit.vary)
    truth = {"E_eff": scene.E_eff, "e": scene.e, "mu": scene.mu}
    assert all(_holds(fit, truth).values())


def test_an_unstated_spin_is_named_where_pt_misses_and_stating_it_mends_the_fit():
    """A ball arriving with a spin the scene does not state (the generator's ωR = 20–60 %
    of v_t0; seed 2 draws 135 rad/s) slips otherwise than the model's: the tangential
    impulse misses and the verdict names the spin as a suspect; the scene stating it, the
    impulse matches and the intervals hold E*, e and μ."""
    rec, truth, told = M.CASES["spin_unknown"].make(2)
    fit, _, _ = _fit("spin_unknown", 2)
    assert "impulse_mismatch" in fit.verdict["causes"]
    assert "Scene.spin" in fit.verdict["messages"]["impulse_mismatch"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        told_spin = fit_contact(
            rec,
            told["scene"].replace(spin=truth["spin"]),
            sensor=told["sensor"],
            systematics=told["systematics"],
            n_boot=0,
        )
    assert "impulse_mismatch" not in told_spin.verdict["causes"]
    assert all(_holds(told_spin, truth).values())


def test_inputs_taken_as_exact_look_for_nothing():
    fit, truth, _ = _fit("discharge", 5, systematics={})
    assert "discharge" not in fit.vary and not fit.dynamics


# ---------------------------------------------------------------- a leaking sensor's window
#: A 25.4 mm steel ball at 0.6 m/s, 15°, on a flat steel target (~100 µs contact), recorded
#: by to_sensor's default rig (2 MHz, 300 kHz 2nd-order low-pass, 100 µs pre-, 200 µs
#: post-trigger) through a discharge of τ = 10–20 contact times: the samples after the pulse
#: lie on its undershoot, −P/τ ≈ −64 N at 1 ms, not on the baseline.
LEAK_SCENE = Scene(**{**GR_RIG, "target_radius": math.inf}, speed=0.6, angle_deg=15.0,
                   mu=0.13, e=0.9)  # fmt: skip


@pytest.fixture(scope="module")
def leak_ideal():
    return impact(LEAK_SCENE, "hunt_crossley", "mindlin")


@pytest.mark.parametrize("tau,seed", [(1e-3, 0), (1e-3, 1), (2e-3, 2)])
def test_a_stated_discharge_is_undone_for_the_window(leak_ideal, tau, seed):
    """The window of a leaking record, told τ, is the contact of the simulator's ideal
    record (its first and last instants of Fn > 0) delayed by the low-pass's group delay
    √2/(2π f_c) (Butterworth order 2), within two sample periods; its record holds the
    force with the leak undone: the impulse of the ideal record (a discharge alone eats
    (T − t̄)/τ ≈ 5 % of it at 1 ms, Harris & Piersol 2002, ch. 12)."""
    rec = to_sensor(leak_ideal, seed=seed, discharge=tau)
    t, fn = leak_ideal["time"].values, leak_ideal["Fn"].values
    on = t[fn > 0]
    rate, fc = rec.attrs["sensor_rate"], rec.attrs["sensor_bandwidth"]
    delay = math.sqrt(2.0) / (2.0 * math.pi * fc)
    w = find_contact(rec, discharge=tau)
    assert w.t_start == pytest.approx(on[0] + delay, abs=2.0 / rate)
    assert w.t_end == pytest.approx(on[-1] + delay, abs=2.0 / rate)
    impulse = np.trapezoid(fn, t)
    got = np.trapezoid(w.record["Fn"].values, w.record["time"].values)
    assert got == pytest.approx(impulse, rel=0.01)


def test_an_unstated_discharge_is_named_where_the_record_is_refused(leak_ideal):
    """Told nothing, the undershoot after the pulse passes for the baseline and the quiet
    pre-trigger for a pulse the file cuts: the refusal says what the record shows — a level
    start and an undershoot after the pulse — and how to state the discharge."""
    rec = to_sensor(leak_ideal, seed=0, discharge=1e-3)
    with pytest.raises(TruncatedPulseError, match="discharge") as info:
        find_contact(rec)
    message = str(info.value)
    assert "sensor=" in message and "'sensor'" in message
    # a file that does start inside the pulse (cut at its middle) is said to be cut, no more
    dry = to_sensor(leak_ideal, seed=0)
    middle = int(np.searchsorted(dry["time"].values, 0.5 * float(leak_ideal["time"][-1])))
    with pytest.raises(TruncatedPulseError, match="cut mid-pulse") as info:
        find_contact(dry.isel(time=slice(middle, None)))
    assert "discharge" not in str(info.value)


def test_analyse_windows_a_leaking_record_with_the_discharge_its_record_states(leak_ideal):
    """analyse's own window is told the record's discharge too: its final normal percussion
    is the ideal record's impulse (the leak alone would eat ≈ 5 % of it by the end of the
    contact at τ = 1 ms, and the record was refused before)."""
    rec = to_sensor(leak_ideal, seed=1, discharge=1e-3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)
        a = analyse(rec, LEAK_SCENE, n_boot=0)
    impulse = np.trapezoid(leak_ideal["Fn"].values, leak_ideal["time"].values)
    assert a.outcomes.values["Pn_f"] == pytest.approx(impulse, rel=0.01)


def test_the_plausibility_checks_and_an_ingest_window_a_leaking_record_told_its_discharge(
    leak_ideal, tmp_path
):
    """check_plausible (its own window: the discharge the record's sensor_* attributes
    state) and the summary of a record without a scene (the discharge its sidecar's
    'sensor' block states) undo the leak as the fits do: the record's percussion is the
    ideal impulse (refused before, as a pulse the file cuts)."""
    import json

    from pipeline.io import write_sensor
    from pipeline.plausibility import check_plausible
    from pipeline.report import _ingest_only

    rec = to_sensor(leak_ideal, seed=1, discharge=1e-3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)
        assert check_plausible(rec, LEAK_SCENE).ok
    impulse = np.trapezoid(leak_ideal["Fn"].values, leak_ideal["time"].values)
    path = write_sensor(rec, tmp_path / "leak.csv")
    path.with_suffix(".json").write_text(json.dumps({"sensor": {"discharge": 1e-3}}))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)
        summary = _ingest_only(path)
    assert summary["Pn_total_Ns"] == pytest.approx(impulse, rel=0.01)


def test_a_simulated_records_sensor_survives_a_sensor_csv(leak_ideal, tmp_path):
    """The sensor to_sensor describes (filter, ADC, cross-talk matrix, mounted mode,
    discharge), written by write_sensor and read back, is the sensor the fits are told:
    the CSV kept the scalars only, under names the fits did not read, so the record read
    back was fitted with no filter, no ADC, no cross-talk and no discharge."""
    from pipeline.io import load, write_sensor

    rec = to_sensor(leak_ideal, seed=0, discharge=1e-3, resonance=8e5, damping_ratio=0.03)
    back = sensor_spec(load(write_sensor(rec, tmp_path / "r.csv")))
    # the stated inputs (to_sensor's defaults: 300 kHz, order 2, 16 bits over ±5 kN)
    assert back.bandwidth == pytest.approx(3e5, rel=1e-12) and back.filter_order == 2
    assert back.quantum == pytest.approx(5000.0 / 2**16, rel=1e-12)
    assert back.discharge == pytest.approx(1e-3, rel=1e-12)
    assert back.resonance == pytest.approx(8e5, rel=1e-12)
    assert back.damping_ratio == pytest.approx(0.03, rel=1e-12)
    # the cross-talk matrix drawn by the sensor model, as the record in memory holds it
    np.testing.assert_allclose(back.crosstalk, sensor_spec(rec).crosstalk, rtol=1e-15)
    # a lab's own line of that name, not a number, is not this writer's: left alone
    lab = write_sensor(rec, tmp_path / "lab.csv", metadata={"sensor_bandwidth": "300 kHz"})
    assert sensor_spec(load(lab)).bandwidth == pytest.approx(3e5, rel=1e-12)


@pytest.mark.parametrize("tau,seed", [(1e-3, 5), (2e-3, 4)])
def test_a_leaking_record_fits_with_its_stated_discharge(leak_ideal, tau, seed):
    """Fitted with the discharge its record states (to_sensor's sensor_* attributes), the
    intervals hold the scene's E*, e and μ (refused before: the window took the undershoot
    for the baseline)."""
    rec = to_sensor(leak_ideal, seed=seed, discharge=tau)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)
        fit = fit_contact(rec, LEAK_SCENE.replace(mu=None, e=None), n_boot=0)
    truth = {"E_eff": LEAK_SCENE.E_eff, "e": LEAK_SCENE.e, "mu": LEAK_SCENE.mu}
    assert all(_holds(fit, truth).values()), (fit.ci(), truth)


# ---------------------------------------------------------------- spikes
def test_find_spikes_gives_the_exact_samples_and_leaves_a_ring_alone():
    rng = np.random.default_rng(3)
    t = np.arange(3000) * 1e-6
    # a half-sine pulse: its corners at the ends (a force the filter has not rounded) are
    # no spikes
    pulse = 1000 * np.sin(np.pi * (t - 1e-3) / 100e-6) * (t >= 1e-3) * (t <= 1.1e-3)
    y = pulse + rng.normal(0, 2.0, t.size)
    where = [500, 1020, 1055, 2400]  # two inside the pulse
    y[where] += [200, -200, 200, -200]
    idx, repaired = find_spikes(y)
    assert idx.tolist() == where
    assert repaired == pytest.approx((pulse + y - y)[where], abs=10.0)
    ring = 300 * np.exp(-(t - 1.2e-3) / 200e-6) * np.sin(2 * np.pi * 370e3 * t) * (t > 1.2e-3)
    assert find_spikes(pulse + ring + rng.normal(0, 2.0, t.size))[0].size == 0
    assert all(find_spikes(np.random.default_rng(s).normal(0, 1, 5000))[0].size == 0
               for s in range(10))  # fmt: skip


@pytest.mark.parametrize("noise", [0.0, 1e-3])
def test_a_spike_is_one_exactly_where_it_passes_the_threshold(noise):
    """On a flat line (σ stated) a lone sample stands off its neighbours' quadratic by its
    own height d, whose noise is √1.5·σ: a spike exactly where |d| > k·√1.5·σ, however the
    search's shortcuts skip a channel no sample of which passes (the flat line's equal
    neighbours take the search's slow path for its smallest step, the noise its fast one)."""
    k, sigma = 5.0, 1.0
    bound = k * np.sqrt(1.5) * sigma
    base = np.random.default_rng(5).normal(0, noise, 400)
    for height, found in ((1.01 * bound, True), (0.99 * bound, False)):
        for sign in (1, -1):
            y = base.copy()
            y[200] += sign * height
            idx, repaired = find_spikes(y, k=k, sigma=sigma)
            assert idx.tolist() == ([200] if found else [])
            if found:
                assert repaired == pytest.approx([base[200]], abs=100 * noise + 1e-12)


def test_spikes_are_left_out_of_the_fit_by_their_indices_never_a_second_impact():
    fit, truth, warned = _fit("spikes", 2)
    expected = {}
    for ch, i in truth["spikes"]:
        expected.setdefault(ch, []).append(i)
    assert {k: sorted(v) for k, v in fit.excluded.items()} == {
        k: sorted(v) for k, v in expected.items()
    }
    assert "spikes" in fit.verdict["causes"] and "second_impact" not in fit.verdict["causes"]
    assert SpikeWarning in warned and MultipleImpactWarning not in warned
    assert all(_holds(fit, truth).values())


def test_analyse_scores_the_repaired_channel_and_says_so():
    scene = Scene(**GR_RIG, speed=0.6, angle_deg=30.0, mu=0.2, e=0.9)
    from pipeline.simulate import impact

    clean = to_sensor(impact(scene), seed=4)
    fn = clean["Fn"].values.copy()
    t = clean["time"].values
    inside = np.flatnonzero((t > 20e-6) & (t < 80e-6))
    where = [int(inside[10]), int(inside[60])]
    fn[where] += [-300.0, 300.0]
    spiked = clean.copy()
    spiked["Fn"] = (clean["Fn"].dims, fn, clean["Fn"].attrs)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)
        a_clean = analyse(clean, scene)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        a = analyse(spiked, scene)
    spikes = [str(w.message) for w in caught if w.category is SpikeWarning]
    assert len(spikes) == 1 and "2 isolated sample(s)" in spikes[0]
    assert a.summary()["repaired"]["spikes"] == {"Fn": where}
    assert "repaired: 2 isolated sample(s)" in a.describe()
    assert a.split.e_poisson == pytest.approx(a_clean.split.e_poisson, abs=2e-3)
    assert not a.window.other_pulses


def test_a_ring_after_the_pulse_is_no_second_impact():
    rec, truth, _ = M.CASES["resonance_close"].make(3)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        win = find_contact(rec)
    assert not win.other_pulses and MultipleImpactWarning not in [w.category for w in caught]
    assert win.t_start == pytest.approx(truth["t0"], abs=5e-6)


# ---------------------------------------------------------------- the screen's own numbers
def test_the_screen_finds_the_ring_at_the_mode_s_damped_frequency():
    """The screen's ring (before the fit refines it) rings at the generator's mode,
    ω_d = ω_n·√(1 − ζ²), with its damping ζ (Harris & Piersol 2002, ch. 2): the search for
    the χ² a damped sinusoid explains peaks at the record's own oscillator."""
    fit, truth, _ = _fit("resonance_near", 2)
    zeta = truth["damping_ratio"]
    f_d = truth["resonance"] * math.sqrt(1.0 - zeta**2)
    assert fit.dynamics["ring_f_d"] == pytest.approx(f_d, rel=0.01)
    assert fit.dynamics["ring_zeta"] == pytest.approx(zeta, rel=0.2)
    assert fit.dynamics["ring_chi2"] > fit.dynamics["ring_threshold"]


@pytest.fixture(scope="module")
def shifted():
    """A fit with a zero shift of Fn among its parameters: (fit, its column P, solution)."""
    fit, _, _ = _fit("zero_shift", 3)
    assert "shift_n" in fit.vary and fit.values["shift_n"] != 0.0
    P = fit.problem.design.local(np.asarray(fit.theta)[None, :])[0]
    return fit, P, fit.problem.solution(fit.theta)[0]


def _forward_rows(fit, P, sol, changes):
    """The fit's rows of the model's change when the parameters take each row of
    ``changes`` ({name: values (K,)}), the forward model predicting every column in full."""
    from pipeline.fit.forward import _I, Solution, weighted_residuals

    K = len(next(iter(changes.values())))
    Pk = np.repeat(P, K + 1, axis=0)
    for name, values in changes.items():
        Pk[1:, _I[name]] = values
    sk = Solution(sol.pulse, sol.tang, np.repeat(sol.index[:1], K + 1))
    pred = fit.model.predict(fit.data, Pk, sk)
    return -weighted_residuals(fit.data, [m[1:] - m[:1] for m in pred], derivative=True)


def _same_rows(fast, full):
    scale = np.max(np.abs(full), axis=1, keepdims=True)
    assert np.all(scale > 0)
    assert np.max(np.abs(fast - full) / scale) < 1e-9


def test_the_bound_s_trial_changes_are_the_forward_model_s(shifted):
    """The bound's trials (:func:`pipeline.fit.dynamics.bounds`) take the model's change
    through each trial chain with the force computed once, each distinct pole run once for
    all trials and each pole's state decaying in closed form after the contact: the same
    rows as the forward model predicting every trial column in full (a zero shift in the
    record, so its held step passes the chains)."""
    from pipeline.fit import dynamics

    fit, P, sol = shifted
    dur = fit.physics["t_c"]
    for name, values, fixed in (
        ("resonance", np.geomspace(1.0, 100.0, 5) / dur, {"damping_ratio": 0.1}),
        ("discharge", np.geomspace(1.0, 1e4, 5) * dur, {}),
    ):
        full = _forward_rows(fit, P, sol, {name: values, **{k: [v] * 5 for k, v in fixed.items()}})
        fast = dynamics._trial_rows(fit.data, fit.model, P, sol, name, values, fixed)
        _same_rows(fast, full)


def test_the_screen_s_zero_shift_trials_are_the_forward_model_s(shifted):
    """The screen's trial zero shifts (:func:`pipeline.fit.dynamics._shift_rows`) pass only
    the shift's change through the chain, every course at once and the channel that
    changes, until the chain has settled: the same rows as the forward model predicting
    every course of 1 N in full with the force — on each channel, the other keeping the
    fitted shift of Fn (its course moving with the trial's), courses from before the onset
    to past the contact's end."""
    from pipeline.fit import dynamics

    fit, P, sol = shifted
    t0, dur = fit.values["t0"], fit.physics["t_c"]
    grid = np.array([(t0 + a * dur, w * dur) for a in (-0.2, 0.3, 0.9) for w in (0.02, 0.7)])
    for param in ("shift_n", "shift_t"):
        full = _forward_rows(
            fit,
            P,
            sol,
            {param: np.ones(len(grid)), "shift_at": grid[:, 0], "shift_width": grid[:, 1]},
        )
        _same_rows(dynamics._shift_rows(fit.data, P, param, grid), full)
