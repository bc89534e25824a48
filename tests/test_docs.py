"""The documentation runs: the notebook executes and states the seed's findings; every
``python`` block of README.md and of the getting-started page executes and finds what it
says; every ``pipeline.*`` name the README mentions exists; every file the README links to
is there; every user-guide page is in the site's contents. The examples' gallery runs
whenever the site is built (``make docs``, in CI).

The notebook runs in a fresh ``python3`` kernel (ipykernel, from this venv) through
nbclient, as ``make test`` would run it on a fresh clone. The README's blocks run in order in
one namespace (the tour builds on itself), in a temporary working directory where
``data_samples`` points at the repository's samples, so the paths read as written and any
file the examples write lands in the temporary directory.
"""

from __future__ import annotations

import importlib
import re
import warnings
from pathlib import Path

import jupytext
import nbclient
import nbformat
import pytest

from pipeline.errors import PipelineWarning, PoorFitWarning

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOK = ROOT / "notebooks" / "seed_verdict.ipynb"
SCRIPT = ROOT / "notebooks" / "seed_verdict.py"
README = ROOT / "README.md"
GETTING_STARTED = ROOT / "docs" / "getting_started.md"
MAIN_RECORD = ROOT / "data_samples" / "gr_15deg_0.6ms.csv"


# ------------------------------------------------------------------------------ the notebook
@pytest.fixture(scope="module")
def executed():
    """The notebook after a full run (a cell error raises CellExecutionError here, which
    fails every test that uses it)."""
    nb = nbformat.read(NOTEBOOK, as_version=4)
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("MPLBACKEND", "Agg")
        mp.setenv("OPENBLAS_NUM_THREADS", "1")
        client = nbclient.NotebookClient(
            nb,
            kernel_name="python3",
            timeout=None,  # no wall-clock limit: the suite runs on loaded machines
            startup_timeout=3600,
            resources={"metadata": {"path": str(NOTEBOOK.parent)}},
        )
        client.execute()
    return nb


def _cell(nb, tag):
    cells = [c for c in nb.cells if tag in c.get("metadata", {}).get("tags", [])]
    assert len(cells) == 1, f"one cell tagged {tag!r} expected, found {len(cells)}"
    return cells[0]


def _stdout(cell) -> str:
    return "".join(
        o.get("text", "")
        for o in cell.outputs
        if o.output_type == "stream" and o.get("name") == "stdout"
    )


def test_notebook_states_the_seeds_three_findings(executed):
    """The findings cell prints, for the 15° record, the library's three verdicts, and all
    three hold: the record was simulated with Mindlin tangential compliance, which makes
    Pt(Pn) leave the rigid line in restitution and Pt peak and fall (Ciornei et al. 2017,
    doi:10.1051/matecconf/201711207005, §4)."""
    from pipeline import analyse
    from pipeline.io import load
    from pipeline.report import findings, scene_from_sidecar

    with pytest.warns(PoorFitWarning):  # the seed's quartic misses this record's structure
        a = analyse(load(MAIN_RECORD), scene_from_sidecar(MAIN_RECORD))
    expected = findings(a)
    lines = _stdout(_cell(executed, "findings")).splitlines()
    assert lines == list(expected.text)
    assert all(line.endswith("**holds**.") for line in lines)


def test_notebook_coulomb_contrast_scores_near_zero(executed):
    """A rigid-Coulomb simulation follows the broken line: its maximum distance is below
    the near-zero level and none of the three findings holds."""
    from pipeline.report import NEAR_ZERO

    out = _stdout(_cell(executed, "coulomb"))
    m = re.search(r"Coulomb record: area ([\d.]+), max distance ([\d.]+)", out)
    assert m, out
    assert float(m.group(2)) < NEAR_ZERO
    assert "**holds**" not in out
    assert out.count("**does not hold**") == 3


def test_notebook_displays_its_figures(executed):
    """Figs. 4, 8, 9 and the Coulomb Fig. 9 display as images (not as a text repr)."""
    shown = [c for c in executed.cells if c.cell_type == "code" and "display(figures." in c.source]
    assert len(shown) == 4
    for c in shown:
        assert any("image/png" in o.get("data", {}) for o in c.outputs), c.source


def test_notebook_is_paired_and_stripped():
    """The committed .ipynb and its py:percent twin hold the same cells; no outputs stored."""
    a = jupytext.read(SCRIPT)
    b = nbformat.read(NOTEBOOK, as_version=4)
    assert b.metadata["jupytext"]["formats"] == "ipynb,py:percent"

    def cells(nb):
        return [(c.cell_type, c.source.strip()) for c in nb.cells]

    assert cells(a) == cells(b), "run `jupytext --sync notebooks/seed_verdict.py`"
    for c in b.cells:
        if c.cell_type == "code":
            assert c.outputs == [] and c.execution_count is None


# ------------------------------------------------------------------------------- the README
def _python_blocks(text: str) -> list[str]:
    return re.findall(r"^```python[ \t]*\n(.*?)^```", text, flags=re.M | re.S)


