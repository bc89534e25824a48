"""Thornton's elastic–perfectly-plastic law against its closed forms.

References: C. Thornton, "Coefficient of restitution for collinear collisions of
elastic-perfectly plastic spheres", J. Appl. Mech. 64:383 (1997), doi:10.1115/1.2787319
(the law, eqs. for δ_y, F_y, R_p, δ_p, v_y and e); K. L. Johnson, Contact Mechanics, CUP
(1985), §6.2 (first yield at p_0 = 1.60 Y) and §11.4 (ρV_Y²/Y ≈ 26 (Y/E*)⁴),
doi:10.1017/CBO9781139171731. The expected numbers are the papers' formulas written out
here, or an integration of the law written here from the paper, never the library's output.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

from pipeline import Scene, contact
from pipeline.errors import InputError

# a 6 mm WC ball on a glass flat (handbook constants), p_y = 1 GPa
WC_ON_GLASS = Scene(
    radius=3e-3, density=15630.0, E=600e9, nu=0.22, target_E=72e9, target_nu=0.23, speed=0.5
)
P_Y = 1e9


def _paper(p_y, E, R):
    """δ_y, F_y and the plastic slope of Thornton (1997) written out: p_0 = (2E*/π)√(δ/R*)
    reaches p_y at δ_y; F_y = (4/3)E*√R*·δ_y^{3/2}; beyond, dF/dδ = π·p_y·R*."""
    d_y = R * (math.pi * p_y / (2 * E)) ** 2
    return d_y, 4 / 3 * E * math.sqrt(R) * d_y**1.5, math.pi * p_y * R


def _paper_unloading(F_max, F_y, d_max, p_y, E):
    """Thornton's unloading radius and permanent approach from (δ_max, F_max)."""
    R_p = 4 * E / (3 * F_max) * ((2 * F_max + F_y) / (2 * math.pi * p_y)) ** 1.5
    return R_p, d_max - (3 * F_max / (4 * E * math.sqrt(R_p))) ** (2 / 3)


def _integrate_rebound(v0, p_y, E, R, m, dense=False):
    """e, δ_max, F_max of one impact at v0, integrated from the paper's law (loading to the
    turning point, then the unloading curve from the (δ_max, F_max) reached); with
    ``dense``, also t_c and δ(t)."""
    d_y, F_y, k = _paper(p_y, E, R)

    def load(d):
        return 4 / 3 * E * math.sqrt(R) * d**1.5 if d <= d_y else F_y + k * (d - d_y)

    def turn(t, y):
        return y[1]

    turn.terminal, turn.direction = True, -1
    t_scale = (m * v0 * v0 / (4 / 3 * E * math.sqrt(R))) ** 0.4 / v0
    opts = dict(method="DOP853", rtol=1e-12, atol=[1e-18, 1e-15])
    first = solve_ivp(
        lambda t, y: [y[1], -load(max(y[0], 0.0)) / m], (0, 50 * t_scale), [0, v0],
        events=turn, dense_output=dense, **opts,
    )  # fmt: skip
    d_max = float(first.y[0, -1])
    F_max = load(d_max)
    R_p, d_p = _paper_unloading(F_max, F_y, d_max, p_y, E) if d_max > d_y else (R, 0.0)

    def unload(d):
        z = d - d_p
        return 4 / 3 * E * math.sqrt(R_p) * math.copysign(abs(z) ** 1.5, z)

    def lets_go(t, y):
        return unload(y[0])

    lets_go.terminal, lets_go.direction = True, -1
    second = solve_ivp(
        lambda t, y: [y[1], -unload(y[0]) / m], (first.t[-1], 50 * t_scale), first.y[:, -1],
        events=lets_go, dense_output=dense, **opts,
    )  # fmt: skip
    assert second.status == 1
    e = -float(second.y[1, -1]) / v0
    if not dense:
        return e, d_max, F_max
    t_m = first.t[-1]

    def delta(t):
        return np.where(
            t <= t_m, first.sol(np.minimum(t, t_m))[0], second.sol(np.maximum(t, t_m))[0]
        )

    return e, d_max, F_max, float(second.t[-1]), delta


