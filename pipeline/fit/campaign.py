r"""Fit many records at once: shared parameters and the hypotheses a campaign can decide.

A lab measures angles × speeds × repeats. Some parameters are properties of the materials
and should be one number for the whole campaign (E*, and the damping or the friction law),
others belong to each impact (its onset t0; its tangential stiffness, which depends on the
surfaces' state). :func:`fit_campaign` fits all the records in one least-squares problem
(:mod:`pipeline.fit.engine`; lmfit drives it) with

- ``shared``: the parameters that are one number for all records (default E*); the others
  of ``E_eff``, ``kt_scale`` are fitted per record (``kt_scale_3`` is record 3's);
- ``mu_law``: ``"constant"`` (one μ) or ``"linear_vt0"``, μ_i = a + b·v_t0,i with the
  initial tangential speed of each impact [m/s], as Garland & Rogers (2009) found
  (parameters ``mu_a`` [-], ``mu_b`` [s/m]);
- ``damping``: ``"constant_e"`` (one restitution for every speed) or ``"constant_alpha"``
  (one material constant: c = α·v0 for the Hunt–Crossley family, so e falls as the speed
  rises; docs/theory.md). ``alpha`` is the law's material constant
  (:attr:`pipeline.contact.NormalLaw.material`): α [s/m] for the Hunt–Crossley family, the
  yield speed v_y [m/s] for Thornton's plastic law (e = e(v_y/v0) falls as v0^{-1/4}).

The hypotheses are fitted side by side (all four combinations by default) and
:meth:`CampaignFit.compare` tabulates them: χ², AIC = χ² + 2k, BIC = χ² + k·ln N (the noise
is measured, :mod:`pipeline.fit.result`), and for nested pairs (constant μ inside the linear
law: b = 0) the likelihood ratio Δχ², scaled by χ²_ν of the larger model when that exceeds 1,
with its χ²₁ p-value. The damping hypotheses are not nested (same number of parameters):
AIC and BIC decide, and ΔAIC > 10 is decisive (Burnham & Anderson 2002).

The fit is Levenberg–Marquardt on the Schur complement of the records' own parameters
(:mod:`pipeline.fit.blocks`): its cost grows linearly with the records (a dense Jacobian
over all records' samples grows with their square and its factorisation with their cube;
``solver="dense"`` keeps that path, which gives the same optimum). The records are
prepared once and kept compacted on disk (:mod:`pipeline.fit.store`), read back a chunk
at a time at each evaluation, so the fit's memory does not grow with the records beyond a
few kB of numbers each (their parameters, normal-equation blocks and misfit shares); an
``executor`` spreads the evaluations over processes. Starting values come
from each record's pulse moments (or a fit of each record alone, or the caller's values):
E* and ``kt_scale`` their medians, e or α from the records' restitutions, μ (or a, b) by
weighted least squares on the identifiable μ_i; each further hypothesis starts from the
records' parameters under the one before.

References
----------
M. J. Garland, R. J. Rogers, J. Appl. Mech. 76:031015 (2009), doi:10.1115/1.3086432.
K. P. Burnham, D. R. Anderson, *Model Selection and Multimodel Inference*, 2nd ed.,
Springer (2002), doi:10.1007/b97636.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field
from types import SimpleNamespace

import numpy as np
import xarray as xr

from .._json import json_ready
from ..contact import NORMAL_LAWS
from ..errors import InputError, PipelineWarning, PoorFitWarning
from ..io import load as read_record
from ..precision import hypothesis_words, plain
from ..scene import Scene
from . import store as store_module
from .blocks import solve_blocks
from .contact import DEFAULT_VARY, _start, e_of_alpha, fit_model
from .engine import Design
from .forward import ForwardModel, prepare
from .procedure import _bounds, _rec, base_name, misfit_of, run_fit, t0_bounds
from .result import FitResult
from .store import RecordStore, RecordSummary, in_order, pack, pack_chunk

__all__ = ["CampaignFit", "fit_campaign", "MU_LAWS", "DAMPING"]

MU_LAWS = ("constant", "linear_vt0")
DAMPING = ("constant_e", "constant_alpha")
_SHAREABLE = ("E_eff", "kt_scale")


class _Campaign(Design):
    """Global → per-record parameters for a campaign hypothesis (module notes), from the
    records' :class:`~pipeline.fit.store.RecordSummary` (no samples needed)."""

    def __init__(self, summary, law, shared, mu_law, damping, tangential, names=None):
        self.summary, self.law = summary, law
        self.mu_law, self.damping = mu_law, damping
        R = len(summary.names)
        # the per-record names (``t0_3``), made once for all of a campaign's hypotheses
        # (``names``: kind → tuple, filled here)
        names = {} if names is None else names
        self.own_names = {}  # kind → its per-record names, in the order of ``names``
        parts, scale = [], []
        self._where = {}  # shared name → index
        self._first = {}  # per-record kind → index of its record 0 (records in order)
        n = 0  # the next global index

        def add(name, sc, per_record=False):
            nonlocal n
            if per_record:
                self._first[name] = n
                if name not in names:
                    names[name] = tuple(f"{name}_{i}" for i in range(R))
                self.own_names[name] = names[name]
                parts.append(names[name])
                scale.append(np.full(R, sc) if np.ndim(sc) == 0 else np.asarray(sc, float))
                n += R
            else:
                self._where[name] = n
                parts.append((name,))
                scale.append([sc])
                n += 1

        add("E_eff", 1e9, "E_eff" not in shared)
        self.damp = n
        if law != "hertz":
            add(
                "alpha" if damping == "constant_alpha" else "e",
                1e-3 if damping == "constant_alpha" else 0.1,
            )
        if tangential == "none":
            self.mu = None
        elif mu_law == "constant":
            self.mu = [n]
            add("mu", 0.01)
        else:
            self.mu = [n, n + 1]
            add("mu_a", 0.01)
            add("mu_b", 0.01)
        self.kt = tangential == "mindlin"
        if self.kt:
            add("kt_scale", 0.1, "kt_scale" not in shared)
        add("speed", 0.1, True)
        add("t0", summary.duration, True)
        self.speed = slice(self._first["speed"], self._first["speed"] + R)
        self.t0 = slice(self._first["t0"], self._first["t0"] + R)
        self.names = tuple(n for part in parts for n in part)
        self.scale = np.concatenate([np.asarray(x, dtype=float) for x in scale])
        self.vt0 = summary.v_t0
        self._cols = None  # per-record column indices and constants, on first use

    def _index(self, name, i):
        """Global index of ``name`` (shared) or of record ``i``'s own ``name``."""
        return self._where[name] if name in self._where else self._first[name] + i

    def shared_index(self) -> list:
        """Global indices of the parameters every record depends on."""
        return sorted(self._where.values())

    def own_index(self) -> np.ndarray:
        """Per record (rows), the global indices of its own parameters (the same kinds for
        all, in the order of ``names``): (R, kinds) integers."""
        R = len(self.summary.names)
        first = sorted(self._first.values())
        return np.arange(R)[:, None] + np.array(first, dtype=int)[None, :]

    def local(self, theta, records=slice(None)):
        """Every record's local parameters, vectorised over records: e(α) for the
        Hunt–Crossley family computed once for all records and rows (one call of the law's
        closed form, not one per record). One (R, B, L) array: record i's (B, L) rows are
        its item i (no array object a record); ``records``: a slice of them only (the
        block solver's chunk)."""
        theta = np.atleast_2d(theta)
        B, R = theta.shape[0], len(self.summary.names)
        if self._cols is None:
            sm = self.summary
            self._cols = {
                "E": np.array([self._index("E_eff", i) for i in range(R)]),
                "kt": np.array([self._index("kt_scale", i) for i in range(R)]) if self.kt else None,
                "nominal": sm.nominal,
                "R_eff": sm.R_eff,
                "m_eff": sm.m_eff,
                "cos_a": sm.cos_a,
            }
        c = self._cols
        P = np.repeat(c["nominal"][records, None, :], B, axis=1)  # (records, B, L)
        P[:, :, 0] = theta[:, c["E"][records]].T
        P[:, :, 4] = theta[:, self.speed][:, records].T
        P[:, :, 5] = theta[:, self.t0][:, records].T
        if self.law == "hertz":
            P[:, :, 1] = 1.0
        elif self.damping == "constant_alpha":
            P[:, :, 1] = e_of_alpha(
                self.law,
                theta[:, self.damp][None, :],
                P[:, :, 0],
                P[:, :, 4],
                c["R_eff"][records, None],
                c["m_eff"][records, None],
                c["cos_a"][records, None],
            )
        else:
            P[:, :, 1] = theta[:, self.damp][None, :]
        if self.mu is None:
            P[:, :, 2] = 0.0
        elif len(self.mu) == 1:
            P[:, :, 2] = theta[:, self.mu[0]][None, :]
        else:
            a, b = theta[:, self.mu[0]][None, :], theta[:, self.mu[1]][None, :]
            P[:, :, 2] = np.maximum(a + b * self.vt0[records, None], 0.0)
        P[:, :, 3] = theta[:, c["kt"][records]].T if self.kt else 1.0
        return P


