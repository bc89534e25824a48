"""``|x|`` in a docstring is an absolute value, not a reStructuredText substitution.

The docstrings are written to read as plain text too, where ``|Δe_t| < 1e-4`` means the
magnitude; reStructuredText would take ``|Δe_t|`` for a substitution and fail the build.
This transform, run before docutils resolves substitutions, puts every reference to a
substitution the page does not define back as the text it was written as.
"""

from __future__ import annotations

from docutils import nodes
from docutils.transforms import Transform
from docutils.transforms.references import Substitutions


class PlainBars(Transform):
    default_priority = Substitutions.default_priority - 1

    def apply(self):
        defined = self.document.substitution_defs
        for ref in list(self.document.findall(nodes.substitution_reference)):
            if ref["refname"] not in defined and ref.astext() not in defined:
                ref.replace_self(nodes.Text(f"|{ref.astext()}|"))


def setup(app):
    app.add_transform(PlainBars)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
