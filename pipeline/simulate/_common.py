"""What both simulation paths share: model names, the default law, scene checks."""

from __future__ import annotations

import math

import numpy as np

from .. import contact
from ..errors import InputError
from ..scene import Scene

TANGENTIAL_MODELS = ("none", "coulomb", "mindlin")
HISTORY_RULES = ("total", "incremental")

#: the Hunt–Crossley family, F = K·δ^1.5·(1 + c·δ̇/v0): the single path evaluates it with a
#: fast scalar expression, and its force stays positive until δ = 0.
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


def _finite_number(value, name, *, positive):
    """A real number (not a bool or a string), finite and > 0 (or ≥ 0), as a float."""
    number = isinstance(value, int | float | np.number) and not isinstance(value, bool)
    x = float(value) if number else math.nan
    if not (math.isfinite(x) and (x > 0 if positive else x >= 0)):
        raise InputError(
            f"{name} must be a finite number {'> 0' if positive else '≥ 0'}; got {value!r}"
        )
    return x


def _check_tangential_damping(value, tangential):
    xg = _finite_number(value, "tangential_damping", positive=False)
    if xg and tangential != "mindlin":
        raise InputError(
            f"tangential_damping acts in parallel with the Mindlin spring; the {tangential!r} "
            "model has none. Use tangential='mindlin' or tangential_damping=0"
        )
    return xg


def _check_kt_scale(value):
    return _finite_number(value, "kt_scale", positive=True)


_law = contact._law  # name -> NormalLaw, InputError naming the choices


def _param(law, e, K, m_eff, v0, alpha=None, param=None):
    """The law's damping parameter: given, from a material constant, or calibrated to e."""
    if param is not None:
        return param
    if alpha is not None:
        return law.material_to_param(alpha, K, m_eff, v0)  # e.g. c = α·v0 (docs/theory.md)
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


#: dimensionless time of the first-contact analysis (δ ≈ v0·t there)
_TAU_FIRST = 1e-8


def _release_rate(sig, x, u, s, fn, fn_rate, k, eta, eta_rate, mu, lam, total):
    """σ·d/dτ of the trial force a sticking Mindlin contact would have (spring + dashpot)
    minus d/dτ(μ·fn), for a contact sliding on the cap in the direction σ: negative where it
    leaves the cap and sticks (dimensionless, arrays or scalars; x > 0).

    On the cap the spring holds σμ·fn − eta·s, the slip changes as s' = −λ·σμ·fn, and the
    total rule's spring k(x)·ξ changes at fixed ξ by (k'/k)·kξ = (u/2x)·kξ.
    """
    rate = sig * k * s - mu * fn_rate + sig * eta_rate * s - eta * lam * mu * fn
    if total:
        rate = rate + 0.5 * u / x * (mu * fn - sig * eta * s)
    return rate


def _first_contact_mode(fn_of, eta_of, kt_coef, s0, mu, lam, total):
    """How a Mindlin contact starts: 0 stick, +1 slide forward, −1 slide backward.

    ``fn_of(x, u)`` and ``eta_of(x)`` give the dimensionless normal force and tangential
    dashpot coefficient (vectorised or scalar); the rest as in :func:`_release_rate`.
    Evaluated at τ = :data:`_TAU_FIRST` (x ≈ τ, u ≈ 1). The contact sticks if the trial
    force (spring grown over the first instant + dashpot) is under the cap; otherwise it
    slides forward unless it would leave that cap at once (release rate < 0), which happens
    under the total rule when a dashpot growing faster than the spring at first contact
    (Tsuji's δ^{1/4}) exceeds the cap alone (x_γ,t·s0 > μ): the stored displacement then
    points backwards and grows like δ^{−1/4}, and the discrete update converges (dt → 0)
    to sliding backwards, Ft = −μ·Fn, at first.
    """
    tau, h = _TAU_FIRST, 0.5 * _TAU_FIRST
    fn = fn_of(tau, 1.0)
    fn_rate = (fn_of(tau + h, 1.0) - fn_of(tau - h, 1.0)) / (2 * h)  # u − 1 = O(τ·fn)
    eta = eta_of(tau)
    eta_rate = (eta_of(tau + h) - eta_of(tau - h)) / (2 * h)
    k = kt_coef * np.sqrt(tau)
    spring = k * s0 * tau if total else 2.0 / 3.0 * k * s0 * tau
    trial = spring + eta * s0
    args = (tau, 1.0, s0, fn, fn_rate, k, eta, eta_rate, mu, lam, total)
    forward = np.asarray(_release_rate(1.0, *args) >= 0)
    backward = np.asarray(_release_rate(-1.0, *args) >= 0)
    slide = np.where(forward | ~backward, 1, -1)
    return np.where(trial < mu * fn, 0, slide)


def _unique(a, axis=None):
    """``np.unique(a, return_inverse=True, axis=axis)`` without its sort when every entry
    (row, for axis=0) is the same — the usual case of one material and one e, where the
    sort would cost more than the whole tabulated batch."""
    a = np.asarray(a)
    if a.shape[0] and np.all(a == a[:1]):
        return a[:1], np.zeros(a.shape[0], dtype=np.intp)
    uniq, inv = np.unique(a, return_inverse=True, axis=axis)
    return uniq, inv.reshape(-1)
