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
from pipeline.fit import engine, fit_contact
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


def _hermite(y, dy, step, k, th):
    """The cubic Hermite interpolant on step k at θ ∈ [0, 1] and its rate d/dτ, in the basis
    h00 = 2θ³ − 3θ² + 1, h10 = θ³ − 2θ² + θ, h01 = −2θ³ + 3θ², h11 = θ³ − θ² (Burden &
    Faires, Numerical Analysis, §3.4)."""
    y0, y1, d0, d1 = y[k], y[k + 1], dy[k], dy[k + 1]
    value = (
        (2 * th**3 - 3 * th**2 + 1) * y0
        + (th**3 - 2 * th**2 + th) * step * d0
        + (-2 * th**3 + 3 * th**2) * y1
        + (th**3 - th**2) * step * d1
    )
    rate = (
        (6 * th**2 - 6 * th) * y0 / step
        + (3 * th**2 - 4 * th + 1) * d0
        + (-6 * th**2 + 6 * th) * y1 / step
        + (3 * th**2 - 2 * th) * d1
    )
    return value, rate


def test_forces_between_the_nodes_are_the_hermite_cubic():
    """The forward model's true forces and their rates between the pulse's nodes: the
    cubic Hermite interpolant of the nodes' values and rates (basis written here), linear
    on a step flagged as holding a stick/slide switch, zero out of contact (before the
    onset, after τ_c); two pulses (e = 0.7, 0.95) on 16 steps, instants drawn at random in
    each step. Tolerance: 1e-12 of the peak force (rounding)."""
    from types import SimpleNamespace

    from pipeline.fit.forward import ForwardModel, Solution
    from pipeline.fit.pulse import normal_pulse

    n = 16
    pulse = normal_pulse("hunt_crossley", np.array([0.7, 0.95]), n)
    rng = np.random.default_rng(3)
    ft = rng.normal(size=pulse.f.shape)  # any node values and rates serve the interpolant
    dft = rng.normal(size=pulse.f.shape)
    kink = np.zeros(pulse.f.shape, dtype=bool)
    kink[0, 5] = kink[1, 11] = True
    sol = Solution(pulse, SimpleNamespace(ft=ft, dft=dft, kink=kink), np.array([0, 1]))
    steps = np.repeat(np.arange(n), 3)
    th = rng.uniform(size=(2, steps.size))
    tau = (steps[None, :] + th) * (pulse.tau_c[:, None] / n)
    before, after = np.full((2, 2), [-0.3, -1e-9]), pulse.tau_c[:, None] * [1.0 + 1e-9, 2.0]
    tau = np.concatenate([before, tau, after], axis=1)
    fn, ftt, rn, rt = ForwardModel("hunt_crossley", "mindlin")._true_forces(sol, tau, True, 2)
    peak = float(pulse.f.max())
    for c in range(2):
        step = pulse.tau_c[c] / n
        want_f, want_rf = _hermite(pulse.f[c], pulse.df[c], step, steps, th[c])
        want_t, want_rt = _hermite(ft[c], dft[c], step, steps, th[c])
        lin = kink[c, steps]
        rise = ft[c, steps + 1] - ft[c, steps]
        want_t = np.where(lin, ft[c, steps] + th[c] * rise, want_t)
        want_rt = np.where(lin, rise / step, want_rt)
        inner = slice(2, 2 + steps.size)
        np.testing.assert_allclose(fn[c, inner], np.maximum(want_f, 0.0), atol=1e-12 * peak)
        np.testing.assert_allclose(rn[c, inner], want_rf, atol=1e-12 * peak / step)
        np.testing.assert_allclose(ftt[c, inner], want_t, atol=1e-12 * peak)
        np.testing.assert_allclose(rt[c, inner], want_rt, atol=1e-12 * peak / step)
        for arr in (fn, ftt, rn, rt):  # out of contact
            assert np.all(arr[c, [0, 1, -2, -1]] == 0.0)


