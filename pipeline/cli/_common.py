"""What the commands share: reading a record and its scene as Python does, argument
parsing that answers a bad argument in one line, and warnings turned into log lines."""

from __future__ import annotations

import argparse
import contextlib
import json
import logging
import warnings
from pathlib import Path

from ..errors import InputError, PipelineWarning

#: Exit statuses of every command (``pipeline --help`` lists them; docs/cli.md explains).
EXIT_OK, EXIT_FAILED_RECORDS, EXIT_BAD_INPUT, EXIT_INTERNAL = 0, 1, 2, 3
#: A fault of the machine while writing the output (:class:`pipeline.errors.OutputError`):
#: the disk full, the output's folder not writable (read-only, no permission, vanished), an
#: input/output error of the device. The previous output stays, whole.
EXIT_DISK_FULL, EXIT_UNWRITABLE, EXIT_DEVICE = 4, 5, 6
#: Interrupted (Ctrl-C), as a shell reports a process that SIGINT ended (128 + 2).
EXIT_INTERRUPTED = 130
#: The exit status of each :attr:`pipeline.errors.OutputError.fault`.
EXIT_FAULT = {"full": EXIT_DISK_FULL, "unwritable": EXIT_UNWRITABLE, "device": EXIT_DEVICE}
EXIT_CODES = (
    "exit status: 0 success; 1 some records failed (reproduce, campaign: the others were "
    "processed and the failures are listed with their reasons); 2 bad input or a bad "
    "argument (a one-line message says which); 3 an internal error (a bug: run with -v "
    "for the traceback, and report it); 4 the disk is full, 5 the output folder cannot be "
    "written (read-only, no permission, vanished), 6 the disk failed (input/output error): "
    "one line names the file, and the previous output is untouched; 130 interrupted"
)


class Parser(argparse.ArgumentParser):
    """An ArgumentParser whose errors are one line (``error: ...``) and exit status 2."""

    def error(self, message):
        self.exit(EXIT_BAD_INPUT, f"error: {self.prog}: {message} (see {self.prog} --help)\n")


def _json_object(text: str, example: str) -> dict:
    try:
        value = json.loads(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"not a JSON object ({exc})") from None
    if not isinstance(value, dict):
        raise argparse.ArgumentTypeError(f"give a JSON object such as {example}")
    return value


def parse_axes(text: str) -> dict:
    """``--axes``: ``Fn=Fz,Ft=-Fx`` or a JSON object ``{"Fn": "Fz", "Ft": "-Fx"}``."""
    text = text.strip()
    if text.startswith("{"):
        return _json_object(text, '{"Fn": "Fz"}')
    out = {}
    for part in filter(None, (p.strip() for p in text.split(","))):
        name, sep, column = part.partition("=")
        if not sep or not name.strip():
            raise argparse.ArgumentTypeError(
                f"{part!r} is not CHANNEL=COLUMN; write e.g. Fn=Fz,Ft=-Fx"
            )
        out[name.strip()] = column.strip() or None
    if not out:
        raise argparse.ArgumentTypeError("empty; write e.g. Fn=Fz,Ft=-Fx")
    return out


def parse_sensitivity_option(text: str) -> dict:
    """``--sensitivity``: ``Fn=0.225mV/N,Ft=4.4 N/V`` or a JSON object
    ``{"Fn": [0.225, "mV/N"]}``; a decimal comma is read (``Fn=0,225 mV/N``). Returns the
    sidecar's form, ``{"Fn": [0.225, "mV/N"]}``."""
    import re

    from ..io import parse_sensitivity

    text = text.strip()
    if text.startswith("{"):
        value = _json_object(text, '{"Fn": [0.225, "mV/N"]}')
    else:
        value = {}
        for part in filter(None, (q.strip() for q in re.split(r"[,;](?=[^,;=]+=)", text))):
            name, sep, spec = part.partition("=")
            if not sep or not name.strip() or not spec.strip():
                raise argparse.ArgumentTypeError(
                    f"{part!r} is not CHANNEL=VALUE UNIT; write e.g. Fn=0.225mV/N,Ft=0.5mV/N"
                )
            value[name.strip()] = spec.strip()
    try:  # checked now (a bad one is argparse's one line); kept as JSON, as a sidecar's
        return {k: [s.value, s.unit] for k, s in parse_sensitivity(value).items()}
    except InputError as exc:
        raise argparse.ArgumentTypeError(exc.reason) from None


