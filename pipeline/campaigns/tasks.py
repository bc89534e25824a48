"""The records of a campaign as tasks: which files, which scene, one record analysed.

:func:`plan` turns a folder, glob or list of files (and optional scenes and table) into
picklable :class:`RecordTask` objects; :func:`run_record` analyses one and returns a
:class:`RecordResult` of plain numbers and strings, or the reason it failed — it never
raises for a bad record, so a campaign lists failures and goes on. Being pure functions of
the task, they run the same in this process, in a dask worker or on a cluster.

A task that names a report folder (``RecordTask.report``) also writes the record's fit
report there, rendered from the analysis and fit just made
(:func:`pipeline.notebook_report.render_record_report`: no kernel, no second analysis),
where the task runs; a report that fails leaves the record analysed and says why in
``RecordResult.report_error``. A fault of the machine on the output (a full disk, a
read-only or vanished folder: :class:`~pipeline.errors.OutputError`) is no record's own and
ends the run; one on a record's input (its file vanished, unreadable) fails that record.
"""

from __future__ import annotations

import dataclasses
import glob as _glob
import json
import logging
import math
import traceback
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from .._json import json_ready
from ..analysis import OUTCOME_UNITS, Analysis, analyse
from ..errors import InputError, OutputError, PipelineWarning
from ..fit import fit_contact
from ..io import RECORD_SUFFIXES, scene_from_metadata
from ..notebook_report import noted, render_record_report
from ..report import load_sample, read_sidecar, sample_files, sensor_from_sidecar, sidecar_path
from ..scene import Scene
from ..score import METRICS, PHASES

__all__ = [
    "RecordTask",
    "RecordResult",
    "record_files",
    "plan",
    "run_record",
    "read_task_record",
    "record_numbers",
    "OUTCOMES",
    "FIT_PARAMETERS",
]

log = logging.getLogger(__name__)

#: Measured outcomes per record (value and ``_std``), with units.
OUTCOMES = dict(OUTCOME_UNITS)

#: Contact parameters a per-record fit reports (value and ``_std``), with units.
FIT_PARAMETERS = {"E_eff": "Pa", "e": "1", "mu": "1", "kt_scale": "1"}

_GLOB_CHARS = set("*?[")
_DATA_SUFFIXES = RECORD_SUFFIXES
_PATTERNS = ", ".join(f"*{s}" for s in RECORD_SUFFIXES)


@dataclass(frozen=True)
class RecordTask:
    """One record of a campaign, as a picklable task (everything a worker needs).

    Attributes
    ----------
    name : str — the record's name in the Dataset (its file name)
    path : str — the record file (its sidecar, if any, beside it: read by the worker)
    given : dict or None — Scene fields given for it (``scenes=``), SI
    row : dict or None — its row of the campaign table (Scene fields)
    repeat : int or None — the table's repeat number, None to number them automatically
    options : dict — keyword arguments of :func:`pipeline.analyse`
    fit : bool — also fit the contact parameters (where :func:`pipeline.fit_contact` exists)
    report : str or None — folder to write the record's fit report into (``<stem>.ipynb``,
        read and written by the worker), None for no report
    report_html : bool — the report's HTML too
    load : dict — keyword arguments of :func:`pipeline.io.load` for the record (a rig's
        ``sensitivity``, ``axes``...), over its sidecar's ``"load"`` block
        (:func:`read_task_record`)
    """

    name: str
    path: str
    given: dict | None = None
    row: dict | None = None
    repeat: int | None = None
    options: dict = field(default_factory=dict)
    fit: bool = True
    report: str | None = None
    report_html: bool = True
    load: dict = field(default_factory=dict)


@dataclass(frozen=True)
class RecordResult:
    """What a task returns: numbers and strings, or the reason it failed.

    Attributes
    ----------
    name : str
    status : str — ``"ok"`` or ``"failed"``
    reason : str — why it failed (``""`` when ok)
    numbers : dict — name → float (SI; see the Dataset's variables)
    texts : dict — name → str
    warnings : tuple of str — the library's warnings for this record
    report_error : str — why the record's report could not be written (``""`` when it
        was, or was not asked for)
    """

    name: str
    status: str
    reason: str = ""
    numbers: dict = field(default_factory=dict)
    texts: dict = field(default_factory=dict)
    warnings: tuple = ()
    report_error: str = ""


