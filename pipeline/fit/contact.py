r"""Fit the contact parameters of one record: :func:`fit_contact` → :class:`ContactFit`.

The model (:mod:`pipeline.fit.forward`) is the simulator's — a normal law of
:data:`pipeline.contact.NORMAL_LAWS`, a tangential model (``"none"``, ``"coulomb"``,
``"mindlin"`` with its history rule) — seen through the record's sensor, and its
parameters are

======== ====== ==============================================================
name     unit   meaning
======== ====== ==============================================================
E_eff    Pa     effective modulus E* (G* follows at the scene's G*/E*)
e        1      normal restitution (the damping calibrated to it; ``alpha`` [s/m]
                instead for the Hunt–Crossley family: c = α·v0)
mu       1      Coulomb friction coefficient
kt_scale 1      tangential stiffness over Mindlin's 8·G*·a
speed    m/s    impact speed
t0       s      instant of first contact on the record's clock
======== ====== ==============================================================

Thornton's elastic–perfectly-plastic law (``normal="thornton"``) is fitted through the
same e — its yield pressure and e are one-to-one at a given E*, speed and ball
(:func:`pipeline.contact.calibrate_thornton`) — and the fit reports both: ``p_y`` [Pa],
the yield pressure, and ``v_y`` [m/s], the yield speed, in ``values``, ``stderr`` and
``ci()`` beside the fitted parameters. Their intervals map e's interval (with its
systematics and model spread) through the closed form, which is steep near e = 1 (an
upper end at e = 1 leaves only a lower bound: the contact may not have yielded), and add
in quadrature what E*, the speed, mass and radius move them by (their covariance,
propagated linearly).

Both force channels are fitted jointly, each sample weighted by 1/σ of its channel's noise
(measured outside the contact), on all the samples with each channel's residual baseline
fitted alongside (:mod:`pipeline.fit.forward`). lmfit's
Levenberg–Marquardt drives the minimisation with the Jacobian of
:mod:`pipeline.fit.engine` (one vectorised model call per iteration); uncertainties come
from the covariance and a block bootstrap, and parameters the data bound on one side only
are reported as such (:mod:`pipeline.fit.uncertainty`).

Choices, and why:

- **Default parameters** vary E*, e, μ, ``kt_scale`` (Mindlin only) and t0; the speed
  comes from the scene (a rig measures it, e.g. by light gates, and the normal pulse alone
  cannot separate it well from E* and e at a few per cent of noise: Pn = (1+e)·m*·v0 ties
  them). Add ``"speed"`` to ``vary`` when it is not known.
- **Starting values** from the record's moments: e from the normal percussion,
  :math:`e_0 = P_n/(m^* v_0) - 1`; the time scale δ*/v0 (hence E*) from the pulse's RMS
  width against the master curve's; t0 from its centroid less the filter's delay; μ from
  the upper plateau of Ft/Fn in compression (:func:`pipeline.percussion.estimate_mu`).
- **Poor fits** (χ²_ν more than five standard deviations above 1, or a runs test on a
  channel's residual signs below z = −2.326 at α = 0.01) are flagged and warned about with
  :class:`~pipeline.errors.PoorFitWarning`, never returned silently.
- **The sensor's own dynamics**: a mounted mode or a discharge the sensor states is modelled
  in series with its low-pass, its values known to their tolerances; one it does not state
  is looked for in the first fit's residuals — and a zero shift with it — fitted where the
  record shows it and kept where it lowers the AIC decisively, else bounded by what the
  record allows, the bound's effect entering the budget (:mod:`pipeline.fit.dynamics`).
  Spikes the window found are left out (:attr:`ContactFit.excluded`).
"""

from __future__ import annotations

import dataclasses
import functools
import math
import time
import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy import special

from .._json import json_ready
from ..contact import NORMAL_LAWS, calibrate_thornton, yield_pressure
from ..errors import InputError, PipelineWarning, PoorFitWarning
from ..percussion import mu_plateau
from ..precision import bound, model_words, reading
from ..scene import Scene
from ..simulate.curved import geometry_error
from ..smooth import runs_test
from . import dynamics
from .engine import Design, Problem, gauss_newton_many
from .forward import (
    _I,
    PARAMS,
    SHIFT_OF,
    SHIFT_PARAMS,
    SYSTEMATIC_PARAMS,
    UNITS,
    ForwardModel,
    RecordData,
    Solution,
    _force_table,
    param_scales,
    prepare,
)
from .procedure import run_fit
from .pulse import E_MIN, normal_pulse
from .result import FitResult, _misfit_words
from .systematics import DEFAULT_SYSTEMATICS, Systematic, resolve
from .tangential import tangential_response
from .verdict import AIC_DECISIVE, alternative_laws, alternative_orders, diagnose, model_spread

__all__ = ["ContactFit", "fit_contact", "DEFAULT_VARY"]


def DEFAULT_VARY(normal: str, tangential: str) -> tuple:
    """The parameters :func:`fit_contact` fits by default for a model."""
    names = ["E_eff"]
    if normal != "hertz":
        names.append("e")
    if tangential in ("coulomb", "mindlin"):
        names.append("mu")
    if tangential == "mindlin":
        names.append("kt_scale")
    names.append("t0")
    return tuple(names)


class _Single(Design):
    """One record: the local parameters are the global ones (``alpha`` → e if asked)."""

    def __init__(self, data: RecordData, law: str, use_alpha: bool):
        self.data, self.law, self.use_alpha = data, law, use_alpha
        self.names = tuple("alpha" if (n == "e" and use_alpha) else n for n in PARAMS)
        self.scale = param_scales(data)
        self.constant_dlocal = not use_alpha  # the identity's columns

    def local(self, theta):
        P = np.array(theta, dtype=float, copy=True)
        if self.use_alpha:
            d = self.data
            P[:, 1] = e_of_alpha(self.law, P[:, 1], P[:, 0], P[:, 4], d.R_eff, d.m_eff, d.cos_a)
        return [P]

    def dlocal(self, theta, vary):
        """∂P/∂θ_vary: the identity's columns (exact), by differences where α gives e."""
        if self.use_alpha:
            return super().dlocal(theta, vary)
        D = np.zeros((theta.shape[0], theta.shape[1], vary.size))
        D[:, vary, np.arange(vary.size)] = 1.0
        return [D]


def e_of_alpha(law, alpha, E, speed, R_eff, m_eff, cos_a):
    """Restitution of ``law`` with its material constant ``alpha`` (α [s/m] for the
    Hunt–Crossley family, the yield speed v_y [m/s] for Thornton's law: the law's
    :attr:`~pipeline.contact.NormalLaw.material`) at E* [Pa] and speed [m/s], for
    R* [m], m* [kg] and the incidence's cosine (docs/theory.md); every argument broadcast,
    so a campaign's records and rows take one call of the law's closed form."""
    L = NORMAL_LAWS[law]
    K = 4.0 / 3.0 * E * np.sqrt(R_eff)
    with np.errstate(invalid="ignore"):
        p = L.material_to_param(alpha, K, m_eff, speed * cos_a)
        e = np.asarray(L.cor(np.maximum(p, 0.0)))
    return np.clip(e, E_MIN, 1.0)


