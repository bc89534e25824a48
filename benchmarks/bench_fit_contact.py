"""Contact-parameter fits: fit time against fitted-value error, recovery, coverage.

Records: :func:`pipeline.simulate.impact` (Hunt–Crossley e = 0.9, Mindlin, total history)
through :func:`pipeline.sensor_model.to_sensor` (2 MHz, 300 kHz 2nd-order Butterworth,
±2 % cross-talk, offsets, drift, 16-bit ADC; the noise as stated) for the Garland–Rogers-style
scene of the seed's 15° record (25.4 mm steel ball on a 25.4 mm steel cap, 0.6 m/s,
μ = 0.131) — never by a fitter's own forward model.

1. **Pareto chart** (issue 9's chart family 3) — ``fit_contact.png``: time per record
   (CPU time of this process, median of repeats) against the error of E*, e and μ, for

   - the master-curve fitter :func:`pipeline.fit_contact` at several ``n_steps`` (the
     tangential model solved piecewise), and with the simulator's batch path
     (:func:`pipeline.simulate.tangential_history`, RK4) as its tangential solver;
   - the same with the default 200-replicate block bootstrap (the default setting, marked);
   - lmfit with ``solve_ivp`` in the residual: :func:`pipeline.simulate.impact` at several
     tolerances, the same samples, weights, sensor model (filter, cross-talk) and starting
     values, lmfit's finite-difference Levenberg–Marquardt; and its bootstrap (refits of
     ``N_BOOT_ODE`` replicates timed, scaled to 200).

   Both fitters vary E*, e, μ and t0 (``kt_scale`` fixed at its true 1: the simulator has
   no such option). Errors: on a noise-free sensor record (the method's own error, hollow
   markers; 1 mN of noise, ~1e-6 of F_max) and the RMS error over the same ``N_REP``
   noisy replicates at 0.4 % of F_max (filled). The speed ratios (``speedups``) are taken at
   equal accuracy on those replicates.
2. **Recovery** — ``fit_contact_recovery.png``: RMS error of E*, e, μ against the noise
   level (at 2 MHz) and the sampling rate (at 0.4 % noise), the issue's targets dashed.
3. **Coverage** — ``fit_contact_coverage.png``: over ``N_COVER`` noisy replicates (0.4 %)
   of a sliding 45° scene and of the 15° scene, how often the 95 % intervals (covariance
   and block bootstrap) cover the truth; target 90–98 %.

Writes ``fit_contact.json`` with every number, and the three PNGs.
"""

from __future__ import annotations

import json
import math
import platform
import time
import warnings
from pathlib import Path

import numpy as np

from pipeline import Scene
from pipeline._atomic import atomic_path, atomic_write_bytes
from pipeline.errors import PipelineWarning
from pipeline.fit import fit_contact
from pipeline.fit.contact import _start, fit_model
from pipeline.fit.forward import ForwardModel, prepare
from pipeline.sensor_model import to_sensor
from pipeline.simulate import impact

from ._truth import GR_RIG as GR

SCENE = Scene(**GR, speed=0.6, angle_deg=15.0, mu=0.131, e=0.9)
SLIDING = Scene(**GR, speed=0.6, angle_deg=45.0, mu=0.10, e=0.9)  # slides throughout
NOISE = 0.004  # of F_max
VARY4 = ("E_eff", "e", "mu", "t0")
N_STEPS = (32, 64, 128, 256)
RK4_STEPS = (128, 256, 512)
ODE_RTOLS = (1e-5, 1e-7, 1e-9)
ODE_SAMPLES = 600
N_REP = 10  # noisy replicates, the same for every method
N_BOOT_ODE = 10
N_COVER = 200
NOISE_LEVELS = (0.001, 0.002, 0.004, 0.01, 0.02, 0.04)
RATES = (0.25e6, 0.5e6, 1e6, 2e6, 4e6, 8e6)
N_RECOVERY = 12
TARGETS = {"E_eff": 0.01, "e": 0.005, "mu": 0.02}


def _quiet(fn, *args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)
        return fn(*args, **kw)


def _cpu(fn, repeat=1):
    """Median CPU time [s] of ``fn()`` over ``repeat`` calls, and its last result."""
    times, out = [], None
    for _ in range(repeat):
        t = time.process_time()
        out = fn()
        times.append(time.process_time() - t)
    return float(np.median(times)), out


