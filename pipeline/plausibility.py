r"""Plausibility before physics: does the record fit the impact its scene describes?

A record whose time column is in µs under a header that says seconds, or whose forces are
in N under a header that says kN, loads without a word and analyses into a confident wrong
answer (e = 1.9·10⁶, e ≈ 1900). The scene predicts the record's scales, so
:func:`check_plausible` compares three measured numbers with them before any physics:

=================  ==========================================  ============================
measured           expected (scene)                            plausible ratio
=================  ==========================================  ============================
contact duration   Hertz contact time :math:`t_c`              1/3 … 3
peak Fn            Hertz peak force :math:`F_{max}`            1/3 … 3
normal impulse Pn  :math:`m^* v_{n0}`                          0.8 … 2.3 (e ∈ [0, 1]
                                                               gives 1 … 2)
=================  ==========================================  ============================

with (Johnson 1985, §11.4; docs/theory.md)

.. math::

    \delta_{max} = \Big(\frac{15 m^* v_{n0}^2}{16 E^* \sqrt{R^*}}\Big)^{2/5},\quad
    F_{max} = \tfrac43 E^*\sqrt{R^*}\,\delta_{max}^{3/2},\quad
    t_c = 2.943\,\delta_{max}/v_{n0}.

A ratio off by a power of 10³ (within a factor √10) is a unit mistake: a
:class:`~pipeline.errors.UnitMismatchError` that names the unit the values fit (the
duration judges the time unit, the peak the force unit, the impulse — when both passed —
the scene's own units). Any other ratio outside its band is a named warning
(:class:`~pipeline.errors.ContactTimeWarning`, :class:`~pipeline.errors.PeakForceWarning`,
:class:`~pipeline.errors.ImpulseWarning`): damping, plasticity or a compliant mount move
these numbers by tens of per cent, not by factors of three. The Hertz checks need the
scene's elastic constants; without them they are skipped and say so.

The checks of the record alone (clipping, a cut pulse, two impacts, a glitch, a flipped
sign) are made where the contact is found, :func:`pipeline.window.find_contact`; those of
the file (the stated sample rate, float range) when it is read (:mod:`pipeline.io`,
:func:`pipeline.record.validate`).

References
----------
K. L. Johnson, Contact Mechanics, Cambridge University Press (1985),
doi:10.1017/CBO9781139171731.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from ._json import json_ready
from .contact import hertz_impact
from .errors import (
    ContactTimeWarning,
    ImpulseWarning,
    InputError,
    PeakForceWarning,
    UnitMismatchError,
)
from .io.metadata import unit_for
from .io.units import force_factor, time_factor
from .record import channel
from .scene import Scene
from .window import find_contact

__all__ = ["Check", "Plausibility", "check_plausible", "BANDS"]

#: Plausible ratio measured/expected of each check (see the module notes).
BANDS = {"contact_time": (1 / 3, 3.0), "peak_force": (1 / 3, 3.0), "impulse": (0.8, 2.3)}
_WARNINGS = {
    "contact_time": ContactTimeWarning,
    "peak_force": PeakForceWarning,
    "impulse": ImpulseWarning,
}


@dataclass(frozen=True)
class Check:
    """One plausibility check.

    Attributes
    ----------
    name : str — ``"contact_time"``, ``"peak_force"`` or ``"impulse"``
    status : str — ``"ok"``, ``"warning"`` or ``"skipped"``
    measured, expected : float — in ``unit`` (NaN when skipped)
    unit : str — ``"s"``, ``"N"`` or ``"N s"``
    note : str — the message (why skipped, what was off)
    """

    name: str
    status: str
    measured: float = math.nan
    expected: float = math.nan
    unit: str = ""
    note: str = ""

    @property
    def ratio(self) -> float:
        """measured / expected [-]."""
        return self.measured / self.expected if self.expected else math.nan


@dataclass(frozen=True)
class Plausibility:
    """The checks :func:`check_plausible` made, in order."""

    checks: tuple

    def __getitem__(self, name: str) -> Check:
        return next(c for c in self.checks if c.name == name)

    @property
    def ok(self) -> bool:
        """True when no check warned."""
        return all(c.status != "warning" for c in self.checks)

    def summary(self) -> dict:
        """Strict-JSON dict ``{name: {status, measured, expected, ratio, unit, note}}``."""
        return json_ready(
            {
                c.name: {
                    "status": c.status,
                    "measured": c.measured,
                    "expected": c.expected,
                    "ratio": c.ratio,
                    "unit": c.unit,
                    "note": c.note,
                }
                for c in self.checks
            }
        )


def check_plausible(record, scene: Scene, *, window=None) -> Plausibility:
    """Compare a record's contact duration, peak force and impulse with the scene's.

    Parameters
    ----------
    record : xarray.Dataset
        A record (:func:`pipeline.io.load`); its ``source_time_unit`` and
        ``source_force_unit`` attributes name the units the file was read in.
    scene : Scene
        The impact: mass, speed, angle; ``E`` and ``nu`` for the Hertz checks.
    window : pipeline.window.ContactWindow, optional
        The record's contact window; found with :func:`pipeline.window.find_contact`
        when not given (its own checks then run too).

    Returns
    -------
    Plausibility

    Raises
    ------
    UnitMismatchError
        The duration, the peak or the impulse is off by a power of 10³ (module notes).
    InputError
        Whatever :func:`pipeline.window.find_contact` raises.

    Warns
    -----
    ContactTimeWarning, PeakForceWarning, ImpulseWarning
        A ratio outside its band (:data:`BANDS`) but not a unit factor.
    """
    if not isinstance(scene, Scene):
        raise InputError("check_plausible needs a pipeline.Scene describing the impact")
    win = find_contact(record) if window is None else window
    src = record.attrs.get("source")
    t_unit = str(record.attrs.get("source_time_unit", "s"))
    f_unit = str(record.attrs.get("source_force_unit", "N")).split(",")[0]
    v_n0 = float(scene.v_n0)
    checks = []
    hertz, why = _hertz(scene)
    if hertz is None:
        checks += [
            Check("contact_time", "skipped", note=why),
            Check("peak_force", "skipped", note=why),
        ]
    else:
        checks.append(_judge("contact_time", win.duration, hertz.t_c, "s", "time", t_unit, src))
        checks.append(_judge("peak_force", win.peak, hertz.F_max, "N", "force", f_unit, src))
    if v_n0 > 0:
        t, fn = channel(win.record, "Fn")
        t = np.concatenate([[win.t_start], t, [win.t_end]])
        fn = np.concatenate([[0.0], fn, [0.0]])
        Pn = float(np.trapezoid(fn, t))
        momentum = float(scene.m_eff) * v_n0
        checks.append(_judge("impulse", Pn, momentum, "N s", "impulse", None, src))
    else:
        checks.append(Check("impulse", "skipped", note="the scene's normal speed is 0"))
    return Plausibility(tuple(checks))


def _hertz(scene):
    if scene.E is None or scene.nu is None:
        return None, "the scene gives no E and nu: no Hertz estimate"
    if not scene.v_n0 > 0:
        return None, "the scene's normal speed is 0: no Hertz estimate"
    try:
        return hertz_impact(scene), ""
    except InputError as exc:  # both bodies rigid
        return None, f"no Hertz estimate: {exc.reason}"


_NAMES = {
    "contact_time": ("the contact lasts", "Hertz theory predicts"),
    "peak_force": ("Fn peaks at", "Hertz theory predicts"),
    "impulse": ("the normal impulse is", "the scene's momentum m*·v_n0 is"),
}


def _judge(name, measured, expected, unit, quantity, stated, src) -> Check:
    lo, hi = BANDS[name]
    centre = math.sqrt(lo * hi)
    ratio = measured / expected
    what, theory = _NAMES[name]
    text = (
        f"{what} {measured:.4g} {unit}; {theory} {expected:.4g} {unit} for the scene "
        f"(ratio {ratio:.3g}, plausible {lo:.2g} to {hi:.2g})"
    )
    if lo <= ratio <= hi:
        return Check(name, "ok", measured, expected, unit, text)
    if not ratio > 0:
        return _warn(name, measured, expected, unit, text + "; is the pulse there at all?")
    log = math.log10(ratio / centre)
    k = round(log / 3)
    if k != 0 and abs(log - 3 * k) <= 0.5:
        raise UnitMismatchError(
            text + ": off by 10^" + f"{3 * k}, a unit mistake. " + _advice(quantity, stated, k),
            quantity=quantity,
            ratio=ratio,
            suggested=_suggest(quantity, stated, k),
            path=src,
        )
    return _warn(name, measured, expected, unit, text + "; check the scene and the record")


def _warn(name, measured, expected, unit, text) -> Check:
    warnings.warn(text, _WARNINGS[name], stacklevel=4)
    return Check(name, "warning", measured, expected, unit, text)


def _suggest(quantity, stated, k) -> str | None:
    if stated is None:
        return None
    factor_of = time_factor if quantity == "time" else force_factor
    factor = factor_of(stated)
    return None if factor is None else unit_for(quantity, factor / 1000.0**k)


def _advice(quantity, stated, k) -> str:
    if quantity == "impulse":
        return (
            "Duration and peak fit the scene, so check the scene's own units (SI: radius "
            "in m, mass in kg, density in kg/m³, speed in m/s)"
        )
    fits = _suggest(quantity, stated, k)
    arg = f"{quantity}_unit"
    if fits:
        return (
            f"The file's {quantity} values fit {fits!r}, not {stated!r}: correct the unit in "
            f"the header (or pass {arg}={fits!r} for a file without units) — or, if the "
            "file is right, the scene's units (SI)"
        )
    return (
        f"No {quantity} unit fits values read as {stated!r}: check the file's {quantity} "
        "column and the scene's units (SI)"
    )
