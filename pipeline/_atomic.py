"""Atomic output: a file, or a whole folder of them, replaced in one rename.

A reader (or a crashed run) never sees a half-written file: :func:`atomic_path` yields a
temporary path in the target's folder and, once the caller has written it without error,
renames it over the target with :func:`os.replace` (atomic on POSIX and Windows). Files get
the usual rw-r--r-- permissions (``mkstemp`` would leave them rw-------).

A run that writes several files (``make reproduce``) must not leave a folder that mixes
the files of two runs. :func:`atomic_dir` yields a *staging* folder beside the target;
once everything is written it takes the target's place in one rename — on Linux an
atomic exchange of the two names (``renameat2(RENAME_EXCHANGE)``), so the target path
never stops holding a complete run; elsewhere (or on a file system without the exchange)
the old folder is renamed away first, leaving a moment with no folder at all, never a
mixed one. Staging and replaced folders carry the writing process's id in their names
(``.<name>.staging-<pid>-*``, ``.<name>.old-<pid>-*``); :func:`clean_stale`, called by
:func:`atomic_dir`, removes those of processes that no longer run (a killed run).
"""

from __future__ import annotations

import contextlib
import ctypes
import errno
import os
import re
import shutil
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path

__all__ = [
    "atomic_path",
    "atomic_write_text",
    "atomic_write_bytes",
    "atomic_dir",
    "clean_stale",
]


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


# ----------------------------------------------------------------------- whole folders
@contextlib.contextmanager
def atomic_dir(path) -> Iterator[Path]:
    """Yield an empty staging folder beside ``path``; on success it replaces ``path``.

    Stale staging folders of killed runs are removed first (:func:`clean_stale`). If the
    block raises, the staging folder is removed and ``path`` keeps the previous run.
    """
    path = Path(os.fspath(path))
    path.parent.mkdir(parents=True, exist_ok=True)
    clean_stale(path)
    stage = Path(tempfile.mkdtemp(prefix=f".{path.name}.staging-{os.getpid()}-", dir=path.parent))
    try:
        yield stage
        os.chmod(stage, 0o755)
        _sync(stage)
        _replace_dir(stage, path)
    except BaseException:
        shutil.rmtree(stage, ignore_errors=True)
        raise


def clean_stale(path) -> list[Path]:
    """Remove the staging and replaced folders of ``path`` left by runs that died.

    Returns the folders removed. A folder whose process (by the id in its name) still
    runs is left alone: that run is writing it.
    """
    path = Path(os.fspath(path))
    pattern = re.compile(rf"^\.{re.escape(path.name)}\.(?:staging|old)-(\d+)-")
    removed = []
    if not path.parent.is_dir():
        return removed
    for entry in path.parent.iterdir():
        m = pattern.match(entry.name)
        if m is None or _alive(int(m.group(1))):
            continue
        if entry.is_dir() and not entry.is_symlink():
            shutil.rmtree(entry, ignore_errors=True)
        else:
            with contextlib.suppress(OSError):
                entry.unlink()
        removed.append(entry)
    return removed


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OSError):  # another user's process, or no way to tell
        return True
    return True


def _sync(folder: Path) -> None:
    """Flush the folder's entries to disk before it is renamed into place (POSIX)."""
    if not hasattr(os, "O_DIRECTORY"):  # pragma: no cover - Windows
        return
    fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _replace_dir(stage: Path, path: Path) -> None:
    """Put ``stage`` at ``path``: one atomic exchange where the system has it."""
    try:
        os.rename(stage, path)  # no folder there yet: one atomic rename
        return
    except OSError as exc:
        if exc.errno not in (errno.EEXIST, errno.ENOTEMPTY, errno.EISDIR, errno.ENOTDIR):
            raise
    if _exchange(stage, path):
        shutil.rmtree(stage, ignore_errors=True)  # stage now holds the previous run
        return
    old = Path(tempfile.mkdtemp(prefix=f".{path.name}.old-{os.getpid()}-", dir=path.parent))
    os.rmdir(old)
    os.rename(path, old)
    os.rename(stage, path)
    shutil.rmtree(old, ignore_errors=True)


_RENAME_EXCHANGE = 2
_AT_FDCWD = -100


def _exchange(a: Path, b: Path) -> bool:
    """Swap two paths atomically (Linux ``renameat2``); False where unsupported."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        renameat2 = libc.renameat2
    except (OSError, AttributeError):  # pragma: no cover - old glibc, musl
        return False
    renameat2.argtypes = [
        ctypes.c_int,
        ctypes.c_char_p,
        ctypes.c_int,
        ctypes.c_char_p,
        ctypes.c_uint,
    ]
    rc = renameat2(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE)
    if rc == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP):  # pragma: no cover
        return False
    raise OSError(err, os.strerror(err), str(b))
