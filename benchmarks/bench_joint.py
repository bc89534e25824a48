"""The joint campaign fit against the number of records: cost, memory, agreement, coverage.

Records: a simulated campaign — the Garland–Rogers rig (``benchmarks/_truth.py``) over
five angles × three speeds with friction μ = 0.10 + 0.20·v_t0 and e = 0.9
(:func:`pipeline.simulate.impact`, Hunt–Crossley + Mindlin), each record through
:func:`pipeline.sensor_model.to_sensor` with its own noise seed — never the fitter's model.

1. **Cost against records**: :func:`pipeline.fit_campaign` (every hypothesis: μ constant
   or linear in v_t0 × e or α constant) on 10 … 1 000 records, CPU time of the process and
   its peak resident memory (each size in a fresh subprocess: ``ru_maxrss``), and the
   log–log slope of cost against records (target ≤ 1.1; the old dense solver grew as
   records^2.3).
2. **The same result as the dense solver** (lmfit on the dense Jacobian over every record,
   ``solver="dense"``, the solver of old) on 8 and 24 records: the largest difference of a
   shared parameter in units of its standard error.
3. **Coverage**: ``N_COVER`` simulated 8-record campaigns, how often the 95 % interval of
   E*, e, a and b holds the truth (target 90–98 %).
4. **Why the fit re-evaluates the records** (:mod:`pipeline.fit.store`): on the bundled
   samples and on 8 simulated records, how far each hypothesis moves each record's E*, e
   and μ from the record's own fit (in its own standard errors) and how wrong a local
   quadratic model of the record's χ² at its own optimum would be there.

Section 1 reads the records as a campaign does, one at a time (:class:`Simulated`: each
made when asked for, its simulation in the CPU time as a file's reading would be), so
the peak memory is the fit's own; with the records kept on disk by the fit it does not
grow with them beyond a few kB each.

``PIPELINE_BENCH_JOINT_MAX`` caps the largest campaign of section 1 (default 1 000) for a
quick check. Writes ``joint.json`` and ``joint.png``.
"""

from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
import time
import warnings
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from pipeline import Scene
from pipeline._atomic import atomic_path, atomic_write_text
from pipeline.errors import PipelineWarning

from ._truth import GR_RIG

SIZES = (10, 30, 100, 300, 1000)
ANGLES = (10.0, 20.0, 30.0, 45.0, 60.0)
SPEEDS = (0.3, 0.6, 1.0)
MU_A, MU_B, E = 0.10, 0.20, 0.9
N_COVER = 40
COVER_RECORDS = 8


