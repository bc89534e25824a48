"""Reports: the seed paper's figures, ``summary.json`` and ``report.md`` for a set of records.

:func:`reproduce` is the main job behind ``make reproduce``: it analyses every bundled
sample that carries a ground-truth sidecar (``<name>.json`` with a ``scene``), ingests and
summarises the others, draws the seed's Figs. 4, 6, 8 and 9 for the main record (the 15°
Garland–Rogers-style one) and states, with numbers, whether the seed's three qualitative
findings hold:

1. the rigid broken line is close to the measured Pt(Pn) in **compression**;
2. it is far from it in **restitution**;
3. the measured tangential percussion **has a maximum and then decreases**.

Verdict rules (all on the dimensionless metrics of :mod:`pipeline.score`, ± their
bootstrap standard deviations σ):

- finding 1 holds when the compression phase's maximum distance is below the restitution
  phase's and its area is below the restitution area;
- finding 2 holds when the restitution phase's maximum distance exceeds
  :data:`NEAR_ZERO` by more than 3σ;
- finding 3 holds when ``Pt_drop`` exceeds :data:`NEAR_ZERO` by more than 3σ.

A record that fails is listed with its reason (``summary.json``: ``status``, ``error``;
``report.md``: "Failed records") and the others go on. The whole output folder is
replaced in one rename (staging folder, :func:`pipeline._atomic.atomic_dir`), so an
interrupted run leaves the previous run complete, never a mix of two.
"""

from __future__ import annotations

import hashlib
import json
import logging
import math
import uuid
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ._atomic import atomic_dir, atomic_write_text, clean_stale
from ._json import json_ready
from .advice import advice_for
from .analysis import Analysis, analyse
from .errors import InputError
from .fit import fit_contact
from .fit.sensor import sensor_spec
from .io import RECORD_SUFFIXES
from .percussion import compression_split, percussions
from .precision import pdg
from .score import NEAR_ZERO
from .sidecar import (
    LOAD_KEYS,
    load_sample,
    read_sidecar,
    sample_files,
    scene_from_sidecar,
    sensor_from_sidecar,
    sidecar_path,
)
from .window import find_contact

__all__ = [
    "NEAR_ZERO",
    "LOAD_KEYS",
    "Findings",
    "findings",
    "fitted_parameters",
    "fitted_parameters_md",
    "load_sample",
    "outcomes_frame",
    "read_sidecar",
    "reproduce",
    "sample_files",
    "scene_from_sidecar",
    "sensor_from_sidecar",
    "sidecar_path",
    "write_manifest",
]

log = logging.getLogger(__name__)

MAIN_RECORD = "gr_15deg_0.6ms.csv"


@dataclass(frozen=True)
class Findings:
    """The seed's three qualitative findings, tested on one analysis."""

    close_in_compression: bool
    far_in_restitution: bool
    Pt_peaks_then_falls: bool
    text: tuple[str, str, str]

    def summary(self) -> dict:
        return {
            "close_in_compression": self.close_in_compression,
            "far_in_restitution": self.far_in_restitution,
            "Pt_peaks_then_falls": self.Pt_peaks_then_falls,
            "text": list(self.text),
        }


def _pm(score, phase, metric):
    """A score ± its bootstrap std, rounded to it (:func:`pipeline.precision.pdg`)."""
    v = score.values[phase][metric]
    s = score.std[phase][metric]
    return pdg(v, s) if np.isfinite(s) and s > 0 else f"{v:.3f}"


