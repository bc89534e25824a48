"""The seed paper's figures, redrawn from the pipeline's results: Fig. 4 (Routh's plane of
percussions), Fig. 6 (the rotating disc), Fig. 8 (a record's forces and their fits) and
Fig. 9 (the measured Pt(Pn) over the rigid broken line); see :mod:`pipeline.figures`.

References
----------
F.-C. Ciornei et al., MATEC Web Conf. 112, 07005 (2017), doi:10.1051/matecconf/201711207005,
Figs. 4, 6, 8 and 9. S. Alaci, F. C. Ciornei, C. Filote, J. Balkan Tribol. Assoc. 22(2), 1552 (2016)
(the rotating-disc rig).
"""

from __future__ import annotations

import math

import matplotlib as mpl
import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Arc

from ..errors import InputError
from ..record import channel
from ..rigid import SphereOnPlane, sphere_on_plane
from ..scene import Scene
from .style import COLORS, DOUBLE, SINGLE, fitting_text, new_figure, panel_label, style

__all__ = [
    "default_scenes",
    "fig4_percussion_plane",
    "disc_kinks",
    "fig6_disc_velocity",
    "fig8_forces",
    "fig9_percussion_plane",
]


def default_scenes() -> dict:
    """The illustrative scenes the figures use when none is given.

    A 25.4 mm steel ball (67 g, as data_samples/README.md) at 1 m/s, e = 0.5, on a plane tilted
    65° (fig. 4; μ = 0.2 slides throughout, μ = 0.7 sticks in compression) and dropped on a
    disc, e = 0.8, μ = 0.15 (fig. 6).
    """
    base = Scene(radius=0.0127, mass=0.067, speed=1.0)
    return {
        "fig4_sliding": base.replace(angle_deg=65.0, mu=0.2, e=0.5),
        "fig4_sticking": base.replace(angle_deg=65.0, mu=0.7, e=0.5),
        "fig6": base.replace(angle_deg=0.0, mu=0.15, e=0.8),
    }


# ------------------------------------------------------------------------- Fig. 4
def _angle_arc(ax, angle, radius, label, color):
    """Arc from the Pn axis (vertical) to a ray at ``angle`` [rad] clockwise from it,
    labelled just past the ray's end of the arc (in data units; needs an equal aspect)."""
    deg = math.degrees(angle)
    ax.add_patch(
        Arc((0, 0), 2 * radius, 2 * radius, theta1=90 - deg, theta2=90, color=color, lw=0.8)
    )
    a = math.radians(90 - deg) - 0.05
    ax.text(
        radius * math.cos(a),
        radius * math.sin(a),
        " " + label,
        color=color,
        ha="left",
        va="center",
        fontsize=8,
    )


def _kappa_text(kappa):
    """κ/(1+κ) as a TeX fraction (2/7 for a solid sphere)."""
    frac = kappa / (1 + kappa)
    for den in range(1, 30):
        num = frac * den
        if abs(num - round(num)) < 1e-9:
            return rf"\frac{{{round(num)}}}{{{den}}}"
    return rf"{frac:.3g}"


def _plane_limits(results):
    """Axis limits (Pt_hi, Pn_hi) [N·s] that show the construction of every result."""
    x_hi = max(2.0 * r.Pt_S if r.Pt_S > 0 else 2.0 * float(r.mu) * r.Pn_f for r in results)
    y_hi = max(1.22 * r.Pn_f for r in results)
    return max(x_hi, 1e-12), max(y_hi, 1e-12)


