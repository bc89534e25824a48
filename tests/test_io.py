"""Readers and writer of pipeline.io: formats, units, axes, and every bad input.

Ground truth here is either the text of the file itself (a row written by hand and read
back) or the closed-form Hertz pulse the samples were made from (Johnson, Contact Mechanics,
1985, doi:10.1017/CBO9781139171731; docs/theory.md, Compliant contact), never the reader's own
earlier output.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

from pipeline.errors import InputError, PlaneImpactWarning
from pipeline.io import load, read_sensor, read_tdms, read_wpd, sniff_format, validate, write_sensor
from pipeline.record import channel, make_record

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = ROOT / "data_samples"
sys.path.insert(0, str(ROOT / "scripts"))
import make_format_samples as samples  # noqa: E402

from pipeline.contact import hertz_impact, hertz_pulse  # noqa: E402

IMPACT = hertz_impact(samples.SCENE)


def _write(tmp_path, name, content):
    p = tmp_path / name
    if isinstance(content, str):
        content = content.encode("utf-8")
    p.write_bytes(content)
    return p


def _raises(path, fragment, **kw):
    """load(path) raises InputError whose message names the file and holds ``fragment``."""
    with pytest.raises(InputError) as info:
        load(path, **kw)
    msg = str(info.value)
    assert type(info.value) is InputError
    assert Path(path).name in msg, msg
    assert fragment in msg, msg
    return info.value


# ----------------------------------------------------------------- write_sensor round trip
def _record(n=200, seed=0, **attrs):
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(1e-7, 1e-6, n)) - 3e-5
    forces = {
        "Fn": rng.normal(0, 300, n),
        "Ft": rng.normal(0, 30, n) * 1e-7,  # tiny values: digits must survive
        "Fy": rng.normal(0, 1, n),
    }
    base = {"source": "gen", "format": "simulated", "kind": "simulated", "radius": 0.0127}
    return make_record(t, forces, attrs={**base, **attrs})


def test_write_sensor_round_trip_is_exact(tmp_path):
    rec = _record()
    p = write_sensor(rec, tmp_path / "r.csv", metadata={"operator": "A. Lab"})
    back = read_sensor(p)
    for name in ("Fn", "Ft", "Fy"):
        np.testing.assert_array_equal(back[name].values, rec[name].values)
    np.testing.assert_array_equal(back["time"].values, rec["time"].values)
    assert back.attrs["meta_operator"] == "A. Lab"
    assert back.attrs["meta_radius"] == "0.0127"
    assert back.attrs["format"] == "sensor_csv" and back.attrs["kind"] == "sensor"
    # header and mapping as specified: Fn -> Fz, Ft -> Fx
    lines = p.read_text().splitlines()
    header = next(ln for ln in lines if not ln.startswith("#"))
    assert header == "time [s],Fx [N],Fy [N],Fz [N]"
    assert [q.name for q in tmp_path.iterdir()] == ["r.csv"]  # no temp file left behind


def test_write_sensor_zero_fy_when_absent_and_overwrite_atomic(tmp_path):
    t = np.arange(4) * 1e-6
    rec = make_record(
        t,
        {"Fn": [0.0, 1.0, 2.0, 0.5], "Ft": [0.0, 0.1, 0.2, 0.05]},
        attrs={"source": "x", "format": "simulated", "kind": "simulated"},
    )
    p = tmp_path / "r.csv"
    p.write_text("old content")
    write_sensor(rec, p)
    back = read_sensor(p)
    np.testing.assert_array_equal(back["Fy"].values, np.zeros(4))
    np.testing.assert_array_equal(back["Fn"].values, [0.0, 1.0, 2.0, 0.5])


def test_write_sensor_refuses_nan_and_bad_metadata(tmp_path):
    rec = read_wpd(
        {"Fn": SAMPLES / "wpd_Fn.csv", "Ft": SAMPLES / "wpd_Ft.csv"}, time_unit="us", force_unit="N"
    )
    with pytest.raises(InputError, match="not finite"):
        write_sensor(rec, tmp_path / "d.csv")
    with pytest.raises(InputError, match="metadata key"):
        write_sensor(_record(), tmp_path / "m.csv", metadata={"a:b": 1})
    assert not list(tmp_path.iterdir())


# ------------------------------------------------------------------------- sensor dialects
TRUTH_T = np.array([0.0, 1.5, 3.0, 4.5])  # in the file's time unit
TRUTH = {"Fx": [0.25, -1.5, 2.0, 0.0], "Fy": [0.0, 0.01, -0.02, 0.0], "Fz": [1.0, 20.5, 3.25, 0.5]}


def _sensor_text(sep=",", dec=".", t_unit="[us]", f_unit="[kN]", eol="\n", meta=True):
    head = ["# operator: A. Lab", "# Trigger level = 2 N", "# free comment"] if meta else []
    cols = [f"time {t_unit}", f"Fx {f_unit}", f"Fy {f_unit}", f"Fz {f_unit}"]
    rows = [sep.join(cols)]
    for k, t in enumerate(TRUTH_T):
        vals = [t, TRUTH["Fx"][k], TRUTH["Fy"][k], TRUTH["Fz"][k]]
        rows.append(sep.join(repr(float(v)).replace(".", dec) for v in vals))
    return eol.join(head + rows) + eol


@pytest.mark.parametrize(
    "sep,dec,t_unit,t_factor,f_unit,f_factor,eol,bom",
    [
        (",", ".", "[s]", 1.0, "[N]", 1.0, "\n", False),
        (";", ",", "(ms)", 1e-3, "(kN)", 1e3, "\r\n", True),
        ("\t", ".", "[us]", 1e-6, "[mN]", 1e-3, "\r\n", False),
        (";", ".", "[µs]", 1e-6, "[kN]", 1e3, "\n", True),  # micro sign U+00B5
        ("\t", ",", "[μs]", 1e-6, "(N)", 1.0, "\n", False),  # Greek mu U+03BC
        (",", ".", "(ns)", 1e-9, "[daN]", 10.0, "\r\n", True),
    ],
)
def test_sensor_dialects_convert_to_si(
    tmp_path, sep, dec, t_unit, t_factor, f_unit, f_factor, eol, bom
):
    text = _sensor_text(sep, dec, t_unit, f_unit, eol)
    data = ("\ufeff" if bom else "") + text
    p = _write(tmp_path, "dialect.csv", data)
    rec = load(p)
    np.testing.assert_allclose(rec["time"].values, TRUTH_T * t_factor, rtol=1e-15, atol=0)
    np.testing.assert_allclose(rec["Fn"].values, np.array(TRUTH["Fz"]) * f_factor, rtol=1e-15)
    np.testing.assert_allclose(rec["Ft"].values, np.array(TRUTH["Fx"]) * f_factor, rtol=1e-15)
    np.testing.assert_allclose(rec["Fy"].values, np.array(TRUTH["Fy"]) * f_factor, rtol=1e-15)
    assert rec.attrs["meta_operator"] == "A. Lab"
    assert rec.attrs["meta_trigger_level"] == "2 N"
    assert rec.attrs["meta_comment"] == "free comment"
    assert rec.attrs["sha256"] == __import__("hashlib").sha256(p.read_bytes()).hexdigest()
    assert rec["Fn"].attrs["units"] == "N" and rec["time"].attrs["units"] == "s"


def test_sensor_utf16_and_explicit_encoding(tmp_path):
    p = _write(tmp_path, "u16.csv", _sensor_text(sep="\t").encode("utf-16"))
    np.testing.assert_allclose(load(p)["Fn"].values, np.array(TRUTH["Fz"]) * 1e3)
    latin = _sensor_text(t_unit="[\u00b5s]").encode("cp1252")
    p = _write(tmp_path, "cp1252.csv", latin)
    err = _raises(p, "not valid UTF-8")
    assert err.line == 4
    rec = read_sensor(p, encoding="cp1252")
    np.testing.assert_allclose(rec["time"].values, TRUTH_T * 1e-6)


def test_sensor_fn_ft_columns_taken_as_they_are(tmp_path):
    p = _write(tmp_path, "nt.csv", "t (ms),Ft (N),Fn (N)\n0,1,10\n1,2,20\n2,3,30\n")
    rec = load(p)
    np.testing.assert_array_equal(rec["Fn"].values, [10, 20, 30])
    np.testing.assert_array_equal(rec["Ft"].values, [1, 2, 3])
    assert "Fy" not in rec


def test_sensor_axes_override(tmp_path):
    p = _write(tmp_path, "ax.csv", _sensor_text(f_unit="[N]", t_unit="[s]"))
    rec = load(p, axes={"Ft": "-Fx"})
    np.testing.assert_array_equal(rec["Ft"].values, -np.array(TRUTH["Fx"]))
    np.testing.assert_array_equal(rec["Fn"].values, TRUTH["Fz"])
    assert rec.attrs["axes"] == "Fn=Fz,Ft=-Fx,Fy=Fy"
    # a sensor mounted on its side; Fy dropped
    rec = load(p, axes={"Fn": "Fx", "Ft": "Fz", "Fy": None})
    np.testing.assert_array_equal(rec["Fn"].values, TRUTH["Fx"])
    np.testing.assert_array_equal(rec["Ft"].values, TRUTH["Fz"])
    assert "Fy" not in rec
    _raises(p, "names no column", axes={"Fn": "Fq"})
    with pytest.raises(InputError, match="not a record channel"):
        load(p, axes={"Fz": "Fz"})
    with pytest.raises(InputError, match="two channels"):
        load(p, axes={"Fn": "Fz", "Ft": "Fz"})


def test_axes_may_name_any_column(tmp_path):
    text = "Time (ms);Force Z (kN);Force X (kN);trigger [V]\n0;1,5;0,25;5\n1;2,5;0,5;0\n"
    p = _write(tmp_path, "vendor.csv", text)
    _raises(p, "other columns: Force Z, Force X, trigger")
    rec = load(p, axes={"Fn": "Force Z", "Ft": "-force x"})
    np.testing.assert_array_equal(rec["Fn"].values, [1500.0, 2500.0])
    np.testing.assert_array_equal(rec["Ft"].values, [-250.0, -500.0])
    assert rec.attrs["ignored_columns"] == "trigger [V]"
    _raises(p, "not a force unit", axes={"Fn": "trigger"})


def test_units_from_arguments_and_clashes(tmp_path):
    p = _write(tmp_path, "nounit.csv", "time,Fx,Fz\n0,1,2\n1,2,3\n")
    _raises(p, "time_unit=")
    _raises(p, "force_unit=", time_unit="ms")
    rec = load(p, time_unit="ms", force_unit="kN")
    np.testing.assert_array_equal(rec["time"].values, [0.0, 1e-3])
    np.testing.assert_array_equal(rec["Fn"].values, [2e3, 3e3])
    q = _write(tmp_path, "unit.csv", "time [ms],Fx [kN],Fz [kN]\n0,1,2\n1,2,3\n")
    _raises(q, "units in the file win", force_unit="N")
    _raises(q, "units in the file win", time_unit="s")
    assert load(q, force_unit="kN", time_unit="ms")["Fn"].values[0] == 2e3  # agreeing: fine
    _raises(q, "not a force unit", force_unit="m")


def test_plane_impact_warning(tmp_path):
    big = "time [s],Fx [N],Fy [N],Fz [N]\n0,0,0.6,1\n1,0,0.1,10\n2,0,0,2\n"  # 6 % of peak Fn
    p = _write(tmp_path, "plane.csv", big)
    with pytest.warns(PlaneImpactWarning, match="plane.csv") as caught:
        load(p)
    assert caught[0].filename == __file__  # the caller's line, not one inside pipeline.io
    q = _tdms(
        tmp_path / "plane.tdms",
        [
            (f, v, {"unit_string": "N", **WF})
            for f, v in (("Fz", [1.0, 10.0, 2.0]), ("Fy", [0.6, 0.1, 0.0]))
        ],
    )
    for reader, path in ((read_sensor, p), (load, q), (read_tdms, q)):
        with pytest.warns(PlaneImpactWarning) as caught:
            reader(path)
        assert caught[0].filename == __file__, (reader, path)
    ok = big.replace("0,0.6,1", "0,0.4,1")  # 4 %: no warning (warnings are errors here)
    load(_write(tmp_path, "ok.csv", ok))


def test_ignored_columns_listed(tmp_path):
    p = _write(tmp_path, "ign.csv", "time [s],trigger [V],Fz [N]\n0,5,1\n1,0,2\n")
    rec = load(p)
    assert rec.attrs["ignored_columns"] == "trigger [V]"
    assert "Ft" not in rec


# -------------------------------------------------------------------------- sensor: errors
@pytest.mark.parametrize(
    "name,content,fragment,line,column",
    [
        ("empty.csv", "", "empty", None, None),
        ("blank.csv", "\n  \r\n", "empty", None, None),
        ("bom_only.csv", "\ufeff", "empty", None, None),
        ("meta_only.csv", "# a: 1\n# b: 2\n", "no header row", None, None),
        ("header_only.csv", "# a: 1\ntime [s],Fz [N]\n", "header only", 2, None),
        ("single.csv", "time [s],Fz [N]\n0,1\n", "single sample", 2, None),
        ("single_gap.csv", "time [s],Fz [N]\n\n\n0,1\n\n", "single sample", 4, None),
        ("text_cell.csv", "time [s],Fx [N],Fz [N]\n0,1,2\n1,abc,3\n2,1,1\n", "'abc'", 3, "Fx [N]"),
        (
            "nan.csv",
            "time [s],Fx [N],Fz [N]\n0,1,2\n1,1,nan\n2,1,1\n",
            "NaN or infinite",
            3,
            "Fz [N]",
        ),
        (
            "inf.csv",
            "time [s],Fx [N],Fz [N]\n0,1,2\n1,1,2\n2,-inf,1\n",
            "NaN or infinite",
            4,
            "Fx [N]",
        ),
        ("gap.csv", "time [s],Fx [N],Fz [N]\n0,1,2\n\n1,,2\n2,1,1\n", "missing", 4, "Fx [N]"),
        ("few.csv", "time [s],Fx [N],Fz [N]\n0,1,2\n1,2\n2,1,1\n", "has 2 fields", 3, None),
        ("many.csv", "time [s],Fx [N],Fz [N]\n0,1,2\n1,2,3,4\n2,1,1\n", "has 4 fields", 3, None),
        # every row one field too many: pandas would only warn and drop data
        ("allmany.csv", "time [s],Fz [N]\n0,1,2\n1,2,3\n", "has 3 fields", 2, None),
        ("back.csv", "time [s],Fz [N]\n0,1\n2,2\n1,3\n", "goes backwards", 4, "time [s]"),
        ("repeat.csv", "t [ms];Fz [N]\n0;1\n1;2\n1;3\n", "repeats", 4, "t [ms]"),
        ("tunit.csv", "time [V],Fz [N]\n0,1\n1,2\n", "not a time unit", 1, "time [V]"),
        ("funit.csv", "# a: 1\ntime [s],Fz [mm]\n0,1\n1,2\n", "not a force unit", 2, "Fz [mm]"),
        (
            "nofn.csv",
            "time [s],Fx [N],Fy [N]\n0,1,0\n1,2,0\n",
            "no normal-force channel",
            1,
            None,
        ),
        ("notime.csv", "x [s],Fz [N]\n0,1\n1,2\n", "no time column", 1, None),
        ("onecol.csv", "time [s]\n0\n1\n", "single column", 1, None),
        ("comma_dec_in_comma_sep.csv", "time [s],Fz [N]\n0,1\n1,2,5\n", "has 3 fields", 3, None),
        ("point_in_comma_file.csv", "time [s];Fz [N]\n0;1,5\n1;2.5\n", "'2.5'", 3, "Fz [N]"),
    ],
)
def test_sensor_bad_input(tmp_path, name, content, fragment, line, column):
    p = _write(tmp_path, name, content)
    err = _raises(p, fragment)
    if line is not None:
        assert err.line == line, str(err)
    if column is not None:
        assert err.column == column, str(err)


def test_temperature_column_t_is_not_time(tmp_path):
    """'T [°C]' beside 'time [s]' was taken for a second time column and the file refused."""
    text = "time [ms],Fx [N],Fz [N],T [°C],Mz [N m]\n0,1,2,21.5,0\n1,2,3,21.6,0\n"
    rec = load(_write(tmp_path, "temp.csv", text))
    np.testing.assert_array_equal(rec["time"].values, [0.0, 1e-3])
    np.testing.assert_array_equal(rec["Fn"].values, [2.0, 3.0])
    assert rec.attrs["ignored_columns"] == "T [°C],Mz [N m]"  # file order
    _raises(_write(tmp_path, "two.csv", "time [s],t [ms],Fz [N]\n0,0,1\n1,1,2\n"), "two time")


@pytest.mark.parametrize(
    "content,eol,encoding",
    [
        ("# a: 1\rtime [s],Fz [kN]\r0,1\r1,2\r", "\r", "utf-8"),
        ("t [µs]\tFz [kN]\r0\t1\r1\t2\r", "\r", "utf-16"),
    ],
)
def test_bare_cr_line_ends(tmp_path, content, eol, encoding):
    """Classic Mac OS line ends: the whole file was one header line (a baffling message)."""
    rec = load(_write(tmp_path, "cr.csv", content.encode(encoding)))
    np.testing.assert_array_equal(rec["Fn"].values, [1e3, 2e3])
    assert rec.sizes["time"] == 2


@pytest.mark.parametrize(
    "name,content,fragment,line,column",
    [
        # a line of one tab in a tab-separated file is a row of empty cells, not a blank
        # line (pandas reads it as a row): the line number was one off
        ("tab.csv", "time [s]\tFz [N]\n0\t1\n\t\n1\t2\n", "missing", 3, "time [s]"),
        # spaces around a tab: pandas refuses the cell; no line was named before
        ("tab2.csv", "time [s]\tFz [N]\n0\t1\n \t \n1\t2\n", "' '", 3, "time [s]"),
        # a no-break space after a number is not blank to pandas: no line was named before
        ("nbsp.csv", "time [s],Fz [N]\n0,1\n1,2\u00a0\n2,3\n", "'2\\xa0'", 3, "Fz [N]"),
        # Excel quotes a cell holding the separator: one cell, not "3 fields"
        ("xl.csv", '"time [s]","Fz [N]"\n"0","1"\n"1","2,5"\n', "'2,5'", 3, "Fz [N]"),
        ("hash.csv", "time [s],Fz [N]\n0,1\n# pause\n1,2\n", "before the header", 3, None),
        ("thou.csv", "t [ms];Fz [N]\n0;1\n1;1.234,5\n", "no thousands separators", 3, "Fz [N]"),
        # a lone trailing separator is tolerated: the bad cell is on line 3, not line 2
        ("trail.csv", "time [s],Fz [N]\n0,1,\n1,abc,\n", "'abc'", 3, "Fz [N]"),
        # a quoted note spanning two lines: the bad row is on line 5, not 4
        (
            "ml.csv",
            'time [s],Fz [N],note\n0,1,"a\nb"\n1,2,x\n0.5,3,y\n',
            "backwards",
            5,
            "time [s]",
        ),
        # a quote never closed: pandas only said 'EOF inside string', no line
        ("quote.csv", 'time [s],Fz [N]\n0,1\n1,"2\n2,3\n3,4\n', "never closed", 3, None),
        # ... and past csv's 128 KiB field limit: a csv.Error escaped
        (
            "quote_big.csv",
            'time [s],Fz [N]\n0,1\n1,"2\n' + "".join(f"{k},{k}\n" for k in range(2, 30000)),
            "never closed",
            3,
            None,
        ),
    ],
)
def test_sensor_bad_line_is_the_one_named(tmp_path, name, content, fragment, line, column):
    err = _raises(_write(tmp_path, name, content), fragment)
    assert err.line == line, str(err)
    assert err.column == column, str(err)


@pytest.mark.parametrize(
    "content",
    [
        "sep=;\ntime [ms];Fz [kN]\n0;1,5\n1;2,5\n",
        '\ufeff"sep=;"\r\n# a: 1\r\ntime [ms];Fz [kN]\r\n0;1,5\r\n1;2,5\r\n',
        "sep=\t\ntime [ms]\tFz [kN]\n0\t1,5\n1\t2,5\n",
    ],
)
def test_excel_sep_hint_line(tmp_path, content):
    """Excel's 'sep=;' first line was taken for the header ('no time column')."""
    rec = load(_write(tmp_path, "xl.csv", content))
    np.testing.assert_array_equal(rec["time"].values, [0.0, 1e-3])
    np.testing.assert_array_equal(rec["Fn"].values, [1500.0, 2500.0])


