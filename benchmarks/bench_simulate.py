"""Oblique-impact simulator: time per impact against error, single path vs batch path.

Scenes: Chung & Ooi (2011) test 4 (PHYSICS.md §6) — R = 2.5 mm aluminium oxide on a rigid
wall, |v| = 3.9 m/s, μ = 0.092, e = 0.98 (Hunt–Crossley, calibrated) — at incidence angles
``ANGLES`` spanning the compliant (< 32.5°) and rigid-sliding regimes.

Reference: :func:`pipeline.simulate.impact` with DOP853 at rtol = atol = 1e-13
(dimensionless), for each tangential model. Errors are the largest over the scenes of
|Δe_t|, |ΔF_max|/F_max and |Δt_c|/t_c.

- ``impact`` (solve_ivp, events at stick/slip switches, a 101-sample record) at rtol 1e-3 …
  1e-10, timed per call (best of ``REPEAT``).
- ``impact_outcomes`` (vectorised fixed-step RK4) at several step counts; errors on the same
  scenes, time per impact measured on ``N_BATCH`` scenes at random angles in one call.

For scale: the DEM code LAMMPS needs ≈7 µs of its time loop per such impact (figure from
issue 3, not measured here).

Writes ``simulate.json`` and ``simulate.png`` into the output directory.
"""

from __future__ import annotations

import json
import platform
import time
from pathlib import Path

import numpy as np

from pipeline import Scene
from pipeline._atomic import atomic_path, atomic_write_bytes
from pipeline.simulate import impact, impact_outcomes

ANGLES = (5.0, 10.0, 15.0, 20.0, 30.0, 45.0, 60.0, 80.0)
RTOLS = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10)
STEPS = (25, 50, 100, 200, 400, 800, 1600)
N_BATCH = 20000
MODELS = (("coulomb", "total"), ("mindlin", "total"), ("mindlin", "incremental"))
LAMMPS_US = 7.0
REPEAT = 3


def _scene(angle):
    return Scene(
        radius=2.5e-3,
        density=4000.0,
        E=380e9,
        nu=0.23,
        speed=3.9,
        angle_deg=angle,
        mu=0.092,
        e=0.98,
    )


def _errors(e_t, F, tc, ref):
    return {
        "err_e_t": float(np.max(np.abs(np.asarray(e_t) - ref["e_t"]))),
        "err_F_max": float(np.max(np.abs(np.asarray(F) / ref["F_max"] - 1.0))),
        "err_t_c": float(np.max(np.abs(np.asarray(tc) / ref["t_c"] - 1.0))),
    }


def run(out_dir: Path) -> dict:
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    scenes = [_scene(a) for a in ANGLES]
    rng = np.random.default_rng(0)
    big = _scene(rng.uniform(1.0, 85.0, N_BATCH))
    results = []
    refs = {}
    for tangential, history in MODELS:
        name = tangential if tangential == "coulomb" else f"mindlin-{history}"
        ref_attrs = [
            impact(
                s, tangential=tangential, history=history, rtol=1e-13, atol=1e-13, samples=101
            ).attrs
            for s in scenes
        ]
        ref = {
            k: np.array([a[key] for a in ref_attrs])
            for k, key in (("e_t", "e_t"), ("F_max", "F_max"), ("t_c", "t_contact"))
        }
        refs[name] = {k: v.tolist() for k, v in ref.items()}
        for rtol in RTOLS:
            dt = np.inf
            for _ in range(REPEAT):  # best of REPEAT: the machine is shared
                t0 = time.perf_counter()
                attrs = [
                    impact(s, tangential=tangential, history=history, rtol=rtol, samples=101).attrs
                    for s in scenes
                ]
                dt = min(dt, (time.perf_counter() - t0) / len(scenes))
            row = {
                "path": "impact (solve_ivp DOP853)",
                "model": name,
                "setting": f"rtol={rtol:g}",
                "rtol": rtol,
                "time_per_impact_s": dt,
            }
            row.update(
                _errors(
                    [a["e_t"] for a in attrs],
                    [a["F_max"] for a in attrs],
                    [a["t_contact"] for a in attrs],
                    ref,
                )
            )
            results.append(row)
        for n in STEPS:
            o = impact_outcomes(scenes, tangential=tangential, history=history, n_steps=n)
            best = np.inf
            for _ in range(REPEAT):
                t0 = time.perf_counter()
                impact_outcomes(big, tangential=tangential, history=history, n_steps=n)
                best = min(best, time.perf_counter() - t0)
            row = {
                "path": "impact_outcomes (batch RK4)",
                "model": name,
                "setting": f"n_steps={n}",
                "n_steps": n,
                "time_per_impact_s": best / N_BATCH,
            }
            row.update(_errors(o.e_t, o.F_max, o.t_contact, ref))
            results.append(row)
    report = {
        "benchmark": "simulate",
        "scenes": "Chung & Ooi (2011) test 4, e = 0.98 (Hunt-Crossley), mu = 0.092, angles "
        + ", ".join(f"{a:g}" for a in ANGLES)
        + " deg",
        "reference": "impact(), DOP853, rtol = atol = 1e-13 (dimensionless)",
        "n_batch": N_BATCH,
        "lammps_time_loop_per_impact_s": LAMMPS_US * 1e-6,
        "machine": {
            "python": platform.python_version(),
            "platform": platform.platform(),
            "numpy": np.__version__,
        },
        "reference_values": refs,
        "results": results,
    }
    atomic_write_bytes(out_dir / "simulate.json", json.dumps(report, indent=2).encode())
    _plot(results, out_dir / "simulate.png")
    return report


def _plot(results, path: Path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.8), constrained_layout=True)
    keys = (
        ("err_e_t", "max |Δe_t|"),
        ("err_F_max", "max |ΔF_max|/F_max"),
        ("err_t_c", "max |Δt_c|/t_c"),
    )
    curves = sorted({(r["path"], r["model"]) for r in results})
    for ax, (key, label) in zip(axes, keys, strict=True):
        for path_name, model in curves:
            rows = [r for r in results if r["path"] == path_name and r["model"] == model]
            x = [r["time_per_impact_s"] for r in rows]
            y = [max(r[key], 1e-16) for r in rows]
            style = "o-" if path_name.startswith("impact (") else "s--"
            ax.loglog(x, y, style, label=f"{path_name.split()[0]}: {model}", ms=4)
        ax.axvline(LAMMPS_US * 1e-6, color="grey", lw=0.8, ls=":")
        ax.text(
            LAMMPS_US * 1e-6, ax.get_ylim()[1], " LAMMPS ≈7 µs", va="top", fontsize=7, color="grey"
        )
        ax.set_xlabel("time per impact [s]")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.suptitle("pipeline.simulate: speed vs accuracy (Chung & Ooi test 4, 8 angles)")
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=120)
    plt.close(fig)
