"""Stability maps of the measurement chain: where each percussion method fails.

Records with known truth (``benchmarks/_truth.py``: Hertz–Mindlin impacts of the bundled
25.4 mm steel ball through the sensor model, no cross-talk) are analysed by
:func:`pipeline.analyse` (``n_boot=0``) over the axes that break methods:

``noise_rate``
    white-noise level σ/F_max × samples per contact (5 … 2000);
``bandwidth_duration``
    the transducer's −3 dB bandwidth × the contact duration (ball radius 2 … 50 mm,
    200 samples per contact);
``threshold``
    the window's detection threshold k (in noise σ) × noise level;
``drift``
    linear baseline drift × baseline curvature (a parabola over the record, the part a
    linear baseline cannot remove; an ideal ADC so that nothing saturates);
``adc``
    ADC resolution (bits over the default ±2.5 kN) × noise level;
``grazing``
    incidence towards grazing × noise level [N] (the normal force falls as v_n0^1.2).

Each cell is analysed for ``SEEDS`` noise seeds. Two methods are scored: the default
(:func:`pipeline.analyse`'s scored source: Simpson on the samples, the quartic for sparse
records) and the seed's quartic. The error of a cell is the median over the seeds of the
worst of the four errors over their tolerances (``_truth.TOL``: 0.02 of P_ref in Pn_f, of
Pt_ref in Pt_f and in the Pt maximum, 0.02 in the deviation score's area), so 1 is the
tolerance. Its status is the worst
over the seeds of

- ``silent``: wrong (error above tolerance) and neither raised nor flagged — must not occur;
- ``flagged``: wrong and flagged (a warning naming the region, a poor-fit flag, a non-finite
  value);
- ``raises``: the analysis raised (the message names the cause);
- ``flag, ok``: flagged although within tolerance (a conservative flag);
- ``ok``.

Letters in the status panels name what flagged: S sparse sampling, N noise, Q coarse ADC,
B filter bandwidth, C curved baseline, P poor quartic fit, W another pipeline warning,
X an exception. Writes ``stability.json`` (every cell) and ``stability_<map>.png``.
"""

from __future__ import annotations

import json
import platform
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import scipy

import pipeline
from benchmarks import _truth
from pipeline import analyse
from pipeline._atomic import atomic_path, atomic_write_bytes
from pipeline._json import json_ready
from pipeline.errors import PipelineWarning, PoorFitWarning
from pipeline.percussion import ResolutionWarning
from pipeline.sensor_model import to_sensor

SEEDS = 2
METHODS = ("default", "quartic")
STATUS = ("ok", "flag, ok", "raises", "flagged", "silent")
STATUS_COLORS = ("#7fc97f", "#d9ef8b", "#beaed4", "#fdc086", "#e31a1c")
FLAG_CODES = {
    "sparse sampling": "S",
    "noise": "N",
    "coarse ADC": "Q",
    "filter bandwidth": "B",
    "curved baseline": "C",
    "poor fit": "P",
    "warning": "W",
    "exception": "X",
}


@dataclass(frozen=True)
class Axis:
    label: str
    values: tuple
    ticks: tuple = ()  # tick labels (default: the values)


@dataclass(frozen=True)
class Cell:
    """What one cell asks of the simulator, the sensor model and the window."""

    scene: object
    samples: float = 200.0
    sensor: dict = field(default_factory=dict)
    window: dict = field(default_factory=dict)
    curvature: float = 0.0  # baseline parabola at the record's ends / the true F_max


@dataclass(frozen=True)
class MeasureMap:
    name: str
    title: str
    x: Axis
    y: Axis
    cell: Callable  # (x, y) -> Cell
    regions: str  # the failure regions this map shows (for the chart and the JSON)


BASE = _truth.BASE_SCENE

