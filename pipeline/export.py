r"""The fitted contact as input lines of the simulators people use: LAMMPS, LIGGGHTS, YADE,
MuJoCo.

A :class:`Contact` holds what was fitted or given — the effective modulus E* [Pa], the
restitution e, the friction coefficient μ, the tangential stiffness as a multiple
``kt_scale`` of Mindlin's 8·G*·a — with the scene it belongs to (ball, target, reference
speed). Each exporter writes the target's own syntax and returns an :class:`Export`: the
input lines, the numbers it converted, and notes on what the conversion keeps and loses.
The conversions (``docs/exports.md`` has the derivations):

**LAMMPS** (``pair_style granular``; ``fix wall/gran granular`` for a flat target). Normal
``hertz`` with k_n = (4/3)·E* given directly (F = k_n·a·δ, a = √(R*δ)), so no version's
material mixing is involved; ``damping tsuji``, whose force −α·√(m*·k_n·a)·δ̇ is the Hertz
dashpot on the *secant* stiffness: α = 2ζ with ζ calibrated exactly to e
(:func:`pipeline.contact.calibrate_hertz_dashpot`, ``"secant"``). LAMMPS turns the number
it reads into α with Tsuji's polynomial α(e), which is only a fit: the exported number is
the input that makes that polynomial give the exact α (for e = 0.9 it is 0.8593; giving
0.9 itself would rebound at e = 0.929); the polynomial reaches e down to 0.31 (below, an
``InputError``). Tangential ``mindlin`` with k_t = 8·G*·kt_scale given
directly (total-displacement history, as :func:`pipeline.simulate.impact`'s default),
tangential damping 0, Coulomb μ, ``limit_damping`` (no attractive normal force, as in the
package's laws). Pitfalls avoided: LAMMPS 29 Sep 2021 and earlier (Debian 12's ``lmp``)
compute a *wall's* ``hertz/material`` stiffness as (4/3)·E/(2(1−ν)) — neither the
E/(1−ν²) of a rigid wall nor the E/(2(1−ν²)) of two like bodies — and its ``mindlin NULL``
stiffness as E(2−ν)(1+ν)/4 instead of 8·G* (``fix_wall_gran.cpp``; as
:mod:`pipeline.simulate.lammps` notes); giving k_n and k_t as numbers avoids both. And
LAMMPS reads numbers in the unit system of its ``units`` command: these need ``units si``.

**LIGGGHTS** (``pair_style gran model hertz tangential history``): material properties per
atom type (Young's modulus, Poisson ratio, restitution, friction). Its damping
:math:`\gamma_n = 2\sqrt{5/6}\,|\beta|\sqrt{S_n m^*}`, β = ln e/√(ln²e + π²), S_n = 2E*a is
the dashpot on the *tangent* stiffness with a closed-form ζ(e) that is only approximate for
Hertz: the exported restitution is the one whose closed form gives the exact ζ. k_t is
8·G*·a from the materials, so ``kt_scale`` ≠ 1 cannot be carried (noted).

**YADE** (``FrictMat`` + ``Ip2_FrictMat_FrictMat_MindlinPhys`` +
``Law2_ScGeom_MindlinPhys_Mindlin``): the same tangent-stiffness closed form through ``en``
(same exported value as LIGGGHTS), friction angle atan μ, k_s from the materials'
average G and ν (exact for like materials), *incremental* tangential history (differs from
the total rule at small incidence; ``docs/theory.md``).

**MuJoCo** (``solref``/``solimp``): contacts are linear soft constraints, so the Hertz law
becomes the linear spring–dashpot with the same contact duration at the reference speed
and the same e: ζ = −ln e/√(π² + ln² e), ω0 = π/(t_c√(1−ζ²)), given as direct stiffness
and damping ``solref="-k -b"`` per unit mass (k = ω0²/d, b = 2ζω0/d with the impedance d of
``solimp``); friction μ in an elliptic cone. No nonlinearity (t_c right at one speed only)
and no tangential compliance (MuJoCo's friction has no displacement memory).

References
----------
LAMMPS ``pair_style granular`` and ``fix wall/gran`` documentation (docs.lammps.org);
Y. Tsuji, T. Tanaka, T. Ishida, Powder Technol. 71:239 (1992),
doi:10.1016/0032-5910(92)88030-L. C. Kloss et al., Prog. Comput. Fluid Dyn. 12:140 (2012),
doi:10.1504/PCFD.2012.047457 (LIGGGHTS). V. Šmilauer et al., Yade documentation 3rd ed.
(2021), doi:10.5281/zenodo.5705394. E. Todorov, T. Erez, Y. Tassa, IROS 2012, 5026,
doi:10.1109/IROS.2012.6386109 (MuJoCo).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

from .contact import calibrate_hertz_dashpot, hertz_impact, zeta_hertz_dashpot_dem
from .errors import InputError
from .scene import Scene
from .simulate.lammps import tsuji_alpha, tsuji_cor_input

__all__ = [
    "TARGETS",
    "Contact",
    "Export",
    "contact_from",
    "export",
    "to_lammps",
    "to_liggghts",
    "to_yade",
    "to_mujoco",
]

#: Export targets, by the name ``--to`` takes.
TARGETS = ("lammps", "liggghts", "yade", "mujoco")


@dataclass(frozen=True)
class Contact:
    """The contact to export: the scene and the fitted (or given) contact parameters.

    Parameters
    ----------
    scene : Scene — ball, target, materials and the reference impact (speed, angle)
    E_eff : float — effective modulus E* [Pa]
    e : float — normal coefficient of restitution [-], 0 < e ≤ 1
    mu : float — Coulomb friction coefficient [-]
    kt_scale : float — tangential stiffness over Mindlin's 8·G*·a [-]
    source : str — where the values came from (a fit file, a scene)
    """

    scene: Scene
    E_eff: float
    e: float
    mu: float
    kt_scale: float = 1.0
    source: str = ""

    def __post_init__(self):
        if not (self.E_eff > 0 and math.isfinite(self.E_eff)):
            raise InputError(f"E_eff = {self.E_eff!r} Pa: give a positive finite modulus")
        if not 0 < self.e <= 1:
            raise InputError(f"e = {self.e!r}: give a restitution with 0 < e ≤ 1")
        if not (self.mu >= 0 and math.isfinite(self.mu)):
            raise InputError(f"mu = {self.mu!r}: give a friction coefficient ≥ 0")
        if not self.kt_scale > 0:
            raise InputError(f"kt_scale = {self.kt_scale!r}: give a positive number")

    @property
    def G_eff(self) -> float:
        """Effective shear modulus [Pa]: the scene's G*, scaled with E* (Poisson ratios kept)."""
        return float(self.scene.G_eff) * self.E_eff / float(self.scene.E_eff)

    @property
    def scene_fitted(self) -> Scene:
        """The scene with μ, e and moduli set to the contact's (for the package's models)."""
        k = self.E_eff / float(self.scene.E_eff)
        return self.scene.replace(
            E=self.scene.E * k,
            target_E=self.scene.target_E * k,
            mu=self.mu,
            e=self.e,
        )


