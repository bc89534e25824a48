"""Atomic output: a file, or a whole folder of them, replaced in one rename.

A reader (or a crashed run) never sees a half-written file: :func:`atomic_path` yields a
temporary path in the target's folder and, once the caller has written it without error,
renames it over the target with :func:`os.replace` (atomic on POSIX and Windows). Files get
the usual rw-r--r-- permissions (``mkstemp`` would leave them rw-------).
:func:`atomic_write_bytes` and :func:`atomic_write_text` write bytes made in memory (a
figure's PNG, a notebook, a netCDF file) with the system's own calls, so that no library
ever writes to a disk that can fill under it.

A run that writes several files (``make reproduce``) must not leave a folder that mixes
the files of two runs. :func:`atomic_dir` yields a *staging* folder beside the target;
once everything is written it takes the target's place in one rename — on Linux an
atomic exchange of the two names (``renameat2(RENAME_EXCHANGE)``), so the target path
never stops holding a complete run; elsewhere (or on a file system without the exchange)
the old folder is renamed away first, leaving a moment with no folder at all, never a
mixed one. Staging and replaced folders carry the writing process's id in their names
(``.<name>.staging-<pid>-*``, ``.<name>.old-<pid>-*``); :func:`clean_stale`, called by
:func:`atomic_dir`, removes those of processes that no longer run (a killed run).
A few files written into a folder that holds other things (``pipeline fit --out DIR``) go
in together (:func:`atomic_files`): each to a temporary beside its target, and none renamed
into place before all are written.

Faults of the machine. Every output passes through this module, and an :class:`OSError`
on its way (a full disk, a folder turned read-only, lost permission or vanished, a failing
device) comes out as :class:`pipeline.errors.OutputError`: one line naming the output as
the caller named it (never its temporary or staging name), the fault, and what the
output's place still holds — the previous output, whole. A staging folder that vanished
(its parent deleted during the run) is never made again (:func:`make_dirs`): the run ends.
"""

from __future__ import annotations

import contextlib
import contextvars
import ctypes
import errno
import os
import re
import shutil
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path

from .errors import OutputError

__all__ = [
    "atomic_path",
    "atomic_write_text",
    "atomic_write_bytes",
    "atomic_files",
    "atomic_dir",
    "make_dirs",
    "clean_stale",
]

#: A staging folder's name (:func:`atomic_dir`): ``.<name>.staging-<pid>-<random>``.
_STAGING = re.compile(r"^\..+\.staging-\d+-")


