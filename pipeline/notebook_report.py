"""Reports as notebooks: a template, its parameters, the outputs of its cells, and HTML.

The templates (``pipeline/templates/*.py``) are jupytext ``py:percent`` notebooks with a
cell tagged ``parameters`` holding defaults, as papermill does it. A report is the template
with one cell tagged ``injected-parameters`` after that cell assigning the given values,
and the outputs of its code cells; it is written as ``.ipynb`` and rendered to a
self-contained ``.html`` (nbconvert; figures embedded), each file atomically. The outputs
are filled in one of two ways:

- **rendered** (:func:`render`; :func:`render_record_report`, the default of
  :func:`record_report`, and what ``pipeline campaign`` does for every record): from
  results already computed — the campaign's own :class:`~pipeline.analysis.Analysis` and
  :class:`~pipeline.fit.ContactFit` of the record — by the library calls the code cells
  make (:func:`record_outputs`), formatted as a kernel formats them (IPython's display
  formatter; figures as PNG, the way ``%matplotlib inline`` shows them). The code cells are
  the template's own, so the notebook opens and runs again as it stands and recomputes
  every output (``tests/test_notebook_report.py`` re-executes one in a kernel and compares).
- **executed** (:func:`execute`; ``record_report(kernel=True)``, ``pipeline report
  --kernel`` and the campaign report): every cell runs in a fresh ``python3`` kernel
  (nbclient). A cell that fails stops the run with :class:`NotebookError` naming the cell;
  the partly executed notebook is still written so the error can be read there.

Why rendering (``make bench``, ``campaign``, measures both in one run): a kernel per record
costs seconds — its start, the library's imports, and the record's analysis and fit done a
second time — where rendering costs what the outputs themselves cost: three figures drawn
to PNG (mostly matplotlib's text layout) and the HTML (with one nbconvert exporter kept per
process). One kernel for many records would save the starts and imports but still analyse
and fit every record twice; the campaign has the analysis, so its reports are rendered
where each record is analysed — on the dask workers when the campaign runs there — and
cost nothing when not asked for.

- :func:`record_report` — one record's fit report (``record_report.py``): the record and
  its scene, the measured outcomes against Routh's prediction, the forces and the plane of
  percussions, the seed's findings, the fitted contact parameters.
- :func:`campaign_report` — a campaign's report (``campaign_report.py``) from its netCDF,
  executed.

The notebooks stay thin: they call the library and show its figures.
"""

from __future__ import annotations

import base64
import contextlib
import copy
import functools
import gc
import io
import json
import logging
import os
import platform
import subprocess
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from . import figures, tables
from ._atomic import atomic_files, atomic_write_text, make_dirs
from ._json import json_ready
from .analysis import analyse
from .errors import InputError, PipelineWarning
from .fit import fit_contact
from .report import findings, load_sample, scene_from_sidecar, sensor_from_sidecar

__all__ = [
    "TEMPLATES",
    "NotebookError",
    "NotebookReport",
    "ReportWarning",
    "execute",
    "render",
    "record_outputs",
    "record_report",
    "require_reports",
    "render_record_report",
    "campaign_report",
    "parameters_cell",
    "noted",
    "to_html",
    "HTML_OPTIONS",
]

#: The report templates shipped with the package.
TEMPLATES = {
    "record": Path(__file__).with_name("templates") / "record_report.py",
    "campaign": Path(__file__).with_name("templates") / "campaign_report.py",
}


class NotebookError(InputError):
    """A cell of a report notebook raised; the message names the cell and the error."""


class ReportWarning(PipelineWarning):
    """A record's report could not be made (the record itself was analysed)."""