def _columns(data, scene, n):
    """``n`` columns of the 15° record's local parameters: the scene's E*, e = 0.9,
    μ = 0.131 and the window's start as t0, the rest as stated."""
    from pipeline.fit.forward import _I

    P = np.tile(data.nominal(), (n, 1))
    P[:, [_I["E_eff"], _I["e"], _I["mu"], _I["t0"]]] = [
        float(scene.E_eff),
        0.9,
        0.131,
        data.window.t_start,
    ]
    return P


def test_one_pass_weighting_and_kept_filters_are_the_plain_ones():
    """What an evaluation keeps or fuses gives the numbers of the plain computation. The
    residuals and their derivatives weighted in one pass (each channel's rows stacked,
    whitened by an AR(2) noise model and projected off the fitted baseline together)
    against :func:`~pipeline.fit.forward.weighted_residuals` of each alone, on the 15°
    record's Fn and Ft, to 1e-13 of each row's scale (the projection's matrix products
    round alike to ~1e-16); and the filtered samples of a force that ends, through the
    low-pass a record keeps for its later evaluations, against the sensor's own sections
    run over the force and the zeros after it, to 1e-13 of the peak, for the record's
    second-order low-pass and for the same record seen through a first- and a third-order
    one (:meth:`RecordData.with_sensor`; each asked for again after the others)."""
    import dataclasses

    from scipy.signal import sosfilt

    from pipeline.fit.forward import (
        _I,
        ForwardModel,
        _sampled,
        _weighted_with_derivatives,
        prepare,
        weighted_residuals,
    )
    from pipeline.fit.noise import NoiseModel

    scene, rec = _record(15.0, seed=3)
    data = prepare(rec, scene)
    ar = NoiseModel(np.array([0.6, -0.2]), 0.8)
    data = dataclasses.replace(
        data, channels=tuple(dataclasses.replace(c, noise=ar) for c in data.channels)
    )
    assert data.n_nuisance == 4 and data.sensor.filtered
    P = _columns(data, scene, 3)
    P[1, _I["e"]] += 1e-6
    P[2, _I["mu"]] += 1e-6
    model = ForwardModel()
    pred, der = model.predict(data, P, model.solve([data], [P])[0], 2)
    r, dr = _weighted_with_derivatives(data, pred, der)
    want_r = weighted_residuals(data, pred)
    want_dr = weighted_residuals(data, der, derivative=True)
    assert r.shape == want_r.shape and dr.shape == want_dr.shape
    np.testing.assert_allclose(r, want_r, rtol=0, atol=1e-13 * np.abs(want_r).max())
    scale = np.abs(want_dr).max(axis=-1, keepdims=True)
    assert np.all(np.abs(dr - want_dr) <= 1e-13 * scale)

    step = float(data.fine[1] - data.fine[0])
    first = data.with_sensor(dataclasses.replace(data.sensor, filter_order=1, notes=()))
    third = data.with_sensor(dataclasses.replace(data.sensor, filter_order=3, notes=()))
    x = np.random.default_rng(5).normal(size=(2, 403))
    for d in (data, first, third, data, first, third):
        for m in (403, 398):
            padded = np.concatenate([x[:, :m], np.zeros((2, 1500))], axis=1)
            want = sosfilt(d.sensor.sos(step), padded, axis=-1)[:, :: d.oversample]
            got = _sampled(d, step, d.sensor.bandwidth, x[:, :m], padded.shape[1])
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-13 * np.abs(want).max())


def _head_on_with_priors():
    """The head-on record's point fit with the default systematics (their prior rows)."""
    scene, rec = _record(0.0, seed=3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)
        return fit_contact(rec, scene, tangential="none", diagnose=False, n_boot=0)


