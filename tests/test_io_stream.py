"""Large files in bounded memory: pipeline.io.load_contact keeps the first contact.

Truth: an exact elastic Hertz pulse (Johnson, Contact Mechanics, CUP 1985, §11.4,
doi:10.1017/CBO9781139171731) in a long record with offset, drift and white noise, written
by pipeline.io.write_sensor (its text is the ground truth: read back exactly). The cropped
record must give the window the whole record gives, and every check the whole file gets.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from pipeline import Scene
from pipeline.contact import hertz_impact, hertz_pulse
from pipeline.errors import InputError, MultipleImpactWarning, NoPulseError
from pipeline.io import load, load_contact, write_sensor
from pipeline.record import make_record
from pipeline.window import find_contact

SCENE = Scene(
    radius=0.0127, density=7850.0, E=210e9, nu=0.3, target_E=210e9, target_nu=0.3, speed=0.5
)
IMPACT = hertz_impact(SCENE)
FS = 2e6
N = 120_000  # 60 ms at 2 MHz, ~9 MB: streamed (over 1 MiB)
T0 = 31e-3 + 0.21e-6


def _file(tmp_path, name="long.csv", extra=None, pulse=True):
    rng = np.random.default_rng(4)
    t = np.arange(N) / FS
    F = hertz_pulse(t - T0, IMPACT)["F"] if pulse else 0.0 * t
    if extra is not None:
        F = F + extra(t)
    rec = make_record(
        t,
        {
            "Fn": F + 4.0 + 150.0 * t + rng.normal(0, 2.0, N),  # 9 N of drift over the file
            "Ft": 0.1 * F - 3.0 + rng.normal(0, 2.0, N),
            "Fy": rng.normal(0, 2.0, N),
        },
        attrs={"source": "gen", "format": "test", "kind": "sensor"},
    )
    return write_sensor(rec, tmp_path / name)


@pytest.mark.parametrize("chunk_rows", [1 << 19, 7_001])
def test_the_contact_of_a_long_file_is_the_whole_files(tmp_path, chunk_rows):
    """Chunks of 7,001 rows put the pulse across a chunk boundary; the cropped record
    is a slice of the whole one, and its window agrees to one sample period."""
    p = _file(tmp_path)
    whole = load(p)
    cut = load_contact(p, margin=5_000, chunk_rows=chunk_rows)
    i0 = int(cut.attrs["crop_first_row"])
    n = cut.sizes["time"]
    assert cut.attrs["crop_rows_total"] == N and cut.attrs["sha256"] == whole.attrs["sha256"]
    for name in ("time", "Fn", "Ft", "Fy"):
        np.testing.assert_array_equal(cut[name].values, whole[name].values[i0 : i0 + n])
    # the kept rows: the margin before the pulse's first sample above σ, and after its last
    assert 10_000 < n < 10_000 + 2 * IMPACT.t_c * FS
    a, b = find_contact(whole), find_contact(cut)
    assert abs(a.t_start - b.t_start) <= 1 / FS and abs(a.t_end - b.t_end) <= 1 / FS
    assert abs(b.t_start - T0) <= 2 / FS


def test_a_later_impact_beyond_the_margin_is_reported(tmp_path):
    t2 = T0 + 10e-3
    p = _file(tmp_path, extra=lambda t: hertz_pulse(t - t2, IMPACT)["F"])
    with pytest.warns(MultipleImpactWarning, match="1 further pulse") as info:
        cut = load_contact(p, margin=5_000)
    assert float(cut.attrs["crop_later_pulses_s"]) == pytest.approx(t2, abs=5 / FS)
    assert "long.csv" in str(info[0].message)


def test_a_bad_row_far_from_the_pulse_gets_the_exact_message(tmp_path):
    p = _file(tmp_path)
    lines = p.read_text().splitlines(keepends=True)
    k = len(lines) - 10
    lines[k] = lines[k].replace(",", ",abc,", 1).replace(",abc,", ",", 1)  # same fields
    cells = lines[k].rstrip("\n").split(",")
    cells[3] = "abc"
    lines[k] = ",".join(cells) + "\n"
    p.write_text("".join(lines))
    with pytest.raises(InputError, match=f"line {k + 1}, column Fz") as a:
        load_contact(p)
    with pytest.raises(InputError) as b:
        load(p)
    assert str(a.value) == str(b.value)


def test_no_pulse_in_a_long_file(tmp_path):
    from pipeline.errors import PlaneImpactWarning

    with pytest.warns(PlaneImpactWarning):  # noise on every axis: Fy as large as Fn
        cut = load_contact(_file(tmp_path, pulse=False), margin=5_000)
    assert cut.sizes["time"] == 10_000
    with pytest.raises(NoPulseError):
        find_contact(cut)


def test_other_formats_are_loaded_whole_and_cut_alike(tmp_path):
    from pathlib import Path

    sample = Path(__file__).resolve().parents[1] / "data_samples" / "sensor.tdms"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        rec = load_contact(sample, margin=100)
    assert rec.sizes["time"] == load(sample).sizes["time"]  # short: nothing to cut
    with pytest.raises(InputError, match="margin must be a whole number of rows"):
        load_contact(_file(tmp_path), margin=10)


@pytest.mark.parametrize(
    "head,sep,dec,eol,bom",
    [
        ("# rig: pendulum\n# sample rate: 1 MHz\n", ",", ".", "\n", False),  # pandas skips
        ('# note: a "quoted\n# rig: pendulum\n', ",", ".", "\r\n", True),  # via a file object
        ("# rig: pendulum\n\n# gain: 2\n", ";", ",", "\n", False),  # blank line, comma
    ],
)
def test_a_streamed_file_reads_as_the_same_bytes_in_memory(tmp_path, head, sep, dec, eol, bom):
    """Over 1 MiB the body goes from disk to the parser; the record must be the one the
    in-memory parse of the same bytes gives, to the bit (values, attributes, hash)."""
    from pipeline.io.sensor import STREAM_BYTES, parse_sensor_bytes

    rng = np.random.default_rng(7)
    n = 40_000
    x, y, z = rng.normal(0, 5, (3, n)) * [[1.0], [0.01], [1.0]]  # Fy: 0.2 % of Fz
    rows = [f"{i},{a:.6f},{b:.6f},{c:.6f}" for i, a, b, c in zip(range(n), x, y, z, strict=True)]
    rows[:100] = [f"{i},0,0,{i}" for i in range(100)]  # integers first: the decimal sniff
    text = head.replace("\n", eol) + f"time [us]{sep}Fx [N]{sep}Fy [N]{sep}Fz [N]{eol}"
    body = eol.join(rows) + eol
    if sep != ",":
        body = body.replace(",", "\x00").replace(".", dec).replace("\x00", sep)
    data = (b"\xef\xbb\xbf" if bom else b"") + (text + body).encode()
    assert len(data) > STREAM_BYTES
    p = tmp_path / "big.csv"
    p.write_bytes(data)
    streamed = load(p)
    import hashlib

    in_memory = parse_sensor_bytes(data, p, hashlib.sha256(data).hexdigest())
    assert streamed.identical(in_memory)
    np.testing.assert_array_equal(streamed["time"].values, np.arange(n) * 1e-6)
