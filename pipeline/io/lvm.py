"""LabVIEW Measurement files (``.lvm``): what LabVIEW's Write To Measurement File writes.

The layout (National Instruments, "Specification for the LabVIEW Measurement File
(.lvm)", tutorial 4139; the dialects below were checked on files LabVIEW wrote)::

    LabVIEW Measurement<TAB>
    Writer_Version<TAB>2
    Separator<TAB>Tab                       file header: how to read the rest
    Decimal_Separator<TAB>,
    Multi_Headings<TAB>Yes
    X_Columns<TAB>No
    Operator<TAB>A. Lab
    ***End_of_Header***<TAB>
    <TAB>
    Channels<TAB>2<TAB><TAB>                segment header: one cell per data column
    Samples<TAB>4000<TAB>4000<TAB>
    Y_Unit_Label<TAB>Volts<TAB>Volts<TAB>
    X_Dimension<TAB>Time<TAB>Time<TAB>
    X0<TAB>-5,0000000000000000E-5<TAB>...
    Delta_X<TAB>5,000000E-7<TAB>5,000000E-7<TAB>
    ***End_of_Header***<TAB><TAB><TAB>
    X_Value<TAB>Fz<TAB>Fx<TAB>Comment       the column line
    <TAB>0,000012<TAB>-0,000004<TAB>trigger  data rows (an empty X cell: X_Columns No)

What :func:`read_lvm` reads:

- one or two header blocks (the file header, then a segment header); several segments
  (one per write, each with its header, separated by a blank line), of which
  ``segment=`` picks one (0-based) when there are several; a whole file header repeated
  before a later session's segment (LabVIEW appending to an existing file);
- the separator the header states (``Separator``: ``Tab``, ``Comma``, ``Semicolon``,
  ``Space`` or the character itself; Tab when absent) and the decimal mark
  (``Decimal_Separator``: ``.`` or ``,``; ``.`` in version-1 files that lack the tag);
- ``X_Columns``: ``No`` (an empty X cell; time = X0 + k·Delta_X from the segment header,
  as LabVIEW's own reader does — or k·Delta_X, with X0 kept in ``attrs["lvm_x0"]``, where
  X0 is an absolute time, ``Time_Pref`` ``Absolute``, too large for double precision to
  hold the step), ``One`` (the first column is time) or ``Multi`` (an X column before
  every channel: the channels read must share their instants); X values that are absolute
  times are refused (:func:`pipeline.record.validate`: their text lost the step);
- the ``Comment`` column (LabVIEW's escapes ``\\09``, ``\\0D\\0A``, ``\\\\`` decoded;
  the comments go to ``attrs["meta_comment"]`` with their lines), CRLF or LF line ends,
  ``Multi_Headings`` Yes or No ("one header only": later writes append rows under the first
  header — time must still increase, so a later write that restarts its X values is an
  error that names its first line), ``***Start_Special***`` blocks (skipped);
- units: each channel's ``Y_Unit_Label`` (``Newtons``, ``N``, ``kN``; ``Volts``/``V``/``mV``
  with a sensitivity, see :mod:`pipeline.io.sensitivity`), else ``force_unit=``; time in
  seconds (LabVIEW's waveform time base; ``X_Dimension`` must be ``Time``), or
  ``time_unit=`` for a file whose X values are in another unit;
- text in UTF-8 (with or without BOM), UTF-16 with BOM, or — what LabVIEW writes on
  Windows — the system code page: a file that is not UTF-8 is read as Windows-1252
  (``attrs["encoding"]``), which changes only names and comments (numbers are ASCII) and
  reads the micro sign right in every Windows code page; ``encoding=`` names another.

Channels are named as LabVIEW names them (``Fz``, ``Untitled``, ``Dev1/ai0``): columns
named as forces (``Fn``, ``Ft``, ``Fx``, ``Fy``, ``Fz``) map as in the sensor CSV, any other
by ``axes={"Fn": "Dev1/ai0"}``.

Why our own reader and not PyPI's ``lvm_read`` (ladisk, MIT, maintained): it evaluates
header cells with Python's ``eval`` (a file can run code), reads and writes a pickle beside
the data file by default (a pickle found there is loaded: code again, and a stale cache
when the file changes), splits on tabs only, turns any unreadable cell into NaN without a
word, and drops undecodable bytes; its errors name no line. Nor ``lvmio`` (MIT, 2026):
young, and its model does not give the per-line errors and the unit, axis and sensitivity
handling every reader here shares (:mod:`pipeline.io._table`). The format is simple and
line-oriented (NI: "do not build parsers where information in one tag is dependent upon
the information found in another tag"); this reader is one pass over the lines, a
segment's rows split as one block by pandas' C parser (200,000 rows in about 0.6 s), every
refusal an :class:`~pipeline.errors.InputError` with the file and line.
"""

