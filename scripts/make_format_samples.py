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
- sensor_volts.lvm — LabVIEW Measurement file as LabVIEW's Write To Measurement File
  writes it on a decimal-comma Windows PC: file header and segment header, CRLF, tabs,
  decimal commas, X_Columns No (time = X0 + k·Delta_X), a Comment column; channels Fz and
  Fx in Volts from a sensor of 0.225 mV/N (Fz) and 0.5 mV/N (Fx), and a Trigger channel
  in Volts; 1 MHz, X0 = −20 µs, noise σ = 2 N; 6 decimals (1 µV) as LabVIEW writes.
- sensor_v5.mat — MATLAB v5 file (scipy.io.savemat): a row vector t_us [µs] and column
  vectors Fz_kN, Fx_kN, Fy_kN in single precision, a char variable; 2 MHz, noise σ = 2 N.
- sensor_v73.mat — MATLAB v7.3 file laid out as MATLAB writes one (h5py): 512-byte text
  header, MATLAB_class attributes, arrays transposed, char as uint16; a struct "data" with
  "raw", a 2-D array (samples × [time s, Fx V, Fy V, Fz V]) named by the sidecar's
  "columns", and "operator"; sensitivities 0.5, 0.5 and 0.225 mV/N; 1 MHz, noise σ = 2 N.

The LVM and MAT samples draw their noise from their own generators (seeds SEED + 1, + 2,
+ 3), so adding them left the earlier files byte-identical.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from pipeline import Scene
from pipeline._atomic import atomic_path, atomic_write_bytes, atomic_write_text
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


#: The sensitivities of the volts samples' sensor [mV/N], per file column.
SENSITIVITY = {"Fz": 0.225, "Fx": 0.5, "Fy": 0.5}
_CRLF = "\r\n"


def _lvm_number(x: float) -> str:
    """A sample as LabVIEW writes it: 6 decimals, decimal comma (this PC's locale)."""
    return f"{x:.6f}".replace(".", ",")


def lvm(path, impact, rng):
    """sensor_volts.lvm (see module notes)."""
    dt, t0 = 1e-6, -20e-6
    n = int(round((impact.t_c + 60e-6) / dt))
    t = t0 + dt * np.arange(n)
    fn, ft, _ = forces(t, impact)
    noise = rng.normal(0.0, 2.0, size=(2, n))
    volts = {
        "Fz": (fn + noise[0]) * SENSITIVITY["Fz"] * 1e-3,
        "Fx": (ft + noise[1]) * SENSITIVITY["Fx"] * 1e-3,
        "Trigger": np.where(t >= 0.0, 5.0, 0.0),
    }
    names = list(volts)
    stamp = "11:02:17,5081634521484375"

    def row(tag, values):
        return "\t".join([tag, *values, ""])

    head = [
        "LabVIEW Measurement\t",
        "Writer_Version\t2",
        "Reader_Version\t2",
        "Separator\tTab",
        "Decimal_Separator\t,",
        "Multi_Headings\tYes",
        "X_Columns\tNo",
        "Time_Pref\tRelative",
        "Operator\tA. Lab",
        "Description\tdrop 3: 25.4 mm steel ball, 0.5 m/s, 15 deg (SYNTHETIC, "
        "scripts/make_format_samples.py)",
        "Date\t2026/11/22",
        f"Time\t{stamp}",
        "***End_of_Header***\t",
        "\t",
        row("Channels", [str(len(names))] + [""] * (len(names) - 1)),
        row("Samples", [str(n)] * len(names)),
        row("Date", ["2026/11/22"] * len(names)),
        row("Time", [stamp] * len(names)),
        row("Y_Unit_Label", ["Volts"] * len(names)),
        row("X_Dimension", ["Time"] * len(names)),
        row("X0", ["-2,0000000000000000E-5"] * len(names)),
        row("Delta_X", ["1,000000E-6"] * len(names)),
        "\t".join(["***End_of_Header***"] + [""] * (len(names) + 1)),
        "\t".join(["X_Value", *names, "Comment"]),
    ]
    rows = []
    for k in range(n):
        cells = ["", *(_lvm_number(volts[c][k]) for c in names)]
        if k == 0:
            cells.append("pre-trigger 20 us")
        rows.append("\t".join(cells))
    atomic_write_text(path, _CRLF.join(head + rows) + _CRLF + _CRLF, newline="")


def _mat_header(text: str) -> bytes:
    """The 116-byte descriptive text MATLAB puts first (fixed, so the file is deterministic)."""
    return text.encode("ascii").ljust(116, b" ")


