"""The files labs write: LabVIEW Measurement (.lvm), MATLAB (.mat v5 and v7.3), and
channels recorded in volts with a stated sensitivity.

Real files written by LabVIEW and by MATLAB (tests/data/README.md says where each comes
from) are read to the numbers written in them; the project's own samples
(data_samples/README.md) to the numbers their generator put in, read back with an
independent reader (scipy, h5py, the text itself); the sensitivity against hand
arithmetic (F = U / S); every refusal against its exception and message.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest
import scipy.io

from pipeline.errors import InputError
from pipeline.io import load, mat_variables, parse_sensitivity, read_lvm, read_mat, sniff_format
from pipeline.io.mat import Unsupported
from pipeline.report import load_sample

ROOT = Path(__file__).resolve().parents[1]
LVM = ROOT / "tests" / "data" / "lvm"
MAT = ROOT / "tests" / "data" / "mat"
SAMPLES = ROOT / "data_samples"


def _raises(fragment, fn, *args, **kwargs):
    with pytest.raises(InputError) as info:
        fn(*args, **kwargs)
    assert fragment in str(info.value), str(info.value)
    return info.value


# ------------------------------------------------------------------------- sensitivity
@pytest.mark.parametrize(
    ("value", "unit", "newtons_per_volt"),
    [
        (0.225, "mV/N", 1 / 0.225e-3),  # S = 0.225 mV/N → k = 4444.4 N/V
        (0.002, "V/N", 500.0),  # S = 2 mV/N
        (4444.0, "N/V", 4444.0),
        (4.4, "N/mV", 4400.0),  # 4.4 N per mV = 4400 N per V
        (22.5, "mV/kN", 1e3 / 22.5e-3),  # 22.5 mV per kN = 0.0225 mV/N
        (10.0, "µV/N", 1e5),
    ],
)
def test_sensitivity_units_against_hand_arithmetic(value, unit, newtons_per_volt):
    s = parse_sensitivity({"Fn": (value, unit)})["Fn"]
    assert s.newtons_per_volt == pytest.approx(newtons_per_volt, rel=1e-12)
    assert (s.value, s.unit) == (value, unit)


@pytest.mark.parametrize(
    ("spec", "fragment"),
    [
        ({"Fn": (0.225, "mV/V")}, "a bridge's ratiometric rating (0.225 mV/V), not a sensitivity"),
        ({"Fn": (0.225, "mV")}, "unit 'mV' is neither a voltage per force"),
        ({"Fn": (-0.225, "mV/N")}, "a sensitivity is a positive finite number"),
        ({"Fn": (0.0, "mV/N")}, "a sensitivity is a positive finite number"),
        ({"Fn": ("0.225", "mV/N")}, "the value '0.225' must be a number"),
        ({"Fn": 0.225}, "give (value, unit)"),
        ({"Fn": "about 0.2"}, "is not a number and a unit"),
        ([("Fn", 0.225)], "sensitivity must be a dict"),
    ],
)
def test_bad_sensitivities(spec, fragment):
    _raises(fragment, parse_sensitivity, spec)


def test_a_text_sensitivity_with_a_decimal_comma():
    s = parse_sensitivity({"Fn": "0,225 mV/N", "Ft": [0.5, "mV/N"]})
    assert s["Fn"].newtons_per_volt == pytest.approx(1 / 0.225e-3, rel=1e-12)
    assert s["Ft"].newtons_per_volt == pytest.approx(2000.0, rel=1e-12)


def _csv(tmp_path, text, name="volts.csv"):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def test_csv_in_millivolts_through_the_sensitivity(tmp_path):
    p = _csv(tmp_path, "time [us],Fz [mV],Fx [V]\n0,22.5,0.05\n1,45,-0.1\n")
    rec = load(p, sensitivity={"Fn": (0.225, "mV/N"), "Ft": (0.5, "mV/N")})
    # 22.5 mV / 0.225 mV/N = 100 N; 0.05 V / 0.5 mV/N = 100 N
    np.testing.assert_allclose(rec["Fn"].values, [100.0, 200.0], rtol=1e-12)
    np.testing.assert_allclose(rec["Ft"].values, [100.0, -200.0], rtol=1e-12)
    assert rec.attrs["sensitivity"] == "Fn=0.225 mV/N,Ft=0.5 mV/N"
    assert rec.attrs["source_force_unit"] == "V,mV"


def test_csv_volts_without_sensitivity_names_the_column(tmp_path):
    p = _csv(tmp_path, "time [s],Fz [V]\n0,0.1\n1,0.2\n")
    err = _raises("Fn (column 'Fz [V]') is in volts ('V'), not a force unit", load, p)
    assert (err.line, err.column) == (1, "Fz [V]")
    assert "sensitivity={'Fn': (0.225, 'mV/N')}" in str(err)


@pytest.mark.parametrize(
    ("text", "kwargs", "fragment"),
    [
        ("time [s],Fz [N]\n0,1\n1,2\n", {"sensitivity": {"Fn": (0.2, "mV/N")}},
         "Fn (column 'Fz [N]') is already a force in 'N': its sensitivity 0.2 mV/N applies"),
        ("time [s],Fz [V]\n0,1\n1,2\n", {"sensitivity": {"Fn": (0.2, "mV/N"),
                                                          "Ft": (1, "mV/N")}},
         "sensitivity given for Ft, but the record has no Ft channel"),
        ("time [s],Fz [V],T [V]\n0,1,2\n1,2,3\n", {"sensitivity": {"Fn": (0.2, "mV/N"),
                                                                   "T": (1, "mV/N")}},
         "sensitivity given for column 'T [V]', which the record does not read"),
        ("time [s],Fz [V]\n0,1\n1,2\n", {"sensitivity": {"Fq": (0.2, "mV/N")}},
         "'Fq', which is neither a record channel (Fn, Ft, Fy) nor a column of the file"),
        ("time,Fz\n0,1\n1,2\n", {"time_unit": "s", "force_unit": "Ohm"},
         "force_unit='Ohm' is not a force unit"),
    ],
)  # fmt: skip
def test_sensitivity_refusals(tmp_path, text, kwargs, fragment):
    _raises(fragment, load, _csv(tmp_path, text), **kwargs)


def test_force_unit_volts_for_a_file_without_units(tmp_path):
    p = _csv(tmp_path, "time,Fz\n0,0.45\n1,0.9\n")
    rec = load(p, time_unit="ms", force_unit="V", sensitivity={"Fn": (4.5, "mV/N")})
    np.testing.assert_allclose(rec["Fn"].values, [100.0, 200.0], rtol=1e-12)


def test_file_columns_as_keys_for_the_decoupling(tmp_path):
    """The raw axes a decoupling matrix reads are named by their columns (Fx, Fz), the
    record channel Fy by its own name: each in volts, each with its sensitivity."""
    p = _csv(tmp_path, "time [s],Fx [V],Fy [V],Fz [V]\n0,0.1,0.002,0.3\n1,0.2,0.004,0.6\n")
    m = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.1, 0.0, 1.0]])
    s = {"Fx": (1.0, "mV/N"), "Fy": (2.0, "mV/N"), "Fz": (4.0, "mV/N")}
    rec = load(p, decouple=m, sensitivity=s)
    fx, fz = np.array([100.0, 200.0]), np.array([75.0, 150.0])  # 0.1 V / 1 mV/N; 0.3 / 4
    np.testing.assert_allclose(rec["Ft"].values, fx, rtol=1e-12)
    np.testing.assert_allclose(rec["Fy"].values, [1.0, 2.0], rtol=1e-12)
    np.testing.assert_allclose(rec["Fn"].values, fz + 0.1 * fx, rtol=1e-12)
    _raises(
        "Fn (column 'Fz [V]') is in volts ('V'), not a force unit",
        load,
        p,
        decouple=m,
        sensitivity={"Fx": (1.0, "mV/N"), "Fy": (2.0, "mV/N")},
    )


def test_tdms_channel_in_volts(tmp_path):
    from nptdms import ChannelObject, TdmsWriter

    p = tmp_path / "v.tdms"
    wf = {"wf_start_offset": 0.0, "wf_increment": 1e-6, "wf_samples": 3, "unit_string": "V"}
    with TdmsWriter(p) as w:
        w.write_segment([ChannelObject("g", "Fz", np.array([0.1, 0.2, 0.4]), properties=wf)])
    rec = load(p, sensitivity={"Fn": (2.0, "N/mV")})  # 0.1 V = 100 mV → 200 N
    np.testing.assert_allclose(rec["Fn"].values, [200.0, 400.0, 800.0], rtol=1e-12)
    assert rec.attrs["sensitivity"] == "Fn=2 N/mV"
    _raises("Fn (column 'Fz') is in volts ('V')", load, p)


def test_digitised_exports_refuse_a_sensitivity():
    _raises(
        "sensitivity= does not apply to digitised exports; they hold forces, not volts",
        load,
        SAMPLES / "wpd_datasets.csv",
        time_unit="us",
        force_unit="N",
        sensitivity={"Fn": (1.0, "mV/N")},
    )


def test_sidecar_sensitivity_at_the_top_level_or_in_load(tmp_path):
    shutil.copy(SAMPLES / "sensor_volts.lvm", tmp_path / "r.lvm")
    side = tmp_path / "r.json"
    side.write_text(json.dumps({"sensitivity": {"Fn": [0.225, "mV/N"], "Ft": [0.5, "mV/N"]}}))
    top = load_sample(tmp_path / "r.lvm")
    side.write_text(
        json.dumps({"load": {"sensitivity": {"Fn": [0.225, "mV/N"], "Ft": [0.5, "mV/N"]}}})
    )
    inner = load_sample(tmp_path / "r.lvm")
    np.testing.assert_array_equal(top["Fn"].values, inner["Fn"].values)
    # the command line's value wins over the sidecar's
    over = load_sample(tmp_path / "r.lvm", sensitivity={"Fn": (0.45, "mV/N"), "Ft": (1, "mV/N")})
    np.testing.assert_allclose(over["Fn"].values, top["Fn"].values / 2, rtol=1e-12)
    side.write_text(
        json.dumps(
            {"sensitivity": {"Fn": [0.225, "mV/N"]}, "load": {"sensitivity": {"Fn": [1, "V/N"]}}}
        )
    )
    _raises("'sensitivity' is given twice", load_sample, tmp_path / "r.lvm")
    side.write_text(json.dumps({"load": {"sensitivity": {"Fn": [0.225, "mV/V"]}}}))
    _raises("(load options sensitivity from r.json)", load_sample, tmp_path / "r.lvm")


def test_cli_sensitivity_option(tmp_path, capsys):
    from pipeline.cli import main
    from pipeline.cli._common import parse_sensitivity_option

    got = parse_sensitivity(parse_sensitivity_option("Fn=0,225 mV/N;Ft=0.5mV/N"))
    assert got["Fn"].newtons_per_volt == pytest.approx(1 / 0.225e-3, rel=1e-12)
    assert got["Ft"].newtons_per_volt == pytest.approx(2000.0, rel=1e-12)
    assert parse_sensitivity_option('{"Fn": [2, "N/V"]}') == {"Fn": [2.0, "N/V"]}
    rec = tmp_path / "drop.lvm"
    shutil.copy(SAMPLES / "sensor_volts.lvm", rec)  # no sidecar: nothing states the rig
    assert main(["analyse", str(rec), "--boot", "0"]) == 2
    err = capsys.readouterr().err
    assert "Fn (column 'Fz') is in volts ('Volts'), not a force unit" in err
    with pytest.raises(SystemExit) as stop:
        main(["analyse", str(rec), "--sensitivity", "Fn=0.225mV/V"])
    assert stop.value.code == 2
    assert "argument --sensitivity: sensitivity['Fn'] is a bridge's" in capsys.readouterr().err


def _volts_without_sensitivity(folder: Path, names=("drop.lvm",)) -> list[Path]:
    """Copies of the LabVIEW sample whose sidecars hold the scene but no sensitivity."""
    side = json.loads((SAMPLES / "sensor_volts.json").read_text())
    del side["sensitivity"]
    out = []
    for name in names:
        rec = folder / name
        shutil.copy(SAMPLES / "sensor_volts.lvm", rec)
        rec.with_suffix(".json").write_text(json.dumps(side))
        out.append(rec)
    return out


SENSITIVITY = "Fn=0.225mV/N,Ft=0.5mV/N"


def test_cli_campaign_sensitivity_reads_every_record(tmp_path, capsys):
    """pipeline campaign --sensitivity: each record's volts become newtons (the sample's
    normal pulse peaks at Hertz's F_max for its scene, 1126.7 N, noise σ 2 N), and the
    manifest keeps the option."""
    import xarray as xr

    from pipeline import Scene
    from pipeline.cli import main
    from pipeline.contact import hertz_impact

    runs = tmp_path / "runs"
    runs.mkdir()
    _volts_without_sensitivity(runs, ("a.lvm", "b.lvm"))
    out = tmp_path / "out"
    fast = ["--no-reports", "--no-fit", "--boot", "0"]
    code = main(["campaign", str(runs), "--out", str(out), *fast, "--sensitivity", SENSITIVITY])
    assert code == 0, capsys.readouterr().err
    with xr.open_dataset(out / "campaign.nc") as ds:
        assert list(ds["status"].values) == ["ok", "ok"]
        f_max = ds["F_max"].values
    scene = Scene.from_dict(json.loads((SAMPLES / "sensor_volts.json").read_text())["scene"])
    np.testing.assert_allclose(f_max, hertz_impact(scene).F_max, atol=12.0)
    settings = json.loads((out / "manifest.json").read_text())["settings"]
    assert settings["load"] == {"sensitivity": {"Fn": [0.225, "mV/N"], "Ft": [0.5, "mV/N"]}}


def test_campaign_load_reaches_the_joint_fit(tmp_path):
    """campaign(load=...) reads the records with it in the joint fit too (it reads them
    again from their files): without it the joint fit would fail on the volts."""
    from pipeline import campaign

    files = _volts_without_sensitivity(tmp_path, ("a.lvm", "b.lvm"))
    load = {"sensitivity": {"Fn": (0.225, "mV/N"), "Ft": (0.5, "mV/N")}}
    ds = campaign(files, load=load, n_boot=0)
    assert list(ds["status"].values) == ["ok", "ok"]
    assert "joint_fit_error" not in ds.attrs
    assert json.loads(ds.attrs["joint_fit_json"])["records"] == ["a.lvm", "b.lvm"]


def test_cli_report_sensitivity_and_its_notebook_reads_the_same(tmp_path, capsys):
    """pipeline report --sensitivity: the report is made, and its parameters cell states
    the option, so that the notebook run again reads the same newtons."""
    import ast

    import nbformat

    from pipeline.cli import main

    (rec,) = _volts_without_sensitivity(tmp_path)
    out = tmp_path / "reports"
    args = ["report", str(rec), "--out", str(out), "--boot", "0", "--no-html"]
    assert main(args) == 2
    assert "is in volts ('Volts')" in capsys.readouterr().err
    assert main([*args, "--sensitivity", SENSITIVITY]) == 0, capsys.readouterr().err
    nb = nbformat.read(out / "drop.ipynb", as_version=4)
    (cell,) = [c for c in nb.cells if "injected-parameters" in c.metadata.get("tags", [])]
    line = next(ln for ln in cell.source.splitlines() if ln.startswith("load_options = "))
    options = ast.literal_eval(line.removeprefix("load_options = "))
    again = load_sample(rec, **options)
    unit = {"Fn": (1.0, "N/V"), "Ft": (1.0, "N/V")}  # 1 N/V: the volts as they are
    fz = load(SAMPLES / "sensor_volts.lvm", sensitivity=unit)["Fn"].values
    np.testing.assert_allclose(again["Fn"].values, fz / 0.225e-3, rtol=1e-12)
    assert main(["report", str(tmp_path / "c.nc"), "--sensitivity", SENSITIVITY]) == 2
    err = capsys.readouterr().err
    assert "no such file" in err
    (tmp_path / "c.nc").write_bytes(b"")
    assert main(["report", str(tmp_path / "c.nc"), "--sensitivity", SENSITIVITY]) == 2
    assert "--sensitivity says how to read a record" in capsys.readouterr().err


# ----------------------------------------------------------------- LabVIEW: real files
def test_lvm_real_file_in_volts_with_sensitivities():
    """relay_express_default.lvm: LabVIEW wrote two channels in V, X0 = 0, Delta_X = 1."""
    p = LVM / "relay_express_default.lvm"
    assert sniff_format(p) == "lvm"
    axes = {"Fn": "Untitled", "Ft": "Untitled 1"}
    rec = load(p, axes=axes, sensitivity={"Fn": (0.225, "mV/N"), "Ft": (2.0, "N/V")})
    np.testing.assert_allclose(rec["time"].values, [0.0, 1.0, 2.0], rtol=0, atol=0)
    np.testing.assert_allclose(rec["Fn"].values, np.array([1.0, 2.5, -3.25]) / 0.225e-3)
    np.testing.assert_allclose(rec["Ft"].values, [8.0, 10.0, 12.0], rtol=1e-15)
    assert rec.attrs["format"] == "lvm" and rec.attrs["source_force_unit"] == "V"
    assert rec.attrs["sensitivity"] == "Fn=0.225 mV/N,Ft=2 N/V"
    assert rec.attrs["meta_operator"] == "Havie" and rec.attrs["lvm_x_columns"] == "One"
    err = _raises("Fn (column 'Untitled') is in volts ('V'), not a force unit", load, p, axes=axes)
    assert err.column == "Untitled"
    _raises("no normal-force channel: the file has no 'Fn' or 'Fz' column (force columns: "
            "none; other columns: Untitled, Untitled 1)", load, p)  # fmt: skip


@pytest.mark.parametrize(
    ("name", "mode", "ft"),
    [
        ("x_columns_no.lvm", "No", [4.0, 5.0, 6.0]),
        ("x_columns_multi.lvm", "Multi", [4.0, 5.0, 6.0]),
    ],
)
def test_lvm_real_x_columns_no_and_multi(name, mode, ft):
    """No: an empty X cell, time = X0 + k·Delta_X; Multi: an X column per channel."""
    rec = load(LVM / name, axes={"Fn": "Untitled", "Ft": "Untitled 1"}, force_unit="N")
    np.testing.assert_array_equal(rec["time"].values, [0.0, 1.0, 2.0])
    np.testing.assert_array_equal(rec["Fn"].values, [1.0, 2.5, -3.25])
    np.testing.assert_array_equal(rec["Ft"].values, ft)
    assert rec.attrs["lvm_x_columns"] == mode


def test_lvm_real_segments():
    p = LVM / "segments.lvm"
    _raises(
        "the file holds 3 segments (0: line 22, Untitled, Untitled 1; 1: line 35, Untitled; "
        "2: line 48, Untitled, Untitled 1, Untitled 2); read one with "
        "pipeline.io.read_lvm(path, segment=k)",
        load,
        p,
        axes={"Fn": "Untitled"},
        force_unit="N",
    )
    rec = read_lvm(p, segment=1, axes={"Fn": "Untitled"}, force_unit="N")
    np.testing.assert_array_equal(rec["Fn"].values, [3.0, 4.0, 5.0])
    assert rec.attrs["meta_comment"] == "line 36: second pass"
    assert (rec.attrs["lvm_segment"], rec.attrs["lvm_segments"]) == (1.0, 3.0)
    _raises("segment=3 but the file holds 3 segment(s) (0 to 2)", read_lvm, p, segment=3)


def test_lvm_segment_header_without_its_blank_line_is_not_read_as_data(tmp_path):
    """A damaged copy where the blank line before a segment header is lost: the header's
    lines (Channels 1, Samples 3...) must not become samples of the segment before."""
    raw = (LVM / "segments.lvm").read_bytes().replace(b"\r\n\r\nChannels", b"\r\nChannels", 1)
    p = tmp_path / "joined.lvm"
    p.write_bytes(raw)
    rec = read_lvm(p, segment=0, axes={"Fn": "Untitled"}, force_unit="N")
    np.testing.assert_array_equal(rec["Fn"].values, [1.0, 2.5, -3.25])
    assert read_lvm(p, segment=1, axes={"Fn": "Untitled"}, force_unit="N").sizes["time"] == 3


def test_lvm_real_one_header_only_appended_write_is_named():
    err = _raises(
        "time goes backwards (2.0 then 0.0 s); time must strictly increase (with 'one header "
        "only' LabVIEW appends a later write",
        load,
        LVM / "one_header_same.lvm",
        axes={"Fn": "Untitled"},
        force_unit="N",
    )
    assert (err.line, err.column) == (26, "X_Value")


def test_lvm_real_escapes_and_code_page():
    rec = load(LVM / "description.lvm", axes={"Fn": "Untitled"}, force_unit="N")
    assert rec.attrs["meta_description"] == "line one\r\nline two\tx, y\\z"
    rec = load(LVM / "comment_cp1252.lvm", axes={"Fn": "Untitled"}, force_unit="N")
    assert rec.attrs["encoding"] == "cp1252"
    assert rec.attrs["meta_comment"] == "line 23: café ñ µ €"
    np.testing.assert_array_equal(rec["Fn"].values, [1.0, 2.5, -3.25])


def test_lvm_sample_reads_to_the_text_and_the_hertz_pulse():
    """data_samples/sensor_volts.lvm: 1 MHz from X0 = −20 µs, Fz and Fx in volts at 0.225
    and 0.5 mV/N; the sidecar states them. Values checked against the file's own text."""
    p = SAMPLES / "sensor_volts.lvm"
    rec = load_sample(p)
    n = rec.sizes["time"]
    np.testing.assert_allclose(rec["time"].values, -20e-6 + 1e-6 * np.arange(n), rtol=1e-12)
    rows = p.read_bytes().decode("ascii").split("\r\n")
    start = rows.index("X_Value\tFz\tFx\tTrigger\tComment") + 1
    cells = [r.split("\t") for r in rows[start : start + n]]
    fz = np.array([float(c[1].replace(",", ".")) for c in cells])
    fx = np.array([float(c[2].replace(",", ".")) for c in cells])
    np.testing.assert_allclose(rec["Fn"].values, fz / 0.225e-3, rtol=1e-12)
    np.testing.assert_allclose(rec["Ft"].values, fx / 0.5e-3, rtol=1e-12)
    # the exact elastic Hertz pulse peaks at 1126.7 N (data_samples/README.md); noise 2 N
    assert float(rec["Fn"].max()) == pytest.approx(1126.7, abs=12.0)
    assert rec.attrs["sensitivity"] == "Fn=0.225 mV/N,Ft=0.5 mV/N"
    assert rec.attrs["ignored_columns"] == "Trigger"
    assert rec.attrs["meta_comment"] == f"line {start + 1}: pre-trigger 20 us"


