"""``pipeline reproduce``: the main job (the seed's figures and verdict on the samples)."""

from __future__ import annotations

import time
from pathlib import Path


def register(sub) -> None:
    p = sub.add_parser("reproduce", help="the seed's figures and verdict on the samples")
    p.add_argument("--samples", default="data_samples", type=Path)
    p.add_argument("--out", default="build/reproduce", type=Path)
    p.add_argument("--boot", default=200, type=int, help="bootstrap replicates")
    p.add_argument("--seed", default=0, type=int)
    p.set_defaults(func=run)


def run(args) -> int:
    from ..report import reproduce

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
