"""``pipeline analyse FILE``: one record's analysis, readable by default, JSON with ``--json``."""

from __future__ import annotations

import json
from pathlib import Path

from ._common import EXIT_CODES, add_record_options, log_warnings, read_record, read_scene
from ._options import nonneg_int


def register(sub) -> None:
    p = sub.add_parser(
        "analyse",
        help="analyse one record; prints a readable summary (--json: the JSON summary)",
        description="Analyse one record against Routh's rigid model and print what it found: "
        "regime, measured e_n, e_t, ω and rebound angle beside the rigid prediction, μ, the "
        "deviation score with bootstrap uncertainties, and where each scene value came from. "
        "The record is read as pipeline.io.load reads it (units, axes, the sidecar's 'load' "
        "block); the scene comes from --scene, else the sidecar, with fields neither gives "
        "taken from the record's metadata where it states them with units.",
        epilog=EXIT_CODES,
    )
    p.add_argument("file", type=Path, help="the record file")
    p.add_argument("--scene", type=Path, help="JSON file of Scene fields (SI units), or a sidecar")
    p.add_argument("--json", action="store_true", help="print the strict-JSON summary instead")
    p.add_argument(
        "--out",
        type=Path,
        help="also write summary.json, summary.txt and the record's figures (seed Figs. 8, 9) "
        "into this folder",
    )
    p.add_argument("--boot", default=200, type=nonneg_int, help="bootstrap replicates [200]")
    p.add_argument("--seed", default=0, type=nonneg_int, help="bootstrap seed [0]")
    p.add_argument(
        "--degree", default=4, type=nonneg_int, help="degree of the polynomial fits [4: quartic]"
    )
    p.add_argument(
        "--source",
        default="auto",
        choices=("auto", "simpson", "trapezoid", "fit"),
        help="which percussions are scored: the samples (Simpson, trapezoid) or the fit",
    )
    add_record_options(p)
    p.add_argument("--mu", type=_how, default="scene", help=_HOW_HELP.format("μ"))
    p.add_argument("--e", type=_how, default="scene", help=_HOW_HELP.format("e"))
    p.set_defaults(func=run)


_HOW_HELP = (
    "{} of the rigid prediction: a number, 'fit' (fitted to the record), 'record' "
    "(estimated from it) or 'scene' (default; from the record's fit when the scene lacks it)"
)


def _how(text):
    """A number, or one of 'scene', 'fit', 'record'."""
    import argparse

    if text in ("scene", "fit", "record"):
        return text
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{text!r} is neither a number nor one of scene, fit, record"
        ) from None


def run(args) -> int:
    from ..advice import advice_for
    from ..analysis import analyse
    from ..sidecar import sensor_from_sidecar

    record = read_record(args.file, args)
    scene, sources = read_scene(args.file, args.scene, record)
    sensor = sensor_from_sidecar(args.file)  # a calibrated rig's, for the fits
    with log_warnings():
        a = analyse(
            record,
            scene,
            n_boot=args.boot,
            seed=args.seed,
            degree=args.degree,
            source=args.source,
            mu=args.mu,
            e=args.e,
            fit_options={"sensor": sensor} if sensor else None,
        )
    advice = advice_for(a.rigid_scene)
    out = {
        **a.summary(),
        "scene_sources": sources,
        "advice": None if advice is None else advice.summary(),
    }
    text = _readable(a, sources, a.plausibility, advice)
    if args.out is not None:
        _write(args.out, a, out, text)
    print(json.dumps(out, indent=1, allow_nan=False) if args.json else text)
    return 0


def _readable(a, sources: dict, checks, advice=None) -> str:
    """:meth:`pipeline.analysis.Analysis.describe`, where the scene's values came from, the
    plausibility checks, and the cheapest model accurate enough for the scene."""
    lines = [a.describe()]
    sel = a.model_selection
    if sel is not None and sel.averaged is not None:  # μ or e came from a contact fit
        from ..precision import as_text

        lines += ["", "the contact fit that gave them:", as_text(sel.averaged.table())]
    lines += ["", "scene values and where they came from:"]
    for name, value in a.scene.to_dict().items():
        unit, scale = _SCENE_UNITS.get(name, ("", 1.0))
        shown = "∞" if value == float("inf") else f"{value * scale:.6g} {unit}".strip()
        lines.append(f"  {name:14s} {shown:<14s} {sources.get(name, 'default')}")
    status = {k: v.get("status") for k, v in checks.summary().items() if isinstance(v, dict)}
    if status:
        lines += ["", "plausibility: " + ", ".join(f"{k} {v}" for k, v in status.items())]
    if advice is not None:
        lines += ["", f"model needed (tol {advice.tol:g}): {advice.model} — {advice.reason}"]
    return "\n".join(lines)


#: The unit each scene field (SI) reads in on the summary, and the factor from SI to it;
#: the others are plain numbers.
_SCENE_UNITS = {
    "radius": ("mm", 1e3),
    "speed": ("m/s", 1.0),
    "density": ("kg/m³", 1.0),
    "mass": ("g", 1e3),
    "E": ("GPa", 1e-9),
    "target_E": ("GPa", 1e-9),
    "target_radius": ("mm", 1e3),
    "target_mass": ("kg", 1.0),
    "angle_deg": ("°", 1.0),
    "spin": ("rad/s", 1.0),
    "surface_speed": ("m/s", 1.0),
    "yield_strength": ("MPa", 1e-6),
    "target_yield_strength": ("MPa", 1e-6),
}


def _write(out: Path, a, summary: dict, text: str) -> None:
    """The files of ``--out``, put in place together (the previous ones stay on a fault)."""
    from .. import figures
    from .._atomic import atomic_files, atomic_write_text

    with atomic_files(out):
        summary = json.dumps(summary, indent=1, allow_nan=False) + "\n"
        atomic_write_text(out / "summary.json", summary)
        atomic_write_text(out / "summary.txt", text + "\n")
        figures.save(figures.fig8_forces(a), out / "fig8_forces.png")
        figures.save(figures.fig9_percussion_plane(a), out / "fig9_percussion_plane.png")
