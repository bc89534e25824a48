r"""Elastic–perfectly-plastic contact: Thornton's law (Thornton 1997; docs/theory.md).

Hertz's law holds until the contact pressure at the centre reaches the limiting (yield)
pressure :math:`p_y`, at the approach

.. math::

    \delta_y = R^*\left(\frac{\pi p_y}{2E^*}\right)^2, \qquad
    F_y = K\delta_y^{3/2}, \qquad K = \tfrac43 E^*\sqrt{R^*};

beyond it the pressure is capped at :math:`p_y` over a growing plastic core and the force
rises linearly, with the Hertz tangent stiffness at the yield point
(:math:`\pi p_y R^* = \tfrac32 K\sqrt{\delta_y} = 2E^*a_y`, so the force is continuous with
a continuous slope there):

.. math::

    F = F_y + \pi p_y R^*(\delta - \delta_y), \qquad \delta \ge \delta_y .

Unloading from :math:`(\delta_{max}, F_{max})` is elastic, Hertzian on the flatter
radius of the permanently deformed contact,

.. math::

    F = \tfrac43 E^*\sqrt{R_p}\,(\delta - \delta_p)^{3/2}, \quad
    R_p = \frac{4E^*}{3F_{max}}\left(\frac{2F_{max} + F_y}{2\pi p_y}\right)^{3/2}, \quad
    \delta_p = \delta_{max} - \left(\frac{3F_{max}}{4E^*\sqrt{R_p}}\right)^{2/3},

and the contact ends at the permanent approach :math:`\delta_p > 0`; reloading follows the
same elastic curve back to :math:`(\delta_{max}, F_{max})`. The force depends on the
approach and on its largest value so far, not on the rate: the energy lost is the plastic
work, the area between loading and unloading.

**The impact.** The yield speed :math:`v_y`, at which the maximum approach just reaches
:math:`\delta_y`, follows from :math:`\tfrac12 m^* v_y^2 = \tfrac{8}{15}E^*\sqrt{R^*}\,
\delta_y^{5/2}` (for a sphere of density ρ on a flat, :math:`v_y = 1.56\,(p_y^5/E^{*4}\rho)^{1/2}`).
In the units of the other laws, δ* = (m*·v0²/K)^{2/5} and δ*/v0, the impact at approach
speed :math:`v_0 > v_y` depends on the one number :math:`r = v_y/v_0`: the yield approach
is :math:`x_y = (5r^2/4)^{2/5}`, the plastic stretch a harmonic oscillation of frequency
:math:`\sqrt{3x_y^{1/2}/2}` about the offset spring, the unloading a Hertz half-pulse, and
the restitution the closed form

.. math::

    e = \sqrt{\frac{6\sqrt3}{5}}\,\sqrt{1 - \frac{r^2}{6}}\,
        \left[\frac{r}{r + 2\sqrt{6/5 - r^2/5}}\right]^{1/4}, \qquad e = 1 \text{ for } r \ge 1,

so e falls as :math:`v_0^{-1/4}` at high speed and de/dr = 0 at r = 1 (the loss grows as
:math:`(1 - r)^2` past the onset). :func:`cor_thornton` is that closed form,
:func:`calibrate_thornton` its inverse. Johnson puts the first yield inside the softer body
at :math:`p_0 = 1.60\,Y` (ν = 0.3, von Mises), Y its yield strength in tension: for a
sphere on a flat :math:`\rho V_Y^2/Y \approx 26(Y/E^*)^4`, about 0.1 m/s for medium-hard
steel (:func:`yield_onset_pressure`).

References
----------
C. Thornton, "Coefficient of restitution for collinear collisions of elastic-perfectly
plastic spheres", J. Appl. Mech. 64:383 (1997), doi:10.1115/1.2787319.
K. L. Johnson, *Contact Mechanics*, Cambridge University Press (1985), §6.2 (first yield,
p_0 = 1.60 Y) and §11.4 (the speed of first yield), doi:10.1017/CBO9781139171731.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .elastic import HERTZ_TC_CONSTANT, _f

__all__ = [
    "JOHNSON_FIRST_YIELD",
    "thornton",
    "ThorntonUnloading",
    "thornton_unloading",
    "yield_approach",
    "yield_force",
    "yield_velocity",
    "yield_pressure",
    "yield_onset_pressure",
    "cor_thornton",
    "calibrate_thornton",
]

#: p_0/Y at the first yield under a Hertz contact (ν = 0.3, von Mises; Johnson 1985, §6.2).
JOHNSON_FIRST_YIELD = 1.60


def _positive(x, name, unit):
    x = np.asarray(x, dtype=float)
    if np.any(~(x > 0)) or np.any(~np.isfinite(x)):
        raise InputError(f"{name} must be finite and > 0 [{unit}]; got {x!r}")
    return x


# ------------------------------------------------------------------ the yield point
def yield_approach(p_y, E_eff, R_eff):
    """Approach at which a Hertz contact's central pressure reaches p_y [m].

    δ_y = R*·(π·p_y/(2E*))², from p_0 = (2E*/π)·√(δ/R*) (Johnson 1985, §4.2).

    Parameters
    ----------
    p_y : float or array — yield (limiting) contact pressure [Pa]
    E_eff : float or array — effective modulus E* [Pa]
    R_eff : float or array — effective radius R* [m]
    """
    p = _positive(p_y, "the yield pressure p_y", "Pa")
    return _f(np.asarray(R_eff) * (np.pi * p / (2.0 * np.asarray(E_eff))) ** 2)


def yield_force(p_y, E_eff, R_eff):
    """Force at the yield point, F_y = (4/3)·E*·√R*·δ_y^{3/2} = (π·p_y)³·R*²/(6E*²) [N].

    Parameters as :func:`yield_approach`.
    """
    d = np.asarray(yield_approach(p_y, E_eff, R_eff))
    return _f(4.0 / 3.0 * np.asarray(E_eff) * np.sqrt(R_eff) * d**1.5)


def yield_velocity(p_y, E_eff, R_eff, m_eff):
    """The normal approach speed at which an impact just reaches the yield point [m/s].

    ½·m*·v_y² = (8/15)·E*·√R*·δ_y^{5/2} (the elastic energy at δ_y); for a sphere of
    density ρ on a flat, v_y = 1.56·√(p_y⁵/(E*⁴·ρ)) (Thornton 1997, eq. 16).

    Parameters
    ----------
    p_y : float or array — yield pressure [Pa]
    E_eff : E* [Pa]; R_eff : R* [m]; m_eff : effective mass m* [kg]
    """
    d = np.asarray(yield_approach(p_y, E_eff, R_eff))
    return _f(np.sqrt(16.0 / 15.0 * np.asarray(E_eff) * np.sqrt(R_eff) * d**2.5 / m_eff))


def yield_pressure(v_y, E_eff, R_eff, m_eff):
    """The yield pressure p_y [Pa] whose yield speed is v_y [m/s]: inverse of
    :func:`yield_velocity` (p_y ∝ v_y^{2/5})."""
    v = _positive(v_y, "the yield speed v_y", "m/s")
    E = np.asarray(E_eff, dtype=float)
    d = (15.0 * np.asarray(m_eff) * v**2 / (16.0 * E * np.sqrt(R_eff))) ** 0.4
    return _f(2.0 * E / np.pi * np.sqrt(d / np.asarray(R_eff)))


def yield_onset_pressure(Y):
    """Central Hertz pressure at which a body of yield strength Y first yields [Pa]:
    p_0 = 1.60·Y (:data:`JOHNSON_FIRST_YIELD`; Johnson 1985, §6.2: von Mises, ν = 0.3,
    the first yield below the surface)."""
    return _f(JOHNSON_FIRST_YIELD * _positive(Y, "the yield strength Y", "Pa"))


# ------------------------------------------------------------------ the force law
def _loading(d, dy, K):
    """Loading curve: Hertz to δ_y, then linear with the Hertz tangent stiffness there."""
    d = np.maximum(d, 0.0)
    elastic = K * d * np.sqrt(d)
    plastic = K * dy * np.sqrt(dy) + 1.5 * K * np.sqrt(dy) * (d - dy)
    return np.where(d <= dy, elastic, plastic)


def _unloading(dm, dy, K):
    """(F_max, √(R_p/R*), δ_p) of the unloading curve from δ_max = dm (K, δ_y as above)."""
    fm = _loading(dm, dy, K)
    with np.errstate(divide="ignore", invalid="ignore"):
        fr = np.maximum(fm / (K * dy * np.sqrt(dy)), 1.0)  # F_max/F_y, 1 while elastic
    rho = np.sqrt(((2.0 * fr + 1.0) / 3.0) ** 1.5 / fr)
    zm = np.cbrt((fm / (rho * K)) ** 2)
    return fm, rho, np.maximum(dm, 0.0) - zm


def _force(d, dm, dy, K, clip=True):
    """Thornton's force at approach d with largest approach so far dm (raised to d)."""
    d = np.asarray(d, dtype=float)
    dm = np.maximum(dm, d)
    _, rho, dp = _unloading(dm, dy, K)
    z = d - dp
    up = rho * K * np.abs(z) * np.sqrt(np.abs(z)) * np.sign(z)
    f = np.where(d >= dm, _loading(d, dy, K), up)
    return np.where(d > 0, np.maximum(f, 0.0), 0.0) if clip else f


