"""``pipeline report FILE --out DIR``: a report notebook, with HTML.

FILE is a record (its fit report: ``<record>.ipynb`` and ``.html``, the scene from
``--scene`` or the record's sidecar; analysed here and rendered, or with ``--kernel``
executed in a Jupyter kernel) or a campaign's ``campaign.nc`` (the campaign report, executed).
"""

from __future__ import annotations

from pathlib import Path

from ._common import add_record_options, load_options, read_scene
from ._options import add_progress, nonneg_int, progress_bar


def register(sub) -> None:
    p = sub.add_parser(
        "report",
        help="the fit report of a record (or a campaign.nc) as notebook and HTML",
        description=__doc__.split("\n\n")[1],
    )
    p.add_argument("file", type=Path, help="a record file, or a campaign's campaign.nc")
    p.add_argument(
        "--out", type=Path, default=Path("build/reports"), help="output folder [build/reports]"
    )
    p.add_argument(
        "--scene",
        type=Path,
        help="JSON file of Scene fields (SI units); default the record's sidecar",
    )
    p.add_argument("--boot", type=nonneg_int, default=200, help="bootstrap replicates [200]")
    p.add_argument("--seed", type=nonneg_int, default=0, help="bootstrap seed [0]")
    p.add_argument("--no-html", action="store_true", help="write the notebook only")
    p.add_argument(
        "--kernel",
        action="store_true",
        help="execute a record's notebook in a fresh Jupyter kernel instead of rendering "
        "it from this process's analysis (the same notebook, seconds slower)",
    )
    add_record_options(p)
    add_progress(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from .._atomic import atomic_files
    from ..errors import InputError
    from ..notebook_report import campaign_report, record_report, require_reports

    if not args.file.is_file():
        raise InputError("no such file; check the path", path=args.file)
    # a campaign's report is executed; a record's is rendered here unless --kernel
    require_reports(execute=args.kernel or args.file.suffix == ".nc", html=not args.no_html)
    load = load_options(args)
    if args.file.suffix == ".nc" and load:
        raise InputError(
            f"--{next(iter(load)).replace('_', '-')} says how to read a record; a campaign's "
            "records were read when it ran (pipeline campaign takes it)",
            path=args.file,
        )
    # the notebook and its HTML go in together (the previous pair stays on a fault)
    with progress_bar(args, total=1, desc="report") as bar, atomic_files(args.out):
        if args.file.suffix == ".nc":
            r = campaign_report(args.file, args.out, html=not args.no_html)
        else:
            from ..sidecar import load_sample

            scene, _ = read_scene(args.file, args.scene, load_sample(args.file, **load))
            r = record_report(
                args.file,
                args.out,
                scene=scene,
                load=load,
                n_boot=args.boot,
                seed=args.seed,
                html=not args.no_html,
                kernel=args.kernel,
            )
        bar.update(1)
    print(f"{r.ipynb}" + (f"\n{r.html}" if r.html else "") + f"  ({r.seconds:.1f} s)")
    return 0
