"""Lab sensor CSV: the tri-axial force transducer's export.

The dialect (what :func:`read_sensor` accepts and :func:`write_sensor` writes)::

    # operator: A. Lab
    # sample rate: 1 MHz
    time [s],Fx [N],Fy [N],Fz [N]
    0.0,0.01,-0.002,0.3
    ...

- optional metadata lines ``# key: value`` (or ``# key = value``) before the table; they
  become record attributes ``meta_<key>`` (key lower-cased, non-alphanumerics → ``_``);
  ``#`` lines without a key are joined into ``meta_comment``;
- one header row; each column name carries its unit in ``[...]`` or ``(...)``: ``time [s]``,
  ``t (ms)``, ``t [us]``/``[µs]``/``[μs]``, ``Fz (kN)`` (see :mod:`pipeline.io.units`);
- separator ``,``, ``;`` or tab (sniffed from the header, or named by Excel's ``sep=;``
  first line); decimal point, or decimal comma when the separator is not a comma; UTF-8
  with or without BOM (UTF-16 with BOM too); CRLF, LF or bare-CR line ends.

Columns: a time column (``time`` or ``t``); force columns ``Fn``/``Ft`` (taken as they are)
or tri-axial ``Fx``, ``Fy``, ``Fz``, mapped by default as in the seed's sensor (Oz normal,
Ox tangential, Oy out of plane)::

    Fn ← Fz,  Ft ← Fx,  Fy ← Fy

``axes=`` overrides this map and the signs: a dict from record channel to file column,
a leading ``-`` flipping the sign, ``None`` dropping the channel, e.g.
``axes={"Ft": "-Fx"}`` (Ft opposes the file's +x) or ``axes={"Fn": "Fx", "Ft": "Fz"}``
(a sensor mounted on its side). Channels not named in ``axes`` keep their default source
unless that column is already taken by an entry of ``axes``. ``axes`` may also name a
column the default map does not know, by its name without the unit
(``axes={"Fn": "Force Z", "Ft": "-Force X"}`` for a header ``Force Z (kN);Force X (kN)``).
Columns not read (a trigger voltage, a moment, an unmapped axis) are listed in the
attribute ``ignored_columns``.

The table body is parsed by pandas' C parser (no Python loop over rows); only when that
parse shows a problem does a slower pass locate the exact line and column for the message.
"""

from __future__ import annotations

import collections
import contextlib
import csv
import io
import itertools
import json
import re
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import InputError
from ..record import make_record
from ._common import (
    DECOUPLE_AXES,
    DEFAULT_AXES,
    FORCE_COLUMNS,
    LINE_END,
    NONFINITE,
    NUMBER,
    BackgroundHash,
    atomic_write_text,
    base_attrs,
    canonical_column,
    check_plane,
    decode,
    decouple_columns,
    exact_floats,
    file_path,
    first_non_increase,
    meta_key,
    read_decoupling,
    read_raw,
    resolve_axes,
    scene_attrs,
)
from .metadata import check_sample_rate, stated_bandwidth
from .sensitivity import by_column, parse_sensitivity, sensitivity_attr
from .units import resolve_force, resolve_unit, split_unit, time_factor

__all__ = ["read_sensor", "write_sensor", "DEFAULT_AXES"]


#: File column written for each record channel by :func:`write_sensor`.
_WRITE_COLUMNS = (("Ft", "Fx"), ("Fy", "Fy"), ("Fn", "Fz"))


# ------------------------------------------------------------------------------ writer
def _numbers(value) -> bool:
    """Is ``value`` a list, tuple or array of real numbers?"""
    if not isinstance(value, list | tuple | np.ndarray) or np.size(value) == 0:
        return False
    a = np.asarray(value)
    return a.dtype.kind in "iuf"