@dataclass(frozen=True, eq=False)
class CampaignFit(FitResult):
    """One joint fit of many records (:func:`fit_campaign`; docs/theory.md).

    Besides the attributes of :class:`~pipeline.fit.result.FitResult`:

    Attributes
    ----------
    mu_law, damping : str — the hypothesis of this fit
    shared : tuple of str — parameters shared by every record
    records : tuple of str — the records' names (``source`` attributes), in order
    model : pipeline.fit.forward.ForwardModel
    datas : sequence of pipeline.fit.forward.RecordData — the records as fitted, read back
        on access from the fit's temporary file (:class:`pipeline.fit.store.RecordStore`:
        each record's ``record`` keeps only its attrs)
    hypotheses : dict — every hypothesis fitted, ``(mu_law, damping)`` → CampaignFit
        (this one included)
    """

    mu_law: str = "constant"
    damping: str = "constant_e"
    shared: tuple = ()
    records: tuple = ()
    model: object = None
    datas: object = ()
    problem: object = None
    hypotheses: dict = field(default_factory=dict)

    def per_record(self):
        """Each record's parameters under this fit (pandas DataFrame, one row per record):
        E_eff [Pa], e, mu, kt_scale, speed [m/s], t0 [s], v_t0 [m/s], angle_deg."""
        import pandas as pd

        sm = self.problem.design.summary
        P = np.asarray(self.problem.design.local(self.theta[None, :]))[:, 0, :]  # (R, L)
        return pd.DataFrame(
            {
                "record": list(self.records),
                "angle_deg": np.asarray(sm.angle_deg, dtype=float),
                "speed": P[:, 4],
                "v_t0": np.asarray(sm.v_t0, dtype=float),
                "E_eff": P[:, 0],
                "e": P[:, 1],
                "mu": P[:, 2],
                "kt_scale": P[:, 3],
                "t0": P[:, 5],
            }
        )

    def compare(self):
        """Every hypothesis fitted, side by side (pandas DataFrame, best AIC first).

        Columns: ``mu_law``, ``damping``, ``k`` (varied parameters), ``chi2``, ``redchi``,
        ``aic``, ``bic``, ``delta_aic``, ``delta_bic`` (from the best), ``lr``, ``lr_p``
        (likelihood ratio against the same damping with constant μ, for the linear law),
        and the shared parameters' values.
        """
        import pandas as pd
        from scipy import stats

        hyp = self.hypotheses or {(self.mu_law, self.damping): self}
        rows = []
        for (ml, dm), f in hyp.items():
            row = {
                "mu_law": ml,
                "damping": dm,
                "k": f.nvarys,
                "chi2": f.chi2,
                "redchi": f.redchi,
                "aic": f.aic,
                "bic": f.bic,
                "lr": math.nan,
                "lr_p": math.nan,
            }
            if ml == "linear_vt0" and ("constant", dm) in hyp:
                small = hyp[("constant", dm)]
                lr = max(small.chi2 - f.chi2, 0.0) / max(1.0, f.redchi)
                row["lr"] = lr
                row["lr_p"] = float(stats.chi2.sf(lr, f.nvarys - small.nvarys))
            v = f.values
            for n in ("E_eff", "e", "alpha", "mu", "mu_a", "mu_b", "kt_scale"):
                if n in v:
                    row[n] = v[n]
            rows.append(row)
        df = pd.DataFrame(rows)
        df["delta_aic"] = df["aic"] - df["aic"].min()
        df["delta_bic"] = df["bic"] - df["bic"].min()
        return df.sort_values("aic").reset_index(drop=True)

    @property
    def best(self) -> CampaignFit:
        """The hypothesis with the lowest AIC."""
        hyp = self.hypotheses or {(self.mu_law, self.damping): self}
        return min(hyp.values(), key=lambda f: f.aic)

    def _verdict_words(self) -> tuple:
        """(the verdict in a sentence, [the hypotheses compared]) (:meth:`table`)."""
        text, details = super()._verdict_words()
        hyp = hypothesis_words(self.mu_law, self.damping, self.model.normal)
        text = f"Joint fit of {len(self.records)} records ({hyp}): " + text[0].lower() + text[1:]
        if len(self.hypotheses) > 1:
            df = self.compare()
            best = df.iloc[0]
            gap = f", ΔAIC = {plain(df['delta_aic'].iloc[1], 3)} to the next" if len(df) > 1 else ""
            details = [
                "best hypothesis by AIC: "
                f"{hypothesis_words(best['mu_law'], best['damping'], self.model.normal)}" + gap,
                *details,
            ]
        return text, details

    def report(self) -> str:
        lines = [
            f"Campaign fit of {len(self.records)} records: {self.model.name}, μ law "
            f"{self.mu_law!r}, damping {self.damping!r}, shared {', '.join(self.shared) or '-'}",
            f"  {self.n_data} samples, χ² = {self.chi2:.6g}, χ²_ν = {self.redchi:.4g}, "
            f"AIC = {self.aic:.6g}, BIC = {self.bic:.6g}" + (" — POOR FIT" if self.poor else ""),
            "  parameters (95 % intervals):",
            *self._param_lines(),
        ]
        if len(self.hypotheses) > 1:
            lines += ["", "  hypotheses (best AIC first):"]
            df = self.compare()
            for _, r in df.iterrows():
                lr = "" if not np.isfinite(r["lr"]) else f", LR {r['lr']:.3g} (p = {r['lr_p']:.2g})"
                lines.append(
                    f"    {r['mu_law']:>10s} / {r['damping']:<14s} k = {int(r['k']):2d}  "
                    f"χ² = {r['chi2']:.6g}  ΔAIC = {r['delta_aic']:8.2f}  "
                    f"ΔBIC = {r['delta_bic']:8.2f}{lr}"
                )
        if self.notes:
            lines += ["  notes:"] + [f"    - {n}" for n in self.notes]
        return "\n".join(lines)

    def summary(self) -> dict:
        return json_ready(
            {
                "records": list(self.records),
                "model": {"normal": self.model.normal, "tangential": self.model.tangential},
                "mu_law": self.mu_law,
                "damping": self.damping,
                "shared": list(self.shared),
                "parameters": self._summary_params(),
                "fit": self._summary_stats(),
                "compare": self.compare().to_dict(orient="records"),
                "per_record": self.per_record().to_dict(orient="records"),
            }
        )

    def to_dataset(self):
        """The per-record parameters on dimension ``record`` (xarray), summary in attrs."""
        import json

        import xarray as xr

        df = self.per_record().set_index("record")
        ds = xr.Dataset.from_dataframe(df)
        units = {"speed": "m/s", "v_t0": "m/s", "E_eff": "Pa", "t0": "s", "angle_deg": "deg"}
        for k in ds.data_vars:
            ds[k].attrs["units"] = units.get(k, "1")
        ds.attrs["summary_json"] = json.dumps(self.summary(), allow_nan=False)
        return ds


