"""Make the small format samples in data_samples/ (synthetic, deterministic).

    python scripts/make_format_samples.py --out data_samples

One physical impact underlies every file: a 25.4 mm steel ball (E = 210 GPa, ν = 0.3,
ρ = 7850 kg/m³) on a steel target cap (radius 50 mm, same steel) at 0.5 m/s, 15° from the
normal. The normal force is the exact elastic Hertz pulse (pipeline.contact.hertz_pulse;
no half-sine shortcut). The tangential force is ILLUSTRATIVE, not a contact model:

    Ft(t) = μ·Fn(t)·tanh((t_r − t)/τ),   μ = 0.12, t_r = 0.7·t_c, τ = 0.06·t_c

i.e. Coulomb sliding (+μ·Fn, opposing the initial slip) early and a sign reversal late in
the contact, as Garland & Rogers (2009) observed. The out-of-plane force is 1 %
cross-talk of Fn. Files:

- sensor_decimal_comma.csv — lab sensor export in a decimal-comma locale: UTF-8 with BOM,
  CRLF, ';' separator, '# key: value' metadata, time in µs, forces in kN, 2 MHz sampling,
  50 µs pre-/post-trigger, white noise (σ = 2 N) and a 1.5 N baseline offset on each axis.
- wpd_Fn.csv — WebPlotDigitizer single-dataset export of Fn (x in µs, y in N), ', '
  separator, points in click order (irregular instants, a few clicked out of order).
- wpd_Ft.csv — the same for Ft in the decimal-comma dialect (';' separator, decimal commas),
  clicked at other instants than Fn.
- wpd_datasets.csv — WebPlotDigitizer "export all" of two datasets named "Normal force"
  and "Tangential force" (different instants, different lengths, blank padding).
- sensor.tdms — NI TDMS written with npTDMS: group "Impact", channels Fx, Fy, Fz [N],
  1 MHz waveform (wf_start_offset = −20 µs, wf_increment = 1 µs), noise σ = 2 N.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from pipeline import Scene
from pipeline._atomic import atomic_path, atomic_write_text
from pipeline.contact import hertz_impact, hertz_pulse

SEED = 20261122
SCENE = Scene(
    radius=0.0127,
    density=7850.0,
    E=210e9,
    nu=0.3,
    target_E=210e9,
    target_nu=0.3,
    target_radius=0.05,
    speed=0.5,
    angle_deg=15.0,
    mu=0.12,
)
MU = SCENE.mu
CROSS_TALK = 0.01


def forces(t, impact):
    """(Fn, Ft, Fy) [N] at times t [s] since first contact (see module notes)."""
    fn = hertz_pulse(t, impact)["F"]
    t_r, tau = 0.7 * impact.t_c, 0.06 * impact.t_c
    ft = MU * fn * np.tanh((t_r - t) / tau)
    return fn, ft, CROSS_TALK * fn


def _fmt_comma(x, decimals):
    return f"{x:.{decimals}f}".replace(".", ",")


def sensor_csv(path, impact, rng):
    dt = 0.5e-6
    t = np.arange(-50e-6, impact.t_c + 50e-6, dt)
    fn, ft, fy = forces(t, impact)
    noise = rng.normal(0.0, 2.0, size=(3, t.size)) + 1.5
    fx, fy, fz = ft + noise[0], fy + noise[1], fn + noise[2]
    meta = [
        "# Rig: pendulum, tri-axial piezoelectric force sensor under a steel target cap",
        "# Ball: steel, diameter 25,4 mm, mass 67,35 g",
        "# Impact speed: 0,5 m/s",
        "# Angle: 15 deg",
        "# Sample rate: 2 MHz",
        "# Trigger: 50 us pre-trigger",
        "# Note: SYNTHETIC sample made by scripts/make_format_samples.py (seed "
        f"{SEED}); Fx illustrative, see data_samples/README.md",
    ]
    rows = [
        f"{_fmt_comma(ti * 1e6, 1)};{_fmt_comma(a / 1e3, 6)};{_fmt_comma(b / 1e3, 6)};"
        f"{_fmt_comma(c / 1e3, 6)}"
        for ti, a, b, c in zip(t, fx, fy, fz, strict=True)
    ]
    text = "\n".join([*meta, "t [µs];Fx [kN];Fy [kN];Fz [kN]", *rows]) + "\n"
    atomic_write_text(path, text, encoding="utf-8-sig", newline="\r\n")


def _clicks(rng, t_c, n, jitter):
    """n irregular click instants over [0, t_c] [s], in a plausible click order."""
    base = np.sort(rng.uniform(0.02, 0.98, size=n - 2))
    x = np.concatenate([[0.0], base, [1.0]]) * t_c
    x = x + rng.normal(0.0, jitter, size=x.size)
    order = np.arange(n)
    for i in rng.choice(n - 1, size=3, replace=False):  # a few clicks out of order
        order[[i, i + 1]] = order[[i + 1, i]]
    return x[order]


def _digitise(rng, impact, n, channel):
    x = _clicks(rng, impact.t_c, n, 0.2e-6)
    fn, ft, _ = forces(np.clip(x, 0, impact.t_c), impact)
    y = fn if channel == "Fn" else ft
    y = y + rng.normal(0.0, 0.004 * impact.F_max, size=y.size)
    return x * 1e6, y  # µs, N


def wpd_single(path, x, y, *, decimal_comma=False):
    if decimal_comma:
        lines = [f"{_fmt_comma(a, 10)};{_fmt_comma(b, 10)}" for a, b in zip(x, y, strict=True)]
    else:
        lines = [f"{a:.10f}, {b:.10f}" for a, b in zip(x, y, strict=True)]
    atomic_write_text(path, "\n".join(lines) + "\n")


def wpd_datasets(path, sets):
    names = list(sets)
    n = max(len(x) for x, _ in sets.values())
    lines = [",".join(f"{name}," for name in names), ",".join("X,Y" for _ in names)]
    for i in range(n):
        cells = []
        for name in names:
            x, y = sets[name]
            cells += [f"{x[i]:.10f}", f"{y[i]:.10f}"] if i < len(x) else ["", ""]
        lines.append(",".join(cells))
    atomic_write_text(path, "\n".join(lines) + "\n")


def tdms(path, impact, rng):
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

    dt, t0 = 1e-6, -20e-6
    n = int(round((impact.t_c + 40e-6) / dt))
    t = t0 + dt * np.arange(n)
    fn, ft, fy = forces(t, impact)
    noise = rng.normal(0.0, 2.0, size=(3, n))
    props = {
        "unit_string": "N",
        "wf_start_offset": t0,
        "wf_increment": dt,
        "wf_samples": n,
        "wf_xunit_string": "s",
    }
    with atomic_path(path) as tmp, TdmsWriter(tmp) as writer:
        writer.write_segment(
            [
                RootObject({"name": "synthetic impact", "author": "make_format_samples.py"}),
                GroupObject("Impact", {"description": "25.4 mm steel ball, 0.5 m/s, 15 deg"}),
                ChannelObject("Impact", "Fx", ft + noise[0], properties=props),
                ChannelObject("Impact", "Fy", fy + noise[1], properties=props),
                ChannelObject("Impact", "Fz", fn + noise[2], properties=props),
            ]
        )


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("data_samples"))
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    impact = hertz_impact(SCENE)
    rng = np.random.default_rng(SEED)
    sensor_csv(args.out / "sensor_decimal_comma.csv", impact, rng)
    fn = _digitise(rng, impact, 31, "Fn")
    ft = _digitise(rng, impact, 23, "Ft")
    wpd_single(args.out / "wpd_Fn.csv", *fn)
    wpd_single(args.out / "wpd_Ft.csv", *ft, decimal_comma=True)
    wpd_datasets(
        args.out / "wpd_datasets.csv",
        {
            "Normal force": _digitise(rng, impact, 28, "Fn"),
            "Tangential force": _digitise(rng, impact, 19, "Ft"),
        },
    )
    tdms(args.out / "sensor.tdms", impact, rng)
    sidecars(args.out)


def sidecars(out: Path) -> None:
    """``<stem>.json`` beside each sample: its scene and the ``load`` arguments it needs.

    ``pipeline.report.reproduce`` reads them (``"load"`` holds keyword arguments of
    ``pipeline.io.load``; ``"paths"`` combines several files into one record).
    """
    scene = {k: (v if np.isfinite(v) else "inf") for k, v in SCENE.to_dict().items()}
    digitised = {"time_unit": "us", "force_unit": "N"}
    entries = {
        "sensor_decimal_comma": {},
        "sensor": {},
        "wpd_datasets": digitised,
        "wpd_Fn": {"paths": {"Fn": "wpd_Fn.csv", "Ft": "wpd_Ft.csv"}, **digitised},
    }
    for stem, load in entries.items():
        side = {
            "synthetic": True,
            "note": "format sample; Fn exact elastic Hertz, Ft illustrative "
            "(see data_samples/README.md)",
            "generator": "python scripts/make_format_samples.py --out data_samples",
            "seed": SEED,
            "scene": scene,
            "load": load,
        }
        atomic_write_text(out / f"{stem}.json", json.dumps(side, indent=1) + "\n")


if __name__ == "__main__":
    main()