def test_decimal_comma_after_4_kib_of_integers(tmp_path):
    """The decimal mark is sniffed from the first 4 KiB of the table: a decimal-comma file
    whose pre-trigger rows are integers ('7;0;0') was refused at its first '0,5'."""
    pre = "".join(f"{k};0;0\n" for k in range(600))  # > 4096 bytes without a comma
    text = "t [us];Fx [N];Fz [N]\n" + pre + "600;0,5;1,25\n601;-0,25;2,5\n"
    rec = load(_write(tmp_path, "late.csv", text))
    np.testing.assert_array_equal(rec["Fn"].values[-3:], [0.0, 1.25, 2.5])
    np.testing.assert_array_equal(rec["Ft"].values[-2:], [0.5, -0.25])
    np.testing.assert_allclose(rec["time"].values[-1], 601e-6, rtol=1e-15)
    # and the other way round: a comma in a text column, decimal points in the numbers
    note = "t [us];Fz [N];note\n0;1,5;a,b\n" + "".join(f"{k};2.5;x\n" for k in range(1, 9))
    _raises(_write(tmp_path, "mixed.csv", note), "'2.5'")  # one file, two decimal marks
    note = "t [us];Fz [N];note\n0;1.5;a,b\n1;2.5;\n"
    np.testing.assert_array_equal(load(_write(tmp_path, "pt.csv", note))["Fn"].values, [1.5, 2.5])