@dataclass(frozen=True)
class Export:
    """One export: the target's input lines and what the conversion did.

    Attributes
    ----------
    target : str — ``lammps``, ``liggghts``, ``yade`` or ``mujoco``
    text : str — the input lines (settings for the contact)
    values : dict — the converted numbers (SI), by name
    notes : tuple of str — what the conversion keeps and what it cannot carry
    script : str — a complete input reproducing the reference impact ("" where none)
    """

    target: str
    text: str
    values: dict
    notes: tuple = ()
    script: str = ""


# ------------------------------------------------------------------ reading a contact
def contact_from(obj, *, scene=None) -> Contact:
    """A :class:`Contact` from a fit result, a Scene, a dict or a JSON file.

    Accepted: a :class:`Contact`; a :class:`~pipeline.Scene` (its E*, e, μ); a fit result
    (:func:`pipeline.fit_contact`: ``.values`` and the scene it was fitted with); a mapping
    or JSON file holding the values as ``"values"`` ({name: number}) or as a fit summary's
    ``"parameters"`` ({name: {"value": number, ...}}, what ``pipeline fit --out`` writes in
    ``fit.json``, with its scene; a model selection's summary gives its chosen fit), with the
    scene as ``"scene"`` (Scene fields) or given as ``scene=``; or a flat mapping / sidecar
    of Scene fields. A value not fitted comes from the scene; a fit of α gives e as the
    restitution it implies (``e_n``).

    Parameters
    ----------
    obj : Contact, Scene, fit result, mapping or path
    scene : Scene, optional — the scene when ``obj`` does not carry one (a fit summary)
    """
    if isinstance(obj, Contact):
        return obj
    if isinstance(obj, Scene):
        return _contact(obj, {}, "scene")
    fit_scene = getattr(getattr(obj, "data", None), "scene", getattr(obj, "scene", None))
    if hasattr(obj, "values") and fit_scene is not None and not isinstance(obj, dict):
        return _contact(scene or fit_scene, _fitted(obj.values, getattr(obj, "physics", {})), "fit")
    path = None
    if isinstance(obj, (str, Path)):
        path = Path(obj)
        try:
            obj = json.loads(path.read_text(encoding="utf-8"))
        except FileNotFoundError:
            raise InputError("no such file; check the path", path=path) from None
        except (ValueError, UnicodeDecodeError) as exc:
            raise InputError(f"not valid JSON: {exc}", path=path) from exc
    if not isinstance(obj, dict):
        raise InputError(
            "a contact to export is a fit, a Scene or a JSON object with 'scene'", path=path
        )
    if "chosen" in obj and isinstance(obj.get("fit"), dict):
        obj = obj["fit"]  # a model selection: the chosen model's fit
    values = obj.get("values", obj.get("parameters", {}))
    values = {k: (v["value"] if isinstance(v, dict) else v) for k, v in values.items()}
    values = _fitted(values, obj.get("physics") or {})
    if scene is None:
        fields = obj.get("scene")
        if fields is None and not ({"values", "parameters"} & set(obj)):
            fields = obj  # a flat scene file
        if fields is None:
            raise InputError(
                "this fit file does not hold its scene: give the scene too "
                "(pipeline export FIT --scene scene.json)",
                path=path,
            )
        scene = Scene.from_dict(fields, path=path)
    return _contact(scene, values, str(path) if path else "mapping")


