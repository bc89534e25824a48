"""Command line: ``pipeline reproduce`` (the main job) and ``pipeline analyse FILE``.

``python -m pipeline.cli reproduce --samples data_samples --out build/reproduce`` is what
``make reproduce`` runs.
"""

from __future__ import annotations

import argparse
import json
import logging
import sys
import time
import warnings
from pathlib import Path

from .errors import InputError


def _reproduce(args) -> int:
    from .report import reproduce

    t0 = time.perf_counter()
    summary = reproduce(args.samples, args.out, n_boot=args.boot, seed=args.seed)
    n_ok = sum("error" not in r for r in summary["records"])
    print(
        f"{n_ok}/{len(summary['records'])} records processed in "
        f"{time.perf_counter() - t0:.1f} s → {args.out}/"
    )
    for key, ok in summary["findings"].items():
        if key != "text":
            print(f"  {key}: {'holds' if ok else 'does not hold'}")
    return 0


def _analyse(args) -> int:
    from . import analyse
    from .io import load
    from .report import scene_from_sidecar
    from .scene import Scene

    if args.scene:
        scene = Scene.from_dict(json.loads(Path(args.scene).read_text(encoding="utf-8")))
    else:
        scene = scene_from_sidecar(args.file)
        if scene is None:
            raise InputError(
                "no scene: give --scene scene.json (Scene fields in SI units) "
                "or put a sidecar <record>.json with a 'scene' beside the file",
                path=args.file,
            )
    # the library's warnings (poor fits, fallbacks) reach the user as log lines naming the
    # problem, not as Python warnings pointing into the library's source
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        a = analyse(load(args.file), scene, n_boot=args.boot, seed=args.seed)
    for w in caught:
        logging.getLogger("pipeline").warning("%s: %s", w.category.__name__, w.message)
    print(json.dumps(a.summary(), indent=1, allow_nan=False))  # strict JSON already
    return 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="pipeline", description=__doc__.splitlines()[0])
    parser.add_argument("-v", "--verbose", action="store_true", help="log the warnings too")
    sub = parser.add_subparsers(dest="command", required=True)
    rp = sub.add_parser("reproduce", help="the seed's figures and verdict on the samples")
    rp.add_argument("--samples", default="data_samples", type=Path)
    rp.add_argument("--out", default="build/reproduce", type=Path)
    rp.add_argument("--boot", default=200, type=int, help="bootstrap replicates")
    rp.add_argument("--seed", default=0, type=int)
    rp.set_defaults(func=_reproduce)
    an = sub.add_parser("analyse", help="analyse one record; prints the JSON summary")
    an.add_argument("file", type=Path)
    an.add_argument("--scene", type=Path, help="JSON file of Scene fields (SI units)")
    an.add_argument("--boot", default=200, type=int)
    an.add_argument("--seed", default=0, type=int)
    an.set_defaults(func=_analyse)
    args = parser.parse_args(argv)
    logging.basicConfig(
        level=logging.INFO if args.verbose else logging.WARNING,
        format="%(levelname)s %(name)s: %(message)s",
    )
    try:
        return args.func(args)
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