def test_undecodable_body_bytes(tmp_path):
    p = _write(tmp_path, "bytes.csv", b"time [s],Fz [N]\n0,1\n1,\xff\xfe2\n2,3\n")
    err = _raises(p, "not valid UTF-8")
    assert err.line == 3


def test_utf16_without_bom_and_bad_encoding_argument(tmp_path):
    """UTF-16 without a BOM decodes as 'UTF-8' with NULs: the message showed a header of
    NULs; a non-string encoding= raised TypeError."""
    p = _write(tmp_path, "u16le.csv", "t [s],Fz [N]\n0,1\n1,2\n".encode("utf-16-le"))
    err = _raises(p, "UTF-16 text without a byte-order mark")
    assert err.line == 1
    np.testing.assert_array_equal(read_sensor(p, encoding="utf-16-le")["Fn"].values, [1, 2])
    with pytest.raises(InputError, match="unknown encoding 5"):
        read_sensor(p, encoding=5)


def test_sniff_cuts_a_long_bare_cr_file_at_a_line_end(tmp_path):
    """sniff_format reads the first 64 KiB cut at the last LF: a bare-CR file has none, so a
    two-byte character straddling the cut made a valid file 'not valid UTF-8'."""
    rows = ["time [s],Fz [N],note{}"] + [f"{k},{k + 1},é" for k in range(6000)]
    text = "\r".join(rows) + "\r"
    # pad the header until an 'é' straddles the 65536-byte cut
    data = next(
        d
        for pad in range(20)
        if (d := text.format(" " * pad).encode())[65535:65537] == "é".encode()
    )
    rec = load(_write(tmp_path, "long_cr.csv", data))
    assert rec.sizes["time"] == len(rows) - 1
    np.testing.assert_array_equal(rec["Fn"].values[:3], [1.0, 2.0, 3.0])