def _draw_plane(ax, results, names, colors, limits=None, seed_labels=True):
    """Draw S, C, T of ``results[0]`` and the LF line and path of each result."""
    ref = results[0]
    Pt_S, Pn_c, Pn_f = ref.Pt_S, ref.Pn_c, ref.Pn_f
    x_hi, y_hi = _plane_limits(results) if limits is None else limits
    grey = COLORS["construction"]

    # construction lines C, T, S and the ray O-B (B = S ∩ T) at angle β
    ax.plot([0, x_hi], [Pn_c, Pn_c], ls="--", lw=0.9, color=grey, gid="line-C")
    ax.plot([0, x_hi], [Pn_f, Pn_f], ls="-", lw=0.9, color=grey, gid="line-T")
    ax.plot([Pt_S, Pt_S], [0, y_hi], ls="-", lw=0.9, color=grey, gid="line-S")
    for y, name in ((Pn_c, "(C)"), (Pn_f, "(T)")):
        # at the right end of its line, or left of a friction ray that crosses it there
        x = 0.98 * x_hi
        for res in results:
            cross = float(res.mu) * y
            if 0.7 * x_hi < cross < x_hi:
                x = min(x, cross - 0.03 * x_hi)
        ax.text(x, y, name, va="bottom", ha="right", color=grey)
    # (S) at the top of its line, unless a friction ray crosses S there (steep LF with a
    # small sticking abscissa): then right of S between C and T, where only the β ray runs
    y_s = 0.985 * y_hi
    for res in results:
        mu = float(res.mu)
        if mu > 0 and abs(Pt_S / mu - 0.95 * y_hi) < 0.12 * y_hi:
            y_s = 0.5 * (Pn_c + Pn_f)
    ax.text(Pt_S, y_s, " (S)", va="top" if y_s > Pn_f else "center", ha="left", color=grey)
    ax.plot([0, Pt_S], [0, Pn_f], ls=":", lw=0.9, color=grey, gid="ray-beta")

    arc_r = 0.42 * Pn_c
    _angle_arc(ax, float(ref.beta), arc_r, r"$\beta$", grey)
    for k, (res, name, col) in enumerate(zip(results, names, colors, strict=True)):
        mu = float(res.mu)
        tag = f"{k + 1}" if len(results) > 1 else ""
        # LF: full ray (thin), the travelled part bold
        Pn_end_ray = min(y_hi, x_hi / mu) if mu > 0 else y_hi
        ax.plot(
            [0, mu * Pn_end_ray], [0, Pn_end_ray], lw=0.7, color=col, alpha=0.6, gid=f"lf-{name}"
        )
        txt_n = 0.93 * Pn_end_ray
        ax.text(
            mu * txt_n,
            txt_n,
            rf"  $_{{{tag}}}$LF" if tag else "  LF",
            color=col,
            ha="left",
            va="center",
        )
        v = np.asarray(res.vertices)
        ax.plot(v[:, 0], v[:, 1], lw=2.0, color=col, solid_joinstyle="miter", gid=f"path-{name}")
        ax.plot(v[-1, 0], v[-1, 1], "o", color=col, ms=4.5, zorder=5)
        if res.regime == "sliding":
            ax.text(v[-1, 0], v[-1, 1], r"$E_1$ ", color=col, ha="right", va="bottom")
        else:
            ax.plot(v[1, 0], v[1, 1], "s", color=col, ms=4, zorder=5)
            ax.text(v[1, 0], v[1, 1], "  A", color=col, ha="left", va="center")
            ax.text(v[-1, 0], v[-1, 1], r"$E_2$  ", color=col, ha="right", va="bottom")
        _angle_arc(
            ax,
            float(res.phi),
            (1.5 if res.regime == "sliding" else 0.6) * arc_r,
            rf"$\varphi_{{{tag}}}$" if tag else r"$\varphi$",
            col,
        )

    # symbolic values of the lines on the opposite axes (as in the seed's Fig. 4)
    if seed_labels:  # ball dropped on a still, fixed plane without spin: the seed's symbols
        kap = _kappa_text(float(ref.kappa))
        s_lab = rf"${kap}\,m v'\sin\alpha$"
        c_lab, t_lab = r"$m v'\cos\alpha$", r"$(1+e)\,m v'\cos\alpha$"
    else:  # spin, moving surface or free target: the general expressions
        s_lab = r"$m_t\,|s_0|$"
        c_lab, t_lab = r"$m^* v_{n0}$", r"$(1+e)\,m^* v_{n0}$"
    top = ax.secondary_xaxis("top")
    top.set_xticks([Pt_S], [s_lab])
    top.tick_params(direction="in", length=3)
    right = ax.secondary_yaxis("right")
    right.set_yticks([Pn_c, Pn_f], [c_lab, t_lab])
    right.tick_params(direction="in", length=3)
    for sec in (top, right):
        sec.spines[:].set_visible(False)

    ax.set_xlim(0, x_hi)
    ax.set_ylim(0, y_hi)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel(r"tangential percussion $P_t$ [N$\cdot$s]")
    ax.set_ylabel(r"normal percussion $P_n$ [N$\cdot$s]")
    ax.spines[["top", "right"]].set_visible(False)


