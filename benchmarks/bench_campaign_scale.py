"""A campaign at scale: 10 to 1,000 records with fits, the joint fit and reports.

Records: the eight bundled Garland–Rogers-style samples with their sidecars, copied (hard
links where the file system allows) into folders of N = 10, 30, 100, 300 and 1,000
records (record i is sample i mod 8). Each N is run as a user runs it —
``campaign(folder, fit=True, reports=...)``: every record analysed with the default
bootstrap (200), its contact fit with its default budget and verdict, its fit report
rendered (notebook and HTML), then the joint campaign fit — in a fresh process, serially
and on a 2-worker ``LocalCluster`` (single-threaded worker processes, started before the
clock: its start-up is reported apart). Per run: wall time, CPU time (this process, its
children and the workers), records per minute, the joint fit's own time, and the peak
resident memory of the process and of each worker (``ru_maxrss``). Cost against N on
log–log: the fitted slope (expect 1; target ≤ :data:`SLOPE_TARGET`). The serial and
distributed Datasets of one size are compared as written (netCDF bytes).

The outcome table of :func:`pipeline.simulate.impact_outcomes` and the fits' pulse tables
are built on their first use and cached on disk; the run uses a cache folder of its own,
filled by a warm-up campaign of a few records before the clock (what its first use costs
is measured by the ``campaign`` benchmark).

The peer, in the same run on :data:`PEER_RECORDS` records: the way a lab works today — a
loop of lmfit with :func:`scipy.integrate.solve_ivp` (``pipeline.simulate.impact``, rtol
1e-7) in the residual, lmfit's covariance as its intervals (no bootstrap: it would cost
200 ODE fits), and one notebook kernel per record executing the record's report
(``record_report(kernel=True)``); its per-record cost times N is drawn beside ours.

Targets (issue 16): the 1,000 records with fits, the joint fit and reports in ≤ 10 minutes
on 2 workers; peak memory flat in N; the Datasets identical. ``PIPELINE_BENCH_CAMPAIGN_MAX``
caps the largest N (default 1000); ``PIPELINE_BENCH_CAMPAIGN_SERIAL_MAX`` the largest N run
serially (default the same).

Writes ``campaign_scale.json`` and ``campaign_scale.png``.
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

from benchmarks.bench_campaign import _cpu, machine
from pipeline._atomic import atomic_path, atomic_write_text

ROOT = Path(__file__).resolve().parents[1]
SIZES = (10, 30, 100, 300, 1000)
#: records of the peer's loop (lmfit + solve_ivp and a kernel per report)
PEER_RECORDS = 3
#: the size whose serial and distributed Datasets are compared
COMPARE_SIZE = 30
TARGET_S = 600.0
SLOPE_TARGET = 1.1
N_BOOT = 200


def _folder(root: Path, n: int) -> Path:
    """``n`` records (copies of the samples and their sidecars) in a folder of their own."""
    src = sorted((ROOT / "data_samples").glob("gr_*.csv"))
    out = root / f"n{n}"
    out.mkdir(parents=True, exist_ok=True)
    for i in range(n):
        csv = src[i % len(src)]
        for a, b in (
            (csv, out / f"r{i:04d}_{csv.name}"),
            (csv.with_suffix(".json"), out / f"r{i:04d}_{csv.stem}.json"),
        ):
            try:
                os.link(a, b)
            except OSError:
                b.write_bytes(a.read_bytes())
    return out


def _worker_usage():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime, r.ru_maxrss / 1024.0


def _one(n: int, mode: str, folder: str, out: str, nc: str | None = None) -> dict:
    """Run in a fresh process: the campaign of ``folder`` (``mode`` "serial" or "dask"),
    timed (module notes)."""
    import pipeline.campaigns as campaigns

    joint_s = []
    with_joint = campaigns.with_joint_fit

    def timed_joint(*a, **kw):
        t = time.perf_counter()
        try:
            return with_joint(*a, **kw)
        finally:
            joint_s.append(time.perf_counter() - t)

    campaigns.with_joint_fit = timed_joint
    client = cluster = None
    t_cluster = 0.0
    kw = {"fit": True, "n_boot": N_BOOT, "seed": 0, "reports": Path(out) / "reports"}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if mode == "dask":
            from distributed import Client

            from pipeline.campaigns.run import local_cluster

            t = time.perf_counter()
            cluster = local_cluster(2)
            client = Client(cluster)
            t_cluster = time.perf_counter() - t
            kw["scheduler"] = client
        try:
            before = client.run(_worker_usage) if client else {}
            rss_before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
            c0, t0 = _cpu(), time.perf_counter()
            ds = campaigns.campaign(folder, **kw)
            wall = time.perf_counter() - t0
            cpu = _cpu() - c0
            after = client.run(_worker_usage) if client else {}
        finally:
            if client is not None:
                client.close()
                cluster.close()
    workers_cpu = sum(after[w][0] - before[w][0] for w in after)
    if nc:
        ds.to_netcdf(nc, engine="h5netcdf")
    failed = int(ds.attrs.get("n_failed", 0))
    reports = sorted((Path(out) / "reports").glob("*.ipynb"))
    return {
        "records": n,
        "mode": mode,
        "wall_s": wall,
        "cpu_s": cpu + workers_cpu,
        "records_per_min": 60.0 * n / wall,
        "joint_fit_s": joint_s[0] if joint_s else float("nan"),
        "joint_fit_ok": "joint_fit_json" in ds.attrs,
        "peak_rss_MB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        "rss_before_MB": rss_before,
        "worker_peak_rss_MB": [after[w][1] for w in sorted(after)],
        "cluster_start_s": t_cluster,
        "failed": failed,
        "reports_written": len(reports),
    }


def _subprocess(fn: str, *args) -> dict:
    code = (
        "import json, warnings; warnings.simplefilter('ignore'); "
        f"import benchmarks.bench_campaign_scale as b; print(json.dumps(b.{fn}(*{args!r})))"
    )
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", PYTHONPATH=str(ROOT))
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=ROOT
    )
    if out.returncode != 0:
        raise RuntimeError(f"{fn}{args} failed:\n{out.stderr[-3000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def _peer(folder: str, out: str, k: int) -> dict:
    """Run in a fresh process: ``k`` records the way a lab works today (module notes)."""
    from benchmarks.bench_fit_contact import ode_fit
    from pipeline.notebook_report import record_report
    from pipeline.report import load_sample, scene_from_sidecar

    files = sorted(Path(folder).glob("*.csv"))[:k]
    fit_cpu, report_cpu, wall = [], [], []
    for f in files:
        record, scene = load_sample(f), scene_from_sidecar(f)
        c, t = _cpu(), time.perf_counter()
        ode_fit(record, scene, 1e-7)
        c1 = _cpu()
        record_report(f, Path(out) / "peer", html=True, kernel=True, n_boot=N_BOOT, seed=0)
        c2 = _cpu()
        wall.append(time.perf_counter() - t)
        fit_cpu.append(c1 - c)
        report_cpu.append(c2 - c1)
    return {
        "records": len(files),
        "fit_cpu_s_per_record": float(np.median(fit_cpu)),
        "kernel_report_cpu_s_per_record": float(np.median(report_cpu)),
        "wall_s_per_record": float(np.median(wall)),
        "cpu_s_per_record": float(np.median(np.add(fit_cpu, report_cpu))),
    }


def _slope(rows, key, smallest=0) -> float:
    """Log–log slope of ``key`` against records over the sizes ≥ ``smallest``."""
    rows = [r for r in rows if np.isfinite(r[key]) and r[key] > 0 and r["records"] >= smallest]
    if len(rows) < 2:
        return float("nan")
    x = np.log([r["records"] for r in rows])
    return float(np.polyfit(x, np.log([r[key] for r in rows]), 1)[0])


def _env_int(name, default) -> int:
    return int(os.environ.get(name, default))


def run(out_dir: Path) -> dict:
    import lmfit

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    largest = _env_int("PIPELINE_BENCH_CAMPAIGN_MAX", max(SIZES))
    serial_max = _env_int("PIPELINE_BENCH_CAMPAIGN_SERIAL_MAX", largest)
    sizes = [n for n in SIZES if n <= largest]
    old_cache = os.environ.get("PIPELINE_CACHE")
    rows = {"serial": [], "dask": []}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        os.environ["PIPELINE_CACHE"] = str(tmp / "cache")
        try:
            # the caches filled before the clock (module notes)
            eight = str(_folder(tmp, 8))
            _subprocess("_one", 8, "serial", eight, str(tmp / "warm"))
            peer = _subprocess("_peer", eight, str(tmp / "peer"), PEER_RECORDS)
            print(f"  peer: {peer['cpu_s_per_record']:.1f} s CPU per record", flush=True)
            nc = {}
            for n in sizes:
                folder = _folder(tmp, n)
                for mode in ("dask", "serial"):
                    if mode == "serial" and n > serial_max:
                        continue
                    if n == COMPARE_SIZE:
                        nc[mode] = str(tmp / f"{mode}.nc")
                    row = _subprocess(
                        "_one", n, mode, str(folder), str(tmp / f"{mode}{n}"), nc.get(mode)
                    )
                    rows[mode].append(row)
                    print(
                        f"  {n} records, {mode}: {row['wall_s']:.1f} s wall "
                        f"({row['records_per_min']:.0f}/min, joint fit {row['joint_fit_s']:.1f} "
                        f"s), peak {row['peak_rss_MB']:.0f} MB",
                        flush=True,
                    )
            identical = None
            if len(nc) == 2:
                identical = Path(nc["serial"]).read_bytes() == Path(nc["dask"]).read_bytes()
        finally:
            if old_cache is None:
                os.environ.pop("PIPELINE_CACHE", None)
            else:
                os.environ["PIPELINE_CACHE"] = old_cache
    big = {m: next((r for r in rows[m] if r["records"] == max(SIZES)), None) for m in rows}
    peak = {m: [r["peak_rss_MB"] + sum(r["worker_peak_rss_MB"]) for r in rows[m]] for m in rows}
    result = {
        "sizes": sizes,
        "n_boot": N_BOOT,
        "rows": rows,
        "slope_wall": {m: _slope(rows[m], "wall_s") for m in rows},
        "slope_cpu": {m: _slope(rows[m], "cpu_s") for m in rows},
        "slope_joint_fit": {m: _slope(rows[m], "joint_fit_s") for m in rows},
        # a fixed cost (imports, the first report's set-up, the cluster's warm-up) bends
        # the line at small N: the slope over N ≥ 100 is the marginal one
        "slope_wall_from_100": {m: _slope(rows[m], "wall_s", 100) for m in rows},
        "slope_joint_fit_from_100": {m: _slope(rows[m], "joint_fit_s", 100) for m in rows},
        "slope_target": SLOPE_TARGET,
        "peak_memory_MB": peak,
        "peak_memory_ratio_largest_to_smallest": {
            m: (v[-1] / v[0] if len(v) > 1 else float("nan")) for m, v in peak.items()
        },
        "target_s": TARGET_S,
        "largest_dask_wall_s": big["dask"]["wall_s"] if big["dask"] else None,
        "meets_target": bool(big["dask"] and big["dask"]["wall_s"] <= TARGET_S),
        "dataset_identical_serial_dask": identical,
        "compare_size": COMPARE_SIZE,
        "peer": {
            **peer,
            "method": "lmfit + solve_ivp (pipeline.simulate.impact, rtol 1e-7) per record, "
            "lmfit's covariance, and one nbclient kernel per record executing its report",
            "lmfit": lmfit.__version__,
        },
        **machine(),
    }
    atomic_write_text(out_dir / "campaign_scale.json", json.dumps(result, indent=2) + "\n")
    _plot(result, out_dir / "campaign_scale.png")
    return result


def _plot(result: dict, path: Path) -> None:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(12.0, 4.0), layout="constrained")
    ax, mx, bx = fig.subplots(1, 3, gridspec_kw={"width_ratios": [1.3, 1, 1]})
    colours = {"serial": "0.45", "dask": "tab:blue"}
    for mode, rows in result["rows"].items():
        if not rows:
            continue
        n = np.array([r["records"] for r in rows], float)
        ax.loglog(
            n,
            [r["wall_s"] for r in rows],
            "o-",
            color=colours[mode],
            label=f"{mode} (slope {result['slope_wall'][mode]:.2f})",
        )
        ax.loglog(
            n,
            [r["joint_fit_s"] for r in rows],
            "s--",
            color=colours[mode],
            ms=4,
            label=f"of which joint fit (slope {result['slope_joint_fit'][mode]:.2f})",
        )
        mx.semilogx(
            n,
            result["peak_memory_MB"][mode],
            "o-",
            color=colours[mode],
            label=f"{mode}" + (" (process + 2 workers)" if mode == "dask" else ""),
        )
    n_all = np.array(result["sizes"], float)
    peer = result["peer"]
    ax.loglog(
        n_all,
        peer["wall_s_per_record"] * n_all,
        ":",
        color="tab:red",
        label=f"peer: lmfit+solve_ivp, kernel per report ({peer['records']} measured)",
    )
    ax.axhline(result["target_s"], color="tab:red", lw=0.8, ls="--")
    ax.text(n_all[0], result["target_s"] * 1.1, "10 min", color="tab:red", fontsize=7)
    for a in (ax, mx):
        a.set_xticks(n_all, [f"{int(v)}" for v in n_all])
        a.minorticks_off()
    ax.set_xlabel("records")
    ax.set_ylabel("wall time [s]")
    ax.legend(fontsize=7, loc="lower right")
    ax.set_title("cost against records (fits, joint fit, reports)", fontsize=9)
    mx.set_ylim(0, None)
    mx.set_xlabel("records")
    mx.set_ylabel("peak resident memory [MB]")
    mx.legend(fontsize=7)
    mx.set_title("peak memory", fontsize=9)
    largest = {m: rows[-1] for m, rows in result["rows"].items() if rows}
    bars = {f"{m}\n{r['records']} records": r["records_per_min"] for m, r in largest.items()}
    bars["peer\n(per-record cost)"] = 60.0 / peer["wall_s_per_record"]
    bx.bar(list(bars), list(bars.values()), color=["0.45", "tab:blue", "tab:red"][: len(bars)])
    bx.set_ylabel("records per minute")
    bx.set_title("throughput", fontsize=9)
    big = result["largest_dask_wall_s"]
    fig.suptitle(
        f"campaign at scale: copies of the 8 samples, bootstrap {result['n_boot']}, contact fits, "
        f"joint fit, rendered reports; 2 workers on {result['cpu_count']} cores"
        + (f"; 1,000 records in {big / 60:.1f} min" if big else ""),
        fontsize=9,
    )
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=120, format="png")


if __name__ == "__main__":
    print(json.dumps(run(Path("build/bench")), indent=2))