# ------------------------------------------------------------------ which records
def record_files(paths) -> list[Path]:
    """The record files of a folder, a glob, a file, or a list of any of these.

    A folder gives its data files (``*.csv``, ``*.tdms``, ``*.lvm``, ``*.mat``), less
    the parts another sidecar combines into one record (:func:`pipeline.report.sample_files`);
    sidecars (``*.json``) are not records. Order: as given, each folder or glob sorted by
    name; duplicates dropped.

    Raises
    ------
    InputError
        A path that does not exist, a glob or folder with no record file.
    """
    items = [paths] if isinstance(paths, (str, Path)) else list(paths)
    if not items:
        raise InputError("no records given: name a folder, a glob or files")
    out: list[Path] = []
    for item in items:
        text = str(item)
        p = Path(item)
        if p.is_dir():
            found = sample_files(p)
            if not found:
                raise InputError(f"no record files ({_PATTERNS}) in this folder", path=p)
            out += found
        elif _GLOB_CHARS & set(text):
            found = sorted(
                Path(q) for q in _glob.glob(text) if Path(q).suffix.lower() in _DATA_SUFFIXES
            )
            if not found:
                raise InputError(f"the pattern {text!r} matches no record file ({_PATTERNS})")
            out += found
        elif p.is_file():
            out.append(p)
        else:
            raise InputError("no such file or folder; check the path", path=p)
    seen, unique = set(), []
    for p in out:
        key = p.resolve()
        if key not in seen:
            seen.add(key)
            unique.append(p)
    return unique


def _read_table(table) -> dict[str, dict]:
    """Rows of the campaign table by file name: ``{name: {field: value}}``."""
    import pandas as pd

    if table is None:
        return {}
    if isinstance(table, (str, Path)):
        path = Path(table)
        try:
            df = pd.read_csv(path, comment="#", skipinitialspace=True)
        except FileNotFoundError:
            raise InputError("no such table file; check the path", path=path) from None
        except (ValueError, pd.errors.ParserError) as exc:
            raise InputError(f"cannot read the table as CSV: {exc}", path=path) from exc
    elif isinstance(table, pd.DataFrame):
        df, path = table, None
    else:
        raise InputError(
            f"table= takes a CSV path or a pandas DataFrame, got {type(table).__name__}"
        )
    key = "file" if "file" in df.columns else "record" if "record" in df.columns else None
    if key is None:
        raise InputError("the table needs a 'file' column naming each record file", path=path)
    allowed = set(Scene.field_names()) | {key, "repeat"}
    unknown = [c for c in df.columns if c not in allowed]
    if unknown:
        raise InputError(
            f"unknown table column(s) {', '.join(map(repr, unknown))}: use 'file', "
            f"'repeat' and Scene fields ({', '.join(Scene.field_names())})",
            path=path,
        )
    rows = {}
    for i, row in enumerate(df.to_dict("records")):
        name = str(row.pop(key)).strip()
        if name in rows:
            raise InputError(f"record {name!r} appears twice", path=path, line=i + 2)
        rows[name] = {k: v for k, v in row.items() if not _missing(v)}
    return rows


def _missing(v) -> bool:
    return v is None or (isinstance(v, float) and math.isnan(v))


def _given(path: Path, scenes) -> dict | None:
    """The Scene fields ``scenes=`` gives for a record (module notes), None if none."""
    if scenes is None:
        return None
    if isinstance(scenes, Scene):
        return scenes.to_dict()
    if isinstance(scenes, Mapping) and scenes and set(scenes) <= set(Scene.field_names()):
        return dict(scenes)  # base fields, possibly partial
    if isinstance(scenes, Mapping):
        s = scenes.get(path.name, scenes.get(path.stem))
    elif callable(scenes):
        s = scenes(path)
    else:
        raise InputError("scenes= takes a Scene, a mapping of file names to Scenes, or a callable")
    if s is None:
        return None
    return s.to_dict() if isinstance(s, Scene) else dict(s)