def write_sensor(record, path, *, metadata: dict | None = None) -> Path:
    """Write a record as a lab sensor CSV (the dialect :func:`read_sensor` reads).

    Parameters
    ----------
    record : xarray.Dataset
        A record (see :mod:`pipeline.record`); every force must be finite at every
        instant (a digitised record whose channels span different times cannot be written).
    path : str or os.PathLike
        Output file; written atomically (temporary file in the same folder, then
        :func:`os.replace`).
    metadata : dict, optional
        Extra ``# key: value`` lines. By default the record's string and number attributes
        are written, lists of numbers as JSON (``sha256`` excepted: it described the
        original file; ``meta_<key>`` attributes are written under ``<key>``), so that a
        record of :func:`pipeline.sensor_model.to_sensor` read back states the same sensor
        to the fits (:func:`pipeline.fit.sensor.sensor_spec`); ``metadata`` adds to or
        overrides them.

    Returns
    -------
    pathlib.Path
        The file written.

    Notes
    -----
    Header ``time [s],Fx [N],Fy [N],Fz [N]`` with Fn → Fz, Ft → Fx, Fy → Fy (zeros when the
    record has no Fy; the Fx column is left out when the record has no Ft). Comma separator,
    decimal point, LF line ends, UTF-8. Numbers are written with Python's shortest
    round-trip repr, so ``read_sensor(write_sensor(r, p))`` gives back r's values exactly.
    """
    meta = {}
    for key, value in record.attrs.items():
        if key == "sha256" or isinstance(value, bool):
            continue
        if isinstance(value, str | int | float | np.integer | np.floating):
            meta[key.removeprefix("meta_")] = value
        elif _numbers(value):  # a list of numbers (per axis, a matrix): as JSON
            meta[key.removeprefix("meta_")] = json.dumps([float(x) for x in np.ravel(value)])
    meta.update(metadata or {})
    lines = []
    for key, value in meta.items():
        key = str(key)
        if not key.strip() or any(c in key for c in ":=\r\n") or key.lstrip().startswith("#"):
            raise InputError(
                f"metadata key {key!r} must be non-empty, one line, without ':' or '='"
            )
        text = str(value)
        if "\n" in text or "\r" in text:
            raise InputError(f"metadata value for {key!r} must fit on one line")
        lines.append(f"# {key.strip()}: {text}\n")

    if "Fn" not in record:
        raise InputError("record has no normal-force channel 'Fn' to write", path=path)
    time = np.asarray(record["time"].values, dtype=float)
    columns = {"time [s]": time}
    for name, column in _WRITE_COLUMNS:
        if name in record:
            values = np.asarray(record[name].values, dtype=float)
        elif name == "Fy" and "Ft" in record:
            values = np.zeros_like(time)
        else:
            continue
        bad = ~np.isfinite(values)
        if bad.any():
            i = int(np.argmax(bad))
            raise InputError(
                f"cannot write {name}: it is not finite at t = {float(time[i])!r} s (sample {i}); "
                "a sensor CSV needs every channel at every instant",
                path=path,
            )
        columns[f"{column} [N]"] = values
    frame = pd.DataFrame(columns)
    body = frame.to_csv(index=False, lineterminator="\n", float_format=None)
    return atomic_write_text(path, "".join(lines) + body)


