r"""What the fits know about the sensor, and how the forward model passes through it.

A measured record is not the contact force: the transducer and its amplifier low-pass
filter it (a causal filter also delays it), the axes leak into each other, and the ADC
rounds it to its step (docs/theory.md; :mod:`pipeline.sensor_model` models all of it for the
synthetic records). The fits model what shifts the fitted parameters and leave out what
only adds noise:

- **the low-pass filter**, where the record says its bandwidth: the model force is computed
  on a grid ``oversample`` times finer than the sampling, passed through the analogue
  Butterworth low-pass of the stated order and cut-off discretised exactly for a
  piecewise-linear input (first-order hold; the discretisation
  :func:`pipeline.sensor_model.to_sensor` uses), then sampled. Left out, a causal filter
  makes the onset t0 come out late by its group delay (0.75 µs for 300 kHz, order 2); on a
  100 µs Garland–Rogers contact the pulse shape absorbs the rest (E*, e, μ move by ~1e-4 at
  300 kHz, ~1e-3 at 75 kHz: ``tests/test_fit_contact.py``), more on shorter contacts;
- **axis cross-talk**, where a calibration (cross-talk) matrix C is known: the model is
  :math:`(F_n, F_t)_{meas} = C_{2\times2}\,(F_n, F_t)`. Without it, an Fn → Ft leak of
  c biases μ by about c/μ (0.5 % of Fn on μ = 0.13: 4 %); the fit then checks whether the
  out-of-plane channel Fy tracks Fn and warns if so (a sign of cross-talk);
- **the ADC**: its step q sets a floor q/√12 under the noise level of the weights, and
  samples at the converter's end codes (saturated) are left out of the fit;
- **the transducer's dynamics**, in series with the low-pass: the mounted mode (natural
  frequency ``resonance`` [Hz], damping ratio ``damping_ratio``) and the piezo's discharge
  (time constant ``discharge`` [s], a first-order high-pass), the whole chain discretised
  at once exactly as the low-pass alone is (:func:`pipeline.sensor_model.foh_filter`).
  Left out, a mode a few contact frequencies up sharpens the pulse (E* several per cent
  high) and rings after it; a discharge undershoots after it and eats the impulse by
  (T − t̄)/τ over a span T (docs/uncertainty.md). Where none is stated, the fit looks for
  them in the record (:mod:`pipeline.fit.dynamics`).

Where the values come from, first found wins: the ``sensor`` argument (a
:class:`SensorSpec`, or a mapping such as a sample sidecar's ``"sensor"`` block); the
``sensor_*`` attributes :func:`pipeline.sensor_model.to_sensor` writes; the ``# key: value``
metadata of a sensor CSV (``bandwidth [Hz]``, ``filter order``, ``adc bits``,
``full scale [N]``, ``sample rate [Hz]``, ``resonance [Hz]``, ``damping ratio``,
``discharge [s]``, as ``meta_*`` attributes). A bandwidth without an
order is taken as a 2nd-order Butterworth (the usual charge-amplifier low-pass), and the
fit's notes say so.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from scipy.signal import sosfilt

from ..errors import InputError, PipelineWarning
from ..io.metadata import parse_quantity, stated_bandwidth
from ..record import channel
from ..sensor_model import butterworth_sos, foh_filter, sensor_zpk

__all__ = ["SensorSpec", "sensor_spec", "CrossTalkWarning", "fy_tracks_fn"]


class CrossTalkWarning(PipelineWarning):
    """The out-of-plane channel follows the normal force: the sensor's axes leak."""


_DEFAULT_ORDER = 2
#: The damping ratio taken for a stated mode whose damping is not stated [-]: a piezo
#: transducer bolted under a target rings lightly (ζ ≈ 0.01–0.1); known to ±100 %
#: (:mod:`pipeline.fit.systematics`).
DEFAULT_DAMPING = 0.05