def _as_list(x, n, what):
    if isinstance(x, (list, tuple)):
        if len(x) != n:
            raise InputError(f"fit_campaign: {len(x)} {what} for {n} records")
        return list(x)
    return [x] * n


@dataclass(frozen=True)
class _Joint:
    """What a joint fit keeps of its problem: the design (per-record parameters) and the
    records (a :class:`~pipeline.fit.store.RecordStore`)."""

    design: Design
    datas: object


class _Parameters:
    """A joint fit's ``params``: its :class:`lmfit.Parameters` (values, ``vary``, ``stderr``
    from the covariance), built on first use and then kept. A fit holds its values and
    covariance as arrays; lmfit's Parameter objects of every record's own parameters would
    take some kB a record and hypothesis (docs/campaigns.md)."""

    def __init__(self, names, theta, varied, cov):
        self._of = (names, theta, varied, cov)
        self._built = None

    def _params(self):
        if self._built is None:
            import lmfit

            names, theta, varied, cov = self._of
            params, j = lmfit.Parameters(), 0
            for nm, value, on in zip(names, theta, varied, strict=True):
                params.add(nm, value=float(value), vary=on)
                if on:
                    if np.isfinite(cov[j, j]):
                        params[nm].stderr = math.sqrt(cov[j, j])
                    j += 1
            self._built = params
        return self._built

    def __getattr__(self, name):
        if name.startswith("_"):  # pickling and copying look for dunders: not lmfit's
            raise AttributeError(name)
        return getattr(self._params(), name)

    def __getitem__(self, name):
        return self._params()[name]

    def __iter__(self):
        return iter(self._params())

    def __len__(self):
        return len(self._of[0])

    def __contains__(self, name):
        return name in self._of[0]

    def __repr__(self):
        return repr(self._params())


