r"""Model no more than a scene needs: the cheapest model within a tolerance, before any data.

The tangential ladder, cheapest first:

``"rigid"``
    rigid bodies, Routh's construction with Coulomb friction and a coefficient of
    restitution (:func:`pipeline.rigid.sphere_on_plane`): closed form, no time history;
``"coulomb"``
    a compliant normal law with Coulomb friction and no tangential compliance
    (:func:`pipeline.simulate.impact` with ``tangential="coulomb"``): force histories in
    time; for a sphere its Pt(Pn) is Routh's broken line for any normal law, so it adds
    to the rigid model only what needs time (Pt(t), Fn(t), t_c);
``"mindlin"``
    the same normal law with Mindlin's tangential compliance (spring 8·G*·a, Coulomb cap,
    displacement history) — the full compliant model every cheaper one is judged against.

:func:`advise` evaluates, at the scene's own point, the comparison the physics stability
maps chart over incidence × μ, restitution and tangential stiffness
(``benchmarks/bench_stability_physics.py``, docs/stability.md): it simulates the scene
with the full model and with Coulomb friction (one adaptive integration each, a few
milliseconds), takes the rigid model in closed form, and returns the cheapest rung whose
predicted quantities stay within ``tol`` of the full model's:

- ``e_t``: |Δe_t| (e_t is the centre's tangential velocity after over before);
- ``omega``: |Δω|/|ω| of the full model (relative; 0 when both are 0);
- ``Pt(Pn)``: the largest |ΔPt| at equal Pn over the impact, over Pt_ref (the deviation
  score's tangential scale, :func:`pipeline.score.references`);
- ``Pt(t)`` (only when asked for, ``quantities=``): the largest |ΔPt| at equal time over
  Pt_ref; the rigid model has no time, so it never meets it.

The reason names the region of the maps the scene lies in, with Maw, Barber & Fawcett's
groups: the stiffness ratio :math:`\eta = 2G^*/E^*` (= (1−ν)/(2−ν) for like materials),
:math:`\chi = \eta\,(1 + 1/\kappa)` and the normalised incidence
:math:`\psi_1 = 2\eta\,|s_0|/(\mu v_{n0})`. Rigid theory predicts sliding throughout for
:math:`\psi_1 \ge 2\chi(1+e)` (= 4χ for e = 1, Maw et al.'s criterion). A compliant
contact slides from its first instant when the Mindlin spring, loaded by the slip, meets
the Coulomb cap at once: near first contact δ ≈ v_n0·t, the spring force
8G*√(R*δ)·s0·t over μ·K·δ^{3/2}·(1 + c) is 1.5·ψ1/(1 + c) (c the Hunt–Crossley damping,
0 for Hertz). So for ψ1 ≥ max(2χ(1+e), 2(1+c)/3) Ft = μ·Fn at every instant in every
model and the rigid answer is exact; for elastic and lightly damped contacts the first
bound is the larger. Heavy damping (e → 0, c large) keeps the contact stuck at first even
where rigid theory slides, and rigid theory is off there (the "restitution" map: 0.08 in
e_t at 45° for e = 0.01). Below the sliding boundary the contact sticks, and tangential
compliance decides e_t and ω (Ft reverses, more often as χ grows).

**Yield.** Where the scene states a yield strength (``Scene.yield_strength``,
``target_yield_strength``), :func:`advise` gives the normal approach speed at which the
contact first yields, ``Advice.yield_speed``: the Hertz pressure at the centre reaching
:math:`p_0 = 1.60\,Y` of the softer body (von Mises, ν = 0.3; Johnson §6.2), reached when
:math:`\tfrac12 m^* v_y^2 = \tfrac{8}{15}E^*\sqrt{R^*}\,\delta_y^{5/2}`,
:math:`\delta_y = R^*(\pi p_0/2E^*)^2` — for a sphere on a flat of its own material
:math:`\rho v_y^2/Y \approx 26\,(Y/E^*)^4` (Johnson §11.4): about 0.1 m/s for a
medium-hard steel, below 1 m/s even for a hardened one. Past it much of e < 1 is plastic
work, not viscous damping: the reason says so, and unless ``normal=`` is given the
compliant models use Thornton's elastic–perfectly-plastic law (``"thornton"``,
:mod:`pipeline.contact.plastic`, calibrated to the scene's e).

The comparison is as exact as the integrations behind it: the adaptive single-impact
solver at ``rtol`` (default 1e-9) and Simpson integrals over ``samples`` = 4001 samples,
so errors below about 1e-6 are at the resolution of the check.

References
----------
N. Maw, J. R. Barber, J. N. Fawcett, "The oblique impact of elastic spheres", Wear 38:101
(1976), doi:10.1016/0043-1648(76)90201-7.
K. L. Johnson, *Contact Mechanics*, CUP (1985), §6.2 and §11.4,
doi:10.1017/CBO9781139171731.
C. Thornton, J. Appl. Mech. 64:383 (1997), doi:10.1115/1.2787319.
F.-C. Ciornei et al., MATEC Web Conf. 112:07005 (2017), doi:10.1051/matecconf/201711207005.
Y. C. Chung, J. Y. Ooi, Granular Matter 13:643 (2011), doi:10.1007/s10035-011-0277-0.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._json import json_ready
from .errors import InputError
from .scene import Scene, how_to_give
from .simulate.curved import geometry_error

__all__ = [
    "advice_for",
    "Advice",
    "advise",
    "geometry_error",
    "LADDER",
    "QUANTITIES",
    "mbf_groups",
]

#: The tangential ladder, cheapest first.
LADDER = ("rigid", "coulomb", "mindlin")
#: Quantities :func:`advise` can judge; the first three are the default.
QUANTITIES = ("e_t", "omega", "Pt(Pn)", "Pt(t)")
_DEFAULT_QUANTITIES = QUANTITIES[:3]
_SAMPLES = 4001


@dataclass(frozen=True)
class Advice:
    """The cheapest model that meets a tolerance for one scene (:func:`advise`).

    Attributes
    ----------
    model : str
        A rung of :data:`LADDER`: ``"rigid"``, ``"coulomb"`` or ``"mindlin"``.
    normal : str or None
        The normal law the model needs (None for the rigid model).
    reason : str
        Why, with the numbers (the map region and the errors of the cheaper rungs).
    errors : dict
        ``{quantity: {model: error}}``: the predicted error [-] of each rung below
        ``"mindlin"`` against it (module notes for each quantity's measure); NaN where a
        quantity is undefined (e_t without tangential motion).
    tol : float
        The tolerance [-].
    quantities : tuple of str
        The quantities judged.
    regime : str
        Rigid theory's regime: ``"sliding"`` (throughout) or ``"sticking"``.
    psi1, chi, eta : float
        Maw–Barber–Fawcett's normalised incidence ψ1, χ and the stiffness ratio η = 2G*/E*.
    geometry : dict or None
        On a curved fixed target, :func:`geometry_error`: what the contact normal turning
        over the cap changes, which every model of the ladder ignores; None on a flat one.
    yield_speed : float or None
        The normal approach speed at which the contact first yields [m/s] (module notes),
        from the scene's yield strengths; None where the scene states none.
    """

    model: str
    normal: str | None
    reason: str
    errors: dict
    tol: float
    quantities: tuple
    regime: str
    psi1: float
    chi: float
    eta: float
    geometry: dict | None = None
    yield_speed: float | None = None

    def summary(self) -> dict:
        """JSON-ready dict (NaN → None, inf → "inf")."""
        return json_ready(
            {
                "model": self.model,
                "normal": self.normal,
                "reason": self.reason,
                "errors": self.errors,
                "tol": self.tol,
                "quantities": list(self.quantities),
                "regime": self.regime,
                "psi1": self.psi1,
                "chi": self.chi,
                "eta": self.eta,
                "geometry": self.geometry,
                "yield_speed": self.yield_speed,
            }
        )


def advice_for(scene: Scene, **options) -> Advice | None:
    """:func:`advise` for a scene that gives what it needs (E, ν, μ, e), else None: what
    ``pipeline analyse`` and the report show beside an analysis (its ``rigid_scene``)."""
    if any(getattr(scene, name) is None for name in ("E", "nu", "mu", "e")):
        return None
    try:
        return advise(scene, **options)
    except InputError:  # e.g. both bodies rigid: no compliant model to judge against
        return None


def mbf_groups(scene: Scene) -> tuple[float, float, float]:
    """Maw–Barber–Fawcett's groups (ψ1, χ, η) of a scene [-] (module notes).

    η = 2·G*/E*, χ = η·(1 + 1/κ), ψ1 = 2η·|s0|/(μ·v_n0) (inf when μ = 0). Needs E and ν.
    Arrays of scenes give arrays.
    """
    eta = 2.0 * np.asarray(scene.G_eff) / np.asarray(scene.E_eff)
    chi = eta * (1.0 + 1.0 / np.asarray(scene.kappa, dtype=float))
    mu = np.asarray(scene.mu, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        psi1 = np.where(
            mu > 0,
            2.0 * eta * np.abs(scene.slip0) / (np.where(mu > 0, mu, 1.0) * scene.v_n0),
            np.inf,
        )
    return _f(psi1), _f(chi), _f(eta)


def _f(x):
    x = np.asarray(x, dtype=float)
    return float(x) if x.ndim == 0 else x


def _percussions(rec):
    """(t, Pn, Pt) of a dense simulated record: cumulative Simpson integrals [s, N·s]."""
    from .percussion import cumulative_percussion

    t = rec["time"].values
    Pn, Pt = (
        cumulative_percussion(t, rec[c].values, method="simpson").values for c in ("Fn", "Ft")
    )
    return t, Pn, Pt


def _rel(a, b):
    """|a − b|/|b|, 0 when both vanish."""
    d = abs(a - b)
    return 0.0 if d == 0 else d / abs(b) if b != 0 else float("inf")


def advise(
    scene: Scene,
    *,
    tol: float = 1e-3,
    quantities=None,
    normal: str | None = None,
    rtol: float = 1e-9,
) -> Advice:
    """The cheapest model whose predicted e_t, ω and Pt(Pn) stay within ``tol`` of the full
    compliant model for this scene (module notes).

    Parameters
    ----------
    scene : Scene
        One impact with ``E``, ``nu`` (the compliant models need them), ``mu`` and ``e``.
    tol : float
        Largest acceptable error of every quantity [-] (module notes for each measure).
    quantities : sequence of str, optional
        What must stay within ``tol``: any of :data:`QUANTITIES`; default
        ``("e_t", "omega", "Pt(Pn)")``. ``"Pt(t)"`` needs time, which the rigid model does
        not give.
    normal : str, optional
        The compliant models' normal law (a name in :data:`pipeline.contact.NORMAL_LAWS`);
        default the simulator's: ``"hertz"`` for e = 1, ``"hunt_crossley"`` otherwise —
        and ``"thornton"`` where the scene states a yield strength and its impact yields
        (module notes).
    rtol : float
        Tolerance of the single-impact integrations (:func:`pipeline.simulate.impact`).

    Returns
    -------
    Advice

    Raises
    ------
    InputError
        A scene without E, ν, μ or e, an array scene, a tolerance that is not positive, or
        an unknown quantity.

    Examples
    --------
    >>> from pipeline import Scene, advise
    >>> s = Scene(radius=2.5e-3, density=4000.0, E=380e9, nu=0.23, speed=3.9,
    ...           angle_deg=75.0, mu=0.092, e=0.98)
    >>> advise(s).model
    'rigid'
    """
    from . import rigid, score, simulate

    if not isinstance(scene, Scene):
        raise InputError("advise needs one pipeline.Scene")
    if not (np.isfinite(tol) and tol > 0):
        raise InputError(f"advise: tol = {tol!r} must be a positive number")
    quantities = _DEFAULT_QUANTITIES if quantities is None else tuple(quantities)
    unknown = [q for q in quantities if q not in QUANTITIES]
    if unknown or not quantities:
        raise InputError(f"advise: quantities {unknown or quantities!r}: choose from {QUANTITIES}")
    scene.require("mu", "e", why="advise (rigid and compliant models alike)")
    if scene.E is None or scene.nu is None:
        raise InputError(
            "advise compares the rigid model with the compliant ones, which need the ball's "
            "elastic constants: give " + how_to_give(("E", "nu"))
        )
    v_y, body = _yield_speed(scene)
    yields = v_y is not None and float(scene.v_n0) > v_y
    if normal is None:
        normal = "thornton" if yields and scene.e < 1 else simulate.default_normal(scene.e)
    full = simulate.impact(scene, normal, "mindlin", samples=_SAMPLES, rtol=rtol)
    coul = simulate.impact(scene, normal, "coulomb", samples=_SAMPLES, rtol=rtol)
    rig = rigid.sphere_on_plane(scene)
    psi1, chi, eta = mbf_groups(scene)
    Pt_ref = score.references(rig)[1]

    t_f, Pn_f, Pt_f = _percussions(full)
    t_c, Pn_c, Pt_c = _percussions(coul)
    e_t = float(full.attrs["e_t"])
    w = float(full.attrs["omega"])
    errors = {q: {} for q in quantities}
    for name, et_m, w_m in (
        ("rigid", float(rig.e_t), float(rig.omega)),
        ("coulomb", float(coul.attrs["e_t"]), float(coul.attrs["omega"])),
    ):
        if "e_t" in errors:
            errors["e_t"][name] = abs(et_m - e_t)
        if "omega" in errors:
            errors["omega"][name] = _rel(w_m, w)
    if "Pt(Pn)" in errors:
        errors["Pt(Pn)"]["rigid"] = float(np.max(np.abs(rig.broken_line(Pn_f) - Pt_f)) / Pt_ref)
        # Coulomb's Pt at the full model's Pn (Pn increases monotonically: Fn ≥ 0)
        Pt_c_at = np.interp(Pn_f, Pn_c, Pt_c)
        errors["Pt(Pn)"]["coulomb"] = float(np.max(np.abs(Pt_c_at - Pt_f)) / Pt_ref)
    if "Pt(t)" in errors:
        errors["Pt(t)"]["rigid"] = float("inf")  # no time in the rigid model
        Pt_c_t = np.interp(t_f, t_c, Pt_c, right=Pt_c[-1])
        errors["Pt(t)"]["coulomb"] = float(np.max(np.abs(Pt_c_t - Pt_f)) / Pt_ref)

    def worst(model):
        vals = [errors[q][model] for q in quantities if np.isfinite(errors[q][model])]
        undefined = any(np.isinf(errors[q][model]) for q in quantities)
        return float("inf") if undefined else max(vals, default=0.0)

    rung = next((m for m in LADDER[:2] if worst(m) <= tol), "mindlin")
    reason = _reason(scene, rung, worst, errors, tol, rig, psi1, chi)
    if v_y is not None:
        reason += ". " + _yield_reason(scene, v_y, body, normal)
    geometry = None
    if np.isfinite(float(scene.target_radius)) and np.isinf(float(scene.target_mass)):
        geometry = geometry_error(scene, tol=tol, normal=normal, rtol=rtol)
        if geometry["exceeds"]:
            reason += (
                f" On this {float(scene.target_radius) * 1e3:.3g} mm cap the contact normal "
                f"turns by {geometry['theta']:.2g} rad while the ball slides over it; every "
                f"model here ignores that, and it moves e_n by {geometry['e_n']:.2g} and e_t "
                f"by {geometry['e_t']:.2g} (beyond tol): take these from "
                "pipeline.simulate.curved.turning_outcomes."
            )
    return Advice(
        model=rung,
        normal=None if rung == "rigid" else normal,
        reason=reason,
        errors=errors,
        tol=float(tol),
        quantities=quantities,
        regime=str(rig.regime),
        psi1=psi1,
        chi=chi,
        eta=eta,
        geometry=geometry,
        yield_speed=v_y,
    )


def _yield_speed(scene: Scene):
    """(v_y [m/s], which body yields first) from the scene's yield strengths, or (None, "")
    (module notes)."""
    from .contact import yield_onset_pressure, yield_velocity

    stated = [
        (float(y), who)
        for y, who in ((scene.yield_strength, "ball"), (scene.target_yield_strength, "target"))
        if y is not None
    ]
    if not stated:
        return None, ""
    Y, who = min(stated)
    p0 = yield_onset_pressure(Y)
    v_y = float(yield_velocity(p0, scene.E_eff, scene.R_eff, scene.m_eff))
    other = (
        "" if len(stated) == 2 else f", the {'target' if who == 'ball' else 'ball'}'s not stated"
    )
    return v_y, f"the {who}'s Y = {Y / 1e6:.4g} MPa{other}; p_0 = 1.60·Y"


def _yield_reason(scene, v_y, body, normal) -> str:
    v0 = float(scene.v_n0)
    if v0 <= v_y:
        return (
            f"The contact stays elastic: v_n0 = {v0:.3g} m/s is below the speed of first "
            f"yield v_y = {v_y:.3g} m/s ({body}; Johnson §11.4)."
        )
    text = (
        f"The impact yields: v_n0 = {v0:.3g} m/s is {v0 / v_y:.3g}× the speed of first yield "
        f"v_y = {v_y:.3g} m/s ({body}; Johnson §11.4), so much of e < 1 is plastic work, not "
        "damping"
    )
    if normal == "thornton":
        return (
            text + ": the compliant models use Thornton's elastic–plastic law (normal='thornton')."
        )
    if float(scene.e) == 1.0:
        return text + ": e = 1 cannot hold past it; give the scene's e and fit normal='thornton'."
    return (
        text + f": Thornton's elastic–plastic law (normal='thornton') describes it, not {normal!r}."
    )


def _reason(scene, rung, worst, errors, tol, rig, psi1, chi) -> str:
    e = float(scene.e)
    crit = 2.0 * chi * (1.0 + e)
    if float(scene.mu) == 0 or rig.slip0 == 0:
        where = "no friction impulse (μ = 0 or no initial slip): Pt = 0 in every model"
    elif rig.regime == "sliding" and rung == "rigid":
        where = (
            f"sliding throughout (ψ1 = {psi1:.3g} ≥ 2χ(1+e) = {crit:.3g}): Ft = μ·Fn at every "
            "instant in every model"
        )
    elif rig.regime == "sliding":
        where = (
            f"rigid theory slides throughout (ψ1 = {psi1:.3g} ≥ 2χ(1+e) = {crit:.3g}) but the "
            "compliant contact does not slide from its first instant (the normal damping "
            "raises the Coulomb cap above the Mindlin spring)"
        )
    else:
        where = (
            f"sticking (ψ1 = {psi1:.3g} < 2χ(1+e) = {crit:.3g}): tangential compliance shapes "
            "Pt(Pn) after the slip stops"
        )
    if rung == "rigid":
        return f"{where}: rigid Coulomb is exact to {worst('rigid'):.1g} (tol {tol:g})"
    if rung == "coulomb":
        missing = [q for q in errors if np.isinf(errors[q]["rigid"])]
        why = (
            f"{', '.join(missing)} needs time, which the rigid model lacks"
            if missing
            else f"the rigid model is off by {worst('rigid'):.2g}"
        )
        return (
            f"{where}: {why}; Coulomb friction on the compliant normal law is exact to "
            f"{worst('coulomb'):.1g} (tol {tol:g})"
        )
    off = max(
        ((q, errors[q]["coulomb"]) for q in errors if np.isfinite(errors[q]["coulomb"])),
        key=lambda kv: kv[1],
        default=("e_t", float("nan")),
    )
    return (
        f"{where}: without tangential compliance {off[0]} is off by {off[1]:.2g} > tol {tol:g}; "
        "Mindlin's tangential compliance is needed"
    )