def _sketch_ball_on_plane(ax, alpha):
    """Small inset: ball falling with velocity v' on a plane tilted α from the horizontal,
    with the contact axes t (down the slope) and n (outward normal)."""
    ins = ax.inset_axes([0.56, 0.02, 0.44, 0.36])
    ins.set_axis_off()
    ins.set_aspect("equal")
    ca, sa = math.cos(alpha), math.sin(alpha)
    t = np.array([ca, -sa])  # down the slope (direction of the initial slip)
    n = np.array([sa, ca])  # outward normal of the plane
    c = np.array([0.0, 0.0])  # contact point
    lo_end, hi_end = c + 1.1 * t, c - 1.4 * t
    ins.plot(*np.stack([hi_end, lo_end]).T, color="black", lw=1.0)
    for k in np.linspace(-1.35, 1.0, 9):  # hatching on the solid side
        p = c + k * t
        ins.plot(*np.stack([p, p - 0.16 * n + 0.1 * t]).T, color="black", lw=0.5)
    R = 0.42
    g = c + R * n
    ins.add_patch(mpl.patches.Circle(g, R, fc="0.88", ec="black", lw=0.8))
    kw = {"arrowstyle": "-|>", "lw": 0.8, "mutation_scale": 6, "shrinkA": 0, "shrinkB": 0}
    top = g + np.array([0, R + 0.75])
    ins.annotate("", g + np.array([0, R + 0.05]), top, arrowprops=dict(kw, color="black"))
    ins.text(*(top + np.array([0.08, -0.3])), "$v'$", fontsize=7, ha="left", va="center")
    ins.annotate("", c + 1.25 * n, c, arrowprops=dict(kw, color="0.4"))
    ins.text(*(c + 1.3 * n), "$n$", fontsize=7, ha="left", va="bottom", color="0.3")
    ins.annotate(
        "", c + 1.0 * t + 0.12 * n, c + 0.35 * t + 0.12 * n, arrowprops=dict(kw, color="0.4")
    )
    ins.text(*(c + 1.0 * t + 0.2 * n), "$t$", fontsize=7, ha="left", va="bottom", color="0.3")
    # the tilt α between the horizontal and the plane, at the lower end
    ins.plot(*np.stack([lo_end, lo_end - np.array([0.9, 0.0])]).T, color="black", lw=0.6)
    deg = math.degrees(alpha)
    ins.add_patch(
        mpl.patches.Arc(lo_end, 1.0, 1.0, theta1=180 - deg, theta2=180, color="0.3", lw=0.6)
    )
    mid = math.radians(180 - deg / 2)
    ins.text(
        *(lo_end + 0.62 * np.array([math.cos(mid), math.sin(mid)])),
        r"$\alpha$",
        fontsize=7,
        ha="right",
        va="center",
    )
    pts = np.stack([hi_end, lo_end, top, c + 1.3 * n, lo_end - np.array([0.9, 0.0])])
    ins.set_xlim(pts[:, 0].min() - 0.2, pts[:, 0].max() + 0.3)
    ins.set_ylim(pts[:, 1].min() - 0.2, pts[:, 1].max() + 0.2)
    return ins


def _same_construction(a: SphereOnPlane, b: SphereOnPlane):
    return all(
        math.isclose(float(getattr(a, k)), float(getattr(b, k)), rel_tol=1e-9)
        for k in ("Pt_S", "Pn_c", "Pn_f")
    )


