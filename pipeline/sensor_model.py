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

Not modelled: the piezo's high-pass discharge time constant (seconds, far longer than a
sub-millisecond window), the transducer's mechanical resonance (assumed above
``bandwidth``), gain errors of each axis (give a ``crosstalk`` matrix with a diagonal
other than 1 to model them).

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
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import xarray as xr
from scipy import signal

from .errors import InputError, PipelineWarning
from .record import FORCE_CHANNELS, channel, make_record, validate
from .scene import Scene

__all__ = ["to_sensor", "butterworth_sos", "SENSOR_DEFAULTS", "SensorSaturationWarning"]

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

    with h the impulse response of the Butterworth low-pass and Q the ADC.
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

    if math.isinf(bandwidth):
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
        sos = butterworth_sos(filter_order, bandwidth, period / os_used)
        ideal = signal.sosfilt(sos, true_fine, axis=-1)[:, lead * os_used :: os_used]
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
            "sensor_filter": (
                "none"
                if math.isinf(bandwidth)
                else f"Butterworth low-pass, order {filter_order}, causal, "
                "first-order-hold discretisation"
            ),
            "sensor_filter_order": filter_order,
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
