"""The misspecification suite's record generator (benchmarks/_misspec.py) against closed forms.

The generator integrates impacts and builds sensor records without the project's simulator
or sensor model; these checks hold it to answers that do not come from its own code:
Johnson's elastic Hertz impact, Chung & Ooi's published benchmark, the exact Hunt–Crossley
energy relation, Coulomb's sliding and sticking percussions, the conservation laws of a
frictionless elastic ball on a curved cap, the Butterworth filter's DC gain and delay, and
the noise models' correlations.
"""

import math

import numpy as np
import pytest

from benchmarks import _misspec as M
from pipeline import Scene
from pipeline.simulate import impact as simulate_impact

STEEL, GLASS = M.MATERIALS["steel"], M.MATERIALS["glass"]
RIGID = M.Material(math.inf, 0.0, 1.0)


def _mass(mat, R):
    return mat.density * 4.0 / 3.0 * math.pi * R**3


@pytest.mark.parametrize(("R_cap", "v"), [(math.inf, 0.6), (0.04, 2.0)])
def test_elastic_hertz_closed_forms(R_cap, v):
    # Johnson, Contact Mechanics (CUP 1985) §11.4, doi:10.1017/CBO9781139171731:
    # δ_max = (15 m v0²/(16 E* √R*))^{2/5}, F_max = K δ_max^{3/2}, t_c = 2.943275 δ_max/v0,
    # and an elastic rebound returns Pn = 2 m v0
    R = 0.006
    imp = M.impact(GLASS, R, STEEL, R_cap, v, 0.0, 0.0, 1.0, normal="hertz", tangential="coulomb")
    m = _mass(GLASS, R)
    E_eff = 1.0 / ((1 - GLASS.nu**2) / GLASS.E + (1 - STEEL.nu**2) / STEEL.E)
    R_eff = 1.0 / (1.0 / R + 1.0 / R_cap)
    d_max = (15 * m * v * v / (16 * E_eff * math.sqrt(R_eff))) ** 0.4
    assert imp.delta_max == pytest.approx(d_max, rel=1e-6)
    assert imp.F_max == pytest.approx(4 / 3 * E_eff * math.sqrt(R_eff) * d_max**1.5, rel=1e-6)
    assert imp.t_contact == pytest.approx(2.943275 * d_max / v, rel=1e-6)
    assert imp.Pn_final == pytest.approx(2 * m * v, rel=1e-6)
    assert imp.e_n == pytest.approx(1.0, abs=1e-6)


def test_chung_ooi_aluminium_sphere_on_rigid_plane():
    # Chung & Ooi, Granular Matter 13:643 (2011), doi:10.1007/s10035-011-0277-0, test 2:
    # an aluminium-alloy sphere (R = 0.1 m, E = 70 GPa, ν = 0.30, 2699 kg/m³) on a rigid
    # plane at 0.2 m/s: F_max 11.37 kN, t_c 732 µs, δ_max 49.7 µm (to their printed digits)
    al = M.Material(70e9, 0.30, 2699.0)
    imp = M.impact(
        al, 0.1, RIGID, math.inf, 0.2, 0.0, 0.0, 1.0, normal="hertz", tangential="coulomb"
    )
    assert imp.F_max == pytest.approx(11.37e3, abs=0.006e3)
    assert imp.t_contact == pytest.approx(732e-6, abs=0.6e-6)
    assert imp.delta_max == pytest.approx(49.7e-6, abs=0.06e-6)


@pytest.mark.parametrize("law", ["hunt_crossley", "hertz_dashpot", "viscoelastic"])
@pytest.mark.parametrize("e", [0.5, 0.7, 0.95])
def test_calibrated_restitution_is_reproduced(law, e):
    # the rebound speed and the normal percussion Pn = (1 + e)·m·v0 of the integrated
    # impact give back the e the damping was calibrated to
    v, a = 1.3, 25.0
    imp = M.impact(STEEL, 0.01, GLASS, math.inf, v, a, 0.25, e, normal=law)
    v0 = v * math.cos(math.radians(a))
    assert imp.e_n == pytest.approx(e, abs=1e-6)
    assert imp.Pn_final == pytest.approx((1 + e) * _mass(STEEL, 0.01) * v0, rel=1e-6)


