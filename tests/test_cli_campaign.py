"""The campaign, report and export commands: every bad argument is one line on stderr and
exit status 2, never a traceback; --help documents every option; the campaign and export
commands write what they say, with progress bars on request."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from pipeline.cli import COMMANDS, main

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = ROOT / "data_samples"


def _run(args, tmp_path):
    """The real command in a subprocess: exit status, stdout, stderr."""
    out = subprocess.run(
        [sys.executable, "-m", "pipeline.cli", *args],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        check=False,
    )
    return out.returncode, out.stdout, out.stderr


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["campaign", str(SAMPLES), "--workers", "x"], "argument --workers: 'x' is not a whole"),
        (["campaign", str(SAMPLES), "--workers", "0"], "argument --workers: give a whole number"),
        (["campaign", str(SAMPLES), "--boot", "-3"], "argument --boot: -3 is negative"),
        (["campaign", "nowhere/*.csv"], "the pattern 'nowhere/*.csv' matches no record file"),
        (["campaign", str(SAMPLES), "--workers", "2", "--batched"], "not allowed with"),
        (["campaign", str(SAMPLES), "--table", "missing.csv"], "no such table file"),
        (["export", "missing.json", "--to", "lammps"], "missing.json: no such file"),
        (["export", str(SAMPLES / "gr_5deg_0.3ms.json"), "--to", "abaqus"], "invalid choice"),
        (["export", str(SAMPLES / "gr_5deg_0.3ms.json")], "the following arguments are required"),
        (["report", "missing.csv"], "missing.csv: no such file; check the path"),
        (["campaign"], "the following arguments are required: DIR|GLOB|FILE"),
        (["frobnicate"], "invalid choice: 'frobnicate'"),
    ],
)
def test_bad_arguments_are_one_line_and_exit_2(args, message, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    try:
        code = main(args)
    except SystemExit as ex:  # argparse's own errors
        code = ex.code
    err = capsys.readouterr().err
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert message in lines[0]
    assert "Traceback" not in err


def _without(monkeypatch, *modules):
    """This process as one where ``modules`` are not installed (their lookup finds none)."""
    import importlib.util

    find = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name in modules else find(name, *a)
    )
    for m in modules:  # an import fails as it would
        monkeypatch.setitem(sys.modules, m, None)


@pytest.mark.parametrize(
    ("args", "missing"),
    [
        (["--no-html"], "nbclient"),  # the campaign's own report is executed
        ([], "nbconvert"),
        (["--no-html"], "jupytext"),  # every notebook's template
        ([], "bokeh"),
    ],
)
def test_campaign_without_the_reports_extra_stops_before_any_record(
    args, missing, tmp_path, capsys, monkeypatch
):
    """A missing package of the 'reports' extra is told before the run, in one line (exit
    2), not after an overnight campaign; no record is analysed and nothing is written."""
    import pipeline.campaigns

    def never(*a, **k):
        raise AssertionError("a record was analysed")

    monkeypatch.setattr(pipeline.campaigns, "campaign", never)
    _without(monkeypatch, missing)
    out = tmp_path / "out"
    code = main(["campaign", str(SAMPLES / "gr_45deg_0.3ms.csv"), "--out", str(out), *args])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert len(err) == 1, err
    assert f"need {missing}:" in err[0] or f"needs {missing}:" in err[0], err
    assert "--no-reports" in err[0]
    assert not out.exists()


def test_a_wrong_path_is_told_before_a_missing_extra(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    _without(monkeypatch, "bokeh", "nbclient")
    code = main(["campaign", "nowhere/*.csv"])
    err = capsys.readouterr().err
    assert code == 2
    assert "the pattern 'nowhere/*.csv' matches no record file" in err


def test_report_without_the_reports_extra_stops_before_the_analysis(
    tmp_path, capsys, monkeypatch
):
    import pipeline.notebook_report

    def never(*a, **k):
        raise AssertionError("the record was analysed")

    monkeypatch.setattr(pipeline.notebook_report, "record_report", never)
    _without(monkeypatch, "nbformat")
    code = main(["report", str(SAMPLES / "gr_45deg_0.3ms.csv"), "--out", str(tmp_path / "r")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert len(err) == 1 and "notebook reports need nbformat" in err[0], err


def test_argparse_errors_exit_2(capsys):
    with pytest.raises(SystemExit) as ex:
        main(["campaign", str(SAMPLES), "--workers", "x"])
    assert ex.value.code == 2


def test_every_option_has_help():
    """Every option of every subcommand carries a help text (argparse's own -h aside)."""
    import argparse

    parser = argparse.ArgumentParser()
    sub = parser.add_subparsers()
    for command in COMMANDS:
        command.register(sub)
    for name, p in sub.choices.items():
        for action in p._actions:
            if isinstance(action, argparse._HelpAction):
                continue
            if name in ("campaign", "report", "export"):
                assert action.help, f"pipeline {name} {action.option_strings or action.dest}"


def test_campaign_command_writes_dataset_figures_and_reports(tmp_path):
    files = [str(SAMPLES / "gr_45deg_0.3ms.csv")]
    bad = tmp_path / "broken.csv"
    bad.write_text("time [s],Fz [N]\n0,1\n")
    code, out, err = _run(
        ["campaign", *files, str(bad), "--out", "camp", "--boot", "0", "--progress"], tmp_path
    )
    assert code == 1, err  # some records failed; the rest are in the outputs
    assert re.search(r"^1/2 records analysed in [\d.]+ s → camp/$", out, flags=re.M), out
    assert "failed: broken.csv:" in out
    camp = tmp_path / "camp"
    assert (camp / "campaign.nc").is_file() and (camp / "campaign.csv").is_file()
    manifest = json.loads((camp / "manifest.json").read_text())
    assert "campaign.nc" in manifest["files"] and "reports/campaign.html" in manifest["files"]
    assert "overview.html" in manifest["files"]  # the records to explore in a browser
    assert not list(tmp_path.glob(".camp.*")), "the staging folder was swapped in"
    assert {p.name for p in camp.glob("campaign_*.png")} >= {"campaign_outcomes.png"}
    reports = camp / "reports"
    assert {p.name for p in reports.iterdir()} == {
        "gr_45deg_0.3ms.ipynb",
        "gr_45deg_0.3ms.html",
        "campaign.ipynb",
        "campaign.html",
    }
    assert "records: 100%" in err and "campaign report: 100%" in err  # tqdm bars on request


@pytest.mark.skipif(shutil.which("lmp") is None, reason="LAMMPS (lmp) is not installed")
def test_export_command_writes_a_script_lammps_runs(tmp_path):
    code, out, err = _run(
        [
            "export",
            str(SAMPLES / "gr_45deg_0.6ms.json"),
            "--to",
            "lammps",
            "--script",
            "--out",
            "in.impact",
        ],
        tmp_path,
    )
    assert code == 0, err
    assert out.strip() == "lammps input → in.impact"
    assert "note: needs 'units si'" in err
    run = subprocess.run(
        ["lmp", "-in", "in.impact", "-log", "none"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        check=False,
    )
    assert "RESULT e_n 0.8" in run.stdout or "RESULT e_n 0.9" in run.stdout, run.stdout[-500:]


def test_analyse_prints_a_readable_summary_and_writes_its_files(tmp_path, capsys):
    """By default a person's summary — regime, measured outcomes beside Routh's, the score
    with uncertainties, where each scene value came from — with the numbers of --json."""
    import json as _json

    rec = SAMPLES / "gr_45deg_0.3ms.csv"
    assert main(["analyse", str(rec), "--boot", "30", "--out", str(tmp_path / "a")]) == 0
    text = capsys.readouterr().out
    assert main(["analyse", str(rec), "--boot", "30", "--json"]) == 0
    summary = _json.loads(capsys.readouterr().out)
    assert "regime (Routh): sliding" in text and summary["rigid"]["regime"] == "sliding"
    e_t = summary["outcomes"]["e_t"]
    assert f"{e_t['value']:.4g} ± {e_t['std']:.2g}" in text
    assert re.search(r"^  speed +0\.3 m/s +scene file gr_45deg_0\.3ms\.json$", text, flags=re.M)
    # each scene value in the unit a person reads, never a power of ten (E = 210 GPa)
    assert re.search(r"^  E +210 GPa +scene file", text, flags=re.M)
    assert re.search(r"^  radius +12\.7 mm ", text, flags=re.M)
    scene_block = text.split("where they came from:")[1].split("\n\n")[0]
    assert "e+" not in scene_block and "e-" not in scene_block
    assert "max_distance" in text and "±" in text
    files = {p.name for p in (tmp_path / "a").iterdir()}
    assert files == {"summary.json", "summary.txt", "fig8_forces.png", "fig9_percussion_plane.png"}
    assert (tmp_path / "a" / "summary.txt").read_text().strip() == text.strip()


def test_report_md_describes_the_record_given(tmp_path):
    """A lab's own record (not synthetic, μ not in its scene): report.md names it, takes μ
    from the record's fit and says so, and does not call it synthetic or bundled."""
    from pipeline.report import reproduce

    samples = tmp_path / "mine"
    samples.mkdir()
    shutil.copy(SAMPLES / "gr_30deg_0.6ms.csv", samples / "run7.csv")
    scene = json.loads((SAMPLES / "gr_30deg_0.6ms.json").read_text())["scene"]
    del scene["mu"]
    (samples / "run7.json").write_text(json.dumps({"scene": scene}))
    reproduce(samples, tmp_path / "out", main="run7.csv", n_boot=0)
    text = (tmp_path / "out" / "report.md").read_text()
    assert "on the record `run7.csv` — a 25.4 mm ball at 0.6 m/s and 30°" in text
    assert re.search(r"μ = 0\.1\d+ \(from the fit\), e = 0\.9 \(from the scene\)", text)
    assert "synthetic" not in text.lower() and "bundled" not in text
    assert "## All 1 records" in text
