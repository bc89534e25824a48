"""Campaign throughput: serial, dask.distributed with 2 workers, and the batched path.

A CPU-bound batch: the eight synthetic Garland–Rogers-style sample records (with their
sidecars) copied ``COPIES`` times into a temporary folder, each analysed with the default
bootstrap (200 replicates) and no contact fit. In one run, interleaved: the serial
campaign, the same on a 2-worker ``LocalCluster`` (single-threaded worker processes; the
cluster, :func:`pipeline.campaigns.run.local_cluster`, is started before the clock and its
start-up time reported apart), and the batched path (:mod:`pipeline.campaigns.batch`).
Goal: dask speed-up ≥ 1.7× over serial with
2 workers. The serial and dask Datasets are also compared byte for byte once written.
Writes ``campaign.json`` and ``campaign.png`` into ``out_dir``.
"""

from __future__ import annotations

import json
import os
import platform
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np

from pipeline._atomic import atomic_path, atomic_write_text
from pipeline.campaigns import campaign

ROOT = Path(__file__).resolve().parents[1]
COPIES = 12
REPEATS = 3
TARGET = 1.7


def _folder(tmp: Path) -> Path:
    src = ROOT / "data_samples"
    for k in range(COPIES):
        for csv in sorted(src.glob("gr_*.csv")):
            shutil.copy(csv, tmp / f"c{k:02d}_{csv.name}")
            shutil.copy(csv.with_suffix(".json"), tmp / f"c{k:02d}_{csv.stem}.json")
    return tmp


def _timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def run(out_dir: Path) -> dict:
    import dask
    import distributed
    from distributed import Client

    from pipeline.campaigns.run import local_cluster

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        folder = _folder(Path(tmp))
        n = len(list(folder.glob("*.csv")))
        t_start, cluster = _timed(lambda: local_cluster(2))
        client = Client(cluster)
        try:
            campaign(folder, fit=False, scheduler=client)  # warm the workers' imports
            times = {"serial": [], "dask_2_workers": [], "batched": []}
            for _ in range(REPEATS):
                t, serial = _timed(lambda: campaign(folder, fit=False))
                times["serial"].append(t)
                t, parallel = _timed(lambda: campaign(folder, fit=False, scheduler=client))
                times["dask_2_workers"].append(t)
                t, _ = _timed(lambda: campaign(folder, fit=False, batched=True))
                times["batched"].append(t)
        finally:
            client.close()
            cluster.close()
        a, b = Path(tmp) / "serial.nc", Path(tmp) / "dask.nc"
        serial.to_netcdf(a, engine="h5netcdf")
        parallel.to_netcdf(b, engine="h5netcdf")
        identical = a.read_bytes() == b.read_bytes()
    best = {k: min(v) for k, v in times.items()}
    result = {
        "records": n,
        "n_boot": 200,
        "best_s": best,
        "all_s": times,
        "records_per_s": {k: n / v for k, v in best.items()},
        "ms_per_record": {k: 1e3 * v / n for k, v in best.items()},
        "dask_speedup": best["serial"] / best["dask_2_workers"],
        "batched_speedup": best["serial"] / best["batched"],
        "target_dask_speedup": TARGET,
        "meets_target": bool(best["serial"] / best["dask_2_workers"] >= TARGET),
        "dask_byte_identical_to_serial": bool(identical),
        "cluster_start_s": t_start,
        "dask": dask.__version__,
        "distributed": distributed.__version__,
        "numpy": np.__version__,
        "python": platform.python_version(),
        "cpu_count": os.cpu_count(),
        "load_average_1min": os.getloadavg()[0],
    }
    atomic_write_text(out_dir / "campaign.json", json.dumps(result, indent=2) + "\n")
    _plot(result, out_dir / "campaign.png")
    return result


def _plot(result: dict, path: Path) -> None:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(5.2, 3.2), layout="tight")
    ax = fig.subplots()
    names = list(result["records_per_s"])
    values = [result["records_per_s"][k] for k in names]
    ax.bar(names, values, color=["0.6", "tab:blue", "tab:green"])
    ax.axhline(TARGET * values[0], color="tab:red", ls="--", lw=1, label=f"goal {TARGET}× serial")
    ax.set_ylabel("records per second")
    ax.set_ylim(0, 1.15 * max(values + [TARGET * values[0]]))
    ax.set_title(
        f"{result['records']} records, bootstrap 200: dask ×{result['dask_speedup']:.2f}, "
        f"batched ×{result['batched_speedup']:.2f}",
        fontsize=9,
    )
    ax.legend(loc="upper left", fontsize=8)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=120, format="png")


if __name__ == "__main__":
    print(json.dumps(run(Path("build/bench")), indent=2))
