"""What the report notebooks show a reader: the verdict in words, and tables of numbers
rounded to their uncertainty in the units a person reads (:mod:`pipeline.precision`).

A record's report (``templates/record_report.py``) shows :func:`record_verdict`,
:func:`record_table`, :func:`outcomes_table`, :func:`score_table` and the fit's own
:meth:`~pipeline.fit.result.FitResult.table`; a campaign's (``templates/campaign_report.py``)
:func:`campaign_verdict`, :func:`records_table`, :func:`trends_table` beside the figure that
shows each trend (:func:`beside`) and :func:`joint_table`. :func:`view` wraps a table for
``display``: plain HTML (:func:`pipeline.precision.html_table`: light markup, the same for the
same table wherever it is made) and text.

Every number here is rounded for reading; the machines' numbers, every digit, stay in the
results' ``summary()`` (``tests/test_notebook_report.py`` checks that each number a report
shows is the summary's to its shown digits).
"""

from __future__ import annotations

import base64
import io
import json
import math
from collections import Counter
from html import escape

import numpy as np
import pandas as pd

from . import precision
from .fit.result import kind_of
from .precision import (
    HYPOTHESIS_WORDS,
    bound,
    hypothesis_words,
    in_unit,
    pdg,
    plain,
    quantity,
    rounded,
)
from .score import NEAR_ZERO

__all__ = [
    "view",
    "beside",
    "record_verdict",
    "fit_notes",
    "record_table",
    "outcomes_table",
    "score_table",
    "implied_table",
    "notes_markdown",
    "campaign_verdict",
    "records_table",
    "trends_table",
    "joint_table",
]


# ------------------------------------------------------------------ display
class _View:
    """A table as a notebook shows it: HTML (styled) and its text."""

    def __init__(self, df, caption, uuid):
        self.df, self.caption, self.uuid = df, caption, uuid

    def _repr_html_(self):
        # the caption as a paragraph above the table: a table's own caption is only as wide
        # as the table, and a verdict over a narrow table would wrap in a thin column
        head = f'<p class="pipeline-caption"><strong>{escape(self.caption)}</strong></p>'
        return (head if self.caption else "") + precision.html_table(self.df, self.uuid)

    def __repr__(self):
        text = self.df.to_string()
        return f"{self.caption}\n{text}" if self.caption else text


def view(df, *, caption=None, uuid: str = "t") -> _View:
    """``df`` for ``display``: an HTML table with ``caption`` above it (default the table's
    ``attrs["verdict"]``) and its text; ``uuid`` names the table's HTML id (one per page)."""
    caption = df.attrs.get("verdict", "") if caption is None else caption
    return _View(df, caption, uuid)


class _Beside:
    """A figure and a table side by side (a flex row that wraps on a narrow page)."""

    def __init__(self, fig, table: _View):
        self.fig, self.table = fig, table

    def _png(self) -> str:
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        buf = io.BytesIO()
        FigureCanvasAgg(self.fig).print_png(buf)
        return base64.b64encode(buf.getvalue()).decode("ascii")

    def _repr_html_(self):
        w, h = (self.fig.get_size_inches() * self.fig.dpi).round().astype(int)
        return (
            '<div class="pipeline-beside" style="display: flex; flex-wrap: wrap; '
            'align-items: flex-start; gap: 1.5em;">'
            f'<img width="{w}" height="{h}" alt="{self.table.caption or "figure"}" '
            f'src="data:image/png;base64,{self._png()}"/>'
            f"<div>{self.table._repr_html_()}</div></div>"
        )

    def __repr__(self):
        return repr(self.table)


def beside(fig, table: _View) -> _Beside:
    """A figure and the table of what it shows, side by side, for ``display``."""
    return _Beside(fig, table)


# ------------------------------------------------------------------ one record
def _pm(value, std) -> str:
    return pdg(value, std) if np.isfinite(std) else plain(value)


