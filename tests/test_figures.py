"""Tests of pipeline.figures: the plotted data must equal the physics, checked against closed
forms (seed eqs. 5–7, docs/theory.md, Rigid bodies) rather than against the code's own output.

SEED: Ciornei et al., MATEC Web Conf. 112, 07005 (2017), doi:10.1051/matecconf/201711207005,
Figs. 4 and 6.
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib
import numpy as np
import pytest

from pipeline import InputError
from pipeline.figures import (
    default_scenes,
    disc_kinks,
    fig4_percussion_plane,
    fig6_disc_velocity,
    save,
)
from pipeline.rigid import sphere_on_plane


def _by_gid(fig, gid):
    found = [a for a in fig.findobj() if a.get_gid() == gid]
    assert found, f"no artist with gid {gid!r}"
    return found


def _xy(line):
    return np.column_stack([line.get_xdata(), line.get_ydata()]).astype(float)


def _png_ok(path):
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(data) > 20_000  # a real drawing, not an empty canvas
    assert [p.name for p in path.parent.iterdir()] == [path.name]  # no temp files left


def test_fig4_draws_the_seed_construction(tmp_path, capsys):
    d = default_scenes()
    sl, st = d["fig4_sliding"], d["fig4_sticking"]
    fig = fig4_percussion_plane(sl, st)
    m, v, a, e = sl.m, sl.speed, math.radians(sl.angle_deg), sl.e
    # SEED eq. 5 and Fig. 4: C at m·v'·cos α, T at (1+e)·m·v'·cos α, S at (2/7)·m·v'·sin α
    (C,) = _by_gid(fig, "line-C")
    (T,) = _by_gid(fig, "line-T")
    (S,) = _by_gid(fig, "line-S")
    np.testing.assert_allclose(C.get_ydata(), m * v * math.cos(a), rtol=1e-12)
    np.testing.assert_allclose(T.get_ydata(), (1 + e) * m * v * math.cos(a), rtol=1e-12)
    np.testing.assert_allclose(S.get_xdata(), 2 / 7 * m * v * math.sin(a), rtol=1e-12)
    # the bold broken lines are exactly sphere_on_plane's vertices: O→E1 and O→A→E2 with
    # E1 = (μ(1+e)·m·v'·cos α, ·) and E2 = ((2/7)·m·v'·sin α, (1+e)·m·v'·cos α) (SEED eq. 7)
    (p_sl,) = _by_gid(fig, "path-sliding")
    (p_st,) = _by_gid(fig, "path-sticking")
    np.testing.assert_allclose(_xy(p_sl), sphere_on_plane(sl).vertices, rtol=1e-12)
    np.testing.assert_allclose(_xy(p_st), sphere_on_plane(st).vertices, rtol=1e-12)
    Pn_f = (1 + e) * m * v * math.cos(a)
    np.testing.assert_allclose(_xy(p_sl)[-1], [sl.mu * Pn_f, Pn_f], rtol=1e-12)
    np.testing.assert_allclose(_xy(p_st)[-1], [2 / 7 * m * v * math.sin(a), Pn_f], rtol=1e-12)
    # the ray at β ends at S ∩ T: tan β = 2·tan α/(7(1+e)) (SEED eq. 6)
    (ray,) = _by_gid(fig, "ray-beta")
    x, y = _xy(ray)[-1]
    assert x / y == pytest.approx(2 * math.tan(a) / (7 * (1 + e)), rel=1e-12)
    ax = p_sl.axes
    assert "[N" in ax.get_xlabel() and "[N" in ax.get_ylabel()
    assert ax.get_aspect() == 1.0  # equal scales: the drawn angles are the true ones
    labels = {t.get_text().strip() for t in fig.findobj(matplotlib.text.Text)}
    assert {"A", "$E_1$", "$E_2$", "(S)", "(C)", "(T)", r"$\beta$"} <= labels
    out = save(fig, tmp_path / "fig4.png")
    _png_ok(out)
    assert capsys.readouterr() == ("", "")


def test_fig4_two_panels_when_constructions_differ():
    d = default_scenes()
    fig = fig4_percussion_plane(d["fig4_sliding"], d["fig4_sticking"].replace(angle_deg=40.0))
    (p_sl,) = _by_gid(fig, "path-sliding")
    (p_st,) = _by_gid(fig, "path-sticking")
    assert p_sl.axes is not p_st.axes
    # shared limits so the two panels compare
    assert p_sl.axes.get_xlim() == p_st.axes.get_xlim()
    assert p_sl.axes.get_ylim() == p_st.axes.get_ylim()


@pytest.mark.parametrize("angle", [65.0, 40.0])  # one panel (the seed's); two panels
def test_fig4_labels_clear_of_the_friction_rays(angle):
    # a steep LF ray (μ = 0.2) crossing S near the top used to run through the "(S)" label
    d = default_scenes()
    fig = fig4_percussion_plane(d["fig4_sliding"], d["fig4_sticking"].replace(angle_deg=angle))
    for ax in {line.axes for g in ("path-sliding", "path-sticking") for line in _by_gid(fig, g)}:
        boxes = dict((t.strip(), b) for t, b in _rendered_text_boxes(ax))
        for line in ax.get_lines():
            if not str(line.get_gid()).startswith("lf-"):
                continue
            (x0, y0), (x1, y1) = _xy(line)
            s = np.linspace(0, 1, 400)[:, None]
            pts = ax.transData.transform(
                np.column_stack([x0 + s[:, 0] * (x1 - x0), y0 + s[:, 0] * (y1 - y0)])
            )
            for name in ("(S)", "(C)", "(T)"):
                b = boxes[name]
                inside = (
                    (pts[:, 0] > b.x0)
                    & (pts[:, 0] < b.x1)
                    & (pts[:, 1] > b.y0)
                    & (pts[:, 1] < b.y1)
                )
                assert not inside.any(), (angle, line.get_gid(), name)


def test_fig4_rejects_a_scene_in_the_wrong_regime():
    d = default_scenes()
    with pytest.raises(InputError, match="scene_sliding is in the sticking regime"):
        fig4_percussion_plane(d["fig4_sticking"], d["fig4_sticking"])


def test_fig6_kink_at_the_closed_form_u_star(tmp_path):
    # Ball dropped vertically (v_n0 = v') on a disc moving at u: relative slip −u.
    # Sticking exit: Pt = (2/7)·m·u, lab velocity v_x'' = Pt/m = (2/7)·u.
    # Sliding exit: Pt = μ(1+e)·m·v', v_x'' = μ(1+e)·v'.
    # They meet at u* = 3.5·μ·(1+e)·v' (docs/theory.md, Rigid bodies regime test with tan α → u/v').
    scene = default_scenes()["fig6"]
    mu, e, v = scene.mu, scene.e, scene.speed
    u_star = 3.5 * mu * (1 + e) * v
    fig = fig6_disc_velocity(scene, np.linspace(0.0, 3.0, 61))
    (kink,) = _by_gid(fig, "kink")
    np.testing.assert_allclose(kink.get_xdata(), [u_star], rtol=1e-12)
    np.testing.assert_allclose(kink.get_ydata(), [2 / 7 * u_star], rtol=1e-12)
    assert disc_kinks(scene)[1] == pytest.approx(u_star, rel=1e-12)
    (curve,) = _by_gid(fig, "v-x")
    u, vx = _xy(curve).T
    assert np.isclose(u, u_star, rtol=1e-12).any()  # the corner is a vertex of the polyline
    np.testing.assert_allclose(vx, np.minimum(2 / 7 * u, mu * (1 + e) * v), rtol=1e-12, atol=1e-15)
    # slopes either side of the kink, from the plotted points
    left, right = u <= u_star, u >= u_star
    assert np.polyfit(u[left], vx[left], 1)[0] == pytest.approx(2 / 7, rel=1e-9)
    assert np.polyfit(u[right], vx[right], 1)[0] == pytest.approx(0.0, abs=1e-12)
    # and the regime really changes there
    just = sphere_on_plane(scene.replace(surface_speed=np.array([0.999, 1.001]) * u_star))
    assert list(just.regime) == ["sticking", "sliding"]
    ax = curve.axes
    assert "[m/s]" in ax.get_xlabel() and "[m/s]" in ax.get_ylabel()
    _png_ok(save(fig, tmp_path / "fig6.png"))


def test_fig6_symmetric_range_has_two_kinks_and_odd_curve():
    scene = default_scenes()["fig6"]
    u_star = 3.5 * scene.mu * (1 + scene.e) * scene.speed
    fig = fig6_disc_velocity(scene, np.linspace(-2.5, 2.5, 41))
    (kink,) = _by_gid(fig, "kink")
    np.testing.assert_allclose(np.sort(kink.get_xdata()), [-u_star, u_star], rtol=1e-12)
    u, vx = _xy(_by_gid(fig, "v-x")[0]).T
    np.testing.assert_allclose(vx, -vx[::-1], atol=1e-15)  # odd in u: mirror image


def test_fig6_bad_input():
    scene = default_scenes()["fig6"]
    with pytest.raises(InputError, match="angle_deg = 0"):
        fig6_disc_velocity(scene.replace(angle_deg=10.0))
    with pytest.raises(InputError, match="two finite"):
        fig6_disc_velocity(scene, [1.0])


def test_figures_leave_pyplot_alone():
    import matplotlib.pyplot as plt

    before = plt.get_fignums()
    fig4_percussion_plane()
    fig6_disc_velocity()
    assert plt.get_fignums() == before


def test_fig4_symbols_follow_the_scene():
    # The seed's symbols ((2/7)·m·v'·sin α ...) hold only for a ball without spin on a still,
    # fixed plane; with spin the general m_t·|s0| labels are used and the S line moves to
    # Pt = (2/7)·m·|v'·sin α − ω0·R| (docs/theory.md, Sign conventions).
    d = default_scenes()
    sl, st = d["fig4_sliding"].replace(spin=-30.0), d["fig4_sticking"].replace(spin=-30.0)
    fig = fig4_percussion_plane(sl, st)
    texts = {t.get_text() for t in fig.findobj(matplotlib.text.Text)}
    assert r"$m_t\,|s_0|$" in texts and not any("sin" in t for t in texts)
    (S,) = _by_gid(fig, "line-S")
    s0 = sl.speed * math.sin(math.radians(sl.angle_deg)) + 30.0 * sl.radius
    np.testing.assert_allclose(S.get_xdata(), 2 / 7 * sl.m * s0, rtol=1e-12)


def _rendered_text_boxes(ax):
    """Window extents of the visible, non-empty texts drawn in ``ax`` (after a real draw)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = ax.figure
    FigureCanvasAgg(fig).draw()
    r = fig.canvas.get_renderer()
    return [
        (t.get_text(), t.get_window_extent(r))
        for t in ax.texts
        if t.get_visible() and t.get_text().strip()
    ]


