"""Write the synthetic Garland–Rogers-style sample records to data_samples/.

Run by ``make data`` (``python scripts/make_samples.py --out data_samples``); re-runnable
and deterministic: the same package version writes the same bytes.

What it makes (Garland & Rogers, J. Appl. Mech. 76:031015, 2009,
doi:10.1115/1.3086432 — whose waveforms are not public, so these are SYNTHETIC):

- a 25.4 mm steel ball (E 210 GPa, ν 0.29, ρ 7850 kg/m³) striking a fixed steel target cap
  of radius 25.4 mm (so R* = 8.47 mm: the rig's striker hits a spherical cap mounted on the
  transducer, Garland & Rogers 2009), at incidence 5°, 15° (the seed paper's case), 30°, 45° and
  speeds 0.3 and 0.6 m/s;
- friction rising linearly with the initial tangential speed, the form Garland & Rogers
  report: μ = a + b·v_t0 with a = 0.10 and b = 0.20 s/m (our choice of values: μ from 0.105
  at 5°/0.3 m/s to 0.185 at 45°/0.6 m/s, plausible for dry steel on steel at these speeds);
- normal restitution e = 0.9 through the Hunt–Crossley law calibrated to it, tangential
  compliance by Mindlin's spring with Coulomb cap (``tangential="mindlin"``);
- the ideal record passed through :func:`pipeline.sensor_model.to_sensor` with its default
  (Garland–Rogers-like) sensor parameters and a fixed seed per file, written by
  :func:`pipeline.io.write_sensor`; a JSON sidecar next to each CSV holds the ground truth.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import math
import sys
from pathlib import Path

import numpy as np
import scipy

import pipeline
from pipeline import Scene
from pipeline._atomic import atomic_write_text
from pipeline.contact import hertz_impact
from pipeline.io import write_sensor
from pipeline.sensor_model import to_sensor
from pipeline.simulate import impact

COMMAND = "make data  (= python scripts/make_samples.py --out data_samples)"

BALL = dict(radius=0.0254 / 2, density=7850.0, E=210e9, nu=0.29)
TARGET = dict(target_E=210e9, target_nu=0.29, target_radius=0.0254)
ANGLES_DEG = (5.0, 15.0, 30.0, 45.0)
SPEEDS = (0.3, 0.6)  # [m/s]
E_N = 0.9
MU_A, MU_B = 0.10, 0.20  # μ = a + b·v_t0, b in [s/m]
NORMAL, TANGENTIAL = "hunt_crossley", "mindlin"
BASE_SEED = 20090315  # seed of file i is BASE_SEED + i (i in the order listed below)
SENSOR = {}  # to_sensor defaults (pipeline.sensor_model.SENSOR_DEFAULTS)
OUTCOME_UNITS = {
    "e_n": "1",
    "e_t": "1",
    "omega": "rad/s",
    "t_contact": "s",
    "F_max": "N",
    "delta_max": "m",
    "Pn_final": "N s",
    "Pt_final": "N s",
    "rebound_angle_deg": "deg",
    "rebound_angle_contact_deg": "deg",
    "E_initial": "J",
    "E_final": "J",
    "W_friction": "J",
    "W_damping": "J",
}
SIM_OPTIONS = {"history": "total", "samples": 2001, "rtol": 1e-9}  # pipeline.simulate.impact
OUTCOME_KEYS = tuple(OUTCOME_UNITS)

TRUTH_DIGITS = 10  # significant digits of simulated outcomes in the sidecars

FILE_NOTE = (
    "SYNTHETIC record (no public Garland-Rogers waveforms exist): simulated by "
    "pipeline.simulate.impact and pipeline.sensor_model.to_sensor; ground truth in {json}"
)


def mu_of(v_t0: float) -> float:
    """Friction coefficient μ = a + b·v_t0 (v_t0 [m/s])."""
    return MU_A + MU_B * v_t0


def stem(angle_deg: float, speed: float) -> str:
    return f"gr_{angle_deg:g}deg_{speed:g}ms"


def scenes():
    """The sample scenes in a fixed order: (name, scene, seed)."""
    i = 0
    for speed in SPEEDS:
        for angle in ANGLES_DEG:
            base = Scene(speed=speed, angle_deg=angle, e=E_N, **BALL, **TARGET)
            yield stem(angle, speed), base.replace(mu=mu_of(float(base.v_t0))), BASE_SEED + i
            i += 1


def jsonable(value):
    """Plain JSON: numpy → python, non-finite floats → "inf"/"-inf"/"nan" strings."""
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return jsonable(value.tolist())
    if isinstance(value, np.bool_ | bool):
        return bool(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, float | np.floating):
        v = float(value)
        return v if math.isfinite(v) else str(v)
    return value


def rounded(value, digits: int = TRUTH_DIGITS):
    """Simulated outcomes to ``digits`` significant digits (floats only, recursively).

    The simulator's last bits move with harmless refactors and platforms; rounding keeps
    ``make data`` byte-stable. Scene and sensor parameters are never rounded.
    """
    if isinstance(value, dict):
        return {k: rounded(v, digits) for k, v in value.items()}
    if isinstance(value, float | np.floating) and math.isfinite(value) and value != 0:
        return float(f"{float(value):.{digits - 1}e}")
    return value


def truth_summary(ideal) -> dict:
    """Peaks and final percussions of the ideal (noise-free) record."""
    t = ideal["time"].values
    fn = ideal["Fn"].values
    ft = ideal["Ft"].values if "Ft" in ideal else np.zeros_like(t)
    return {
        "Fn_max [N]": float(fn.max()),
        "t_Fn_max [s]": float(t[np.argmax(fn)]),
        "Ft_max [N]": float(ft.max()),
        "Ft_min [N]": float(ft.min()),
        "Pn_final [N s]": float(np.trapezoid(fn, t)),
        "Pt_final [N s]": float(np.trapezoid(ft, t)),
        "t_first [s]": float(t[0]),
        "t_last [s]": float(t[-1]),
        "samples": int(t.size),
    }


def make_one(out: Path, name: str, scene: Scene, seed: int) -> dict:
    ideal = impact(scene, normal=NORMAL, tangential=TANGENTIAL, **SIM_OPTIONS)
    sensor = to_sensor(ideal, seed=seed, **SENSOR)
    csv_path = out / f"{name}.csv"
    json_name = f"{name}.json"

    # The CSV header reads like a lab export; the sidecar holds the full truth.
    to_write = sensor.copy()
    to_write.attrs = {
        "source": csv_path.name,
        "sha256": "",
        "format": "sensor_csv",
        "kind": "sensor",
    }
    hz = hertz_impact(scene)
    write_sensor(
        to_write,
        csv_path,
        metadata={
            "note": FILE_NOTE.format(json=json_name),
            "rig": "Garland-Rogers-style pendulum: 25.4 mm steel ball on a 25.4 mm steel cap "
            "over a tri-axial piezo transducer (Fz normal, Fx tangential, Fy out of plane)",
            "impact speed [m/s]": f"{scene.speed:g}",
            "incidence [deg]": f"{scene.angle_deg:g}",
            "sample rate [Hz]": f"{sensor.attrs['sensor_rate']:g}",
            "adc bits": str(sensor.attrs["sensor_bits"]),
            "full scale [N]": f"{sensor.attrs['sensor_full_scale'][0]:g}",
            "bandwidth [Hz]": f"{sensor.attrs['sensor_bandwidth']:g}",
            "pre-trigger [s]": f"{sensor.attrs['sensor_pre_trigger']:g}",
        },
    )
    csv_sha = hashlib.sha256(csv_path.read_bytes()).hexdigest()

    scene_fields = set(Scene.field_names())
    sim_attrs = {k: v for k, v in ideal.attrs.items() if k not in scene_fields}
    sensor_params = {
        k.removeprefix("sensor_"): v for k, v in sensor.attrs.items() if k.startswith("sensor_")
    }
    sidecar = {
        "synthetic": True,
        "description": (
            "Synthetic Garland-Rogers-style oblique impact record (no public file of the "
            "Garland & Rogers 2009 waveforms exists). Ideal forces from "
            "pipeline.simulate.impact, then the sensor model pipeline.sensor_model.to_sensor."
        ),
        "file": csv_path.name,
        "file_sha256": csv_sha,
        "columns": {"time [s]": "time", "Fz [N]": "Fn", "Fx [N]": "Ft", "Fy [N]": "Fy"},
        "generator": {
            "command": COMMAND,
            "script": "scripts/make_samples.py",
            "package": "pipeline",
            "version": pipeline.__version__,
            "numpy": np.__version__,
            "scipy": scipy.__version__,
            "python": ".".join(map(str, sys.version_info[:3])),
        },
        "seed": seed,
        "scene": scene.to_dict(),
        "friction_law": {
            "form": "mu = a + b * v_t0",
            "a": MU_A,
            "b [s/m]": MU_B,
            "v_t0 [m/s]": float(scene.v_t0),
            "mu": float(scene.mu),
            "note": "linear in the initial tangential speed as Garland & Rogers (2009) "
            "observed; a and b are this project's choice",
        },
        "model": {
            "normal": NORMAL,
            "tangential": TANGENTIAL,
            "history_rule": sim_attrs.get("history_rule"),
            "e_requested": E_N,
            "damping_param": rounded(sim_attrs.get("damping_param")),
            "damping_param_name": sim_attrs.get("damping_param_name"),
            "damping_note": "Hunt-Crossley F = K d^1.5 (1 + c d'/v0), c calibrated exactly "
            "so that e_n = e (pipeline.contact.calibrate_hunt_crossley_family)",
            "impact_options": SIM_OPTIONS,
        },
        "simulated_attrs": rounded(sim_attrs),
        "outcome": rounded({k: sim_attrs.get(k) for k in OUTCOME_KEYS}),
        "outcome_units": OUTCOME_UNITS,
        "truth": rounded(truth_summary(ideal)),
        "hertz_elastic_reference": {
            "F_max [N]": hz.F_max,
            "t_c [s]": hz.t_c,
            "delta_max [m]": hz.delta_max,
        },
        "sensor": sensor_params,
        "sensor_model": "pipeline.sensor_model.to_sensor (defaults SENSOR_DEFAULTS)",
    }
    text = json.dumps(jsonable(sidecar), indent=1, allow_nan=False, sort_keys=False) + "\n"
    atomic_write_text(out / json_name, text)
    return {
        "name": name,
        "rows": int(sensor.sizes["time"]),
        "bytes": csv_path.stat().st_size,
        "e_n": sim_attrs.get("e_n"),
        "e_t": sim_attrs.get("e_t"),
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--out",
        type=Path,
        default=Path("data_samples"),
        help="output folder (default data_samples)",
    )
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    for name, scene, seed in scenes():
        info = make_one(args.out, name, scene, seed)
        print(
            f"{info['name']}: {info['rows']} rows, {info['bytes']} bytes, "
            f"e_n={info['e_n']}, e_t={info['e_t']}"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
