"""Polynomial fits: one batched QR vs a Python loop of single fits vs lmfit.

Records: ``N_RECORDS`` quartic pulses (Legendre coefficients near those of a Hertz pulse of
≈1.2 kN, randomly perturbed) on one grid of ``N_SAMPLES`` instants spanning 100 µs starting
1 ms into the record (a Garland–Rogers-like contact sampled at 1 MHz, Garland & Rogers 2009), plus
white noise σ = ``SIGMA`` N. Every method fits a quartic; the error is measured against the
known generating polynomial (RMS over the grid), whose expected value for an unbiased
least-squares fit is σ·√(p/n).

lmfit's ``PolynomialModel`` is fitted on the scaled variable x ∈ [−1, 1] (on raw times its
power basis is singular to working precision); it is timed on the first ``N_LMFIT`` records.

Writes ``fit.json`` and ``fit.png`` into the output directory.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
from numpy.polynomial import legendre as L

from pipeline._atomic import atomic_path, atomic_write_bytes
from pipeline.smooth import fit_polynomial, fit_polynomials_batch

N_RECORDS = 5000
N_SAMPLES = 100
N_LMFIT = 1000
SIGMA = 2.0  # [N]
T0, TW = 1.0e-3, 100e-6  # [s]
DEGREE = 4


def _records(seed=0):
    rng = np.random.default_rng(seed)
    t = np.linspace(T0, T0 + TW, N_SAMPLES)
    x = np.linspace(-1.0, 1.0, N_SAMPLES)
    base = np.array([650.0, 0.0, -900.0, 0.0, 245.0])  # quartic of a 1.2 kN Hertz pulse
    coef = base * rng.uniform(0.5, 1.5, (N_RECORDS, 1)) + rng.normal(0, 20.0, (N_RECORDS, 5))
    truth = coef @ L.legvander(x, DEGREE).T
    Y = truth + rng.normal(0.0, SIGMA, truth.shape)
    return t, x, coef, truth, Y


def _best_of(fn, repeat=3):
    best = np.inf
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def run(out_dir: Path) -> dict:
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    t, x, coef, truth, Y = _records()

    # 1. one batched QR for all records
    t_batch, batch = _best_of(lambda: fit_polynomials_batch(t, Y, degree=DEGREE, warn=False))
    fit_b = batch(t)

    # 2. a Python loop of single fits (same algorithm, one record at a time)
    def loop():
        return [fit_polynomial(t, y, degree=DEGREE, warn=False) for y in Y]

    t_loop, singles = _best_of(loop, repeat=1)
    coef_loop = np.array([s.coef for s in singles])
    fit_l = coef_loop @ L.legvander(x, DEGREE).T

    # 3. lmfit PolynomialModel on the scaled variable
    from lmfit.models import PolynomialModel

    model = PolynomialModel(degree=DEGREE)

    def lm():
        res = []
        for y in Y[:N_LMFIT]:
            params = model.guess(y, x=x)
            res.append(model.fit(y, params, x=x).eval(x=x))
        return np.array(res)

    t_lm, fit_lm = _best_of(lm, repeat=1)

    def rms_err(fitted, n):
        return np.sqrt(np.mean((fitted - truth[:n]) ** 2, axis=1))

    err_b = rms_err(fit_b, N_RECORDS)
    err_l = rms_err(fit_l, N_RECORDS)
    err_lm = rms_err(fit_lm, N_LMFIT)
    expected = SIGMA * np.sqrt((DEGREE + 1) / N_SAMPLES)
    scale = np.abs(truth).max(axis=1)

    # conditioning: raw power basis in seconds vs Legendre on the scaled window
    cond_raw = float(np.linalg.cond(np.vander(t, DEGREE + 1)))
    cond_leg = float(np.linalg.cond(L.legvander(x, DEGREE)))

    result = {
        "records": N_RECORDS,
        "samples_per_record": N_SAMPLES,
        "degree": DEGREE,
        "noise_sigma_N": SIGMA,
        "time_per_fit_s": {
            "batched_qr": t_batch / N_RECORDS,
            "loop_single": t_loop / N_RECORDS,
            "lmfit_polynomial_model": t_lm / N_LMFIT,
        },
        "speedup_batched_vs_loop": t_loop / t_batch,
        "speedup_batched_vs_lmfit": (t_lm / N_LMFIT) / (t_batch / N_RECORDS),
        "lmfit_records_timed": N_LMFIT,
        "rms_error_vs_truth_N": {
            "expected_sigma_sqrt_p_over_n": expected,
            "batched_qr_median": float(np.median(err_b)),
            "loop_single_median": float(np.median(err_l)),
            "lmfit_median": float(np.median(err_lm)),
            "batched_qr_max_relative_to_peak": float(np.max(err_b / scale)),
        },
        "max_rel_coef_diff_batched_vs_loop": float(
            np.max(np.abs(batch.coef - coef_loop)) / np.max(np.abs(coef_loop))
        ),
        "max_rel_curve_diff_batched_vs_lmfit": float(
            np.max(np.abs(fit_b[:N_LMFIT] - fit_lm)) / np.max(np.abs(fit_lm))
        ),
        "coef_rms_error_N": float(np.sqrt(np.mean((batch.coef - coef) ** 2))),
        "condition_number": {"raw_power_basis_seconds": cond_raw, "legendre_scaled": cond_leg},
        "flagged_poor_fraction": float(batch.poor.mean()),
    }
    atomic_write_bytes(out_dir / "fit.json", json.dumps(result, indent=2).encode())
    _plot(out_dir / "fit.png", result, err_b, err_lm, expected)
    return result


def _plot(path: Path, result, err_b, err_lm, expected):
    from matplotlib.figure import Figure  # no pyplot: no global backend or figure state

    fig = Figure(figsize=(9.0, 3.6), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    names = ["batched QR", "loop of single fits", "lmfit PolynomialModel"]
    times = [
        result["time_per_fit_s"][k] * 1e6
        for k in ("batched_qr", "loop_single", "lmfit_polynomial_model")
    ]
    bars = ax1.bar(names, times, color=["tab:green", "tab:blue", "tab:gray"])
    ax1.set_yscale("log")
    ax1.set_ylim(top=3.0 * max(times))  # room for the value above the tallest bar
    ax1.set_ylabel("time per fit [µs]")
    ax1.set_title(
        f"quartic fits, {result['records']} records × {result['samples_per_record']} samples"
    )
    for b, v in zip(bars, times, strict=True):
        ax1.annotate(
            f"{v:.3g} µs", (b.get_x() + b.get_width() / 2, v), ha="center", va="bottom", fontsize=8
        )
    ax1.tick_params(axis="x", labelsize=8)
    bins = np.linspace(0, max(err_b.max(), err_lm.max()), 40)
    ax2.hist(err_b, bins=bins, alpha=0.7, label="batched QR", color="tab:green")
    ax2.hist(err_lm, bins=bins, alpha=0.7, label=f"lmfit (first {err_lm.size})", color="tab:gray")
    ax2.axvline(expected, color="k", ls="--", label=r"$\sigma\sqrt{p/n}$")
    ax2.set_xlabel("RMS error vs generating polynomial [N]")
    ax2.set_ylabel("records")
    ax2.legend(fontsize=8)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=150, format="png")


if __name__ == "__main__":
    import sys

    print(json.dumps(run(Path(sys.argv[1] if len(sys.argv) > 1 else "build/bench")), indent=2))
