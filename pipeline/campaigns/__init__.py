r"""Campaigns: many records (angles × speeds × repeats) analysed into one ``xarray.Dataset``.

A lab does not measure one impact. :func:`campaign` takes a folder, a glob or a list of
record files, finds each record's scene (module notes), analyses every record
(:func:`pipeline.analyse`: window, percussions, Routh's prediction, deviation score, the
measured outcomes e_n, e_t, ω and rebound angle with bootstrap uncertainties), fits the
contact parameters of each record where the fitter is installed, and gathers everything into
one Dataset with a ``record`` dimension:

- coordinates ``angle`` [deg], ``speed`` [m/s], ``v_t0`` [m/s], ``repeat`` (the n-th record
  of the same angle and speed, or the table's ``repeat`` column);
- ``status`` (``"ok"`` or ``"failed"``) and ``reason`` (why it failed, ``""`` when ok): a
  record that fails is listed and the rest goes on; input files are only read;
- measured outcomes and their 1-σ bootstrap spread (``e_n``, ``e_n_std``, ...), the rigid
  prediction beside them (``e_t_rigid``, ...), the regime, the deviation score as
  ``score(record, phase, metric)`` and ``score_std``, μ estimated from the record;
- the fitted contact parameters where available (``fit_<name>``, ``fit_<name>_std``) and
  the joint fit of all records (:mod:`pipeline.campaigns.joint`: ``joint_<name>``,
  ``attrs["joint_fit_json"]``);
- the campaign's trends in ``attrs`` and as scalar variables (:func:`trends`): the friction
  law μ = a + b·v_t0 fitted to the records' μ, and the two damping hypotheses for e(v)
  (constant e; constant Hunt–Crossley material constant α, under which e falls with speed).

Where each record's scene comes from (``scene_source``), later entries winning field by
field: ``scenes=`` (one Scene or a mapping of Scene fields for all, a mapping from file name
or stem to Scene, or a callable of the path), the record's JSON sidecar (``<stem>.json``
with a ``"scene"`` object), then a row of ``table=`` (a pandas DataFrame or CSV file with a
``file`` column and Scene fields such as ``speed``, ``angle_deg``, ``mu``, ``e``; optional
``repeat``); fields none of them gives come from the record's metadata where it states them
with units (``# impact speed [m/s]: 0.6``). The plausibility checks
(:func:`pipeline.plausibility.check_plausible`) run before the physics, as for ``pipeline
analyse``.

Reports (``reports=FOLDER``): each analysed record's fit report, a notebook
(``<stem>.ipynb``, and ``.html``) rendered from the analysis and fit the campaign has just
made, with the template's code cells that recompute them
(:mod:`pipeline.notebook_report`), written by whichever process analysed the record. A
report that cannot be made is a :class:`~pipeline.notebook_report.ReportWarning` naming the
record; the record stays in the Dataset, which is the same with or without reports.

Scale-out (``docs/cluster.md``): ``workers=N`` runs the records as tasks on a local
dask.distributed cluster of N single-threaded worker processes, ``scheduler="tcp://..."``
(or a ``distributed.Client``) on an existing cluster; the joint fit's evaluations of the
records run on the same workers (:func:`pipeline.fit_campaign`'s ``executor``). Each task
is a pure function of the record's file and scene, so the gathered Dataset is identical,
byte for byte once written, to the serial run's. Results are gathered as columns as they
arrive (:class:`~pipeline.campaigns.dataset.Gathered`) and the joint fit keeps its records
on disk (:mod:`pipeline.fit.store`), so no process's memory grows with the records beyond
a few kB a record. ``batched=True`` analyses the records in this process with the
bootstrap of all records in one vectorised pass (:mod:`pipeline.campaigns.batch`).

Overview (:mod:`pipeline.campaigns.overview`): :func:`write_overview` writes the page a
reader explores in a browser — every record a point in e_t(α), μ(v_t0) and the deviation
from rigid theory, its name and values on hover, its report on a click — one HTML file that
needs no server and no network (``pipeline campaign`` writes it as ``overview.html``).

References
----------
P. P. Garland, R. J. Rogers, J. Appl. Mech. 76:031015 (2009), doi:10.1115/1.3086432
(friction rising linearly with the initial tangential speed).
K. H. Hunt, F. R. E. Crossley, J. Appl. Mech. 42:440 (1975), doi:10.1115/1.3423596.
"""

from __future__ import annotations

import inspect
import warnings
from collections.abc import Callable
from pathlib import Path

import xarray as xr

from ..analysis import analyse
from ..errors import InputError
from ..notebook_report import ReportWarning
from .batch import analyse_tasks
from .dataset import Gathered, assemble, table_of, trends, with_trends, write_campaign
from .joint import joint_fit, with_joint_fit
from .overview import write_overview
from .run import connect, iter_results, run_tasks
from .tasks import (
    FIT_PARAMETERS,
    OUTCOMES,
    RecordResult,
    RecordTask,
    plan,
    record_files,
    record_numbers,
    run_record,
)

__all__ = [
    "campaign",
    "RecordTask",
    "RecordResult",
    "record_files",
    "plan",
    "run_record",
    "record_numbers",
    "run_tasks",
    "iter_results",
    "assemble",
    "Gathered",
    "trends",
    "with_trends",
    "table_of",
    "write_campaign",
    "write_overview",
    "joint_fit",
    "with_joint_fit",
    "OUTCOMES",
    "FIT_PARAMETERS",
]


