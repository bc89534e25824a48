r"""Fit friction, restitution and tangential compliance to rebound kinematics.

Many laboratories measure only what a camera sees — the tangential restitution of the
centre e_t, the spin ω after impact, the rebound angle, the normal restitution e_n —
against the incidence angle θ (from the normal), not forces. :func:`fit_outcomes` fits
three models to such a table:

``"rigid"`` (μ, e)
    Routh's rigid sphere with Coulomb friction (docs/theory.md): the contact point slides
    and, if its slip reaches zero, rolls.
``"walton"`` (μ, e, β0)
    Walton's three-parameter rigid model (Walton 1993; measured by Foerster et al. 1994).
    The restitution of the contact point's tangential velocity,
    β = −s_after/s_before ∈ [−1, 1], is that of sliding friction until it reaches β0:

    .. math:: \beta = \min\left[\beta_0,\; -1 + \mu(1 + e)\left(1 + \tfrac1\kappa\right)
              \frac{v_{n0}}{s_0}\right],

    so the slip may reverse (β0 > 0), which a rigid body cannot do and a compliant contact
    does. β0 = 0 is Routh's model.
``"hertz_mindlin"`` (μ, e, kt_scale)
    Hertz normal contact (Hunt–Crossley damping calibrated to e), Mindlin tangential spring
    k_t = kt_scale·8·G*·a with Coulomb cap (total-displacement rule), by the batch path of
    :func:`pipeline.simulate.impact_outcomes` on the table's rows — no ODE per residual.

Each column is weighted by its 1-σ uncertainty (``<column>_err``); a column given without
one has its σ estimated from its own residual scatter (stated in ``notes``). lmfit's
``Minimizer`` drives the least squares.

Outcomes, for a sphere with slip s0 = v_t0 − ω0·R at first contact (v_t0 = v·sin θ − u
relative to a surface moving at u) and Pt the tangential percussion against it, σ the
sign of s0: e_t = 1 − σ·Pt/(m·v_t0), ω = σ·ω0 + Pt·R/I on the slip's axis (as
:func:`pipeline.analyse` and :func:`pipeline.simulate.impact` give it), rebound angle of
the centre atan(e_t·v_t0/(e_n·v_n0)) (degrees from the normal, on the scene's axis).

References
----------
O. R. Walton, Mech. Mater. 16:239 (1993), doi:10.1016/0167-6636(93)90048-V.
S. F. Foerster, M. Y. Louge, H. Chang, K. Allia, Phys. Fluids 6:1108 (1994),
doi:10.1063/1.868282.
N. Maw, J. R. Barber, J. N. Fawcett, Wear 38:101 (1976), doi:10.1016/0043-1648(76)90201-7.
A. H. Kharaz, D. A. Gorham, A. D. Salman, Powder Technol. 120:281 (2001),
doi:10.1016/S0032-5910(01)00283-2.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from .._json import json_ready
from ..errors import InputError, PoorFitWarning
from ..scene import Scene
from ..simulate import impact_outcomes

__all__ = ["OutcomeFit", "fit_outcomes", "OUTCOME_MODELS", "OUTCOME_COLUMNS"]

#: the parameters of each model, in order
OUTCOME_MODELS = {
    "rigid": ("mu", "e"),
    "walton": ("mu", "e", "beta0"),
    "hertz_mindlin": ("mu", "e", "kt_scale"),
}
#: the kinematic columns a table may hold, with their units
OUTCOME_COLUMNS = {"e_t": "1", "omega": "rad/s", "rebound_deg": "deg", "e_n": "1"}
_BOUNDS = {"mu": (0.0, 5.0), "e": (0.01, 1.0), "beta0": (-1.0, 1.0), "kt_scale": (0.02, 20.0)}
_START = {"mu": 0.2, "e": 0.9, "beta0": 0.3, "kt_scale": 1.0}


@dataclass(frozen=True)
class OutcomeFit:
    """The result of :func:`fit_outcomes` (the interface of the contact fits).

    Attributes
    ----------
    model : str
    values : dict — fitted (and fixed) parameters
    stderr : dict — 1-σ standard errors (NaN where fixed or not estimable)
    identifiable : dict — False where the data bound a parameter on one side only, or not
        at all (then ``notes`` says why)
    notes : list of str
    aic, bic, redchi : float
    params : lmfit.Parameters; result : lmfit.MinimizerResult
    data : pandas.DataFrame — the table that was fitted
    scene : Scene
    columns : tuple — the kinematic columns fitted
    sigma : dict — the (median) 1-σ used per column
    bounds : dict — {name: (lo, hi)} for the parameters the data bound on one side only
    """

    model: str
    values: dict
    stderr: dict
    identifiable: dict
    notes: list
    aic: float
    bic: float
    redchi: float
    params: object
    result: object
    data: object
    scene: Scene
    columns: tuple
    sigma: dict = field(default_factory=dict)
    bounds: dict = field(default_factory=dict)

    def ci(self, level=0.95):
        """{name: (lo, hi)} from the covariance (normal quantile); a parameter the data
        bound on one side only has ±inf on the open side; fixed ones are (v, v)."""
        from scipy.stats import norm

        z = float(norm.ppf(0.5 + level / 2.0))
        out = {}
        for k, v in self.values.items():
            s = self.stderr.get(k, math.nan)
            if not self.params[k].vary:
                out[k] = (v, v)
            elif not self.identifiable.get(k, True):
                out[k] = self.bounds.get(k, (-math.inf, math.inf))
            elif math.isfinite(s):
                out[k] = (v - z * s, v + z * s)
            else:
                out[k] = (-math.inf, math.inf)
        return out

    def table(self, level: float = 0.95, *, style: bool = False):
        """The fit for a person to read (as :meth:`pipeline.fit.result.FitResult.table`):
        each parameter rounded to its standard error (PDG), a bound where the data bound it
        on one side only, ``"fixed"`` where it was not fitted; the fit in words in
        ``attrs["verdict"]``, the notes in ``attrs["details"]``."""
        from .. import precision

        ci = self.ci(level)
        rows = []
        for k, v in self.values.items():
            row = {"name": k, "value": v, "stderr": self.stderr.get(k, math.nan), "ci": ci[k]}
            if not self.params[k].vary:
                row["status"] = "fixed"
            elif not self.identifiable.get(k, True) and k in self.bounds:
                lo, hi = self.bounds[k]
                lower = math.isinf(hi) or hi >= _BOUNDS.get(k, (0.0, math.inf))[1]
                row.update(status="lower" if lower else "upper", value=lo if lower else hi)
            elif not self.identifiable.get(k, True):
                row["stderr"] = math.nan
            rows.append(row)
        verdict = (
            f"Rebound outcomes ({', '.join(self.columns)}) of {len(self.data)} impacts fitted "
            f"by the {self.model!r} model: χ²_ν = {self.redchi:.3g}."
        )
        df = precision.parameter_table(rows, verdict=verdict, details=self.notes, level=level)
        return precision.styled(df) if style else df

    def predict(self, angle_deg, speed=None):
        """The model's outcomes at incidences ``angle_deg`` [deg] (dict of arrays)."""
        return _predict(self.model, self.values, self.scene, np.asarray(angle_deg, float), speed)

    def report(self) -> str:
        """lmfit's fit report plus what the parameters imply."""
        import lmfit

        lines = [
            f"fit_outcomes: model {self.model!r} on {len(self.data)} rows "
            f"({', '.join(self.columns)})",
            lmfit.fit_report(self.result),
            "",
            "[[Implied]]",
        ]
        for k, v in self.values.items():
            lo, hi = self.ci(0.95)[k]
            flag = "" if self.identifiable.get(k, True) else "  (not identifiable)"
            lines.append(f"    {k:9s} = {v:.6g}   95% [{lo:.6g}, {hi:.6g}]{flag}")
        theta_c = _critical_angle(self.values, self.scene)
        if math.isfinite(theta_c):
            lines.append(f"    rigid sliding throughout above θ = {theta_c:.2f}° (Routh)")
        lines += [f"    note: {n}" for n in self.notes]
        return "\n".join(lines)

    def summary(self) -> dict:
        """Strict-JSON summary."""
        return json_ready(
            {
                "model": self.model,
                "values": self.values,
                "stderr": self.stderr,
                "ci95": {k: list(v) for k, v in self.ci(0.95).items()},
                "identifiable": self.identifiable,
                "notes": list(self.notes),
                "aic": self.aic,
                "bic": self.bic,
                "redchi": self.redchi,
                "n_rows": len(self.data),
                "columns": list(self.columns),
                "sigma_used": self.sigma,
            }
        )

    def to_dataset(self):
        """xarray.Dataset on dimension ``row``: angle, and per column measured, model and
        residual (measured − model), with units."""
        import xarray as xr

        angle = self.data["angle_deg"].to_numpy(float)
        speed = self.data["speed"].to_numpy(float) if "speed" in self.data else None
        pred = _predict(self.model, self.values, self.scene, angle, speed)
        data = {"angle_deg": ("row", angle, {"units": "deg"})}
        for c in self.columns:
            meas = self.data[c].to_numpy(float)
            u = OUTCOME_COLUMNS[c]
            data[c] = ("row", meas, {"units": u, "long_name": f"measured {c}"})
            data[f"{c}_model"] = ("row", pred[c], {"units": u})
            data[f"{c}_residual"] = ("row", meas - pred[c], {"units": u})
        return xr.Dataset(
            data,
            attrs={
                "model": self.model,
                "generator": "pipeline.fit_outcomes",
                **{f"fit_{k}": float(v) for k, v in self.values.items()},
            },
        )


