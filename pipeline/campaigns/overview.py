"""A campaign's overview a reader explores in a browser, from the file alone.

:func:`write_overview` writes ``overview.html``: every analysed record is a point in three
linked panels — the tangential restitution e_t against the incidence α (with its 1-σ
bootstrap bar and Routh's rigid prediction for the record), the friction coefficient μ
estimated from the record against the initial tangential speed v_t0 (with the campaign's
friction law, :func:`pipeline.campaigns.trends`), and the deviation from rigid theory (the
dimensionless maximum distance of Pt(Pn) from Routh's broken line, :mod:`pipeline.score`)
against the incidence. Hovering a point names the record and gives its values rounded to
their uncertainty (:mod:`pipeline.precision`); clicking it opens the record's report
(``reports/<stem>.html``, written by ``pipeline campaign``) in a new tab and marks the
record in all three panels (they share one data source). A record that failed is listed
under the panels with its reason, and a record that lacks a panel's value is named under
that panel: no record is dropped silently.

The page is one self-contained HTML file: the plotting library's JavaScript (BokehJS) is
inlined, so it opens from the disk with no server and no network, moved or copied with the
reports beside it. Why Bokeh rather than Altair/Vega-Lite or Plotly (sizes measured, in
``docs/campaigns.md``): the smallest self-contained file at a campaign's scale (the data as
binary arrays; Vega-Lite's JSON rows grow faster), inlined resources without a second
package to fetch them (Altair needs ``vl-convert-python`` to inline its JavaScript), and a
click that opens a URL and linked selection across panels without custom JavaScript.
"""

from __future__ import annotations

import html
import json
import math
import os
from pathlib import Path

import numpy as np
import xarray as xr

from .._atomic import atomic_write_text
from ..errors import InputError
from ..figures.style import COLORS, GROUP_COLORS
from ..precision import pdg, plain
from ..score import NEAR_ZERO

__all__ = ["write_overview", "overview_html", "OVERVIEW"]

#: File name of the overview in a campaign's output folder.
OVERVIEW = "overview.html"

#: Colours and markers of the impact-speed groups (as the campaign figures', Okabe–Ito).
_GROUP_STYLES = tuple(
    zip(GROUP_COLORS, ("circle", "square", "triangle", "diamond", "inverted_triangle", "plus"),
        strict=True)
)  # fmt: skip

#: The panels: (id, x column, y column, x label, y label, heading, what a missing value is).
_PANELS = (
    (
        "e_t",
        "angle",
        "e_t",
        "incidence α [deg]",
        "tangential restitution e_t [-]",
        "Tangential restitution against incidence",
        "no e_t",
    ),
    (
        "mu",
        "v_t0",
        "mu",
        "initial tangential speed v_t0 [m/s]",
        "μ from the record [-]",
        "Friction against the initial slip",
        "no μ",
    ),
    (
        "score",
        "angle",
        "score",
        "incidence α [deg]",
        "max. distance from Routh's line [-]",
        "How far rigid theory is off",
        "no score",
    ),
)


def require_bokeh() -> None:
    """Raise :class:`~pipeline.errors.InputError` (saying what to install) where bokeh is
    missing; ``pipeline campaign`` asks before its run, not after it."""
    try:
        import bokeh  # noqa: F401
    except ImportError:
        raise InputError(
            "the campaign overview needs bokeh: install the package with its 'reports' extra "
            "(pip install 'pipeline[reports]'), or leave the reports out (--no-reports)"
        ) from None


def _pm(value: float, std: float, unit: str = "") -> str:
    """``value ± std`` rounded to the uncertainty (:func:`pipeline.precision.pdg`), or the
    value alone at :data:`pipeline.precision.PLAIN_DIGITS` significant digits; "–" for none."""
    if not math.isfinite(value):
        return "–"
    text = pdg(value, std) if math.isfinite(std) and std > 0 else plain(value)
    return f"{text} {unit}".rstrip()


