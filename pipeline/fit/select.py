r"""The cheapest model a record needs: :func:`select_model` → :class:`ModelSelection`.

The tangential ladder, cheapest first (docs/theory.md):

``"rigid"``
    Rigid bodies (Routh, Coulomb friction): the impact is instantaneous, the percussions
    :math:`P_n = (1+e)\,m^* v_{n0}` and :math:`P_t = \min(\mu P_n,\; m_t s_0)` (docs/theory.md
    §3) are delivered at t0, and the record shows them as the sensor's impulse response
    (with no known filter, spread over one sample interval). Parameters e, μ, t0. It can
    only be adequate for a record that does not resolve the contact (a contact shorter
    than the sensor's rise time); on any record that does, its residuals say so.
``"coulomb"``
    A compliant normal law with Coulomb friction and no tangential compliance: Routh's
    broken line on the compliant pulse. Parameters E*, e (damped laws), μ, t0.
``"mindlin"``
    The same with Mindlin's tangential spring (``kt_scale``), which lets the tangential
    force reverse (Maw, Barber & Fawcett 1976). Parameters E*, e, μ, ``kt_scale``, t0.

and, for the compliant rungs, the normal laws: elastic Hertz (no damping parameter), the
Hunt–Crossley family, Hertz with a linear dashpot, viscoelastic, and Thornton's
elastic–perfectly-plastic law (its loss is plastic work, not damping: a metal struck past
its yield speed, :mod:`pipeline.contact.plastic`). The Coulomb rung tries the elastic, the
default damped and the plastic law; the Mindlin rung every law.

**The rule.** Every candidate is fitted (:func:`pipeline.fit.fit_contact`'s model, the
inputs taken as exact and no bootstrap, so that the candidates compare like for like). A
candidate is *adequate* when it passes the misfit test every fit uses
(:func:`pipeline.fit.procedure.misfit`: χ²_ν against its spread, the runs test on each
channel's residual signs; at most 1.5 % false alarms on records the model describes).
The candidates of one ladder rung form a complexity class; within it they are ranked by
AIC, with Akaike weights :math:`w_k \propto e^{-\Delta_k/2}` (Burnham & Anderson 2002).
The chosen class is the simplest whose best candidate is adequate (rigid → Coulomb →
Mindlin); where none is, the class of the best AIC overall. The chosen model is that
class's best candidate, refitted with the caller's options (its systematics, the block
bootstrap, the verdict), and :attr:`ModelSelection.averaged` averages the class's
candidates by their weights: the values :math:`\bar\theta = \sum_k w_k\theta_k` and a
``model`` term :math:`\sqrt{\sum_k w_k(\theta_k - \bar\theta)^2}` in the budget, so
the intervals include the spread between laws the data cannot tell apart (two laws of
equal weight and different E* widen E*'s interval to both).

References
----------
N. Maw, J. R. Barber, J. N. Fawcett, Wear 38:101 (1976),
doi:10.1016/0043-1648(76)90201-7.
H. Akaike, IEEE Trans. Autom. Control 19:716 (1974), doi:10.1109/TAC.1974.1100705.
K. P. Burnham, D. R. Anderson, *Model Selection and Multimodel Inference*, 2nd ed.,
Springer (2002), doi:10.1007/b97636, §4.2 (Akaike weights), §6.3 (the averaged estimate's
unconditional variance).
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass

import numpy as np
from scipy import special

from .._json import json_ready
from ..errors import InputError, PipelineWarning
from ..precision import model_words
from .contact import DEFAULT_VARY, ContactFit, fit_contact, fit_model
from .forward import _I, ANALYTIC, SYSTEMATIC_PARAMS, ForwardModel, RecordData, weighted_residuals
from .result import _cut_words, in_domain, kind_of
from .verdict import akaike_weights

__all__ = [
    "ModelSelection",
    "AveragedFit",
    "select_model",
    "LADDER",
    "DEFAULT_CANDIDATES",
    "RigidModel",
]

LADDER = ("rigid", "coulomb", "mindlin")
#: (ladder rung, normal law) fitted by default, in order of preference among equals
DEFAULT_CANDIDATES = (
    ("rigid", None),
    ("coulomb", "hertz"),
    ("coulomb", "hunt_crossley"),
    ("coulomb", "thornton"),
    ("mindlin", "hertz"),
    ("mindlin", "hunt_crossley"),
    ("mindlin", "hertz_dashpot"),
    ("mindlin", "viscoelastic"),
    ("mindlin", "thornton"),
)


class RigidModel:
    """Rigid-body impact seen by the sensor (module notes): impulses at t0.

    Same interface as :class:`pipeline.fit.forward.ForwardModel` for the fitting engine.
    """

    normal = None
    tangential = "rigid"
    history = ""
    n_steps = 0
    channels = ("Fn", "Ft")
    name = "rigid"

    def solve(self, datas, Ps):
        return [None for _ in Ps]

    def _impulses(self, data: RecordData, P):
        v0 = P[:, _I["speed"]] * data.cos_a
        pn = (1.0 + P[:, _I["e"]]) * data.m_eff * v0
        s0 = np.abs(data.slip0(P[:, _I["speed"]]))
        pt = np.minimum(P[:, _I["mu"]] * pn, data.m_eff * s0 / data.lam)
        return pn, pt

    @staticmethod
    def _kernel(data: RecordData, t, t0):
        """The sensor's response to a unit impulse at t0, and its time derivative [1/s]."""
        from scipy import signal

        tau = t[None, :] - t0[:, None]
        spec = data.sensor
        if spec.filtered:
            b, a = signal.butter(spec.filter_order, 2 * np.pi * spec.bandwidth, analog=True)
            r, p, _ = signal.residue(b, a)
            ts = np.maximum(tau, 0.0)[..., None]
            ex = np.exp(p * ts)
            g = np.where(tau >= 0, np.real(np.sum(r * ex, axis=-1)), 0.0)
            dg = np.where(tau >= 0, np.real(np.sum(r * p * ex, axis=-1)), 0.0)
            return g, dg
        dt = float(np.median(np.diff(t))) if t.size > 1 else 1.0
        g = np.maximum(0.0, 1.0 - np.abs(tau) / dt) / dt
        dg = np.where(np.abs(tau) < dt, -np.sign(tau) / dt**2, 0.0)
        return g, dg

    def predict(self, data, P, sol=None, nderiv=0, analytic=ANALYTIC):
        pn, pt = self._impulses(data, P)
        C = data.sensor.crosstalk
        out, der = [], []
        for ch in data.channels:
            g, dg = self._kernel(data, ch.t, P[:, _I["t0"]])
            row = {"Fn": 0, "Ft": 1}[ch.name]
            if C is None:
                w = pn if ch.name == "Fn" else pt
            else:
                w = C[row, 0] * pn + C[row, 1] * pt
            out.append(w[:, None] * g)
            if nderiv:
                b = slice(0, nderiv)
                # only t0 moves an impulse's response (the other analytic parameters are
                # the compliant models'; a rigid fit varies e, μ and t0)
                d = np.zeros((g[b].shape[0], len(analytic), g.shape[1]))
                if "t0" in analytic:
                    d[:, analytic.index("t0")] = -w[b, None] * dg[b]
                der.append(d)
        return (out, der) if nderiv else out

    def residuals(self, datas, Ps, nderiv=None, analytic=None):
        out, ders = [], []
        for i, (d, P) in enumerate(zip(datas, Ps, strict=True)):
            nd = 0 if nderiv is None else nderiv[i]
            pred = self.predict(d, P, None, nd, ANALYTIC if analytic is None else analytic[i])
            if nd:
                pred, der = pred
                ders.append(weighted_residuals(d, der, derivative=True))
            out.append(weighted_residuals(d, pred))
        sols = [None] * len(Ps)
        return (out, sols, ders) if nderiv is not None else (out, sols)

    def physics(self, data, P, sol=None) -> dict:
        pn, pt = (float(x[0]) for x in self._impulses(data, P[:1]))
        sc = data.scene
        vt0 = float(sc.v_t0)
        return {
            "t_c": 0.0,
            "F_max": math.inf,
            "delta_max": 0.0,
            "e_n": float(P[0, _I["e"]]),
            "Pn_final": pn,
            "Pt_final": pt,
            "e_t": 1.0 - pt / (data.m_eff * vt0) if vt0 else math.nan,
            "omega": float(sc.spin) + pt / (float(sc.kappa) * float(sc.m) * float(sc.radius)),
            "regime": "sliding" if P[0, _I["mu"]] * pn < pt * (1 + 1e-12) else "sticking",
            "slide_share": 1.0,
        }

    def curves(self, data, P, sol, t):
        z = np.zeros(np.asarray(t).shape)
        return {"Fn": z, "Ft": z}


