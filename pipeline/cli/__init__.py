"""The ``pipeline`` command: one module per subcommand.

``python -m pipeline.cli reproduce --samples data_samples --out build/reproduce`` is what
``make reproduce`` runs. Each subcommand module has ``register(subparsers)``, which adds
its parser and sets ``func``; :func:`main` runs it.

Exit statuses (:data:`pipeline.cli._common.EXIT_CODES`; docs/cli.md): 0 success; 1 some
records failed (``reproduce``, ``campaign``: the rest were processed); 2 bad input or a bad
argument — one line, ``error: ...``, never a traceback; 3 an internal error (a bug; ``-v``
shows the traceback); 4 the disk is full, 5 the output folder cannot be written (read-only,
no permission, vanished), 6 the disk failed (an input/output error) — one line naming the
file and saying that the previous output is untouched (:class:`pipeline.errors.OutputError`);
130 interrupted (Ctrl-C). The standard output is flushed before the status is returned, so
a full disk under it is one of these lines too, not a message of the interpreter's.
"""

from __future__ import annotations

import contextlib
import errno
import logging
import os
import sys
import traceback

from ..errors import InputError, OutputError
from . import analyse, campaign, export, fit, report, reproduce
from ._common import (
    EXIT_BAD_INPUT,
    EXIT_CODES,
    EXIT_FAULT,
    EXIT_INTERNAL,
    EXIT_INTERRUPTED,
    Parser,
)

#: The subcommand modules, in the order ``pipeline --help`` lists them.
COMMANDS = (reproduce, analyse, fit, campaign, report, export)


def main(argv=None) -> int:
    parser = Parser(
        prog="pipeline", description="Impact-force histories to physics.", epilog=EXIT_CODES
    )
    parser.add_argument(
        "-v",
        "--verbose",
        action="store_true",
        help="log INFO lines too: other libraries' warnings, a dask cluster's messages; "
        "an internal error's traceback",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    for command in COMMANDS:
        command.register(sub)
    args = parser.parse_args(argv)
    logging.basicConfig(
        level=logging.INFO if args.verbose else logging.WARNING,
        format="%(levelname)s %(name)s: %(message)s",
    )
    if not args.verbose:
        # a dask cluster's INFO lines (started, stopped; here and in its workers): with -v
        os.environ.setdefault("DASK_LOGGING__DISTRIBUTED", "warning")
    stdout, sys.stdout = sys.stdout, _Stdout(sys.stdout)
    try:
        with _one_blas_thread():
            return _run(args)
    finally:
        sys.stdout = stdout


#: The variables that set a BLAS library's threads; a user who sets one keeps it.
BLAS_THREADS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


@contextlib.contextmanager
def _one_blas_thread():
    """Run the command, and the processes it starts, on one BLAS thread.

    A fit's linear algebra is small (a few thousand rows by a few dozen columns at most),
    and BLAS threads only wait on each other there: on two busy cores a first fit took
    about 1.5 times the wall time, and twice the CPU, with OpenBLAS's default threads. A
    campaign runs its records in parallel instead. Unless the user set one of
    :data:`BLAS_THREADS`, the loaded BLAS is limited to one thread (threadpoolctl) and the
    variables are set for the processes the command starts, both until it returns.
    """
    if any(name in os.environ for name in BLAS_THREADS):
        yield
        return
    from threadpoolctl import threadpool_limits

    os.environ.update(dict.fromkeys(BLAS_THREADS, "1"))
    try:
        with threadpool_limits(limits=1, user_api="blas"):
            yield
    finally:
        for name in BLAS_THREADS:
            os.environ.pop(name, None)


def _run(args) -> int:
    """Run the subcommand; every way it can end is an exit status and at most one line."""
    try:
        status = args.func(args)
        sys.stdout.flush()
        return status
    except OutputError as exc:  # a fault of the machine: the previous output is untouched
        return _fail(exc, EXIT_FAULT[exc.fault])
    except InputError as exc:
        return _fail(exc, EXIT_BAD_INPUT)
    except OSError as exc:  # not an output's: a library's own file, or an input
        action = "cannot use" if exc.errno == errno.EIO else "cannot write"  # a read, maybe
        fault = OutputError(
            exc.errno, exc.strerror or str(exc), exc.filename or "a file", action=action
        )
        if fault.fault == "unwritable" and exc.errno != errno.EROFS:
            return _fail(exc, EXIT_BAD_INPUT)  # a missing or unreadable input, most likely
        return _fail(fault, EXIT_FAULT[fault.fault])
    except KeyboardInterrupt:
        return _fail("interrupted; the previous output is untouched", EXIT_INTERRUPTED)
    except Exception as exc:  # a bug: one line (the traceback with -v), never a crash dump
        if args.verbose:
            traceback.print_exc(file=sys.stderr)
        return _fail(
            f"internal error ({type(exc).__name__}: {_one_line(str(exc))}); run with "
            "-v for the traceback and report it",
            EXIT_INTERNAL,
        )


def _fail(message, status: int) -> int:
    """Say ``error: <message>`` in one line on stderr; return ``status``."""
    try:
        print(f"error: {_one_line(str(message))}", file=sys.stderr, flush=True)
    except OSError:  # stderr itself full or gone: the status says it (and nothing at exit)
        _to_devnull(sys.stderr)
    return status


def _to_devnull(stream) -> None:
    """Point ``stream``'s file descriptor at the null device: what it still holds is
    dropped, not written again (and failed again) when the interpreter exits."""
    with contextlib.suppress(OSError, ValueError), open(os.devnull, "w") as null:
        os.dup2(null.fileno(), stream.fileno())


class _Stdout:
    """``sys.stdout`` whose faults name it: a full disk under a redirected output is an
    :class:`OutputError` on "the standard output", and its unwritten rest is dropped (so
    the interpreter does not fail again at exit with a message of its own). A reader that
    went away (``| head``) is no fault: the rest of the output is dropped."""

    def __init__(self, stream):
        self._stream = stream

    def write(self, text):
        return self._guard(self._stream.write, text)

    def flush(self):
        return self._guard(self._stream.flush)

    def _guard(self, fn, *args):
        try:
            return fn(*args)
        except OSError as exc:
            _to_devnull(self._stream)
            if exc.errno == errno.EPIPE:
                return None
            raise OutputError(exc.errno, exc.strerror, "the standard output") from exc

    def __getattr__(self, name):
        return getattr(self._stream, name)


def _one_line(text: str) -> str:
    return " ".join(text.split())


if __name__ == "__main__":
    sys.exit(main())