@dataclass(frozen=True, eq=False)
class ContactFit(FitResult):
    """The contact parameters of one record (:func:`fit_contact`; docs/theory.md).

    Besides the attributes of :class:`~pipeline.fit.result.FitResult` (``values``,
    ``stderr``, ``ci(level)``, ``identifiable``, ``notes``, ``aic``, ``bic``, ``redchi``,
    ``params``, ``result``):

    Attributes
    ----------
    model : pipeline.fit.forward.ForwardModel — normal law, tangential model, history rule
    data : pipeline.fit.forward.RecordData — the samples, weights and sensor model used
    dynamics : dict — what the fit found of the sensor's own dynamics
        (:mod:`pipeline.fit.dynamics`): ``what`` (in words) and the screen's numbers where
        it fitted a mode, a discharge or a zero shift the sensor does not state;
        ``bounds`` (the lowest f_n [Hz], the shortest τ [s] the record allows) where it
        bounded them instead
    physics : dict — what the fitted parameters imply: ``t_c`` [s], ``F_max`` [N],
        ``delta_max`` [m], ``e_n``, ``e_t`` [-], ``omega`` [rad/s], ``Pn_final``,
        ``Pt_final`` [N·s], ``regime`` (``"sliding"``: the slip never stops),
        ``slide_share`` (share of the normal percussion delivered while sliding)
    """

    model: object = None
    data: object = None
    physics: dict = None
    problem: object = None
    systematics: tuple = ()
    verdict: dict = None
    alternatives: dict = field(default_factory=dict)
    dynamics: dict = field(default_factory=dict)

    @property
    def normal(self) -> str:
        return self.model.normal

    # ------------------------------------------------- what a plastic fit implies
    @functools.cached_property
    def _yield95(self) -> dict:
        return _yield_point(self, 0.95)

    def _derived(self, level=0.95) -> dict:
        """{name: (value, stderr, (lo, hi))} of ``p_y`` [Pa] and ``v_y`` [m/s] for a fit of
        Thornton's law (module notes); empty for the other laws."""
        if self.model is None or self.normal != "thornton":
            return {}
        return self._yield95 if level == 0.95 else _yield_point(self, level)

    @functools.cached_property
    def _yield_values(self) -> dict:
        """``p_y`` [Pa] and ``v_y`` [m/s] at the fitted parameters (no interval: the verdict's
        fits of Thornton's law need only these); empty for the other laws."""
        if self.model is None or self.normal != "thornton":
            return {}
        return {k: v[0] for k, v in _yield_point(self, None).items()}

    @property
    def values(self) -> dict:
        """{name: value} [SI] (:attr:`FitResult.values`), and for Thornton's law the yield
        pressure ``p_y`` [Pa] and yield speed ``v_y`` [m/s] it implies."""
        out = super().values
        out.update(self._yield_values)
        return out

    @property
    def stderr(self) -> dict:
        out = super().stderr
        out.update({k: v[1] for k, v in self._derived().items()})
        return out

    def ci(self, level: float = 0.95, method: str = "auto", kind: str = "total") -> dict:
        """Intervals {name: (lo, hi)} (:meth:`FitResult.ci`), with ``p_y`` and ``v_y`` for
        Thornton's law (their total intervals, with ``kind="total"``; module notes)."""
        out = super().ci(level, method, kind)
        if kind == "total":
            out.update({k: v[2] for k, v in self._derived(level).items()})
        return out

    def _derived_rows(self, level) -> list:
        """The yield pressure and speed of Thornton's law in :meth:`table` (a lower bound
        where e's interval reaches 1)."""
        rows = []
        for k, (v, se, (lo, hi)) in self._derived(level).items():
            if math.isinf(hi):
                rows.append({"name": k, "value": lo, "status": "lower", "kind": "contact"})
            else:
                rows.append(
                    {"name": k, "value": v, "stderr": se, "ci": (lo, hi), "kind": "contact"}
                )
        return rows

    def _param_lines(self, level=0.95) -> list:
        lines = super()._param_lines(level)
        for k, (v, se, (lo, hi)) in self._derived(level).items():
            what = "yield pressure" if k == "p_y" else "yield speed"
            if math.isinf(hi):
                lines.append(
                    f"    {k:<12s} ≥ {lo:.6g} {UNITS[k]} ({what}, implied; only a lower bound, "
                    f"{level:.0%}: e's interval reaches 1)"
                )
            else:
                lines.append(
                    f"    {k:<12s} = {v:.6g} ± {se:.2g} {UNITS[k]}  [{lo:.6g}, {hi:.6g}] "
                    f"({level:.0%}; {what}, implied)"
                )
        return lines

    def _summary_params(self) -> dict:
        out = super()._summary_params()
        for k, (v, se, ci) in self._derived().items():
            out[k] = {"value": v, "unit": UNITS[k], "vary": False, "derived": True,
                      "stderr": se, "ci95": list(ci)}  # fmt: skip
        return out

    @property
    def excluded(self) -> dict:
        """{channel: [sample indices of the record]} left out of the fit: the spikes no force
        history can make (:func:`pipeline.window.find_spikes`; the verdict's ``spikes``)
        and samples at the ADC's end codes."""
        return {k: list(v) for k, v in self.data.excluded.items()}

    @property
    def tangential(self) -> str:
        return self.model.tangential

    def _P(self):
        return self.problem.design.local(self.theta[None, :])[0]

    def predicted(self) -> list:
        """The fitted model as measured at the fitted samples, one array per channel [N]
        (with the channel's fitted residual baseline, where one is fitted)."""
        P = self._P()
        sol = self.problem.solution(self.theta)[0]  # kept from the fit's last evaluation
        out = []
        for c, m in zip(self.data.channels, self.model.predict(self.data, P, sol), strict=True):
            out.append(m[0] + (c.y - m[0]) - c.project(c.y - m[0]))
        return out

    def true_forces(self, t) -> dict:
        """The fitted contact forces (before the sensor) at instants ``t`` [s]: ``Fn``,
        ``Ft`` [N], and ``Ft_rigid``, Routh's broken line on the fitted normal pulse
        (Ft = μ·Fn until the slip would stop, then 0; docs/theory.md). Empty for
        :func:`pipeline.select_model`'s rigid candidate: its impulses at t0 have no force
        history (:meth:`predicted` holds them as the sensor records them)."""
        if self.model.normal is None:
            return {}
        P = self._P()
        sol = self.model.solve([self.data], [P])[0]
        out = self.model.curves(self.data, P, sol, t)
        if self.tangential != "none":
            k = sol.index[:1]
            pul = sol.pulse.take(k)
            d = self.data
            v0 = P[0, 4] * d.cos_a
            tr = tangential_response(
                pul, abs(float(d.slip0(P[0, 4]))) / v0, d.lam, P[0, 2], 0.0, tangential="coulomb"
            )

            rig = self.model.curves(d, P, Solution(pul, tr, np.zeros(1, int)), t)
            out["Ft_rigid"] = rig["Ft"]
        return out

    def residuals(self) -> list:
        """(y − model)/σ per channel."""
        return [
            (c.y - m) / c.sigma for c, m in zip(self.data.channels, self.predicted(), strict=True)
        ]

    def runs_z(self) -> dict:
        """Runs-test z of each channel's residual signs (pipeline.smooth.runs_test), on the
        fit's (whitened) residuals where the misfit test ran."""
        if self.misfit is not None:
            return dict(self.misfit.runs_z)
        return {
            c.name: float(runs_test(r))
            for c, r in zip(self.data.channels, self.residuals(), strict=True)
        }

    def report(self) -> str:
        """lmfit's fit report, then the physics the fit implies (and the notes)."""
        from lmfit import fit_report

        ph = self.physics
        lines = [
            f"Contact fit of {self.data.record.attrs.get('source', 'a record')}: normal "
            f"{self.normal!r}, tangential {self.tangential!r}"
            + (f" ({self.model.history} history)" if self.tangential == "mindlin" else ""),
            f"  {self.n_data} samples, χ² = {self.chi2:.5g}, χ²_ν = {self.redchi:.4g}, "
            f"AIC = {self.aic:.5g}, BIC = {self.bic:.5g}"
            + (" — POOR FIT (structured residuals)" if self.poor else ""),
            "  verdict: "
            + (
                "not diagnosed"
                if self.verdict is None
                else self._verdict_state()
                + (
                    f" — causes: {', '.join(self.verdict['causes'])}"
                    if self.verdict["causes"]
                    else ""
                )
            ),
            "  parameters (95 % intervals, "
            + ("block bootstrap" if self.boot is not None else "covariance")
            + " for the data, widened by the systematics and the model spread):",
            *self._param_lines(),
            *self._budget_lines(),
            *self._systematics_lines(),
            *self._law_lines(),
            "  implied:",
            f"    t_c = {ph['t_c'] * 1e6:.2f} µs, F_max = {ph['F_max']:.5g} N, "
            f"δ_max = {ph['delta_max'] * 1e6:.3f} µm, e_n = {ph['e_n']:.4f}",
        ]
        if "e_t" in ph:
            lines.append(
                f"    e_t = {ph['e_t']:.4f}, ω = {ph['omega']:.4g} rad/s, regime {ph['regime']} "
                f"(sliding during {ph['slide_share']:.0%} of the normal percussion)"
            )
        if self.notes:
            lines.append("  notes:")
            lines += [f"    - {n}" for n in self.notes]
        lines += ["", "lmfit report:", fit_report(self.params)]
        return "\n".join(lines)

    def _verdict_state(self) -> str:
        """The verdict in three words: ok; the forces fit (the residuals at the noise level)
        but a cause biases the parameters; or the model misses the record."""
        if self.verdict["ok"]:
            return "ok"
        if self.misfit is not None and self.misfit.ok:
            return "the forces fit, the parameters do not hold as fitted"
        return "the model does not describe the record"

    def _verdict_words(self) -> tuple:
        """(the verdict in a sentence, [each cause's message]) (:meth:`table`)."""
        v = self.verdict
        if v is None:
            return super()._verdict_words()
        model = model_words(self.normal, self.tangential)
        redchi = self.misfit.redchi if self.misfit is not None else self.redchi
        causes = list(v["causes"])
        said = [_CAUSE_WORDS.get(c, model_words(c)) for c in causes]
        if v["ok"]:
            text = (
                f"The model ({model}) describes the record: the residuals are at the noise "
                f"level (χ²_ν = {redchi:.3g})"
                + (f"; noted: {', '.join(said)}" if said else "")
                + "."
            )
        else:
            modelled = ("coloured_noise", "sensor_dynamics", "spikes")
            missed = [w for c, w in zip(causes, said, strict=True) if c not in modelled]
            if self.misfit is not None and self.misfit.ok:
                # the residuals are at the noise level: what fails is how the parameters
                # read (a turning normal, a better law, a traded impulse), not the forces
                text = (
                    f"The model ({model}) fits the record's forces to the noise level "
                    f"(χ²_ν = {redchi:.3g}), but its parameters do not hold as fitted: "
                    + ("; ".join(missed) or "see the causes")
                    + "."
                )
            else:
                if self.misfit is not None:
                    missed += _misfit_words(self.misfit)
                text = (
                    f"The model ({model}) does not describe the record: "
                    + ("; ".join(missed) or "the misfit test fails")
                    + "."
                )
        messages = v.get("messages", {})
        return text, [
            f"{_CAUSE_WORDS.get(c, model_words(c))}: {messages[c]}" for c in causes if c in messages
        ]

    def _systematics_lines(self) -> list:
        if not self.systematics:
            return ["  inputs taken as exact (systematics={})"]
        lines = ["  inputs known to a tolerance (stated value, standard uncertainty; source):"]
        for s in self.systematics:
            u = "fitted freely" if not math.isfinite(s.sigma) else f"u = {s.sigma:.3g}"
            lines.append(f"    {s.name:<10s} {s.value:<12.6g} {u}; {s.source}")
        return lines

    def _law_lines(self) -> list:
        if not self.alternatives:
            return []
        lines = ["  the laws compared (inputs exact): ΔAIC, Akaike weight, E*, e"]
        for law, row in sorted(self.alternatives.items(), key=lambda kv: kv[1]["aic"]):
            v = row["values"]
            lines.append(
                f"    {law:<16s} {row['delta_aic']:>10.1f} {row['weight']:>8.3f} "
                f"{v.get('E_eff', math.nan):>12.5g} {v.get('e', math.nan):>8.4f}"
            )
        return lines

    def summary(self) -> dict:
        """Every number of the fit, strict-JSON ready (units in :data:`UNITS` and keys)."""
        d = self.data
        return json_ready(
            {
                "source": d.record.attrs.get("source", ""),
                "sha256": d.record.attrs.get("sha256", ""),
                "scene": d.scene.to_dict(),
                "model": {
                    "normal": self.normal,
                    "tangential": self.tangential,
                    "history": self.model.history if self.tangential == "mindlin" else None,
                    "n_steps": self.model.n_steps,
                },
                "parameters": self._summary_params(),
                "physics": {
                    (k if k in ("regime", "slide_share", "e_n", "e_t") else k + _unit(k)): v
                    for k, v in self.physics.items()
                },
                "fit": self._summary_stats(),
                "channels": {
                    c.name: {"samples": int(c.t.size), "sigma_N": c.sigma_rms} for c in d.channels
                },
                "runs_z": self.runs_z(),
                "sensor": d.sensor.summary(),
                "window": d.window.summary(),
                "noise": {c.name: c.noise.summary() for c in d.channels},
                "budget": self.budget,
                "systematics": [
                    {"name": s.name, "value": s.value, "u": s.sigma, "source": s.source}
                    for s in self.systematics
                ],
                "verdict": None
                if self.verdict is None
                else {k: v for k, v in self.verdict.items() if k != "impulse"}
                | {"impulse": self.verdict.get("impulse", {})},
                "laws": self.alternatives,
                "sensor_dynamics": self.dynamics,
                "excluded": self.excluded,
            }
        )

    def to_dataset(self):
        """Measured, model and residuals per channel on the fitted samples (xarray).

        Variables ``<ch>`` (measured less baseline), ``<ch>_model`` [N] and
        ``<ch>_residual`` [(y − model)/σ], ``<ch>_true`` (the model before the sensor) [N]
        and ``Ft_rigid`` [N] (neither for a rigid fit: :meth:`true_forces`) on coordinate
        ``time_<ch>`` [s]; attrs: the summary as JSON.
        """
        import json

        import xarray as xr

        ds = xr.Dataset()
        for c, m in zip(self.data.channels, self.predicted(), strict=True):
            tname = f"time_{c.name}"
            tf = self.true_forces(c.t)
            coords = {tname: (tname, c.t, {"units": "s"})}
            ds = ds.assign_coords(coords)
            ds[c.name] = (
                tname,
                c.y,
                {"units": "N", "long_name": f"measured {c.name} less baseline"},
            )
            ds[f"{c.name}_model"] = (
                tname,
                m,
                {"units": "N", "long_name": "fitted model, as measured"},
            )
            ds[f"{c.name}_residual"] = (
                tname,
                (c.y - m) / c.sigma,
                {"units": "1", "long_name": "(measured − model)/σ"},
            )
            if tf.get(c.name) is not None:
                ds[f"{c.name}_true"] = (
                    tname,
                    tf[c.name],
                    {"units": "N", "long_name": "fitted contact force"},
                )
            if c.name == "Ft" and "Ft_rigid" in tf:
                ds["Ft_rigid"] = (
                    tname,
                    tf["Ft_rigid"],
                    {"units": "N", "long_name": "Routh (rigid) Ft on the fitted Fn"},
                )
        ds.attrs["summary_json"] = json.dumps(self.summary(), allow_nan=False)
        ds.attrs["normal_model"] = self.normal
        ds.attrs["tangential_model"] = self.tangential
        return ds