def thornton(delta, delta_max, p_y, E_eff, R_eff):
    r"""Thornton's elastic–perfectly-plastic normal force [N] (module notes).

    Parameters
    ----------
    delta : float or array — normal approach (overlap) [m]
    delta_max : float or array — the largest approach reached so far [m] (values below
        ``delta`` are taken as ``delta``: the contact is then loading)
    p_y : float or array — yield (limiting) contact pressure [Pa], > 0
    E_eff : float or array — effective modulus E* [Pa]
    R_eff : float or array — effective radius R* [m]

    Returns
    -------
    F : compressive normal force [N], ≥ 0; zero for δ ≤ 0 and below the permanent
        approach δ_p of the unloading curve.

    Notes
    -----
    Loading (δ = δ_max): :math:`F = K\delta^{3/2}` to δ_y, then
    :math:`F = F_y + \pi p_y R^*(\delta - \delta_y)`; unloading and reloading below δ_max:
    :math:`F = \tfrac43 E^*\sqrt{R_p}(\delta - \delta_p)^{3/2}` (:func:`thornton_unloading`).
    The force does not depend on the approach rate.

    References
    ----------
    C. Thornton, J. Appl. Mech. 64:383 (1997), doi:10.1115/1.2787319.
    """
    K = 4.0 / 3.0 * np.asarray(E_eff) * np.sqrt(R_eff)
    dy = np.asarray(yield_approach(p_y, E_eff, R_eff))
    return _f(_force(delta, delta_max, dy, K))


