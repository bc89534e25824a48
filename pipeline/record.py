"""The record: one impact's force history as an :class:`xarray.Dataset`.

Every reader (:mod:`pipeline.io`) and the simulator (:mod:`pipeline.simulate`) return
this layout, and every later stage reads it:

- coordinate ``time`` [s], strictly increasing and finite;
- variables ``Fn`` (normal force, > 0 compressive) and ``Ft`` (tangential force, > 0
  opposing the initial slip) [N], and ``Fy`` (out-of-plane) [N] where measured;
- each variable carries ``attrs["units"]``;
- dataset ``attrs``: ``source`` (file name or generator), ``sha256`` (of the raw bytes,
  "" when there is no file), ``format`` (reader or generator name), ``kind``
  (``"sensor"``, ``"digitised"`` or ``"simulated"``) and the scene fields that were given
  (as numbers, under their :class:`~pipeline.Scene` field names).

Digitised records (WebPlotDigitizer) sample Fn and Ft at different instants. The record
keeps every digitised point: ``time`` is the sorted union of both channels' instants, and
boolean variables ``Fn_measured``/``Ft_measured`` mark which instants each channel was
digitised at. Between its own points a channel is linearly interpolated; outside its own
digitised span it is NaN. Fits and integrals use each channel's measured points only
(``record.Fn[record.Fn_measured]``). Forces must be finite wherever they were measured.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import xarray as xr

from .errors import InputError

__all__ = [
    "adc_step",
    "make_record",
    "validate",
    "channel",
    "FORCE_CHANNELS",
    "KINDS",
    "FORCE_RANGE",
    "TIME_RANGE",
    "TIME_RESOLUTION",
]

FORCE_CHANNELS = ("Fn", "Ft", "Fy")
KINDS = ("sensor", "digitised", "simulated")

#: Range of a record's largest |force| [N] (a record of zeros excepted). Far beyond any
#: sensor (atomic-force microscopes resolve ~1e-12 N, crash rigs measure ~1e7 N), and far
#: inside the floats: squares, sums over 10⁸ samples and products with times stay finite
#: and normal, so nothing later overflows to inf or underflows to 0.
FORCE_RANGE = (1e-20, 1e20)
#: Range of a record's time steps and instants [s]: the smallest step at least 1e-20 s
#: (no digitiser samples faster than ~1e-11 s), no instant beyond ±1e20 s.
TIME_RANGE = (1e-20, 1e20)
#: The coarsest resolution of a record's instants, as a share of its smallest step: an
#: instant of 3.5e9 s (an absolute clock) is held to 4.8e-7 s, half a 1 MHz step.
TIME_RESOLUTION = 1e-3

_LONG_NAMES = {
    "Fn": "normal force (compressive > 0)",
    "Ft": "tangential force (> 0 opposing the initial slip)",
    "Fy": "out-of-plane force",
}


def make_record(
    time,
    forces: dict,
    *,
    attrs: dict | None = None,
    measured: dict | None = None,
    extra: dict | None = None,
) -> xr.Dataset:
    """Assemble a record from arrays already in SI units.

    Parameters
    ----------
    time : array_like
        Sample instants [s].
    forces : dict
        ``{"Fn": array, "Ft": array, ["Fy": array]}`` [N], each the length of ``time``.
    attrs : dict, optional
        Dataset attributes (``source``, ``sha256``, ``format``, ``kind``, scene fields...).
    measured : dict, optional
        ``{"Fn": bool array, ...}`` for digitised records (see module notes).
    extra : dict, optional
        Further variables on ``time``: ``{name: (array, units, long_name)}``.

    Returns
    -------
    xarray.Dataset
        The record; :func:`validate` has been applied.
    """
    t = np.asarray(time, dtype=float)
    data_vars = {}
    for name, values in forces.items():
        if name not in FORCE_CHANNELS:
            raise InputError(f"unknown force channel {name!r}; expected one of {FORCE_CHANNELS}")
        data_vars[name] = time_variable(
            np.asarray(values, dtype=float), {"units": "N", "long_name": _LONG_NAMES[name]}
        )
    for name, mask in (measured or {}).items():
        data_vars[f"{name}_measured"] = time_variable(
            np.asarray(mask, dtype=bool), {"long_name": f"instants at which {name} was digitised"}
        )
    for name, (values, units, long_name) in (extra or {}).items():
        data_vars[name] = time_variable(
            np.asarray(values, dtype=float), {"units": units, "long_name": long_name}
        )
    ds = xr.Dataset(
        data_vars,
        coords={"time": time_variable(pd.Index(t), {"units": "s", "long_name": "time"})},
        attrs=dict(attrs or {}),
    )
    ds.attrs.setdefault("sha256", "")
    validate(ds)
    return ds


def time_variable(values: np.ndarray | pd.Index, attrs: dict) -> xr.Variable:
    """A variable on ``time`` from a NumPy array of floats or booleans (the coordinate: a
    pandas Index of them), built as xarray builds its own, without its probe for duck
    arrays: that probe (``array_type("dask")`` on a new Variable's data, and
    ``is_duck_dask_array`` on a new index's) imports dask wherever it is installed, ~0.3 s
    of a first fit's, though a record is NumPy throughout. A process that uses dask imports
    it as before (tests/test_imports.py)."""
    return xr.Variable(("time",), values, attrs, fastpath=True)


def times(record: xr.Dataset) -> np.ndarray:
    """The record's instants [s], read from its time index (read-only; xarray's own read of
    the coordinate converts the index anew each time, at tens of µs a read)."""
    index = record.xindexes.get("time")
    t = (record.variables["time"].values if index is None else index.index.values).view()
    t.flags.writeable = False  # a view: the record's own instants
    return t


def channel(record: xr.Dataset, name: str, t=None) -> tuple[np.ndarray, np.ndarray]:
    """The instants [s] and values [N] at which channel ``name`` was actually measured
    (``t``: the record's instants, :func:`times`, where read already)."""
    if t is None:
        t = times(record)
    f = record.variables[name].values
    mask_name = f"{name}_measured"
    if mask_name in record:
        m = record.variables[mask_name].values.astype(bool)
        return t[m], f[m]
    return t, f


def validate(record: xr.Dataset) -> xr.Dataset:
    """Check a record's invariants; return it unchanged or raise :class:`InputError`.

    Checks: a ``time`` coordinate in seconds, finite and strictly increasing, with at least
    two samples, steps and instants within :data:`TIME_RANGE`, instants that double precision
    holds to :data:`TIME_RESOLUTION` of the smallest step; an ``Fn`` variable; every
    force variable in newtons, finite wherever it was measured, its largest magnitude zero
    or within :data:`FORCE_RANGE`; the ``source``, ``sha256`` and ``format`` attributes
    present. The two ranges keep every later stage inside the floats: a file whose forces
    are 1e300 N or whose time steps are 1e-300 s (a unit gone wrong) is refused here, never
    turned into an inf or a 0 further down.
    """
    src = record.attrs.get("source", "<record>")
    if "time" not in record.coords:
        raise InputError("record has no 'time' coordinate", path=src)
    t = record.variables["time"].values
    if record["time"].attrs.get("units") != "s":
        raise InputError("record time must carry units 's'", path=src)
    if t.ndim != 1 or t.size < 2:
        raise InputError(f"record needs at least 2 samples, has {t.size}", path=src)
    if not np.all(np.isfinite(t)):
        raise InputError("record time has NaN or infinite values", path=src)
    steps = np.diff(t)
    if np.any(steps <= 0):
        i = int(np.argmax(steps <= 0))
        raise InputError(
            f"time does not strictly increase at sample {i + 1} "
            f"({t[i]!r} s then {t[i + 1]!r} s); sort or de-duplicate the samples",
            path=src,
        )
    if steps.min() < TIME_RANGE[0] or max(abs(t[0]), abs(t[-1])) > TIME_RANGE[1]:
        i = int(np.argmin(steps))
        raise InputError(
            f"time steps of {steps[i]:.3g} s (samples {i} to {i + 1}) over instants up to "
            f"{max(abs(t[0]), abs(t[-1])):.3g} s lie outside what any digitiser records "
            f"(steps ≥ {TIME_RANGE[0]:g} s, instants within ±{TIME_RANGE[1]:g} s): the "
            "time unit is wrong; correct it in the file's header or with time_unit=",
            path=src,
        )
    span = max(abs(t[0]), abs(t[-1]))
    if np.spacing(span) > TIME_RESOLUTION * steps.min():
        raise InputError(
            f"time instants up to {span:.10g} s are held (in double precision) only to "
            f"{np.spacing(span):.2g} s, too coarse for steps of {steps.min():.3g} s: the "
            "samples' spacing is lost; export time relative to the record's start (an "
            "absolute clock, such as LabVIEW's seconds since 1904 or a Unix time, cannot "
            "be read to that step)",
            path=src,
        )
    if "Fn" not in record:
        raise InputError("record has no normal-force channel 'Fn'", path=src)
    for name in FORCE_CHANNELS:
        if name not in record:
            continue
        var = record[name]
        if var.attrs.get("units") != "N":
            raise InputError(f"record variable {name} must carry units 'N'", path=src)
        _, values = channel(record, name)
        bad = ~np.isfinite(values)
        if bad.any():
            raise InputError(
                f"{name} has {int(bad.sum())} NaN or infinite values (first at measured "
                f"sample {int(np.argmax(bad))}); remove or repair those samples",
                path=src,
            )
        peak = float(np.max(np.abs(values))) if values.size else 0.0
        if peak != 0.0 and not FORCE_RANGE[0] <= peak <= FORCE_RANGE[1]:
            raise InputError(
                f"{name} peaks at |{name}| = {peak:.3g} N, outside what any force sensor "
                f"measures ({FORCE_RANGE[0]:g} to {FORCE_RANGE[1]:g} N); the force unit or "
                "scale is wrong: correct it in the file's header or with force_unit=",
                path=src,
            )
    for key in ("source", "sha256", "format"):
        if key not in record.attrs:
            raise InputError(f"record lacks the {key!r} attribute", path=src)
    return record


def adc_step(values) -> float:
    """Step of the grid the values lie on [same unit], 0 when they lie on none.

    The greatest common divisor q of the gaps between distinct values (Euclid's algorithm
    in floating point, remainders within 1e-9 of the values' scale counted as zero),
    accepted when every gap is a whole multiple of q to 1e-3 of q and q is coarser than
    1e-6 of the scale: the ADC quantum of a raw converter output, or the printed resolution
    of a file's column. A smooth pulse sampled 200 times leaves gaps of 5q, 16q, 27q, ...
    whose smallest is not the step. Needs three distinct values.
    """
    u = np.unique(np.asarray(values, dtype=float))
    u = u[np.isfinite(u)]
    if u.size < 3:
        return 0.0
    gaps = np.unique(np.diff(u))
    scale = float(np.max(np.abs(u)))
    tol = 1e-9 * scale
    q = float(gaps[0])
    for g in gaps[1:256]:  # a few hundred gaps pin the divisor down
        a, b = float(g), q
        while b > tol:
            r = math.fmod(a, b)
            a, b = b, (0.0 if r < tol or b - r < tol else r)
        q = a
        if q <= 1e-6 * scale:
            return 0.0
    k = gaps / q
    return q if np.all(np.abs(k - np.round(k)) < 1e-3) else 0.0