def _yield_point(fit, level) -> dict:
    """``p_y`` [Pa] and ``v_y`` [m/s] of a Thornton fit: {name: (value, stderr, (lo, hi))}
    (module notes); ``level`` None: the values alone (stderr and interval NaN)."""
    d, design = fit.data, fit.problem.design
    theta = np.asarray(fit.theta, dtype=float)

    def logs(th, e=None):
        P = design.local(np.asarray(th, dtype=float)[None, :])[0][0]
        r = calibrate_thornton(np.clip(P[_I["e"]] if e is None else e, 1e-12, 1.0))
        v_y = r * P[_I["speed"]] * d.cos_a
        E, R, m = P[_I["E_eff"]], d.R_eff_of(P[_I["radius"]]), d.m_eff_of(P[_I["mass"]])
        return np.log([float(yield_pressure(v_y, E, R, m)), float(v_y)])

    centre = logs(theta)
    if level is None:
        return {
            k: (math.exp(c), math.nan, (math.nan, math.nan))
            for k, c in zip(("p_y", "v_y"), centre, strict=True)
        }
    vary = fit.vary
    g = np.zeros((2, len(vary)))
    for j, name in enumerate(vary):
        i = fit.names.index(name)
        h = 1e-7 * max(abs(theta[i]), 1e-12)
        up, down = theta.copy(), theta.copy()
        up[i] += h
        down[i] -= h
        g[:, j] = (logs(up) - logs(down)) / (2 * h)
    cov = np.where(np.isfinite(fit.cov), fit.cov, 0.0)
    rest = np.einsum("ij,jk,ik->i", g, cov, g)
    z = float(special.ndtri(0.5 + level / 2.0))
    e_lo = e_hi = None
    if "e" in vary and "e" not in fit.one_sided:
        j = vary.index("e")
        rest = rest - g[:, j] ** 2 * cov[j, j]  # e's part: its interval, mapped
        e_lo, e_hi = FitResult.ci(fit, level)["e"]
    rest = np.sqrt(np.maximum(rest, 0.0))
    out = {}
    for k, name in enumerate(("p_y", "v_y")):
        lo_e = hi_e = 0.0
        if e_lo is not None:
            lo_e = centre[k] - logs(theta, max(e_lo, 1e-9))[k]
            hi_e = math.inf if e_hi >= 1.0 else logs(theta, e_hi)[k] - centre[k]
        lo = centre[k] - math.hypot(lo_e, z * rest[k])
        hi = centre[k] + math.hypot(hi_e, z * rest[k])
        value = math.exp(centre[k])
        se = value * (hi - lo) / (2 * z) if math.isfinite(hi) else math.nan
        out[name] = (value, se, (math.exp(lo), math.exp(hi)))
    return out