def test_prior_rows_of_the_jacobian():
    """The Jacobian's rows of the inputs known to a tolerance (kept per problem): the row
    of prior k is 1/u_k in the column of parameter k where it varies, 0 elsewhere (module
    notes of pipeline.fit.engine), for one row of θ, for two, and for one again."""
    fit = _head_on_with_priors()
    problem = fit.problem
    assert problem.prior_index.size >= 3
    want = np.zeros((problem.prior_index.size, problem.vary.size))
    for row, (k, u) in enumerate(zip(problem.prior_index, problem.prior_sigma, strict=True)):
        if k in problem.vary:
            want[row, list(problem.vary).index(k)] = 1.0 / u
    assert np.count_nonzero(want) >= 3
    theta = np.stack([fit.theta, fit.theta])
    theta[1, problem.vary[0]] *= 1.001
    for rows in (theta[:1], theta, theta[1:]):
        r, J = problem.evaluate(rows, jacobian=True)
        assert J.shape == (rows.shape[0], problem.n_rows, problem.vary.size)
        for b in range(rows.shape[0]):
            np.testing.assert_array_equal(J[b, problem.n_data :], want)


def test_kept_gain_is_the_pseudo_inverse_of_the_jacobian_where_it_was_taken():
    """Problem.gain: K = (JᵀJ)⁻¹Jᵀ of the Jacobian at θ — after a fit, the one its
    covariance worked out and kept (the dynamics' bounds reuse it), at the optimum; at
    another θ, that point's — each against the normal equations' solution with the
    Jacobian there (prior rows included; its columns scaled to unit norm, their units
    differing by 10¹⁵), to 1e-8 of its largest entry per parameter; and a K handed to
    :meth:`keep_gain` is the one returned at its θ, never at another."""
    fit = _head_on_with_priors()
    problem = fit.problem
    assert problem.prior_index.size >= 1
    moved = fit.theta.copy()
    moved[problem.vary[0]] *= 1.01
    for theta in (fit.theta, moved, fit.theta):
        J = problem.evaluate(theta[None, :], jacobian=True)[1][0]
        K = problem.gain(theta)
        s = np.linalg.norm(J, axis=0)
        want = np.linalg.solve((J / s).T @ (J / s), (J / s).T) / s[:, None]
        assert K.shape == want.shape == (problem.vary.size, problem.n_rows)
        tol = 1e-8 * np.abs(want).max(axis=1, keepdims=True)
        assert np.all(np.abs(K - want) <= tol)
    # a K worked out elsewhere is kept with the Jacobian of its θ, and only there
    problem.residual(fit.theta)
    given = np.zeros((problem.vary.size, problem.n_rows))
    problem.keep_gain(fit.theta, given)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(engine, "_pseudo_inverse", _must_not_run)
        assert problem.gain(fit.theta) is given
    problem.keep_gain(moved, given)  # not the point last evaluated: nothing kept
    assert problem.gain(fit.theta) is given
    assert problem.gain(moved) is not given


def _must_not_run(J):
    raise AssertionError("the pseudo-inverse was worked out again")