def scenes(n: int):
    """The campaign's first ``n`` scenes (angles × speeds, repeated)."""
    out = []
    for i in range(n):
        s = Scene(
            **GR_RIG, speed=SPEEDS[(i // len(ANGLES)) % len(SPEEDS)], angle_deg=ANGLES[i % 5], e=E
        )
        out.append(s.replace(mu=MU_A + MU_B * float(s.v_t0)))
    return out


class Simulated(Sequence):
    """The campaign's first ``n`` sensor records, each made when asked for (the ideal impact
    of each angle and speed simulated once), as a campaign reads records from files: the
    joint fit reads each once and never holds them all."""

    def __init__(self, n: int, seed: int = 0):
        self.scenes, self.seed, self._ideal = scenes(n), seed, {}

    def __len__(self) -> int:
        return len(self.scenes)

    def __getitem__(self, i):
        from pipeline.sensor_model import to_sensor
        from pipeline.simulate import impact

        s = self.scenes[i]
        key = (s.angle_deg, s.speed)
        if key not in self._ideal:
            self._ideal[key] = impact(s, samples=2001)
        rec = to_sensor(self._ideal[key], seed=self.seed * 100_000 + i)
        rec.attrs["source"] = f"r{i:04d}"
        return rec


def records(n: int, seed: int = 0, *, lazy: bool = False):
    """``n`` sensor records of the campaign (a list, or with ``lazy`` a :class:`Simulated`
    sequence) and the scenes the fit is told (no μ, no e)."""
    recs = Simulated(n, seed)
    told = [s.replace(mu=None, e=None) for s in recs.scenes]
    return (recs if lazy else list(recs)), told


def _fit(recs, told, **kw):
    from pipeline import fit_campaign

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)
        return fit_campaign(recs, told, mu_law="linear_vt0", damping="constant_e", **kw)


def _one_size(n: int) -> dict:
    """Run in a subprocess: the joint fit of ``n`` records made as it reads them, timed
    (CPU, the records' simulation included) and its peak memory."""
    import resource

    recs, told = records(n, lazy=True)
    recs[0]  # the imports and the first ideal impact before the clock
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    t = time.process_time()
    fit = _fit(recs, told)
    cpu = time.process_time() - t
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    best = fit.best
    return {
        "records": n,
        "cpu_s": cpu,
        "peak_rss_MB": peak / 1024.0,
        "rss_before_fit_MB": before / 1024.0,
        "store_bytes_per_record": fit.datas.nbytes / n,
        "hypotheses": len(fit.hypotheses),
        "best": {"mu_law": best.mu_law, "damping": best.damping},
        "values": {k: best.values.get(k) for k in ("E_eff", "e", "mu_a", "mu_b")},
        "iterations": {f"{k[0]}/{k[1]}": f.result.njev for k, f in fit.hypotheses.items()},
    }


def _sizes() -> list:
    rows = []
    largest = int(os.environ.get("PIPELINE_BENCH_JOINT_MAX", max(SIZES)))
    for n in [n for n in SIZES if n <= largest]:
        cmd = [
            sys.executable,
            "-c",
            f"import json, benchmarks.bench_joint as b; print(json.dumps(b._one_size({n})))",
        ]
        env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
        out = subprocess.run(cmd, capture_output=True, text=True, check=True, env=env)
        rows.append(json.loads(out.stdout.strip().splitlines()[-1]))
        print(f"  joint fit of {n} records: {rows[-1]['cpu_s']:.1f} s CPU", flush=True)
    return rows


def _agreement() -> list:
    rows = []
    for n in (8, 24):
        recs, told = records(n, seed=7)
        blocks = _fit(recs, told, hypotheses="one")
        t = time.process_time()
        dense = _fit(recs, told, hypotheses="one", solver="dense")
        t_dense = time.process_time() - t
        diff = {
            k: abs(blocks.values[k] - dense.values[k]) / dense.stderr[k]
            for k in ("E_eff", "e", "mu_a", "mu_b")
        }
        rows.append(
            {
                "records": n,
                "max_difference_in_stderr": max(diff.values()),
                "difference_in_stderr": diff,
                "chi2_blocks": blocks.chi2,
                "chi2_dense": dense.chi2,
                "dense_cpu_s": t_dense,
            }
        )
    return rows


def _coverage() -> dict:
    truth = {"E_eff": float(scenes(1)[0].E_eff), "e": E, "mu_a": MU_A, "mu_b": MU_B}
    hold = {k: 0 for k in truth}
    for c in range(N_COVER):
        recs, told = records(COVER_RECORDS, seed=100 + c)
        fit = _fit(recs, told, hypotheses="one")
        ci = fit.ci()
        for k, v in truth.items():
            hold[k] += int(ci[k][0] <= v <= ci[k][1])
    return {
        "campaigns": N_COVER,
        "records_each": COVER_RECORDS,
        "coverage": {k: v / N_COVER for k, v in hold.items()},
    }


def _local_model(recs, told) -> dict:
    """What a local model would get wrong (module notes, 4): per hypothesis, how far the
    joint fit moves each record's E*, e and μ from the record's own fit, in its own
    standard errors, and the relative error of the Gauss–Newton model of the record's χ²
    (r + J·ΔP at its own optimum) in the χ² it gains there."""
    from pipeline.fit.contact import DEFAULT_VARY, fit_model
    from pipeline.fit.engine import local_jacobians
    from pipeline.fit.forward import PARAMS, ForwardModel, prepare

    model = ForwardModel()
    names = ("E_eff", "e", "mu", "kt_scale", "t0")
    idx = np.array([PARAMS.index(k) for k in names])
    joint = _fit(recs, told)
    own, lin = [], []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)
        for r, s in zip(recs, told, strict=True):
            vary = DEFAULT_VARY("hunt_crossley", "mindlin")
            f = fit_model(r, s, model, vary, n_boot=0, systematics={})
            d = prepare(r, s)
            P = d.nominal()[None, :]
            P[0, idx] = [f.params[k].value for k in names]
            res, J, _ = local_jacobians(model, [d], [P], [idx])
            own.append((f, P))
            lin.append((d, res[0][0], J[0][0][idx].T))
    kinds = ("E_eff", "e", "mu")
    out = {}
    for (ml, dm), h in joint.hypotheses.items():
        per = h.per_record()
        moved, err = [], []
        for i, ((f, P0), (d, r0, J)) in enumerate(zip(own, lin, strict=True)):
            se = np.array([f.stderr[k] for k in kinds])
            step = np.array([per.loc[i, k] - f.params[k].value for k in kinds])
            moved.append(np.where(np.isfinite(se) & (se > 0), np.abs(step) / se, np.nan))
            P1 = P0.copy()
            P1[0, idx] = [per.loc[i, k] for k in names]
            r1 = model.residuals([d], [P1])[0][0][0]
            q = r0 + J @ (P1[0, idx] - P0[0, idx])
            gain = float(r1 @ r1 - r0 @ r0)
            err.append(abs(float(q @ q - r0 @ r0) - gain) / max(gain, 1e-300))
        moved = np.array(moved)
        out[f"{ml}/{dm}"] = {
            "moved_in_own_stderr_median": dict(
                zip(kinds, np.nanmedian(moved, 0).tolist(), strict=True)
            ),
            "moved_in_own_stderr_max": dict(zip(kinds, np.nanmax(moved, 0).tolist(), strict=True)),
            "records_mu_one_sided": int(np.isnan(moved[:, 2]).sum()),
            "quadratic_model_chi2_gain_error_max": float(max(err)),
            "quadratic_model_chi2_gain_error_median": float(np.median(err)),
        }
    return out


