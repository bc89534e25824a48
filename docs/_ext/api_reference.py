"""The API reference, generated from the package's ``__all__`` lists.

Every public module (no ``_`` in its dotted name, outside :data:`SKIP`) gets a page:
its docstring, then autosummary tables of the names in its ``__all__`` (autosummary makes
one page per function and class) and its constants with their ``#:`` comments. Each
object is documented once, on the page of the module a reader imports it from: the
shallowest public module that exports it, the defining one among equals
(``pipeline.io.load``, not the private ``pipeline.io._dispatch``). A name added to an
``__all__`` has its page in the next build, and a docstring that does not parse fails it.

The modules are listed under the stages of :data:`STAGES`, in the order data flows; a
module no stage names is listed after them.

A cross-reference in a docstring may name an object by any public path that reaches it
(``pipeline.analyse``, ``pipeline.fit.fit_contact``, a name relative to the current
module): :func:`resolve_alias` follows it to the page where the object is documented. A
reference that reaches no object stays an error (the build is nitpicky).
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import re
import sys
from pathlib import Path

from docutils import nodes
from sphinx import addnodes
from sphinx.transforms import SphinxTransform

#: The stages in the order data flows (layout.md); each lists module-name prefixes.
STAGES = [
    ("Scenes and records", ["pipeline.scene", "pipeline.record", "pipeline.io"]),
    ("Checks of a record", ["pipeline.window", "pipeline.plausibility", "pipeline.errors"]),
    ("From forces to percussions", ["pipeline.smooth", "pipeline.percussion"]),
    ("Models", ["pipeline.rigid", "pipeline.contact", "pipeline.advice"]),
    ("Records with known truth", ["pipeline.simulate", "pipeline.sensor_model"]),
    ("Fitting contact parameters", ["pipeline.fit"]),
    ("One record, many records", ["pipeline.score", "pipeline.analysis", "pipeline.campaigns"]),
    ("Outputs", ["pipeline.report", "pipeline.tables", "pipeline.precision",
                 "pipeline.figures", "pipeline.export", "pipeline.notebook_report"]),
]
#: Module prefixes with no reference pages (the command line is documented in cli.md).
SKIP = ("pipeline.cli", "pipeline.templates")

#: {id(object): documented dotted name} of every function and class on a page, and
#: {(name, id(object)): documented dotted name} of the constants; filled by write_reference.
_CANONICAL: dict[int, str] = {}
_CANONICAL_DATA: dict[tuple[str, int], str] = {}


def _walk(package) -> list[str]:
    return [m.name for m in pkgutil.walk_packages(package.__path__, package.__name__ + ".")
            if not m.name.startswith(SKIP)]


def _is_reachable(name: str) -> bool:
    # A submodule shadowed by a name of its package (pipeline.figures.style is a function)
    # cannot have a page of its own: its names are on the package's page.
    parent, _, last = name.rpartition(".")
    return getattr(importlib.import_module(parent), last, None) is importlib.import_module(name)


def public_modules(package) -> list[str]:
    """The public modules of ``package``, in the order of :data:`STAGES`."""
    found = [m for m in _walk(package)
             if not any(p.startswith("_") for p in m.split(".")) and _is_reachable(m)]
    ordered = []
    for _, heads in STAGES:
        for head in heads:
            for m in [head] + sorted(found):
                if m in found and m not in ordered and (m == head or m.startswith(head + ".")):
                    ordered.append(m)
    return ordered + sorted(set(found) - set(ordered))


def _attribute_docs(package) -> dict[tuple[str, str], str]:
    """The ``#:`` comments and docstrings of module-level constants, by (module, name)."""
    from sphinx.pycode import ModuleAnalyzer

    docs = {}
    for name in _walk(package):
        try:
            found = ModuleAnalyzer.for_module(name).find_attr_docs()
        except Exception:  # noqa: BLE001 - a module without source: no docs to take
            continue
        for (scope, attr), lines in found.items():
            if not scope:
                docs[(name, attr)] = "\n".join(lines).strip()
    return docs


def _kind(obj) -> str:
    if inspect.isclass(obj):
        return "exceptions" if issubclass(obj, BaseException) else "classes"
    return "functions" if callable(obj) else "data"


def _short_repr(obj) -> str | None:
    text = repr(obj)
    return text if len(text) <= 60 and "\n" not in text else None


