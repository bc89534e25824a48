"""Peak memory and time of ``load`` and ``pipeline analyse`` against the size of the file.

Files: long sensor CSVs (written by :func:`pipeline.io.write_sensor`) of one elastic Hertz
impact (a 25.4 mm steel ball at 0.5 m/s, F_max ≈ 1.1 kN) in the middle of a 2 MHz record
with offset, drift and 2 N white noise — a trigger-less acquisition. Sizes ``ROWS``
(default 0.25 M, 1 M and 2 M rows, about 17 to 140 MB); ``PIPELINE_BENCH_ROWS=20000000``
adds the issue's 20 M-row file (~1.4 GB). The files are made once under
``build/bench_data/`` (kept between runs; free disk space is checked first).

Each measurement runs in a fresh interpreter and reports its own peak RSS (``VmHWM`` of
``/proc/self/status``; ``ru_maxrss`` would include the forking parent's): plain
``pandas.read_csv``, ``pipeline.io.load`` (the whole record in memory), and
``pipeline analyse FILE --scene ...`` (the command line, which streams a file over 64 MiB
and keeps only the contact: :func:`pipeline.io.load_contact`).
The interpreter with the package imported is measured too, so the figures show what the
data cost. Target (issue 11): peak RSS of ``analyse`` ≤ 1.2 × the file size on the largest
file. Writes ``memory.json`` and ``memory.png``.
"""

from __future__ import annotations

import json
import os
import platform
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

from pipeline._atomic import atomic_path, atomic_write_text

ROWS = [250_000, 1_000_000, 2_000_000]
TARGET = 1.2
DATA = Path("build/bench_data")
VERSION = 1  # of the generator: a change makes new files

SCENE = {
    "radius": 0.0127, "density": 7850.0, "E": 210e9, "nu": 0.3, "target_E": 210e9,
    "target_nu": 0.3, "speed": 0.5, "angle_deg": 15.0, "mu": 0.12, "e": 1.0,
}  # fmt: skip

_PROBE = r"""
import json, resource, sys, time
t0 = time.perf_counter()
what, path = sys.argv[1], sys.argv[2]
if what == "imports":
    import pipeline, pipeline.io, pandas
elif what == "pandas":
    import pandas
    pandas.read_csv(path, comment="#")
elif what == "load":
    from pipeline.io import load
    load(path)
elif what == "analyse":
    import contextlib, io
    from pipeline.cli import main
    with contextlib.redirect_stdout(io.StringIO()):
        code = main(["analyse", path, "--scene", sys.argv[3], "--boot", "0"])
    assert code == 0, code
seconds = time.perf_counter() - t0
try:  # this process's own high-water mark (ru_maxrss would count the forking parent's)
    with open("/proc/self/status") as fh:
        peak = next(int(l.split()[1]) * 1024 for l in fh if l.startswith("VmHWM:"))
except (OSError, StopIteration):
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
print(json.dumps({"seconds": seconds, "peak_rss": peak}))
"""