def _rows(ds: xr.Dataset, links: dict) -> dict:
    """The columns of the plotted records (status ok, angle and speed known): numbers as
    arrays, and the texts of the tooltip that round a value to its uncertainty."""
    ok = (ds["status"] == "ok").values & np.isfinite(ds["angle"].values)
    ok &= np.isfinite(ds["speed"].values)
    idx = np.flatnonzero(ok)

    def col(name):
        return ds[name].values[idx].astype(float) if name in ds else np.full(idx.size, np.nan)

    total = dict(phase="total", metric="max_distance")
    score = ds["score"].sel(**total).values[idx].astype(float)
    score_std = ds["score_std"].sel(**total).values[idx].astype(float)
    e_t, e_t_std = col("e_t"), col("e_t_std")
    names = [str(n) for n in ds["record"].values[idx]]
    speed = col("speed")
    e_fit, e_fit_std = col("fit_E_eff") / 1e9, col("fit_E_eff_std") / 1e9
    notes = [sum(1 for w in str(ds["warnings"].values[i]).splitlines() if w.strip()) for i in idx]
    return {
        "record": names,
        "url": [links.get(n, "") for n in names],
        "report": [links.get(n, "none written") for n in names],
        "group": [f"{v:g} m/s" for v in np.round(speed, 6)],
        "angle": col("angle"),
        "speed": speed,
        "v_t0": col("v_t0"),
        "e_t": e_t,
        "e_t_lo": e_t - e_t_std,
        "e_t_hi": e_t + e_t_std,
        "e_t_text": [_pm(v, s) for v, s in zip(e_t, e_t_std, strict=True)],
        "e_t_rigid": col("e_t_rigid"),
        "mu": col("mu_record"),
        "score": score,
        "score_lo": score - score_std,
        "score_hi": score + score_std,
        "score_text": [_pm(v, s) for v, s in zip(score, score_std, strict=True)],
        "E_text": [_pm(v, s, "GPa") for v, s in zip(e_fit, e_fit_std, strict=True)],
        "regime": [str(r) for r in ds["regime"].values[idx]],
        "notes": np.array(notes, dtype=int),
    }


#: The tooltip of a record (Bokeh's template: ``@column`` is the record's value, as text).
_TOOLTIP = """<div class="record-tip"><b>@record</b><br>
α = @angle{0.[00]}°, v = @speed{0.[000]} m/s, v<sub>t0</sub> = @v_t0{0.000} m/s<br>
regime (Routh): @regime<br>
e<sub>t</sub> = @e_t_text (rigid: @e_t_rigid{0.000})<br>
μ from the record = @mu{0.000}<br>
deviation from rigid = @score_text<br>
E* fitted = @E_text<br>
notes in its report: @notes<br>
report: @report</div>"""

#: A click on a record opens its report in a new tab (none for a record without one).
_OPEN_REPORT = """
const source = cb_data.source;
for (const i of source.selected.indices) {
  const url = source.data.url[i];
  if (url) window.open(url, "_blank");
  break;
}
"""


def _links(ds: xr.Dataset, page: Path, reports: Path | None) -> dict:
    """Record name → its report's URL relative to the page, where the report exists."""
    if reports is None:
        return {}
    out = {}
    for name in ds["record"].values:
        report = reports / f"{Path(str(name)).stem}.html"
        if report.is_file():
            out[str(name)] = Path(_relative(report, page.parent)).as_posix()
    return out


def _relative(path: Path, start: Path) -> str:
    return os.path.relpath(path.resolve(), start.resolve())