def _first_paragraph(module) -> str:
    """A module's first paragraph, its cross-references as plain code (the table has no
    module context to resolve them in)."""
    text = (inspect.getdoc(module) or "").split("\n\n")[0].replace("\n", " ").strip()

    def plain(m):
        name = m.group(2)
        return f"``{name.rpartition('.')[2] if m.group(1) else name}``"

    return re.sub(r":[a-z:]+:`(~?)\.?([^`<]*?)(?: <[^>]*>)?`", plain, text)


def _homes(modules: list[str]) -> dict[tuple[str, int], str]:
    """{(name, id(object)): the module whose page documents it}."""
    homes: dict[tuple[str, int], tuple] = {}
    for order, name in enumerate(modules):
        mod = sys.modules[name]
        for attr in getattr(mod, "__all__", []):
            if attr.startswith("__"):
                continue
            obj = getattr(mod, attr)
            rank = (name.count("."), getattr(obj, "__module__", None) != name, order)
            key = (attr, id(obj))
            if key not in homes or rank < homes[key][0]:
                homes[key] = (rank, name)
    return {key: name for key, (_, name) in homes.items()}


def _module_page(name: str, names: list[str], attr_docs) -> str:
    mod = sys.modules[name]
    groups: dict[str, list[str]] = {"classes": [], "functions": [], "exceptions": [],
                                    "data": []}
    for attr in names:
        groups[_kind(getattr(mod, attr))].append(attr)
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
            if (value := _short_repr(obj)) is not None:
                lines += [f"   :value: {value}"]
            lines += [""] + [f"   {d}" for d in doc.splitlines()] + [""]
    return "\n".join(lines)


def write_reference(package, out: Path) -> None:
    """Write ``out/<module>.rst`` for every public module and ``out/_modules.rst``, the
    stage tables that api.rst includes; fill the map :func:`resolve_alias` reads."""
    attr_docs = _attribute_docs(package)
    modules = public_modules(package)
    for name in modules:
        importlib.import_module(name)
    homes = _homes(modules)
    _CANONICAL.clear()
    _CANONICAL_DATA.clear()
    names: dict[str, list[str]] = {m: [] for m in modules}
    for name in modules:  # in each module's own __all__ order
        mod = sys.modules[name]
        for attr in getattr(mod, "__all__", []):
            obj = getattr(mod, attr, None)
            if homes.get((attr, id(obj))) == name:
                names[name].append(attr)
                if _kind(obj) == "data":
                    _CANONICAL_DATA[(attr, id(obj))] = f"{name}.{attr}"
                else:
                    _CANONICAL[id(obj)] = f"{name}.{attr}"
    out.mkdir(parents=True, exist_ok=True)
    for name in modules:
        _write_if_changed(out / f"{name}.rst", _module_page(name, names[name], attr_docs))
    for stale in set(out.glob("pipeline*.rst")) - {out / f"{m}.rst" for m in modules}:
        stale.unlink()
    # autosummary's stubs of names that moved or went (a fresh clone has none)
    stubs = {f"{name}.rst" for name in _CANONICAL.values()}
    for stale in (out / "generated").glob("*.rst"):
        if stale.name not in stubs:
            stale.unlink()

    index, placed = [], set()
    for title, heads in STAGES + [("Other modules", [])]:
        mods = [m for m in modules if m not in placed and (
            title == "Other modules" or any(m == h or m.startswith(h + ".") for h in heads))]
        if not mods:
            continue
        placed.update(mods)
        index += [title, "-" * len(title), "", ".. list-table::", "   :widths: 30 70", ""]
        for m in mods:
            index += [f"   * - :mod:`{m}`", f"     - {_first_paragraph(sys.modules[m])}"]
        index += ["", ".. toctree::", "   :hidden:", ""] + [f"   reference/{m}" for m in mods]
        index += [""]
    _write_if_changed(out / "_modules.rst", "\n".join(index))


def _write_if_changed(path: Path, text: str) -> None:
    # Sphinx rebuilds a page whose source changed: leave unchanged pages untouched.
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


# --------------------------------------------------------------------- cross-references
def _lookup(dotted: str):
    """The object a dotted path reaches, or None."""
    parts = dotted.split(".")
    for k in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:k]))
        except ImportError:
            continue
        try:
            for attr in parts[k:]:
                obj = getattr(obj, attr)
        except AttributeError:
            return None
        return obj
    return None