@dataclass(frozen=True, eq=False)
class AveragedFit:
    """The model-averaged contact parameters of a :class:`ModelSelection` (module notes).

    Attributes
    ----------
    values : dict — {name: averaged value}: the chosen fit's value shifted by the weighted
        mean offset of the class's candidates
    weights : dict — {normal law: Akaike weight} within the chosen class
    fit : ContactFit — the chosen candidate's full fit (its systematics and bootstrap)
    model_spread : dict — {name: σ} spread of the candidates about the average
    """

    values: dict
    weights: dict
    fit: ContactFit
    model_spread: dict

    @property
    def budget(self) -> dict:
        """The chosen fit's budget with the class's spread as its ``model`` term."""
        out = {}
        for name, row in self.fit.budget.items():
            row = dict(row)
            if name in self.model_spread:
                row["model"] = self.model_spread[name]
                row["total"] = math.sqrt(
                    sum(v * v for k, v in row.items() if k != "total" and np.isfinite(v))
                )
            out[name] = row
        return out

    def ci(self, level: float = 0.95, kind: str = "total") -> dict:
        """Intervals {name: (lo, hi)}: the chosen fit's
        (:meth:`~pipeline.fit.result.FitResult.ci`), moved to the averaged value and widened
        by the class's spread in place of its own model term."""
        base = self.fit.ci(level, kind="stat")
        z = float(special.ndtri(0.5 + level / 2.0))
        out = {}
        for name, (lo, hi) in base.items():
            if name not in self.values or not (np.isfinite(lo) and np.isfinite(hi)):
                out[name] = (lo, hi)
                continue
            extra = 0.0
            if kind == "total" and name in self.budget:
                row = self.budget[name]
                extra = math.sqrt(sum(x * x for k, x in row.items() if k not in ("stat", "total")))
            out[name] = in_domain(
                name, self.values[name], lo, hi, z * extra, centre=self.fit.values[name]
            )
        return out

    @property
    def stderr(self) -> dict:
        return {n: row["total"] for n, row in self.budget.items()}

    def table(self, level: float = 0.95, *, style: bool = False):
        """The averaged parameters for a person to read (as
        :meth:`pipeline.fit.result.FitResult.table`): rounded to their combined standard
        uncertainty, the budget as shares (its ``model`` term the laws' spread), the
        verdict — the laws' weights and the chosen fit's — in words."""
        from .. import precision

        budget, ci = self.budget, self.ci(level)
        rows = [
            {"name": n, "value": v, "stderr": budget.get(n, {}).get("total", math.nan)}
            for n, v in self.values.items()
            if kind_of(n) == "contact"
        ]
        for r in rows:
            r["ci"] = ci.get(r["name"])
        for n in self.fit.lower_only + self.fit.upper_only:
            side = "lower" if n in self.fit.lower_only else "upper"
            rows.append({"name": n, "value": self.fit.values[n], "status": side})
        text, details = self.fit._verdict_words()
        laws = sorted(self.weights.items(), key=lambda kv: -kv[1])
        weights = ", ".join(f"{model_words(law)} {w:.2f}" for law, w in laws if w >= 0.005)
        if any(w < 0.005 for _, w in laws):
            weights += ", the others < 0.01"
        df = precision.parameter_table(
            rows,
            {r["name"]: budget[r["name"]] for r in rows if r["name"] in budget},
            verdict=f"{text} Averaged over the laws by their Akaike weights ({weights}).",
            details=[*details, *_cut_words(rows, self.fit.normal)],
            level=level,
        )
        return precision.styled(df) if style else df


