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
Hunt–Crossley family, Hertz with a linear dashpot, viscoelastic.

**The rule.** Every candidate is fitted (:func:`pipeline.fit.fit_contact`, no bootstrap).
A candidate is *white* when its residuals are noise at the measured level: χ²_ν within
three standard deviations of 1 (≤ 1 + 3·√(2/(N − k))) and no channel's residual signs run
in long stretches (runs test z ≥ −2.326, α = 0.01). The chosen model is the simplest
candidate that is white **or** within ΔAIC ≤ 2 of the best AIC — simplest meaning lower on
the ladder, then fewer parameters, then earlier in ``candidates``. So a model is never
preferred for fitting better than the noise allows, and when none is white the data's
own ranking (AIC) decides among the near-best. The chosen fit is then refitted with the
block bootstrap for its intervals.

References
----------
N. Maw, J. R. Barber, J. N. Fawcett, Wear 38:101 (1976),
doi:10.1016/0043-1648(76)90201-7.
H. Akaike, IEEE Trans. Autom. Control 19:716 (1974), doi:10.1109/TAC.1974.1100705.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass

import numpy as np

from .._json import json_ready
from ..errors import InputError, PipelineWarning
from .contact import DEFAULT_VARY, ContactFit, fit_model
from .forward import _I, ANALYTIC, ForwardModel, RecordData, weighted_residuals

__all__ = ["ModelSelection", "select_model", "LADDER", "DEFAULT_CANDIDATES", "RigidModel"]

LADDER = ("rigid", "coulomb", "mindlin")
#: (ladder rung, normal law) fitted by default, in order of preference among equals
DEFAULT_CANDIDATES = (
    ("rigid", None),
    ("coulomb", "hertz"),
    ("coulomb", "hunt_crossley"),
    ("mindlin", "hertz"),
    ("mindlin", "hunt_crossley"),
    ("mindlin", "hertz_dashpot"),
    ("mindlin", "viscoelastic"),
)
_RUNS_Z = -2.326


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

    def predict(self, data, P, sol=None, nderiv=0):
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
                d = np.zeros((g[b].shape[0], len(ANALYTIC), g.shape[1]))
                d[:, ANALYTIC.index("t0")] = -w[b, None] * dg[b]
                der.append(d)
        return (out, der) if nderiv else out

    def residuals(self, datas, Ps, nderiv=None):
        out, ders = [], []
        for i, (d, P) in enumerate(zip(datas, Ps, strict=True)):
            nd = 0 if nderiv is None else nderiv[i]
            pred = self.predict(d, P, None, nd)
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


def _rank(c, order):
    rung, normal = c
    n_par = len(DEFAULT_VARY(normal, rung)) if rung != "rigid" else 3
    return (LADDER.index(rung), n_par, order)


@dataclass(frozen=True, eq=False)
class ModelSelection:
    """The candidates fitted to one record and the one chosen (:func:`select_model`).

    Attributes
    ----------
    table : pandas.DataFrame — one row per candidate: ``model`` (ladder rung), ``normal``,
        ``parameters`` (fitted values, text), ``k``, ``chi2``, ``redchi``, ``aic``, ``bic``,
        ``delta_aic``, ``rms`` [N] (RMS residual over both channels), ``noise`` [N] (RMS of
        the channels' σ), ``runs_z`` (the worse channel's runs-test z), ``white`` (bool),
        ``cost_s`` [s], ``chosen`` (bool)
    chosen : str — the chosen ladder rung
    chosen_normal : str or None — its normal law
    fit : ContactFit — the chosen candidate's fit (with the bootstrap)
    fits : dict — every candidate's fit, keyed by (rung, normal)
    rule : str — why it was chosen
    """

    table: object
    chosen: str
    chosen_normal: str | None
    fit: ContactFit
    fits: dict
    rule: str

    def report(self) -> str:
        cols = ["model", "normal", "k", "redchi", "delta_aic", "rms", "noise", "runs_z", "white"]
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
    history = opts.get("history", "total")
    n_steps = int(opts.get("n_steps", 128))
    fits, rows = {}, []
    for order, (rung, normal) in enumerate(cands):
        t0 = time.perf_counter()
        if rung == "rigid":
            model, vary = RigidModel(), ("e", "mu", "t0")
        else:
            model = ForwardModel(normal, rung, history, n_steps)
            vary = DEFAULT_VARY(normal, rung)
        fit_opts = {k: v for k, v in opts.items() if k not in ("history", "n_steps")}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", PipelineWarning)
            f = fit_model(record, scene, model, vary, n_boot=0, **fit_opts)
        cost = time.perf_counter() - t0
        fits[(rung, normal)] = f
        res = f.residuals()
        sig = [c.sigma for c in f.data.channels]
        rz = min((z for z in f.runs_z().values() if np.isfinite(z)), default=math.nan)
        n, k = f.n_data, f.nvarys
        white = f.redchi <= 1 + 3 * math.sqrt(2.0 / max(n - k, 1)) and not (rz < _RUNS_Z)
        raw = np.concatenate([r * s for r, s in zip(res, sig, strict=True)])
        rows.append(
            {
                "model": rung,
                "normal": normal,
                "parameters": ", ".join(
                    f"{p}={f.values[p]:.5g}" + ("+" if p in f.lower_only else "") for p in f.vary
                ),
                "k": k,
                "chi2": f.chi2,
                "redchi": f.redchi,
                "aic": f.aic,
                "bic": f.bic,
                "rms": float(np.sqrt(np.mean(raw**2))),
                "noise": float(np.sqrt(np.mean(np.square(sig)))),
                "runs_z": rz,
                "white": bool(white),
                "cost_s": cost,
                "_rank": _rank((rung, normal), order),
            }
        )
    import pandas as pd

    df = pd.DataFrame(rows)
    df["delta_aic"] = df["aic"] - df["aic"].min()
    eligible = df[df["white"] | (df["delta_aic"] <= 2.0)]
    pick = min(eligible.index, key=lambda i: df.loc[i, "_rank"])
    rung, normal = df.loc[pick, "model"], df.loc[pick, "normal"]
    normal = (
        None if normal is None or (isinstance(normal, float) and math.isnan(normal)) else normal
    )
    why = (
        "the simplest whose residuals are white at the noise level"
        if df.loc[pick, "white"]
        else "no candidate is white; the simplest within ΔAIC ≤ 2 of the best"
    )
    df["chosen"] = df.index == pick
    df = df.drop(columns="_rank")
    if rung == "rigid":
        model, vary = RigidModel(), ("e", "mu", "t0")
    else:
        model, vary = ForwardModel(normal, rung, history, n_steps), DEFAULT_VARY(normal, rung)
    fit_opts = {k: v for k, v in opts.items() if k not in ("history", "n_steps")}
    best = fit_model(record, scene, model, vary, n_boot=n_boot, seed=seed, **fit_opts)
    return ModelSelection(df, rung, normal, best, fits, why)
