"""The command line reads what Python reads, and answers every bad argument in one line.

Exit statuses (pipeline.cli): 0 success, 1 some records failed, 2 bad input or argument,
3 internal error. Records are the bundled samples (synthetic; provenance in
data_samples/README.md).
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

from pipeline.cli import BLAS_THREADS, main

SAMPLES = Path(__file__).resolve().parents[1] / "data_samples"
MAIN = SAMPLES / "gr_15deg_0.6ms.csv"


def _run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_a_scene_without_elastic_constants_is_told_how_to_give_them_on_the_command_line(
    tmp_path, capsys
):
    """``pipeline fit`` on a record whose sidecar's scene has no E: one line, exit 2, naming
    the scene's JSON keys a command-line user writes, not only Python's Scene(E=...)."""
    shutil.copy(MAIN, tmp_path / MAIN.name)
    side = json.loads(MAIN.with_suffix(".json").read_text(encoding="utf-8"))
    del side["scene"]["E"]
    (tmp_path / MAIN.with_suffix(".json").name).write_text(json.dumps(side), encoding="utf-8")
    code, out, err = _run(capsys, "fit", tmp_path / MAIN.name)
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1, err
    assert '"E" and "nu" in the scene\'s JSON' in err, err


def test_a_hint_the_fit_left_out_says_which_way_the_aic_moved(capsys):
    """Garland & Rogers' 30° record (the sample) hints at a mode its fit does not keep: the
    note says how the AIC moved, never that fitting the mode "lowered" it by a negative
    amount."""
    code, out, _ = _run(capsys, "fit", SAMPLES / "gr_30deg_0.6ms.csv", "--json")
    notes = [n for n in json.loads(out)["fit"]["notes"] if "hinted at" in n]
    assert code == 0 and notes
    for note in notes:
        moved = re.search(r"lowered the AIC by ([-\d.]+) only|it rose by ([-\d.]+)\)", note)
        assert moved and float(moved.group(1) or moved.group(2)) > 0, note


@pytest.mark.parametrize("name", ["wpd_Fn.csv", "wpd_datasets.csv", "sensor.tdms"])
def test_analyse_reads_the_bundled_samples_as_their_sidecars_say(capsys, name):
    """The digitised samples carry no units: the sidecar's 'load' block gives them (and
    combines wpd_Fn.csv with wpd_Ft.csv). This exited 2 before."""
    code, out, err = _run(capsys, "analyse", SAMPLES / name, "--boot", 0, "--json")
    assert code == 0, err
    summary = json.loads(out)
    assert summary["plausibility"]["peak_force"]["status"] == "ok"
    assert summary["scene_sources"]["speed"] == f"scene file {Path(name).stem}.json"


def test_analyse_takes_units_and_axes_on_the_command_line(tmp_path, capsys):
    """A WebPlotDigitizer export without its sidecar: units from the arguments, as
    load(..., time_unit=, force_unit=) takes them; the scene from --scene."""
    shutil.copy(SAMPLES / "wpd_datasets.csv", tmp_path / "w.csv")
    scene = tmp_path / "scene.json"
    scene.write_text(json.dumps(json.loads((SAMPLES / "wpd_datasets.json").read_text())["scene"]))
    code, _, err = _run(capsys, "analyse", tmp_path / "w.csv", "--scene", scene)
    assert code == 2 and "no time unit in the file" in err and err.count("\n") == 1
    argv = ["analyse", tmp_path / "w.csv", "--scene", scene, "--boot", 0, "--json"]
    code, out, err = _run(capsys, *argv, "--time-unit", "us", "--force-unit", "N")
    assert code == 0, err
    assert json.loads(out)["plausibility"]["contact_time"]["status"] == "ok"
    # a wrong unit is caught by the plausibility check, with the unit that fits
    code, _, err = _run(capsys, *argv, "--time-unit", "ms", "--force-unit", "N")
    assert code == 2 and "fit 'us', not 'ms'" in err
    code, out, err = _run(capsys, "analyse", MAIN, "--axes", "Fn=Fz,Ft=-Fx", "--boot", 0, "--json")
    assert code == 0, err
    assert json.loads(out)["rigid"]["regime"] == "sticking"


def test_scene_fields_from_the_record_metadata(tmp_path, capsys):
    """sensor_decimal_comma.csv states '# Impact speed: 0,5 m/s' and '# Angle: 15 deg':
    a scene file without them is completed from the record, and the output says so."""
    shutil.copy(SAMPLES / "sensor_decimal_comma.csv", tmp_path / "r.csv")
    truth = json.loads((SAMPLES / "sensor_decimal_comma.json").read_text())["scene"]
    partial = {k: v for k, v in truth.items() if k not in ("speed", "angle_deg")}
    scene = tmp_path / "scene.json"
    scene.write_text(json.dumps(partial))
    argv = ["analyse", tmp_path / "r.csv", "--scene", scene, "--boot", 0, "--json"]
    code, out, err = _run(capsys, *argv)
    assert code == 0, err
    summary = json.loads(out)
    assert summary["scene"]["speed"] == 0.5 and summary["scene"]["angle_deg"] == 15.0
    assert summary["scene_sources"]["speed"] == "record metadata 'impact_speed' = '0,5 m/s'"
    assert summary["scene_sources"]["radius"] == "scene file scene.json"


def _bad_scenes(tmp_path):
    cases = {
        "malformed.json": b'{"radius": 0.0127,',
        "list.json": b"[1, 2, 3]",
        "latin1.json": '{"radius": 0.0127, "note": "caf\xe9"}'.encode("latin-1"),
    }
    for name, data in cases.items():
        (tmp_path / name).write_bytes(data)
    (tmp_path / "folder.json").mkdir()
    return {
        "malformed.json": "not valid JSON",
        "list.json": "not a list",
        "latin1.json": "not UTF-8",
        "folder.json": "is a directory",
        "missing.json": "no such scene file",
    }


def test_every_bad_scene_is_one_line_and_exit_2(tmp_path, capsys):
    for name, fragment in _bad_scenes(tmp_path).items():
        code, out, err = _run(capsys, "analyse", MAIN, "--scene", tmp_path / name)
        assert code == 2, name
        assert err.startswith("error: ") and err.count("\n") == 1, err
        assert fragment in err and name in err
        assert "Traceback" not in err and not out


@pytest.mark.parametrize(
    "argv,fragment",
    [
        (["analyse", MAIN, "--axes", "Fn"], "is not CHANNEL=COLUMN"),
        (["analyse", MAIN, "--axes", "{bad"], "not a JSON object"),
        (["analyse", MAIN, "--boot", "x"], "'x' is not a whole number"),
        (["analyse", MAIN, "--time-unit", "fortnight"], "is not a time unit"),
        (["analyse", MAIN, "--force-unit", "kg"], "is not a force unit"),
        (["analyse", MAIN, "--axes", "Fn=Fq"], "names no column"),
        (["analyse", MAIN, "--decouple", "no_such.txt"], "no such file"),
        (["analyse", SAMPLES / "no_such.csv"], "no such file"),
        (["analyse"], "the following arguments are required: file"),
        (["frobnicate"], "invalid choice"),
        (["reproduce", "--samples", "no_such_folder"], "no such folder"),
    ],
)
def test_every_bad_argument_is_one_line_and_exit_2(capsys, argv, fragment):
    try:
        code = main([str(a) for a in argv])
    except SystemExit as exc:  # argparse's own errors exit through Parser.error
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2
    assert err.startswith("error: ") and err.count("\n") == 1, err
    assert fragment in err


def test_an_internal_error_is_one_line_and_exit_3(capsys, monkeypatch):
    import pipeline.analysis

    def broken(*args, **kwargs):
        raise ZeroDivisionError("a bug")

    monkeypatch.setattr(pipeline.analysis, "analyse", broken)
    code, _, err = _run(capsys, "analyse", MAIN, "--boot", 0)
    assert code == 3
    assert (
        err == "error: internal error (ZeroDivisionError: a bug); run with -v for the "
        "traceback and report it\n"
    )


# ----------------------------------------------------------------------------- reproduce
def _samples(tmp_path, *names):
    folder = tmp_path / "samples"
    folder.mkdir()
    for name in names:
        for p in SAMPLES.glob(Path(name).stem + ".*"):
            shutil.copy(p, folder / p.name)
    return folder


def test_reproduce_goes_on_past_any_failure_and_exits_1(tmp_path, capsys, monkeypatch):
    """A bad file (InputError) and a bug (any other exception) in one record each: both
    listed with their reason in summary.json and report.md; the rest processed; exit 1."""
    import pipeline.report as report

    folder = _samples(tmp_path, "gr_15deg_0.6ms.csv", "gr_30deg_0.6ms.csv", "wpd_datasets.csv")
    (folder / "broken.csv").write_text("time [s],Fz [N]\n0.0,abc\n", encoding="utf-8")
    real = report.analyse

    def flaky(record, scene, **kw):
        if record.attrs["source"] == "gr_30deg_0.6ms.csv":
            raise KeyError("a bug in a stage")
        return real(record, scene, **kw)

    monkeypatch.setattr(report, "analyse", flaky)
    out = tmp_path / "out"
    code, stdout, _ = _run(capsys, "reproduce", "--samples", folder, "--out", out, "--boot", 0)
    assert code == 1
    summary = json.loads((out / "summary.json").read_text())
    status = {r["file"]: r["status"] for r in summary["records"]}
    assert status == {
        "broken.csv": "failed",
        "gr_15deg_0.6ms.csv": "ok",
        "gr_30deg_0.6ms.csv": "failed",
        "wpd_datasets.csv": "ok",
    }
    assert summary["n_failed"] == 2
    assert summary["failures"]["gr_30deg_0.6ms.csv"] == "KeyError: 'a bug in a stage'"
    assert "line 2" in summary["failures"]["broken.csv"]
    report_md = (out / "report.md").read_text()
    assert "## Failed records" in report_md and "(internal error)" in report_md
    assert "failed: gr_30deg_0.6ms.csv" in stdout
    manifest = json.loads((out / "manifest.json").read_text())
    assert sorted(manifest["files"]) == sorted(
        p.name for p in out.iterdir() if p.name != "manifest.json"
    )


def test_reproduce_without_its_main_record_still_writes_a_report(tmp_path, capsys):
    folder = _samples(tmp_path, "wpd_datasets.csv")
    out = tmp_path / "out"
    code, _, _ = _run(capsys, "reproduce", "--samples", folder, "--out", out, "--boot", 0)
    assert code == 1
    assert "could not be analysed" in (out / "report.md").read_text()
    assert not list(out.glob("*.png"))


@pytest.mark.parametrize(
    "sidecar,fragment",
    [
        (None, "the sidecar is a directory"),
        ('{"load": "x"}', "'load' must be an object"),
        ('{"load": {"time_unt": "us"}}', "did you mean 'time_unit'"),
        ('{"load": {"paths": ["a.csv"]}}', "'paths' must map channels"),
        ('{"scene": {"radius": 0.0127, "density": 7850}}', "does not give speed"),
        ('{"load": {"time_unit": "us"}}', "(load options time_unit from x.json)"),
    ],
)
def test_bad_sidecars_fail_their_record_with_the_sidecar_named(tmp_path, sidecar, fragment):
    from pipeline.report import reproduce

    folder = _samples(tmp_path, "gr_15deg_0.6ms.csv")
    shutil.copy(MAIN, folder / "x.csv")
    if sidecar is None:
        (folder / "x.json").mkdir()
    else:
        (folder / "x.json").write_text(sidecar)
    summary = reproduce(folder, tmp_path / "out", n_boot=0)
    (bad,) = [r for r in summary["records"] if r["file"] == "x.csv"]
    assert bad["status"] == "failed" and fragment in bad["error"], bad["error"]
    assert "x.json" in bad["error"]
    assert summary["findings"] is not None  # the main record went on


def test_analyse_names_the_model_the_scene_needs(capsys):
    """The 15° sample sticks (tan 15° < 3.5·μ·(1+e), docs/theory.md, Rigid bodies), where
    tangential compliance shapes Pt(Pn): advise says Mindlin, in the text and in the JSON."""
    code, out, _ = _run(capsys, "analyse", MAIN, "--boot", 0)
    assert code == 0 and "model needed (tol 0.001): mindlin — sticking" in out
    code, out, _ = _run(capsys, "analyse", MAIN, "--boot", 0, "--json")
    assert code == 0 and json.loads(out)["advice"]["model"] == "mindlin"


def test_analyse_names_an_impossible_outcome_and_its_cause(tmp_path, capsys, caplog):
    """The issue's record: the Ft channel of the opposite sign convention gave e_t = 1.38
    for a ball with no spin on a still surface, with only the quartic's PoorFitWarning. Now
    the bound it breaks and the likeliest cause are named, in the log and in the JSON."""
    lines = MAIN.read_text(encoding="utf-8").splitlines()
    i = next(k for k, ln in enumerate(lines) if not ln.startswith("#"))
    rows = []
    for r in lines[i + 1 :]:
        cells = r.split(",")
        cells[1] = repr(-float(cells[1]))  # Fx, the tangential axis
        rows.append(",".join(cells))
    p = tmp_path / "flipped.csv"
    p.write_text("\n".join([*lines[: i + 1], *rows]) + "\n", encoding="utf-8")
    shutil.copy(MAIN.with_suffix(".json"), p.with_suffix(".json"))
    code, out, err = _run(capsys, "analyse", p, "--boot", 0)
    assert code == 0, err
    logged = caplog.text  # the CLI's log lines (pipeline.cli._common.log_warnings)
    assert "TangentialRestitutionWarning" in logged and "opposite sign convention" in logged
    assert "e_t_bound warning" in out
    code, out, err = _run(capsys, "analyse", p, "--boot", 0, "--json")
    check = json.loads(out)["plausibility"]["e_t_bound"]
    assert check["status"] == "warning" and check["measured"] == pytest.approx(1.38, abs=0.01)


def test_log_warnings_only_the_pipelines_own_are_warnings(caplog):
    """A normal run's log holds the library's findings (WARNING), not another library's
    noise: a dask client's unclosed socket is an INFO line (shown with -v), and a warning
    repeated is logged once."""
    import logging

    from pipeline.cli._common import log_warnings
    from pipeline.errors import PoorFitWarning

    with caplog.at_level(logging.DEBUG, logger="pipeline"), log_warnings():
        warnings.warn("unclosed <socket.socket fd=12>", ResourceWarning, stacklevel=1)
        for _ in range(2):
            warnings.warn("Fn: the quartic misses structure", PoorFitWarning, stacklevel=1)
    got = [(r.levelname, r.getMessage()) for r in caplog.records]
    assert got == [
        ("INFO", "ResourceWarning: unclosed <socket.socket fd=12>"),
        ("WARNING", "PoorFitWarning: Fn: the quartic misses structure"),
    ]


def test_record_options_travel_as_json_with_absolute_paths(tmp_path, monkeypatch):
    """The record options a campaign's manifest and a report's parameters cell keep are
    JSON, the decoupling matrix's path absolute (a notebook run from elsewhere, a worker
    in another folder read the same file); options not given are left to the sidecar."""
    import argparse

    from pipeline.cli._common import load_options

    monkeypatch.chdir(tmp_path)
    args = argparse.Namespace(
        time_unit=None,
        force_unit="N",
        axes=None,
        decouple=Path("rig/matrix.json"),
        sensitivity={"Ft": [0.5, "mV/N"]},
    )
    got = load_options(args)
    assert got == {
        "force_unit": "N",
        "decouple": str((tmp_path / "rig" / "matrix.json").resolve()),
        "sensitivity": {"Ft": [0.5, "mV/N"]},
    }
    assert json.loads(json.dumps(got)) == got


_BLAS_DURING_A_COMMAND = """
import contextlib, io, json, os
from threadpoolctl import threadpool_info
import pipeline.cli as cli

