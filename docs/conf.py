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

The API reference is generated, not written by hand (``docs/_ext/api_reference.py``): every
public module's ``__all__`` is listed under the stage it belongs to, each object on the
page of the module a reader imports it from, so a name added to an ``__all__`` gets its
page in the next build, and a docstring that does not parse fails it.
"""

from __future__ import annotations

import os
import re
import sys
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
    "numpydoc_dash",  # docs/_ext: "name : type — meaning [unit]" entries split for numpydoc
    "sphinx_gallery.gen_gallery",
    "api_reference",  # docs/_ext: the reference pages from the modules' __all__
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
autosummary_generate = True  # api_reference.py names the pages to read
autosummary_imported_members = True
autodoc_default_options = {"member-order": "bysource"}
autodoc_typehints = "none"  # the numpydoc sections state types and units
numpydoc_show_class_members = False  # the class template lists them
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False  # types are words here ("float or array"), not targets
add_module_names = False

# Examples (sphinx-gallery runs each script at build time) -----------------------------------
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r".*\.py$",  # run every example, not only plot_*
    "within_subsection_order": "FileNameSortKey",  # 01_..., 02_...: the tour's order
    "image_scrapers": ("gallery_figures.scraper",),  # docs/_ext
    "download_all_examples": False,
    "remove_config_comments": True,
    "abort_on_example_error": True,
    "show_memory": False,
    "matplotlib_animations": False,
    "min_reported_time": 5,
    "write_computation_times": False,  # its page loads DataTables from a CDN
}

# HTML ---------------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"pipeline {release}"
html_static_path = ["_static"]
html_css_files = ["custom.css"]
html_show_sourcelink = False
html_copy_source = False
# the colour mode stated (the theme reads it from the context), so that its script finds a
# mode it knows: left empty, it logs a console error on every page ("Got invalid theme mode")
html_context = {"default_mode": "auto"}
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


def _drop_theme_template(app, exception) -> None:
    # pydata-sphinx-theme ships a Jinja template among its static files; copied into the
    # site it is a page of unrendered {{ ... }} links. Nothing links to it.
    if exception is None:
        (Path(app.outdir) / "_static" / "webpack-macros.html").unlink(missing_ok=True)


def setup(app):
    app.connect("build-finished", _drop_theme_template)
    app.connect("source-read", _user_guide_contents)