@dataclass(frozen=True)
class ThorntonUnloading:
    """The elastic unloading curve of Thornton's law from a largest approach.

    Attributes
    ----------
    F_max : float — force at the largest approach [N]
    R_p : float — radius of the unloading Hertz curve [m] (R* while elastic, larger once
        the contact has yielded)
    delta_p : float — permanent approach, where the unloading force returns to zero [m]
    """

    F_max: float
    R_p: float
    delta_p: float


def thornton_unloading(delta_max, p_y, E_eff, R_eff) -> ThorntonUnloading:
    r"""The unloading curve of Thornton's law from ``delta_max`` [m] (module notes).

    :math:`R_p = \frac{4E^*}{3F_{max}}\left(\frac{2F_{max} + F_y}{2\pi p_y}\right)^{3/2}`,
    :math:`\delta_p = \delta_{max} - (3F_{max}/(4E^*\sqrt{R_p}))^{2/3}`; R_p = R* and
    δ_p = 0 while δ_max ≤ δ_y.

    Parameters
    ----------
    delta_max : float or array — largest approach [m]
    p_y : yield pressure [Pa]; E_eff : E* [Pa]; R_eff : R* [m]

    References
    ----------
    C. Thornton, J. Appl. Mech. 64:383 (1997), doi:10.1115/1.2787319.
    """
    K = 4.0 / 3.0 * np.asarray(E_eff) * np.sqrt(R_eff)
    dy = np.asarray(yield_approach(p_y, E_eff, R_eff))
    fm, rho, dp = _unloading(np.asarray(delta_max, dtype=float), dy, K)
    return ThorntonUnloading(_f(fm), _f(rho**2 * np.asarray(R_eff)), _f(dp))


# ------------------------------------------------------------------ the impact
def _e_of_r(r):
    """Thornton's closed-form e(r) and d e/d r for 0 < r ≤ 1 (arrays)."""
    g = np.sqrt(1.2 - 0.2 * r * r)
    q = r / (r + 2.0 * g)
    e = math.sqrt(6.0 * math.sqrt(3.0) / 5.0) * np.sqrt(1.0 - r * r / 6.0) * q**0.25
    dg = -0.2 * r / g
    dlog = -(r / 6.0) / (1.0 - r * r / 6.0) + 0.25 * (1.0 / r - (1.0 + 2.0 * dg) / (r + 2.0 * g))
    return e, e * dlog