def _errors(values, scene):
    return {
        "E_eff": abs(values["E_eff"] / scene.E_eff - 1.0),
        "e": abs(values["e"] - scene.e),
        "mu": abs(values["mu"] / scene.mu - 1.0),
    }


def _rms(errs):
    return {k: float(np.sqrt(np.mean([e[k] ** 2 for e in errs]))) for k in errs[0]}


# ----------------------------------------------------------------- ODE in the loop
def ode_fit(record, scene, rtol, *, n_boot=0, seed=0):
    """lmfit with simulate.impact in the residual: the same data, weights, sensor model and
    starting values as fit_contact, E*, e, μ, t0 varied (finite-difference LM)."""
    import lmfit
    from scipy.signal import sosfilt

    data = prepare(record, scene)
    s0 = _start(data, ForwardModel(), float(scene.speed))
    C = data.sensor.crosstalk if data.sensor.crosstalk is not None else np.eye(3)
    grid = data.fine if data.sos is not None else data.channels[0].t
    n0 = data.channels[0].t.size

    def model(p):
        k = p["E_eff"] / scene.E_eff  # scale both moduli: E* with G*/E* unchanged
        sc = scene.replace(E=scene.E * k, target_E=scene.target_E * k, e=p["e"], mu=p["mu"])
        sim = impact(sc, normal="hunt_crossley", rtol=rtol, samples=ODE_SAMPLES)
        tt = sim.time.values + p["t0"]
        fn = np.interp(grid, tt, sim.Fn.values, left=0.0, right=0.0)
        ft = np.interp(grid, tt, sim.Ft.values, left=0.0, right=0.0)
        m = np.stack([C[0, 0] * fn + C[0, 1] * ft, C[1, 0] * fn + C[1, 1] * ft])
        if data.sos is None:  # an unfiltered sensor: the samples' own grid
            return m
        return sosfilt(data.sos, m, axis=-1)[:, :: data.oversample]

    def residual(params, target):
        # the same weighted residuals as fit_contact, the baseline fitted alike
        m = model(params.valuesdict())
        return np.concatenate(
            [
                c.project((yc - mc) / c.sigma)
                for c, yc, mc in zip(data.channels, target, m, strict=True)
            ]
        )

    y = [c.y for c in data.channels]

    params = lmfit.Parameters()
    params.add("E_eff", s0["E_eff"], min=s0["E_eff"] / 20, max=s0["E_eff"] * 20)
    params.add("e", s0["e"], min=0.1, max=1.0)
    params.add("mu", s0["mu"], min=0.0)
    params.add(
        "t0",
        s0["t0"],
        min=data.channels[0].t[0],
        max=data.window.t_start + 0.5 * data.window.duration,
    )
    res = lmfit.minimize(residual, params, args=(y,))
    values = {k: res.params[k].value for k in VARY4}
    boot = []
    if n_boot:
        rng = np.random.default_rng(seed)
        best = model(values)
        r = [res.residual[:n0], res.residual[n0:]]
        for _ in range(n_boot):
            ystar = [
                b + c.sigma * rc[rng.integers(0, rc.size, rc.size)]
                for b, c, rc in zip(best, data.channels, r, strict=True)
            ]
            rb = lmfit.minimize(residual, res.params.copy(), args=(ystar,))
            boot.append([rb.params[k].value for k in VARY4])
    return values, res, np.array(boot)


