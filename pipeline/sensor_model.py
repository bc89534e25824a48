r"""Sensor model: an ideal force record → what a tri-axial piezo rig would export.

The simulator (:mod:`pipeline.simulate`) produces *ideal* records: the exact contact
force, densely sampled, zero outside the contact. A laboratory record of the same impact
(Garland & Rogers' pendulum rig, docs/theory.md: a spherical target cap on a tri-axial
piezoelectric force transducer) differs from it in the ways :func:`to_sensor` models, in
the order the signal meets them on its way through the hardware:

1. **Acquisition window.** The digitiser records ``pre_trigger`` seconds before the
   contact and ``post_trigger`` seconds after it, where the true force is zero; the first
   sample falls at an arbitrary sub-sample ``phase`` relative to the contact start
   (the trigger is asynchronous with the sample clock).
2. **Axis cross-talk** of the transducer, a mixing matrix :math:`C` with unit diagonal and
   off-diagonal entries of a few per cent: :math:`\mathbf F_{meas} = C\,\mathbf F_{true}`
   in the axis order (Fn, Ft, Fy).
3. **Finite bandwidth** of transducer and charge amplifier: an analogue Butterworth
   low-pass of order ``filter_order`` and cut-off ``bandwidth`` [Hz], applied *causally*,
   as the hardware does. A causal filter delays the signal: for order 2 the delay of a
   slowly varying signal is :math:`\sqrt2/(2\pi f_c)` (0.75 µs at 300 kHz). The filter
   is discretised exactly for a piecewise-linear input (first-order hold) on a grid
   ``oversample`` times finer than the output rate, then sampled at ``rate`` [Hz].
4. **Baseline**: a constant offset [N] and a linear drift [N/s] per axis, counted from the
   first sample, then **white noise** [N rms] per axis, independent from sample to sample
   (amplifier and ADC noise at the sample instants).
5. **ADC quantisation**: a bipolar converter of ``bits`` bits spanning ``full_scale`` [N]
   (±full_scale/2), mid-tread rounding to the step :math:`q = \text{full\_scale}/2^{bits}`;
   values beyond the range saturate at the end codes (with a warning).

   In series with it, where given, the **mounted transducer's mode** (the target and
   the crystal a mass on a stiff spring: natural frequency ``resonance`` [Hz], damping
   ratio ``damping_ratio``), :math:`H(s) = \omega_n^2/(s^2 + 2\zeta\omega_n s +
   \omega_n^2)`: a short pulse rings after the contact at
   :math:`\omega_d = \omega_n\sqrt{1-\zeta^2}`, decaying as :math:`e^{-\zeta\omega_n t}`
   (logarithmic decrement :math:`2\pi\zeta/\sqrt{1-\zeta^2}`), and H(0) = 1 keeps the
   percussion; and the **piezo's discharge** through the charge amplifier's time
   constant ``discharge`` [s], a first-order high-pass :math:`H(s) = s/(s + 1/\tau)`: a
   constant force decays as :math:`e^{-t/\tau}`, and after a pulse the signal undershoots
   and recovers with τ. The whole chain is discretised at once, exactly for a
   piecewise-linear input (:func:`foh_filter`).

Not modelled: gain errors of each axis (give a ``crosstalk`` matrix with a diagonal other
than 1 to model them).

The output keeps the ideal record's clock: its ``time`` [s] is on the same axis as the
input's, so a record simulated from first contact at t = 0 comes back with negative
pre-trigger times, as laboratory exports do.

References
----------
M. J. Garland, R. J. Rogers, "An Experimental Study of Contact Forces During Oblique
Elastic Impact", J. Appl. Mech. 76:031015 (2009), doi:10.1115/1.3086432.
S. Butterworth, "On the Theory of Filter Amplifiers", Wireless Engineer 7:536 (1930).
G. F. Franklin, J. D. Powell, M. L. Workman, *Digital Control of Dynamic Systems*,
3rd ed., Addison-Wesley (1998), §6.3.2 (first-order-hold equivalent).
C. M. Harris, A. G. Piersol, *Harris' Shock and Vibration Handbook*, 5th ed., McGraw-Hill
(2002), ch. 12 (piezoelectric transducers: mounted resonance, discharge time constant).
"""

