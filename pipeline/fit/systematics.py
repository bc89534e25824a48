r"""Inputs a lab knows only to a tolerance: the systematics of :func:`pipeline.fit_contact`.

A fit takes the impact speed, the ball's mass and radius, each channel's gain, the sensor's
cross-talk, its filter's bandwidth and its clock as given. None of them is known exactly,
and each one's error moves the fitted parameters (a 2 % speed error moves E* by 3.3 % and
e by 0.018). Each is therefore a parameter of the forward model
(:data:`pipeline.fit.forward.SYSTEMATIC_PARAMS`) fitted with the contact's, constrained by
its stated value and standard uncertainty u: one residual row (θ − θ₀)/u, a Gaussian prior
(a GUM Type B evaluation; JCGM 100:2008 §4.3). What the record itself determines (a leak
that the stick phases separate from μ, a bandwidth that the pulse's rise resolves, a
speed that the impulse and the pulse's shape tie to E* and e) the data pull to its value;
what it cannot (the leak while the contact slides throughout, the radius, which enters
only with E* as E*·√R*) keeps its prior, and its uncertainty passes into the parameters
it is tied to. Every interval then holds both (:mod:`pipeline.fit.uncertainty`, the
budget).

Why fitted nuisance parameters and not Monte Carlo over the inputs: one fit gives every
term of the budget at once (the linearised estimator's weights on the prior rows), the
data can correct an input they determine (Monte Carlo cannot), and the cost is a few more
Jacobian columns, most in closed form (:data:`pipeline.fit.forward.ANALYTIC`);
``make bench`` (``misspec``) measures the coverage it gives.

``systematics`` maps a name to its standard uncertainty: a float is relative to the stated
value (for the gains, the leak and the time base, whose stated values are 1, 0 and 0, the
float is the absolute uncertainty of a dimensionless number), ``(u, "abs")`` is absolute
in SI units, ``"auto"`` (cross-talk, bandwidth) takes the rule below, 0 means exact.

=============  ===============================  ==========================================
name           parameter, stated value          default u (``systematics=None``)
=============  ===============================  ==========================================
``speed``      impact speed [m/s], the scene's  1 % (light gates, a pendulum's release)
``mass``       ball mass [kg], the scene's      0.1 % (weighed)
``radius``     ball radius [m], the scene's     0.1 % (measured; enters E* as √R*)
``gain_n``     Fn channel's gain, 1             1 % (a charge amplifier's calibration)
``gain_t``     Ft channel's gain, 1             1 %
``crosstalk``  the in-plane leaks, Fn → Ft      ``"auto"``: with a cross-talk matrix (given,
               (``leak``, of Fn) and Ft → Fn    or the record decoupled) its residual,
               (``leak_tn``, of Ft), 0; one u   ±0.2 % → u = 0.2 %/√3; without, a
               for both                         tri-axial piezo sensor's specification,
                                                ±3 % → u = 3 %/√3 = 1.7 % (a rectangular
                                                bound, GUM §4.3.7), or Fy's own leak where
                                                it shows more
``bandwidth``  filter cut-off [Hz], stated      ``"auto"``: 10 % of a stated cut-off;
                                                fitted freely (bounded below where the
                                                record cannot resolve it) when none is
                                                stated
``time_base``  record clock's relative error    1e-4 (a digitiser's clock)
``resonance``  the mounted transducer's mode's  10 % of a stated one (a tap test on the
               natural frequency [Hz], stated   mount, or the maker's figure for it);
                                                none stated: looked for in the record
                                                (:mod:`pipeline.fit.dynamics`)
``damping_``   that mode's damping ratio,       50 % of a stated one (a decay read off a
``ratio``      stated                           tap test); not stated with a stated mode:
                                                0.05 ± 0.05
``discharge``  the piezo's discharge time       10 % of a stated one (the amplifier's
               constant [s], stated             setting); none stated: looked for
=============  ===============================  ==========================================

A mode or a discharge that is not stated is no input known to a tolerance: where the
mapping holds ``"resonance"`` (``"discharge"``) the fit looks for one in the record and
fits it where the record shows it, or bounds it by what the record allows and carries the
effect of the bound into the budget under that name (:mod:`pipeline.fit.dynamics`);
without the key, none is modelled.

``{}`` takes every input as exact (the fit of old, and its speed); a mapping lists every
input known only to a tolerance, the others exact — ``{**DEFAULT_SYSTEMATICS,
"speed": 0.02}`` changes one default and keeps the rest.

References
----------
JCGM 100:2008, *Evaluation of measurement data — Guide to the expression of uncertainty in
measurement* (GUM), §4.3 (Type B evaluation), §5.1 (combined standard uncertainty).
"""