# -------------------------------------------------------------- LabVIEW: dialects, errors
HEAD = (
    "LabVIEW Measurement{s}\nWriter_Version{s}2\nReader_Version{s}2\nSeparator{s}{name}\n"
    "Decimal_Separator{s}{dec}\nMulti_Headings{s}Yes\nX_Columns{s}{x}\nTime_Pref{s}Relative\n"
    "Operator{s}me\n***End_of_Header***{s}\n{s}\n"
)


def _lvm(tmp_path, body, *, sep="\t", dec=".", x="One", eol="\n", name="r.lvm"):
    names = {"\t": "Tab", ",": "Comma", ";": "Semicolon"}
    text = HEAD.format(s=sep, name=names[sep], dec=dec, x=x) + body.replace("\t", sep)
    p = tmp_path / name
    p.write_bytes(text.replace("\n", eol).encode())
    return p


SEGMENT = (
    "Channels\t2\t\t\nSamples\t3\t3\t\nY_Unit_Label\tkN\tN\t\nX_Dimension\tTime\tTime\t\n"
    "X0\t-1.0000000000000000E-6\t-1.0000000000000000E-6\t\nDelta_X\t5.000000E-7\t5.000000E-7\t\n"
    "***End_of_Header***\t\t\t\nX_Value\tFz\tFx\tComment\n"
)