def fig4_percussion_plane(scene_sliding: Scene = None, scene_sticking: Scene = None) -> Figure:
    """Seed Fig. 4: Routh's plane of percussions for a ball striking a tilted plane.

    Parameters
    ----------
    scene_sliding : Scene, optional
        A scalar scene in the sliding regime (μ ≤ tan β); drawn as 1LF → E1.
    scene_sticking : Scene, optional
        A scalar scene in the sticking regime; drawn as 2LF → A → E2 along S.
        Defaults for both: :func:`default_scenes`.

    Returns
    -------
    matplotlib.figure.Figure
        One panel when both scenes share the lines S, C, T (they differ only in μ, as in
        the seed's figure), otherwise two panels (a) sliding, (b) sticking. Pt is
        horizontal, Pn vertical, both [N·s], equal scales so the angles are true: the
        friction angles φ = atan μ and β (seed eq. 6) are measured from the Pn axis; the
        dotted ray O–B (B = S ∩ T) at angle β separates the regimes. Artists with a
        ``gid``: ``"path-sliding"``, ``"path-sticking"`` (the rigid broken lines, their
        data equal :attr:`SphereOnPlane.vertices`), ``"line-C"``, ``"line-T"``,
        ``"line-S"``, ``"ray-beta"``.

    Raises
    ------
    InputError
        If a scene is an array of scenes, or is not in the regime its argument names.
    """
    d = default_scenes()
    scene_sliding = d["fig4_sliding"] if scene_sliding is None else scene_sliding
    scene_sticking = d["fig4_sticking"] if scene_sticking is None else scene_sticking
    results = []
    for scene, want in ((scene_sliding, "sliding"), (scene_sticking, "sticking")):
        res = sphere_on_plane(scene)
        if np.ndim(res.Pn_f) != 0:
            raise InputError("fig4_percussion_plane draws single scenes, not arrays of scenes")
        if res.regime != want:
            raise InputError(
                f"fig4_percussion_plane: scene_{want} is in the {res.regime} regime "
                f"(μ = {float(res.mu):.3g}, tan β = {math.tan(float(res.beta)):.3g}); "
                f"{'lower' if want == 'sliding' else 'raise'} μ or change the angle"
            )
        results.append(res)
    names = ("sliding", "sticking")
    colors = (COLORS["sliding"], COLORS["sticking"])
    seed_labels = all(
        float(sc.spin) == 0 and float(sc.surface_speed) == 0 and math.isinf(sc.target_mass)
        for sc in (scene_sliding, scene_sticking)
    )
    with style():
        if _same_construction(*results):
            fig, ax = new_figure(width=SINGLE, height=4.0, layout="compressed")
            _draw_plane(ax, results, names, colors, seed_labels=seed_labels)
            _sketch_ball_on_plane(ax, math.radians(float(scene_sliding.angle_deg)))
        else:
            fig, axes = new_figure(1, 2, width=DOUBLE, height=4.0, layout="compressed")
            scenes = (scene_sliding, scene_sticking)
            for ax, res, scene, name, col, tag in zip(
                axes, results, scenes, names, colors, ("(a)", "(b)"), strict=True
            ):
                _draw_plane(
                    ax,
                    [res],
                    [name],
                    [col],
                    limits=_plane_limits(results),
                    seed_labels=seed_labels,
                )
                _sketch_ball_on_plane(ax, math.radians(float(scene.angle_deg)))
                panel_label(ax, tag, x=-0.12)
        return fig


# ------------------------------------------------------------------------- Fig. 6
def disc_kinks(scene: Scene):
    """Surface speeds u* [m/s] where a ball dropped on a moving surface changes regime.

    Returns ``(u_minus, u_plus)`` [m/s] with u± = ±U − ω0·R and
    U = (1+κ)/κ·μ·(1+e)·v_n0 (= 3.5·μ·(1+e)·v' for a solid sphere): the slip s0 = −u − ω0·R
    at which the sticking line S, Pt = κ/(1+κ)·m·|s0|, meets the termination line T on
    the friction line LF, μ·(1+e)·m·v_n0 (seed eq. 6 with tan α → |s0|/v_n0). The disc
    is a fixed target (``target_mass = inf``).
    """
    kappa = float(scene.kappa)
    U = (1 + kappa) / kappa * float(scene.mu) * (1 + float(scene.e)) * float(scene.v_n0)
    s = float(scene.spin) * float(scene.radius)
    return (-U - s, U - s)


