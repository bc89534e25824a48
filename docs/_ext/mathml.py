"""Equations as MathML, written at build time (docutils' LaTeX → MathML converter).

Browsers draw MathML themselves, so the pages need no MathJax: nothing is fetched when a
page is viewed, and the site works offline. An equation the converter cannot read fails
the build (a warning, and ``make docs`` treats warnings as errors) instead of showing raw
TeX.
"""

from __future__ import annotations

import re

from docutils import nodes
from docutils.utils.math import latex2mathml
from sphinx.util import logging

logger = logging.getLogger(__name__)


#: Size commands the converter does not know (or knows only first in a group): MathML
#: sizes fences and sums itself.
_SIZES = re.compile(r"\\([Bb]igg?[lrm]?|textstyle|displaystyle)(?![a-zA-Z])")


def _mathml(node, latex: str, block: bool) -> str:
    try:
        return latex2mathml.tex2mathml(_SIZES.sub("", latex), as_block=block)
    except (SyntaxError, latex2mathml.MathError) as exc:
        logger.warning("equation not converted to MathML (%s): %s", exc, latex,
                       location=node, type="mathml")
        return f"<code>{latex}</code>"


def visit_math(self, node):
    self.body.append(_mathml(node, node.astext(), block=False))
    raise nodes.SkipNode


def visit_displaymath(self, node):
    latex = node.astext()
    parts = [latex] if node.get("nowrap") else latex.split("\n\n")
    self.body.append(self.starttag(node, "div", CLASS="math"))
    if node.get("number"):
        self.body.append(f'<span class="eqno">({node["number"]})</span>')
    self.body += [_mathml(node, p.strip(), block=True) for p in parts if p.strip()]
    self.body.append("</div>\n")
    raise nodes.SkipNode


def setup(app):
    app.add_html_math_renderer("mathml", (visit_math, None), (visit_displaymath, None))
    return {"parallel_read_safe": True, "parallel_write_safe": True}