def _start_vector(design, init, vary) -> tuple:
    """(θ₀, varied, lower, upper): arrays over the global parameters from the starting
    values ``init`` (name → value) and the names in ``vary``, θ₀ clipped to the bounds."""
    names = design.names
    sm = design.summary
    vary = set(vary)
    varied = np.array([n in vary for n in names])
    lower = np.full(len(names), -np.inf)
    upper = np.full(len(names), np.inf)
    theta0 = np.empty(len(names))
    for i, n in enumerate(names):
        base = base_name(n)
        if base == "t0":
            r = _rec(n, len(sm.names))
            lo, hi = t0_bounds(sm.t_first[r], sm.t_start[r], sm.duration[r])
        else:
            lo, hi = _bounds(base, init[n], None)
        if varied[i]:
            lower[i], upper[i] = lo, hi
        theta0[i] = float(np.clip(init[n], lower[i], upper[i]))
    return theta0, varied, lower, upper


def _joint(model, store, design, start, executor=None) -> dict:
    """The joint fit by the block solver (:mod:`pipeline.fit.blocks`) from ``start``
    (:func:`_start_vector`), as the fields of a :class:`CampaignFit` (those
    :func:`pipeline.fit.procedure.run_fit` gives a dense one)."""
    names = design.names
    sm = design.summary
    theta0, varied, lower, upper = start
    res = solve_blocks(model, store, design, theta0, varied, lower, upper, executor=executor)
    n = int(sm.n_data.sum())
    k = int(varied.sum())
    nuisance = int(sm.n_nuisance.sum())
    redchi = res.chi2 / max(n - k - nuisance, 1)
    cov = res.cov * max(1.0, redchi)
    check = misfit_of(res.misfit_parts, k, nuisance)
    notes = []
    if not check.ok or not res.success:
        reasons = list(check.reasons) + ([] if res.success else [res.message])
        msg = f"joint fit ({model.name}): " + "; ".join(reasons)
        notes.append(msg)
        warnings.warn(msg, PoorFitWarning, stacklevel=3)
    varied = tuple(bool(v) for v in varied)
    return dict(
        names=names,
        theta=res.theta,
        varied=varied,
        cov=cov,
        chi2=res.chi2,
        n_data=n,
        n_nuisance=nuisance,
        params=_Parameters(names, res.theta, varied, cov),
        result=SimpleNamespace(
            nfev=res.nfev, njev=res.njev, success=res.success, message=res.message
        ),
        notes=tuple(notes),
        poor=bool(notes),
        misfit=check,
        problem=_Joint(design, store),
    )