from __future__ import annotations

import functools
import math
import warnings
from dataclasses import dataclass

import numpy as np
import xarray as xr
from scipy import signal

from .errors import InputError, PipelineWarning
from .record import FORCE_CHANNELS, channel, make_record, validate
from .scene import Scene

__all__ = [
    "to_sensor",
    "butterworth_sos",
    "sensor_zpk",
    "foh_filter",
    "FohFilter",
    "SENSOR_DEFAULTS",
    "SensorSaturationWarning",
]

#: Defaults of :func:`to_sensor`, plausible for the Garland–Rogers rig (docs/theory.md).
SENSOR_DEFAULTS = {
    "rate": 2.0e6,  # [Hz] ~200 samples over a 100 µs contact
    "noise": 2.0,  # [N rms] ~0.15–0.3 % of a 0.6–1.4 kN peak
    "offset": (4.0, -3.0, 2.0),  # [N] residual baseline after the amplifier reset
    "drift": (2.0, -1.5, 1.0),  # [N/s] charge-amplifier drift (invisible over < 1 ms)
    "bits": 16,  # ADC resolution
    "full_scale": 5000.0,  # [N] span of the ADC, ±2.5 kN
    "bandwidth": 300.0e3,  # [Hz] -3 dB cut-off of transducer + amplifier
    "filter_order": 2,  # Butterworth order
    "crosstalk": 0.02,  # off-diagonal cross-talk entries drawn in ±2 %
    "pre_trigger": 100.0e-6,  # [s]
    "post_trigger": 200.0e-6,  # [s]
    "resonance": math.inf,  # [Hz] mounted transducer's mode: none (far above the band)
    "damping_ratio": 0.05,  # [-] of that mode: a bolted piezo transducer rings lightly
    "discharge": math.inf,  # [s] charge amplifier's time constant: none (DC coupled)
}

_AXES = FORCE_CHANNELS  # ("Fn", "Ft", "Fy"): the order of every per-axis parameter
_OFF_DIAGONAL = [(0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1)]


class SensorSaturationWarning(PipelineWarning):
    """The simulated signal exceeded the ADC range and was clipped."""


def _per_axis(value, name, *, nonneg=True, allow_inf=False):
    a = np.asarray(value, dtype=float)
    if a.ndim == 0:
        a = np.full(3, float(a))
    if a.shape != (3,):
        raise InputError(
            f"to_sensor: {name} must be one number or three (for Fn, Ft, Fy); got {value!r}"
        )
    if np.isnan(a).any() or (not allow_inf and not np.isfinite(a).all()):
        raise InputError(f"to_sensor: {name} = {value!r} must be finite")
    if nonneg and (a < 0).any():
        raise InputError(f"to_sensor: {name} = {value!r} must be ≥ 0")
    return a


def _positive(value, name, *, allow_inf=False):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"to_sensor: {name} must be a number, got {value!r}") from None
    if not (v > 0) or (not allow_inf and not math.isfinite(v)):
        raise InputError(
            f"to_sensor: {name} = {value!r} must be positive and finite"
            + (" (or inf)" if allow_inf else "")
        )
    return v


def _nonneg(value, name):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"to_sensor: {name} must be a number, got {value!r}") from None
    if not (v >= 0) or not math.isfinite(v):
        raise InputError(f"to_sensor: {name} = {value!r} must be finite and ≥ 0")
    return v


def butterworth_sos(order: int, bandwidth: float, dt: float) -> np.ndarray:
    """The sensor's low-pass as digital second-order sections [-].

    An analogue Butterworth low-pass of ``order`` and ``bandwidth`` [Hz] (−3 dB), made
    discrete for the step ``dt`` [s] exactly for inputs linear between samples
    (first-order hold), for :func:`scipy.signal.sosfilt`. The same filter
    :func:`to_sensor` applies and :mod:`pipeline.fit` models.
    """
    z, p, k = signal.butter(order, 2.0 * np.pi * bandwidth, analog=True, output="zpk")
    A, B, C, D = signal.zpk2ss(z, p, k)
    Ad, Bd, Cd, Dd, _ = signal.cont2discrete((A, B, C, D), dt, method="foh")
    b, a = signal.ss2tf(Ad, Bd, Cd, Dd)
    return signal.tf2sos(b[0], a)