@dataclass(frozen=True, eq=False)
class ModelSelection:
    """The candidates fitted to one record and the one chosen (:func:`select_model`).

    Attributes
    ----------
    table : pandas.DataFrame — one row per candidate: ``model`` (ladder rung), ``normal``,
        ``parameters`` (fitted values, text), ``k``, ``chi2``, ``redchi``, ``aic``, ``bic``,
        ``delta_aic``, ``rms`` [N] (RMS residual over both channels), ``noise`` [N] (RMS of
        the channels' σ), ``runs_z`` (the worse channel's runs-test z), ``white`` (bool:
        adequate, the misfit test passes), ``verdict`` (``"ok"`` or the misfit's reasons),
        ``weight`` (Akaike weight within its rung), ``cost_s`` [s], ``chosen`` (bool)
    chosen : str — the chosen ladder rung
    chosen_normal : str or None — its normal law
    fit : ContactFit — the chosen candidate's fit (with the bootstrap)
    fits : dict — every candidate's fit, keyed by (rung, normal)
    rule : str — why it was chosen
    averaged : AveragedFit — the chosen rung's laws averaged by their weights
    """

    table: object
    chosen: str
    chosen_normal: str | None
    fit: ContactFit
    fits: dict
    rule: str
    averaged: AveragedFit | None = None

    def report(self) -> str:
        cols = ["model", "normal", "k", "redchi", "delta_aic", "weight", "rms", "noise", "white"]
        df = self.table[cols + ["chosen"]].copy()
        lines = [
            f"Model selection: chosen {self.chosen!r}"
            + (f" with normal law {self.chosen_normal!r}" if self.chosen_normal else "")
            + f" — {self.rule}",
            df.to_string(index=False, float_format=lambda x: f"{x:.4g}"),
        ]
        return "\n".join(lines)

    def summary(self) -> dict:
        return json_ready(
            {
                "chosen": self.chosen,
                "chosen_normal": self.chosen_normal,
                "rule": self.rule,
                "table": self.table.to_dict(orient="records"),
                "fit": self.fit.summary(),
                "averaged": None
                if self.averaged is None
                else {
                    "values": self.averaged.values,
                    "weights": self.averaged.weights,
                    "ci95": {k: list(v) for k, v in self.averaged.ci().items()},
                },
            }
        )