@dataclass(frozen=True)
class NotebookReport:
    """Files of one report.

    Attributes
    ----------
    ipynb : pathlib.Path — the notebook
    html : pathlib.Path or None — its HTML rendering (None when not asked for)
    seconds : float — wall time of the execution, or of the rendering [s]
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


def require_reports(*, execute: bool = False, html: bool = True) -> None:
    """Raise :class:`~pipeline.errors.InputError` (saying what to install) where a package
    the reports need is missing — before a run, not after it: every notebook's
    (nbformat, jupytext, IPython), an executed one's (nbclient, ipykernel) and the HTML's
    (nbconvert). Looks the packages up without importing them."""
    import importlib.util

    needed = ["nbformat", "jupytext", "IPython"]
    needed += ["nbclient", "ipykernel"] if execute else []
    needed += ["nbconvert"] if html else []
    for module in needed:
        if importlib.util.find_spec(module) is None:
            _need(module)  # its ImportError, told as what to install


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


@functools.cache
def _read_template(template: Path):
    """The template as a notebook (read once per process; callers get a copy)."""
    if not template.is_file():
        raise InputError("no such notebook template", path=template)
    if template.suffix == ".py":
        return _need("jupytext").read(template)
    return _need("nbformat").read(template, 4)


def _notebook(template, parameters: dict):
    """The template with the parameters cell after the one tagged ``parameters`` (first if
    none) and the parameters in its metadata, as papermill records them."""
    nb = copy.deepcopy(_read_template(Path(template).resolve()))
    cells = list(nb.cells)
    tagged = [i for i, c in enumerate(cells) if "parameters" in c.metadata.get("tags", [])]
    at = tagged[0] + 1 if tagged else 0
    cells.insert(at, parameters_cell(parameters))
    nb.cells = cells
    nb.metadata.setdefault("papermill", {})["parameters"] = json.loads(
        json.dumps(parameters, default=str)
    )
    return nb


def _write(nb, out: Path, html: bool) -> Path | None:
    """Write the notebook and (``html``) its HTML beside it, atomically and together
    (:func:`pipeline._atomic.atomic_files`); the HTML's path."""
    with atomic_files(out.parent):
        atomic_write_text(out, _need("nbformat").writes(nb))
        if not html:
            return None
        return atomic_write_text(out.with_suffix(".html"), to_html(nb))


