"""A channel recorded in volts, and the sensitivity that turns it into newtons.

A force transducer's conditioning (an IEPE/ICP supply, a charge amplifier, a bridge
amplifier) outputs a voltage proportional to the force, and its calibration sheet states
the ratio: the sensitivity S, e.g. 0.225 mV/N, so that

.. math:: F\\,[\\mathrm{N}] = U\\,[\\mathrm{V}] / S\\,[\\mathrm{V/N}]
          = U\\,[\\mathrm{V}] \\cdot k\\,[\\mathrm{N/V}], \\qquad k = 1/S.

Either form is accepted, in the units the sheets use: ``"mV/N"``, ``"V/N"`` (and
``"mV/kN"``, ``"V/kN"``, ``"µV/N"``, ``"mV/lbf"``) for S, ``"N/V"``, ``"N/mV"`` (and
``"kN/V"``, ...) for k — any voltage unit over any force unit of
:mod:`pipeline.io.units`, or the inverse. A bridge's ratiometric rating (``mV/V``) is not a
sensitivity until multiplied by the excitation voltage and divided by the capacity: the
message says so.

:func:`parse_sensitivity` reads the ``sensitivity=`` argument of :func:`pipeline.io.load`
(and the sidecar key ``"sensitivity"``, and the command line's ``--sensitivity``): a dict
from record channel (``"Fn"``, ``"Ft"``, ``"Fy"``, after ``axes``) — or from a file column
that no record channel takes (a raw axis that only the decoupling matrix reads) — to
``(value, unit)``, a ``[value, unit]`` list (JSON) or a string ``"0.225 mV/N"``. The value is
positive: a sensor mounted the other way round is a ``-`` in ``axes``, not a negative
sensitivity. :func:`by_column` resolves the keys to the file's columns; every key must
name a channel the record reads, so a misspelt key is an error, not a silent no-op. The
record keeps what was applied in ``attrs["sensitivity"]`` (``"Fn=0.225 mV/N"``, comma
separated).
"""

from __future__ import annotations

import math
import numbers
import re
from dataclasses import dataclass

from ..errors import InputError
from ..record import FORCE_CHANNELS
from .units import force_factor, volt_factor

__all__ = ["Sensitivity", "parse_sensitivity", "by_column", "sensitivity_attr"]

_TEXT = re.compile(r"^\s*([+-]?(?:\d+(?:[.,]\d*)?|[.,]\d+)(?:[eE][+-]?\d+)?)\s*(\S.*?)\s*$")
_EXAMPLE = "sensitivity={'Fn': (0.225, 'mV/N')}"


@dataclass(frozen=True)
class Sensitivity:
    """A channel's stated sensitivity.

    Attributes
    ----------
    value : float — the number as stated [unit]
    unit : str — as stated: voltage per force (``"mV/N"``) or force per voltage (``"N/V"``)
    newtons_per_volt : float — k = 1/S [N/V], the factor that takes volts to newtons
    """

    value: float
    unit: str
    newtons_per_volt: float

    def __str__(self) -> str:
        return f"{self.value:g} {self.unit}"


def _newtons_per_volt(value: float, unit: str) -> float | None:
    """k [N/V] of ``value`` in ``unit`` (a force per voltage, or a voltage per force);
    None when ``unit`` is neither."""
    num, sep, den = unit.replace(" ", "").partition("/")
    if not sep or not num or not den:
        return None
    f, v = force_factor(num), volt_factor(den)
    if f is not None and v is not None:  # k stated: force per voltage
        return value * f / v
    v, f = volt_factor(num), force_factor(den)
    if f is not None and v is not None:  # S stated: voltage per force, k = 1/S
        return f / (value * v)
    return None