def _prepared(start, items, scenes, sensors, noises, model, how, starts, load) -> tuple:
    """A chunk of records prepared (:func:`pipeline.fit.forward.prepare`), here or in an
    executor's process: the chunk as a store writes it, its summary rows and, for
    ``starts`` "moments" or "fits", each record's starting values. ``items``: the records,
    or what ``load`` reads them from; ``start``: the first one's index."""
    states, rows, singles = [], [], []
    for i, (item, s, se, no) in enumerate(zip(items, scenes, sensors, noises, strict=True)):
        r = item if isinstance(item, xr.Dataset) else load(item)
        d = prepare(r, s, channels=model.channels, sensor=se, noise=no, **how)
        if starts == "moments":
            singles.append(_start(d, model, float(d.scene.speed)))
        elif starts == "fits":
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", PipelineWarning)
                vary = DEFAULT_VARY(model.normal, model.tangential)
                single = fit_model(
                    r, s, model, vary, sensor=se, noise=no, n_boot=0, systematics={}, **how
                )
            singles.append(_single_values(single))
        rows.append(RecordSummary.row(d, str(r.attrs.get("source", f"record {start + i}"))))
        states.append(pack(d))
    return pack_chunk(states), rows, (_columns(singles) if singles else None)


def _single_values(fit) -> dict:
    """A single-record fit's starting values for the joint fit: its values (the optimiser's
    for a parameter bounded only from below), standard errors and identifiability."""
    out = {n: float(fit.params[n].value) for n in fit.vary}
    out.update({f"{n}_stderr": fit.stderr[n] for n in fit.vary})
    out.update({f"{n}_identifiable": bool(fit.identifiable[n]) for n in fit.vary})
    return out