def make_file(rows: int) -> Path:
    """The benchmark file of ``rows`` rows (made once; see the module notes)."""
    from pipeline import Scene
    from pipeline.contact import hertz_impact, hertz_pulse
    from pipeline.io import write_sensor
    from pipeline.record import make_record

    path = DATA / f"impact_{rows}_v{VERSION}.csv"
    if path.exists():
        return path
    DATA.mkdir(parents=True, exist_ok=True)
    need = 60 * rows  # bytes, with room
    free = shutil.disk_usage(DATA).free
    if free < 3 * need:
        raise RuntimeError(f"{free / 1e9:.1f} GB free under {DATA}: too little for {rows} rows")
    impact = hertz_impact(Scene(**SCENE))
    rng = np.random.default_rng(rows)
    parts = []
    step = 2_000_000
    for a in range(0, rows, step):  # in parts: the generator's memory stays bounded too
        k = np.arange(a, min(a + step, rows))
        t = k * 5e-7
        F = hertz_pulse(t - (rows // 2) * 5e-7 - 1e-7, impact)["F"]
        rec = make_record(
            t,
            {
                "Fn": F + 4.0 + 0.5 * t + rng.normal(0, 2.0, k.size),
                "Ft": 0.1 * F - 3.0 + rng.normal(0, 2.0, k.size),
                "Fy": rng.normal(0, 2.0, k.size),
            },
            attrs={"source": "bench", "format": "bench", "kind": "sensor"},
        )
        part = DATA / f".part{a}.csv"
        write_sensor(rec, part, metadata={"sample rate": "2 MHz"} if a == 0 else None)
        parts.append(part)
    with atomic_path(path) as tmp, open(tmp, "wb") as out:
        for i, part in enumerate(parts):
            with open(part, "rb") as fh:
                if i:  # later parts: their data rows only
                    for line in fh:
                        if line.startswith(b"time [s]"):
                            break
                shutil.copyfileobj(fh, out, 1 << 20)
            part.unlink()
    return path


def _probe(what: str, path: Path, scene: Path) -> dict:
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", MPLBACKEND="Agg")
    out = subprocess.run(
        [sys.executable, "-c", _PROBE, what, str(path), str(scene)],
        env=env, check=True, capture_output=True, text=True,
    )  # fmt: skip
    return json.loads(out.stdout.strip().splitlines()[-1])


def run(out_dir: Path) -> dict:
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    rows = list(ROWS)
    extra = int(os.environ.get("PIPELINE_BENCH_ROWS", "0") or 0)
    if extra and extra not in rows:
        rows.append(extra)
    scene = DATA / "scene.json"
    DATA.mkdir(parents=True, exist_ok=True)
    atomic_write_text(scene, json.dumps(SCENE))
    results = []
    for n in rows:
        path = make_file(n)
        size = path.stat().st_size
        entry = {"rows": n, "file_bytes": size}
        for what in ("imports", "pandas", "load", "analyse"):
            entry[what] = _probe(what, path, scene)
        entry["analyse_rss_over_file"] = entry["analyse"]["peak_rss"] / size
        entry["load_rss_over_file"] = entry["load"]["peak_rss"] / size
        results.append(entry)
    largest = results[-1]
    result = {
        "files": results,
        "target_analyse_rss_over_file": TARGET,
        "largest_rows": largest["rows"],
        "meets_target": bool(largest["analyse_rss_over_file"] <= TARGET),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "cpu_count": os.cpu_count(),
    }
    atomic_write_text(out_dir / "memory.json", json.dumps(result, indent=2) + "\n")
    _plot(result, out_dir / "memory.png")
    return result


def _plot(result: dict, path: Path) -> None:
    from matplotlib.figure import Figure

    files = result["files"]
    mb = np.array([f["file_bytes"] for f in files]) / 1e6
    fig = Figure(figsize=(9, 3.4), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    for what, style in (("imports", ":"), ("pandas", "--"), ("load", "-"), ("analyse", "-")):
        rss = np.array([f[what]["peak_rss"] for f in files]) / 1e6
        sec = np.array([f[what]["seconds"] for f in files])
        label = {"imports": "interpreter + imports", "pandas": "pandas.read_csv",
                 "load": "pipeline.io.load", "analyse": "pipeline analyse"}[what]  # fmt: skip
        ax1.plot(mb, rss, style, marker="o", label=label)
        ax2.plot(mb, sec, style, marker="o", label=label)
    ax1.plot(mb, TARGET * mb, color="tab:red", lw=0.8, label=f"{TARGET} × file size")
    ax1.set(xlabel="file size [MB]", ylabel="peak RSS [MB]", xscale="log", yscale="log")
    ax2.set(xlabel="file size [MB]", ylabel="wall time [s]", xscale="log", yscale="log")
    ax1.legend(fontsize=7)
    ax1.set_title("memory", fontsize=9)
    ax2.set_title("time", fontsize=9)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=120, format="png")


if __name__ == "__main__":
    print(json.dumps(run(Path("build/bench")), indent=2))