@pytest.mark.parametrize("sep", ["\t", ",", ";"])
@pytest.mark.parametrize("eol", ["\n", "\r\n"])
def test_lvm_separators_and_line_ends(tmp_path, sep, eol):
    dec = "." if sep == "," else ","
    rows = "\t0.25\t1.5\tstart\n\t0.5\t-2\n\t1e-3\t3\n".replace(".", dec)
    p = _lvm(tmp_path, SEGMENT.replace(".", dec) + rows, sep=sep, dec=dec, x="No", eol=eol)
    rec = load(p)
    np.testing.assert_allclose(rec["time"].values, [-1e-6, -0.5e-6, 0.0], rtol=0, atol=1e-21)
    np.testing.assert_allclose(rec["Fn"].values, [250.0, 500.0, 1.0], rtol=1e-15)
    np.testing.assert_allclose(rec["Ft"].values, [1.5, -2.0, 3.0], rtol=1e-15)


def test_lvm_without_segment_header_and_with_a_special_block(tmp_path):
    body = (
        "***Start_Special***\nanything\tat all\n***End_Special***\n"
        "X_Value\tFz (N)\tFx (N)\tComment\n0\t1\t2\n1e-6\t3\t4\n"
    )
    rec = load(_lvm(tmp_path, body))
    np.testing.assert_array_equal(rec["time"].values, [0.0, 1e-6])
    np.testing.assert_array_equal(rec["Fn"].values, [1.0, 3.0])
    _raises("no force unit in the file; give force_unit=", load,
            _lvm(tmp_path, "X_Value\tFz\tComment\n0\t1\n1\t2\n", name="nounit.lvm"))  # fmt: skip


