"""Run every benchmark: ``python -m benchmarks --out build/bench [name ...]``."""

from __future__ import annotations

import argparse
import importlib
import inspect
import pkgutil
from pathlib import Path

import benchmarks


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m benchmarks")
    parser.add_argument("--out", default="build/bench", type=Path)
    parser.add_argument("names", nargs="*", help="benchmark names (bench_<name>.py); all if none")
    parser.add_argument(
        "--replicates",
        type=int,
        help="replicates per case, for the benchmarks that take them (misspec)",
    )
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    found = sorted(
        m.name for m in pkgutil.iter_modules(benchmarks.__path__) if m.name.startswith("bench_")
    )
    wanted = [n if n.startswith("bench_") else f"bench_{n}" for n in args.names] or found
    for name in wanted:
        module = importlib.import_module(f"benchmarks.{name}")
        print(f"[bench] {name} ...", flush=True)
        kw = {}
        if args.replicates is not None and "replicates" in inspect.signature(module.run).parameters:
            kw["replicates"] = args.replicates
        module.run(args.out, **kw)
        print(f"[bench] {name} done -> {args.out}", flush=True)


if __name__ == "__main__":
    main()