def add_record_options(p) -> None:
    """The options that say how to read a record, as :func:`pipeline.io.load` takes them."""
    g = p.add_argument_group(
        "reading the record (as pipeline.io.load; the sidecar's "
        "'load' block supplies what is not given)"
    )
    g.add_argument("--time-unit", help="time unit of a file without one: s, ms, us, ns")
    g.add_argument("--force-unit", help="force unit of a file without one: N, kN, mN, lbf")
    g.add_argument(
        "--axes",
        type=parse_axes,
        metavar="MAP",
        help="record channel ← file column, a leading '-' flips the sign: Fn=Fz,Ft=-Fx",
    )
    g.add_argument(
        "--decouple",
        type=Path,
        metavar="FILE",
        help="3×3 decoupling matrix of the sensor (CSV rows or JSON), applied to raw "
        "(Fx, Fy, Fz) before the axis map",
    )
    g.add_argument(
        "--sensitivity",
        type=parse_sensitivity_option,
        metavar="MAP",
        help="channels recorded in volts: record channel = sensitivity, in mV/N, V/N, N/V or "
        'N/mV: Fn=0.225mV/N,Ft=0.5mV/N (or JSON {"Fn": [0.225, "mV/N"]})',
    )


#: The options :func:`add_record_options` adds, as :func:`pipeline.io.load` names them.
LOAD_OPTIONS = ("time_unit", "force_unit", "axes", "decouple", "sensitivity")


def load_options(args) -> dict:
    """The :data:`LOAD_OPTIONS` given on the command line (the sidecar supplies the rest),
    as JSON values (a manifest and a report's parameters cell hold them; a path made
    absolute, for a notebook run from elsewhere and a worker)."""
    given = {k: v for k in LOAD_OPTIONS if (v := getattr(args, k, None)) is not None}
    if "decouple" in given:
        given["decouple"] = str(Path(given["decouple"]).resolve())
    return given


#: Files above this size are read keeping only the contact and its margins
#: (pipeline.io.load_contact): memory stays bounded whatever the file's length.
BIG_FILE = 64 << 20


def read_record(path, args):
    """The record at ``path`` read with the command's options over its sidecar's; a file
    over :data:`BIG_FILE` bytes streamed, keeping only its first contact."""
    from ..sidecar import load_sample

    try:
        big = Path(path).stat().st_size > BIG_FILE
    except OSError:
        big = False  # the reader says what is wrong with the path
    return load_sample(path, contact_only=big, **load_options(args))


def read_scene(record_path, scene_path=None, record=None):
    """The scene of a record, and where each field came from.

    From ``--scene`` (a JSON file of Scene fields, or a sidecar with a ``"scene"``), else
    the record's sidecar; fields neither gives are filled from the record's metadata
    where it states them with units (:func:`pipeline.io.scene_from_metadata`).

    Returns
    -------
    (Scene, dict)
        The scene and ``{field: source}``.
    """
    from ..io import scene_from_metadata
    from ..scene import Scene, read_scene_fields
    from ..sidecar import sidecar_path

    fields, origin = {}, None
    if scene_path is not None:
        fields, origin = read_scene_fields(scene_path), Path(scene_path)
    else:
        side = sidecar_path(record_path)
        if side.exists() or side.is_symlink():
            from ..sidecar import read_sidecar

            data = read_sidecar(record_path)
            if "scene" in data:
                fields, origin = read_scene_fields(side), side
    sources = {k: f"scene file {origin.name}" for k in fields}
    if record is not None:
        for name, (value, note) in scene_from_metadata(record).items():
            if fields.get(name) is None:
                fields[name] = value
                sources[name] = note
    if not fields:
        raise InputError(
            "no scene: give --scene scene.json (Scene fields in SI units), put a sidecar "
            "<record>.json with a 'scene' beside the file, or state the impact in the "
            "record's metadata with units ('# impact speed [m/s]: 0.6')",
            path=record_path,
        )
    return Scene.from_dict(fields, path=origin or record_path), sources


@contextlib.contextmanager
def log_warnings():
    """The library's warnings (poor fits, plausibility) reach the user as log lines naming
    the problem, each once, not as Python warnings pointing into the library's source.

    Only the pipeline's own (:class:`~pipeline.errors.PipelineWarning`) are WARNING lines;
    another library's (a dask client's unclosed socket, a deprecation) say nothing about
    the records and are INFO lines, shown with ``-v``.
    """
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        yield
    log = logging.getLogger("pipeline")
    seen = dict.fromkeys((w.category, str(w.message)) for w in caught)
    for category, message in seen:
        level = logging.WARNING if issubclass(category, PipelineWarning) else logging.INFO
        log.log(level, "%s: %s", category.__name__, message)
