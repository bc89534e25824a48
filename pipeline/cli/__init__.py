"""The ``pipeline`` command: one module per subcommand.

``python -m pipeline.cli reproduce --samples data_samples --out build/reproduce`` is what
``make reproduce`` runs. Each subcommand module has ``register(subparsers)``, which adds
its parser and sets ``func``; :func:`main` runs it and turns an
:class:`~pipeline.errors.InputError` into a one-line message and exit status 2.
"""

from __future__ import annotations

import argparse
import logging
import sys

from ..errors import InputError
from . import analyse, reproduce

#: The subcommand modules, in the order ``pipeline --help`` lists them.
COMMANDS = (reproduce, analyse)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(
        prog="pipeline", description="Impact-force histories to physics."
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
        print(f"error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
