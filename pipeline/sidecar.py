"""A record's JSON sidecar, and a record read as its sidecar says.

A sample ``<name>.csv`` (or any record file) may carry a sidecar ``<name>.json`` beside it:
its ``"scene"`` (Scene fields, SI; the ground truth of a simulated sample), its
``"sensor"`` block, and a ``"load"`` block of :func:`pipeline.io.load` options (see
:data:`LOAD_KEYS`). These readers sit just above :mod:`pipeline.io` so that a command that
only reads and fits a record (``pipeline fit``) does not import the report stack
(:mod:`pipeline.report` re-exports them).
"""

from __future__ import annotations

import contextlib
import difflib
from pathlib import Path

from .errors import InputError
from .io import RECORD_SUFFIXES, load, load_contact, read_json
from .scene import Scene

__all__ = [
    "LOAD_KEYS",
    "SIDECAR_LOAD_KEYS",
    "load_sample",
    "read_sidecar",
    "sample_files",
    "scene_from_sidecar",
    "sensor_from_sidecar",
    "sidecar_path",
]

#: Keys a sidecar's ``"load"`` block may hold: :func:`pipeline.io.load`'s options, and
#: ``"paths"`` ({channel: file}) to combine files of the same folder.
LOAD_KEYS = (
    "paths",
    "time_unit",
    "force_unit",
    "axes",
    "channels",
    "decouple",
    "sensitivity",
    "columns",
)
#: Sidecar keys that are also read at its top level: ``"sensitivity"`` (the rig's, as
#: ``{"Fn": [0.225, "mV/N"]}``) and, for a MATLAB record, ``"columns"`` (a 2-D array's
#: column names; the samples' sidecars describe a CSV's columns under that key).
SIDECAR_LOAD_KEYS = ("sensitivity", "columns")


def sidecar_path(path) -> Path:
    """The JSON sidecar of a record: ``<stem>.json`` beside it."""
    return Path(path).with_suffix(".json")


def read_sidecar(path) -> dict:
    """The JSON sidecar ``<stem>.json`` of a sample ({} without one).

    Keys used here: ``"scene"`` (Scene fields, SI; ``"inf"`` allowed) and ``"load"``
    (keyword arguments of :func:`pipeline.io.load`, see :data:`LOAD_KEYS`; ``"paths"`` —
    ``{channel: file}`` — combines several files of the same folder into one record);
    ``"sensitivity"`` and, beside a ``.mat`` record, ``"columns"`` may also stand at the
    top level (:data:`SIDECAR_LOAD_KEYS`).

    Raises
    ------
    InputError
        Naming the sidecar: a directory, unreadable, not UTF-8, malformed JSON, not an
        object, or a ``"load"`` block that is not an object of known options.
    """
    side = sidecar_path(path)
    if not side.exists() and not side.is_symlink():
        return {}
    data = read_json(side, what="sidecar")
    block = data.get("load", {})
    if not isinstance(block, dict):
        raise InputError(
            f"'load' must be an object of pipeline.io.load options ({', '.join(LOAD_KEYS)}), "
            f"not {block!r}",
            path=side,
        )
    allowed = LOAD_KEYS + Scene.field_names()
    for key in block:
        if key not in allowed:
            close = difflib.get_close_matches(key, allowed, n=1)
            raise InputError(
                f"unknown 'load' option {key!r}"
                + (f" (did you mean {close[0]!r}?)" if close else "")
                + f"; the options are {', '.join(LOAD_KEYS)} and scene fields",
                path=side,
            )
    paths = block.get("paths")
    if paths is not None and (
        not isinstance(paths, dict)
        or not all(isinstance(k, str) and isinstance(v, str) for k, v in paths.items())
    ):
        raise InputError(
            f"'load' → 'paths' must map channels to file names, e.g. "
            f'{{"Fn": "fn.csv", "Ft": "ft.csv"}}, not {paths!r}',
            path=side,
        )
    return data


def scene_from_sidecar(path) -> Scene | None:
    """The ground-truth scene of a sample from its JSON sidecar (None without one)."""
    data = read_sidecar(path)
    if "scene" not in data:
        return None
    return Scene.from_dict(data["scene"], path=sidecar_path(path))


def sensor_from_sidecar(path) -> dict | None:
    """The stated sensor of a record: its sidecar's ``"sensor"`` block (bandwidth [Hz],
    filter_order, quantum [N], crosstalk_matrix, ...; read by
    :func:`pipeline.fit.sensor.sensor_spec`), None without one. Every fit of the record
    takes it as stated — ``pipeline fit`` and ``pipeline analyse``, a campaign's fits and
    a report's — so that one record gives the same numbers whichever way it is fitted.

    Raises
    ------
    InputError
        Naming the sidecar, where ``"sensor"`` is not an object.
    """
    block = read_sidecar(path).get("sensor")
    if block is not None and not isinstance(block, dict):
        raise InputError(
            f"'sensor' must be an object of sensor properties (bandwidth, filter_order, "
            f"quantum, crosstalk_matrix, ...), not {block!r}",
            path=sidecar_path(path),
        )
    return block


def load_sample(path, *, contact_only: bool = False, **options):
    """Load a record as its sidecar's ``"load"`` block says (combining files where
    ``"paths"`` is given); ``options`` (:func:`pipeline.io.load` keywords that are not
    None) override the block's. ``contact_only``: keep only the first contact and its
    margins (:func:`pipeline.io.load_contact`, bounded memory for a large file).

    A bad option from the sidecar is reported with the sidecar named beside the record.
    """
    path = Path(path)
    side = read_sidecar(path)
    block = dict(side.get("load", {}))
    for key in SIDECAR_LOAD_KEYS:  # the rig's sensitivity, a MATLAB array's column names
        if key not in side or (key == "columns" and path.suffix.lower() != ".mat"):
            continue  # a text record's sidecar describes its columns: no option
        if key in block and block[key] != side[key]:
            raise InputError(
                f"{key!r} is given twice, at the top level and in 'load', differently; keep one",
                path=sidecar_path(path),
            )
        block[key] = side[key]
    given = {k: v for k, v in options.items() if v is not None}
    kwargs = {**block, **given}
    paths = kwargs.pop("paths", None)
    target = path if paths is None else {ch: path.parent / p for ch, p in paths.items()}
    try:
        if contact_only and paths is None:
            return load_contact(target, **kwargs)
        return load(target, **kwargs)
    except InputError as exc:
        from_side = sorted(k for k in block if k not in given)
        if not from_side:
            raise
        raise type(exc)(
            f"{exc.reason} (load options {', '.join(from_side)} from {sidecar_path(path).name})",
            path=exc.path,
            line=exc.line,
            column=exc.column,
        ) from exc


def sample_files(samples) -> list[Path]:
    """The records of a sample folder: data files, less those another sidecar combines."""
    samples = Path(samples)
    if not samples.is_dir():
        raise InputError("no such folder of samples; check the path", path=samples)
    files = sorted(
        p
        for p in samples.iterdir()
        if p.suffix.lower() in RECORD_SUFFIXES and not p.name.startswith(".") and p.is_file()
    )
    parts = set()
    for p in files:
        with contextlib.suppress(InputError):  # a bad sidecar fails its own record later
            paths = read_sidecar(p).get("load", {}).get("paths", {})
            parts |= {q for q in paths.values() if q != p.name}
    return [p for p in files if p.name not in parts]
