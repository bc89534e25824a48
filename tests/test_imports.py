"""The package's imports point one way: no module imports one that imports it back.

Every stage imports only the stages below it (record → window → smoothing → percussion →
rigid / contact / simulate → fit → analysis → report → campaigns → CLI), so a reader knows
what a module may touch and an import inside a function never hides a cycle. The graph is
read from the source (``ast``), imports inside functions included, and a cycle, direct or
through a chain, fails with the chain and the lines that close it. The notebook templates
(``pipeline/templates``) are notebooks, not modules of the package, and are left out.
"""

from __future__ import annotations

import ast
import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "pipeline"
SAMPLE = PACKAGE.parent / "data_samples" / "gr_30deg_0.6ms.csv"


def module_files(root: Path) -> dict[str, tuple[Path, bool]]:
    """``{dotted name: (file, is_package)}`` of every module under the package ``root``."""
    out = {}
    for p in sorted(root.rglob("*.py")):
        if "templates" in p.relative_to(root).parts:
            continue
        parts = list(p.relative_to(root.parent).with_suffix("").parts)
        is_pkg = parts[-1] == "__init__"
        if is_pkg:
            parts.pop()
        out[".".join(parts)] = (p, is_pkg)
    return out


def import_graph(root: Path) -> dict[str, dict[str, int]]:
    """``{module: {imported module of the package: line}}`` from the source, function-level
    imports included; ``from .x import name`` counts as importing ``x.name`` where that is a
    module, else ``x``."""
    mods = module_files(root)

    def resolve(name: str) -> str | None:
        parts = name.split(".")
        while parts:
            if ".".join(parts) in mods:
                return ".".join(parts)
            parts.pop()
        return None

    graph = {}
    for name, (path, is_pkg) in mods.items():
        package = name if is_pkg else name.rpartition(".")[0]
        edges = {}
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package.split(".")[: len(package.split(".")) - node.level + 1]
                    mod = ".".join(base + ([node.module] if node.module else []))
                else:
                    mod = node.module or ""
                targets = [
                    f"{mod}.{a.name}" if f"{mod}.{a.name}" in mods else mod for a in node.names
                ]
            else:
                continue
            for t in targets:
                r = resolve(t)
                if r is not None and r != name:
                    edges.setdefault(r, node.lineno)
        graph[name] = edges
    return graph


def find_cycle(graph: dict[str, dict[str, int]]) -> list[str] | None:
    """One cycle of ``graph`` as a list of modules (first = last), or None."""
    state: dict[str, int] = {}  # 1 on the current path, 2 done
    path: list[str] = []

    def visit(v):
        state[v] = 1
        path.append(v)
        for w in sorted(graph.get(v, {})):
            if state.get(w) == 1:
                return path[path.index(w) :] + [w]
            if w not in state:
                found = visit(w)
                if found:
                    return found
        path.pop()
        state[v] = 2
        return None

    for v in sorted(graph):
        if v not in state:
            found = visit(v)
            if found:
                return found
    return None


def test_the_package_imports_one_way():
    graph = import_graph(PACKAGE)
    assert len(graph) > 50, "the graph must cover the package"
    assert "pipeline.fit.contact" in graph["pipeline.fit"]  # the walker sees the imports
    cycle = find_cycle(graph)
    assert cycle is None, "import cycle: " + " → ".join(
        f"{a} (line {graph[a][b]})" for a, b in zip(cycle, cycle[1:], strict=False)
    )


def test_a_cycle_is_found_however_it_is_hidden(tmp_path):
    """The check itself: a cycle through a chain of three modules, closed by an import
    inside a function and a submodule importing its own package, is reported."""
    pkg = tmp_path / "pkg"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from . import b\n")
    (pkg / "b.py").write_text("from .sub import c\n")
    (pkg / "sub" / "__init__.py").write_text("from .c import f\n")
    (pkg / "sub" / "c.py").write_text("def f():\n    from ..a import g\n    return g\n")
    cycle = find_cycle(import_graph(pkg))
    assert cycle is not None and set(cycle) == {"pkg.a", "pkg.b", "pkg.sub.c"}
    (pkg / "sub" / "c.py").write_text("def f():\n    from .. import sub\n")
    assert set(find_cycle(import_graph(pkg))) == {"pkg.sub", "pkg.sub.c"}
    (pkg / "sub" / "c.py").write_text("import math\n")
    assert find_cycle(import_graph(pkg)) is None


