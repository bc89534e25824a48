"""Fuzzing every reader and the scene parser, and the netCDF round trip of every format.

Properties: whatever bytes a file holds, ``pipeline.io.load`` and each reader
(``read_sensor``, ``read_wpd``, ``read_tdms``, ``read_lvm``, ``read_mat``), the scene
parser (``Scene.from_file``), a sample's sidecar (``pipeline.report.load_sample``) and a
decoupling-matrix file either return their result (a record that passes
``pipeline.record.validate``, a Scene) or raise ``InputError`` naming the file — never
another exception, never a bare pandas/numpy/npTDMS/scipy/h5py/json traceback — and never
change a byte of the file.
And a valid sensor CSV or LabVIEW Measurement file in any accepted dialect loads to the
values written in it, in SI (volts through their sensitivity).

Example counts are multiples of the profile's unit (tests/conftest.py): 100 in
``make test``, 500 under the ``fuzz`` profile CI runs (over 10,000 examples in all).
"""

from __future__ import annotations

import json
import shutil
import tempfile
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pipeline import Scene
from pipeline.errors import InputError, PipelineWarning
from pipeline.io import (
    load,
    read_decoupling,
    read_lvm,
    read_mat,
    read_sensor,
    read_tdms,
    read_wpd,
    validate,
)

SAMPLES = Path(__file__).resolve().parents[1] / "data_samples"
SAMPLE_FILES = {
    "sensor_decimal_comma.csv": {},
    "wpd_Fn.csv": {"time_unit": "us", "force_unit": "N"},
    "wpd_datasets.csv": {"time_unit": "us", "force_unit": "N"},
    "sensor.tdms": {},
    "sensor_volts.lvm": {"sensitivity": {"Fn": (0.225, "mV/N"), "Ft": (0.5, "mV/N")}},
    "sensor_v5.mat": {},
    "sensor_v73.mat": {
        "sensitivity": {"Fn": (0.225, "mV/N"), "Ft": (0.5, "mV/N"), "Fy": (0.5, "mV/N")},
        "columns": {"data.raw": ["time [s]", "Fx [V]", "Fy [V]", "Fz [V]"]},
    },
}
SMALL = {  # short valid files: mutations reach every line of them quickly
    "small.csv": b"# a: 1\r\ntime [ms];Fx [kN];Fy [kN];Fz [kN]\r\n0;0,1;0;1,5\r\n"
    b"1;0,2;0;2,5\r\n2;0,1;0;1,0\r\n",
    "Fn.csv": b"2, 20\n1, 10\n3, 5\n4, 1\n",
    "wpd_datasets.csv": b"Fn,,Ft,\nX,Y,X,Y\n1,2,1.5,3\n2,3,2.5,4\n3,1,,\n",
    "small.lvm": b"LabVIEW Measurement\t\r\nSeparator\tTab\r\nDecimal_Separator\t,\r\n"
    b"X_Columns\tNo\r\n***End_of_Header***\t\r\n\t\r\nChannels\t2\t\t\r\n"
    b"Y_Unit_Label\tVolts\tN\t\r\nX0\t0,0E+0\t0,0E+0\t\r\nDelta_X\t1,0E-6\t1,0E-6\t\r\n"
    b"***End_of_Header***\t\t\t\r\nX_Value\tFz\tFx\tComment\r\n\t0,1\t2\tc\r\n"
    b"\t0,3\t1\r\n\t0,2\t0\r\n",
}
ORIGINALS = {name: (SAMPLES / name).read_bytes() for name in SAMPLE_FILES} | SMALL
TOKENS = [
    "",
    " ",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "abc",
    "1e400",
    "-1e-400",
    "1,5",
    "1.5",
    "0",
    "-0",
    '"',
    "#",
    "[kN]",
    "(ms)",
    "µs",
    "\t",
    ";",
    ",",
    "1_0",
    "0x10",
    "\x00",
    "é",
    "\u00a0",  # no-break space
    "1.000,5",  # thousands separator
    '"1,5"',  # Excel-quoted cell
    "\r",
    "T [°C]",
    "Fz (kN)",
]

_TMP = Path(tempfile.mkdtemp(prefix="io_fuzz_"))
#: The profile's example unit (tests/conftest.py): 100 by default, 500 under "fuzz".
UNIT = settings.default.max_examples


def teardown_module(module):
    shutil.rmtree(_TMP, ignore_errors=True)