def _wc():
    s = WC_ON_GLASS
    return float(s.E_eff), float(s.R_eff), float(s.m_eff)


def test_yield_point_against_the_paper():
    E, R, m = _wc()
    d_y, F_y, _ = _paper(P_Y, E, R)
    assert contact.yield_approach(P_Y, E, R) == pytest.approx(d_y, rel=1e-14)
    assert contact.yield_force(P_Y, E, R) == pytest.approx(F_y, rel=1e-14)
    # Thornton's F_y = π³p_y³R*²/(6E*²), a closed form in p_y alone
    assert contact.yield_force(P_Y, E, R) == pytest.approx(
        math.pi**3 * P_Y**3 * R**2 / (6 * E**2), rel=1e-13
    )
    # ½m*v_y² = (8/15)E*√R*·δ_y^{5/2}; for a sphere on a flat Thornton's eq. 16:
    # v_y = 1.56 (p_y⁵/(E*⁴ρ))^{1/2} (1.56 rounded from √(2.4352) = 1.5605)
    v_y = contact.yield_velocity(P_Y, E, R, m)
    assert 0.5 * m * v_y**2 == pytest.approx(8 / 15 * E * math.sqrt(R) * d_y**2.5, rel=1e-13)
    rho = WC_ON_GLASS.density
    assert v_y == pytest.approx(1.56 * math.sqrt(P_Y**5 / (E**4 * rho)), rel=5e-4)
    assert contact.yield_pressure(v_y, E, R, m) == pytest.approx(P_Y, rel=1e-13)


def test_johnson_first_yield_speed_of_steel():
    """Johnson §11.4: a sphere striking a flat of the same material first yields at
    ρV_Y²/Y ≈ 26 (Y/E*)⁴, with p_0 = 1.60 Y (§6.2); 26 is Johnson's rounding of
    (4/5π)(0.8π)⁵ = 25.5."""
    Y = 1.0e9  # a medium-hard steel
    s = Scene(radius=0.01, density=7850.0, E=210e9, nu=0.3, target_E=210e9, target_nu=0.3,
              speed=1.0)  # fmt: skip
    v = contact.yield_velocity(contact.yield_onset_pressure(Y), s.E_eff, s.R_eff, s.m_eff)
    assert s.density * v**2 / Y == pytest.approx(26 * (Y / s.E_eff) ** 4, rel=0.025)
    assert 0.05 < v < 0.2  # "about 0.1 m/s for medium-hard steel"


def test_loading_is_continuous_with_its_slope_at_the_yield_point():
    E, R, _ = _wc()
    d_y, F_y, k = _paper(P_Y, E, R)
    eps = 1e-9 * d_y
    below, at, above = (
        contact.thornton(d, d, P_Y, E, R) for d in (d_y - eps, d_y, d_y + eps)
    )  # loading: δ = δ_max
    assert at == pytest.approx(F_y, rel=1e-13)
    assert (at - below) / eps == pytest.approx(k, rel=1e-6)
    assert (above - at) / eps == pytest.approx(k, rel=1e-6)
    # past it the force is linear with slope π p_y R*
    d = np.array([2.0, 5.0, 40.0]) * d_y
    assert contact.thornton(d, d, P_Y, E, R) == pytest.approx(F_y + k * (d - d_y), rel=1e-13)


