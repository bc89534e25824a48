"""Named columns of numbers → a record: what the LabVIEW and MATLAB readers share.

A reader hands over the time column and the other columns, each with the unit the file
states (or None) and, for a text file, the line of each sample. :func:`table_record`
then does what every reader does, the same way: force columns recognised by name (``Fn``,
``Ft``, ``Fx``, ``Fy``, ``Fz``, any case, ``F_z``), the axis map (``axes=``), units
(``time_unit=``/``force_unit=`` where the file has none), volts through their sensitivity
(:mod:`pipeline.io.sensitivity`), the decoupling matrix, finite values, strictly
increasing time, the out-of-plane check, and the record with its attributes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..record import make_record
from ._common import (
    DECOUPLE_AXES,
    FORCE_COLUMNS,
    base_attrs,
    canonical_column,
    check_plane,
    decouple_columns,
    first_non_increase,
    resolve_axes,
    to_newtons,
)
from .sensitivity import by_column, parse_sensitivity, sensitivity_attr
from .units import resolve_force, resolve_unit

__all__ = ["Column", "table_record"]


@dataclass(frozen=True, eq=False)
class Column:
    """One column of a file.

    Attributes
    ----------
    name : str — as the file names it (messages, attributes)
    values : numpy.ndarray or callable — the numbers as read, in the file's unit, or a
        function that reads them (called only for a column the record reads: a text
        column no channel takes is never parsed)
    unit : str or None — the unit the file states
    lines : numpy.ndarray or None — the file line of each sample (text files)
    unit_line : int or None — the file line that states the unit (text files)
    """

    name: str
    values: object
    unit: str | None = None
    lines: np.ndarray | None = None
    unit_line: int | None = None

    def array(self) -> np.ndarray:
        """The values as floats (read now if they were deferred)."""
        values = self.values() if callable(self.values) else self.values
        return np.asarray(values, dtype=float)

    def where(self, i: int) -> tuple[str, dict]:
        """(" at sample i" or "", {line, column}) for a message about sample ``i``."""
        if self.lines is not None:
            return "", {"line": int(self.lines[i]), "column": self.name}
        return f" at sample {i}", {"column": self.name}


def _classify(columns: list[Column], p):
    """``{key: Column}`` of force columns (key: canonical name) and of the others (key:
    their name); two columns for one force are an error."""
    forces, others = {}, {}
    for col in columns:
        canon = canonical_column(col.name)
        if canon in FORCE_COLUMNS:
            if canon in forces:
                raise InputError(
                    f"columns {forces[canon].name!r} and {col.name!r} both read as {canon}; "
                    "rename one of them or name the one to read with axes=",
                    path=p,
                )
            forces[canon] = col
        elif col.name not in others and canon != "time":
            others[col.name] = col
    return forces, others


def table_record(
    p,
    sha: str,
    fmt: str,
    *,
    time: Column,
    columns: list[Column],
    time_unit=None,
    force_unit=None,
    axes=None,
    sensitivity=None,
    decouple=None,
    scene=None,
    attrs=None,
    time_hint: str = "",
):
    """The record of a file's columns (see the module notes).

    Parameters
    ----------
    p : pathlib.Path — the file (messages, ``source``)
    sha : str — SHA-256 of its bytes
    fmt : str — the record's ``format`` attribute
    time : Column or callable — the time column (its unit, or ``time_unit=``), or a
        function of the columns the record reads that returns it (a file whose channels
        each carry their own instants)
    columns : list of Column — every other column
    time_unit, force_unit, axes, sensitivity : as :func:`pipeline.io.load`
    decouple : (matrix, attrs) or None — from :func:`pipeline.io.read_decoupling`
    scene : dict — validated scene fields
    attrs : dict — further attributes (the file's metadata)
    time_hint : str — appended to the message when time does not increase

    Returns
    -------
    xarray.Dataset
        The record (``kind="sensor"``), SI units.
    """
    sens = parse_sensitivity(sensitivity, path=p)
    forces, others = _classify(columns, p)
    chosen = resolve_axes(forces, axes, p, others=others)
    known = {**others, **forces}
    matrix, decouple_attrs = decouple if decouple is not None else (None, {})
    needed = [key for key, _ in chosen.values()]
    if matrix is not None:
        missing = [c for c in DECOUPLE_AXES if c not in forces]
        if missing:
            raise InputError(
                f"decouple= needs the raw Fx, Fy and Fz columns; the file has no "
                f"{', '.join(missing)}",
                path=p,
            )
        needed += [c for c in DECOUPLE_AXES if c not in needed]
    col_sens = by_column(sens, chosen, list(known), p, read=needed, label=lambda k: known[k].name)
    feeds = {key: name for name, (key, _) in chosen.items()}

    if callable(time):
        time = time([known[key] for key in needed])
    t_factor, t_unit = resolve_unit("time", time.unit, time_unit, path=p, column=time.name)
    t_raw = time.array()
    n = t_raw.size
    values = {key: known[key].array() for key in needed}
    for key in needed:
        if values[key].size != n:
            raise InputError(
                f"column {known[key].name!r} has {values[key].size} samples but the time "
                f"column {time.name!r} has {n}; they must be sampled together",
                path=p,
            )
    if n == 0:
        raise InputError("no samples: the record has no data rows", path=p)
    if n == 1:
        raise InputError("a single sample: a record needs at least two time samples", path=p)
    _finite(time, t_raw, "time", p)
    with np.errstate(over="ignore", invalid="ignore"):  # out of range: refused below
        t = t_raw * t_factor
    if (step := first_non_increase(t)) is not None:
        i, verb = step
        at, where = time.where(i + 1)
        raise InputError(
            f"time {verb}{at} ({float(t_raw[i])!r} then {float(t_raw[i + 1])!r} {t_unit}); "
            f"time must strictly increase{time_hint}",
            path=p,
            **where,
        )

    si, units = {}, {}
    for key in needed:
        col = known[key]
        factor, unit = resolve_force(
            col.unit,
            force_unit,
            col_sens.get(key),
            path=p,
            column=col.name,
            line=col.unit_line,
            channel=feeds.get(key),
        )
        _finite(col, values[key], "force", p)
        si[key], units[key] = to_newtons(values[key], factor, p, col.name), unit
    if matrix is not None:  # cross-talk: corrected = M @ raw (Fx, Fy, Fz), in N
        si = decouple_columns(si, matrix, p)
    forces_si = {name: si[key] * sign for name, (key, sign) in chosen.items()}
    check_plane(forces_si, p)

    out = base_attrs(p, sha, fmt, "sensor")
    out["source_time_unit"] = t_unit
    out["source_force_unit"] = ",".join(sorted({units[key] for key, _ in chosen.values()}))
    out["axes"] = ",".join(
        f"{name}={'-' if sign < 0 else ''}{known[key].name}" for name, (key, sign) in chosen.items()
    )
    if col_sens:
        out["sensitivity"] = sensitivity_attr(
            {feeds.get(key, known[key].name): s for key, s in col_sens.items()}
        )
    read = {id(known[k]) for k in needed}
    ignored = [c.name for c in columns if id(c) not in read]
    if ignored:
        out["ignored_columns"] = ",".join(ignored)
    out.update(decouple_attrs)
    out.update(attrs or {})
    out.update(scene or {})
    return make_record(t, forces_si, attrs=out)


def _finite(col: Column, values: np.ndarray, what: str, p) -> None:
    bad = ~np.isfinite(values)
    if bad.any():
        i = int(np.argmax(bad))
        at, where = col.where(i)
        raise InputError(
            f"{what} value {float(values[i])!r}{at} is missing, NaN or infinite; repair the "
            "file or cut the record",
            path=p,
            **where,
        )