@functools.lru_cache(maxsize=64)
def _butter_zpk(order: int, bandwidth: float) -> tuple[tuple, tuple, float]:
    """The analogue Butterworth low-pass's zeros, poles [rad/s] and gain (scipy's design,
    kept: a fit with the sensor's mode free designs the chain anew at every mode it tries,
    the low-pass the same each time)."""
    zb, pb, kb = signal.butter(order, 2.0 * np.pi * bandwidth, analog=True, output="zpk")
    return tuple(zb), tuple(pb), float(kb)


def sensor_zpk(
    bandwidth: float = math.inf,
    filter_order: int = 2,
    resonance: float = math.inf,
    damping_ratio: float = 0.05,
    discharge: float = math.inf,
):
    """Analogue zeros, poles [rad/s] and gain of the sensor chain (module notes).

    The Butterworth low-pass of ``filter_order`` and ``bandwidth`` [Hz] (none if inf), in
    series with the mounted mode ωn²/(s² + 2ζωn s + ωn²) at ``resonance`` [Hz] (none if
    inf) of ``damping_ratio`` ζ [-], and the discharge s/(s + 1/τ) of time constant
    ``discharge`` τ [s] (none if inf).

    Returns
    -------
    z, p : numpy.ndarray (complex) — zeros and poles [rad/s]; k : float — gain
    """
    z, p, k = [], [], 1.0
    if math.isfinite(bandwidth):
        zb, pb, kb = _butter_zpk(int(filter_order), float(bandwidth))
        z += zb
        p += pb
        k *= kb
    if math.isfinite(resonance):
        wn = 2.0 * np.pi * resonance
        zeta = float(damping_ratio)
        root = np.sqrt(complex(zeta * zeta - 1.0))
        p += [wn * (-zeta + root), wn * (-zeta - root)]
        k *= wn * wn
    if math.isfinite(discharge):
        z.append(0.0)
        p.append(-1.0 / discharge)
    return np.asarray(z, dtype=complex), np.asarray(p, dtype=complex), k


@dataclass(frozen=True, eq=False)
class FohFilter:
    r"""A linear analogue filter discretised exactly for a piecewise-linear input (first-order
    hold), in parallel form: :math:`H(z) = D + \sum_i c_i\,(1 - z^{-1})/(1 - q_i z^{-1})`,
    q_i = exp(p_i·dt) (:func:`foh_filter`). Call it on samples ``x`` (…, n), zero state.

    Attributes
    ----------
    direct : float — D [-] (the analogue filter's gain at s → ∞ plus every pole's −r/p)
    poles : numpy.ndarray — q_i of the real poles and of one pole of each complex pair
    gains : numpy.ndarray — c_i
    pair : numpy.ndarray of bool — the pole stands for a conjugate pair (its part doubled,
        real part taken)
    dt : float — the step [s]
    """

    direct: float
    poles: np.ndarray
    gains: np.ndarray
    pair: np.ndarray
    dt: float

    def __call__(self, x, axis=-1):
        x = np.asarray(x, dtype=float)
        y = self.direct * x
        for q, c, two in zip(self.poles, self.gains, self.pair, strict=True):
            if two:
                w = signal.lfilter([1.0, -1.0], [1.0, -q], x.astype(complex), axis=axis)
                y = y + 2.0 * (c * w).real
            else:
                w = signal.lfilter([1.0, -1.0], [1.0, -q.real], x, axis=axis)
                y = y + c.real * w
        return y

    def slowest_rate(self) -> float:
        """The slowest pole's decay rate −Re p [1/s] (inf without poles)."""
        if not self.poles.size:
            return math.inf
        return float(np.min(-np.log(np.abs(self.poles)))) / self.dt


#: Poles closer than this (relative) are moved apart before the partial fractions: a
#: double pole (a mode of ζ = 1/√2 at a 2nd-order Butterworth's cut-off) has none.
_POLE_SEPARATION = 1e-8