def _fitted(values, physics) -> dict:
    """The fitted values, with e from the fit's e_n where it fitted α (e = e(α, v0))."""
    values = dict(values)
    if values.get("e") is None and physics.get("e_n") is not None:
        values["e"] = physics["e_n"]
    return values


def _contact(scene: Scene, values: dict, source: str) -> Contact:
    # the fitted μ and e stand in for a scene that did not know them
    known = {k: float(values[k]) for k in ("mu", "e") if values.get(k) is not None}
    scene = scene.replace(**known)
    scene.require("mu", "e", why="an export")
    try:
        E_eff = float(values.get("E_eff", scene.E_eff))
    except InputError:
        raise InputError("an export needs E* (fitted E_eff, or E and nu in the scene)") from None
    return Contact(
        scene=scene,
        E_eff=E_eff,
        e=float(scene.e),
        mu=float(scene.mu),
        kt_scale=float(values.get("kt_scale", 1.0)),
        source=source,
    )


# ------------------------------------------------------------------ conversions
def _invert(fn, target, lo, hi, what):
    from scipy.optimize import brentq

    f_lo, f_hi = fn(lo) - target, fn(hi) - target
    if f_lo * f_hi > 0:
        raise InputError(f"{what}: the exact damping cannot be expressed in this target's input")
    return float(brentq(lambda x: fn(x) - target, lo, hi, xtol=1e-15, rtol=1e-15))


def _lammps_tsuji_input(e: float) -> tuple[float, float]:
    """(number to give ``damping tsuji``, α it makes): α = 2ζ, ζ the exact secant-stiffness
    damping ratio for e; the number is where LAMMPS's polynomial reaches that α
    (:func:`pipeline.simulate.lammps.tsuji_cor_input`)."""
    if e == 1.0:
        return 1.0, float(tsuji_alpha(1.0))
    alpha = 2.0 * float(calibrate_hertz_dashpot(e, "secant"))
    return float(tsuji_cor_input(alpha)), alpha


def _dem_restitution_input(e: float) -> tuple[float, float]:
    """(restitution to give LIGGGHTS/YADE, ζ it makes): their closed-form ζ(e_in) on the
    tangent stiffness equals the exact ζ for e."""
    zeta = float(calibrate_hertz_dashpot(e, "tangent"))
    if e == 1.0:
        return 1.0, 0.0
    return _invert(lambda x: float(zeta_hertz_dashpot_dem(x)), zeta, 1e-12, 1.0, f"e = {e}"), zeta


def _num(x: float) -> str:
    """A number as LAMMPS/LIGGGHTS/YADE read it back exactly (17 significant digits)."""
    return repr(float(x))