@pytest.mark.parametrize(
    ("body", "kwargs", "fragment", "line"),
    [
        (SEGMENT + "\t1\t2\n\t1\tx\n", {"x": "No"}, "cell 'x' is not a number", 21),
        (SEGMENT + "\t1\t2\n\t\t2\n", {"x": "No"}, "force value nan is missing", 21),
        (SEGMENT + "\t1\t2\tc\td\te\n\t1\t2\n", {"x": "No"},
         "6 cells but the column line (line 19) names 4", 20),
        (SEGMENT + "\tNaN\t2\n\t1\t2\n", {"x": "No"}, "force value nan is missing, NaN", 20),
        (SEGMENT.replace("5.000000E-7", "0") + "\t1\t2\n\t1\t2\n", {"x": "No"},
         "the time step must be a positive number", 17),
        (SEGMENT.replace("Time", "Frequency") + "0\t1\t2\n1\t1\t2\n", {},
         "X_Dimension is 'Frequency', not Time", 15),
        (SEGMENT.replace("kN", "Volts") + "0\t1\t2\n1\t1\t2\n", {},
         "Fn (column 'Fz') is in volts ('Volts')", 14),
        (SEGMENT.replace("kN", "kg") + "0\t1\t2\n1\t1\t2\n", {}, "unit 'kg' is not a force unit",
         14),
        (SEGMENT[:-30], {}, "truncated: a segment header never ends", 18),
        (SEGMENT.replace("X_Value", "Time"), {}, "is not the column line", 19),
        (SEGMENT, {}, "header only: the segment has no data rows", 19),
    ],
)  # fmt: skip
def test_lvm_refusals(tmp_path, body, kwargs, fragment, line):
    err = _raises(fragment, load, _lvm(tmp_path, body, **kwargs))
    assert err.line == line


