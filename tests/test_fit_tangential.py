"""pipeline.fit.tangential: the piecewise Mindlin solution against the closed form of a stick
under a steady normal load, and a batch of columns against the same columns one by one."""

from __future__ import annotations

import numpy as np
import pytest

from pipeline.fit.pulse import NormalPulse, normal_pulse
from pipeline.fit.tangential import tangential_response


def _steady(F, tau_c, n):
    """A 'pulse' of one column at constant approach x = 1 and force F (u = 0, f' = 0): the
    tangential problem alone, with constant coefficients."""
    one = np.ones((1, n + 1))
    return NormalPulse(
        e=np.ones(1),
        tau_c=np.array([tau_c]),
        x=one,
        u=0.0 * one,
        f=F * one,
        df=0.0 * one,
        xg=np.ones((1, 2, n)),
    )


@pytest.mark.parametrize("history", ["total", "incremental"])
def test_stick_then_slide_under_a_steady_load_is_the_closed_form(history):
    """At constant normal load (x = 1) the stick is a harmonic oscillator of ω² = λ·kc for
    either history rule (Mindlin 1949's tangential stiffness, a linear spring until the
    Coulomb cap; Johnson 1985 §7.4 without the annulus of partial slip):
    Ft = kc·s0·sin(ωτ)/ω, Pt = s0·(1 − cos ωτ)/λ, until Ft reaches μF at sin(ωτ*) =
    μFω/(kc·s0); then the contact slides at Ft = μF and, the normal percussion not growing,
    Pt stays at its value at τ*. Magnus's exponential is exact for constant coefficients,
    so the stick is exact to rounding; the switch is located by regula falsi between nodes,
    within h²·max|g''|/(8·g'(τ*)) of τ* (g = Ft − μF, the linear interpolant's error)."""
    s0, lam, kc, F, mu = 0.3, 3.5, 1.2, 1.0, 0.1
    tau_c, n = 3.0, 128
    tr = tangential_response(_steady(F, tau_c, n), s0, lam, mu, kc, history=history)
    w = np.sqrt(lam * kc)
    amp = kc * s0 / w
    t_star = np.arcsin(mu * F / amp) / w
    tau = np.linspace(0.0, tau_c, n + 1)
    stick = tau < t_star
    np.testing.assert_allclose(tr.ft[0, stick], amp * np.sin(w * tau[stick]), rtol=0, atol=1e-13)
    np.testing.assert_allclose(
        tr.p[0, stick], s0 * (1 - np.cos(w * tau[stick])) / lam, rtol=0, atol=1e-13
    )
    np.testing.assert_allclose(tr.ft[0, ~stick][:-1], mu * F, rtol=1e-14)  # the last node: 0
    h = tau_c / n
    dt = h**2 * amp * w**2 / (8 * amp * w * np.cos(w * t_star))
    p_star = s0 * (1 - np.cos(w * t_star)) / lam
    # after the switch Pt = Pt(τ_s) + μ·(Pn − Pn(τ_s)): constant on the nodes, Pn(τ_s) = 1 − u
    # read off u's cubic, whose end rates are −F (this steady 'pulse' is no impact): |u(τ_s)|
    # ≤ h·F·max(θ − 3θ² + 2θ³) = h·F·√3/18
    after = tr.p[0, ~stick]
    np.testing.assert_allclose(after, after[0], rtol=1e-14)
    assert after[0] == pytest.approx(p_star, abs=mu * F * dt + mu * h * F * np.sqrt(3) / 18)
    assert tr.segments[0] == 2 and not tr.slip_stops[0]
    assert tr.kink[0].sum() == 1 and tr.kink[0, int(t_star / h)]
    # the normal percussion does not grow here: the slide's share is that bound on u alone
    assert 0.0 <= tr.slide_share[0] <= h * F * np.sqrt(3) / 18


@pytest.mark.parametrize("history", ["total", "incremental"])
def test_columns_solved_together_equal_columns_solved_one_by_one(history):
    """A batch whose columns take different paths at once — sticking (5°, 15°), gross slip
    (45°, 70°), no initial slip, no friction, a stiff and a soft spring, two restitutions —
    gives each column what it gives alone (the segments advance the rows in each mode
    together, by row indices where the modes differ)."""
    ang = np.array([5.0, 15.0, 45.0, 70.0, 15.0, 30.0, 10.0, 0.0])
    s0 = np.tan(np.radians(ang))
    mu = np.array([0.3, 0.13, 0.1, 0.2, 0.0, 0.13, 0.5, 0.2])
    kc = np.array([1.2, 1.2, 1.2, 0.5, 1.2, 40.0, 0.05, 1.2])
    lam = np.full(ang.size, 3.5)
    e = np.where(np.arange(ang.size) % 2 == 0, 0.9, 0.6)
    pul = normal_pulse("hunt_crossley", e, 64)
    both = tangential_response(pul, s0, lam, mu, kc, history=history)
    assert len(set(both.segments.tolist())) > 1  # the case this test is about
    for i in range(ang.size):
        one = tangential_response(pul.take([i]), s0[i], lam[i], mu[i], kc[i], history=history)
        for name in ("p", "ft", "dft"):
            np.testing.assert_allclose(getattr(both, name)[i], getattr(one, name)[0], atol=1e-13)
        for name in ("segments", "slip_stops", "kink"):
            np.testing.assert_array_equal(getattr(both, name)[i], getattr(one, name)[0])
        assert both.slide_share[i] == pytest.approx(one.slide_share[0], abs=1e-13)