# ------------------------------------------------------------------------------ reader
def read_sensor(
    path,
    *,
    time_unit=None,
    force_unit=None,
    axes=None,
    encoding=None,
    decouple=None,
    sensitivity=None,
    _crop=None,
    **scene_fields,
):
    """Read a lab sensor CSV into a record.

    Parameters
    ----------
    path : str or os.PathLike
        The CSV file.
    time_unit, force_unit : str, optional
        Units for columns whose header carries none (``"s"``, ``"ms"``, ``"us"``; ``"N"``,
        ``"kN"``...). A unit written in the header wins; an argument that contradicts it is
        an error.
    axes : dict, optional
        Record channel → file column, sign by a leading ``-`` (see module notes).
    encoding : str, optional
        Text encoding when the file is not UTF-8/UTF-16-with-BOM (e.g. ``"cp1252"``).
    decouple : array_like or path, optional
        The sensor's 3×3 decoupling matrix (or a file holding it, see
        :func:`pipeline.io.read_decoupling`), applied to the raw (Fx, Fy, Fz) in N before
        the axis map; its provenance goes in the attributes (``decouple_*``).
    sensitivity : dict, optional
        ``{"Fn": (0.225, "mV/N")}`` for columns recorded in volts (``Fz [V]``; see
        :mod:`pipeline.io.sensitivity`); recorded in ``attrs["sensitivity"]``.
    **scene_fields : float
        Scene fields stored in the record's attributes (names as :class:`pipeline.Scene`).

    Returns
    -------
    xarray.Dataset
        The record (``format="sensor_csv"``, ``kind="sensor"``), SI units.

    Raises
    ------
    InputError
        For any malformed file: see :func:`pipeline.io.load`.

    Warns
    -----
    PlaneImpactWarning
        When max|Fy| exceeds 5 % of max|Fn|.
    """
    scene = scene_attrs(scene_fields)
    matrix = None if decouple is None else read_decoupling(decouple)
    sens = parse_sensitivity(sensitivity)
    head = _stream_head(path) if encoding is None else None
    if head is not None:  # a large UTF-8 file: the parser reads it, not a copy in memory
        p, raw, sha = file_path(path), head, BackgroundHash(file_path(path))
    else:
        p, raw, sha = read_raw(path, background_hash=True)
    return parse_sensor_bytes(
        raw,
        p,
        sha,
        time_unit=time_unit,
        force_unit=force_unit,
        axes=axes,
        scene=scene,
        encoding=encoding,
        decouple=matrix,
        sensitivity=sens,
        head_only=head is not None,
        crop=_crop,
    )


#: Files larger than this are streamed from disk to the parser (their head read first);
#: smaller ones are read whole (one read, and the hash from memory).
STREAM_BYTES = 1 << 20
_HEAD_BYTES = 1 << 16


def _stream_head(path) -> bytes | None:
    """The first 64 KiB of a large file that may be streamed, or None to read it whole
    (small, UTF-16, or without a line feed in its head: bare-CR line ends are rewritten)."""
    p = file_path(path)
    try:
        if p.stat().st_size <= STREAM_BYTES:
            return None
        with open(p, "rb") as fh:
            head = fh.read(_HEAD_BYTES)
    except OSError:
        return None  # read_raw gives the message
    if head.startswith((b"\xff\xfe", b"\xfe\xff")) or b"\n" not in head:
        return None
    return head


# --------------------------------------------------------------------- the text parser
#: Excel's separator hint, a first line ``sep=;`` (or ``"sep=;"``).
_SEP_HINT = re.compile(r'^"?sep=([,;\t])"?\r?$')


def _split_head(text: str, p: Path):
    """Metadata, header line, its number, the body's start and the separator named by an
    Excel ``sep=`` first line (or None): a loop over the head lines only."""
    if not text or text.isspace():
        raise InputError("file is empty; export the record again", path=p)
    meta, comments, sep = {}, [], None
    pos, lineno = 0, 0
    while pos <= len(text):
        nl = text.find("\n", pos)
        end = len(text) if nl < 0 else nl
        line = text[pos:end].rstrip("\r")
        lineno += 1
        stripped = line.strip(_ASCII_SPACE)  # as the byte scan of _head_and_body
        nxt = len(text) + 1 if nl < 0 else nl + 1
        if lineno == 1 and (m := _SEP_HINT.match(line)):
            sep = m.group(1)
        elif stripped.startswith("#"):
            body = stripped.lstrip("#").strip()
            m = re.match(r"^([^:=]+?)\s*[:=]\s*(.*)$", body)
            if m:
                key, value = m.group(1), m.group(2).strip()
                name, unit = split_unit(key)  # "impact speed [m/s]: 0.6" → "0.6 m/s"
                if unit and name:
                    key, value = name, f"{value} {unit}"
                meta[meta_key(key)] = value
            elif body:
                comments.append(body)
        elif stripped:
            if comments:
                meta.setdefault("meta_comment", "\n".join(comments))
            return meta, line, lineno, min(nxt, len(text)), sep
        pos = nxt
    raise InputError(
        "no header row: the file holds only '#' metadata lines; a sensor CSV needs a header "
        "such as 'time [s],Fx [N],Fy [N],Fz [N]' followed by data rows",
        path=p,
    )


