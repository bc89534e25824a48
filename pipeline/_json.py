"""Strict JSON for every summary the package writes (one converter, one rule).

``json.dumps(json_ready(x), allow_nan=False)`` works for any summary: numpy scalars and
arrays become numbers and lists, NaN becomes ``null``, ±inf the strings ``"inf"`` and
``"-inf"`` (as in the sample sidecars, which read back with ``float``).
"""

from __future__ import annotations

import numpy as np

__all__ = ["json_ready"]


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