def test_measured_axes_and_bandwidth_groups_are_the_sensor_formulas():
    """The measured forces and their analytic derivatives (E*, t0) of the 15° record's
    model (filtered: a linear map, so the axes mix before it as after it), under
    cross-talk matrices with a unit diagonal and without, gains of 1 and not, leaks of 0
    and not, against the sensor's formulas applied here to the model's forces on the true
    axes (no cross-talk, gains 1, leaks 0):
    Fn_meas = g_n·(C00·Fn + C01·Ft + leak_tn·Ft), Ft_meas = g_t·(C10·Fn + C11·Ft + leak·Fn),
    to 1e-13 of each row's scale — an evaluation leaves out the factors that are exactly 1,
    so a wrong one left out fails. Then the filtered model of columns at two bandwidths
    (the rows grouped by bandwidth) against each column alone (one bandwidth for every
    row), and the restitutions an evaluation refuses (> 1, NaN; below 1 for Hertz's law)."""
    import dataclasses

    from pipeline.errors import InputError
    from pipeline.fit.forward import _I, ForwardModel, prepare

    scene, rec = _record(15.0, seed=3)
    data = prepare(rec, scene)
    P0 = _columns(data, scene, 2)
    P0[1, _I["e"]] += 1e-3
    model = ForwardModel()
    analytic = ("E_eff", "t0")

    def measured(d, P):
        pred, der = model.predict(d, P, model.solve([d], [P])[0], 1, analytic)
        return pred, [x[0] for x in der]  # (C, n) per channel; (2, n) per channel

    plain = dataclasses.replace(data, sensor=dataclasses.replace(data.sensor, crosstalk=None))
    (fn, ft), (dfn, dft) = measured(plain, P0)
    unit_diag = np.array([[1.0, 0.004, -0.008], [-0.018, 1.0, 0.019], [0.004, 0.012, 1.0]])
    general = np.array([[0.97, 0.004, -0.008], [-0.018, 1.03, 0.019], [0.004, 0.012, 1.0]])
    for C in (None, unit_diag, general):
        for gains, leaks in (
            ((1.0, 1.0), (0.0, 0.0)),
            ((1.0, 0.98), (0.003, 0.0)),
            ((1.02, 1.0), (0.0, -0.002)),
            ((0.99, 1.01), (0.003, -0.002)),
        ):
            P = P0.copy()
            P[:, [_I["gain_n"], _I["gain_t"]]] = gains
            P[:, [_I["leak"], _I["leak_tn"]]] = leaks
            d = dataclasses.replace(data, sensor=dataclasses.replace(data.sensor, crosstalk=C))
            (gn, gt), (dgn, dgt) = measured(d, P)
            c = np.eye(2) if C is None else C[:2, :2]
            # (Fn, Ft) measured = M·(Fn, Ft) true, M the formulas' matrix
            M = np.array(
                [
                    [gains[0] * c[0, 0], gains[0] * (c[0, 1] + leaks[1])],
                    [gains[1] * (c[1, 0] + leaks[0]), gains[1] * c[1, 1]],
                ]
            )
            for i, got in enumerate(((gn, dgn), (gt, dgt))):
                for g, (a, b) in zip(got, ((fn, ft), (dfn, dft)), strict=True):
                    want = M[i, 0] * a + M[i, 1] * b
                    scale = np.abs(want).max(axis=-1, keepdims=True)
                    assert np.all(np.abs(g - want) <= 1e-13 * scale), (C, gains, leaks)

    P = P0.copy()
    P[1, _I["bandwidth"]] = 0.6 * P[0, _I["bandwidth"]]
    both = model.predict(data, P, model.solve([data], [P])[0])
    for k in range(2):
        alone = model.predict(data, P[k : k + 1], model.solve([data], [P[k : k + 1]])[0])
        for b, a in zip(both, alone, strict=True):
            np.testing.assert_allclose(b[k], a[0], rtol=0, atol=1e-13 * np.abs(a).max())
    for bad in (1.0 + 1e-9, np.nan):
        P = P0.copy()
        P[0, _I["e"]] = bad
        with pytest.raises(InputError, match="restitution"):
            model.solve([data], [P])
    with pytest.raises(InputError, match="only has e = 1"):  # the elastic law: e = 0.9
        ForwardModel("hertz").solve([data], [P0])


def test_ft_to_fn_leak_reaches_fn_with_and_without_a_modelled_filter():
    """The Ft → Fn leak (Fn_meas = g_n·(Fn + leak_tn·Ft), the sensor's formula) on the 15°
    record, its filter modelled and not (an infinite bandwidth: each channel's model at its
    own instants): Fn with leak_tn = 0.01 less Fn with none is 0.01·g_n·Ft, and Fn's
    derivative with respect to leak_tn is g_n·Ft at leak_tn = 0 (where a fit starts it),
    Ft the model's own at the same instants on the true axes, to 1e-13 of its peak. Without
    the filter the leak once moved Fn by nothing, and its derivative was zero: the fit could
    not see a leak the record showed."""
    import dataclasses

    from pipeline.fit.forward import _I, ForwardModel, prepare

    scene, rec = _record(15.0, seed=3)
    data = prepare(rec, scene)
    data = dataclasses.replace(data, sensor=dataclasses.replace(data.sensor, crosstalk=None))
    assert [c.name for c in data.channels] == ["Fn", "Ft"]
    assert np.array_equal(data.channels[0].t, data.channels[1].t)  # one clock: precondition
    model = ForwardModel()
    for bandwidth in (None, np.inf):
        P = _columns(data, scene, 1)
        P[:, _I["gain_n"]] = 1.02
        if bandwidth is not None:
            P[:, _I["bandwidth"]] = bandwidth
        sol = model.solve([data], [P])[0]
        (fn0, ft), (dfn, _) = model.predict(data, P, sol, 1, ("leak_tn",))
        P1 = P.copy()
        P1[:, _I["leak_tn"]] = 0.01
        fn1 = model.predict(data, P1, model.solve([data], [P1])[0])[0]
        scale = np.abs(ft).max()
        assert scale > 0.05 * np.abs(fn0).max()  # an Ft to leak: precondition
        tol = 1e-13 * max(scale, np.abs(fn0).max())
        np.testing.assert_allclose(fn1 - fn0, 0.01 * 1.02 * ft, rtol=0, atol=tol)
        np.testing.assert_allclose(dfn[0, 0], 1.02 * ft[0], rtol=0, atol=tol)


