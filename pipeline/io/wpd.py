"""WebPlotDigitizer exports: digitised force curves.

Two layouts are read (WebPlotDigitizer 4.x, "View data" → "Download .CSV"):

**Single dataset** — no header, one ``x,y`` row per click, in click order::

    0.0123,45.6
    0.0051, 12.3

(``x, y`` with a space is also written; in decimal-comma locales the separator is ``;`` and
the decimals commas: ``0,0123;45,6``). Rows are sorted by ``x``. The file holds one channel;
which one is given by ``channels="Fn"`` (or ``"Ft"``, ``"Fy"``) or, when not given, guessed
from the file name (``Fn.csv``, ``normal_force.csv``, ``wpd_ft.csv``...; see
:data:`CHANNEL_SPELLINGS`). Two single exports are combined by passing both:
``read_wpd({"Fn": "fn.csv", "Ft": "ft.csv"}, ...)`` or ``read_wpd(["fn.csv", "ft.csv"])``
(channels from the file names, or ``channels=["Fn", "Ft"]``).

**"Export all"** (``wpd_datasets.csv``) — row 1 holds the dataset names in the X columns
(blanks in the Y columns), row 2 ``X,Y,X,Y,...``, then the points; shorter datasets are
padded with blank cells::

    Fn,,Ft,
    X,Y,X,Y
    0.01,12.1,0.012,3.1
    0.02,40.0,,

Datasets map to channels by name (case-insensitive, common spellings: ``Fn``, ``F_n``,
``normal``, ``normal force``; ``Ft``, ``tangential``, ``friction``...);
``channels={"Fn": "dataset name", "Ft": "..."}`` overrides. Unmapped datasets are listed
in the attribute ``ignored_datasets``.

Digitised files carry no units: ``time_unit=`` (the plot's x axis, e.g. ``"ms"``) and
``force_unit=`` (its y axis, e.g. ``"N"``) are required.

The record keeps every digitised point (:mod:`pipeline.record`): ``time`` is the sorted
union of all channels' instants, ``Fn_measured``/``Ft_measured`` mark each channel's own
points, values between a channel's points are linear interpolations and outside its span
NaN. Two clicks of one dataset at the same ``x`` are an error (time must strictly
increase): delete one of them, nothing is averaged.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..record import FORCE_CHANNELS, make_record
from ._common import LINE_END, NONFINITE, NUMBER, base_attrs, decode, read_raw, scene_attrs
from .units import resolve_unit

__all__ = ["read_wpd", "CHANNEL_SPELLINGS"]

#: Dataset names (lower-cased, spaces, '_' and '-' removed) understood for each channel.
CHANNEL_SPELLINGS = {
    "Fn": {"fn", "normal", "normalforce", "forcenormal", "fnormal"},
    "Ft": {
        "ft",
        "tangential",
        "tangentialforce",
        "forcetangential",
        "ftangential",
        "friction",
        "frictionforce",
        "ff",
        "ffriction",
        "shear",
        "shearforce",
    },
    "Fy": {"fy", "outofplane", "outofplaneforce", "lateral", "lateralforce"},
}

_UNIT_HINT = {
    "time": " — the unit of the digitised plot's x axis, e.g. time_unit='ms'",
    "force": " — the unit of the digitised plot's y axis, e.g. force_unit='N'",
}


def _squash(name: str) -> str:
    return re.sub(r"[\s_\-.]+", "", name).lower()


def _channel_of(name: str) -> str | None:
    key = _squash(name)
    for channel, spellings in CHANNEL_SPELLINGS.items():
        if key in spellings:
            return channel
    return None


def _channel_from_filename(p: Path) -> str | None:
    stem = p.stem
    tokens = re.findall(r"[A-Za-z]+", stem)  # "wpd_Fn1" -> wpd, Fn
    candidates = {stem, *tokens}
    candidates |= {a + b for a, b in zip(tokens, tokens[1:], strict=False)}
    found = {_channel_of(c) for c in candidates if len(_squash(c)) > 1} - {None}
    return found.pop() if len(found) == 1 else None


# --------------------------------------------------------------------------- cells
def _number(cell: str, dec: str, p: Path, lineno: int, column: str, what: str) -> float:
    c = cell.strip().strip('"').strip()
    if dec == ",":
        if "." in c:
            raise InputError(
                f"cell {cell.strip()!r} has a decimal point in a decimal-comma file",
                path=p,
                line=lineno,
                column=column,
            )
        c = c.replace(",", ".")
    if NUMBER.match(c) and np.isfinite(value := float(c)):
        return value
    if NONFINITE.match(c) or NUMBER.match(c):  # NaN, inf, or a number past float range
        raise InputError(
            f"{what} value {cell.strip()!r} is NaN or infinite; delete or repair this point",
            path=p,
            line=lineno,
            column=column,
        )
    raise InputError(
        f"cell {cell.strip()!r} is not a number; delete or repair this point",
        path=p,
        line=lineno,
        column=column,
    )


def _lines(text: str):
    """(1-based line number, line) of the non-blank lines."""
    return [(k + 1, line) for k, line in enumerate(LINE_END.split(text)) if line.strip()]


def _dialect(lines) -> tuple[str, str]:
    """(separator, decimal mark) of a WPD export: ``;`` + decimal comma, or ``,`` + point."""
    if any(";" in line for _, line in lines):
        return ";", ("," if any("," in line for _, line in lines) else ".")
    if any("\t" in line for _, line in lines):
        return "\t", "."
    return ",", "."


def _sorted_points(x, y, linenos, p: Path, dataset: str):
    x, y, linenos = np.asarray(x, float), np.asarray(y, float), np.asarray(linenos)
    if x.size == 0:
        raise InputError(
            f"dataset {dataset!r} has no points; digitise it or delete its two columns", path=p
        )
    if x.size == 1:
        raise InputError(
            f"dataset {dataset!r} has a single point; a channel needs at least two",
            path=p,
            line=int(linenos[0]),
        )
    order = np.argsort(x, kind="stable")
    x, y, linenos = x[order], y[order], linenos[order]
    dup = np.flatnonzero(np.diff(x) == 0)
    if dup.size:
        i = int(dup[0])
        a, b = sorted((int(linenos[i]), int(linenos[i + 1])))
        raise InputError(
            f"dataset {dataset!r} has two points at x = {float(x[i])!r} (lines {a} and {b}); time "
            "must strictly increase: delete one of the two clicks",
            path=p,
            line=b,
        )
    return x, y


# ------------------------------------------------------------------------- parsers
def _parse_single(text: str, p: Path):
    """Points of a single-dataset export: ``(x, y)`` sorted by x."""
    lines = _lines(text)
    if not lines:
        raise InputError("file is empty; export the dataset again", path=p)
    sep, dec = _dialect(lines)
    xs, ys, nos = [], [], []
    for lineno, line in lines:
        cells = line.split(sep)
        if len(cells) != 2:
            raise InputError(
                f"has {len(cells)} fields; a WebPlotDigitizer single-dataset export has two "
                "(x, y) per line",
                path=p,
                line=lineno,
            )
        xs.append(_number(cells[0], dec, p, lineno, "1 (x)", "time"))
        ys.append(_number(cells[1], dec, p, lineno, "2 (y)", "force"))
        nos.append(lineno)
    return _sorted_points(xs, ys, nos, p, p.name)


def _parse_datasets(text: str, p: Path) -> dict:
    """Datasets of an "export all" file: ``{name: (x, y)}``, each sorted by x."""
    lines = _lines(text)
    if len(lines) < 2:
        raise InputError(
            "an 'export all' file needs a row of dataset names and an 'X,Y,...' row", path=p
        )
    sep, dec = _dialect(lines[1:])  # not the names row: a name may hold ';' or ','
    (l1, names_line), (l2, xy_line) = lines[0], lines[1]
    heads = [c.strip().strip('"').strip() for c in names_line.split(sep)]
    xy = [c.strip().strip('"').strip().upper() for c in xy_line.split(sep)]
    ncols = len(xy)
    if ncols < 2 or ncols % 2 or xy != ["X", "Y"] * (ncols // 2):
        raise InputError(
            f"second row should read X,Y,X,Y,... (got {xy_line.strip()!r})", path=p, line=l2
        )
    heads += [""] * (ncols - len(heads))
    if len(heads) > ncols and any(heads[ncols:]):
        raise InputError("more dataset names than X,Y column pairs", path=p, line=l1)
    names = [heads[2 * k] for k in range(ncols // 2)]
    for k, name in enumerate(names):
        if not name:
            raise InputError(f"dataset in column {2 * k + 1} has no name", path=p, line=l1)
        if heads[2 * k + 1]:
            raise InputError(
                f"a dataset name {heads[2 * k + 1]!r} sits in a Y column; names go in the X "
                "columns",
                path=p,
                line=l1,
                column=2 * k + 2,
            )
    if len(set(names)) != len(names):
        raise InputError(f"two datasets share a name ({names}); rename one", path=p, line=l1)
    points = {name: ([], [], []) for name in names}
    for lineno, line in lines[2:]:
        cells = line.split(sep)
        if len(cells) > ncols and any(c.strip() for c in cells[ncols:]):
            raise InputError(
                f"has {len(cells)} fields but the X,Y row has {ncols}", path=p, line=lineno
            )
        cells += [""] * (ncols - len(cells))
        for k, name in enumerate(names):
            cx, cy = cells[2 * k].strip(), cells[2 * k + 1].strip()
            if not cx and not cy:
                continue
            if not cx or not cy:
                raise InputError(
                    f"dataset {name!r} has an x without a y (or a y without an x)",
                    path=p,
                    line=lineno,
                    column=2 * k + (2 if not cy else 1),
                )
            xs, ys, nos = points[name]
            xs.append(_number(cx, dec, p, lineno, 2 * k + 1, "time"))
            ys.append(_number(cy, dec, p, lineno, 2 * k + 2, "force"))
            nos.append(lineno)
    return {name: _sorted_points(*pts, p, name) for name, pts in points.items()}


def is_datasets_text(text: str) -> bool:
    """True when the second non-blank line reads ``X,Y[,X,Y...]`` (an "export all" file)."""
    lines = _lines(text[:65536])
    if len(lines) < 2:
        return False
    line = lines[1][1]
    for sep in (";", "\t", ","):
        cells = [c.strip().strip('"').strip().upper() for c in line.split(sep)]
        if len(cells) >= 2 and len(cells) % 2 == 0 and cells == ["X", "Y"] * (len(cells) // 2):
            return True
    return False


# -------------------------------------------------------------------------- record
def _map_datasets(datasets: dict, channels, p: Path) -> dict:
    """Channel → dataset name."""
    listed = ", ".join(repr(n) for n in datasets)
    if channels is not None:
        if not isinstance(channels, dict):
            raise InputError(
                f"channels must be a dict such as {{'Fn': 'normal', 'Ft': 'friction'}} for "
                f"an 'export all' file, got {channels!r}",
                path=p,
            )
        mapping = {}
        for channel, name in channels.items():
            if channel not in FORCE_CHANNELS:
                raise InputError(
                    f"channels key {channel!r} is not a record channel; use "
                    f"{', '.join(FORCE_CHANNELS)}",
                    path=p,
                )
            match = [n for n in datasets if n == name] or [
                n for n in datasets if isinstance(name, str) and n.lower() == name.lower()
            ]
            if len(match) != 1:
                raise InputError(
                    f"channels[{channel!r}] = {name!r} names no dataset of the file "
                    f"(datasets: {listed})",
                    path=p,
                )
            mapping[channel] = match[0]
        return mapping
    mapping = {}
    for name in datasets:
        channel = _channel_of(name)
        if channel is None:
            continue
        if channel in mapping:
            raise InputError(
                f"datasets {mapping[channel]!r} and {name!r} both look like {channel}; say "
                f"which one with channels={{'{channel}': '<dataset name>'}}",
                path=p,
            )
        mapping[channel] = name
    return mapping


def _digitised_record(series: dict, attrs: dict, *, time_unit, force_unit, path, scene):
    """Record from ``{channel: (x, y)}`` in file units (see module notes)."""
    if "Fn" not in series:
        raise InputError(
            "no normal-force channel: name the dataset 'Fn' (or 'normal') or pass "
            "channels={'Fn': '<dataset name>'}",
            path=path,
        )
    t_factor, t_unit = resolve_unit("time", None, time_unit, path=path, hint=_UNIT_HINT["time"])
    f_factor, f_unit = resolve_unit("force", None, force_unit, path=path, hint=_UNIT_HINT["force"])
    own = {ch: (x * t_factor, y * f_factor) for ch, (x, y) in series.items()}
    time = np.unique(np.concatenate([x for x, _ in own.values()]))
    forces, measured = {}, {}
    for ch in FORCE_CHANNELS:
        if ch not in own:
            continue
        x, y = own[ch]
        inside = (time >= x[0]) & (time <= x[-1])
        forces[ch] = np.where(inside, np.interp(time, x, y), np.nan)
        measured[ch] = np.isin(time, x)
    attrs = dict(attrs)
    attrs["source_time_unit"] = t_unit
    attrs["source_force_unit"] = f_unit
    attrs.update(scene)
    return make_record(time, forces, attrs=attrs, measured=measured)


def _as_path(x) -> bool:
    return isinstance(x, str | os.PathLike)


def read_wpd(
    path, *, time_unit=None, force_unit=None, channels=None, encoding=None, **scene_fields
):
    """Read WebPlotDigitizer export(s) into a digitised record.

    Parameters
    ----------
    path : str, os.PathLike, list of paths or dict
        One file (single-dataset or "export all" ``wpd_datasets.csv``, told apart by
        content); a list of single-dataset files; or ``{"Fn": path, "Ft": path}``.
    time_unit : str
        Unit of the plot's x axis (``"s"``, ``"ms"``, ``"us"``...). Required.
    force_unit : str
        Unit of the plot's y axis (``"N"``, ``"kN"``...). Required.
    channels : str, list of str or dict, optional
        Single file: the channel it holds (``"Fn"``, ``"Ft"``, ``"Fy"``); default from the
        file name. List of files: one channel per file. "Export all" file: ``{channel:
        dataset name}`` overriding the name-based map.
    encoding : str, optional
        Text encoding when not UTF-8 / UTF-16 with BOM.
    **scene_fields : float
        Scene fields stored in the attributes (names as :class:`pipeline.Scene`).

    Returns
    -------
    xarray.Dataset
        The record (``kind="digitised"``, ``format="wpd"`` or ``"wpd_datasets"``), with
        ``Fn_measured``/``Ft_measured`` masks. For several files, ``source`` and
        ``sha256`` list each file's name and hash, joined by ``","`` in channel order.

    Raises
    ------
    InputError
        Missing units, unknown channel, non-numeric cell, NaN/inf, duplicated x, a single
        point, undecodable bytes, an unreadable file.
    """
    scene = scene_attrs(scene_fields)
    if isinstance(path, dict):
        if channels is not None:
            raise InputError(
                "channels= does not apply when path is a dict: its keys already name the "
                f"channels ({', '.join(map(str, path))}); drop channels= or pass a list"
            )
        return _read_singles(
            list(path.values()), list(path.keys()), time_unit, force_unit, encoding, scene
        )
    if isinstance(path, list | tuple):
        if channels is not None and not isinstance(channels, list | tuple):
            raise InputError(
                "for a list of files give channels as a list, e.g. channels=['Fn', 'Ft']"
            )
        return _read_singles(list(path), channels, time_unit, force_unit, encoding, scene)
    p, raw, sha = read_raw(path)
    text = decode(raw, p, encoding)
    if is_datasets_text(text):
        datasets = _parse_datasets(text, p)
        mapping = _map_datasets(datasets, channels, p)
        attrs = base_attrs(p, sha, "wpd_datasets", "digitised")
        attrs["channels"] = ",".join(f"{ch}={name}" for ch, name in mapping.items())
        ignored = [n for n in datasets if n not in mapping.values()]
        if ignored:
            attrs["ignored_datasets"] = ",".join(ignored)
        series = {ch: datasets[name] for ch, name in mapping.items()}
        return _digitised_record(
            series, attrs, time_unit=time_unit, force_unit=force_unit, path=p, scene=scene
        )
    if isinstance(channels, dict | list | tuple):
        # {"Fn": "..."} or ["Fn"]: the one channel a single-dataset file holds
        if len(channels) != 1:
            raise InputError(
                "a single-dataset export holds one channel: pass channels='Fn' (or 'Ft', "
                "'Fy'); combine two exports with load({'Fn': fn_path, 'Ft': ft_path}, ...)",
                path=p,
            )
        channels = next(iter(channels))
    return _read_singles(
        [path],
        None if channels is None else [channels],
        time_unit,
        force_unit,
        encoding,
        scene,
        parsed={0: (p, text, sha)},
    )


def _read_singles(paths, channels, time_unit, force_unit, encoding, scene, parsed=None):
    if not paths:
        raise InputError("no files given")
    if channels is not None and len(channels) != len(paths):
        raise InputError(f"{len(paths)} files but {len(channels)} channels; give one per file")
    series, names, shas = {}, [], []
    first = None
    for k, path in enumerate(paths):
        if parsed and k in parsed:
            p, text, sha = parsed[k]
        else:
            if not _as_path(path):
                raise InputError(f"expected a file path, got {path!r}")
            p, raw, sha = read_raw(path)
            text = decode(raw, p, encoding)
        first = first or p
        if is_datasets_text(text):
            raise InputError(
                "this is an 'export all' file; pass it alone (with channels={...} if needed)",
                path=p,
            )
        channel = None if channels is None else channels[k]
        if channel is None:
            channel = _channel_from_filename(p)
            if channel is None:
                raise InputError(
                    "cannot tell which force this single-dataset export holds from its name; "
                    "pass channels='Fn' (or 'Ft', 'Fy'), or rename the file e.g. 'Fn.csv'",
                    path=p,
                )
        elif channel not in FORCE_CHANNELS:
            raise InputError(
                f"channel {channel!r} is not a record channel; use {', '.join(FORCE_CHANNELS)}",
                path=p,
            )
        if channel in series:
            raise InputError(f"two files give channel {channel}", path=p)
        series[channel] = _parse_single(text, p)
        names.append(p.name)
        shas.append(sha)
    if "Fn" not in series:
        raise InputError(
            f"no normal-force channel: the export(s) hold "
            f"{', '.join(series)} only; load it together with the Fn export, e.g. "
            "load({'Fn': 'fn.csv', 'Ft': 'ft.csv'}, time_unit=..., force_unit=...)",
            path=", ".join(names),
        )
    attrs = base_attrs(first, ",".join(shas), "wpd", "digitised")
    attrs["source"] = ", ".join(names)  # a heading, a message: as a person lists them
    attrs["channels"] = ",".join(f"{ch}={n}" for ch, n in zip(series, names, strict=True))
    return _digitised_record(
        series, attrs, time_unit=time_unit, force_unit=force_unit, path=attrs["source"], scene=scene
    )
