"""Running campaign tasks: serially, or as dask.distributed tasks (``docs/cluster.md``).

Each task is a pure function of its :class:`~pipeline.campaigns.tasks.RecordTask`, so the
results gathered from a cluster, put back in task order, equal the serial ones. Records go
to the cluster in chunks (:data:`CHUNKS_PER_WORKER` per worker, at most
:data:`MAX_CHUNK` records each), so that a record's ~20 ms is not eaten by the scheduler's
round trip, and a chunk's results are handed on as soon as they arrive and released on the
cluster: no process holds more than a few chunks' results at a time, whatever the number of
records (:func:`iter_results`). Run serially, the process frees the records' cyclic
garbage every :data:`COLLECT_EVERY` records and hands the memory freed back to the system
(glibc's ``malloc_trim``, as dask's workers do with their trim threshold): a record's fits
leave reference cycles that hold arrays, which Python's oldest generation collects only
now and then, and a serial campaign's peak grew by ~0.3 MB a record over its first few
hundred records. A worker that cannot write the output (a full disk:
:class:`~pipeline.errors.OutputError`) ends the run with the same one-line error as this
process would.

A dask client, scheduler and worker keep their last messages, task transitions and events
for debugging (``distributed.admin.low-level-log-length``: 1,000 of each by default), and
a message holds what it carries: on a cluster a joint fit's evaluations send chunks of
records of up to ~1.4 MB (:mod:`pipeline.fit.blocks`), and the logs of the client and of a
local cluster's scheduler (both in this process) held ~35 MB of them after a joint fit of
1,000 records, and could hold a thousand chunks each where the records are shorter. The
clients and local clusters started here (:func:`open_client`, :func:`local_cluster`) keep
:data:`LOG_LENGTH` of each; a client or cluster the caller made keeps its own settings.
"""

from __future__ import annotations

import contextlib
import logging

from .._memory import release
from ..errors import InputError, OutputError

__all__ = [
    "run_tasks",
    "iter_results",
    "connect",
    "local_cluster",
    "open_client",
    "LOG_LENGTH",
    "CHUNKS_PER_WORKER",
    "MAX_CHUNK",
]

#: Chunks of records per worker: enough to balance uneven records, few enough that the
#: scheduler's per-task cost (~ms) stays small against the work.
CHUNKS_PER_WORKER = 2
#: Records between two releases of a serial run's freed memory (:func:`iter_results`):
#: a full collection costs tens of ms, a record some hundreds.
COLLECT_EVERY = 20
#: Messages, transitions and events kept for debugging by each dask client, scheduler and
#: worker started here (module notes; dask's ``distributed.admin.low-level-log-length``).
LOG_LENGTH = 16
#: Most records in one chunk (a chunk's results wait on its worker until all are done:
#: ~13 kB a record).
MAX_CHUNK = 50


def local_cluster(workers: int):
    """A ``distributed.LocalCluster`` of ``workers`` single-threaded processes for records.

    The workers' C allocator keeps freed memory for reuse (``MALLOC_MMAP_THRESHOLD_`` 32 MiB,
    ``MALLOC_TRIM_THRESHOLD_`` 256 MiB) instead of dask's default ``MALLOC_TRIM_THRESHOLD_``
    of 64 kiB: the bootstrap makes temporaries of a few hundred kB, and handing each back to
    the system and faulting it in again made a record cost ~1.5× as long in a worker as in
    a long-running process (measured: 47 against 32 ms; ``make bench``, ``campaign``).

    The workers' statistical profiler is off: it samples every task's stack every 10 ms
    and keeps an hour of those trees, and a record's deep stacks (its fit, its report's
    figures) made each worker grow by ~0.8 MB a record (from 306 MB at 10 records to
    774 MB at 1,000; ``make bench``, ``campaign_scale``). With it off a worker peaks at
    266 MB at 10 records and 351 MB at 1,000.

    The scheduler and the workers keep :data:`LOG_LENGTH` of their recent messages,
    transitions and events (module notes).
    """
    import dask
    from distributed import LocalCluster

    env = dict(dask.config.get("distributed.nanny.pre-spawn-environ", {}))
    env.update(MALLOC_MMAP_THRESHOLD_=32 << 20, MALLOC_TRIM_THRESHOLD_=256 << 20)
    settings = {
        "distributed.nanny.pre-spawn-environ": env,
        "distributed.worker.profile.enabled": False,
        "distributed.admin.low-level-log-length": LOG_LENGTH,
    }
    with dask.config.set(settings):
        return LocalCluster(
            n_workers=int(workers),
            threads_per_worker=1,
            processes=True,
            dashboard_address=":0",  # a free port: never the warning that 8787 is taken
        )


def open_client(address, **options):
    """A ``distributed.Client`` of ``address`` (a scheduler's, or a cluster; ``options`` as
    the Client's) that keeps :data:`LOG_LENGTH` of its recent messages (module notes)."""
    import dask
    from distributed import Client

    with dask.config.set({"distributed.admin.low-level-log-length": LOG_LENGTH}):
        return Client(address, **options)


