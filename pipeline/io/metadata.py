"""What a record's ``# key: value`` lines say: scene fields with units, and the sample rate.

A sensor export often states the impact it recorded (``# impact speed [m/s]: 0.6``,
``# Angle: 15 deg``). :func:`scene_from_metadata` reads those lines into
:class:`~pipeline.Scene` fields **only when they carry a unit** — in the key's brackets or
after the number — so that a bare ``# speed: 0.6`` (m/s? mm/ms?) is never guessed.
Dimensionless fields (ν, μ, e, κ) need none. Decimal commas are read (``0,5 m/s``).

=========================  ==================================================  ====================
field                      keys (case, spaces and ``_`` ignored)               units
=========================  ==================================================  ====================
``radius``                 radius, ball radius, sphere radius                  m, mm, cm, µm, in
(radius)                   diameter, ball diameter, sphere diameter (halved)   m, mm, cm, µm, in
``mass``                   mass, ball mass, sphere mass                        kg, g, mg
``density``                density, ball density                               kg/m³, g/cm³
``E``                      young's modulus, ball E, E (with a pressure unit)   Pa, kPa, MPa, GPa
``nu``                     poisson ratio, poisson's ratio, nu                  —
``target_E``               target E, target young's modulus, target modulus    Pa … GPa
``target_nu``              target poisson ratio, target nu                     —
``target_radius``          target radius, cap radius                           m …
``target_mass``            target mass                                         kg, g
``speed``                  speed, impact speed, velocity, impact velocity, v0  m/s, mm/s, cm/s, km/h
``angle_deg``              angle, incidence, incidence angle, impact angle     deg, °, rad
``mu``                     mu, friction coefficient, coefficient of friction   —
``e``                      restitution, coefficient of restitution, cor, e     —
``kappa``                  kappa                                               —
``spin``                   spin, initial spin                                  rad/s, rpm
``surface_speed``          surface speed, disc speed                           m/s …
``yield_strength``         yield strength, ball yield strength, yield stress   Pa … GPa
``target_yield_strength``  target yield strength, target yield stress          Pa … GPa
=========================  ==================================================  ====================

:func:`check_sample_rate` compares a stated sample rate (``# sample rate: 2 MHz``,
``# sample rate [Hz]: 2e6``, ``# fs: 1 MS/s``) with the time column: off by a power of
10³ is a :class:`~pipeline.errors.UnitMismatchError` naming the time unit the values fit,
any other disagreement over 1 % a :class:`~pipeline.errors.SampleRateWarning`.
:func:`stated_bandwidth` reads the sensor's low-pass bandwidth (``# bandwidth [Hz]:
300000``), which the sensor reader keeps as ``attrs["sensor_bandwidth"]`` [Hz] for the
resolution checks of :func:`pipeline.percussion.resolution`.
"""

from __future__ import annotations

import math
import re
import warnings

import numpy as np

from ..errors import InputError, SampleRateWarning, UnitMismatchError, caller_level
from ._common import IO_DIR
from .units import TIME_UNITS

__all__ = [
    "parse_quantity",
    "scene_from_metadata",
    "check_sample_rate",
    "stated_sample_rate",
    "stated_bandwidth",
]

_PI = math.pi

#: Units by kind → factor to SI (angles to degrees: the scene's angle_deg).
UNITS = {
    "length": {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "um": 1e-6, "µm": 1e-6, "μm": 1e-6, "in": 0.0254},
    "mass": {"kg": 1.0, "g": 1e-3, "mg": 1e-6},
    "density": {
        "kg/m3": 1.0,
        "kg/m³": 1.0,
        "kg/m^3": 1.0,
        "g/cm3": 1e3,
        "g/cm³": 1e3,
        "g/cm^3": 1e3,
    },
    "pressure": {"pa": 1.0, "kpa": 1e3, "mpa": 1e6, "gpa": 1e9},
    "speed": {"m/s": 1.0, "mm/s": 1e-3, "cm/s": 1e-2, "km/h": 1 / 3.6},
    "angle": {"deg": 1.0, "°": 1.0, "degree": 1.0, "degrees": 1.0, "rad": 180.0 / _PI},
    "angular_speed": {"rad/s": 1.0, "rpm": 2 * _PI / 60},
    "frequency": {
        "hz": 1.0,
        "khz": 1e3,
        "mhz": 1e6,
        "ghz": 1e9,
        "s/s": 1.0,
        "ks/s": 1e3,
        "ms/s": 1e6,
        "gs/s": 1e9,
        "sps": 1.0,
        "ksps": 1e3,
        "msps": 1e6,
    },
    "dimensionless": {"": 1.0, "-": 1.0, "1": 1.0},
}
_CASELESS = ("pressure", "frequency")  # "MPa" and "mpa", "MHz" and "mhz" are one unit