def record_verdict(a, fit=None) -> str:
    """The record's verdict in words (Markdown): its impact, how far rigid-body theory is
    off, whether the seed's findings hold, and what the contact fit says."""
    from .report import findings

    sc, src = a.scene, a.record.attrs.get("source", "record")
    total = a.score.values["total"]["max_distance"]
    std = a.score.std["total"]["max_distance"]
    sig = std if np.isfinite(std) else 0.0
    far = total - 3 * sig > NEAR_ZERO
    lines = [
        f"## `{src}`: {sc.speed:g} m/s at {sc.angle_deg:g}° — Routh predicts {a.rigid.regime}",
        "",
        (
            f"- **Rigid-body theory is off**: the measured Pt(Pn) lies up to "
            f"{_pm(total, std)} (of Pt_ref) from Routh's broken line, against the near-zero "
            f"level {NEAR_ZERO:g}."
            if far
            else f"- **Rigid-body theory holds**: the measured Pt(Pn) stays within "
            f"{_pm(total, std)} (of Pt_ref) of Routh's broken line (near-zero level "
            f"{NEAR_ZERO:g})."
        ),
    ]
    f = findings(a)
    held = sum(map(bool, (f.close_in_compression, f.far_in_restitution, f.Pt_peaks_then_falls)))
    lines.append(f"- The seed's three findings: {held} of 3 hold on this record (below).")
    if fit is not None:
        table = fit.table()
        values = ", ".join(
            f"{r['quantity']} {'' if r['value'][:1] in '≥≤' else '= '}{r['value']}"
            + (f" {r['unit']}" if r["unit"] else "")
            for _, r in table.iterrows()
        )
        lines.append(f"- **The contact fit**: {table.attrs['verdict']} {values}.")
    return "\n".join(lines)


def fit_notes(fit, table) -> list:
    """What a report lists under a fit: what stands behind its verdict
    (``table.attrs["details"]``, each cause's message named), then the fit's notes that
    are not one of those messages again."""
    said = set((getattr(fit, "verdict", None) or {}).get("messages", {}).values())
    return [*table.attrs["details"], *(n for n in fit.notes if n not in said)]


def notes_markdown(title: str, notes) -> str:
    """``notes`` (warnings, a fit's notes) as a Markdown list under ``title``, their text
    escaped so that no ``*`` or ``_`` of a message turns into emphasis."""
    esc = str.maketrans({c: "\\" + c for c in "\\`*_[]<>#|"})
    return f"**{title}:**\n\n" + "\n".join(f"- {str(n).translate(esc)}" for n in notes)


def record_table(a) -> pd.DataFrame:
    """The record and its scene: file, contact window, ball, impact, the μ and e of the
    rigid prediction and where they came from."""
    sc, rs, w = a.scene, a.rigid_scene, a.window
    rows = [
        ("record", f"{a.record.attrs.get('source', '')} ({a.record.attrs.get('format', '?')})"),
        (
            "contact window",
            f"{w.n_samples} samples, {plain((w.t_end - w.t_start) * 1e6)} µs",
        ),
        ("ball", f"R = {plain(sc.radius * 1e3)} mm, m = {plain(float(sc.m) * 1e3)} g"),
        (
            "impact",
            f"v = {sc.speed:g} m/s at {sc.angle_deg:g}° (v_n0 = {plain(float(sc.v_n0))} m/s, "
            f"v_t0 = {plain(float(sc.v_t0))} m/s)",
        ),
        ("μ of the rigid model", f"{float(rs.mu):.4g} (from the {a.sources.get('mu')})"),
        ("e of the rigid model", f"{float(rs.e):.4g} (from the {a.sources.get('e')})"),
        ("μ estimated from the record", plain(a.mu_record)),
        ("regime (Routh)", str(a.rigid.regime)),
    ]
    return pd.DataFrame(rows, columns=["", "value"]).set_index("")


def outcomes_table(a) -> pd.DataFrame:
    """The measured outcomes ± their bootstrap std, rounded to it, beside Routh's rigid
    prediction (index: the quantities' symbols)."""
    rs = a.rigid
    rigid = {
        "e_n": float(a.rigid_scene.e),
        "e_t": float(rs.e_t),
        "omega": float(rs.omega),
        "rebound_deg": float(np.degrees(np.arctan2(float(rs.v_t), float(rs.v_n)))),
    }
    rows = []
    for k, r in rigid.items():
        unit, v, s, rv = in_unit(k, a.outcomes.values[k], a.outcomes.std[k], r)
        rows.append(
            {
                "quantity": quantity(k).symbol,
                "measured": _pm(v, s),
                "rigid (Routh)": plain(rv),
                "unit": unit,
                "meaning": quantity(k).meaning,
            }
        )
    return pd.DataFrame(rows).set_index("quantity")