def test_unloading_curve_against_the_paper():
    E, R, _ = _wc()
    d_y, F_y, k = _paper(P_Y, E, R)
    d_max = 12.0 * d_y
    F_max = F_y + k * (d_max - d_y)
    R_p, d_p = _paper_unloading(F_max, F_y, d_max, P_Y, E)
    u = contact.thornton_unloading(d_max, P_Y, E, R)
    assert (u.F_max, u.R_p, u.delta_p) == pytest.approx((F_max, R_p, d_p), rel=1e-12)
    assert u.R_p > R and 0 < u.delta_p < d_max
    # the unloading curve leaves (δ_max, F_max) and lets go at δ_p
    d = np.array([d_max, 0.5 * (d_p + d_max), d_p, 0.5 * d_p])
    F = contact.thornton(d, d_max, P_Y, E, R)
    assert F[0] == pytest.approx(F_max, rel=1e-12)
    assert F[1] == pytest.approx(4 / 3 * E * math.sqrt(R_p) * (d[1] - d_p) ** 1.5, rel=1e-12)
    assert F[2] == pytest.approx(0.0, abs=1e-12 * F_max) and F[3] == 0.0
    # below the yield point nothing is permanent: unloading retraces Hertz
    e = contact.thornton_unloading(0.5 * d_y, P_Y, E, R)
    assert (e.R_p, e.delta_p) == pytest.approx((R, 0.0), abs=1e-15)


@pytest.mark.parametrize(
    "ratio, e_table",
    [(3.29, 0.8463), (6.59, 0.7262), (13.18, 0.6164), (26.36, 0.5207), (52.72, 0.4388)],
)
def test_restitution_against_v_over_vy(ratio, e_table):
    """e against v/v_y from Thornton's closed form (1997, eq. 27), as tabulated by
    integrating the law for a 6 mm WC ball on glass at p_y = 1 GPa (v_y = 0.091 m/s): the
    table's v/v_y carries 3–4 digits, so the tolerance is what rounding v/v_y by 0.005
    moves e by (de/d(v/v_y) from the closed form itself at that point), plus the table's
    last digit; and the law integrated here from the paper gives the same e."""
    e = contact.cor_thornton(1 / ratio)
    slope = abs(contact.cor_thornton(1 / (ratio + 1e-3)) - e) / 1e-3
    assert e == pytest.approx(e_table, abs=0.005 * slope + 5e-5)
    E, R, m = _wc()
    v_y = contact.yield_velocity(P_Y, E, R, m)
    assert _integrate_rebound(ratio * v_y, P_Y, E, R, m)[0] == pytest.approx(e, abs=1e-8)
    assert contact.calibrate_thornton(e) == pytest.approx(1 / ratio, rel=1e-10)


def test_restitution_limits_and_calibration():
    # e = 1 up to the yield speed, and de/dr = 0 there (the loss grows as (1 − r)²)
    assert contact.cor_thornton([1.0, 2.0, 50.0]) == pytest.approx([1.0, 1.0, 1.0])
    r = 1 - np.array([1e-2, 1e-3])
    loss = 1 - contact.cor_thornton(r)
    assert loss[0] / loss[1] == pytest.approx(100.0, rel=0.02)
    # high speed: e ∝ (v_y/v)^{1/4}
    lo = contact.cor_thornton(np.array([1e-8, 1e-6]))
    assert lo[1] / lo[0] == pytest.approx(100**0.25, rel=1e-6)
    e = np.linspace(0.05, 1.0, 96)
    assert contact.cor_thornton(contact.calibrate_thornton(e)) == pytest.approx(e, abs=1e-14)
    law = contact.NORMAL_LAWS["thornton"]
    assert law.calibrate(0.73) == pytest.approx(contact.calibrate_thornton(0.73))
    assert law.material_to_param(0.1, 1e9, 1e-3, 0.5) == pytest.approx(0.2)  # v_y/v0
    for bad in (0.0, 1.2, -0.1):
        with pytest.raises(InputError, match=r"reaches every e in \(0, 1\]"):
            contact.calibrate_thornton(bad)
    with pytest.raises(InputError, match="yield pressure"):
        contact.yield_approach(-1.0, 1e11, 1e-3)