from __future__ import annotations

import csv
import io
import re
import warnings

import numpy as np
import pandas as pd

from ..errors import InputError
from ..record import TIME_RESOLUTION
from ._common import (
    LINE_END,
    NONFINITE,
    NUMBER,
    decode,
    exact_floats,
    meta_key,
    read_decoupling,
    read_raw,
    scene_attrs,
)
from ._table import Column, table_record
from .units import signal_factor, split_unit, time_factor

__all__ = ["read_lvm", "is_lvm_text"]

MAGIC = "LabVIEW Measurement"
END = "***End_of_Header***"
_SEPARATORS = {"tab": "\t", "comma": ",", "semicolon": ";", "space": " "}
_FORMAT_TAGS = {
    "writer_version",
    "reader_version",
    "separator",
    "decimal_separator",
    "multi_headings",
    "x_columns",
}
_ESCAPE = re.compile(r"\\(\\|[0-9A-Fa-f]{2})")
_MAX_COMMENTS = 20
#: Segment-header tags kept as metadata (``meta_<tag>``, their first cell).
_SEGMENT_TAGS = (
    "Notes",
    "Test_Name",
    "Test_Numbers",
    "Test_Series",
    "UUT_Part_Number",
    "UUT_Serial_Numbers",
    "UUT_Name",
)


def _is_number(cell: str) -> bool:
    """A decimal number (point), or LabVIEW's ``NaN``/``Inf`` (refused later, by line)."""
    return bool(NUMBER.match(cell) or NONFINITE.match(cell))


def is_lvm_text(head: str) -> bool:
    """Whether decoded text starts as a LabVIEW Measurement file."""
    return head.lstrip("\ufeff").startswith(MAGIC)


def _unescape(text: str) -> str:
    """LabVIEW's comment escapes: ``\\\\`` → ``\\``, ``\\09`` → tab, ``\\0D\\0A`` → CR LF."""
    return _ESCAPE.sub(lambda m: "\\" if m.group(1) == "\\" else chr(int(m.group(1), 16)), text)


class _Segment:
    """A segment: its header (tag → cells after the tag), column line and data rows."""

    def __init__(self, file_header: dict, header_line: int):
        self.file_header = file_header
        self.header: dict = {}
        self.header_line = header_line
        self.names: list | None = None
        self.names_line: int | None = None
        self.rows: list = []  # the data lines, as text
        self.first_row: int | None = None  # the line number of the first


def _separator(lines: list, p) -> str:
    """The separator the file header states (Tab when it states none)."""
    first = lines[0].lstrip("\ufeff")
    trail = first[len(MAGIC) : len(MAGIC) + 1]
    for n, line in enumerate(lines, start=1):
        if line.startswith(END):
            break
        if line.startswith("Separator") and len(line) > len("Separator"):
            char = line[len("Separator")]
            value = line[len("Separator") + 1 :].split(char)[0].strip()
            sep = _SEPARATORS.get(value.lower(), value if len(value) == 1 else None)
            if sep is None:
                raise InputError(
                    f"Separator {value!r} is not a separator LabVIEW writes (Tab, Comma)",
                    path=p,
                    line=n,
                )
            return sep
    return trail if trail in ("\t", ",", ";") else "\t"


