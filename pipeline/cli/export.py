"""``pipeline export FIT --to lammps|liggghts|yade|mujoco``: the contact as simulator input.

FIT is a JSON file: a fit's summary (``fit.json`` of ``pipeline fit --out``, with
``--scene``), any object with ``"scene"`` (Scene fields, SI) and ``"values"`` (``E_eff``,
``e``, ``mu``, ``kt_scale``), or a plain scene or sidecar file.
Prints the target's input lines (or writes them with ``--out``), each conversion's limits
as comments on stderr.
"""

from __future__ import annotations

import sys
from pathlib import Path

from ._common import read_scene

#: :data:`pipeline.export.TARGETS`, spelled out so that registering the command does not
#: import the exporters (every command registers every subcommand; a test keeps the two equal).
TARGETS = ("lammps", "liggghts", "yade", "mujoco")


def register(sub) -> None:
    p = sub.add_parser(
        "export",
        help="write a fitted contact as LAMMPS, LIGGGHTS, YADE or MuJoCo input",
        description=__doc__.split("\n\n")[1],
    )
    p.add_argument("fit", type=Path, metavar="FIT", help="JSON file: a fit summary or a scene")
    p.add_argument("--to", required=True, choices=TARGETS, help="the simulator to write for")
    p.add_argument(
        "--scene",
        type=Path,
        help="JSON file of Scene fields, for a fit file that does not hold its scene",
    )
    p.add_argument("--out", type=Path, help="write the lines to this file instead of stdout")
    p.add_argument(
        "--script",
        action="store_true",
        help="LAMMPS: a complete input that runs the reference impact, not only the settings",
    )
    p.set_defaults(func=run)


def run(args) -> int:
    from .._atomic import atomic_write_text
    from ..errors import InputError
    from ..export import contact_from, export

    scene = read_scene(None, args.scene)[0] if args.scene else None
    ex = export(contact_from(args.fit, scene=scene), args.to)
    if args.script and not ex.script:
        raise InputError(f"--script: no runnable script for {args.to}; leave --script out")
    text = ex.script if args.script else ex.text
    if args.out:
        atomic_write_text(args.out, text)
        print(f"{args.to} input → {args.out}")
    else:
        sys.stdout.write(text)
    for note in ex.notes:
        print(f"note: {note}", file=sys.stderr)
    return 0