MAPS = (
    MeasureMap(
        "noise_rate",
        "noise level × sampling rate",
        Axis("samples per contact", (5, 8, 12, 16, 20, 25, 30, 50, 100, 200, 500, 2000)),
        Axis("noise σ / F_max", (1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3)),
        lambda x, y: Cell(BASE, samples=x, sensor={"noise_rel": y}),
        "sparse sampling (S) below 20 samples per contact; noise (N) where 3·σ·Δt·√n "
        "exceeds 2 % of the percussions",
    ),
    MeasureMap(
        "bandwidth_duration",
        "filter bandwidth × contact duration",
        Axis("bandwidth f_c [kHz]", (10e3, 20e3, 50e3, 100e3, 200e3, 500e3, 1e6, 3e6)),
        Axis("ball radius [mm] (contact duration ∝ R)", (2e-3, 4e-3, 8e-3, 12.7e-3, 25e-3, 50e-3)),
        lambda x, y: Cell(
            BASE.replace(radius=y),
            sensor={"bandwidth": x, "noise_rel": 1e-3, "full_scale_rel": 4.0},
        ),
        "filter bandwidth (B) where f_c·t_c < 3: the low-pass smears the pulse",
    ),
    MeasureMap(
        "threshold",
        "window threshold × noise level",
        Axis("detection threshold k [σ]", (1.5, 2.0, 3.0, 5.0, 10.0, 20.0, 50.0, 100.0, 300.0)),
        Axis("noise σ / F_max", (1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3)),
        lambda x, y: Cell(BASE, sensor={"noise_rel": y}, window={"k": x}),
        "no pulse above k·σ (X: raises); noise (N)",
    ),
    MeasureMap(
        "drift",
        "baseline drift × baseline curvature",
        Axis("linear drift [N/s]", (0.0, 1e2, 1e4, 1e5, 1e6, 1e7)),
        Axis("curvature at the record's ends / F_max", (0.0, 1e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1)),
        lambda x, y: Cell(
            BASE,
            sensor={"drift": x, "bits": None, "full_scale": float("inf")},
            curvature=y,
        ),
        "curved baseline (C): a linear drift is removed exactly, a curved one is not",
    ),
    MeasureMap(
        "adc",
        "ADC resolution × noise level",
        Axis("ADC bits over ±2.5 kN", (4, 6, 8, 10, 12, 14, 16, 20)),
        Axis("noise σ / F_max", (0.0, 1e-4, 1e-3, 1e-2)),
        lambda x, y: Cell(BASE, sensor={"bits": x, "noise_rel": y}),
        "coarse ADC (Q) where the step exceeds 2 % of a channel's peak and the noise",
    ),
    MeasureMap(
        "grazing",
        "incidence towards grazing × noise",
        Axis("incidence [deg]", (45.0, 60.0, 70.0, 80.0, 85.0, 88.0, 89.0, 89.5)),
        Axis("noise σ [N]", (0.2, 2.0, 20.0)),
        lambda x, y: Cell(BASE.replace(angle_deg=x), sensor={"noise": y}),
        "noise (N): at grazing incidence F_max ∝ v_n0^1.2 falls towards the noise",
    ),
)


def _curve(rec, amplitude):
    """The record plus a baseline parabola of ``amplitude`` [N] at its ends, 0 mid-record."""
    if amplitude == 0:
        return rec
    t = rec["time"].values
    u = (t - 0.5 * (t[0] + t[-1])) / (0.5 * (t[-1] - t[0]))
    out = rec.copy()
    for c in ("Fn", "Ft"):
        out[c] = rec[c] + amplitude * u**2
        out[c].attrs = dict(rec[c].attrs)
    return out


