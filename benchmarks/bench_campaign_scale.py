"""A campaign at scale: 10 to 10,000 records with fits and the joint fit, in flat memory.

Records: the eight bundled Garland–Rogers-style samples with their sidecars, copied (hard
links where the file system allows) into folders of N = 10, 30, 100, 300, 1,000, 3,000
and 10,000 records (record i is sample i mod 8). Each N is run as a user runs it —
``campaign(folder, fit=True)``: every record analysed with the default bootstrap (200),
its contact fit with its default budget and verdict, then the joint campaign fit of all
records (four hypotheses) — in a fresh process:

- ``dask``: on a 2-worker ``LocalCluster`` (single-threaded worker processes, started
  before the clock: its start-up is reported apart; its scheduler runs in the main
  process), every N, without reports (10,000 records' notebooks would be ~10 GB);
- ``serial``: in one process, every N up to ``PIPELINE_BENCH_CAMPAIGN_SERIAL_MAX``
  (default 1,000: 10,000 records take about an hour serially); at each N run both ways,
  the two Datasets are compared as written (netCDF bytes);
- ``dask_reports``: the same on 2 workers with every record's fit report rendered
  (notebook and HTML), at 100 and 1,000 records;
- ``external``: one campaign of :data:`EXTERNAL_RECORDS` records as a cluster runs it — a
  ``dask scheduler --port ...`` and two ``dask worker tcp://...`` processes started from
  the command line with the settings ``docs/cluster.md`` gives, and ``pipeline campaign
  DIR --scheduler tcp://... --no-reports`` — its ``campaign.nc`` compared with the serial
  Dataset of the same records.

Per run: wall time, CPU time (this process, its children and the workers), records per
minute, the joint fit's own time and the bytes of its temporary file of records
(:class:`pipeline.fit.store.RecordStore`), and the peak resident memory (``ru_maxrss``) of
every process: the main one (with the scheduler inside it for a ``LocalCluster``; also its
peak before the joint fit), each worker and, for the external cluster, the scheduler.
Cost against N on log–log: the fitted slope (target ≤ :data:`SLOPE_TARGET`); memory
against N: each process's growth per 1,000 records (a straight-line fit) and its peak
(target ≤ :data:`MEMORY_TARGET_MB` at every N).

What the joint fit itself holds a record, apart from the processes' resident memory (which
a cluster's messages, the allocator and the records' analysis blur): in a fresh process,
Python's ``tracemalloc`` over :func:`pipeline.fit_campaign` (four hypotheses) of the
simulated campaign of ``benchmarks/bench_joint.py`` at :data:`TRACED_RECORDS` records,
read in chunks of :data:`TRACED_CHUNK` (so that both sizes span several chunks): the fit's
largest traced memory and what it keeps after, and their growth per record between the
two sizes (``joint_fit_traced``).

The outcome table of :func:`pipeline.simulate.impact_outcomes` and the fits' pulse tables
are built on their first use and cached on disk; the run uses a cache folder of its own,
filled by a warm-up campaign of a few records before the clock.

The peer, in the same run on :data:`PEER_RECORDS` records: the way a lab works today — a
loop of lmfit with :func:`scipy.integrate.solve_ivp` (``pipeline.simulate.impact``, rtol
1e-7) in the residual, lmfit's covariance as its intervals (no bootstrap: it would cost
200 ODE fits), and one notebook kernel per record executing the record's report
(``record_report(kernel=True)``); its per-record cost times N is drawn beside ours.

Targets (issue 22): 10,000 records with fits and the joint fit in ≤ 30 minutes on 2
cores, the peak memory of every process ≤ 1 GB and flat against N, the log–log slope of
the time ≤ 1.05, the Datasets identical serially and distributed; (issue 16) 1,000
records with reports in ≤ 10 minutes on 2 workers. ``PIPELINE_BENCH_CAMPAIGN_MAX`` caps
the largest N (default 10,000) for a quick check, ``PIPELINE_BENCH_CAMPAIGN_REPORTS_MAX``
the largest N run with reports (default 1,000).

Writes ``campaign_scale.json`` and ``campaign_scale.png``, both after every run, so that a
run stopped part-way leaves what it measured.
"""

from __future__ import annotations

import json
import os
import resource
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

from benchmarks.bench_campaign import _cpu, machine
from pipeline._atomic import atomic_path, atomic_write_text
from pipeline.campaigns.run import LOG_LENGTH

