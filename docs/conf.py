"""Sphinx configuration of the documentation site (``make docs`` → build/docs/html).

Why Sphinx and not MkDocs + mkdocstrings: the docstrings are numpydoc, which Sphinx's
``numpydoc`` reads as written; ``autosummary`` makes one page per public function and class;
``sphinx-gallery`` runs every example script at build time and keeps its printed output and
figures beside its code, so no example goes stale; ``myst-parser`` reads the Markdown pages
of ``docs/`` in place. pvlib and xarray, whose users ours resemble, build their sites the
same way (pydata-sphinx-theme). The build needs no network: no intersphinx inventories are
fetched, and the pages load nothing from elsewhere when viewed: no web fonts, and the
docstrings' equations are written as MathML at build time (``docs/_ext/mathml.py``), which
the browser draws itself, instead of MathJax fetched from a CDN.

The API reference is generated here, not written by hand (:func:`write_reference`): every
public module's ``__all__`` is listed under the stage it belongs to, each object on the
page of the shallowest public module that exports it (``pipeline.io.load``, not the private
module that defines it), so a name added to an ``__all__`` gets its page in the next build,
and a docstring that does not parse fails it.
"""

from __future__ import annotations

import importlib
import inspect
import os
import pkgutil
import re
import sys
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(HERE / "_ext"))
os.environ.setdefault("MPLBACKEND", "Agg")

import pipeline  # noqa: E402

project = "pipeline"
author = "the pipeline developers"
copyright = "the pipeline developers"  # noqa: A001 - Sphinx's name
release = version = pipeline.__version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
    "mathml",  # docs/_ext: equations as MathML, no MathJax
    "plain_bars",  # docs/_ext: |x| in a docstring is a magnitude
]
html_math_renderer = "mathml"

root_doc = "index"
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "**.ipynb_checkpoints", "reference/_*.rst"]
templates_path = ["_templates"]

# Markdown pages (the user guide) ------------------------------------------------------------
myst_enable_extensions = ["colon_fence", "deflist"]
myst_heading_anchors = 3  # `[campaigns.md](campaigns.md#reports)` resolves

# API reference ------------------------------------------------------------------------------
autosummary_generate = True
autosummary_imported_members = True
autodoc_default_options = {"member-order": "bysource"}
autodoc_typehints = "none"  # the numpydoc sections state types and units
numpydoc_show_class_members = False  # the class template lists them
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False  # types are prose here ("float — speed [m/s]")
add_module_names = False

# Examples (sphinx-gallery runs each script at build time) -----------------------------------
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r".*\.py$",  # run every example, not only plot_*
    "within_subsection_order": "FileNameSortKey",  # 01_..., 02_...: the tour's order
    "ignore_pattern": r"__init__\.py",
    "image_scrapers": ("gallery_figures.scraper",),  # docs/_ext
    "download_all_examples": False,
    "remove_config_comments": True,
    "abort_on_example_error": True,
    "show_memory": False,
    "matplotlib_animations": False,
    "min_reported_time": 5,
}



# HTML ---------------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"pipeline {release}"
html_static_path = ["_static"]
html_css_files = ["custom.css"]
html_show_sourcelink = False
html_copy_source = False
html_theme_options = {
    "navbar_align": "left",
    "show_toc_level": 2,
    "navigation_with_keys": False,
    "header_links_before_dropdown": 5,
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
    "secondary_sidebar_items": ["page-toc"],
}
html_sidebars = {"index": [], "getting_started": []}

# The pipeline's figures draw inside a style context; the examples' figures need no pyplot.
warnings.filterwarnings("ignore", message="Matplotlib is currently using agg")


# ---------------------------------------------------------------------------- API reference
#: The stages in the order data flows (README "Layout"); a public module not named here is
#: listed after them, so a new module is documented without editing this file.
STAGES = [
    ("Scenes and records", ["pipeline.scene", "pipeline.record", "pipeline.io"]),
    ("Checks of a record", ["pipeline.window", "pipeline.plausibility", "pipeline.errors"]),
    ("From forces to percussions", ["pipeline.smooth", "pipeline.percussion"]),
    ("Models", ["pipeline.rigid", "pipeline.contact", "pipeline.advice"]),
    ("Records with known truth", ["pipeline.simulate", "pipeline.sensor_model"]),
    ("Fitting contact parameters", ["pipeline.fit"]),
    ("One record, many records", ["pipeline.score", "pipeline.analysis", "pipeline.campaigns"]),
    ("Outputs", ["pipeline.report", "pipeline.figures", "pipeline.export",
                 "pipeline.notebook_report"]),
]
#: Modules with no public names of their own (the command line is documented in cli.md).
SKIP = ("pipeline.cli", "pipeline.templates")


def _public_modules() -> list[str]:
    found = [
        m.name
        for m in pkgutil.walk_packages(pipeline.__path__, "pipeline.")
        if not any(p.startswith("_") for p in m.name.split("."))
        and not m.name.startswith(SKIP)
    ]
    # A submodule shadowed by a name of its package (pipeline.figures.style is a function)
    # cannot have a page of its own: its names are documented on the package's page.
    found = [m for m in found if _is_reachable(m)]
    ordered = []
    for _, heads in STAGES:
        for head in heads:
            ordered += [head] + sorted(m for m in found if m.startswith(head + "."))
    return ordered + sorted(set(found) - set(ordered))