def test_lvm_absolute_x0_keeps_the_step(tmp_path):
    """Time_Pref Absolute: X0 is LabVIEW's seconds since 1904 (3.48e9 s, held in double
    precision to 4.8e-7 s). X0 + k·Delta_X would round a 0.5 µs step to 0 or 4.8e-7 s;
    time counts from the first sample instead, and X0 is kept as the file states it."""
    x0 = "3.4835261505500000E+9"
    body = SEGMENT.replace("-1.0000000000000000E-6", x0) + "\t1\t2\n\t3\t4\n\t5\t6\n"
    rec = load(_lvm(tmp_path, body, x="No"))
    np.testing.assert_allclose(rec["time"].values, [0.0, 0.5e-6, 1e-6], rtol=1e-12, atol=0)
    assert rec.attrs["lvm_x0"] == x0
    # a small X0 (Time_Pref Relative) is the time's origin, as the file says
    rec = load(_lvm(tmp_path, SEGMENT + "\t1\t2\n\t3\t4\n", x="No", name="rel.lvm"))
    np.testing.assert_allclose(rec["time"].values, [-1e-6, -0.5e-6], rtol=1e-12)
    assert "lvm_x0" not in rec.attrs


def test_absolute_time_values_are_refused_not_rounded(tmp_path):
    """Time written as an absolute clock (a Unix time, 1.7e9 s) in 1 µs steps: double
    precision holds those instants to 2.4e-7 s, so the spacing read would be 0.95 or
    1.19 µs, not 1 µs. The record is refused, saying what to do."""
    rows = "".join(f"{1.7e9 + k * 1e-6:.6f},{k}\n" for k in range(5))
    p = _csv(tmp_path, "time [s],Fz [N]\n" + rows)
    _raises("too coarse for steps of", load, p)
    _raises("export time relative to the record's start", load, p)
    body = "X_Value\tFz (N)\tComment\n" + rows.replace(",", "\t")
    _raises("held (in double precision) only to 2.4e-07 s", load, _lvm(tmp_path, body))


