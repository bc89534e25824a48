"""Running campaign tasks: serially, or as dask.distributed tasks (``docs/cluster.md``).

Each task is a pure function of its :class:`~pipeline.campaign.tasks.RecordTask`, so the
results gathered from a cluster, put back in task order, equal the serial ones.
"""

from __future__ import annotations

from ..errors import InputError

__all__ = ["run_tasks"]


def run_tasks(tasks, fn, *, workers=None, scheduler=None, progress=None) -> list:
    """``[fn(t) for t in tasks]``, serially or as dask.distributed tasks, in task order."""
    if scheduler is None and not workers:
        out = []
        for t in tasks:
            r = fn(t)
            out.append(r)
            if progress is not None:
                progress(r)
        return out
    try:
        from distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise InputError(
            "running on dask needs the 'distributed' extra: pip install 'pipeline[distributed]'"
        ) from None
    cluster = None
    if scheduler is not None and not isinstance(scheduler, str):
        client = scheduler  # a distributed.Client the caller owns
    elif scheduler is not None:
        try:
            client = Client(scheduler, timeout="10s")
        except (OSError, TimeoutError) as exc:
            raise InputError(f"cannot reach the dask scheduler at {scheduler}: {exc}") from exc
    else:
        if int(workers) < 1:
            raise InputError(f"workers must be ≥ 1, got {workers}")
        cluster = LocalCluster(
            n_workers=int(workers),
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
        )
        client = Client(cluster)
    try:
        futures = client.map(fn, tasks, pure=False)
        if progress is not None:
            for f in as_completed(futures):
                progress(f.result())
        return client.gather(futures)
    finally:
        if client is not scheduler:
            client.close()
        if cluster is not None:
            cluster.close()