def _parse(text: str, p):
    """The file's segments (see module notes); InputError with the line where it breaks."""
    lines = LINE_END.split(text)
    if lines and lines[-1] == "":
        lines.pop()
    if not lines or not is_lvm_text(lines[0]):
        raise InputError(
            f"not a LabVIEW Measurement file: the first line is not {MAGIC!r}", path=p, line=1
        )
    sep = _separator(lines, p)
    segments: list[_Segment] = []
    file_header: dict = {}
    state = "file"
    current = None
    blank = " \t" + sep
    starts = set("0123456789+-.,") | {sep}

    def is_row(line: str) -> bool:
        """A data line: not blank, first cell empty or a number (a header line starts with
        a tag, a special block with ***)."""
        if not line.strip(blank):
            return False
        if line[0] in starts:
            return True
        tag = line.split(sep, 1)[0].strip()
        return not tag or _is_number(tag.replace(",", "."))

    def take_rows(seg: _Segment, i: int) -> int:
        """Append the data lines from index ``i`` on to ``seg``; the index after them."""
        j = i
        while j < len(lines) and is_row(lines[j]):
            j += 1
        seg.rows.extend(lines[i:j])
        if seg.first_row is None:
            seg.first_row = i + 1
        return j

    i = 1
    while i < len(lines):
        line = lines[i]
        n = i + 1
        i += 1
        cells = line.split(sep)
        tag = cells[0].strip()
        if state == "special":
            if tag.startswith("***End_Special***"):
                state = "between"
            continue
        if state == "file":
            if tag == END:
                state = "between"
            elif tag:
                file_header[tag] = (cells[1].strip() if len(cells) > 1 else "", n)
            continue
        if state == "header":
            if tag == END:
                state = "columns"
            elif tag:
                current.header[tag] = (cells[1:], n)
            continue
        if not line.strip(blank):
            continue
        if state == "columns":
            if tag != "X_Value":
                raise InputError(
                    "the line after the segment header (its ***End_of_Header***) is not the "
                    "column line ('X_Value' and the channel names)",
                    path=p,
                    line=n,
                )
            current.names = [c.strip() for c in cells]
            current.names_line = n
            i, state = take_rows(current, i), "between"
            continue
        # between segments
        if is_lvm_text(line):  # a later session appended to the file: a new file header
            sep_here = _separator(lines[n - 1 :], p)
            if sep_here != sep:
                raise InputError(
                    "an appended file header states another separator than the first",
                    path=p,
                    line=n,
                )
            file_header, state = {}, "file"
        elif tag.startswith("***Start_Special***"):
            state = "special"
        elif tag == "X_Value":  # a column line without a segment header
            current = _Segment(file_header, n)
            current.names, current.names_line = [c.strip() for c in cells], n
            segments.append(current)
            i = take_rows(current, i)
        elif _is_number(tag.replace(",", ".")) or tag == "":
            if current is None or current.names is None:
                raise InputError(
                    "a data row before any column line ('X_Value' and the channel names)",
                    path=p,
                    line=n,
                )
            # rows after a blank line: a later write without its own header
            nxt = _Segment(current.file_header, current.header_line)
            nxt.header, nxt.names, nxt.names_line = current.header, current.names, n
            segments.append(nxt)
            current, i = nxt, take_rows(nxt, i - 1)
        else:
            current = _Segment(file_header, n)
            current.header[tag] = (cells[1:], n)
            segments.append(current)
            state = "header"
    if state in ("file", "header", "columns", "special"):
        what = {
            "file": "the file header never ends",
            "header": "a segment header never ends",
            "columns": "the file ends before the column line",
            "special": "a ***Start_Special*** block never ends",
        }[state]
        raise InputError(
            f"truncated: {what} (no {END if state != 'special' else '***End_Special***'}); "
            "copy the file again from the acquisition PC",
            path=p,
            line=len(lines),
        )
    if not segments:
        raise InputError("no data: the file holds a header but no segment", path=p)
    return sep, segments


