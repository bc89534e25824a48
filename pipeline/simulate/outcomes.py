"""Outcomes of many impacts at once: :func:`impact_outcomes` → :class:`ImpactOutcomes`.

The front end of the batch path (see :mod:`pipeline.simulate`): scenes grouped by normal
law, each group integrated by the vectorised fixed-step integrator of
:mod:`pipeline.simulate.batch` or, with ``method="table"``, looked up in the outcome tables
of :mod:`pipeline.simulate.table` (built by that same integrator once per law, cached on
disk) with integration as the fallback where a table cannot answer within its bound."""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from .. import contact
from ..errors import InputError, PipelineWarning
from ..scene import Scene
from ._common import (
    _check_kt_scale,
    _check_models,
    _check_tangential_damping,
    _check_target,
    _law,
    _param,
)
from .batch import _batch_group, _calibrate_many
from .table import tabulated

__all__ = ["ImpactOutcomes", "impact_outcomes"]


@dataclass(frozen=True)
class ImpactOutcomes:
    """Outcomes of many impacts (arrays shaped like the scenes).

    Attributes
    ----------
    e_n : normal restitution [-]
    e_t : tangential velocity of the centre after / before [-] (NaN when v_t0 = 0)
    omega : spin after impact [rad/s], > 0 in the sense Pt > 0 produces
    t_contact : contact duration [s]
    F_max : peak normal force [N]
    delta_max : maximum approach [m]
    Pn_final, Pt_final : normal and tangential percussion at separation [N·s]
    Ft_reverses : bool — the tangential force changed sign during contact
    friction_ratio_max : largest |Ft|/(μ·Fn) at the step ends in contact (Mindlin; NaN for
        the other models): ≤ 1 up to rounding where Coulomb's law holds
    normal : law name per scene; tangential, history : model names; n_steps : RK4 steps
    per elastic contact duration
    """

    e_n: np.ndarray
    e_t: np.ndarray
    omega: np.ndarray
    t_contact: np.ndarray
    F_max: np.ndarray
    delta_max: np.ndarray
    Pn_final: np.ndarray
    Pt_final: np.ndarray
    Ft_reverses: np.ndarray
    friction_ratio_max: np.ndarray
    normal: np.ndarray
    tangential: str
    history: str
    n_steps: int

    _UNITS = {
        "e_n": "1",
        "e_t": "1",
        "omega": "rad/s",
        "t_contact": "s",
        "F_max": "N",
        "delta_max": "m",
        "Pn_final": "N s",
        "Pt_final": "N s",
        "Ft_reverses": "1",
        "friction_ratio_max": "1",
    }

    def to_dataset(self):
        """The outcomes as an :class:`xarray.Dataset` on dimension ``scene`` (flattened)."""
        import xarray as xr

        data = {
            k: ("scene", np.ravel(getattr(self, k)), {"units": u}) for k, u in self._UNITS.items()
        }
        data["normal"] = ("scene", np.ravel(self.normal).astype(str))
        return xr.Dataset(
            data,
            attrs={
                "tangential_model": self.tangential,
                "history_rule": self.history,
                "n_steps": self.n_steps,
                "generator": "pipeline.simulate.impact_outcomes",
            },
        )


def _stack_scenes(scenes):
    if isinstance(scenes, Scene):
        return scenes
    scenes = list(scenes)
    if not scenes or not all(isinstance(s, Scene) for s in scenes):
        raise InputError("impact_outcomes() needs a Scene (array fields) or a list of Scenes")
    fields = {}
    for name in Scene.field_names():
        if name in ("density", "mass"):
            continue
        vals = [getattr(s, name) for s in scenes]
        if any(v is None for v in vals):
            if all(v is None for v in vals):
                fields[name] = None  # unknown for every scene (not the field's default)
                continue
            raise InputError(f"Scene.{name} is given for some scenes but not others")
        fields[name] = np.array(vals, dtype=float)
    fields["mass"] = np.array([float(s.m) for s in scenes])
    return Scene(**fields)