# ----------------------------------------------------------------- 1. Pareto
def _pareto():
    ideal = impact(SCENE, normal="hunt_crossley", samples=2001)
    F_max = ideal.attrs["F_max"]
    clean = to_sensor(ideal, noise=1e-3, bits=None, seed=1)  # 1 mN: ~1e-6 of F_max
    noisy = [to_sensor(ideal, noise=NOISE * F_max, seed=100 + i) for i in range(N_REP)]
    methods = []

    def ours(label, rep_time=5, **kw):
        # like for like with the ODE fitter: the inputs exact, no verdict (its other laws)
        opts = dict(n_boot=0, vary=VARY4, systematics={}, diagnose=False, **kw)
        t, fit = _cpu(lambda: _quiet(fit_contact, noisy[0], SCENE, **opts), rep_time)
        clean_fit = _quiet(fit_contact, clean, SCENE, **{**opts, "n_boot": 0})
        errs = [
            _errors(_quiet(fit_contact, r, SCENE, **{**opts, "n_boot": 0}).values, SCENE)
            for r in noisy
        ]
        methods.append(
            {
                "method": label,
                "time_s": t,
                "error_noise_free": _errors(clean_fit.values, SCENE),
                "rms_error_noisy": _rms(errs),
                "stderr": {k: fit.stderr[k] for k in ("E_eff", "e", "mu")},
            }
        )

    for n in N_STEPS:
        ours(f"master curve, n_steps={n}", n_steps=n)

    def rk4(n):
        m = ForwardModel("hunt_crossley", "mindlin", "total", n, solver="rk4")
        return lambda r, **kw: _quiet(fit_model, r, SCENE, m, VARY4, systematics={}, **kw)

    for n in RK4_STEPS:
        f = rk4(n)
        t, _ = _cpu(lambda f=f: f(noisy[0], n_boot=0), 3)
        clean_fit = f(clean, n_boot=0)
        errs = [_errors(f(r, n_boot=0).values, SCENE) for r in noisy]
        methods.append(
            {
                "method": "master curve, RK4 tangential (simulate.tangential_history), "
                f"n_steps={n}",
                "time_s": t,
                "error_noise_free": _errors(clean_fit.values, SCENE),
                "rms_error_noisy": _rms(errs),
            }
        )
    base = next(m for m in methods if m["method"] == "master curve, n_steps=128")
    exact = dict(vary=VARY4, systematics={}, diagnose=False)
    t, _ = _cpu(lambda: _quiet(fit_contact, noisy[0], SCENE, n_boot=200, **exact), 5)
    methods.append(
        {
            "method": "master curve + block bootstrap (200), n_steps=128 [default intervals]",
            "time_s": t,
            "error_noise_free": base["error_noise_free"],
            "rms_error_noisy": base["rms_error_noisy"],
            "default": True,
        }
    )
    # the replicates refitted by iterated Gauss–Newton steps, one vectorised model call per
    # iteration (the bootstrap of old), in the same run
    import pipeline.fit.procedure as procedure

    linear = procedure.block_bootstrap
    procedure.block_bootstrap = lambda *a, **k: linear(*a, **{**k, "iters": 4})
    try:
        t_old, _ = _cpu(lambda: _quiet(fit_contact, noisy[0], SCENE, n_boot=200, **exact), 3)
    finally:
        procedure.block_bootstrap = linear
    t_budget, _ = _cpu(lambda: _quiet(fit_contact, noisy[0], SCENE, n_boot=200, vary=VARY4), 3)
    methods.append(
        {
            "method": "master curve + iterated bootstrap refits (200, the old default)",
            "time_s": t_old,
            "error_noise_free": base["error_noise_free"],
            "rms_error_noisy": base["rms_error_noisy"],
            "old_default": True,
        }
    )
    methods.append(
        {
            "method": "master curve + default budget (systematics, verdict's laws) + "
            "bootstrap (200)",
            "time_s": t_budget,
            "error_noise_free": base["error_noise_free"],
            "rms_error_noisy": base["rms_error_noisy"],
            "budget": True,
        }
    )
    for rtol in ODE_RTOLS:
        t, (vals, res, _) = _cpu(lambda rtol=rtol: _quiet(ode_fit, noisy[0], SCENE, rtol), 1)
        clean_vals = _quiet(ode_fit, clean, SCENE, rtol)[0]
        errs = [_errors(_quiet(ode_fit, r, SCENE, rtol)[0], SCENE) for r in noisy]
        methods.append(
            {
                "method": f"lmfit + solve_ivp (simulate.impact), rtol={rtol:g}",
                "time_s": t,
                "nfev": int(res.nfev),
                "error_noise_free": _errors(clean_vals, SCENE),
                "rms_error_noisy": _rms(errs),
                "rtol": rtol,
            }
        )
    # the ODE fitter's bootstrap: refits of N_BOOT_ODE replicates, scaled to 200
    t_fit = next(m for m in methods if m.get("rtol") == 1e-7)["time_s"]
    t_all, _ = _cpu(lambda: _quiet(ode_fit, noisy[0], SCENE, 1e-7, n_boot=N_BOOT_ODE), 1)
    per_rep = (t_all - t_fit) / N_BOOT_ODE
    ode_boot = next(m for m in methods if m.get("rtol") == 1e-7)
    methods.append(
        {
            "method": "lmfit + solve_ivp, rtol=1e-07, + bootstrap (200; "
            f"{N_BOOT_ODE} timed, scaled)",
            "time_s": t_fit + 200 * per_rep,
            "error_noise_free": ode_boot["error_noise_free"],
            "rms_error_noisy": ode_boot["rms_error_noisy"],
            "rtol": 1e-7,
            "bootstrap": True,
        }
    )
    return methods, F_max