def task_fields(task: RecordTask) -> tuple[dict, list]:
    """The Scene fields of a task and where they came from, later ones winning field by
    field: given (``scenes=``), the record's sidecar, its table row (module notes)."""
    fields, sources = {}, []
    if task.given:
        fields.update(task.given)
        sources.append("given")
    side = read_sidecar(task.path).get("scene")
    if side is not None:
        Scene.from_dict(side, path=sidecar_path(task.path))  # its own errors, named
        fields.update(side)
        sources.append("sidecar")
    if task.row:
        fields.update(task.row)
        sources.append("table")
    return fields, sources


def plan(
    paths,
    *,
    scenes=None,
    table=None,
    fit=True,
    reports=None,
    report_html=True,
    load=None,
    **options,
) -> list[RecordTask]:
    """The tasks of a campaign: one :class:`RecordTask` per record file.

    Parameters are those of :func:`campaign`. Fails early (``InputError``) on what makes the
    whole campaign impossible (no records, an unreadable table, a table row naming no
    record); sidecars are read by the tasks themselves (in parallel on a cluster), so a
    record whose scene is missing or invalid fails alone.
    """
    files = record_files(paths)
    rows = _read_table(table)
    names = {p.name for p in files} | {p.stem for p in files}
    stray = [k for k in rows if k not in names]
    if stray:
        raise InputError(
            f"the table names record(s) not among the files: {', '.join(map(repr, stray))}"
        )
    tasks = []
    for p in files:
        row = dict(rows.get(p.name, rows.get(p.stem)) or {})
        repeat = int(row.pop("repeat")) if "repeat" in row else None
        given = _given(p, scenes)
        tasks.append(
            RecordTask(
                p.name,
                str(p),
                given,
                row or None,
                repeat,
                dict(options),
                fit,
                None if reports is None else str(Path(reports).resolve()),
                report_html,
                dict(load or {}),
            )
        )
    return tasks


# ------------------------------------------------------------------ one record
def read_task_record(task: RecordTask):
    """The task's record: :func:`pipeline.report.load_sample` with the task's ``load``
    options over its sidecar's."""
    return load_sample(task.path, **task.load)


def guarded(task: RecordTask, fn):
    """``fn(task)`` with the library's warnings collected and any failure caught.

    Returns ``(value, None, warnings)`` on success, ``(None, failed RecordResult,
    warnings)`` otherwise: an :class:`InputError` gives its message as the reason, any
    other exception (a bug or a numerical failure) its type and message, logged with its
    traceback at debug level — the record is listed and the campaign goes on. A record
    whose file vanished since the campaign listed it says so.

    Raises
    ------
    OutputError
        The campaign's output cannot be written (a full disk, a read-only or vanished
        folder): that ends the run, whichever record met it (docs/cli.md).
    """
    failed = None
    value = None
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            value = fn(task)
        except OutputError:
            raise
        except InputError as exc:
            failed = RecordResult(task.name, "failed", str(exc))
        except Exception as exc:
            log.debug("%s: %s", task.name, traceback.format_exc())
            failed = RecordResult(task.name, "failed", f"{type(exc).__name__}: {exc}")
    msgs = tuple(
        f"{w.category.__name__}: {w.message}"
        for w in caught
        if issubclass(w.category, PipelineWarning)
    )
    if failed is not None:
        if not Path(task.path).exists():
            failed = dataclasses.replace(
                failed,
                reason=f"{task.path}: the file vanished during the run (deleted or moved "
                "after the campaign listed it)",
            )
        failed = dataclasses.replace(failed, warnings=msgs)
    return value, failed, msgs


