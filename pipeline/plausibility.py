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

**After the physics** (:func:`check_outcomes`, run by :func:`pipeline.analyse`): a passive
impact — no spin before it, a surface at rest — cannot give the ball energy, so an outcome
that breaks one of these bounds is a mistake in the record or the scene, named with its
likeliest cause:

=====================  =====================================  ====================================
bound                  broken when                            warning (likeliest cause)
=====================  =====================================  ====================================
e_n ≤ 1                the ball leaves faster than it came    :class:`NormalRestitutionWarning`
                                                              (force gain, scene mass or speed)
e_t ≤ 1                Pt_f < 0: friction sped the ball up    :class:`TangentialRestitutionWarning`
(no spin, still        along its slip                         (Ft's sign convention flipped)
surface)
kinetic energy         ½m v² + ½I ω² after > before           :class:`EnergyGainWarning`
                                                              (swapped channels, a gain)
|Pt| ≤ μ·Pn            Coulomb's cone, μ known (scene)        :class:`FrictionBoundWarning`
                                                              (μ too low, cross-talk, Ft gain)
Ft opposes the slip    Pt < 0 when Fn first reaches half its  :class:`FrictionDirectionWarning`
at first               peak (no compliance reverses Ft so     (Ft's sign convention flipped)
                       early)
=====================  =====================================  ====================================

"Broken" means beyond the measurement's own uncertainty: by more than the sum of
:data:`BOUND_Z` standard deviations (the bootstrap's where the analysis ran one; else
white noise of the measured level integrated over the window, with the baseline's own
error), the disagreement of the integration rules (trapezoid, Simpson and, for the fit's
percussions, the fit: what a sparse or poorly fitted record leaves uncertain), a floor of a
few per cent (:data:`BOUND_FLOOR`) that covers what no noise model holds (a filter's
tail, a digitised curve's clicks) and, for the tangential bounds, the
Fn → Ft cross-talk a sensor may have: :data:`LEAK_BOUND` of Pn (tri-axial piezo sensors
are specified to ±1–3 % cross-talk; 0.2 % for a record decoupled with its calibration
matrix, none for a simulated one). A 2 % leak is 40 % of μ·Pn at μ = 0.05, so at small μ
only gross violations can be told from cross-talk. On 216 simulated sensor records (three
normal laws, Coulomb and Mindlin, 2°–85°, e 0.5 and 0.95, μ 0.05 and 0.3, the sensor
model's ±2 % cross-talk) none is flagged.

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
    EnergyGainWarning,
    FrictionBoundWarning,
    FrictionDirectionWarning,
    ImpulseWarning,
    InputError,
    NormalRestitutionWarning,
    PeakForceWarning,
    TangentialRestitutionWarning,
    UnitMismatchError,
)
from .io.metadata import unit_for
from .io.units import FORCE_UNITS, force_factor, time_factor
from .record import channel
from .scene import Scene
from .window import find_contact

__all__ = ["Check", "Plausibility", "check_plausible", "check_outcomes", "BANDS"]

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
        when not given (its own checks then run too; a discharge the record's sensor
        states undone, :func:`pipeline.fit.sensor.sensor_spec`).

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
    win = window
    if win is None:
        from .fit.sensor import sensor_spec  # the fits' reading of the record's sensor

        win = find_contact(record, discharge=sensor_spec(record).discharge)
    src = record.attrs.get("source")
    t_unit = str(record.attrs.get("source_time_unit", "s"))
    f_unit = str(record.attrs.get("source_force_unit", "N")).split(",")[0]
    v_n0 = float(scene.v_n0)
    checks = []
    hertz, why = _hertz(scene)
    Pn = momentum = math.nan
    if v_n0 > 0:
        t, fn = channel(win.record, "Fn")
        t = np.concatenate([[win.t_start], t, [win.t_end]])
        fn = np.concatenate([[0.0], fn, [0.0]])
        Pn = float(np.trapezoid(fn, t))
        momentum = float(scene.m_eff) * v_n0
    if hertz is None:
        checks += [
            Check("contact_time", "skipped", note=why),
            Check("peak_force", "skipped", note=why),
        ]
    else:
        checks.append(_judge("contact_time", win.duration, hertz.t_c, "s", "time", t_unit, src))
        hint = _swapped(win, hertz.F_max)
        if not hint:  # swapped channels also look like a unit factor of a few
            _other_force_unit(win.peak / hertz.F_max, Pn / momentum, f_unit, src)
        checks.append(
            _judge("peak_force", win.peak, hertz.F_max, "N", "force", f_unit, src, hint=hint)
        )
    if v_n0 > 0:
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


def _other_force_unit(peak_ratio, impulse_ratio, stated, src) -> None:
    """UnitMismatchError when the peak and the impulse are both off the scene's and both fit
    it once read in another force unit that is not a power of 10³ away (pounds-force under
    a newton header: 4.45×; decanewtons: 10×). The peak alone cannot tell a factor of a few
    from damping or a wrong scene; the two together, each within its band, can."""
    lo_p, hi_p = BANDS["peak_force"]
    lo_i, hi_i = BANDS["impulse"]
    if (
        lo_p <= peak_ratio <= hi_p
        or not np.isfinite(impulse_ratio)
        or lo_i <= impulse_ratio <= hi_i
    ):
        return
    here = force_factor(stated)
    if here is None:
        return
    for unit, factor in FORCE_UNITS.items():
        scale = factor / here
        if abs(math.log10(scale) / 3 - round(math.log10(scale) / 3)) < 1e-9:
            continue  # the same unit or a power of 10³ away: _judge names those
        if lo_p <= peak_ratio * scale <= hi_p and lo_i <= impulse_ratio * scale <= hi_i:
            raise UnitMismatchError(
                f"Fn peaks at {peak_ratio:.3g} and the normal impulse is {impulse_ratio:.3g} of "
                f"what the scene predicts (Hertz, m*·v_n0); both fit once the values are read "
                f"in {unit!r} (×{scale:.4g}), not {stated!r}: a unit mistake. Correct the "
                f"force unit in the header (or pass force_unit={unit!r}) — or, if the file is "
                "right, check the scene",
                quantity="force",
                ratio=peak_ratio,
                suggested=unit,
                path=src,
            )


def _swapped(win, F_max) -> str:
    """A hint when Ft, not Fn, peaks where Hertz theory puts the normal force."""
    if "Ft" not in win.record:
        return ""
    lo, hi = BANDS["peak_force"]
    ft = float(np.max(np.abs(channel(win.record, "Ft")[1])))
    if lo <= win.peak / F_max <= hi or not lo <= ft / F_max <= hi:
        return ""
    return (
        f"; Ft peaks at {ft:.4g} N, which does fit: the normal and tangential columns look "
        "swapped (check the axis map, axes={'Fn': ..., 'Ft': ...})"
    )


def _judge(name, measured, expected, unit, quantity, stated, src, hint="") -> Check:
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
    return _warn(
        name, measured, expected, unit, text + (hint or "; check the scene and the record")
    )


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


# ----------------------------------------------------------------------- after the physics
#: An outcome breaks a bound when it lies this many standard deviations beyond it ...
BOUND_Z = 3.0
#: ... and beyond it by more than this floor (module notes): e_n and the kinetic-energy
#: ratio [-], Pt_f against Pn_f (e_t), the friction cone against μ·Pn [-], and the early
#: Pt against the largest |Pt| (friction direction).
BOUND_FLOOR = {"e_n": 0.02, "e_t": 0.01, "energy": 0.02, "friction_cone": 0.05, "direction": 0.02}
#: Fn → Ft cross-talk allowed for [of Fn]: a sensor record's, a decoupled one's (module notes).
LEAK_BOUND = {"sensor": 0.02, "decoupled": 0.002, "simulated": 0.0}


def check_outcomes(
    scene: Scene, percussions, outcomes, split, window, *, source, sigma, n_baseline=0, mu=None
):
    """The bounds a passive impact's outcome must keep (module notes), checked on a record's
    measured percussions.

    Parameters
    ----------
    scene : Scene — the impact (mass, radius, κ, speeds, spin, target)
    percussions : pipeline.percussion.Percussions
    outcomes : pipeline.analysis.Outcomes — measured e_n, e_t, ω with bootstrap std (NaN
        without a bootstrap)
    split : pipeline.percussion.CompressionSplit — maximum compression (Pn_c, its method)
    window : pipeline.window.ContactWindow
    source : str — which percussions (``"fit"``, ``"trapezoid"``, ``"simpson"``)
    sigma : dict — noise σ of each force channel [N] (``Fn``, ``Ft``)
    n_baseline : int — samples the subtracted baseline was fitted to (0: none subtracted)
    mu : float, optional — the friction coefficient, where it is known independently of
        this record (the scene's, or given): the friction cone is checked against it

    Returns
    -------
    tuple of Check
        ``e_n_bound``, ``e_t_bound``, ``energy``, ``friction_cone``, ``friction_direction``
        (``"skipped"`` where a bound does not apply, with the reason).

    Warns
    -----
    NormalRestitutionWarning, TangentialRestitutionWarning, EnergyGainWarning,
    FrictionBoundWarning, FrictionDirectionWarning
    """
    u = _Uncertainty.of(percussions, outcomes, window, source, sigma, n_baseline)
    Pn = np.asarray(percussions.Pn(source), dtype=float)
    Pt = percussions.Pt(source)
    src = window.record.attrs.get("source", "the record")
    checks = [_e_n_bound(outcomes, float(Pn[-1]), float(split.Pn_c), u, split, src)]
    if Pt is None:
        return tuple(checks + [Check(n, "skipped", note="no Ft channel") for n in _AFTER[1:]])
    Pt = np.asarray(Pt, dtype=float)
    checks.append(_e_t_bound(scene, outcomes, float(Pn[-1]), float(Pt[-1]), u, src))
    checks.append(_energy(scene, float(Pn[-1]), float(Pt[-1]), u, src))
    checks.append(_friction_cone(percussions.time, Pn, Pt, mu, u, src))
    checks.append(_friction_direction(scene, window, percussions.time, Pn, Pt, u, src))
    return tuple(checks)


_AFTER = ("e_n_bound", "e_t_bound", "energy", "friction_cone", "friction_direction")


@dataclass(frozen=True)
class _Uncertainty:
    """What a measured percussion may be off by, on the percussion grid [N·s] per channel:
    ``sd`` its noise (standard deviation), ``spread`` the disagreement of the integration
    rules (systematic: a sparse or poorly fitted record), ``leak`` the Fn → Ft cross-talk
    allowed for [of Fn] (module notes), ``final`` the standard deviations of Pn_f, Pt_f
    (the bootstrap's where it ran, else ``sd``'s last values)."""

    sd: dict
    spread: dict
    leak: float
    final: dict

    @classmethod
    def of(cls, perc, outcomes, window, source, sigma, n_baseline):
        t = perc.time
        dt = np.diff(t)
        step = float(np.median(dt)) if dt.size else 0.0
        n = np.arange(t.size, dtype=float)
        # white noise of σ over n samples (σ·dt·√n), and the baseline's own error σ/√n_b
        # carried over the n samples (σ·dt·n/√n_b)
        grow = np.sqrt(n + (n * n / n_baseline if n_baseline else 0.0))
        sd = {c: float(s) * step * grow for c, s in sigma.items()}
        rules = ("fit", "trapezoid", "simpson") if source == "fit" else ("trapezoid", "simpson")
        spread = {}
        for c, get in (("Fn", perc.Pn), ("Ft", perc.Pt)):
            series = [get(r) for r in rules]
            if series[0] is not None:
                stack = np.asarray(series, dtype=float)
                spread[c] = stack.max(axis=0) - stack.min(axis=0)
        if window.kind == "simulated":
            leak = LEAK_BOUND["simulated"]
        else:
            decoupled = any(str(k).startswith("decouple") for k in window.record.attrs)
            leak = LEAK_BOUND["decoupled" if decoupled else "sensor"]
        final = {}
        for c, key in (("Fn", "Pn_f"), ("Ft", "Pt_f")):
            boot = float(outcomes.std.get(key, math.nan))
            last = float(sd[c][-1]) if c in sd else math.nan
            final[c] = boot if np.isfinite(boot) and boot > 0 else last
        return cls(sd, spread, leak, final)


def _beyond(excess, sd, floor) -> bool:
    """True when ``excess`` > 0 lies beyond the floor (what is systematic: a leak, the
    integration rules' spread, a filter's tail) plus BOUND_Z·sd (the noise)."""
    return bool(excess > floor + (BOUND_Z * sd if np.isfinite(sd) else 0.0))


def _e_n_bound(outcomes, Pn_f, Pn_c, u, split, src) -> Check:
    e_n = float(outcomes.values["e_n"])
    s = float(outcomes.std["e_n"])
    s = s if np.isfinite(s) and s > 0 else math.sqrt(2.0) * u.final["Fn"] / Pn_c
    if not _beyond(e_n - 1.0, s, BOUND_FLOOR["e_n"] + u.spread["Fn"][-1] / Pn_c):
        return Check("e_n_bound", "ok", e_n, 1.0, "1", f"e_n = {e_n:.4g} ≤ 1")
    if split.method == "momentum":
        cause = (
            "maximum compression is where Pn reaches the scene's momentum m*·v_n0, so the "
            "likeliest cause is a force gain or unit too large, or a scene mass or speed too "
            "small (or a second strike merged into the window)"
        )
    else:
        cause = (
            "likeliest cause: a baseline that drifts under the pulse or a second strike merged "
            "into the window (check the window's end)"
        )
    return _warn_bound(
        "e_n_bound",
        e_n,
        1.0,
        "1",
        f"{src}: e_n = {e_n:.4g} (± {s:.2g}): the normal percussion Pn_f = {Pn_f:.4g} N s is "
        f"more than twice the {Pn_c:.4g} N s at maximum compression: the ball left faster than "
        f"it came, which no passive impact does; {cause}",
        NormalRestitutionWarning,
    )


def _e_t_bound(scene, outcomes, Pn_f, Pt_f, u, src) -> Check:
    if float(scene.spin) != 0.0 or float(scene.surface_speed) != 0.0:
        return Check(
            "e_t_bound", "skipped", note="the ball spins or the surface moves: e_t may exceed 1"
        )
    if not float(scene.v_t0) > 0:
        return Check("e_t_bound", "skipped", note="no tangential approach (v_t0 = 0)")
    e_t = float(outcomes.values["e_t"])
    s = u.final["Ft"]
    floor = (BOUND_FLOOR["e_t"] + u.leak) * Pn_f + u.spread["Ft"][-1]
    if not _beyond(-Pt_f, s, floor):
        return Check("e_t_bound", "ok", e_t, 1.0, "1", f"e_t = {e_t:.4g} ≤ 1")
    return _warn_bound(
        "e_t_bound",
        e_t,
        1.0,
        "1",
        f"{src}: e_t = {e_t:.4g} > 1 with no spin and a still surface: the tangential "
        f"percussion Pt_f = {Pt_f:.4g} N s (± {s:.2g}) is negative, so friction sped the ball "
        "up along its slip, which a passive impact cannot do. Likeliest cause: the Ft channel "
        "has the opposite sign convention (Ft > 0 must oppose the initial slip: load it with "
        "axes={'Ft': '-Fx'}), or the scene's angle has the wrong sign",
        TangentialRestitutionWarning,
    )


def _energy(scene, Pn_f, Pt_f, u, src) -> Check:
    """Kinetic energy of the ball after against before, the target fixed: v_n = Pn_f/m −
    v_n0, v_t = v_t0 − σ·Pt_f/m, ω = ω0 + σ·Pt_f·R/I on the scene's axis, σ the sign of the
    initial slip that Pt opposes (docs/theory.md)."""
    if not math.isinf(float(scene.target_mass)):
        return Check(
            "energy", "skipped", note="a target of finite mass: its motion is not measured"
        )
    m, R, kappa = float(scene.m), float(scene.radius), float(scene.kappa)
    inertia = kappa * m * R * R
    v_n0, v_t0, w0 = float(scene.v_n0), float(scene.v_t0), float(scene.spin)
    K0 = 0.5 * m * (v_n0**2 + v_t0**2) + 0.5 * inertia * w0**2
    if not K0 > 0:
        return Check("energy", "skipped", note="the scene brings no kinetic energy")
    sigma = -1.0 if float(scene.slip0) < 0 else 1.0  # Pt opposes the initial slip
    v_n, v_t = Pn_f / m - v_n0, v_t0 - sigma * Pt_f / m
    w = w0 + sigma * Pt_f * R / inertia
    K1 = 0.5 * m * (v_n**2 + v_t**2) + 0.5 * inertia * w**2
    ratio = K1 / K0
    dn, dt = abs(v_n), abs(w * R - v_t)  # ∂K/∂Pn, ∂K/∂Pt
    s = math.hypot(dn * u.final["Fn"], dt * u.final["Ft"]) / K0
    off_t = u.leak * Pn_f + u.spread["Ft"][-1]  # what Pt may be off by, systematically
    floor = BOUND_FLOOR["energy"] + (dn * u.spread["Fn"][-1] + dt * off_t) / K0
    if not _beyond(ratio - 1.0, s, floor):
        return Check("energy", "ok", ratio, 1.0, "1", f"kinetic energy after/before = {ratio:.4g}")
    return _warn_bound(
        "energy",
        ratio,
        1.0,
        "1",
        f"{src}: the ball leaves with {K1:.4g} J of kinetic energy (translation and spin), "
        f"{ratio:.3g} times the {K0:.4g} J it brought: a passive impact cannot give energy. "
        "Likeliest cause: a force gain or unit too large, a scene speed or mass too small, or "
        "the normal and tangential channels swapped (check the axis map)",
        EnergyGainWarning,
    )


def _friction_cone(t, Pn, Pt, mu, u, src) -> Check:
    if mu is None or not np.isfinite(mu):
        return Check("friction_cone", "skipped", note="μ is not known apart from this record")
    Pn_f = float(Pn[-1])
    use = Pn >= 0.1 * Pn_f
    if not use.any() or not Pn_f > 0:
        return Check("friction_cone", "skipped", note="no normal percussion")
    excess = np.abs(Pt) - mu * Pn
    floor = (BOUND_FLOOR["friction_cone"] * mu + u.leak) * Pn
    floor = floor + u.spread["Ft"] + mu * u.spread["Fn"]
    z = np.where(use, excess - floor - BOUND_Z * np.nan_to_num(u.sd["Ft"]), -np.inf)
    k = int(np.argmax(z))
    worst = float(np.max(np.abs(Pt[use]) / Pn[use])) / mu if mu > 0 else math.inf
    if not z[k] > 0:
        return Check("friction_cone", "ok", worst, 1.0, "1", f"max |Pt|/(μ·Pn) = {worst:.3g}")
    ratio = float(abs(Pt[k]) / (mu * Pn[k])) if mu > 0 else math.inf
    return _warn_bound(
        "friction_cone",
        worst,
        1.0,
        "1",
        f"{src}: |Pt| reaches {ratio:.3g}·μ·Pn (μ = {mu:.4g}, known apart from this record) "
        f"at t = {float(t[k]):.6g} s: Coulomb's law allows at most μ·Pn. Likeliest cause: "
        "the scene's μ is too low, Fn leaking into Ft (cross-talk: give the sensor's matrix), "
        "an Ft gain too large, or swapped channels",
        FrictionBoundWarning,
    )


def _friction_direction(scene, window, t, Pn, Pt, u, src) -> Check:
    if float(scene.slip0) == 0.0:
        return Check("friction_direction", "skipped", note="no initial slip")
    tn, fn = channel(window.record, "Fn")
    i = int(np.argmax(fn >= 0.5 * np.max(fn)))
    k = int(np.clip(np.searchsorted(t, tn[i]), 0, t.size - 1))
    early = float(Pt[k])
    s = float(u.sd["Ft"][k])
    floor = BOUND_FLOOR["direction"] * float(np.max(np.abs(Pt)))
    floor += u.leak * float(Pn[k]) + float(u.spread["Ft"][k])
    if not _beyond(-early, s, floor):
        return Check(
            "friction_direction", "ok", early, 0.0, "N s", f"Pt = {early:.4g} N s ≥ 0 early on"
        )
    return _warn_bound(
        "friction_direction",
        early,
        0.0,
        "N s",
        f"{src}: when Fn first reaches half its peak (t = {float(t[k]):.6g} s) the tangential "
        f"percussion is {early:.4g} N s (± {s:.2g}), against the slip: friction pushed the ball "
        "along its slip from the start, and no tangential compliance reverses the force that "
        "early. Likeliest cause: the Ft channel has the opposite sign convention (Ft > 0 must "
        "oppose the initial slip: load it with axes={'Ft': '-Fx'})",
        FrictionDirectionWarning,
    )


def _warn_bound(name, measured, bound, unit, text, category) -> Check:
    warnings.warn(text, category, stacklevel=4)
    return Check(name, "warning", float(measured), float(bound), unit, text)