@dataclass(frozen=True)
class SensorSpec:
    """The sensor properties a fit models (module notes).

    Attributes
    ----------
    bandwidth : float — −3 dB cut-off of the Butterworth low-pass [Hz]; inf: none
    filter_order : int — its order
    quantum : float — ADC step [N] (0: not quantised or unknown)
    full_scale : float — ADC span [N] (±full_scale/2 saturates); inf: unknown
    crosstalk : numpy.ndarray or None — 3×3 mixing matrix, rows measured (Fn, Ft, Fy),
        columns true (Fn, Ft, Fy); None: unknown
    source : str — where the values came from
    notes : tuple of str — assumptions made (e.g. an order not stated)
    resonance : float — natural frequency of the mounted transducer's mode [Hz]; inf: none
    damping_ratio : float — its damping ratio ζ [-]
    discharge : float — discharge time constant τ of the piezo and its amplifier [s]; inf:
        none
    damping_stated : bool — False where ζ is the default taken for a mode stated without it
    """

    bandwidth: float = math.inf
    filter_order: int = _DEFAULT_ORDER
    quantum: float = 0.0
    full_scale: float = math.inf
    crosstalk: np.ndarray | None = None
    source: str = "none"
    notes: tuple = field(default_factory=tuple)
    resonance: float = math.inf
    damping_ratio: float = DEFAULT_DAMPING
    discharge: float = math.inf
    damping_stated: bool = True

    @property
    def filtered(self) -> bool:
        return math.isfinite(self.bandwidth)

    @property
    def dynamic(self) -> bool:
        """A mode or a discharge is stated."""
        return math.isfinite(self.resonance) or math.isfinite(self.discharge)

    def delay(self) -> float:
        """Low-frequency group delay of the filter and the mode [s] (0 without them): −Σ
        cos θ_k/ω_c over the Butterworth poles ω_c·e^{iθ_k}, √2/(2π f_c) for order 2, plus
        the mode's 2ζ/ωn."""
        out = 0.0
        if math.isfinite(self.resonance):
            out += 2.0 * self.damping_ratio / (2 * np.pi * self.resonance)
        if not self.filtered:
            return out
        n = self.filter_order
        k = np.arange(1, n + 1)
        poles = np.exp(1j * np.pi * (2 * k + n - 1) / (2 * n))
        return out + float(-np.sum(poles.real) / (2 * np.pi * self.bandwidth))

    def ring_time(
        self, bandwidth=None, resonance=None, damping_ratio=None, discharge=None
    ) -> float:
        """Time for the chain's impulse response to decay below 1e-16 of its scale [s]: 37
        time constants of its slowest pole — the low-pass's ω_c·sin(π/(2n)), the mode's
        ζωn, the discharge's 1/τ — (0 without any); at the values given instead of the
        stated ones."""
        bw = self.bandwidth if bandwidth is None else bandwidth
        fn = self.resonance if resonance is None else resonance
        zeta = self.damping_ratio if damping_ratio is None else damping_ratio
        tau = self.discharge if discharge is None else discharge
        rates = []
        if math.isfinite(bw):
            rates.append(2 * np.pi * bw * math.sin(math.pi / (2 * self.filter_order)))
        if math.isfinite(fn):
            rates.append(2 * np.pi * fn * zeta)
        if math.isfinite(tau):
            rates.append(1.0 / tau)
        return 37.0 / min(rates) if rates else 0.0

    def sos(self, dt: float, bandwidth: float | None = None) -> np.ndarray:
        """Second-order sections of the low-pass discretised at step ``dt`` [s] (FOH), at
        ``bandwidth`` [Hz] instead of the stated one if given."""
        bw = self.bandwidth if bandwidth is None else bandwidth
        return _sos(self.filter_order, float(bw), float(dt)).copy()

    def chain(self, dt, bandwidth=None, resonance=None, damping_ratio=None, discharge=None):
        """The whole chain — low-pass, mode, discharge — discretised at step ``dt`` [s] (FOH):
        a callable on samples (…, n) (:class:`pipeline.sensor_model.FohFilter`; the
        low-pass's second-order sections where it is alone), at the values given instead
        of the stated ones."""
        bw = self.bandwidth if bandwidth is None else bandwidth
        fn = self.resonance if resonance is None else resonance
        zeta = self.damping_ratio if damping_ratio is None else damping_ratio
        tau = self.discharge if discharge is None else discharge
        return _chain(self.filter_order, float(bw), float(fn), float(zeta), float(tau), float(dt))

    def summary(self) -> dict:
        return {
            "bandwidth_Hz": self.bandwidth,
            "filter_order": self.filter_order,
            "quantum_N": self.quantum,
            "full_scale_N": self.full_scale,
            "crosstalk": None if self.crosstalk is None else self.crosstalk.tolist(),
            "resonance_Hz": self.resonance,
            "damping_ratio": self.damping_ratio if math.isfinite(self.resonance) else None,
            "discharge_s": self.discharge,
            "source": self.source,
            "notes": list(self.notes),
        }