def test_missing_file_directory_and_scene_fields(tmp_path):
    _raises(tmp_path / "nope.csv", "no such file")
    with pytest.raises(InputError, match="directory"):
        load(tmp_path)
    p = _write(tmp_path, "ok.csv", "time [s],Fz [N]\n0,1\n1,2\n")
    with pytest.raises(InputError, match="unknown keyword 'radiu'.*radius.*angle_deg"):
        load(p, radiu=0.01)
    with pytest.raises(InputError, match="must be a number"):
        load(p, radius="1 cm")
    with pytest.raises(InputError, match="must be a number"):
        load(p, mu=True)
    rec = load(p, radius=0.0127, angle_deg=15)
    assert rec.attrs["radius"] == 0.0127 and rec.attrs["angle_deg"] == 15.0
    with pytest.raises(InputError, match="channels= does not apply"):
        load(p, channels={"Fn": "x"})


def test_numbers_without_header_refused(tmp_path):
    p = _write(tmp_path, "nohead.csv", "0,1,2,3\n1,2,3,4\n")
    with pytest.raises(InputError, match="no header row") as info:
        sniff_format(p)
    assert "nohead.csv" in str(info.value)


# --------------------------------------------------------------------- the sensor samples
def test_sensor_sample_matches_hertz_truth():
    rec = load(SAMPLES / "sensor_decimal_comma.csv", radius=0.0127)
    assert sniff_format(SAMPLES / "sensor_decimal_comma.csv") == "sensor_csv"
    assert rec.attrs["source_time_unit"] == "µs" and rec.attrs["source_force_unit"] == "kN"
    t = rec["time"].values
    np.testing.assert_allclose(t[0], -50e-6, rtol=1e-12)
    np.testing.assert_allclose(np.diff(t), 0.5e-6, rtol=1e-9)  # 2 MHz
    # first data row of the file, by hand: "-50,0;0,001270;0,002245;0,002606" (kN)
    np.testing.assert_allclose([rec.Ft[0], rec.Fy[0], rec.Fn[0]], [1.270, 2.245, 2.606], rtol=1e-12)
    truth = hertz_pulse(t, IMPACT)["F"]
    resid = rec["Fn"].values - truth
    # noise sigma 2 N plus 1.5 N offset (the script's documented sensor model)
    assert abs(resid.mean() - 1.5) < 0.5
    assert 1.5 < resid.std() < 2.5


def test_tdms_sample_matches_hertz_truth():
    p = SAMPLES / "sensor.tdms"
    assert sniff_format(p) == "tdms"
    rec = load(p)
    t = rec["time"].values
    n = t.size
    np.testing.assert_allclose(t, -20e-6 + 1e-6 * np.arange(n), rtol=0, atol=1e-18)
    resid = rec["Fn"].values - hertz_pulse(t, IMPACT)["F"]
    assert abs(resid.mean()) < 0.6 and 1.5 < resid.std() < 2.5
    assert rec.attrs["tdms_group"] == "Impact" and rec.attrs["format"] == "tdms"


# ------------------------------------------------------------------------------- WPD
def _wpd_rows(path, sep, dec):
    rows = []
    for line in Path(path).read_text().splitlines():
        x, y = line.split(sep)
        rows.append((float(x.replace(dec, ".")), float(y.replace(dec, "."))))
    return np.array(sorted(rows))


