"""Speed of ``pipeline.io.load`` on a large sensor CSV against plain ``pandas.read_csv``.

A 1,000,000-row tri-axial sensor CSV (``# key: value`` metadata lines, header
``time [s],Fx [N],Fy [N],Fz [N]``, written by :func:`pipeline.io.write_sensor`) is read in the
same run by ``pandas.read_csv(path, comment="#")`` — the plain call a user would make — and by
``pipeline.io.load(path)`` (sniffing, SHA-256 of the raw bytes, unit conversion, every check
of the file, the xarray record). The file is streamed from disk to pandas' C parser (no
copy of its bytes in memory) while a thread hashes it. Best of 5 each, interleaved so that
machine load hits both alike. Target (issue 11): load ≤ 1.2 × pandas. Writes ``load.json``
and ``load.png`` into ``out_dir``.
"""

from __future__ import annotations

import json
import os
import platform
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

from pipeline import Scene
from pipeline._atomic import atomic_path, atomic_write_text
from pipeline.contact import hertz_impact, hertz_pulse
from pipeline.io import load, write_sensor
from pipeline.record import make_record

N_ROWS = 1_000_000
REPEATS = 5
TARGET = 1.2


def make_file(path: Path, n: int = N_ROWS, seed: int = 0) -> Path:
    """A tri-axial record at 1 MHz: an elastic Hertz pulse every 200 µs plus noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 1e-6
    scene = Scene(
        radius=0.0127, density=7850.0, E=210e9, nu=0.3, target_E=210e9, target_nu=0.3, speed=0.5
    )
    pulse = hertz_pulse(t % 2e-4, hertz_impact(scene))["F"]
    forces = {
        "Fn": pulse + rng.normal(0, 2.0, n),
        "Ft": 0.1 * pulse + rng.normal(0, 2.0, n),
        "Fy": rng.normal(0, 2.0, n),
    }
    rec = make_record(
        t, forces, attrs={"source": "bench", "format": "simulated", "kind": "simulated"}
    )
    return write_sensor(rec, path, metadata={"sample rate": "1 MHz", "rig": "benchmark"})


def _time(fn) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def run(out_dir: Path) -> dict:
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        path = make_file(Path(tmp) / "big_sensor.csv")
        size = path.stat().st_size
        check = load(path)  # warm the page cache, and check what is read
        assert check.sizes["time"] == N_ROWS
        t_pandas, t_load = [], []
        for _ in range(REPEATS):
            t_pandas.append(_time(lambda: pd.read_csv(path, comment="#")))
            t_load.append(_time(lambda: load(path)))
    best_pandas, best_load = min(t_pandas), min(t_load)
    ratio = best_load / best_pandas
    result = {
        "rows": N_ROWS,
        "file_bytes": size,
        "pandas_read_csv_s": best_pandas,
        "pipeline_load_s": best_load,
        "ratio": ratio,
        "target_ratio": TARGET,
        "meets_target": bool(ratio <= TARGET),
        "all_pandas_s": t_pandas,
        "all_load_s": t_load,
        "pandas": pd.__version__,
        "numpy": np.__version__,
        "engine": "pandas C parser (pyarrow not used)",
        "python": platform.python_version(),
        "cpu_count": os.cpu_count(),
    }
    atomic_write_text(out_dir / "load.json", json.dumps(result, indent=2) + "\n")
    _plot(result, out_dir / "load.png")
    return result


def _plot(result: dict, path: Path) -> None:
    from matplotlib.figure import Figure  # no pyplot: no global backend or figure state

    fig = Figure(figsize=(5, 3.2), layout="tight")
    ax = fig.subplots()
    names = ["pandas.read_csv", "pipeline.io.load"]
    values = [result["pandas_read_csv_s"], result["pipeline_load_s"]]
    ax.bar(names, values, color=["0.6", "tab:blue"])
    ax.axhline(TARGET * values[0], color="tab:red", ls="--", lw=1, label=f"target {TARGET}× pandas")
    ax.set_ylabel(f"best of {REPEATS} [s]")
    ax.set_title(f"{result['rows']:,} rows: load / pandas = {result['ratio']:.2f}")
    ax.legend(loc="upper left", fontsize=8)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=120, format="png")


if __name__ == "__main__":
    print(json.dumps(run(Path("build/bench")), indent=2))