def score_table(a) -> pd.DataFrame:
    """The deviation score per phase: area and maximum distance from Routh's broken line
    (dimensionless, of Pt_ref and P_ref) ± their bootstrap std."""
    v, s = a.score.values, a.score.std
    rows = [
        {
            "phase": phase,
            "area": _pm(v[phase]["area"], s[phase]["area"]),
            "max. distance": _pm(v[phase]["max_distance"], s[phase]["max_distance"]),
        }
        for phase in ("total", "compression", "restitution")
    ]
    return pd.DataFrame(rows).set_index("phase")


def implied_table(fit) -> pd.DataFrame:
    """What the fitted parameters imply (contact time, peak force, e_t, ω, ...), each in its
    unit at four significant digits (the fit gives them no uncertainty)."""
    rows = []
    for k, v in (fit.physics or {}).items():
        if isinstance(v, str):
            rows.append({"quantity": k, "value": v, "unit": "", "meaning": ""})
            continue
        unit, x = in_unit(k, v)
        q = quantity(k)
        rows.append({"quantity": q.symbol, "value": plain(x), "unit": unit, "meaning": q.meaning})
    return pd.DataFrame(rows, columns=["quantity", "value", "unit", "meaning"]).set_index(
        "quantity"
    )


# ------------------------------------------------------------------ a campaign
def _json_attr(ds, key) -> dict:
    return json.loads(ds.attrs.get(key, "{}") or "{}")


def _num(d: dict, key: str) -> float:
    """A trend's entry ``key`` as a float, NaN where it holds none (the JSON writes what too
    few records allow to fit as null)."""
    v = d.get(key)
    return float(v) if isinstance(v, (int, float)) else math.nan


def _fitted(d: dict, key: str) -> bool:
    return math.isfinite(_num(d, key))


def campaign_verdict(ds) -> str:
    """The campaign's verdict in words (Markdown): records analysed and failed, how far
    rigid-body theory is off, the friction and restitution trends, the joint fit."""
    ok = ds["status"].values == "ok"
    n, n_ok = int(ds.sizes["record"]), int(ok.sum())
    lines = [f"## {ds.attrs.get('source', 'campaign')}: {n_ok} of {n} records analysed", ""]
    if n_ok:
        sel = dict(phase="total", metric="max_distance")
        d = ds["score"].sel(**sel).values[ok]
        s = np.nan_to_num(ds["score_std"].sel(**sel).values[ok])
        off = int(np.sum(d - 3 * s > NEAR_ZERO))
        lines.append(
            f"- **Rigid-body theory** is off (the measured Pt(Pn) farther than the near-zero "
            f"level {NEAR_ZERO:g} from Routh's broken line, by three standard deviations) "
            f"for {off} of {n_ok} records; the largest distance is {plain(float(np.max(d)), 3)}."
        )
    tr = _json_attr(ds, "trends_json")
    fr, re_ = tr.get("friction", {}), tr.get("restitution", {})
    if _fitted(fr, "mu_const"):
        const = f"μ = {pdg(fr['mu_const'], _num(fr, 'mu_const_std'))}"
        if not _fitted(fr, "mu_a"):
            text = (
                f"is taken as constant, {const}: a law in the tangential speed needs three "
                f"records or more with different v_t0 ({tr.get('n_used', 0)} analysed)."
            )
        else:
            gap = abs(_num(fr, "aic_linear") - _num(fr, "aic_constant"))
            law = (
                f"μ = {rounded(fr['mu_a'], _num(fr, 'mu_a_std'))} + "
                f"{rounded(fr['mu_b'], _num(fr, 'mu_b_std'))} s/m · v_t0"
            )
            text = (
                f"changes with the tangential speed: {law}, preferred to a constant "
                f"{const} by ΔAIC = {plain(gap, 3)}."
                if _num(fr, "aic_linear") < _num(fr, "aic_constant")
                else f"is constant, {const} (the linear law {law} is not better: ΔAIC = "
                f"{plain(gap, 3)})."
            )
        lines.append("- **Friction** " + text)
    if "e_const" in re_:
        pref = re_.get("preferred")
        gap = abs(_num(re_, "aic_constant_e") - _num(re_, "aic_constant_alpha"))
        e_text = f"e = {pdg(re_['e_const'], _num(re_, 'e_const_std'))}"
        a_text = f"α = {pdg(re_['alpha'], _num(re_, 'alpha_std'))} s/m"
        lines.append(
            "- **Restitution**: "
            + (
                f"constant, {e_text}, rather than falling with speed ({a_text}); "
                if pref == "constant_e"
                else f"falls with speed at a constant {a_text}, rather than a constant {e_text}; "
            )
            + f"ΔAIC = {plain(gap, 3)}."
        )
    jf = _json_attr(ds, "joint_fit_json")
    if jf:
        df = joint_table(ds)
        values = ", ".join(
            f"{r['quantity']} = {r['value']}" + (f" {r['unit']}" if r["unit"] else "")
            for _, r in df.iterrows()
        )
        lines.append(
            f"- **The joint fit of every record's forces** ({df.attrs['verdict']}): {values}."
        )
    warned = [w for w in ds.attrs.get("joint_fit_warnings", "").splitlines() if w.strip()]
    if warned:  # by kind: each names every record and channel (in the attribute)
        kinds = Counter(w.split(":")[0].strip() for w in warned)
        lines.append(
            "- The joint fit warned: "
            + ", ".join(f"{k} ×{n}" for k, n in kinds.items())
            + " (one per hypothesis fitted; every record's and channel's reason in "
            "`ds.attrs['joint_fit_warnings']`)."
        )
    if ds.attrs.get("joint_fit_error"):
        lines.append(f"- The joint fit failed: {ds.attrs['joint_fit_error']}")
    for name, status, reason in zip(
        ds["record"].values, ds["status"].values, ds["reason"].values, strict=True
    ):
        if status != "ok":
            lines.append(f"- `{name}` failed: {reason}")
    return "\n".join(lines)


