"""Report notebooks: a template with a papermill-style parameters cell, written as .ipynb
and rendered to HTML — its outputs rendered from an analysis already made (the campaign's)
or executed in a kernel; a failing cell is an error naming the notebook. A rendered report
states the numbers of the analysis and fit it reports, and running it again in a kernel
gives the same outputs."""

from __future__ import annotations

import base64
import copy
import io
import re
import subprocess
import warnings
from pathlib import Path

import nbformat
import numpy as np
import pytest
from _shown import UNIT_SCALE, close, html_tables, last_digit, parse_interval, parse_value, rows_of

from pipeline import analyse, campaign, fit_contact
from pipeline.errors import InputError
from pipeline.notebook_report import (
    TEMPLATES,
    NotebookError,
    ReportWarning,
    execute,
    record_report,
    render,
    render_record_report,
)
from pipeline.report import load_sample, scene_from_sidecar, sensor_from_sidecar
from pipeline.tables import record_verdict

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / "data_samples" / "gr_30deg_0.3ms.csv"
OTHER = ROOT / "data_samples" / "gr_45deg_0.3ms.csv"
N_BOOT, SEED = 30, 3


def _stdout(cell) -> str:
    return "".join(o.get("text", "") for o in cell.outputs if o.output_type == "stream")


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    return record_report(RECORD, tmp_path_factory.mktemp("rep"), n_boot=N_BOOT, seed=SEED)


def test_record_report_states_this_records_numbers(report):
    """The notebook's parameters are those given; its verdict and tables are the library's
    own for this record and these parameters (the sensor its sidecar states, as ``pipeline
    fit`` takes it)."""
    from pipeline.io import load

    nb = nbformat.read(report.ipynb, as_version=4)
    injected = [c for c in nb.cells if "injected-parameters" in c.metadata.get("tags", [])]
    assert len(injected) == 1
    tags = [c.metadata.get("tags", []) for c in nb.cells]
    assert tags.index(["injected-parameters"]) == tags.index(["parameters"]) + 1
    assert "n_boot = 30" in injected[0].source and "seed = 3" in injected[0].source
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rec, scene, sensor = load(RECORD), scene_from_sidecar(RECORD), sensor_from_sidecar(RECORD)
        a = analyse(rec, scene, n_boot=30, seed=3, fit_options={"sensor": sensor})
        fit = fit_contact(rec, scene, n_boot=30, seed=3, sensor=sensor)
    # the verdict comes first, right after the parameters
    first = nb.cells[tags.index(["injected-parameters"]) + 1]
    assert first.metadata["tags"] == ["verdict"]
    assert _markdown(first) == record_verdict(a, fit)
    assert _markdown(first).startswith("## `gr_30deg_0.3ms.csv`: 0.3 m/s at 30°")
    record = rows_of(html_tables(_html(nb, "record")[0])[0])
    assert record[0]["value"] == "gr_30deg_0.3ms.csv (sensor_csv)"


def _markdown(cell) -> str:
    return "".join(o.data["text/markdown"] for o in cell.outputs if "text/markdown" in o.data)


def _html(nb, tag) -> list:
    """The HTML of each output of the cell tagged ``tag``."""
    (cell,) = [c for c in nb.cells if tag in c.metadata.get("tags", [])]
    return [o.data["text/html"] for o in cell.outputs if "text/html" in o.get("data", {})]


def test_record_report_shows_figures_and_renders_html(report):
    nb = nbformat.read(report.ipynb, as_version=4)
    pngs = [
        o
        for c in nb.cells
        if c.cell_type == "code"
        for o in c.outputs
        if "image/png" in o.get("data", {})
    ]
    assert len(pngs) >= 2  # seed Figs. 8 and 9 for this record
    assert not [
        o for c in nb.cells if c.cell_type == "code" for o in c.outputs if o.output_type == "error"
    ]
    html = report.html.read_text(encoding="utf-8")
    assert html.lstrip().lower().startswith("<!doctype html>")
    assert "gr_30deg_0.3ms.csv" in html and "data:image/png;base64," in html
    # the code of every cell folded under a summary a reader can open; nothing from the
    # network (the page works offline): no script at all, no remote source or stylesheet
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert html.count('<details class="pipeline-code">') == len(code)
    assert html.count("<summary>the template's default parameters</summary>") == 1
    assert html.count("<summary>parameters of this report</summary>") == 1
    assert "<script" not in html
    assert not re.search(r"""(src|href)=["']?(https?:)?//""", html)