#: Installed (the dev and campaign extras) but never used by a fit: xarray imports dask on
#: its first new Variable where dask is installed (~0.3 s of a first fit's) unless the
#: record is built without its probe for duck arrays (pipeline.record.time_variable).
UNUSED_BY_A_FIT = ("dask", "distributed", "h5py", "h5netcdf", "bokeh", "nbformat", "sphinx")

#: The package's own modules ``pipeline fit`` has no use for: the report stack (the record
#: and its sidecar are read by pipeline.sidecar) and the exporters (``pipeline export``'s
#: choices are spelled out in pipeline.cli.export).
NOT_BY_A_FIT = ("pipeline.report", "pipeline.analysis", "pipeline.advice", "pipeline.export")

_FIT_THEN_DASK = """
NOT_BY_A_FIT = NAMES
import contextlib, io, json, sys
from pipeline.cli import main
with contextlib.redirect_stdout(io.StringIO()) as out:
    status = main(["fit", sys.argv[1]])
after_fit = sorted({m.split(".")[0] for m in sys.modules} & set(sys.argv[2:]))
stages = sorted(m for m in sys.modules if m in NOT_BY_A_FIT)
# a user's dask in the same process, after the fit: xarray still sees dask arrays
import dask.array as da
import numpy as np
import xarray as xr
from pipeline.record import make_record
from pipeline.window import apply_window, find_contact
rec = make_record(np.arange(6.0), {"Fn": np.arange(6.0)}, attrs={"source": "s", "format": "f"})
lazy = rec.chunk({"time": 3})
x = xr.DataArray(da.ones(4, chunks=2), dims="x")
print(json.dumps({"status": status, "report": out.getvalue()[:200], "after_fit": after_fit,
                  "stages": stages,
                  "chunks": lazy.chunks["time"], "lazy_sum": float(lazy["Fn"].sum()),
                  "dask_sum": float((2 * x).sum())}))
""".replace("NAMES", repr(NOT_BY_A_FIT))


def test_a_fit_from_the_command_line_imports_nothing_it_does_not_use():
    """``pipeline fit`` in a fresh process imports neither dask nor the package's report and
    export stacks (a first fit costs its imports, docs/benchmarks.md); dask, imported
    afterwards in the same process, still backs xarray objects (a chunked record, a dask
    DataArray)."""
    if importlib.util.find_spec("dask") is None:  # pragma: no cover - installed by [dev]
        pytest.skip("dask is not installed: nothing could import it")
    out = subprocess.run(
        [sys.executable, "-c", _FIT_THEN_DASK, str(SAMPLE), *UNUSED_BY_A_FIT],
        capture_output=True,
        text=True,
        cwd=PACKAGE.parent,
        check=True,
        env=dict(os.environ, OPENBLAS_NUM_THREADS="1"),
    )
    got = json.loads(out.stdout)
    assert got["status"] == 0 and got["report"].startswith("Contact fit of gr_30deg_0.6ms.csv")
    assert got["after_fit"] == []
    assert got["stages"] == []
    assert got["chunks"] == [3, 3]
    assert got["lazy_sum"] == pytest.approx(15.0, abs=1e-12)  # 0 + 1 + ... + 5
    assert got["dask_sum"] == pytest.approx(8.0, abs=1e-12)


def test_the_export_command_offers_the_exporters_targets():
    """``pipeline export --to`` spells out its choices (registering it imports nothing):
    they are :data:`pipeline.export.TARGETS`."""
    from pipeline import export
    from pipeline.cli import export as command

    assert command.TARGETS == export.TARGETS