def test_wpd_single_sorted_and_named_from_file(tmp_path):
    rec = load(SAMPLES / "wpd_Fn.csv", time_unit="us", force_unit="N")
    assert rec.attrs["format"] == "wpd" and rec.attrs["kind"] == "digitised"
    rows = _wpd_rows(SAMPLES / "wpd_Fn.csv", ",", ".")
    np.testing.assert_allclose(rec["time"].values, rows[:, 0] * 1e-6, rtol=1e-15)
    np.testing.assert_array_equal(rec["Fn"].values, rows[:, 1])
    assert rec["Fn_measured"].values.all()
    # digitised points lie on the Hertz pulse within the digitising noise (0.4 % F_max,
    # 0.2 µs jitter): a wrong time unit would put them far off
    truth = hertz_pulse(np.clip(rec["time"].values, 0, IMPACT.t_c), IMPACT)["F"]
    assert np.max(np.abs(rec["Fn"].values - truth)) < 0.05 * IMPACT.F_max


def test_wpd_single_channel_argument_and_unknown_name(tmp_path):
    p = _write(tmp_path, "curve1.csv", "2, 20\n1, 10\n3, 5\n")
    _raises(p, "channels='Fn'", time_unit="ms", force_unit="N")
    rec = load(p, channels="Fn", time_unit="ms", force_unit="N")
    np.testing.assert_array_equal(rec["time"].values, [1e-3, 2e-3, 3e-3])
    np.testing.assert_array_equal(rec["Fn"].values, [10, 20, 5])
    _raises(p, "is not a record channel", channels="Fz", time_unit="ms", force_unit="N")
    same = load(p, channels={"Fn": "curve1"}, time_unit="ms", force_unit="N")
    np.testing.assert_array_equal(same["Fn"].values, [10, 20, 5])
    _raises(p, "holds one channel", channels=["Fn", "Ft"], time_unit="ms", force_unit="N")
    with pytest.raises(InputError, match="axes= does not apply"):
        load(p, axes={"Fn": "Fz"}, time_unit="ms", force_unit="N")
    q = _write(tmp_path, "normal_force.csv", "0;1,5\n1;2,5\n")
    rec = load(q, time_unit="s", force_unit="kN")
    np.testing.assert_array_equal(rec["Fn"].values, [1500.0, 2500.0])


def test_wpd_combined_exports_keep_every_point():
    paths = {"Fn": SAMPLES / "wpd_Fn.csv", "Ft": SAMPLES / "wpd_Ft.csv"}
    rec = load(paths, time_unit="us", force_unit="N")
    fn = _wpd_rows(paths["Fn"], ",", ".")
    ft = _wpd_rows(paths["Ft"], ";", ",")
    t_fn, v_fn = channel(rec, "Fn")
    t_ft, v_ft = channel(rec, "Ft")
    np.testing.assert_allclose(t_fn, fn[:, 0] * 1e-6, rtol=1e-15)
    np.testing.assert_array_equal(v_fn, fn[:, 1])
    np.testing.assert_allclose(t_ft, ft[:, 0] * 1e-6, rtol=1e-15)
    np.testing.assert_array_equal(v_ft, ft[:, 1])
    assert rec.sizes["time"] == len(np.union1d(fn[:, 0], ft[:, 0]))
    # between its own points a channel is the linear interpolation; outside its span NaN
    t = rec["time"].values
    k = np.flatnonzero(~rec["Fn_measured"].values & ~np.isnan(rec["Fn"].values))[0]
    i = np.searchsorted(t_fn, t[k])
    lam = (t[k] - t_fn[i - 1]) / (t_fn[i] - t_fn[i - 1])
    np.testing.assert_allclose(
        rec["Fn"].values[k], (1 - lam) * v_fn[i - 1] + lam * v_fn[i], rtol=1e-12
    )
    outside = (t < t_fn[0]) | (t > t_fn[-1])
    assert outside.any() and np.isnan(rec["Fn"].values[outside]).all()
    # the list form gives the same record
    same = load([paths["Fn"], paths["Ft"]], time_unit="us", force_unit="N")
    np.testing.assert_array_equal(same["Ft"].values, rec["Ft"].values)
    assert rec.attrs["source"] == "wpd_Fn.csv, wpd_Ft.csv"
    assert len(rec.attrs["sha256"].split(",")) == 2
    validate(rec)


def test_wpd_dict_refuses_channels():
    """channels= beside a {channel: path} dict was silently ignored."""
    paths = {"Fn": SAMPLES / "wpd_Fn.csv", "Ft": SAMPLES / "wpd_Ft.csv"}
    with pytest.raises(InputError, match="channels= does not apply when path is a dict"):
        load(paths, channels={"Fn": "wpd_Ft.csv"}, time_unit="us", force_unit="N")


def test_wpd_cp1252_advice_names_read_wpd(tmp_path):
    """The undecodable-bytes advice named only read_sensor, also for a WPD export."""
    text = "Normalkraft é,,Ft,\nX,Y,X,Y\n1,2,1,1\n2,3,2,2\n"
    p = _write(tmp_path, "ds.csv", text.encode("cp1252"))
    err = _raises(p, "read_wpd(path, encoding='cp1252'", time_unit="ms", force_unit="N")
    assert err.line == 1
    rec = read_wpd(
        p, encoding="cp1252", channels={"Fn": "Normalkraft é"}, time_unit="ms", force_unit="N"
    )
    np.testing.assert_array_equal(rec["Fn"].values, [2.0, 3.0])


def test_wpd_ft_alone_has_no_normal_force():
    p = SAMPLES / "wpd_Ft.csv"
    _raises(p, "no normal-force channel", time_unit="us", force_unit="N")


def test_wpd_datasets_sample():
    p = SAMPLES / "wpd_datasets.csv"
    assert sniff_format(p) == "wpd_datasets"
    rec = load(p, time_unit="us", force_unit="N", radius=0.0127)
    assert rec.attrs["channels"] == "Fn=Normal force,Ft=Tangential force"
    assert int(rec["Fn_measured"].sum()) == 28 and int(rec["Ft_measured"].sum()) == 19
    t, f = channel(rec, "Fn")
    truth = hertz_pulse(np.clip(t, 0, IMPACT.t_c), IMPACT)["F"]
    assert np.max(np.abs(f - truth)) < 0.05 * IMPACT.F_max


DATASETS = "normal,,Friction,,junk,\nX,Y,X,Y,X,Y\n3,30,1,1,0,0\n1,10,2,2,1,1\n2,20,,,2,2\n"