def records_table(ds, *, fits: bool = False) -> pd.DataFrame:
    """Every record: incidence, speed, regime, the measured outcomes ± their bootstrap std
    (rounded to it), μ estimated from the record and the deviation score; with ``fits``,
    each record's fitted E*, e, μ, k_t/k_M ± their standard errors and χ²_ν instead (an
    empty table where the campaign fitted none)."""
    if fits and "fit_E_eff" not in ds:
        return pd.DataFrame()
    cols = {
        "α [°]": lambda i: f"{float(ds['angle'].values[i]):g}",
        "v [m/s]": lambda i: f"{float(ds['speed'].values[i]):g}",
        "status": lambda i: str(ds["status"].values[i]),
        "regime": lambda i: str(ds["regime"].values[i]),
    }

    def pm(name, scale=1.0):
        std, ident = f"{name}_std", name.replace("fit_", "fit_identifiable_", 1)

        def cell(i):
            v = float(ds[name].values[i]) * scale
            s = float(ds[std].values[i]) * scale if std in ds else math.nan
            if not np.isfinite(v):
                return "–"
            if ident in ds and not ds[ident].values[i] and not np.isfinite(s):
                return bound(v, "lower")  # bounded from below only (pipeline.campaigns.tasks)
            return _pm(v, s)

        return cell

    cols.update(
        {
            "e_n": pm("e_n"),
            "e_t": pm("e_t"),
            "ω [rad/s]": pm("omega"),
            "θ_r [°]": pm("rebound_deg"),
            "μ (record)": lambda i: plain(float(ds["mu_record"].values[i])),
        }
    )
    if "score" in ds:

        def dist(i):
            sel = dict(phase="total", metric="max_distance")
            v = float(ds["score"].sel(**sel).values[i])
            s = float(ds["score_std"].sel(**sel).values[i])
            return _pm(v, s) if np.isfinite(v) else "–"

        cols["max. distance"] = dist
    if fits:
        cols = {
            "α [°]": cols["α [°]"],
            "v [m/s]": cols["v [m/s]"],
            "status": cols["status"],
            "E* [GPa]": pm("fit_E_eff", 1e-9),
            "e": pm("fit_e"),
            "μ": pm("fit_mu"),
            "k_t/k_M": pm("fit_kt_scale"),
            "χ²_ν": lambda i: plain(float(ds["fit_redchi"].values[i]), 3),
        }
    if (ds["status"].values == "ok").all():
        del cols["status"]
    rows = []
    for i, name in enumerate(ds["record"].values):
        row = {"record": str(name)}
        ok = ds["status"].values[i] == "ok"
        for k, f in cols.items():
            row[k] = f(i) if ok or k == "status" else "–"
        rows.append(row)
    return pd.DataFrame(rows).set_index("record")