def foh_filter(z, p, k, dt: float) -> FohFilter:
    r"""The analogue filter (zeros ``z``, poles ``p`` [rad/s], gain ``k``) discretised at step
    ``dt`` [s] exactly for inputs linear between samples (first-order hold).

    Notes
    -----
    The triangle-hold equivalent :math:`H(z) = \frac{(z-1)^2}{z\,T}
    \mathcal Z\{H(s)/s^2\}` (Franklin, Powell & Workman 1998, §6.3.2), taken term by
    term of the partial fractions :math:`H(s) = D + \sum_i r_i/(s - p_i)`, gives for each
    pole :math:`-r_i/p_i + \frac{r_i (q_i - 1)}{p_i^2 T}\frac{1 - z^{-1}}{1 - q_i z^{-1}}`,
    :math:`q_i = e^{p_i T}` — the parallel form of :class:`FohFilter`, which keeps its
    precision where a pole lies close to z = 1 (a discharge of seconds sampled at MHz),
    unlike the polynomial coefficients of a transfer function.
    """
    z = np.asarray(z, dtype=complex)
    p = np.asarray(p, dtype=complex).copy()
    scale = np.max(np.abs(p)) if p.size else 1.0
    for i in range(1, p.size):  # separate coincident poles
        while np.any(np.abs(p[:i] - p[i]) < _POLE_SEPARATION * scale):
            p[i] = p[i] * (1.0 + _POLE_SEPARATION) + 1j * _POLE_SEPARATION * scale * np.sign(
                p[i].imag or 1.0
            )
    direct = float(k) if z.size == p.size else 0.0
    if z.size > p.size:
        raise ValueError("an improper filter (more zeros than poles) has no hold equivalent")
    upper = np.flatnonzero(p.imag >= -1e-12 * scale)
    qs, cs, pairs = [], [], []
    for i in upper:
        pi = p[i]
        r = k * np.prod(pi - z) / np.prod(pi - np.delete(p, i))
        x = pi * dt
        qs.append(np.exp(x))
        cs.append(r * np.expm1(x) / (pi * pi * dt))
        two = abs(pi.imag) > 1e-12 * scale
        pairs.append(two)
        direct += float(((-r / pi) * (2.0 if two else 1.0)).real)
    return FohFilter(direct, np.array(qs), np.array(cs), np.array(pairs, dtype=bool), float(dt))


def _seed_sequence(seed):
    if isinstance(seed, np.random.SeedSequence):
        return seed
    if seed is None:
        return np.random.SeedSequence()
    try:
        s = int(seed)
    except (TypeError, ValueError):
        raise InputError(f"to_sensor: seed must be an integer or None, got {seed!r}") from None
    if s != seed or s < 0:
        raise InputError(f"to_sensor: seed must be a non-negative integer, got {seed!r}")
    return np.random.SeedSequence(s)