def test_energy_balance_is_the_plastic_work():
    """½m*v0²(1 − e²) is the area between the loading and unloading curves (the plastic
    work), and the simulator's W_damping is that work."""
    s = WC_ON_GLASS.replace(speed=6.59 * 0.0911, e=None, mu=0.0, angle_deg=0.0)
    E, R, m = _wc()
    v0 = float(s.v_n0)
    e, d_max, F_max = _integrate_rebound(v0, P_Y, E, R, m)
    d_y, F_y, k = _paper(P_Y, E, R)
    R_p, d_p = _paper_unloading(F_max, F_y, d_max, P_Y, E)
    tight = dict(epsabs=0.0, epsrel=1e-13, limit=200)
    work_in = quad(lambda d: contact.thornton(d, d, P_Y, E, R), 0, d_max, points=[d_y], **tight)[0]
    work_back = quad(lambda d: 4 / 3 * E * math.sqrt(R_p) * (d - d_p) ** 1.5, d_p, d_max, **tight)[
        0
    ]
    assert work_in == pytest.approx(0.5 * m * v0**2, rel=1e-10)
    # (the integrated e carries its ODE's ~1e-9, times 2e/(1 − e²) ≈ 3 in 1 − e²)
    assert work_in - work_back == pytest.approx(0.5 * m * v0**2 * (1 - e**2), rel=1e-7)
    r = contact.yield_velocity(P_Y, E, R, m) / v0
    e_closed = contact.cor_thornton(r)
    assert work_in - work_back == pytest.approx(0.5 * m * v0**2 * (1 - e_closed**2), rel=1e-11)
    from pipeline.simulate import impact

    sim = impact(s.replace(mu=0.0), "thornton", "none", param=r, rtol=1e-11)
    assert sim.attrs["e_n"] == pytest.approx(e, abs=1e-8)
    assert sim.attrs["W_damping"] == pytest.approx(work_in - work_back, rel=1e-7)
    assert sim.attrs["delta_max"] == pytest.approx(d_max, rel=1e-8)
    assert sim.attrs["F_max"] == pytest.approx(F_max, rel=1e-8)


# ------------------------------------------------------------------ the fit
def test_master_curve_is_the_integrated_law():
    """The fit's Thornton pulse (closed-form phases, no table) against the dimensionless
    impact integrated here from the paper's law, at e on both sides of the old tables'
    nodes: x and f within 1e-9 of δ* and of the peak, duration within 1e-9, rebound −u = e."""
    from pipeline.fit.pulse import normal_pulse

    e = np.array([0.137, 0.42, 0.73, 0.9, 0.995])
    p = normal_pulse("thornton", e, 128)
    assert -p.u[:, -1] == pytest.approx(e, abs=1e-12)
    for k, ek in enumerate(e):
        # unit K, m*, v0: v_y = r, p_y from δ_y = (5r²/4)^{2/5} with E* = 3/4, R* = 1
        r = contact.calibrate_thornton(ek)
        d_y = (1.25 * r * r) ** 0.4
        p_y = 2 * 0.75 / math.pi * math.sqrt(d_y)
        assert contact.yield_velocity(p_y, 0.75, 1.0, 1.0) == pytest.approx(r, rel=1e-12)
        e_int, d_max, F_max, t_c, delta = _integrate_rebound(1.0, p_y, 0.75, 1.0, 1.0, True)
        assert e_int == pytest.approx(ek, abs=1e-9)
        assert p.tau_c[k] == pytest.approx(t_c, rel=1e-9)
        tau = np.arange(129) * p.tau_c[k] / 128
        assert p.x[k] == pytest.approx(delta(tau), abs=1e-9 * d_max)
        # the force at the nodes: the law at the pulse's own (δ, δ_max)
        dm = np.where(tau <= p.tau_c[k] - _unloading_time(p, k), p.x[k], d_max)
        F = contact.thornton(p.x[k], dm, p_y, 0.75, 1.0)
        assert p.f[k] == pytest.approx(F, abs=1e-9 * F_max)


def _unloading_time(p, k):
    """Time from the pulse's turning point (u = 0) to its end, from its nodes."""
    j = int(np.argmax(p.u[k] < 0))
    tau = np.arange(p.u.shape[1]) * p.tau_c[k] / (p.u.shape[1] - 1)
    frac = p.u[k, j - 1] / (p.u[k, j - 1] - p.u[k, j])  # u crosses zero in step j − 1
    return p.tau_c[k] - (tau[j - 1] + frac * (tau[j] - tau[j - 1]))


