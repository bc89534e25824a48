"""Campaign throughput: serial, dask.distributed with 2 workers, and the batched path.

A CPU-bound batch: the eight synthetic Garland–Rogers-style sample records (with their
sidecars) copied ``COPIES`` times into a temporary folder, each analysed with the default
bootstrap (200 replicates) and no contact fit. In one run, interleaved: the serial
campaign, the same on a 2-worker ``LocalCluster`` (single-threaded worker processes; the
cluster, :func:`pipeline.campaigns.run.local_cluster`, is started before the clock and its
start-up time reported apart), and the batched path (:mod:`pipeline.campaigns.batch`).
Goal: dask speed-up ≥ 1.7× over serial with
2 workers. The serial and dask Datasets are also compared byte for byte once written.

The records' reports (:mod:`pipeline.notebook_report`), in the same run: the per-record
tasks with their contact fits (``fit=True``, bootstrap 200; the joint fit left out) run
serially without reports, with rendered reports, and with rendered reports but no HTML;
the CPU time of this process, per record, with reports less without is what a report costs
beyond the analysis it shows (goal ≤ :data:`REPORT_GOAL_S`), with less without HTML its
HTML. Against it, the old way on a subset (:data:`KERNEL_RECORDS` records): each report
executed in a kernel of its own (``record_report(kernel=True)``; CPU time of this process
and of the kernels, and wall time). The first report of a process pays imports and the
HTML exporter's set-up once: timed apart (``first_report_extra_s``). The same tasks on the
2 workers, with and without reports, give the wall time per record there.

The outcome table of :func:`pipeline.simulate.impact_outcomes` (``method="table"``): its
first use in a fresh process builds it (about a second) and caches it on disk; timed in
fresh processes with an empty and with a filled cache folder, and the two workers asking
for a new table at once count their builds (one: the other reads it from disk). The run
uses a cache folder of its own.

Writes ``campaign.json`` and ``campaign.png`` into ``out_dir``.
"""

from __future__ import annotations

import json
import os
import platform
import resource
import shutil
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

from pipeline._atomic import atomic_path, atomic_write_text
from pipeline.campaigns import campaign, plan, run_record, run_tasks
from pipeline.notebook_report import record_report

ROOT = Path(__file__).resolve().parents[1]
COPIES = 12
REPEATS = 3
TARGET = 1.7
#: records whose reports are rendered, and the subset executed one kernel each (the old way)
REPORT_RECORDS = 16
KERNEL_RECORDS = 3
#: goal: CPU time of a record's report beyond the analysis it shows [s]
REPORT_GOAL_S = 0.5
#: an outcome table's key (law, damping parameter, history, ζ_t, χ) and a scene sweep for it
TABLE_KEY = ("hunt_crossley", 0.3, "total", 0.0, 4.0)


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


def _cpu() -> float:
    """CPU time of this process and of its children that have ended [s]."""
    me, kids = (resource.getrusage(w) for w in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN))
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def machine() -> dict:
    """The versions and the machine a campaign benchmark ran on."""
    import dask
    import distributed

    return {
        "dask": dask.__version__,
        "distributed": distributed.__version__,
        "numpy": np.__version__,
        "python": platform.python_version(),
        "cpu_count": os.cpu_count(),
        "load_average_1min": os.getloadavg()[0],
    }


def _reports(files, tmp: Path, client) -> dict:
    """Per-record cost of the reports, rendered (serial and on the workers) and executed in
    a kernel each (module notes)."""
    opts = {"n_boot": 200, "seed": 0}
    ways = {
        "none": {},
        "rendered": {"reports": tmp / "rendered"},
        "rendered_no_html": {"reports": tmp / "no-html", "report_html": False},
    }
    tasks = {k: plan(files, fit=True, **opts, **kw) for k, kw in ways.items()}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        # one-time costs: the pulse tables of the fits, then the report's imports and set-up
        run_tasks(tasks["none"][:1], run_record)
        c0 = _cpu()
        run_tasks(tasks["none"][:1], run_record)
        c1 = _cpu()
        run_tasks(tasks["rendered"][:1], run_record)
        c2 = _cpu()
        cpu = {k: [] for k in ways}
        for _ in range(REPEATS):
            for k, ts in tasks.items():
                c = _cpu()
                results = run_tasks(ts, run_record)
                cpu[k].append((_cpu() - c) / len(ts))
                assert not any(r.report_error for r in results), "a report failed"
        wall_dask = {}
        for k in ("none", "rendered"):
            run_tasks(tasks[k][:2], run_record, scheduler=client)  # warm the workers
            t, _ = _timed(lambda k=k: run_tasks(tasks[k], run_record, scheduler=client))
            wall_dask[k] = t / len(files)
        kernel_cpu, kernel_wall = [], []
        for f in files[:KERNEL_RECORDS]:
            c, t0 = _cpu(), time.perf_counter()
            record_report(f, tmp / "kernel", html=True, kernel=True, **opts)
            kernel_wall.append(time.perf_counter() - t0)
            kernel_cpu.append(_cpu() - c)
    best = {k: min(v) for k, v in cpu.items()}
    rendered = best["rendered"] - best["none"]
    old = float(np.median(kernel_cpu))
    return {
        "records": len(files),
        "analysis_and_fit_cpu_s_per_record": best["none"],
        "rendered_cpu_s_per_record": rendered,
        "rendered_html_cpu_s_per_record": best["rendered"] - best["rendered_no_html"],
        "first_report_extra_s": (c2 - c1) - (c1 - c0) - rendered,
        "goal_s": REPORT_GOAL_S,
        "meets_goal": bool(rendered <= REPORT_GOAL_S),
        "kernel_records": len(kernel_cpu),
        "kernel_cpu_s_per_record": old,
        "kernel_cpu_s_per_record_beyond_analysis": old - best["none"],
        "kernel_wall_s_per_record": float(np.median(kernel_wall)),
        "speedup_cpu": old / best["rendered"],
        "dask_2_workers_wall_s_per_record": wall_dask,
        "all_cpu_s_per_record": cpu,
        "kernel_cpu_s": kernel_cpu,
        "kernel_wall_s": kernel_wall,
    }