def fig6_disc_velocity(scene: Scene = None, surface_speeds=None) -> Figure:
    """Analogue of seed Fig. 6: post-impact horizontal velocity of a ball dropped on a disc.

    A ball falls vertically (``angle_deg = 0``) onto a horizontal disc whose surface moves
    at speed u under the impact point. Relative to the surface the ball slips at
    s0 = −u − ω0·R, i.e. the scene is ``scene.replace(surface_speed=u)`` and
    :func:`~pipeline.rigid.sphere_on_plane` gives ``v_t``, the ball's tangential velocity
    relative to the surface after impact. In the laboratory frame the ball leaves with

    .. math::

        v_x'' = v_t + u = \\operatorname{sign}(u)\\,\\frac{P_t}{m} =
        \\begin{cases} \\frac{\\kappa}{1+\\kappa}\\,u
                       & |u| \\le u^* \\text{ (sticks: leaves rolling)} \\\\
                       \\operatorname{sign}(u)\\,\\mu(1+e)\\,v' & |u| \\ge u^*
                       \\text{ (slides throughout)} \\end{cases}

    (no initial spin; positive along the surface's motion; the friction impulse drags the
    ball along, Pt ≥ 0 opposing the initial slip −u), with the kink at
    u* = (1+κ)/κ·μ(1+e)·v' = 3.5·μ(1+e)·v' for a solid sphere (:func:`disc_kinks`; with a
    spin ω0 the kinks shift by −ω0·R). Rigid theory thus predicts a linear rise and then a
    plateau; the seed (its Fig. 6, after Alaci et al. 2016) reports a measured run-out
    distance that rises linearly up to a critical disc speed and decreases beyond it.

    Parameters
    ----------
    scene : Scene, optional
        Ball, drop speed ``speed`` [m/s], ``mu``, ``e``, ``kappa``, ``spin``; a scalar
        scene with ``angle_deg == 0`` (its ``surface_speed`` is ignored). Default:
        :func:`default_scenes` ``["fig6"]``.
    surface_speeds : array_like, optional
        Disc surface speeds u [m/s] to plot; default 0 … 2.5·u* (201 points). The kink
        points u* inside the range are inserted so the polyline shows the corner exactly.

    Returns
    -------
    matplotlib.figure.Figure
        Artists with a ``gid``: ``"v-x"`` (the curve: x = u [m/s], y = v_x'' [m/s]),
        ``"kink"`` (marker(s) at (u*, v_x''(u*))).

    Raises
    ------
    InputError
        For an array scene or a non-zero ``angle_deg``.
    """
    scene = default_scenes()["fig6"] if scene is None else scene
    if np.ndim(scene.speed) or any(np.ndim(getattr(scene, f)) for f in Scene.field_names()):
        raise InputError("fig6_disc_velocity takes a single scene, not an array of scenes")
    if float(scene.angle_deg) != 0.0:
        raise InputError(
            "fig6_disc_velocity: the disc rig drops the ball vertically; give angle_deg = 0 "
            f"(got {scene.angle_deg} deg)"
        )
    kinks = disc_kinks(scene)
    if surface_speeds is None:
        hi = 2.5 * max(abs(kinks[1]), 1e-3)
        surface_speeds = np.linspace(0.0, hi, 201)
    u = np.asarray(surface_speeds, dtype=float).ravel()
    if u.size < 2 or not np.all(np.isfinite(u)):
        raise InputError("fig6_disc_velocity needs at least two finite surface speeds [m/s]")
    lo, hi = u.min(), u.max()
    inside = [k for k in kinks if lo < k < hi and float(scene.mu) > 0]
    u = np.unique(np.concatenate([u, inside]))
    res = sphere_on_plane(scene.replace(surface_speed=u))
    vx = np.asarray(res.v_t_scene) + u  # laboratory frame: relative velocity + surface speed
    stick = np.asarray(res.regime) == "sticking"
    kap = float(scene.kappa)
    m_ratio = float(np.asarray(res.m_eff).flat[0]) / float(scene.m)
    shift = float(scene.spin) * float(scene.radius)
    U = kinks[1] + shift  # u* without the spin's shift: (1+κ)/κ·μ(1+e)·v_n0
    plateau = kap / (1 + kap) * m_ratio * U  # = μ(1+e)·(m*/m)·v'
    vx_k = np.array([float(np.asarray(vx)[np.searchsorted(u, k)]) for k in inside], dtype=float)

    with style():
        fig, ax = new_figure(width=SINGLE, height=2.7)
        grey = COLORS["construction"]
        span = hi - lo
        if inside:  # shade the sticking band between the kinks (or a kink and the edge)
            band_lo = min(inside) if (len(inside) == 2 or inside[0] < -shift) else lo
            band_hi = max(inside) if (len(inside) == 2 or inside[0] > -shift) else hi
            ax.axvspan(band_lo, band_hi, color=COLORS["sticking"], alpha=0.08, lw=0)
        ax.plot(u, vx, color="black", lw=1.6, gid="v-x", zorder=3)
        dash = {"ls": (0, (4, 3)), "lw": 0.8, "color": grey, "zorder": 2}
        for uk, vk in zip(inside, vx_k, strict=True):
            side = 1.0 if uk > -shift else -1.0
            # each branch continued a little past the kink, to show the corner (short enough
            # to stay clear of the regime labels)
            ue = np.array([uk, uk + side * 0.08 * span])
            ax.plot(ue, kap / (1 + kap) * m_ratio * (ue + shift), **dash)
            ax.plot([uk - side * 0.08 * span, uk], [vk, vk], **dash)
            ax.axvline(uk, color=grey, lw=0.6, ls=":")
            if side > 0:
                text = (
                    rf"$u^* = {_kappa_inv_text(kap)}\,\mu(1+e)\,v'$" + "\n$\\;\\,$= "
                    if shift == 0
                    else "$u^*$ = "
                )
                ax.annotate(
                    text + f"{uk:.3g} m/s",
                    xy=(uk, vk),
                    xytext=(10, -34),
                    textcoords="offset points",
                    fontsize=8,
                    arrowprops={"arrowstyle": "-", "lw": 0.6, "color": "0.3"},
                )
            else:  # the mirror kink: a short tag
                ax.annotate(
                    "$-u^*$" if shift == 0 else f"{uk:.3g} m/s".replace("-", "\u2212"),
                    xy=(uk, vk),
                    xytext=(-6, 6),
                    textcoords="offset points",
                    ha="right",
                    va="bottom",
                    fontsize=8,
                )
        if inside:
            ax.plot(inside, vx_k, "o", color="black", mfc="white", ms=5, zorder=5, gid="kink")
        y_lo = min(0.0, float(np.min(vx)) * 1.25)
        # the curve fills the lower 72 % of the axes: the regime label (three lines at the
        # top, ~20 % of the height) stays clear of the plateau and the kink's dashes
        y_hi = y_lo + (max(float(np.max(vx)), plateau, 1e-12) - y_lo) / 0.72
        if stick.any():
            xs = u[stick]
            u_sym = "u" if shift == 0 else r"(u + \omega_0 R)"
            ax.text(
                0.5 * (xs.min() + xs.max()),
                0.97,
                "sticking:\nleaves rolling\n" + rf"$v_x'' = {_kappa_text(kap)}\,{u_sym}$",
                transform=ax.get_xaxis_transform(),  # x in m/s, y as a fraction of the axes
                color=COLORS["sticking"],
                ha="center",
                va="top",
                fontsize=8,
            )
        right = ~stick & (u > -shift)
        if right.any():
            xs = u[right]
            ax.text(
                0.5 * (xs.min() + xs.max()),
                # under the plateau, below the u* note; below v = 0 when that band is larger
                0.35 * plateau if plateau >= -y_lo else 0.5 * y_lo,
                "sliding throughout\n" + r"$v_x'' = \mu(1+e)\,v'$",
                color=COLORS["sliding"],
                ha="center",
                va="center",
                fontsize=8,
            )
        ax.axhline(0.0, color="black", lw=0.5) if y_lo < 0 else None
        ax.set_xlim(lo, hi)
        ax.set_ylim(y_lo, y_hi)
        ax.set_xlabel(r"surface speed of the disc under the ball $u$ [m/s]")
        ax.set_ylabel(r"velocity after impact $v_x''$ [m/s]")
        return fig