def select_model(record, scene, *, candidates=None, **options) -> ModelSelection:
    """Fit the ladder of models to one record and choose the cheapest adequate one.

    Parameters
    ----------
    record : xarray.Dataset — a force record with ``Fn`` and ``Ft`` [N]
    scene : Scene — as :func:`pipeline.fit.fit_contact` (μ and e may be unknown)
    candidates : sequence of (rung, normal), optional
        Rungs of :data:`LADDER` with a normal law (None for ``"rigid"``); default
        :data:`DEFAULT_CANDIDATES`.
    **options
        Passed to every fit (:func:`pipeline.fit.fit_contact`'s options); ``n_boot`` (default
        200) and ``seed`` apply to the refit of the chosen model only.

    Returns
    -------
    ModelSelection

    Notes
    -----
    The rule (module notes): the simplest candidate whose residuals are white at the noise
    level, or within ΔAIC ≤ 2 of the best.
    """
    cands = list(DEFAULT_CANDIDATES if candidates is None else candidates)
    if not cands:
        raise InputError("select_model: no candidates")
    for rung, normal in cands:
        if rung not in LADDER:
            raise InputError(f"select_model: unknown rung {rung!r}; choose from {LADDER}")
        if (rung == "rigid") != (normal is None):
            raise InputError(
                "select_model: the 'rigid' rung has no normal law (None); the others need one"
            )
    opts = dict(options)
    n_boot = int(opts.pop("n_boot", 200))
    seed = int(opts.pop("seed", 0))
    history = opts.pop("history", "total")
    n_steps = int(opts.pop("n_steps", 128))
    systematics = opts.pop("systematics", None)
    fits, rows = {}, []
    for rung, normal in cands:
        t0 = time.perf_counter()
        model, vary = _model(rung, normal, history, n_steps)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", PipelineWarning)
            f = fit_model(record, scene, model, vary, n_boot=0, systematics={}, **opts)
        cost = time.perf_counter() - t0
        fits[(rung, normal)] = f
        res = f.residuals()
        sig = [c.sigma for c in f.data.channels]
        rz = min((z for z in f.misfit.runs_z.values() if np.isfinite(z)), default=math.nan)
        raw = np.concatenate([r * s for r, s in zip(res, sig, strict=True)])
        rows.append(
            {
                "model": rung,
                "normal": normal,
                "parameters": ", ".join(
                    f"{p}{'≥' if p in f.lower_only else '≤' if p in f.upper_only else '='}"
                    f"{f.values[p]:.5g}"
                    for p in f.vary
                ),
                "k": f.nvarys,
                "chi2": f.chi2,
                "redchi": f.redchi,
                "aic": f.aic,
                "bic": f.bic,
                "rms": float(np.sqrt(np.mean(raw**2))),
                "noise": float(np.sqrt(np.mean([c.sigma_rms**2 for c in f.data.channels]))),
                "runs_z": rz,
                "white": bool(f.misfit.ok),
                "verdict": "ok" if f.misfit.ok else "; ".join(f.misfit.reasons),
                "cost_s": cost,
            }
        )
    import pandas as pd

    df = pd.DataFrame(rows)
    df["delta_aic"] = df["aic"] - df["aic"].min()
    df["weight"] = 0.0
    for rung in LADDER:
        sel = df.index[df["model"] == rung]
        if len(sel):
            w = akaike_weights({i: df.loc[i, "aic"] for i in sel})
            df.loc[sel, "weight"] = [w[i] for i in sel]
    best = {r: df[df["model"] == r]["aic"].idxmin() for r in LADDER if (df["model"] == r).any()}
    adequate = [r for r in LADDER if r in best and df.loc[best[r], "white"]]
    if adequate:
        rung = adequate[0]
        why = (
            f"the simplest rung whose best law (by AIC, Akaike weight "
            f"{df.loc[best[rung], 'weight']:.2f}) passes the misfit test"
        )
    else:
        rung = df.loc[df["aic"].idxmin(), "model"]
        why = "no candidate passes the misfit test; the rung of the best AIC"
    pick = best[rung]
    normal = df.loc[pick, "normal"]
    normal = (
        None if normal is None or (isinstance(normal, float) and math.isnan(normal)) else normal
    )
    df["chosen"] = df.index == pick
    model, vary = _model(rung, normal, history, n_steps)
    full = dict(opts, n_boot=n_boot, seed=seed)
    if rung == "rigid":
        chosen = fit_model(record, scene, model, vary, **full)
    else:
        chosen = fit_contact(
            record,
            scene,
            normal=normal,
            tangential=rung,
            vary=vary,
            systematics=systematics,
            history=history,
            n_steps=n_steps,
            **full,
        )
    averaged = _average(chosen, {(r, n): f for (r, n), f in fits.items() if r == rung}, df, rung)
    return ModelSelection(df, rung, normal, chosen, fits, why, averaged)