def _costs(methods) -> dict:
    """The interval's and the budget's costs against the point fit's, measured in one run:
    issue 16 asks intervals ≤ 5× the point fit, issue 15 a fit with the default budget ≤ 3×
    the old default (the point fit with the iterated bootstrap refits)."""
    point = next(m for m in methods if m["method"] == "master curve, n_steps=128")["time_s"]
    boot = next(m for m in methods if m.get("default"))["time_s"]
    old = next(m for m in methods if m.get("old_default"))["time_s"]
    budget = next(m for m in methods if m.get("budget"))["time_s"]
    return {
        "point_fit_s": point,
        "with_bootstrap_s": boot,
        "intervals_over_point_fit": boot / point,
        "old_bootstrap_s": old,
        "default_budget_s": budget,
        "budget_over_old_default": budget / old,
    }


def _ratios(methods):
    """Speed ratios of the ODE fitter's time over the master curve's (n_steps 128; with the
    bootstrap: the default setting), and whether the master curve is as accurate: its RMS
    errors of E*, e and μ over the same noisy replicates within 5 % of the ODE fitter's (or
    below). On the near noise-free record the ODE fitter runs the very solver that made the
    data, so its own error there is its interpolation's; the master curve's, ~1e-5, is two
    orders under the errors any noise gives (both are in the JSON)."""
    ours = next(m for m in methods if m["method"] == "master curve, n_steps=128")
    ours_b = next(m for m in methods if m.get("default"))
    out = {}
    for m in methods:
        if "rtol" not in m:
            continue
        acc = all(
            ours["rms_error_noisy"][k] <= 1.05 * m["rms_error_noisy"][k]
            for k in ("E_eff", "e", "mu")
        )
        ref = ours_b if m.get("bootstrap") else ours
        out[m["method"]] = {
            "speedup": m["time_s"] / ref["time_s"],
            "against": ref["method"],
            "equal_or_better_accuracy": bool(acc),
        }
    return out


# ----------------------------------------------------------------- 2. recovery
def _recovery(F_max):
    ideal = impact(SCENE, normal="hunt_crossley", samples=4001)
    rows = []
    for kind, values in (("noise", NOISE_LEVELS), ("rate", RATES)):
        for v in values:
            noise, rate = (v, 2e6) if kind == "noise" else (NOISE, v)
            errs, ses = [], []
            for i in range(N_RECOVERY):
                rec = to_sensor(ideal, noise=noise * F_max, rate=rate, seed=500 + i)
                fit = _quiet(fit_contact, rec, SCENE, n_boot=0, systematics={}, diagnose=False)
                errs.append(_errors(fit.values, SCENE))
                ses.append([fit.stderr[k] for k in ("E_eff", "e", "mu")])
            rows.append(
                {
                    "axis": kind,
                    "noise_of_F_max": noise,
                    "rate_Hz": rate,
                    "samples_per_contact": ideal.attrs["t_contact"] * rate,
                    "rms_error": _rms(errs),
                    "median_stderr": dict(
                        zip(("E_eff", "e", "mu"), np.median(ses, axis=0).tolist(), strict=True)
                    ),
                }
            )
    return rows


