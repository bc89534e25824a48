"""Killed runs: ``pipeline reproduce`` killed (SIGKILL) mid-run never leaves a folder that
mixes two runs, and the next run removes what a killed one left.

After each kill the output folder must be one complete run: exactly the files its
``manifest.json`` lists, each with the SHA-256 listed (pipeline._atomic.atomic_dir swaps
the staging folder in with one rename).

The kills land where the test chooses, not where the machine's speed puts them: each run is
started under ``tests/_killpoint.py``, which numbers the run's operations on its own output
(the staging folder made, each file written into it, the rename that swaps it in, the
removal of the previous run) and stops just before the chosen one; the test then kills it.
A reference run lists the operations, so the test knows for each kill which run the folder
must hold afterwards — the previous one up to the swap, the new one after it — and that a
staging folder is left behind by every kill after the first operation. A stop point past
the last operation lets a run finish. A few kills at random instants (which may land during
the imports) check the same invariant without assuming where they land.

A small samples folder (the main record and one digitised export) and no bootstrap keep a
run near 2 s; two workers go on at once, each with its own output folder.
``PIPELINE_KILLS`` sets the number of kills: a local ``make test`` 12, CI (``CI`` set) 50.
"""

from __future__ import annotations

import hashlib
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

SAMPLES = Path(__file__).resolve().parents[1] / "data_samples"
DRIVER = Path(__file__).resolve().parent / "_killpoint.py"
KILLS = int(os.environ.get("PIPELINE_KILLS", "50" if os.environ.get("CI") else "12"))

pytestmark = [
    pytest.mark.skipif(not hasattr(signal, "SIGKILL"), reason="needs SIGKILL"),
    pytest.mark.slow,
]


def _complete(out: Path) -> str:
    """The run id of the complete run in ``out``; AssertionError for anything else."""
    manifest = json.loads((out / "manifest.json").read_text(encoding="utf-8"))
    present = sorted(p.name for p in out.iterdir() if p.name != "manifest.json")
    assert present == sorted(manifest["files"]), (present, sorted(manifest["files"]))
    for name, entry in manifest["files"].items():
        assert hashlib.sha256((out / name).read_bytes()).hexdigest() == entry["sha256"], name
    return manifest["run_id"]


def _debris(parent: Path, out: Path) -> list[str]:
    return sorted(p.name for p in parent.iterdir() if p.name.startswith(f".{out.name}."))


class _Runner:
    """Starts ``pipeline reproduce`` runs into one output folder under the kill driver."""

    def __init__(self, tmp: Path, k: int):
        self.out = tmp / f"out{k}"
        self.env = dict(os.environ, MPLBACKEND="Agg", MPLCONFIGDIR=str(tmp / f"mpl{k}"))
        self.env.update(OPENBLAS_NUM_THREADS="1", KILLPOINT_OUT=str(self.out))
        self.args = ["reproduce", "--samples", str(tmp / "samples"), "--out", str(self.out)]
        self.args += ["--boot", "0"]

    def start(self, stop_at: int):
        """A run that stops before operation ``stop_at`` (negative: never), and the read
        end of its report pipe."""
        r, w = os.pipe()
        env = dict(self.env, KILLPOINT_AT=str(stop_at), KILLPOINT_FD=str(w))
        proc = subprocess.Popen(
            [sys.executable, str(DRIVER), *self.args],
            env=env,
            pass_fds=(w,),
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
        )
        os.close(w)
        return proc, os.fdopen(r, "r", encoding="utf-8")

    def operations(self) -> list[tuple[str, list[str]]]:
        """Run to the end and return its operations (event, paths), in order."""
        proc, report = self.start(-1)
        with report:
            lines = report.read().splitlines()
        _, err = proc.communicate()
        assert proc.returncode == 0, err.decode(errors="replace")
        assert lines and lines[-1] == "done", lines[-3:]
        ops = []
        for line in lines[:-1]:
            tag, event, paths = line.split(" ", 2)
            assert tag == "op", line
            ops.append((event, paths.split("\t")))
        return ops

    def run_to(self, stop_at: int) -> bool:
        """Start a run, kill it just before operation ``stop_at``; True if it finished
        first (``stop_at`` past its last operation)."""
        proc, report = self.start(stop_at)
        with report:
            for line in report:  # "stop ..." once it stopped; "done" at its end
                if line.startswith(("stop ", "done")):
                    break
        if line.startswith("stop "):
            assert int(line.split()[1]) == stop_at, line
            proc.send_signal(signal.SIGKILL)
        _, err = proc.communicate()
        if line.startswith("stop "):
            assert proc.returncode == -signal.SIGKILL
            return False
        assert proc.returncode == 0, err.decode(errors="replace")
        return True

    def kill_at_random(self, delay: float) -> None:
        proc, report = self.start(-1)
        time.sleep(delay)
        proc.send_signal(signal.SIGKILL)
        proc.communicate()
        report.close()