def findings(a: Analysis) -> Findings:
    """Test the seed's three findings on an analysis (module notes give the rules)."""
    sc = a.score
    v, s = sc.values, sc.std

    def sig(phase, metric):
        x = s[phase][metric]
        return x if np.isfinite(x) else 0.0

    c, r = v["compression"], v["restitution"]
    one = c["max_distance"] < r["max_distance"] and c["area"] < r["area"]
    two = r["max_distance"] - 3 * sig("restitution", "max_distance") > NEAR_ZERO
    three = v["total"]["Pt_drop"] - 3 * sig("total", "Pt_drop") > NEAR_ZERO
    t1 = (
        f"Compression: area {_pm(sc, 'compression', 'area')}, maximum distance "
        f"{_pm(sc, 'compression', 'max_distance')}; restitution: area "
        f"{_pm(sc, 'restitution', 'area')}, maximum distance "
        f"{_pm(sc, 'restitution', 'max_distance')}. The broken line is "
        + (
            "closer in compression than in restitution: **holds**."
            if one
            else "not closer in compression: **does not hold**."
        )
    )
    t2 = (
        f"Restitution maximum distance {_pm(sc, 'restitution', 'max_distance')} "
        f"(of Pt_ref) against the near-zero level {NEAR_ZERO}: "
        + ("**holds**." if two else "**does not hold**.")
    )
    t3 = (
        f"Pt peaks at {_pm(sc, 'total', 'Pt_max')} × Pt_ref where Pn = "
        f"{_pm(sc, 'total', 'Pn_at_Pt_max')} × P_ref "
        f"({(sc.t_Pt_max - a.window.t_start) * 1e6:.1f} µs after contact start), then "
        f"falls by {_pm(sc, 'total', 'Pt_drop')} × Pt_ref: "
        + ("**holds**." if three else "**does not hold**.")
    )
    return Findings(bool(one), bool(two), bool(three), (t1, t2, t3))


def outcomes_frame(a: Analysis) -> pd.DataFrame:
    """The measured outcomes of an analysis and their spread, as a record's report shows them.

    Returns
    -------
    pandas.DataFrame
        Index ``quantity``: ``e_n [-]``, ``e_t [-]``, ``omega [rad/s]``,
        ``rebound_deg [deg]``; columns ``measured`` (the value) and ``std`` (its 1-σ
        bootstrap spread), in those units.
    """
    units = (("e_n", "-"), ("e_t", "-"), ("omega", "rad/s"), ("rebound_deg", "deg"))
    rows = [
        {"quantity": f"{k} [{u}]", "measured": a.outcomes.values[k], "std": a.outcomes.std[k]}
        for k, u in units
    ]
    return pd.DataFrame(rows).set_index("quantity")


