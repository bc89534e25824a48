"""Stability maps of the physics: where rigid theory, the simulator and impact laws fail.

``incidence_mu``
    incidence × μ: |Δe_t| of Routh's rigid model (:func:`pipeline.rigid.sphere_on_plane`)
    against Hertz–Mindlin (:func:`pipeline.simulate.impact_outcomes`), for e = 1 (Hertz)
    and e = 0.6 (Hunt–Crossley), with Maw–Barber–Fawcett's criterion ψ1 = 4χ and Routh's
    sliding boundary ψ1 = 2χ(1+e) drawn on it; :func:`pipeline.advise` at the tolerance
    ``TOL`` on a coarser grid (its verdict must be "mindlin" wherever rigid theory is off).
``restitution``
    e → 0 and e → 1 × incidence: the same |Δe_t|, and the batch simulator against the
    adaptive single-impact solver (their difference must stay within the batch path's
    stated 2e-5, or the batch path must flag the scene).
``tangential_stiffness``
    very soft to very stiff tangential contact (k_t = scale·8G*a) × incidence, e = 1:
    rigid theory against Mindlin, and the batch integrator's fixed step (``N_STEPS``)
    against a converged one (16×): the tangential period it must resolve shrinks as
    scale^(−1/2).
``grazing``
    incidence from near-normal to grazing × μ: rigid vs Mindlin and batch vs single path.
``curved_target``
    a fixed rigid convex cap of radius R_cap (10 mm … 1 m) under the ball, × incidence at 2 m/s
    and × speed at 75° (μ 0.131, e 0.9, the secant Hertz dashpot): |Δe_n| and |Δe_t| on
    the first contact's frame between the normal turning over the cap
    (:func:`pipeline.simulate.curved.turning_outcomes`) and the held frame every model of
    the ladder and the fitter keep, with the tolerance's contour; where LAMMPS (``lmp``)
    is installed, a few cells replayed there (``fix wall/gran/region`` on a sphere) give
    both models' distance to it. Silent: a cell beyond the tolerance that
    :func:`pipeline.advise` does not flag (checked on a coarser grid).
``rod_paradox``
    the slender rod of docs/theory.md, Rigid bodies (m = 1 kg, L = 1 m, lower end strikes, v_G =
    (0.3,
    −1.0) m/s, e = 0.9) over rod angle × μ: ΔKE/KE0 under Newton's, Poisson's and Stronge's
    laws (:func:`pipeline.rigid.planar_impact`); where Newton's law creates energy (Kane's
    paradox) it must raise an ``EnergyGainWarning``.

Material: the bundled samples' steel ball (``benchmarks/_truth.py``). Writes
``stability_physics.json`` and ``stability_physics_<map>.png``.
"""

from __future__ import annotations

import json
import platform
import time
import warnings
from pathlib import Path

import numpy as np
import scipy

import pipeline
from benchmarks import _truth
from pipeline import contact
from pipeline import rigid as _rigid
from pipeline._atomic import atomic_path, atomic_write_bytes
from pipeline._json import json_ready
from pipeline.advice import advise, mbf_groups
from pipeline.errors import PipelineWarning
from pipeline.simulate import impact, impact_outcomes, tangential_history

TOL = 1e-3  # advise's default tolerance on e_t
BATCH_BOUND = 2e-5  # impact_outcomes' stated |Δe_t| at its default n_steps
N_STEPS = 400  # impact_outcomes' default
BASE = _truth.BASE_SCENE.replace(e=1.0)
ANGLES = np.linspace(1.0, 89.0, 45)
MUS = np.geomspace(0.01, 1.0, 25)


