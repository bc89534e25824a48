"""NI TDMS files (LabVIEW / NI DAQ), read with npTDMS (the ``tdms`` extra).

A TDMS file holds groups of channels. The reader takes the group whose channels are named
like forces (``Fn``, ``Ft``, ``Fx``, ``Fy``, ``Fz``, optionally with a unit, ``Fz (kN)``),
or the group named by ``group=``. Tri-axial channels map as in the sensor CSV (Fz → Fn,
Fx → Ft, Fy → Fy; ``axes=`` overrides, see :mod:`pipeline.io.sensor`).

Time: a channel named ``time`` (or ``t``) in the group when there is one (unit from its
``unit_string`` property); otherwise the waveform properties of the force channels —
``wf_start_offset`` + k·``wf_increment`` for k < ``wf_samples`` (npTDMS's
``channel.time_track()``), in ``wf_xunit_string`` (when absent: ``time_unit=``, else NI's
default, seconds). All force
channels must share one time track. Units come from each channel's ``unit_string``
property, or else from a unit in its name (``Fz (kN)``; a name and a property that disagree
are an error); ``force_unit=``/``time_unit=`` supply one where the file has none. Two
channels that read as the same force (``Fz`` and ``Fz (raw)``) are an error; among several
time-named channels, one whose unit is not a time unit (a temperature ``T`` in degC) is
not the time track.
"""

from __future__ import annotations

import io
import logging

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
    read_decoupling,
    read_raw,
    resolve_axes,
    scene_attrs,
    to_newtons,
)
from .sensitivity import by_column, parse_sensitivity, sensitivity_attr
from .units import resolve_force, resolve_unit, signal_factor, split_unit, time_factor

__all__ = ["read_tdms"]


def _open(raw: bytes, p):
    try:
        from nptdms import TdmsFile
    except ImportError as exc:  # pragma: no cover - the tdms extra is installed in dev
        raise InputError("reading TDMS needs npTDMS: pip install 'pipeline[tdms]'", path=p) from exc
    if not raw.startswith(b"TDSm"):
        raise InputError(
            "not a TDMS file (it does not start with the 'TDSm' tag); export the "
            "measurement as .tdms again",
            path=p,
        )
    # npTDMS reads what it can of a truncated file and only logs a warning: catch those
    # warnings, a shortened record must not pass as a whole one.
    log = logging.getLogger("nptdms")
    caught = _Collect()
    log.addHandler(caught)
    console = _nptdms_console()
    level = console.level if console is not None else None
    if console is not None:
        console.setLevel(logging.CRITICAL + 1)  # the library does not print; we report
    try:
        tdms = TdmsFile.read(io.BytesIO(raw))
    except Exception as exc:  # npTDMS raises many types on a corrupt file
        raise InputError(
            f"cannot read this TDMS file ({type(exc).__name__}: {exc}); it is corrupt or "
            "truncated — copy it again from the acquisition PC",
            path=p,
        ) from exc
    finally:
        log.removeHandler(caught)
        if console is not None:
            console.setLevel(level)
    if caught.messages:
        raise InputError(
            f"this TDMS file is truncated or corrupt (npTDMS: {caught.messages[0]}); copy it "
            "again from the acquisition PC",
            path=p,
        )
    return tdms


def _nptdms_console():
    try:
        from nptdms.log import log_manager

        return log_manager.console_handler
    except (ImportError, AttributeError):  # pragma: no cover - npTDMS internals changed
        return None


class _Collect(logging.Handler):
    """Warnings npTDMS logs while reading: truncation, cropped data, unsupported scaling,
    version mismatch. A string property that is not UTF-8 (decoded with replacement
    characters, logged by ``nptdms.types``) does not make the data wrong and is let pass."""

    def __init__(self):
        super().__init__(level=logging.WARNING)
        self.messages = []

    def emit(self, record):
        if not record.name.startswith("nptdms.types"):
            self.messages.append(record.getMessage())


def _columns(group, p):
    """``{canonical name: channel}`` and the time channel (or None) of a group.

    Two channels for one force (``Fz`` and ``Fz (raw)``) are an error, not a silent pick.
    Among several time-named channels, one whose unit is not a time unit (a temperature
    ``T`` in degC) is not the time track.
    """
    forces, times = {}, []
    for ch in group.channels():
        base, _ = split_unit(ch.name)
        canon = canonical_column(base)
        if canon == "time":
            times.append(ch)
        elif canon in FORCE_COLUMNS:
            if canon in forces:
                raise InputError(
                    f"channels {forces[canon].name!r} and {ch.name!r} of group {group.name!r} "
                    f"both read as {canon}; rename one of them or export only one",
                    path=p,
                )
            forces[canon] = ch
    if len(times) > 1:
        times = [ch for ch in times if _is_time_track(ch)] or times
    if len(times) > 1:
        raise InputError(
            f"several time channels in group {group.name!r} "
            f"({', '.join(repr(ch.name) for ch in times)}); keep one",
            path=p,
        )
    return forces, (times[0] if times else None)


