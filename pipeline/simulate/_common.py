"""What both simulation paths share: model names, the default law, scene checks."""

from __future__ import annotations

import numpy as np

from .. import contact
from ..errors import InputError
from ..scene import Scene

TANGENTIAL_MODELS = ("none", "coulomb", "mindlin")
HISTORY_RULES = ("total", "incremental")

#: laws whose dimensionless force depends on the damping parameter alone (F = K·δ^1.5·(1 +
#: c·δ̇/v0)): their normal problem is integrated once per distinct parameter value.
_SELF_SIMILAR = ("hunt_crossley", "lankarani_nikravesh", "flores")


def default_normal(e) -> str:
    """The default normal law for restitution ``e``: ``"hertz"`` if e == 1, else
    ``"hunt_crossley"``."""
    return "hertz" if float(e) == 1.0 else "hunt_crossley"


def _check_models(tangential, history):
    if tangential not in TANGENTIAL_MODELS:
        raise InputError(
            f"unknown tangential model {tangential!r}; choose one of {TANGENTIAL_MODELS}"
        )
    if history not in HISTORY_RULES:
        raise InputError(f"unknown Mindlin history rule {history!r}; choose one of {HISTORY_RULES}")


_law = contact._law  # name -> NormalLaw, InputError naming the choices


def _param(law, e, K, m_eff, v0, alpha=None, param=None):
    """The law's damping parameter: given, from a material constant, or calibrated to e."""
    if param is not None:
        return param
    if alpha is not None:
        return law.material_to_param(alpha, K, m_eff, v0)  # e.g. c = α·v0 (PHYSICS.md §4)
    return law.calibrate(e)


def _check_target(scene: Scene):
    """Refuse a movable flat target, as :func:`pipeline.rigid.sphere_on_plane` does."""
    if np.any(np.isfinite(np.asarray(scene.target_mass)) & np.isinf(scene.target_radius)):
        raise InputError(
            "a movable flat target (finite target_mass, target_radius = inf) is not a scene "
            "the simulator can take: its tangential inverse mass depends on where its centre "
            "of mass lies, which the scene does not say. Give target_radius for a free "
            "sphere, or leave target_mass = inf for a fixed target"
        )