# ----------------------------------------------------------------------- one file
@contextlib.contextmanager
def atomic_path(path, *, mode: int = 0o644) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; rename it over ``path`` on success.

    The temporary file keeps ``path``'s suffix (so writers that choose a format by suffix,
    such as ``Figure.savefig``, still work) and is removed if the block raises. Inside
    :func:`atomic_files` the rename waits for the group's end. An :class:`OSError` of the
    block on the temporary file (or naming no file) becomes an
    :class:`~pipeline.errors.OutputError` naming ``path``.
    """
    path = Path(os.fspath(path))
    existed = path.exists()
    make_dirs(path.parent)
    tmp, in_block = None, False
    try:
        fd, tmp = tempfile.mkstemp(
            prefix=f".{path.stem}.", suffix=f".tmp{path.suffix}", dir=path.parent
        )
        os.close(fd)
        in_block = True
        yield Path(tmp)
        in_block = False
        os.chmod(tmp, mode)
        group = _GROUP.get()
        if group is not None and group.holds(path):
            group.pending.append((tmp, path))
        else:
            os.replace(tmp, path)
    except BaseException as exc:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
        if _on(exc, tmp, path, anywhere=not in_block):
            raise _fault(exc, path, _kept_file(path, existed)) from exc
        raise


def atomic_write_bytes(path, data) -> Path:
    """Write ``data`` (bytes, or any buffer) to ``path`` atomically, flushed to the disk."""
    with atomic_path(path) as tmp:
        fd = os.open(tmp, os.O_WRONLY | os.O_TRUNC | getattr(os, "O_BINARY", 0))
        try:
            view = memoryview(data).cast("B")
            while view:
                view = view[os.write(fd, view) :]
            os.fsync(fd)
        finally:
            os.close(fd)
    return Path(path)


def atomic_write_text(path, text: str, *, encoding: str = "utf-8", newline: str = "\n") -> Path:
    """Write ``text`` to ``path`` atomically (``newline`` replaces every ``\\n``)."""
    if newline not in ("", "\n"):
        text = text.replace("\n", os.linesep if newline is None else newline)
    return atomic_write_bytes(path, text.encode(encoding))


def make_dirs(folder) -> Path:
    """Make ``folder`` and its missing parents (``mkdir -p``) for an output.

    Never makes a staging folder (:func:`atomic_dir`) again: one that is missing vanished
    during its run (its parent deleted), and the files already written into it with it, so
    that is an :class:`~pipeline.errors.OutputError` (ENOENT), as is any other failure.
    """
    folder = Path(os.fspath(folder))
    missing, p = [], folder
    while not p.is_dir() and p != p.parent:
        missing.append(p)
        p = p.parent
    if not missing:
        return folder
    gone = next((m for m in missing if _STAGING.match(m.name)), None)
    if gone is not None:
        raise OutputError(errno.ENOENT, os.strerror(errno.ENOENT), folder)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise _fault(exc, folder, "nothing was written") from exc
    group = _GROUP.get()
    if group is not None:
        group.made += [m for m in reversed(missing) if group.holds(m) or group.below(m)]
    return folder


# ----------------------------------------------------------------------- files together
class _Group:
    def __init__(self, folder: Path):
        self.folder = os.path.abspath(folder)
        self.pending: list[tuple[str, Path]] = []  # (temporary, target), written
        self.made: list[Path] = []  # folders made for the group, parents first

    def holds(self, path) -> bool:
        """``path`` is the group's folder or inside it (a cache file elsewhere is not)."""
        path = os.path.abspath(path)
        return path == self.folder or path.startswith(self.folder + os.sep)

    def below(self, folder) -> bool:
        """The group's folder is inside ``folder`` (made to reach it)."""
        return self.folder.startswith(os.path.join(os.path.abspath(folder), ""))


_GROUP: contextvars.ContextVar[_Group | None] = contextvars.ContextVar("group", default=None)


@contextlib.contextmanager
def atomic_files(folder) -> Iterator[None]:
    """Files written into ``folder`` in the block (by :func:`atomic_path` and the writers
    built on it) go into place together at its end: none is renamed over its target
    before all are written. If the block raises, no target changes and the folders made
    for the files are removed again. Files elsewhere (a cache) are written as usual. A
    group inside a group joins it (its files should be in the outer group's folder).

    Only the renames are left at the end (no data written, no space needed): a fault
    between two of them (the file system turned read-only in that instant) leaves the
    files renamed so far new, each whole, and the error says which.
    """
    if _GROUP.get() is not None:
        yield
        return
    folder = Path(os.fspath(folder))
    existed = folder.is_dir()
    group = _Group(folder)
    token = _GROUP.set(group)
    try:
        yield
    except BaseException as exc:
        _drop(group)
        if isinstance(exc, OutputError):
            exc.kept = (
                f"the files in {folder} are the previous ones, untouched"
                if existed
                else "nothing was written"
            )
        raise
    finally:
        _GROUP.reset(token)
    done = []
    for i, (tmp, path) in enumerate(group.pending):
        try:
            os.replace(tmp, path)
        except OSError as exc:
            group.pending = group.pending[i:]
            _drop(group, folders=False)
            kept = (
                f"already replaced: {', '.join(p.name for p in done)}; the other files in "
                f"{folder} are the previous ones"
                if done
                else f"the files in {folder} are the previous ones, untouched"
            )
            raise _fault(exc, path, kept) from exc
        done.append(path)


def _drop(group: _Group, *, folders: bool = True) -> None:
    """Remove a failed group's temporary files and (``folders``) the folders made for it."""
    for tmp, _ in group.pending:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
    for folder in reversed(group.made if folders else []):
        with contextlib.suppress(OSError):
            folder.rmdir()  # only if empty: never another run's files


