"""Figures of fitted contact parameters: :func:`fig_contact_fit` (see :mod:`pipeline.figures`)."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from .style import COLORS, SINGLE, new_figure, panel_label, style

__all__ = ["fig_contact_fit"]


def fig_contact_fit(fit) -> Figure:
    """A contact fit: measured against model against rigid, and the residuals.

    Parameters
    ----------
    fit : pipeline.fit.ContactFit
        From :func:`pipeline.fit_contact` (or the ``fit`` of :func:`pipeline.select_model`).

    Returns
    -------
    Figure
        Top: the fitted samples of Fn and Ft (markers, gid ``measured-Fn``/``measured-Ft``,
        baseline removed), the model as the sensor records it (lines, gid
        ``model-Fn``/``model-Ft``), the contact forces before the sensor (thin, gid
        ``true-Fn``/``true-Ft``) and Routh's rigid Ft on the fitted normal force (dotted,
        gid ``rigid-Ft``: μ·Fn until the slip would stop, then 0), against time [µs] from
        the fitted onset t0. Bottom: residuals (measured − model)/σ of each channel (gid
        ``residual-Fn``/``residual-Ft``) with the ±2 band.
    """
    d = fit.data
    t0 = fit.values["t0"]
    cols = {"Fn": COLORS["sliding"], "Ft": COLORS["sticking"]}
    labels = {"Fn": r"$F_n$", "Ft": r"$F_t$"}
    model = fit.predicted()
    with style():
        fig, (ax, axr) = new_figure(
            2, 1, width=SINGLE, height=4.0, sharex=True, gridspec_kw={"height_ratios": [2.3, 1.0]}
        )
        every = 1
        for ch, m in zip(d.channels, model, strict=True):
            us = (ch.t - t0) * 1e6
            every = max(1, ch.t.size // 120)
            ax.plot(
                us[::every],
                ch.y[::every],
                "o",
                ms=2.0,
                mfc="none",
                mew=0.5,
                color=cols[ch.name],
                gid=f"measured-{ch.name}",
                label=f"{labels[ch.name]} measured",
            )
            ax.plot(
                us,
                m,
                "-",
                lw=1.2,
                color=cols[ch.name],
                gid=f"model-{ch.name}",
                label=f"{labels[ch.name]} model (as measured)",
            )
            axr.plot(
                us,
                (ch.y - m) / ch.sigma,
                ".",
                ms=1.5,
                color=cols[ch.name],
                gid=f"residual-{ch.name}",
            )
        tt = np.linspace(d.channels[0].t[0], d.channels[0].t[-1], 800)
        true = fit.true_forces(tt)
        us = (tt - t0) * 1e6
        for name in ("Fn", "Ft"):
            if true.get(name) is not None and any(c.name == name for c in d.channels):
                ax.plot(
                    us,
                    true[name],
                    "-",
                    lw=0.6,
                    color=COLORS["construction"],
                    gid=f"true-{name}",
                    label="contact force" if name == "Fn" else None,
                )
        if true.get("Ft_rigid") is not None:
            ax.plot(
                us,
                true["Ft_rigid"],
                ":",
                lw=1.2,
                color=COLORS["rigid"],
                gid="rigid-Ft",
                label=r"rigid (Routh) $F_t$",
            )
        for axis in (ax, axr):
            axis.axhline(0.0, lw=0.6, color=COLORS["construction"])
        axr.axhspan(-2, 2, color=COLORS["construction"], alpha=0.15, lw=0)
        ax.set_ylabel("force [N]")
        axr.set_ylabel(r"residual [$\sigma$]")
        axr.set_xlabel(r"time from fitted onset $t_0$ [$\mu$s]")
        fig.legend(
            loc="outside upper center",
            ncols=2,
            fontsize=7,
            title=_legend_title(fit),
            title_fontsize=7,
        )
        panel_label(ax, "(a)")
        panel_label(axr, "(b)")
        return fig


#: The parameters' symbols in the figure (mathtext).
_TEX = {
    "E_eff": "$E^*$",
    "e": "$e$",
    "mu": r"$\mu$",
    "kt_scale": r"$k_t/k_M$",
    "alpha": r"$\alpha$",
}


def _legend_title(fit) -> str:
    """The model, χ²_ν and the fitted parameters as the fit's table rounds them (two to a
    line: the figure is one column wide)."""
    from ..precision import model_words, plain

    model = model_words(fit.normal, fit.tangential)
    table = fit.table()
    parts = []
    for name, row in table.iterrows():
        value = row["value"].removesuffix(" (no uncertainty)")
        op = "" if value[:1] in "≥≤" else "= "
        parts.append(
            f"{_TEX.get(name, row['quantity'])} {op}{value}"
            + (f" {row['unit']}" if row["unit"] else "")
        )
    lines = [f"{model}: $\\chi^2_\\nu$ = {plain(fit.redchi, 3)}"]
    lines += [", ".join(parts[i : i + 2]) for i in range(0, len(parts), 2)]
    return "\n".join(lines)