def cor_thornton(r):
    r"""Coefficient of restitution of Thornton's law at r = v_y/v0 [-] (module notes).

    Parameters
    ----------
    r : float or array — yield speed over the normal approach speed [-], ≥ 0

    Returns
    -------
    e [-]: 1 for r ≥ 1 (the impact stays elastic), 0 for r = 0 (p_y = 0), else

    .. math:: e = \sqrt{\frac{6\sqrt3}{5}}\,\sqrt{1 - \frac{r^2}{6}}\,
              \left[\frac{r}{r + 2\sqrt{6/5 - r^2/5}}\right]^{1/4}.

    References
    ----------
    C. Thornton, J. Appl. Mech. 64:383 (1997), doi:10.1115/1.2787319, eq. (27).
    """
    r = np.asarray(r, dtype=float)
    if np.any(~(r >= 0)) or np.any(np.isnan(r)):
        raise InputError(f"Thornton's r = v_y/v0 must be ≥ 0; got r = {r!r}")
    rr = np.clip(r, 1e-300, 1.0)
    e = _e_of_r(rr)[0]
    return _f(np.where(r >= 1.0, 1.0, np.where(r > 0, e, 0.0)))


def calibrate_thornton(e):
    """The r = v_y/v0 [-] at which Thornton's law rebounds with restitution e ∈ (0, 1].

    Inverts the closed form of :func:`cor_thornton` (increasing in r) to double precision:
    bisection-safeguarded Newton iteration on √(1 − e(r)), which is linear in 1 − r at the
    onset of yield where e(r) itself is flat (de/dr = 0 at r = 1), from the cubic Hermite
    interpolant of a table of r and dr/d√(1 − e) made once (~3e-8 of r at most: one Newton step
    lands within rounding, a second confirms it); r = 1 for e = 1 (the onset; every r ≥ 1
    gives e = 1). Multiply by v0 for the yield speed; :func:`yield_pressure` gives p_y.

    Raises
    ------
    InputError
        For e outside (0, 1].
    """
    from .damping import _newton_increasing

    e_in = np.asarray(e, dtype=float)
    if np.any(~((e_in > 0) & (e_in <= 1))):
        raise InputError(f"Thornton's law reaches every e in (0, 1]; got e = {e!r}")
    e = np.atleast_1d(e_in)
    h_target = np.sqrt(1.0 - e)
    r0 = _cor_start(h_target)

    def fun(r, idx):
        val, der = _e_of_r(r)
        h = np.sqrt(np.maximum(1.0 - val, 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            dh = np.where(h > 0, der / (2.0 * h), np.inf)
        return h_target[idx] - h, dh

    r = _newton_increasing(fun, r0, np.zeros_like(e), np.ones_like(e), rtol=1e-15)
    return _f(np.where(e >= 1.0, 1.0, r).reshape(e_in.shape))


#: √(1 − e) below which :func:`_cor_table` interpolates linearly.
_H_LINEAR = 1e-3


@functools.cache
def _cor_table():
    """(√(1 − e) at the nodes, each interval's cubic in t ∈ [0, 1] across it: (intervals, 4),
    coefficients of 1, t, t², t³) of Thornton's closed form r(√(1 − e)) on r from 1e-14 to
    1, √(1 − e) increasing: the cubic Hermite interpolant of r and its slope
    dr/d√(1 − e) at the nodes, Newton's starting values for :func:`calibrate_thornton`
    (:func:`_cor_start`). Where 1 − e < 1e-6 (√(1 − e) < :data:`_H_LINEAR`) it is computed
    from e to no better than 1e-10 of itself, too coarse for the slopes, and r is linear in
    √(1 − e) (the loss grows as (1 − r)²): there the interpolant is linear."""
    r = np.concatenate([np.geomspace(1e-14, 0.5, 300), 1.0 - np.geomspace(0.5, 1e-9, 300)[1:]])
    e, de = _e_of_r(r)
    h = np.sqrt(np.maximum(1.0 - e, 0.0))
    slope = -2.0 * h / de  # dr/dh: dh/dr = −(de/dr)/(2h)
    h, r, slope = h[::-1], r[::-1], slope[::-1]
    step = np.diff(h)
    r0, r1, d0, d1 = r[:-1], r[1:], slope[:-1] * step, slope[1:] * step
    coef = np.column_stack([r0, d0, 3.0 * (r1 - r0) - 2.0 * d0 - d1, 2.0 * (r0 - r1) + d0 + d1])
    linear = h[:-1] < _H_LINEAR
    zero = np.zeros_like(r0)
    coef[linear] = np.column_stack([r0, r1 - r0, zero, zero])[linear]
    return h, coef


def _cor_start(h):
    """r at √(1 − e) = ``h`` (array) from :func:`_cor_table`, held at the table's ends
    beyond them."""
    nodes, coef = _cor_table()
    i = np.searchsorted(nodes, h, side="right") - 1
    np.minimum(np.maximum(i, 0, out=i), coef.shape[0] - 1, out=i)
    c = coef[i]
    t = np.clip((h - nodes[i]) / (nodes[i + 1] - nodes[i]), 0.0, 1.0)
    return ((c[:, 3] * t + c[:, 2]) * t + c[:, 1]) * t + c[:, 0]


@dataclass(frozen=True)
class _Impact:
    """A dimensionless Thornton impact (δ*, δ*/v0 units, K = m* = v0 = 1) at r ≤ 1 (arrays).

    Phases: Hertz loading to x_y (duration tau_y), the plastic stretch (a harmonic
    oscillation of ξ = x − x_y + ξ0 at frequency ω, amplitude A, phase θ, duration s_m),
    Hertz unloading on ρ² = R_p/R* from x_m to x_p (duration tau_u, rebound speed e)."""

    xy: np.ndarray
    k: np.ndarray
    A: np.ndarray
    theta: np.ndarray
    xm: np.ndarray
    fm: np.ndarray
    rho: np.ndarray
    zm: np.ndarray
    e: np.ndarray
    tau_y: np.ndarray
    s_m: np.ndarray
    tau_u: np.ndarray

    @property
    def tau_c(self):
        return self.tau_y + self.s_m + self.tau_u

    @property
    def xp(self):
        return self.xm - self.zm

    def state(self, tau):
        """(x, u, f, df) at instants tau (shape (M, n), from first contact)."""
        tau = np.asarray(tau, dtype=float)
        col = (lambda a: a[:, None]) if tau.ndim == 2 else (lambda a: a)
        xy, k, A, th = col(self.xy), col(self.k), col(self.A), col(self.theta)
        w = np.sqrt(k)
        t1, t2 = col(self.tau_y), col(self.tau_y + self.s_m)
        L = (col(self.e) ** 2 / col(self.rho)) ** 0.4  # the unloading's length (U²/ρ)^{2/5}
        # loading (Hertz): the canonical half-pulse; unloading: the rise of a Hertz impact
        # of speed e on ρ, run backwards (both rises looked up at once)
        U = col(self.e)
        (x1, z3), (u1, u3) = _hertz_rise(
            np.clip(np.stack([tau / _HALF, (col(self.tau_c) - tau) * U / L / _HALF]), 0.0, 1.0)
        )
        # the plastic stretch
        ph = w * np.maximum(tau - t1, 0.0) - th
        xi = A * np.cos(ph)  # ξ, the stretch's spring
        x2 = xy / 3.0 + xi
        u2 = -A * w * np.sin(ph)
        z = L * z3  # the unloading's elastic approach
        x3, u3 = col(self.xp) + z, -U * u3
        rho = col(self.rho)
        q1 = np.sqrt(x1)
        first, second = tau <= t1, tau <= t2  # the phases (each test once)
        x = np.where(first, x1, np.where(second, x2, x3))
        u = np.where(first, u1, np.where(second, u2, u3))
        f = np.where(first, x1 * q1, np.where(second, k * xi, rho * z**1.5))
        df = np.where(first, 1.5 * q1 * u1, np.where(second, k * u2, 1.5 * rho * np.sqrt(z) * u3))
        return x, u, f, df


#: Duration of the canonical Hertz rise (x'' = −x^{3/2}, x(0) = 0, x'(0) = 1) to its peak
#: (5/4)^{2/5}: half the elastic contact time in δ*/v0 units.
_HALF = 0.5 * HERTZ_TC_CONSTANT * 1.25**0.4


def _stretch(r):
    """The plastic stretch of the impact at r = v_y/v0 (array, clipped to (0, 1]): x_y,
    the slope k, the oscillation's amplitude A and phase θ (ξ = x − x_y + (2/3)x_y =
    A·cos(√k·s − θ) from the yield point), and the largest approach x_m = x_y/3 + A."""
    r = np.clip(np.asarray(r, dtype=float), 1e-300, 1.0)
    xy = (1.25 * r * r) ** 0.4  # ½r² = (2/5)x_y^{5/2}
    k = 1.5 * np.sqrt(xy)
    xi0 = 2.0 / 3.0 * xy  # F_y/k
    uy2 = np.maximum(1.0 - r * r, 0.0)  # the rate at the yield point, squared
    A = np.sqrt(xi0 * xi0 + uy2 / k)
    return xy, k, A, np.arctan2(np.sqrt(uy2 / k), xi0), xy / 3.0 + A


def _impact(r) -> _Impact:
    """The dimensionless Thornton impact at r = v_y/v0 (array, clipped to (0, 1])."""
    from scipy import special  # loaded on first use

    xy, k, A, theta, xm = _stretch(r)
    fm, rho, xp = _unloading(xm, xy, 1.0)
    zm = xm - xp
    e = np.sqrt(0.8 * rho) * zm**1.25
    tau_y = _HALF * special.betainc(0.4, 0.5, np.clip(np.asarray(r, dtype=float), 0.0, 1.0) ** 2)
    L = (e * e / rho) ** 0.4
    return _Impact(xy, k, A, theta, xm, fm, rho, zm, e, tau_y, theta / np.sqrt(k), _HALF * L / e)


@functools.cache
def _rise_table(n=4096):
    """Nodes of the canonical Hertz rise (x'' = −x^{3/2}, x(0) = 0, x'(0) = 1) on n equal
    steps of s = τ/τ_half: x, u = x' (exact, from the inverse incomplete beta function;
    :func:`pipeline.contact.hertz_pulse`) and u' = −x^{3/2}."""
    from scipy import special

    s = np.linspace(0.0, 1.0, n + 1)
    w = special.betaincinv(0.4, 0.5, s)  # 0.8·x^{5/2}
    w[-1] = 1.0
    x = (1.25 * w) ** 0.4
    u = np.sqrt(np.maximum(1.0 - w, 0.0))
    return x, u, -(x**1.5)  # x, u and u' = −x^{3/2}


def _hertz_rise(s):
    """(x, u) of the canonical Hertz rise at s = τ/τ_half ∈ [0, 1]: cubic Hermite
    interpolation of :func:`_rise_table` (values and rates; ~1e-13 of δ*)."""
    x, u, a = _rise_table()
    n = x.size - 1
    h = _HALF / n
    p = np.asarray(s, dtype=float) * n
    i = np.floor(p).astype(np.intp)
    np.minimum(np.maximum(i, 0, out=i), n - 1, out=i)  # np.clip's checks cost more
    t = p - i
    x0, x1, u0, u1 = x[i], x[i + 1], u[i], u[i + 1]
    a0, a1 = a[i], a[i + 1]
    t2, t3 = t * t, t * t * t
    h00, h10, h01, h11 = 2 * t3 - 3 * t2 + 1, t3 - 2 * t2 + t, -2 * t3 + 3 * t2, t3 - t2
    xs = h00 * x0 + h10 * h * u0 + h01 * x1 + h11 * h * u1
    us = h00 * u0 + h10 * h * a0 + h01 * u1 + h11 * h * a1
    return xs, us


def _law_force(delta, delta_dot, r, K, m_eff, v0, clip=True):
    """The law in :class:`~pipeline.contact.NormalLaw`'s signature for one impact from
    approach speed v0 at δ = 0: r = v_y/v0, the largest approach that impact's own
    (closed form), loading while δ̇ ≥ 0."""
    r = np.asarray(r, dtype=float)
    K, m_eff, v0 = (np.asarray(a, dtype=float) for a in (K, m_eff, v0))
    dstar = (m_eff * v0 * v0 / K) ** 0.4
    dy = dstar * (1.25 * r * r) ** 0.4
    dm = dstar * _stretch(r)[4]  # the impact's largest approach ((5/4)^{2/5}·δ* for r ≥ 1)
    d = np.asarray(delta, dtype=float)
    dm = np.where(np.asarray(delta_dot) >= 0, d, dm)
    return _force(d, dm, dy, K, clip=clip)


def _no_damping(delta, r, K, m_eff, v0):
    return _f(np.zeros_like(np.asarray(delta, dtype=float)))
