r"""The scene: one impact of a ball on a target, in SI units.

A :class:`Scene` carries everything the rigid and compliant models need: the ball's
geometry, mass and elastic constants, the target's, the impact speed and angle, friction
and restitution. Effective (two-body) properties follow docs/theory.md:

.. math::

    \frac{1}{E^*} = \frac{1-\nu_1^2}{E_1} + \frac{1-\nu_2^2}{E_2}, \quad
    \frac{1}{G^*} = \frac{2-\nu_1}{G_1} + \frac{2-\nu_2}{G_2}, \quad
    \frac{1}{R^*} = \frac{1}{R_1} + \frac{1}{R_2}, \quad
    \frac{1}{m^*} = \frac{1}{m_1} + \frac{1}{m_2}

and the approach and slip speeds follow docs/theory.md:
:math:`v_{n0} = v\cos\alpha`, :math:`v_{t0} = v\sin\alpha - u` (``u`` the target's
surface speed along the slip direction).

Fields may be numpy arrays (broadcast against each other) where a function says it
accepts arrays of scenes; validation then applies element-wise.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ._json import read_json
from .errors import InputError

__all__ = ["Scene", "read_scene_fields"]

_INF = math.inf


def _arr(x):
    return np.asarray(x, dtype=float)


def how_to_give(names) -> str:
    """How a user gives the scene fields ``names``, in Python and on the command line."""
    python = "Scene(" + ", ".join(f"{n}=..." for n in names) + ")"
    keys = " and ".join(f'"{n}"' for n in names)
    return f"{python} in Python, or {keys} in the scene's JSON (the record's sidecar, --scene)"


@dataclass(frozen=True)
class Scene:
    """One impact of a ball on a target.

    Parameters
    ----------
    radius : float
        Ball radius [m].
    speed : float
        Impact speed [m/s]; the relative speed when both bodies move.
    density : float, optional
        Ball density [kg/m³]. Give ``density`` or ``mass``.
    mass : float, optional
        Ball mass [kg].
    E : float, optional
        Ball Young's modulus [Pa]; needed by compliant models.
    nu : float, optional
        Ball Poisson ratio [-], 0 ≤ ν < 0.5; needed by compliant models.
    target_E : float
        Target Young's modulus [Pa]; ``inf`` (default) is a rigid target.
    target_nu : float
        Target Poisson ratio [-]. Default 0.
    target_radius : float
        Radius of a curved target cap or second sphere [m]; ``inf`` (default) is flat.
    target_mass : float
        Mass of the second body [kg]; ``inf`` (default) is a fixed target.
    angle_deg : float
        Angle between the incoming velocity and the surface normal [deg] (the seed's
        tilt α), 0 ≤ α < 90.
    mu : float or None
        Coulomb friction coefficient [-]. ``None``: not known (a scene read from a file
        that does not give it); models that need μ then refuse the scene, and
        :func:`pipeline.analyse` takes μ from the record.
    e : float or None
        Normal coefficient of restitution [-], 0 ≤ e ≤ 1. ``None``: not known, as for μ.
    kappa : float
        I/(m·R²) [-]; 0.4 for a solid sphere.
    spin : float
        Spin before impact [rad/s] on the scene's tangential axis t (the direction of
        v·sin α): positive in the sense a friction force opposing a slip along +t produces,
        so the contact point slips at ``slip0`` = v_t0 − spin·R. (Results are reported on
        the axis of the initial slip, which is −t when ``slip0`` < 0: see
        :mod:`pipeline.simulate`.)
    surface_speed : float
        Tangential speed of the target surface along +t [m/s] (the seed's rotating-disc
        rig); v_t0 = v·sin α − surface_speed.
    yield_strength : float or None
        Ball's yield strength in tension Y [Pa]. ``None`` (default): not stated. With it,
        :func:`pipeline.advise` gives the speed at which the contact first yields
        (Johnson 1985, §6.2 and §11.4: the central pressure reaching 1.60·Y) and says
        whether the impact yields.
    target_yield_strength : float or None
        The target's yield strength Y [Pa]; ``None`` (default): not stated. The contact
        first yields in the body with the lower Y.
    """

    radius: float
    speed: float
    density: float | None = None
    mass: float | None = None
    E: float | None = None
    nu: float | None = None
    target_E: float = _INF
    target_nu: float = 0.0
    target_radius: float = _INF
    target_mass: float = _INF
    angle_deg: float = 0.0
    mu: float | None = 0.0
    e: float | None = 1.0
    kappa: float = 0.4
    spin: float = 0.0
    surface_speed: float = 0.0
    yield_strength: float | None = None
    target_yield_strength: float | None = None

    def __post_init__(self):
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            if v is None:
                if f.name in _REQUIRED:
                    raise InputError(f"Scene.{f.name} is required: give a number")
                continue
            if _is_bool(v) or isinstance(v, (str, bytes)):  # True is not a radius, nor is "1"
                raise InputError(f"Scene.{f.name} must be a number, got {v!r}")
            try:
                a = _arr(v)
            except (TypeError, ValueError):
                raise InputError(f"Scene.{f.name} must be a number, got {v!r}") from None
            if a.dtype.kind not in "fiu":
                raise InputError(f"Scene.{f.name} must be a number, got {v!r}")
            if np.isnan(a).any():
                raise InputError(f"Scene.{f.name} is NaN; give a number")
            object.__setattr__(self, f.name, float(a) if a.ndim == 0 else a)
        self._check_mass()
        checks = [
            ("radius", lambda a: (a > 0) & np.isfinite(a), "a positive finite radius [m]"),
            ("speed", lambda a: (a >= 0) & np.isfinite(a), "a finite speed ≥ 0 [m/s]"),
            ("E", lambda a: a > 0, "a positive Young's modulus [Pa]"),
            ("nu", lambda a: (a >= 0) & (a < 0.5), "a Poisson ratio with 0 ≤ ν < 0.5"),
            ("target_E", lambda a: a > 0, "a positive modulus [Pa] (inf = rigid)"),
            ("target_nu", lambda a: (a >= 0) & (a < 0.5), "a Poisson ratio with 0 ≤ ν < 0.5"),
            ("target_radius", lambda a: a > 0, "a positive radius [m] (inf = flat)"),
            ("target_mass", lambda a: a > 0, "a positive mass [kg] (inf = fixed)"),
            ("angle_deg", lambda a: (a >= 0) & (a < 90), "an angle with 0 ≤ α < 90 [deg]"),
            ("mu", lambda a: (a >= 0) & np.isfinite(a), "a friction coefficient μ ≥ 0"),
            ("e", lambda a: (a >= 0) & (a <= 1), "a restitution coefficient with 0 ≤ e ≤ 1"),
            ("kappa", lambda a: (a > 0) & np.isfinite(a), "κ = I/(m·R²) > 0 (0.4 solid)"),
            ("spin", np.isfinite, "a finite spin [rad/s]"),
            ("surface_speed", np.isfinite, "a finite surface speed [m/s]"),
            ("yield_strength", lambda a: a > 0, "a positive yield strength [Pa]"),
            ("target_yield_strength", lambda a: a > 0, "a positive yield strength [Pa]"),
        ]
        for name, ok, want in checks:
            v = getattr(self, name)
            if v is not None and not np.all(ok(_arr(v))):
                raise InputError(f"Scene.{name} = {v!r} is out of range: give {want}")

    def _check_mass(self):
        d, m = self.density, self.mass
        if d is None and m is None:
            raise InputError("Scene needs the ball's density [kg/m³] or its mass [kg]")
        for name, v in (("density", d), ("mass", m)):
            if v is not None and not np.all((_arr(v) > 0) & np.isfinite(_arr(v))):
                raise InputError(f"Scene.{name} = {v!r} must be positive and finite")
        if d is not None and m is not None:
            derived = _arr(d) * (4.0 / 3.0) * np.pi * _arr(self.radius) ** 3
            if not np.allclose(derived, m, rtol=1e-6, atol=0):
                raise InputError(
                    f"Scene: mass {m!r} kg disagrees with density {d!r} kg/m³ and radius "
                    f"{self.radius!r} m (which give {derived!r} kg); give only one of them"
                )

    # ----------------------------------------------------------------- derived
    @property
    def m(self):
        """Ball mass [kg]."""
        if self.mass is not None:
            return self.mass
        return self.density * (4.0 / 3.0) * np.pi * self.radius**3

    @property
    def m_eff(self):
        """Effective mass m* = 1/(1/m + 1/m_target) [kg]."""
        return _scalar(1.0 / (1.0 / _arr(self.m) + 1.0 / _arr(self.target_mass)))

    @property
    def R_eff(self):
        """Effective radius R* = 1/(1/R + 1/R_target) [m]."""
        return _scalar(1.0 / (1.0 / _arr(self.radius) + 1.0 / _arr(self.target_radius)))

    def require(self, *names: str, why: str = "this model") -> None:
        """Raise :class:`InputError` unless every field in ``names`` is known (not None).

        Parameters
        ----------
        names : str — Scene field names, e.g. ``"mu"``, ``"e"``
        why : str — what needs them, for the message
        """
        missing = [n for n in names if getattr(self, n) is None]
        if missing:
            raise InputError(
                f"{why} needs {', '.join(missing)}, which the scene does not give: set "
                + how_to_give(missing)
                + " (pipeline.analyse takes them from the record when they are unknown)"
            )

    def _need_elastic(self):
        if self.E is None or self.nu is None:
            raise InputError(
                "this model needs the ball's elastic constants: give " + how_to_give(("E", "nu"))
            )

    @property
    def E_eff(self):
        """Effective modulus E* [Pa]: 1/E* = (1−ν1²)/E1 + (1−ν2²)/E2."""
        self._need_elastic()
        inv = (1 - self.nu**2) / _arr(self.E) + (1 - self.target_nu**2) / _arr(self.target_E)
        _need_compliance(inv)
        return _scalar(1.0 / inv)

    @property
    def G_eff(self):
        """Effective shear modulus G* [Pa]: 1/G* = (2−ν1)/G1 + (2−ν2)/G2."""
        self._need_elastic()
        g1 = _arr(self.E) / (2 * (1 + self.nu))
        g2 = _arr(self.target_E) / (2 * (1 + self.target_nu))
        inv = (2 - self.nu) / g1 + (2 - self.target_nu) / g2
        _need_compliance(inv)
        return _scalar(1.0 / inv)

    @property
    def v_n0(self):
        """Approach speed v·cos α [m/s] (> 0)."""
        return self.speed * np.cos(np.radians(self.angle_deg))

    @property
    def v_t0(self):
        """Tangential speed of the centre relative to the target surface, v·sin α − u [m/s]."""
        return self.speed * np.sin(np.radians(self.angle_deg)) - self.surface_speed

    @property
    def slip0(self):
        """Initial slip of the contact point, v_t0 − spin·R [m/s] (docs/theory.md)."""
        return self.v_t0 - self.spin * self.radius

    # ----------------------------------------------------------------- helpers
    def replace(self, **changes) -> Scene:
        """A copy with some fields changed (validated again)."""
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict:
        """The fields given (None omitted), as plain floats or lists (JSON-ready)."""
        out = {}
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            if v is None:
                continue
            out[f.name] = v.tolist() if isinstance(v, np.ndarray) else float(v)
        return out

    @classmethod
    def from_dict(cls, d, *, path=None) -> Scene:
        """Build a Scene from a mapping of field names to numbers (SI units).

        The strings ``"inf"`` and ``"-inf"`` stand for ±infinity (strict JSON has no
        infinity; :func:`pipeline._json.json_ready` writes them so). A key that is not a
        field is an error naming the closest field, so a misspelt key is never dropped.
        ``mu`` and ``e`` left out are None (not known), not the defaults 0 and 1.

        Parameters
        ----------
        d : mapping
        path : str or os.PathLike, optional
            The file the mapping came from, named in error messages.
        """
        import difflib

        if not isinstance(d, Mapping):
            raise InputError(
                f"a scene is a mapping of field names to numbers, got {type(d).__name__}",
                path=path,
            )
        names = cls.field_names()
        unknown = [k for k in d if k not in names]
        if unknown:
            hints = []
            for k in unknown:
                close = difflib.get_close_matches(str(k), names, n=1, cutoff=0.6)
                hints.append(f"{k!r}" + (f" (did you mean {close[0]!r}?)" if close else ""))
            raise InputError(
                f"unknown scene field{'s' if len(unknown) > 1 else ''} {', '.join(hints)}; "
                f"the fields are {', '.join(names)}",
                path=path,
            )
        missing = [k for k in _REQUIRED if d.get(k) is None]
        if d.get("density") is None and d.get("mass") is None:
            missing.append("density or mass")
        if missing:
            raise InputError(f"the scene does not give {', '.join(missing)}", path=path)
        try:
            # μ and e a file does not give are unknown (None), not 0 and 1: the rigid model
            # is never fed a value nobody gave (analyse takes them from the record)
            fields = {"mu": None, "e": None, **d}
            return cls(**{k: _from_json(v) for k, v in fields.items()})
        except InputError as exc:
            if path is None:
                raise
            raise InputError(exc.reason, path=path) from None

    @classmethod
    def from_file(cls, path) -> Scene:
        """Read a scene from a JSON file (see :func:`read_scene_fields`).

        Raises
        ------
        InputError
            Naming the file: unreadable, not UTF-8, malformed JSON, not an object, an
            unknown or missing field, a value that is not a number.
        """
        return cls.from_dict(read_scene_fields(path), path=path)

    @classmethod
    def field_names(cls) -> tuple[str, ...]:
        return tuple(f.name for f in dataclasses.fields(cls))


def read_scene_fields(path) -> dict:
    """The scene fields a JSON file gives, not yet validated as a Scene.

    The file holds either the fields themselves (``{"radius": 0.0127, "speed": 0.6, ...}``)
    or a sample sidecar whose ``"scene"`` object holds them (other keys of a sidecar are
    left to their readers).

    Raises
    ------
    InputError
        Naming the file: missing, a directory, not UTF-8, malformed JSON, not an object, or
        a ``"scene"`` key that is not an object.
    """
    data = read_json(path, what="scene file")
    if "scene" in data:
        data = data["scene"]
        if not isinstance(data, Mapping):
            raise InputError(
                f"'scene' must be an object of scene fields, not a {type(data).__name__}",
                path=path,
            )
    return dict(data)


#: Fields without which there is no scene.
_REQUIRED = ("radius", "speed")


def _from_json(v):
    """``"inf"``/``"-inf"`` (strict JSON's infinity) as floats; anything else unchanged."""
    if isinstance(v, str) and v.strip().lower() in ("inf", "+inf", "-inf", "infinity"):
        return float(v)
    if isinstance(v, list):
        return [_from_json(x) for x in v]
    return v


def _is_bool(v) -> bool:
    return isinstance(v, (bool, np.bool_)) or (isinstance(v, np.ndarray) and v.dtype.kind == "b")


def _need_compliance(inv):
    if np.any(np.asarray(inv) == 0):
        raise InputError(
            "ball and target are both rigid (E = target_E = inf): a compliant model needs "
            "a finite Young's modulus for at least one of them"
        )


def _scalar(a):
    a = np.asarray(a, dtype=float)
    return float(a) if a.ndim == 0 else a