def impact_outcomes(
    scenes,
    normal=None,
    tangential="mindlin",
    *,
    history="total",
    n_steps=400,
    alpha=None,
    param=None,
    target_kappa=None,
    tangential_damping=0.0,
    kt_scale=1.0,
    method="rk4",
) -> ImpactOutcomes:
    """Outcomes of many oblique impacts at once (vectorised, no per-scene loop).

    Parameters
    ----------
    scenes : Scene or sequence of Scene
        A Scene whose fields are arrays (broadcast together) or a list of scalar Scenes.
    normal : str, optional
        Normal law for all scenes; default per scene ``"hertz"`` if e == 1 else
        ``"hunt_crossley"``.
    tangential : {"mindlin", "coulomb", "none"}
    history : {"total", "incremental"}
        Mindlin history rule.
    n_steps : int
        RK4 steps per elastic contact duration (t_c = 2.943·t*); damped contacts, which
        last longer, take proportionally more.
    alpha, param, target_kappa, tangential_damping, kt_scale
        As in :func:`impact`.
    method : {"rk4", "table"}
        ``"rk4"`` (default): integrate every scene. ``"table"``: Mindlin outcomes from
        :mod:`pipeline.simulate.table` — a table of the dimensionless tangential problem
        per normal law, damping, history rule, tangential damping and stiffness group,
        built once (~1–3 s) and cached, interpolated within its stated error (Γ to 1e-4,
        |Δe_t| ≤ 1e-4·m_t/m* plus the 800-step RK4 error behind it) at well under 1 µs per
        impact; scenes outside it are integrated. ``Ft_reverses`` is then the nearest
        node's, and ``friction_ratio_max`` NaN (not tracked).

    Returns
    -------
    ImpactOutcomes

    Notes
    -----
    Every scene is integrated in its own dimensionless time τ = t·v_n0/δ_max with the same
    step, so the loop runs over time steps only. For the elastic Hertz law the normal
    problem is one universal function of τ (:func:`pipeline.contact.hertz_pulse`, exact),
    so only the tangential state (Pt, ξ or Ft) is integrated, by RK4 with the Coulomb cap
    applied inside the stages and the discrete history rule
    (:func:`pipeline.contact.mindlin_total` / :func:`~pipeline.contact.mindlin_incremental`)
    after each step: the LAMMPS/YADE update with an RK4 predictor. In these variables the
    tangential problem depends only on s0/(μ·v_n0), m*/m_t and G*/E* (the groups of Maw,
    Barber & Fawcett 1976). Coulomb friction needs no integration: Pt = min(μ·Pn,
    m_t·s0) exactly.

    Stated error (against :func:`impact` at rtol 1e-13; ``benchmarks/bench_simulate.py``):
    at the default n_steps = 400, for the elastic Hertz and Hunt–Crossley-family laws,
    |Δe_t| < 2e-5 (total rule ≈ 2e-6), |Δe_n| < 1e-6, relative F_max and t_contact < 1e-5;
    e_t errors fall roughly as n_steps⁻² (total rule) and n_steps⁻¹·⁵ (incremental: the
    stick/slip kinks). The error is one of Pt (|ΔPt| ≲ 2e-5·m*·v_n0 on those scenes; up to
    ~5e-5·m*·v_n0 for the incremental rule with heavy damping, e ≈ 0.2, and μ ≈ 1, where the
    longer contact holds more stick/slip switches); e_t = 1 − Pt/(m*·v_t0)
    magnifies it where v_t0 ≪ v_n0 or the initial slip is mostly spin. Laws whose damping
    grows as δ^{1/4} at first contact (linear dashpot on Hertz, viscoelastic) are not
    smooth there and converge more slowly: at n_steps = 400 and e ≥ 0.05,
    |Δe_n|, |Δe_t| < 1e-4, relative t_contact < 5e-4 and F_max < 1e-3 (the peak force of
    a heavily damped dashpot comes right after first contact). With a tangential dashpot
    (x_γ,t = 1, Tsuji dashpot at e = 0.98, Chung & Ooi test 4, 1–89°): |Δe_t| ≤ 3.1e-5 at
    n_steps = 400, 1e-6 at 1600.
    Scenes whose damping is too stiff for the explicit fixed step (e.g. an absurd material
    constant) come back as NaN with a :class:`~pipeline.errors.PipelineWarning`.
    """
    _check_models(tangential, history)
    xg = _check_tangential_damping(tangential_damping, tangential)
    if method not in ("rk4", "table"):
        raise InputError(f"method must be 'rk4' or 'table'; got {method!r}")
    if int(n_steps) < 4:
        raise InputError("n_steps must be at least 4")
    n_steps = int(n_steps)
    sc = _stack_scenes(scenes)
    _check_target(sc)
    sc.require(*(("mu",) if tangential != "none" else ()), why=f"the {tangential!r} model")
    if param is None and alpha is None or normal is None:
        sc.require("e", why="calibrating the normal law's damping")
    hi = contact.hertz_impact(sc)
    arrs = np.broadcast_arrays(
        *(
            np.asarray(a, dtype=float)
            for a in (
                hi.delta_max,
                hi.K,
                hi.m_eff,
                hi.v0,
                sc.m,
                sc.target_mass,
                sc.kappa,
                sc.radius,
                sc.target_radius,
                sc.v_t0,
                sc.spin,
                0.0 if sc.mu is None else sc.mu,  # None: a frictionless model
                np.nan if sc.e is None else sc.e,  # None: damping given by param/alpha
                sc.G_eff,
                sc.R_eff,
            )
        )
    )
    shape = arrs[0].shape
    (dstar, K, m_eff, v0, m1, m2, k1, R1, R2, vt0, spin, mu, e, G, Rs) = (
        a.ravel().copy() for a in arrs
    )
    k2 = (
        k1
        if target_kappa is None
        else np.broadcast_to(np.asarray(target_kappa, dtype=float), shape).ravel()
    )
    with np.errstate(divide="ignore"):
        inv_m2 = np.where(np.isinf(m2), 0.0, 1.0 / m2)
    lam = m_eff * ((1 + 1 / k1) / m1 + (1 + 1 / k2) * inv_m2)
    slip0 = vt0 - spin * R1
    sign = np.where(slip0 < 0, -1.0, 1.0)
    s0 = np.abs(slip0) / v0
    ktc = _check_kt_scale(kt_scale) * 8.0 * G * np.sqrt(Rs * dstar) * dstar**2 / (m_eff * v0**2)
    if normal is None:
        names = np.where(e == 1.0, "hertz", "hunt_crossley")
    else:
        _law(normal)
        names = np.full(e.shape, normal, dtype=object)
    names = names.astype(object)
    if normal == "hertz" and np.any(e < 1):
        raise InputError("the elastic 'hertz' law cannot give e < 1; choose a damped law")
    out = {k: np.empty(e.size) for k in ("e_n", "p", "tau_c", "f_max", "x_max")}
    out["reverses"] = np.zeros(e.size, dtype=bool)
    out["ratio"] = np.full(e.size, np.nan)
    for name in sorted(set(names)):
        law = _law(name)
        idx = np.nonzero(names == name)[0]
        elastic = name == "hertz"
        if param is not None:
            prm = np.broadcast_to(np.asarray(param, dtype=float), shape).ravel()[idx]
        elif alpha is not None:
            prm = np.asarray(
                _param(
                    law,
                    None,
                    K[idx],
                    m_eff[idx],
                    v0[idx],
                    alpha=np.broadcast_to(alpha, shape).ravel()[idx],
                )
            )
        else:
            prm = _calibrate_many(law, e[idx])
        if method == "table" and tangential == "mindlin":
            found, res = tabulated(name, prm, s0[idx], lam[idx], mu[idx], ktc[idx], xg, history)
            for k in out:
                out[k][idx[found]] = res[k]
            idx, prm = idx[~found], prm[~found]  # the rest is integrated
            if idx.size == 0:
                continue
        res = _batch_group(
            law,
            elastic,
            prm,
            s0[idx],
            lam[idx],
            mu[idx],
            ktc[idx],
            xg,
            tangential,
            history,
            n_steps,
        )
        for k in out:
            out[k][idx] = res[k]
    # an explicit fixed step cannot follow a contact whose damping is too stiff for it:
    # such outcomes are unphysical (e_n outside [0, 1], non-finite) — flag, never return them
    bad = ~np.isfinite(out["e_n"]) | (out["e_n"] > 1 + 1e-6) | (out["e_n"] < 0)
    bad |= ~np.isfinite(out["p"]) | ~np.isfinite(out["tau_c"])
    if np.any(bad):
        warnings.warn(
            f"impact_outcomes: {int(bad.sum())} of {bad.size} scenes are too stiffly damped "
            f"for n_steps = {n_steps} (explicit RK4 unstable); their outcomes are NaN. "
            "Raise n_steps or use impact() for them.",
            PipelineWarning,
            stacklevel=2,
        )
        for k in ("e_n", "p", "tau_c", "f_max", "x_max"):
            out[k] = np.where(bad, np.nan, out[k])
    tstar = dstar / v0
    Pt = out["p"] * m_eff * v0
    vt0s = sign * vt0
    with np.errstate(divide="ignore", invalid="ignore"):
        e_t = np.where(vt0s != 0, (vt0s - out["p"] * v0) / np.where(vt0s != 0, vt0s, 1.0), np.nan)
    omega = sign * spin + Pt / (k1 * m1 * R1)

    def r(a):
        return np.asarray(a).reshape(shape)

    return ImpactOutcomes(
        e_n=r(out["e_n"]),
        e_t=r(e_t),
        omega=r(omega),
        t_contact=r(out["tau_c"] * tstar),
        F_max=r(out["f_max"] * m_eff * v0**2 / dstar),
        delta_max=r(out["x_max"] * dstar),
        Pn_final=r((1 + out["e_n"]) * m_eff * v0),
        Pt_final=r(Pt),
        Ft_reverses=r(out["reverses"]),
        friction_ratio_max=r(out["ratio"]),
        normal=r(names),
        tangential=tangential,
        history=history,
        n_steps=n_steps,
    )