def blas():
    return {"env": os.environ.get("OPENBLAS_NUM_THREADS"),
            "threads": {i["filepath"]: i["num_threads"] for i in threadpool_info()
                        if i["user_api"] == "blas"}}

seen, run = {"before": blas()}, cli._run

def spy(args):
    seen["during"] = blas()
    return run(args)

cli._run = spy
with contextlib.redirect_stderr(io.StringIO()):
    seen["status"] = cli.main(["fit", "no-such-record.csv"])
seen["after"] = blas()
print(json.dumps(seen))
"""


@pytest.mark.parametrize("user", [None, "2"])
def test_the_command_runs_on_one_blas_thread_unless_the_user_chose(user):
    """A command limits the loaded BLAS to one thread, and sets the variable for the
    processes it starts, until it returns (a command run from Python leaves the process
    as it was); a number the user set is left as it is."""
    env = {k: v for k, v in os.environ.items() if k not in BLAS_THREADS}
    if user is not None:
        env["OPENBLAS_NUM_THREADS"] = user
    out = subprocess.run(
        [sys.executable, "-c", _BLAS_DURING_A_COMMAND],
        capture_output=True,
        text=True,
        check=True,
        env=env,
    )
    got = json.loads(out.stdout)
    assert got["status"] == 2  # the record does not exist: bad input, under the limit
    before, during, after = got["before"], got["during"], got["after"]
    assert before["threads"], "no BLAS library loaded"
    # as it was before, for the libraries loaded then (one loaded by the command, e.g.
    # scipy's, keeps the threads the command's variables gave it)
    assert after["env"] == before["env"]
    assert {k: after["threads"][k] for k in before["threads"]} == before["threads"]
    if user is None:
        assert during["env"] == "1"
        assert set(during["threads"].values()) == {1}
    else:
        assert during == before and before["env"] == user