def campaign(
    paths,
    *,
    scenes=None,
    table=None,
    fit: bool = True,
    workers: int | None = None,
    scheduler=None,
    batched: bool = False,
    progress: Callable | None = None,
    reports=None,
    report_html: bool = True,
    load=None,
    **options,
) -> xr.Dataset:
    """Analyse many records into one Dataset (module notes give its layout).

    Parameters
    ----------
    paths : str, os.PathLike or list
        A folder, a glob (``"runs/*.csv"``), a record file, or a list of these.
    scenes : Scene, mapping or callable, optional
        Scene(s) for records without a sidecar (module notes: where scenes come from): a
        Scene or a mapping of Scene fields (a base, possibly partial), a mapping of file
        names to Scenes, or a callable of the path.
    table : pandas.DataFrame or path, optional
        Per-record scene fields and repeat numbers, keyed by a ``file`` column.
    fit : bool
        Fit each record's contact parameters too (where :func:`pipeline.fit_contact` is
        installed).
    workers : int, optional
        Run on a local dask.distributed cluster of this many worker processes.
    scheduler : str or distributed.Client, optional
        Run on an existing dask cluster (``"tcp://host:8786"``) or client.
    batched : bool
        Analyse in this process with one vectorised bootstrap for all records
        (:mod:`pipeline.campaigns.batch`); not with ``workers``/``scheduler``.
    progress : callable, optional
        Called with each :class:`RecordResult` as it completes (the CLI's progress bar).
    reports : str or os.PathLike, optional
        Folder to write each analysed record's fit report into (module notes), from the
        process that analyses it: on a cluster, a folder every worker writes to at the same
        path. None (default): no reports, at no cost.
    report_html : bool
        The reports' HTML beside their notebooks.
    load : dict, optional
        Keyword arguments of :func:`pipeline.io.load` for every record, over each record's
        sidecar ``"load"`` block: a rig's ``sensitivity`` (``{"Fn": (0.225, "mV/N")}``),
        ``axes``, ``time_unit``, ``force_unit``, ``decouple``.
    **options
        Keyword arguments of :func:`pipeline.analyse` (``n_boot``, ``seed``, ``degree``,
        ``source``, ...), the same for every record.

    Returns
    -------
    xarray.Dataset
        Dimension ``record`` (module notes); ``attrs["trends_json"]`` and the ``trend_*``
        variables hold :func:`trends`.

    Raises
    ------
    InputError
        No records, an unreadable table, bad options, an unreachable scheduler. A bad
        record never raises: it is listed with ``status="failed"`` and its ``reason`` (a
        record whose file vanished during the run too).
    OutputError
        A record's report cannot be written (a full disk, a read-only or vanished folder),
        here or in a dask worker: the run ends.

    Warns
    -----
    ReportWarning
        A record's report could not be written, or is not where this process reads it
        (written on a worker's own disk).
    """
    _check_options(options)
    if batched and (workers or scheduler is not None):
        raise InputError("batched=True runs in this process; leave out workers/scheduler")
    tasks = plan(
        paths,
        scenes=scenes,
        table=table,
        fit=fit,
        reports=reports,
        report_html=report_html,
        load=load,
        **options,
    )
    gathered = Gathered(len(tasks))
    with connect(workers=workers, scheduler=scheduler) as client:
        if batched:
            for i, r in enumerate(analyse_tasks(tasks, progress=progress)):
                gathered.add(i, r)
        else:
            for i, r in iter_results(tasks, run_record, scheduler=client, progress=progress):
                gathered.add(i, r)
        if reports is not None:
            _check_reports(tasks, gathered)
        ds = assemble(tasks, gathered)
        ds.attrs["source"] = _label(paths)
        ds = with_trends(ds)
        if not fit:
            return ds
        # on a cluster, the joint fit's evaluations run on its workers too
        on = {} if client is None else {"executor": client.get_executor(pure=False)}
        return with_joint_fit(ds, tasks, **on)


def _check_reports(tasks, gathered) -> None:
    """A :class:`ReportWarning` for each analysed record whose report is missing: one that
    failed, or one written where this process cannot read it (a worker's own disk)."""
    for task, name, status, error in zip(
        tasks,
        gathered.result("name"),
        gathered.result("status"),
        gathered.result("report_error"),
        strict=True,
    ):
        if status != "ok":
            continue
        path = Path(task.report) / f"{Path(task.name).stem}.ipynb"
        if error:
            warnings.warn(f"{name}: no report: {error}", ReportWarning, stacklevel=3)
        elif not path.is_file():
            warnings.warn(
                f"{name}: its report is not at {path}: the worker wrote it on a disk of its "
                "own; give an output folder on the file system the workers share",
                ReportWarning,
                stacklevel=3,
            )


def _label(paths) -> str:
    """How the campaign's records were named (for titles): the folder, glob or files."""
    items = [paths] if isinstance(paths, (str, Path)) else list(paths)
    if len(items) == 1:
        return str(items[0])
    return f"{items[0]} and {len(items) - 1} more"


def _check_options(options: dict) -> None:
    allowed = set(inspect.signature(analyse).parameters) - {"record", "scene"}
    unknown = sorted(set(options) - allowed)
    if unknown:
        raise InputError(
            f"unknown option(s) {', '.join(unknown)}; campaign passes these to analyse: "
            f"{', '.join(sorted(allowed))}"
        )
