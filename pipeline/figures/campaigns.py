"""Campaign figures (:func:`pipeline.campaign`): outcomes, friction, restitution and the
deviation score against incidence and speed; :func:`campaign_figures` draws them all (see
:mod:`pipeline.figures`)."""

from __future__ import annotations

import math

import numpy as np
from matplotlib.figure import Figure

from ..contact import cor_hunt_crossley_alpha
from ..precision import rounded
from ..rigid import sphere_on_plane
from ..scene import Scene
from ..score import NEAR_ZERO
from ..simulate import impact_outcomes
from .style import (
    COLORS,
    DOUBLE,
    GROUP_COLORS,
    SINGLE,
    fitting_text,
    new_figure,
    panel_label,
    style,
)

__all__ = [
    "campaign_outcomes",
    "campaign_friction",
    "campaign_restitution",
    "campaign_score",
    "campaign_figures",
    "CAMPAIGN_FIGURES",
]


# ============================================================== campaigns
#: Colours and markers of the speed groups in the campaign figures.
_SPEED_STYLES = tuple(zip(GROUP_COLORS, ("o", "s", "^", "D", "v", "P"), strict=True))


def _campaign_title(fig, ds, what: str) -> None:
    """Name the campaign and its records on a figure (every figure names its data)."""
    ok = int((ds["status"] == "ok").sum())
    n = int(ds.sizes["record"])
    import textwrap

    label = full = textwrap.shorten(str(ds.attrs.get("source", "campaign")), 60, placeholder=" …")
    counts = f"{ok} of {n} records" + (f" ({n - ok} failed)" if ok < n else "")
    text = f"{what} — {label}: {counts}"
    width = fig.get_figwidth() * 0.95
    if fitting_text(text, width, 8) != text:  # too long for one line: the campaign below
        while label and fitting_text(f"{label} …: {counts}", width, 8).count("\n"):
            label = label[:-1]  # the campaign's name shortened, its counts whole
        text = f"{what}\n{label}{' …' * (label != full)}: {counts}"
    fig.suptitle(text, fontsize=8)


def _speed_groups(ds):
    """``[(speed, index array of ok records)]`` by impact speed (rounded to 1e-6 m/s)."""
    ok = np.flatnonzero((ds["status"] == "ok").values)
    speeds = np.round(ds["speed"].values[ok], 6)
    return [(float(v), ok[speeds == v]) for v in np.unique(speeds)]


def _campaign_scene(ds, i) -> Scene:
    import json

    return Scene.from_dict(json.loads(str(ds["scene_json"].values[i])))


def _trends(ds) -> dict:
    import json

    return json.loads(ds.attrs.get("trends_json", "{}"))


def _joint(ds) -> dict:
    """The campaign's joint fit (``pipeline.campaigns.joint``), {} without one."""
    import json

    return json.loads(ds.attrs.get("joint_fit_json", "{}"))


def _mu_law(tr, v_t0, joint=None):
    f = tr.get("friction", {})
    jv = (joint or {}).get("values", {})
    if "mu_a" in jv and "mu_b" in jv:  # the joint fit of the forces wins
        return np.maximum(jv["mu_a"] + jv["mu_b"] * np.asarray(v_t0), 0.0)
    if "mu" in jv:
        return np.full_like(np.asarray(v_t0, dtype=float), jv["mu"])
    a, b = f.get("mu_a"), f.get("mu_b")
    if a is not None and b is not None:
        return np.maximum(a + b * np.asarray(v_t0), 0.0)
    c = f.get("mu_const")
    return None if c is None else np.full_like(np.asarray(v_t0, dtype=float), c)