def run_record(task: RecordTask) -> RecordResult:
    """Analyse one record (a campaign task); never raises for a bad record.

    Every failure, including an unexpected one, comes back as ``status="failed"`` with its
    reason (:func:`guarded`); warnings of the library are collected in ``warnings``.
    """
    value, failed, msgs = guarded(task, _analysis_of)
    if failed is not None:
        return failed
    return result_of(task, value, msgs, try_report(task, value))


def _task_scene(task: RecordTask, record) -> tuple[Scene, str]:
    """The record's Scene and where it came from: :func:`task_fields`, and for fields they
    leave out, the record's metadata where it states them with units
    (:func:`pipeline.io.scene_from_metadata`)."""
    fields, sources = task_fields(task)
    meta = {k: v for k, (v, _) in scene_from_metadata(record).items() if fields.get(k) is None}
    if meta:
        fields.update(meta)
        sources.append("metadata")
    missing = [k for k in ("radius", "speed") if fields.get(k) is None]
    if fields.get("density") is None and fields.get("mass") is None:
        missing.append("density or mass")
    if missing and sources in ([], ["metadata"]):
        told = f" (its metadata gives only {', '.join(sorted(meta))})" if meta else ""
        raise InputError(
            f"no scene for this record{told}: put a sidecar <record>.json with a 'scene' "
            "beside it, state the impact in its metadata with units, or give scenes= / a "
            "table row (pipeline campaign --scene/--table)",
            path=task.path,
        )
    return Scene.from_dict(fields, path=task.path), "+".join(sources)


@dataclass(frozen=True, eq=False)
class Analysed:
    """One record analysed: the analysis, fitted numbers, where its scene came from, the
    analysis' warnings (:func:`noted`) and, kept for the record's report only, its contact
    fit (a few MB)."""

    analysis: Analysis
    fitted: dict
    scene_source: str
    fit: object = None
    notes: tuple = ()


def _analysis_of(task: RecordTask, **override) -> Analysed:
    """The record's :class:`~pipeline.analysis.Analysis` (its plausibility checks first;
    options overridden by ``override``), as ``pipeline analyse`` and ``reproduce`` run it,
    and its contact fit."""
    rec = read_task_record(task)
    scene, source = _task_scene(task, rec)
    sensor = sensor_from_sidecar(task.path)  # its sidecar read once for both
    a, notes = noted(analyse, rec, scene, **_with_sensor({**task.options, **override}, sensor))
    f = fit_contact(rec, scene, **_fit_options(task, sensor)) if task.fit else None
    fitted = {} if f is None else _fit_numbers(f)
    return Analysed(a, fitted, source, f if task.report is not None else None, notes)


def _fit_options(task: RecordTask, sensor) -> dict:
    """The options of the task's contact fit: the analysis' ``n_boot`` and ``seed``, and
    ``sensor``, the one its sidecar states (:func:`pipeline.sidecar.sensor_from_sidecar`),
    as ``pipeline fit`` takes it."""
    out = {k: task.options[k] for k in ("n_boot", "seed") if k in task.options}
    return out if sensor is None else {**out, "sensor": sensor}


def _with_sensor(options: dict, sensor) -> dict:
    """The analysis' ``options`` with ``sensor``, the one the record's sidecar states, for
    its fits (``fit_options``; one given in the options wins), as ``pipeline analyse`` runs
    it."""
    if sensor is None:
        return options
    return {**options, "fit_options": {"sensor": sensor, **(options.get("fit_options") or {})}}


def try_report(task: RecordTask, done: Analysed, *, reanalyse: bool = False) -> str:
    """Write the record's report when the task asks for one (:func:`write_report`); why it
    failed, ``""`` if it did not (or none was asked). A failed report leaves the record
    ``ok``; its warnings are the report's, not the record's."""
    if task.report is None:
        return ""
    _, failed, _ = guarded(task, lambda t: write_report(t, done, reanalyse=reanalyse))
    return "" if failed is None else failed.reason