# ----------------------------------------------------------------------- whole folders
@contextlib.contextmanager
def atomic_dir(path) -> Iterator[Path]:
    """Yield an empty staging folder beside ``path``; on success it replaces ``path``.

    Stale staging folders of killed runs are removed first (:func:`clean_stale`). If the
    block raises, the staging folder is removed and ``path`` keeps the previous run; an
    :class:`OSError` on the staging folder (an :class:`~pipeline.errors.OutputError` from
    a writer, in this process or a dask worker's) becomes an ``OutputError`` naming the
    file under ``path`` and saying that ``path`` is untouched.
    """
    path = Path(os.fspath(path))
    existed = path.is_dir()
    kept = f"{path} holds the previous run, untouched" if existed else f"{path} was not created"
    make_dirs(path.parent)
    clean_stale(path)
    try:
        stage = Path(
            tempfile.mkdtemp(prefix=f".{path.name}.staging-{os.getpid()}-", dir=path.parent)
        )
    except OSError as exc:
        raise _fault(exc, path, kept) from exc
    token = _GROUP.set(None)  # the staged files go in with the folder, not a group's
    try:
        yield stage
    except BaseException as exc:
        kept += _discard(stage)
        moved = _staged(exc, stage, path)
        if moved is None:
            raise
        raise _fault(exc, moved, kept) from exc
    finally:
        _GROUP.reset(token)
    try:
        os.chmod(stage, 0o755)
        _sync(stage)
        _replace_dir(stage, path)
    except OSError as exc:
        kept = (getattr(exc, "kept", "") or kept) + _discard(stage)
        raise _fault(exc, path, kept, action="cannot move the new run into") from exc


def _discard(stage: Path) -> str:
    """Remove a failed run's staging folder; what the message says if it stays."""
    shutil.rmtree(stage, ignore_errors=True)
    if stage.exists():
        return f" (its staging folder {stage.name} stays; the next run removes it)"
    return ""


def _staged(exc, stage: Path, path: Path) -> Path | None:
    """Where under ``path`` the file an OSError names would be, for an error on the
    staging folder; None for any other exception (not a fault of this output)."""
    if not isinstance(exc, OSError) or exc.filename is None:
        return None
    try:
        rel = Path(os.path.abspath(exc.filename)).relative_to(os.path.abspath(stage))
    except ValueError:
        return None
    return path / rel


def clean_stale(path) -> list[Path]:
    """Remove the staging and replaced folders of ``path`` left by runs that died.

    Returns the folders removed. A folder whose process (by the id in its name) still
    runs is left alone: that run is writing it. A folder that cannot be read or removed
    (read-only, gone) is left as it is.
    """
    path = Path(os.fspath(path))
    pattern = re.compile(rf"^\.{re.escape(path.name)}\.(?:staging|old)-(\d+)-")
    removed = []
    try:
        entries = list(path.parent.iterdir())
    except OSError:
        return removed
    for entry in entries:
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
    try:
        os.rename(stage, path)
    except OSError as exc:
        try:
            os.rename(old, path)  # the previous run back in its place
        except OSError:
            exc.kept = f"the previous run is in {old}, whole; rename it back to {path}"
        raise
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


# ----------------------------------------------------------------------- faults
def _on(exc, *paths, anywhere: bool = False) -> bool:
    """An OSError, not yet an OutputError, on one of ``paths`` (``anywhere``: on any file),
    or naming no file (a write to an open file)."""
    if not isinstance(exc, OSError) or isinstance(exc, OutputError):
        return False
    if anywhere or exc.filename is None:
        return True
    return os.fspath(exc.filename) in {os.fspath(p) for p in paths if p is not None}


def _kept_file(path: Path, existed: bool) -> str:
    return f"{path} is the previous one, untouched" if existed else f"{path} was not created"


def _fault(exc: OSError, path, kept: str, *, action: str | None = None) -> OutputError:
    """``exc`` as an :class:`OutputError` on ``path`` (an OutputError keeps its action)."""
    if action is None:
        action = getattr(exc, "action", "cannot write")
    return OutputError(exc.errno, exc.strerror or str(exc), path, kept, action)