def _quiet(fn, *args, **kwargs):
    """Call fn, collecting (not raising) its warnings; return (result, messages)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = fn(*args, **kwargs)
    msgs = list(dict.fromkeys(f"{w.category.__name__}: {w.message}" for w in caught))
    for m in msgs:
        log.info("%s", m)
    return out, msgs


def _ingest_only(path: Path) -> dict:
    """Summary of a record without a known scene: window, percussions, Poisson e."""
    rec = load_sample(path)
    # a discharge the sidecar's or the record's sensor states is undone for the window
    win = find_contact(rec, discharge=sensor_spec(rec, sensor_from_sidecar(path)).discharge)
    perc = percussions(win)
    split = compression_split(perc, method="closure", source="trapezoid")
    return {
        "file": path.name,
        "format": rec.attrs.get("format"),
        "kind": rec.attrs.get("kind"),
        "samples": int(rec.sizes["time"]),
        "window": win.summary(),
        "Pn_total_Ns": float(perc.Pn("trapezoid")[-1]),
        "Pt_total_Ns": None if perc.Pt_fit is None else float(perc.Pt("trapezoid")[-1]),
        "e_poisson_closure": split.e_poisson,
    }


def _analyse_sample(path, scene, n_boot, seed):
    sensor = sensor_from_sidecar(path)  # a calibrated rig's, for the fits
    fit_options = None if sensor is None else {"sensor": sensor}
    return analyse(load_sample(path), scene, n_boot=n_boot, seed=seed, fit_options=fit_options)


def _one(path: Path, n_boot: int, seed: int):
    """The summary entry of one sample, and its Analysis (None when ingested only).

    Every failure is caught — a bad file (InputError), a bug (any other exception) — and
    becomes the entry's ``status``/``error``: one record never stops a batch.
    """
    try:
        scene = scene_from_sidecar(path)
        if scene is None:
            entry, msgs = _quiet(_ingest_only, path)
            a = None
        else:
            a, msgs = _quiet(_analyse_sample, path, scene, n_boot, seed)
            advice = advice_for(a.rigid_scene)
            entry = {
                "file": path.name,
                **a.summary(),
                "findings": findings(a).summary(),
                "advice": None if advice is None else advice.summary(),
            }
        entry = {"status": "ok", **entry, "warnings": msgs}
        return entry, a
    except Exception as exc:  # reported, and the batch goes on
        kind = "bad input" if isinstance(exc, InputError | OSError) else "internal error"
        log.warning("%s failed (%s): %s", path.name, kind, exc)
        return {
            "file": path.name,
            "status": "failed",
            "error": f"{type(exc).__name__}: {exc}",
            "error_kind": kind,
        }, None


# --------------------------------------------------------------------------- the main job
def reproduce(
    samples="data_samples",
    out="build/reproduce",
    *,
    main=MAIN_RECORD,
    n_boot: int = 200,
    seed: int = 0,
) -> dict:
    """Run the whole chain on the bundled samples and write the seed's figures and a report.

    Parameters
    ----------
    samples : path
        Folder of sample records (``*.csv``, ``*.tdms``, ``*.lvm``, ``*.mat``; ``*.json``
        are sidecars).
    out : path
        Output folder: ``fig4_percussion_plane.png``, ``fig6_disc_velocity.png``,
        ``fig8_forces.png``, ``fig9_percussion_plane.png`` (when the main record was
        analysed), ``summary.json``, ``report.md`` and ``manifest.json`` (every file's
        SHA-256 and the run's settings).
    main : str
        File name of the record the figures and findings are made for.
    n_boot, seed : int
        Bootstrap replicates and seed for the score's uncertainties.

    Returns
    -------
    dict
        The summary written to ``summary.json``: ``records`` (one entry per sample, with
        ``status`` ``"ok"`` or ``"failed"`` and, for a failure, its ``error``),
        ``failures`` (file → error) and ``n_failed``.

    Notes
    -----
    A record that fails — for any reason, bad input or a bug — is listed with its reason
    and the others go on. The outputs are written into a staging folder that replaces
    ``out`` in one rename (:func:`pipeline._atomic.atomic_dir`): ``out`` holds the
    previous run or this one, never a mix, and a killed run's staging folder is removed
    by the next run.

    Raises
    ------
    InputError
        No sample folder, or no records in it.
    """
    samples, out = Path(samples), Path(out)
    files = sample_files(samples)
    if not files:
        patterns = ", ".join(f"*{s}" for s in RECORD_SUFFIXES)
        raise InputError(f"no sample records ({patterns}) in {samples}")
    clean_stale(out)  # a killed run's staging folder goes now, not only when this one ends
    records, analyses = [], {}
    for path in files:
        entry, a = _one(path, n_boot, seed)
        records.append(entry)
        if a is not None:
            analyses[path.name] = a
    a = analyses.get(main)
    f = None if a is None else findings(a)
    failures = {r["file"]: r["error"] for r in records if r["status"] == "failed"}
    if a is None and main not in failures:
        failures[main] = "the main record is not among the samples, or has no scene"
    summary = {
        "main": main,
        "near_zero": NEAR_ZERO,
        "findings": None if f is None else f.summary(),
        "n_records": len(records),
        "n_failed": sum(r["status"] == "failed" for r in records),
        "failures": failures,
        "records": records,
    }
    summary["fitted_parameters"] = fitted = fitted_parameters(files, n_boot=n_boot, seed=seed)
    with atomic_dir(out) as stage:
        if a is not None:
            from . import figures  # matplotlib: only where figures are drawn

            figs = {
                "fig4_percussion_plane.png": figures.fig4_percussion_plane(),
                "fig6_disc_velocity.png": figures.fig6_disc_velocity(),
                "fig8_forces.png": figures.fig8_forces(a),
                "fig9_percussion_plane.png": figures.fig9_percussion_plane(a),
            }
            for name, fig in figs.items():
                figures.save(fig, stage / name)
        atomic_write_text(
            stage / "summary.json",
            json.dumps(json_ready(summary), indent=1, allow_nan=False) + "\n",
        )
        text = (
            _report_md(main, a, f, records, analyses, _provenance(samples / main))
            if a is not None
            else _failed_report_md(main, failures, records)
        )
        atomic_write_text(stage / "report.md", text + fitted_parameters_md(fitted))
        write_manifest(stage, samples=str(samples), main=main, n_boot=n_boot, seed=seed)
    return json_ready(summary)


def write_manifest(folder, **settings) -> Path:
    """Write ``manifest.json``: every other file's SHA-256 and size, and the run's settings.

    A reader (or a test) can tell a complete run from a damaged one: the folder holds
    exactly the files listed, each with its hash.
    """
    folder = Path(folder)
    files = {}
    for p in sorted(folder.rglob("*")):
        if p.name == "manifest.json" or not p.is_file():
            continue
        files[p.relative_to(folder).as_posix()] = {
            "sha256": hashlib.sha256(p.read_bytes()).hexdigest(),
            "bytes": p.stat().st_size,
        }
    manifest = {"run_id": uuid.uuid4().hex, "settings": settings, "files": files}
    return atomic_write_text(folder / "manifest.json", json.dumps(manifest, indent=1) + "\n")


def _failure_lines(records) -> list[str]:
    failed = [r for r in records if r["status"] == "failed"]
    if not failed:
        return []
    lines = ["", "## Failed records", ""]
    lines += [f"- `{r['file']}` ({r['error_kind']}): {r['error']}" for r in failed]
    return lines


def _failed_report_md(main, failures, records) -> str:
    lines = [
        "# Rigid versus deformable: the seed's verdict, measured",
        "",
        f"The main record `{main}` could not be analysed, so there are no figures and no "
        f"verdict: {failures.get(main, 'see below')}.",
        "",
        f"{sum(r['status'] == 'ok' for r in records)} of {len(records)} records were "
        "processed; every number is in `summary.json`.",
    ]
    return "\n".join(lines + _failure_lines(records)) + "\n"


def _provenance(path) -> str:
    """What the record's sidecar says of where it came from ("" when it says nothing)."""
    side = read_sidecar(path) if Path(path).exists() else {}
    if side.get("synthetic"):
        return "synthetic: made as its sidecar `" + Path(path).with_suffix(".json").name + "` says"
    return str(side.get("note", "") or side.get("description", ""))


def _report_md(main, a: Analysis, f: Findings, records, analyses, provenance="") -> str:
    sc, rs = a.scene, a.rigid_scene
    lines = [
        "# Rigid versus deformable: the seed's verdict, measured",
        "",
        "Ciornei et al., MATEC Web Conf. 112, 07005 (2017) fitted Garland & Rogers' 15° "
        "force record with quartics, integrated it into percussions and laid Pt(Pn) over "
        f"Routh's rigid broken line. This report does the same on the record `{main}`"
        + (f" ({provenance})" if provenance else "")
        + f" — a {2e3 * sc.radius:.3g} mm ball at {sc.speed:g} m/s and {sc.angle_deg:g}°, "
        f"μ = {rs.mu:.3g} (from the {a.sources.get('mu', 'scene')}), e = {rs.e:.3g} (from the "
        f"{a.sources.get('e', 'scene')}) — and states each finding with numbers.",
        "",
        f"Rigid prediction: **{a.rigid.regime}** regime (tan α = "
        f"{math.tan(math.radians(rs.angle_deg)):.3f} vs {(1 + rs.kappa) / rs.kappa:g}·μ·(1+e) = "
        f"{(1 + rs.kappa) / rs.kappa * rs.mu * (1 + rs.e):.3f} with μ = {rs.mu:.3g}, "
        f"e = {rs.e:.3g}); P_ref = Pn_f = {a.score.P_ref:.4g} N·s, "
        f"Pt_ref = Pt_f = {a.score.Pt_ref:.4g} N·s. Percussions scored from "
        + (
            f"the degree-{a.fits.Fn.degree} fit's exact integral"
            if a.source == "fit"
            else f"the {a.source} integral of the samples"
        )
        + "; measured e (Poisson) = "
        f"{a.split.e_poisson:.4f}. Metrics are dimensionless (of P_ref, Pt_ref), "
        f"± bootstrap standard deviation ({a.score.n_boot} replicates).",
        "",
        "## The seed's three findings",
        "",
        f"1. *The broken line is a good approximation in compression.* {f.text[0]}",
        f"2. *It is far off in restitution.* {f.text[1]}",
        f"3. *The measured tangential percussion peaks, then decreases.* {f.text[2]}",
        "",
        f"The seed's quartic fit gives area {a.score_fit['area']:.3f} and maximum distance "
        f"{a.score_fit['max_distance']:.3f} (against {a.score['area']:.3f} and "
        f"{a.score['max_distance']:.3f} from the samples); quartic residual RMS "
        f"{a.fits.Fn.rms:.3g} N (Fn), {a.fits.Ft.rms:.3g} N (Ft)"
        + (" — flagged as structured." if (a.fits.Fn.poor or a.fits.Ft.poor) else "."),
        "",
        f"## All {len(records)} records",
        "",
        "| record | regime | area | max distance | Pt drop | compression area | "
        "restitution area | e (Poisson) | model needed | checks |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in records:
        name = r["file"]
        if r["status"] == "failed":
            lines.append(f"| {name} | failed: {r['error']} |  |  |  |  |  |  |  |  |")
        elif name in analyses:
            x = analyses[name]
            advice = r.get("advice")
            lines.append(
                f"| {name} | {x.rigid.regime} | {_pm(x.score, 'total', 'area')} | "
                f"{_pm(x.score, 'total', 'max_distance')} | "
                f"{_pm(x.score, 'total', 'Pt_drop')} | "
                f"{_pm(x.score, 'compression', 'area')} | "
                f"{_pm(x.score, 'restitution', 'area')} | {x.split.e_poisson:.4f} | "
                f"{'—' if advice is None else advice['model']} | {_checks(x)} |"
            )
        else:
            lines.append(
                f"| {name} | no scene (ingested only) |  |  |  |  |  | "
                f"{r['e_poisson_closure']:.4f} (closure) |  |  |"
            )
    lines += [
        "",
        "*Model needed*: the cheapest of rigid < coulomb < mindlin whose e_t, ω and Pt(Pn) "
        "stay within 1e-3 of the full Hertz–Mindlin model for the record's scene "
        "(`pipeline.advise`; the reason for each is in `summary.json`, `advice`).",
        "",
        "*Checks*: the plausibility checks that warned (`pipeline.plausibility`): the record "
        "against its scene (contact time, peak force, impulse) and the measured outcome "
        "against the bounds of a passive impact (e_n ≤ 1, e_t ≤ 1, no kinetic energy gained, "
        "|Pt| ≤ μ·Pn, friction against the slip); each warning, with its likeliest cause, is "
        "in `summary.json` (`warnings`, `plausibility`).",
        "",
        "Figures: `fig4_percussion_plane.png` (seed Fig. 4), `fig6_disc_velocity.png` "
        "(analogue of seed Fig. 6), `fig8_forces.png` (seed Fig. 8), "
        "`fig9_percussion_plane.png` (seed Fig. 9). Every number is in `summary.json`.",
    ]
    return "\n".join(lines + _failure_lines(records)) + "\n"


def _checks(a: Analysis) -> str:
    """The plausibility checks that warned for a record, or "ok"."""
    bad = [c.name for c in a.plausibility.checks if c.status == "warning"]
    return ", ".join(bad) if bad else "ok"


# --------------------------------------------------------------------------- contact fits
#: sidecar truth of each fitted parameter: the scene's E* (from E, ν), e and μ; Mindlin's
#: stiffness itself (kt_scale 1); first contact at the sensor's trigger instant
_TRUTH = {
    "E_eff": lambda side, sc: float(sc.E_eff),
    "e": lambda side, sc: sc.e,
    "mu": lambda side, sc: sc.mu,
    "kt_scale": lambda side, sc: 1.0,
    "t0": lambda side, sc: float(side.get("sensor", {}).get("trigger_time", 0.0)),
}


def fitted_parameters(paths, *, n_boot: int = 200, seed: int = 0) -> list:
    """The contact parameters fitted to every simulated sample, with its truth beside them.

    For each record whose sidecar states the simulation's ``model`` (the Garland–Rogers-style
    samples), :func:`pipeline.fit_contact` fits that model (normal law, tangential model,
    history rule) with the sidecar's ``sensor`` block (bandwidth, filter order, ADC step,
    cross-talk matrix: a calibrated rig's) and ``n_boot`` block-bootstrap replicates.

    Returns
    -------
    list of dict
        Per record: ``file``, ``model``, and per parameter ``value``, ``stderr``, ``ci95``,
        ``identifiable``, ``truth`` and ``error`` (value − truth); a failed fit gives
        ``error`` with the reason. Records without such a sidecar are skipped.
    """
    out = []
    for path in paths:
        try:
            side = read_sidecar(path)
        except (InputError, OSError):
            continue  # the record's own entry reports its sidecar
        model = side.get("model")
        if not isinstance(model, dict) or "scene" not in side:
            continue
        try:
            scene = scene_from_sidecar(path)
            rec, _ = _quiet(load_sample, path)
            fit, msgs = _quiet(
                fit_contact,
                rec,
                scene,
                normal=model.get("normal", "hunt_crossley"),
                tangential=model.get("tangential", "mindlin"),
                history=model.get("history_rule") or "total",
                sensor=side.get("sensor"),
                n_boot=n_boot,
                seed=seed,
            )
        except Exception as exc:  # one record's fit never stops the report
            log.warning("%s: contact fit failed: %s", Path(path).name, exc)
            out.append({"file": Path(path).name, "error": f"{type(exc).__name__}: {exc}"})
            continue
        ci = fit.ci(0.95)
        params = {}
        for name in fit.vary:
            truth = _TRUTH[name](side, scene) if name in _TRUTH else None
            v = fit.values[name]
            params[name] = {
                "value": v,
                "stderr": fit.stderr[name],
                "ci95": list(ci[name]),
                "identifiable": bool(fit.identifiable[name]),
                "truth": truth,
                "error": None if truth is None else v - truth,
            }
        out.append(
            {
                "file": Path(path).name,
                "model": f"{fit.normal}+{fit.tangential}",
                "redchi": fit.redchi,
                "regime": fit.physics.get("regime"),
                "parameters": params,
                "warnings": msgs,
            }
        )
    return json_ready(out)


def fitted_parameters_md(entries) -> str:
    """The section of report.md tabulating :func:`fitted_parameters` (empty without fits)."""
    if not entries:
        return ""
    lines = [
        "",
        "## Fitted contact parameters against the truth",
        "",
        "`pipeline.fit_contact` on each synthetic sample with the model it was simulated with "
        "and its sidecar's sensor block; value ± standard error, the truth from the sidecar "
        "in brackets. A parameter the data bound only from below is shown as ≥ its 95 % "
        "bound. Intervals, bootstrap and notes are in `summary.json` (`fitted_parameters`).",
        "",
        "| record | χ²_ν | E* [GPa] | e | μ | kt_scale | t0 [µs] |",
        "|---|---|---|---|---|---|---|",
    ]

    def cell(p, name, scale=1.0, digits=4):
        q = p.get(name)
        if q is None:
            return "—"
        v = q["value"] * scale
        t = "" if q["truth"] is None else f" [{q['truth'] * scale:.{digits}g}]"
        if not q["identifiable"]:
            return f"≥ {v:.{digits}g}{t}"
        se = q["stderr"]
        pm = f" ± {se * scale:.2g}" if se is not None else ""
        return f"{v:.{digits}g}{pm}{t}"

    for r in entries:
        if "error" in r and "parameters" not in r:
            lines.append(f"| {r['file']} | failed: {r['error']} |  |  |  |  |  |")
            continue
        p = r["parameters"]
        lines.append(
            f"| {r['file']} | {r['redchi']:.3f} | {cell(p, 'E_eff', 1e-9, 5)} | {cell(p, 'e')} "
            f"| {cell(p, 'mu')} | {cell(p, 'kt_scale', 1.0, 3)} | {cell(p, 't0', 1e6, 2)} |"
        )
    return "\n".join(lines) + "\n"