def _walton_pt(theta, speed, mu, e, beta0, scene):
    """Tangential percussion Pt/m [m/s] of Walton's model (β0 = 0: Routh), on the scene's
    axis (against the initial slip s0 = v_t0 − ω0·R, so of the sign of s0)."""
    vn = speed * np.cos(theta)
    vt = speed * np.sin(theta) - float(scene.surface_speed)
    s0 = vt - float(scene.spin) * float(scene.radius)
    kap = float(scene.kappa)
    with np.errstate(divide="ignore", invalid="ignore"):
        beta_slide = -1.0 + mu * (1.0 + e) * (1.0 + 1.0 / kap) * vn / np.abs(s0)
    beta = np.minimum(beta0, beta_slide)
    return np.sign(s0) * (1.0 + beta) * np.abs(s0) * kap / (1.0 + kap)


def _predict(model, values, scene, angle_deg, speed=None):
    theta = np.radians(np.asarray(angle_deg, dtype=float))
    v = np.full(theta.shape, float(scene.speed)) if speed is None else np.asarray(speed, float)
    mu, e = values["mu"], values["e"]
    m, R, kap = float(scene.m), float(scene.radius), float(scene.kappa)
    vt0 = v * np.sin(theta) - float(scene.surface_speed)  # relative to the surface
    # the initial slip's sign: Pt opposes it, and ω is counted on its axis (docs/theory.md)
    sign = np.where(vt0 - float(scene.spin) * R < 0, -1.0, 1.0)
    if model in ("rigid", "walton"):
        pt_m = _walton_pt(theta, v, mu, e, values.get("beta0", 0.0), scene)
        e_n = np.full(theta.shape, e)
    else:
        sc = scene.replace(angle_deg=np.degrees(theta), speed=v, mu=mu, e=e)
        out = impact_outcomes(sc, normal=_NORMAL, kt_scale=values["kt_scale"], n_steps=_STEPS)
        pt_m = sign * out.Pt_final / m  # Pt_final is on the slip's axis
        e_n = out.e_n
    with np.errstate(divide="ignore", invalid="ignore"):
        e_t = 1.0 - pt_m / vt0
    omega = sign * (float(scene.spin) + pt_m / (kap * R))
    rebound = np.degrees(np.arctan2(e_t * vt0, e_n * v * np.cos(theta)))
    return {"e_t": e_t, "omega": omega, "rebound_deg": rebound, "e_n": e_n}


