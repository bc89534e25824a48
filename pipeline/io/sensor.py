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
- separator ``,``, ``;`` or tab (sniffed from the header); decimal point, or decimal comma
  when the separator is not a comma; UTF-8 with or without BOM (UTF-16 with BOM too);
  CRLF or LF line ends.

Columns: a time column (``time`` or ``t``); force columns ``Fn``/``Ft`` (taken as they are)
or tri-axial ``Fx``, ``Fy``, ``Fz``, mapped by default as in the seed's sensor (Oz normal,
Ox tangential, Oy out of plane)::

    Fn ← Fz,  Ft ← Fx,  Fy ← Fy

``axes=`` overrides this map and the signs: a dict from record channel to file column,
a leading ``-`` flipping the sign, ``None`` dropping the channel, e.g.
``axes={"Ft": "-Fx"}`` (Ft opposes the file's +x) or ``axes={"Fn": "Fx", "Ft": "Fz"}``
(a sensor mounted on its side). Channels not named in ``axes`` keep their default source
unless that column is already taken by an entry of ``axes``. Other columns (a trigger
voltage, a moment) are not read; their names are listed in the attribute
``ignored_columns``.

The table body is parsed by pandas' C parser (no Python loop over rows); only when that
parse shows a problem does a slower pass locate the exact line and column for the message.
"""

from __future__ import annotations

import io
import os
import re
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import InputError
from ..record import FORCE_CHANNELS, make_record
from ._common import (
    atomic_write_text,
    base_attrs,
    check_plane,
    decode,
    meta_key,
    read_raw,
    scene_attrs,
)
from .units import resolve_unit, split_unit

__all__ = ["read_sensor", "write_sensor", "DEFAULT_AXES"]

#: Default map from record channel to tri-axial file column (seed's sensor: Oz normal).
DEFAULT_AXES = {"Fn": "Fz", "Ft": "Fx", "Fy": "Fy"}

#: File column written for each record channel by :func:`write_sensor`.
_WRITE_COLUMNS = (("Ft", "Fx"), ("Fy", "Fy"), ("Fn", "Fz"))


# ------------------------------------------------------------------------------ writer
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
        are written (``sha256`` excepted: it described the original file; ``meta_<key>``
        attributes are written under ``<key>``); ``metadata`` adds to or overrides them.

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
                f"cannot write {name}: it is not finite at t = {time[i]!r} s (sample {i}); "
                "a sensor CSV needs every channel at every instant",
                path=path,
            )
        columns[f"{column} [N]"] = values
    if "Fn [N]" not in columns and "Fz [N]" not in columns:
        raise InputError("record has no normal-force channel 'Fn' to write", path=path)
    frame = pd.DataFrame(columns)
    body = frame.to_csv(index=False, lineterminator="\n", float_format=None)
    return atomic_write_text(path, "".join(lines) + body)


# ------------------------------------------------------------------------------ reader
def read_sensor(path, *, time_unit=None, force_unit=None, axes=None, encoding=None, **scene_fields):
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
    p, raw, sha = read_raw(path)
    text = decode(raw, p, encoding)
    return _parse_sensor_text(
        text, p, sha, time_unit=time_unit, force_unit=force_unit, axes=axes, scene=scene
    )


def _parse_sensor_text(text, p, sha, **kw):  # replaced by the full parser in the next commit
    raise NotImplementedError("read_sensor is being written")
