"""The ``pipeline`` command: one module per subcommand.

``python -m pipeline.cli reproduce --samples data_samples --out build/reproduce`` is what
``make reproduce`` runs. Each subcommand module has ``register(subparsers)``, which adds
its parser and sets ``func``; :func:`main` runs it.

Exit statuses (:data:`pipeline.cli._common.EXIT_CODES`): 0 success; 1 some records failed
(``reproduce``: the rest were processed); 2 bad input or a bad argument — one line,
``error: ...``, never a traceback; 3 an internal error (a bug; ``-v`` shows the
traceback).
"""

from __future__ import annotations

import logging
import sys
import traceback

from ..errors import InputError
from . import analyse, campaign, export, fit, report, reproduce
from ._common import EXIT_BAD_INPUT, EXIT_CODES, EXIT_INTERNAL, Parser

#: The subcommand modules, in the order ``pipeline --help`` lists them.
COMMANDS = (reproduce, analyse, fit, campaign, report, export)


def main(argv=None) -> int:
    parser = Parser(
        prog="pipeline", description="Impact-force histories to physics.", epilog=EXIT_CODES
    )
    parser.add_argument("-v", "--verbose", action="store_true", help="log the warnings too")
    sub = parser.add_subparsers(dest="command", required=True)
    for command in COMMANDS:
        command.register(sub)
    args = parser.parse_args(argv)
    logging.basicConfig(
        level=logging.INFO if args.verbose else logging.WARNING,
        format="%(levelname)s %(name)s: %(message)s",
    )
    try:
        return args.func(args)
    except InputError as exc:
        print(f"error: {_one_line(str(exc))}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except OSError as exc:  # the output cannot be written: a full disk, no permission
        print(f"error: {_one_line(str(exc))}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except Exception as exc:  # a bug: one line (the traceback with -v), never a crash dump
        if args.verbose:
            traceback.print_exc(file=sys.stderr)
        print(
            f"error: internal error ({type(exc).__name__}: {_one_line(str(exc))}); run with "
            "-v for the traceback and report it",
            file=sys.stderr,
        )
        return EXIT_INTERNAL


def _one_line(text: str) -> str:
    return " ".join(text.split())


if __name__ == "__main__":
    sys.exit(main())
