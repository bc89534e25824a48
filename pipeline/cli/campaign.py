"""``pipeline campaign DIR|GLOB|FILES --out DIR``: many records into one Dataset and reports.

Writes ``campaign.nc`` (the Dataset of :func:`pipeline.campaign`), ``campaign.csv`` (one row
per record), the campaign figures, and under ``reports/`` one fit-report notebook per
analysed record (``<record>.ipynb`` and ``.html``, rendered from the campaign's own analysis
where the record is analysed) and the campaign's own (``campaign.ipynb``, ``.html``,
executed), the overview a reader explores in a browser (``overview.html``: every record a
point, hover for its values, click for its report), and ``manifest.json``; the folder is
staged and swapped in whole. A record that fails is listed with its reason; exit status 0
when every record was analysed, 1 when some failed (the rest are in the outputs), 2 for
bad input.
"""

from __future__ import annotations

import time
from pathlib import Path

from ._common import EXIT_FAILED_RECORDS, add_record_options, load_options, log_warnings
from ._options import add_progress, nonneg_int, pos_int, progress_bar


def register(sub) -> None:
    p = sub.add_parser(
        "campaign",
        help="analyse many records into one Dataset, figures and reports",
        description=__doc__.split("\n\n")[1],
    )
    p.add_argument(
        "paths",
        nargs="+",
        metavar="DIR|GLOB|FILE",
        help="a folder of records, a quoted glob ('runs/*.csv') or record files",
    )
    p.add_argument(
        "--out", type=Path, default=Path("build/campaign"), help="output folder [build/campaign]"
    )
    p.add_argument(
        "--scene",
        type=Path,
        help="JSON file of Scene fields (SI units) for records without a sidecar; a "
        "sidecar or table row overrides it field by field",
    )
    p.add_argument(
        "--table",
        type=Path,
        help="CSV with a 'file' column and per-record Scene fields (speed, angle_deg, mu, "
        "e, ...) and an optional 'repeat' column",
    )
    p.add_argument("--boot", type=nonneg_int, default=200, help="bootstrap replicates [200]")
    p.add_argument("--seed", type=nonneg_int, default=0, help="bootstrap seed [0]")
    run = p.add_mutually_exclusive_group()
    run.add_argument(
        "--workers",
        type=pos_int,
        help="run the records on a local dask cluster of N worker processes "
        "(needs the 'distributed' extra)",
    )
    run.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="run the records on an existing dask cluster, e.g. tcp://10.0.0.5:8786",
    )
    run.add_argument(
        "--batched",
        action="store_true",
        help="analyse in this process with one vectorised bootstrap for all records",
    )
    p.add_argument("--no-fit", action="store_true", help="do not fit contact parameters per record")
    p.add_argument(
        "--no-reports",
        action="store_true",
        help="do not write the report notebooks (nor the overview)",
    )
    p.add_argument(
        "--no-html",
        action="store_true",
        help="write the report notebooks without HTML (and no overview)",
    )
    add_record_options(p)
    add_progress(p)
    p.set_defaults(func=run_campaign)


def run_campaign(args) -> int:
    from .._atomic import atomic_dir
    from ..campaigns import campaign, record_files, write_campaign
    from ..campaigns.overview import OVERVIEW, require_bokeh, write_overview
    from ..errors import InputError
    from ..notebook_report import require_reports
    from ..report import write_manifest
    from ..scene import read_scene_fields

    t0 = time.perf_counter()
    base = read_scene_fields(args.scene) if args.scene else None
    files = record_files(args.paths)  # a wrong path is told first, then a missing extra
    if args.table is not None and not Path(args.table).is_file():
        raise InputError("no such table file; check the path", path=args.table)
    if not args.no_reports:  # now, not after the campaign
        require_reports(execute=True, html=not args.no_html)  # the campaign's is executed
        if not args.no_html:
            require_bokeh()
    options = {"n_boot": args.boot, "seed": args.seed}
    load = load_options(args)
    # the whole folder is staged and swapped in with one rename (as pipeline reproduce); the
    # records' reports are written into it as the records are analysed
    with atomic_dir(args.out) as stage, log_warnings():
        with progress_bar(args, total=len(files), desc="records") as bar:
            ds = campaign(
                files,
                scenes=base,
                table=args.table,
                fit=not args.no_fit,
                workers=args.workers,
                scheduler=args.scheduler,
                batched=args.batched,
                progress=lambda r: bar.update(1),
                reports=None if args.no_reports else stage / "reports",
                report_html=not args.no_html,
                load=load,
                **options,
            )
        ds.attrs["source"] = " ".join(args.paths)
        write_campaign(ds, stage)
        overview = None if args.no_reports or args.no_html else stage / OVERVIEW
        if not args.no_reports:
            _campaign_report(args, stage, overview)
        if overview is not None:
            # after the reports: each record's point links its report where there is one
            write_overview(ds, overview, reports=stage / "reports")
        write_manifest(stage, paths=list(args.paths), n_boot=args.boot, seed=args.seed, load=load)
    ok = int((ds["status"] == "ok").sum())
    print(
        f"{ok}/{ds.sizes['record']} records analysed in {time.perf_counter() - t0:.1f} s "
        f"→ {args.out}/"
    )
    for name, status, reason in zip(
        ds["record"].values, ds["status"].values, ds["reason"].values, strict=True
    ):
        if status != "ok":
            print(f"  failed: {name}: {reason}")
    return EXIT_FAILED_RECORDS if ok < ds.sizes["record"] else 0


def _campaign_report(args, out: Path, overview: Path | None) -> None:
    """Execute the campaign's own report (one kernel) beside the records' (a progress bar
    of one), linking the overview written next."""
    from ..notebook_report import campaign_report

    with progress_bar(args, total=1, desc="campaign report") as bar:
        campaign_report(
            out / "campaign.nc", out / "reports", html=not args.no_html, overview=overview
        )
        bar.update(1)