#: The verdict's causes in words (:meth:`ContactFit.table`; pipeline.fit.verdict).
_CAUSE_WORDS = {
    "normal_law": "another normal law fits decisively better",
    "sensor_filter": "the sensor's filter is not as stated",
    "crosstalk": "the force axes leak into each other (cross-talk)",
    "coloured_noise": "the noise is coloured (modelled)",
    "impulse_mismatch": "the model's impulse differs from the measured one",
    "ft_sign": "Ft pushes the ball along its slip: its sign convention is the opposite",
    "geometry": "the contact normal turns on the curved target",
    "second_impact": "a second impact follows",
    "sensor_dynamics": "the sensor's own mode, discharge or zero shift shows (modelled)",
    "spikes": "isolated spikes were left out",
}


def _unit(k):
    return {
        "t_c": "_s",
        "F_max": "_N",
        "delta_max": "_m",
        "Pn_final": "_Ns",
        "Pt_final": "_Ns",
        "omega": "_rad_per_s",
        "Ft_max": "_N",
        "Ft_min": "_N",
    }.get(k, "")


# ------------------------------------------------------------------ starting values
def _moments(t, y):
    w = np.maximum(y, 0.0)
    area = np.trapezoid(w, t)
    mean = np.trapezoid(w * t, t) / area
    var = np.trapezoid(w * (t - mean) ** 2, t) / area
    return area, mean, math.sqrt(max(var, 0.0))


def _in_window(c, w):
    """(t [s], y [N]) of the fitted channel ``c`` inside the contact window ``w``."""
    inside = (c.t >= w.t_start) & (c.t <= w.t_end)
    return c.t[inside], c.y[inside]


def _start(data: RecordData, model: ForwardModel, speed: float) -> dict:
    v0 = speed * data.cos_a
    area, mean, width = _moments(*_in_window(data.channels[0], data.window))
    e0 = 1.0 if model.normal == "hertz" else float(np.clip(area / (data.m_eff * v0) - 1, 0.2, 0.99))
    if model.normal is None:  # rigid: impulses at t0
        return {
            "E_eff": 1.0,
            "e": e0,
            "mu": _mu_start(data, mean),
            "kt_scale": 1.0,
            "speed": speed,
            "t0": mean - data.sensor.delay(),
        }
    mt, wt, peak = _pulse_moments(model.normal, e0, model.n_steps)
    T = width / wt
    ds = T * v0
    K = data.m_eff * v0 * v0 / ds**2.5
    E0 = 3.0 * K / (4.0 * math.sqrt(data.R_eff))
    t0 = mean - mt * T - data.sensor.delay()
    mu0 = 0.1
    if model.tangential != "none" and len(data.channels) > 1:
        mu0 = _mu_start(data, t0 + T * peak)
    return {"E_eff": E0, "e": e0, "mu": mu0, "kt_scale": 1.0, "speed": speed, "t0": t0}


def _mu_start(data, t_peak):
    """μ from the upper plateau of Ft/Fn before the peak (pipeline.percussion.estimate_mu)
    of the fitted samples inside the window: the record's less their baselines, as the
    window's record holds them, without cutting that record (spikes left out, not
    repaired)."""
    ch = {c.name: c for c in data.channels}
    m = math.nan
    if "Fn" in ch and "Ft" in ch:
        w = data.window
        m = mu_plateau(*_in_window(ch["Fn"], w), *_in_window(ch["Ft"], w), t_peak)
    C = data.sensor.crosstalk
    if C is not None and np.isfinite(m):
        # the measured ratio is (C10 + C11·μ)/(C00 + C01·μ): undo the sensor's mixing
        den = C[1, 1] - C[0, 1] * m
        m = (C[0, 0] * m - C[1, 0]) / den if den > 0 else m
    return float(np.clip(m, 1e-3, 2.0)) if np.isfinite(m) and m > 0 else 0.1


# ------------------------------------------------------------------ the fit
def fit_contact(
    record,
    scene: Scene,
    *,
    normal: str = "hunt_crossley",
    tangential: str = "mindlin",
    vary=None,
    systematics=None,
    **options,
) -> ContactFit:
    """Fit the contact parameters of one force record (module notes).

    Parameters
    ----------
    record : xarray.Dataset
        A record (:func:`pipeline.io.load`, or :func:`pipeline.simulate.impact` →
        :func:`pipeline.sensor_model.to_sensor`) with ``Fn`` and, unless
        ``tangential="none"``, ``Ft`` [N].
    scene : Scene
        The impact: radii, masses, speed [m/s], angle [deg], Poisson ratios (and E, for the
        starting value); μ and e may be None (unknown).
    normal : str
        Normal law, a key of :data:`pipeline.contact.NORMAL_LAWS` (``"hertz"`` is elastic,
        e = 1).
    tangential : {"mindlin", "coulomb", "none"}
    vary : sequence of str, optional
        Parameters to fit (names in the module table); default :func:`DEFAULT_VARY`. The
        others are fixed at the scene's values (E_eff from E and ν, ``e``, ``mu``,
        ``speed``; ``kt_scale`` 1) or, where the scene leaves them unknown, at the
        starting values.

    Other Parameters
    ----------------
    history : {"total", "incremental"}
        Mindlin history rule (default ``"total"``, as the simulator).
    sensor : SensorSpec or mapping
        Sensor properties (bandwidth [Hz], filter_order, quantum [N], crosstalk_matrix), e.g.
        a sample sidecar's ``"sensor"`` block; default: from the record
        (:func:`pipeline.fit.sensor.sensor_spec`).
    noise : mapping
        σ per channel [N], instead of the noise measured outside the contact.
    margin : float
        Samples kept on each side of the contact window [fraction of its duration];
        default: every sample.
    baseline : bool
        Fit each channel's residual offset and drift with the contact (default for sensor
        records; :mod:`pipeline.fit.forward`).
    n_steps : int
        Steps of the tabulated pulse per contact (default 128).
    oversample : int
        Fine-grid factor of the filter model (default 4).
    n_boot : int
        Block-bootstrap replicates (default 200; 0: covariance intervals only).
    seed : int
        Seed of the bootstrap (default 0).
    start : mapping
        Starting values overriding the module's rules.
    window_options : dict
        Passed to :func:`pipeline.window.find_contact`.
    zero_shift : None or False
        None (default): a zero shift of Fn or Ft is fitted where the record shows one
        (:mod:`pipeline.fit.dynamics`, with the discharge); False: never.

    Returns
    -------
    ContactFit

    Raises
    ------
    InputError
        Unknown model or parameter names, a scene without elastic constants, a record
        without the channels or samples to fit.

    Warns
    -----
    PoorFitWarning
        When the residuals show structure the model misses (module notes).

    Examples
    --------
    >>> fit = fit_contact(load("data_samples/gr_15deg_0.6ms.csv"), scene)  # doctest: +SKIP
    >>> fit.values["E_eff"], fit.ci()["mu"], fit.identifiable["mu"]  # doctest: +SKIP
    """
    t_begin = time.perf_counter()
    opts = dict(options)
    history = opts.pop("history", "total")
    n_steps = int(opts.pop("n_steps", 128))
    model = ForwardModel(normal, tangential, history, n_steps)
    vary = DEFAULT_VARY(normal, tangential) if vary is None else tuple(vary)
    allowed = set(PARAMS) | {"alpha"}
    bad = [v for v in vary if v not in allowed]
    if bad:
        raise InputError(f"fit_contact: unknown parameter(s) {bad}; choose from {sorted(allowed)}")
    if "alpha" in vary and "e" in vary:
        raise InputError("vary 'e' or 'alpha' (the same damping, two parametrisations), not both")
    if normal == "hertz" and ("e" in vary or "alpha" in vary):
        raise InputError("the elastic 'hertz' law has e = 1: nothing to vary; choose a damped law")
    if tangential != "mindlin" and "kt_scale" in vary:
        raise InputError(f"kt_scale is a Mindlin parameter; tangential={tangential!r} has none")
    if tangential == "none" and "mu" in vary:
        raise InputError("tangential='none' is frictionless: mu cannot be fitted")
    check = bool(opts.pop("diagnose", True))
    opts["systematics"] = systematics
    data = _prepare(record, scene, model, opts)  # once: the verdict's fits share it
    fit = fit_model(record, scene, model, vary, t_begin=t_begin, data=data, **opts)
    if not check:
        return fit
    return _diagnosed(fit, record, scene, vary, opts, t_begin, data)


