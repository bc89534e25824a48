r"""The batched path: many records on one machine, the bootstrap of all of them at once.

:func:`pipeline.analyse` spends most of its time in the bootstrap (replicates of the
percussions of three sources, re-fits, two scores). A campaign stores the score and the
outcomes of the *scored* source only, and for sampled records that source's replicates are
linear in the noise:

.. math::

    P^{(b)}(t) = P(t) + \sigma \int_{t_s}^{t} Z^{(b)}\,dt', \qquad Z^{(b)} \sim N(0, 1)
    \text{ at the samples,}

so :func:`analyse_tasks` runs every stage of each record without the bootstrap, then draws
the noise of a chunk of records as one array (records × replicates × samples, shorter
windows padded with zero-length steps that add nothing) and integrates it in one vectorised
cumulative trapezoid, and scores the replicates record by record (vectorised over the
replicates). The values are those of :func:`pipeline.analyse`; the standard deviations come
from other draws of the same noise model, integrated by the trapezoid rule (for white
noise Simpson's weights spread an integral by up to √(10/9) ≈ 1.05 times more, so the
batched standard deviations of a Simpson-scored record may come out a few % lower; the
scatter of a 200-replicate std is itself ±5 %), and the quartic's score (``score_fit``)
carries none. Records whose channels are not sampled on the percussion grid (digitised)
take :func:`pipeline.analyse`'s own bootstrap. A record's report (``reports=``) shows
:func:`pipeline.analyse`'s own bootstrap too, the one its notebook recomputes: the record is
analysed again for it.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .. import analysis as _an
from .. import score as _score
from ..record import channel
from ..smooth import noise_level
from .tasks import RecordResult, RecordTask, _analysis_of, guarded, result_of, try_report

__all__ = ["analyse_tasks", "CHUNK"]

#: Records whose replicates are drawn and integrated together (bounds the memory:
#: chunk × n_boot × samples × 8 bytes per channel).
CHUNK = 64


def analyse_tasks(tasks: list[RecordTask], *, progress=None) -> list[RecordResult]:
    """Analyse the tasks in this process, bootstrapping all records at once (module notes).

    Returns the same :class:`~pipeline.campaigns.tasks.RecordResult` list as running
    :func:`~pipeline.campaigns.tasks.run_record` on each task would, failures included.
    """
    results: list[RecordResult | None] = [None] * len(tasks)
    pending = []  # (index, task, analysed, warnings, n_boot, report error)
    for i, task in enumerate(tasks):
        value, failed, msgs = guarded(task, _without_bootstrap)
        if failed is not None:
            results[i] = failed
            _tick(progress, failed)
            continue
        done, n_boot = value
        report_error = try_report(task, done, reanalyse=n_boot > 0)
        if n_boot > 0:
            pending.append(
                (i, task, dataclasses.replace(done, fit=None), msgs, n_boot, report_error)
            )
        else:
            results[i] = result_of(task, done, msgs, report_error)
            _tick(progress, results[i])
        if len(pending) == CHUNK:
            _flush(pending, results, progress)
            pending = []
    _flush(pending, results, progress)
    return results


def _flush(pending, results, progress) -> None:
    """Bootstrap a chunk of analyses together and put their results in place."""
    if not pending:
        return
    for (k, t, done, msgs, _, report_error), boot in zip(pending, _bootstrap(pending), strict=True):
        done = dataclasses.replace(done, analysis=_rescore(done.analysis, boot))
        results[k] = result_of(t, done, msgs, report_error)
        _tick(progress, results[k])


def _without_bootstrap(task):
    """(Analysed, replicates still to draw): the record analysed without its bootstrap
    where the batch can draw it, with its own where not (digitised)."""
    n_boot = int(task.options.get("n_boot", 200))
    done = _analysis_of(task, n_boot=0)
    if n_boot > 0 and not _sampled_on_grid(done.analysis):
        return _analysis_of(task), 0
    return done, n_boot


def _tick(progress, result):
    if progress is not None:
        progress(result)


def _sampled_on_grid(a) -> bool:
    """Both channels sampled at every grid instant but the padded window ends (sensor
    records; digitised channels are clicked at instants of their own)."""
    grid = a.percussions.time
    for name in ("Fn", "Ft"):
        t, _ = channel(a.window.record, name)
        inner = grid[(grid >= t[0]) & (grid <= t[-1])]
        if grid.size - inner.size > 2 or not np.array_equal(inner, t):
            return False
    return a.source in ("simpson", "trapezoid")


def _bootstrap(chunk) -> list[tuple]:
    """``(Pn_b, Pt_b)`` on each record's grid for a chunk of analyses, drawn and integrated
    together: noise Z (records, B, grid) per channel, zero at the grid's padded window ends
    (no sample there) and past a shorter grid's end, where zero-length steps add nothing."""
    n_boot = max(item[4] for item in chunk)
    rng = np.random.default_rng(int(chunk[0][1].options.get("seed", 0)))
    grids = [item[2].analysis.percussions.time for item in chunk]
    g_max = max(g.size for g in grids)
    T = np.stack([np.pad(g, (0, g_max - g.size), mode="edge") for g in grids])
    dt = np.diff(T, axis=-1)[:, None, :]
    out = []
    reps = {}
    for name in ("Fn", "Ft"):
        mask = np.zeros((len(chunk), g_max))
        sig = np.empty(len(chunk))
        for k, item in enumerate(chunk):
            a = item[2].analysis
            mask[k, : grids[k].size] = np.isin(grids[k], channel(a.window.record, name)[0])
            sig[k] = noise_level(a.window, a.fits, name)
        Z = rng.standard_normal((len(chunk), n_boot, g_max)) * (sig[:, None] * mask)[:, None, :]
        steps = 0.5 * (Z[..., 1:] + Z[..., :-1]) * dt
        zero = np.zeros(steps.shape[:-1] + (1,))
        reps[name] = np.concatenate([zero, np.cumsum(steps, axis=-1)], axis=-1)
    for k, item in enumerate(chunk):
        a, g = item[2].analysis, grids[k].size
        out.append(
            (
                a.percussions.Pn(a.source) + reps["Fn"][k, :, :g],
                a.percussions.Pt(a.source) + reps["Ft"][k, :, :g],
            )
        )
    return out


def _rescore(a, boot):
    """``a`` with its score and outcomes given the bootstrap replicates ``boot``."""
    perc, split = a.percussions, a.split
    b = _an._boot_for(split, {a.source: boot}, perc)
    score = _score.deviation_score(
        perc.time,
        perc.Pn(a.source),
        perc.Pt(a.source),
        a.rigid,
        split.Pn_c,
        boot=b,
        source=a.source,
    )
    outcomes = _an._outcomes(a.scene, perc, split, a.source, b)
    return dataclasses.replace(a, score=score, outcomes=outcomes)