def _sniff_separator(header: str, p: Path, lineno: int) -> str:
    counts = {sep: header.count(sep) for sep in (";", "\t", ",")}
    sep = max(counts, key=lambda k: counts[k])
    if counts[sep] == 0:
        raise InputError(
            f"header {header.strip()!r} has a single column; a sensor CSV needs a time "
            "column and force columns separated by ',', ';' or tab",
            path=p,
            line=lineno,
        )
    return sep


def _sniff_decimal(sample: str, sep: str) -> str:
    if sep == ",":
        return "."
    return "," if "," in sample else "."


class _Skip:
    """The body of a file on disk: its first ``rows`` lines are the head."""

    def __init__(self, path: Path, rows: int):
        self.path, self.rows = path, rows

    def close(self):
        pass


class _LazyText:
    """A UTF-8 body kept as bytes; decoded only when an error message needs its lines.

    ``raw`` may hold only the file's head (a large file streamed to the parser): the rest
    is read from ``p`` when an error message needs it.
    """

    def __init__(self, raw: bytes, offset: int, p: Path, header_line: int, *, head_only=False):
        self._raw, self.offset, self.p, self.header_line = raw, offset, p, header_line
        self._head_only = head_only

    @property
    def raw(self) -> bytes:
        if self._head_only:
            self._raw, self._head_only = read_raw(self.p)[1], False
        return self._raw

    def __getitem__(self, item: slice):
        start = self.offset + (item.start or 0)
        stop = self.offset + item.stop
        raw = self._raw if self._head_only and stop <= len(self._raw) else self.raw
        return raw[start:stop].decode("utf-8", errors="replace")

    @property
    def data(self) -> bytes:
        return self.raw[self.offset :]

    def __str__(self):
        try:
            return self.data.decode("utf-8")
        except UnicodeDecodeError as exc:
            line = self.header_line + self.data[: exc.start].count(b"\n") + 1
            raise InputError(
                f"bytes at offset {exc.start} of the table are not valid UTF-8; re-save "
                "the file as UTF-8, or for a legacy Windows export call "
                "pipeline.io.read_sensor(path, encoding='cp1252')",
                path=self.p,
                line=line,
            ) from exc


#: What pandas' C parser skips around a number (C ``isspace``); not Unicode spaces.
_ASCII_SPACE = " \t\n\v\f\r"


def _data_lines(body: str, first_line: int, sep: str):
    """(line number, cells) of every row pandas reads from the body (error path only);
    cells ``None`` for a row whose quote is never closed (it runs to the end).

    As in pandas' C parser, a line is blank when it holds only spaces and tabs other than
    the separator, a quote opens a quoted cell only at the start of a cell, and a quoted
    cell may span lines (the row's number is that of its first line).
    """
    blank = " \t".replace(sep, "")
    lines = LINE_END.split(body)
    reader = csv.reader(lines, delimiter=sep)
    while True:
        k = reader.line_num  # lines consumed so far: the row starts at lines[k]
        try:
            cells = next(reader, None)
        except csv.Error:  # a quoted cell past csv's field size limit: a quote never closed
            yield first_line + k, None
            return
        if cells is None:
            return
        if reader.line_num - k > 1 or lines[k].strip(blank):
            yield first_line + k, cells


def _row(body, first_line: int, sep: str, row: int) -> tuple[int | None, list | None]:
    """(line number, cells) of data row ``row`` (0-based, as pandas counts rows);
    ``(None, None)`` if the lines run out first (a quoted cell spanning lines)."""
    lines = _data_lines(str(body), first_line, sep)
    return next(itertools.islice(lines, row, None), (None, None))


