"""Tests of pipeline.rigid against closed forms, classical results and an independent solver.

Sources:
- SEED: Ciornei et al., MATEC Web Conf. 112, 07005 (2017), doi:10.1051/matecconf/201711207005,
  eqs. 5–7 and Fig. 4 (restated in docs/theory.md, Rigid bodies).
- WM: Wang & Mason, J. Appl. Mech. 59, 635 (1992), doi:10.1115/1.2893771.
- STRONGE: Stronge, Proc. R. Soc. Lond. A 431, 169 (1990), doi:10.1098/rspa.1990.0125;
  Impact Mechanics, CUP (2000), ch. 5.
- GOLDSMITH: Goldsmith, Impact (1960), ch. 2: a sphere that ends rolling keeps its angular
  momentum about the contact point, so v_t = v_t0/(1+κ) (5/7 for a solid sphere).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pipeline import InputError, Scene
from pipeline.rigid import (
    LAWS,
    MODES,
    EnergyGainWarning,
    inverse_mass_matrix,
    planar_impact,
    slender_rod_contact,
    sphere_on_plane,
)

M, R, V = 0.067, 0.0127, 1.5  # 25.4 mm steel ball (Garland & Rogers 2009), 1.5 m/s
KAPPA = 0.4


def ball(**kw):
    kw.setdefault("radius", R)
    kw.setdefault("mass", M)
    kw.setdefault("speed", V)
    return Scene(**kw)


# ----------------------------------------------------------------- sphere on a plane
def test_seed_eq7_end_point_E2_and_corner_A():
    # SEED eq. 7: sticking regime ends at E2 = ((2/7)·m·v'·sin α, (1+e)·m·v'·cos α);
    # the corner A lies on LF and S: Pt_A = (2/7)·m·v'·sin α, Pn_A = Pt_A/μ.
    a, mu, e = math.radians(40.0), 0.5, 0.8
    r = sphere_on_plane(ball(angle_deg=40.0, mu=mu, e=e))
    assert r.regime == "sticking"
    E2 = (2 / 7 * M * V * math.sin(a), (1 + e) * M * V * math.cos(a))
    assert r.vertices.shape == (3, 2)
    np.testing.assert_allclose(r.vertices[0], [0.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(r.vertices[1], [E2[0], E2[0] / mu], rtol=1e-12)
    np.testing.assert_allclose(r.vertices[2], E2, rtol=1e-12)
    np.testing.assert_allclose([r.Pt_f, r.Pn_f], E2, rtol=1e-12)
    # lines C and T (SEED eq. 5): Pn_c = m·v'·cos α, Pn_f = (1+e)·Pn_c
    assert r.Pn_c == pytest.approx(M * V * math.cos(a), rel=1e-12)
    assert r.Pn_T == pytest.approx((1 + e) * r.Pn_C, rel=1e-12)
    assert r.Pt_S == pytest.approx(E2[0], rel=1e-12)
    np.testing.assert_allclose(r.corner, r.vertices[1], rtol=1e-12)


def test_seed_end_point_E1_sliding():
    # docs/theory.md, Rigid bodies / SEED Fig. 4: sliding throughout ends at E1, Pt = μ(1+e)·m·v_n0.
    a, mu, e = math.radians(60.0), 0.1, 0.7
    r = sphere_on_plane(ball(angle_deg=60.0, mu=mu, e=e))
    assert r.regime == "sliding"
    E1 = (mu * (1 + e) * M * V * math.cos(a), (1 + e) * M * V * math.cos(a))
    assert r.vertices.shape == (2, 2)
    np.testing.assert_allclose(r.vertices[1], E1, rtol=1e-12)
    assert np.all(np.isnan(r.corner))
    assert r.lf_slope == mu


@pytest.mark.parametrize("mu, e", [(0.1, 0.9), (0.3, 0.5), (0.05, 0.0)])
def test_seed_eq6_regime_boundary(mu, e):
    # SEED eq. 6: β = atan[2·tan α/(7(1+e))]; sliding iff μ ≤ tan β ⇔ tan α ≥ 3.5·μ·(1+e).
    alpha_star = math.degrees(math.atan(3.5 * mu * (1 + e)))
    above = sphere_on_plane(ball(angle_deg=alpha_star + 0.01, mu=mu, e=e))
    below = sphere_on_plane(ball(angle_deg=alpha_star - 0.01, mu=mu, e=e))
    assert above.regime == "sliding"
    assert below.regime == "sticking"
    for r, a in ((above, alpha_star + 0.01), (below, alpha_star - 0.01)):
        ta = math.tan(math.radians(a))
        assert r.beta == pytest.approx(math.atan(2 * ta / (7 * (1 + e))), rel=1e-12)
        assert r.phi == pytest.approx(math.atan(mu), rel=1e-12)
    assert math.tan(above.beta) > mu > math.tan(below.beta)


def test_tangential_restitution_sliding_and_sticking():
    # docs/theory.md, Rigid bodies: sliding e_t = 1 − μ(1+e)/tan α; sticking e_t = 5/7 (GOLDSMITH).
    mu, e = 0.15, 0.8
    sl = sphere_on_plane(ball(angle_deg=70.0, mu=mu, e=e))
    assert sl.regime == "sliding"
    assert sl.e_t == pytest.approx(1 - mu * (1 + e) / math.tan(math.radians(70.0)), rel=1e-12)
    st_ = sphere_on_plane(ball(angle_deg=20.0, mu=mu, e=e))
    assert st_.regime == "sticking"
    assert st_.e_t == pytest.approx(5 / 7, rel=1e-12)
    # rolling after sticking: contact point at rest, v_t = ω·R (docs/theory.md, Sign conventions)
    assert st_.v_t == pytest.approx(st_.omega * R, rel=1e-12)
    assert st_.slip_f == 0.0
    assert sl.v_n == pytest.approx(e * V * math.cos(math.radians(70.0)), rel=1e-12)


def test_kappa_generalisation_hollow_sphere():
    # Thin shell κ = 2/3: S at Pt = κ/(1+κ)·m·v_t0 = 0.4·m·v_t0, rolling exit e_t = 1/(1+κ)
    # (GOLDSMITH: angular momentum about the contact point conserved).
    r = sphere_on_plane(ball(angle_deg=30.0, mu=1.0, e=0.5, kappa=2 / 3))
    assert r.regime == "sticking"
    assert r.Pt_f == pytest.approx(0.4 * M * V * 0.5, rel=1e-12)
    assert r.e_t == pytest.approx(0.6, rel=1e-12)
    # tan β = κ/(1+κ)·tan α/(1+e)
    assert math.tan(r.beta) == pytest.approx(0.4 * math.tan(math.radians(30)) / 1.5, rel=1e-12)


@pytest.mark.parametrize("spin", [-150.0, -40.0, 0.0, 30.0, 200.0])
@pytest.mark.parametrize("mu", [0.05, 0.4])
def test_angular_momentum_about_contact_point_is_conserved(spin, mu):
    # Both impulses act at the contact point, so m·v_t + I·ω/R is unchanged by the impact
    # (ω positive in the forward-rolling sense, docs/theory.md, Sign conventions) — whatever the
    # regime. The
    # scene's spin is on the scene's axis, so compare on that axis (the *_scene values).
    r = sphere_on_plane(ball(angle_deg=35.0, mu=mu, e=0.6, spin=spin))
    before = M * V * math.sin(math.radians(35.0)) + KAPPA * M * R * spin
    after = M * r.v_t_scene + KAPPA * M * R * r.omega_scene
    assert after == pytest.approx(before, rel=1e-12, abs=1e-15)
    if r.regime == "sticking":
        assert r.v_t_scene - r.omega_scene * R == pytest.approx(0.0, abs=1e-12)
    else:  # slip keeps its sign while sliding: a rigid ball never reverses slip
        assert np.sign(r.v_t_scene - r.omega_scene * R) == np.sign(r.slip0)
    # on the slip axis (docs/theory.md: ω positive in the sense Pt > 0 produces) the slip is ≥ 0
    assert r.slip_f >= 0 and r.v_t - r.omega * R == pytest.approx(r.slip_f, abs=1e-12)
    assert r.Pt_f >= 0


def test_spin_that_cancels_slip_gives_no_friction():
    # slip0 = v_t0 − ω·R = 0: the ball arrives rolling; no tangential impulse (docs/theory.md, Sign
    # conventions).
    vt0 = V * math.sin(math.radians(30.0))
    r = sphere_on_plane(ball(angle_deg=30.0, mu=0.3, e=0.8, spin=vt0 / R))
    assert r.slip0 == pytest.approx(0.0, abs=1e-15)
    assert r.Pt_f == 0.0 and r.regime == "sticking"
    assert r.e_t == pytest.approx(1.0, rel=1e-12)


def test_negative_slip_is_the_mirror_image():
    # Surface faster than the ball (slip −u) must mirror the ball sliding at +u on a still
    # surface: same percussions and regime; on the scene's axis the tangential velocity and
    # spin change sign, on the slip axis (docs/theory.md: ω in the sense Pt > 0 produces) they
    # agree.
    for u, mu in ((2.0, 0.1), (0.3, 0.5)):
        neg = sphere_on_plane(ball(surface_speed=u, mu=mu, e=0.7))
        pos = sphere_on_plane(ball(surface_speed=-u, mu=mu, e=0.7))
        assert neg.slip0 == -u
        assert neg.regime == pos.regime
        assert neg.Pt_f == pytest.approx(pos.Pt_f, rel=1e-12) and neg.Pt_f > 0
        assert neg.v_t_scene == pytest.approx(-pos.v_t_scene, rel=1e-12)
        assert neg.omega_scene == pytest.approx(-pos.omega_scene, rel=1e-12)
        assert neg.v_t == pytest.approx(pos.v_t, rel=1e-12)
        assert neg.omega == pytest.approx(pos.omega, rel=1e-12) and neg.omega > 0
        np.testing.assert_allclose(neg.vertices, pos.vertices, rtol=1e-12)
        # the ball is dragged along the surface: lab velocity v_t + u has the sign of u
        assert neg.v_t_scene + u > 0


def test_zero_slip_and_frictionless_cases():
    # Normal drop on a still plane: no slip, no friction impulse, v_n = e·v (Newton).
    r = sphere_on_plane(ball(mu=0.5, e=0.6))
    assert r.Pt_f == 0.0 and r.regime == "sticking" and r.omega == 0.0
    assert np.isnan(r.e_t)
    assert r.v_n == pytest.approx(0.6 * V, rel=1e-12)
    # μ = 0: the tangential velocity is untouched (e_t = 1), the ball slides.
    f = sphere_on_plane(ball(angle_deg=30.0, mu=0.0, e=0.6))
    assert f.Pt_f == 0.0 and f.regime == "sliding" and f.e_t == 1.0 and f.omega == 0.0


def test_two_body_free_sphere_target():
    # Equal free spheres, head-on, e = 1: Pn = (1+e)·m*·v = m·v, so the striker stops
    # (Newton's cradle); the relative separation speed is e·v.
    r = sphere_on_plane(ball(target_mass=M, target_radius=R, e=1.0))
    assert r.m_eff == pytest.approx(M / 2, rel=1e-12)
    assert r.Pn_f == pytest.approx(M * V, rel=1e-12)
    assert r.v_n == pytest.approx(V, rel=1e-12)
    # Oblique, sticking, target a thin shell (κ2 = 2/3) of mass 2m: the relative slip of
    # the contact points stops, with 1/m_t = (1 + 1/κ)/m + (1 + 1/κ2)/m2 = 3.5/m + 1.25/m.
    r = sphere_on_plane(
        ball(angle_deg=30.0, target_mass=2 * M, target_radius=R, mu=1.0), target_kappa=2 / 3
    )
    assert r.regime == "sticking"
    m_t = M / 4.75
    assert r.Pt_f == pytest.approx(m_t * V * 0.5, rel=1e-12)
    # relative slip after = v_t − ω1·R1 − ω2·R2 = 0 with ω2 = Pt·R/(κ2·m2·R²)
    omega2 = r.Pt_f / (2 / 3 * 2 * M * R)
    assert r.v_t - r.omega * R - omega2 * R == pytest.approx(0.0, abs=1e-12)
    # default target_kappa is the ball's: m_t = κ/(1+κ)·m*
    r = sphere_on_plane(ball(angle_deg=30.0, target_mass=2 * M, target_radius=R, mu=1.0))
    assert r.m_t == pytest.approx(2 / 7 * r.m_eff, rel=1e-12)
    with pytest.raises(InputError, match="movable flat target"):
        sphere_on_plane(ball(target_mass=1.0))


@settings(max_examples=150, deadline=None)
@given(
    angle=st.floats(0.0, 89.9),
    speed=st.floats(0.0, 10.0),
    mu=st.floats(0.0, 3.0),
    e=st.floats(0.0, 1.0),
    spin=st.floats(-2000.0, 2000.0),
    u=st.floats(-10.0, 10.0),
    kappa=st.floats(0.05, 1.0),
)
def test_sphere_on_plane_obeys_coulomb_and_never_gains_energy(angle, speed, mu, e, spin, u, kappa):
    # In the frame of the (uniformly moving) surface: kinetic energy cannot rise, the
    # friction impulse obeys Coulomb (Pt ≤ μ·Pn), angular momentum about the contact point
    # is conserved, and a rigid ball never reverses its slip (docs/theory.md, Rigid bodies).
    sc = ball(angle_deg=angle, speed=speed, mu=mu, e=e, spin=spin, surface_speed=u, kappa=kappa)
    r = sphere_on_plane(sc)
    I = kappa * M * R**2  # noqa: E741
    KE0 = 0.5 * M * (sc.v_n0**2 + sc.v_t0**2) + 0.5 * I * spin**2
    KE1 = 0.5 * M * (r.v_n**2 + r.v_t**2) + 0.5 * I * r.omega**2  # either axis
    assert KE1 <= KE0 * (1 + 1e-12) + 1e-300
    assert 0.0 <= r.Pt_f <= mu * r.Pn_f * (1 + 1e-12) + 1e-300
    L0 = M * sc.v_t0 + I * spin / R
    L1 = M * r.v_t_scene + I * r.omega_scene / R
    assert L1 == pytest.approx(L0, rel=1e-9, abs=1e-12 * M * (1 + abs(u)))
    assert r.slip_f >= 0


def test_array_scenes_match_loop_of_scalars():
    angles = np.array([0.0, 10.0, 25.0, 40.0, 60.0, 80.0])
    mus = np.array([0.1, 0.3, 0.0, 0.2, 0.5, 0.05])
    spins = np.array([0.0, 20.0, -30.0, 0.0, 5.0, 0.0])
    arr = sphere_on_plane(ball(angle_deg=angles, mu=mus, e=0.75, spin=spins))
    assert arr.vertices.shape == (6, 3, 2)
    for i in range(angles.size):
        one = sphere_on_plane(ball(angle_deg=angles[i], mu=mus[i], e=0.75, spin=spins[i]))
        for name in ("Pn_c", "Pn_f", "Pt_f", "beta", "omega", "v_t", "v_n", "Pt_S"):
            assert getattr(arr, name)[i] == pytest.approx(getattr(one, name), rel=1e-14)
        assert arr.regime[i] == one.regime
        np.testing.assert_array_equal(np.isnan(arr.e_t[i]), np.isnan(one.e_t))
        # the (3, 2) path draws the same broken line as the scalar (k, 2) path
        np.testing.assert_allclose(arr.vertices[i][[0, -1]], one.vertices[[0, -1]], rtol=1e-14)
        if one.regime == "sticking":
            np.testing.assert_allclose(arr.vertices[i], one.vertices, rtol=1e-14)


def test_broken_line_passes_through_the_vertices():
    # docs/theory.md, Rigid bodies: Pt_rigid(Pn) = min(μ·Pn, Pt_S) — through O, A and E2.
    r = sphere_on_plane(ball(angle_deg=30.0, mu=0.4, e=0.9))
    assert r.regime == "sticking"
    np.testing.assert_allclose(r.broken_line(r.vertices[:, 1]), r.vertices[:, 0], rtol=1e-12)
    Pn = np.linspace(0, r.Pn_f, 7)
    expect = np.where(Pn * 0.4 < r.Pt_S, 0.4 * Pn, (2 / 7) * M * V * 0.5)
    np.testing.assert_allclose(r.broken_line(Pn), expect, rtol=1e-12)


# ----------------------------------------------------------------- general planar body
def sphere_W(m=M, kappa=KAPPA):
    # contact point at r = (0, −R) from the centre: W = diag(1/m + R²/I, 1/m)
    return inverse_mass_matrix(m, kappa * m * R**2, 0.0, -R)


def test_inverse_mass_matrix_of_a_sphere():
    np.testing.assert_allclose(sphere_W(), np.diag([3.5 / M, 1 / M]), rtol=1e-12)


@pytest.mark.parametrize("angle, mu", [(20.0, 0.4), (60.0, 0.1), (45.0, 0.35), (0.0, 0.3)])
def test_sphere_all_three_laws_agree_with_sphere_on_plane(angle, mu):
    # docs/theory.md, Restitution: for a sphere the contact normal passes through the centre of
    # mass, so
    # Newton, Poisson and Stronge coincide; all equal Routh's construction.
    e = 0.7
    ref = sphere_on_plane(ball(angle_deg=angle, mu=mu, e=e))
    a = math.radians(angle)
    res = [planar_impact(sphere_W(), V * math.sin(a), V * math.cos(a), mu, e, law) for law in LAWS]
    for r in res:
        assert r.Pn == pytest.approx(ref.Pn_f, rel=1e-12)
        assert r.Pt == pytest.approx(ref.Pt_f, rel=1e-12, abs=1e-16)
        assert r.e_newton == pytest.approx(e, rel=1e-12)
        assert r.e_poisson == pytest.approx(e, rel=1e-12)
        assert r.e_energetic == pytest.approx(e, rel=1e-12)
    expect_mode = {"sliding": "sliding", "sticking": "slide-stick-compression"}[ref.regime]
    if angle == 0.0:
        expect_mode = "sticking"
    assert {r.mode for r in res} == {expect_mode}


def _rod_setup():
    """Uniform slender rod, docs/theory.md, Rigid bodies: m = 1 kg, L = 1 m, 40° to the ground,
    lower end
    strikes, v_G = (0.3, −1.0) m/s, ω = 0.

    Frame: x = t along the ground (the direction of the initial slip, since the end's
    velocity is v_G for ω = 0), y = n up, pointing into the rod. The rod rises towards +x
    from its lower end, so the lower end sits at r = −(L/2)(cos θ, sin θ) from the centre.
    I = m·L²/12. Contact velocity change for an impulse J at the end (Δv_G = J/m,
    Δω = (r × J)/I, Δu = Δv_G + Δω·(−r_y, r_x)):
        W_tt = 1/m + r_y²/I, W_nn = 1/m + r_x²/I, W_tn = W_nt = −r_x·r_y/I.
    """
    m, L, th = 1.0, 1.0, math.radians(40.0)
    I = m * L**2 / 12  # noqa: E741
    rx, ry = -0.5 * L * math.cos(th), -0.5 * L * math.sin(th)
    W = np.array([[1 / m + ry**2 / I, -rx * ry / I], [-rx * ry / I, 1 / m + rx**2 / I]])
    return m, I, np.array([rx, ry]), W, 0.3, 1.0


def _rod_KE_after(m, I, r, Pt, Pn, vG=(0.3, -1.0)):  # noqa: E741
    # physical impulse on the rod J = (−Pt, Pn) (Pt opposes the slip along +x)
    J = np.array([-Pt, Pn])
    v = np.asarray(vG) + J / m
    w = (r[0] * J[1] - r[1] * J[0]) / I
    return 0.5 * m * v @ v + 0.5 * I * w**2


def test_slender_rod_newton_creates_energy_poisson_stronge_do_not():
    # docs/theory.md, Rigid bodies check case (Kane's paradox, WM §4, STRONGE 1990): with μ = 0.8, e
    # = 0.9
    # the end slides, sticks during compression (|W_tn/W_tt| = 0.66 ≤ μ), and Newton's law
    # then raises the kinetic energy; Poisson's and Stronge's lower it.
    m, I, r, W, vt0, vn0 = _rod_setup()
    KE0 = 0.5 * m * (0.3**2 + 1.0**2)
    with pytest.warns(EnergyGainWarning, match="law='newton' creates kinetic energy"):
        out = {law: planar_impact(W, vt0, vn0, 0.8, 0.9, law) for law in LAWS}
    assert [law for law, res in out.items() if res.energy_gain] == ["newton"]
    for law, res in out.items():
        assert res.mode == "slide-stick-compression", law
        dKE_bodies = _rod_KE_after(m, I, r, res.Pt, res.Pn) - KE0
        assert res.dKE == pytest.approx(dKE_bodies, rel=1e-10, abs=1e-14), law
    assert out["newton"].dKE > 0.02
    assert out["poisson"].dKE < -0.04
    assert out["energetic"].dKE < -0.04
    # each law honours its own definition of e
    assert out["newton"].e_newton == pytest.approx(0.9, rel=1e-12)
    assert out["poisson"].e_poisson == pytest.approx(0.9, rel=1e-12)
    assert out["energetic"].e_energetic == pytest.approx(0.9, rel=1e-12)
    # and the helper builds the same contact data
    rod = slender_rod_contact(1.0, 1.0, math.radians(40.0), (0.3, -1.0))
    np.testing.assert_allclose(rod.W, W, rtol=1e-14)
    assert (rod.v_t0, rod.v_n0) == pytest.approx((0.3, 1.0), rel=1e-14)


def test_stronge_equals_poisson_when_slip_never_stops():
    # STRONGE (2000) §5: without stick or reversal the energetic and kinetic coefficients
    # coincide. Rod with μ = 0.1: the slip only decreases by a little, the end slides
    # throughout. e* is recomputed here from the Poisson path by quadrature of v_n dPn.
    _, _, _, W, vt0, vn0 = _rod_setup()
    mu, e = 0.1, 0.6
    p = planar_impact(W, vt0 + 2.0, vn0, mu, e, "poisson")
    s = planar_impact(W, vt0 + 2.0, vn0, mu, e, "energetic")
    assert p.mode == s.mode == "sliding"
    assert s.Pn == pytest.approx(p.Pn, rel=1e-12)
    Pn = np.linspace(0, p.Pn, 200001)
    vn = -vn0 - W[1, 0] * mu * Pn + W[1, 1] * Pn
    work = np.concatenate([[0], np.cumsum(0.5 * (vn[1:] + vn[:-1]) * np.diff(Pn))])
    ic = np.argmin(np.abs(vn))
    e_star = math.sqrt((work[-1] - work[ic]) / -work[ic])
    assert e_star == pytest.approx(e, rel=1e-6)


def _reference_solver(W, vt0, vn0, mu, e, law, n=20000):
    """Independent impulse-space time-stepping (Moreau-style): at each step dPn the
    tangential increment is the one in [−μ·dPn, μ·dPn] that brings the slip closest to
    zero (Coulomb's law as a projection). Termination per law with linear interpolation.
    Vectorised over cases. Returns Pt (on the caller's axis, physical impulse along −t),
    Pn."""
    Wtt, Wtn, Wnn = W[..., 0, 0], W[..., 0, 1], W[..., 1, 1]
    # a generous step: bound the end by 3·(1+e)·v_n0/λ_min(W)
    lam = np.linalg.eigvalsh(W)[..., 0]
    h = 3 * 2 * vn0 / lam / n
    s, vn = vt0.astype(float).copy(), -vn0.astype(float)
    Pt = np.zeros_like(s)
    Pn = np.zeros_like(s)
    work = np.zeros_like(s)
    Wc = np.full_like(s, np.nan)
    Pc = np.full_like(s, np.nan)
    done = np.zeros(s.shape, bool)
    outPt, outPn = np.full_like(s, np.nan), np.full_like(s, np.nan)
    for _ in range(4 * n):
        dPt = np.clip((s + Wtn * h) / Wtt, -mu * h, mu * h)
        s1 = s - Wtt * dPt + Wtn * h
        vn1 = vn - Wtn * dPt + Wnn * h
        w1 = work + 0.5 * (vn + vn1) * h
        crossing = np.isnan(Pc) & (vn1 >= 0)
        frac_c = np.where(crossing, -vn / np.where(vn1 != vn, vn1 - vn, 1.0), 0.0)
        Pc = np.where(crossing, Pn + frac_c * h, Pc)
        Wc = np.where(crossing, work + 0.5 * vn * frac_c * h, Wc)
        if law == "newton":
            target, cur, nxt = e * vn0, vn, vn1
        elif law == "poisson":
            target, cur, nxt = (1 + e) * Pc, Pn, Pn + h
        else:
            # restitution work so far vs e²·|compression work| (STRONGE's definition)
            target, cur, nxt = -Wc * e**2, work - Wc, w1 - Wc
        hit = ~done & ~np.isnan(Pc) & (nxt >= target)
        f = np.clip((target - cur) / np.where(nxt != cur, nxt - cur, 1.0), 0, 1)
        outPt = np.where(hit, Pt + f * dPt, outPt)
        outPn = np.where(hit, Pn + f * h, outPn)
        done |= hit
        s, vn, work, Pt, Pn = s1, vn1, w1, Pt + dPt, Pn + h
        if done.all():
            break
    return outPt, outPn


def _random_cases(rng, N):
    ang = rng.uniform(0, np.pi, N)
    lam = rng.uniform(0.1, 3.0, (N, 2))
    Q = np.stack([[np.cos(ang), -np.sin(ang)], [np.sin(ang), np.cos(ang)]]).transpose(2, 0, 1)
    W = Q @ (lam[:, :, None] * np.swapaxes(Q, 1, 2))
    return W, rng.uniform(-1.5, 1.5, N), rng.uniform(0.2, 1.5, N), rng.uniform(0, 1.5, N)


@pytest.mark.parametrize("law", LAWS)
def test_closed_form_matches_independent_time_stepping(law):
    # The closed form must agree with a brute-force impulse-space integration that knows
    # nothing of modes or segments (first-order scheme, step 3e-4 of the scale; observed
    # agreement ~7e-5 of the scale, tolerance 5e-4).
    rng = np.random.default_rng(7)
    W, vt0, vn0, mu = _random_cases(rng, 400)
    vt0[:30] = 0.0  # zero initial slip: sticking or slip onset
    e = rng.uniform(0.0, 1.0, 400)
    if law == "newton":  # some of these create energy (Kane's paradox) and say so
        with pytest.warns(EnergyGainWarning, match=r"creates kinetic energy in \d+ of 400"):
            res = planar_impact(W, vt0, vn0, mu, e, law)
    else:
        res = planar_impact(W, vt0, vn0, mu, e, law)
    # flagged exactly where the kinetic energy, recomputed as J·u0 + ½·JᵀWJ, rises
    J = np.stack([-res.t_sign * res.Pt, res.Pn], axis=-1)
    dKE = np.einsum("ij,ij->i", J, np.stack([vt0, -vn0], -1)) + 0.5 * np.einsum(
        "ij,ijk,ik->i", J, W, J
    )
    KE_scale = 0.5 * (vt0**2 + vn0**2) / np.linalg.eigvalsh(W)[:, 0]
    clear = np.abs(dKE) > 1e-6 * KE_scale  # off the boundary ΔKE = 0
    np.testing.assert_array_equal(res.energy_gain[clear], dKE[clear] > 0)
    assert law == "newton" or not res.energy_gain.any()
    Pt_ref, Pn_ref = _reference_solver(W, vt0, vn0, mu, e, law)
    scale = vn0 / np.linalg.eigvalsh(W)[:, 0]
    assert not np.any(np.isnan(Pn_ref))
    np.testing.assert_allclose(res.Pn / scale, Pn_ref / scale, atol=5e-4)
    np.testing.assert_allclose(res.t_sign * res.Pt / scale, Pt_ref / scale, atol=5e-4)
    # the random set exercises every mode
    assert set(res.mode) == set(MODES)


@settings(max_examples=150, deadline=None)
@given(
    l1=st.floats(0.05, 20.0),
    l2=st.floats(0.05, 20.0),
    ang=st.floats(0.0, math.pi),
    vt0=st.floats(-3.0, 3.0),
    vn0=st.floats(0.01, 3.0),
    mu=st.floats(0.0, 3.0),
    e=st.floats(0.0, 1.0),
)
def test_poisson_and_stronge_never_create_energy(l1, l2, ang, vt0, vn0, mu, e):
    # WM (1992) recommend Poisson's hypothesis because, unlike Newton's law, it does not raise
    # the energy of a planar impact (their abstract); STRONGE (1990):
    # the energetic coefficient dissipates by construction. dKE is recomputed here as
    # J·u0 + ½·JᵀWJ (the code uses ½·J·(u0 + u_f)).
    c, s = math.cos(ang), math.sin(ang)
    Q = np.array([[c, -s], [s, c]])
    W = Q @ np.diag([l1, l2]) @ Q.T
    W = 0.5 * (W + W.T)
    KE_scale = 0.5 * (vt0**2 + vn0**2) / min(l1, l2)
    for law in ("poisson", "energetic"):
        r = planar_impact(W, vt0, vn0, mu, e, law)
        J = np.array([-r.t_sign * r.Pt, r.Pn])  # physical impulse on the caller's axes
        dKE = J @ np.array([vt0, -vn0]) + 0.5 * J @ W @ J
        assert r.dKE == pytest.approx(dKE, abs=1e-9 * KE_scale)
        assert r.dKE <= 1e-12 * KE_scale
        # v_n is a sum of terms of the size of the whole velocity (W·P cancels vn0 and
        # the tangential part's coupling): its rounding scales with |v0|, not with vn0
        assert r.Pn >= 0 and r.v_n >= -1e-12 * math.hypot(vt0, vn0)


@pytest.mark.filterwarnings("ignore::pipeline.rigid.EnergyGainWarning")  # Newton: tested above
def test_array_input_matches_loop_of_scalars():
    rng = np.random.default_rng(3)
    W, vt0, vn0, mu = _random_cases(rng, 40)
    for law in LAWS:
        arr = planar_impact(W, vt0, vn0, mu, 0.8, law)
        assert arr.vertices.shape == (40, 3, 2)
        for i in range(40):
            one = planar_impact(W[i], vt0[i], vn0[i], mu[i], 0.8, law)
            P_scale = abs(one.Pn) + abs(one.Pt)
            KE_scale = 0.5 * (vt0[i] ** 2 + vn0[i] ** 2) / np.linalg.eigvalsh(W[i])[0]
            scales = {"Pt": P_scale, "Pn": P_scale, "Pn_c": P_scale, "dKE": KE_scale}
            scales.update(s=abs(vt0[i]) + vn0[i], v_n=abs(vt0[i]) + vn0[i])
            for name, scale in scales.items():
                assert getattr(arr, name)[i] == pytest.approx(
                    getattr(one, name), rel=1e-12, abs=1e-12 * scale
                ), (law, name, i)
            # the mode is a classification: compare it where a 1e-9 change of μ keeps it
            # (on a boundary the two paths' roundings may fall on either side)
            near = {
                planar_impact(W[i], vt0[i], vn0[i], mu[i] * f, 0.8, law).mode
                for f in (1 - 1e-9, 1 + 1e-9)
            }
            if near == {one.mode}:
                assert arr.mode[i] == one.mode, (law, i)
            np.testing.assert_allclose(arr.vertices[i][[0, -1]], one.vertices[[0, -1]])
            if abs(one.dKE) > 1e-9 * KE_scale:  # the flag, off its boundary
                assert arr.energy_gain[i] == one.energy_gain, (law, i)


@pytest.mark.filterwarnings("ignore::pipeline.rigid.EnergyGainWarning")  # Newton: tested above
def test_negative_initial_slip_is_the_mirror_image():
    _, _, _, W, vt0, vn0 = _rod_setup()
    Wm = W * np.array([[1, -1], [-1, 1]])  # t → −t flips the off-diagonal terms
    for law in LAWS:
        a = planar_impact(W, vt0, vn0, 0.8, 0.9, law)
        b = planar_impact(Wm, -vt0, vn0, 0.8, 0.9, law)
        assert a.energy_gain == b.energy_gain == (law == "newton")
        assert (b.Pt, b.Pn, b.dKE) == pytest.approx((a.Pt, a.Pn, a.dKE), rel=1e-12)
        assert b.s == pytest.approx(-a.s, abs=1e-14) and b.mode == a.mode and b.t_sign == -1


def test_zero_initial_slip_sticks_or_starts_sliding():
    _, _, _, W, _, vn0 = _rod_setup()  # |W_tn/W_tt| = 0.66
    stuck = planar_impact(W, 0.0, vn0, 0.8, 0.5, "energetic")
    assert stuck.mode == "sticking" and stuck.s == 0.0
    # sticking ratio Pt/Pn = W_tn/W_tt from the first instant
    assert stuck.Pt / stuck.Pn == pytest.approx(W[0, 1] / W[0, 0], rel=1e-12)
    onset = planar_impact(W, 0.0, vn0, 0.3, 0.5, "energetic")
    assert onset.mode == "slip-onset"
    assert onset.Pt == pytest.approx(0.3 * onset.Pn, rel=1e-12)
    # W_tn < 0: the contact starts slipping along −t, and friction opposes it
    assert onset.t_sign == -1 and onset.s < 0


def test_bad_input_raises():
    W = sphere_W()
    with pytest.raises(InputError, match="law"):
        planar_impact(W, 1.0, 1.0, 0.2, 0.5, "kane")
    with pytest.raises(InputError, match="positive definite"):
        planar_impact(np.array([[1.0, 2.0], [2.0, 1.0]]), 1.0, 1.0, 0.2, 0.5, "newton")
    with pytest.raises(InputError, match="symmetric"):
        planar_impact(np.array([[1.0, 0.2], [0.0, 1.0]]), 1.0, 1.0, 0.2, 0.5, "newton")
    with pytest.raises(InputError, match="v_n0 = \\[0.0\\] is out of range"):
        planar_impact(W, 1.0, 0.0, 0.2, 0.5, "newton")
    with pytest.raises(InputError, match="e = \\[1.5\\]"):
        planar_impact(W, 1.0, 1.0, 0.2, 1.5, "newton")


@pytest.mark.parametrize("u", [-0.5, 0.5, 2.0])  # slip +, slip + (slower surface), slip −
def test_spin_convention_matches_the_simulator(u):
    """Rigid ω and v_t on the slip axis equal the compliant simulator's Coulomb limit.

    With tangential="coulomb" (no tangential compliance) the simulated end state is Routh's
    (docs/theory.md, Rigid bodies), and both report ω "positive in the sense that Pt > 0 produces"
    (docs/theory.md, Sign conventions).
    """
    from pipeline.simulate import impact

    sc = Scene(
        radius=R, mass=M, E=210e9, nu=0.3, speed=1.0, angle_deg=30.0, mu=0.3, e=0.8, surface_speed=u
    )
    r = sphere_on_plane(sc)
    sim = impact(sc, normal="hunt_crossley", tangential="coulomb")
    assert sim.attrs["omega"] == pytest.approx(float(r.omega), rel=1e-6)
    assert sim.attrs["e_t"] == pytest.approx(float(r.e_t), rel=1e-6)