def _model_curves(ds, idx, angles):
    """Rigid (Routh) and compliant (Hertz–Mindlin) outcomes against incidence for the scene
    of record ``idx[0]``, with μ, e (and E*, kt_scale) from the campaign's joint fit where
    there is one, else from its trends (friction law, constant e)."""
    tr, jf = _trends(ds), _joint(ds)
    jv = jf.get("values", {})
    base = _campaign_scene(ds, idx[0])
    if "E_eff" in jv and base.E is not None and base.nu is not None:
        k = jv["E_eff"] / float(base.E_eff)
        base = base.replace(E=base.E * k, target_E=base.target_E * k)
    e = jv.get("e", tr.get("restitution", {}).get("e_const"))
    e = float(np.nanmean(ds["e_n"].values[idx])) if e is None else e
    v_t0 = base.speed * np.sin(np.radians(angles))
    mu = _mu_law(tr, v_t0, jf)
    if mu is None:
        mu = np.full_like(angles, float(np.nanmean(ds["mu_rigid"].values[idx])))
    scenes = base.replace(
        angle_deg=angles, speed=np.full_like(angles, base.speed), mu=mu, e=min(max(e, 0.0), 1.0)
    )
    r = sphere_on_plane(scenes)
    rigid = {
        "e_t": np.asarray(r.e_t),
        "omega": np.asarray(r.omega),
        "rebound_deg": np.degrees(np.arctan2(np.asarray(r.v_t), np.asarray(r.v_n))),
    }
    compliant = None
    if base.E is not None and base.nu is not None:
        o = impact_outcomes(scenes, tangential="mindlin")
        v_n0 = base.speed * np.cos(np.radians(angles))
        compliant = {
            "e_t": o.e_t,
            "omega": o.omega,
            "rebound_deg": np.degrees(np.arctan2(o.e_t * v_t0, o.e_n * v_n0)),
        }
    return rigid, compliant


def campaign_outcomes(ds) -> Figure:
    """e_t, ω and the rebound angle against incidence, measured and predicted.

    Parameters
    ----------
    ds : xarray.Dataset
        A campaign (:func:`pipeline.campaign`).

    Returns
    -------
    Figure
        Three panels against the incidence α [deg]: the tangential restitution e_t [-], the
        spin after impact ω [rad/s] and the rebound angle from the normal [deg]. Measured
        values with their bootstrap 1-σ bars, one marker per impact speed (gid
        ``measured-<quantity>-<speed>``); Routh's rigid prediction (dashed, gid
        ``rigid-<quantity>-<speed>``) and the compliant Hertz–Mindlin model (solid, gid
        ``compliant-<quantity>-<speed>``), both with μ from the campaign's friction law
        and its constant e (:func:`pipeline.campaigns.trends`), or the campaign's joint fit
        of the forces where there is one (:mod:`pipeline.campaigns.joint`).
    """
    quantities = (
        ("e_t", r"$e_t$ [-]"),
        ("omega", r"$\omega$ [rad/s]"),
        ("rebound_deg", "rebound angle [deg]"),
    )
    with style():
        fig, axes = new_figure(1, 3, width=DOUBLE, height=2.6)
        groups = _speed_groups(ds)
        if groups:
            lo = max(0.5, float(np.nanmin(ds["angle"].values[groups[0][1]])) - 5.0)
            hi = min(89.0, float(np.nanmax(ds["angle"].values)) + 5.0)
        for k, (v, idx) in enumerate(groups):
            color, marker = _SPEED_STYLES[k % len(_SPEED_STYLES)]
            angles = np.linspace(lo, hi, 90)
            rigid, compliant = _model_curves(ds, idx, angles)
            for ax, (q, label) in zip(axes, quantities, strict=True):
                ax.errorbar(
                    ds["angle"].values[idx],
                    ds[q].values[idx],
                    yerr=ds[f"{q}_std"].values[idx],
                    fmt=marker,
                    ms=4,
                    mfc="none",
                    color=color,
                    capsize=1.5,
                    lw=0.8,
                    gid=f"measured-{q}-{v:g}",
                    label=f"measured, {v:g} m/s",
                )
                ax.plot(angles, rigid[q], "--", lw=0.9, color=color, gid=f"rigid-{q}-{v:g}")
                if compliant is not None:
                    ax.plot(
                        angles, compliant[q], "-", lw=1.0, color=color, gid=f"compliant-{q}-{v:g}"
                    )
                ax.set_ylabel(label)
        for ax in axes:
            ax.set_xlabel(r"incidence $\alpha$ [deg]")
        axes[2].plot([], [], "--", color=COLORS["construction"], label="rigid (Routh)")
        axes[2].plot([], [], "-", color=COLORS["construction"], label="Hertz–Mindlin")
        fig.legend(*axes[2].get_legend_handles_labels(), loc="outside lower center", ncols=4)
        for ax, tag in zip(axes, ("(a)", "(b)", "(c)"), strict=True):
            panel_label(ax, tag)
        _campaign_title(fig, ds, "Outcomes against incidence")
        return fig