#: Scene field → (unit kind, metadata keys with spaces, "_", "'" and "-" removed).
FIELDS = {
    "radius": ("length", {"radius", "ballradius", "sphereradius"}),
    "diameter": ("length", {"diameter", "balldiameter", "spherediameter"}),
    "mass": ("mass", {"mass", "ballmass", "spheremass"}),
    "density": ("density", {"density", "balldensity", "spheredensity"}),
    "E": ("pressure", {"youngsmodulus", "youngmodulus", "balle", "ballyoungsmodulus", "e"}),
    "nu": ("dimensionless", {"nu", "poissonratio", "poissonsratio", "ballnu"}),
    "target_E": ("pressure", {"targete", "targetyoungsmodulus", "targetmodulus"}),
    "target_nu": ("dimensionless", {"targetnu", "targetpoissonratio", "targetpoissonsratio"}),
    "target_radius": ("length", {"targetradius", "capradius"}),
    "target_mass": ("mass", {"targetmass"}),
    "speed": (
        "speed",
        {"speed", "impactspeed", "velocity", "impactvelocity", "v0", "incomingspeed"},
    ),
    "angle_deg": (
        "angle",
        {"angle", "incidence", "incidenceangle", "impactangle", "angleofincidence"},
    ),
    "mu": ("dimensionless", {"mu", "frictioncoefficient", "coefficientoffriction"}),
    "e": ("dimensionless", {"restitution", "coefficientofrestitution", "cor", "e"}),
    "kappa": ("dimensionless", {"kappa"}),
    "spin": ("angular_speed", {"spin", "initialspin"}),
    "surface_speed": ("speed", {"surfacespeed", "discspeed"}),
    "yield_strength": (
        "pressure",
        {"yieldstrength", "ballyieldstrength", "yieldstress", "ballyieldstress"},
    ),
    "target_yield_strength": ("pressure", {"targetyieldstrength", "targetyieldstress"}),
}
_RATE_KEYS = {
    "samplerate",
    "samplingrate",
    "samplefrequency",
    "samplingfrequency",
    "fs",
    "rate",
    "samplingfreq",
}

_BANDWIDTH_KEYS = {
    "bandwidth",
    "filterbandwidth",
    "sensorbandwidth",
    "cutoff",
    "cutofffrequency",
    "lowpass",
    "lowpassfilter",
    "antialiasfilter",
}

_QUANTITY = re.compile(
    r"^\s*(?P<num>[+-]?(?:\d+(?:[.,]\d*)?|[.,]\d+)(?:[eE][+-]?\d+)?)\s*(?P<unit>[^\d\s].*?)?\s*$"
)


def _squash(key: str) -> str:
    return re.sub(r"[\s_'’\-]+", "", key.removeprefix("meta_")).lower()


def parse_quantity(text) -> tuple[float, str] | None:
    """``"0,5 m/s"`` → ``(0.5, "m/s")``; ``"15"`` → ``(15.0, "")``; None when the text is not
    one number with an optional unit (``"steel, diameter 25,4 mm"``)."""
    if not isinstance(text, str):
        return None
    m = _QUANTITY.match(text)
    if m is None:
        return None
    num = m.group("num")
    if "," in num:
        if "." in num:
            return None
        num = num.replace(",", ".")
    value = float(num)
    if not math.isfinite(value):
        return None
    return value, (m.group("unit") or "").strip()


def _factor(kind: str, unit: str) -> float | None:
    table = UNITS[kind]
    u = unit.replace(" ", "")
    if kind in _CASELESS:
        u = u.lower()
    return table.get(u)


def _kind_of(unit: str) -> str | None:
    for kind in UNITS:
        if kind != "dimensionless" and _factor(kind, unit) is not None:
            return kind
    return None