@pytest.mark.parametrize("ratio", [1.5, 6.59, 40.0])
def test_thornton_records_against_the_papers_closed_forms(ratio):
    # Thornton, J. Appl. Mech. 64:383 (1997), doi:10.1115/1.2787319: with r = v_y/v0,
    # e = √(6√3/5)·√(1 − r²/6)·[r/(r + 2√(6/5 − r²/5))]^{1/4} (eq. 27); the loading stores
    # ½m·v0² = (2/5)K·δ_y^{5/2} + F_y·(δ_m − δ_y) + ½·π·p_y·R*·(δ_m − δ_y)² at the turning
    # point (Hertz to δ_y, then linear); and Pn = (1 + e)·m·v0
    r, v, a = 1.0 / ratio, 1.3, 25.0
    imp = M.impact(STEEL, 0.01, GLASS, math.inf, v, a, 0.25, None, normal="thornton", law_param=r)
    e = math.sqrt(6 * math.sqrt(3) / 5) * math.sqrt(1 - r * r / 6)
    e *= (r / (r + 2 * math.sqrt(6 / 5 - r * r / 5))) ** 0.25
    m, v0 = _mass(STEEL, 0.01), v * math.cos(math.radians(a))
    E_eff = 1.0 / ((1 - GLASS.nu**2) / GLASS.E + (1 - STEEL.nu**2) / STEEL.E)
    K = 4 / 3 * E_eff * math.sqrt(0.01)
    d_y = (1.25 * m * (r * v0) ** 2 / K) ** 0.4  # ½m·v_y² = (2/5)K·δ_y^{5/2}
    k = 1.5 * K * math.sqrt(d_y)  # π·p_y·R*: the Hertz tangent at δ_y
    x = imp.delta_max - d_y
    assert imp.e_n == pytest.approx(e, abs=1e-6)
    assert 0.4 * K * d_y**2.5 + K * d_y**1.5 * x + 0.5 * k * x * x == pytest.approx(
        0.5 * m * v0 * v0, rel=1e-5
    )
    assert imp.F_max == pytest.approx(K * d_y**1.5 + k * x, rel=1e-5)
    assert imp.Pn_final == pytest.approx((1 + e) * m * v0, rel=1e-6)
    assert M.calibrate("thornton", e) == pytest.approx(r, rel=1e-6)


@pytest.mark.parametrize("e", [0.5, 0.8, 0.99])
def test_hunt_crossley_damping_solves_the_exact_relation(e):
    # c(1 + e) = ln[(1 + c)/(1 − c·e)] (docs/theory.md, "Damping"); Hunt & Crossley's own
    # guess 3(1 − e)/2 is the small-damping limit of it
    c = M.hunt_crossley_c(e)
    assert c * (1 + e) == pytest.approx(math.log((1 + c) / (1 - c * e)), rel=1e-12)
    if e > 0.95:
        assert c == pytest.approx(1.5 * (1 - e), rel=0.02)


def test_coulomb_sliding_and_sticking_percussions():
    # rigid-body Coulomb friction (Routh; docs/theory.md): Pt = μ·Pn while the contact
    # point slides throughout; when the slip stops, Pt = m·v_t0/(1 + 1/κ) = (2/7)·m·v_t0
    R, v, mu, e = 0.004, 2.0, 0.2, 0.8
    m = _mass(STEEL, R)
    slide = M.impact(STEEL, R, STEEL, math.inf, v, 70.0, mu, e, tangential="coulomb")
    assert slide.Pt_final == pytest.approx(mu * slide.Pn_final, rel=1e-6)
    stick = M.impact(STEEL, R, STEEL, math.inf, v, 10.0, mu, e, tangential="coulomb")
    v_t0 = v * math.sin(math.radians(10.0))
    assert stick.Pt_final == pytest.approx(2 / 7 * m * v_t0, rel=1e-6)
    assert stick.Pt_final < 0.9 * mu * stick.Pn_final  # it did stop slipping


