"""Make one file-system operation under a folder fail as the system would (a full disk, a
read-only or vanished folder, no permission, a failing device), in this process.

:func:`inject` replaces, for the time of a ``with`` block, the functions of :mod:`os`
through which the pipeline reaches the disk (``pipeline._atomic``; ``tempfile``'s
``mkstemp`` and ``mkdtemp`` and ``pathlib``'s ``mkdir`` call them too): ``open``,
``write``, ``fsync``, ``close``, ``replace``, ``rename``, ``mkdir``, ``chmod``. Each call on
a path under ``root`` (or on a file descriptor opened there) is an *operation*, counted in
order; operation ``at`` raises ``OSError(error, strerror, path)`` instead of running (no
path for a call on a descriptor, as the kernel's errors have none; a ``close`` closes
first, as Linux does). ``at=None`` only counts: ``.ops`` lists ``(kind, path)`` for a
reference run; ``at`` may also pick the operation by kind and output (:func:`on`).

Cleaning up after a fault (``unlink``, ``rmdir``, ``shutil.rmtree``) is not counted: the
writers' own clean-up is what the tests check.
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
import shutil
from pathlib import Path

#: The faults a test injects, one errno each: a full disk, a read-only file system, no
#: permission, a folder that vanished, a failing device.
ERRORS = (errno.ENOSPC, errno.EROFS, errno.EACCES, errno.ENOENT, errno.EIO)

#: The exit status of ``pipeline`` for each (docs/cli.md).
STATUS = {errno.ENOSPC: 4, errno.EROFS: 5, errno.EACCES: 5, errno.ENOENT: 5, errno.EIO: 6}

#: The words of the one-line message for each.
WORDS = {
    errno.ENOSPC: "the disk is full",
    errno.EROFS: "the file system is read-only",
    errno.EACCES: "no permission to write there",
    errno.ENOENT: "the output folder vanished",
    errno.EIO: "the disk failed (input/output error)",
}

_PATH_OPS = ("open", "replace", "rename", "mkdir", "chmod")
_FD_OPS = ("write", "fsync", "close")


class Injector:
    """The operations seen so far (``ops``: ``(kind, path)``, a rename's target as its
    path) and whether the fault was raised (``fired``)."""

    def __init__(self, root, at, error):
        self.root = os.path.abspath(root) + os.sep
        self.at = at if callable(at) or at is None else (lambda k, kind, path, at=at: k == at)
        self.error = error
        self.ops: list[tuple[str, str]] = []
        self.fired = False
        self.cleaning = False
        self._fds: dict[int, str] = {}

    def _ours(self, path) -> str | None:
        if path is None or isinstance(path, int):
            return None
        path = os.path.abspath(os.fsdecode(os.fspath(path)))
        return path if (path + os.sep).startswith(self.root) else None

    def _count(self, kind, path) -> None:
        if self.cleaning:
            return
        self.ops.append((kind, path))
        if not self.fired and self.at is not None and self.at(len(self.ops) - 1, kind, path):
            self.fired = True
            where = [path] if kind in _PATH_OPS else []  # the kernel names no file for a fd
            raise OSError(self.error, os.strerror(self.error), *where)

    def wrap(self, kind, real):
        if kind in _FD_OPS:

            def on_fd(fd, *args, **kwargs):
                path = self._fds.get(fd)
                if path is not None and kind == "close":
                    del self._fds[fd]
                    result = real(fd)  # Linux closes the descriptor even when close fails
                    self._count(kind, path)
                    return result
                if path is not None:
                    self._count(kind, path)
                return real(fd, *args, **kwargs)

            return on_fd

        def on_path(*args, **kwargs):
            named = args[:2] if kind in ("replace", "rename") else args[:1]
            ours = [p for p in map(self._ours, named) if p is not None]
            if ours and "dir_fd" not in kwargs:
                self._count(kind, ours[-1])
            result = real(*args, **kwargs)
            if kind == "open" and ours:
                self._fds[result] = ours[0]
            return result

        return on_path


@contextlib.contextmanager
def inject(root, *, at=None, error=errno.ENOSPC):
    """Operation ``at`` under ``root`` fails with ``error`` (module notes); yields the
    :class:`Injector`. ``at`` is the operation's index, or a test ``at(index, kind,
    path)``: the first operation it accepts fails (:func:`on`)."""
    inj = Injector(root, at, error)
    real = {name: getattr(os, name) for name in _PATH_OPS + _FD_OPS}
    rmtree = shutil.rmtree

    def cleaning(*args, **kwargs):
        inj.cleaning = True
        try:
            return rmtree(*args, **kwargs)
        finally:
            inj.cleaning = False

    for name, fn in real.items():
        setattr(os, name, inj.wrap(name, fn))
    shutil.rmtree = cleaning
    try:
        yield inj
    finally:
        for name, fn in real.items():
            setattr(os, name, fn)
        shutil.rmtree = rmtree


#: A writer's temporary file (``.<stem>.<random>.tmp<suffix>``) and a staging folder
#: (``.<name>.staging-<pid>-<random>``).
_TMP = re.compile(r"^\.(?P<stem>.+)\.[^.]+\.tmp(?P<suffix>\.[^.]*)?$")
_STAGE = re.compile(r"^\.(?P<name>.+)\.staging-\d+-.*$")


def target(path: str) -> str:
    """The output an operation's path stands for: a temporary file as its target, a
    staging folder as the folder it becomes."""
    parts = []
    for part in Path(path).parts:
        stage, tmp = _STAGE.match(part), _TMP.match(part)
        if stage is not None:
            parts.append(stage["name"])
        elif tmp is not None:
            parts.append(tmp["stem"] + (tmp["suffix"] or ""))
        else:
            parts.append(part)
    return str(Path(*parts))


def on(kind: str, name: str):
    """``at=`` for :func:`inject`: the first operation of ``kind`` on the output whose path
    (:func:`target`) ends with ``name``."""
    return lambda k, op, path: op == kind and target(path).endswith(name)