@pytest.mark.parametrize(
    "spin, speeds",
    [(0.0, None), (-20.0, None), (0.0, np.linspace(-2.5, 2.5, 41))],
)
def test_fig6_labels_inside_the_axes_and_apart(spin, speeds):
    # with a spin the sticking line crosses v = 0 and the sliding label used to be placed
    # below the axes, over the tick labels
    fig = fig6_disc_velocity(default_scenes()["fig6"].replace(spin=spin), speeds)
    (curve,) = _by_gid(fig, "v-x")
    ax = curve.axes
    boxes = _rendered_text_boxes(ax)
    assert len(boxes) >= 3
    frame, page = ax.get_window_extent(), fig.bbox
    for text, b in boxes:
        # above the x tick labels and below the top of the axes; sideways the u* note may
        # reach into the right margin, but not off the page
        assert frame.y0 <= b.y0 and b.y1 <= frame.y1, text
        assert page.x0 <= b.x0 and b.x1 <= page.x1, text
    for i, (ta, a) in enumerate(boxes):
        for tb, b in boxes[i + 1 :]:
            assert not a.overlaps(b), (ta, tb)


@pytest.fixture(scope="module")
def sticking_analysis():
    """A sticking-regime Coulomb impact (tan α < 3.5·μ·(1+e)) analysed with μ and e taken
    from the record while the scene's guesses are off."""
    import warnings

    from pipeline import Scene, analyse
    from pipeline.errors import PoorFitWarning
    from pipeline.simulate import impact

    truth = Scene(
        radius=0.0127, density=7850.0, E=210e9, nu=0.29, speed=0.5, angle_deg=15.0, mu=0.3, e=0.8
    )
    rec = impact(truth, tangential="coulomb")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PoorFitWarning)
        return analyse(rec, truth.replace(mu=0.6, e=0.5), mu="record", e="record", n_boot=0)