@functools.lru_cache(maxsize=64)
def _sos(order, bandwidth, dt):
    if order in (1, 2):
        return foh_butterworth(order, bandwidth, dt)
    return butterworth_sos(order, bandwidth, dt)


class _Sos:
    """The low-pass alone as a callable (second-order sections)."""

    def __init__(self, sos):
        self.sos = sos

    def __call__(self, x, axis=-1):
        return sosfilt(self.sos, x, axis=axis)


@functools.lru_cache(maxsize=256)
def _chain(order, bandwidth, resonance, zeta, discharge, dt):
    if math.isinf(resonance) and math.isinf(discharge):
        if math.isinf(bandwidth):
            return None
        return _Sos(_sos(order, bandwidth, dt))
    return foh_filter(*sensor_zpk(bandwidth, order, resonance, zeta, discharge), dt)


def foh_butterworth(order: int, bandwidth: float, dt: float) -> np.ndarray:
    r"""The Butterworth low-pass of order 1 or 2 and cut-off ``bandwidth`` [Hz] discretised
    at step ``dt`` [s] for inputs linear between samples (first-order hold), as one
    second-order section [-]: :func:`pipeline.sensor_model.butterworth_sos` in closed form.

    A fit with the cut-off among its parameters needs the filter at a new bandwidth every
    evaluation; the state-space route takes about a millisecond, this some microseconds.

    Notes
    -----
    With the poles p of H(s) = Σ r/(s − p) (ω_c·e^{±i3π/4} for order 2, −ω_c for order 1),
    the hold equivalent is, term by term (Franklin, Powell & Workman 1998, §6.3.2),

    .. math::

        H(z) = \sum_p \Big(-rac{r}{p} + rac{r\,(q - 1)}{p^2 T}\,
        rac{1 - z^{-1}}{1 - q z^{-1}}\Big), \qquad q = e^{pT},

    which for a conjugate pair adds up to one biquad over 1 − 2 Re q·z⁻¹ + |q|²·z⁻².

    References
    ----------
    G. F. Franklin, J. D. Powell, M. Workman, *Digital Control of Dynamic Systems*, 3rd
    ed., Addison-Wesley (1998).
    """
    wc = 2.0 * math.pi * float(bandwidth)
    if order == 1:  # H = ω_c/(s + ω_c): r = ω_c, p = −ω_c
        x = -wc * dt
        q = math.exp(x)
        c = -math.expm1(x) / x  # r·(q − 1)/(p²T), r/(p²T) = 1/(ω_c·T) = −1/x
        d = 1.0  # −r/p
        return np.array([[d + c, -(d * q + c), 0.0, 1.0, -q, 0.0]])
    if order != 2:
        raise ValueError(f"closed form for orders 1 and 2, got {order}")
    p = wc * complex(-math.sqrt(0.5), math.sqrt(0.5))  # the upper pole
    r = wc * wc / (p - p.conjugate())  # H = ω_c²/((s − p)(s − p̄))
    x = p * dt
    # expm1 of a complex argument without cancellation: e^a·cos b − 1 + i·e^a·sin b
    em1 = complex(
        math.expm1(x.real) * math.cos(x.imag) - 2.0 * math.sin(0.5 * x.imag) ** 2,
        math.exp(x.real) * math.sin(x.imag),
    )
    q = em1 + 1.0
    c = r * em1 / (p * p * dt)
    d = 2.0 * (-r / p).real
    a1, a2 = -2.0 * q.real, abs(q) ** 2
    n0, n2 = 2.0 * c.real, 2.0 * (c * q.conjugate()).real
    return np.array([[d + n0, d * a1 - n2 - n0, d * a2 + n2, 1.0, a1, a2]])