from __future__ import annotations

import dataclasses
import difflib
import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..record import channel
from .forward import PARAMS

__all__ = ["SYSTEMATICS", "DEFAULT_SYSTEMATICS", "DYNAMICS", "Systematic", "resolve", "PARAM_OF"]

#: The systematics' names, in the order of the budget.
SYSTEMATICS = (
    "speed",
    "mass",
    "radius",
    "gain_n",
    "gain_t",
    "crosstalk",
    "bandwidth",
    "time_base",
    "resonance",
    "damping_ratio",
    "discharge",
)
#: Each systematic's model parameter (:data:`pipeline.fit.forward.PARAMS`).
PARAM_OF = {s: ("leak" if s == "crosstalk" else s) for s in SYSTEMATICS}
DEFAULT_SYSTEMATICS = {
    "speed": 0.01,
    "mass": 0.001,
    "radius": 0.001,
    "gain_n": 0.01,
    "gain_t": 0.01,
    "crosstalk": "auto",
    "bandwidth": "auto",
    "time_base": 1e-4,
    "resonance": 0.10,
    "damping_ratio": 0.5,
    "discharge": 0.10,
}
#: The sensor's dynamics among the systematics: modelled only where stated (or found).
DYNAMICS = ("resonance", "damping_ratio", "discharge")
#: Cross-talk bounds (module notes): an uncalibrated sensor's specification and the
#: residual of a calibration matrix, as fractions of Fn (rectangular: u = bound/√3).
CROSSTALK_SPEC, CROSSTALK_CALIBRATED = 0.03, 0.002
#: Relative standard uncertainty of a stated filter cut-off.
BANDWIDTH_STATED = 0.10
_ABSOLUTE = ("gain_n", "gain_t", "crosstalk", "time_base")  # dimensionless, stated 1 or 0


@dataclass(frozen=True)
class Systematic:
    """One input known to a tolerance, as the fit uses it.

    Attributes
    ----------
    name : str — the systematic (:data:`SYSTEMATICS`)
    param : str — its model parameter
    value : float — stated value (SI; the parameter's units)
    sigma : float — standard uncertainty (SI); inf: fitted freely (no prior)
    source : str — where the value and its uncertainty come from (for the report)
    """

    name: str
    param: str
    value: float
    sigma: float
    source: str


def resolve(systematics, data, tangential: str) -> tuple[Systematic, ...]:
    """The systematics of one record's fit (module notes), the inapplicable ones left out.

    Parameters
    ----------
    systematics : mapping or None — see the module notes
    data : pipeline.fit.forward.RecordData — the prepared record (its scene and sensor)
    tangential : str — the tangential model (a frictionless fit has no Ft channel)

    Raises
    ------
    InputError
        An unknown name (the closest known one named), a negative or non-numeric value, an
        ``"auto"`` where none is defined.
    """
    given = DEFAULT_SYSTEMATICS if systematics is None else systematics
    origin = "default" if systematics is None else "given"
    if not isinstance(given, Mapping):
        raise InputError(
            f"systematics must be a mapping of input → standard uncertainty, or None for the "
            f"defaults; got {type(given).__name__}"
        )
    unknown = [k for k in given if k not in SYSTEMATICS]
    if unknown:
        k = unknown[0]
        close = difflib.get_close_matches(str(k), SYSTEMATICS, n=1)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise InputError(f"unknown systematic {k!r}{hint}; known: {', '.join(SYSTEMATICS)}")
    nominal = dict(zip(PARAMS, data.nominal(), strict=True))
    out = []
    for name in SYSTEMATICS:
        if name not in given:
            continue
        param = PARAM_OF[name]
        stated = float(nominal[param])
        if name in ("gain_t", "crosstalk") and tangential == "none":
            continue
        if name in DYNAMICS:
            found = _dynamics(name, given[name], data, origin)
            if found is not None:
                out.append(found)
            continue
        spec = given[name]
        if isinstance(spec, str):
            if spec != "auto" or name not in ("crosstalk", "bandwidth"):
                raise InputError(
                    f"systematics[{name!r}] = {spec!r}: 'auto' is defined for crosstalk and "
                    "bandwidth only; give a standard uncertainty (a float, relative, or "
                    "(u, 'abs'))"
                )
            found = _auto(name, data)
        else:
            sigma, how = _sigma(name, spec, stated, origin)
            found = None if sigma == 0.0 else Systematic(name, param, stated, sigma, how)
        if found is None:
            continue
        if name == "bandwidth" and (data.fine is None or not math.isfinite(found.value)):
            continue  # no modelled filter to be uncertain about
        out.append(found)
        if name == "crosstalk":  # the same bound on the leak the other way, Ft → Fn
            out.append(dataclasses.replace(found, param="leak_tn"))
    return tuple(out)