_NORMAL = "hunt_crossley"
_STEPS = 200  # batch RK4 steps: |Δe_t| ~ 1e-4, well under measured scatter (~1e-2)


def _critical_angle(values, scene):
    """Incidence above which Routh's rigid sphere slides throughout [deg]."""
    kap = float(scene.kappa)
    t = values["mu"] * (1.0 + values["e"]) * (1.0 + 1.0 / kap)
    still = scene.spin == 0 and scene.surface_speed == 0  # else it depends on the speed
    return math.degrees(math.atan(t)) if still else math.nan


def _read_table(table):
    import pandas as pd

    if not isinstance(table, pd.DataFrame):
        raise InputError("fit_outcomes needs a pandas DataFrame (columns angle_deg, e_t, ...)")
    if "angle_deg" not in table:
        raise InputError("the table needs a column 'angle_deg' (incidence from the normal, deg)")
    columns = tuple(c for c in OUTCOME_COLUMNS if c in table)
    if not columns:
        raise InputError(
            "the table needs at least one of the columns " + ", ".join(OUTCOME_COLUMNS)
        )
    for c in ("angle_deg", *columns, *(f"{c}_err" for c in columns if f"{c}_err" in table)):
        vals = pd.to_numeric(table[c], errors="coerce").to_numpy(float)
        bad = ~np.isfinite(vals)
        if np.any(bad):
            row = int(np.nonzero(bad)[0][0])
            raise InputError(f"not a finite number in row {row}", column=c)
        if c.endswith("_err") and np.any(vals <= 0):
            raise InputError("uncertainties must be > 0", column=c)
    ang = table["angle_deg"].to_numpy(float)
    if np.any((ang <= 0) | (ang >= 90)):
        raise InputError("incidence angles must lie in (0, 90) degrees", column="angle_deg")
    return table.reset_index(drop=True), columns


