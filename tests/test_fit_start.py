"""The fit's starting values: μ from the plateau of Ft/Fn (pipeline.percussion.mu_plateau)
against its definition, and the fit's start read from its own samples against the window's
record (pipeline.percussion.estimate_mu)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from _rig import GR_RIG as GR

from pipeline import Scene
from pipeline.errors import PipelineWarning
from pipeline.fit.contact import _mu_start
from pipeline.fit.forward import prepare
from pipeline.percussion import estimate_mu, mu_plateau
from pipeline.sensor_model import to_sensor
from pipeline.simulate import impact


def test_mu_plateau_is_the_sliding_ratio_not_the_stuck_one():
    """A pulse Fn = sin(πt/T) whose first 30 % slides (Ft = μ·Fn, Coulomb's law with
    equality) and then sticks (Ft/Fn falling to 0.2·μ): the plateau before maximum
    compression (T/2) is μ, the stuck samples skipped; the ratio on another clock (Ft's
    instants between Fn's) reads the same through the interpolation."""
    mu, T = 0.23, 1e-4
    t = np.linspace(0.0, T, 401)
    fn = np.sin(np.pi * t / T)
    ratio = np.where(t < 0.3 * T, mu, mu * np.interp(t, [0.3 * T, 0.5 * T], [1.0, 0.2]))
    assert mu_plateau(t, fn, t, ratio * fn, 0.5 * T) == pytest.approx(mu, rel=1e-12)
    tt = t[:-1] + 0.5 * (t[1] - t[0])  # Ft between Fn's samples
    fn_t = np.sin(np.pi * tt / T)
    rt = np.where(tt < 0.3 * T, mu, 0.2 * mu)
    # linear interpolation of a sine on 400 steps: relative error ≤ (π/400)²/8 ≈ 8e-6
    assert mu_plateau(t, fn, tt, rt * fn_t, 0.5 * T) == pytest.approx(mu, rel=1e-4)
    assert np.isnan(mu_plateau(t, fn, t, mu * fn, -1.0))  # no sample before t_c


@pytest.mark.parametrize(("angle", "mu"), [(45.0, 0.10), (15.0, 0.131)])
def test_fit_mu_start_reads_the_window_record(angle, mu):
    """The fit's starting μ comes from its own samples inside the window (the record less
    the window's baselines) without cutting the window's record: the same number as
    estimate_mu on that record, for a record that slides throughout and one that sticks."""
    sc = Scene(**GR, speed=0.6, angle_deg=angle, mu=mu, e=0.9)
    # no cross-talk: the start then unmixes nothing, and reads the plateau itself
    rec = to_sensor(impact(sc, samples=2001), crosstalk=np.eye(3), seed=11)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)
        data = prepare(rec, sc)
    w = data.window
    t_c = w.t_start + 0.45 * w.duration
    m = estimate_mu(w, t_c)
    assert 0.5 * mu < m < 1.5 * mu  # a sensible plateau, the case this test is about
    assert _mu_start(data, t_c) == pytest.approx(m, rel=1e-12)