_MISSING = object()


def _documented(target: str):
    """The documented name of what ``target`` reaches (a member the reference does not
    document, such as a dataclass field, gives its class's name and the member's); None
    where it reaches an object with no page (a private helper, another package's class);
    :data:`_MISSING` where it reaches nothing."""
    parent, _, last = target.rpartition(".")
    obj = _lookup(target)
    owner = _lookup(parent) if parent else None
    if obj is None:
        if inspect.isclass(owner) and (last in getattr(owner, "__dataclass_fields__", {})
                                       or last in getattr(owner, "__annotations__", {})):
            return f"{_CANONICAL.get(id(owner), owner.__qualname__)}.{last}"
        return _MISSING
    if inspect.ismodule(obj):
        return obj.__name__
    if id(obj) in _CANONICAL and _kind(obj) != "data":
        return _CANONICAL[id(obj)]
    if (last, id(obj)) in _CANONICAL_DATA:
        return _CANONICAL_DATA[(last, id(obj))]
    if inspect.isclass(owner) and id(owner) in _CANONICAL:
        return f"{_CANONICAL[id(owner)]}.{last}"
    return None


def resolve_alias(app, env, node, contnode):
    """``missing-reference``: follow a Python reference by any public path to the page
    that documents its object. A reference that reaches an object without a page of its
    own (a private helper, numpy's or xarray's classes: no inventories are fetched) is
    shown as code without a link; one that reaches nothing is left to fail the build."""
    if node.get("refdomain") != "py":
        return None
    target = node["reftarget"].lstrip("~.")
    module, cls = node.get("py:module"), node.get("py:class")
    candidates = [target] + [f"{c}.{target}" for c in (module, cls) if c]
    if module and cls:
        candidates.append(f"{module}.{cls}.{target}")
    # a docstring is written in its own module, which may not be the page's
    # (or, for a method, in its base class's module)
    documented = _lookup(node["refdoc"].rpartition("/")[2])
    if inspect.ismodule(documented):
        candidates.append(f"{documented.__name__}.{target}")
    for kind in getattr(documented, "__mro__", [documented]):
        if isinstance(getattr(kind, "__module__", None), str):
            candidates.append(f"{kind.__module__}.{target}")
    domain = env.domains["py"]
    exists = False
    for candidate in candidates:
        name = _documented(candidate)
        if name is _MISSING:
            continue
        exists = True
        if name is None:
            continue
        # the object's own role, any role, then the class of a member not documented
        for role, dotted in ((node["reftype"], name), ("obj", name),
                             ("class", name.rpartition(".")[0])):
            found = domain.resolve_xref(env, node["refdoc"], app.builder, role, dotted,
                                        node, contnode)
            if found is not None:
                return found
    return contnode if exists else None


class LinkNames(SphinxTransform):
    """In the user guide's Markdown pages, inline code that is a dotted name of the package
    (`` `pipeline.fit_contact` ``, `` `pipeline.io.load()` ``) links to its API page, like
    a cross-reference: a name that reaches nothing fails the build."""

    default_priority = 400
    _NAME = re.compile(r"^(pipeline(?:\.[A-Za-z_]\w*)+)(?:\(\))?$")

    def apply(self):
        if not str(self.env.doc2path(self.env.docname)).endswith(".md"):
            return
        for lit in list(self.document.findall(nodes.literal)):
            match = self._NAME.match(lit.astext())
            if match is None or isinstance(lit.parent, (nodes.reference, addnodes.pending_xref)):
                continue
            xref = addnodes.pending_xref("", refdomain="py", reftype="obj",
                                         reftarget=match.group(1), refexplicit=True,
                                         refwarn=True, refdoc=self.env.docname)
            lit.replace_self(xref)
            xref += lit


def setup(app):
    import pipeline

    here = Path(app.confdir)
    def write(app, config):
        write_reference(pipeline, here / "reference")
        # autosummary reads these pages for its stubs (not the pages Sphinx found last
        # time, which would miss a module added since)
        config.autosummary_generate = [f"reference/{m}.rst" for m in public_modules(pipeline)]

    app.connect("config-inited", write)
    app.connect("missing-reference", resolve_alias)
    app.add_transform(LinkNames)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