def _swap_index(ops, out: Path) -> int:
    """Index of the rename that puts the staging folder in the output folder's place."""
    for i, (event, paths) in enumerate(ops):
        if event in ("os.rename", "os.replace") and len(paths) == 2 and paths[1] == str(out):
            return i
    raise AssertionError(f"no rename onto {out} among the run's operations: {ops}")


def _worker(tmp: Path, k: int, n: int, seed: int) -> dict:
    run = _Runner(tmp, k)
    parent = run.out.parent
    t0 = time.perf_counter()
    run.operations()  # the first run creates the folder (a plain rename)
    full = time.perf_counter() - t0
    # a run onto an existing folder: the operations every later run makes, in order
    ops = run.operations()
    swap = _swap_index(ops, run.out)
    assert ops[0][0] == "os.mkdir", ops[0]  # the staging folder comes first
    rng = random.Random(seed)
    # stop points: before anything is written, in the staging folder, the swap itself, just
    # after it (the previous run being removed), past the end; then chosen at random
    points = [0, 1, swap, swap + 1, len(ops) + 10]
    n_timed = max((n - len(points)) // 4, 0)
    points += [rng.randrange(len(ops) + 1) for _ in range(max(n - len(points) - n_timed, 0))]
    last = _complete(run.out)
    seen = {last}
    staged = finished = 0
    for i in points:
        done = run.run_to(i)
        now = _complete(run.out)  # whatever the kill, one whole run
        mine = [d for d in _debris(parent, run.out) if "staging-" in d]
        if done:
            assert now not in seen and not mine, (i, now, mine)
            finished += 1
        elif i <= swap:
            assert now == last, f"killed before the swap (op {i}), yet the folder changed"
            assert bool(mine) == (i > 0), (i, mine)  # the staging folder exists after op 0
        else:
            assert now not in seen, f"killed after the swap (op {i}), yet the old run is there"
            assert mine, f"killed while removing the previous run (op {i}): no folder left"
        staged += bool(mine)
        seen.add(now)
        last = now
    for _ in range(n_timed):  # anywhere at all, imports included: the invariant holds
        run.kill_at_random(rng.uniform(0.0, 1.1 * full))
        seen.add(_complete(run.out))
    assert run.run_to(-1)  # the next complete run removes every staging folder left
    return {
        "out": run.out,
        "staged": staged,
        "finished": finished,
        "runs": len(seen),
        "ops": len(ops),
        "last": _complete(run.out),
    }


def test_killed_runs_leave_one_whole_run_and_no_debris(tmp_path):
    samples = tmp_path / "samples"
    samples.mkdir()
    for name in ("gr_15deg_0.6ms", "wpd_datasets"):
        for p in SAMPLES.glob(f"{name}.*"):
            shutil.copy(p, samples / p.name)
    n = (KILLS + 1) // 2
    with ThreadPoolExecutor(2) as pool:
        results = list(pool.map(lambda k: _worker(tmp_path, k, n, 1000 + k), (0, 1)))
    for r in results:
        assert _debris(tmp_path, r["out"]) == []
        assert r["staged"] > 0 and r["finished"] > 0
    print(
        f"\n{2 * n} kills over {results[0]['ops']} operations per run; "
        f"{sum(r['staged'] for r in results)} left a staging folder; "
        f"{sum(r['finished'] for r in results)} runs finished before their kill"
    )


def test_driver_stops_where_asked(tmp_path):
    """The kill driver itself: a run stopped before an operation has made exactly the ones
    before it (its staging folder exists only once the first operation, its creation,
    happened)."""
    samples = tmp_path / "samples"
    samples.mkdir()
    for p in SAMPLES.glob("wpd_datasets.*"):
        shutil.copy(p, samples / p.name)
    run = _Runner(tmp_path, 0)
    assert not run.run_to(0)
    assert not run.out.exists() and _debris(tmp_path, run.out) == []
    assert not run.run_to(1)
    left = _debris(tmp_path, run.out)
    assert len(left) == 1 and "staging-" in left[0] and not run.out.exists()
