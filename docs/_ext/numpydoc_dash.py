"""The project's one-line numpydoc entries, ``name : type — meaning [unit]``, split for
numpydoc into its two-line form (``name : type`` over the indented meaning).

numpydoc reads everything after the colon as the type, so without this the meaning would
be drawn as part of the type. Only entry lines of the sections that list names (Parameters,
Returns, Attributes, ...) are split, at their first " — "; an entry without a type
(``**kwargs — passed to ...``) keeps its name alone on the first line.
"""

from __future__ import annotations

import re

SECTIONS = {"Parameters", "Other Parameters", "Returns", "Yields", "Receives", "Raises",
            "Warns", "Attributes"}
_HEADER = re.compile(r"^(\s*)(\S.*?)\s*$")
_ENTRY = re.compile(r"^(\s*)(\S.*?) — (.+)$")


def split_entries(lines: list[str]) -> list[str]:
    out, indent = [], None  # indent: the entries' indentation inside a listing section
    for i, line in enumerate(lines):
        nxt = lines[i + 1] if i + 1 < len(lines) else ""
        head = _HEADER.match(line)
        if head and re.fullmatch(r"\s*-{3,}\s*", nxt) and not re.fullmatch(r"\s*-+\s*", line):
            indent = head.group(1) if head.group(2) in SECTIONS else None
            out.append(line)
            continue
        m = _ENTRY.match(line)
        if indent is not None and m and m.group(1) == indent:
            out += [f"{indent}{m.group(2)}", f"{indent}    {m.group(3)}"]
        else:
            out.append(line)
    return out


def _process(app, what, name, obj, options, lines):
    lines[:] = split_entries(lines)


def setup(app):
    app.setup_extension("numpydoc")
    app.connect("autodoc-process-docstring", _process, priority=400)  # before numpydoc's
    return {"parallel_read_safe": True, "parallel_write_safe": True}