# ----------------------------------------------------------------- 3. coverage
def _coverage():
    out = {}
    for label, scene in (("sliding 45°", SLIDING), ("15° (sticking regime)", SCENE)):
        ideal = impact(scene, normal="hunt_crossley", samples=2001)
        F_max = ideal.attrs["F_max"]
        truth = {"E_eff": scene.E_eff, "e": scene.e, "mu": scene.mu}
        hits = {m: {k: 0 for k in truth} for m in ("covariance", "bootstrap")}
        n = 0
        for i in range(N_COVER):
            rec = to_sensor(ideal, noise=NOISE * F_max, seed=10_000 + i)
            # the data's intervals (inputs exact): the bootstrap and the covariance judged
            fit = _quiet(
                fit_contact, rec, scene, n_boot=200, seed=i, systematics={}, diagnose=False
            )
            n += 1
            for m in hits:
                ci = fit.ci(0.95, method=m)
                for k, v in truth.items():
                    hits[m][k] += int(ci[k][0] <= v <= ci[k][1])
        out[label] = {
            "replicates": n,
            "coverage": {m: {k: h / n for k, h in hs.items()} for m, hs in hits.items()},
            "wilson_95": {m: {k: _wilson(h, n) for k, h in hs.items()} for m, hs in hits.items()},
            "regime": fit.physics["regime"],
        }
    return out


def _wilson(k, n, z=1.96):
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return [c - h, c + h]


# ----------------------------------------------------------------- run
def run(out_dir: Path) -> dict:
    import lmfit
    import scipy

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    _quiet(fit_contact, to_sensor(impact(SCENE), seed=0), SCENE, n_boot=0)  # tables built
    methods, F_max = _pareto()
    result = {
        "scene": SCENE.to_dict(),
        "noise_of_F_max": NOISE,
        "timing": "CPU time of this process (time.process_time), median of repeats; "
        "single-threaded (OPENBLAS_NUM_THREADS=1)",
        "peers": {
            "lmfit": lmfit.__version__,
            "scipy": scipy.__version__,
            "numpy": np.__version__,
            "python": platform.python_version(),
            "ode_in_the_loop": f"pipeline.simulate.impact (scipy.integrate.solve_ivp DOP853), "
            f"{ODE_SAMPLES} samples",
        },
        "methods": methods,
        "speedups": _ratios(methods),
        "costs": _costs(methods),
        "recovery": _recovery(F_max),
        "recovery_targets": TARGETS,
        "coverage": _coverage(),
    }
    atomic_write_bytes(out_dir / "fit_contact.json", json.dumps(result, indent=1).encode())
    _plot_pareto(out_dir / "fit_contact.png", result)
    _plot_recovery(out_dir / "fit_contact_recovery.png", result)
    _plot_coverage(out_dir / "fit_contact_coverage.png", result)
    return result


_LABELS = {"E_eff": "E* (relative)", "e": "e (absolute)", "mu": "μ (relative)"}


def _family(m):
    name = m["method"]
    if name.startswith("lmfit"):
        return "lmfit + solve_ivp in the residual", "tab:gray", "s"
    if "RK4" in name:
        return "master curve, RK4 tangential (batch path)", "tab:blue", "^"
    return "master curve (pipeline.fit_contact)", "tab:green", "o"


def _plot_pareto(path, result):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10.5, 3.9), layout="constrained")
    axes = fig.subplots(1, 3)
    for ax, k in zip(axes, ("E_eff", "e", "mu"), strict=True):
        for fam in (
            "master curve (pipeline.fit_contact)",
            "master curve, RK4 tangential (batch path)",
            "lmfit + solve_ivp in the residual",
        ):
            ms = [
                m
                for m in result["methods"]
                if _family(m)[0] == fam
                and not any(m.get(k) for k in ("bootstrap", "default", "old_default", "budget"))
            ]
            if not ms:
                continue
            _, color, marker = _family(ms[0])
            t = np.array([m["time_s"] for m in ms])
            en = np.array([max(m["error_noise_free"][k], 1e-9) for m in ms])
            ax.plot(t, en, marker=marker, mfc="none", color=color, ls=":", lw=0.8)
            ax.plot(
                t,
                [m["rms_error_noisy"][k] for m in ms],
                marker=marker,
                color=color,
                ls="-",
                lw=1.0,
                label=fam if k == "E_eff" else None,
            )
        for m in result["methods"]:
            if m.get("default") or m.get("bootstrap"):
                _, color, marker = _family(m)
                ax.plot(
                    m["time_s"],
                    m["rms_error_noisy"][k],
                    marker="*" if m.get("default") else "D",
                    ms=11 if m.get("default") else 6,
                    color=color,
                    ls="none",
                    label=(
                        "default: + block bootstrap (200)"
                        if m.get("default")
                        else "lmfit + solve_ivp + bootstrap (200)"
                    )
                    if k == "E_eff"
                    else None,
                )
        ax.axhline(
            TARGETS[k],
            color="tab:red",
            ls="--",
            lw=0.8,
            label="issue 8 target" if k == "E_eff" else None,
        )
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("CPU time per record [s]")
        ax.set_ylabel(f"error in {_LABELS[k]}")
        ax.set_title(_LABELS[k])
    fig.legend(loc="outside lower center", ncols=3, fontsize=7)
    fig.suptitle(
        "Contact-parameter fit: time against error (filled: RMS over noisy replicates at "
        f"{NOISE:.1%} of F_max; hollow: noise-free record, the method's own error)",
        fontsize=9,
    )
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=150, format="png")