def test_wpd_datasets_mapping_padding_and_override(tmp_path):
    p = _write(tmp_path, "wpd_datasets.csv", DATASETS)
    rec = load(p, time_unit="s", force_unit="N")
    np.testing.assert_array_equal(channel(rec, "Fn")[1], [10, 20, 30])
    np.testing.assert_array_equal(channel(rec, "Ft")[0], [1, 2])
    assert rec.attrs["ignored_datasets"] == "junk"
    rec = load(p, channels={"Fn": "JUNK", "Ft": "normal"}, time_unit="s", force_unit="N")
    np.testing.assert_array_equal(channel(rec, "Fn")[1], [0, 1, 2])
    _raises(p, "names no dataset", channels={"Fn": "missing"}, time_unit="s", force_unit="N")
    q = _write(tmp_path, "two.csv", "Fn,,normal force,\nX,Y,X,Y\n0,1,0,1\n1,2,1,2\n")
    _raises(q, "both look like Fn", time_unit="s", force_unit="N")
    r = _write(tmp_path, "dc.csv", "Fn;;Ft;\nX;Y;X;Y\n0,5;1,5;0;1\n1,5;2,5;;\n2;1;1;2\n")
    rec = load(r, time_unit="ms", force_unit="N")
    np.testing.assert_allclose(channel(rec, "Fn")[0], [0.5e-3, 1.5e-3, 2e-3])


@pytest.mark.parametrize(
    "name,content,kw,fragment,line",
    [
        ("Fn1.csv", "1,2\n2,3\n", {"force_unit": "N"}, "time_unit=", None),
        ("Fn2.csv", "1,2\n2,3\n", {"time_unit": "ms"}, "force_unit=", None),
        ("Fn3.csv", "1,2\n2,3\n", {"time_unit": "kg", "force_unit": "N"}, "not a time unit", None),
        (
            "Fn3b.csv",
            "1,2\n2,3\n",
            {"time_unit": "s", "force_unit": "Pa"},
            "not a force unit",
            None,
        ),
        ("Fn4.csv", "1,2\n3,3\n1,5\n", {}, "two points at x = 1.0 (lines 1 and 3)", 3),
        ("Fn5.csv", "1,2\n", {}, "single point", 1),
        ("Fn6.csv", "1,2\n2,x\n", {}, "'x' is not a number", 2),
        ("Fn7.csv", "1,2\n2,nan\n", {}, "NaN or infinite", 2),
        ("Fn8.csv", "1,2\n2,inf\n", {}, "NaN or infinite", 2),
        ("Fn9.csv", "1,2\n2,3,4\n", {}, "has 3 fields", 2),
        ("Fn10.csv", "1,5;2\n2;3.5\n", {}, "decimal point in a decimal-comma file", 2),
        ("Fn10b.csv", "1;2\n2;3.5\n2;1\n", {}, "two points at x = 2.0", 3),
        ("Fn11.csv", "1,2\n2,1_0\n", {}, "not a number", 2),
        ("ds1.csv", "Fn,,Ft,\nX,Y,X,Y\n1,2,3,\n2,3,4,5\n", {}, "x without a y", 3),
        ("ds2.csv", "Fn,,Ft,\nX,Y,X,Y\n1,2,3,4\n", {}, "single point", 3),
        ("ds3.csv", "A,,B,\nX,Y,X,Y\n1,2,3,4\n2,3,4,5\n", {}, "no normal-force channel", None),
        ("ds4.csv", "Fn,,\nX,Y,X,Y\n1,2,3,4\n2,3,4,5\n", {}, "has no name", 1),
        ("ds5.csv", "Fn,,Ft,\nX,Y,X,Y\n1,2,3,4,5,6\n2,3,4,5\n", {}, "has 6 fields", 3),
    ],
)
def test_wpd_bad_input(tmp_path, name, content, kw, fragment, line):
    p = _write(tmp_path, name, content)
    units = {"time_unit": "ms", "force_unit": "N"}
    args = kw if "unit" in fragment else {**units, **kw}
    err = _raises(p, fragment, **args)
    if line is not None:
        assert err.line == line, str(err)


# ------------------------------------------------------------------------------- TDMS
def _tdms(path, channels, groups=("Impact",), root=None):
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

    objs = [RootObject(root or {})]
    for g in groups:
        objs.append(GroupObject(g))
        for name, data, props in channels:
            objs.append(ChannelObject(g, name, np.asarray(data), properties=props))
    with TdmsWriter(str(path)) as w:
        w.write_segment(objs)
    return path


WF = {"wf_start_offset": 0.0, "wf_increment": 2.0, "wf_samples": 3, "wf_xunit_string": "ms"}


def test_tdms_units_time_channel_and_groups(tmp_path):
    p = _tdms(
        tmp_path / "a.tdms",
        [
            ("Fz", [1.0, 2.0, 3.0], {"unit_string": "kN", **WF}),
            ("Fx", [0.1, 0.2, 0.3], {"unit_string": "kN", **WF}),
        ],
    )
    rec = read_tdms(p)
    np.testing.assert_allclose(rec["time"].values, [0.0, 2e-3, 4e-3], rtol=1e-15)
    np.testing.assert_allclose(rec["Fn"].values, [1e3, 2e3, 3e3], rtol=1e-15)
    np.testing.assert_allclose(rec["Ft"].values, [100.0, 200.0, 300.0], rtol=1e-15)
    rec = load(p, axes={"Ft": "-Fx"})
    np.testing.assert_allclose(rec["Ft"].values, [-100.0, -200.0, -300.0], rtol=1e-15)
    _raises(p, "units in the file win", force_unit="N")
    # explicit time channel in microseconds, no waveform properties
    q = _tdms(
        tmp_path / "b.tdms",
        [("time", [0.0, 1.0, 2.5], {"unit_string": "us"}), ("Fn", [1.0, 2.0, 3.0], {})],
    )
    _raises(q, "force_unit=")
    rec = load(q, force_unit="N")
    np.testing.assert_allclose(rec["time"].values, [0.0, 1e-6, 2.5e-6], rtol=1e-15)
    r = _tdms(
        tmp_path / "c.tdms",
        [("Fz", [1.0, 2.0, 3.0], {"unit_string": "N", **WF})],
        groups=("A", "B"),
    )
    _raises(r, "group=")
    assert read_tdms(r, group="B").attrs["tdms_group"] == "B"