def test_failing_cell_raises_naming_the_notebook(tmp_path):
    out = tmp_path / "bad.ipynb"
    with pytest.raises(NotebookError) as err:
        execute(
            TEMPLATES["record"],
            {"record": str(tmp_path / "missing.csv"), "scene_json": "", "n_boot": 0, "seed": 0},
            out,
            html=False,
        )
    assert str(err.value).startswith(f"{out}: a cell of the report failed")
    assert "InputError" in str(err.value)
    assert out.is_file()  # the partly executed notebook is kept to read the error in it


def test_templates_are_percent_scripts_with_a_parameters_cell():
    import jupytext

    for path in TEMPLATES.values():
        nb = jupytext.read(path)
        tagged = [c for c in nb.cells if "parameters" in c.metadata.get("tags", [])]
        assert len(tagged) == 1, path


# ------------------------------------------------------------------ rendered reports
_NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")


def _unit(printed: str) -> float:
    """One unit in the last digit of a number as printed ("0.897302" → 1e-6)."""
    mantissa, _, exponent = printed.lower().partition("e")
    decimals = len(mantissa.partition(".")[2])
    return 10.0 ** (int(exponent or 0) - decimals)


def _same_text(a: str, b: str) -> bool:
    """The same text, numbers allowed to differ by one unit in their last printed digit
    (the same value computed again may round the other way)."""
    na, nb_ = _NUMBER.findall(a), _NUMBER.findall(b)
    if _NUMBER.split(a) != _NUMBER.split(b) or len(na) != len(nb_):
        return False
    return all(
        abs(float(x) - float(y)) <= max(_unit(x), _unit(y)) * (1 + 1e-9)
        for x, y in zip(na, nb_, strict=True)
    )


def _png(data: str) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(base64.b64decode(data))).convert("RGB"), float)


def _assert_same_outputs(nb, other):
    """Cell by cell: the same kinds of output, texts alike (:func:`_same_text`), figures of
    the same size in pixels and alike to well under one grey level on average."""
    code = [(c, d) for c, d in zip(nb.cells, other.cells, strict=True) if c.cell_type == "code"]
    assert code
    for cell, again in code:
        where = cell.metadata.get("tags", cell.source[:40])
        assert len(cell.outputs) == len(again.outputs), where
        for o, p in zip(cell.outputs, again.outputs, strict=True):
            assert o.output_type == p.output_type, where
            if o.output_type == "stream":
                assert o.name == p.name and _same_text(o.text, p.text), (where, o.text, p.text)
                continue
            assert set(o.data) == set(p.data), where
            for mime in o.data:
                if mime == "image/png":
                    x, y = _png(o.data[mime]), _png(p.data[mime])
                    assert x.shape == y.shape, where
                    assert np.mean(np.abs(x - y)) < 0.5, where
                else:
                    assert _same_text(o.data[mime], p.data[mime]), (where, mime)