def _plot_recovery(path, result):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.0, 3.6), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    rows = result["recovery"]
    for ax, axis, xkey, xlabel in (
        (ax1, "noise", "noise_of_F_max", "noise σ / F_max (2 MHz)"),
        (ax2, "rate", "samples_per_contact", f"samples per contact ({NOISE:.1%} noise)"),
    ):
        rs = [r for r in rows if r["axis"] == axis]
        x = [r[xkey] for r in rs]
        for k, c in (("E_eff", "tab:blue"), ("e", "tab:orange"), ("mu", "tab:green")):
            ax.plot(x, [r["rms_error"][k] for r in rs], "o-", color=c, label=_LABELS[k])
            ax.axhline(TARGETS[k], color=c, ls="--", lw=0.8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(xlabel)
        ax.set_ylabel(f"RMS error over {N_RECOVERY} replicates")
    ax1.legend(fontsize=8, title="dashed: issue 8 targets", title_fontsize=7)
    fig.suptitle("Recovery against noise and sampling rate (15° scene, fit_contact)", fontsize=9)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=150, format="png")


def _plot_coverage(path, result):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 3.4), layout="constrained")
    axes = fig.subplots(1, len(result["coverage"]), sharey=True)
    for ax, (label, cov) in zip(np.atleast_1d(axes), result["coverage"].items(), strict=True):
        for j, (m, c) in enumerate((("covariance", "tab:blue"), ("bootstrap", "tab:green"))):
            xs = np.arange(3) + (j - 0.5) * 0.3
            p = [cov["coverage"][m][k] for k in ("E_eff", "e", "mu")]
            lo = [cov["wilson_95"][m][k][0] for k in ("E_eff", "e", "mu")]
            hi = [cov["wilson_95"][m][k][1] for k in ("E_eff", "e", "mu")]
            ax.errorbar(
                xs,
                p,
                yerr=[np.subtract(p, lo), np.subtract(hi, p)],
                fmt="o",
                color=c,
                capsize=3,
                label=m,
            )
        ax.axhspan(0.90, 0.98, color="tab:gray", alpha=0.2, lw=0, label="target 90–98 %")
        ax.axhline(0.95, color="k", lw=0.6)
        ax.set_xticks(range(3), ["E*", "e", "μ"])
        ax.set_title(f"{label}: {cov['replicates']} replicates", fontsize=9)
        ax.set_ylim(0.8, 1.0)
    np.atleast_1d(axes)[0].set_ylabel("coverage of the 95 % interval")
    np.atleast_1d(axes)[0].legend(fontsize=7, loc="lower left")
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=150, format="png")


def rerender(out_dir: Path) -> dict:
    """Recompute the ratios and redraw the charts from an existing ``fit_contact.json``."""
    out_dir = Path(out_dir)
    result = json.loads((out_dir / "fit_contact.json").read_text())
    result["speedups"] = _ratios(result["methods"])
    atomic_write_bytes(out_dir / "fit_contact.json", json.dumps(result, indent=1).encode())
    _plot_pareto(out_dir / "fit_contact.png", result)
    _plot_recovery(out_dir / "fit_contact_recovery.png", result)
    _plot_coverage(out_dir / "fit_contact_coverage.png", result)
    return result


if __name__ == "__main__":
    import sys

    print(json.dumps(run(Path(sys.argv[1] if len(sys.argv) > 1 else "build/bench")), indent=1))