def execute(
    template,
    parameters: dict,
    out,
    *,
    html: bool = True,
    timeout: float | None = 600.0,
    kernel_name: str = "python3",
) -> NotebookReport:
    """Run a notebook template with parameters in a fresh kernel; write ``out`` and its .html.

    Parameters
    ----------
    template : path — a jupytext ``py:percent`` script or an ``.ipynb``
    parameters : dict — name → value (Python literals: str, numbers, bool, None, lists)
    out : path — the executed notebook to write (``.ipynb``); the HTML goes beside it
    html : bool — also render HTML
    timeout : float or None — per-cell time limit [s]; None: none, and an hour for the
        kernel to start (for loaded machines)
    kernel_name : str — Jupyter kernel (``python3``: this Python's ipykernel)

    Raises
    ------
    NotebookError
        A cell raised (the partly executed notebook is written all the same).
    InputError
        The template does not exist, or the notebook packages are missing.
    """
    nbclient = _need("nbclient")
    out = Path(out)
    nb = _notebook(template, parameters)
    make_dirs(out.parent)
    limits = {} if timeout is not None else {"startup_timeout": 3600}
    client = nbclient.NotebookClient(
        nb,
        kernel_name=kernel_name,
        timeout=timeout,
        resources={"metadata": {"path": str(out.parent)}},
        **limits,
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
    html_path = _write(nb, out, html)
    if error is not None:
        first = str(error).strip().splitlines()
        last = next((ln for ln in reversed(first) if ln.strip()), "a cell raised")
        raise NotebookError(f"a cell of the report failed ({last}); see the notebook", path=out)
    return NotebookReport(out, html_path, seconds)


# ------------------------------------------------------------------ rendered outputs
#: What a kernel running the templates reports of itself (``language_info``).
_LANGUAGE_INFO = {
    "name": "python",
    "version": platform.python_version(),
    "mimetype": "text/x-python",
    "file_extension": ".py",
    "codemirror_mode": {"name": "ipython", "version": 3},
    "pygments_lexer": "ipython3",
    "nbconvert_exporter": "python",
}


def render(template, parameters: dict, outputs: dict, out, *, html: bool = True):
    """Write a template with parameters as a notebook whose code cells carry ``outputs``.

    Parameters
    ----------
    template : path — a jupytext ``py:percent`` script or an ``.ipynb``
    parameters : dict — name → value, as for :func:`execute`
    outputs : dict — tag → list of nbformat outputs: every code cell but the parameters'
        carries one of these tags and gets its outputs (:func:`record_outputs`)
    out : path — the notebook to write (``.ipynb``); the HTML goes beside it
    html : bool — also render HTML

    Returns
    -------
    NotebookReport

    Raises
    ------
    ValueError
        The template and the outputs disagree: a code cell whose tags name no outputs, or
        outputs that no cell is tagged for (the template changed without its renderer).
    """
    t0 = time.perf_counter()
    out = Path(out)
    nb = _notebook(template, parameters)
    unused = set(outputs)
    count = 0
    for cell in nb.cells:
        if cell.cell_type != "code":
            continue
        count += 1
        cell.execution_count = count
        tags = cell.metadata.get("tags", [])
        if "parameters" in tags or "injected-parameters" in tags:
            continue
        name = next((t for t in tags if t in outputs), None)
        if name is None:
            raise ValueError(
                f"{template}: a code cell tagged {tags} has no rendered outputs (one of "
                f"{sorted(outputs)}): {cell.source.splitlines()[0]!r}"
            )
        cell.outputs = outputs[name]
        unused.discard(name)
    if unused:
        raise ValueError(f"{template}: no code cell is tagged {sorted(unused)}")
    nb.metadata["language_info"] = dict(_LANGUAGE_INFO)
    html_path = _write(nb, out, html)
    return NotebookReport(out, html_path, time.perf_counter() - t0)


@functools.cache
def _formatter():
    """IPython's display formatter, with matplotlib figures as the templates show them."""
    f = _need("IPython.core.formatters").DisplayFormatter()
    f.formatters["image/png"].for_type(Figure, _png)
    return f


def _png(fig) -> str:
    """A figure as PNG (base64) at its own dpi and size, as the templates' inline backend
    shows it (``bbox_inches=None``: the figures lay themselves out). Drawn once: IPython's
    ``print_figure`` runs the layout in a draw of its own before the one it saves."""
    buf = io.BytesIO()
    FigureCanvasAgg(fig).print_png(buf)
    return base64.b64encode(buf.getvalue()).decode("ascii")


def _display(obj):
    """The output of ``display(obj)`` in a kernel."""
    data, metadata = _formatter().format(obj)
    return _need("nbformat").v4.new_output("display_data", data=data, metadata=metadata)


def _printed(lines) -> list:
    """The outputs of ``print(line)`` for each line in a kernel (none for no lines)."""
    text = "".join(f"{line}\n" for line in lines)
    if not text:
        return []
    return [_need("nbformat").v4.new_output("stream", name="stdout", text=text)]


def record_outputs(analysis, fit, notes=()) -> dict:
    """The outputs of the record template's code cells, from results already computed.

    Parameters
    ----------
    analysis : Analysis — :func:`pipeline.analyse` of the record with the report's options
    fit : ContactFit — :func:`pipeline.fit_contact` of the record with its ``n_boot``, ``seed``
    notes : sequence of str — the warnings :func:`pipeline.analyse` issued, as
        ``"<category>: <message>"`` (:func:`noted`)

    Returns
    -------
    dict
        Cell tag → nbformat outputs: what the template's cells print and display, made by
        the same library calls.
    """
    markdown = _need("IPython.display").Markdown
    a = analysis
    table = fit.table()
    return {
        "verdict": [_display(markdown(tables.record_verdict(a, fit)))],
        "record": [
            _display(tables.view(tables.record_table(a), caption="", uuid="record")),
            *_markdown_if(notes, "Notes on the analysis"),
        ],
        "outcomes": [
            _display(tables.view(tables.outcomes_table(a), caption="", uuid="outcomes")),
            _display(
                tables.view(
                    tables.score_table(a),
                    caption="Deviation from Routh's broken line",
                    uuid="score",
                )
            ),
        ],
        "forces": [_display(figures.fig8_forces(a))],
        "plane": [_display(figures.fig9_percussion_plane(a))],
        "findings": [_display(markdown("\n".join(f"- {line}" for line in findings(a).text)))],
        "fit": [
            _display(tables.view(table, uuid="fit")),
            _display(figures.fig_contact_fit(fit)),
            _display(
                tables.view(
                    tables.implied_table(fit),
                    caption="What the fitted parameters imply",
                    uuid="implied",
                )
            ),
            *_markdown_if(tables.fit_notes(fit, table), "Notes on the fit"),
        ],
    }


def _markdown_if(notes, title) -> list:
    """The output of ``if notes: display(Markdown(notes_markdown(title, notes)))``."""
    if not notes:
        return []
    return [_display(_need("IPython.display").Markdown(tables.notes_markdown(title, notes)))]


def noted(fn, *args, **kwargs):
    """``fn(*args, **kwargs)`` and the warnings it issued, as ``"<category>: <message>"``.

    The warnings are recorded whatever the filters say (as the record template records
    those of :func:`pipeline.analyse`) and then issued again, so the caller's own filters
    and records see them as if not caught.
    """
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        value = fn(*args, **kwargs)
    for w in caught:
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno, source=w.source)
    return value, tuple(f"{w.category.__name__}: {w.message}" for w in caught)