def scene_from_metadata(attrs) -> dict:
    """Scene fields a record's metadata states with units.

    Parameters
    ----------
    attrs : mapping or xarray.Dataset
        A record (or its ``attrs``): the ``meta_<key>`` attributes a reader made of the
        file's ``# key: value`` lines.

    Returns
    -------
    dict
        ``{field: (value in SI, where it came from)}``, e.g. ``{"speed": (0.6, "record
        metadata 'impact_speed' = '0.6 m/s'")}``; a diameter gives ``radius``.

    Raises
    ------
    InputError
        A known key whose value carries a unit of the wrong kind (``# speed: 5 mm``), or
        two keys for one field that disagree (a radius and a diameter).
    """
    attrs = getattr(attrs, "attrs", attrs)
    src = attrs.get("source")
    out: dict = {}
    for key, text in attrs.items():
        if not str(key).startswith("meta_"):
            continue
        squashed = _squash(str(key))
        parsed = parse_quantity(text)
        if parsed is None:
            continue
        value, unit = parsed
        for field, (kind, keys) in FIELDS.items():
            if squashed not in keys:
                continue
            if field == "E" and squashed == "e" and _kind_of(unit) != "pressure":
                continue  # "e" is the restitution; "E" with a pressure unit the modulus
            factor = _factor(kind, unit)
            if factor is None:
                if kind != "dimensionless" and not unit:
                    break  # no unit: not guessed
                want = ", ".join(u for u in UNITS[kind] if u) or "none"
                raise InputError(
                    f"metadata '{key.removeprefix('meta_')}: {text}' reads as the scene's "
                    f"{field} but {unit!r} is not a unit of it (use {want})",
                    path=src,
                )
            si = value * factor
            name = "radius" if field == "diameter" else field
            si = si / 2 if field == "diameter" else si
            note = f"record metadata {key.removeprefix('meta_')!r} = {text!r}"
            if name in out and not math.isclose(out[name][0], si, rel_tol=1e-9):
                raise InputError(
                    f"the metadata gives two values for {name}: {out[name][1]} and {note}; "
                    "correct one of them",
                    path=src,
                )
            out[name] = (si, note)
            break
    return out


def stated_sample_rate(attrs) -> tuple[float, str] | None:
    """The sample rate [Hz] a record's metadata states with a unit, and its text."""
    return _stated_frequency(attrs, _RATE_KEYS)


def stated_bandwidth(attrs) -> tuple[float, str] | None:
    """The sensor's low-pass bandwidth [Hz] the metadata states with a unit
    (``# bandwidth [Hz]: 300000``, ``# cutoff: 300 kHz``), and its text."""
    return _stated_frequency(attrs, _BANDWIDTH_KEYS)


def _stated_frequency(attrs, keys) -> tuple[float, str] | None:
    for key, text in attrs.items():
        if not str(key).startswith("meta_") or _squash(str(key)) not in keys:
            continue
        parsed = parse_quantity(text)
        if parsed is None:
            continue
        value, unit = parsed
        factor = _factor("frequency", unit)
        if factor is not None and value > 0:
            return value * factor, f"{key.removeprefix('meta_')}: {text}"
    return None


def check_sample_rate(attrs, time, time_unit: str, path) -> None:
    """Compare the stated sample rate with the median step of ``time`` [s].

    Parameters
    ----------
    attrs : mapping — the record's attributes so far (``meta_<key>`` entries)
    time : array — the time column in seconds
    time_unit : str — the unit the time column was read in
    path — the file, for messages

    Raises
    ------
    UnitMismatchError
        The step is off from 1/rate by a power of 10³ (within a factor 2): the time values
        are in another unit than the header says; the message names the one they fit.

    Warns
    -----
    SampleRateWarning
        Any other disagreement over 1 %.
    """
    stated = stated_sample_rate(attrs)
    if stated is None or len(time) < 2:
        return
    rate, text = stated
    step = float(np.median(np.diff(time)))
    expected = 1.0 / rate
    ratio = step / expected
    if abs(ratio - 1.0) <= 0.01:
        return
    k = round(math.log10(ratio) / 3)
    if k != 0 and abs(math.log10(ratio) - 3 * k) <= math.log10(2):
        fits = unit_for("time", TIME_UNITS.get(time_unit, 1.0) / 1000.0**k)
        raise UnitMismatchError(
            f"the time column steps by {step:.4g} s (read as {time_unit!r}) but the file "
            f"states '{text}', a step of {expected:.4g} s: {ratio:.3g} times longer. The "
            + (
                f"time values are in {fits!r}, not {time_unit!r}: correct the header"
                if fits
                else "time values are in no unit the header could name"
            ),
            quantity="time",
            ratio=ratio,
            suggested=fits,
            path=path,
        )
    warnings.warn(
        f"{path}: the time column steps by {step:.4g} s (median) but the file states "
        f"'{text}', a step of {expected:.4g} s ({ratio:.3g} times); check the file",
        SampleRateWarning,
        stacklevel=caller_level(IO_DIR),
    )


#: The names :func:`unit_for` gives, for each factor to SI.
_CANONICAL = {
    "time": {1.0: "s", 1e-3: "ms", 1e-6: "us", 1e-9: "ns"},
    "force": {1.0: "N", 1e3: "kN", 1e-3: "mN", 1e6: "MN"},
}


def unit_for(quantity: str, factor: float) -> str | None:
    """The usual unit of ``quantity`` (``"time"``, ``"force"``) with this factor to SI."""
    for f, name in _CANONICAL[quantity].items():
        if math.isclose(f, factor, rel_tol=1e-9):
            return name
    return None