def test_fig9_names_the_rigid_lines_and_states_the_mu_it_drew(sticking_analysis):
    from pipeline.figures import fig9_percussion_plane

    a = sticking_analysis
    assert a.rigid.regime == "sticking"
    assert a.rigid_scene.mu == pytest.approx(0.3, rel=0.02)  # from the record, not 0.6
    fig = fig9_percussion_plane(a)
    (line,) = _by_gid(fig, "rigid-line")
    ax = line.axes
    np.testing.assert_allclose(_xy(line), np.asarray(a.rigid.vertices) * 1e3, rtol=1e-12)
    # the title quotes the μ and e the broken line was drawn with
    assert f"μ = {a.rigid_scene.mu:.3g}" in ax.get_title()
    assert f"e = {a.rigid_scene.e:.3g}" in ax.get_title()
    boxes = _rendered_text_boxes(ax)
    labels = [t for t, _ in boxes]
    for name in ("LF", "(S)", "A", "$E_2$", "(C)", "(T)"):
        assert any(t.strip() == name for t in labels), name
    # no label lies on the measured curve (nor on another label)
    curve = np.vstack(
        [
            _xy(line)
            for gid in ("measured-compression", "measured-restitution")
            for line in _by_gid(fig, gid)
        ]
    )
    pts = ax.transData.transform(curve[np.all(np.isfinite(curve), axis=1)])
    for text, b in boxes:
        inside = (pts[:, 0] > b.x0) & (pts[:, 0] < b.x1) & (pts[:, 1] > b.y0) & (pts[:, 1] < b.y1)
        assert not inside.any(), text
    for i, (ta, a) in enumerate(boxes):
        for tb, b in boxes[i + 1 :]:
            assert not a.overlaps(b), (ta, tb)