# ------------------------------------------------------------------ LAMMPS
def to_lammps(contact, *, script: bool = True, steps_per_contact: int = 4000) -> Export:
    """LAMMPS ``pair_style granular`` (and ``fix wall/gran``) lines for the contact.

    Parameters
    ----------
    contact : Contact or anything :func:`contact_from` takes
    script : bool — also write a complete input that runs the scene's reference impact
        (one ball, the target as a frozen sphere or a wall) and prints ``e_n e_t omega``
    steps_per_contact : int — time steps per Hertz contact duration in that script

    Returns
    -------
    Export — ``text`` holds the settings; ``script`` the runnable input (``units si``).
    """
    c = contact_from(contact)
    s = c.scene
    kn = 4.0 / 3.0 * c.E_eff
    kt = 8.0 * c.G_eff * c.kt_scale
    e_in, alpha = _lammps_tsuji_input(c.e)
    model = (
        f"hertz {_num(kn)} {_num(e_in)} damping tsuji "
        f"tangential mindlin {_num(kt)} 0.0 {_num(c.mu)} limit_damping"
    )
    flat = not math.isfinite(s.target_radius)
    lines = [
        "# pipeline export: fitted contact for LAMMPS (units si: Pa, kg, m, s)",
        f"# E* = {c.E_eff:.6g} Pa, e = {c.e:.6g}, mu = {c.mu:.6g}, kt_scale = {c.kt_scale:.6g}",
        f"# kn = (4/3) E* = {kn:.6g} Pa; kt = 8 G* kt_scale = {kt:.6g} Pa",
        f"# damping tsuji input {e_in:.10g} -> alpha = {alpha:.10g} (exact for e = {c.e:.6g})",
    ]
    if flat:
        lines += [
            "pair_style granular",
            f"pair_coeff * * {model}",
            f"fix wall all wall/gran granular {model} zplane 0.0 NULL",
        ]
    else:
        lines += ["pair_style granular", f"pair_coeff * * {model}"]
    notes = (
        "needs 'units si' (the numbers are SI) and atom_style sphere with diameters, not radii",
        "normal: Hertz with a Tsuji dashpot on the secant stiffness, exact e at every speed; "
        "a Hunt-Crossley fit's e is carried, its speed dependence (if alpha was held) is not",
        "kn and kt are given directly: LAMMPS 29 Sep 2021 and before compute a wall's "
        "hertz/material stiffness with 2(1-nu) in place of 1-nu^2 (rigid wall) or "
        "2(1-nu^2) (like bodies) and its 'mindlin NULL' stiffness wrongly; numbers avoid both",
        "tangential: Mindlin total-displacement history (LAMMPS 'mindlin'), no tangential "
        "damping; history rule and rolling/twisting resistance are not fitted",
    )
    values = {"kn": kn, "kt": kt, "tsuji_input": e_in, "alpha": alpha, "mu": c.mu}
    deck = _lammps_script(c, lines, model, flat, steps_per_contact) if script else ""
    return Export("lammps", "\n".join(lines) + "\n", values, notes, deck)