def fit_outcomes(table, scene: Scene, *, model="hertz_mindlin", vary=None) -> OutcomeFit:
    """Fit μ, e and a tangential parameter to a table of rebound kinematics.

    Parameters
    ----------
    table : pandas.DataFrame
        ``angle_deg`` [deg] (incidence from the normal) and at least one of ``e_t`` [-],
        ``omega`` [rad/s] (positive in the sense friction spins the ball up),
        ``rebound_deg`` [deg] (centre, from the normal), ``e_n`` [-]; optionally ``speed``
        [m/s] per row and ``<column>_err``, 1-σ uncertainties.
    scene : Scene
        The ball (radius, mass, kappa, E, nu), target, speed (unless per row) and spin;
        its ``mu`` and ``e`` start the fit, and ``e`` is held there when the table has no
        ``e_n`` and ``vary`` does not name it (e_t alone sets μ(1 + e), not both).
    model : {"hertz_mindlin", "walton", "rigid"}
    vary : sequence of str, optional
        The parameters to fit (default: the model's, less ``e`` as said above).

    Returns
    -------
    OutcomeFit

    Raises
    ------
    InputError
        An unknown model or parameter, a table without the columns, a non-finite entry.
    """
    import lmfit

    if model not in OUTCOME_MODELS:
        raise InputError(f"unknown outcome model {model!r}; choose one of {list(OUTCOME_MODELS)}")
    data, columns = _read_table(table)
    names = OUTCOME_MODELS[model]
    notes = []
    if vary is None:
        vary = list(names)
        if "e_n" not in columns and scene.e is not None:
            vary.remove("e")
            notes.append(f"e fixed at the scene's {scene.e:g}: the table has no e_n column")
    unknown = set(vary) - set(names)
    if unknown:
        raise InputError(f"model {model!r} has no parameter(s) {sorted(unknown)}; it has {names}")
    if model == "hertz_mindlin" and (scene.E is None or scene.nu is None):
        raise InputError("the hertz_mindlin model needs the scene's E and nu")
    params = lmfit.Parameters()
    start = {"mu": scene.mu, "e": scene.e}
    for k in names:
        v0 = start.get(k)
        v0 = _START[k] if v0 is None else float(v0)
        lo, hi = _BOUNDS[k]
        params.add(k, value=float(np.clip(v0, lo, hi)), min=lo, max=hi, vary=k in vary)
    angle = data["angle_deg"].to_numpy(float)
    speed = data["speed"].to_numpy(float) if "speed" in data else None
    meas = {c: data[c].to_numpy(float) for c in columns}
    given = {c: data[f"{c}_err"].to_numpy(float) for c in columns if f"{c}_err" in data}
    sigma = {c: given.get(c, np.full(len(data), _DEFAULT_SIGMA[c])) for c in columns}

    def residual(p):
        vals = p.valuesdict()
        pred = _predict(model, vals, scene, angle, speed)
        return np.concatenate([(pred[c] - meas[c]) / sigma[c] for c in columns])

    def run(prms):
        return lmfit.Minimizer(residual, prms, scale_covar=False, nan_policy="raise").minimize(
            method="leastsq"
        )

    _start_from_grid(model, params, residual)
    result = run(params)
    estimated = [c for c in columns if c not in given]
    for _ in range(3 if estimated else 0):  # σ of the columns given without one
        pred = _predict(model, result.params.valuesdict(), scene, angle, speed)
        dof = max(len(data) - sum(p.vary for p in params.values()) / len(columns), 1.0)
        for c in estimated:
            rms = math.sqrt(float(np.sum((pred[c] - meas[c]) ** 2)) / dof)
            sigma[c] = np.full(len(data), max(rms, 1e-12 * _DEFAULT_SIGMA[c]))
        result = run(result.params)
    if estimated:
        notes.append(
            "no uncertainties for "
            + ", ".join(estimated)
            + ": each column's σ estimated from its residual scatter (reduced χ² ≈ 1 then "
            "says nothing about the fit's quality)"
        )
    values = {k: float(result.params[k].value) for k in names}
    stderr = {
        k: float(result.params[k].stderr)
        if result.params[k].vary and result.params[k].stderr is not None
        else math.nan
        for k in names
    }
    identifiable, bounds = _identifiability(model, values, stderr, result, scene, angle, notes)
    if not result.success or (not estimated and result.redchi > 4.0):
        warnings.warn(
            f"fit_outcomes ({model}): "
            + (result.message if not result.success else f"reduced chi2 = {result.redchi:.3g}")
            + "; the model does not describe these data within their uncertainties",
            PoorFitWarning,
            stacklevel=2,
        )
        notes.append("poor fit: " + (result.message if not result.success else "reduced χ² > 4"))
    return OutcomeFit(
        model=model,
        values=values,
        stderr=stderr,
        identifiable=identifiable,
        notes=notes,
        aic=float(result.aic),
        bic=float(result.bic),
        redchi=float(result.redchi),
        params=result.params,
        result=result,
        data=data,
        scene=scene,
        columns=columns,
        sigma={c: float(np.median(sigma[c])) for c in columns},
        bounds=bounds,
    )


