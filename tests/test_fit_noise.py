"""The fit's noise model and baseline basis against their definitions.

The noise model (pipeline.fit.noise) is the Yule–Walker AR fit of the pre-trigger samples
(Durbin 1960, doi:10.2307/1401322; Ljung & Box 1978, doi:10.1093/biomet/65.2.297): its
autocorrelations are the biased sample estimates Σ x_k x_{k+j} / Σ x_k² of the centred
samples, and an AR(1) series φ·n_{k−1} + ε_k is recovered to its sampling error √((1 − φ²)/n).
"""

from __future__ import annotations

import numpy as np
import pytest

from pipeline import Scene
from pipeline.fit.forward import baseline_basis, prepare
from pipeline.fit.noise import measure_noise
from pipeline.sensor_model import to_sensor
from pipeline.simulate import impact


def _ar1(phi, n, seed):
    rng = np.random.default_rng(seed)
    e = rng.normal(size=n + 200)
    x = np.zeros_like(e)
    for k in range(1, e.size):
        x[k] = phi * x[k - 1] + e[k]
    return x[200:]  # the start-up transient dropped


def test_an_ar1_noise_is_measured_to_its_sampling_error():
    n, phi = 4000, 0.6
    x = _ar1(phi, n, seed=4)
    model = measure_noise(x)
    assert model.phi.size >= 1
    assert model.phi[0] == pytest.approx(phi, abs=4 * np.sqrt((1 - phi**2) / n))
    c = x - x.mean()
    assert model.lag1 == pytest.approx(float(c[:-1] @ c[1:]) / float(c @ c), rel=1e-12)
    assert model.innovation == pytest.approx(np.sqrt(1 - phi**2), rel=0.05)


def test_white_or_constant_noise_is_white():
    white = measure_noise(np.random.default_rng(2).normal(size=2000))
    assert white.white and white.ljung_box_p >= 0.01
    const = measure_noise(np.full(500, 3.0))
    assert const.white and const.n == 500


def test_the_baseline_basis_is_orthonormal_and_spans_offset_and_drift():
    t = 1.5e-3 + np.arange(301) * 1e-6  # instants far from 0, as a record's are
    B = baseline_basis(t)
    np.testing.assert_allclose(B.T @ B, np.eye(2), rtol=0, atol=1e-12)
    line = 4.0 - 2.0e3 * t  # any offset and drift [N] is projected out
    np.testing.assert_allclose(line - B @ (B.T @ line), 0.0, rtol=0, atol=1e-12 * 4.0)


def _sensor_record(**options):
    scene = Scene(radius=0.0127, density=7800.0, E=200e9, nu=0.3, speed=0.6, angle_deg=0.0)
    ideal = impact(scene, normal="hertz", tangential="none", samples=1001)
    return scene, to_sensor(ideal, rate=1e6, pre_trigger=4e-4, post_trigger=3e-4, **options)


def _pre_trigger(data, rec):
    """The samples a channel's noise is measured on: those before the contact less a tenth
    of its duration."""
    t, f = rec["time"].values, rec["Fn"].values
    win = data.window
    pre = t < win.t_start - 0.1 * win.duration
    return t[pre], f[pre]


def test_the_noise_is_measured_on_the_pre_trigger_samples_less_their_least_squares_line():
    scene, rec = _sensor_record(noise=2.0, seed=3)
    data = prepare(rec, scene, channels=("Fn",))
    t, f = _pre_trigger(data, rec)
    A = np.column_stack([np.ones(t.size), t])
    expected = measure_noise(f - A @ np.linalg.lstsq(A, f, rcond=None)[0])
    model = data.channels[0].noise
    assert model.n == expected.n > 64
    assert model.lag1 == pytest.approx(expected.lag1, rel=1e-9)
    assert model.ljung_box_p == pytest.approx(expected.ljung_box_p, rel=1e-9)
    np.testing.assert_allclose(model.phi, expected.phi, rtol=1e-9)


def test_pre_trigger_samples_on_one_adc_level_show_white_noise():
    """A noise-free record whose pre-trigger lies on one converter level: nothing to measure
    (the rounding of its line's fit is no correlated noise). Seeded: unseeded, to_sensor
    draws the sensor's cross-talk afresh, and some draws clip Ft (refused)."""
    scene, rec = _sensor_record(noise=0.0, bits=16, full_scale=5000.0, seed=3)
    data = prepare(rec, scene, channels=("Fn",))
    _, f = _pre_trigger(data, rec)
    assert f.size > 64 and np.ptp(f) == 0.0  # the precondition: one level
    assert data.channels[0].noise.white