#: The options of :func:`fit_contact` that choose the samples, their weights and the sensor
#: model (:func:`pipeline.fit.forward.prepare`'s).
_PREPARE = ("sensor", "noise", "margin", "baseline", "oversample", "window_options", "quiet_after")


def _prepare(record, scene, model, options) -> RecordData:
    """The record prepared for fitting ``model`` with the options given."""
    given = {k: options[k] for k in _PREPARE if k in options}
    return prepare(record, scene, channels=model.channels, **given)


def fit_model(
    record, scene, model, vary, *, t_begin=None, data=None, lean=False, **options
) -> ContactFit:
    """Fit ``model`` (a :class:`~pipeline.fit.forward.ForwardModel`, or the rigid model of
    :mod:`pipeline.fit.select`) to one record: the work behind :func:`fit_contact`, whose
    options it takes. ``data``: the record already prepared with those options
    (:func:`pipeline.fit.forward.prepare`), as the verdict's fits share it. ``lean``: a fit
    read for its χ² and values alone, as the verdict's fits of the other laws and filter
    orders are (:func:`pipeline.fit.procedure.run_fit`: no misfit test, no standard errors;
    no ``physics`` either, but where α is fitted).

    Where the systematics look for the sensor's dynamics (their mapping holds
    ``"resonance"``, ``"discharge"``) and the sensor states none, the fit's residuals are
    screened for a mode, a discharge and a zero shift (:mod:`pipeline.fit.dynamics`); what
    the screen finds is fitted, and kept where it lowers the AIC decisively."""
    t_begin = time.perf_counter() if t_begin is None else t_begin
    opts = dict(options)
    found = opts.pop("found", None)
    if found is not None or model.normal is None:
        return _fit_model(record, scene, model, vary, t_begin, opts, data, found, lean)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fit = _fit_model(record, scene, model, vary, t_begin, opts, data, lean=lean)
    want = _screened(fit, opts)
    findings = dynamics.screen(fit.problem, fit.theta, fit.data, model, **want)
    out = _bounded(_with_dynamics(fit, findings, record, scene, model, vary, t_begin, opts), want)
    for w in caught:  # the first fit's warnings, but its misfit where the dynamics explain it
        if out is fit or not issubclass(w.category, PoorFitWarning):
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno, source=w.source)
    return out


def _screened(fit, opts) -> dict:
    """What the dynamics screen looks for in ``fit``'s record (module notes of
    :mod:`pipeline.fit.dynamics`): a mode and a discharge where the systematics name them
    and the sensor states none; a zero shift with the discharge, unless ``zero_shift``
    says otherwise."""
    syst = opts.get("systematics")
    given = DEFAULT_SYSTEMATICS if syst is None else syst
    spec = fit.data.sensor
    sensor_kind = fit.data.window.kind == "sensor" and fit.data.fine is not None
    return {
        "mode": sensor_kind and "resonance" in given and not math.isfinite(spec.resonance),
        "discharge": sensor_kind and "discharge" in given and not math.isfinite(spec.discharge),
        "shift": sensor_kind and "discharge" in given and opts.get("zero_shift") is not False,
    }


def _with_dynamics(fit, findings, record, scene, model, vary, t_begin, opts) -> ContactFit:
    """``fit`` refitted with what the screen found, where that lowers the AIC decisively
    against ``fit`` refitted on the same weights (the noise measured before the contact);
    else ``fit``."""
    if not findings:
        return fit
    spec = fit.data.sensor
    found, sensor = {}, spec
    if findings.mode is not None:
        fn, zeta, chi2, fd, delta = findings.mode
        sensor = dataclasses.replace(sensor, resonance=fn, damping_ratio=zeta)
        why = (
            f"not stated: fitted — the record rings at {reading('resonance', fd)} after the pulse, "
            f"logarithmic decrement {delta:.3g} (χ² {chi2:.0f} explained)"
        )
        found["resonance"] = (fn, why)
        found["damping_ratio"] = (zeta, why)
    if findings.discharge is not None:
        tau, chi2 = findings.discharge
        sensor = dataclasses.replace(sensor, discharge=tau)
        found["discharge"] = (
            tau,
            f"not stated: fitted — the record undershoots after the pulse (χ² {chi2:.0f} "
            "explained)",
        )
    if findings.shift:
        why = "not stated: fitted — the record's zero steps during the contact"
        found.update({k: (v, why) for k, v in findings.shift.items()})
    extra = {"sensor": sensor, "quiet_after": True}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)
        try:
            data = _prepare(record, scene, model, {**opts, **extra})  # once, for every trial
            alt = _fit_model(record, scene, model, vary, t_begin, {**opts, **extra}, data, found)
            if findings.mode is not None:
                # a ring of the pulse's own frequency leaves the joint problem many local
                # optima: also started from the contact fitted with the mode held, the
                # better of the two kept
                held = {**opts, **extra, "n_boot": 0, "systematics": {}}
                first = _fit_model(record, scene, model, vary, t_begin, held, data, None)
                warm = dict(zip(first.names, map(float, first.theta), strict=True))
                start = {**{n: warm[n] for n in vary if n in warm}, **(opts.get("start") or {})}
                other = _fit_model(
                    record, scene, model, vary, t_begin, {**opts, **extra, "start": start},
                    data, found,
                )  # fmt: skip
                alt = min(alt, other, key=lambda f: f.aic)
        except (InputError, np.linalg.LinAlgError):
            return fit
    base_aic = _aic_on(fit, alt, record, scene, model, opts)
    gain = base_aic - alt.aic
    if not gain > AIC_DECISIVE:
        change = (
            f"lowered the AIC by {gain:.1f} only (≤ {AIC_DECISIVE:g})"
            if gain > 0
            else f"did not lower the AIC (it rose by {-gain:.1f})"
        )
        note = f"the residuals hinted at {_what(findings)}, but fitting it {change}: left out"
        return dataclasses.replace(fit, notes=fit.notes + (note,))
    if alt.poor:  # its own PoorFitWarning was held back with the trial's
        warnings.warn(
            next(n for n in alt.notes if "the model misses structure" in n), PoorFitWarning, 3
        )
    info = dict(findings.scores, aic_gain=gain, what=_what(findings))
    terms = dynamics.shift_spread(alt) if findings.shift else {}
    return dataclasses.replace(alt, dynamics=info, extra_terms=terms)