def _refused_or_read(path: Path, read, *names):
    """``read()`` returns its result or raises InputError naming the file (``names``: the
    file names that count); the file's bytes are unchanged either way."""
    before = path.read_bytes()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)  # a mutated file may well warn
        try:
            out = read()
        except InputError as exc:
            # only units are passed here, so every refusal is about the file: it names it
            assert any(n in str(exc) for n in (path.name, *names)), str(exc)
            out = None
    assert path.read_bytes() == before, "the input file was changed"
    return out


def _check(name: str, data: bytes, kwargs: dict, reader=load):
    path = _TMP / name
    path.write_bytes(data)
    rec = _refused_or_read(path, lambda: reader(path, **kwargs))
    if rec is None:
        return
    validate(rec)
    t = rec["time"].values
    assert t.size >= 2 and np.all(np.diff(t) > 0) and np.all(np.isfinite(t))
    assert rec.attrs["format"] in ("sensor_csv", "wpd", "wpd_datasets", "tdms", "lvm", "mat")


# ---------------------------------------------------------------------------- mutations
def _flip(data: bytes, draw) -> bytes:
    if not data:
        return data
    i = draw(st.integers(0, len(data) - 1))
    b = draw(st.integers(0, 255))
    return data[:i] + bytes([b]) + data[i + 1 :]


def _truncate(data: bytes, draw) -> bytes:
    return data[: draw(st.integers(0, len(data)))]


def _lines(data: bytes):
    return data.split(b"\n")


def _delete_line(data: bytes, draw) -> bytes:
    lines = _lines(data)
    i = draw(st.integers(0, len(lines) - 1))
    return b"\n".join(lines[:i] + lines[i + 1 :])


def _duplicate_line(data: bytes, draw) -> bytes:
    lines = _lines(data)
    i = draw(st.integers(0, len(lines) - 1))
    j = draw(st.integers(0, len(lines)))
    return b"\n".join(lines[:j] + [lines[i]] + lines[j:])


def _replace_cell(data: bytes, draw) -> bytes:
    lines = _lines(data)
    i = draw(st.integers(0, len(lines) - 1))
    line = lines[i]
    sep = next((s for s in (b";", b"\t", b",") if s in line), b",")
    cells = line.split(sep)
    k = draw(st.integers(0, len(cells) - 1))
    token = draw(st.sampled_from(TOKENS) | st.text(max_size=6)).encode("utf-8")
    cells[k] = token
    lines[i] = sep.join(cells)
    return b"\n".join(lines)


MUTATORS = [_flip, _truncate, _delete_line, _duplicate_line, _replace_cell]


@st.composite
def mutated(draw):
    name = draw(st.sampled_from(sorted(ORIGINALS)))
    data = ORIGINALS[name]
    for _ in range(draw(st.integers(1, 3))):
        data = draw(st.sampled_from(MUTATORS))(data, draw)
    kwargs = dict(SAMPLE_FILES.get(name, {"time_unit": "ms", "force_unit": "N"}))
    if name == "small.csv":
        kwargs = {}
    if name == "small.lvm":
        kwargs = {"sensitivity": {"Fn": (2.0, "N/mV")}}
    return name, data, kwargs


@settings(max_examples=10 * UNIT, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated())
def test_mutated_files_give_record_or_input_error(case):
    name, data, kwargs = case
    _check(name, data, kwargs)


READERS = {".csv": read_sensor, ".tdms": read_tdms, ".lvm": read_lvm, ".mat": read_mat}


@settings(max_examples=3 * UNIT, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated())
def test_each_reader_called_directly_gives_record_or_input_error(case):
    """The format readers themselves, not only load's sniffing in front of them: each is
    handed whatever the mutation made of a file of its format."""
    name, data, kwargs = case
    if name.startswith(("wpd", "Fn")):
        reader = read_wpd
        kwargs = {"time_unit": "us", "force_unit": "N", **kwargs}
        if not name.startswith("wpd_datasets"):
            kwargs["channels"] = "Fn"
    else:
        reader = READERS[Path(name).suffix]
    _check(name, data, kwargs, reader=reader)


@settings(max_examples=5 * UNIT, deadline=None)
@given(
    data=st.binary(max_size=400)
    | st.text(
        alphabet=st.sampled_from(list("0123456789.,;\t\n\r -+eE#[]()xyXYFtnzms")), max_size=300
    ).map(lambda s: s.encode()),
    name=st.sampled_from(["r.csv", "Fn.csv", "r.tdms", "r.txt", "r.lvm", "r.mat"]),
    units=st.booleans(),
)
def test_random_bytes_give_record_or_input_error(data, name, units):
    kwargs = {"time_unit": "ms", "force_unit": "N"} if units else {}
    _check(name, data, kwargs)