def _lammps_script(c: Contact, settings, model, flat, steps) -> str:
    s = c.scene
    tc = float(hertz_impact(c.scene_fitted).t_c)
    dt = tc / steps
    R1 = float(s.radius)
    a = math.radians(float(s.angle_deg))
    vx, vz = float(s.speed) * math.sin(a), -float(s.speed) * math.cos(a)
    gap = 1e-6 * R1
    rho = float(s.m) / (4.0 / 3.0 * math.pi * R1**3)
    box = 4.0 * (R1 + (0.0 if flat else float(s.target_radius)))
    head = [
        f"# pipeline export: the reference impact ({s.speed:g} m/s at {s.angle_deg:g} deg)",
        "units si",
        "atom_style sphere",
        "atom_modify map array",
        "dimension 3",
        "boundary f f f",
        "newton off",
        "comm_modify vel yes",
        f"region box block {-box!r} {box!r} {-box!r} {box!r} {-box!r} {box!r} units box",
        f"create_box {1 if flat else 2} box",
    ]
    if flat:
        z1 = R1 + gap
        body = [
            f"create_atoms 1 single 0 0 {z1!r} units box",
            f"set atom 1 diameter {2 * R1!r} density {rho!r}",
            "group ball type 1",
            *[ln for ln in settings if not ln.startswith("#")],
        ]
    else:
        R2 = float(s.target_radius)
        z1 = R1 + R2 + gap
        body = [
            f"create_atoms 1 single 0 0 {z1!r} units box",
            "create_atoms 2 single 0 0 0 units box",
            f"set atom 1 diameter {2 * R1!r} density {rho!r}",
            f"set atom 2 diameter {2 * R2!r} density {rho!r}",
            "group ball type 1",
            "group target type 2",
            *[ln for ln in settings if not ln.startswith("#")],
            "fix hold target freeze",
        ]
    tail = [
        f"velocity ball set {vx!r} 0 {vz!r} units box",
        "neighbor 0.001 bin",
        "fix integrate ball nve/sphere",
        f"timestep {dt!r}",
        "compute spin ball property/atom omegay",
        f"variable e_n equal vz[1]/{-vz!r}",
        f"variable e_t equal vx[1]/{vx!r}" if vx != 0 else "variable e_t equal 1.0",
        "variable omega equal c_spin[1]",
        "thermo_style custom step v_e_n v_e_t v_omega",
        f"thermo {steps}",
        f"run {int(1.6 * steps)}",
        'print "RESULT e_n ${e_n} e_t ${e_t} omega ${omega}"',
    ]
    return "\n".join(head + body + tail) + "\n"


# ------------------------------------------------------------------ LIGGGHTS
def _materials(c: Contact) -> tuple[float, float, float, float]:
    """(E ball, ν ball, E target, ν target) [Pa, -] scaled so their E* is the fitted one."""
    s = c.scene
    k = c.E_eff / float(s.E_eff)
    return float(s.E) * k, float(s.nu), float(s.target_E) * k, float(s.target_nu)


def to_liggghts(contact) -> Export:
    """LIGGGHTS ``gran model hertz`` material properties for the contact (2 atom types:
    1 ball, 2 target)."""
    c = contact_from(contact)
    E1, n1, E2, n2 = _materials(c)
    E2 = min(E2, 1e6 * E1)  # a rigid target: LIGGGHTS needs a number (1e6 × the ball's)
    e_in, zeta = _dem_restitution_input(c.e)
    lines = [
        "# pipeline export: fitted contact for LIGGGHTS-PUBLIC 3.x (units si)",
        f"# E* = {c.E_eff:.6g} Pa, e = {c.e:.6g} (restitution input {e_in:.10g}: exact "
        f"zeta = {zeta:.6g} on the tangent stiffness), mu = {c.mu:.6g}",
        "pair_style gran model hertz tangential history tangential_damping off limitForce on",
        "pair_coeff * *",
        f"fix m1 all property/global youngsModulus peratomtype {_num(E1)} {_num(E2)}",
        f"fix m2 all property/global poissonsRatio peratomtype {_num(n1)} {_num(n2)}",
        "fix m3 all property/global coefficientRestitution peratomtypepair 2 "
        + " ".join([_num(e_in)] * 4),
        "fix m4 all property/global coefficientFriction peratomtypepair 2 "
        + " ".join([_num(c.mu)] * 4),
    ]
    notes = [
        "the dashpot is LIGGGHTS' own (tangent stiffness, closed-form beta(e)); the "
        "restitution given is the one that makes it rebound with the fitted e",
        "k_t = 8 G* a from Young's moduli and Poisson ratios (total history, as LAMMPS)",
    ]
    if not math.isfinite(float(c.scene.target_E)):
        notes.append("rigid target written as 1e6 times the ball's modulus")
    if abs(c.kt_scale - 1.0) > 1e-3:
        notes.append(
            f"kt_scale = {c.kt_scale:.4g} cannot be carried: LIGGGHTS hertz takes k_t from "
            "the materials (exported as 1)"
        )
    values = {"E_ball": E1, "E_target": E2, "restitution_input": e_in, "mu": c.mu}
    return Export("liggghts", "\n".join(lines) + "\n", values, tuple(notes))