def _run_chunk(fn, chunk):
    """The results of a chunk of tasks, or the :class:`OutputError` that ended it: returned,
    not raised, so the worker does not log it with its traceback; the client raises it."""
    try:
        return [fn(t) for t in chunk]
    except OutputError as exc:
        return exc


def _results(part) -> list:
    if isinstance(part, OutputError):
        raise part
    return part


def run_tasks(tasks, fn, *, workers=None, scheduler=None, progress=None) -> list:
    """``[fn(t) for t in tasks]``, serially or as dask.distributed tasks, in task order."""
    out = [None] * len(tasks)
    for i, r in iter_results(tasks, fn, workers=workers, scheduler=scheduler, progress=progress):
        out[i] = r
    return out


def iter_results(tasks, fn, *, workers=None, scheduler=None, progress=None):
    """``(i, fn(tasks[i]))`` for every task, as they complete (in task order when serial),
    serially or as dask.distributed tasks (module notes; ``workers`` and ``scheduler`` as
    :func:`connect`); ``progress`` is called with each result."""
    with connect(workers=workers, scheduler=scheduler) as client:
        if client is None:
            for i, t in enumerate(tasks):
                r = fn(t)
                if i % COLLECT_EVERY == COLLECT_EVERY - 1:
                    release()  # the records' cyclic garbage, and the memory it held
                if progress is not None:
                    progress(r)
                yield i, r
            return
        yield from _distributed(client, tasks, fn, progress)


def _distributed(client, tasks, fn, progress):
    from distributed import as_completed

    futures = {}
    try:
        n_workers = max(1, len(client.scheduler_info().get("workers", {})))
        size = max(1, min(MAX_CHUNK, -(-len(tasks) // (CHUNKS_PER_WORKER * n_workers))))
        for a in range(0, len(tasks), size):
            futures[client.submit(_run_chunk, fn, tasks[a : a + size], pure=False)] = a
        for f in as_completed(list(futures)):
            part = _results(f.result())
            a = futures.pop(f)
            f.release()  # its results leave the cluster's memory
            for k, r in enumerate(part):
                if progress is not None:
                    progress(r)
                yield a + k, r
    except BaseException:  # the run ends here: the chunks still running are cancelled
        with contextlib.suppress(Exception):
            client.cancel(list(futures))
        raise


@contextlib.contextmanager
def connect(*, workers=None, scheduler=None):
    """The dask client a campaign runs on, for the length of the ``with`` block: None
    (serial: neither given), the caller's ``distributed.Client`` (``scheduler=client``),
    one connected to the scheduler at an address (``"tcp://host:8786"``), or one of a
    local cluster of ``workers`` processes (:func:`local_cluster`), started here and
    stopped at the end — quietly when an error ends the run."""
    if scheduler is None and not workers:
        yield None
        return
    try:
        import distributed  # noqa: F401
    except ImportError:
        raise InputError(
            "running on dask needs the 'distributed' extra: pip install 'pipeline[distributed]'"
        ) from None
    cluster = None
    if scheduler is not None and not isinstance(scheduler, str):
        client = scheduler  # a distributed.Client the caller owns
    elif scheduler is not None:
        try:
            client = open_client(scheduler, timeout="10s")
        except (OSError, TimeoutError) as exc:
            raise InputError(f"cannot reach the dask scheduler at {scheduler}: {exc}") from exc
    else:
        if int(workers) < 1:
            raise InputError(f"workers must be ≥ 1, got {workers}")
        cluster = local_cluster(workers)
        client = open_client(cluster)
    hushed = contextlib.nullcontext()
    try:
        yield client
    except BaseException:
        if cluster is not None:
            hushed = _hushed(client)
        raise
    finally:
        with hushed:
            if client is not scheduler:
                client.close()
            if cluster is not None:
                with _nanny_quiet():
                    cluster.close()


@contextlib.contextmanager
def _nanny_quiet():
    """The local cluster's nannies stop their workers without a word: every result was
    returned, and a worker slow to exit (a loaded machine, a thread left running by a
    library) is killed after 4 s with a WARNING that would be the last line of a good run."""
    log = logging.getLogger("distributed.nanny")
    level = log.level
    log.setLevel(logging.ERROR)
    try:
        yield
    finally:
        log.setLevel(level)


def _quiet():
    logging.getLogger("distributed").setLevel(logging.ERROR)


@contextlib.contextmanager
def _hushed(client):
    """A local cluster stopped mid-run (an error ends the campaign, and says why), without
    its workers and nannies logging each chunk they cancel and each worker they stop."""
    with contextlib.suppress(Exception):
        client.run(_quiet)  # in the workers (their event loops answer while a chunk runs)
    log = logging.getLogger("distributed")
    level = log.level
    _quiet()  # the nannies, in this process
    try:
        yield
    finally:
        log.setLevel(level)