def campaign_friction(ds) -> Figure:
    """μ estimated from each record against the initial tangential speed, with the law.

    Returns
    -------
    Figure
        μ [-] against v_t0 [m/s]: the records' μ (gid ``measured-mu``), the fitted linear
        law μ = a + b·v_t0 (gid ``law-linear``) and the constant (gid ``law-constant``)
        from :func:`pipeline.campaigns.trends`, with the fitted values in the legend.
    """
    tr = _trends(ds).get("friction", {})
    with style():
        fig, ax = new_figure(width=SINGLE, height=3.0)
        ok = (ds["status"] == "ok").values
        x, y = ds["v_t0"].values[ok], ds["mu_record"].values[ok]
        ax.plot(x, y, "o", mfc="none", color=COLORS["measured"], gid="measured-mu", label="records")
        if x.size:
            xx = np.linspace(0.0, float(np.nanmax(x)) * 1.05, 50)
            a, b = tr.get("mu_a"), tr.get("mu_b")
            if a is not None and b is not None:
                ax.plot(
                    xx,
                    a + b * xx,
                    "-",
                    color=COLORS["fit"],
                    gid="law-linear",
                    label="fit to the records: " + _law_text(tr, "mu_a", "mu_b"),
                )
            joint = _joint(ds)
            jv, js = joint.get("values", {}), joint.get("stderr", {})
            if "mu_a" in jv and "mu_b" in jv:
                ax.plot(
                    xx,
                    jv["mu_a"] + jv["mu_b"] * xx,
                    "--",
                    color=COLORS["sticking"],
                    gid="law-joint",
                    label="joint fit of the forces: "
                    + _law_text({**jv, **{f"{k}_std": v for k, v in js.items()}}, "mu_a", "mu_b"),
                )
            c = tr.get("mu_const")
            if c is not None:
                ax.axhline(
                    c,
                    ls=":",
                    color=COLORS["construction"],
                    gid="law-constant",
                    label=rf"constant: $\mu = {rounded(c, tr.get('mu_const_std', math.nan))}$",
                )
        ax.set_xlabel(r"initial tangential speed $v_{t0}$ [m/s]")
        ax.set_ylabel(r"$\mu$ from the record [-]")
        ax.set_xlim(left=0.0)
        fig.legend(loc="outside lower center", ncols=1, fontsize=6.5)
        _campaign_title(fig, ds, "Friction")
        return fig


def _law_text(values: dict, a: str, b: str) -> str:
    """``$μ = a + b s/m·v_t0$`` (mathtext) with each coefficient rounded to its uncertainty
    (the ``<name>_std`` beside it in ``values``)."""
    ra = rounded(values[a], values.get(f"{a}_std") or math.nan)
    rb = rounded(values[b], values.get(f"{b}_std") or math.nan)
    return rf"$\mu = {ra} + {rb}\,\mathrm{{s/m}}\cdot v_{{t0}}$"


