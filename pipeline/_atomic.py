"""Atomic file output: write beside the target, then rename over it.

A reader (or a crashed run) never sees a half-written file: :func:`atomic_path` yields a
temporary path in the target's folder and, once the caller has written it without error,
renames it over the target with :func:`os.replace` (atomic on POSIX and Windows). Files get
the usual rw-r--r-- permissions (``mkstemp`` would leave them rw-------).
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path

__all__ = ["atomic_path", "atomic_write_text", "atomic_write_bytes"]


@contextlib.contextmanager
def atomic_path(path, *, mode: int = 0o644) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; rename it over ``path`` on success.

    The temporary file keeps ``path``'s suffix (so writers that choose a format by suffix,
    such as ``Figure.savefig``, still work) and is removed if the block raises.
    """
    path = Path(os.fspath(path))
    path.parent.mkdir(parents=True, exist_ok=True)  # Path("r.csv").parent is Path(".")
    fd, tmp = tempfile.mkstemp(
        prefix=f".{path.stem}.", suffix=f".tmp{path.suffix}", dir=path.parent
    )
    os.close(fd)
    try:
        yield Path(tmp)
        os.chmod(tmp, mode)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def atomic_write_text(path, text: str, *, encoding: str = "utf-8", newline: str = "\n") -> Path:
    """Write ``text`` to ``path`` atomically (``newline`` replaces every ``\\n``)."""
    with atomic_path(path) as tmp, open(tmp, "w", encoding=encoding, newline=newline) as fh:
        fh.write(text)
        fh.flush()
        os.fsync(fh.fileno())
    return Path(path)


def atomic_write_bytes(path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically."""
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        fh.write(data)
        fh.flush()
        os.fsync(fh.fileno())
    return Path(path)
