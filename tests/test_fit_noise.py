"""The fit's noise model and baseline basis against their definitions.

The noise model (pipeline.fit.noise) is the Yule–Walker AR fit of the pre-trigger samples
(Durbin 1960, doi:10.2307/1401322; Ljung & Box 1978, doi:10.1093/biomet/65.2.297): its
autocorrelations are the biased sample estimates Σ x_k x_{k+j} / Σ x_k² of the centred
samples, and an AR(1) series φ·n_{k−1} + ε_k is recovered to its sampling error √((1 − φ²)/n).
"""

from __future__ import annotations

import numpy as np
import pytest

from pipeline.fit.forward import baseline_basis
from pipeline.fit.noise import measure_noise


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