def campaign_restitution(ds) -> Figure:
    """Normal restitution against impact speed with both damping hypotheses.

    Returns
    -------
    Figure
        e_n [-] against the approach speed v_n0 [m/s]: measured (gid ``measured-e``, 1-σ
        bars), e constant (gid ``law-constant_e``) and the Hunt–Crossley material
        constant α held fixed (gid ``law-constant_alpha``, e falls with speed), fitted by
        :func:`pipeline.campaigns.trends`; the preferred hypothesis is named in the legend.
    """
    tr = _trends(ds).get("restitution", {})
    with style():
        fig, ax = new_figure(width=SINGLE, height=2.6)
        ok = (ds["status"] == "ok").values
        v_n0 = ds["speed"].values[ok] * np.cos(np.radians(ds["angle"].values[ok]))
        ax.errorbar(
            v_n0,
            ds["e_n"].values[ok],
            yerr=ds["e_n_std"].values[ok],
            fmt="o",
            mfc="none",
            color=COLORS["measured"],
            capsize=1.5,
            gid="measured-e",
            label="records",
        )
        if "e_const" in tr and v_n0.size:
            vv = np.linspace(float(np.nanmin(v_n0)) * 0.8, float(np.nanmax(v_n0)) * 1.2, 60)
            pref = tr.get("preferred")
            ax.plot(
                vv,
                np.full_like(vv, tr["e_const"]),
                ":",
                color=COLORS["sliding"],
                gid="law-constant_e",
                label=f"e constant = {rounded(tr['e_const'], tr.get('e_const_std', math.nan))}"
                + (" (preferred)" if pref == "constant_e" else ""),
            )
            ax.plot(
                vv,
                cor_hunt_crossley_alpha(tr["alpha"], vv),
                "-",
                color=COLORS["sticking"],
                gid="law-constant_alpha",
                label=r"$\alpha$ constant = "
                + f"{rounded(tr['alpha'], tr.get('alpha_std', math.nan))} s/m"
                + (" (preferred)" if pref == "constant_alpha" else ""),
            )
        ax.set_xlabel(r"approach speed $v_{n0}$ [m/s]")
        ax.set_ylabel(r"$e_n$ (Poisson) [-]")
        fig.legend(loc="outside lower center", ncols=2, fontsize=6.5)
        _campaign_title(fig, ds, "Restitution")
        return fig


def campaign_score(ds) -> Figure:
    """The deviation from Routh's broken line against incidence, by phase.

    Returns
    -------
    Figure
        The dimensionless maximum distance [-] of the measured Pt(Pn) from the rigid broken
        line (:mod:`pipeline.score`) in compression and in restitution against the
        incidence α [deg], with bootstrap 1-σ bars (gid ``score-<phase>``), and the
        near-zero level of :data:`pipeline.score.NEAR_ZERO` (gid ``near-zero``).
    """
    with style():
        fig, ax = new_figure(width=SINGLE, height=2.6)
        ok = (ds["status"] == "ok").values
        styles = {
            "compression": (COLORS["sliding"], "o"),
            "restitution": (COLORS["sticking"], "s"),
        }
        for phase, (color, marker) in styles.items():
            sel = dict(phase=phase, metric="max_distance")
            ax.errorbar(
                ds["angle"].values[ok],
                ds["score"].sel(**sel).values[ok],
                yerr=ds["score_std"].sel(**sel).values[ok],
                fmt=marker,
                mfc="none",
                color=color,
                capsize=1.5,
                gid=f"score-{phase}",
                label=phase,
            )
        ax.axhline(NEAR_ZERO, ls=":", color=COLORS["construction"], gid="near-zero")
        ax.set_xlabel(r"incidence $\alpha$ [deg]")
        ax.set_ylabel("max. distance from\nthe rigid line [-]")
        ax.set_ylim(bottom=0.0)
        fig.legend(loc="outside lower center", ncols=2, fontsize=6.5)
        _campaign_title(fig, ds, "Deviation from rigid theory")
        return fig


#: The campaign figures by file name (what :func:`campaign_figures` returns).
CAMPAIGN_FIGURES = {
    "campaign_outcomes.png": campaign_outcomes,
    "campaign_friction.png": campaign_friction,
    "campaign_restitution.png": campaign_restitution,
    "campaign_score.png": campaign_score,
}


def campaign_figures(ds) -> dict:
    """``{file name: Figure}`` of every campaign figure for a campaign Dataset."""
    return {name: fn(ds) for name, fn in CAMPAIGN_FIGURES.items()}