def _is_time_track(ch) -> bool:
    """A timestamp channel, or one whose unit (if any) is a time unit."""
    if np.issubdtype(ch.dtype, np.datetime64):
        return True
    unit = _unit(ch, "time")
    return unit is None or time_factor(unit) is not None


def _unit(ch, kind, p=None):
    """Unit of a channel: its ``unit_string`` property, else a unit in its name
    (``Fz (kN)``) when that is a recognised ``kind`` unit; a clash between the two is an
    InputError (when ``p`` is given)."""
    factor_of = time_factor if kind == "time" else signal_factor
    prop = _prop(ch, "unit_string") or None
    _, named = split_unit(ch.name)
    if named is not None and factor_of(named) is None:
        named = None  # "Fz (raw)": a label, not a unit
    if p is not None and prop and named and factor_of(prop) not in (None, factor_of(named)):
        raise InputError(
            f"the channel name gives {kind} in {named!r} but its unit_string property says "
            f"{prop!r}; correct one of them",
            path=p,
            column=ch.name,
        )
    return prop or named


def _prop(ch, name, default=None):
    value = ch.properties.get(name, default)
    if isinstance(value, bytes):
        value = value.decode("utf-8", "replace")
    return value


def read_tdms(
    path,
    *,
    time_unit=None,
    force_unit=None,
    axes=None,
    group=None,
    decouple=None,
    sensitivity=None,
    **scene_fields,
):
    """Read an NI TDMS file into a record.

    Parameters
    ----------
    path : str or os.PathLike
        The ``.tdms`` file.
    time_unit, force_unit : str, optional
        Units where the file has none (``unit_string`` / ``wf_xunit_string`` missing);
        a unit in the file wins and a contradicting argument is an error.
    axes : dict, optional
        Record channel → TDMS channel, sign by a leading ``-`` (as for the sensor CSV).
    group : str, optional
        The group to read when several hold force channels.
    decouple : array_like or path, optional
        The sensor's 3×3 decoupling matrix (see :func:`pipeline.io.read_decoupling`),
        applied to the raw (Fx, Fy, Fz) in N before the axis map.
    sensitivity : dict, optional
        ``{"Fn": (0.225, "mV/N")}`` for channels whose ``unit_string`` is volts (see
        :mod:`pipeline.io.sensitivity`); recorded in ``attrs["sensitivity"]``.
    **scene_fields : float
        Scene fields stored in the attributes (names as :class:`pipeline.Scene`).

    Returns
    -------
    xarray.Dataset
        The record (``format="tdms"``, ``kind="sensor"``), SI units.

    Raises
    ------
    InputError
        Not a TDMS file, corrupt, no force channels, no time track, mismatched lengths,
        bad units, NaN/inf, time not strictly increasing.
    """
    scene = scene_attrs(scene_fields)
    matrix, decouple_attrs = (None, {}) if decouple is None else read_decoupling(decouple)
    sens = parse_sensitivity(sensitivity)
    p, raw, sha = read_raw(path)
    tdms = _open(raw, p)
    try:
        groups = tdms.groups()
        candidates = [(g, *_columns(g, p)) for g in groups]
    except InputError:
        raise
    except Exception as exc:
        raise InputError(f"cannot list the TDMS channels ({exc})", path=p) from exc
    listing = (
        "; ".join(
            f"{g.name}: {', '.join(c.name for c in g.channels()) or '-'}" for g, _, _ in candidates
        )
        or "no groups"
    )
    if group is not None:
        found = [c for c in candidates if c[0].name == group]
        if not found:
            raise InputError(f"no group {group!r} (groups and channels: {listing})", path=p)
    else:
        found = [c for c in candidates if c[1]]
        if not found:
            raise InputError(
                f"no force channels (named Fn/Ft or Fx/Fy/Fz) in any group ({listing})", path=p
            )
        if len(found) > 1:
            raise InputError(
                "several groups hold force channels; call pipeline.io.read_tdms(path, "
                f"group=...) ({listing})",
                path=p,
            )
    g, force_chs, time_ch = found[0]
    chosen = resolve_axes(force_chs, axes, p)
    feeds = {col: name for name, (col, _) in chosen.items()}
    needed = [col for col, _ in chosen.values()]
    if matrix is not None:
        missing = [c for c in DECOUPLE_AXES if c not in force_chs]
        if missing:
            raise InputError(
                f"decouple= needs the raw Fx, Fy and Fz channels; group {g.name!r} has no "
                f"{', '.join(missing)}",
                path=p,
            )
        needed += [c for c in DECOUPLE_AXES if c not in needed]
    col_sens = by_column(
        sens, chosen, list(force_chs), p, read=needed, label=lambda c: force_chs[c].name
    )
    try:
        data = {col: np.asarray(force_chs[col][:], dtype=float) for col in needed}
    except (TypeError, ValueError) as exc:
        raise InputError(f"force channels are not numeric ({exc})", path=p) from exc
    lengths = {col: v.size for col, v in data.items()}
    if len(set(lengths.values())) != 1:
        raise InputError(
            f"force channels have different lengths {lengths}; they must share one time track",
            path=p,
        )
    n = next(iter(lengths.values()))
    if time_ch is not None:
        where = f"time channel {time_ch.name!r}"
        values = np.asarray(time_ch[:])
        if np.issubdtype(values.dtype, np.datetime64):
            # absolute timestamps: seconds since the first sample
            if values.size and np.isnat(values).any():
                raise InputError(f"the {where} has missing timestamps", path=p)
            t_raw = (values - values[:1]) / np.timedelta64(1, "ns") * 1e-9
            if time_unit not in (None, "s"):
                raise InputError(
                    f"the {where} holds timestamps; drop time_unit={time_unit!r}", path=p
                )
            t_factor, t_unit = 1.0, "s"
        else:
            try:
                t_raw = values.astype(float)
            except (TypeError, ValueError) as exc:
                raise InputError(f"time channel is not numeric ({exc})", path=p) from exc
            t_factor, t_unit = resolve_unit(
                "time", _unit(time_ch, "time", p), time_unit, path=p, column=time_ch.name
            )
    else:
        tracks = []
        for col, _ in chosen.values():
            ch = force_chs[col]
            if "wf_increment" not in ch.properties:
                raise InputError(
                    f"channel {ch.name!r} has no time track: no 'time' channel in group "
                    f"{g.name!r} and no waveform properties (wf_increment)",
                    path=p,
                )
            try:
                tracks.append(np.asarray(ch.time_track(), dtype=float))
            except Exception as exc:
                raise InputError(
                    f"bad waveform properties on channel {ch.name!r} ({exc})", path=p
                ) from exc
        t_raw = tracks[0]
        if any(tr.shape != t_raw.shape or not np.array_equal(tr, t_raw) for tr in tracks[1:]):
            raise InputError(
                "force channels have different time tracks (wf_start_offset/wf_increment); "
                "they must be sampled together",
                path=p,
            )
        ch0 = force_chs[next(iter(chosen.values()))[0]]
        # no wf_xunit_string: time_unit= supplies it, else NI's default, seconds
        xunit = _prop(ch0, "wf_xunit_string") or (None if time_unit is not None else "s")
        t_factor, t_unit = resolve_unit("time", xunit, time_unit, path=p, column=ch0.name)
        where = "waveform time track"
    if t_raw.size != n:
        raise InputError(f"the {where} has {t_raw.size} samples but the force channels {n}", path=p)
    if n == 0:
        raise InputError("the force channels are empty", path=p)
    if n == 1:
        raise InputError("a single sample: a record needs at least two", path=p)
    t = t_raw * t_factor
    if not np.all(np.isfinite(t)):
        raise InputError(f"the {where} has NaN or infinite values", path=p)
    if (step := first_non_increase(t)) is not None:
        i, verb = step
        raise InputError(
            f"time {verb} at sample {i + 1} ({float(t_raw[i])!r} then "
            f"{float(t_raw[i + 1])!r} {t_unit}) in the {where}; time must strictly increase",
            path=p,
        )
    si, units = {}, {}
    for col in needed:
        ch = force_chs[col]
        factor, unit = resolve_force(
            _unit(ch, "force", p),
            force_unit,
            col_sens.get(col),
            path=p,
            column=ch.name,
            channel=feeds.get(col),
        )
        units[col] = unit
        values = data[col]
        bad = ~np.isfinite(values)
        if bad.any():
            i = int(np.argmax(bad))
            raise InputError(
                f"force value {float(values[i])!r} at sample {i} is NaN or infinite; repair the "
                "channel or cut the record",
                path=p,
                column=ch.name,
            )
        si[col] = to_newtons(values, factor, p, ch.name)
    if matrix is not None:  # cross-talk: corrected = M @ raw (Fx, Fy, Fz), in N
        si = decouple_columns(si, matrix, p)
    forces = {name: si[col] * sign for name, (col, sign) in chosen.items()}
    units = {units[col] for col, _ in chosen.values()}
    check_plane(forces, p)
    attrs = base_attrs(p, sha, "tdms", "sensor")
    attrs["source_time_unit"] = t_unit
    attrs["source_force_unit"] = ",".join(sorted(units))
    attrs["tdms_group"] = g.name
    if col_sens:
        attrs["sensitivity"] = sensitivity_attr(
            {feeds.get(c, force_chs[c].name): s for c, s in col_sens.items()}
        )
    attrs.update(decouple_attrs)
    attrs["axes"] = ",".join(
        f"{name}={'-' if sign < 0 else ''}{force_chs[col].name}"
        for name, (col, sign) in chosen.items()
    )
    attrs.update(scene)
    return make_record(t, forces, attrs=attrs)
