"""Units of time and force found in file headers, and their SI factors.

A column name carries its unit in square brackets or parentheses: ``time [s]``,
``Fz (kN)``, ``t [us]``, ``t [µs]`` (micro sign U+00B5) or ``t [μs]`` (Greek mu U+03BC).
:func:`split_unit` separates name and unit; :func:`time_factor` and :func:`force_factor`
give the factor that converts a value in that unit to seconds or newtons.
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

# Case-insensitive aliases that are unambiguous ("mn" is not: mN or MN).
_TIME_LOWER = {k.lower(): v for k, v in TIME_UNITS.items()}
_FORCE_LOWER = {"n": 1.0, "kn": 1e3, "dan": 10.0, "lbf": FORCE_UNITS["lbf"]}

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
    known = TIME_UNITS if kind == "time" else FORCE_UNITS
    arg = f"{kind}_unit"
    if given is not None:
        if not isinstance(given, str) or factor_of(given) is None:
            raise InputError(
                f"{arg}={given!r} is not a {kind} unit; use one of {', '.join(known)}",
                path=path,
            )
    if found is not None:
        f = factor_of(found)
        if f is None:
            raise InputError(
                f"unit {found!r} is not a {kind} unit; use one of {', '.join(known)} "
                "in the column header",
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
    if given is None:
        raise InputError(
            f"no {kind} unit in the file; give {arg}= (one of {', '.join(known)}){hint}",
            path=path,
            line=line,
            column=column,
        )
    return factor_of(given), given
