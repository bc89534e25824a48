"""Report notebooks: a template with a papermill-style parameters cell, executed headless,
written as .ipynb and rendered to HTML; a failing cell is an error naming the notebook."""

from __future__ import annotations

import warnings
from pathlib import Path

import nbformat
import pytest

from pipeline.notebook_report import TEMPLATES, NotebookError, execute, record_report

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / "data_samples" / "gr_30deg_0.3ms.csv"


def _stdout(cell) -> str:
    return "".join(o.get("text", "") for o in cell.outputs if o.output_type == "stream")


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    return record_report(RECORD, tmp_path_factory.mktemp("rep"), n_boot=30, seed=3)


def test_record_report_states_this_records_numbers(report):
    """The notebook's summary is the library's own for this record and these parameters."""
    from pipeline import analyse
    from pipeline.io import load
    from pipeline.report import scene_from_sidecar

    nb = nbformat.read(report.ipynb, as_version=4)
    injected = [c for c in nb.cells if "injected-parameters" in c.metadata.get("tags", [])]
    assert len(injected) == 1
    tags = [c.metadata.get("tags", []) for c in nb.cells]
    assert tags.index(["injected-parameters"]) == tags.index(["parameters"]) + 1
    assert "n_boot = 30" in injected[0].source and "seed = 3" in injected[0].source
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = analyse(load(RECORD), scene_from_sidecar(RECORD), n_boot=30, seed=3)
    summary = _stdout(nb.cells[tags.index(["injected-parameters"]) + 1])
    assert a.describe() in summary
    assert summary.startswith("gr_30deg_0.3ms.csv: sensor_csv")


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
