"""``pipeline analyse FILE``: one record's summary."""

from __future__ import annotations

import json
from pathlib import Path

from ._common import EXIT_CODES, add_record_options, log_warnings, read_record, read_scene


def register(sub) -> None:
    p = sub.add_parser(
        "analyse",
        help="analyse one record; prints the JSON summary",
        description="Analyse one record against Routh's rigid model and print the JSON "
        "summary. The record is read as pipeline.io.load reads it (units, axes, the "
        "sidecar's 'load' block); the scene comes from --scene, else the sidecar, with "
        "fields neither gives taken from the record's metadata where it states them with "
        "units.",
        epilog=EXIT_CODES,
    )
    p.add_argument("file", type=Path)
    p.add_argument("--scene", type=Path, help="JSON file of Scene fields (SI units), or a sidecar")
    p.add_argument("--boot", default=200, type=int, help="bootstrap replicates")
    p.add_argument("--seed", default=0, type=int)
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
    from ..report import check_and_analyse, read_sidecar

    record = read_record(args.file, args)
    scene, sources = read_scene(args.file, args.scene, record)
    sensor = read_sidecar(args.file).get("sensor")  # a calibrated rig's, for the fits
    with log_warnings():
        a, checks = check_and_analyse(
            record,
            scene,
            n_boot=args.boot,
            seed=args.seed,
            mu=args.mu,
            e=args.e,
            fit_options={"sensor": sensor} if sensor else None,
        )
    out = {**a.summary(), "scene_sources": sources, "plausibility": checks.summary()}
    print(json.dumps(out, indent=1, allow_nan=False))  # strict JSON already
    return 0
