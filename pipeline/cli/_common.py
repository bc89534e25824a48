"""What the commands share: the scene of a record, and warnings turned into log lines."""

from __future__ import annotations

import contextlib
import json
import logging
import warnings
from pathlib import Path

from ..errors import InputError


def read_scene(record_path, scene_path=None):
    """The scene from ``--scene`` (a JSON file of Scene fields), else the record's sidecar."""
    from ..report import scene_from_sidecar
    from ..scene import Scene

    if scene_path:
        return Scene.from_dict(json.loads(Path(scene_path).read_text(encoding="utf-8")))
    scene = scene_from_sidecar(record_path)
    if scene is None:
        raise InputError(
            "no scene: give --scene scene.json (Scene fields in SI units) "
            "or put a sidecar <record>.json with a 'scene' beside the file",
            path=record_path,
        )
    return scene


@contextlib.contextmanager
def log_warnings():
    """The library's warnings (poor fits, fallbacks) reach the user as log lines naming the
    problem, not as Python warnings pointing into the library's source."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        yield
    for w in caught:
        logging.getLogger("pipeline").warning("%s: %s", w.category.__name__, w.message)