# ------------------------------------------------------------------------ netCDF round trip
@pytest.mark.parametrize(
    "source,kwargs",
    [
        ("sensor_decimal_comma.csv", {}),
        ("wpd_Fn.csv", {"time_unit": "us", "force_unit": "N"}),
        ("wpd_datasets.csv", {"time_unit": "us", "force_unit": "N"}),
        ({"Fn": "wpd_Fn.csv", "Ft": "wpd_Ft.csv"}, {"time_unit": "us", "force_unit": "N"}),
        ("sensor.tdms", {}),
        *((name, SAMPLE_FILES[name]) for name in ("sensor_volts.lvm", "sensor_v5.mat")),
        ("sensor_v73.mat", SAMPLE_FILES["sensor_v73.mat"]),
    ],
)
def test_netcdf_round_trip_loses_nothing(tmp_path, source, kwargs):
    if isinstance(source, dict):
        source = {k: SAMPLES / v for k, v in source.items()}
    else:
        source = SAMPLES / source
    rec = load(source, radius=0.0127, mass=0.06735, angle_deg=15, **kwargs)
    for key, value in rec.attrs.items():  # netCDF-serialisable attributes only
        assert isinstance(value, str | float), (key, value)
    out = tmp_path / "r.nc"
    rec.to_netcdf(out, engine="h5netcdf")
    with xr.open_dataset(out, engine="h5netcdf") as back:
        back = back.load()
    xr.testing.assert_identical(rec, back)
    assert back.attrs == rec.attrs
    for name in rec.variables:
        assert back[name].dtype == rec[name].dtype, name
        assert back[name].attrs == rec[name].attrs, name


# ------------------------------------------------------------- valid dialects, known values
TIME_UNITS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "μs": 1e-6, "ns": 1e-9}
FORCE_UNITS = {"N": 1.0, "kN": 1e3, "mN": 1e-3, "daN": 10.0}


@st.composite
def sensor_dialect(draw):
    """A valid sensor CSV in a random dialect, and the SI values it holds."""
    sep = draw(st.sampled_from([",", ";", "\t"]))
    dec = "." if sep == "," else draw(st.sampled_from([".", ","]))
    t_unit = draw(st.sampled_from(sorted(TIME_UNITS)))
    f_unit = draw(st.sampled_from(sorted(FORCE_UNITS)))
    n = draw(st.integers(2, 12))
    # values exactly representable as short decimals: the text is the ground truth
    t = np.cumsum(draw(st.lists(st.integers(1, 999), min_size=n, max_size=n))) / 8
    fz = np.array(draw(st.lists(st.integers(-9999, 99999), min_size=n, max_size=n))) / 4
    fx = np.array(draw(st.lists(st.integers(-999, 999), min_size=n, max_size=n))) / 16

    def num(v):
        text = repr(float(v))
        if draw(st.booleans()) and v != 0:
            text = f"{v:.6E}"  # scientific notation, 1,250000E-03 in a decimal-comma file
        text = text.replace(".", dec)
        return f'"{text}"' if draw(st.integers(0, 9)) == 0 else text  # Excel quoting

    bracket = draw(st.sampled_from(["[{}]", "({})", " [{}]", " ({})"]))
    space = draw(st.sampled_from(["", " "]))
    tname = draw(st.sampled_from(["time", "Time", "t", "T"]))
    cols = [f"{tname}{space}{bracket.format(t_unit).strip()}"]
    cols += [
        f"Fx{space}{bracket.format(f_unit).strip()}",
        f"Fz{space}{bracket.format(f_unit).strip()}",
    ]
    extra = draw(st.booleans())
    if extra:
        cols.append("T [°C]")  # a temperature: not a second time column
    trail = sep if draw(st.booleans()) else ""
    rows = []
    for k in range(n):
        cells = [num(t[k]), num(fx[k]), num(fz[k])] + (["21" + dec + "5"] if extra else [])
        rows.append(sep.join(cells) + trail)
        if draw(st.integers(0, 5)) == 0:
            rows.append(draw(st.sampled_from(["", " ", "  "])))  # blank line inside the table
    meta = draw(st.lists(st.sampled_from(["# operator: A. Lab", "# gain = 10 N/V", "# note"])))
    excel = [f"sep={sep}"] if draw(st.booleans()) else []
    eol = draw(st.sampled_from(["\n", "\r\n", "\r"]))
    text = eol.join(excel + meta + [sep.join(cols) + trail] + rows) + eol
    encoding = draw(st.sampled_from(["utf-8", "utf-8-sig", "utf-16"]))
    truth = {"time": t * TIME_UNITS[t_unit], "Fn": fz * FORCE_UNITS[f_unit]}
    truth["Ft"] = fx * FORCE_UNITS[f_unit]
    return text.encode(encoding), truth


