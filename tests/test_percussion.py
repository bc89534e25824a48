"""Percussions and restitution coefficients against closed forms.

- Elastic Hertz impact (exact history: pipeline.contact.hertz_pulse; Johnson, Contact
  Mechanics, CUP 1985, §11.4, doi:10.1017/CBO9781139171731; docs/theory.md, Compliant contact):
  Pn(t_c/2) = m*·v0, Pn(t_c) = 2·m*·v0, and every restitution coefficient is 1.
- Hunt–Crossley damped impact (Hunt & Crossley, J. Appl. Mech. 42:440, 1975,
  doi:10.1115/1.3423596), integrated here with solve_ivp, with c calibrated so that the
  exact energy integral c(1+e) = ln[(1+c)/(1−ce)] gives the requested e (docs/theory.md, Compliant
  contact):
  Poisson's, Newton's and Stronge's coefficients all equal e for a sphere (docs/theory.md,
  Restitution;
  Stronge, Proc. R. Soc. A 431:169, 1990, doi:10.1098/rspa.1990.0125).
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest
from _rig import GR_RIG
from scipy.integrate import solve_ivp

from pipeline.contact import calibrate_hunt_crossley_family, hertz_impact, hertz_pulse
from pipeline.errors import InputError, PipelineWarning, PoorFitWarning
from pipeline.percussion import (
    MIN_BANDWIDTH_PRODUCT,
    MIN_SAMPLES_PER_CONTACT,
    RESOLUTION_TOL,
    SOURCES,
    ResolutionWarning,
    adc_step,
    compression_split,
    cumulative_percussion,
    normal_work,
    percussions,
    resolution,
    restitution_energetic,
    restitution_newton,
    restitution_poisson,
)
from pipeline.record import make_record
from pipeline.scene import Scene
from pipeline.smooth import fit_window
from pipeline.window import find_contact

SCENE = Scene(
    radius=0.0127, density=7800.0, E=200e9, nu=0.3, target_E=200e9, target_nu=0.3, speed=0.5
)
IMPACT = hertz_impact(SCENE)
MV = IMPACT.m_eff * IMPACT.v0
T0 = 1.0e-3  # contact starts 1 ms into the record
MU = 0.3  # a sliding tangential force Ft = μ·Fn for the Pt checks


def hertz_record(n=200):
    h = IMPACT.t_c / n  # t_c/2 and t_c fall on samples
    t = T0 + np.arange(-10, n + 11) * h
    F = hertz_pulse(t - T0, IMPACT)["F"]
    return make_record(
        t,
        {"Fn": F, "Ft": MU * F},
        attrs={"source": "hertz_pulse", "format": "test", "kind": "simulated"},
    )


def fitted(window, **kw):
    with warnings.catch_warnings():
        # noise-free data: any polynomial's residuals are structured, and flagged as such
        warnings.simplefilter("ignore", PoorFitWarning)
        return fit_window(window, **kw)


@pytest.mark.parametrize(
    "fit_kw",
    [{"method": "spline"}, {"method": "polynomial", "degree": 8, "end_constraints": True}],
)
def test_hertz_percussions_from_fit_and_raw_samples(fit_kw):
    w = find_contact(hertz_record())
    p = percussions(w, fitted(w, **fit_kw))
    i_half = int(np.argmin(np.abs(p.time - (T0 + IMPACT.t_c / 2))))
    assert p.time[i_half] == pytest.approx(T0 + IMPACT.t_c / 2, abs=1e-15)
    for src in SOURCES:
        Pn = p.Pn(src)
        # zero at contact start up to the rounding of the sums behind it (SIMD order)
        assert Pn[0] == pytest.approx(0.0, abs=1e-12 * MV), src
        assert Pn[i_half] == pytest.approx(MV, rel=1e-3), src
        assert Pn[-1] == pytest.approx(2 * MV, rel=1e-3), src
        assert p.Pt(src)[-1] == pytest.approx(2 * MU * MV, rel=1e-3), src
    # the fit's exact antiderivative at t_c/2 itself, not only on the grid
    assert p.fit_n.antiderivative(T0 + IMPACT.t_c / 2) == pytest.approx(MV, rel=1e-3)
    assert p.disagreement_n < 1e-3 * p.Pn_total
    ds = p.to_dataset()
    assert ds["Pn_simpson"].attrs["units"] == "N s"


def test_hertz_restitution_is_one_every_way():
    w = find_contact(hertz_record())
    p = percussions(w, fitted(w, method="spline"))
    for src in SOURCES:
        s = compression_split(p, SCENE, source=src)
        assert s.method == "momentum"
        assert s.e_poisson == pytest.approx(1.0, abs=1e-3)
        assert s.e_newton == pytest.approx(1.0, abs=1e-3)
        assert s.e_energetic == pytest.approx(1.0, abs=1e-3)
        # maximum compression of the elastic pulse is at t_c/2, Pt there is μ·m*v0
        assert s.t_c == pytest.approx(T0 + IMPACT.t_c / 2, abs=1e-3 * IMPACT.t_c)
        assert s.Pt_c == pytest.approx(MU * MV, rel=1e-3)
        # energy: W_c = m*v0²/2 (all kinetic energy of approach stored)
        assert s.W_c == pytest.approx(0.5 * IMPACT.m_eff * IMPACT.v0**2, rel=1e-12)
    # without mass and speed: the closure estimate (mean Pn = m*·v0 over the contact). The
    # window of a simulated record may end one sample past the contact (whether the sample
    # at t_c counts as inside is a matter of rounding), which moves the mean Pn by up to
    # (h/t_c)·2m*v0: the tolerance is two samples of 200
    s = compression_split(p)
    assert s.method == "closure"
    assert s.Pn_c == pytest.approx(MV, rel=2 / 200)
    assert s.e_poisson == pytest.approx(1.0, abs=2 * 2 / 200)
    assert np.isnan(s.e_newton)
    # with the mass alone, closure estimates the approach speed
    s = compression_split(p, m=IMPACT.m_eff)
    assert s.v_n0 == pytest.approx(IMPACT.v0, rel=2 / 200) and not s.v_n0_given
    # the documented peak-of-Fn fallback warns; for elastic contact it is exact
    with pytest.warns(PipelineWarning, match="peak of Fn"):
        s = compression_split(p, method="peak_force")
    assert s.t_c == pytest.approx(T0 + IMPACT.t_c / 2, abs=2e-3 * IMPACT.t_c)
    assert s.e_poisson == pytest.approx(1.0, abs=1e-3)


def hunt_crossley_record(e, n=400):
    """Integrate m*·δ'' = −K·δ^{3/2}(1 + c·δ'/v0) to separation; sample n + 1 points."""
    c = float(calibrate_hunt_crossley_family(e))
    K, m, v0 = IMPACT.K, IMPACT.m_eff, IMPACT.v0

    def rhs(_, y):
        d = max(y[0], 0.0)
        return [y[1], -K * d**1.5 * (1.0 + c * y[1] / v0) / m]

    def separated(_, y):
        return y[0]

    separated.terminal = True
    separated.direction = -1
    sol = solve_ivp(
        rhs,
        (0.0, 10 * IMPACT.t_c),
        [0.0, v0],
        method="DOP853",
        rtol=1e-12,
        atol=[1e-9 * IMPACT.delta_max, 1e-9 * v0],
        events=separated,
        dense_output=True,
    )
    t_f = float(sol.t_events[0][0])
    v_out = -float(sol.y_events[0][0][1])
    t = np.linspace(0.0, t_f, n + 1)
    d, dd = sol.sol(t)
    d = np.maximum(d, 0.0)
    F = np.maximum(K * d**1.5 * (1.0 + c * dd / v0), 0.0)
    F[0] = F[-1] = 0.0
    rec = make_record(
        T0 + t,
        {"Fn": F, "Ft": MU * F},
        attrs={"source": "hunt_crossley ODE", "format": "test", "kind": "simulated"},
    )
    return rec, v_out / v0, sol


@pytest.mark.parametrize("e", [0.5, 0.8])
def test_hunt_crossley_restitution_poisson_newton_energetic(e):
    rec, e_ode, sol = hunt_crossley_record(e)
    assert e_ode == pytest.approx(e, abs=1e-6)  # the calibration and the ODE agree
    w = find_contact(rec)
    p = percussions(w, fitted(w, method="spline"))
    for src in SOURCES:
        s = compression_split(p, SCENE, source=src)
        assert s.e_poisson == pytest.approx(e, abs=1e-3), src
        assert s.e_newton == pytest.approx(e, abs=1e-3), src
        assert s.e_energetic == pytest.approx(e, abs=1e-3), src
        assert s.Pn_f == pytest.approx((1 + e) * MV, rel=1e-3)
    # maximum compression where the ODE's approach rate vanishes
    s = compression_split(p, SCENE)
    t_grid = np.linspace(0.0, sol.t[-1], 20001)
    t_cmax = t_grid[np.argmin(np.abs(sol.sol(t_grid)[1]))]  # dense output: δ' = 0
    assert s.t_c - T0 == pytest.approx(t_cmax, abs=2e-3 * IMPACT.t_c)
    # closure (no mass, no speed): the approach returns to zero at separation
    s = compression_split(p)
    assert s.e_poisson == pytest.approx(e, abs=1e-3)
    # the peak of Fn comes before maximum compression when damped: e_P biased upward
    with pytest.warns(PipelineWarning):
        s = compression_split(p, method="peak_force")
    assert s.t_c - T0 < t_cmax
    assert s.e_poisson > e + 0.01


def test_scene_contradicting_the_impulse_falls_back_with_warning():
    w = find_contact(hertz_record())
    p = percussions(w, fitted(w, method="spline"))
    heavy = SCENE.replace(density=3 * 7800.0)  # m*·v0 above the record's whole impulse
    with pytest.warns(PipelineWarning, match="never reached"):
        s = compression_split(p, heavy)
    assert s.method == "closure"
    with pytest.raises(InputError, match="never reaches"):
        compression_split(p, heavy, method="momentum")


def test_coefficient_functions_closed_forms():
    # Pn_c = m v0 = 2, Pn_f = (1 + e) m v0 with e = 0.6, m = 0.5 kg, v0 = 4 m/s
    m, v0, e = 0.5, 4.0, 0.6
    assert restitution_poisson(2.0, 3.2) == pytest.approx(e)
    assert restitution_newton(3.2, m, v0) == pytest.approx(e)
    assert restitution_energetic(3.2, m, v0) == pytest.approx(e)
    # W(m v0) = m v0²/2 = 4 J (kinetic energy of approach); W(Pn_f) − W_c = −e²·4 J
    assert normal_work(2.0, m, v0) == pytest.approx(4.0)
    assert normal_work(3.2, m, v0) - 4.0 == pytest.approx(-(e**2) * 4.0)


def test_cumulative_percussion_pads_zero_ends_and_integrates_exactly():
    # F = 6·(t − 1)(2 − t) on [1, 2] s: ∫ = 1 N·s; Simpson is exact for a parabola
    t = np.linspace(1.0, 2.0, 11)[1:-1]
    F = 6.0 * (t - 1.0) * (2.0 - t)
    cum = cumulative_percussion(t, F, method="simpson", t_start=1.0, t_end=2.0)
    tp, P = cum["time"].values, cum.values
    assert cum.attrs["units"] == "N s"
    assert tp[0] == 1.0 and tp[-1] == 2.0
    assert P[-1] == pytest.approx(1.0, rel=1e-12)
    exact = 3.0 * (tp - 1.0) ** 2 - 2.0 * (tp - 1.0) ** 3
    np.testing.assert_allclose(P, exact, atol=1e-12)
    P = cumulative_percussion(t, F, method="trapezoid", t_start=1.0, t_end=2.0).values
    assert P[-1] == pytest.approx(1.0 - 1.0 / 100.0, rel=1e-12)  # trapezoid error h²/12·∫F''


def test_digitised_channels_on_their_own_instants():
    # WebPlotDigitizer-like: Fn at 41 points, Ft at 29 other points inside the contact;
    # each channel is integrated on its own points (padded with F = 0 at the window ends)
    # and put on the common grid. Sparse points: docs/theory.md, Compliant contact totals within
    # 3e-3.
    tn = np.linspace(0.0, IMPACT.t_c, 41)
    tt = np.linspace(0.0, IMPACT.t_c, 31)[1:-1] + 0.7e-6
    tu = np.union1d(tn, tt)
    Fn = np.interp(tu, tn, hertz_pulse(tn, IMPACT)["F"])
    Ft = np.interp(tu, tt, MU * hertz_pulse(tt, IMPACT)["F"], left=np.nan, right=np.nan)
    rec = make_record(
        tu,
        {"Fn": Fn, "Ft": Ft},
        measured={"Fn": np.isin(tu, tn), "Ft": np.isin(tu, tt)},
        attrs={"source": "d.csv", "format": "wpd", "kind": "digitised"},
    )
    w = find_contact(rec)
    p = percussions(w, fitted(w, method="spline"))
    assert p.time.size == tu.size
    for src in SOURCES:
        assert p.Pn(src)[-1] == pytest.approx(2 * MV, rel=3e-3), src
        assert p.Pt(src)[-1] == pytest.approx(2 * MU * MV, rel=3e-3), src
    assert p.disagreement_n < 3e-3 * p.Pn_total
    assert p.disagreement_t < 3e-3 * p.Pt_total
    s = compression_split(p, SCENE)
    assert s.e_poisson == pytest.approx(1.0, abs=3e-3)
    assert s.Pt_c == pytest.approx(MU * MV, rel=3e-3)


def test_summaries_are_strict_json():
    import json

    w = find_contact(hertz_record())  # simulated: noise not estimated (NaN)
    fits = fitted(w, method="polynomial", degree=6, end_constraints=True)
    p = percussions(w, fits)
    s = compression_split(p)  # no mass, no speed: e_newton NaN
    for part in (w.summary(), fits.Fn.summary(), p.summary(), s.summary()):
        json.dumps(part, allow_nan=False)  # NaN would raise ValueError
    assert s.summary()["e_newton"] is None
    assert w.summary()["noise_N"]["Fn"] is None
    assert s.summary()["method"] == "closure"


# ------------------------------------------------------------------ resolution (stability maps)
# A Garland–Rogers-like impact (Garland & Rogers 2009): 25.4 mm steel ball on a steel cap, 15°,
# Mindlin contact with a tangential reversal, through the sensor model without cross-talk.
GR = Scene(
    **GR_RIG,
    speed=0.6,
    angle_deg=15.0,
    mu=0.131,
    e=0.9,
)


@pytest.fixture(scope="module")
def gr_ideal():
    from pipeline.simulate import impact

    return impact(GR)


def _resolve(record, **kw):
    """find_contact → percussions (the spline, which follows the pulse) → resolution."""
    w = find_contact(record)
    return resolution(w, percussions(w), record=record, **kw)


def _sensor(ideal, **kw):
    from pipeline.sensor_model import to_sensor

    kw = {"seed": 3, "crosstalk": 0.0, **kw}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the sensor model's saturation warning is not ours
        return to_sensor(ideal, **kw)


def test_noise_error_is_the_trapezoid_weights_closed_form_and_matches_monte_carlo():
    # uniform samples: trapezoid weights dt inside, dt/2 at the two ends, so
    # sd(P_f) = σ·dt·√(n − 3/2) for n samples (no padded ends: the window spans the samples)
    rng = np.random.default_rng(0)
    n, dt, sigma = 201, 0.5e-6, 3.0
    t = T0 + np.arange(n) * dt
    clean = hertz_pulse(t - T0, IMPACT)["F"]
    ends = []
    for _ in range(400):
        rec = make_record(
            t,
            {"Fn": clean + sigma * rng.standard_normal(n)},
            attrs={"source": "mc", "format": "test", "kind": "digitised"},
        )
        ends.append(cumulative_percussion(t, rec["Fn"].values).values[-1])
    mc = np.std(ends, ddof=1)
    want = sigma * dt * np.sqrt(n - 1.5)
    # 400 draws: the sample sd is within 3·(1/√(2·399)) ≈ 11 % of the true sd
    assert mc == pytest.approx(want, rel=0.11)
    # a digitised record's window spans its samples and estimates no noise: give it σ
    w = dataclasses.replace(find_contact(rec), noise={"Fn": sigma})
    p = percussions(w, fitted(w, method="spline"))
    res = resolution(w, p, scale=(1.0, 1.0), warn=False)
    assert res.noise_error["Fn"] == pytest.approx(want, rel=1e-12)


def test_adc_step_finds_the_grid_of_quantised_and_printed_values():
    rng = np.random.default_rng(1)
    q = 5000.0 / 2**12
    codes = rng.integers(-300, 300, 500)
    assert adc_step(codes * q + 0.0) == pytest.approx(q, rel=1e-9)
    # every other code only: the smallest gap is 2q and the grid 2q
    assert adc_step(2 * codes * q) == pytest.approx(2 * q, rel=1e-9)
    # gaps of 2q and 3q only: the grid is q (the smallest gap over 2)
    vals = np.cumsum(np.tile([2, 3], 50)) * q
    assert adc_step(vals) == pytest.approx(q, rel=1e-9)
    # a column printed with three decimals
    assert adc_step(np.round(rng.normal(0, 10, 300), 3)) == pytest.approx(1e-3, rel=1e-6)
    assert adc_step(rng.normal(0, 10, 300)) == 0.0  # continuous values: no grid
    assert adc_step([1.0, 2.0]) == 0.0  # fewer than three distinct values


def test_a_clean_dense_record_is_in_no_failure_region(gr_ideal):
    res = _resolve(_sensor(gr_ideal, noise=0.5))
    assert res.ok and not res.flags
    assert res.n_samples["Fn"] > 200
    assert res.bandwidth_product > 3.0 and res.adc_error["Ft"] < 0.02


def test_sparse_sampling_is_flagged(gr_ideal):
    t_c = gr_ideal.attrs["t_contact"]
    rate = 12 / t_c  # 12 samples over the contact, ~14 in the window around it
    rec = _sensor(gr_ideal, noise=0.5, rate=rate, pre_trigger=40 / rate, post_trigger=80 / rate)
    with pytest.warns(ResolutionWarning, match="sparse sampling: Fn has 1[2-5] samples"):
        res = _resolve(rec)
    assert "sparse sampling" in res.flags and res.n_samples["Fn"] < MIN_SAMPLES_PER_CONTACT


def test_noise_is_flagged_when_three_sd_exceed_the_tolerance(gr_ideal):
    with pytest.warns(ResolutionWarning, match=r"noise: .*Ft: sd\(P_f\)"):
        res = _resolve(_sensor(gr_ideal, noise=40.0))
    # 3 % of F_max on Ft (≈ 0.1·Fn): the tangential percussion's sd is several per cent
    assert res.noise_error["Ft"] > RESOLUTION_TOL / 3 > res.noise_error["Fn"]


def test_a_stated_narrow_bandwidth_is_flagged(gr_ideal):
    t_c = gr_ideal.attrs["t_contact"]
    with pytest.warns(ResolutionWarning, match="filter bandwidth: the stated bandwidth"):
        res = _resolve(_sensor(gr_ideal, noise=0.5, bandwidth=1.0 / t_c))
    # the filter's tail lengthens the window: f_c·(t_e − t_s) a little above 1
    assert 1.0 < res.bandwidth_product < MIN_BANDWIDTH_PRODUCT


def test_a_coarse_undithered_adc_is_flagged_a_dithered_one_is_noise(gr_ideal):
    with pytest.warns(ResolutionWarning, match="coarse ADC: Ft steps by 19.53 N"):
        res = _resolve(_sensor(gr_ideal, bits=8, noise=0.5))
    assert res.adc_step["Ft"] == pytest.approx(5000.0 / 2**8, rel=1e-9)
    # noise of several steps dithers the converter: no ADC flag (the noise check decides)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ResolutionWarning)
        res = _resolve(_sensor(gr_ideal, bits=8, noise=60.0))
    assert "coarse ADC" not in res.flags and "noise" in res.flags


def test_a_curved_baseline_is_flagged_a_linear_drift_is_not(gr_ideal):
    rec = _sensor(gr_ideal, noise=0.5, drift=(2e5, -1e5, 0.0))
    res = _resolve(rec)  # a linear drift: removed exactly, nothing to flag
    assert res.ok and res.baseline_error["Fn"] < 1e-3
    t = rec["time"].values
    u = (t - 0.5 * (t[0] + t[-1])) / (0.5 * (t[-1] - t[0]))
    bent = rec.copy()
    bent["Ft"] = rec["Ft"] + 10.0 * u**2  # 10 N at the record's ends, 0 mid-record
    bent["Ft"].attrs = dict(rec["Ft"].attrs)
    with pytest.warns(ResolutionWarning, match="curved baseline: Ft"):
        res = _resolve(bent)
    assert res.baseline_error["Ft"] > RESOLUTION_TOL / 3


def test_a_fit_off_the_samples_is_a_poor_fit_not_a_record_flag(gr_ideal):
    # the seed's quartic cannot follow the tangential reversal of a dense Mindlin record
    w = find_contact(_sensor(gr_ideal, noise=0.5))
    p = percussions(w, fitted(w, method="polynomial", degree=4))
    with pytest.warns(PoorFitWarning, match="fitted curve: .*Ft: .* misses the pulse"):
        res = resolution(w, p)
    assert "fit off the samples" in res.fit_flags and res.ok
    assert res.fit_departure["Ft"] > RESOLUTION_TOL / 2


def test_adc_step_is_the_greatest_common_step_of_the_values():
    """A quantised smooth pulse leaves gaps of several steps (5q, 16q, ...) whose smallest
    is not the step; continuous values lie on no grid."""
    from pipeline.percussion import adc_step

    q = 5000.0 / 2**16
    t = np.linspace(0.0, 1.0, 200)
    F = np.round(1300.0 * np.sin(np.pi * t) ** 1.5 / q) * q
    assert np.diff(np.unique(F)).min() > 2 * q  # the smallest gap is not the step here
    assert adc_step(F) == pytest.approx(q, rel=1e-9)
    assert adc_step(np.round(np.linspace(0.0, 7.0, 50), 1)) == pytest.approx(0.1, rel=1e-9)
    rng = np.random.default_rng(0)
    assert adc_step(rng.normal(size=500)) == 0.0