#: Each record's starting values that the joint fit reads (:func:`_starts`), and their
#: defaults where a record's lack them (None: required).
_START = {
    "t0": None,
    "E_eff": None,
    "kt_scale": 1.0,
    "e": 1.0,
    "mu": math.nan,
    "mu_stderr": math.nan,
    "mu_identifiable": True,
}


def _columns(rows) -> dict:
    """Records' starting values as arrays over the records (:data:`_START`): from one
    mapping per record, or from the columns of a :meth:`CampaignFit.per_record` frame."""
    if hasattr(rows, "columns"):
        n = len(rows)
        return {k: rows[k].to_numpy() if k in rows else np.full(n, d) for k, d in _START.items()}
    return {
        k: np.array(
            [r[k] if d is None else r.get(k, d) for r in rows],
            dtype=bool if k == "mu_identifiable" else float,
        )
        for k, d in _START.items()
    }


def _starts(singles, design, law):
    """Starting values of the global parameters from the records' starting values
    (:func:`_columns` of the single-record fits' :func:`_single_values`, of their moments,
    of the hypothesis before, or of the caller's ``starts``: E_eff, e, mu, kt_scale, t0 per
    record; the standard errors weigh μ where given)."""
    init = {}
    sm = design.summary
    E = np.asarray(singles["E_eff"], dtype=float)
    kt = np.minimum(np.maximum(np.asarray(singles["kt_scale"], dtype=float), 0.05), 20.0)
    per_record = {"t0": singles["t0"], "speed": sm.speed, "E_eff": E, "kt_scale": kt}
    for kind, names in design.own_names.items():
        init.update(zip(names, np.asarray(per_record[kind], dtype=float).tolist(), strict=True))
    init["E_eff"] = float(np.median(E))
    init["kt_scale"] = float(np.median(kt))
    es = np.asarray(singles["e"], dtype=float)
    init["e"] = float(np.median(es))
    if law != "hertz":
        L = NORMAL_LAWS[law]
        a = []
        for i, e in enumerate(es):
            K = 4.0 / 3.0 * E[i] * math.sqrt(sm.R_eff[i])
            unit = float(L.material_to_param(1.0, K, sm.m_eff[i], sm.speed[i] * sm.cos_a[i]))
            a.append(float(L.calibrate(min(e, 0.999999))) / unit if unit else 0.0)
        init["alpha"] = float(np.median(a))
    mus = np.asarray(singles["mu"], dtype=float)
    ok = np.asarray(singles["mu_identifiable"], dtype=bool) & np.isfinite(mus)
    if not ok.any():
        ok = np.isfinite(mus)
    se = np.asarray(singles["mu_stderr"], dtype=float)
    w = np.where(np.isfinite(se) & (se > 0), 1.0 / np.maximum(se, 1e-12) ** 2, 1.0)[ok]
    init["mu"] = float(np.average(mus[ok], weights=w)) if ok.any() else 0.1
    vt = design.vt0[ok]
    if ok.sum() >= 2 and np.ptp(vt) > 0:
        A = np.column_stack([np.ones(ok.sum()), vt]) * np.sqrt(w)[:, None]
        (a0, b0), *_ = np.linalg.lstsq(A, mus[ok] * np.sqrt(w), rcond=None)
        init["mu_a"], init["mu_b"] = float(a0), float(b0)
    else:
        init["mu_a"], init["mu_b"] = init["mu"], 0.0
    return init


