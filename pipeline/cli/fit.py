"""``pipeline fit FILE``: the contact parameters of one record, as a report a person reads."""

from __future__ import annotations

import json
from pathlib import Path

from ._common import EXIT_CODES, add_record_options, log_warnings, read_record, read_scene


def register(sub) -> None:
    p = sub.add_parser(
        "fit",
        help="fit the contact parameters (E*, e, μ, kt_scale) of one record; prints a report",
        description="Fit the contact parameters of one record (pipeline.fit_contact, or "
        "pipeline.select_model with --model auto) and print the report. The record and its "
        "scene are read as for 'pipeline analyse'.",
        epilog=EXIT_CODES,
    )
    p.add_argument("file", type=Path)
    p.add_argument("--scene", type=Path, help="JSON file of Scene fields (SI units)")
    p.add_argument(
        "--model",
        default="hunt_crossley+mindlin",
        help="NORMAL+TANGENTIAL, e.g. hunt_crossley+mindlin (default), hertz+coulomb; "
        "'auto' fits the ladder rigid → coulomb → mindlin and keeps the cheapest adequate",
    )
    p.add_argument(
        "--sensor",
        type=Path,
        help="JSON file of sensor properties (bandwidth [Hz], filter_order, quantum [N], "
        "crosstalk_matrix); default: the sidecar's 'sensor' block, else the record's metadata",
    )
    p.add_argument("--boot", default=200, type=int, help="block-bootstrap replicates")
    p.add_argument("--seed", default=0, type=int)
    p.add_argument(
        "--out",
        type=Path,
        help="write fit.json (the summary), fit.txt (the full report, every digit) and fit.png",
    )
    p.add_argument("--json", action="store_true", help="print the strict-JSON summary")
    add_record_options(p)
    p.set_defaults(func=run)


def _sensor(args):
    from ..errors import InputError
    from ..sidecar import sensor_from_sidecar

    if args.sensor is not None:
        try:
            return json.loads(args.sensor.read_text(encoding="utf-8"))
        except (OSError, ValueError, UnicodeDecodeError) as exc:
            raise InputError(f"cannot read the sensor file: {exc}", path=args.sensor) from None
    return sensor_from_sidecar(args.file)


def run(args) -> int:
    from .._atomic import atomic_files, atomic_write_text
    from ..errors import InputError
    from ..fit import fit_contact, select_model

    record = read_record(args.file, args)
    scene, _ = read_scene(args.file, args.scene, record)
    sensor = _sensor(args)
    with log_warnings():
        if args.model == "auto":
            sel = select_model(record, scene, sensor=sensor, n_boot=args.boot, seed=args.seed)
            fit = sel.fit
            head = sel.report() + "\n\n"
            summary = sel.summary()
        else:
            normal, plus, tangential = args.model.partition("+")
            if not plus:
                raise InputError(
                    f"--model {args.model!r}: give NORMAL+TANGENTIAL, e.g. hunt_crossley+mindlin"
                )
            fit = fit_contact(
                record,
                scene,
                normal=normal,
                tangential=tangential,
                sensor=sensor,
                n_boot=args.boot,
                seed=args.seed,
            )
            head = ""
            summary = fit.summary()
    if args.out is not None:  # the three files go in together (the previous stay on a fault)
        from .. import figures  # matplotlib: only where a figure is drawn

        with atomic_files(args.out):
            atomic_write_text(args.out / "fit.json", json.dumps(summary, indent=1, allow_nan=False))
            atomic_write_text(args.out / "fit.txt", head + fit.report() + "\n")
            figures.save(figures.fig_contact_fit(fit), args.out / "fit.png")
    if args.json:
        print(json.dumps(summary, indent=1, allow_nan=False))
    else:
        print(_readable(fit, sel.averaged if args.model == "auto" else None, head))
    return 0


def _readable(fit, averaged=None, head="") -> str:
    """The fit for a person: what was fitted, the verdict in words, the parameters rounded
    to their uncertainty with the budget's shares, what they imply, the notes; every digit
    is in --json and in --out's fit.txt."""
    import textwrap

    from ..precision import as_text, plain_quantities

    lines = [
        f"Contact fit of {fit.data.record.attrs.get('source', 'the record')} "
        f"({fit.n_data} samples)",
    ]
    if head:
        lines += ["", head.rstrip()]  # the candidates and the selection's rule
    lines += ["", as_text(fit.table() if averaged is None else averaged.table())]
    if fit.physics:
        lines += ["", *textwrap.wrap("implied: " + plain_quantities(fit.physics), 100)]
    if fit.notes:
        lines += ["", "notes:"] + [f"- {n}" for n in fit.notes]
    lines += ["", "(every digit: --json, or fit.txt and fit.json with --out)"]
    return "\n".join(lines)
