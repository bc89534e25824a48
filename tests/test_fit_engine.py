"""pipeline.fit.engine and procedure: the fit's Jacobian and covariance against an
independent finite-difference Gauss–Newton covariance, and its values against the truth.

The records are made by ``pipeline.simulate.impact`` (adaptive DOP853, events) and
``pipeline.sensor_model.to_sensor`` (filter, noise), never by the fitter's forward model.
The reference covariance is the textbook one of weighted least squares at the optimum,

    C = (JᵀJ)⁻¹ · max(1, χ²/ν),

J the derivatives of the weighted residuals (y − m)/σ by central differences written
here (not the engine's analytic columns nor its forward differences), ν the samples less
the fitted parameters and baseline terms (Press et al., Numerical Recipes, 3rd ed.,
§15.4–15.5).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from _rig import GR_RIG as GR

from pipeline import Scene
from pipeline.errors import PipelineWarning
from pipeline.fit import fit_contact
from pipeline.sensor_model import to_sensor
from pipeline.simulate import impact

#: relative central-difference step of each parameter
_STEP = 1e-5


def _record(angle_deg, seed):
    scene = Scene(**GR, speed=0.6, angle_deg=angle_deg, mu=0.131, e=0.9)
    tangential = "none" if angle_deg == 0 else "mindlin"
    ideal = impact(scene, normal="hunt_crossley", tangential=tangential, samples=2001)
    rec = to_sensor(
        ideal,
        noise=0.004 * ideal.attrs["F_max"],
        rate=1e6 if angle_deg == 0 else 2e6,
        pre_trigger=4e-4,
        post_trigger=5e-4,
        seed=seed,
    )
    return scene, rec


def _fd_covariance(fit):
    """(JᵀJ)⁻¹·max(1, χ²_ν) with J of the fit's weighted data residuals by central
    differences in each varied parameter (its own scale: E* in Pa, t0 in s)."""
    problem, theta = fit.problem, fit.theta
    idx = [fit.names.index(n) for n in fit.vary]
    n = problem.n_data
    cols = []
    for i in idx:
        h = _STEP * (abs(theta[i]) if fit.names[i] != "t0" else fit.data.window.duration)
        up, down = theta.copy(), theta.copy()
        up[i] += h
        down[i] -= h
        r = problem.evaluate(np.stack([up, down]))[0][:, :n]
        cols.append((r[0] - r[1]) / (2 * h))
    J = np.column_stack(cols)
    r0 = problem.evaluate(theta[None, :])[0][0, :n]
    nu = n - len(idx) - problem.datas[0].n_nuisance
    return np.linalg.inv(J.T @ J) * max(1.0, float(r0 @ r0) / nu), float(r0 @ r0)


@pytest.mark.parametrize(
    "angle_deg, vary, truth_of",
    [
        (0.0, None, ("E_eff", "e")),
        (15.0, ("E_eff", "e", "mu", "t0"), ("E_eff", "e", "mu")),
    ],
    ids=["head-on", "oblique"],
)
def test_point_fit_covariance_is_the_finite_difference_one(angle_deg, vary, truth_of):
    """The exact point fit of a simulated record (head-on: E*, e, t0 on Fn; 15°: E*, e, μ,
    t0 on Fn and Ft): χ² at the optimum, the covariance and lmfit's standard errors and
    correlations as (JᵀJ)⁻¹·max(1, χ²_ν) from a central-difference Jacobian (module notes)
    — standard errors to 2e-5 of themselves, correlations to 2e-5 (the engine's forward
    differences of e and μ, steps 1e-6, are good to ~1e-6 of a column; the central
    differences here to ~(1e-5)²); and E*, e (μ) within four standard errors of the
    simulated truth."""
    scene, rec = _record(angle_deg, seed=7)
    kw = dict(systematics={}, diagnose=False, n_boot=0)
    if angle_deg == 0:
        kw["tangential"] = "none"
    else:
        kw["vary"] = vary
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)
        fit = fit_contact(rec, scene, **kw)
    assert fit.result.success and not fit.poor
    cov_fd, chi2 = _fd_covariance(fit)
    assert fit.chi2 == pytest.approx(chi2, rel=1e-12)
    se_fd = np.sqrt(np.diag(cov_fd))
    se = np.sqrt(np.diag(fit.cov))
    np.testing.assert_allclose(se, se_fd, rtol=2e-5)
    corr = fit.cov / np.outer(se, se)
    np.testing.assert_allclose(corr, cov_fd / np.outer(se_fd, se_fd), atol=2e-5)
    for j, name in enumerate(fit.vary):  # what lmfit's report shows is the same covariance
        par = fit.params[name]
        assert par.stderr == pytest.approx(se[j], rel=1e-12)
        for k, other in enumerate(fit.vary):
            if k != j:
                assert par.correl[other] == pytest.approx(corr[j, k], abs=1e-12)
    truth = {"E_eff": float(scene.E_eff), "e": 0.9, "mu": 0.131}
    for name in truth_of:
        j = fit.vary.index(name)
        z = (fit.theta[fit.names.index(name)] - truth[name]) / se[j]
        assert abs(z) < 4.0, (name, z)
