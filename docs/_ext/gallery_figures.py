"""The sphinx-gallery scraper of the examples' figures.

The pipeline's figures are :class:`~matplotlib.figure.Figure` objects made without pyplot,
so pyplot's list of figures (what sphinx-gallery's own scraper reads) never holds them.
This one shows every Figure an example binds to a name (or holds in a list or tuple),
once, after the code block that made it.
"""

from __future__ import annotations

from matplotlib.figure import Figure
from sphinx_gallery.scrapers import figure_rst

_shown: dict[str, list[Figure]] = {}  # the figures already shown, of the example running


def scraper(block, block_vars, gallery_conf):
    if block_vars["src_file"] not in _shown:  # a new example: let the last one's go
        _shown.clear()
    shown = _shown.setdefault(block_vars["src_file"], [])
    paths = []
    for value in list(block_vars["example_globals"].values()):
        for fig in value if isinstance(value, (list, tuple)) else [value]:
            if isinstance(fig, Figure) and not any(fig is f for f in shown):
                shown.append(fig)
                path = next(block_vars["image_path_iterator"])
                fig.savefig(path, dpi=150, bbox_inches="tight")
                paths.append(path)
    # one image each, at its own size (sphinx-gallery shrinks several into a row)
    return "".join(figure_rst([path], gallery_conf["src_dir"]) for path in paths)