def _figures(rows: dict, trends: dict):
    """The three linked panels (Bokeh figures sharing one data source)."""
    from bokeh.models import (
        ColumnDataSource,
        CustomJS,
        HoverTool,
        TapTool,
        Whisker,
    )
    from bokeh.plotting import figure
    from bokeh.transform import factor_cmap, factor_mark

    source = ColumnDataSource(rows, name="records")
    factors = sorted(set(rows["group"]), key=lambda g: float(g.split()[0]))
    colors = [_GROUP_STYLES[k % len(_GROUP_STYLES)][0] for k in range(len(factors))]
    markers = [_GROUP_STYLES[k % len(_GROUP_STYLES)][1] for k in range(len(factors))]
    color = factor_cmap("group", colors, factors)
    marker = factor_mark("group", markers, factors)
    panels = {}
    for key, x, y, xlabel, ylabel, *_ in _PANELS:
        p = figure(
            name=f"panel-{key}",
            height=400,
            min_width=300,
            sizing_mode="stretch_width",
            tools="pan,wheel_zoom,box_zoom,reset,save",
            toolbar_location="above",
            x_axis_label=xlabel,
            y_axis_label=ylabel,
        )
        if key == "e_t":
            p.scatter(
                x,
                "e_t_rigid",
                source=source,
                marker="x",
                size=7,
                color=COLORS["construction"],
                legend_label="rigid prediction (Routh)",
            )
        if key in ("e_t", "score"):
            p.add_layout(
                Whisker(
                    base=x,
                    lower=f"{y}_lo",
                    upper=f"{y}_hi",
                    source=source,
                    line_color=color,
                    upper_head=None,
                    lower_head=None,
                )
            )
        if key == "mu":
            law = trends.get("friction", {})
            a, b = law.get("mu_a"), law.get("mu_b")
            vmax = np.nanmax(rows["v_t0"]) if np.isfinite(rows["v_t0"]).any() else 0.0
            if a is not None and b is not None and vmax > 0:
                xx = np.linspace(0.0, 1.05 * vmax, 2)
                p.line(
                    xx,
                    a + b * xx,
                    color=COLORS["fit"],
                    line_width=1.5,
                    legend_label="the campaign's law (below)",
                )
        if key == "score" and np.isfinite(rows[x]).any():
            p.line(
                [np.nanmin(rows[x]), np.nanmax(rows[x])],
                [NEAR_ZERO, NEAR_ZERO],
                line_dash="dashed",
                color=COLORS["construction"],
                legend_label=f"{NEAR_ZERO:g}: on Routh's line",
            )
        points = p.scatter(
            x,
            y,
            source=source,
            size=9,
            marker=marker,
            fill_color=color,
            fill_alpha=0.25,
            line_color=color,
            line_width=1.5,
            legend_group="group",
            name=f"records-{key}",
        )
        p.add_tools(
            HoverTool(
                renderers=[points],
                tooltips=_TOOLTIP,
                point_policy="snap_to_data",
            ),
            TapTool(renderers=[points], callback=CustomJS(code=_OPEN_REPORT)),
        )
        # the legend under the panel, where it hides no record
        legend = p.legend[0]
        legend.orientation = "horizontal"
        legend.ncols = 2
        legend.label_text_font_size = "9pt"
        legend.border_line_alpha = 0.0
        legend.click_policy = "hide"
        p.add_layout(legend, "below")
        p.toolbar.logo = None
        p.x_range.range_padding = p.y_range.range_padding = 0.12  # no point on the frame
        panels[key] = p
    return panels


def _missing(rows: dict) -> dict:
    """Panel id → names of plotted records without that panel's value."""
    out = {}
    for key, x, y, *_ in _PANELS:
        bad = ~(np.isfinite(rows[x]) & np.isfinite(rows[y]))
        out[key] = [n for n, b in zip(rows["record"], bad, strict=True) if b]
    return out


