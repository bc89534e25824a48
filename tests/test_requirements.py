"""The declared minimums are the versions the suite is run against.

``requirements-min.txt`` pins, exactly, the lowest version pyproject.toml allows of every
runtime dependency and of every package of the runtime extras (tdms, distributed,
reports); ``make test-min`` installs the package under those pins in ``.venv-min/`` and runs
the suite there (docs/getting_started.md). A floor raised or lowered in one file and not the
other, or a dependency added without its pin, fails here, so the minimums a lab is promised
are the ones that were tested.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

from packaging.requirements import Requirement
from packaging.version import Version

ROOT = Path(__file__).resolve().parents[1]
RUNTIME_EXTRAS = ("tdms", "distributed", "reports")


def floors(requirements) -> dict[str, Version | None]:
    """``{name: the version of its one >= bound, or None}`` of PEP 508 requirement strings."""
    out = {}
    for text in requirements:
        req = Requirement(text)
        bounds = [Version(s.version) for s in req.specifier if s.operator == ">="]
        out[req.name.lower()] = bounds[0] if len(bounds) == 1 else None
    return out


def pins(path: Path) -> dict[str, Version]:
    """``{name: version}`` of the exact pins (``name==version``) of a constraints file."""
    out = {}
    for line in path.read_text(encoding="utf-8").splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            (spec,) = Requirement(line).specifier
            assert spec.operator == "==", f"{path.name}: {line!r} is not an exact pin"
            out[Requirement(line).name.lower()] = Version(spec.version)
    return out


def test_every_runtime_requirement_is_pinned_at_its_declared_floor():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    declared = floors(project["dependencies"])
    for extra in RUNTIME_EXTRAS:
        declared |= floors(project["optional-dependencies"][extra])
    assert None not in declared.values(), f"a runtime requirement without one >= floor: {declared}"
    assert pins(ROOT / "requirements-min.txt") == declared