def test_lvm_not_an_lvm_and_truncated_header(tmp_path):
    p = tmp_path / "x.lvm"
    p.write_text("time [s],Fz [N]\n0,1\n")
    err = _raises("not a LabVIEW Measurement file: the first line is not 'LabVIEW Measurement'",
                  load, p)  # fmt: skip
    assert err.line == 1
    p.write_text("LabVIEW Measurement\t\nWriter_Version\t2\nSeparator\tTab\n")
    _raises("truncated: the file header never ends", load, p)
    p.write_text("LabVIEW Measurement\t\nSeparator\tPipe\n***End_of_Header***\n")
    _raises("Separator 'Pipe' is not a separator LabVIEW writes", load, p)


# ------------------------------------------------------------------ MATLAB: real files
def test_mat_real_v5_matrix_with_named_columns():
    """testmulti: MATLAB 7.4 saved a = [1 2 3 4 5; 2 0 0 0 0; 3 0 0 0 0] (uint8)."""
    p = MAT / "testmulti_7.4_GLNX86.mat"
    assert sniff_format(p) == "mat"
    rec = load(p, columns={"a": ["time [s]", "Fz [N]", "Fx [N]", None, None]})
    np.testing.assert_array_equal(rec["time"].values, [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(rec["Fn"].values, [2.0, 0.0, 0.0])
    np.testing.assert_array_equal(rec["Ft"].values, [3.0, 0.0, 0.0])
    assert (rec.attrs["mat_version"], rec.attrs["mat_variable"]) == ("5", "a")
    assert rec.attrs["meta_header"].startswith("MATLAB 5.0 MAT-file, Platform: GLNX86")
    _raises(
        "no time vector, but 2-D arrays: a (3×5 uint8); name the columns of one, "
        "columns={'a': ['time [s]', 'Fz [N]', ...]}",
        load,
        p,
    )
    _raises("columns= names 4 columns but 'a' is 3×5 uint8", load, p, columns=["t [s]"] * 4)


def test_mat_real_v73_layout():
    """testhdf5: MATLAB wrote the 1×9 row 0:π/4:2π as a 9×1 HDF5 dataset; string_v73:
    a char array as uint16 code units and a string object."""
    got = mat_variables(MAT / "testhdf5_7.4_GLNX86.mat")
    np.testing.assert_allclose(got["testdouble"], np.arange(9) * np.pi / 4, rtol=1e-15)
    assert got["testdouble"].shape == (9,)
    strings = mat_variables(MAT / "string_v73.mat")
    assert strings["my_char"] == "hello char"
    assert isinstance(strings["my_string"], Unsupported)
    assert strings["my_string"].kind == "MATLAB string object"
    cell = mat_variables(MAT / "struct_in_cell_v73.mat")
    assert isinstance(cell["x"]["test"], Unsupported) and cell["x"]["test"].kind == "cell array"
    _raises(
        "no record in the file: no time vector (t, time, t_s, time_us...) nor sample rate (fs) "
        "beside the force vectors (variables: testdouble (9 float64))",
        load,
        MAT / "testhdf5_7.4_GLNX86.mat",
    )


def test_mat_real_unsupported_variables_are_named():
    _raises("variables: testsparse (sparse matrix)", load, MAT / "testsparse_7.4_GLNX86.mat")
    _raises(
        "no time vector, and no sample rate (fs)",
        read_mat,
        MAT / "teststruct_7.4_GLNX86.mat",
        variable="teststruct",
    )


# -------------------------------------------------------------- MATLAB: samples, dialects
def test_mat_v5_sample_against_scipy():
    p = SAMPLES / "sensor_v5.mat"
    raw = scipy.io.loadmat(p)
    rec = load(p)
    assert raw["t_us"].shape[0] == 1 and raw["Fz_kN"].shape[1] == 1  # a row and a column
    assert raw["Fz_kN"].dtype == np.float32
    np.testing.assert_allclose(rec["time"].values, raw["t_us"].ravel() * 1e-6, rtol=1e-15)
    np.testing.assert_allclose(np.diff(rec["time"].values), 0.5e-6, rtol=1e-9)
    np.testing.assert_array_equal(rec["Fn"].values, raw["Fz_kN"].ravel().astype(float) * 1e3)
    assert (rec.attrs["source_time_unit"], rec.attrs["source_force_unit"]) == ("us", "kN")
    assert rec.attrs["ignored_variables"] == "operator"


def test_mat_v73_sample_against_h5py():
    """sensor_v73.mat: a struct data with a 2-D array raw, columns and sensitivities from
    the sidecar; h5py holds it transposed, as MATLAB writes."""
    p = SAMPLES / "sensor_v73.mat"
    with h5py.File(p, "r") as f:
        raw = f["data/raw"][()].T
        assert f["data"].attrs["MATLAB_class"] == b"struct"
    assert p.read_bytes()[:19] == b"MATLAB 7.3 MAT-file"
    rec = load_sample(p)
    np.testing.assert_array_equal(rec["time"].values, raw[:, 0])
    np.testing.assert_allclose(rec["Fn"].values, raw[:, 3] / 0.225e-3, rtol=1e-12)
    np.testing.assert_allclose(rec["Ft"].values, raw[:, 1] / 0.5e-3, rtol=1e-12)
    np.testing.assert_allclose(rec["Fy"].values, raw[:, 2] / 0.5e-3, rtol=1e-12)
    assert rec.attrs["mat_variable"] == "data.raw" and rec.attrs["mat_version"] == "7.3"
    assert mat_variables(p)["data"]["operator"] == "A. Lab"
    _raises(
        "no time vector, but 2-D arrays: data.raw (166×4 float64)",
        load,
        p,
    )


def _matlab_h5(path, variables: dict):
    """A v7.3 file laid out as MATLAB writes it: 512-byte header, MATLAB_class, arrays
    transposed, structs as groups."""
    with h5py.File(path, "w", userblock_size=512) as f:

        def put(group, name, value):
            if isinstance(value, dict):
                g = group.create_group(name)
                g.attrs["MATLAB_class"] = np.bytes_(b"struct")
                for k, v in value.items():
                    put(g, k, v)
                return
            arr = np.atleast_2d(value)  # MATLAB has no 1-D arrays
            ds = group.create_dataset(name, data=arr.T)
            cls = {"f": "double" if arr.dtype == np.float64 else "single"}.get(
                arr.dtype.kind, str(arr.dtype)
            )
            ds.attrs["MATLAB_class"] = np.bytes_(cls.encode())

        for name, value in variables.items():
            put(f, name, value)
    with open(path, "r+b") as fh:
        fh.write(b"MATLAB 7.3 MAT-file, Platform: GLNXA64, HDF5 schema 1.00 .".ljust(116))


def test_mat_v73_struct_of_vectors_with_a_sample_rate(tmp_path):
    """data.fs_kHz and data.t0_us give the time; data.Fz_N an int16 row, data.Fx a
    single column (force_unit= for it)."""
    p = tmp_path / "drop.mat"
    _matlab_h5(
        p,
        {
            "data": {
                "fs_kHz": np.array(500.0),
                "t0_us": np.array(-4.0),
                "Fz_N": np.array([[1, 5, 9, 4, 0]], dtype=np.int16),
                "Fx_N": np.array([[0.5], [1.0], [0.0], [-1.0], [0.0]], dtype=np.float32),
            },
            "note": np.array([[104, 105]], dtype=np.uint16),
        },
    )
    rec = load(p)
    # fs = 500 kHz → dt = 2 µs; t0 = −4 µs
    np.testing.assert_allclose(rec["time"].values, [-4e-6, -2e-6, 0.0, 2e-6, 4e-6], atol=1e-21)
    np.testing.assert_array_equal(rec["Fn"].values, [1.0, 5.0, 9.0, 4.0, 0.0])
    np.testing.assert_array_equal(rec["Ft"].values, [0.5, 1.0, 0.0, -1.0, 0.0])
    assert rec.attrs["mat_variable"] == "data"


def test_mat_v5_volts_row_vectors_and_names(tmp_path):
    p = tmp_path / "run.mat"
    scipy.io.savemat(p, {"t": np.array([[0.0, 1.0, 2.0]]), "Fz_mV": np.array([[9.0, 18, 4.5]])})
    rec = load(p, time_unit="ms", sensitivity={"Fn": (4.5, "mV/N")})
    np.testing.assert_allclose(rec["time"].values, [0.0, 1e-3, 2e-3], rtol=1e-15)
    np.testing.assert_allclose(rec["Fn"].values, [2.0, 4.0, 1.0], rtol=1e-15)
    _raises("Fn (column 'Fz') is in volts ('mV')", load, p, time_unit="ms")
    _raises("no time unit in the file; give time_unit=", load, p, sensitivity={"Fn": (1, "V/N")})


@pytest.mark.parametrize(
    ("variables", "kwargs", "fragment"),
    [
        ({"t_s": [0.0, 1.0], "Fz_N": [1 + 1j, 2]}, {}, "variable 'Fz_N' is a complex array"),
        ({"t_s": [0.0, 1.0], "Fz_N": [1.0, 2.0, 3.0]}, {},
         "column 'Fz' has 3 samples but the time column 't' has 2"),
        ({"t_s": [0.0, 1.0], "time_s": [0.0, 1.0], "Fz_N": [1.0, 2.0]}, {},
         "two time vectors (t, time); keep one"),
        ({"a": {"t_s": [0.0, 1.0]}, "b": {"t_s": [0.0, 1.0]}}, {},
         "several structs hold a time (a, b); name one"),
        ({"t_s": [0.0, 1.0], "Fz_N": [1.0, 2.0]}, {"variable": "nope"},
         "no variable 'nope' in the file"),
        ({"t_s": [0.0, 1.0], "Fz_N": [1.0, 2.0]}, {"columns": ["time [s]"]},
         "columns= names the columns of a 2-D array, and the file holds 0"),
        ({"t_s": [1.0, 0.0], "Fz_N": [1.0, 2.0]}, {}, "time goes backwards at sample 1"),
    ],
)  # fmt: skip
def test_mat_refusals(tmp_path, variables, kwargs, fragment):
    p = tmp_path / "bad.mat"
    scipy.io.savemat(p, variables)
    _raises(fragment, read_mat, p, **kwargs)


def test_mat_damaged_files_never_read_as_text(tmp_path):
    good = (SAMPLES / "sensor_v73.mat").read_bytes()
    p = tmp_path / "cut.mat"
    p.write_bytes(good[: len(good) // 2])
    err = _raises("cannot read this MATLAB v7.3 (HDF5) file", load, p)
    assert "UTF-8" not in str(err)
    p.write_bytes(bytes(range(256)) * 4)
    err = _raises("cannot read this MATLAB file", load, p)
    assert "UTF-8" not in str(err)
    q = tmp_path / "v5_named.dat"  # a MATLAB file under another name: sniffed by its header
    q.write_bytes((SAMPLES / "sensor_v5.mat").read_bytes())
    assert sniff_format(q) == "mat" and load(q).attrs["format"] == "mat"
    h = tmp_path / "plain.h5"
    with h5py.File(h, "w") as f:
        f["x"] = [1.0, 2.0]
    _raises("an HDF5 file that is not a MATLAB v7.3 file", load, h)
    _raises("columns= does not apply to sensor CSV files", load, SAMPLES / "gr_5deg_0.3ms.csv",
            columns=["time [s]"])  # fmt: skip


def _v5_elements(raw: bytes, start: int, end: int):
    """(type, data offset, bytes) of the MAT v5 data elements in raw[start:end], little
    endian, written here from MathWorks' "MAT-File Format" (v5, ch. 1) for the test."""
    import struct

    pos, out = start, []
    while pos < end:
        first, second = struct.unpack_from("<II", raw, pos)
        if first >> 16:
            out.append((first & 0xFFFF, pos + 4, first >> 16))
            pos += 8
        else:
            out.append((first, pos + 8, second))
            pos += 8 + second + (-second % 8)
    return out


@pytest.mark.parametrize("damage", ["type", "size", "dims", "text_type"])
def test_mat_v5_tags_that_contradict_the_file_are_refused_not_a_crash(tmp_path, damage):
    """A v5 file whose one byte of a data element's tag is damaged — the real part's data
    type made one no MAT-file has, its byte count doubled, its array's dimensions grown, or
    a char array's text given a type no MAT-file has — is refused with an InputError naming
    it. SciPy's reader trusts the tags, and the first and the last of these crashed the
    process (a segmentation fault; the last now and then, as the memory past its data lay),
    so each read runs in a process of its own here."""
    import subprocess
    import sys

    raw = bytearray((SAMPLES / "sensor_v5.mat").read_bytes())
    arrays = _v5_elements(raw, 128, len(raw))
    matrix = arrays[-2]  # the last numeric vector
    assert matrix[0] == 14  # miMATRIX: the precondition
    flags, dims, name, real = _v5_elements(raw, matrix[1], matrix[1] + matrix[2])[:4]
    assert real[0] in (7, 9) and real[2] > 16  # single or double data
    if damage == "type":
        raw[real[1] - 8] = 230
    elif damage == "text_type":  # the last array: the operator's name, text in UTF-8
        text = _v5_elements(raw, arrays[-1][1], arrays[-1][1] + arrays[-1][2])[3]
        assert arrays[-1][0] == 14 and text[0] == 16  # miUTF8: the precondition
        raw[text[1] - 7] = 0x9A  # type 16 → 0x9A10, which scipy read past its data
    elif damage == "size":
        raw[real[1] - 4 : real[1]] = (2 * real[2]).to_bytes(4, "little")
    else:
        raw[dims[1] : dims[1] + 4] = (10**6).to_bytes(4, "little")
    p = tmp_path / "damaged.mat"
    p.write_bytes(bytes(raw))
    code = (
        "import sys\nfrom pipeline.errors import InputError\nfrom pipeline.io import read_mat\n"
        "try:\n    read_mat(sys.argv[1])\nexcept InputError as exc:\n    print(exc)\n"
    )
    out = subprocess.run([sys.executable, "-c", code, str(p)], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr[-2000:]
    assert "damaged.mat" in out.stdout and "cannot read this MATLAB file" in out.stdout, out
    if damage == "text_type":  # refused by the tag check, before scipy reads past the data
        assert "a data element's type is one no MAT-file has" in out.stdout, out


def test_mat_v5_check_refuses_none_of_scipys_own_readable_files():
    """SciPy's own MAT v5 test files (MATLAB 6.1–7.4, both byte orders, cells, structs,
    sparse, objects, UTF-8 names): the tag check refuses none that SciPy reads."""
    import io
    import warnings

    from pipeline.io.mat import _check_v5, _version

    folder = Path(scipy.io.__file__).parent / "matlab" / "tests" / "data"
    files = sorted(folder.glob("*.mat"))
    if len(files) < 20:
        pytest.skip("SciPy was installed without its test data")
    read = 0
    for f in files:
        raw = f.read_bytes()
        if _version(raw) != "5":
            continue
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                scipy.io.loadmat(io.BytesIO(raw))
        except Exception:  # noqa: BLE001 - a file SciPy refuses is not this test's
            continue
        _check_v5(raw, f)  # raises InputError on a file it refuses
        read += 1
    assert read >= 50