def _bounded(fit, want) -> ContactFit:
    """``fit`` with the bound of a mode or a discharge it looked for but neither found nor
    was told in its budget (:func:`pipeline.fit.dynamics.bounds`): each parameter's
    largest shift over what the record allows, as a rectangular bound (u = shift/√3)."""
    which = {
        "mode": want["mode"] and "resonance" not in fit.vary,
        "discharge": want["discharge"] and "discharge" not in fit.vary,
    }
    found = dynamics.bounds(fit.problem, fit.theta, fit.data, fit.model, **which)
    if not found:
        return fit
    terms, notes = {k: dict(v) for k, v in fit.extra_terms.items()}, []
    for name, b in found.items():
        for param, shift in b["effect"].items():
            if param not in SYSTEMATIC_PARAMS and shift > 0:
                terms.setdefault(param, {})[name] = shift / math.sqrt(3.0)
        what = (
            f"a mounted mode at f_n {bound(b['limit'] * 1e-3, 'lower')} kHz "
            f"(ζ = {dynamics.ZETA_BOUND})"
            if name == "resonance"
            else f"a discharge of τ {bound(b['limit'] * 1e3, 'lower')} ms"
        )
        notes.append(
            f"{name}: none stated and none shows in the record, which allows {what}; its "
            "largest effect enters the budget as a rectangular bound"
        )
    info = dict(fit.dynamics, bounds={k: b["limit"] for k, b in found.items()})
    return dataclasses.replace(
        fit, extra_terms=terms, notes=fit.notes + tuple(notes), dynamics=info
    )


def _what(findings) -> str:
    parts = []
    if findings.mode is not None:
        parts.append(f"a mounted mode near {reading('resonance', findings.mode[0])}")
    if findings.discharge is not None:
        parts.append(f"a discharge of τ ≈ {reading('discharge', findings.discharge[0])}")
    if findings.shift:
        chans = [c for c, p in SHIFT_OF.items() if p in findings.shift]
        parts.append(f"a zero shift of {' and '.join(chans)}")
    return " and ".join(parts)


def _aic_on(fit, alt, record, scene, model, opts) -> float:
    """AIC of ``fit``'s model (without the dynamics found) refitted on ``alt``'s weights:
    the noise measured before the contact, the same samples."""
    data = _prepare(record, scene, model, {**opts, "sensor": fit.data.sensor, "quiet_after": True})
    p = fit.problem
    design = _Single(data, model.normal, p.design.use_alpha)
    varied = np.zeros(len(fit.names), dtype=bool)
    varied[p.vary] = True
    priors = {
        int(k): (v, u) for k, v, u in zip(p.prior_index, p.prior_value, p.prior_sigma, strict=True)
    }
    problem = Problem(model, [data], design, varied, priors)
    lower, upper = dynamics.fit_bounds(fit)
    _, chi2 = gauss_newton_many(problem, fit.theta[None, :], lower=lower, upper=upper, iters=6)
    return float(chi2[0]) + 2 * (fit.nvarys + data.n_nuisance)


def _fit_model(
    record, scene, model, vary, t_begin, opts, data=None, found=None, lean=False
) -> ContactFit:
    """One fit of ``model`` with the options of :func:`fit_contact` (on ``data``, the record
    prepared with them, where given); ``found`` maps the sensor's parameters the screen
    found to (start value, source): fitted freely; ``lean`` as :func:`fit_model`'s."""
    opts = dict(opts)
    given = {k: opts.pop(k) for k in _PREPARE if k in opts}
    n_boot = int(opts.pop("n_boot", 200))
    seed = int(opts.pop("seed", 0))
    start = dict(opts.pop("start", None) or {})
    systematics = opts.pop("systematics", None)
    time_error = opts.pop("time_error", None)
    if opts.pop("zero_shift", None) not in (None, False):
        raise InputError("zero_shift is None (where the record shows one) or False (never)")
    if opts:
        raise InputError(
            f"fit_contact: unknown option(s) {', '.join(sorted(opts))}; see its docstring"
        )
    normal, tangential = model.normal, model.tangential
    use_alpha = "alpha" in vary
    if data is None:
        data = _prepare(record, scene, model, given)
    notes = list(data.notes)
    design = _Single(data, normal, use_alpha)
    starts = {}  # the record's starting values, worked out where one is needed

    def s0(name, default=None):
        if not starts:
            starts.update(_start(data, model, float(scene.speed)))
        return starts.get(name, default)

    fixed = {
        "E_eff": float(scene.E_eff),
        "e": 1.0 if normal == "hertz" else scene.e,
        "mu": scene.mu,
        "kt_scale": 1.0,
        "speed": float(scene.speed),
        "t0": None,  # the start's, where not fitted
    }
    for name, value in fixed.items():
        if value is None and name not in vary:
            if name == "mu" and tangential == "none":
                fixed[name] = 0.0
                continue
            if name != "t0":
                notes.append(f"{name} is neither in the scene nor fitted: held at its start value")
            fixed[name] = s0(name)
    nominal = dict(zip(PARAMS, data.nominal(), strict=True))
    fixed.update({n: nominal[n] for n in PARAMS if n not in fixed})
    init = {
        n: (start[n] if n in start else s0(n, fixed[n])) if n in vary else fixed[n] for n in PARAMS
    }
    if use_alpha and "alpha" not in start:
        L = NORMAL_LAWS[normal]
        v0 = init["speed"] * data.cos_a
        K = 4.0 / 3.0 * init["E_eff"] * math.sqrt(data.R_eff)
        p = float(L.calibrate(s0("e")))
        init["alpha"] = p / float(L.material_to_param(1.0, K, data.m_eff, v0)) if p else 0.0
    syst = () if normal is None else resolve(systematics, data, tangential)
    if found:  # what the screen found is fitted freely, from where it found it
        syst = tuple(s for s in syst if s.param not in found) + tuple(
            Systematic(k, k, float(v), math.inf, why) for k, (v, why) in found.items()
        )
    priors = {}
    for s in syst:
        vary = (*vary, s.param) if s.param not in vary else vary
        init[s.param] = s.value
        if math.isfinite(s.sigma):
            priors[s.param] = (s.value, s.sigma)
    init.update(start)
    n_pass = 1 if data.window.kind != "digitised" or time_error == 0 or normal is None else 3
    for k in range(n_pass):
        last = k == n_pass - 1
        with warnings.catch_warnings():
            if not last:  # the passes before the effective variances are not the answer
                warnings.simplefilter("ignore", PipelineWarning)
            kw = run_fit(
                model, [data], design, init, vary, list(notes), n_boot=n_boot if last else 0,
                seed=seed, priors=priors, lean=lean and last,
            )  # fmt: skip
        if k < n_pass - 1:  # digitised: weigh each click by its effective variance
            data, note = effective_variance(data, model, design, kw, time_error)
            design = _Single(data, normal, use_alpha)
            init.update(zip(design.names, kw["theta"], strict=True))
            if k == n_pass - 2:
                notes.append(note)
    kw["systematics"] = syst
    physics = {}  # a lean fit's, but an α fit's: the verdict starts the other laws at its e_n
    if not lean or use_alpha:
        P = design.local(kw["theta"][None, :])[0]
        sol = kw["problem"].solution(kw["theta"])[0]
        physics = model.physics(data, P, sol)
    kw.update(data=data, physics=physics)
    kw["cost_s"] = time.perf_counter() - t_begin
    return ContactFit(**kw)