def render_record_report(
    record,
    analysis,
    fit,
    out_dir,
    *,
    notes=(),
    options: dict | None = None,
    load: dict | None = None,
    scene_given: bool = True,
    html: bool = True,
    name: str | None = None,
) -> NotebookReport:
    """Write the fit report of one record from its analysis and fit, without a kernel.

    Parameters
    ----------
    record : path — the record file (the notebook's ``record`` parameter)
    analysis : Analysis — ``analyse(load_sample(record), scene, **options)``
    fit : ContactFit — ``fit_contact(load_sample(record), scene, n_boot=, seed=)`` with the
        options' ``n_boot`` and ``seed``
    out_dir : path — folder of the report: ``<name>.ipynb`` and ``<name>.html``
    notes : sequence of str — the analysis' warnings (:func:`noted`)
    options : dict, optional — the keyword arguments of :func:`pipeline.analyse` that
        made ``analysis`` (``n_boot`` and ``seed`` among them; default theirs)
    load : dict, optional — the keyword arguments of :func:`pipeline.io.load` the record
        was read with over its sidecar's (a rig's ``sensitivity``...), for the notebook to
        read it the same way
    scene_given : bool — False: the scene is the record's sidecar's (the notebook reads it
        there again); True: the notebook states ``analysis.scene`` as ``scene_json``
    html : bool — also render HTML
    name : str, optional — report file stem; default the record's file name without suffix

    Returns
    -------
    NotebookReport
    """
    record = Path(record).resolve()
    scene = analysis.scene if scene_given else None
    parameters = _record_parameters(record, scene, options or {}, load)
    with _gc_paused():
        return render(
            TEMPLATES["record"],
            parameters,
            record_outputs(analysis, fit, notes),
            Path(out_dir) / f"{name or record.stem}.ipynb",
            html=html,
        )