def to_sensor(
    record: xr.Dataset,
    *,
    rate: float = SENSOR_DEFAULTS["rate"],
    noise=SENSOR_DEFAULTS["noise"],
    offset=SENSOR_DEFAULTS["offset"],
    drift=SENSOR_DEFAULTS["drift"],
    bits: int | None = SENSOR_DEFAULTS["bits"],
    bandwidth: float = SENSOR_DEFAULTS["bandwidth"],
    filter_order: int = SENSOR_DEFAULTS["filter_order"],
    crosstalk=SENSOR_DEFAULTS["crosstalk"],
    pre_trigger: float = SENSOR_DEFAULTS["pre_trigger"],
    post_trigger: float = SENSOR_DEFAULTS["post_trigger"],
    full_scale=SENSOR_DEFAULTS["full_scale"],
    phase: float | None = None,
    oversample: int | None = None,
    seed=None,
    resonance: float = SENSOR_DEFAULTS["resonance"],
    damping_ratio: float = SENSOR_DEFAULTS["damping_ratio"],
    discharge: float = SENSOR_DEFAULTS["discharge"],
) -> xr.Dataset:
    r"""What a tri-axial piezo force rig would record of an ideal force history.

    Parameters
    ----------
    record : xarray.Dataset
        Ideal record (:mod:`pipeline.record` layout): ``Fn``, ``Ft`` and optionally ``Fy``
        [N] on ``time`` [s]. The true force is taken as linearly interpolated between the
        record's samples and zero outside its span (a simulated record spans the contact).
        A missing ``Ft`` or ``Fy`` is a zero true force on that axis; the output always
        has all three axes, as a tri-axial transducer exports them.
    rate : float
        Sampling rate of the digitiser [Hz]. Default 2 MHz.
    noise : float or (3,) array_like
        White-noise standard deviation per axis [N rms]. Default 2 N.
    offset : float or (3,) array_like
        Baseline offset per axis (Fn, Ft, Fy) [N]. Default (4, −3, 2) N.
    drift : float or (3,) array_like
        Linear baseline drift per axis [N/s], zero at the first sample. Default
        (2, −1.5, 1) N/s.
    bits : int or None
        ADC resolution [bits]; ``None`` (or 0) for an ideal converter (no quantisation).
        Default 16.
    bandwidth : float
        −3 dB cut-off of the transducer and amplifier [Hz]; ``inf`` for none. Default
        300 kHz.
    filter_order : int
        Order of the Butterworth low-pass. Default 2.
    crosstalk : float or (3, 3) array_like
        A number c: the six off-diagonal entries of the mixing matrix are drawn
        uniformly in [−c, c] from ``seed`` (diagonal 1). A 3×3 matrix: used as given,
        rows the measured axes, columns the true axes, order (Fn, Ft, Fy). Default 0.02.
    pre_trigger, post_trigger : float
        Time recorded before the record's first and after its last instant [s].
        Defaults 100 µs and 200 µs.
    full_scale : float or (3,) array_like
        Span of the ADC per axis [N]: it converts −full_scale/2 … +full_scale/2;
        ``inf`` for no clipping (needs ``bits=None``). Default 5 kN.
    phase : float, optional
        Delay of the first sample after ``time[0] − pre_trigger`` [s], in [0, 1/rate).
        Default: drawn uniformly from ``seed``.
    oversample : int, optional
        Fine-grid factor for the band-limiting filter. Default: enough to resolve the
        input record, at least 4, at most 64.
    seed : int, numpy.random.SeedSequence or None
        Seed of the random draws (phase, cross-talk, noise). The same seed gives the same
        output; the draws are made in a fixed order, so changing e.g. ``noise`` keeps the
        phase and cross-talk matrix. ``None`` draws fresh entropy, recorded in the
        output's ``sensor_seed`` attribute so the record can be reproduced.
    resonance : float
        Natural frequency of the mounted transducer's mode [Hz], in series with the
        low-pass; ``inf`` (default) for none.
    damping_ratio : float
        Damping ratio ζ of that mode [-], in (0, 1). Default 0.05.
    discharge : float
        Discharge time constant τ of the piezo and its charge amplifier [s], a first-order
        high-pass in series; ``inf`` (default) for none.

    Returns
    -------
    xarray.Dataset
        A record of ``kind`` ``"sensor"``, ``format`` ``"simulate.to_sensor"``, with
        ``Fn``, ``Ft``, ``Fy`` [N] sampled at ``rate`` on the input's clock. ``attrs``:
        the input's scene fields under their own names; every input attribute again as
        ``truth_<name>``; every sensor parameter as ``sensor_<name>`` (per-axis values
        as lists in the order Fn, Ft, Fy; ``sensor_crosstalk_matrix`` the 3×3 matrix
        row-major; ``sensor_quantum`` the ADC step [N], 0 when not quantised;
        ``sensor_bits`` 0 when not quantised; ``sensor_seed`` the entropy used;
        ``sensor_saturated`` the number of clipped values).

    Warns
    -----
    SensorSaturationWarning
        When the signal left the ADC range and was clipped.

    Raises
    ------
    InputError
        For a malformed record or an out-of-range parameter.

    Notes
    -----
    Measured signal on axis i at sample instant t_k (see the module notes):

    .. math::

        y_i(t_k) = Q\Big[(h * \textstyle\sum_j C_{ij}F_j)(t_k) + o_i + d_i(t_k - t_0)
        + \sigma_i\,\varepsilon_{ik}\Big],\qquad \varepsilon_{ik}\sim N(0,1)

    with h the impulse response of the sensor chain (the Butterworth low-pass, and the
    mode and the discharge where given) and Q the ADC.
    """
    validate(record)
    rate = _positive(rate, "rate")
    bandwidth = _positive(bandwidth, "bandwidth", allow_inf=True)
    pre = _nonneg(pre_trigger, "pre_trigger")
    post = _nonneg(post_trigger, "post_trigger")
    noise_a = _per_axis(noise, "noise")
    offset_a = _per_axis(offset, "offset", nonneg=False)
    drift_a = _per_axis(drift, "drift", nonneg=False)
    fs_a = _per_axis(full_scale, "full_scale", allow_inf=True)
    if (fs_a <= 0).any():
        raise InputError(f"to_sensor: full_scale = {full_scale!r} must be positive")
    if bits is None or bits == 0:
        nbits = 0
    else:
        if int(bits) != bits or not 1 <= int(bits) <= 32:
            raise InputError(f"to_sensor: bits = {bits!r} must be an integer in 1…32 or None")
        nbits = int(bits)
        if not np.isfinite(fs_a).all():
            raise InputError(
                "to_sensor: a quantising ADC (bits given) needs a finite "
                "full_scale [N]; use bits=None for an ideal converter"
            )
    if int(filter_order) != filter_order or not 1 <= int(filter_order) <= 8:
        raise InputError(f"to_sensor: filter_order = {filter_order!r} must be 1…8")
    filter_order = int(filter_order)
    resonance = _positive(resonance, "resonance", allow_inf=True)
    discharge = _positive(discharge, "discharge", allow_inf=True)
    damping_ratio = _positive(damping_ratio, "damping_ratio")
    if not damping_ratio < 1.0:
        raise InputError(
            f"to_sensor: damping_ratio = {damping_ratio!r} must lie in (0, 1): a mode that "
            "rings (a mounted transducer's is ~0.01–0.1)"
        )
    dynamics = math.isfinite(resonance) or math.isfinite(discharge)

    ss = _seed_sequence(seed)
    rng = np.random.default_rng(ss)
    # Fixed order of draws: phase, cross-talk, noise — so that a parameter set to zero
    # leaves the other draws unchanged.
    u_phase = rng.random()
    u_cross = rng.uniform(-1.0, 1.0, size=6)

    C = np.asarray(crosstalk, dtype=float)
    if C.ndim == 0:
        c = float(C)
        if not (0 <= c < 1):
            raise InputError(f"to_sensor: crosstalk = {crosstalk!r} must be in [0, 1)")
        C = np.eye(3)
        for (i, j), u in zip(_OFF_DIAGONAL, u_cross, strict=True):
            C[i, j] = c * u
    elif C.shape != (3, 3) or not np.isfinite(C).all():
        raise InputError(
            "to_sensor: crosstalk must be a number or a finite 3×3 matrix "
            "(rows measured Fn, Ft, Fy; columns true Fn, Ft, Fy)"
        )

    period = 1.0 / rate
    if phase is None:
        ph = u_phase * period
    else:
        ph = _nonneg(phase, "phase")
        if ph >= period:
            raise InputError(f"to_sensor: phase = {phase!r} s must be below 1/rate = {period} s")

    t_in = record["time"].values
    t_first, t_last = float(t_in[0]), float(t_in[-1])
    n = int(math.floor((t_last - t_first + pre + post) * rate * (1 + 1e-12))) + 1
    t0 = t_first - pre + ph
    k = np.arange(n)
    t_out = t0 + k * period
    z = rng.standard_normal((3, n))

    ideal_pts = [
        channel(record, name) if name in record else (t_in[[0, -1]], np.zeros(2)) for name in _AXES
    ]

    if math.isinf(bandwidth) and not dynamics:
        ideal = np.stack([np.interp(t_out, tc, fc, left=0.0, right=0.0) for tc, fc in ideal_pts])
        os_used = 1
    else:
        if oversample is None:
            dt_rec = float(np.median(np.diff(t_in)))
            os_used = int(np.clip(math.ceil(period / dt_rec), 4, 64))
        else:
            if int(oversample) != oversample or oversample < 1:
                raise InputError(f"to_sensor: oversample = {oversample!r} must be an integer ≥ 1")
            os_used = int(oversample)
        # Start the fine grid early enough to see the whole input from zero state.
        lead = max(0, math.ceil((t0 - t_first) * rate))
        m = (n + lead - 1) * os_used + 1
        t_fine = (t0 - lead * period) + np.arange(m) * (period / os_used)
        true_fine = np.stack(
            [np.interp(t_fine, tc, fc, left=0.0, right=0.0) for tc, fc in ideal_pts]
        )
        step = period / os_used
        if dynamics:
            chain = sensor_zpk(bandwidth, filter_order, resonance, damping_ratio, discharge)
            filtered = foh_filter(*chain, step)(true_fine)
        else:
            filtered = signal.sosfilt(butterworth_sos(filter_order, bandwidth, step), true_fine)
        ideal = filtered[:, lead * os_used :: os_used]
    # The same linear filter acts on every axis, so mixing after it equals mixing before.
    mixed = C @ ideal

    y = mixed + offset_a[:, None] + drift_a[:, None] * (k * period)[None, :] + noise_a[:, None] * z

    saturated = 0
    quantum = np.zeros(3)
    if nbits:
        quantum = fs_a / 2.0**nbits
        codes = np.round(y / quantum[:, None])
        lo, hi = -(2.0 ** (nbits - 1)), 2.0 ** (nbits - 1) - 1
        clip = (codes < lo) | (codes > hi)
        saturated = int(clip.sum())
        y = np.clip(codes, lo, hi) * quantum[:, None]
    elif np.isfinite(fs_a).any():
        half = (fs_a / 2.0)[:, None]
        clip = np.abs(y) > half
        saturated = int(clip.sum())
        y = np.clip(y, -half, half)
    if saturated:
        warnings.warn(
            f"to_sensor: {saturated} samples exceeded the ADC range ±full_scale/2 = "
            f"{(fs_a / 2).tolist()} N and were clipped; raise full_scale",
            SensorSaturationWarning,
            stacklevel=2,
        )

    attrs = _output_attrs(record.attrs)
    seed_used = ss.entropy if ss.entropy is not None else 0
    attrs.update(
        {
            "sensor_rate": rate,
            "sensor_noise": noise_a.tolist(),
            "sensor_offset": offset_a.tolist(),
            "sensor_drift": drift_a.tolist(),
            "sensor_bits": nbits,
            "sensor_full_scale": fs_a.tolist(),
            "sensor_quantum": quantum.tolist(),
            "sensor_bandwidth": bandwidth,
            "sensor_filter": _describe(
                bandwidth, filter_order, resonance, damping_ratio, discharge
            ),
            "sensor_filter_order": filter_order,
            "sensor_resonance": resonance,
            "sensor_damping_ratio": damping_ratio,
            "sensor_discharge": discharge,
            "sensor_oversample": os_used,
            "sensor_crosstalk": (float(crosstalk) if np.ndim(crosstalk) == 0 else "matrix"),
            "sensor_crosstalk_matrix": C.ravel().tolist(),
            "sensor_pre_trigger": pre,
            "sensor_post_trigger": post,
            "sensor_phase": ph,
            "sensor_t_start": t0,
            "sensor_trigger_time": t_first,
            "sensor_seed": int(seed_used) if seed_used < 2**63 else str(seed_used),
            "sensor_saturated": saturated,
            "sensor_axes": ",".join(_AXES),
        }
    )
    return make_record(t_out, dict(zip(_AXES, y, strict=True)), attrs=attrs)


def _describe(bandwidth, order, resonance, zeta, discharge) -> str:
    parts = []
    if math.isfinite(bandwidth):
        parts.append(f"Butterworth low-pass, order {order}")
    if math.isfinite(resonance):
        parts.append(f"mounted mode {resonance:.6g} Hz, ζ = {zeta:.4g}")
    if math.isfinite(discharge):
        parts.append(f"discharge τ = {discharge:.6g} s")
    if not parts:
        return "none"
    return ", ".join(parts) + ", causal, first-order-hold discretisation"


def _output_attrs(truth: dict) -> dict:
    scene_fields = set(Scene.field_names())
    out = {
        "source": "pipeline.simulate.to_sensor",
        "sha256": "",
        "format": "simulate.to_sensor",
        "kind": "sensor",
    }
    for key, value in truth.items():
        if key in scene_fields:
            out[key] = value
        out[f"truth_{key}"] = value
    return out
