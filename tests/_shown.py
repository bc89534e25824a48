"""Reading a rounded number back: what a table or a report shows, and whether it states a
machine's number to its shown digits.

The units are written out here (SI → the unit shown), independently of the package's own
table of them, so a wrong scale in the package fails the tests.
"""

from __future__ import annotations

import math
import re

#: SI → the unit shown.
UNIT_SCALE = {
    "": 1.0,
    "GPa": 1e-9,
    "µs": 1e6,
    "ms": 1e3,
    "mN·s": 1e3,
    "N": 1.0,
    "kN": 1e-3,
    "m/s": 1.0,
    "s/m": 1.0,
    "rad/s": 1.0,
    "%": 1e2,
    "ppm": 1e6,
    "g": 1e3,
    "mm": 1e3,
    "µm": 1e6,
    "kHz": 1e-3,
    "°": 1.0,
}

_SUP = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻", "0123456789-")
_NUM = r"[-+−]?\d+(?:\.\d*)?"
_PM = re.compile(
    rf"^\(?(?P<v>{_NUM})(?: ± (?P<s>{_NUM}))?\)?(?:×10(?P<x>[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+))?"
    r"(?: \((?:fixed|no uncertainty)\))?$"
)
_BOUND = re.compile(rf"^(?P<op>[≥≤]) (?P<v>{_NUM})(?:×10(?P<x>[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+))?$")
_INTERVAL = re.compile(rf"^\[(?P<lo>{_NUM}|-?∞), (?P<hi>{_NUM}|∞)\](?:×10(?P<x>[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+))?$")


def _float(text: str) -> float:
    return float(text.replace("−", "-").replace("∞", "inf"))


def last_digit(text: str, exp: int = 0) -> float:
    """One unit in the last shown digit of a number ("0.8998" → 1e-4), times 10**exp."""
    return 10.0 ** (exp - len(text.partition(".")[2]))


def _exp(m) -> int:
    return int(m["x"].translate(_SUP)) if m["x"] else 0


def states(printed: str, value: float, unit: str = "") -> bool:
    """``printed`` (a number in ``unit``) is ``value`` [SI] rounded to its shown digits:
    within half a unit of its last digit (and a hair for the float)."""
    shown = value * UNIT_SCALE[unit]
    return abs(_float(printed) - shown) <= 0.5 * last_digit(printed) * (1 + 1e-9) + 1e-12 * abs(
        shown
    )


def parse_value(cell: str) -> dict:
    """``"114.7 ± 0.4"``, ``"(1.23 ± 0.03)×10⁶"``, ``"0.9 (fixed)"`` → {"v", "s" (or None),
    "unit_v", "unit_s" (one unit in the last digit of each, in the shown unit)}; or a bound
    ``"≥ 0.131"`` → {"op", "v", "unit_v"}."""
    m = _BOUND.match(cell)
    if m:
        e = _exp(m)
        return {"op": m["op"], "v": _float(m["v"]) * 10.0**e, "unit_v": last_digit(m["v"], e)}
    m = _PM.match(cell)
    assert m, f"not a rounded value: {cell!r}"
    e = _exp(m)
    out = {"v": _float(m["v"]) * 10.0**e, "unit_v": last_digit(m["v"], e), "s": None}
    if m["s"] is not None:
        out.update(s=_float(m["s"]) * 10.0**e, unit_s=last_digit(m["s"], e))
    return out


def parse_interval(cell: str) -> tuple:
    """``"[113.9, 115.4]"`` → ((lo, hi), one unit in the last digit)."""
    m = _INTERVAL.match(cell)
    assert m, f"not an interval: {cell!r}"
    e = _exp(m)
    digits = m["lo"] if "∞" not in m["lo"] else m["hi"]
    return (_float(m["lo"]) * 10.0**e, _float(m["hi"]) * 10.0**e), last_digit(digits, e)


def close(shown: float, unit_digit: float, value: float) -> bool:
    """``shown`` is ``value`` (in the shown unit) rounded to the digit ``unit_digit``."""
    if math.isinf(value) or math.isinf(shown):
        return shown == value
    return abs(shown - value) <= 0.5 * unit_digit * (1 + 1e-9) + 1e-12 * abs(value)


def html_tables(html: str) -> list:
    """The tables of an HTML page or fragment, each as ``{"head": [row, ...], "body":
    [row, ...]}`` of cell texts (a caption dropped)."""
    from html.parser import HTMLParser

    class _Tables(HTMLParser):
        def __init__(self):
            super().__init__()
            self.tables, self.part, self.row, self.cell, self.skip = [], "body", None, None, 0

        def handle_starttag(self, tag, attrs):
            if tag == "table":
                self.tables.append({"head": [], "body": []})
            elif tag == "thead":
                self.part = "head"
            elif tag == "tbody":
                self.part = "body"
            elif tag == "caption":
                self.skip += 1
            elif tag == "tr":
                self.row = []
            elif tag in ("td", "th"):
                self.cell = []

        def handle_endtag(self, tag):
            if tag == "caption":
                self.skip -= 1
            elif tag == "thead":
                self.part = "body"
            elif tag in ("td", "th") and self.cell is not None:
                self.row.append("".join(self.cell).strip())
                self.cell = None
            elif tag == "tr" and self.row is not None:
                self.tables[-1][self.part].append(self.row)
                self.row = None

        def handle_data(self, data):
            if self.cell is not None and not self.skip:
                self.cell.append(data)

    p = _Tables()
    p.feed(html)
    return p.tables


def rows_of(table: dict) -> list:
    """A table's body rows as dicts keyed by its last header row's cells."""
    names = table["head"][-1]
    return [dict(zip(names, row, strict=True)) for row in table["body"]]