ROOT = Path(__file__).resolve().parents[1]
SIZES = (10, 30, 100, 300, 1000, 3000, 10000)
REPORT_SIZES = (100, 1000)
#: records of the campaign on the external scheduler and workers
EXTERNAL_RECORDS = 300
#: records of the peer's loop (lmfit + solve_ivp and a kernel per report)
PEER_RECORDS = 3
TARGET_S = 1800.0
REPORTS_TARGET_S = 600.0
SLOPE_TARGET = 1.05
MEMORY_TARGET_MB = 1024.0
N_BOOT = 200
#: records of the joint fits traced in one process (module notes), and their chunk
TRACED_RECORDS = (64, 256)
TRACED_CHUNK = 16
#: what docs/cluster.md tells a cluster's processes (the workers' allocator keeping freed
#: memory, their statistical profiler off, short logs of recent messages)
CLUSTER_ENV = {
    "DASK_DISTRIBUTED__NANNY__PRE_SPAWN_ENVIRON__MALLOC_TRIM_THRESHOLD_": "268435456",
    "DASK_DISTRIBUTED__NANNY__PRE_SPAWN_ENVIRON__MALLOC_MMAP_THRESHOLD_": "33554432",
    "DASK_DISTRIBUTED__WORKER__PROFILE__ENABLED": "False",
    "DASK_DISTRIBUTED__ADMIN__LOW_LEVEL_LOG_LENGTH": str(LOG_LENGTH),
}


def _folder(root: Path, n: int) -> Path:
    """``n`` records (copies of the samples and their sidecars) in a folder of their own."""
    src = sorted((ROOT / "data_samples").glob("gr_*.csv"))
    out = root / f"n{n}"
    out.mkdir(parents=True, exist_ok=True)
    for i in range(n):
        csv = src[i % len(src)]
        for a, b in (
            (csv, out / f"r{i:05d}_{csv.name}"),
            (csv.with_suffix(".json"), out / f"r{i:05d}_{csv.stem}.json"),
        ):
            try:
                os.link(a, b)
            except OSError:
                b.write_bytes(a.read_bytes())
    return out


def _usage():
    """CPU time [s] and peak resident memory [MB] of the process it runs in."""
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime, r.ru_maxrss / 1024.0