@settings(max_examples=2 * UNIT, deadline=None)
@given(sensor_dialect())
def test_valid_sensor_dialects_load_to_known_si_values(case):
    """Odd but valid dialects (units with or without a space, µ/μ, decimal comma with
    scientific notation, Excel quoting and sep= line, trailing separators, blank lines in
    the table, a temperature column 'T [°C]', CR/LF/CRLF, BOM, UTF-16) load to the values
    written, converted to SI."""
    data, truth = case
    path = _TMP / "dialect.csv"
    path.write_bytes(data)
    rec = load(path)
    np.testing.assert_allclose(rec["time"].values, truth["time"], rtol=1e-15, atol=0)
    np.testing.assert_allclose(rec["Fn"].values, truth["Fn"], rtol=1e-15, atol=0)
    np.testing.assert_allclose(rec["Ft"].values, truth["Ft"], rtol=1e-15, atol=0)


SEP_NAMES = {"\t": "Tab", ",": "Comma", ";": "Semicolon"}


@st.composite
def lvm_dialect(draw):
    """A valid LabVIEW Measurement file in a random dialect, and the SI values it holds."""
    sep = draw(st.sampled_from(["\t", ",", ";"]))
    dec = "." if sep == "," else draw(st.sampled_from([".", ","]))
    x_mode = draw(st.sampled_from(["No", "One", "Multi"]))
    n = draw(st.integers(2, 10))
    step = draw(st.sampled_from([1, 2, 5])) * 1e-6  # short decimals: the text is the truth
    x0 = draw(st.integers(-20, 20)) * step
    t = x0 + step * np.arange(n)
    fz = np.array(draw(st.lists(st.integers(-9999, 99999), min_size=n, max_size=n))) / 8
    fx = np.array(draw(st.lists(st.integers(-999, 999), min_size=n, max_size=n))) / 16
    unit = draw(st.sampled_from(["Newtons", "N", "kN", "Volts", "mV"]))
    scale = {"Newtons": 1.0, "N": 1.0, "kN": 1e3, "Volts": 2000.0, "mV": 2.0}[unit]

    def num(v):
        text = f"{v:.15E}" if draw(st.booleans()) and v != 0 else repr(float(v))
        return text.replace(".", dec)

    def row(tag, cells):
        return sep.join([tag, *cells, ""])

    width = ["", ""] if x_mode != "Multi" else ["", "", ""]
    per = (lambda v: [v, v]) if x_mode != "Multi" else (lambda v: [v, "", v])
    head = [
        f"LabVIEW Measurement{sep}",
        f"Separator{sep}{SEP_NAMES[sep]}",
        *([f"Decimal_Separator{sep}{dec}"] if dec == "," or draw(st.booleans()) else []),
        f"Multi_Headings{sep}{draw(st.sampled_from(['Yes', 'No']))}",
        f"X_Columns{sep}{x_mode}",
        f"Operator{sep}A. Lab",
        f"***End_of_Header***{sep}",
        sep,
        row("Channels", ["2", *width[1:]]),
        row("Samples", per(str(n))),
        row("Y_Unit_Label", per(unit)),
        row("X_Dimension", per("Time")),
        row("X0", per(num(x0))),
        row("Delta_X", per(num(step))),
        sep.join(["***End_of_Header***", *width, ""]),
        sep.join(["X_Value", "Fz", *(["X_Value"] if x_mode == "Multi" else []), "Fx", "Comment"]),
    ]
    rows = []
    for k in range(n):
        x = "" if x_mode == "No" else num(t[k])
        cells = [x, num(fz[k])] + ([x] if x_mode == "Multi" else []) + [num(fx[k])]
        if draw(st.integers(0, 4)) == 0:
            cells.append(draw(st.sampled_from(["trigger", "c\\09d", "ok"])))
        rows.append(sep.join(cells))
    eol = draw(st.sampled_from(["\n", "\r\n"]))
    text = eol.join(head + rows) + eol + draw(st.sampled_from(["", eol]))
    sens = {"Fn": (0.5, "mV/N"), "Ft": (0.5, "mV/N")} if scale in (2000.0, 2.0) else None
    truth = {"time": t, "Fn": fz * scale, "Ft": fx * scale}
    return text.encode(draw(st.sampled_from(["utf-8", "utf-8-sig", "cp1252"]))), sens, truth


