"""``pipeline analyse FILE``: one record's summary."""

from __future__ import annotations

import json
from pathlib import Path

from ._common import log_warnings, read_scene


def register(sub) -> None:
    p = sub.add_parser("analyse", help="analyse one record; prints the JSON summary")
    p.add_argument("file", type=Path)
    p.add_argument("--scene", type=Path, help="JSON file of Scene fields (SI units)")
    p.add_argument("--boot", default=200, type=int)
    p.add_argument("--seed", default=0, type=int)
    p.set_defaults(func=run)


def run(args) -> int:
    from .. import analyse
    from ..io import load

    scene = read_scene(args.file, args.scene)
    with log_warnings():
        a = analyse(load(args.file), scene, n_boot=args.boot, seed=args.seed)
    print(json.dumps(a.summary(), indent=1, allow_nan=False))  # strict JSON already
    return 0
