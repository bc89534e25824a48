"""JSON in and out: strict JSON for every summary the package writes (one converter, one
rule), and one strict reader for the JSON files it is given (scenes, sidecars, matrices).

``json.dumps(json_ready(x), allow_nan=False)`` works for any summary: numpy scalars and
arrays become numbers and lists, NaN becomes ``null``, ±inf the strings ``"inf"`` and
``"-inf"`` (as in the sample sidecars, which read back with ``float``).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from .errors import InputError

__all__ = ["json_ready", "read_json"]


def json_ready(obj):
    """Plain-Python copy of ``obj`` for strict JSON (the one converter every summary uses).

    numpy scalars and arrays become numbers and lists; NaN becomes None; ±inf the strings
    ``"inf"``/``"-inf"`` (as in the sample sidecars, which
    :func:`pipeline.report.scene_from_sidecar` reads back with ``float``).
    """
    if isinstance(obj, dict):
        return {str(k): json_ready(v) for k, v in obj.items()}
    if isinstance(obj, np.ndarray):
        return json_ready(obj.tolist())
    if isinstance(obj, (list, tuple)):
        return [json_ready(v) for v in obj]
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not np.isfinite(obj):
        return None if np.isnan(obj) else ("inf" if obj > 0 else "-inf")
    return obj


def read_json(path, *, what: str = "JSON file") -> dict:
    """A JSON file holding one object, read strictly.

    Parameters
    ----------
    path : str or os.PathLike
    what : str — what the file is, for messages (``"scene file"``, ``"sidecar"``)

    Raises
    ------
    InputError
        Missing file, a directory, unreadable or not UTF-8, malformed JSON (line and
        column named), nesting too deep, a key given twice, or a value that is not an
        object.
    """
    p = Path(os.fspath(path))
    if p.is_dir():
        raise InputError(f"the {what} is a directory; give the path of a JSON file", path=p)
    try:
        raw = p.read_bytes()
    except FileNotFoundError:
        raise InputError(f"no such {what}; check the path", path=p) from None
    except OSError as exc:
        raise InputError(f"cannot read the {what} ({exc.strerror or exc})", path=p) from exc
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(
            f"the {what} is not UTF-8 text (bytes at offset {exc.start}); save it as UTF-8",
            path=p,
            line=raw[: exc.start].count(b"\n") + 1,
        ) from None

    def pairs(items):
        seen = {}
        for key, value in items:
            if key in seen:
                raise InputError(f"key {key!r} appears twice in the {what}; keep one", path=p)
            seen[key] = value
        return seen

    try:
        data = json.loads(text, object_pairs_hook=pairs)
    except json.JSONDecodeError as exc:
        raise InputError(
            f"the {what} is not valid JSON: {exc.msg}", path=p, line=exc.lineno, column=exc.colno
        ) from None
    except RecursionError:
        raise InputError(f"the {what} nests too deeply to be read", path=p) from None
    if not isinstance(data, dict):
        raise InputError(
            f"the {what} must hold a JSON object {{...}}, not a {type(data).__name__}", path=p
        )
    return data