def _model(rung, normal, history, n_steps):
    if rung == "rigid":
        return RigidModel(), ("e", "mu", "t0")
    return ForwardModel(normal, rung, history, n_steps), DEFAULT_VARY(normal, rung)


def _average(chosen, fits, df, rung) -> AveragedFit:
    """The rung's candidates averaged by their Akaike weights (module notes)."""
    rows = df[df["model"] == rung]
    weights = {
        (rung, None if not isinstance(n, str) else n): float(w)
        for n, w in zip(rows["normal"], rows["weight"], strict=True)
    }
    own = fits[(rung, chosen.normal if rung != "rigid" else None)]
    values, spread = {}, {}
    for name in chosen.vary:
        if name in SYSTEMATIC_PARAMS or name in chosen.one_sided:
            continue
        have = {k: f.values[name] for k, f in fits.items() if name in f.values}
        mean = sum(weights[k] * v for k, v in have.items()) / sum(weights[k] for k in have)
        values[name] = chosen.values[name] + (mean - own.values[name])
        spread[name] = math.sqrt(sum(weights[k] * (v - mean) ** 2 for k, v in have.items()))
    laws = {("rigid" if k[1] is None else k[1]): w for k, w in weights.items()}
    return AveragedFit(values, laws, chosen, spread)