# ------------------------------------------------------------------ YADE
def to_yade(contact) -> Export:
    """YADE materials and the Hertz–Mindlin interaction (Python, for ``yade``)."""
    c = contact_from(contact)
    E1, n1, E2, n2 = _materials(c)
    E2 = min(E2, 1e6 * E1)
    e_in, zeta = _dem_restitution_input(c.e)
    rho = float(c.scene.m) / (4.0 / 3.0 * math.pi * float(c.scene.radius) ** 3)
    phi = math.atan(c.mu)
    lines = [
        "# pipeline export: fitted contact for YADE (SI units)",
        f"# E* = {c.E_eff:.6g} Pa, e = {c.e:.6g} (en input {e_in:.10g}), mu = {c.mu:.6g}",
        "from yade import FrictMat, MatchMaker",
        "from yade import Ip2_FrictMat_FrictMat_MindlinPhys, Law2_ScGeom_MindlinPhys_Mindlin",
        f"ball = FrictMat(young={_num(E1)}, poisson={_num(n1)}, density={_num(rho)}, "
        f"frictionAngle={_num(phi)}, label='ball')",
        f"target = FrictMat(young={_num(E2)}, poisson={_num(n2)}, density={_num(rho)}, "
        f"frictionAngle={_num(phi)}, label='target')",
        f"physics = Ip2_FrictMat_FrictMat_MindlinPhys(en=MatchMaker(algo='val', val={_num(e_in)}))",
        "law = Law2_ScGeom_MindlinPhys_Mindlin()",
    ]
    notes = [
        "YADE's Mindlin law adds tangential increments (incremental history): at small "
        "incidence it differs from the total rule the package and LAMMPS use",
        "en: YADE's closed-form damping on the tangent stiffness, given so that it "
        "rebounds with the fitted e",
        "frictionAngle = atan(mu); YADE takes the smaller of the two materials'",
    ]
    if abs(c.kt_scale - 1.0) > 1e-3:
        notes.append(f"kt_scale = {c.kt_scale:.4g} cannot be carried (exported as 1)")
    values = {"young_ball": E1, "young_target": E2, "en": e_in, "frictionAngle": phi}
    return Export("yade", "\n".join(lines) + "\n", values, tuple(notes))


# ------------------------------------------------------------------ MuJoCo
def to_mujoco(contact, *, impedance: float = 0.99) -> Export:
    """MuJoCo ``solref``/``solimp`` and friction for the contact (MJCF attributes).

    Parameters
    ----------
    contact : Contact or anything :func:`contact_from` takes
    impedance : float — the constraint impedance d of ``solimp`` (dmin = dmax), < 1
    """
    c = contact_from(contact)
    if not 0 < impedance < 1:
        raise InputError(f"impedance = {impedance!r}: give 0 < d < 1")
    tc = float(hertz_impact(c.scene_fitted).t_c)
    ln = math.log(c.e)
    zeta = -ln / math.sqrt(math.pi**2 + ln**2)
    w0 = math.pi / (tc * math.sqrt(1.0 - zeta**2))
    k, b = w0**2 / impedance, 2.0 * zeta * w0 / impedance
    d = impedance
    attrs = (
        f'solref="{-k:.8g} {-b:.8g}" solimp="{d} {d} 0.001 0.5 2" '
        f'friction="{c.mu:.8g} 0.005 0.0001" condim="3"'
    )
    lines = [
        "<!-- pipeline export: fitted contact for MuJoCo (SI) -->",
        f"<!-- linear equivalent at {c.scene.speed:g} m/s: t_c = {tc:.6g} s, e = {c.e:.6g} -->",
        '<option cone="elliptic"/>',
        f"<default><geom {attrs}/></default>",
    ]
    notes = (
        "MuJoCo's contact is a linear spring-damper: contact time matches the Hertz "
        f"contact only at {c.scene.speed:g} m/s (Hertz t_c scales as v^-1/5)",
        "no tangential compliance (kt_scale) and no Mindlin force reversal: friction is a "
        "velocity-level constraint",
        "solref negative = direct stiffness and damping per unit mass, divided by the "
        "impedance so that the effective values are omega0^2 and 2 zeta omega0",
    )
    values = {"stiffness": k, "damping": b, "zeta": zeta, "omega0": w0, "t_c": tc}
    return Export("mujoco", "\n".join(lines) + "\n", values, notes)


_EXPORTERS = {"lammps": to_lammps, "liggghts": to_liggghts, "yade": to_yade, "mujoco": to_mujoco}


def export(contact, to: str) -> Export:
    """Export a contact to one of :data:`TARGETS`."""
    try:
        fn = _EXPORTERS[to]
    except KeyError:
        raise InputError(
            f"unknown export target {to!r}; choose one of {', '.join(TARGETS)}"
        ) from None
    return fn(contact)