def _start_from_grid(model, params, residual):
    """Start μ (and β0) at the best point of a coarse grid: the rigid models' min() kinks
    leave a least-squares start in the sticking regime without a gradient in μ. For
    Hertz–Mindlin the grid runs on μ alone (a few batch evaluations)."""
    grids = {"mu": np.geomspace(0.01, 2.0, 25 if model != "hertz_mindlin" else 9)}
    if model == "walton":
        grids["beta0"] = np.linspace(-0.9, 0.9, 13)
    names = [k for k in grids if params[k].vary]
    if not names:
        return
    trial = params.copy()
    with np.errstate(all="ignore"):
        start_ss = float(np.sum(residual(trial) ** 2))
    best, best_ss = [params[k].value for k in names], start_ss * (1.0 - 1e-9)
    for point in np.stack(np.meshgrid(*(grids[k] for k in names)), -1).reshape(-1, len(names)):
        for k, v in zip(names, point, strict=True):
            trial[k].value = float(v)
        with np.errstate(all="ignore"):
            ss = float(np.sum(residual(trial) ** 2))
        if ss < best_ss:
            best, best_ss = point, ss
    for k, v in zip(names, best, strict=True):
        params[k].value = float(v)


#: start values of the σ of a column without uncertainties (replaced by its scatter)
_DEFAULT_SIGMA = {"e_t": 0.01, "omega": 10.0, "rebound_deg": 0.5, "e_n": 0.01}


def _identifiability(model, values, stderr, result, scene, angle, notes):
    """Which parameters the data pin down; one-sided bounds where they do not."""
    ident = {k: bool(result.params[k].vary and math.isfinite(stderr[k])) for k in values}
    bounds = {}
    theta_c = _critical_angle(values, scene)
    if model in ("rigid", "walton") and math.isfinite(theta_c):
        kap = float(scene.kappa)
        tan_max = math.tan(math.radians(float(np.max(angle))))
        if theta_c >= float(np.max(angle)) and result.params["mu"].vary:
            # every row sticks (rigid) or has reached β0: μ only has a lower bound
            lo = tan_max / ((1.0 + values["e"]) * (1.0 + 1.0 / kap))
            ident["mu"] = False
            bounds["mu"] = (lo, math.inf)
            notes.append(
                f"mu: every row is in the sticking regime of the model, so the data give "
                f"only mu >= {lo:.4g}"
            )
        if model == "walton" and result.params["beta0"].vary:
            beta_slide_min = -1.0 + values["mu"] * (1.0 + values["e"]) * (
                1.0 + 1.0 / kap
            ) / math.tan(math.radians(float(np.min(angle))))
            if beta_slide_min <= values["beta0"]:
                ident["beta0"] = False
                bounds["beta0"] = (beta_slide_min, 1.0)
                notes.append(
                    f"beta0: every row slides, so the data give only beta0 >= {beta_slide_min:.4g}"
                )
    for k, ok in ident.items():
        if result.params[k].vary and not ok and k not in bounds:
            notes.append(f"{k}: no standard error (at a bound or not constrained by the data)")
    return ident, bounds