def mat_v5(path, impact, rng):
    """sensor_v5.mat (see module notes)."""
    import io

    import scipy.io

    dt, t0 = 0.5e-6, -30e-6
    n = int(round((impact.t_c + 80e-6) / dt))
    t = t0 + dt * np.arange(n)
    fn, ft, fy = forces(t, impact)
    noise = rng.normal(0.0, 2.0, size=(3, n))
    buf = io.BytesIO()
    scipy.io.savemat(
        buf,
        {
            "t_us": (t * 1e6)[np.newaxis, :],  # a 1×n row vector
            "Fz_kN": ((fn + noise[0]) / 1e3).astype(np.float32)[:, np.newaxis],
            "Fx_kN": ((ft + noise[1]) / 1e3).astype(np.float32)[:, np.newaxis],
            "Fy_kN": ((fy + noise[2]) / 1e3).astype(np.float32)[:, np.newaxis],
            "operator": "A. Lab",
        },
        format="5",
        do_compression=False,
        oned_as="column",
    )
    raw = bytearray(buf.getvalue())
    raw[:116] = _mat_header(
        "MATLAB 5.0 MAT-file, written by scripts/make_format_samples.py (SYNTHETIC)"
    )
    atomic_write_bytes(path, bytes(raw))


def mat_v73(path, impact, rng):
    """sensor_v73.mat (see module notes)."""
    import h5py

    dt, t0 = 1e-6, -20e-6
    n = int(round((impact.t_c + 60e-6) / dt))
    t = t0 + dt * np.arange(n)
    fn, ft, fy = forces(t, impact)
    noise = rng.normal(0.0, 2.0, size=(3, n))
    raw = np.column_stack(
        [
            t,
            (ft + noise[0]) * SENSITIVITY["Fx"] * 1e-3,
            (fy + noise[1]) * SENSITIVITY["Fy"] * 1e-3,
            (fn + noise[2]) * SENSITIVITY["Fz"] * 1e-3,
        ]
    )  # MATLAB's n×4 array
    with atomic_path(path) as tmp:
        with h5py.File(tmp, "w", userblock_size=512, track_order=False) as f:
            data = f.create_group("data")
            data.attrs["MATLAB_class"] = np.bytes_(b"struct")
            ds = data.create_dataset("raw", data=raw.T)  # stored transposed, as MATLAB does
            ds.attrs["MATLAB_class"] = np.bytes_(b"double")
            chars = np.array([ord(c) for c in "A. Lab"], dtype=np.uint16)[:, np.newaxis]
            op = data.create_dataset("operator", data=chars)  # a 1×6 char row, transposed
            op.attrs["MATLAB_class"] = np.bytes_(b"char")
            op.attrs["MATLAB_int_decode"] = np.int32(2)
        header = _mat_header(
            "MATLAB 7.3 MAT-file, written by scripts/make_format_samples.py (SYNTHETIC), "
            "HDF5 schema 1.00 ."
        )
        with open(tmp, "r+b") as fh:
            fh.write(header + b"\x00" * 8 + b"\x00\x02IM")  # version 0x0200, endianness


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
    lvm(args.out / "sensor_volts.lvm", impact, np.random.default_rng(SEED + 1))
    mat_v5(args.out / "sensor_v5.mat", impact, np.random.default_rng(SEED + 2))
    mat_v73(args.out / "sensor_v73.mat", impact, np.random.default_rng(SEED + 3))
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
        "sensor_volts": {},
        "sensor_v5": {},
        "sensor_v73": {},
    }
    mv_n = {c: [v, "mV/N"] for c, v in SENSITIVITY.items()}
    rig = {  # the sidecar's own keys: the rig's sensitivity, a MATLAB array's columns
        "sensor_volts": {"sensitivity": {"Fn": mv_n["Fz"], "Ft": mv_n["Fx"]}},
        "sensor_v73": {
            "sensitivity": {"Fn": mv_n["Fz"], "Ft": mv_n["Fx"], "Fy": mv_n["Fy"]},
            "columns": {"data.raw": ["time [s]", "Fx [V]", "Fy [V]", "Fz [V]"]},
        },
    }
    for stem, load in entries.items():
        side = {
            "synthetic": True,
            "note": "format sample; Fn exact elastic Hertz, Ft illustrative "
            "(see data_samples/README.md)",
            "generator": "python scripts/make_format_samples.py --out data_samples",
            "seed": SEED,
            "scene": scene,
            **rig.get(stem, {}),
            "load": load,
        }
        atomic_write_text(out / f"{stem}.json", json.dumps(side, indent=1) + "\n")


if __name__ == "__main__":
    main()