def _peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _one(n: int, mode: str, folder: str, out: str, nc: str | None = None) -> dict:
    """Run in a fresh process: the campaign of ``folder`` (``mode`` "serial", "dask" or
    "dask_reports"), timed and its memory measured (module notes)."""
    import pipeline.campaigns as campaigns
    import pipeline.fit.campaign as fit_campaign

    joint = {"s": [], "peak_before_MB": [], "store_bytes": []}
    with_joint = campaigns.with_joint_fit

    def timed_joint(*a, **kw):
        joint["peak_before_MB"].append(_peak_mb())
        t = time.perf_counter()
        try:
            return with_joint(*a, **kw)
        finally:
            joint["s"].append(time.perf_counter() - t)

    class Store(fit_campaign.RecordStore):
        def _fill(self, *a, **kw):  # every way a store is made (RecordStore.of_packed too)
            super()._fill(*a, **kw)
            joint["store_bytes"].append(self.nbytes)

    campaigns.with_joint_fit = timed_joint
    fit_campaign.RecordStore = Store
    client = cluster = None
    t_cluster = 0.0
    kw = {"fit": True, "n_boot": N_BOOT, "seed": 0}
    if mode == "dask_reports":
        kw["reports"] = Path(out) / "reports"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if mode != "serial":
            from pipeline.campaigns.run import local_cluster, open_client

            t = time.perf_counter()
            cluster = local_cluster(2)  # and its client, as `campaign(workers=2)` starts them
            client = open_client(cluster)
            t_cluster = time.perf_counter() - t
            kw["scheduler"] = client
        try:
            before = client.run(_usage) if client else {}
            rss_before = _peak_mb()
            c0, t0 = _cpu(), time.perf_counter()
            ds = campaigns.campaign(folder, **kw)
            wall = time.perf_counter() - t0
            cpu = _cpu() - c0
            after = client.run(_usage) if client else {}
        finally:
            if client is not None:
                client.close()
                cluster.close()
    workers_cpu = sum(after[w][0] - before[w][0] for w in after)
    if nc:
        ds.to_netcdf(nc, engine="h5netcdf")
    reports = sorted((Path(out) / "reports").glob("*.ipynb"))
    return {
        "records": n,
        "mode": mode,
        "wall_s": wall,
        "cpu_s": cpu + workers_cpu,
        "records_per_min": 60.0 * n / wall,
        "joint_fit_s": joint["s"][0] if joint["s"] else float("nan"),
        "joint_fit_ok": "joint_fit_json" in ds.attrs,
        "joint_fit_store_MB": joint["store_bytes"][0] / 1e6 if joint["store_bytes"] else 0.0,
        "peak_rss_MB": _peak_mb(),
        "peak_rss_before_joint_fit_MB": joint["peak_before_MB"][0]
        if joint["peak_before_MB"]
        else float("nan"),
        "rss_before_MB": rss_before,
        "worker_peak_rss_MB": [after[w][1] for w in sorted(after)],
        "scheduler_peak_rss_MB": None,
        "cluster_start_s": t_cluster,
        "failed": int(ds.attrs.get("n_failed", 0)),
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


def _traced(sizes, chunk) -> dict:
    """Run in a fresh process: the joint fit of the simulated campaign at each of
    ``sizes`` records, its largest traced memory and what it keeps after (module notes)."""
    import gc
    import tracemalloc

    import dask.array  # noqa: F401  (xarray imports it at the first record with a spike)

    from benchmarks.bench_joint import records
    from pipeline import fit_campaign
    from pipeline.fit import store

    store.CHUNK = chunk
    out = {"records": [], "peak_MB": [], "kept_MB": []}
    for n in (8, *sizes):  # 8: the imports and caches before the measures
        recs, told = records(n, lazy=True)
        recs[0]
        gc.collect()
        tracemalloc.start()
        base = tracemalloc.get_traced_memory()[0]
        fit = fit_campaign(recs, told, mu_law="linear_vt0", damping="constant_e")
        gc.collect()
        kept, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        del fit
        if n in sizes:
            out["records"].append(n)
            out["peak_MB"].append((peak - base) / 1e6)
            out["kept_MB"].append((kept - base) / 1e6)
    dn = out["records"][-1] - out["records"][0]
    for k in ("peak", "kept"):
        mb = out[f"{k}_MB"]
        out[f"{k}_bytes_per_record"] = (mb[-1] - mb[0]) * 1e6 / dn
    out["chunk"] = chunk
    return out


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _command(name: str) -> str:
    """The console script ``name`` of this Python's environment (else the one on PATH)."""
    exe = Path(sys.executable).with_name(name)
    return str(exe) if exe.exists() else shutil.which(name) or name


def _external(n: int, folder: Path, out: Path, logs: Path) -> dict:
    """A campaign on a scheduler and two workers started from the command line, by the
    ``pipeline campaign --scheduler`` command (module notes)."""
    from distributed import Client

    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", PYTHONPATH=str(ROOT), **CLUSTER_ENV)
    logs.mkdir(parents=True, exist_ok=True)
    dask = _command("dask")
    procs = []

    def start(name, argv):
        log = open(logs / f"{name}.log", "w")  # noqa: SIM115 - closed with the process
        procs.append((subprocess.Popen(argv, env=env, stdout=log, stderr=log, cwd=ROOT), log))

    try:
        start("scheduler", [dask, "scheduler", "--host", "127.0.0.1", "--port", str(port),
                            "--no-dashboard"])  # fmt: skip
        for k in range(2):
            start(
                f"worker{k}",
                [dask, "worker", address, "--nworkers", "1", "--nthreads", "1",
                 "--no-dashboard", "--name", f"worker{k}",
                 "--local-directory", str(logs / f"worker{k}")],
            )  # fmt: skip
        with Client(address, timeout="60s") as client:
            client.wait_for_workers(2, timeout=120)
            before = client.run(_usage)
        argv = [_command("pipeline"), "campaign", str(folder), "--scheduler",
                address, "--no-reports", "--boot", str(N_BOOT), "--seed", "0",
                "--out", str(out)]  # fmt: skip
        c0, t0 = _cpu(), time.perf_counter()
        with open(logs / "campaign.log", "w") as log:
            cmd = subprocess.Popen(argv, env=env, stdout=log, stderr=log, cwd=ROOT)
            _, status, usage = os.wait4(cmd.pid, 0)
            cmd.returncode = os.waitstatus_to_exitcode(status)
        wall = time.perf_counter() - t0
        cpu = _cpu() - c0
        with Client(address, timeout="60s") as client:
            after = client.run(_usage)
            scheduler = client.run_on_scheduler(_usage)
    finally:
        for p, log in reversed(procs):
            p.terminate()
            try:
                p.wait(timeout=30)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
            log.close()
    return {
        "records": n,
        "mode": "external",
        "command": " ".join(["pipeline"] + argv[1:]),
        "exit_status": cmd.returncode,
        "wall_s": wall,
        "cpu_s": cpu + sum(after[w][0] - before[w][0] for w in after),
        "records_per_min": 60.0 * n / wall,
        "peak_rss_MB": usage.ru_maxrss / 1024.0,
        "worker_peak_rss_MB": [after[w][1] for w in sorted(after)],
        "scheduler_peak_rss_MB": scheduler[1],
    }


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


def _processes(row) -> dict:
    """{process: peak resident memory [MB]} of one run."""
    out = {"main": row["peak_rss_MB"]}
    for k, v in enumerate(row["worker_peak_rss_MB"]):
        out[f"worker {k}"] = v
    if row.get("scheduler_peak_rss_MB") is not None:
        out["scheduler"] = row["scheduler_peak_rss_MB"]
    return out


def _growth(rows) -> dict:
    """Each process' peak memory against the records: MB per 1,000 records (straight
    line through the runs), and the largest over the smallest run's."""
    out = {}
    if len(rows) < 2:
        return out
    n = np.array([r["records"] for r in rows], float)
    for name in _processes(rows[0]):
        mb = np.array([_processes(r).get(name, np.nan) for r in rows])
        out[name] = {
            "MB_per_1000_records": float(np.polyfit(n, mb, 1)[0] * 1000.0),
            "largest_over_smallest": float(mb[-1] / mb[0]),
        }
    return out


def _env_int(name, default) -> int:
    return int(os.environ.get(name, default))


def summarise(
    rows: dict, peer: dict | None, identical: dict, external: dict | None, traced: dict | None
) -> dict:
    """The figures of the runs so far (module notes)."""
    import lmfit

    result = {
        "n_boot": N_BOOT,
        "rows": rows,
        "slope_wall": {m: _slope(rows[m], "wall_s") for m in rows},
        "slope_cpu": {m: _slope(rows[m], "cpu_s") for m in rows},
        "slope_joint_fit": {m: _slope(rows[m], "joint_fit_s") for m in rows},
        # a fixed cost (imports, the cluster's warm-up, the workers' first fit) bends the
        # line at small N: the slope over N ≥ 100 is the marginal one
        "slope_wall_from_100": {m: _slope(rows[m], "wall_s", 100) for m in rows},
        "slope_joint_fit_from_100": {m: _slope(rows[m], "joint_fit_s", 100) for m in rows},
        "slope_target": SLOPE_TARGET,
        "peak_memory_MB": {m: [_processes(r) for r in rows[m]] for m in rows},
        "memory_growth": {m: _growth(rows[m]) for m in rows},
        "largest_process_MB": max(
            (
                max(_processes(r).values())
                for r in [r for m in rows for r in rows[m]] + ([external] if external else [])
            ),
            default=None,
        ),
        "memory_target_MB": MEMORY_TARGET_MB,
        "target_s": TARGET_S,
        "reports_target_s": REPORTS_TARGET_S,
        "dataset_identical_serial_dask": identical,
        "external": external,
        "joint_fit_traced": traced,
        "cluster_env": CLUSTER_ENV,
        "lmfit": lmfit.__version__,
        **machine(),
    }
    big = {m: max(rows[m], key=lambda r: r["records"]) for m in rows if rows[m]}
    if "dask" in big:
        result["largest_dask"] = {
            k: big["dask"][k] for k in ("records", "wall_s", "joint_fit_s", "peak_rss_MB")
        }
        result["meets_target"] = bool(
            big["dask"]["records"] >= max(SIZES) and big["dask"]["wall_s"] <= TARGET_S
        )
    if peer is not None:
        result["peer"] = {
            **peer,
            "method": "lmfit + solve_ivp (pipeline.simulate.impact, rtol 1e-7) per record, "
            "lmfit's covariance, and one nbclient kernel per record executing its report",
        }
    return result


def run(out_dir: Path) -> dict:
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    largest = _env_int("PIPELINE_BENCH_CAMPAIGN_MAX", max(SIZES))
    serial_max = _env_int("PIPELINE_BENCH_CAMPAIGN_SERIAL_MAX", 1000)
    reports_max = _env_int("PIPELINE_BENCH_CAMPAIGN_REPORTS_MAX", max(REPORT_SIZES))
    sizes = [n for n in SIZES if n <= largest]
    old_cache = os.environ.get("PIPELINE_CACHE")
    rows = {"dask": [], "serial": [], "dask_reports": []}
    identical, external, peer, traced = {}, None, None, None
    result = {}

    def save():
        nonlocal result
        result = summarise(rows, peer, identical, external, traced)
        result["sizes"] = sizes
        atomic_write_text(out_dir / "campaign_scale.json", json.dumps(result, indent=2) + "\n")
        _plot(result, out_dir / "campaign_scale.png")

    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        os.environ["PIPELINE_CACHE"] = str(tmp / "cache")
        try:
            # the caches filled before the clock (module notes)
            eight = str(_folder(tmp, 8))
            _subprocess("_one", 8, "serial", eight, str(tmp / "warm"))
            peer = _subprocess("_peer", eight, str(tmp / "peer"), PEER_RECORDS)
            print(f"  peer: {peer['cpu_s_per_record']:.1f} s CPU per record", flush=True)
            traced = _subprocess("_traced", TRACED_RECORDS, TRACED_CHUNK)
            print(
                f"  joint fit alone, traced: {traced['peak_bytes_per_record'] / 1e3:.1f} kB a "
                f"record at its largest, {traced['kept_bytes_per_record'] / 1e3:.1f} kB kept",
                flush=True,
            )
            ext_n = min(EXTERNAL_RECORDS, largest)
            for n in sorted(set(sizes) | {ext_n}):
                folder = _folder(tmp, n)
                runs = [("dask", n in sizes), ("serial", n <= serial_max or n == ext_n)]
                runs.append(("dask_reports", n in REPORT_SIZES and n in sizes and n <= reports_max))
                nc = {}
                for mode, wanted in runs:
                    if not wanted:
                        continue
                    if mode != "dask_reports":
                        nc[mode] = str(tmp / f"{mode}{n}.nc")
                    row = _subprocess(
                        "_one", n, mode, str(folder), str(tmp / f"{mode}{n}"), nc.get(mode)
                    )
                    rows[mode].append(row)
                    print(
                        f"  {n} records, {mode}: {row['wall_s']:.1f} s wall "
                        f"({row['records_per_min']:.0f}/min, joint fit {row['joint_fit_s']:.1f} "
                        f"s), peak {max(_processes(row).values()):.0f} MB",
                        flush=True,
                    )
                    shutil.rmtree(tmp / f"{mode}{n}", ignore_errors=True)
                    save()
                if len(nc) == 2:
                    identical[str(n)] = (
                        Path(nc["serial"]).read_bytes() == Path(nc["dask"]).read_bytes()
                    )
                if n == ext_n:
                    external = _external(n, folder, tmp / "external", tmp / "external-logs")
                    external.update(_same_dataset(nc["serial"], tmp / "external" / "campaign.nc"))
                    print(
                        f"  {n} records on a command-line scheduler and 2 workers: "
                        f"{external['wall_s']:.1f} s, same Dataset: {external['same_dataset']}",
                        flush=True,
                    )
                for path in nc.values():
                    Path(path).unlink(missing_ok=True)
                if n not in sizes:
                    rows["serial"] = [r for r in rows["serial"] if r["records"] != n]
                save()
                shutil.rmtree(folder, ignore_errors=True)
        finally:
            if old_cache is None:
                os.environ.pop("PIPELINE_CACHE", None)
            else:
                os.environ["PIPELINE_CACHE"] = old_cache
    return result


def _same_dataset(a, b) -> dict:
    """Whether the Datasets of two netCDF files are the same (values, attrs, encodings),
    and whether the files are the same bytes."""
    import xarray as xr

    if not Path(b).is_file():
        return {"same_dataset": False, "same_bytes": False}
    with xr.open_dataset(a, engine="h5netcdf") as x, xr.open_dataset(b, engine="h5netcdf") as y:
        same = bool(x.identical(y))
    return {"same_dataset": same, "same_bytes": Path(a).read_bytes() == Path(b).read_bytes()}


def _plot(result: dict, path: Path) -> None:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(13.0, 4.2), layout="constrained")
    ax, mx, bx = fig.subplots(1, 3, gridspec_kw={"width_ratios": [1.3, 1.2, 0.8]})
    colours = {"serial": "0.45", "dask": "tab:blue", "dask_reports": "tab:green"}
    labels = {"serial": "serial", "dask": "2 workers", "dask_reports": "2 workers, reports"}
    sizes = sorted({r["records"] for rows in result["rows"].values() for r in rows})
    for mode, rows in result["rows"].items():
        if not rows:
            continue
        n = np.array([r["records"] for r in rows], float)
        ax.loglog(
            n,
            [r["wall_s"] for r in rows],
            "o-",
            color=colours[mode],
            label=f"{labels[mode]} (slope {result['slope_wall'][mode]:.2f})",
        )
        if mode != "dask_reports":
            ax.loglog(
                n,
                [r["joint_fit_s"] for r in rows],
                "s--",
                color=colours[mode],
                ms=4,
                label=f"of which joint fit (slope {result['slope_joint_fit'][mode]:.2f})",
            )
        if mode == "dask_reports":
            continue
        procs = result["peak_memory_MB"][mode]
        main = f"{labels[mode]}: main" + (" (+ scheduler)" if mode == "dask" else "")
        mx.semilogx(n, [p["main"] for p in procs], "o-", color=colours[mode], label=main)
        for k in range(max((len(r["worker_peak_rss_MB"]) for r in rows), default=0)):
            mx.semilogx(n, [p.get(f"worker {k}", np.nan) for p in procs], "^:",
                        color=colours[mode], ms=4, label="workers" if k == 0 else None)  # fmt: skip
    ext = result.get("external")
    if ext:
        ax.loglog([ext["records"]], [ext["wall_s"]], "D", color="tab:purple",
                  label="command-line scheduler + 2 workers")  # fmt: skip
        for name, mb in _processes(ext).items():
            mx.semilogx([ext["records"]], [mb], "D" if name == "scheduler" else "d",
                        color="tab:purple", ms=5,
                        label="command-line cluster" if name == "main" else None)  # fmt: skip
    if not sizes:
        return
    n_all = np.array(sizes, float)
    peer = result.get("peer")
    if peer:
        ax.loglog(
            n_all,
            peer["wall_s_per_record"] * n_all,
            ":",
            color="tab:red",
            label=f"peer: lmfit+solve_ivp, kernel per report ({peer['records']} measured)",
        )
    ax.axhline(result["target_s"], color="tab:red", lw=0.8, ls="--")
    ax.text(n_all[0], result["target_s"] * 1.1, "30 min", color="tab:red", fontsize=7)
    mx.axhline(result["memory_target_MB"], color="tab:red", lw=0.8, ls="--")
    for a in (ax, mx):
        a.set_xticks(n_all, [f"{int(v):,}" for v in n_all])
        a.minorticks_off()
        a.set_xlabel("records")
    ax.set_ylabel("wall time [s]")
    ax.legend(fontsize=6.5, loc="lower right")
    ax.set_title("cost against records (fits, joint fit)", fontsize=9)
    mx.set_ylim(0, max(result["memory_target_MB"] * 1.1, result["largest_process_MB"] or 0))
    mx.set_ylabel("peak resident memory [MB]")
    mx.legend(fontsize=6.5, loc="center left")
    mx.set_title("peak memory of each process", fontsize=9)
    largest = {m: rows[-1] for m, rows in result["rows"].items() if rows}
    bars = {f"{labels[m]}\n{r['records']:,}": r["records_per_min"] for m, r in largest.items()}
    colors = [colours[m] for m in largest]
    if peer:
        bars["peer"] = 60.0 / peer["wall_s_per_record"]
        colors.append("tab:red")
    bx.bar(list(bars), list(bars.values()), color=colors)
    bx.tick_params(axis="x", labelsize=6.5)
    bx.set_ylabel("records per minute")
    bx.set_title("throughput", fontsize=9)
    big = result.get("largest_dask")
    fig.suptitle(
        f"campaign at scale: copies of the 8 samples, bootstrap {result['n_boot']}, contact "
        f"fits, joint fit; 2 workers on {result['cpu_count']} cores"
        + (f"; {big['records']:,} records in {big['wall_s'] / 60:.1f} min" if big else ""),
        fontsize=9,
    )
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=120, format="png")


if __name__ == "__main__":
    print(json.dumps(run(Path("build/bench")), indent=2))
