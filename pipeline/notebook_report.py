"""Reports as notebooks: a template, parameters, headless execution, HTML.

The templates (``pipeline/templates/*.py``) are jupytext ``py:percent`` notebooks with a
cell tagged ``parameters`` holding defaults, as papermill does it: :func:`execute` reads the
template, inserts after that cell one tagged ``injected-parameters`` that assigns the given
values, runs every cell in a fresh ``python3`` kernel (nbclient), writes the executed
``.ipynb`` and renders it to a self-contained ``.html`` (nbconvert; figures embedded), each
file atomically. A cell that fails stops the run with :class:`NotebookError` naming the
cell; the partly executed notebook is still written so the error can be read there.

- :func:`record_report` — one record's fit report (``record_report.py``): the record and
  its scene, the measured outcomes against Routh's prediction, the forces and the plane of
  percussions, the seed's findings, the fitted contact parameters where the fitter exists.
- :func:`campaign_report` — a campaign's report (``campaign_report.py``) from its netCDF.

The notebooks stay thin: they call the library and show its figures.
"""

from __future__ import annotations

import json
import logging
import os
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path

from ._atomic import atomic_write_text
from ._json import json_ready
from .errors import InputError

__all__ = [
    "TEMPLATES",
    "NotebookError",
    "NotebookReport",
    "execute",
    "record_report",
    "campaign_report",
    "parameters_cell",
]

#: The report templates shipped with the package.
TEMPLATES = {
    "record": Path(__file__).with_name("templates") / "record_report.py",
    "campaign": Path(__file__).with_name("templates") / "campaign_report.py",
}


class NotebookError(InputError):
    """A cell of a report notebook raised; the message names the cell and the error."""


@dataclass(frozen=True)
class NotebookReport:
    """Files of one executed report.

    Attributes
    ----------
    ipynb : pathlib.Path — the executed notebook
    html : pathlib.Path or None — its HTML rendering (None when not asked for)
    seconds : float — wall time of the execution [s]
    """

    ipynb: Path
    html: Path | None
    seconds: float


def _need(module: str):
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError:
        raise InputError(
            f"notebook reports need {module}: install the package with its 'reports' extra "
            "(pip install 'pipeline[reports]'), or leave the reports out (--no-reports)"
        ) from None


def parameters_cell(parameters: dict):
    """The ``injected-parameters`` code cell assigning ``parameters`` (Python literals)."""
    nbformat = _need("nbformat")
    lines = ["# Parameters (injected)"]
    for k, v in parameters.items():
        if not k.isidentifier():
            raise InputError(f"notebook parameter {k!r} is not a Python name")
        lines.append(f"{k} = {v!r}")
    cell = nbformat.v4.new_code_cell("\n".join(lines))
    cell.metadata["tags"] = ["injected-parameters"]
    return cell


def _with_parameters(nb, parameters: dict):
    """``nb`` with the parameters cell after the one tagged ``parameters`` (first if none)."""
    cells = list(nb.cells)
    tagged = [i for i, c in enumerate(cells) if "parameters" in c.metadata.get("tags", [])]
    at = tagged[0] + 1 if tagged else 0
    cells.insert(at, parameters_cell(parameters))
    nb.cells = cells
    return nb