def test_an_ft_to_fn_leak_the_record_shows_is_fitted_without_a_modelled_filter():
    """A 15° record whose Fn carries 3 % of Ft (C01 = 0.03 of to_sensor's mixing matrix,
    the matrix not stated to the fit), with no filter (bandwidth inf: each channel's model
    at its own instants), fitted with a cross-talk uncertainty of 0.05: leak_tn comes out
    within 3 standard errors of 0.03, with a standard error well below the stated 0.05 (the
    record, not the prior, bounds it). The leak once never reached Fn there: leak_tn stayed
    at 0 ± 0.05 and E* took up the misfit."""
    scene = Scene(**GR, speed=0.6, angle_deg=15.0, mu=0.131, e=0.9)
    ideal = impact(scene, normal="hunt_crossley", tangential="mindlin", samples=2001)
    C = np.eye(3)
    C[0, 1] = 0.03
    rec = to_sensor(
        ideal,
        noise=0.004 * ideal.attrs["F_max"],
        rate=2e6,
        bandwidth=np.inf,
        crosstalk=C,
        pre_trigger=4e-4,
        post_trigger=5e-4,
        seed=1,
    )
    del rec.attrs["sensor_crosstalk_matrix"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)
        fit = fit_contact(rec, scene, systematics={"crosstalk": 0.05}, diagnose=False, n_boot=0)
    value, se = fit.values["leak_tn"], fit.stderr["leak_tn"]
    assert se < 0.02
    assert abs(value - 0.03) < 3 * se, (value, se)


def test_kept_parts_follow_the_columns_they_are_kept_for():
    """What an evaluation keeps per the values of the columns a fit seldom moves (mass,
    radius, time base, gains, bandwidth: RecordData._static) follows them: after the
    15° record's model at the stated values, the model with each of them moved gives what
    the record with nothing kept gives (to 1e-14 of the peak), and not the first
    model (by more than 1e-6 of it)."""
    import dataclasses

    from pipeline.fit.forward import _I, ForwardModel, prepare

    scene, rec = _record(15.0, seed=3)
    data = prepare(rec, scene)
    model = ForwardModel()
    P0 = _columns(data, scene, 2)
    P0[1, _I["e"]] += 1e-3

    def predict(d, P):
        return np.concatenate(model.predict(d, P, model.solve([d], [P])[0]), axis=1)

    first = predict(data, P0)
    for name, factor in (
        ("mass", 1.01),
        ("radius", 0.99),
        ("gain_n", 1.02),
        ("bandwidth", 0.8),
        ("time_base", None),
    ):
        P = P0.copy()
        if factor is None:
            P[:, _I[name]] = 1e-3
        else:
            P[:, _I[name]] *= factor
        got = predict(data, P)
        fresh = predict(dataclasses.replace(data), P)  # a record with nothing kept
        scale = np.abs(fresh).max()
        np.testing.assert_allclose(got, fresh, rtol=0, atol=1e-14 * scale, err_msg=name)
        assert np.abs(got - first).max() > 1e-6 * scale, name