def _fields(cells: list, n: int) -> int:
    """Number of fields, not counting one empty cell after a trailing separator."""
    return n if len(cells) == n + 1 and not cells[-1] else len(cells)


def _fields_error(cells: list, n: int, p: Path, lineno: int) -> InputError:
    hint = "check for a stray or missing separator"
    if cells and cells[0].lstrip().startswith("#"):
        hint = "'#' lines are read only before the header: delete this one"
    return InputError(
        f"has {len(cells)} fields but the header has {n}; {hint}", path=p, line=lineno
    )


def _unclosed_quote(p: Path, lineno: int) -> InputError:
    return InputError(
        "a quoted cell opened on this line is never closed; delete the stray '\"'",
        path=p,
        line=lineno,
    )


def _is_number(cell: str, dec: str) -> bool:
    """Whether pandas reads ``cell`` (quotes removed) as a float or as NaN/inf."""
    if cell == "" or NONFINITE.match(cell):
        return True
    c = cell.strip(_ASCII_SPACE)
    if dec == ",":
        if "." in c:
            return False
        c = c.replace(",", ".")
    return bool(NUMBER.match(c))


def _diagnose(body, first_line, sep, dec, names, p, original):
    """Find the first malformed body line and raise an InputError that names it."""
    n = len(names)
    if "EOF inside string" in str(original):  # a quote never closed: the last row runs on
        ((lineno, _),) = collections.deque(_data_lines(body, first_line, sep), maxlen=1)
        raise _unclosed_quote(p, lineno) from original
    for lineno, cells in _data_lines(body, first_line, sep):
        if cells is None:
            raise _unclosed_quote(p, lineno) from original
        if _fields(cells, n) != n:
            raise _fields_error(cells, n, p, lineno) from original
        for name, cell in zip(names, cells, strict=False):
            if name is not None and not _is_number(cell, dec):
                raise InputError(
                    f"cell {cell.strip(_ASCII_SPACE) or cell!r} is not a number; fix or "
                    "delete this line "
                    f"(decimal {'comma' if dec == ',' else 'point'} expected"
                    f"{', no thousands separators' if '.' in cell and ',' in cell else ''})",
                    path=p,
                    line=lineno,
                    column=name,
                ) from original
    for lineno, cells in _data_lines(body, first_line, sep):  # a lone trailing separator
        if cells is not None and len(cells) != n:
            raise _fields_error(cells, n, p, lineno) from original
    raise InputError(
        f"cannot parse the table ({original}); check the separator and decimal mark",
        path=p,
    ) from original


def _head_and_body(raw: bytes, p: Path, encoding):
    """Split a file into its decoded head (metadata + header) and its body.

    UTF-8 files (the usual case) keep the body as bytes, handed to pandas' C parser without a
    decode-and-copy; other encodings are decoded in full and the body passed as text.
    Returns ``(raw, head, body offset in raw or None, full text or None)``; bare-CR line
    ends (classic Mac OS) are turned into LF first, so ``raw`` may be a new bytes object.
    """
    if encoding is not None or raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        text = decode(raw, p, encoding)
        if "\n" not in text:
            text = text.replace("\r", "\n")
        return raw, text, None, text
    if b"\n" not in raw:  # (a CR byte is never part of a multi-byte UTF-8 character)
        raw = raw.replace(b"\r", b"\n")
    start = 3 if raw.startswith(b"\xef\xbb\xbf") else 0
    pos = start
    while pos < len(raw):
        nl = raw.find(b"\n", pos)
        end = len(raw) if nl < 0 else nl + 1
        stripped = raw[pos:end].strip()
        first, pos = pos == start, end
        if first and _SEP_HINT.match(raw[start:end].rstrip(b"\n").decode("latin-1")):
            continue
        if stripped and not stripped.startswith(b"#"):
            break
    head = decode(raw[start:pos], p)
    return raw, head, pos, None


