"""Run ``python -m pipeline.cli ...`` and stop it just before a chosen file-system operation.

Used by ``tests/test_kill.py`` so that a kill lands where the test chooses, whatever the
machine's speed. An audit hook (:func:`sys.addaudithook`, PEP 578) sees every operation the
run makes on its own output before the operation happens: the staging folder created,
each file opened for writing inside it, the rename that swaps it in, the removal of the
previous run. Only the run's own paths count (``<out>``, and ``.<out>.staging-<pid>-*``,
``.<out>.old-<pid>-*`` of this process), so the numbering does not depend on what earlier
runs left behind.

Environment:

``KILLPOINT_OUT``
    The output folder the run writes (its ``--out``).
``KILLPOINT_AT``
    Index of the operation to stop at (0 the first); negative: never stop.
``KILLPOINT_FD``
    A file descriptor (inherited) the driver writes to: ``stop <i> <event> <paths>`` when it
    stops (then it waits to be killed), else one ``op <event> <paths>`` line per operation
    (paths tab-separated: a rename's source and target where both are the run's) and
    ``done`` at exit.

Usage: ``python tests/_killpoint.py <pipeline.cli arguments>``.
"""

from __future__ import annotations

import atexit
import os
import runpy
import sys
import threading

_WRITE_FLAGS = os.O_WRONLY | os.O_RDWR | os.O_CREAT | os.O_APPEND | os.O_TRUNC
_EVENTS = {
    "open",
    "os.mkdir",
    "os.rename",
    "os.replace",
    "os.remove",
    "os.rmdir",
    "os.chmod",
    "shutil.rmtree",
}


def _install(out: str, stop_at: int, fd: int) -> None:
    parent, name = os.path.split(os.path.abspath(out))
    mine = (
        os.path.join(parent, name),
        os.path.join(parent, f".{name}.staging-{os.getpid()}-"),
        os.path.join(parent, f".{name}.old-{os.getpid()}-"),
    )
    count = [0]
    busy = threading.local()

    def ours(path) -> str | None:
        if isinstance(path, bytes):
            path = os.fsdecode(path)
        if not isinstance(path, str):
            return None
        path = os.path.abspath(path)
        if path == mine[0] or path.startswith(mine[0] + os.sep) or path.startswith(mine[1:]):
            return path
        return None

    def hook(event, args):
        if event not in _EVENTS or getattr(busy, "on", False):
            return
        busy.on = True
        try:
            if event == "open":
                mode, flags = args[1], args[2]
                writes = (isinstance(mode, str) and any(c in mode for c in "wax+")) or (
                    mode is None and isinstance(flags, int) and flags & _WRITE_FLAGS
                )
                paths = [args[0]] if writes else []
            elif event in ("os.rename", "os.replace"):
                paths = [args[0], args[1]]
            else:
                paths = [args[0]]
            hits = [p for p in map(ours, paths) if p is not None]
            if not hits:
                return
            hit = "\t".join(hits)
            i = count[0]
            count[0] += 1
            if i == stop_at:
                os.write(fd, f"stop {i} {event} {hit}\n".encode())
                threading.Event().wait()  # until SIGKILL
            if stop_at < 0:
                os.write(fd, f"op {event} {hit}\n".encode())
        finally:
            busy.on = False

    sys.addaudithook(hook)
    atexit.register(lambda: os.write(fd, b"done\n"))


def main() -> None:
    _install(
        os.environ["KILLPOINT_OUT"],
        int(os.environ["KILLPOINT_AT"]),
        int(os.environ["KILLPOINT_FD"]),
    )
    sys.argv = ["pipeline.cli", *sys.argv[1:]]
    runpy.run_module("pipeline.cli", run_name="__main__", alter_sys=True)


if __name__ == "__main__":
    main()