@pytest.mark.parametrize(
    "channels,fragment",
    [
        ([("Fz", [1.0, 2.0, 3.0], {"unit_string": "N"})], "no time track"),
        ([("Mz", [1.0, 2.0, 3.0], {"unit_string": "N", **WF})], "no force channels"),
        (
            [
                ("Fz", [1.0, 2.0, 3.0], {"unit_string": "N", **WF}),
                ("Fx", [1.0, 2.0], {"unit_string": "N", **WF}),
            ],
            "different lengths",
        ),
        ([("Fz", [1.0, np.nan, 3.0], {"unit_string": "N", **WF})], "NaN or infinite"),
        ([("Fz", [1.0], {"unit_string": "N", **WF})], "single sample"),
        (  # a unit past the float range once in newtons, as the CSV reader refuses it
            [("Fz", [1.0, 2.0, 1e303], {"unit_string": "MN", **WF})],
            "'Fz' overflows when converted to newtons (×1e+06)",
        ),
        ([("Fz", [1.0, 2.0, 3.0], {"unit_string": "V", **WF})], "not a force unit"),
        ([("Fz", [1.0, 2.0, 3.0], {"unit_string": "N", **WF, "wf_increment": 0.0})], "repeats"),
        (
            [
                ("time", [0.0, 2.0, 1.0], {"unit_string": "s"}),
                ("Fz", [1.0, 2.0, 3.0], {"unit_string": "N"}),
            ],
            "goes backwards",
        ),
    ],
)
def test_tdms_bad_input(tmp_path, channels, fragment):
    p = _tdms(tmp_path / "bad.tdms", channels)
    _raises(p, fragment)


def test_tdms_unit_in_channel_name(tmp_path):
    """'Fz (kN)' without unit_string is kilonewtons (it was read as whatever force_unit=
    said); a name and a unit_string that disagree are refused."""
    p = _tdms(tmp_path / "named.tdms", [("Fz (kN)", [1.0, 2.0, 3.0], WF)])
    rec = load(p)
    np.testing.assert_allclose(rec["Fn"].values, [1e3, 2e3, 3e3], rtol=1e-15)
    assert rec.attrs["source_force_unit"] == "kN"
    _raises(p, "units in the file win", force_unit="N")
    q = _tdms(tmp_path / "clash.tdms", [("Fz (kN)", [1.0, 2.0, 3.0], {**WF, "unit_string": "N"})])
    _raises(q, "unit_string property says 'N'")
    # a parenthesis that is no unit is a label: the property decides
    r = _tdms(tmp_path / "label.tdms", [("Fz (raw)", [1.0, 2.0, 3.0], {**WF, "unit_string": "N"})])
    np.testing.assert_array_equal(load(r)["Fn"].values, [1.0, 2.0, 3.0])


def test_tdms_duplicate_force_channel_and_temperature_channel(tmp_path):
    two = [
        ("Fz", [1.0, 2.0, 3.0], {"unit_string": "N", **WF}),
        ("Fz (raw)", [7.0, 8.0, 9.0], {"unit_string": "N", **WF}),
    ]
    _raises(_tdms(tmp_path / "two.tdms", two), "'Fz' and 'Fz (raw)'")  # was: last one won
    temp = [
        ("time", [0.0, 1.0, 2.0], {"unit_string": "ms"}),
        ("T", [20.0, 21.0, 22.0], {"unit_string": "degC"}),  # a temperature, not time
        ("Fz", [1.0, 2.0, 3.0], {"unit_string": "N"}),
    ]
    rec = load(_tdms(tmp_path / "temp.tdms", temp))
    np.testing.assert_allclose(rec["time"].values, [0.0, 1e-3, 2e-3], rtol=1e-15)
    times = [("time", [0.0, 1.0, 2.0], {"unit_string": "s"}), *temp[1:]]
    times[1] = ("t", [0.0, 1.0, 2.0], {"unit_string": "ms"})
    _raises(_tdms(tmp_path / "times.tdms", times), "several time channels")


def test_tdms_time_unit_supplies_a_missing_wf_xunit_string(tmp_path):
    """Without wf_xunit_string the file carries no time unit: time_unit= supplies it (it
    clashed with an assumed 's'); with neither, NI's default, seconds."""
    wf = {"wf_start_offset": 0.0, "wf_increment": 2.0, "wf_samples": 3, "unit_string": "N"}
    p = _tdms(tmp_path / "nox.tdms", [("Fz", [1.0, 2.0, 3.0], wf)])
    np.testing.assert_allclose(load(p, time_unit="ms")["time"].values, [0, 2e-3, 4e-3], rtol=1e-15)
    np.testing.assert_allclose(load(p)["time"].values, [0.0, 2.0, 4.0], rtol=1e-15)
    q = _tdms(tmp_path / "x.tdms", [("Fz", [1.0, 2.0, 3.0], {**wf, "wf_xunit_string": "s"})])
    _raises(q, "units in the file win", time_unit="ms")