def _classify(raw_names: list, header: str, p: Path, header_line: int):
    """The header's time column ``(j, name, unit)``, its force columns ``{"Fz": (j, name,
    unit), ...}`` and its other columns ``{base name: (j, name, unit)}``."""
    time_cols, force_cols, other_cols = [], {}, {}
    for j, h in enumerate(raw_names):
        base, unit = split_unit(h)
        canon = canonical_column(base)
        if canon == "time":
            time_cols.append((j, h, unit))
        elif canon in FORCE_COLUMNS:
            if canon in force_cols:
                raise InputError(f"two {canon} columns", path=p, line=header_line, column=h)
            force_cols[canon] = (j, h, unit)
        elif h and base not in other_cols:
            other_cols[base] = (j, h, unit)
    if len(time_cols) > 1:
        # "time [s]" beside "T [°C]": a time-named column in a non-time unit is not time
        timed = [c for c in time_cols if c[2] is None or time_factor(c[2]) is not None]
        if len(timed) == 1:
            for c in time_cols:
                if c is not timed[0]:
                    other_cols.setdefault(split_unit(c[1])[0], c)
            time_cols = timed
    if len(time_cols) > 1:
        raise InputError(
            f"two time columns ({', '.join(repr(c[1]) for c in time_cols)}); keep one",
            path=p,
            line=header_line,
        )
    if not time_cols:
        raise InputError(
            f"no time column in the header {header.strip()!r}; name it 'time [s]' (or 't' "
            "with its unit)",
            path=p,
            line=header_line,
        )
    return time_cols[0], force_cols, other_cols


def parse_sensor_bytes(
    raw,
    p,
    sha,
    *,
    time_unit=None,
    force_unit=None,
    axes=None,
    scene=None,
    encoding=None,
    fmt="sensor_csv",
    decouple=None,
    sensitivity=None,
    head_only=False,
    crop=None,
):
    """Parse the bytes of a sensor CSV (``p`` and ``sha`` for messages and attributes;
    ``decouple`` the ``(matrix, attrs)`` of :func:`~pipeline.io._common.read_decoupling`;
    ``head_only``: ``raw`` is the file's head and the body is streamed from ``p``; ``crop``
    a :class:`pipeline.io.stream.Cropper` that keeps only the contact of a streamed body)."""
    raw, head, body_offset, full_text = _head_and_body(raw, p, encoding)
    if head_only and body_offset + 4096 > len(raw):  # the head does not hold the header
        return parse_sensor_bytes(
            read_raw(p)[1], p, sha, time_unit=time_unit, force_unit=force_unit, axes=axes,
            scene=scene, encoding=encoding, fmt=fmt, decouple=decouple,
            sensitivity=sensitivity, crop=crop,
        )  # fmt: skip
    meta, header, header_line, body_start, sep = _split_head(head, p)
    if full_text is not None:
        body = full_text[body_start:]
        body_source = io.StringIO(body)
    elif head_only:
        # pandas reads the file itself, skipping the head's lines (faster than through a
        # Python file object) — where a line of the head is a line to its tokenizer: no
        # quote that could join lines, no blank line it would not count
        lines = head.splitlines()
        plain = '"' not in head and all(ln.strip() for ln in lines) and len(lines) == header_line
        body_source = _Skip(p, header_line) if plain else open(p, "rb")  # noqa: SIM115
        body = _LazyText(raw, body_offset, p, header_line, head_only=True)
    else:
        # BytesIO over the bytes object shares its buffer: no copy of a large file.
        body_source = io.BytesIO(raw)
        body_source.seek(body_offset)
        body = _LazyText(raw, body_offset, p, header_line)
    try:
        return _parse_table(
            body, body_source, body_offset, full_text, meta, header, header_line, sep, p,
            sha, time_unit=time_unit, force_unit=force_unit, axes=axes, scene=scene,
            fmt=fmt, decouple=decouple, sensitivity=sensitivity, crop=crop,
        )  # fmt: skip
    finally:
        body_source.close()