def _record_parameters(record: Path, scene, options: dict, load=None) -> dict:
    """The record template's parameters: the file, the scene (None: the sidecar's), the
    keyword arguments of :func:`pipeline.analyse` (``n_boot``, ``seed`` and the others)
    and those of :func:`pipeline.io.load` (as Python literals)."""
    options = dict(options)
    return {
        "record": str(record),
        "scene_json": "" if scene is None else json.dumps(_json_scene(scene)),
        "n_boot": int(options.pop("n_boot", 200)),
        "seed": options.pop("seed", 0),
        "analyse_options": options,
        "load_options": _literal(dict(load or {})),
    }


def _literal(value):
    """``value`` as a Python literal for a parameters cell: a sensitivity as its ``(value,
    unit)``, a path as a string, an array as nested lists."""
    from .io import Sensitivity

    if isinstance(value, dict):
        return {k: _literal(v) for k, v in value.items()}
    if isinstance(value, Sensitivity):
        return (value.value, value.unit)
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if hasattr(value, "tolist"):  # a NumPy array or number
        return value.tolist()
    return value


@contextlib.contextmanager
def _gc_paused():
    """The cyclic garbage collector paused while a report is made. Its figures allocate some
    10^5 short-lived objects, and the collections they trigger would each traverse every
    long-lived object of the process (measured: 15 % of a report's cost); their cycles are
    collected after, by the next collection."""
    if not gc.isenabled():
        yield
        return
    gc.disable()
    try:
        yield
    finally:
        gc.enable()


def to_html(nb) -> str:
    """A notebook as one self-contained HTML page: figures embedded, no input prompts, the
    code of each cell folded away (a reader opens it by its "code" summary), nothing
    loaded from the network (:data:`HTML_OPTIONS`)."""
    quiet = logging.getLogger("traitlets")  # nbconvert's accessibility hints are not ours
    level = quiet.level
    quiet.setLevel(logging.ERROR)
    info = nb.metadata.get("language_info", {})
    try:
        body, _ = _exporter(info.get("pygments_lexer", info.get("name"))).from_notebook_node(nb)
    finally:
        quiet.setLevel(level)
    return body


#: The options of the reports' nbconvert HTML exporter: no prompts, and the package's own
#: template (``templates/html/pipeline_report``: JupyterLab's page with each cell's code
#: folded under a "code" a reader can open, and nothing loaded from the network).
HTML_OPTIONS = {
    "exclude_input_prompt": True,
    "exclude_output_prompt": True,
    "template_name": "pipeline_report",
    "extra_template_basedirs": [str(Path(__file__).with_name("templates") / "html")],
}


@functools.cache
def _exporter(lexer):
    """One nbconvert HTML exporter per process (and code lexer): making one (its templates,
    its Jinja environment) costs more than converting a report with it. Its code
    highlighting and HTML sanitising remember their recent results — the template's code
    and markdown are the same in every report — through nbconvert's ``filters`` option:
    the same HTML at about 60 % of the cost."""
    _need("nbconvert")
    from nbconvert import HTMLExporter
    from nbconvert.filters.highlight import Highlight2HTML
    from nbconvert.filters.strings import clean_html

    highlighter = Highlight2HTML(pygments_lexer=lexer)

    @functools.lru_cache(maxsize=256)
    def highlighted(source, language, magics):
        return highlighter(source, language, {"magics_language": magics} if magics else {})

    def highlight_code(source, language=None, metadata=None):
        return highlighted(source, language, (metadata or {}).get("magics_language"))

    return HTMLExporter(
        **HTML_OPTIONS,
        filters={
            "highlight_code": highlight_code,
            "clean_html": functools.lru_cache(maxsize=256)(clean_html),
        },
    )