def _num(value, name, src):
    if isinstance(value, (list, tuple, np.ndarray)):
        value = np.asarray(value, dtype=float).ravel()
        if value.size == 0:
            raise InputError(f"sensor {name} is empty ({src})")
        value = value[0]  # per-axis lists (Fn, Ft, Fy): the normal axis's
    try:
        return float(value)
    except (TypeError, ValueError):
        raise InputError(f"sensor {name} = {value!r} is not a number ({src})") from None


#: The fields a sensor mapping may hold (the fits read some; a sensor CSV writes them all).
_KNOWN = frozenset(
    {
        "rate",
        "noise",
        "offset",
        "drift",
        "bits",
        "full_scale",
        "quantum",
        "bandwidth",
        "filter",
        "filter_order",
        "oversample",
        "crosstalk",
        "crosstalk_matrix",
        "pre_trigger",
        "post_trigger",
        "phase",
        "t_start",
        "trigger_time",
        "seed",
        "saturated",
        "axes",
        "resonance",
        "damping_ratio",
        "discharge",
    }
)


def _from_mapping(m: Mapping, src: str) -> SensorSpec:
    if not _KNOWN.issuperset(m):
        unknown = sorted(set(m) - _KNOWN)
        raise InputError(
            f"unknown sensor field(s) {', '.join(map(repr, unknown))} ({src}); the fits read "
            "bandwidth [Hz], filter_order, quantum [N] or bits with full_scale [N], "
            "crosstalk_matrix (3×3, row-major), resonance [Hz], damping_ratio and discharge [s]"
        )
    notes = []
    bw = _num(m["bandwidth"], "bandwidth", src) if "bandwidth" in m else math.inf
    if bw <= 0:
        raise InputError(f"sensor bandwidth = {bw!r} Hz must be positive ({src})")
    if "filter_order" in m:
        order = int(_num(m["filter_order"], "filter_order", src))
    else:
        order = _DEFAULT_ORDER
        if math.isfinite(bw):
            notes.append(
                f"the sensor's filter order is not stated: a Butterworth of order {order} "
                "is assumed"
            )
    if not 1 <= order <= 8:
        raise InputError(f"sensor filter_order = {order!r} must be 1…8 ({src})")
    fs = _num(m["full_scale"], "full_scale", src) if "full_scale" in m else math.inf
    if "quantum" in m:
        q = _num(m["quantum"], "quantum", src)
    elif "bits" in m and math.isfinite(fs) and _num(m["bits"], "bits", src) > 0:
        q = fs / 2.0 ** _num(m["bits"], "bits", src)
    else:
        q = 0.0
    C = m.get("crosstalk_matrix")
    if C is None and np.ndim(m.get("crosstalk", 0.0)) == 2:
        C = m["crosstalk"]
    if C is not None:
        C = np.asarray(C, dtype=float)
        if C.size != 9 or not np.isfinite(C).all():
            raise InputError(f"sensor crosstalk_matrix must hold 9 finite numbers ({src})")
        C = C.reshape(3, 3)
    fn = _num(m["resonance"], "resonance", src) if m.get("resonance") is not None else math.inf
    if not fn > 0:
        raise InputError(f"sensor resonance = {fn!r} Hz must be positive, or inf for none ({src})")
    tau = _num(m["discharge"], "discharge", src) if m.get("discharge") is not None else math.inf
    if not tau > 0:
        raise InputError(f"sensor discharge = {tau!r} s must be positive, or inf for none ({src})")
    if m.get("damping_ratio") is not None:
        zeta = _num(m["damping_ratio"], "damping_ratio", src)
        if not 0 < zeta < 1:
            raise InputError(
                f"sensor damping_ratio = {zeta!r} must lie in (0, 1): the mounted mode rings "
                f"(a bolted piezo transducer's ζ ≈ 0.01–0.1) ({src})"
            )
    else:
        zeta = DEFAULT_DAMPING
        if math.isfinite(fn):
            notes.append(
                f"the mounted mode's damping ratio is not stated: ζ = {zeta} is assumed (a "
                "bolted piezo transducer rings lightly), known to ±100 %"
            )
    stated = m.get("damping_ratio") is not None or not math.isfinite(fn)
    return SensorSpec(bw, order, q, fs, C, src, tuple(notes), fn, zeta, tau, stated)


