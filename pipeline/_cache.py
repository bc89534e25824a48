"""Tables computed once per machine: a cache folder shared by processes.

Some tables cost seconds to compute and are the same for every process of a machine (the
normal-pulse master curves of :mod:`pipeline.fit.pulse`, the outcome tables of
:mod:`pipeline.simulate.table`). They are written to a cache folder —
``$PIPELINE_CACHE``, default ``~/.cache/pipeline``; ``PIPELINE_CACHE=""`` keeps them in
memory only — as ``<stem>-<key>.npz``, ``key`` a digest of everything the content depends
on (a version number bumped when the code that computes it changes, and its inputs), so a
stale file is never read: it is simply not asked for.

Processes that share the folder compute a table once between them: :func:`cached_arrays`
holds a lock on ``<stem>-<key>.lock`` (POSIX ``flock``) while it reads or builds, so the
others wait and then read the file the first one wrote — a campaign's dask workers, which
inherit the folder from the process that starts them (on a cluster, point
``PIPELINE_CACHE`` at a shared folder). Where no lock can be taken (no ``fcntl``, a
read-only folder) each process builds its own; a file that cannot be written (a read-only
or full disk) leaves the table in memory. Files are written atomically
(:mod:`pipeline._atomic`), so a reader never sees half of one.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import os
from collections.abc import Callable
from pathlib import Path

import numpy as np

try:
    import fcntl
except ImportError:  # not POSIX: no build lock, each process builds its own tables
    fcntl = None

from ._atomic import atomic_write_bytes

__all__ = ["cache_dir", "build_lock", "digest", "cached_arrays"]


def cache_dir() -> Path | None:
    """The cache folder (module notes), or None where caching on disk is off."""
    env = os.environ.get("PIPELINE_CACHE")
    if env is not None:
        return Path(env) if env else None
    return Path.home() / ".cache" / "pipeline"


def digest(spec: str) -> str:
    """A file-name key for the text ``spec`` naming everything a table depends on."""
    return hashlib.sha256(spec.encode()).hexdigest()[:24]


@contextlib.contextmanager
def build_lock(path):
    """Hold the lock of one cache file while it is read or built (module notes): another
    process building it makes this one wait, then read it. No lock without a cache file,
    without ``fcntl`` or where the lock file cannot be made."""
    if path is None or fcntl is None:
        yield
        return
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fh = open(path.with_suffix(".lock"), "a")
    except OSError:
        yield
        return
    with fh:
        fcntl.flock(fh, fcntl.LOCK_EX)  # released when the file is closed
        yield


def read_arrays(path, names) -> dict | None:
    """The arrays ``names`` of the ``.npz`` file at ``path``, or None where it is missing,
    unreadable or lacks one of them."""
    try:
        with np.load(path) as z:
            return {k: z[k] for k in names}
    except (OSError, KeyError, ValueError, EOFError):
        return None


def write_arrays(path, arrays: dict) -> None:
    """Write ``arrays`` to the ``.npz`` file at ``path`` atomically; a folder that cannot
    take it (read-only, full) leaves the caller's table in memory only."""
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    with contextlib.suppress(OSError):
        atomic_write_bytes(path, buf.getvalue())


def cached_arrays(stem: str, spec: str, names, build: Callable[[], dict]) -> tuple[dict, bool]:
    """The arrays of one table: read from the cache folder, else built and written there.

    Parameters
    ----------
    stem : str — the file name's prefix (``normal-pulse``, ``outcome-table``)
    spec : str — everything the table depends on (its key is a digest of it)
    names : sequence of str — the arrays ``build`` returns and the file holds
    build : callable — ``build() -> {name: numpy.ndarray}``

    Returns
    -------
    (arrays, built) — ``built`` is False where the arrays were read from the cache
    """
    folder = cache_dir()
    path = None if folder is None else folder / f"{stem}-{digest(spec)}.npz"
    with build_lock(path):
        found = None if path is None else read_arrays(path, names)
        if found is not None:
            return found, False
        arrays = build()
        if path is not None:
            write_arrays(path, arrays)
        return arrays, True