def effective_variance(data, model, design, kw, time_error=None):
    """The record with each digitised point weighed by its effective variance, and a note.

    A click lands off the curve in force and in time: σ_i² = σ_F² + (F′(t_i)·σ_t)², F′ the
    fitted curve's slope there (Orear 1982: an error in x acts as an error in y of the
    curve's slope times it). σ_F and σ_t are estimated together from the fit's residuals,
    whose squares regress on (1, F′²) by non-negative least squares, unless ``time_error``
    [s] gives σ_t; a steep flank's clicks then count for what they are worth.

    References
    ----------
    J. Orear, Am. J. Phys. 50:912 (1982), doi:10.1119/1.12972.
    """
    from scipy.optimize import nnls

    P = design.local(kw["theta"][None, :])[0]
    sol = kw["problem"].solution(kw["theta"])[0]
    chans, parts = [], []
    for c, m in zip(data.channels, model.predict(data, P, sol), strict=True):
        step = 1e-3 * float(np.median(np.diff(c.t))) if c.t.size > 1 else 1e-9
        ahead = model.curves(data, P, sol, c.t + step)
        behind = model.curves(data, P, sol, c.t - step)
        slope = (ahead[c.name] - behind[c.name]) / (2 * step)
        r2 = (c.y - m[0]) ** 2
        if time_error is None:
            (sf2, st2), _ = nnls(np.column_stack([np.ones_like(r2), slope**2]), r2)
        else:
            st2 = float(time_error) ** 2
            sf2 = max(float(np.mean(r2 - slope**2 * st2)), 0.0)
        floor = 1e-6 * float(np.max(np.abs(c.y)))
        sigma = np.sqrt(np.maximum(sf2 + slope**2 * st2, floor**2))
        chans.append(dataclasses.replace(c, sigma=sigma))
        parts.append(f"{c.name}: σ_F = {math.sqrt(sf2):.3g} N, σ_t = {math.sqrt(st2):.3g} s")
    note = (
        "digitised points weighed by their effective variance σ_F² + (F′·σ_t)² (clicks off in "
        "force and in time; Orear 1982): " + "; ".join(parts)
    )
    return dataclasses.replace(data, channels=tuple(chans)), note


def _fitted_sensor(fit):
    """The fit's sensor with the mode and the discharge at their fitted values."""
    spec = fit.data.sensor
    v = fit.values
    fitted = {k: v[k] for k in ("resonance", "damping_ratio", "discharge") if k in fit.vary}
    return dataclasses.replace(spec, **fitted) if fitted else spec


def _geometry(fit, scene) -> dict | None:
    """On a curved fixed target, what the contact normal's turn over the cap (which the
    model ignores) moves e_n and e_t by at the fitted e and μ
    (:func:`pipeline.simulate.curved.geometry_error`), each judged against the uncertainty
    of the parameter it biases (a bias of one standard error already pulls a 95 %
    interval's coverage under 85 %): e_n against e's standard error (``tol``), e_t against
    what μ's relative standard error moves it by — e_t = 1 − (1 + 1/κ)·Pt/(m·v_t0) with
    Pt ∝ μ while the contact slides, so (1 − e_t)·σ_μ/μ (``tol_t``) — both at least 1e-3.
    Where μ is bounded only from below (the contact sticks) e_t is not judged: its change
    then moves the spring's stiffness, which the turn's own curvature term (δ/r) rivals.
    None on a flat or movable target.
    """
    if math.isinf(float(scene.target_radius)) or math.isfinite(float(scene.target_mass)):
        return None
    v, se = fit.values, fit.stderr
    e = v.get("e", fit.physics.get("e_n", math.nan))
    mu = v.get("mu", math.nan)
    if not (0.0 < e <= 1.0 and mu >= 0.0):
        return None

    def floor(x):
        return max(1e-3, x) if math.isfinite(x) else 1e-3

    tol = floor(se.get("e", math.nan) if "e" in fit.vary else 0.0)
    rel = se["mu"] / mu if "mu" in fit.vary and mu > 0 else math.inf
    e_t = fit.physics.get("e_t", math.nan)
    tol_t = floor((1.0 - e_t) * rel) if math.isfinite(rel) else math.inf
    # a normal impact turns nothing: geometry_error's zeros, at any valid e and μ, need no
    # scene of them (a copy, validated again)
    head_on = float(scene.v_t0) == 0 and math.isfinite(mu)
    try:
        at = scene if head_on else scene.replace(e=e, mu=mu)
        out = geometry_error(at, tol=tol, normal=fit.model.normal)
    except (InputError, RuntimeError):
        return None
    return {**out, "tol_t": tol_t, "exceeds": bool(out["e_n"] > tol or out["e_t"] > tol_t)}


def _warm_start(fit, model, vary) -> dict:
    """Starting values of ``model``'s fit of the same record from ``fit``'s optimum (the
    verdict's fits: inputs taken as exact, another law, another filter order), for the
    parameters in ``vary``.

    The same law: ``fit``'s contact parameters. Another law: its pulse started where
    ``fit``'s lies — first the same restitution (every law's percussion is (1 + e)·m*·v0)
    and the time scale and onset that give the same centroid and RMS width (the moments
    :func:`_start` matches on the record), then the restitution, time scale and onset whose
    pulse is closest to the fitted, noise-free one in least squares
    (:func:`_shape_match`; E* ∝ T^(−5/2) at one speed): the law's own fit then starts a
    fraction of a standard error from its optimum. μ and ``kt_scale`` as fitted. Another
    filter order delays the pulse differently: the onset moves by the difference of the
    delays."""
    theta = dict(zip(fit.names, (float(v) for v in fit.theta), strict=True))
    out = {n: theta[n] for n in ("E_eff", "e", "alpha", "mu", "kt_scale", "t0") if n in theta}
    if model.normal != fit.normal and fit.normal is not None and model.normal is not None:
        e = float(fit.physics["e_n"]) if "alpha" in fit.names else theta["e"]
        e = min(max(e, E_MIN), 1.0)
        mean, width, _ = _pulse_moments(fit.normal, e, fit.model.n_steps)
        mean_l, width_l, _ = _pulse_moments(model.normal, e, model.n_steps)
        lam = width / width_l
        e_l, lam, shift = _shape_match(
            fit.model, fit.normal, e, model.normal, lam, mean - mean_l * lam, "e" in vary
        )
        ds, T, Fs, v0 = (float(a[0]) for a in fit.model.scales(fit.data, fit._P()))
        out.update(e=e_l, E_eff=theta["E_eff"] * lam**-2.5, t0=theta["t0"] + shift * T)
    return {n: v for n, v in out.items() if n in vary}


def _stated_start(fit, vary) -> dict:
    """Starting values of ``fit``'s model refitted with its inputs taken as exact (the
    verdict's own law): ``fit``'s parameters in ``vary`` moved to where the systematics
    back at their stated values put them, linearised — δc = −(J_cᵀJ_c)⁻¹J_cᵀ(r + J_s·Δs),
    J the fit's Jacobian on the data's rows, c the contact parameters, Δs the systematics'
    steps back — so that the refit starts a small fraction of a standard error from its
    optimum. ``fit``'s own values where a systematic has no stated value (a mode the screen
    found), where the step is beyond :data:`_LINEAR_REACH` standard errors (a wrong
    model's systematics move far, beyond the linearisation's reach), and for a parameter
    without a standard error (bound on one side only)."""
    theta = dict(zip(fit.names, (float(v) for v in fit.theta), strict=True))
    start = {n: theta[n] for n in vary}
    p = fit.problem
    names = [fit.names[i] for i in p.vary]
    held = [n for n in names if n not in vary]
    if not held or any(n not in fit.priors for n in held):
        return start
    n = p.n_data
    J = p.jacobian(fit.theta)[:n]
    scale = np.linalg.norm(J, axis=0)  # the columns' units differ by 10¹⁵ (Pa, s)
    free = [k for k in vary if k in names and scale[names.index(k)] > 0]
    c = [names.index(k) for k in free]
    step = np.array([fit.priors[k][0] - theta[k] for k in held])
    rhs = p.residual(fit.theta)[:n] + J[:, [names.index(k) for k in held]] @ step
    dc = -np.linalg.lstsq(J[:, c] / scale[c], rhs, rcond=None)[0] / scale[c]
    stderr = fit.stderr  # a property worked out at each call
    se = np.array([stderr.get(k, math.nan) for k in free])
    known = np.isfinite(se)  # a parameter bound on one side only keeps its value
    if not np.all(np.abs(dc[known]) <= _LINEAR_REACH * se[known]):
        return start
    moved = {k: start[k] + float(d) for k, d, ok in zip(free, dc, known, strict=True) if ok}
    return {**start, **moved}


#: The largest step, in standard errors, :func:`_stated_start` takes from the linearisation.
_LINEAR_REACH = 3.0