def _one(key: str, spec, path) -> Sensitivity:
    if isinstance(spec, str):
        m = _TEXT.match(spec)
        if m is None:
            raise InputError(
                f"sensitivity[{key!r}] = {spec!r} is not a number and a unit, e.g. '0.225 mV/N'",
                path=path,
            )
        number = m.group(1)
        if "," in number and "." not in number:
            number = number.replace(",", ".")
        value, unit = float(number), m.group(2)
    elif isinstance(spec, list | tuple) and len(spec) == 2:
        value, unit = spec
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise InputError(
                f"sensitivity[{key!r}]: the value {value!r} must be a number, as in {_EXAMPLE}",
                path=path,
            )
        if not isinstance(unit, str):
            raise InputError(
                f"sensitivity[{key!r}]: the unit {unit!r} must be a string such as 'mV/N'",
                path=path,
            )
        value = float(value)
    else:
        raise InputError(
            f"sensitivity[{key!r}] = {spec!r}: give (value, unit), as in {_EXAMPLE}", path=path
        )
    unit = unit.strip()
    if unit.replace(" ", "").lower() in ("mv/v", "v/v", "µv/v", "uv/v"):
        raise InputError(
            f"sensitivity[{key!r}] is a bridge's ratiometric rating ({value:g} {unit}), not a "
            "sensitivity: multiply it by the excitation voltage and divide by the rated "
            "capacity (2 mV/V · 10 V / 500 N = 0.04 mV/N)",
            path=path,
        )
    if _newtons_per_volt(1.0, unit) is None:
        raise InputError(
            f"sensitivity[{key!r}]: unit {unit!r} is neither a voltage per force (mV/N, V/N) "
            "nor a force per voltage (N/V, N/mV)",
            path=path,
        )
    if not (math.isfinite(value) and value > 0):
        raise InputError(
            f"sensitivity[{key!r}] = {value!r} {unit}: a sensitivity is a positive finite "
            "number (a sensor mounted the other way round is a '-' in axes)",
            path=path,
        )
    k = _newtons_per_volt(value, unit)
    if not (math.isfinite(k) and k > 0):
        raise InputError(
            f"sensitivity[{key!r}] = {value!r} {unit} is out of any sensor's range", path=path
        )
    return Sensitivity(value, unit, k)


def parse_sensitivity(spec, *, path=None) -> dict[str, Sensitivity]:
    """``{key: Sensitivity}`` from ``load``'s ``sensitivity=`` (None gives ``{}``).

    Parameters
    ----------
    spec : dict or None
        ``{"Fn": (0.225, "mV/N"), "Ft": [4.4, "N/V"], "Fy": "0.5 mV/N"}``: a record channel
        (or a file column) → (value, unit).
    path : optional — the file the spec came from (a sidecar), for messages

    Raises
    ------
    InputError
        Not a dict, a key that is not a string, or an entry that is not a positive number
        with a voltage-per-force or force-per-voltage unit.
    """
    if spec is None:
        return {}
    if isinstance(spec, Sensitivity):
        raise InputError(f"sensitivity= maps channels to values, as in {_EXAMPLE}", path=path)
    if not isinstance(spec, dict):
        raise InputError(
            f"sensitivity must be a dict such as {{'Fn': (0.225, 'mV/N')}}, got {spec!r}",
            path=path,
        )
    out = {}
    for key, value in spec.items():
        if not isinstance(key, str) or not key.strip():
            raise InputError(f"sensitivity key {key!r} must name a channel such as 'Fn'", path=path)
        out[key.strip()] = value if isinstance(value, Sensitivity) else _one(key, value, path)
    return out


def by_column(sens: dict, chosen: dict, columns, path, *, read=None, label=None) -> dict:
    """``{file column: Sensitivity}`` for the channels ``chosen`` (record channel → (file
    column, sign), as :func:`pipeline.io._common.resolve_axes` gives it).

    A key that is a record channel names the column that channel reads; any other key must
    be a column of the file (``columns``: its names) among those the record ``read``s (its
    channels' and the decoupling's raw axes; ``label`` gives a column's name as the file
    writes it, for the message). A key that matches neither is an error.
    """
    out: dict = {}
    for key, s in sens.items():
        if key in FORCE_CHANNELS:
            if key not in chosen:
                raise InputError(
                    f"sensitivity given for {key}, but the record has no {key} channel "
                    f"(channels: {', '.join(chosen)}); drop it or map the column with axes=",
                    path=path,
                )
            col = chosen[key][0]
        else:
            match = [c for c in columns if c == key] or [
                c for c in columns if c.lower() == key.lower()
            ]
            if len(match) != 1:
                raise InputError(
                    f"sensitivity given for {key!r}, which is neither a record channel "
                    f"({', '.join(FORCE_CHANNELS)}) nor a column of the file "
                    f"({', '.join(columns) or 'none'})",
                    path=path,
                )
            col = match[0]
        if col in out and out[col] != s:
            raise InputError(f"two sensitivities for column {col!r}; give one", path=path)
        out[col] = s
    unused = [c for c in out if read is not None and c not in read]
    if unused:
        name = label or str
        raise InputError(
            f"sensitivity given for column {name(unused[0])!r}, which the record does not read "
            f"(it reads {', '.join(name(c) for c in read)})",
            path=path,
        )
    return out


def sensitivity_attr(applied: dict) -> str:
    """``"Fn=0.225 mV/N,Ft=4.4 N/V"``: what the record's ``attrs["sensitivity"]`` holds."""
    return ",".join(f"{name}={s}" for name, s in applied.items())
