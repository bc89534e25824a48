"""Killed runs: ``pipeline reproduce`` killed (SIGKILL) at random moments never leaves a
folder that mixes two runs, and the next run removes what a killed one left.

After each kill the output folder must be one complete run: exactly the files its
``manifest.json`` lists, each with the SHA-256 listed (pipeline._atomic.atomic_dir swaps
the staging folder in with one rename). A small samples folder (the main record and one
digitised export) and no bootstrap keep one run near 2 s; two runs go on at once, each
with its own output folder. ``PIPELINE_KILLS`` sets the number of kills: CI (``.ci/run``)
makes 60; a local ``make test`` 12, about 15 s (``CI`` set: 50).
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


def _worker(tmp: Path, k: int, n: int, seed: int) -> dict:
    out = tmp / f"out{k}"
    env = dict(os.environ, MPLBACKEND="Agg", MPLCONFIGDIR=str(tmp / f"mpl{k}"))
    env["OPENBLAS_NUM_THREADS"] = "1"
    cmd = [sys.executable, "-m", "pipeline.cli", "reproduce", "--samples", str(tmp / "samples")]
    cmd += ["--out", str(out), "--boot", "0"]
    t0 = time.perf_counter()
    subprocess.run(cmd, env=env, check=True, capture_output=True)
    full = time.perf_counter() - t0
    runs = {_complete(out)}
    rng = random.Random(seed)
    staged = 0
    for _ in range(n):
        proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(rng.uniform(0.0, 1.1 * full))
        proc.send_signal(signal.SIGKILL)
        proc.wait()
        runs.add(_complete(out))  # the old run or the new one, each whole
        staged += any(f"staging-{proc.pid}-" in name for name in _debris(tmp, out))
    subprocess.run(cmd, env=env, check=True, capture_output=True)
    return {"out": out, "runs": runs, "staged": staged, "last": _complete(out), "full": full}


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
        # the next complete run removed every staging folder the killed ones left
        assert _debris(tmp_path, r["out"]) == []
    print(
        f"\n{2 * n} kills; {sum(r['staged'] for r in results)} while a run was writing; "
        f"{sum(len(r['runs']) - 1 for r in results)} runs finished before their kill; "
        f"one run {min(r['full'] for r in results):.2f} s"
    )
    # some kills landed while a run was writing (its staging folder was left): the moments
    # covered the dangerous part of the run, not only the imports
    assert sum(r["staged"] for r in results) > 0
    assert sum(len(r["runs"]) for r in results) > 2  # some killed runs had finished
