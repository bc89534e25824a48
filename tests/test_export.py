"""Exports: the fitted contact in LAMMPS, LIGGGHTS, YADE and MuJoCo input.

The LAMMPS test runs the exported input with ``lmp`` (Debian's ``lammps`` package; skipped
only where it is absent) and compares the rebound it computes with the package's own
simulator for the same contact: Hertz with the secant-stiffness dashpot (what LAMMPS
``damping tsuji`` is), Mindlin tangential spring with the total-displacement history
(LAMMPS ``mindlin``). The conversion formulas are checked against the closed forms they
rest on (Tsuji et al. 1992, doi:10.1016/0032-5910(92)88030-L; the linear spring–dashpot
restitution e = exp(−ζπ/√(1−ζ²))).
"""

from __future__ import annotations

import json
import math
import re
import shutil
import subprocess
import warnings
from pathlib import Path

import pytest

from pipeline import Scene
from pipeline.contact import cor_hertz_dashpot, hertz_impact, zeta_hertz_dashpot_dem
from pipeline.errors import InputError
from pipeline.export import Contact, contact_from, export, to_lammps, to_mujoco
from pipeline.simulate.lammps import tsuji_alpha

ROOT = Path(__file__).resolve().parents[1]
SIDECAR = ROOT / "data_samples" / "gr_30deg_0.6ms.json"
CAP = Scene.from_dict(json.loads(SIDECAR.read_text())["scene"])  # steel ball on a steel cap
FLAT = CAP.replace(target_radius=math.inf, target_E=math.inf, angle_deg=45.0, mu=0.12, e=0.8)