def test_frictionless_elastic_ball_over_a_cap_conserves_energy_and_momentum():
    # central force about the cap's centre: the angular momentum m·r·w is conserved and,
    # elastic, so is the kinetic energy; the line of centres turns by ≈ w·t_c/(R + R_cap)
    R, R_cap, v, a = 0.005, 0.02, 2.5, 75.0
    kw = dict(normal="hertz", tangential="coulomb")
    imp = M.impact(STEEL, R, STEEL, R_cap, v, a, 0.0, 1.0, turning_normal=True, **kw)
    v_n0, v_t0 = v * math.cos(math.radians(a)), v * math.sin(math.radians(a))
    assert imp.w_end == pytest.approx(v_t0, rel=1e-8)  # r is R + R_cap at both ends
    assert math.hypot(imp.e_n * v_n0, imp.w_end) == pytest.approx(v, rel=1e-8)
    assert imp.theta_end == pytest.approx(v_t0 * imp.t_contact / (R + R_cap), rel=2e-3)
    # the centripetal term (the ball tends to leave a convex cap) shortens the contact and
    # weakens the normal percussion against the fixed-frame integration, by about
    # (v_t0²/(R + R_cap))/(v_n0/t_c) ≈ 1 %, the order of the centripetal over the contact
    # acceleration
    flat = M.impact(STEEL, R, STEEL, R_cap, v, a, 0.0, 1.0, **kw)
    ratio = (v_t0**2 / (R + R_cap)) / (v_n0 / flat.t_contact)
    assert 0.02 * ratio < 1 - imp.t_contact / flat.t_contact < ratio
    assert 0.02 * ratio < 1 - imp.Pn_final / flat.Pn_final < ratio


@pytest.mark.parametrize(
    ("law", "angle", "R_cap"),
    [
        ("hunt_crossley", 15.0, math.inf),
        ("hunt_crossley", 35.0, 0.03),
        ("viscoelastic", 25.0, 0.05),
    ],
)
def test_the_control_is_the_fitters_model(law, angle, R_cap):
    # not a closed form: an independent integration of the same model. The control case
    # (Hunt–Crossley, Mindlin with the total-displacement rule, the contact frame fixed)
    # must be what pipeline.simulate integrates — and the fitter assumes — or the control
    # would test something else; the two integrators agree to ~1e-8 of F_max
    scene = Scene(
        radius=0.005, density=GLASS.density, E=GLASS.E, nu=GLASS.nu, target_E=STEEL.E,
        target_nu=STEEL.nu, target_radius=R_cap, speed=1.0, angle_deg=angle, mu=0.2, e=0.7,
    )  # fmt: skip
    sim = simulate_impact(scene, normal=law, samples=2001)
    ours = M.impact(GLASS, 0.005, STEEL, R_cap, 1.0, angle, 0.2, 0.7, normal=law)
    fn, ft = ours.forces(sim.time.values)
    np.testing.assert_allclose(fn, sim.Fn.values, rtol=0, atol=1e-6 * ours.F_max)
    np.testing.assert_allclose(ft, sim.Ft.values, rtol=0, atol=1e-6 * ours.F_max)
    assert ours.t_contact == pytest.approx(sim.attrs["t_contact"], rel=1e-6)


def test_sensor_chain_gain_delay_and_mixing():
    # the digital Butterworth has unit DC gain, so each channel's integral is the mixed
    # percussion, and a 2nd-order one delays a slow pulse's centroid by √2/(2π f_c)
    imp = M.impact(STEEL, 0.008, STEEL, math.inf, 0.5, 30.0, 0.2, 0.8)
    mix = np.array([[1.02, 0.0, 0.0], [0.03, 0.99, 0.0], [-0.006, 0.0, 1.0]])
    fc = 5.0 / imp.t_contact
    rig = M.Rig(rate=2e6, bandwidth=fc, filter_order=2, mixing=mix, noise=0.0, bits=0)
    t, f, t0 = M.measure(imp, rig, np.random.default_rng(0), phase=0.2e-6)
    assert t0 == pytest.approx(rig.pre + 0.2e-6, rel=1e-12)
    P = np.array([imp.Pn_final, imp.Pt_final, 0.0])
    got = np.array([np.trapezoid(f[k], t) for k in ("Fn", "Ft", "Fy")])
    np.testing.assert_allclose(got, mix @ P, rtol=0, atol=1e-5 * imp.Pn_final)
    tt = np.linspace(0.0, imp.t_contact, 20001)
    fn_true = imp.forces(tt)[0]
    centroid_true = t0 + np.trapezoid(tt * fn_true, tt) / np.trapezoid(fn_true, tt)
    centroid = np.trapezoid(t * f["Fn"], t) / np.trapezoid(f["Fn"], t)
    delay = math.sqrt(2.0) / (2 * math.pi * fc)
    assert centroid - centroid_true == pytest.approx(delay, rel=0.01)