_TABLE_PROBE = """
import json, sys, time
from pipeline.simulate.table import outcome_table
t0 = time.perf_counter()
table = outcome_table(*json.loads(sys.argv[1]))
print(json.dumps({"s": time.perf_counter() - t0, "built": table.build_seconds > 0}))
"""


def _outcome_table(client) -> dict:
    """The outcome table's first use in fresh processes, with an empty and a filled cache
    folder, and two workers asking for a new one at once (module notes)."""
    from pipeline.simulate.table import outcome_table

    def fresh(key):
        out = subprocess.run(
            [sys.executable, "-c", _TABLE_PROBE, json.dumps(key)],
            capture_output=True,
            text=True,
            check=True,
        )
        return json.loads(out.stdout)

    cold, warm = fresh(TABLE_KEY), fresh(TABLE_KEY)
    other = (*TABLE_KEY[:-1], TABLE_KEY[-1] + 1.0)  # a key no process has built

    def on_worker():
        return outcome_table(*other).build_seconds > 0

    built = client.run(on_worker)
    return {
        "key": list(TABLE_KEY),
        "fresh_process_empty_cache_s": cold["s"],
        "fresh_process_empty_cache_built": cold["built"],
        "fresh_process_filled_cache_s": warm["s"],
        "fresh_process_filled_cache_built": warm["built"],
        "workers_asking_at_once": len(built),
        "workers_that_built": int(sum(built.values())),
    }


def run(out_dir: Path) -> dict:
    from distributed import Client

    from pipeline.campaigns.run import local_cluster

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    old_cache = os.environ.get("PIPELINE_CACHE")
    with tempfile.TemporaryDirectory() as tmp:
        # a cache folder of this run's own, inherited by the workers and the probes
        os.environ["PIPELINE_CACHE"] = str(Path(tmp) / "cache")
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
            files = sorted(folder.glob("*.csv"))[:REPORT_RECORDS]
            reports = _reports(files, Path(tmp), client)
            table = _outcome_table(client)
        finally:
            client.close()
            cluster.close()
            if old_cache is None:
                os.environ.pop("PIPELINE_CACHE", None)
            else:
                os.environ["PIPELINE_CACHE"] = old_cache
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
        "reports": reports,
        "outcome_table": table,
        **machine(),
    }
    atomic_write_text(out_dir / "campaign.json", json.dumps(result, indent=2) + "\n")
    _plot(result, out_dir / "campaign.png")
    return result


def _plot(result: dict, path: Path) -> None:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10.4, 3.6), layout="constrained")
    ax, bx = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1, 1.2]})
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
    r = result["reports"]
    bars = {
        "kernel per record\n(CPU, all of it)": r["kernel_cpu_s_per_record"],
        "kernel per record\n(wall)": r["kernel_wall_s_per_record"],
        "rendered\n(CPU beyond analysis)": r["rendered_cpu_s_per_record"],
        "of which HTML": r["rendered_html_cpu_s_per_record"],
    }
    bx.bar(list(bars), list(bars.values()), color=["0.6", "0.8", "tab:blue", "tab:cyan"])
    bx.axhline(r["goal_s"], color="tab:red", ls="--", lw=1, label=f"goal {r['goal_s']:g} s")
    bx.set_yscale("log")
    bx.set_ylabel("seconds per record's report")
    bx.tick_params(axis="x", labelsize=7)
    bx.set_title(
        f"reports: rendered {r['rendered_cpu_s_per_record']:.2f} s against a kernel each "
        f"{r['kernel_cpu_s_per_record']:.1f} s (CPU, ×{r['speedup_cpu']:.0f})",
        fontsize=9,
    )
    bx.legend(loc="upper right", fontsize=8)
    t = result["outcome_table"]
    fig.supxlabel(
        f"outcome table (impact_outcomes method='table'): first use in a fresh process "
        f"{t['fresh_process_empty_cache_s']:.2f} s (built, cached on disk), with the cache "
        f"{t['fresh_process_filled_cache_s'] * 1e3:.0f} ms; {t['workers_asking_at_once']} "
        f"workers asking at once built it {t['workers_that_built']}×",
        fontsize=8,
    )
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=120, format="png")


if __name__ == "__main__":
    print(json.dumps(run(Path("build/bench")), indent=2))
