"""Run a command beside CPU-burning processes: ``python scripts/loaded.py CMD ARGS...``.

``make test-loaded`` (and CI) runs the test suite this way, one busy-looping process per
core beside it (``BURNERS`` overrides the count), so a test that assumes the machine is
fast or idle — a wall-clock limit, a sleep standing in for "the other process has got
there by now" — fails here first, not on a shared CI machine one day in ten. The exit
status is the command's.
"""

from __future__ import annotations

import multiprocessing
import os
import subprocess
import sys


def _burn() -> None:
    x = 0
    while True:
        x = (x * 1103515245 + 12345) & 0xFFFFFFFF


def main(argv: list[str]) -> int:
    if not argv:
        print(__doc__, file=sys.stderr)
        return 2
    n = int(os.environ.get("BURNERS", os.cpu_count() or 2))
    burners = [multiprocessing.Process(target=_burn, daemon=True) for _ in range(n)]
    for p in burners:
        p.start()
    print(f"running beside {n} CPU-burning process(es): {' '.join(argv)}", flush=True)
    try:
        return subprocess.call(argv)
    finally:
        for p in burners:
            p.kill()
            p.join()


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
