"""The one look of every figure: sizes, colours, rcParams (:func:`style`), a pyplot-free
:func:`new_figure` and an atomic :func:`save` (see :mod:`pipeline.figures`)."""

from __future__ import annotations

import io
from contextlib import contextmanager
from pathlib import Path

import matplotlib as mpl
from matplotlib.figure import Figure

from .._atomic import atomic_write_bytes

__all__ = [
    "STYLE",
    "SINGLE",
    "DOUBLE",
    "COLORS",
    "GROUP_COLORS",
    "style",
    "new_figure",
    "save",
    "panel_label",
    "fitting_text",
]


#: Figure widths [inch]: one journal column and the full page width.
SINGLE, DOUBLE = 3.5, 7.2

#: Colours used across figures (colour-blind safe, Okabe–Ito).
COLORS = {
    "sliding": "#0072B2",  # blue
    "sticking": "#D55E00",  # vermillion
    "measured": "#000000",
    "fit": "#009E73",  # green
    "rigid": "#CC79A7",  # purple
    "construction": "#7F7F7F",  # grey: auxiliary lines C, T, S
    "accent": "#E69F00",  # orange
}

#: The colours of a campaign's impact-speed groups, in order (its figures and its overview).
GROUP_COLORS = tuple(
    COLORS[k] for k in ("sliding", "sticking", "fit", "accent", "rigid", "measured")
)

#: rcParams applied by :func:`style` (publication look: 8–9 pt text, thin frames).
STYLE = {
    "font.family": "serif",
    "font.serif": ["DejaVu Serif"],
    "mathtext.fontset": "dejavuserif",
    "font.size": 9,
    "axes.labelsize": 9,
    "axes.titlesize": 9,
    "legend.fontsize": 8,
    "legend.frameon": False,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "xtick.direction": "in",
    "ytick.direction": "in",
    "xtick.top": False,
    "ytick.right": False,
    "axes.linewidth": 0.8,
    "lines.linewidth": 1.4,
    "lines.markersize": 5,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "savefig.dpi": 300,
    "savefig.bbox": "tight",
    "savefig.pad_inches": 0.03,
    "figure.dpi": 150,
}


@contextmanager
def style():
    """Context manager applying :data:`STYLE` (restores the caller's rcParams after)."""
    with mpl.rc_context(STYLE):
        yield


def new_figure(nrows=1, ncols=1, *, width=SINGLE, height=None, layout="constrained", **subplots_kw):
    """A constrained-layout :class:`~matplotlib.figure.Figure` and its axes, without pyplot.

    Every figure lays itself out inside its canvas — titles, labels and legends included —
    in its first draw, so it looks the same shown as drawn (a notebook, an HTML report) and
    saved tightly (:func:`save`); ``tests/test_figures.py`` checks each one.

    Parameters
    ----------
    nrows, ncols : int — grid of axes
    width : float — figure width [inch]; :data:`SINGLE` or :data:`DOUBLE`
    height : float, optional — figure height [inch]; default width·0.8/ncols·nrows
    layout : str — matplotlib's layout engine: ``"constrained"``, or ``"compressed"``
        for axes of a fixed aspect (equal scales), which it lays out in one draw
    **subplots_kw — passed to :meth:`Figure.subplots` (``sharey=``, ``gridspec_kw=``...)

    Returns
    -------
    (Figure, Axes or ndarray of Axes)
    """
    if height is None:
        height = width * 0.8 * nrows / ncols
    fig = Figure(figsize=(width, height), layout=layout)
    axes = fig.subplots(nrows, ncols, squeeze=True, **subplots_kw)
    return fig, axes


def save(fig: Figure, path, **savefig_kw) -> Path:
    """Write ``fig`` to ``path`` atomically (temporary file, then rename).

    The format follows the suffix (``.png``, ``.pdf``, ``.svg``). The figure is drawn in
    memory and written by :func:`pipeline._atomic.atomic_write_bytes`, so a full disk is
    one :class:`~pipeline.errors.OutputError`. Returns the path.
    """
    path = Path(path)
    buf = io.BytesIO()
    with style():
        fig.savefig(buf, format=path.suffix.lstrip(".") or None, **savefig_kw)
    atomic_write_bytes(path, buf.getbuffer())
    return path


def fitting_text(text: str, width: float, fontsize: float) -> str:
    """``text`` broken into lines no wider than ``width`` [inch] at ``fontsize`` [pt] in the
    current font (measured, not guessed): at spaces where it can, inside a word (a long
    file name) where it must; each line of ``text`` kept on its own."""
    from matplotlib.font_manager import FontProperties
    from matplotlib.textpath import text_to_path

    prop = FontProperties(size=fontsize)
    room = width * 72.0

    def fits(s):
        return text_to_path.get_text_width_height_descent(s, prop, ismath=False)[0] <= room

    out = []
    for line in text.split("\n"):
        current = ""
        for word in line.split(" "):
            trial = f"{current} {word}" if current else word
            if fits(trial):
                current = trial
                continue
            if current:
                out.append(current)
            while not fits(word) and len(word) > 1:  # a word wider than the line
                k = len(word) - 1
                while k > 1 and not fits(word[:k]):
                    k -= 1
                out.append(word[:k])
                word = word[k:]
            current = word
        out.append(current)
    return "\n".join(out)


def panel_label(ax, text, *, x=-0.02, y=1.02):
    """Bold panel tag such as ``(a)`` at the upper left, outside the axes."""
    ax.text(x, y, text, transform=ax.transAxes, ha="right", va="bottom", fontweight="bold")