def trends_table(ds, which: str) -> pd.DataFrame:
    """The campaign's trend of ``which`` (``"friction"`` or ``"restitution"``): each
    hypothesis with its parameters ± their standard errors and its AIC, the preferred one
    marked (:func:`pipeline.campaigns.trends`)."""
    tr = _json_attr(ds, "trends_json").get(which, {})

    def row(law, params, aic_key, unit=""):
        text = "; ".join(
            f"{sym} = {pdg(tr[k], _num(tr, f'{k}_std'))}" + (f" {u}" if u else "")
            for sym, k, u in params
            if _fitted(tr, k)
        )
        return {"hypothesis": law, "parameters": text, "AIC": _num(tr, aic_key)}

    if which == "friction":
        rows = [
            row("μ = μ_a + μ_b·v_t0", (("μ_a", "mu_a", ""), ("μ_b", "mu_b", "s/m")), "aic_linear"),
            row("μ constant", (("μ", "mu_const", ""),), "aic_constant"),
        ]
    elif which == "restitution":
        rows = [
            row("e constant", (("e", "e_const", ""),), "aic_constant_e"),
            row("α constant (e falls with speed)", (("α", "alpha", "s/m"),), "aic_constant_alpha"),
        ]
    else:
        raise ValueError(f"which must be 'friction' or 'restitution', got {which!r}")
    rows = [r for r in rows if r["parameters"]]
    if not rows:
        df = pd.DataFrame(columns=["parameters", "ΔAIC"])
        df.attrs["verdict"] = f"No {which} trend (too few records)"
        return df
    best = min(rows, key=lambda r: r["AIC"])
    preferred, lowest = best["hypothesis"], best["AIC"]
    for r in rows:
        r["ΔAIC"] = plain(r.pop("AIC") - lowest, 3)
    df = pd.DataFrame(rows).set_index("hypothesis")
    n = tr.get("n_used", _json_attr(ds, "trends_json").get("n_used"))
    df.attrs["verdict"] = (
        f"{which.capitalize()}"
        + (f" over {n} records" if n is not None else "")
        + (
            f": {preferred} preferred (lowest AIC)"
            if len(rows) > 1
            else f": {preferred} (the only hypothesis so few records allow)"
        )
    )
    return df


def joint_table(ds) -> pd.DataFrame:
    """The joint fit of every record's forces (:mod:`pipeline.campaigns.joint`): the chosen
    hypothesis' shared parameters ± their standard errors, rounded to them, in their units;
    its comparison with the other hypotheses in ``attrs["compare"]``."""
    jf = _json_attr(ds, "joint_fit_json")
    if not jf:
        df = precision.parameter_table(
            [], verdict=ds.attrs.get("joint_fit_error", "no joint fit (fewer than two records)")
        )
        df.attrs["compare"] = pd.DataFrame()
        return df
    values, stderr = jf.get("values", {}), jf.get("stderr", {})
    rows = [
        {"name": k, "value": v, "stderr": stderr.get(k) if stderr.get(k) is not None else math.nan}
        for k, v in values.items()
        if isinstance(v, (int, float)) and kind_of(k) == "contact"
    ]
    hyp = jf.get("hypothesis", {})
    chosen = next(
        (
            c
            for c in jf.get("compare", [])
            if (c.get("mu_law"), c.get("damping")) == (hyp.get("mu_law"), hyp.get("damping"))
        ),
        {},
    )
    verdict = (
        f"{hypothesis_words(hyp.get('mu_law'), hyp.get('damping'), jf.get('normal'))}: the best of "
        f"{len(jf.get('compare', []))} hypotheses by AIC"
        + (f", χ²_ν = {plain(chosen['redchi'], 3)}" if chosen.get("redchi") is not None else "")
    )
    df = precision.parameter_table(rows, verdict=verdict, normal=jf.get("normal"))
    df = df.drop(columns=[c for c in df.columns if c.endswith("interval")])
    compare = pd.DataFrame(jf.get("compare", []))
    if not compare.empty:
        compare = pd.DataFrame(
            {
                "μ law": compare["mu_law"].map(lambda x: HYPOTHESIS_WORDS.get(x, x)),
                "damping": compare["damping"].map(lambda x: HYPOTHESIS_WORDS.get(x, x)),
                "k": compare["k"],
                "χ²_ν": compare["redchi"].map(lambda x: plain(x, 3)),
                "ΔAIC": compare["delta_aic"].map(lambda x: plain(x, 3)),
                "ΔBIC": compare["delta_bic"].map(lambda x: plain(x, 3)),
            }
        )
    df.attrs["compare"] = compare
    return df
