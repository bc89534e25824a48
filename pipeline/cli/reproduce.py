"""``pipeline reproduce``: the main job (the seed's figures and verdict on the samples)."""

from __future__ import annotations

import time
from pathlib import Path

from ._common import EXIT_CODES, EXIT_FAILED_RECORDS, EXIT_OK


def register(sub) -> None:
    p = sub.add_parser(
        "reproduce",
        help="the seed's figures and verdict on the samples",
        description="Analyse every sample, draw the seed's figures for the main record and "
        "write summary.json and report.md. A record that fails is listed with its reason "
        "and the others go on; the output folder is replaced in one rename, so it holds "
        "the previous run or this one, never a mix.",
        epilog=EXIT_CODES,
    )
    p.add_argument("--samples", default="data_samples", type=Path)
    p.add_argument("--out", default="build/reproduce", type=Path)
    p.add_argument("--boot", default=200, type=int, help="bootstrap replicates")
    p.add_argument("--seed", default=0, type=int)
    p.set_defaults(func=run)


def run(args) -> int:
    from ..report import reproduce

    t0 = time.perf_counter()
    summary = reproduce(args.samples, args.out, n_boot=args.boot, seed=args.seed)
    n = summary["n_records"]
    print(
        f"{n - summary['n_failed']}/{n} records processed in "
        f"{time.perf_counter() - t0:.1f} s → {args.out}/"
    )
    for key, ok in (summary["findings"] or {}).items():
        if key != "text":
            print(f"  {key}: {'holds' if ok else 'does not hold'}")
    for name, error in summary["failures"].items():
        print(f"  failed: {name}: {error}")
    return EXIT_OK if not summary["failures"] else EXIT_FAILED_RECORDS
