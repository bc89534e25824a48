"""Units of time, force and voltage found in file headers, and their SI factors.

A column name carries its unit in square brackets or parentheses: ``time [s]``,
``Fz (kN)``, ``t [us]``, ``t [µs]`` (micro sign U+00B5) or ``t [μs]`` (Greek mu U+03BC).
:func:`split_unit` separates name and unit; :func:`time_factor`, :func:`force_factor` and
:func:`volt_factor` give the factor that converts a value in that unit to seconds, newtons
or volts. A force channel recorded in volts (``Fz [V]``, LabVIEW's ``Volts``) becomes
newtons only through its stated sensitivity (:mod:`pipeline.io.sensitivity`):
:func:`resolve_force` asks for one and names the column when it is missing.
"""

from __future__ import annotations

import re

from ..errors import InputError

__all__ = [
    "TIME_UNITS",
    "FORCE_UNITS",
    "split_unit",
    "time_factor",
    "force_factor",
    "resolve_unit",
    "VOLT_UNITS",
    "volt_factor",
    "resolve_force",
    "signal_factor",
]

#: Time units → factor to seconds.
TIME_UNITS = {
    "s": 1.0,
    "sec": 1.0,
    "ms": 1e-3,
    "us": 1e-6,
    "\u00b5s": 1e-6,  # micro sign
    "\u03bcs": 1e-6,  # Greek small mu
    "ns": 1e-9,
}

#: Force units → factor to newtons.
FORCE_UNITS = {
    "N": 1.0,
    "mN": 1e-3,
    "kN": 1e3,
    "MN": 1e6,
    "daN": 10.0,
    "lbf": 4.4482216152605,  # international pound-force, exact by definition
}

#: Voltage units → factor to volts: a force channel in one of these needs its sensitivity.
VOLT_UNITS = {"V": 1.0, "mV": 1e-3, "uV": 1e-6, "\u00b5V": 1e-6, "\u03bcV": 1e-6}

# Case-insensitive aliases that are unambiguous ("mn" is not: mN or MN). LabVIEW writes
# unit labels as words ("Newtons", "Volts").
_TIME_LOWER = {k.lower(): v for k, v in TIME_UNITS.items()}
_FORCE_LOWER = {
    "n": 1.0,
    "kn": 1e3,
    "dan": 10.0,
    "lbf": FORCE_UNITS["lbf"],
    "newton": 1.0,
    "newtons": 1.0,
    "kilonewton": 1e3,
    "kilonewtons": 1e3,
}
_VOLT_LOWER = {
    "v": 1.0,
    "volt": 1.0,
    "volts": 1.0,
    "mv": 1e-3,  # no rig records megavolts
    "millivolt": 1e-3,
    "millivolts": 1e-3,
    "uv": 1e-6,
    "\u00b5v": 1e-6,
    "\u03bcv": 1e-6,
}

_UNIT_RE = re.compile(r"^\s*(?P<name>.*?)\s*[\[(]\s*(?P<unit>[^\])]*?)\s*[\])]\s*$")


def split_unit(header: str) -> tuple[str, str | None]:
    """Split ``"Fz (kN)"`` into ``("Fz", "kN")``; a name without a unit gives ``(name, None)``."""
    m = _UNIT_RE.match(header)
    if m is None:
        return header.strip(), None
    return m.group("name"), m.group("unit")


def _normalise(unit: str) -> str:
    return unit.strip().replace(" ", "")


def time_factor(unit: str) -> float | None:
    """Factor from ``unit`` to seconds, or ``None`` when ``unit`` is not a time unit."""
    u = _normalise(unit)
    if u in TIME_UNITS:
        return TIME_UNITS[u]
    return _TIME_LOWER.get(u.lower())


def force_factor(unit: str) -> float | None:
    """Factor from ``unit`` to newtons, or ``None`` when ``unit`` is not a force unit."""
    u = _normalise(unit)
    if u in FORCE_UNITS:
        return FORCE_UNITS[u]
    return _FORCE_LOWER.get(u.lower())


def volt_factor(unit: str) -> float | None:
    """Factor from ``unit`` to volts, or ``None`` when ``unit`` is not a voltage unit."""
    u = _normalise(unit)
    if u in VOLT_UNITS:
        return VOLT_UNITS[u]
    return _VOLT_LOWER.get(u.lower())


def signal_factor(unit) -> tuple[float, str] | None:
    """``(factor, "force")`` to newtons or ``(factor, "volt")`` to volts of a force channel's
    unit; None when ``unit`` is neither."""
    if not isinstance(unit, str):
        return None
    if (f := force_factor(unit)) is not None:
        return f, "force"
    if (v := volt_factor(unit)) is not None:
        return v, "volt"
    return None