def _analyse_one(tr, cell: Cell, seed: int) -> dict:
    """Errors, flags and status of both methods for one record."""
    kw = _truth.sensor_kwargs(tr, cell.samples, **cell.sensor)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the sensor model's own warnings are not flags
        rec = _curve(to_sensor(tr.record, seed=seed, **kw), cell.curvature * tr.F_max)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            a = analyse(rec, tr.scene, n_boot=0, window_options=cell.window or None)
        except Exception as exc:  # every failure is a result here
            return {
                m: {
                    "status": "raises",
                    "flags": ["exception"],
                    "error": float("nan"),
                    "errors": {},
                    "message": f"{type(exc).__name__}: {exc}"[:300],
                }
                for m in METHODS
            }
    common, fit_flags = set(), set()
    for w in caught:
        if issubclass(w.category, ResolutionWarning):
            continue  # named by a.resolution.flags below
        if issubclass(w.category, PoorFitWarning):
            fit_flags.add("poor fit")
        elif issubclass(w.category, PipelineWarning):
            common.add("warning")
    common |= set(a.resolution.flags)
    fit_flags |= {"poor fit" for _ in a.resolution.fit_flags}
    out = {}
    perc = a.percussions
    for m, src in (("default", a.source), ("quartic", "fit")):
        errs = _truth.errors(tr, perc.time, perc.Pn(src), perc.Pt(src))
        norm = max(errs[q] / _truth.TOL[q] for q in _truth.QUANTITIES)
        flags = set(common)
        if src == "fit":
            flags |= fit_flags
        if not np.isfinite(norm):
            flags.add("warning")
        bad = not norm <= 1.0
        status = ("flagged" if bad else "flag, ok") if flags else ("silent" if bad else "ok")
        out[m] = {
            "status": status,
            "flags": sorted(flags),
            "error": norm,
            "errors": errs,
            "source": src,
        }
    return out


def _run_map(spec: MeasureMap, truths: dict) -> list:
    cells = []
    for iy, y in enumerate(spec.y.values):
        for ix, x in enumerate(spec.x.values):
            cell = spec.cell(x, y)
            key = (float(cell.scene.radius), float(cell.scene.angle_deg))
            if key not in truths:
                truths[key] = _truth.truth(cell.scene)
            runs = [_analyse_one(truths[key], cell, seed) for seed in range(SEEDS)]
            for m in METHODS:
                rs = [r[m] for r in runs]
                errs = [r["error"] for r in rs]
                fin = [e for e in errs if np.isfinite(e)]
                cells.append(
                    {
                        "ix": ix,
                        "iy": iy,
                        "x": x,
                        "y": y,
                        "method": m,
                        "status": STATUS[max(STATUS.index(r["status"]) for r in rs)],
                        "error_over_tol": float(np.median(fin)) if fin else float("nan"),
                        "errors_median": {
                            q: float(np.median([r["errors"].get(q, np.nan) for r in rs]))
                            for q in _truth.QUANTITIES
                        },
                        "flags": sorted({f for r in rs for f in r["flags"]}),
                        "message": next((r["message"] for r in rs if "message" in r), None),
                    }
                )
    return cells


def run(out_dir: Path) -> dict:
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    truths = {}
    maps = {}
    for spec in MAPS:
        t0 = time.perf_counter()
        cells = _run_map(spec, truths)
        counts = {
            m: {s: sum(c["status"] == s for c in cells if c["method"] == m) for s in STATUS}
            for m in METHODS
        }
        maps[spec.name] = {
            "title": spec.title,
            "x": {"label": spec.x.label, "values": list(spec.x.values)},
            "y": {"label": spec.y.label, "values": list(spec.y.values)},
            "regions": spec.regions,
            "status_counts": counts,
            "seconds": time.perf_counter() - t0,
            "cells": cells,
        }
        _plot(spec, cells, out_dir / f"stability_{spec.name}.png")
    report = {
        "benchmark": "stability",
        "what": "pipeline.analyse on simulated records through the sensor model; error of "
        "the default method and of the seed's quartic against the simulated truth, and "
        "whether each raised or flagged where it was wrong",
        "tolerance": _truth.TOL,
        "seeds_per_cell": SEEDS,
        "base_scene": BASE.to_dict(),
        "sensor": "to_sensor defaults except the mapped axis; cross-talk 0; pre/post "
        "trigger >= 30/60 samples",
        "status": {
            "silent": "wrong and neither raised nor flagged (must not occur)",
            "flagged": "wrong and flagged",
            "raises": "analyse raised",
            "flag, ok": "flagged although within tolerance",
            "ok": "within tolerance, not flagged",
        },
        "flag_codes": FLAG_CODES,
        "silent_cells": sum(
            m["status_counts"][k]["silent"] for m in maps.values() for k in METHODS
        ),
        "machine": {
            "python": platform.python_version(),
            "platform": platform.platform(),
            "numpy": np.__version__,
            "scipy": scipy.__version__,
            "pipeline": pipeline.__version__,
        },
        "maps": maps,
    }
    atomic_write_bytes(
        out_dir / "stability.json", json.dumps(json_ready(report), indent=1).encode()
    )
    return report


