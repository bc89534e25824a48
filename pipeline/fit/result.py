"""What every fit result shares: values, uncertainties, intervals, information criteria.

:class:`FitResult` is the common base of :class:`~pipeline.fit.contact.ContactFit` and
:class:`~pipeline.fit.campaign.CampaignFit` (docs/theory.md). The noise of every channel
is measured (outside the contact), so the likelihood of a fit is that of Gaussian noise of
known σ and

.. math::

    \\mathrm{AIC} = \\chi^2 + 2k, \\qquad \\mathrm{BIC} = \\chi^2 + k\\ln N

(k varied parameters, N samples): differences of these between models fitted to the same
samples are the differences of −2 ln L plus the penalties. lmfit's own ``aic``/``bic``
(which estimate σ from the residuals) stay in :attr:`FitResult.result`.

**Intervals inside the parameter's domain** (:func:`in_domain`; docs/uncertainty.md). The
systematics and the model spread widen the data's interval, and a wide model spread can
carry a symmetric interval past what the parameter can be (e above 1 on a plastic record
fitted with a damped law, a negative E*). A positive scale parameter (:data:`LOG_SCALE`:
E*, the tangential stiffness' scale) has its interval built on the log scale — the data's
Wald interval θ·exp(±z·σ/θ), the widening by its relative σ — so it stays positive and
reads as a factor either way; a parameter with a bounded domain (:data:`DOMAINS`: e in
[0, 1], μ and α ≥ 0) has its interval cut at the domain's end, which :meth:`FitResult.table`
notes. The standard uncertainties (``stderr``, the budget) stay as they are.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import special

from .. import precision
from .._json import json_ready
from .forward import SYSTEMATIC_PARAMS, UNITS
from .procedure import MISFIT_Z, base_name
from .uncertainty import normal_interval, one_sided_bound, percentile_interval

__all__ = ["FitResult", "kind_of", "DOMAINS", "LOG_SCALE", "in_domain"]

#: The domain (lo, hi) of the parameters that have one, in SI; its ends may be reached (e =
#: 1 is an elastic impact, μ = 0 a frictionless one): intervals stay inside (:func:`in_domain`).
DOMAINS = {
    "E_eff": (0.0, math.inf),
    "kt_scale": (0.0, math.inf),
    "e": (0.0, 1.0),
    "mu": (0.0, math.inf),
    "alpha": (0.0, math.inf),
    "beta0": (-1.0, 1.0),
}
#: Positive scale parameters: their intervals are built on the log scale (module notes).
LOG_SCALE = ("E_eff", "kt_scale")


def in_domain(name, value, lo, hi, widen=0.0, centre=None) -> tuple:
    """A parameter's interval (lo, hi) [its unit], widened and kept inside its domain.

    Parameters
    ----------
    name : str — the parameter (a campaign's ``kt_scale_3`` is a ``kt_scale``)
    value : float — its value [its unit]: the interval is placed about it
    lo, hi : float — the data's interval, about ``centre`` (default ``value``)
    widen : float — z·σ of the terms beyond the data's [its unit], added to each side's
        half width in quadrature (0: none)
    centre : float, optional — where the data's interval was found (a model average moves
        it to ``value``)

    Returns
    -------
    (lo, hi)
        For a parameter of :data:`LOG_SCALE`: the half widths ln(centre/lo), ln(hi/centre)
        with widen/value in quadrature, about ln(value); otherwise lo and hi moved by
        value − centre, widened, and cut at the ends of its :data:`DOMAINS` entry.
    """
    base = base_name(name)
    c = value if centre is None else centre
    if widen > 0 or c != value:
        if base in LOG_SCALE and value > 0 and c > 0 and lo > 0:
            w = widen / value
            a, b = math.hypot(math.log(c / lo), w), math.hypot(math.log(hi / c), w)
            return value * math.exp(-a), value * math.exp(b)
        lo, hi = value - math.hypot(c - lo, widen), value + math.hypot(hi - c, widen)
    d_lo, d_hi = DOMAINS.get(base, (-math.inf, math.inf))
    return max(lo, d_lo), min(hi, d_hi)


def kind_of(name: str) -> str:
    """What a fitted parameter is: ``"contact"`` (a physical one), ``"per record"`` (a
    campaign's parameter of one record, ``kt_scale_3``) or ``"nuisance"`` (the onset, an
    input known to a tolerance)."""
    base, _, index = name.rpartition("_")
    if name == "t0" or name in SYSTEMATIC_PARAMS:
        return "nuisance"
    return "per record" if index.isdigit() and base else "contact"


def _misfit_words(m, records=()) -> list:
    """What failed the misfit test (:class:`pipeline.fit.procedure.Misfit`), its numbers
    at a reader's precision; a campaign's channels (``"3:Ft"``) named by their record's
    name in ``records``."""
    out = []
    if any(r.startswith("χ²_ν") for r in m.reasons):
        out.append(
            f"the residuals' χ²_ν is {precision.plain(m.redchi, 3)}, "
            f"{precision.plain(m.chi2_z, 3)} standard deviations above 1"
        )
    runs = [k for k in m.runs_z if any(r.startswith(f"{k} residual") for r in m.reasons)]
    if runs:

        def name(key):
            i, _, ch = key.rpartition(":")
            return f"{records[int(i)]} {ch}" if i.isdigit() and int(i) < len(records) else key

        z = ", ".join(f"{name(k)} z = {precision.plain(m.runs_z[k], 3)}" for k in runs)
        long = sum(1 for v in m.runs_z.values() if np.isfinite(v) and v < -MISFIT_Z)
        if long > len(runs):  # a campaign's misfit names its worst channels only
            z += f"; and in {long - len(runs)} more of the {len(m.runs_z)} channels"
        out.append(f"the residual signs run in long stretches ({z})")
    return out or list(m.reasons)


def _cut_words(rows, normal=None) -> list:
    """What :meth:`FitResult.table` says of the intervals that end at their domain's end
    (``normal``: the fit's law, which names a campaign's ``alpha``)."""
    out = []
    for r in rows:
        d_lo, d_hi = DOMAINS.get(base_name(r["name"]), (-math.inf, math.inf))
        lo, hi = r.get("ci") or (math.nan, math.nan)
        if r.get("status", "fitted") == "fitted" and (lo == d_lo or hi == d_hi):
            sym = precision.quantity(precision.reads_as(r["name"], normal)).symbol
            end = f"{d_hi if hi == d_hi else d_lo:g}"
            out.append(
                f"{sym}'s interval ends at {end}, the end of the values {sym} can take: an "
                "interval is kept inside them (docs/uncertainty.md)."
            )
    return out


@dataclass(frozen=True, eq=False)
class FitResult:
    """A fit's parameters with their uncertainty (see the module notes).

    Attributes
    ----------
    names : tuple of str — every parameter of the model (fixed ones too)
    theta : numpy.ndarray — their values at the optimum (SI, units in :data:`UNITS`)
    varied : tuple of bool — which were fitted
    cov : numpy.ndarray — covariance of the varied parameters (module
        :mod:`pipeline.fit.uncertainty`)
    chi2 : float — Σ((y − model)/σ)² at the optimum
    n_data : int — number of samples fitted
    n_nuisance : int — baseline parameters fitted alongside (:mod:`pipeline.fit.forward`)
    params : lmfit.Parameters — the final parameters (stderr and correlations from ``cov``)
    result : lmfit.MinimizerResult
    boot : numpy.ndarray or None — bootstrap refits, shape (n_boot, len(names))
    blocks : dict — block length of each residual series in the bootstrap
    profiles : dict — {name: (grid, Δχ²)} for the parameters profiled: the one-sided ones
        and those flat at the optimum (their intervals come from the profile)
    lower_only : tuple of str — parameters the data bound only from below
    upper_only : tuple of str — parameters the data bound only from above
    notes : tuple of str — what the fit assumed, left out or could not determine
    poor : bool — the residuals show structure the model misses (a PoorFitWarning was given)
    cost_s : float — wall time of the fit [s]
    cov_stat : numpy.ndarray or None — the data's part of ``cov`` (the rest is the priors')
    sys_weights : numpy.ndarray or None — (varied, priors): each prior's weight on each
        varied parameter (:class:`pipeline.fit.uncertainty.CovarianceParts`)
    priors : dict — {name: (stated value, standard uncertainty)} of the constrained
        parameters (the systematics), in the order of ``sys_weights``' columns
    chi2_prior : float — the prior rows' share of ``chi2``
    misfit : pipeline.fit.procedure.Misfit or None — the misfit test
    model_spread : dict — {name: σ} spread between the models the data cannot tell apart
        (the budget's ``model`` term; :func:`pipeline.fit_contact`)
    extra_terms : dict — {name: {term: σ}} further Type B terms of the budget (the bounds
        of a mode or a discharge the record does not show: :mod:`pipeline.fit.dynamics`)
    """

    names: tuple
    theta: np.ndarray
    varied: tuple
    cov: np.ndarray
    chi2: float
    n_data: int
    params: object
    result: object
    boot: np.ndarray | None = None
    blocks: dict = field(default_factory=dict)
    profiles: dict = field(default_factory=dict)
    lower_only: tuple = ()
    upper_only: tuple = ()
    notes: tuple = ()
    poor: bool = False
    cost_s: float = math.nan
    n_nuisance: int = 0
    cov_stat: np.ndarray | None = None
    sys_weights: np.ndarray | None = None
    priors: dict = field(default_factory=dict)
    chi2_prior: float = 0.0
    misfit: object = None
    model_spread: dict = field(default_factory=dict)
    extra_terms: dict = field(default_factory=dict)

    # ------------------------------------------------------------ numbers
    @property
    def vary(self) -> tuple:
        """Names of the fitted parameters."""
        return tuple(n for n, v in zip(self.names, self.varied, strict=True) if v)

    @property
    def nvarys(self) -> int:
        return sum(self.varied)

    @property
    def one_sided(self) -> tuple:
        """The parameters the data bound on one side only (:attr:`lower_only`,
        :attr:`upper_only`)."""
        return self.lower_only + self.upper_only

    @property
    def values(self) -> dict:
        """{name: value} [SI]; a parameter bounded only from below (above) gives its 95 %
        lower (upper) bound (see :attr:`identifiable`), the optimiser's value is in
        :attr:`params`."""
        return self._parameter_values()

    def _parameter_values(self) -> dict:
        """:attr:`values` of the model's parameters alone, without what a subclass adds
        that they imply (:class:`pipeline.fit.ContactFit`'s yield point of Thornton's law)."""
        out = {n: float(v) for n, v in zip(self.names, self.theta, strict=True)}
        if self.one_sided:
            ci = self.ci(0.95)
            out.update({n: ci[n][0] for n in self.lower_only})
            out.update({n: ci[n][1] for n in self.upper_only})
        return out

    @property
    def stderr(self) -> dict:
        """{name: standard error} from the covariance (a parameter flat at the optimum:
        its 95 % profile interval's half width over 1.96); NaN for fixed parameters and for
        those the data bound on one side only."""
        out = {n: math.nan for n in self.names}
        for i, n in enumerate(self.vary):
            out[n] = math.sqrt(self.cov[i, i]) if np.isfinite(self.cov[i, i]) else math.nan
        out.update(self._profiled_se())
        for n in self.one_sided:
            out[n] = math.nan
        return out

    def _profile_interval(self, name, level) -> tuple:
        """Both ends of a flat-topped parameter's profile interval (Δχ² within z², the
        covariance's scale)."""
        grid, d = self.profiles[name]
        lv, scale = 0.5 + level / 2.0, max(1.0, self.redchi)
        return one_sided_bound(grid, d, lv, scale), one_sided_bound(grid[::-1], d[::-1], lv, scale)

    def _profiled_se(self) -> dict:
        z = float(special.ndtri(0.975))
        out = {}
        for n in self.profiles:
            if n not in self.one_sided:
                lo, hi = self._profile_interval(n, 0.95)
                out[n] = (hi - lo) / (2 * z)
        return out

    @property
    def identifiable(self) -> dict:
        """{name: bool} for the fitted parameters: False where the data bound it on one
        side only (:attr:`notes` says why)."""
        se, one_sided = self.stderr, set(self.one_sided)
        return {n: n not in one_sided and np.isfinite(se[n]) for n in self.vary}

    @property
    def redchi(self) -> float:
        """χ² of the data over N − k − k_baseline (a parameter with a prior brings its own
        row and costs no degree of freedom): about 1 when the model fits to the measured
        noise."""
        k = self.nvarys - len(self.priors)
        return (self.chi2 - self.chi2_prior) / max(self.n_data - k - self.n_nuisance, 1)

    @property
    def aic(self) -> float:
        """χ² + 2k (module notes; k counts the fitted baseline too)."""
        return self.chi2 + 2 * (self.nvarys + self.n_nuisance)

    @property
    def bic(self) -> float:
        """χ² + k·ln N (module notes; k counts the fitted baseline too)."""
        return self.chi2 + (self.nvarys + self.n_nuisance) * math.log(max(self.n_data, 1))

    def _stat_se(self) -> dict:
        """{varied name: the data's standard error} (the covariance's data part)."""
        cov = self.cov if self.cov_stat is None else self.cov_stat
        out = {
            n: math.sqrt(cov[i, i]) if np.isfinite(cov[i, i]) else math.nan
            for i, n in enumerate(self.vary)
        }
        out.update(self._profiled_se())
        return out

    @property
    def budget(self) -> dict:
        """The uncertainty budget: {parameter: {"stat": σ, "<systematic>": σ, ...,
        "model": σ, "total": σ}} (standard uncertainties, SI).

        ``stat`` is the data's (the block bootstrap's spread where it ran — its 95 %
        percentile interval's half width over 1.96 —, else the covariance's); each
        systematic's is its prior's weight on the parameter (:mod:`pipeline.fit.uncertainty`,
        :class:`~pipeline.fit.uncertainty.CovarianceParts`); ``model`` the spread between
        the models the data cannot tell apart (:func:`pipeline.fit_contact`); ``total``
        adds them in quadrature (GUM §5.1, uncorrelated inputs), so the terms add up by
        construction. A parameter bounded on one side only has NaN throughout.
        """
        from .systematics import SYSTEMATICS

        stat = self._stat_se()
        if self.boot is not None:
            ci = self.ci(0.95, kind="stat")
            z = float(special.ndtri(0.975))
            stat = {n: (ci[n][1] - ci[n][0]) / (2 * z) for n in self.vary}
        names = list(self.priors)
        by_name = {n: n for n in names}
        by_name.update({"leak": "crosstalk", "leak_tn": "crosstalk"})
        out = {}
        for i, n in enumerate(self.vary):
            if n in SYSTEMATIC_PARAMS:
                continue  # a systematic itself: its posterior is in stderr
            row = {"stat": stat[n]}
            for j, pname in enumerate(names):
                w = 0.0 if self.sys_weights is None else float(self.sys_weights[i, j])
                key = by_name.get(pname, pname)  # the two leaks: one systematic
                row[key] = math.hypot(row.get(key, 0.0), w)
            for key, u in self.extra_terms.get(n, {}).items():
                row[key] = math.hypot(row.get(key, 0.0), u)
            row["model"] = float(self.model_spread.get(n, 0.0))
            terms = [v for k, v in row.items() if k != "total"]
            row["total"] = math.sqrt(sum(v * v for v in terms))
            if n in self.one_sided:
                row = dict.fromkeys(row, math.nan)
            order = ["stat", *[s for s in SYSTEMATICS if s in row]]
            order += [k for k in row if k not in order and k not in ("model", "total")]
            order += ["model", "total"]
            out[n] = {k: row[k] for k in order if k in row}
        return out

    def ci(self, level: float = 0.95, method: str = "auto", kind: str = "total") -> dict:
        """Confidence intervals {name: (lo, hi)} of the fitted parameters.

        Parameters
        ----------
        level : float — confidence level in (0, 1)
        method : {"auto", "bootstrap", "covariance"}
            The data's part: ``"bootstrap"``, the percentile interval of the block-bootstrap
            refits; ``"covariance"``, value ± z·(its standard error); ``"auto"``, the
            bootstrap where it was run.
        kind : {"total", "stat"}
            ``"total"`` (default) widens the data's interval by the systematics and the
            model spread of :attr:`budget`, each side in quadrature (a symmetric data
            interval becomes value ± z·total); ``"stat"``: the data's alone.

        Every interval lies inside its parameter's domain (module notes, :func:`in_domain`):
        E* and the tangential stiffness' scale on the log scale (the covariance's interval
        value·exp(±z·total/value)), e, μ and α cut at their domain's ends. A parameter
        bounded only from below gets (profile lower bound, +inf) either way; one bounded
        only from above (0, profile upper bound).
        """
        if not 0 < level < 1:
            raise ValueError(f"level must lie in (0, 1), got {level!r}")
        if method not in ("auto", "bootstrap", "covariance"):
            raise ValueError(f"method must be 'auto', 'bootstrap' or 'covariance', got {method!r}")
        if kind not in ("total", "stat"):
            raise ValueError(f"kind must be 'total' or 'stat', got {kind!r}")
        use_boot = self.boot is not None and method in ("auto", "bootstrap")
        if method == "bootstrap" and self.boot is None:
            raise ValueError("no bootstrap was run (fit with n_boot > 0)")
        se = {n: math.nan for n in self.names}
        se.update(self._stat_se())
        extra = {}
        if kind == "total":
            budget = self.budget
            for n, row in budget.items():
                sys = [v for k, v in row.items() if k not in ("stat", "total")]
                extra[n] = math.sqrt(sum(v * v for v in sys))
        z = float(special.ndtri(0.5 + level / 2.0))
        out = {}
        for i, n in enumerate(self.names):
            if not self.varied[i]:
                continue
            if n in self.one_sided:
                grid, d = self.profiles[n]
                scale = max(1.0, self.redchi)
                if n in self.lower_only:
                    out[n] = (one_sided_bound(grid, d, level, scale), math.inf)
                else:  # the grid runs upwards: the bound is the largest value inside
                    out[n] = (0.0, one_sided_bound(grid[::-1], d[::-1], level, scale))
                continue
            if n in self.priors:  # a systematic: its posterior, data and prior together
                j = self.vary.index(n)
                lo, hi = normal_interval(float(self.theta[i]), math.sqrt(self.cov[j, j]), level)
                out[n] = (lo, hi)
                continue
            v = float(self.theta[i])
            if n in self.profiles:  # flat at the optimum: the bootstrap would not move it
                lo, hi = self._profile_interval(n, level)
            elif use_boot:
                lo, hi = percentile_interval(self.boot[:, i], level)
            elif base_name(n) in LOG_SCALE and v > 0:  # Wald on the log scale
                lo, hi = v * math.exp(-z * se[n] / v), v * math.exp(z * se[n] / v)
            else:
                lo, hi = normal_interval(v, se[n], level)
            out[n] = in_domain(n, v, lo, hi, z * extra.get(n, 0.0))
        return out

    # ------------------------------------------------------------ text
    def table(self, level: float = 0.95, *, nuisance: bool = False, style: bool = False):
        """The fit for a person to read: the verdict in words, the parameters rounded to
        their uncertainty in the units a person uses, the budget as shares.

        Parameters
        ----------
        level : float — level of the intervals shown
        nuisance : bool — also show the parameters fitted alongside (the onset t0, the
            inputs known to a tolerance, a campaign's per-record ones), after the
            physical ones; default only the physical parameters
        style : bool — return a pandas Styler (the verdict its caption) for HTML

        Returns
        -------
        pandas.DataFrame (or its Styler)
            One row per parameter (:func:`pipeline.precision.parameter_table`): ``value``
            is value ± the combined standard uncertainty (the budget's ``total``) rounded
            by the Particle Data Group's rule, a bound (``≥ 0.131``) where the data bound
            the parameter on one side only; the interval at ``level`` (:meth:`ci`), and
            each budget term's share of the total variance [%]. ``attrs["verdict"]``
            states the verdict in a sentence, ``attrs["details"]`` what stands behind it.
            Every digit stays in ``summary()``.
        """
        budget = self.budget
        ci, se, values = self.ci(level), self.stderr, self.values
        rows = []
        for n in self.vary:
            kind = kind_of(n)
            if kind != "contact" and not nuisance:
                continue
            status = "fitted"
            if n in self.lower_only:
                status = "lower"
            elif n in self.upper_only:
                status = "upper"
            s = budget[n]["total"] if n in budget else se[n]
            rows.append(
                {
                    "name": n,
                    "value": values[n],
                    "stderr": s,
                    "ci": ci[n],
                    "status": status,
                    "kind": kind,
                }
            )
        rows += self._derived_rows(level)
        rows.sort(key=lambda r: r["kind"] != "contact")  # the physical parameters first
        verdict, details = self._verdict_words()
        details = list(details) + _cut_words(rows, self._normal_law)
        df = precision.parameter_table(
            rows,
            {r["name"]: budget[r["name"]] for r in rows if r["name"] in budget},
            verdict=verdict,
            details=details,
            level=level,
            normal=self._normal_law,
        )
        return precision.styled(df) if style else df

    @property
    def _normal_law(self):
        """The fit's normal law (None where it has none): what a campaign's ``alpha`` is."""
        return getattr(getattr(self, "model", None), "normal", None)

    def _unit(self, name) -> str:
        """The SI unit of parameter ``name`` (:data:`~pipeline.fit.forward.UNITS`; a
        campaign's ``alpha`` in its law's unit: :func:`pipeline.precision.reads_as`)."""
        return UNITS.get(base_name(precision.reads_as(name, self._normal_law)), "")

    def _derived_rows(self, level) -> list:
        """Rows of :meth:`table` for quantities the fitted parameters imply (none here)."""
        return []

    def _verdict_words(self) -> tuple:
        """(the verdict in a sentence, [what stands behind it]) from the misfit test."""
        m = self.misfit
        if m is None:
            if self.poor:
                return (
                    f"The model does not describe the data: the residuals show structure it "
                    f"misses (χ²_ν = {self.redchi:.3g}).",
                    [],
                )
            return f"The fit's residuals: χ²_ν = {self.redchi:.3g}.", []
        if m.ok:
            return (
                f"The model describes the data: the residuals are at the noise level "
                f"(χ²_ν = {m.redchi:.3g}).",
                [],
            )
        words = _misfit_words(m, getattr(self, "records", ()))
        return "The model does not describe the data: " + "; ".join(words) + ".", []

    def _budget_lines(self) -> list:
        """The uncertainty budget as a table: one row per parameter, one column per term."""
        budget = self.budget
        if not budget:
            return []
        cols = []
        for row in budget.values():
            cols += [k for k in row if k not in cols]
        head = f"    {'':<10s}" + "".join(f"{c:>11s}" for c in cols)
        lines = ["  uncertainty budget (standard uncertainties, SI units):", head]
        for name, row in budget.items():
            cells = "".join(f"{row.get(c, math.nan):>11.3g}" for c in cols)
            lines.append(f"    {name:<10s}{cells}")
        return lines

    def _param_lines(self, level=0.95) -> list:
        ci, se, values, vary = self.ci(level), self.stderr, self.values, set(self.vary)
        one_sided = set(self.one_sided)
        lines = []
        for n in self.names:
            v = values[n]
            unit = self._unit(n)
            if n not in vary:
                lines.append(f"    {n:<12s} = {v:.6g} {unit} (fixed)")
            elif n in one_sided:
                op, side = ("≥", "lower") if n in self.lower_only else ("≤", "upper")
                lines.append(
                    f"    {n:<12s} {op} {v:.6g} {unit} (not identifiable: only an {side} bound"
                    f", {level:.0%})"
                )
            else:
                lo, hi = ci[n]
                lines.append(
                    f"    {n:<12s} = {v:.6g} ± {se[n]:.2g} {unit}  [{lo:.6g}, {hi:.6g}] "
                    f"({level:.0%})"
                )
        return lines

    def _summary_params(self) -> dict:
        # each property once, not once a parameter: a campaign's fit has thousands
        ci, values, se, ident = self.ci(0.95), self.values, self.stderr, self.identifiable
        vary = set(self.vary)
        out = {}
        for n in self.names:
            entry = {"value": values[n], "unit": self._unit(n), "vary": n in vary}
            if n in vary:
                entry.update(stderr=se[n], ci95=list(ci[n]), identifiable=ident[n])
                if n in self.priors:
                    entry["stated"], entry["stated_u"] = self.priors[n]
            out[n] = entry
        return out

    def _summary_stats(self) -> dict:
        return json_ready(
            {
                "chi2": self.chi2,
                "redchi": self.redchi,
                "n_data": self.n_data,
                "n_varied": self.nvarys,
                "aic": self.aic,
                "bic": self.bic,
                "poor": self.poor,
                "n_boot": 0 if self.boot is None else int(self.boot.shape[0]),
                "block_length": dict(self.blocks),
                "cost_s": self.cost_s,
                "notes": list(self.notes),
            }
        )