def _samples():
    """The bundled Garland–Rogers-style samples and their scenes (not made by the fit's
    model: their joint fit is poor)."""
    from pipeline.report import load_sample, scene_from_sidecar

    files = sorted((Path(__file__).resolve().parents[1] / "data_samples").glob("gr_*.csv"))
    return [load_sample(f) for f in files], [scene_from_sidecar(f) for f in files]


def _slope(rows) -> float:
    x = np.log([r["records"] for r in rows])
    y = np.log([r["cpu_s"] for r in rows])
    return float(np.polyfit(x, y, 1)[0])


def _plot(result, path: Path) -> None:
    from matplotlib.figure import Figure

    rows = result["sizes"]
    n = np.array([r["records"] for r in rows], dtype=float)
    cpu = np.array([r["cpu_s"] for r in rows])
    mem = np.array([r["peak_rss_MB"] for r in rows])
    fig = Figure(figsize=(9.0, 3.6), layout="constrained")
    ax, axm = fig.subplots(1, 2)
    ax.loglog(n, cpu, "o-", label=f"block solver (slope {result['slope']:.2f})")
    ax.loglog(n, cpu[0] * n / n[0], ":", color="0.5", label="slope 1")
    old = result.get("dense_growth")
    if old:
        ax.loglog(
            n,
            old["cpu_s_at_8"] * (n / 8.0) ** 2.3,
            "--",
            color="C3",
            label="dense solver, records^2.3 (issue)",
        )
    ax.axhline(120.0, color="C2", lw=0.8, ls="--", label="target: 1 000 records in 2 min")
    ax.set_xlabel("records")
    ax.set_ylabel("CPU time of the joint fit [s]")
    ax.set_ylim(cpu.min() / 3, max(cpu.max() * 3, 200))
    ax.legend(fontsize=7)
    ax.set_title("pipeline.fit_campaign, every hypothesis", fontsize=9)
    axm.semilogx(
        n, mem, "o-", label=f"{result['memory_MB_per_1000_records']:.0f} MB per 1,000 records"
    )
    axm.set_ylim(0, mem.max() * 1.3)
    axm.set_xlabel("records")
    axm.set_ylabel("peak resident memory [MB]")
    axm.legend(fontsize=7)
    axm.set_title("memory of the whole process (records read as fitted)", fontsize=9)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=130)


def run(out_dir: Path) -> dict:
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    sizes = _sizes()
    agreement = _agreement()
    coverage = _coverage()
    local = {
        "bundled samples": _local_model(*_samples()),
        "simulated, 8 records": _local_model(*records(COVER_RECORDS, seed=3)),
    }
    result = {
        "sizes": sizes,
        "slope": _slope(sizes),
        # the fit's memory beyond the process' own: a straight line through the peaks
        "memory_MB_per_1000_records": float(
            np.polyfit([r["records"] for r in sizes], [r["peak_rss_MB"] for r in sizes], 1)[0]
            * 1000.0
        ),
        "target_slope": 1.1,
        "target_1000_s": 120.0,
        "agreement_with_dense": agreement,
        "dense_growth": {"cpu_s_at_8": agreement[0]["dense_cpu_s"], "exponent": 2.3},
        "coverage": coverage,
        "local_model": local,
        "python": platform.python_version(),
        "cpu_count": os.cpu_count(),
    }
    result["meets_targets"] = bool(
        result["slope"] <= 1.1
        and sizes[-1]["cpu_s"] <= 120.0
        and all(a["max_difference_in_stderr"] < 0.1 for a in agreement)
        and all(0.9 <= v <= 0.98 for v in coverage["coverage"].values())
    )
    atomic_write_text(out_dir / "joint.json", json.dumps(result, indent=2) + "\n")
    _plot(result, out_dir / "joint.png")
    print(
        f"  slope {result['slope']:.2f}; 1000 records {sizes[-1]['cpu_s']:.0f} s; coverage "
        f"{coverage['coverage']}",
        flush=True,
    )
    return result