def _setting(header: dict, tag: str, default: str) -> str:
    value = header.get(tag)
    return default if value is None or not value[0] else value[0]


def _cell(header: dict, tag: str, k: int):
    """The segment header's cell for data column ``k`` (``None`` when absent or empty)."""
    entry = header.get(tag)
    if entry is None:
        return None
    cells, _ = entry
    if k - 1 < len(cells) and cells[k - 1].strip():
        return cells[k - 1].strip()
    return None


def _numbers(texts: list, dec: str) -> np.ndarray:
    """Floats of the cells, strictly (``1_0`` or ``0x10`` are not numbers); a ValueError
    names the first cell that is not."""
    if dec == ",":
        texts = [c.replace(",", ".") for c in texts]
    try:
        values = np.array(texts, dtype=float)
    except ValueError:
        values = None
    if values is None or any("_" in c for c in texts):
        for i, c in enumerate(texts):
            if not _is_number(c.strip()):
                raise ValueError(i)
    return values


def _split(seg: _Segment, sep: str, n: int, numeric=(), dec="."):
    """The rows as a DataFrame of ``n`` columns by pandas' C parser, columns ``numeric``
    as floats (decimal mark ``dec``), the others as text (missing cells ``""``); None when
    the parser refuses them or a row has more cells than the column line names."""
    extra = 4  # trailing separators: empty cells past the column line are let pass
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", pd.errors.ParserWarning)
            frame = pd.read_csv(
                io.StringIO("\n".join(seg.rows)),
                sep=sep,
                header=None,
                names=range(n + extra),
                index_col=False,
                dtype={k: (float if k in numeric else str) for k in range(n + extra)},
                decimal=dec,
                keep_default_na=False,
                na_values={k: [""] for k in numeric},
                quoting=csv.QUOTE_NONE,
                engine="c",
                skip_blank_lines=False,
                **exact_floats(),
            )
    except (ValueError, pd.errors.ParserError, pd.errors.ParserWarning):
        return None
    if len(frame) != len(seg.rows) or (frame.iloc[:, n:] != "").to_numpy().any():
        return None
    return frame.iloc[:, :n]


def _cells(seg: _Segment, sep: str, n: int, p) -> pd.DataFrame:
    """The rows as ``n`` columns of text (missing cells ``""``); a row with more non-empty
    cells than the column line names is refused with its line."""
    frame = _split(seg, sep, n)
    if frame is not None:
        return frame
    for i, line in enumerate(seg.rows):  # the error path: find the row
        cells = line.split(sep)
        if len(cells) > n and any(c.strip() for c in cells[n:]):
            raise InputError(
                f"{len(cells)} cells but the column line (line {seg.names_line}) names {n}; "
                "the file is damaged",
                path=p,
                line=seg.first_row + i,
            )
    raise InputError(  # pragma: no cover - pandas split what str.split would not
        "cannot split the rows into cells; check the separator", path=p, line=seg.first_row
    )