def _ticks(axis: Axis):
    if axis.ticks:
        return list(axis.ticks)
    return [f"{v:g}" if isinstance(v, (int, float)) else str(v) for v in axis.values]


def _plot(spec: MeasureMap, cells, path: Path):
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.figure import Figure

    nx, ny = len(spec.x.values), len(spec.y.values)
    fig = Figure(figsize=(13.0, 8.5), layout="constrained")
    axes = fig.subplots(2, 2)
    cmap = ListedColormap(STATUS_COLORS)
    snorm = BoundaryNorm(np.arange(len(STATUS) + 1) - 0.5, len(STATUS))
    for row, m in enumerate(METHODS):
        err = np.full((ny, nx), np.nan)
        stat = np.zeros((ny, nx))
        letters = {}
        for c in cells:
            if c["method"] != m:
                continue
            err[c["iy"], c["ix"]] = c["error_over_tol"]
            stat[c["iy"], c["ix"]] = STATUS.index(c["status"])
            letters[(c["iy"], c["ix"])] = "".join(FLAG_CODES[f] for f in c["flags"])
        ax_e, ax_s = axes[row]
        im = ax_e.pcolormesh(
            np.log10(np.clip(err, 1e-3, 1e3)), cmap="viridis", vmin=-3, vmax=3, shading="flat"
        )
        if np.any(np.isfinite(err)):
            ax_e.contour(
                np.arange(nx) + 0.5,
                np.arange(ny) + 0.5,
                np.log10(np.where(np.isfinite(err), err, 1e3)),
                levels=[0.0],
                colors="w",
                linewidths=1.5,
            )
        fig.colorbar(im, ax=ax_e, label="log10(error / tolerance), white line: = 1")
        ax_s.pcolormesh(stat, cmap=cmap, norm=snorm, shading="flat")
        for (iy, ix), s in letters.items():
            ax_s.text(ix + 0.5, iy + 0.5, s, ha="center", va="center", fontsize=7)
        name = "default (analyse)" if m == "default" else "seed's quartic"
        ax_e.set_title(f"{name}: error")
        ax_s.set_title(f"{name}: status (letters: what flagged)")
        for ax in (ax_e, ax_s):
            ax.set_xticks(np.arange(nx) + 0.5, _ticks(spec.x), fontsize=7, rotation=30)
            ax.set_yticks(np.arange(ny) + 0.5, _ticks(spec.y), fontsize=7)
            ax.set_xlabel(spec.x.label)
            ax.set_ylabel(spec.y.label)
    handles = [
        axes[0][1].plot([], [], "s", color=col, ms=10, label=s)[0]
        for s, col in zip(STATUS, STATUS_COLORS, strict=True)
    ]
    handles += [
        axes[0][1].plot([], [], " ", label=f"{code}: {name}")[0]
        for name, code in FLAG_CODES.items()
    ]
    fig.legend(handles=handles, loc="outside right upper", fontsize=8, title="status / flags")
    fig.suptitle(f"Stability map — {spec.title}\nregions: {spec.regions}", fontsize=10)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")


if __name__ == "__main__":
    import sys

    out = run(Path(sys.argv[1] if len(sys.argv) > 1 else "build/bench"))
    print(json.dumps({k: v["status_counts"] for k, v in out["maps"].items()}, indent=1))