def execute(
    template,
    parameters: dict,
    out,
    *,
    html: bool = True,
    timeout: float = 600.0,
    kernel_name: str = "python3",
) -> NotebookReport:
    """Run a notebook template with parameters; write ``out`` (.ipynb) and its .html.

    Parameters
    ----------
    template : path — a jupytext ``py:percent`` script or an ``.ipynb``
    parameters : dict — name → value (Python literals: str, numbers, bool, None, lists)
    out : path — the executed notebook to write (``.ipynb``); the HTML goes beside it
    html : bool — also render HTML
    timeout : float — per-cell time limit [s]
    kernel_name : str — Jupyter kernel (``python3``: this Python's ipykernel)

    Raises
    ------
    NotebookError
        A cell raised (the partly executed notebook is written all the same).
    InputError
        The template does not exist, or the notebook packages are missing.
    """
    jupytext = _need("jupytext")
    nbclient = _need("nbclient")
    nbformat = _need("nbformat")
    template, out = Path(template), Path(out)
    if not template.is_file():
        raise InputError("no such notebook template", path=template)
    nb = jupytext.read(template) if template.suffix == ".py" else nbformat.read(template, 4)
    nb = _with_parameters(nb, parameters)
    nb.metadata.setdefault("papermill", {})["parameters"] = json.loads(
        json.dumps(parameters, default=str)
    )
    out.parent.mkdir(parents=True, exist_ok=True)
    client = nbclient.NotebookClient(
        nb,
        kernel_name=kernel_name,
        timeout=timeout,
        resources={"metadata": {"path": str(out.parent)}},
    )
    t0 = time.perf_counter()
    error = None
    try:
        # the kernel's own start-up chatter (e.g. ipykernel's note on TCP transport) would
        # land on the user's terminal; cell errors come back through the protocol
        client.execute(stderr=subprocess.DEVNULL)
    except nbclient.exceptions.CellExecutionError as exc:
        error = exc
    seconds = time.perf_counter() - t0
    atomic_write_text(out, nbformat.writes(nb))
    html_path = None
    if html:
        html_path = out.with_suffix(".html")
        atomic_write_text(html_path, to_html(nb))
    if error is not None:
        first = str(error).strip().splitlines()
        last = next((ln for ln in reversed(first) if ln.strip()), "a cell raised")
        raise NotebookError(f"a cell of the report failed ({last}); see the notebook", path=out)
    return NotebookReport(out, html_path, seconds)


def to_html(nb) -> str:
    """A notebook as one self-contained HTML page (figures embedded, no input prompts)."""
    nbconvert = _need("nbconvert")
    exporter = nbconvert.HTMLExporter(exclude_input_prompt=True, exclude_output_prompt=True)
    quiet = logging.getLogger("traitlets")  # nbconvert's accessibility hints are not ours
    level = quiet.level
    quiet.setLevel(logging.ERROR)
    try:
        body, _ = exporter.from_notebook_node(nb)
    finally:
        quiet.setLevel(level)
    return body


def record_report(
    record,
    out_dir,
    *,
    scene=None,
    n_boot: int = 200,
    seed: int = 0,
    html: bool = True,
    name: str | None = None,
) -> NotebookReport:
    """Execute the per-record fit report for one record file.

    Parameters
    ----------
    record : path — the record file (a sidecar beside it may give its scene and load options)
    out_dir : path — folder of the report: ``<name>.ipynb`` and ``<name>.html``
    scene : Scene, optional — the record's scene; default its sidecar's
    n_boot, seed : int — bootstrap replicates and seed of the analysis
    html : bool — also render HTML
    name : str, optional — report file stem; default the record's file name without suffix

    Returns
    -------
    NotebookReport
    """
    record = Path(record).resolve()
    scene_json = "" if scene is None else json.dumps(_json_scene(scene))
    stem = name or record.stem
    return execute(
        TEMPLATES["record"],
        {"record": str(record), "scene_json": scene_json, "n_boot": int(n_boot), "seed": seed},
        Path(out_dir) / f"{stem}.ipynb",
        html=html,
    )


def campaign_report(dataset, out_dir, *, html: bool = True) -> NotebookReport:
    """Execute the campaign report for a campaign's netCDF file (``campaign.nc``).

    Writes ``campaign.ipynb`` and ``campaign.html`` into ``out_dir``.
    """
    dataset = Path(dataset).resolve()
    if not dataset.is_file():
        raise InputError("no such campaign file; run pipeline campaign first", path=dataset)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    # relative to the notebook (which runs in its own folder), so the pair can move together
    rel = os.path.relpath(dataset, out_dir.resolve())
    return execute(TEMPLATES["campaign"], {"dataset": rel}, out_dir / "campaign.ipynb", html=html)


def _json_scene(scene) -> dict:
    return json_ready(scene.to_dict() if hasattr(scene, "to_dict") else dict(scene))
