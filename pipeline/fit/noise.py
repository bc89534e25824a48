r"""The noise a record carries, measured before the trigger, and the fits' whitening of it.

The weights of a fit are 1/σ of each channel's noise, and its covariance and misfit test
assume that noise is white. A charge amplifier's low-pass filter, mains pick-up or 1/f
noise makes neighbouring samples correlated, and then χ² over-counts the information in the
record: the covariance intervals shrink (covering the truth 34–70 % of the time under
AR(1) noise with φ = 0.9), and the residuals' long runs are blamed on the model.

So the noise is measured where the record holds nothing else: the pre-trigger samples, less
their baseline. An autoregressive model

.. math::

    n_k = \sum_{j=1}^{p} \phi_j\, n_{k-j} + \varepsilon_k, \qquad
    \varepsilon_k \sim N(0, s^2\sigma^2)

is fitted to them by the Yule–Walker equations (Levinson–Durbin recursion), its order p ≤
:data:`P_MAX` chosen by BIC (n·ln s²_p + p·ln n; Schwarz 1978), and kept only where the
autocorrelation of those samples is significant (Ljung–Box statistic over :data:`LB_LAGS`
lags beyond its 1 − :data:`LB_ALPHA` quantile; Ljung & Box 1978). A fit then works with the
whitened residuals :math:`(r_k - \sum_j \phi_j r_{k-j})/s` — generalised least squares with
the measured correlation (prewhitening; the channel's baseline basis is whitened alike) —
so its χ², covariance, runs test and bootstrap see white noise again. An AR model of low
order also approximates 1/f noise over the few hundred samples of a contact well enough for
the intervals (``make bench``, misspec, measures the coverage).

References
----------
G. M. Ljung, G. E. P. Box, Biometrika 65:297 (1978), doi:10.1093/biomet/65.2.297.
G. Schwarz, Ann. Stat. 6:461 (1978), doi:10.1214/aos/1176344136.
J. Durbin, Rev. Inst. Int. Stat. 28:233 (1960), doi:10.2307/1401322 (the recursion).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import special

__all__ = ["NoiseModel", "measure_noise", "P_MAX", "LB_LAGS", "LB_ALPHA"]

#: Highest AR order tried.
P_MAX = 8
#: Lags of the Ljung–Box test, and its level.
LB_LAGS, LB_ALPHA = 10, 0.01
#: Fewest pre-trigger samples to measure the noise's correlation on.
MIN_SAMPLES = 64


@dataclass(frozen=True)
class NoiseModel:
    """A channel's noise correlation (module notes).

    Attributes
    ----------
    phi : numpy.ndarray — AR coefficients φ_1 … φ_p (empty: white)
    innovation : float — s, the innovations' standard deviation over the noise's σ
    ljung_box_p : float — p-value of the Ljung–Box test on the pre-trigger samples
    lag1 : float — their lag-1 autocorrelation
    n : int — samples measured
    """

    phi: np.ndarray
    innovation: float = 1.0
    ljung_box_p: float = math.nan
    lag1: float = math.nan
    n: int = 0

    @property
    def white(self) -> bool:
        return self.phi.size == 0

    def whiten(self, r):
        """``r`` (…, n), white noise of unit variance where ``r`` is this noise over σ."""
        if self.white:
            return r
        from scipy.signal import lfilter

        a = np.concatenate([[1.0], -self.phi])
        return lfilter(a, [1.0], r, axis=-1) / self.innovation

    def summary(self) -> dict:
        return {
            "ar_order": int(self.phi.size),
            "phi": self.phi.tolist(),
            "innovation_over_sigma": self.innovation,
            "ljung_box_p": self.ljung_box_p,
            "lag1_autocorrelation": self.lag1,
            "samples": self.n,
        }


WHITE = NoiseModel(np.zeros(0))


def _acf(x, max_lag):
    """Autocorrelations of ``x`` at lags 0 … ``max_lag`` (< its size), the biased estimate;
    None where ``x`` is constant."""
    x = np.asarray(x, dtype=float)
    n = x.size
    x = x - np.add.reduce(x) / n  # numpy's mean, without its wrapper
    # (x[: n − k] @ x[k:]: the same BLAS dot, by the lighter call)
    ac = np.array([x[: n - k].dot(x[k:]) for k in range(max_lag + 1)]) / n
    return ac / ac[0] if ac[0] > 0 else None


def _levinson(rho, p_max):
    """AR coefficients of orders 0…p_max and their innovation variances (over the
    variance) from autocorrelations ``rho`` (Levinson–Durbin)."""
    phis, vs = [np.zeros(0)], [1.0]
    phi, v = phis[0], 1.0
    for k in range(1, p_max + 1):
        acc = rho[k] - (phi @ rho[k - 1 : 0 : -1] if k > 1 else 0.0)
        kappa = acc / v
        new = np.empty(k)  # (φ − κ·φ reversed, κ), a new array each order
        np.subtract(phi, kappa * phi[::-1], out=new[:-1])
        new[-1] = kappa
        phi = new
        v = v * (1.0 - kappa * kappa)
        if not v > 0:
            break
        phis.append(phi)
        vs.append(v)
    return phis, vs


def measure_noise(x) -> NoiseModel:
    """The noise model of a channel from its pre-trigger samples ``x`` less their baseline
    (any units; module notes). White when there are fewer than :data:`MIN_SAMPLES` or no
    significant correlation."""
    x = np.asarray(x, dtype=float)
    n = x.size
    lags = min(LB_LAGS, n // 4)
    rho = _acf(x, max(lags, P_MAX)) if n >= MIN_SAMPLES else None
    if rho is None:
        return NoiseModel(np.zeros(0), n=n)
    # (numpy's sum, without its wrapper)
    q = n * (n + 2) * float(np.add.reduce(rho[1 : lags + 1] ** 2 / (n - np.arange(1, lags + 1))))
    p_value = float(special.chdtrc(lags, q))
    if p_value >= LB_ALPHA:
        return NoiseModel(np.zeros(0), 1.0, p_value, float(rho[1]), n)
    phis, vs = _levinson(rho, min(P_MAX, n // 8))
    bic = [n * math.log(v) + k * math.log(n) for k, v in enumerate(vs)]
    k = min(range(len(bic)), key=bic.__getitem__)  # numpy's argmin (the first; all finite)
    if k == 0:
        return NoiseModel(np.zeros(0), 1.0, p_value, float(rho[1]), n)
    return NoiseModel(phis[k], math.sqrt(vs[k]), p_value, float(rho[1]), n)