def test_fig8_legend_clear_of_the_data(sticking_analysis):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from pipeline.figures import fig8_forces

    fig = fig8_forces(sticking_analysis)
    FigureCanvasAgg(fig).draw()
    r = fig.canvas.get_renderer()
    (leg,) = fig.legends
    for ax in fig.axes:
        assert not leg.get_window_extent(r).overlaps(ax.get_window_extent(r))
    assert "[N]" in fig.axes[0].get_ylabel() and "[$\\mu$s]" in fig.axes[1].get_xlabel()


# ------------------------------------------------------------------ inside the canvas
@pytest.fixture(scope="module")
def record_figures(tmp_path_factory, sticking_analysis):
    """Every figure of a record the project draws (seed Figs. 8 and 9, the contact fit), for
    a sticking and a sliding sample and for a record whose name is long."""
    import shutil
    import warnings

    from pipeline import analyse, fit_contact
    from pipeline.figures import fig8_forces, fig9_percussion_plane, fig_contact_fit
    from pipeline.report import load_sample, scene_from_sidecar

    samples = Path(__file__).resolve().parents[1] / "data_samples"
    long = tmp_path_factory.mktemp("long") / ("a_record_named_by_its_rig_and_date_" * 2 + ".csv")
    shutil.copy(samples / "gr_15deg_0.6ms.csv", long)
    cases = {
        "15deg": (load_sample(samples / "gr_15deg_0.6ms.csv"), "gr_15deg_0.6ms.csv"),
        "45deg": (load_sample(samples / "gr_45deg_0.3ms.csv"), "gr_45deg_0.3ms.csv"),
        "long name": (load_sample(long), "gr_15deg_0.6ms.csv"),
    }
    figs = {"fig9 sticking Coulomb": fig9_percussion_plane(sticking_analysis)}
    for case, (rec, sidecar) in cases.items():
        scene = scene_from_sidecar(samples / sidecar)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            a = analyse(rec, scene, n_boot=0)
            fit = fit_contact(rec, scene.replace(mu=None), n_boot=0)
        figs[f"fig8 {case}"] = fig8_forces(a)
        figs[f"fig9 {case}"] = fig9_percussion_plane(a)
        figs[f"fit {case}"] = fig_contact_fit(fit)
    return figs


def test_every_figure_lies_inside_its_canvas(record_figures):
    """Titles, labels and legends inside the canvas at the size each figure is drawn, in
    its first draw: the reports show figures as drawn (no tight crop), so anything outside
    is cut there (issue 21: the seed's Fig. 9 lost the start of its title and the end of
    its legend). The campaign's figures: tests/test_campaign.py."""
    from _canvas import outside_canvas

    d = default_scenes()
    figs = {
        **record_figures,
        "fig4": fig4_percussion_plane(),
        "fig4 two panels": fig4_percussion_plane(
            d["fig4_sliding"], d["fig4_sticking"].replace(angle_deg=40.0)
        ),
        "fig6": fig6_disc_velocity(),
        "fig6 spin": fig6_disc_velocity(d["fig6"].replace(spin=-20.0)),
    }
    out = {name: outside_canvas(fig) for name, fig in figs.items()}
    assert not {k: v for k, v in out.items() if v}, out
