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
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._json import json_ready
from .forward import UNITS
from .uncertainty import normal_interval, one_sided_bound, percentile_interval

__all__ = ["FitResult"]


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
    profiles : dict — {name: (grid, Δχ²)} for the parameters profiled
    lower_only : tuple of str — parameters the data bound only from below
    notes : tuple of str — what the fit assumed, left out or could not determine
    poor : bool — the residuals show structure the model misses (a PoorFitWarning was given)
    cost_s : float — wall time of the fit [s]
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
    notes: tuple = ()
    poor: bool = False
    cost_s: float = math.nan
    n_nuisance: int = 0

    # ------------------------------------------------------------ numbers
    @property
    def vary(self) -> tuple:
        """Names of the fitted parameters."""
        return tuple(n for n, v in zip(self.names, self.varied, strict=True) if v)

    @property
    def nvarys(self) -> int:
        return sum(self.varied)

    @property
    def values(self) -> dict:
        """{name: value} [SI]; a parameter bounded only from below gives its 95 % lower
        bound (see :attr:`identifiable`), the optimiser's value is in :attr:`params`."""
        out = {n: float(v) for n, v in zip(self.names, self.theta, strict=True)}
        for n in self.lower_only:
            out[n] = self.ci(0.95)[n][0]
        return out

    @property
    def stderr(self) -> dict:
        """{name: standard error} from the covariance; NaN for fixed parameters and for
        those the data bound only from below."""
        out = {n: math.nan for n in self.names}
        for i, n in enumerate(self.vary):
            out[n] = math.sqrt(self.cov[i, i]) if np.isfinite(self.cov[i, i]) else math.nan
        for n in self.lower_only:
            out[n] = math.nan
        return out

    @property
    def identifiable(self) -> dict:
        """{name: bool} for the fitted parameters: False where the data bound it only from
        below (:attr:`notes` says why)."""
        return {n: n not in self.lower_only and np.isfinite(self.stderr[n]) for n in self.vary}

    @property
    def redchi(self) -> float:
        """χ²/(N − k − k_baseline): about 1 when the model fits to the measured noise."""
        return self.chi2 / max(self.n_data - self.nvarys - self.n_nuisance, 1)

    @property
    def aic(self) -> float:
        """χ² + 2k (module notes; k counts the fitted baseline too)."""
        return self.chi2 + 2 * (self.nvarys + self.n_nuisance)

    @property
    def bic(self) -> float:
        """χ² + k·ln N (module notes; k counts the fitted baseline too)."""
        return self.chi2 + (self.nvarys + self.n_nuisance) * math.log(max(self.n_data, 1))

    def ci(self, level: float = 0.95, method: str = "auto") -> dict:
        """Confidence intervals {name: (lo, hi)} of the fitted parameters.

        Parameters
        ----------
        level : float — confidence level in (0, 1)
        method : {"auto", "bootstrap", "covariance"}
            ``"bootstrap"``: percentile interval of the block-bootstrap refits;
            ``"covariance"``: value ± z·stderr; ``"auto"``: the bootstrap where it was run.
            A parameter bounded only from below gets (profile lower bound, +inf) either way.
        """
        if not 0 < level < 1:
            raise ValueError(f"level must lie in (0, 1), got {level!r}")
        if method not in ("auto", "bootstrap", "covariance"):
            raise ValueError(f"method must be 'auto', 'bootstrap' or 'covariance', got {method!r}")
        use_boot = self.boot is not None and method in ("auto", "bootstrap")
        if method == "bootstrap" and self.boot is None:
            raise ValueError("no bootstrap was run (fit with n_boot > 0)")
        se = {n: math.nan for n in self.names}
        for i, n in enumerate(self.vary):
            se[n] = math.sqrt(self.cov[i, i]) if np.isfinite(self.cov[i, i]) else math.nan
        out = {}
        for i, n in enumerate(self.names):
            if not self.varied[i]:
                continue
            if n in self.lower_only:
                grid, d = self.profiles[n]
                out[n] = (one_sided_bound(grid, d, level, max(1.0, self.redchi)), math.inf)
            elif use_boot:
                out[n] = percentile_interval(self.boot[:, i], level)
            else:
                out[n] = normal_interval(float(self.theta[i]), se[n], level)
        return out

    # ------------------------------------------------------------ text
    def _param_lines(self, level=0.95) -> list:
        ci = self.ci(level)
        se = self.stderr
        lines = []
        for n in self.names:
            v = self.values[n]
            unit = UNITS.get(n.rsplit("_", 1)[0] if n not in UNITS else n, "")
            if n not in self.vary:
                lines.append(f"    {n:<12s} = {v:.6g} {unit} (fixed)")
            elif n in self.lower_only:
                lines.append(
                    f"    {n:<12s} ≥ {v:.6g} {unit} (not identifiable: only a lower bound, "
                    f"{level:.0%})"
                )
            else:
                lo, hi = ci[n]
                lines.append(
                    f"    {n:<12s} = {v:.6g} ± {se[n]:.2g} {unit}  [{lo:.6g}, {hi:.6g}] "
                    f"({level:.0%})"
                )
        return lines

    def _summary_params(self) -> dict:
        ci = self.ci(0.95)
        out = {}
        for n in self.names:
            entry = {
                "value": self.values[n],
                "unit": UNITS.get(n.rsplit("_", 1)[0] if n not in UNITS else n, ""),
                "vary": n in self.vary,
            }
            if n in self.vary:
                entry.update(
                    stderr=self.stderr[n],
                    ci95=list(ci[n]),
                    identifiable=self.identifiable[n],
                )
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