def read_lvm(
    path,
    *,
    time_unit=None,
    force_unit=None,
    axes=None,
    sensitivity=None,
    decouple=None,
    segment=None,
    encoding=None,
    **scene_fields,
):
    """Read a LabVIEW Measurement file (``.lvm``) into a record.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    time_unit : str, optional
        The X values' unit when they are not LabVIEW's seconds.
    force_unit : str, optional
        Unit of channels without a ``Y_Unit_Label`` (a force unit, or ``"V"`` with a
        sensitivity); a label in the file wins and a contradicting argument is an error.
    axes : dict, optional
        Record channel → channel name, sign by a leading ``-`` (as for the sensor CSV):
        ``{"Fn": "Dev1/ai0", "Ft": "-Dev1/ai1"}``.
    sensitivity : dict, optional
        ``{"Fn": (0.225, "mV/N")}`` for channels recorded in volts
        (:mod:`pipeline.io.sensitivity`).
    decouple : array_like or path, optional
        The sensor's 3×3 decoupling matrix (:func:`pipeline.io.read_decoupling`).
    segment : int, optional
        Which segment (0-based) of a file that holds several.
    encoding : str, optional
        The text encoding, when neither UTF-8 nor Windows-1252 (e.g. ``"cp1250"``).
    **scene_fields : float
        Scene fields stored in the attributes (names as :class:`pipeline.Scene`).

    Returns
    -------
    xarray.Dataset
        The record (``format="lvm"``, ``kind="sensor"``), SI units; attributes as every
        reader's, and ``lvm_x_columns``, ``lvm_segment`` (of ``lvm_segments``), ``lvm_x0``
        (an absolute X0 left out of the time, see the module notes), the file
        and segment header's other tags as ``meta_<tag>``, the comments as
        ``meta_comment``, ``sensitivity`` where one was applied.

    Raises
    ------
    InputError
        Not an LVM file, a header that never ends, a row with more cells than the column
        line names, a cell that is not a number, a missing/NaN/infinite value, time not
        strictly increasing, channels read at different instants, a unit that is not a
        force (or volts without a sensitivity), no normal-force channel, several segments
        and no ``segment=``.
    """
    scene = scene_attrs(scene_fields)
    matrix = None if decouple is None else read_decoupling(decouple)
    p, raw, sha = read_raw(path)
    text, used_encoding = _decode(raw, p, encoding)
    sep, segments = _parse(text, p)
    if segment is None:
        if len(segments) > 1:
            listing = "; ".join(
                f"{i}: line {s.names_line}, {', '.join(_channel_names(s)) or 'no channels'}"
                for i, s in enumerate(segments)
            )
            raise InputError(
                f"the file holds {len(segments)} segments ({listing}); read one with "
                "pipeline.io.read_lvm(path, segment=k)",
                path=p,
            )
        index = 0
    else:
        if isinstance(segment, bool) or not isinstance(segment, int):
            raise InputError(f"segment={segment!r} must be a whole number", path=p)
        if not 0 <= segment < len(segments):
            raise InputError(
                f"segment={segment} but the file holds {len(segments)} segment(s) "
                f"(0 to {len(segments) - 1})",
                path=p,
            )
        index = segment
    seg = segments[index]
    time, columns, meta = _segment_columns(seg, sep, p, None if time_unit is not None else "s")
    attrs = meta  # the time column, read with the record, may add lvm_x0 to it
    attrs.update(
        lvm_x_columns=_setting(seg.file_header, "X_Columns", "One"),
        lvm_segment=float(index),
        lvm_segments=float(len(segments)),
        **({"encoding": used_encoding} if used_encoding else {}),
    )
    return table_record(
        p,
        sha,
        "lvm",
        time=time,
        columns=columns,
        time_unit=time_unit,
        force_unit=force_unit,
        axes=axes,
        sensitivity=sensitivity,
        decouple=matrix,
        scene=scene,
        attrs=attrs,
        time_hint=(
            " (with 'one header only' LabVIEW appends a later write under the first header:"
            " a restart of the X values starts a new write here; cut the file there)"
        ),
    )


def _decode(raw: bytes, p, encoding) -> tuple[str, str | None]:
    """The text, and the encoding used when it was not UTF-8 (see module notes)."""
    if encoding is not None or raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        return decode(raw, p, encoding), encoding
    try:
        return decode(raw, p), None
    except InputError:
        if b"\x00" in raw:
            raise InputError(
                "holds NUL bytes: not a LabVIEW Measurement text file", path=p
            ) from None
        text = raw.decode("cp1252", errors="replace").removeprefix("\ufeff")
        return text, "cp1252"


def _channel_names(seg: _Segment) -> list:
    names = seg.names or []
    return [n for k, n in enumerate(names) if k > 0 and n not in ("X_Value", "Comment")]