def test_fit_recovers_a_plastic_contact():
    """A Thornton record (pipeline.simulate.impact, DOP853 at rtol 1e-10, seen through
    to_sensor's filter, noise and ADC; a normal impact, so that only Fn is fitted and the
    test stays quick) fitted with the law: the 95 % intervals hold E*, e and the yield
    pressure and speed the record was made with; the default law's fit names the plastic
    law (normal_law) and the impulse it contradicts (impulse_mismatch)."""
    import warnings

    from pipeline import fit_contact
    from pipeline.errors import PipelineWarning
    from pipeline.sensor_model import to_sensor
    from pipeline.simulate import impact

    s = WC_ON_GLASS.replace(speed=0.6, mu=None, e=None)
    E, R, m = _wc()
    v0 = float(s.v_n0)
    v_y = contact.yield_velocity(P_Y, E, R, m)
    sim = impact(s, "thornton", "none", param=v_y / v0, samples=4001, rtol=1e-10)
    rec = to_sensor(sim, noise=0.3, seed=11)
    told = s
    fit = fit_contact(rec, told, normal="thornton", tangential="none", n_boot=50)
    ci = fit.ci()
    truth = {"E_eff": E, "e": sim.attrs["e_n"], "p_y": P_Y, "v_y": v_y}
    for name, value in truth.items():
        assert ci[name][0] <= value <= ci[name][1], (name, value, ci[name])
    assert fit.verdict["ok"] and fit.verdict["causes"] == []
    assert fit.ci()["p_y"][1] - fit.ci()["p_y"][0] < 0.1 * P_Y
    # the yield pressure follows e one-to-one at the fitted E*, speed and ball
    r = contact.calibrate_thornton(fit.values["e"])
    v_fit = fit.values["speed"] * math.cos(math.radians(float(s.angle_deg)))
    assert fit.values["v_y"] == pytest.approx(r * v_fit, rel=1e-9)
    # (a flat target: R* and m* are the fitted ball's radius and mass)
    p_fit = contact.yield_pressure(
        r * v_fit, fit.values["E_eff"], fit.values["radius"], fit.values["mass"]
    )
    assert fit.values["p_y"] == pytest.approx(p_fit, rel=1e-9)
    row = fit.summary()["parameters"]["p_y"]
    assert row["derived"] and row["unit"] == "Pa" and row["ci95"] == pytest.approx(ci["p_y"])
    assert "yield pressure, implied" in fit.report()
    # the human table: the yield point with the contact parameters, p_y in GPa (issue 21)
    table = fit.table()
    assert list(table.index) == ["E_eff", "e", "p_y", "v_y"]
    assert table.loc["p_y", "unit"] == "GPa" and table.loc["v_y", "unit"] == "m/s"
    value, _, sigma = table.loc["p_y", "value"].partition(" ± ")
    assert abs(float(value) * 1e9 - row["value"]) <= 0.5 * 10 ** -len(value.split(".")[1]) * 1e9
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)
        default = fit_contact(rec, told, tangential="none", n_boot=0)
    assert {"normal_law", "impulse_mismatch"} <= set(default.verdict["causes"])
    # the default law's model spread is wide, and its intervals stay where E* and e can be
    # (E* > 0, e ≤ 1; docs/uncertainty.md) and hold the truth
    (E_lo, E_hi), (e_lo, e_hi) = default.ci()["E_eff"], default.ci()["e"]
    assert 0 < E_lo <= E <= E_hi and e_lo <= truth["e"] <= e_hi <= 1.0
    assert min(default.alternatives, key=lambda k: default.alternatives[k]["aic"]) == "thornton"
    assert default.verdict["impulse"]["Pn"]["e_impulse"] == pytest.approx(truth["e"], abs=0.03)