def _outcomes(scene, **kw):
    """impact_outcomes, with its warnings recorded as flags (NaN outcomes)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", PipelineWarning)
        o = impact_outcomes(scene, **kw)
    return o, [str(w.message) for w in caught if issubclass(w.category, PipelineWarning)]


def _incidence_mu():
    out = {"panels": []}
    for e in (1.0, 0.6):
        A, M = np.meshgrid(ANGLES, MUS)
        sc = BASE.replace(angle_deg=A, mu=M, e=e)
        o, flags = _outcomes(sc)
        rig = _rigid.sphere_on_plane(sc)
        err = np.abs(np.asarray(rig.e_t) - o.e_t)
        _, chi, eta = mbf_groups(BASE.replace(e=e))
        # the advice on a coarser grid
        adv = []
        for a in ANGLES[2::5]:
            for mu in MUS[1::4]:
                ad = advise(BASE.replace(angle_deg=float(a), mu=float(mu), e=e), tol=TOL)
                i, j = int(np.argmin(np.abs(MUS - mu))), int(np.argmin(np.abs(ANGLES - a)))
                adv.append(
                    {
                        "angle_deg": float(a),
                        "mu": float(mu),
                        "model": ad.model,
                        "rigid_error_e_t": ad.errors["e_t"]["rigid"],
                        "map_error_e_t": float(err[i, j]),
                        # rigid wrongly advised where the map shows it off by more than TOL
                        "silent": ad.model == "rigid" and err[i, j] > TOL,
                    }
                )
        out["panels"].append(
            {
                "e": e,
                "normal": "hertz" if e == 1 else "hunt_crossley",
                "abs_delta_e_t": err,
                "rel_delta_omega": np.abs(np.asarray(rig.omega) / o.omega - 1.0),
                "chi": chi,
                "eta": eta,
                # ψ1 = 2η·tan α/μ (no spin): ψ1 = 4χ and ψ1 = 2χ(1+e) as tan α/μ
                "mbf_line_tan_alpha_over_mu": 4.0 * chi / (2.0 * eta),
                "routh_line_tan_alpha_over_mu": 2.0 * chi * (1.0 + e) / (2.0 * eta),
                "batch_flags": flags,
                "advice": adv,
                "silent": sum(a["silent"] for a in adv),
            }
        )
    out["silent"] = sum(p["silent"] for p in out["panels"])
    return out


def _single_et(scene):
    return float(impact(scene, samples=3, rtol=1e-10).attrs["e_t"])


def _restitution():
    es = np.array([0.01, 0.03, 0.1, 0.2, 0.4, 0.6, 0.8, 0.9, 0.95, 0.99, 0.999, 1.0])
    angles = np.array([5.0, 15.0, 25.0, 35.0, 45.0, 60.0, 75.0, 85.0])
    E, A = np.meshgrid(es, angles)
    sc = BASE.replace(angle_deg=A, e=E)
    o, flags = _outcomes(sc)
    rig = _rigid.sphere_on_plane(sc)
    single = np.array([[_single_et(BASE.replace(angle_deg=a, e=e)) for e in es] for a in angles])
    d_batch = np.abs(o.e_t - single)
    return {
        "x": es,
        "y": angles,
        "abs_delta_e_t_rigid": np.abs(np.asarray(rig.e_t) - single),
        "abs_delta_e_t_batch_vs_single": d_batch,
        "batch_flags": flags,
        # silent: the batch path beyond its stated bound and not NaN-flagged
        "silent": int(np.sum((d_batch > BATCH_BOUND) & np.isfinite(o.e_t))),
    }


def _stiffness():
    scales = np.geomspace(1e-3, 1e4, 22)  # 1e0 is on the grid
    angles = np.array([2.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 40.0, 60.0])
    S, A = np.meshgrid(scales, angles)
    sc = BASE.replace(angle_deg=A)
    hi = contact.hertz_impact(sc)
    s0 = np.asarray(sc.v_t0) / hi.v0
    lam = 1.0 + 1.0 / float(sc.kappa)  # m*/m_t for a fixed target
    ktc = (
        8.0 * sc.G_eff * np.sqrt(sc.R_eff * hi.delta_max) * hi.delta_max**2 / (hi.m_eff * hi.v0**2)
    )
    unit = contact.HertzImpact(1.0, 1.25, contact.HERTZ_TC_CONSTANT, 1.25, 1.0, 1.0)

    def e_t(n):
        h = contact.HERTZ_TC_CONSTANT / n
        tau = np.arange(2 * n + 1) * (h / 2)
        tau[-1] = contact.HERTZ_TC_CONSTANT
        p = contact.hertz_pulse(tau, unit)
        q = np.sqrt(np.maximum(p["delta"], 0.0))[:, None] * np.ones(S.size)
        f = p["F"][:, None] * np.ones(S.size)
        th = tangential_history(q, f, h, s0.ravel(), lam, float(sc.mu), (S * ktc).ravel())
        return (1.0 - th.p[-1] / s0.ravel()).reshape(S.shape)

    et_n, et_ref = e_t(N_STEPS), e_t(16 * N_STEPS)
    rig = np.asarray(_rigid.sphere_on_plane(sc).e_t)
    # tangential natural frequency of the stuck contact at maximum compression, times the step
    omega_h = np.sqrt(lam * S * ktc) * contact.HERTZ_TC_CONSTANT / N_STEPS
    d_batch = np.abs(et_n - et_ref)
    beyond = d_batch > BATCH_BOUND
    return {
        "x": scales,
        "y": angles,
        "abs_delta_e_t_rigid": np.abs(rig - et_ref),
        "abs_delta_e_t_batch_vs_converged": d_batch,
        "omega_t_h": omega_h,
        # the stated bound is impact_outcomes' at the physical stiffness (scale 1), where it
        # holds; tangential_history with a scaled k_t (the contact fits' kt_scale) states
        # none and flags nothing: beyond the bound there, unflagged (a simulator change,
        # docs/stability.md)
        "silent": int(np.sum(beyond & (S == 1.0))),
        "unflagged_beyond_bound_scaled_kt": int(np.sum(beyond)),
        "largest_resolved_omega_t_h": float(np.min(np.where(beyond, omega_h, np.inf))),
    }


def _grazing():
    angles = np.array([0.01, 0.1, 1.0, 5.0, 30.0, 60.0, 85.0, 89.0, 89.9, 89.99])
    mus = np.array([0.05, 0.131, 0.3, 1.0])
    A, M = np.meshgrid(angles, mus)
    sc = BASE.replace(angle_deg=A, mu=M)
    o, flags = _outcomes(sc)
    rig = _rigid.sphere_on_plane(sc)
    single = np.array(
        [[_single_et(BASE.replace(angle_deg=a, mu=mu)) for a in angles] for mu in mus]
    )
    d_batch = np.abs(o.e_t - single)
    return {
        "x": angles,
        "y": mus,
        "abs_delta_e_t_rigid": np.abs(np.asarray(rig.e_t) - single),
        "abs_delta_e_t_batch_vs_single": d_batch,
        "t_contact_over_hertz_90deg": o.t_contact
        / contact.hertz_impact(BASE.replace(angle_deg=0.0)).t_c,
        "batch_flags": flags,
        "silent": int(np.sum((d_batch > BATCH_BOUND) & np.isfinite(o.e_t))),
    }


def _rod():
    thetas = np.linspace(5.0, 85.0, 33)
    mus = np.linspace(0.0, 1.5, 31)
    T, M = np.meshgrid(thetas, mus)
    out = {"x": thetas, "y": mus}
    KE0 = 0.5 * (0.3**2 + 1.0**2)  # m = 1 kg, ω = 0
    silent = 0
    for law in _rigid.LAWS:
        Ws, vts, vns = [], [], []
        for th in thetas:
            rod = _rigid.slender_rod_contact(1.0, 1.0, np.radians(th), (0.3, -1.0))
            Ws.append(rod.W)
            vts.append(rod.v_t0)
            vns.append(rod.v_n0)
        W = np.broadcast_to(np.array(Ws), M.shape + (2, 2))
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", PipelineWarning)
            r = _rigid.planar_impact(W, np.array(vts)[None, :], np.array(vns)[None, :], M, 0.9, law)
        warned = any(issubclass(w.category, _rigid.EnergyGainWarning) for w in caught)
        gain = np.asarray(r.dKE) > 1e-9 * KE0
        # every energy-creating impact must be flagged (the flag and the warning)
        silent += int(np.sum(gain & ~np.asarray(r.energy_gain))) + int(gain.any() and not warned)
        out[f"dKE_over_KE0_{law}"] = np.asarray(r.dKE) / KE0
        out[f"energy_gain_{law}"] = np.asarray(r.energy_gain)
        out[f"warned_{law}"] = warned
    out["silent"] = silent
    return out


CAPS = np.array([0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0])
CAP_SPEED = 2.0
CAP_NORMAL = "hertz_dashpot_secant"  # LAMMPS's law: the replay runs the same contact


def _curved():
    from pipeline.simulate.curved import geometry_error, turning_outcomes
    from pipeline.simulate.lammps import lammps_version, run_lammps

    base = BASE.replace(speed=CAP_SPEED, e=0.9, target_E=np.inf)  # rigid, as LAMMPS's wall
    angles = np.array([5.0, 15.0, 30.0, 45.0, 60.0, 70.0, 75.0, 80.0, 85.0])
    speeds = np.array([0.3, 0.6, 1.0, 2.0, 3.0, 5.0])

    def grid(scenes):
        g = [[geometry_error(s, normal=CAP_NORMAL, tol=TOL) for s in row] for row in scenes]
        return {k: np.array([[d[k] for d in row] for row in g]) for k in ("e_n", "e_t", "theta")}

    by_angle = grid([[base.replace(angle_deg=a, target_radius=r) for a in angles] for r in CAPS])
    by_speed = grid(
        [[base.replace(speed=v, angle_deg=75.0, target_radius=r) for v in speeds] for r in CAPS]
    )
    # advise on a coarser grid: every cell beyond the tolerance must be named in its reason
    silent, checked = 0, 0
    for r in CAPS[::2]:
        for a in angles[::2]:
            adv = advise(base.replace(angle_deg=a, target_radius=r), tol=TOL)
            beyond = max(adv.geometry["e_n"], adv.geometry["e_t"]) > TOL
            silent += int(beyond and "turning_outcomes" not in adv.reason)
            checked += 1
    replay = []
    if lammps_version() is not None:
        cells = [(a, r) for a in (45.0, 75.0, 85.0) for r in (0.02, 0.1)]
        scenes = [base.replace(angle_deg=a, target_radius=r) for a, r in cells]
        lmp = run_lammps(scenes, dt=1e-8)
        for i, (sc, (a, r)) in enumerate(zip(scenes, cells, strict=True)):
            o = turning_outcomes(sc, CAP_NORMAL)
            replay.append(
                {
                    "angle_deg": a,
                    "cap_m": r,
                    "lammps_e_n": float(lmp.e_n[i]),
                    "turning_minus_lammps_e_n": o["turning"]["e_n"] - float(lmp.e_n[i]),
                    "held_minus_lammps_e_n": o["fixed"]["e_n"] - float(lmp.e_n[i]),
                    "turning_minus_lammps_e_t": o["turning"]["e_t"] - float(lmp.e_t[i]),
                    "held_minus_lammps_e_t": o["fixed"]["e_t"] - float(lmp.e_t[i]),
                }
            )
    return {
        "x": angles,
        "y": CAPS,
        "speeds": speeds,
        "abs_delta_e_n": by_angle["e_n"],
        "abs_delta_e_t": by_angle["e_t"],
        "theta": by_angle["theta"],
        "abs_delta_e_n_by_speed": by_speed["e_n"],
        "lammps": replay,
        "lammps_version": lammps_version(),
        "advise_checked": checked,
        "silent": silent,
    }


MAPS = {
    "incidence_mu": _incidence_mu,
    "restitution": _restitution,
    "tangential_stiffness": _stiffness,
    "grazing": _grazing,
    "curved_target": _curved,
    "rod_paradox": _rod,
}


def run(out_dir: Path) -> dict:
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    maps = {}
    for name, fn in MAPS.items():
        t0 = time.perf_counter()
        maps[name] = fn()
        maps[name]["seconds"] = time.perf_counter() - t0
        PLOTS[name](maps[name], out_dir / f"stability_physics_{name}.png")
    report = {
        "benchmark": "stability_physics",
        "material": BASE.to_dict(),
        "tolerance_e_t": TOL,
        "batch_stated_bound_e_t": BATCH_BOUND,
        "silent_cells": sum(int(m["silent"]) for m in maps.values()),
        "machine": {
            "python": platform.python_version(),
            "platform": platform.platform(),
            "numpy": np.__version__,
            "scipy": scipy.__version__,
            "pipeline": pipeline.__version__,
        },
        "maps": maps,
    }
    atomic_write_bytes(
        out_dir / "stability_physics.json", json.dumps(json_ready(report), indent=1).encode()
    )
    return report


# ------------------------------------------------------------------ charts
def _logmesh(ax, fig, x, y, z, label, vmin=-8, vmax=0):
    im = ax.pcolormesh(
        x,
        y,
        np.log10(np.clip(z, 10.0**vmin, None)),
        vmin=vmin,
        vmax=vmax,
        cmap="viridis",
        shading="nearest",
    )
    fig.colorbar(im, ax=ax, label=label)
    return im


def _plot_incidence_mu(m, path):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(13.0, 5.2), layout="constrained")
    for ax, p in zip(fig.subplots(1, 2), m["panels"], strict=True):
        _logmesh(ax, fig, ANGLES, MUS, p["abs_delta_e_t"], "log10 |e_t(rigid) − e_t(Mindlin)|")
        ax.contour(
            ANGLES,
            MUS,
            np.log10(np.maximum(p["abs_delta_e_t"], 1e-12)),
            levels=[np.log10(TOL)],
            colors="w",
            linewidths=1.5,
        )
        tt = np.tan(np.radians(ANGLES))
        ax.plot(
            ANGLES,
            tt / p["routh_line_tan_alpha_over_mu"],
            "r--",
            lw=1.5,
            label="Routh: sliding throughout below (ψ1 = 2χ(1+e))",
        )
        ax.plot(
            ANGLES,
            tt / p["mbf_line_tan_alpha_over_mu"],
            "k:",
            lw=1.5,
            label="Maw–Barber–Fawcett ψ1 = 4χ (compliance matters above)",
        )
        for a in p["advice"]:
            ax.text(
                a["angle_deg"],
                a["mu"],
                a["model"][0].upper(),
                ha="center",
                va="center",
                fontsize=7,
                color="r" if a["silent"] else "w",
                weight="bold",
            )
        ax.set_yscale("log")
        ax.set_ylim(MUS[0], MUS[-1])
        ax.set_xlabel("incidence α [deg]")
        ax.set_ylabel("μ")
        ax.set_title(
            f"e = {p['e']:g} ({p['normal']}): white line |Δe_t| = {TOL:g}\n"
            "letters: advise(tol=1e-3) → R rigid, M mindlin",
            fontsize=9,
        )
        ax.text(25, 0.35, "compliance dominates:\nrigid theory off", fontsize=9, ha="center")
        ax.text(
            65, 0.02, "sliding throughout:\nrigid theory exact", color="w", fontsize=9, ha="center"
        )
        ax.legend(fontsize=7, loc="upper left")
    fig.suptitle(
        "Physics stability map — incidence × μ: where rigid theory is off against "
        "Hertz–Mindlin (steel ball, R = 12.7 mm, 0.6 m/s)"
    )
    _save(fig, path)


def _plot_restitution(m, path):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(13.0, 4.8), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    xi = np.arange(len(m["x"]))
    _logmesh(ax1, fig, xi, m["y"], m["abs_delta_e_t_rigid"], "log10 |Δe_t| rigid vs Mindlin")
    _logmesh(
        ax2,
        fig,
        xi,
        m["y"],
        m["abs_delta_e_t_batch_vs_single"],
        "log10 |Δe_t| batch (400 steps) vs adaptive",
        vmin=-10,
        vmax=-2,
    )
    for ax in (ax1, ax2):
        ax.set_xticks(xi, [f"{v:g}" for v in m["x"]], rotation=40, fontsize=7)
        ax.set_xlabel("restitution e (Hunt–Crossley; Hertz at 1)")
        ax.set_ylabel("incidence α [deg]")
    ax1.set_title(
        "rigid theory vs Hertz–Mindlin; e → 0: damping-dominated contact,\n"
        "the Mindlin spring never reaches the Coulomb cap",
        fontsize=9,
    )
    ax2.set_title(
        f"simulator: batch vs single path (stated bound {BATCH_BOUND:g}); "
        f"silent cells: {m['silent']}",
        fontsize=9,
    )
    fig.suptitle("Physics stability map — e → 0 and e → 1")
    _save(fig, path)


def _plot_stiffness(m, path):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(13.0, 4.8), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    _logmesh(ax1, fig, m["x"], m["y"], m["abs_delta_e_t_rigid"], "log10 |Δe_t| rigid vs Mindlin")
    _logmesh(
        ax2,
        fig,
        m["x"],
        m["y"],
        m["abs_delta_e_t_batch_vs_converged"],
        f"log10 |Δe_t| {N_STEPS} vs {16 * N_STEPS} steps",
        vmin=-10,
        vmax=-2,
    )
    ax2.contour(m["x"], m["y"], m["omega_t_h"], levels=[0.5, 1.0, 2.0], colors="w", linewidths=0.8)
    for ax in (ax1, ax2):
        ax.set_xscale("log")
        ax.axvline(1.0, color="r", lw=0.8, ls="--")
        ax.set_xlabel("k_t / (8·G*·a)  (1: Mindlin)")
        ax.set_ylabel("incidence α [deg]")
    ax1.set_title(
        "soft tangential contact: rigid theory off; stiff: it tends to Coulomb", fontsize=9
    )
    ax2.set_title(
        f"batch RK4 step vs the tangential period (white: ω_t·h = 0.5, 1, 2): beyond "
        f"{BATCH_BOUND:g} from ω_t·h ≈ {m['largest_resolved_omega_t_h']:.2g}\n"
        f"(k_t ≫ Mindlin's, only via tangential_history's kt_coef: unflagged there)",
        fontsize=9,
    )
    fig.suptitle("Physics stability map — very soft and very stiff tangential contact (e = 1)")
    _save(fig, path)


def _plot_grazing(m, path):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(13.0, 4.2), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    xi = np.arange(len(m["x"]))
    yi = np.arange(len(m["y"]))
    _logmesh(ax1, fig, xi, yi, m["abs_delta_e_t_rigid"], "log10 |Δe_t| rigid vs Mindlin")
    _logmesh(
        ax2,
        fig,
        xi,
        yi,
        m["abs_delta_e_t_batch_vs_single"],
        "log10 |Δe_t| batch vs adaptive",
        vmin=-12,
        vmax=-2,
    )
    for ax in (ax1, ax2):
        ax.set_xticks(xi, [f"{v:g}" for v in m["x"]], fontsize=7)
        ax.set_yticks(yi, [f"{v:g}" for v in m["y"]], fontsize=7)
        ax.set_xlabel("incidence α [deg] (near-normal … grazing)")
        ax.set_ylabel("μ")
    ax1.set_title(
        "near-normal: compliance dominates (e_t ≈ 1 from tangential recoil);\n"
        "grazing: slides throughout, rigid exact",
        fontsize=9,
    )
    ax2.set_title(f"simulator paths agree; silent cells: {m['silent']}", fontsize=9)
    fig.suptitle("Physics stability map — near-normal to grazing incidence (e = 1)")
    _save(fig, path)


def _plot_curved(m, path):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(15.0, 4.6), layout="constrained")
    axes = fig.subplots(1, 3)
    xi, yi, si = (np.arange(len(m[k])) for k in ("x", "y", "speeds"))
    panels = [
        (axes[0], xi, m["abs_delta_e_n"], "|Δe_n|", m["x"], "incidence α [deg]"),
        (axes[1], xi, m["abs_delta_e_t"], "|Δe_t|", m["x"], "incidence α [deg]"),
        (axes[2], si, m["abs_delta_e_n_by_speed"], "|Δe_n| at 75°", m["speeds"], "speed [m/s]"),
    ]
    for ax, x, z, label, ticks, xlabel in panels:
        _logmesh(ax, fig, x, yi, z, f"log10 {label}", vmin=-7, vmax=-1)
        ax.contour(x, yi, np.log10(np.clip(z, 1e-12, None)), levels=[np.log10(TOL)], colors="w")
        ax.set_xticks(x, [f"{v:g}" for v in ticks], fontsize=7)
        ax.set_yticks(yi, [f"{v * 1e3:g}" for v in m["y"]], fontsize=7)
        ax.set_xlabel(xlabel)
        ax.set_ylabel("cap radius R_cap [mm]")
    for row in m["lammps"]:
        i = int(np.argmin(np.abs(m["x"] - row["angle_deg"])))
        j = int(np.argmin(np.abs(m["y"] - row["cap_m"])))
        axes[0].plot(i, j, "o", mfc="none", mec="w", ms=9)
        axes[0].annotate(
            f"{row['turning_minus_lammps_e_n']:+.0e}\n{row['held_minus_lammps_e_n']:+.0e}",
            (i, j + 0.22),
            fontsize=6,
            color="w",
            ha="center",
        )
    axes[0].set_title(
        f"e_n at {CAP_SPEED:g} m/s, turning normal vs held frame (dashed: {TOL:g});\n"
        "circles: LAMMPS replays, turning − LAMMPS over held − LAMMPS",
        fontsize=9,
    )
    axes[1].set_title("e_t: the same", fontsize=9)
    axes[2].set_title("grows as v_t² and as t_c/(R + R_cap)", fontsize=9)
    fig.suptitle(
        "Physics stability map — a steel ball on a rigid fixed cap (μ 0.131, e 0.9): where "
        f"holding the first contact's frame fails; advise silent in {m['silent']} of "
        f"{m['advise_checked']} cells checked"
    )
    _save(fig, path)


def _plot_rod(m, path):
    from matplotlib.colors import TwoSlopeNorm
    from matplotlib.figure import Figure

    fig = Figure(figsize=(15.0, 4.6), layout="constrained")
    axes = fig.subplots(1, 3)
    norm = TwoSlopeNorm(vcenter=0.0, vmin=-0.3, vmax=0.3)
    for ax, law in zip(axes, _rigid.LAWS, strict=True):
        im = ax.pcolormesh(
            m["x"], m["y"], m[f"dKE_over_KE0_{law}"], cmap="RdBu_r", norm=norm, shading="nearest"
        )
        gain = m[f"energy_gain_{law}"]
        if np.any(gain):
            ax.contour(m["x"], m["y"], gain.astype(float), levels=[0.5], colors="k")
            ax.text(
                0.5,
                0.9,
                "Kane's paradox:\nenergy created (flagged)",
                transform=ax.transAxes,
                ha="center",
                va="top",
                fontsize=8,
            )
        ax.set_title(f"law = {law}: ΔKE/KE0", fontsize=9)
        ax.set_xlabel("rod angle to the ground θ [deg]")
        ax.set_ylabel("μ")
    fig.colorbar(im, ax=axes, label="ΔKE / KE0 (> 0: energy created)")
    fig.suptitle(
        "Physics stability map — the slender rod's energy paradox (e = 0.9, "
        f"v_G = (0.3, −1.0) m/s); silent (unflagged) gains: {m['silent']}"
    )
    _save(fig, path)


def _save(fig, path):
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")


PLOTS = {
    "incidence_mu": _plot_incidence_mu,
    "restitution": _plot_restitution,
    "tangential_stiffness": _plot_stiffness,
    "grazing": _plot_grazing,
    "curved_target": _plot_curved,
    "rod_paradox": _plot_rod,
}


if __name__ == "__main__":
    import sys

    out = run(Path(sys.argv[1] if len(sys.argv) > 1 else "build/bench"))
    print({k: (v["silent"], round(v["seconds"], 1)) for k, v in out["maps"].items()})