def test_noise_models():
    # AR(1): lag-1 autocorrelation φ (standard error √((1 − φ²)/n)); 1/f: spectral slope −1
    rng = np.random.default_rng(1)
    n = 2**15
    for kind in ("white", "ar1", "pink"):
        z = M.coloured_noise(n, kind, rng)
        assert z.std() == pytest.approx(1.0, abs=0.05)
    z = M.coloured_noise(n, "ar1", rng, phi=0.9)
    r1 = np.corrcoef(z[:-1], z[1:])[0, 1]
    assert r1 == pytest.approx(0.9, abs=5 * math.sqrt((1 - 0.81) / n))
    z = M.coloured_noise(n, "pink", rng)
    f = np.fft.rfftfreq(n)[1:]
    p = np.abs(np.fft.rfft(z)[1:]) ** 2
    edges = np.logspace(np.log10(f[0]), np.log10(f[-1]), 20)
    k = np.digitize(f, edges)
    fb = np.array([f[k == i].mean() for i in range(1, 20) if np.any(k == i)])
    pb = np.array([p[k == i].mean() for i in range(1, 20) if np.any(k == i)])
    slope = np.polyfit(np.log(fb), np.log(pb), 1)[0]
    assert slope == pytest.approx(-1.0, abs=0.1)


@pytest.mark.parametrize("name", list(M.CASES))
def test_cases_are_reproducible_and_complete(name):
    case = M.CASES[name]
    rec, truth, told = case.make(3)
    again = case.make(3)[0]
    scale = float(np.abs(rec.Fn.values).max())
    for ch in ("Fn", "Ft", "Fy"):
        np.testing.assert_allclose(again[ch].values, rec[ch].values, rtol=0, atol=1e-12 * scale)
    assert rec.attrs["kind"] == "sensor"
    assert set(truth) >= {"E_eff", "e", "mu", "kt_scale", "speed", "t0"}
    lowest = 0.4 if name.startswith("plastic") else 0.5  # plastic: e from the drawn v/v_y
    assert lowest <= truth["e"] <= 0.95 and 0.1 <= truth["mu"] <= 0.4
    # 50–500 samples per elastic contact time; a damped contact lasts within ~25 % of it
    assert 0.75 * 50 <= truth["rate"] * truth["t_contact"] <= 1.25 * 500
    assert set(case.causes) <= set(M.CAUSES)
    assert told["scene"].mu is None and told["scene"].e is None
    assert told["scene"].E_eff == pytest.approx(truth["E_eff"], rel=1e-12)
    speed_ratio = told["scene"].speed / truth["speed"]
    want = 0.02 if name == "speed_off" else abs(truth["told_errors"]["speed"])
    assert abs(speed_ratio - 1) == pytest.approx(want, abs=1e-12)


def test_told_inputs_carry_errors_at_the_fitters_default_tolerances():
    """What the lab tells is off by draws at the standard uncertainties the fitter assumes
    when told nothing (pipeline.fit.systematics.DEFAULT_SYSTEMATICS): over 400 draws each
    relative error's standard deviation is its tolerance within the sampling error of a
    standard deviation (±4/√(2·400) ≈ 14 %)."""
    from pipeline.fit.systematics import BANDWIDTH_STATED
    from pipeline.fit.systematics import DEFAULT_SYSTEMATICS as D

    assert M.TOLD_U == {
        "speed": D["speed"],
        "mass": D["mass"],
        "radius": D["radius"],
        "gain": D["gain_n"],
        "bandwidth": BANDWIDTH_STATED,
    }
    assert D["gain_t"] == D["gain_n"]
    draws = [M._told("control", s) for s in range(400)]
    for key in ("speed", "mass", "radius", "bandwidth"):
        sd = np.std([d[key] for d in draws])
        assert sd == pytest.approx(M.TOLD_U[key], rel=0.14)
    sd = np.std([d["gains"] for d in draws])
    assert sd == pytest.approx(M.TOLD_U["gain"], rel=0.14)
    # the control's record is measured with the drawn gains, and a stated matrix is off
    # the true one by its calibration residual (≤ 0.2 % per term), never more
    stated = 0
    for seed in range(8):
        rec, truth, told = M.CASES["control"].make(seed)
        g = truth["told_errors"]["gains"]
        true = np.asarray(truth["mixing"])
        assert np.diag(true)[:2] == pytest.approx([1 + g[0], 1 + g[1]], abs=1e-12)
        if "crosstalk_matrix" in told["sensor"]:
            stated += 1
            C = np.reshape(told["sensor"]["crosstalk_matrix"], (3, 3))
            res = np.diag([1 / (1 + g[0]), 1 / (1 + g[1]), 1.0]) @ true - C
            assert 0 < np.abs(res).max() <= M.CALIBRATION_RESIDUAL
    assert 0 < stated < 8