def overview_html(ds: xr.Dataset, *, links: dict | None = None, title: str | None = None) -> str:
    """The overview page of a campaign as one self-contained HTML document.

    Parameters
    ----------
    ds : xarray.Dataset — a campaign (:func:`pipeline.campaign`)
    links : dict, optional — record name → URL of its report (a record without one is not
        clickable); also ``"campaign"`` → the campaign report's URL
    title : str, optional — the page's title; default names the campaign's source

    Returns
    -------
    str
        The page: the panels with BokehJS inlined, the failed records listed with their
        reasons.
    """
    require_bokeh()
    from bokeh.embed import components
    from bokeh.resources import Resources

    links = dict(links or {})
    n = int(ds.sizes["record"])
    ok = int((ds["status"] == "ok").sum())
    source = str(ds.attrs.get("source", "campaign"))
    title = title or f"Campaign overview — {source}"
    rows = _rows(ds, links)
    trends = json.loads(ds.attrs.get("trends_json", "{}"))
    panels = _figures(rows, trends)
    script, divs = components(panels)
    notes = {key: [] for key, *_ in _PANELS}
    law = trends.get("friction", {})
    if law.get("mu_a") is not None and law.get("mu_b") is not None:
        a = _pm(law["mu_a"], law.get("mu_a_std", math.nan))
        b = _pm(law["mu_b"], law.get("mu_b_std", math.nan), "s/m")
        notes["mu"].append(f"The campaign's friction law: μ = {a} + ({b})·v<sub>t0</sub>.")
    for key, names in _missing(rows).items():
        if names:
            what = next(p[-1] for p in _PANELS if p[0] == key)
            notes[key].append(f"Not shown here ({what}): {', '.join(map(html.escape, names))}")
    cells = [
        f'<div class="panel" id="{key}"><h2>{heading}</h2>{divs[key]}'
        + "".join(f'<p class="note">{n}</p>' for n in notes[key])
        + "</div>"
        for key, *_, heading, _ in _PANELS
    ]
    failed = [
        (str(r), str(why), a, v)
        for r, s, why, a, v in zip(
            ds["record"].values,
            ds["status"].values,
            ds["reason"].values,
            ds["angle"].values,
            ds["speed"].values,
            strict=True,
        )
        if s != "ok"
    ]
    esc = html.escape
    campaign_link = (
        f' The campaign report: <a href="{esc(links["campaign"])}">its tables, trends and '
        "joint fit</a>."
        if "campaign" in links
        else ""
    )
    head = (
        f"<h1>{esc(title)}</h1>"
        f'<p class="lead">{ok} of {n} records analysed'
        + (f", <b>{n - ok} failed</b> (listed below)" if ok < n else "")
        + ". Hover a point for its record and values (rounded to their 1-σ uncertainty); "
        "click it to open the record's report; the three panels show the same records, "
        "selected together. The toolbar zooms and pans, ↻ resets; a click on a legend's "
        "entry hides those records." + campaign_link + "</p>"
    )
    table = ""
    if failed:
        body = "".join(
            f"<tr><td>{esc(r)}</td><td>{_num(a, '°')}</td><td>{_num(v, ' m/s')}</td>"
            f"<td>{esc(why)}</td></tr>"
            for r, why, a, v in failed
        )
        table = (
            '<h2>Failed records</h2><table class="failed"><thead><tr><th>record</th>'
            "<th>incidence</th><th>speed</th><th>why it failed</th></tr></thead>"
            f"<tbody>{body}</tbody></table>"
        )
    return _PAGE.format(
        title=esc(title),
        # BokehJS inlined: its core alone, what the panels use (not its widgets, tables,
        # WebGL or MathJax parts, another 2.7 MB)
        resources=Resources(mode="inline", components=["bokeh"]).render(),
        head=head,
        panels="".join(cells),
        failed=table,
        script=script,
    )


def _num(x, unit: str) -> str:
    return f"{x:g}{unit}" if np.isfinite(x) else "–"


def write_overview(ds: xr.Dataset, path, *, reports=None) -> Path:
    """Write a campaign's overview page (module notes) to ``path``, atomically.

    Parameters
    ----------
    ds : xarray.Dataset — a campaign (:func:`pipeline.campaign`)
    path : path — the page to write (``pipeline campaign`` writes ``<out>/overview.html``)
    reports : path, optional — the folder of the records' reports (``<stem>.html``) and of
        the campaign's (``campaign.html``); each record whose report is there is linked,
        relative to the page, so the folder can be moved or copied whole. None: no links.

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    InputError
        bokeh is not installed (the ``reports`` extra).
    OutputError
        The page cannot be written (a full disk, a read-only or vanished folder).
    """
    path = Path(path)
    reports = None if reports is None else Path(reports)
    links = _links(ds, path, reports)
    if reports is not None and (reports / "campaign.html").is_file():
        links["campaign"] = Path(_relative(reports / "campaign.html", path.parent)).as_posix()
    return atomic_write_text(path, overview_html(ds, links=links))


_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{title}</title>
{resources}
<style>
body {{ font-family: system-ui, -apple-system, "Segoe UI", sans-serif; margin: 1.5em auto;
       max-width: 1500px; padding: 0 1em; color: #222; }}
h1 {{ font-size: 1.4em; margin-bottom: 0.3em; }}
h2 {{ font-size: 1.15em; margin-top: 1.5em; }}
p.lead {{ max-width: 60em; line-height: 1.4; }}
.panel h2 {{ font-size: 1em; margin: 0.5em 0 0.2em; }}
.panels {{ display: grid; gap: 1em;
           grid-template-columns: repeat(auto-fit, minmax(320px, 1fr)); }}
.panel {{ min-width: 0; }}
p.note {{ font-size: 0.85em; color: #555; margin: 0.3em 0; }}
table.failed {{ border-collapse: collapse; font-size: 0.9em; }}
table.failed td, table.failed th {{ border-bottom: 1px solid #ddd; padding: 0.3em 0.8em;
                                    text-align: left; vertical-align: top; }}
.record-tip {{ font-size: 12px; line-height: 1.35; max-width: 22em; }}
</style>
</head>
<body>
{head}
<div class="panels">{panels}</div>
{failed}
{script}
</body>
</html>
"""