def fit_campaign(
    records,
    scenes,
    *,
    shared=("E_eff",),
    mu_law: str = "constant",
    damping: str = "constant_e",
    normal: str = "hunt_crossley",
    tangential: str = "mindlin",
    **options,
) -> CampaignFit:
    """One joint fit of many records with shared parameters (module notes).

    Parameters
    ----------
    records : sequence of xarray.Dataset, or of paths — the records, or what ``load``
        reads them from (where they are prepared: in an ``executor``'s process if one is
        given);
        a lazy sequence (one that reads each record from its file when indexed) is read
        once, a record at a time, so that a campaign of many records is never all in
        memory
    scenes : Scene or sequence of Scene — one per record (or one for all)
    shared : sequence of str — of ``"E_eff"``, ``"kt_scale"``: one value for every record
    mu_law : {"constant", "linear_vt0"} — μ, or μ = a + b·v_t0 [b in s/m]
    damping : {"constant_e", "constant_alpha"} — one e, or one material constant α (the
        law's: [s/m] for the Hunt–Crossley family, the yield speed [m/s] for Thornton's)
    normal, tangential : str — the model, as :func:`pipeline.fit.fit_contact`

    Other Parameters
    ----------------
    hypotheses : {"all", "one"}
        ``"all"`` (default) also fits the other μ laws and damping hypotheses, for
        :meth:`CampaignFit.compare`; ``"one"`` only the one asked for.
    history, sensor, noise, margin, n_steps, oversample, window_options
        As :func:`pipeline.fit.fit_contact` (``sensor`` and ``noise`` may be lists, one per
        record).
    n_boot, seed : int
        Block-bootstrap replicates of the joint fit (default 0: covariance intervals; the
        bootstrap needs ``solver="dense"``).
    solver : {"blocks", "dense"}
        ``"blocks"`` (default): Levenberg–Marquardt on the Schur complement of the records'
        own parameters (:mod:`pipeline.fit.blocks`), time linear in the records, memory
        flat (the records on disk);
        ``"dense"``: lmfit on the dense Jacobian over all records (the same optimum, its
        cost growing with the square of the records and more).
    executor : concurrent.futures.Executor, optional
        Prepare the records and evaluate them a chunk at a time in its processes (the
        block solver; a dask ``Client.get_executor()``, as a campaign on a cluster does):
        the same fit, its time divided among the processes.
    load : callable, optional
        Reads a record from an entry of ``records`` that is not a record (default
        :func:`pipeline.io.load`, of a path).
    starts : {"moments", "fits"} or sequence of mapping
        Starting values: ``"moments"`` (default) each record's from its pulse's moments
        (:mod:`pipeline.fit.contact`: E*, e, t0, the Ft/Fn plateau for μ); ``"fits"`` a fit
        of each record alone; or the caller's, one mapping per record with ``E_eff``,
        ``e``, ``mu``, ``kt_scale``, ``t0`` (a campaign's per-record fits).

    Returns
    -------
    CampaignFit
        The fit of the hypothesis asked for; ``.hypotheses`` holds every one fitted.

    Raises
    ------
    InputError
        Fewer than two records, mismatched lists, unknown laws or hypotheses.
    """
    t_begin = time.perf_counter()
    opts = dict(options)
    hyps = opts.pop("hypotheses", "all")
    history = opts.pop("history", "total")
    sensors = opts.pop("sensor", None)
    noises = opts.pop("noise", None)
    margin = opts.pop("margin", None)
    n_steps = int(opts.pop("n_steps", 128))
    oversample = int(opts.pop("oversample", 4))
    n_boot = int(opts.pop("n_boot", 0))
    seed = int(opts.pop("seed", 0))
    window_options = opts.pop("window_options", None)
    starts = opts.pop("starts", "moments")
    solver = opts.pop("solver", "blocks")
    executor = opts.pop("executor", None)
    load = opts.pop("load", None) or read_record
    if opts:
        raise InputError(f"fit_campaign: unknown option(s) {', '.join(sorted(opts))}")
    if solver not in ("blocks", "dense"):
        raise InputError(f"solver must be 'blocks' or 'dense', got {solver!r}")
    if solver == "blocks" and n_boot:
        raise InputError(
            "fit_campaign: the bootstrap needs solver='dense' (the block solver gives "
            "covariance intervals)"
        )
    if not hasattr(records, "__len__"):
        records = list(records)
    n_records = len(records)  # a lazy sequence is read one record at a time, once
    if n_records < 2:
        raise InputError("fit_campaign needs at least two records (fit_contact fits one)")
    if mu_law not in MU_LAWS:
        raise InputError(f"mu_law {mu_law!r} is unknown; choose one of {MU_LAWS}")
    if damping not in DAMPING:
        raise InputError(f"damping {damping!r} is unknown; choose one of {DAMPING}")
    if hyps not in ("all", "one"):
        raise InputError(f"hypotheses must be 'all' or 'one', got {hyps!r}")
    shared = tuple(shared)
    bad = [s for s in shared if s not in _SHAREABLE]
    if bad:
        raise InputError(f"fit_campaign: cannot share {bad}; shareable: {_SHAREABLE}")
    if normal == "hertz" and damping == "constant_alpha":
        raise InputError("the elastic 'hertz' law has no damping constant; use a damped law")
    scenes = _as_list(scenes, n_records, "scenes")
    if not all(isinstance(s, Scene) for s in scenes):
        raise InputError("fit_campaign: scenes must be pipeline.Scene objects")
    sensors = _as_list(sensors, n_records, "sensors")
    noises = _as_list(noises, n_records, "noise settings")
    model = ForwardModel(normal, tangential, history, n_steps)
    own_starts = starts in ("moments", "fits")
    how = {"margin": margin, "oversample": oversample, "window_options": window_options}
    size = store_module.CHUNK

    def part(a):
        b = min(a + size, n_records)
        if isinstance(records, (list, tuple)):
            items = records[a:b]
        else:
            items = [records[i] for i in range(a, b)]
        return a, items, scenes[a:b], sensors[a:b], noises[a:b], model, how, starts, load

    jobs = (part(a) for a in range(0, n_records, size))
    on = executor if n_records > size else None  # one chunk: nothing to share
    columns = []  # each chunk's records' starting values (_columns)

    def packed():
        for blob, rows, starts_ in in_order(on, _prepared, jobs):
            columns.append(starts_)
            yield blob, rows

    store = RecordStore.of_packed(packed(), chunk=size)
    if own_starts:
        singles = {k: np.concatenate([c[k] for c in columns]) for k in _START}
        columns.clear()  # the chunks' columns, now joined
    else:
        singles = _columns(_as_list(starts, n_records, "starts"))
    names = store.summary.names
    todo = [(mu_law, damping)]
    if hyps == "all":
        todo += [(m, d) for m in MU_LAWS for d in DAMPING if (m, d) != (mu_law, damping)]
        if normal == "hertz":
            todo = [(m, d) for m, d in todo if d == "constant_e"]
        if tangential == "none":
            todo = [(m, d) for m, d in todo if m == "constant"]
    fits, own_names = {}, {}
    for ml, dm in todo:
        design = _Campaign(store.summary, normal, shared, ml, dm, tangential, own_names)
        init = _starts(singles, design, normal)
        vary = [n for n in design.names if not n.startswith("speed_")]
        if normal == "hertz":
            vary = [n for n in vary if n not in ("e", "alpha")]
        if solver == "dense":  # every record in memory: the dense path is for a few
            kw = run_fit(model, list(store), design, init, vary, [], n_boot=n_boot, seed=seed)
            kw["problem"] = _Joint(design, store)
        else:  # the names and values of every record's parameters not kept through the fit
            start = _start_vector(design, init, vary)
            del init, vary
            kw = _joint(model, store, design, start, executor)
        kw.update(
            mu_law=ml,
            damping=dm,
            shared=shared,
            records=names,
            model=model,
            datas=store,
            cost_s=time.perf_counter() - t_begin,
        )
        fits[(ml, dm)] = CampaignFit(**kw)
        if solver == "blocks":  # the next hypothesis starts from this one's records
            singles = _columns(fits[(ml, dm)].per_record())
    for f in fits.values():
        f.hypotheses.update(fits)
    return fits[(mu_law, damping)]
