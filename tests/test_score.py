"""Deviation score: closed-form curves, simulated records with known truth, bootstrap.

The broken line is Routh's rigid prediction for a sphere on a plane (docs/theory.md, Rigid bodies;
seed
eqs. 4–7, Ciornei et al. 2017, doi:10.1051/matecconf/201711207005).
"""

import warnings

import numpy as np
import pytest

from pipeline import Scene
from pipeline.analysis import analyse
from pipeline.errors import PoorFitWarning
from pipeline.percussion import ResolutionWarning
from pipeline.rigid import sphere_on_plane
from pipeline.score import deviation_metrics, deviation_score, references
from pipeline.simulate import impact

# Chung & Ooi (2011) test 4 scene, doi:10.1007/s10035-011-0277-0 (Chung & Ooi 2011)
TEST4 = dict(radius=2.5e-3, density=4000.0, E=380e9, nu=0.23, speed=3.9, mu=0.092, e=0.98)

#: "Near zero": a record that follows the broken line scores below these. The Coulomb
#: simulation departs from the line only by its friction regularisation (slip speeds below
#: 1e-6·v_t0 are not fully sliding) and by sampling the kink at corner A on a 2001-point
#: grid, both well under 0.1 % of P_ref; the thresholds leave a factor ≥ 10 for noise.
NEAR_ZERO = {"area": 0.01, "max_distance": 0.02}


def _line_scene(angle):
    # μ = 0.2, e = 0.9: sliding throughout iff tan α ≥ 3.5·μ·(1+e) = 1.33, i.e. α ≥ 53.1°
    return Scene(radius=0.0127, mass=0.067, speed=0.5, angle_deg=angle, mu=0.2, e=0.9)


@pytest.mark.parametrize("angle", [5.0, 70.0])  # sticking and sliding (tan α vs 3.5·μ·(1+e))
def test_curve_on_the_broken_line_scores_zero(angle):
    rig = sphere_on_plane(_line_scene(angle))
    Pn = np.linspace(0.0, float(rig.Pn_f), 4001)
    Pt = np.minimum(float(rig.mu) * Pn, float(rig.Pt_S))
    t = np.linspace(0.0, 1e-4, Pn.size)
    m = deviation_metrics(t, Pn, Pt, rig, float(rig.Pn_c))
    for phase in ("total", "compression", "restitution"):
        assert m[phase]["area"] == pytest.approx(0.0, abs=1e-12)
        assert m[phase]["max_distance"] == pytest.approx(0.0, abs=1e-12)
    assert m["total"]["end_Pt"] == pytest.approx(0.0, abs=1e-12)
    assert m["total"]["end_Pn"] == pytest.approx(0.0, abs=1e-12)
    assert m["total"]["Pt_drop"] == pytest.approx(0.0, abs=1e-12)
    assert m["total"]["Pt_max"] == pytest.approx(1.0, rel=1e-12)


def test_constant_offset_in_restitution_has_known_area():
    rig = sphere_on_plane(_line_scene(70.0))  # sliding: the line is Pt = μ·Pn throughout
    P_ref, Pt_ref = references(rig)
    assert P_ref == pytest.approx(float(rig.Pn_f))
    Pn = np.linspace(0.0, P_ref, 20001)
    d = 0.1 * Pt_ref
    Pn_c = float(rig.Pn_c)
    Pt = float(rig.mu) * Pn + np.where(Pn > Pn_c, d, 0.0)
    m = deviation_metrics(np.linspace(0, 1e-4, Pn.size), Pn, Pt, rig, Pn_c)
    frac_r = 1.0 - Pn_c / P_ref  # = e/(1+e): the restitution share of Pn
    # area = d/Pt_ref × (restitution width in Pn/P_ref), up to one grid step at the jump
    assert m["restitution"]["area"] == pytest.approx(0.1 * frac_r, abs=2e-5)
    assert m["compression"]["area"] == pytest.approx(0.0, abs=2e-5)
    assert m["total"]["max_distance"] == pytest.approx(0.1, rel=1e-9)
    assert m["compression"]["max_distance"] == pytest.approx(0.0, abs=1e-12)
    assert m["total"]["end_Pt"] == pytest.approx(0.1, rel=1e-9)


def test_peak_and_fall_of_Pt():
    """Pt rises along LF to Pn = a, then falls linearly to b at the end: closed forms."""
    rig = sphere_on_plane(_line_scene(70.0))
    P_ref, Pt_ref = references(rig)
    mu = float(rig.mu)
    Pn = np.linspace(0.0, P_ref, 10001)
    a = 0.7 * P_ref
    top = mu * a
    b = 0.25 * top
    Pt = np.where(Pn <= a, mu * Pn, top + (b - top) * (Pn - a) / (P_ref - a))
    m = deviation_metrics(np.linspace(0, 1e-4, Pn.size), Pn, Pt, rig, float(rig.Pn_c))
    assert m["total"]["Pt_max"] == pytest.approx(top / Pt_ref, rel=1e-9)
    assert m["total"]["Pn_at_Pt_max"] == pytest.approx(0.7, abs=1e-4)
    assert m["total"]["Pt_drop"] == pytest.approx((top - b) / Pt_ref, rel=1e-9)
    # the gap grows linearly from 0 at a to (μ·P_ref − b) at the end: a triangle
    tri = 0.5 * (1 - 0.7) * (mu * P_ref - b) / Pt_ref
    assert m["total"]["area"] == pytest.approx(tri, rel=1e-6)
    assert m["total"]["max_distance"] == pytest.approx((mu * P_ref - b) / Pt_ref, rel=1e-9)