def test_pulse_interpolant_is_the_cubic_hermite_of_the_nodes():
    """The segments' x, u, f between the nodes (the switches' states, the partial steps' Gauss
    points) are the cubic Hermite interpolants of the node values with the rates u, −f, f'
    (scipy's CubicHermiteSpline on each column, independently), x and f floored at 0, τ
    clipped to the contact; x alone the same (to rounding) as x of all three."""
    from scipy.interpolate import CubicHermiteSpline

    from pipeline.fit.tangential import _Pulse

    pul = normal_pulse("hunt_crossley", np.array([0.9, 0.5, 0.75]), 64)
    pl = _Pulse(pul)
    rng = np.random.default_rng(3)
    rows = np.array([2, 0])
    tau = rng.uniform(-0.05, 1.05, (2, 7)) * pul.tau_c[rows, None]
    tau[0, :2] = pl.tau[rows[0], [5, 64]]  # on a node, and the last one
    x, u, f = pl.at(rows, tau)
    for i, row in enumerate(rows):
        t = np.clip(tau[i], 0.0, pul.tau_c[row])
        nodes = np.linspace(0.0, pul.tau_c[row], 65)
        for got, y, dy, floor in (
            (x, pul.x, pul.u, True),
            (u, pul.u, -pul.f, False),
            (f, pul.f, pul.df, True),
        ):
            want = CubicHermiteSpline(nodes, y[row], dy[row])(t)
            want = np.maximum(want, 0.0) if floor else want
            np.testing.assert_allclose(got[i], want, rtol=0, atol=1e-13 * np.abs(y[row]).max())
    np.testing.assert_allclose(pl.at(rows, tau, only_x=True), x, rtol=0, atol=1e-14 * pul.x.max())


#: Columns where stick and slide tie at one instant (law, rule, steps, e, s0, λ, μ, kc, and
#: the coarse grid's error allowed, of the percussion's scale): the
#: spring reaching its cap at the contact's first instant ((2/3)·kc·s0 ≈ μ for the
#: incremental rule, the force there only rounding), and Thornton's cap letting go faster
#: than the spring unloads. Each once ran stick and slide of (next to) no length to the
#: segment limit and returned no tangential force. The error allowed is the coarse grid's own:
#: ~1 % at 64 steps, 12 % at the let-go of a stiff spring (kc ≈ 60, μ ≈ 0.8) whose sticks
#: there are shorter than a step (on 128 steps it is 0.3 %).
_TIES = [
    ("viscoelastic", "incremental", 128, 0.8356171651282855, 1.8540909696735473,
     2.1488571039971816, 0.01633948131947873, 0.09968930510479386, 1e-2),
    ("hunt_crossley", "incremental", 64, 0.8802879830632857, 1.217778945408206,
     2.6205531736316363, 0.0771984530825341, 0.1133735990355715, 1e-2),
    ("thornton", "incremental", 64, 0.3886322332116267, 3.353789071996579,
     2.6610816440492235, 0.9929647830851447, 87.12481237356087, 1e-2),
    # creeping rather than stuck: slides of ~1e-4 of a step between sticks of none
    ("thornton", "incremental", 64, 0.14490470081807333, 0.07438766902405017,
     3.2749811201870123, 0.8428124043928613, 62.141581576208466, 0.15),
]  # fmt: skip


@pytest.mark.parametrize("law, history, n, e, s0, lam, mu, kc, tol", _TIES)
def test_stick_and_slide_tied_at_one_instant_move_on(law, history, n, e, s0, lam, mu, kc, tol):
    """Such a column's solution converges as the steps shrink: on its own grid it agrees
    with the same column on 32× finer steps (within the coarse grid's discretisation error
    ``tol``), neither near the segment limit; where the slip never stops (Pt below s0/λ
    throughout: gross slip from the first step) Pt is μ·Pn, whose end is μ·(1 + e) (Routh's
    sliding impact)."""
    coarse = tangential_response(normal_pulse(law, np.array([e]), n), s0, lam, mu, kc,
                                 history=history)  # fmt: skip
    fine = tangential_response(normal_pulse(law, np.array([e]), 32 * n), s0, lam, mu, kc,
                               history=history)  # fmt: skip
    assert max(coarse.segments[0], fine.segments[0]) < 32
    scale = np.abs(fine.p).max()
    np.testing.assert_allclose(coarse.p[0], fine.p[0, ::32], rtol=0, atol=tol * scale)
    if not fine.slip_stops[0]:
        assert coarse.p[0].max() == pytest.approx(mu * (1.0 + e), rel=1e-3)