def write_report(task: RecordTask, done: Analysed, *, reanalyse: bool = False):
    """Write the record's fit report into ``task.report``, rendered from ``done``: the
    analysis made with the task's options and its contact fit (made here, for the report
    alone, when the campaign does not fit).

    ``reanalyse``: analyse the record again first, with :func:`pipeline.analyse`'s own
    bootstrap — the batched path draws its replicates otherwise, and the notebook must show
    what running it gives. Returns the :class:`~pipeline.notebook_report.NotebookReport`.
    """
    a, notes, fit = done.analysis, done.notes, done.fit
    rec = read_task_record(task) if reanalyse or fit is None else None
    sensor = sensor_from_sidecar(task.path) if rec is not None else None
    if reanalyse:
        a, notes = noted(analyse, rec, a.scene, **_with_sensor(task.options, sensor))
    if fit is None:
        fit = fit_contact(rec, a.scene, **_fit_options(task, sensor))
    return render_record_report(
        task.path,
        a,
        fit,
        task.report,
        notes=notes,
        options=task.options,
        load=task.load,
        html=task.report_html,
        name=Path(task.name).stem,
    )


def result_of(task: RecordTask, done: Analysed, msgs=(), report_error="") -> RecordResult:
    """The ``ok`` result of a task from its analysis (and its report's error, if any)."""
    numbers, texts = record_numbers(done.analysis)
    numbers.update(done.fitted)
    texts["scene_source"] = done.scene_source
    return RecordResult(task.name, "ok", "", numbers, texts, tuple(msgs), report_error)


def record_numbers(a: Analysis) -> tuple[dict, dict]:
    """The campaign's per-record numbers and strings of one analysis."""
    rs, sc = a.rigid, a.rigid_scene
    numbers = {}
    for k in OUTCOMES:
        numbers[k] = a.outcomes.values[k]
        numbers[f"{k}_std"] = a.outcomes.std[k]
    v_n = float(rs.v_n)
    numbers.update(
        e_t_rigid=float(rs.e_t),
        omega_rigid=float(rs.omega),
        rebound_deg_rigid=math.degrees(math.atan2(float(rs.v_t), v_n)),
        mu_record=a.mu_record,
        mu_rigid=float(sc.mu),
        e_rigid=float(sc.e),
        F_max=float(a.record["Fn"].max()),
        t_contact=float(a.window.t_end - a.window.t_start),
        noise_Fn=float(a.window.noise.get("Fn", float("nan"))),
        angle=float(a.scene.angle_deg),
        speed=float(a.scene.speed),
        v_t0=float(a.scene.v_t0),
    )
    for phase in PHASES:
        for m in METRICS:
            numbers[f"score/{phase}/{m}"] = a.score.values[phase][m]
            numbers[f"score_std/{phase}/{m}"] = a.score.std[phase][m]
    attrs = a.record.attrs
    texts = {
        "file": str(attrs.get("source", "")),
        "sha256": str(attrs.get("sha256", "")),
        "format": str(attrs.get("format", "")),
        "regime": str(rs.regime),
        "mu_source": a.sources.get("mu", ""),
        "e_source": a.sources.get("e", ""),
        "scene_json": json.dumps(json_ready(a.scene.to_dict()), sort_keys=True),
    }
    return numbers, texts


def _fit_numbers(f) -> dict:
    """Fitted contact parameters of one record from its contact fit.

    :func:`pipeline.fit_contact` with its default model and the campaign's bootstrap
    (``n_boot``, ``seed``): ``fit_<name>`` and ``fit_<name>_std`` for the names in
    :data:`FIT_PARAMETERS` it reports, ``fit_redchi``, and ``fit_identifiable_<name>``
    (1 or 0: μ of a contact that sticks throughout has only a lower bound).
    """
    out = {}
    for name in FIT_PARAMETERS:
        if name in f.values:
            out[f"fit_{name}"] = float(f.values[name])
            out[f"fit_{name}_std"] = float(f.stderr.get(name, float("nan")))
            out[f"fit_identifiable_{name}"] = float(bool(f.identifiable.get(name, True)))
    out["fit_redchi"] = float(f.redchi)
    return out