def test_tdms_corrupt_and_not_tdms(tmp_path):
    good = (SAMPLES / "sensor.tdms").read_bytes()
    p = _write(tmp_path, "cut.tdms", good[: len(good) // 2])
    _raises(p, "TDMS")
    q = _write(tmp_path, "fake.tdms", b"time [s],Fz [N]\n0,1\n1,2\n")
    _raises(q, "not a TDMS file")


def test_wpd_number_past_float_range_is_refused(tmp_path):
    """'1e400' overflows to inf: refused like an explicit inf (found by test_io_fuzz)."""
    p = tmp_path / "Fn.csv"
    p.write_text("1e400, 5\n2, 20\n1, 10\n4, 1\n", encoding="utf-8")
    with pytest.raises(InputError, match=r"Fn\.csv, line 1.*infinite"):
        load(p, time_unit="ms", force_unit="N")


# ------------------------------------------------------------------ cross-talk decoupling
def _crosstalk_pair(tmp_path, C):
    """The same ideal impact through the sensor model with cross-talk C and without, as
    sensor CSVs (no noise, offset, drift or ADC: only the linear mixing differs)."""
    from pipeline.sensor_model import to_sensor

    t = np.linspace(0.0, IMPACT.t_c, 801)
    F = hertz_pulse(t, IMPACT)["F"]
    ideal = make_record(
        t,
        {"Fn": F, "Ft": 0.15 * F * np.cos(np.pi * t / IMPACT.t_c), "Fy": 0.0 * F},
        attrs={"source": "hertz_pulse", "format": "test", "kind": "simulated"},
    )
    quiet = dict(noise=0.0, offset=0.0, drift=0.0, bits=None, full_scale=np.inf, seed=3)
    mixed = write_sensor(to_sensor(ideal, crosstalk=C, **quiet), tmp_path / "mixed.csv")
    clean = write_sensor(to_sensor(ideal, crosstalk=np.eye(3), **quiet), tmp_path / "clean.csv")
    return mixed, clean


# The sensor model orders axes (Fn, Ft, Fy) and write_sensor writes them as (Fz, Fx, Fy):
# P maps model order to the file's raw (Fx, Fy, Fz) order.
P = np.array([[0, 1, 0], [0, 0, 1], [1, 0, 0]], dtype=float)
C_MODEL = np.array([[1.0, 0.03, -0.02], [0.025, 1.0, 0.015], [-0.01, 0.02, 1.0]])


def test_decouple_with_the_inverse_crosstalk_recovers_the_ideal_forces(tmp_path):
    """pipeline.sensor_model.to_sensor mixes F_meas = C·F_true (its own cross-talk
    matrix, model order); decoupling the file with M = P·C⁻¹·Pᵀ (file order Fx, Fy, Fz)
    gives back the record the sensor would give without cross-talk."""
    mixed, clean = _crosstalk_pair(tmp_path, C_MODEL)
    M = P @ np.linalg.inv(C_MODEL) @ P.T
    rec = load(mixed, decouple=M)
    ref = load(clean)
    scale = float(np.max(np.abs(ref["Fn"].values)))
    for name in ("Fn", "Ft", "Fy"):
        # one inversion and a 3-term sum per sample: a few ulp of the peak
        np.testing.assert_allclose(rec[name].values, ref[name].values, rtol=0, atol=1e-12 * scale)
    raw = load(mixed)
    assert np.max(np.abs(raw["Fy"].values)) > 0.01 * scale  # the mixing was there to undo
    assert rec.attrs["decouple_axes"] == "Fx,Fy,Fz"
    assert [float(x) for x in rec.attrs["decouple_matrix"].split(",")] == M.ravel().tolist()
    assert rec.attrs["decouple_source"] == "array"


def test_decouple_from_a_file_records_its_provenance(tmp_path):
    mixed, clean = _crosstalk_pair(tmp_path, C_MODEL)
    M = P @ np.linalg.inv(C_MODEL) @ P.T
    text = "# calibration sheet 2024-03\n" + "\n".join(
        ";".join(repr(float(x)) for x in row) for row in M
    )
    m_file = _write(tmp_path, "decouple.txt", text + "\n")
    rec = load(mixed, decouple=m_file)
    assert rec.attrs["decouple_source"] == "decouple.txt"
    assert (
        rec.attrs["decouple_sha256"]
        == __import__("hashlib").sha256(m_file.read_bytes()).hexdigest()
    )
    as_json = _write(tmp_path, "m.json", json.dumps({"matrix": M.tolist()}))
    np.testing.assert_array_equal(load(mixed, decouple=as_json)["Fn"].values, rec["Fn"].values)


@pytest.mark.parametrize(
    "spec,fragment",
    [
        (np.eye(2), "must be 3×3"),
        ([[1, 0, 0], [0, 1, 0], [0, 0, np.nan]], "must be 3×3 and finite"),
        ([[1, 1, 0], [1, 1, 0], [0, 0, 1]], "singular"),
        ("no_such_matrix.txt", "no such file"),
    ],
)
def test_bad_decoupling_matrices(tmp_path, spec, fragment):
    mixed, _ = _crosstalk_pair(tmp_path, C_MODEL)
    with pytest.raises(InputError, match=fragment):
        load(mixed, decouple=spec)


def test_decouple_needs_raw_axes(tmp_path):
    p = _write(tmp_path, "fnft.csv", "time [s],Fn [N],Ft [N]\n0,1,0\n1e-6,2,0\n")
    with pytest.raises(
        InputError, match="needs the raw Fx, Fy and Fz columns; the header has no Fx"
    ):
        load(p, decouple=np.eye(3))
    with pytest.raises(InputError, match="decouple= does not apply to digitised"):
        load(SAMPLES / "wpd_datasets.csv", time_unit="us", force_unit="N", decouple=np.eye(3))


# ------------------------------------------------------------------ metadata and the scene
def test_metadata_with_units_fills_scene_fields(tmp_path):
    from pipeline.io import scene_from_metadata

    text = (
        "# impact speed [m/s]: 0.6\n# Angle: 15 deg\n# ball diameter: 25,4 mm\n"
        "# mass [g]: 67.35\n# restitution: 0.9\n# speed of sound: 5000\n"
        "# E: 210 GPa\n# operator: A. Lab\ntime [s],Fz [N]\n0,1\n1e-6,2\n"
    )
    rec = load(_write(tmp_path, "meta.csv", text))
    fields = scene_from_metadata(rec)
    assert {k: v for k, (v, _) in fields.items()} == pytest.approx(
        {"speed": 0.6, "angle_deg": 15.0, "radius": 0.0127, "mass": 0.06735, "e": 0.9, "E": 210e9}
    )
    assert fields["radius"][1] == "record metadata 'ball_diameter' = '25,4 mm'"
    assert rec.attrs["meta_impact_speed"] == "0.6 m/s"  # the key's unit kept with the value


@pytest.mark.parametrize(
    "line,fragment",
    [
        ("# speed: 5 mm", "'mm' is not a unit of it"),
        ("# radius: 1 cm\n# diameter: 1 cm", "two values for radius"),
    ],
)
def test_metadata_that_contradicts_itself(tmp_path, line, fragment):
    from pipeline.io import scene_from_metadata

    rec = load(_write(tmp_path, "m.csv", f"{line}\ntime [s],Fz [N]\n0,1\n1e-6,2\n"))
    with pytest.raises(InputError, match=fragment):
        scene_from_metadata(rec)


def test_a_bare_number_is_not_guessed(tmp_path):
    from pipeline.io import scene_from_metadata

    rec = load(_write(tmp_path, "m.csv", "# speed: 0.6\ntime [s],Fz [N]\n0,1\n1e-6,2\n"))
    assert scene_from_metadata(rec) == {}


# ------------------------------------------------------------------------- sample rate
def test_stated_sample_rate_against_the_time_column(tmp_path):
    from pipeline.errors import SampleRateWarning, UnitMismatchError

    body = "time [s],Fz [N]\n" + "".join(f"{k * 0.5},{k}\n" for k in range(5))
    p = _write(tmp_path, "rate.csv", "# sample rate: 2 MHz\n" + body)
    with pytest.raises(UnitMismatchError, match="time values are in 'us', not 's'") as info:
        load(p)
    assert info.value.ratio == pytest.approx(1e6)
    ok = _write(tmp_path, "ok.csv", "# sample rate [Hz]: 2\n" + body)
    assert load(ok).sizes["time"] == 5
    off = _write(tmp_path, "off.csv", "# sample rate: 2.5 Hz\n" + body)
    with pytest.warns(SampleRateWarning, match="states 'sample_rate: 2.5 Hz'"):
        load(off)


def test_the_stated_bandwidth_becomes_sensor_bandwidth_in_hz():
    """'# bandwidth [Hz]: 300000' in a sensor export (the bundled GR-style sample) is kept as
    attrs['sensor_bandwidth'] [Hz], which the resolution checks of the percussions read; a
    unit after the number works too, and a bare number is not guessed."""
    from pipeline.io.metadata import stated_bandwidth

    rec = load(SAMPLES / "gr_15deg_0.6ms.csv")
    assert rec.attrs["sensor_bandwidth"] == pytest.approx(3e5, rel=1e-12)
    assert stated_bandwidth({"meta_cutoff": "300 kHz"})[0] == pytest.approx(3e5, rel=1e-12)
    assert stated_bandwidth({"meta_bandwidth": "300000"}) is None