def test_replicates_vectorise():
    rig = sphere_on_plane(_line_scene(5.0))
    rng = np.random.default_rng(3)
    Pn = np.linspace(0, float(rig.Pn_f), 500)
    Pt = np.minimum(float(rig.mu) * Pn, float(rig.Pt_S)) + rng.normal(0, 1e-5, (7, 500))
    t = np.linspace(0, 1e-4, 500)
    batch = deviation_metrics(t, np.broadcast_to(Pn, Pt.shape), Pt, rig, np.full(7, rig.Pn_c))
    for i in range(7):
        one = deviation_metrics(t, Pn, Pt[i], rig, float(rig.Pn_c))
        for phase in ("total", "restitution"):
            for k, v in one[phase].items():
                assert batch[phase][k][i] == pytest.approx(float(v), rel=1e-12, abs=1e-15)


def _analyse(record, scene, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PoorFitWarning)  # the quartic misfits dense pulses
        return analyse(record, scene, **kw)


@pytest.mark.parametrize("angle", [15.0, 60.0])
def test_coulomb_record_scores_near_zero(angle):
    scene = Scene(angle_deg=angle, **TEST4)
    a = _analyse(impact(scene, tangential="coulomb"), scene, n_boot=50)
    assert a.rigid.regime == ("sticking" if angle == 15.0 else "sliding")
    for k, limit in NEAR_ZERO.items():
        assert abs(a.score[k]) < limit, (k, a.score[k])
    assert abs(a.score["end_Pt"]) < NEAR_ZERO["max_distance"]


def test_mindlin_at_15deg_scores_clearly_above_and_finds_the_Pt_maximum():
    scene = Scene(angle_deg=15.0, **TEST4)
    rec = impact(scene, tangential="mindlin")
    a = _analyse(rec, scene, n_boot=50)
    assert a.score["area"] > 10 * NEAR_ZERO["area"]
    assert a.score["max_distance"] > 10 * NEAR_ZERO["max_distance"]
    assert a.score["Pt_drop"] > 0.05  # Pt peaks, then falls: the seed's observation
    assert a.score.values["compression"]["area"] < a.score.values["restitution"]["area"]
    # the Pt maximum sits where Ft changes sign (dPt/dt = Ft = 0)
    t = rec["time"].values
    Ft = rec["Ft"].values
    i = np.flatnonzero((Ft[:-1] > 0) & (Ft[1:] <= 0))[0]
    t_rev = t[i] - Ft[i] * (t[i + 1] - t[i]) / (Ft[i + 1] - Ft[i])
    t_c = float(rec.attrs["t_contact"])
    assert abs(a.score.t_Pt_max - t_rev) < 0.03 * t_c


def test_bootstrap_std_matches_monte_carlo_spread():
    """The bootstrap's std of a metric ≈ its spread over independent noise realisations."""
    from pipeline.simulate import to_sensor

    scene = Scene(angle_deg=15.0, **TEST4)
    ideal = impact(scene, tangential="mindlin")
    areas, stds = [], []
    for seed in range(12):
        rec = to_sensor(
            ideal, seed=seed, noise=20.0, bits=None, crosstalk=0.0, rate=20e6, full_scale=np.inf
        )
        # 20 N of noise on this 6 µs pulse puts the record in the noise region, and the
        # 300 kHz sensor in the bandwidth one: flagged, as it should be
        with pytest.warns(ResolutionWarning, match="noise: Ft"):
            a = _analyse(rec, scene, n_boot=100, seed=seed)
        areas.append(a.score["Pt_max"])
        stds.append(a.score.std["total"]["Pt_max"])
    spread = np.std(areas, ddof=1)
    assert 0.5 * spread < np.median(stds) < 2.0 * spread


def test_score_of_single_curve_without_bootstrap_has_nan_std():
    rig = sphere_on_plane(_line_scene(70.0))
    Pn = np.linspace(0, float(rig.Pn_f), 100)
    s = deviation_score(np.linspace(0, 1, 100), Pn, float(rig.mu) * Pn, rig, float(rig.Pn_c))
    assert s.n_boot == 0 and np.isnan(s.std["total"]["area"])
    assert s["area"] == pytest.approx(0.0, abs=1e-12)


def test_bootstrap_std_of_an_empty_phase_is_nan_without_warnings():
    # every replicate ends before maximum compression (Pn_c above the whole curve): the
    # restitution phase is empty, its metrics NaN, and their spread NaN — not a RuntimeWarning
    rig = sphere_on_plane(_line_scene(70.0))
    Pn = np.linspace(0, float(rig.Pn_f), 50)
    Pt = float(rig.mu) * Pn
    boot = (np.tile(Pn, (5, 1)), np.tile(Pt, (5, 1)) * np.linspace(0.9, 1.1, 5)[:, None])
    s = deviation_score(
        np.linspace(0, 1, 50), Pn, Pt, rig, 2 * float(rig.Pn_f), boot=boot + (np.full(5, 2.0),)
    )
    assert np.isnan(s.std["restitution"]["area"]) and np.isnan(s.values["restitution"]["area"])
    # compression: Pt_max spreads as the replicates' scale, std of 0.9…1.1 × Pt_max
    want = np.std(np.linspace(0.9, 1.1, 5), ddof=1) * s.values["compression"]["Pt_max"]
    assert s.std["compression"]["Pt_max"] == pytest.approx(want, rel=1e-9)