def _shape_match(model, law, e, other, lam, shift, free_e) -> tuple[float, float, float]:
    """(e′, λ, c): ``other``'s dimensionless pulse f′((τ − c)/λ; e′)/λ closest in least
    squares to ``law``'s f(τ; e) (both on ``model``'s steps; τ in δ*/v0 of ``law``'s pulse),
    from λ and c given and e′ = e (e′ held there unless ``free_e``): the other law's pulse
    as the record shows it, its time scale λ·T and onset c·T from ``law``'s T and onset
    (force × time = m*·v0 for both, so f′ scales as 1/λ). Two Gauss–Newton steps on a
    grid of 2·n_steps instants, f′ linear in e′ between the pulses at e and e ± 0.01 (one
    table lookup); kept where they lower the misfit. A start, not a fit: the law's fit
    refines it."""
    n = model.n_steps
    tau, target = _shape_target(law, e, n)
    h = (-0.01 if e + 0.01 > 1.0 else 0.01) if free_e else 0.0
    sol = Solution(normal_pulse(other, [e, e + h], n), None, np.array([0, 1]))
    table = _force_table(sol, False, sol.pulse.tau_c[:, None] / n)  # once for every call

    def fitted(p, jacobian=True):  # p = (e′ as a fraction of the step h, λ, c): the model
        t, lam_, c = p  # and its Jacobian, both pulses at the same instants
        arg = (tau - c) / lam_
        nd = 2 if jacobian else 0
        out = model._true_forces(sol, arg[None, :], False, nderiv=nd, table=table)
        f = out[0]
        m = (f[0] + t * (f[1] - f[0])) / lam_
        if not jacobian:
            return m, None
        g = out[2]
        rate = (g[0] + t * (g[1] - g[0])) / lam_**2
        return m, np.stack([(f[1] - f[0]) / lam_, -m / lam_ - arg * rate, -rate])

    cols = [0, 1, 2] if free_e else [1, 2]
    lo, hi = sorted(((E_MIN - e) / h, (1.0 - e) / h)) if h else (0.0, 0.0)
    start = p = np.array([0.0, lam, shift])
    chi2 = None
    for _ in range(2):
        m, J = fitted(p)
        r = target - m
        chi2 = float(r @ r) if chi2 is None else chi2
        p = p.copy()
        p[cols] += np.linalg.lstsq(J[cols].T, r, rcond=None)[0]
        p[0] = min(max(p[0], lo), hi)  # e′ in [E_MIN, 1]
        if not p[1] > 0:
            return e, lam, shift
    r = target - fitted(p, jacobian=False)[0]
    if not float(r @ r) < chi2:
        p = start
    return e + p[0] * h, float(p[1]), float(p[2])


@functools.lru_cache(maxsize=64)
def _shape_target(law, e, n_steps) -> tuple[np.ndarray, np.ndarray]:
    """(τ, f(τ; e)): ``law``'s dimensionless pulse at restitution ``e`` on the grid of
    :func:`_shape_match`, 2·n_steps instants from a quarter contact before it to half a
    contact after (kept: the verdict matches every other law to the same pulse)."""
    base = normal_pulse(law, e, n_steps)
    tc = float(base.tau_c[0])
    tau = np.linspace(-0.25 * tc, 1.5 * tc, 2 * n_steps + 1)
    sol = Solution(base, None, np.zeros(1, int))
    target = ForwardModel(law, "none", "total", n_steps)._true_forces(sol, tau[None, :], False)
    for a in (tau, target[0][0]):
        a.flags.writeable = False
    return tau, target[0][0]


@functools.lru_cache(maxsize=1024)
def _pulse_moments(law, e, n_steps) -> tuple[float, float, float]:
    """(centroid, RMS width, instant of the peak) of ``law``'s dimensionless pulse at
    restitution ``e`` [δ*/v0], on the fit's table (kept: a record's fits and the verdict's
    start from the same few restitutions)."""
    pul = normal_pulse(law, e, n_steps)
    tau = np.linspace(0.0, pul.tau_c[0], pul.n_steps + 1)
    _, mean, width = _moments(tau, pul.f[0])
    return mean, width, float(tau[np.argmax(pul.f[0])])


def _diagnosed(fit, record, scene, vary, options, t_begin, data) -> ContactFit:
    """``fit`` with its model spread and verdict (pipeline.fit.verdict): the other laws'
    fits, and the other filter orders' where the filter shapes the pulse (or the fit is
    poor). Every one of them fits the record as prepared for ``fit`` (``data``) from a
    start at ``fit``'s optimum (:func:`_warm_start`); the tables' fits, with the inputs
    taken as exact and read for their AIC and values alone, are lean (:func:`fit_model`)."""
    quiet = {k: v for k, v in options.items() if k not in ("n_boot", "seed", *_PREPARE)}
    m = fit.model
    spec = data.sensor
    if fit.dynamics.get("what"):  # the others are judged with the dynamics found, as stated
        data = fit.data.with_sensor(_fitted_sensor(fit))
        spec = data.sensor
        held = {k: fit.values[k] for k in SHIFT_PARAMS if k in fit.vary}
        quiet["start"] = {**(quiet.get("start") or {}), **held}

    def refit(model, start_from=fit, order=None, warm=None, lean=False, **extra):
        alt_vary = tuple("e" if v == "alpha" and model.normal != m.normal else v for v in vary)
        warm = _warm_start(start_from, model, alt_vary) if warm is None else warm
        seen = data
        if order is not None:
            seen = data.with_sensor(dataclasses.replace(spec, filter_order=order, notes=()))
            if "t0" in warm:  # another order delays the pulse by another time
                warm["t0"] += start_from.data.sensor.delay() - seen.sensor.delay()
        opts = {**quiet, **extra, "start": {**quiet.get("start", {}), **warm}}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", PipelineWarning)
            try:
                return fit_model(
                    record, scene, model, alt_vary, n_boot=0, data=seen, lean=lean, **opts
                )
            except InputError:
                return None

    laws = alternative_laws(m.normal)
    orders = alternative_orders(fit)
    as_exact = {"lean": True, "systematics": {}}  # the tables' fits (model_spread)
    own = refit(m, warm=_stated_start(fit, vary), **as_exact) if laws or orders else None
    exact = {m.normal: own} if laws else {}
    for law in laws:
        other = ForwardModel(law, m.tangential, m.history, m.n_steps)
        exact[law] = refit(other, own or fit, **as_exact)
    exact = {k: f for k, f in exact.items() if f is not None}
    spread, table = model_spread(fit, exact) if m.normal in exact else ({}, {})
    # the filter orders, where the filter shapes the pulse: their spread adds to the laws'
    by_order = {spec.filter_order: own} if orders else {}
    for k in orders:
        by_order[k] = refit(m, own or fit, order=k, **as_exact)
    by_order = {k: f for k, f in by_order.items() if f is not None}
    order_table = {}
    if spec.filter_order in by_order:
        extra, order_table = model_spread(fit, by_order, own=spec.filter_order)
        spread = {n: math.hypot(spread.get(n, 0.0), extra.get(n, 0.0)) for n in spread | extra}

    def refit_order(order, law=None):
        if not spec.filtered:
            return None
        if law in (None, m.normal):
            return refit(m, by_order.get(order, fit), order=order)
        other = ForwardModel(law, m.tangential, m.history, m.n_steps)
        return refit(other, exact.get(law, fit), order=order)

    def refit_law(law):
        return refit(ForwardModel(law, m.tangential, m.history, m.n_steps), exact.get(law, fit))

    fit = dataclasses.replace(fit, model_spread=spread, alternatives=table)
    verdict = diagnose(
        fit,
        table,
        orders=order_table,
        refit_order=refit_order,
        refit_law=refit_law,
        geometry=(geometry := _geometry(fit, scene)),
    )
    verdict["filter_orders"] = order_table
    verdict["geometry"] = geometry
    notes = fit.notes + tuple(verdict["messages"].values())
    return dataclasses.replace(
        fit, verdict=verdict, notes=notes, cost_s=time.perf_counter() - t_begin
    )