_FORCE_UNITS = {"": 1.0, "n": 1.0, "kn": 1e3, "mn": 1e-3}
_FREQUENCY_UNITS = {"": 1.0, "hz": 1.0, "khz": 1e3, "mhz": 1e6}
_TIME_UNITS = {"": 1.0, "s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "μs": 1e-6}


def _from_metadata(attrs) -> dict:
    """Sensor fields stated in a record's ``# key: value`` metadata (``meta_*`` attributes),
    units in the value (``5000 N``) or, as older readers kept them, in the key
    (``meta_full_scale_n``)."""
    out = {}
    bw = stated_bandwidth(attrs)
    if bw is not None:
        out["bandwidth"] = bw[0]
    for key, text in attrs.items():
        k = str(key)
        if not k.startswith("meta_"):
            continue
        squashed = k.removeprefix("meta_").replace("_", "").replace(" ", "").lower()
        q = parse_quantity(text if isinstance(text, str) else str(text))
        if q is None:
            continue
        value, unit = q
        if squashed in ("filterorder", "order"):
            out["filter_order"] = value
        elif squashed in ("adcbits", "bits"):
            out["bits"] = value
        elif squashed.startswith("fullscale"):
            unit = unit or squashed.removeprefix("fullscale")
            if unit.lower() in _FORCE_UNITS:
                out["full_scale"] = value * _FORCE_UNITS[unit.lower()]
        elif squashed == "bandwidthhz" and "bandwidth" not in out:  # unit kept in the key
            out["bandwidth"] = value
        elif squashed.startswith(("resonance", "mountedresonance", "naturalfrequency")):
            unit = unit or squashed.rsplit("resonance", 1)[-1].rsplit("frequency", 1)[-1]
            factor = _FREQUENCY_UNITS.get(unit.lower())
            if factor is not None:
                out["resonance"] = value * factor
        elif squashed in ("dampingratio", "damping"):
            out["damping_ratio"] = value
        elif squashed.startswith(("discharge", "timeconstant")):
            unit = unit or squashed.rsplit("discharge", 1)[-1].rsplit("timeconstant", 1)[-1]
            factor = _TIME_UNITS.get(unit.lower())
            if factor is not None:
                out["discharge"] = value * factor
    return out


def _written(value):
    """A ``sensor_*`` attribute as :func:`pipeline.io.write_sensor` wrote it in a sensor
    CSV's metadata and the reader gave it back: the text of a number or of a JSON list of
    numbers, as that number or list; None for other text (a lab's own ``sensor_…`` line,
    ``300 kHz``, is not this writer's, and is left to the metadata's reading)."""
    if not isinstance(value, str):
        return value
    with contextlib.suppress(ValueError):
        return json.loads(value) if value.lstrip().startswith("[") else float(value)
    return None


#: The prefixes of a record's attributes that may state its sensor.
_NAMED = ("meta_", "sensor_", "decouple")
#: The fields of a record's ``sensor_*`` attributes the fits read.
_READ = frozenset(
    {
        "bandwidth",
        "filter_order",
        "quantum",
        "full_scale",
        "bits",
        "crosstalk_matrix",
        "resonance",
        "damping_ratio",
        "discharge",
    }
)


def sensor_spec(record, sensor=None) -> SensorSpec:
    """The sensor a record was measured with (module notes give the order of sources).

    Parameters
    ----------
    record : xarray.Dataset — the record
    sensor : SensorSpec or mapping, optional — stated properties (win over the record's)

    Returns
    -------
    SensorSpec
    """
    decoupled = None  # a loader's decoupling matrix applied (``decouple…`` attributes)
    if isinstance(sensor, SensorSpec):
        spec = sensor
    elif isinstance(sensor, Mapping):
        spec = _from_mapping(sensor, "the sensor argument")
    elif sensor is not None:
        raise InputError(
            f"sensor must be a SensorSpec or a mapping (e.g. a sidecar's 'sensor' block), "
            f"got {type(sensor).__name__}"
        )
    else:
        meta, stated, written = {}, {}, {}  # one pass: a record carries scores of others
        decoupled = False
        attrs = record.attrs
        try:  # most of a record's attributes are none of these (a single test: a score of them)
            named = [k for k in attrs if k.startswith(_NAMED)]
        except (AttributeError, TypeError):  # a key that is no string
            named = [k for k in attrs if str(k).startswith(_NAMED)]
        for k in named:  # each starts with one of the prefixes: its first letter tells which
            key = str(k)
            if key[0] == "s":  # sensor_…, of the fields read
                if (name := key.removeprefix("sensor_")) in _READ:
                    stated[name] = attrs[k]
            elif key[0] == "d":  # decouple…
                decoupled = True
            elif not key.startswith("meta_sensor_"):
                meta[k] = attrs[k]
            elif (name := key.removeprefix("meta_sensor_")) in _READ and (
                value := _written(attrs[k])
            ) is not None:  # to_sensor's, through a sensor CSV
                written[name] = value
        stated = {**written, **stated}  # the record's own attributes win
        fields = _from_metadata(meta)
        fields.update(stated)
        if "bandwidth" in stated and "filter_order" in stated:
            src = "the record's sensor_* attributes"
        else:
            src = "the record's metadata"
        spec = _from_mapping(fields, src) if fields else SensorSpec()
    if decoupled is None and spec.crosstalk is not None:
        decoupled = any(str(k).startswith("decouple") for k in record.attrs)
    if spec.crosstalk is not None and decoupled:
        # the loader already applied a decoupling matrix: nothing left to mix
        spec = dataclasses.replace(
            spec,
            crosstalk=None,
            notes=spec.notes + ("the record was decoupled when loaded: no cross-talk modelled",),
        )
    return spec


def fy_tracks_fn(data, fn_model, *, min_leak: float = 0.002, z: float = 4.0):
    """How much the out-of-plane channel follows the fitted normal force, where it does.

    The slope k of Fy (less its baseline) on the fitted Fn as measured, by least squares
    over the fitted samples, with its standard error σ_Fy/√ΣFn². Returns k [-] when
    |k| > max(``min_leak``, ``z``·s.e.) — the axes leak into each other, and an Fn → Ft leak
    of the same size would bias μ by about k/μ — else None (no Fy channel, a known
    cross-talk matrix, or no significant slope).

    Parameters
    ----------
    data : pipeline.fit.forward.RecordData
    fn_model : numpy.ndarray — the fitted Fn at ``data``'s Fn samples [N]
    """
    rec = data.record
    if "Fy" not in rec or data.sensor.crosstalk is not None:
        return None
    t, fy = channel(rec, "Fy")
    fn_t = data.channels[0].t
    base = data.window.baseline.get("Fy")
    y = np.interp(fn_t, t, fy - (base(t) if base is not None else 0.0))
    m = np.asarray(fn_model, dtype=float)
    ss = float(np.dot(m, m))
    sigma = float(data.window.noise.get("Fy", np.nan))
    if not (ss > 0 and np.isfinite(sigma) and sigma > 0):
        return None
    k = float(np.dot(y, m) / ss)
    se = sigma / math.sqrt(ss)
    return k if abs(k) > max(min_leak, z * se) else None