def record_report(
    record,
    out_dir,
    *,
    scene=None,
    n_boot: int = 200,
    seed: int = 0,
    html: bool = True,
    name: str | None = None,
    kernel: bool = False,
    load: dict | None = None,
) -> NotebookReport:
    """The fit report of one record file: analysed here and rendered, or executed.

    Parameters
    ----------
    record : path — the record file (a sidecar beside it may give its scene and load options)
    out_dir : path — folder of the report: ``<name>.ipynb`` and ``<name>.html``
    scene : Scene, optional — the record's scene; default its sidecar's
    n_boot, seed : int — bootstrap replicates and seed of the analysis and the fit
    html : bool — also render HTML
    name : str, optional — report file stem; default the record's file name without suffix
    kernel : bool — execute the notebook in a fresh Jupyter kernel (:func:`execute`)
        instead of analysing and fitting the record in this process and rendering the
        outputs (:func:`render_record_report`; the same notebook, seconds faster)
    load : dict, optional — keyword arguments of :func:`pipeline.io.load` over the
        sidecar's ``"load"`` block (a rig's ``sensitivity``, ``axes``...)

    Returns
    -------
    NotebookReport

    Raises
    ------
    InputError
        No such record, no scene (neither given nor in a sidecar), a record that cannot be
        analysed; with ``kernel=True`` a :class:`NotebookError` naming the failed cell.
    """
    record = Path(record).resolve()
    options = {"n_boot": int(n_boot), "seed": seed}
    if kernel:
        return execute(
            TEMPLATES["record"],
            _record_parameters(record, scene, options, load),
            Path(out_dir) / f"{name or record.stem}.ipynb",
            html=html,
        )
    t0 = time.perf_counter()
    rec = load_sample(record, **(load or {}))
    given = scene is not None
    scene = scene if given else scene_from_sidecar(record)
    if scene is None:
        raise InputError(
            "no scene: give one (--scene) or put a sidecar beside the record", path=record
        )
    with warnings.catch_warnings():
        # as in the notebook: the analysis' warnings are its notes, the fit's are in its report
        warnings.simplefilter("ignore")
        sensor = sensor_from_sidecar(record)  # the rig's, stated: as the notebook fits
        fit_options = None if sensor is None else {"sensor": sensor}
        a, notes = noted(analyse, rec, scene, n_boot=n_boot, seed=seed, fit_options=fit_options)
        fit = fit_contact(rec, scene, n_boot=n_boot, seed=seed, sensor=sensor)
    r = render_record_report(
        record,
        a,
        fit,
        out_dir,
        notes=notes,
        options=options,
        load=load,
        scene_given=given,
        html=html,
        name=name,
    )
    return NotebookReport(r.ipynb, r.html, time.perf_counter() - t0)


def campaign_report(dataset, out_dir, *, html: bool = True, overview=None) -> NotebookReport:
    """Execute the campaign report for a campaign's netCDF file (``campaign.nc``).

    Writes ``campaign.ipynb`` and ``campaign.html`` into ``out_dir``.

    Parameters
    ----------
    dataset : path — the campaign's netCDF file
    out_dir : path — the folder of the report
    html : bool — also render HTML
    overview : path, optional — the campaign's overview page
        (:func:`pipeline.campaigns.write_overview`), linked from the report; default
        ``overview.html`` beside the dataset where there is one
    """
    dataset = Path(dataset).resolve()
    if not dataset.is_file():
        raise InputError("no such campaign file; run pipeline campaign first", path=dataset)
    out_dir = make_dirs(out_dir)
    if overview is None and dataset.with_name("overview.html").is_file():
        overview = dataset.with_name("overview.html")
    # relative to the notebook (which runs in its own folder), so they can move together
    parameters = {"dataset": os.path.relpath(dataset, out_dir.resolve())}
    if overview is not None:
        rel = os.path.relpath(Path(overview).resolve(), out_dir.resolve())
        parameters["overview"] = Path(rel).as_posix()
    return execute(TEMPLATES["campaign"], parameters, out_dir / "campaign.ipynb", html=html)


def _json_scene(scene) -> dict:
    return json_ready(scene.to_dict() if hasattr(scene, "to_dict") else dict(scene))