def _run_lammps(script: str, tmp_path: Path) -> dict:
    (tmp_path / "in.impact").write_text(script)
    out = subprocess.run(
        ["lmp", "-in", "in.impact", "-log", "none"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        check=False,
    )
    line = [ln for ln in out.stdout.splitlines() if ln.startswith("RESULT")]
    assert line, out.stdout[-2000:] + out.stderr[-2000:]
    words = line[0].split()
    return {words[i]: float(words[i + 1]) for i in range(1, len(words), 2)}


def _package_prediction(contact: Contact) -> dict:
    from pipeline.simulate import impact

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sim = impact(
            contact.scene_fitted,
            normal="hertz_dashpot_secant",
            tangential="mindlin",
            history="total",
            rtol=1e-10,
        )
    return {k: float(sim.attrs[k]) for k in ("e_n", "e_t", "omega")}


@pytest.mark.skipif(shutil.which("lmp") is None, reason="LAMMPS (lmp) is not installed")
@pytest.mark.parametrize(
    ("scene", "values"),
    [
        (CAP, {"E_eff": 1.0e11, "e": 0.9, "mu": 0.16}),  # a steel cap: two spheres
        (FLAT, {}),  # a rigid flat wall: fix wall/gran
    ],
    ids=["cap", "wall"],
)
def test_lammps_runs_the_export_and_rebounds_as_the_package_predicts(scene, values, tmp_path):
    """e_n within 1e-3 and e_t within 3e-3 of the package's simulation; ω within 1 %.
    (The residue is LAMMPS' explicit velocity-Verlet step and, on the cap, the contact
    normal turning as the ball slides, which the package's fixed normal leaves out.)"""
    contact = contact_from({"scene": scene.to_dict(), "values": values})
    lmp = _run_lammps(to_lammps(contact).script, tmp_path)
    ours = _package_prediction(contact)
    assert lmp["e_n"] == pytest.approx(ours["e_n"], abs=1e-3)
    assert lmp["e_t"] == pytest.approx(ours["e_t"], abs=3e-3)
    assert lmp["omega"] == pytest.approx(ours["omega"], rel=0.01)
    assert ours["e_n"] == pytest.approx(contact.e, abs=1e-6)


def test_lammps_tsuji_input_gives_the_exact_damping():
    """The number given to 'damping tsuji' is where Tsuji's polynomial reaches α = 2ζ, ζ
    the secant-stiffness dashpot's exact damping ratio for e: the dashpot then rebounds with
    e, whereas giving e itself would not (e = 0.9 → 0.929)."""
    for e in (0.4, 0.6, 0.9, 0.97):
        ex = to_lammps(Contact(CAP, 1e11, e, 0.1))
        alpha = tsuji_alpha(ex.values["tsuji_input"])
        assert alpha == pytest.approx(ex.values["alpha"], rel=1e-12)
        assert cor_hertz_dashpot(alpha / 2, "secant") == pytest.approx(e, abs=1e-7)
    naive = cor_hertz_dashpot(tsuji_alpha(0.9) / 2, "secant")
    assert naive == pytest.approx(0.929, abs=1e-3)


def test_lammps_gives_stiffnesses_directly():
    """kn = (4/3)·E*, kt = 8·G*·kt_scale (Pa), written to full precision in the lines."""
    c = Contact(CAP, 1.2e11, 0.9, 0.15, kt_scale=0.7)
    ex = to_lammps(c)
    kn = 4 / 3 * 1.2e11
    G = float(CAP.G_eff) * 1.2e11 / float(CAP.E_eff)
    assert ex.values["kn"] == pytest.approx(kn, rel=1e-15)
    assert ex.values["kt"] == pytest.approx(8 * G * 0.7, rel=1e-15)
    line = next(ln for ln in ex.text.splitlines() if ln.startswith("pair_coeff"))
    words = line.split()
    assert float(words[4]) == ex.values["kn"]
    assert float(words[words.index("mindlin") + 1]) == ex.values["kt"]
    assert "limit_damping" in words and "hertz/material" not in words


def test_liggghts_and_yade_restitution_input_rebounds_with_e():
    """LIGGGHTS and YADE damp on the tangent stiffness with the closed form
    ζ = √(5/6)·|ln e|/√(ln²e + π²); the exported restitution makes that ζ the exact one."""
    for target in ("liggghts", "yade"):
        ex = export(Contact(CAP, 1e11, 0.85, 0.2), target)
        key = "restitution_input" if target == "liggghts" else "en"
        zeta = zeta_hertz_dashpot_dem(ex.values[key])
        assert cor_hertz_dashpot(zeta, "tangent") == pytest.approx(0.85, abs=1e-7)


def test_liggghts_materials_give_the_fitted_modulus():
    """1/E* = (1−ν1²)/E1 + (1−ν2²)/E2 of the exported per-type moduli is the fitted E*."""
    ex = export(Contact(CAP, 1.3e11, 0.9, 0.2, kt_scale=0.5), "liggghts")
    E = re.search(r"youngsModulus peratomtype (\S+) (\S+)", ex.text).groups()
    nu = re.search(r"poissonsRatio peratomtype (\S+) (\S+)", ex.text).groups()
    inv = sum((1 - float(n) ** 2) / float(x) for x, n in zip(E, nu, strict=True))
    assert 1 / inv == pytest.approx(1.3e11, rel=1e-12)
    assert any("kt_scale = 0.5 cannot be carried" in n for n in ex.notes)
    y = export(Contact(CAP, 1.3e11, 0.9, 0.2), "yade")
    assert f"frictionAngle={math.atan(0.2)!r}" in y.text


def test_mujoco_linear_contact_matches_duration_and_restitution():
    """The exported spring–damper (effective k = d·k_in, b = d·b_in) has the Hertz contact
    duration at the reference speed, π/(ω0√(1−ζ²)) = t_c, and e = exp(−ζπ/√(1−ζ²))."""
    c = Contact(CAP, float(CAP.E_eff), 0.7, 0.3)
    ex = to_mujoco(c, impedance=0.95)
    k, b = (-float(x) for x in re.search(r'solref="(\S+) (\S+)"', ex.text).groups())
    k_eff, b_eff = 0.95 * k, 0.95 * b
    w0 = math.sqrt(k_eff)
    zeta = b_eff / (2 * w0)
    assert math.exp(-zeta * math.pi / math.sqrt(1 - zeta**2)) == pytest.approx(0.7, rel=1e-6)
    tc = math.pi / (w0 * math.sqrt(1 - zeta**2))
    assert tc == pytest.approx(hertz_impact(CAP).t_c, rel=1e-6)
    assert 'friction="0.3 ' in ex.text and '<option cone="elliptic"/>' in ex.text


def test_contact_from_fit_json_scene_and_errors(tmp_path):
    f = tmp_path / "fit.json"
    f.write_text(
        json.dumps({"scene": CAP.to_dict(), "values": {"E_eff": {"value": 9e10}, "mu": 0.2}})
    )
    c = contact_from(f)
    assert (c.E_eff, c.mu, c.e, c.kt_scale) == (9e10, 0.2, CAP.e, 1.0)
    assert contact_from(SIDECAR).E_eff == pytest.approx(float(CAP.E_eff))
    # parameters without a scene (a summary written by hand): the scene must be given
    summary = tmp_path / "summary.json"
    summary.write_text(json.dumps({"parameters": {"mu": {"value": 0.3, "vary": True}}}))
    with pytest.raises(InputError, match="does not hold its scene: give the scene too"):
        contact_from(summary)
    assert contact_from(summary, scene=CAP).mu == 0.3
    (tmp_path / "bad.json").write_text("{not json")
    with pytest.raises(InputError, match=r"bad\.json: not valid JSON"):
        contact_from(tmp_path / "bad.json")
    with pytest.raises(InputError, match=r"^unknown export target 'abaqus'; choose one of"):
        export(CAP, "abaqus")
    with pytest.raises(InputError, match="an export needs mu"):
        contact_from(CAP.replace(mu=None))
    with pytest.raises(InputError, match=r"e = 1\.5: give a restitution"):
        Contact(CAP, 1e11, 1.5, 0.1)


def test_a_fit_summary_carries_its_scene_so_it_exports_alone(tmp_path):
    """`pipeline fit --out` then `pipeline export fit.json`: the summary holds the scene the
    fit used; μ and e the scene did not know come from the fit (not an error)."""
    from pipeline.cli import main
    from pipeline.fit import fit_contact
    from pipeline.io import load

    rec = ROOT / "data_samples" / "gr_45deg_0.6ms.csv"
    scene = Scene.from_dict(json.loads(rec.with_suffix(".json").read_text())["scene"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = fit_contact(load(rec), scene.replace(mu=None, e=None), n_boot=0)
    f = tmp_path / "fit.json"
    f.write_text(json.dumps(fit.summary(), allow_nan=False))
    c = contact_from(f)
    for name in ("E_eff", "mu", "e"):
        assert getattr(c, name) == pytest.approx(fit.values[name], rel=1e-12), name
    assert c.scene.radius == scene.radius and c.scene.target_radius == scene.target_radius
    # the CLI: fit, then export the fit file with no --scene
    out = tmp_path / "fit"
    assert main(["fit", str(rec), "--boot", "0", "--out", str(out)]) == 0
    assert main(["export", str(out / "fit.json"), "--to", "yade"]) == 0