def resolve_force(
    found: str | None,
    given: str | None,
    sensitivity=None,
    *,
    path,
    column=None,
    line=None,
    channel=None,
) -> tuple[float, str]:
    """The factor that takes a force column to newtons, and its unit as written.

    As :func:`resolve_unit` for forces, and a column in volts (``V``, ``mV``, ``Volts``)
    is converted through its ``sensitivity`` (a
    :class:`~pipeline.io.sensitivity.Sensitivity`): F [N] = U [V] · newtons_per_volt.

    Parameters
    ----------
    found : str or None — the unit written in the file
    given : str or None — ``force_unit=`` (a force or a voltage unit)
    sensitivity : Sensitivity or None — the column's stated sensitivity
    path, column, line — for messages
    channel : str, optional — the record channel the column feeds (``"Fn"``), for messages

    Raises
    ------
    InputError
        No unit anywhere, a unit that is neither a force nor a voltage, a clash between the
        file and ``force_unit=``, a column in volts without a sensitivity, or a sensitivity
        for a column already in a force unit.
    """
    known = f"{', '.join(FORCE_UNITS)} (or {', '.join(list(VOLT_UNITS)[:3])} with a sensitivity)"
    sig, unit = _pick(
        "force", found, given, signal_factor, known, path=path, column=column, line=line
    )
    factor, kind = sig
    who = f"{channel} (column {column!r})" if channel and column else repr(column or channel)
    if kind == "volt":
        if sensitivity is None:
            raise InputError(
                f"{who} is in volts ({unit!r}), not a force unit: give the channel's "
                f"sensitivity, e.g. sensitivity={{{(channel or 'Fn')!r}: (0.225, 'mV/N')}} "
                '(units mV/N, V/N, N/V or N/mV; the sidecar\'s "sensitivity" or the '
                "command line's --sensitivity)",
                path=path,
                line=line,
                column=column,
            )
        return factor * sensitivity.newtons_per_volt, unit
    if sensitivity is not None:
        raise InputError(
            f"{who} is already a force in {unit!r}: its sensitivity {sensitivity} applies "
            "only to a channel recorded in volts; drop it",
            path=path,
            line=line,
            column=column,
        )
    return factor, unit


def resolve_unit(
    kind: str, found: str | None, given: str | None, *, path, column=None, line=None, hint=""
) -> tuple[float, str]:
    """Pick the unit of a quantity from the file (``found``) or the argument (``given``).

    Parameters
    ----------
    kind : {"time", "force"}
    found : str or None
        Unit written in the file.
    given : str or None
        Unit passed by the user (``time_unit=`` / ``force_unit=``).
    path, column, line
        For error messages (``line``: the header's line, where the unit was looked for).
    hint : str
        Extra advice appended when no unit is known.

    Returns
    -------
    factor : float
        Multiplier to SI (s or N).
    unit : str
        The unit used, as written.

    Raises
    ------
    InputError
        No unit anywhere, a unit that is not a time/force unit, or a clash between the
        file's unit and the argument.
    """
    factor_of = time_factor if kind == "time" else force_factor
    known = ", ".join(TIME_UNITS if kind == "time" else FORCE_UNITS)
    return _pick(
        kind,
        found,
        given,
        factor_of,
        known,
        where=" in the column header",
        path=path,
        column=column,
        line=line,
        hint=hint,
    )


def _pick(kind, found, given, factor_of, known: str, *, path, column, line, hint="", where=""):
    """``(factor_of(unit), unit)`` of the unit the file states (``found``) or the argument
    (``given``), as :func:`resolve_unit` says; ``known`` lists the accepted units, ``where``
    says where the file states them."""
    arg = f"{kind}_unit"
    if given is not None and (not isinstance(given, str) or factor_of(given) is None):
        raise InputError(f"{arg}={given!r} is not a {kind} unit; use one of {known}", path=path)
    if found is None and given is None:
        raise InputError(
            f"no {kind} unit in the file; give {arg}= (one of {known}){hint}",
            path=path,
            line=line,
            column=column,
        )
    if found is None:
        return factor_of(given), given
    f = factor_of(found)
    if f is None:
        raise InputError(
            f"unit {found!r} is not a {kind} unit; use one of {known}{where}",
            path=path,
            line=line,
            column=column,
        )
    if given is not None and factor_of(given) != f:
        raise InputError(
            f"the file gives {kind} in {found!r} but {arg}={given!r} was passed; "
            f"drop {arg} (units in the file win) or correct the file",
            path=path,
            line=line,
            column=column,
        )
    return f, found