def _sigma(name, spec, stated, origin="given") -> tuple[float, str]:
    """(standard uncertainty [SI], how it was given) of one systematic."""
    absolute = isinstance(spec, tuple | list) and len(spec) == 2 and spec[1] == "abs"
    raw = spec[0] if absolute else spec
    try:
        u = float(raw)
    except (TypeError, ValueError):
        raise InputError(
            f"systematics[{name!r}] = {spec!r} is not a standard uncertainty: give a float "
            "(relative) or (u, 'abs')"
        ) from None
    if not (u >= 0 and math.isfinite(u)):
        raise InputError(f"systematics[{name!r}] = {spec!r} must be a finite number ≥ 0")
    if absolute or name in _ABSOLUTE:
        return u, f"u = {u:.3g} ({origin})"
    return u * abs(stated), f"{u:.3g} of the stated value ({origin})"


def _dynamics(name, spec, data, origin) -> Systematic | None:
    """A stated mode's frequency or damping, or a stated discharge, with its tolerance; None
    where none is stated (or no filter is modelled)."""
    sensor = data.sensor
    stated_mode = math.isfinite(sensor.resonance)
    if data.fine is None or (name == "discharge" and not math.isfinite(sensor.discharge)):
        return None
    if name != "discharge" and not stated_mode:
        return None
    if isinstance(spec, str):
        raise InputError(
            f"systematics[{name!r}] = {spec!r}: give a standard uncertainty (a float, "
            "relative, or (u, 'abs'))"
        )
    param = PARAM_OF[name]
    value = float(getattr(sensor, param))
    if name == "damping_ratio" and not sensor.damping_stated:
        u = DAMPING_UNSTATED
        return Systematic(name, param, value, u, f"not stated: {value:.3g} ± {u:.3g} (default)")
    sigma, how = _sigma(name, spec, value, origin)
    return None if sigma == 0.0 else Systematic(name, param, value, sigma, how)


#: Standard uncertainty of the damping ratio taken for a stated mode whose damping is not
#: stated [-] (pipeline.fit.sensor.DEFAULT_DAMPING = 0.05: ±100 %).
DAMPING_UNSTATED = 0.05


def _auto(name, data) -> Systematic | None:
    if name == "bandwidth":
        bw = float(data.sensor.bandwidth)
        if data.fine is None:
            return None
        if math.isfinite(bw):
            return Systematic(
                name,
                "bandwidth",
                bw,
                BANDWIDTH_STATED * bw,
                f"stated {bw:.4g} Hz, known to {BANDWIDTH_STATED:.0%} (default)",
            )
        if data.window.kind != "sensor":
            return None
        # no stated cut-off: fitted from a start well above the pulse's content, with no
        # prior (where the record cannot resolve it, only a lower bound is reported)
        start = 10.0 / max(data.window.duration, 1e-300)
        return Systematic(name, "bandwidth", start, math.inf, "not stated: fitted")
    # cross-talk
    calibrated = data.sensor.crosstalk is not None or any(
        str(k).startswith("decouple") for k in data.record.attrs
    )
    if calibrated:
        u = CROSSTALK_CALIBRATED / math.sqrt(3.0)
        return Systematic(name, "leak", 0.0, u, "a calibration matrix's residual, ±0.2 % (default)")
    u = CROSSTALK_SPEC / math.sqrt(3.0)
    source = "no cross-talk matrix: a tri-axial sensor's ±3 % specification (default)"
    fy = fy_leak(data)
    if fy is not None and abs(fy[0]) + 2 * fy[1] > u:
        u = abs(fy[0]) + 2 * fy[1]
        source = f"no cross-talk matrix: Fy follows Fn by {fy[0]:+.2%} (± {fy[1]:.1g})"
    return Systematic(name, "leak", 0.0, u, source)


def fy_leak(data) -> tuple[float, float] | None:
    """(slope, standard error) of the out-of-plane Fy (less its baseline) on the measured Fn
    over the fitted samples [-]: how much the sensor's axes leak, where the record shows it;
    None without an Fy channel or a noise estimate."""
    rec = data.record
    if "Fy" not in rec:
        return None
    t, fy = channel(rec, "Fy")
    fn = data.channels[0]
    base = data.window.baseline.get("Fy")
    y = np.interp(fn.t, t, fy - (base(t) if base is not None else 0.0))
    ss = float(np.dot(fn.y, fn.y))
    sigma = float(data.window.noise.get("Fy", np.nan))
    if not (ss > 0 and np.isfinite(sigma) and sigma > 0):
        return None
    return float(np.dot(y, fn.y) / ss), sigma / math.sqrt(ss)