def test_a_campaign_holds_the_yield_speed_constant():
    """Three normal Thornton impacts of one ball at 0.3, 0.6 and 1.2 m/s (p_y = 1 GPa, so
    one yield speed v_y = 0.086 m/s and e falling with speed, Thornton's eq. 27) fitted
    jointly with the material constant held (``damping="constant_alpha"``): ``alpha`` is
    then v_y, recovered within its interval, and read as v_y in m/s — not Hunt–Crossley's
    α in s/m — in the table, the report, the summary, a campaign's Dataset and its
    report's table (pipeline.precision.reads_as)."""
    import json
    import warnings

    import xarray as xr

    from pipeline import fit_campaign
    from pipeline._json import json_ready
    from pipeline.campaigns import joint
    from pipeline.errors import PipelineWarning
    from pipeline.sensor_model import to_sensor
    from pipeline.simulate import impact
    from pipeline.tables import joint_table

    E, R, m = _wc()
    v_y = contact.yield_velocity(P_Y, E, R, m)
    recs, scenes = [], []
    for i, v in enumerate((0.3, 0.6, 1.2)):
        s = WC_ON_GLASS.replace(speed=v, mu=None, e=None)
        sim = impact(s, "thornton", "none", param=v_y / v, samples=4001, rtol=1e-10)
        recs.append(to_sensor(sim, noise=0.3, seed=40 + i))
        scenes.append(s)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)
        fit = fit_campaign(
            recs, scenes, normal="thornton", tangential="none", damping="constant_alpha",
            hypotheses="one",
        )  # fmt: skip
    lo, hi = fit.ci()["alpha"]
    assert lo <= v_y <= hi and hi - lo < 0.05 * v_y
    row = fit.table().loc["alpha"]
    assert (row["quantity"], row["unit"]) == ("v_y", "m/s")
    assert "v_y constant" in fit.table().attrs["verdict"]
    assert fit.summary()["parameters"]["alpha"]["unit"] == "m/s"
    assert any(ln.split()[0] == "alpha" and " m/s " in ln for ln in fit.report().splitlines())
    # a campaign's Dataset and its report (the joint fit as pipeline.campaigns stores it)
    jf = json_ready({
        "records": ["a", "b", "c"],
        "normal": fit.model.normal,
        "hypothesis": {"mu_law": "constant", "damping": "constant_alpha"},
        "values": dict(fit.values),
        "stderr": dict(fit.stderr),
        "compare": fit.compare().to_dict("records"),
    })  # fmt: skip
    ds = xr.Dataset()
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(joint, "joint_fit", lambda tasks, ds, **kw: jf)
        ds = joint.with_joint_fit(ds, [])
    assert ds["joint_alpha"].attrs["units"] == "m/s" and ds["joint_E_eff"].attrs["units"] == "Pa"
    assert json.loads(ds.attrs["joint_fit_json"])["normal"] == "thornton"
    shown = joint_table(ds).loc["alpha"]
    assert (shown["quantity"], shown["unit"]) == ("v_y", "m/s")


def test_calibration_starts_newton_within_1e7_of_the_root():
    """calibrate_thornton's start (the cubic Hermite interpolant of its table of r against
    √(1 − e), linear where 1 − e < 1e-6) lies within 1e-7 of the root — so that one Newton
    step reaches rounding — and its result is the root, to 1e-12: both against r found by
    Brent's method on the closed form (cor_thornton) to 1e-15."""
    from scipy.optimize import brentq

    from pipeline.contact.plastic import _cor_start

    e = np.concatenate([np.linspace(0.05, 0.999, 60), 1.0 - np.geomspace(1e-9, 1e-4, 6)])
    root = np.array(
        [brentq(lambda r, x=x: float(contact.cor_thornton(r)) - x, 1e-12, 1.0, xtol=1e-16,
                rtol=1e-15) for x in e]
    )  # fmt: skip
    start = _cor_start(np.sqrt(1.0 - e))
    close = 1.0 - e > 1e-6  # where 1 − e carries ten digits and more
    assert np.all(np.abs(start - root)[close] <= 1e-7 * root[close])
    assert np.all(np.abs(start - root)[~close] <= 1e-5 * root[~close])
    got = contact.calibrate_thornton(e)
    assert np.all(np.abs(got - root)[close] <= 1e-12 * root[close])