def _kappa_inv_text(kappa):
    """(1+κ)/κ as text (3.5 for a solid sphere)."""
    return f"{(1 + kappa) / kappa:.3g}"


# ============================================================== measured records (seed Figs. 8, 9)
def _name_record(ax, analysis) -> None:
    """Name the record a figure shows (file name and impact) in the top axes' title."""
    sc = analysis.scene
    src = analysis.record.attrs.get("source", "record")
    width = ax.figure.get_figwidth() * 0.8
    title = fitting_text(f"{src}: {sc.speed:g} m/s at {sc.angle_deg:g}°", width, 7)
    ax.set_title(title, fontsize=7, loc="right")


def fig8_forces(analysis) -> Figure:
    """Seed Fig. 8: the measured forces, their quartic fits and the fits' residuals.

    Parameters
    ----------
    analysis : pipeline.analysis.Analysis
        From :func:`pipeline.analyse`; its window record (baseline removed) gives the
        samples and its ``fits`` the polynomials.

    Returns
    -------
    Figure
        Top: Fn and Ft samples (markers, gid ``samples-Fn``/``samples-Ft``) and fits
        (lines, gid ``fit-Fn``/``fit-Ft``) against time [µs] from contact start, the
        instant of maximum compression dashed. Bottom: residuals [N].
    """
    a = analysis
    rec = a.window.record
    t0 = a.window.t_start
    with style():
        fig, (ax, axr) = new_figure(
            2, 1, width=SINGLE, height=3.9, sharex=True, gridspec_kw={"height_ratios": [2.3, 1.0]}
        )
        tt = np.linspace(a.window.t_start, a.window.t_end, 600)
        cols = {"Fn": COLORS["sliding"], "Ft": COLORS["sticking"]}
        labels = {"Fn": r"$F_n$", "Ft": r"$F_t$"}
        every = 1
        for name in ("Fn", "Ft"):
            fitc = getattr(a.fits, name)
            if fitc is None or name not in rec:
                continue
            t, f = channel(rec, name)
            every = max(1, t.size // 80)
            us = (t - t0) * 1e6
            ax.plot(
                us[::every],
                f[::every],
                "o",
                ms=2.2,
                mfc="none",
                mew=0.6,
                color=cols[name],
                gid=f"samples-{name}",
                label=f"{labels[name]} data",
            )
            ax.plot(
                (tt - t0) * 1e6,
                fitc(tt),
                "-",
                lw=1.3,
                color=cols[name],
                gid=f"fit-{name}",
                label=f"{labels[name]} degree-{fitc.degree} fit",
            )
            axr.plot(us, f - fitc(t), ".", ms=1.5, color=cols[name], gid=f"residual-{name}")
        tc = (a.split.t_c - t0) * 1e6
        for axis in (ax, axr):
            axis.axvline(tc, ls="--", lw=0.8, color=COLORS["construction"])
            axis.axhline(0.0, lw=0.6, color=COLORS["construction"])
        ax.text(
            tc,
            ax.get_ylim()[1],
            " max. compression",
            va="top",
            ha="left",
            fontsize=7,
            color=COLORS["construction"],
        )
        ax.set_ylabel("force [N]")
        axr.set_ylabel("residual [N]")
        axr.set_xlabel(r"time from contact start [$\mu$s]")
        # above the axes: inside, the falling Fn of the restitution phase runs through any
        # corner the legend could take
        fig.legend(
            loc="outside upper center",
            ncols=2,
            fontsize=7,
            title=f"data: 1 in {every} samples shown" if every > 1 else None,
            title_fontsize=6,
        )
        panel_label(ax, "(a)")
        panel_label(axr, "(b)")
        _name_record(ax, a)
        return fig


def fig9_percussion_plane(analysis) -> Figure:
    """Seed Fig. 9: measured Pt(Pn) over Routh's rigid broken line, phases marked.

    Parameters
    ----------
    analysis : pipeline.analysis.Analysis

    Returns
    -------
    Figure
        Pt horizontal, Pn vertical [mN·s] as in the seed. The measured curve from the
        scored percussions (gid ``measured-compression``/``measured-restitution``), the
        quartic-fit curve (gid ``measured-fit``), the rigid broken line (gid
        ``rigid-line``: its vertices are the rigid result's), lines C and T, and the Pt
        maximum (gid ``Pt-max``).
    """
    a = analysis
    perc, rig = a.percussions, a.rigid
    k = 1e3  # N·s → mN·s
    Pn, Pt = perc.Pn(a.source) * k, perc.Pt(a.source) * k
    comp = Pn <= a.split.Pn_c * k
    with style():
        fig, ax = new_figure(width=SINGLE, height=3.8)
        grey = COLORS["construction"]
        Pn_f, Pn_c = float(rig.Pn_f) * k, float(rig.Pn_c) * k
        x_hi = 1.15 * max(np.max(Pt), float(rig.Pt_f) * k, 1e-12)
        y_hi = 1.12 * max(np.max(Pn), Pn_f)
        ax.plot([0, x_hi], [Pn_c, Pn_c], "--", lw=0.8, color=grey)
        ax.plot([0, x_hi], [Pn_f, Pn_f], "-", lw=0.8, color=grey)
        ax.text(0.99 * x_hi, Pn_c, "(C)", ha="right", va="bottom", color=grey)
        ax.text(0.99 * x_hi, Pn_f, "(T)", ha="right", va="bottom", color=grey)
        v = np.asarray(rig.vertices) * k
        ax.plot(
            v[:, 0],
            v[:, 1],
            "-",
            lw=3.2,  # wider than the measured curve, which may lie right on it (Coulomb)
            color=COLORS["rigid"],
            gid="rigid-line",
            label="rigid body (Routh)",
            solid_joinstyle="miter",
        )
        ax.plot(v[-1, 0], v[-1, 1], "o", ms=4, color=COLORS["rigid"])
        sticking = rig.regime == "sticking"

        def tag(text, xy, dx, dy, ha, va):  # a label offset from its point [pt], glyphs only
            ax.annotate(
                text,
                xy,
                xytext=(dx, dy),
                textcoords="offset points",
                ha=ha,
                va=va,
                color=COLORS["rigid"],
            )

        tag(r"$E_2$" if sticking else r"$E_1$", v[-1], -4, 2, "right", "bottom")
        # the seed's names of the rigid lines: LF (slope μ) on the side of the line away
        # from the measured curve; S beside the vertical sticking segment, between C (or A)
        # and T, clear of the dashed line C
        lf_end = v[1] if sticking else v[-1]
        at = 0.45 * lf_end
        if np.interp(at[1], Pn, Pt) < at[0]:  # the measured curve runs left of LF
            tag("LF", at, 6, -2, "left", "top")
        else:
            tag("LF", at, -6, 2, "right", "bottom")
        if sticking:
            ax.plot(v[1, 0], v[1, 1], "s", ms=3.5, color=COLORS["rigid"])
            tag("A", v[1], -5, 2, "right", "bottom")
            tag("(S)", (v[1, 0], 0.5 * (max(v[1, 1], Pn_c) + v[-1, 1])), -5, 0, "right", "center")
        rest = ~comp
        rest[max(int(np.count_nonzero(comp)) - 1, 0)] = True  # join the two phases
        for phase, mask, color in (
            ("compression", comp, COLORS["measured"]),
            ("restitution", rest, COLORS["accent"]),
        ):
            ax.plot(
                np.where(mask, Pt, np.nan),
                np.where(mask, Pn, np.nan),
                "-",
                lw=1.6,
                color=color,
                gid=f"measured-{phase}",
                label=f"measured: {phase}",
            )
        ax.plot(
            perc.Pt_fit * k,
            perc.Pn_fit * k,
            ":",
            lw=1.1,
            color=COLORS["fit"],
            gid="measured-fit",
            label=f"degree-{a.fits.Ft.degree} fit (seed's)",
        )
        i = int(np.argmax(Pt))
        ax.plot(
            Pt[i],
            Pn[i],
            "v",
            ms=5,
            color=COLORS["accent"],
            gid="Pt-max",
            zorder=6,
            ls="none",
            label=r"maximum of measured $P_t$",  # in the legend: no text on the curves
        )
        ax.set_xlim(0, x_hi)
        ax.set_ylim(0, y_hi)
        ax.set_xlabel(r"tangential percussion $P_t$ [mN$\cdot$s]")
        ax.set_ylabel(r"normal percussion $P_n$ [mN$\cdot$s]")
        fig.legend(loc="outside lower center", ncols=2, fontsize=6.5)
        sc = a.rigid_scene  # the μ and e the broken line was drawn with
        title = (  # two lines at least: a record's name may be long, the figure is narrow
            f"{a.record.attrs.get('source', 'record')}: {sc.angle_deg:g}°, {sc.speed:g} m/s\n"
            f"rigid with μ = {sc.mu:.3g}, e = {sc.e:.3g}: {rig.regime}"
        )
        ax.set_title(fitting_text(title, fig.get_figwidth() * 0.8, 8), fontsize=8)
        return fig