def _is_reachable(name: str) -> bool:
    parent, _, last = name.rpartition(".")
    return getattr(importlib.import_module(parent), last, None) is importlib.import_module(name)


def _attribute_docs() -> dict[tuple[str, str], str]:
    """The ``#:`` comments and docstrings of module-level constants, by (module, name)."""
    from sphinx.pycode import ModuleAnalyzer

    docs = {}
    for m in pkgutil.walk_packages(pipeline.__path__, "pipeline."):
        if m.name.startswith(SKIP):
            continue
        try:
            found = ModuleAnalyzer.for_module(m.name).find_attr_docs()
        except Exception:  # noqa: BLE001 - a module without source: no docs to take
            continue
        for (scope, name), lines in found.items():
            if not scope:
                docs[(m.name, name)] = "\n".join(lines).strip()
    return docs


def _kind(obj) -> str:
    if inspect.isclass(obj):
        return "exceptions" if issubclass(obj, BaseException) else "classes"
    if callable(obj):
        return "functions"
    return "data"


def _short(obj) -> str | None:
    text = repr(obj)
    return text if len(text) <= 60 and "\n" not in text else None


def _first_line(module) -> str:
    doc = inspect.getdoc(module) or ""
    return doc.split("\n\n")[0].replace("\n", " ").strip()


def write_reference(out: Path) -> None:
    """Write ``reference/<module>.rst`` (one page per public module, its names in
    autosummary tables) and ``reference/_modules.rst`` (the stage tables, included by
    api.rst)."""
    attr_docs = _attribute_docs()
    modules = _public_modules()
    done: set[tuple[str, int]] = set()
    out.mkdir(parents=True, exist_ok=True)
    pages = {}
    for name in modules:
        mod = importlib.import_module(name)
        groups: dict[str, list[str]] = {"classes": [], "functions": [], "exceptions": [],
                                        "data": []}
        for attr in getattr(mod, "__all__", []):
            if attr.startswith("__"):
                continue
            obj = getattr(mod, attr)
            key = (attr, id(obj))
            if key in done:  # documented on a shallower module's page
                continue
            done.add(key)
            groups[_kind(obj)].append(attr)
        lines = [name, "=" * len(name), "", f".. automodule:: {name}", "   :no-members:", "",
                 f".. currentmodule:: {name}", ""]
        titles = {"classes": "Classes", "functions": "Functions",
                  "exceptions": "Exceptions and warnings"}
        for group, title in titles.items():
            if groups[group]:
                lines += [title, "-" * len(title), "", ".. autosummary::",
                          "   :toctree: generated", "   :nosignatures:", ""]
                lines += [f"   {a}" for a in groups[group]] + [""]
        if groups["data"]:
            lines += ["Constants", "---------", ""]
            for attr in groups["data"]:
                obj = getattr(mod, attr)
                doc = attr_docs.get((name, attr)) or next(
                    (d for (m, a), d in attr_docs.items()
                     if a == attr and getattr(sys.modules.get(m), attr, None) is obj), "")
                lines += [f".. py:data:: {attr}"]
                if (value := _short(obj)) is not None:
                    lines += [f"   :value: {value}"]
                lines += [""] + [f"   {d}" for d in doc.splitlines()] + [""]
        pages[name] = "\n".join(lines)
    for name, text in pages.items():
        _write_if_changed(out / f"{name}.rst", text)
    for stale in set(out.glob("pipeline*.rst")) - {out / f"{name}.rst" for name in pages}:
        stale.unlink()

    index = []
    placed = set()
    for title, heads in STAGES + [("Other modules", [])]:
        mods = [m for m in modules if m not in placed and (
            any(m == h or m.startswith(h + ".") for h in heads) or title == "Other modules")]
        if not mods:
            continue
        placed.update(mods)
        index += [title, "-" * len(title), "", ".. list-table::", "   :widths: 30 70", ""]
        for m in mods:
            index += [f"   * - :mod:`{m}`", f"     - {_first_line(sys.modules[m])}"]
        index += ["", ".. toctree::", "   :hidden:", ""] + [f"   reference/{m}" for m in mods]
        index += [""]
    _write_if_changed(out / "_modules.rst", "\n".join(index))


def _write_if_changed(path: Path, text: str) -> None:
    # Sphinx rebuilds a page whose source changed: leave unchanged pages untouched.
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


def _reference(app, config) -> None:
    # Before Sphinx looks for source files, so the pages are found on a fresh clone.
    write_reference(HERE / "reference")


# ------------------------------------------------------------------------------- user guide
def _user_guide_contents(app, docname, source) -> None:
    """The user guide's contents are the pages its table (in index.md) links to, in that
    order: a page added to the table is in the site's navigation, with nothing else to
    edit."""
    if docname != "user_guide":
        return
    table = (HERE / "index.md").read_text(encoding="utf-8")
    pages = re.findall(r"^\| \[[^]]+\]\(([\w-]+)\.md\)", table, flags=re.M)
    source[0] += "\n```{toctree}\n:hidden:\n\n" + "\n".join(pages) + "\n```\n"


def setup(app):
    app.connect("config-inited", _reference)
    app.connect("source-read", _user_guide_contents)