@settings(max_examples=2 * UNIT, deadline=None)
@given(lvm_dialect())
def test_valid_lvm_dialects_load_to_known_si_values(case):
    """Separators tab, comma, semicolon; decimal point or comma; X columns No (time from
    X0 + k·Delta_X), One or Multi; units as LabVIEW labels them (Newtons, kN, Volts, mV
    through a 0.5 mV/N sensitivity); comments; CRLF or LF; UTF-8, BOM or Windows-1252."""
    data, sens, truth = case
    path = _TMP / "dialect.lvm"
    path.write_bytes(data)
    rec = load(path, sensitivity=sens)
    np.testing.assert_allclose(rec["time"].values, truth["time"], rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(rec["Fn"].values, truth["Fn"], rtol=1e-12, atol=0)
    np.testing.assert_allclose(rec["Ft"].values, truth["Ft"], rtol=1e-12, atol=0)


# ------------------------------------------------------------------ scene files, sidecars
_JSON = st.recursive(
    st.none()
    | st.booleans()
    | st.floats(allow_nan=True, allow_infinity=True)
    | st.integers(-(10**30), 10**30)
    | st.sampled_from(["inf", "-inf", "nan", "1", "", "0.0127"])
    | st.text(max_size=8),
    lambda inner: st.lists(inner, max_size=4)
    | st.dictionaries(st.sampled_from([*Scene.field_names(), "scene", "x", "Speed"]), inner,
                      max_size=6),
    max_leaves=20,
)  # fmt: skip
SCENE_FILE = json.dumps(
    {"radius": 0.0127, "speed": 0.6, "density": 7850.0, "E": 2.1e11, "nu": 0.29,
     "target_mass": "inf", "angle_deg": 15.0}
).encode()  # fmt: skip


def _scene_bytes():
    """Bytes of a scene file: random JSON values, random bytes, or a good file mutated."""
    return (
        _JSON.map(lambda v: json.dumps(v).encode())
        | st.binary(max_size=200)
        | st.builds(
            lambda d, i, b: d[:i] + bytes([b]) + d[i + 1 :],
            st.just(SCENE_FILE),
            st.integers(0, len(SCENE_FILE) - 1),
            st.integers(0, 255),
        )
        | st.fixed_dictionaries(
            {k: st.just(v) for k, v in json.loads(SCENE_FILE).items()},
            optional={k: _JSON for k in Scene.field_names() if k not in json.loads(SCENE_FILE)},
        ).map(lambda d: json.dumps(d).encode())
    )


@settings(max_examples=4 * UNIT, deadline=None)
@given(data=_scene_bytes())
def test_scene_files_give_scene_or_input_error(data):
    path = _TMP / "scene.json"
    path.write_bytes(data)
    scene = _refused_or_read(path, lambda: Scene.from_file(path))
    assert scene is None or isinstance(scene, Scene)


@settings(max_examples=2 * UNIT, deadline=None)
@given(data=_scene_bytes() | _JSON.map(lambda v: json.dumps({"load": v}).encode()))
def test_sidecars_give_record_or_input_error(data):
    """A sample and whatever its sidecar holds: the record as the sidecar's 'load' block
    says, or an InputError naming the sidecar or the record."""
    from pipeline.report import load_sample, scene_from_sidecar

    folder = _TMP / "side"
    folder.mkdir(exist_ok=True)
    (folder / "r.csv").write_bytes(SMALL["small.csv"])
    side = folder / "r.json"
    side.write_bytes(data)
    _refused_or_read(
        side, lambda: (load_sample(folder / "r.csv"), scene_from_sidecar(folder / "r.csv")), "r.csv"
    )


@settings(max_examples=UNIT, deadline=None)
@given(
    data=st.binary(max_size=120)
    | st.lists(st.lists(st.sampled_from(["1", "0", "-0.5", "1e308", "nan", "x", ""]),
                        max_size=4), max_size=4).map(
        lambda rows: "\n".join(",".join(r) for r in rows).encode()
    ),
    suffix=st.sampled_from([".txt", ".csv", ".json", ".npy"]),
)  # fmt: skip
def test_decoupling_files_give_matrix_or_input_error(data, suffix):
    path = _TMP / f"m{suffix}"
    path.write_bytes(data)
    out = _refused_or_read(path, lambda: read_decoupling(path))
    if out is not None:
        assert out[0].shape == (3, 3) and np.all(np.isfinite(out[0]))
