"""Argument types and progress bars the subcommands share.

Every bad argument becomes argparse's one-line error (exit status 2); progress bars
(tqdm, on stderr) show on a terminal, or always with ``--progress``.
"""

from __future__ import annotations

import argparse
import contextlib
import sys


def nonneg_int(text: str) -> int:
    """An integer ≥ 0 (argparse type)."""
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if v < 0:
        raise argparse.ArgumentTypeError(f"{text} is negative; give a whole number ≥ 0")
    return v


def pos_int(text: str) -> int:
    """An integer ≥ 1 (argparse type)."""
    v = nonneg_int(text)
    if v < 1:
        raise argparse.ArgumentTypeError("give a whole number ≥ 1")
    return v


def add_progress(parser) -> None:
    """``--progress/--no-progress`` (default: a bar when stderr is a terminal)."""
    parser.add_argument(
        "--progress",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="show progress bars on stderr (default: when stderr is a terminal)",
    )


@contextlib.contextmanager
def progress_bar(args, *, total: int, desc: str):
    """A tqdm bar for ``total`` steps, or a silent stand-in when progress is off."""
    from tqdm import tqdm

    show = getattr(args, "progress", None)
    show = sys.stderr.isatty() if show is None else show
    with tqdm(total=total, desc=desc, disable=not show, file=sys.stderr, leave=True) as bar:
        yield bar