def _analysis_and_fit(record, **options):
    """The record analysed and fitted as a user would, independently of any report (with
    the sensor its sidecar states, as ``pipeline fit`` takes it)."""
    rec, scene, sensor = (
        load_sample(record),
        scene_from_sidecar(record),
        sensor_from_sidecar(record),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = analyse(rec, scene, fit_options={"sensor": sensor}, **options)
        return a, fit_contact(rec, scene, sensor=sensor, **options)


@pytest.fixture(scope="module")
def campaign_made(tmp_path_factory):
    """The report pipeline.campaign writes for RECORD as it analyses and fits it."""
    folder = tmp_path_factory.mktemp("campaign-reports")
    campaign([RECORD], n_boot=N_BOOT, seed=SEED, reports=folder)
    return folder


#: The symbols the fit's table shows, and the summary's names of their parameters.
_SYMBOLS = {"E*": "E_eff", "e": "e", "μ": "mu", "k_t/k_M": "kt_scale", "α": "alpha"}


def _check(cell: str, value: float, unit: str = "", std: float | None = None):
    """``cell`` ("v ± s" or "v") in ``unit`` states ``value`` (and ``std``) [SI] to its
    shown digits."""
    got = parse_value(cell)
    k = UNIT_SCALE[unit]
    assert close(got["v"], got["unit_v"], value * k), (cell, value)
    if std is not None:
        assert got["s"] is not None and close(got["s"], got["unit_s"], std * k), (cell, std)


def test_every_number_a_record_report_rounds_is_the_summarys(campaign_made):
    """Each number the rendered report shows — the measured outcomes and Routh's, the
    deviation score, the findings, the fitted parameters with their uncertainty, interval
    and budget shares, what the fit implies — equals, to its shown digits, the one
    summary() holds for the same record, scene and bootstrap (issue 21)."""
    nb = nbformat.read(campaign_made / "gr_30deg_0.3ms.ipynb", as_version=4)
    a, fit = _analysis_and_fit(RECORD, n_boot=N_BOOT, seed=SEED)
    sa, sf = a.summary(), fit.summary()
    outcomes, score = (rows_of(html_tables(h)[0]) for h in _html(nb, "outcomes"))
    rigid = {
        "e_n": sa["rigid_scene"]["e"],
        "e_t": sa["rigid"]["e_t"],
        "ω": sa["rigid"]["omega_rad_per_s"],
    }
    names = {"e_n": "e_n", "e_t": "e_t", "ω": "omega", "θ_r": "rebound_deg"}
    assert [r[""] for r in outcomes] == list(names)
    for r in outcomes:
        o = sa["outcomes"][names[r[""]]]
        unit = {"°": ""}.get(r["unit"], r["unit"])  # degrees are the summary's unit
        _check(r["measured"], o["value"], unit, o["std"])
        if r[""] in rigid:
            _check(r["rigid (Routh)"], rigid[r[""]], unit)
    assert [r[""] for r in score] == ["total", "compression", "restitution"]
    for r in score:
        for col, metric in (("area", "area"), ("max. distance", "max_distance")):
            m = sa["score"][r[""]][metric]
            _check(r[col], m["value"], "", m["std"])
    # the findings: every "value ± std" in the order the three sentences state them
    findings_md = "".join(o.data["text/markdown"] for o in _cell(nb, "findings").outputs)
    stated = re.findall(r"(\d+(?:\.\d+)?) ± (\d+(?:\.\d+)?)", findings_md)
    order = [
        ("compression", "area"),
        ("compression", "max_distance"),
        ("restitution", "area"),
        ("restitution", "max_distance"),
        ("restitution", "max_distance"),
        ("total", "Pt_max"),
        ("total", "Pn_at_Pt_max"),
        ("total", "Pt_drop"),
    ]
    assert len(stated) == len(order), findings_md
    for (v, s_), (phase, metric) in zip(stated, order, strict=True):
        m = sa["score"][phase][metric]
        _check(f"{v} ± {s_}", m["value"], "", m["std"])
    # the fit: value ± the budget's total, interval, shares; then what it implies
    fitted, implied = (html_tables(h)[0] for h in _html(nb, "fit"))
    rows = rows_of(fitted)
    assert [r["quantity"] for r in rows] == ["E*", "e", "μ", "k_t/k_M"]
    for r in rows:
        name = _SYMBOLS[r["quantity"]]
        p, b = sf["parameters"][name], sf["budget"][name]
        _check(r["value"], p["value"], r["unit"], b["total"])
        (lo, hi), digit = parse_interval(r["95 % interval"])
        k = UNIT_SCALE[r["unit"]]
        assert close(lo, digit, p["ci95"][0] * k) and close(hi, digit, p["ci95"][1] * k), r
        for term, sigma in b.items():
            if term == "total":
                continue
            share = 100.0 * (sigma / b["total"]) ** 2
            if r[term] == "<0.1":
                assert 0 < share < 0.05, (name, term)
            else:
                assert close(float(r[term]), last_digit(r[term]), share), (name, term, r[term])
    physics = {"t_c": "t_c_s", "F_max": "F_max_N", "δ_max": "delta_max_m", "e_t": "e_t"}
    seen = set()
    for r in rows_of(implied):
        if r[""] in physics:
            _check(r["value"], sf["physics"][physics[r[""]]], r["unit"])
            seen.add(r[""])
    assert seen == set(physics)


def _cell(nb, tag):
    (cell,) = [c for c in nb.cells if tag in c.metadata.get("tags", [])]
    return cell


def test_a_rendered_report_run_again_in_a_kernel_gives_the_same_outputs(campaign_made):
    """The notebook as written (code cells, parameters) recomputes every output the campaign
    rendered into it: texts, tables and figures."""
    import nbclient

    nb = nbformat.read(campaign_made / "gr_30deg_0.3ms.ipynb", as_version=4)
    again = copy.deepcopy(nb)
    for cell in again.cells:
        if cell.cell_type == "code":
            cell.outputs = []
    nbclient.NotebookClient(
        again,
        kernel_name="python3",
        timeout=None,  # no wall-clock limit: the suite runs on loaded machines
        startup_timeout=3600,
        resources={"metadata": {"path": str(campaign_made)}},
    ).execute(stderr=subprocess.DEVNULL)
    _assert_same_outputs(nb, again)
    assert (campaign_made / "gr_30deg_0.3ms.html").is_file()


def test_a_batched_campaigns_report_shows_what_running_it_gives(tmp_path):
    """The batched path draws its bootstrap otherwise (pipeline.campaigns.batch); the report,
    which recomputes with pipeline.analyse's own, shows analyse's spreads, not the batch's."""
    ds = campaign([RECORD], n_boot=N_BOOT, seed=SEED, fit=False, batched=True, reports=tmp_path)
    nb = nbformat.read(tmp_path / "gr_30deg_0.3ms.ipynb", as_version=4)
    a, _ = _analysis_and_fit(RECORD, n_boot=N_BOOT, seed=SEED)
    # e_t's spread: analyse's 0.0017, the batch's 0.0012 (seed 3, 30 replicates)
    (e_t,) = [r for r in rows_of(html_tables(_html(nb, "outcomes")[0])[0]) if r[""] == "e_t"]
    std = parse_value(e_t["measured"])
    assert close(std["s"], std["unit_s"], a.outcomes.std["e_t"])
    assert not close(std["s"], std["unit_s"], float(ds["e_t_std"].values[0]))  # the batch's


def test_a_report_that_fails_is_named_and_the_campaign_goes_on(tmp_path, monkeypatch):
    """A record whose report cannot be rendered, and one whose report is not where the
    campaign reads it (as when a worker writes to a disk of its own): each is a
    ReportWarning naming the record; both records are analysed; the Dataset is the one
    warnings of the Dataset are the analysis' alone."""
    from pipeline.campaigns import tasks

    def failing(record, *args, **kwargs):
        if Path(record).name == RECORD.name:
            raise InputError("no room for it", path=record)

    monkeypatch.setattr(tasks, "render_record_report", failing)
    with pytest.warns(ReportWarning) as caught:
        ds = campaign([RECORD, OTHER], n_boot=0, fit=False, reports=tmp_path)
    assert list(ds["status"].values) == ["ok", "ok"]
    messages = sorted(str(w.message) for w in caught if w.category is ReportWarning)
    assert len(messages) == 2, messages
    assert messages[0] == f"{RECORD.name}: no report: {RECORD}: no room for it"
    assert messages[1].startswith(f"{OTHER.name}: its report is not at {tmp_path}")
    plain = campaign([RECORD, OTHER], n_boot=0, fit=False)
    assert list(ds["warnings"].values) == list(plain["warnings"].values)


def test_render_needs_outputs_for_every_code_cell_and_a_cell_for_every_output(tmp_path):
    """A template changed without its renderer (or the reverse) is an error, not a report
    with outputs under the wrong code."""
    params = {"record": "r.csv", "scene_json": "", "n_boot": 0, "seed": 0}
    with pytest.raises(ValueError, match="has no rendered outputs"):
        render(TEMPLATES["record"], params, {"record": []}, tmp_path / "a.ipynb")
    tags = ("verdict", "record", "outcomes", "forces", "plane", "findings", "fit", "spare")
    with pytest.raises(ValueError, match=r"no code cell is tagged \['spare'\]"):
        render(TEMPLATES["record"], params, dict.fromkeys(tags, []), tmp_path / "b.ipynb")
    assert not list(tmp_path.iterdir())


def test_html_is_nbconverts_own(report, campaign_made):
    """The HTML of reports made one after another (the exporter remembers the template's
    highlighted code) is what a fresh nbconvert HTMLExporter makes of each."""
    from nbconvert import HTMLExporter

    from pipeline.notebook_report import HTML_OPTIONS, to_html

    for path in (report.ipynb, campaign_made / "gr_30deg_0.3ms.ipynb"):
        nb = nbformat.read(path, as_version=4)
        fresh = HTMLExporter(**HTML_OPTIONS)
        expected, _ = fresh.from_notebook_node(nb)
        assert to_html(nb) == expected, path


def test_a_fits_notes_state_each_cause_once_in_the_units_a_person_reads(tmp_path):
    """The sample from a tri-axial sensor has a verdict (cross-talk, another law, an
    impulse off): the report lists each cause's message once, named for its cause — not
    again as a bare note — and its numbers read in their units, with no e-notation
    (issue 21)."""
    record = ROOT / "data_samples" / "sensor.tdms"
    a, fit = _analysis_and_fit(record, n_boot=N_BOOT, seed=SEED)
    messages = list(fit.verdict["messages"].values())
    assert len(messages) >= 2
    made = render_record_report(record, a, fit, tmp_path, html=False, scene_given=False)
    nb = nbformat.read(made.ipynb, as_version=4)
    (cell,) = [c for c in nb.cells if c.cell_type == "code" and "Notes on the fit" in _markdown(c)]
    notes = _markdown(cell)
    for m in messages:  # Markdown escapes ``_`` and ``*``: compare the words
        words = re.sub(r"\\(.)", r"\1", notes)
        assert words.count(m) == 1, m
    code = re.compile(r"sensor=\{[^}]*\}")  # a snippet to state a value, as Python reads it
    assert not re.search(r"\d[eE][-+]?\d", code.sub("", notes)), notes