def _run_blocks(path: Path, tmp_path, monkeypatch) -> dict:
    """Run a page's python blocks in order in one namespace, in a temporary working
    directory where ``data_samples`` points at the repository's samples."""
    blocks = _python_blocks(path.read_text(encoding="utf-8"))
    assert blocks, f"{path.name} lost its python example"
    (tmp_path / "data_samples").symlink_to(ROOT / "data_samples", target_is_directory=True)
    monkeypatch.chdir(tmp_path)
    ns = {"__name__": "__readme__"}
    for i, code in enumerate(blocks, 1):
        with warnings.catch_warnings():
            # Everything not ours is still an error; the pipeline's own warnings (e.g. the
            # quartic's PoorFitWarning on the 15° record) are part of what the page shows.
            warnings.simplefilter("error")
            warnings.simplefilter("ignore", PipelineWarning)
            try:
                exec(compile(code, f"{path.name} python block {i}", "exec"), ns)
            except Exception as exc:  # name the block, then fail
                first = code.strip().splitlines()[0]
                pytest.fail(f"{path.name} python block {i} ({first!r}) raised {exc!r}")
    return ns


def test_readme_example_runs_and_finds_what_it_says(tmp_path, monkeypatch):
    """The README's taste: the 15° sample sticks and lies far from Routh's line (the seed's
    verdict, Ciornei et al. 2017 §4: its maximum distance is well above the near-zero
    level), and its contact fit recovers the E* the record was simulated with (steel on
    steel, 1/E* = 2(1 − ν²)/E: 114.6 GPa) within 1 % with a verdict that the model describes
    the record."""
    from pipeline.report import NEAR_ZERO, scene_from_sidecar

    ns = _run_blocks(README, tmp_path, monkeypatch)
    a, fit = ns["a"], ns["fit"]
    assert a.rigid.regime == "sticking"
    assert a.score["max_distance"] > 10 * NEAR_ZERO
    truth = scene_from_sidecar(MAIN_RECORD)
    assert fit.values["E_eff"] == pytest.approx(truth.E / (2 * (1 - truth.nu**2)), rel=0.01)
    assert fit.verdict["ok"]
    # a rig's record with its mode stated: the interval holds the E* it was simulated with
    lo, hi = ns["rig_fit"].ci()["E_eff"]
    assert lo <= truth.E / (2 * (1 - truth.nu**2)) <= hi
    # Thornton's law on a plastic record: the yield pressure it was made with, 1 GPa, and
    # the yield speed the README derives from it (Thornton 1997, J. Appl. Mech. 64:383)
    # inside their intervals
    ci = ns["plastic"].ci()
    assert ci["p_y"][0] <= 1e9 <= ci["p_y"][1] and ci["v_y"][0] <= ns["v_y"] <= ci["v_y"][1]


def test_getting_started_example_runs(tmp_path, monkeypatch):
    """The getting-started page's first result states the seed's three findings."""
    ns = _run_blocks(GETTING_STARTED, tmp_path, monkeypatch)
    assert ns["a"].rigid.regime == "sticking"
    assert len(ns["findings"](ns["a"]).text) == 3


def test_readme_links_resolve():
    """Every relative link of the README names a file or folder of the repository."""
    text = README.read_text(encoding="utf-8")
    links = re.findall(r"\]\(([^)#\s]+)[^)]*\)", text)
    local = [x for x in links if not re.match(r"[a-z]+:", x)]
    assert local
    assert [x for x in local if not (ROOT / x).exists()] == []


def test_user_guide_lists_every_page():
    """The site's user guide is built from the table in docs/index.md (docs/conf.py): a page
    left out of it is not in the site's contents, and ``make docs`` fails on it."""
    index = (ROOT / "docs" / "index.md").read_text(encoding="utf-8")
    listed = set(re.findall(r"^\| \[[^]]+\]\(([\w-]+)\.md\)", index, flags=re.M))
    outside = {"index", "getting_started", "user_guide"}  # the site's own pages
    pages = {p.stem for p in (ROOT / "docs").glob("*.md")} - outside
    assert sorted(pages - listed) == [], "add a row for the page to docs/index.md's table"
    assert sorted(listed - pages) == []


def test_readme_names_exist():
    """Every ``pipeline.x.y`` the README mentions is a real module or attribute."""
    text = README.read_text(encoding="utf-8")
    names = sorted(set(re.findall(r"\bpipeline(?:\.[A-Za-z_]\w*)+", text)))
    assert names
    missing = []
    for name in names:
        parts = name.split(".")
        obj, k = None, len(parts)
        while k > 0:  # longest importable module prefix, then attributes
            try:
                obj = importlib.import_module(".".join(parts[:k]))
                break
            except ImportError:
                k -= 1
        try:
            for attr in parts[k:]:
                obj = getattr(obj, attr)
        except AttributeError:
            missing.append(name)
    assert missing == []


def test_readme_two_commands_first():
    """The two commands a newcomer needs come before the tour."""
    text = README.read_text(encoding="utf-8")
    heads = re.findall(r"^## (.+)$", text, flags=re.M)
    assert heads[0] == "Two commands"
    first = text.index("## Two commands")
    assert text.index("make reproduce", first) < text.index("```python")
    assert text.index("make test", first) < text.index("```python")
    makefile = (ROOT / "Makefile").read_text(encoding="utf-8")
    assert re.search(r"^reproduce:", makefile, flags=re.M)
    assert re.search(r"^test:", makefile, flags=re.M)