def _parse_table(
    body, body_source, body_offset, full_text, meta, header, header_line, sep, p, sha, *,
    time_unit, force_unit, axes, scene, fmt, decouple, sensitivity=None, crop=None,
):  # fmt: skip
    """The table after the head: columns, units, the parse, the checks, the record."""
    sep = sep or _sniff_separator(header, p, header_line)
    dec = _sniff_decimal(body[:4096], sep)
    raw_names = [h.strip().strip('"').strip() for h in header.split(sep)]
    time_col, force_cols, other_cols = _classify(raw_names, header, p, header_line)
    chosen = resolve_axes(force_cols, axes, p, others=other_cols, line=header_line)
    columns = {**other_cols, **force_cols}  # every column but time, by name
    t_factor, t_unit = resolve_unit(
        "time", time_col[2], time_unit, path=p, column=time_col[1], line=header_line
    )
    matrix, decouple_attrs = decouple if decouple is not None else (None, {})
    needed = [col for col, _ in chosen.values()]
    if matrix is not None:
        missing = [c for c in DECOUPLE_AXES if c not in force_cols]
        if missing:
            raise InputError(
                f"decouple= needs the raw Fx, Fy and Fz columns; the header has no "
                f"{', '.join(missing)}",
                path=p,
                line=header_line,
            )
        needed += [c for c in DECOUPLE_AXES if c not in needed]
    col_sens = by_column(
        parse_sensitivity(sensitivity, path=p), chosen, list(columns), p, read=needed,
        label=lambda c: columns[c][1],
    )  # fmt: skip
    feeds = {col: name for name, (col, _) in chosen.items()}
    f_factors = {}  # file column → (factor to N, unit)
    for col in needed:
        _, h, unit = columns[col]
        f_factors[col] = resolve_force(
            unit, force_unit, col_sens.get(col), path=p, column=h, line=header_line,
            channel=feeds.get(col),
        )  # fmt: skip
    f_units = {f_factors[col][1] for col, _ in chosen.values()}

    # The body: pandas' C parser, no Python loop over rows.
    wanted = {time_col[0]: "time"}
    for col in needed:
        wanted[columns[col][0]] = col
    names = [wanted.get(j) for j in range(len(raw_names))]
    ignored = [h for j, h in enumerate(raw_names) if h and j not in wanted]
    shown = [h if names[j] else None for j, h in enumerate(raw_names)]  # for messages
    labels = [f"c{j}" for j in range(len(raw_names))]
    first_line = header_line + 1
    parse_errors = (
        ValueError,
        pd.errors.ParserError,
        pd.errors.EmptyDataError,
        pd.errors.ParserWarning,
    )

    def parse(decimal, chunksize=None):
        skip = {}
        if isinstance(body_source, _Skip):
            source, skip = str(body_source.path), {"skiprows": body_source.rows}
        else:
            source = body_source
            body_source.seek(0 if full_text is not None else body_offset)
        with warnings.catch_warnings():
            # pandas only warns when every row has more fields than the header and then
            # drops data: make that an error
            warnings.simplefilter("error", pd.errors.ParserWarning)
            return pd.read_csv(
                source,
                **skip,
                sep=sep,
                decimal=decimal,
                header=None,
                names=labels,
                index_col=False,
                # no usecols: with it pandas silently drops surplus fields on a line
                dtype={lab: (float if j in wanted else object) for j, lab in enumerate(labels)},
                engine="c",
                skip_blank_lines=True,
                chunksize=chunksize,
                **exact_floats(),
            )

    def to_forces(cols):
        """File columns (file units) → record channels [N]: units, decoupling, axes."""
        si = {}
        if matrix is not None:  # cross-talk: corrected = M @ raw (Fx, Fy, Fz), in N
            raw3 = {c: cols[c] * f_factors[c][0] for c in DECOUPLE_AXES}
            si = decouple_columns(raw3, matrix, p)
        forces = {}
        for name, (col, sign) in chosen.items():
            if col in si:
                forces[name] = si[col] * sign if sign != 1.0 else si[col]
                continue
            factor = f_factors[col][0] * sign
            values = cols[col]
            forces[name] = values * factor if factor != 1.0 else values
        return forces

    crop_attrs = {}
    if crop is not None:  # a large file: keep only the contact and its margins

        def chunks():
            with warnings.catch_warnings():
                warnings.simplefilter("error", pd.errors.ParserWarning)
                for frame in parse(dec, chunksize=crop.chunk_rows):
                    yield {wanted[j]: frame[labels[j]].to_numpy() for j in sorted(wanted)}

        try:
            cols, crop_attrs = crop.run(chunks(), t_factor, to_forces)
        except parse_errors as exc:
            raise crop.Damaged(str(exc)) from exc
        frame = None
    else:
        cols = None
    try:
        frame = parse(dec) if cols is None else None
    except parse_errors as exc:
        # The decimal mark is sniffed from the first 4 KiB: integers there ("0;0") hide a
        # decimal comma further down. The other mark is taken only if every cell reads.
        frame = None
        if sep != ",":
            with contextlib.suppress(*parse_errors):
                frame = parse("," if dec == "." else ".")
        if frame is None:
            _diagnose(str(body), first_line, sep, dec, shown, p, exc)
    n = len(frame) if cols is None else len(cols["time"])
    if n == 0:
        raise InputError("header only: the file has no data rows", path=p, line=header_line)
    if n == 1:
        raise InputError(
            "a single sample: a record needs at least two time samples",
            path=p,
            line=_row(body, first_line, sep, 0)[0],
        )
    if cols is None:
        cols = {wanted[j]: frame[labels[j]].to_numpy() for j in sorted(wanted)}
    # Too few fields on a line fill NaN silently: check every used column for non-finite.
    for key, values in cols.items():
        bad = ~np.isfinite(values)
        if bad.any():
            row = int(np.argmax(bad))
            line, cells = _row(body, first_line, sep, row)
            if cells is not None and _fields(cells, len(raw_names)) != len(raw_names):
                raise _fields_error(cells, len(raw_names), p, line)
            what = "time" if key == "time" else "force"
            raise InputError(
                f"{what} value {float(values[row])!r} is missing, NaN or infinite; repair or "
                "delete this line",
                path=p,
                line=line,
                column=shown[names.index(key)],
            )
    t = cols["time"] * t_factor if t_factor != 1.0 else cols["time"]
    if (step := first_non_increase(t)) is not None:
        i, verb = step
        line, _ = _row(body, first_line, sep, i + 1)
        raise InputError(
            f"time {verb} ({float(cols['time'][i])!r} then {float(cols['time'][i + 1])!r} "
            f"{t_unit}); time must strictly increase: remove duplicate rows or sort the file",
            path=p,
            line=line,
            column=time_col[1],
        )
    forces = to_forces(cols)
    check_plane(forces, p)
    check_sample_rate(meta, t, t_unit, p)
    if not isinstance(sha, str):
        sha = sha.hexdigest()
    attrs = base_attrs(p, sha, fmt, "sensor")
    attrs["source_time_unit"] = t_unit
    attrs["source_force_unit"] = ",".join(sorted(f_units))
    attrs["axes"] = ",".join(
        f"{name}={'-' if sign < 0 else ''}{col}" for name, (col, sign) in chosen.items()
    )
    if ignored:
        attrs["ignored_columns"] = ",".join(ignored)
    if col_sens:
        attrs["sensitivity"] = sensitivity_attr(
            {feeds.get(c, columns[c][1]): s for c, s in col_sens.items()}
        )
    attrs.update(decouple_attrs)
    attrs.update(crop_attrs)
    attrs.update(meta)
    bandwidth = stated_bandwidth(meta)
    if bandwidth is not None:
        attrs["sensor_bandwidth"] = bandwidth[0]
    attrs.update(scene or {})
    return make_record(t, forces, attrs=attrs)