def _segment_columns(seg: _Segment, sep: str, p, x_unit):
    """The time column (a function of the channels read), the channel columns and the
    metadata of a segment; ``x_unit`` the X values' unit (LabVIEW's seconds, or None when
    ``time_unit=`` gives it)."""
    fh, header, names = seg.file_header, seg.header, seg.names
    dec = _setting(fh, "Decimal_Separator", ".")
    if dec not in (".", ","):
        line = fh["Decimal_Separator"][1]
        raise InputError(f"Decimal_Separator {dec!r} is neither '.' nor ','", path=p, line=line)
    x_mode = _setting(fh, "X_Columns", "One").capitalize()
    if x_mode not in ("No", "One", "Multi"):
        raise InputError(
            f"X_Columns {x_mode!r} is not No, One or Multi",
            path=p,
            line=fh.get("X_Columns", ("", None))[1],
        )
    has_comment = len(names) > 1 and names[-1] == "Comment"
    width = len(names) - (1 if has_comment else 0)
    channels = [k for k in range(1, width) if names[k] != "X_Value"]
    if not channels:
        raise InputError("the column line names no channel", path=p, line=seg.names_line)
    if not seg.rows:
        raise InputError("header only: the segment has no data rows", path=p, line=seg.names_line)
    lines = seg.first_row + np.arange(len(seg.rows))
    # the usual file: every cell but the comments a number, read by the C parser at once;
    # else the text, whose error path names the line and column of the first bad cell
    fast = _split(seg, sep, len(names), numeric=range(width), dec=dec)
    table = fast if fast is not None else _cells(seg, sep, len(names), p)
    by_k: dict = {}
    comments = []
    if has_comment:
        notes = table[len(names) - 1].str.strip().to_numpy()
        for i in np.flatnonzero(notes != "")[: _MAX_COMMENTS + 1]:
            comments.append(f"line {lines[i]}: {_unescape(notes[i])}")
        extra = int(np.count_nonzero(notes != "")) - len(comments)

    def numbers(k: int, name: str) -> np.ndarray:
        """The column's numbers; a cell that is not one is refused with its line."""
        if fast is not None:
            return fast[k].to_numpy(dtype=float)
        texts = table[k].str.strip()
        if dec == ",":
            texts = texts.str.replace(",", ".", regex=False)
        values = pd.to_numeric(texts, errors="coerce").to_numpy(dtype=float)
        bad = np.isnan(values) & ~texts.str.fullmatch(r"[+-]?nan", case=False).to_numpy()
        if bad.any():
            i = int(np.argmax(bad))
            cell = table[k].iat[i].strip()
            what = "is empty" if not cell else f"{cell!r} is not a number"
            raise InputError(
                f"cell {what}; repair or delete this line (decimal "
                f"{'comma' if dec == ',' else 'point'}, as the header's Decimal_Separator)",
                path=p,
                line=int(lines[i]),
                column=name,
            )
        return values

    out = []
    for k in channels:
        base, unit = split_unit(names[k])
        label = _cell(header, "Y_Unit_Label", k)
        if unit is not None and not _is_unit(unit):
            base, unit = names[k], None  # "Excitation (Trigger)": a label, not a unit
        if unit is not None and label is not None and signal_factor(unit) != signal_factor(label):
            raise InputError(
                f"channel {names[k]!r} names the unit {unit!r} but its Y_Unit_Label says "
                f"{label!r}; correct one of them",
                path=p,
                line=header["Y_Unit_Label"][1],
            )
        where = header["Y_Unit_Label"][1] if label else seg.names_line
        col = Column(
            base, (lambda k=k, name=names[k]: numbers(k, name)), label or unit, lines, where
        )
        out.append(col)
        by_k[id(col)] = k
    meta = {}
    for tag, (value, _) in fh.items():
        if tag.lower() not in _FORMAT_TAGS and value:
            meta[meta_key(tag)] = _unescape(value)
    for tag, (cells, _) in header.items():
        values = [c.strip() for c in cells if c.strip()]
        if tag in _SEGMENT_TAGS and values:
            meta[meta_key(tag)] = _unescape(values[0])
    if comments:
        more = len(comments) - _MAX_COMMENTS + extra
        meta["meta_comment"] = "\n".join(comments[:_MAX_COMMENTS]) + (
            f"\n(and {more} more)" if more > 0 else ""
        )

    def time_of(read: list) -> Column:
        """The instants of the channels read: the X column, or X0 + k·Delta_X."""
        if x_mode == "One":
            return Column("X_Value", lambda: numbers(0, "X_Value"), x_unit, lines)
        ks = [by_k[id(c)] for c in read if id(c) in by_k]
        if x_mode == "Multi":
            for k in ks:
                if names[k - 1] != "X_Value":
                    raise InputError(
                        f"X_Columns is Multi but channel {names[k]!r} has no X_Value column "
                        "before it",
                        path=p,
                        line=seg.names_line,
                    )
            xs = {k: numbers(k - 1, f"X_Value of {names[k]}") for k in ks}
            first = xs[ks[0]]
            for k in ks[1:]:
                if xs[k].shape != first.shape or not np.array_equal(xs[k], first):
                    raise InputError(
                        f"channels {names[ks[0]]!r} and {names[k]!r} are sampled at different "
                        "instants (their X_Value columns differ); a record needs one time base",
                        path=p,
                        line=seg.names_line,
                    )
            return Column("X_Value", first, x_unit, lines)
        steps = {}
        for k in ks:
            x0, dx = _cell(header, "X0", k) or "0", _cell(header, "Delta_X", k)
            if dx is None:
                raise InputError(
                    f"X_Columns is No (no time column) and channel {names[k]!r} has no "
                    "Delta_X in the segment header: its instants are unknown",
                    path=p,
                    line=header.get("Delta_X", (None, seg.names_line))[1],
                )
            steps[k] = (x0, dx)
        if len(set(steps.values())) > 1:
            raise InputError(
                "the channels read have different X0 or Delta_X in the segment header; a "
                "record needs one time base",
                path=p,
                line=header["Delta_X"][1],
            )
        x0, dx = next(iter(steps.values()))
        try:
            start, step = _numbers([x0, dx], dec)
        except ValueError as exc:
            bad = (x0, dx)[exc.args[0]]
            raise InputError(
                f"X0/Delta_X cell {bad!r} is not a number", path=p, line=header["Delta_X"][1]
            ) from None
        if not (np.isfinite(start) and np.isfinite(step) and step > 0):
            raise InputError(
                f"Delta_X = {dx!r}, X0 = {x0!r}: the time step must be a positive number",
                path=p,
                line=header["Delta_X"][1],
            )
        with np.errstate(over="ignore", invalid="ignore"):  # refused as not finite
            t = step * np.arange(len(lines))
            span = max(abs(start), abs(start + t[-1]))
        if np.spacing(span) <= TIME_RESOLUTION * step:
            return Column("X0 + k·Delta_X", start + t, x_unit, None)
        # an absolute X0 (Time_Pref Absolute: seconds since 1904) would round every
        # instant to a share of the step: time counts from the segment's first sample
        meta["lvm_x0"] = x0
        return Column("k·Delta_X (from X0)", t, x_unit, None)

    _check_dimension(header, [by_k[id(c)] for c in out], p)
    return time_of, out, meta


def _check_dimension(header: dict, ks: list, p) -> None:
    """``X_Dimension`` must be Time where it is stated."""
    for k in ks:
        dim = _cell(header, "X_Dimension", k)
        if dim is not None and dim.lower() != "time":
            raise InputError(
                f"X_Dimension is {dim!r}, not Time: this segment is not a time record",
                path=p,
                line=header["X_Dimension"][1],
            )


def _is_unit(unit: str) -> bool:
    return signal_factor(unit) is not None or time_factor(unit) is not None
