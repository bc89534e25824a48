r"""Contact window: where the impact starts and ends in a record, and the baseline removed.

A force sensor exports more than the contact: pre- and post-trigger samples, an offset, a
slow drift and white noise (docs/theory.md). This stage finds the contact, removes a linear
baseline from every force channel and reports the noise it measured.

Sensor records (``kind="sensor"``), per :func:`find_contact`:

1. **Initial baseline.** The line through the medians of the first and last 10 % of the
   record (pre- and post-trigger samples are baseline) — or the median of one end alone,
   when that leaves the record's samples closer to it (the other end lies inside a pulse
   the file cuts; see :func:`_initial_baseline`).
2. **Noise.** Residuals :math:`r = F_n - b(t)`; the noise level is the normalised median
   absolute deviation :math:`\hat\sigma = 1.4826\,\mathrm{median}|r - \mathrm{median}\,r|`
   over the samples currently taken as baseline (robust: the pulse does not inflate it).
3. **Detection.** Excursions are where :math:`|r| > k\hat\sigma`, each widened to the
   stretch where it stays beyond :math:`\pm\hat\sigma`. The default threshold is a
   Bonferroni bound: :math:`k = \Phi^{-1}(1 - \alpha/(2n))` for :math:`n` samples and a
   false-alarm probability :math:`\alpha = 10^{-3}` for the whole record, so pure white
   Gaussian noise exceeds it anywhere in the record with probability ≈ α
   (:math:`k \approx 5.3` for 5 000 samples, 5.8 for 10⁵). An excursion of at most
   :data:`GLITCH_SAMPLES` samples is a *spike*; a longer one with at least two samples
   above threshold is a *pulse*. The contact is the **first** positive pulse at least
   :data:`MINOR_PULSE` of the largest.
4. **Ends.** Each end is the zero crossing of :math:`r` (the pulse starts and ends at zero
   force), linearly interpolated between the last sample above :math:`\hat\sigma` and
   its outward neighbour, or that neighbour's instant when it lies in
   :math:`(0, \hat\sigma]` (see :func:`_ends` for why σ and not 0).
5. **Refit.** The baseline :math:`b(t) = a + s\,(t - t_{ref})` is refitted by least squares
   to the samples outside the window widened by ``guard``·duration on each side (ringing
   after the pulse is kept out), and outside the other impacts and the spikes; steps 2–5
   repeat until the window no longer changes.

**A leaking sensor.** A piezo transducer's charge leaks through its amplifier's time
constant τ, a first-order high-pass (:mod:`pipeline.sensor_model`): after a pulse of
impulse P the output undershoots by about P/τ and recovers over τ, so where τ is a few
dozen contact times every sample after a short record's pulse lies on the undershoot, not
on the baseline. Where ``discharge`` states τ, steps 1–5 work on the record with the
discharge undone (:func:`_undo_discharge`: :math:`F = F_m + \frac1\tau\int F_m\,dt`, the
exact inverse of the high-pass as the sensor model discretises it), the baseline being the
raw record's offset and drift seen through that same inversion; :attr:`ContactWindow.record`
then holds the force so restored, and :attr:`ContactWindow.baseline` the raw record's line.
Where none is stated and the quiet pre-trigger passes for a pulse the file cuts (it lies
level, above the undershoot), the :class:`TruncatedPulseError` says so and how to state τ.

Plausibility checks on the way, each with the number that tripped it (the typed errors and
warnings of :mod:`pipeline.errors`):

=================================  ==========================  ===============================
what                               how it shows                outcome
=================================  ==========================  ===============================
nothing above the noise            no pulse, or spikes only    :class:`NoPulseError`
pulse cut by the file's start/end  the pulse reaches the       :class:`TruncatedPulseError`
                                   first or last sample
sign-flipped normal channel        the largest pulse is        :class:`SignFlipError`
                                   negative
clipping (ADC saturation)          a flat run at Fn's or Ft's  :class:`ClippedSignalError`
                                   extreme inside the pulse
two impacts                        a later pulse ≥ 5 % of the  :class:`MultipleImpactWarning`;
                                   first or lasting half as    the window keeps to the first
                                   long, or a dip inside the   (it ends at the dip)
                                   pulse to half its humps
trigger glitch                     a spike > 2·k·σ away from   :class:`TriggerGlitchWarning`;
                                   the pulse                   ignored
electrical spike                   one sample no band-limited  :class:`SpikeWarning`;
                                   force can make              repaired (:func:`find_spikes`)
=================================  ==========================  ===============================

**Spikes.** Before anything else, every force channel of a sensor record is searched for
isolated samples that no force history can make: the sensor's low-pass spreads whatever
the force does over several samples, so a single sample that stands off the curve its
neighbours draw — by more than the noise allows, while those neighbours lie on it — is an
electrical artefact (a switching transient, an ADC bit error), not force. Such a sample is
replaced by its neighbours' curve for every later step (the window, its baseline and
noise, :attr:`ContactWindow.record`), listed in :attr:`ContactWindow.spikes`, and left out
of the contact fits (:mod:`pipeline.fit.forward`). Left in, a spike inside the pulse
looks to the window like a dip between two impacts, and to a fit like a pulse several
times stiffer.

Errors where the record cannot give a right answer (a clipped or cut pulse has lost part
of its impulse; a flipped channel would be analysed as tension), warnings where the
analysis can go on, on the part it trusts: the first impact, the samples around a spike.
A flat run counts as clipping when equal neighbours are that rare in the baseline's noise
that the run's chance is below :data:`CLIP_CHANCE`, or when it holds 10 % of the pulse's
samples (a noise-free quantised record, whose top may repeat a value by right).

Every channel (``Fn``, ``Ft``, ``Fy``) gets its own line and noise level, fitted on the
same out-of-contact samples. The end points are uncertain by about one sample period plus
the time the pulse needs to rise above the noise: for a Hertz start,
:math:`F \approx K (v_0 t)^{3/2}`, that is :math:`(\hat\sigma/K)^{2/3}/v_0`.

Digitised records (``kind="digitised"``) are already windowed and carry no baseline: the
window is their time span and nothing is subtracted (a curve whose Fn is mostly negative
is a :class:`SignFlipError`). Simulated records
(``kind="simulated"``) are noise-free: the window runs from the last sample before the first
``Fn > 0`` to the first sample after the last ``Fn > 0`` (the contact lies inside, its ends
within one sample of the window's), again with nothing subtracted. In both, a second pulse
— Fn back at zero (simulated) or within :data:`DIGITISED_ZERO` of the peak (digitised) for
at least one sample, then up again for two — is a second impact however soon it comes: a
:class:`MultipleImpactWarning`, and the window ends where the force first came back. A
record without ``kind`` is treated as a sensor record.

References
----------
F. R. Hampel, "The influence curve and its role in robust estimation", J. Am. Stat. Assoc.
69:383 (1974), doi:10.1080/01621459.1974.10482962 (the MAD scale estimate).
"""

from __future__ import annotations

import copy
import dataclasses
import math
import warnings
from dataclasses import dataclass, field
from statistics import NormalDist

import numpy as np
import xarray as xr

from ._json import json_ready
from .errors import (
    ClippedSignalError,
    InputError,
    MultipleImpactWarning,
    NoPulseError,
    SignFlipError,
    SpikeWarning,
    TriggerGlitchWarning,
    TruncatedPulseError,
    caller_level,
)
from .precision import reading
from .record import FORCE_CHANNELS, KINDS, adc_step, channel, times

__all__ = [
    "Baseline",
    "Spike",
    "find_spikes",
    "ContactWindow",
    "find_contact",
    "apply_window",
    "default_threshold",
    "mad_sigma",
]

#: MAD → σ for Gaussian noise: 1/Φ⁻¹(3/4).
#: The standard normal distribution (its quantiles give the MAD scale and the thresholds).
_NORMAL = NormalDist()
_MAD_TO_SIGMA = 1.0 / _NORMAL.inv_cdf(0.75)


#: Samples up to which a median sorts them rather than selects: a sort (vectorised) beats
#: the selection on a few hundred, the selection's linear time the sort's n log n beyond.
_SORT_MEDIAN = 256


def _median(a, scratch=False, nan=True):
    """:func:`numpy.median` of all the values of ``a`` (the same value, NaN if any is NaN) by
    one :func:`numpy.partition` at the middle, without its general-axis machinery (a few µs
    a call; the window takes a score of medians). ``scratch``: ``a`` is a temporary array of
    floats, reordered in place; ``nan``: ``a`` may hold a NaN (False: it is known not to)."""
    a = np.asarray(a, dtype=float).ravel()
    n = a.size
    if n == 0:
        return np.median(a)  # NaN, with numpy's warning
    h = n // 2
    # as numpy: the middle one or two order statistics, and the largest (a NaN sorts last).
    # One selection at h, the order statistic below it the largest of the lower part: the
    # same numbers as numpy's selection of all three at once, at a fraction of its time
    p = a if scratch else a.copy()
    if n <= _SORT_MEDIAN:
        p.sort()
        top, below = p[-1], p[h - 1]
    else:
        p.partition(h)
        top = p[h:].max() if nan else 0.0
        below = p[:h].max() if n % 2 == 0 else None
    if top != top:  # NaN
        return top
    return p[h] if n % 2 else (below + p[h]) / 2


def _row_medians(a, scratch=False):
    """:func:`_median` of each row of the 2-D array ``a`` (rows of at least one value);
    ``scratch``: ``a`` is a temporary array of floats, reordered in place."""
    n = a.shape[1]
    h = n // 2
    p = a if scratch else a.copy()
    if n <= _SORT_MEDIAN:
        p.sort(axis=1)
        top, below = p[:, -1], p[:, h - 1]
    else:
        p.partition(h, axis=1)
        top = p[:, h:].max(axis=1)
        below = p[:, :h].max(axis=1) if n % 2 == 0 else None
    mid = p[:, h] if n % 2 else (below + p[:, h]) / 2
    nan = np.isnan(top)
    return np.where(nan, top, mid) if nan.any() else mid


def mad_sigma(r) -> float:
    """Robust noise level: 1.4826·median|r − median r| [same unit as ``r``]."""
    return _mad_sigma(np.array(r, dtype=float).ravel())  # a copy, reordered


def _mad_sigma(p) -> float:
    """:func:`mad_sigma` of the 1-D array of floats ``p``, a temporary reordered in place
    (|p − median| holds the same values as |r − median|, without two temporaries)."""
    median = _median(p, scratch=True)
    np.abs(np.subtract(p, median, out=p), out=p)
    # a finite median: p held no NaN, nor does |p − median| (no ∞ − ∞)
    return float(_MAD_TO_SIGMA * _median(p, scratch=True, nan=not math.isfinite(median)))


def default_threshold(n: int, false_alarm: float = 1e-3) -> float:
    """Detection threshold k [-] in units of σ for ``n`` samples of white Gaussian noise.

    k = Φ⁻¹(1 − α/(2n)): the chance that any of ``n`` noise samples exceeds k·σ in absolute
    value is at most α = ``false_alarm`` (Bonferroni). Never below 4.
    """
    if not 0 < false_alarm < 1:
        raise InputError(f"false_alarm must lie in (0, 1), got {false_alarm!r}")
    return float(max(4.0, -_NORMAL.inv_cdf(false_alarm / (2.0 * max(int(n), 1)))))


@dataclass(frozen=True)
class Baseline:
    """A linear baseline b(t) = offset + slope·(t − t_ref) of one channel.

    Attributes
    ----------
    offset : float — value at ``t_ref`` [N]
    slope : float — drift [N/s]
    t_ref : float — reference instant [s]
    """

    offset: float = 0.0
    slope: float = 0.0
    t_ref: float = 0.0

    def __call__(self, t):
        """The baseline at ``t`` [s], in N."""
        return self.offset + self.slope * (np.asarray(t, dtype=float) - self.t_ref)


@dataclass(frozen=True)
class Spike:
    """One sample no force history can make (:func:`find_spikes`), repaired.

    Attributes
    ----------
    channel : str — the force channel
    index : int — the sample's index in the record
    t : float — its instant [s]
    value : float — the recorded value [N]
    repaired : float — the value its neighbours' curve gives there [N]
    """

    channel: str
    index: int
    t: float
    value: float
    repaired: float


#: Weights of the least-squares quadratic through the samples at offsets −3…−1, 1…3,
#: evaluated at offset 0 (its variance under white noise: σ²·Σw² = σ²/2).
_SPIKE_OFFSETS = np.array([-3, -2, -1, 1, 2, 3])
_SPIKE_WEIGHTS = np.array([-2.0, 3.0, 6.0, 6.0, 3.0, -2.0]) / 14.0
_SPIKE_TERMS = tuple(zip(_SPIKE_OFFSETS.tolist(), _SPIKE_WEIGHTS.tolist(), strict=True))
#: A spike stands off its neighbours' quadratic by more than this many times the RMS
#: misfit of that quadratic to the neighbours (on 3 degrees of freedom): smooth curves —
#: a pulse, a decaying ring — stay below ~2 where the noise does not hide them, and a
#: spike on noise stands ~|spike|/σ above it.
SPIKE_ISOLATION = 4.0


def _quadratic_projector():
    X = np.column_stack([np.ones(6), _SPIKE_OFFSETS, _SPIKE_OFFSETS**2.0])
    return np.linalg.qr(X)[0]


_SPIKE_Q = _quadratic_projector()


def _quadratic_reach():
    """Weights of the neighbours' quadratic (offsets ±1…±3) at offsets −5, −4, 4, 5, and the
    variance of each prediction less its sample, over σ²."""
    X = np.column_stack([np.ones(6), _SPIKE_OFFSETS, _SPIKE_OFFSETS**2.0])
    far = np.array([-5.0, -4.0, 4.0, 5.0])
    W = np.column_stack([np.ones(4), far, far**2]) @ np.linalg.solve(X.T @ X, X.T)
    return W, 1.0 + np.sum(W * W, axis=1)


_REACH_OFFSETS = np.array([-5, -4, 4, 5])
_REACH_W, _REACH_VAR = _quadratic_reach()


def _spike_stats(y, k):
    """(d, misfit²) at samples ``k``: the sample less its neighbours' quadratic, and that
    quadratic's mean squared misfit to the six neighbours (3 degrees of freedom)."""
    nb = y[k[:, None] + _SPIKE_OFFSETS[None, :]]
    d = y[k] - nb @ _SPIKE_WEIGHTS
    rss = np.einsum("kj,kj->k", nb, nb) - np.sum((nb @ _SPIKE_Q) ** 2, axis=1)
    return d, np.maximum(rss, 0.0) / 3.0


def _spike_residuals(Y):
    """d of :func:`_spike_stats` at every interior sample 3 … n − 4 of each row of ``Y``
    (the misfit, which only the few candidates need, left out)."""
    n = Y.shape[1]
    d = Y[:, 3:-3].copy()
    term = np.empty_like(d)
    for offset, weight in _SPIKE_TERMS:
        d -= np.multiply(Y[:, 3 + offset : n - 3 + offset], weight, out=term)
    return d


def _spike_at(y, i, n, kk, sd, sigma):
    """The value sample ``i`` of ``y`` takes on its neighbours' curve where it is a spike
    (:func:`find_spikes`), else None."""
    dk, m2 = _spike_stats(y, np.array([i]))
    if not (abs(dk[0]) > kk * sd and dk[0] ** 2 > SPIKE_ISOLATION**2 * m2[0]):
        return None
    sides = (
        y[i] - (4 * y[i - 1] + y[i - 2] - 2 * y[i - 3]) / 3,
        y[i] - (4 * y[i + 1] + y[i + 2] - 2 * y[i + 3]) / 3,
    )
    if min(np.sign(dk[0]) * d for d in sides) <= 3.0 * math.sqrt(10 / 3) * sigma:
        return None  # on a line through the neighbours of one side: a corner
    if 5 <= i < n - 5:  # the neighbours' curve reaches the samples beyond them
        far = y[i + _REACH_OFFSETS] - _REACH_W @ y[i + _SPIKE_OFFSETS]
        allowed = np.maximum(5.0 * sigma * np.sqrt(_REACH_VAR), abs(dk[0]) / 3.0)
        if np.any(np.abs(far) > allowed):
            return None
    trial = y.copy()
    trial[i] = y[i] - dk[0]
    near = np.arange(max(i - 3, 3), min(i + 4, n - 3))
    near = near[near != i]
    dn, _ = _spike_stats(trial, near)
    if near.size and np.max(np.abs(dn)) > 4.0 * sd:
        return None
    return float(trial[i])


def find_spikes(y, *, k: float | None = None, false_alarm: float = 1e-3, sigma=None):
    """Isolated samples of ``y`` that no band-limited signal makes, and their repairs.

    Each interior sample is compared with the least-squares quadratic through its six
    neighbours (three on each side): the difference d has variance 1.5·σ² under white
    noise σ. A sample is a spike when |d| exceeds k·√1.5·σ (k the Bonferroni threshold of
    :func:`default_threshold` for the record's length), when the neighbours lie on their
    quadratic (|d| above :data:`SPIKE_ISOLATION` times its RMS misfit to them), and when,
    once it is replaced by the quadratic's value, its neighbours are back within 4·√1.5·σ
    of theirs and the samples four and five away lie on the quadratic too (within 5 of
    their σ or a third of the spike: a ringing tone fails this, a lone spike on a smooth
    curve passes); and when it stands off the
    lines through its three neighbours on either side, each extrapolated to it, by more
    than 3·√(10/3)·σ the same way (a kink, where two lines meet, lies on both: a pulse's
    corner the filter has not rounded is no spike). Spikes are taken largest first, each
    repaired before the next is judged.

    Parameters
    ----------
    y : array_like — one channel's samples [N], uniformly sampled
    k : float, optional — threshold in σ [-]; default from the length and ``false_alarm``
    false_alarm : float — chance that white noise alone gives a spike in the record [-]
    sigma : float, optional — the noise σ [N]; default: the MAD of d over the record / √1.5

    Returns
    -------
    (indices, repaired) : numpy.ndarray of int, numpy.ndarray of float — the spikes'
    indices (ascending) and the values their neighbours' quadratic gives there [N]
    """
    y = np.array(y, dtype=float, copy=True).reshape(1, -1)
    if y.size < 7:
        return np.zeros(0, int), np.zeros(0)
    kk = default_threshold(y.size, false_alarm) if k is None else float(k)
    return _find_spikes(y, kk, sigma)[0]


def _find_spikes(Y, kk, sigma=None):
    """:func:`find_spikes` of each row of ``Y`` (channels of n ≥ 7 samples on one clock,
    repaired in place) at the threshold ``kk`` [-]: [(indices, repaired), ...]. The
    residuals and their noise are measured for all the rows at once."""
    D = _spike_residuals(Y)  # at samples 3 … n − 4
    if sigma is None:
        p = D.copy()  # reordered: |p − median| holds the values |D − median| does
        median = _row_medians(p, scratch=True)
        np.abs(np.subtract(p, median[:, None], out=p), out=p)
        sigmas = _MAD_TO_SIGMA * _row_medians(p, scratch=True)
        sigmas = sigmas / math.sqrt(1.5)
    else:
        sigmas = np.full(Y.shape[0], float(sigma))
    spans = Y.max(axis=1) - Y.min(axis=1)  # numpy.ptp
    tops = np.abs(D).max(axis=1)
    return [
        _spikes_of(y, d, float(s), float(span), None, kk, float(top))
        for y, d, s, span, top in zip(Y, D, sigmas.tolist(), spans, tops, strict=True)
    ]


def _smallest_step(y) -> float:
    """The smallest step between distinct neighbours of ``y`` (∞ where all are equal)."""
    steps = np.abs(np.diff(y))
    smallest = steps.min()
    if not smallest > 0:  # equal neighbours (or a NaN) somewhere: leave them out
        smallest = np.min(np.where(steps > 0, steps, np.inf))
    return float(smallest)


def _spikes_of(y, d, sigma, span, step, kk, top=math.nan):
    """The spikes of one channel ``y`` (repaired in place) from its residuals ``d``, the noise
    σ [N] they show, its range, its smallest step (None: worked out here where needed) and
    its largest |d| [N] (where known: no sample is a candidate where that is within the
    threshold) (:func:`_find_spikes`)."""
    if not sigma > 0:
        sigma = float(np.std(d)) / math.sqrt(1.5)
    sigma = max(sigma, _RESOLUTION_FLOOR * span)
    # the converter's rounding noise q/√12 where it is larger: q divides every gap between
    # distinct values, so no step between neighbours below √12·σ leaves the grid's search
    # (a sort of the record) anything to find. It can only raise σ: where no sample stands
    # out at this σ (below), none stands out at the larger one, and the step is not needed
    if not (kk > 0 and sigma > 0 and top <= kk * (sigma * math.sqrt(1.5))):
        if step is None:
            step = _smallest_step(y)
        if math.isfinite(step) and step > math.sqrt(12) * sigma:
            sigma = max(sigma, adc_step(y) / math.sqrt(12))
    if not sigma > 0:
        return np.zeros(0, int), np.zeros(0)
    n = y.size
    sd = sigma * math.sqrt(1.5)
    if top <= kk * sd:  # no sample stands out: no candidate (a NaN top says nothing)
        return np.zeros(0, int), np.zeros(0)
    found, values = [], []
    candidates = np.flatnonzero(np.abs(d) > kk * sd)
    candidates = (3 + candidates[np.argsort(-np.abs(d[candidates]), kind="stable")]).tolist()
    while True:  # largest first; a pass again after each repair (a near one may now pass)
        for i in candidates:
            repaired = _spike_at(y, i, n, kk, sd, sigma)
            if repaired is not None:
                found.append(i)
                values.append(repaired)
                y[i] = repaired
                candidates.remove(i)
                break
        else:
            break
    idx = np.argsort(found)
    return np.asarray(found, dtype=int)[idx], np.asarray(values)[idx]


@dataclass(frozen=True)
class _Uncut:
    """A window's record not cut yet: the record it is cut from (:func:`apply_window`)."""

    source: xr.Dataset


class _WindowedRecord:
    """:attr:`ContactWindow.record`, cut from its source record when first read.

    A fit reads only the window's numbers, and cutting an xarray Dataset (its index, its
    variables, its attributes copied) costs more than finding the window: so
    :func:`find_contact` leaves an :class:`_Uncut` here, and the first read replaces it by
    :func:`apply_window`'s Dataset (a record changed in place between the two shows the
    change, as any xarray view would; the pipeline never changes a record in place).
    """

    def __set_name__(self, owner, name):
        self.slot = "_" + name

    def __get__(self, window, owner=None):
        if window is None:
            return self
        value = window.__dict__[self.slot]
        if isinstance(value, _Uncut):
            value = apply_window(value.source, window)
            window.__dict__[self.slot] = value
        return value

    def __set__(self, window, value):
        # the dataclass's __init__ passes this descriptor itself where no record is given
        window.__dict__[self.slot] = None if value is self else value

    def __repr__(self):
        return "None"  # the default, as a signature shows it


@dataclass(frozen=True)
class ContactWindow:
    """The contact found in a record (all SI).

    Attributes
    ----------
    t_start, t_end : float
        Contact start and end [s] (interpolated zero crossings for sensor records).
    kind : str
        The record kind the window was found for (``sensor``, ``digitised``, ``simulated``).
    noise : dict
        Noise level σ per force channel [N] (NaN where not estimated: digitised and
        simulated records).
    baseline : dict
        :class:`Baseline` per force channel (zero lines where nothing was subtracted).
    n_samples : int
        Samples of the record inside [t_start, t_end].
    threshold : float
        Detection threshold k [-] (contact where |Fn| > k·σ); NaN when not used.
    peak : float
        Largest baseline-corrected Fn in the window [N].
    record : xarray.Dataset
        The baseline-corrected samples inside [t_start, t_end] (same layout as the input;
        attrs ``window_t_start``, ``window_t_end`` [s], ``baseline_removed``), cut from the
        record by :func:`apply_window` when first read (a fit reads only the numbers above).
    other_pulses : tuple of (t_start [s], t_end [s], peak [N])
        Further impacts found after the contact (sensor records; see the module notes).
    glitches : tuple of (t [s], value [N])
        Spikes of a few samples outside the contact, ignored.
    spikes : tuple of Spike
        Isolated samples no force can make (:func:`find_spikes`), repaired for the window
        and left out of the fits.
    """

    t_start: float
    t_end: float
    kind: str
    noise: dict = field(default_factory=dict)
    baseline: dict = field(default_factory=dict)
    n_samples: int = 0
    threshold: float = float("nan")
    peak: float = float("nan")
    record: xr.Dataset | None = field(default=_WindowedRecord(), repr=False, compare=False)
    other_pulses: tuple = ()
    glitches: tuple = ()
    spikes: tuple = ()

    @property
    def duration(self) -> float:
        """Contact duration t_end − t_start [s]."""
        return self.t_end - self.t_start

    def __getstate__(self):
        """A pickled or copied window carries its cut record (not the whole source)."""
        return {**self.__dict__, "_record": self.record}

    def spike_indices(self) -> dict:
        """{channel: [sample indices]} of the spikes (:attr:`spikes`)."""
        out = {}
        for sp in self.spikes:
            out.setdefault(sp.channel, []).append(sp.index)
        return out

    def summary(self) -> dict:
        """JSON-ready dict of the window's numbers (units in the key names; NaN → None)."""
        return json_ready(
            {
                "kind": self.kind,
                "t_start_s": self.t_start,
                "t_end_s": self.t_end,
                "duration_s": self.duration,
                "n_samples": self.n_samples,
                "threshold_sigma": self.threshold,
                "peak_N": self.peak,
                "noise_N": dict(self.noise),
                "baseline": {
                    k: {"offset_N": b.offset, "slope_N_per_s": b.slope, "t_ref_s": b.t_ref}
                    for k, b in self.baseline.items()
                },
                "other_pulses": [
                    {"t_start_s": a, "t_end_s": b, "peak_N": p} for a, b, p in self.other_pulses
                ],
                "glitches": [{"t_s": a, "value_N": v} for a, v in self.glitches],
                "spikes": [
                    {
                        "channel": sp.channel,
                        "index": sp.index,
                        "t_s": sp.t,
                        "value_N": sp.value,
                        "repaired_N": sp.repaired,
                    }
                    for sp in self.spikes
                ],
            }
        )


def apply_window(record: xr.Dataset, window: ContactWindow) -> xr.Dataset:
    """Subtract the window's baselines and keep the samples inside [t_start, t_end].

    Parameters
    ----------
    record : xarray.Dataset
        A record (see :mod:`pipeline.record`); not modified.
    window : ContactWindow
        From :func:`find_contact`.

    Returns
    -------
    xarray.Dataset
        A new record: forces minus baseline [N], samples with t_start ≤ t ≤ t_end, attrs
        ``window_t_start``, ``window_t_end`` [s] and ``baseline_removed`` (0/1) added.
    """
    t = times(record)
    idx = _inside(t, window.t_start, window.t_end)
    # select first, then copy: only the window's samples are copied (the input stays as is).
    # Data never set through .values, which has xarray probe the arrays for dask arrays and
    # so import dask (pipeline.record.time_variable): a deep copy of the selection (the
    # record's attrs set aside: copied below, the immutable ones shared), the baseline
    # subtracted in place from an array in memory, else (lazily loaded, dask) by a new
    # Variable
    sel = record.isel(time=idx)
    sel.attrs = {}
    out = sel.copy(deep=True)
    removed = False
    for name in list(out.data_vars):
        base = window.baseline.get(name)
        if base is None or (base.offset == 0 and base.slope == 0):
            continue
        removed = True
        var = out.variables[name]
        data = var.data
        if type(data) is np.ndarray and data.flags.writeable and data is var.data:
            np.subtract(data, base(t[idx]), out=data)  # the copy's own array
        else:
            new = xr.Variable(var.dims, var.values - base(t[idx]), fastpath=True)
            new.attrs, new.encoding = var.attrs, dict(var.encoding)
            out[name] = new
    out.attrs = _copied(record.attrs)
    out.attrs.update(
        window_t_start=float(window.t_start),
        window_t_end=float(window.t_end),
        baseline_removed=int(removed),
    )
    return out


#: Four ulps of 1 [-].
_EPS4 = 4 * float(np.finfo(float).eps)


def _inside(t, t_start, t_end):
    """The indices of the instants ``t`` [s] in [t_start, t_end] [s]: a slice where they are
    one run (sorted times), else an array."""
    # a tolerance of a few ulp keeps samples that sit exactly on the window's ends
    tol = _EPS4 * max(abs(t_start), abs(t_end), 1e-300)
    idx = ((t >= t_start - tol) & (t <= t_end + tol)).nonzero()[0]  # (flatnonzero)
    if idx.size and idx[-1] - idx[0] + 1 == idx.size:
        return slice(int(idx[0]), int(idx[-1]) + 1)
    return idx


#: Attribute values no one can change in place: shared by a copy.
_IMMUTABLE = (str, int, float, bool, type(None), bytes, complex, np.str_, np.integer, np.floating)


def _copied(attrs) -> dict:
    """A deep copy of ``attrs``: its mutable values (lists, arrays, dicts) copied deeply, the
    immutable ones shared (a record's score of strings and numbers at a third of
    :func:`copy.deepcopy`'s cost)."""
    return {k: v if isinstance(v, _IMMUTABLE) else copy.deepcopy(v) for k, v in attrs.items()}


def find_contact(
    record: xr.Dataset,
    *,
    k: float | None = None,
    false_alarm: float = 1e-3,
    guard: float = 0.25,
    max_iter: int = 20,
    discharge: float = math.inf,
) -> ContactWindow:
    """Find the contact in a record, remove the baseline and estimate the noise.

    Parameters
    ----------
    record : xarray.Dataset
        A record (:mod:`pipeline.record`); its ``attrs["kind"]`` selects the method
        (see the module notes). Not modified.
    k : float, optional
        Detection threshold in units of the noise σ [-]; default
        :func:`default_threshold` (n samples, ``false_alarm``).
    false_alarm : float
        Probability α that white noise alone crosses the default threshold somewhere in
        the record [-].
    guard : float
        Margin on each side of the contact, as a fraction of its duration [-], left out of
        the baseline fit.
    max_iter : int
        Maximum baseline/detection iterations.
    discharge : float
        The sensor's discharge time constant τ [s] (a piezo and its charge amplifier: a
        first-order high-pass), where it is known; ``inf`` (default) for none. A sensor
        record's window is then found on the record with the discharge undone (module
        notes), and :attr:`ContactWindow.record` holds the force so restored.

    Returns
    -------
    ContactWindow

    Raises
    ------
    NoPulseError
        No pulse above the noise (the message gives the peak and the noise level), or
        only spikes.
    TruncatedPulseError
        The pulse runs past the first or last sample.
    SignFlipError
        The largest pulse of Fn is negative (a digitised Fn mostly negative).
    ClippedSignalError
        Fn or Ft sits at its extreme over a flat run inside the pulse.
    InputError
        Too few samples outside the contact to estimate a sensor baseline.

    Warns
    -----
    MultipleImpactWarning
        Further pulses after the contact, or a second impact merged into it (the window
        then ends at the dip between them); listed in ``other_pulses``.
    TriggerGlitchWarning
        Spikes away from the pulse, ignored; listed in ``glitches``.
    SpikeWarning
        Isolated samples no force can make elsewhere (inside or near the pulse, or on
        another channel), repaired; every one is listed in ``spikes``.
    """
    kind = record.attrs.get("kind", "sensor") or "sensor"
    if kind not in KINDS:
        raise InputError(
            f"record kind {kind!r} is unknown; expected one of {KINDS}",
            path=record.attrs.get("source"),
        )
    if kind == "digitised":
        return _passthrough(record)
    if kind == "simulated":
        return _simulated(record)
    try:
        tau = float(discharge)
    except (TypeError, ValueError):
        tau = math.nan
    if not tau > 0:
        raise InputError(
            f"discharge = {discharge!r} must be the sensor's discharge time constant τ > 0 "
            "[s], or inf for none",
            path=record.attrs.get("source"),
        )
    return _sensor(
        record, k=k, false_alarm=false_alarm, guard=guard, max_iter=max_iter, discharge=tau
    )


# ------------------------------------------------------------------ internals
def _channels(record):
    return [c for c in FORCE_CHANNELS if c in record]


def _finish(record, t, t_start, t_end, kind, noise, baseline, threshold, peak, **found):
    """The window of ``record`` (instants ``t`` [s]), its record left to be cut when read;
    ``found``: the other pulses, glitches and spikes."""
    inside = _inside(t, float(t_start), float(t_end))
    n_samples = inside.stop - inside.start if isinstance(inside, slice) else inside.size
    return ContactWindow(
        t_start=float(t_start),
        t_end=float(t_end),
        kind=kind,
        noise=noise,
        baseline=baseline,
        n_samples=int(n_samples),
        threshold=float(threshold),
        peak=float(peak),
        record=_Uncut(record),
        **found,
    )


def _passthrough(record):
    t = times(record)
    tf, fn = channel(record, "Fn")
    if -np.min(fn) > max(np.max(fn), 0.0):
        raise SignFlipError(
            f"the digitised Fn is {'all ' if np.max(fn) <= 0 else 'mostly '}negative (from "
            f"{float(np.min(fn)):.4g} N to {float(np.max(fn)):.4g} N): Fn must be compressive "
            "> 0. Calibrate the plot's y axis again in WebPlotDigitizer (or digitise the "
            "normal force, not another curve)",
            path=record.attrs.get("source"),
        )
    # a digitised curve's baseline is zero up to the clicks' error: a return below
    # DIGITISED_ZERO of the peak between two humps separates two impacts
    end, later = _first_pulse(tf, fn, DIGITISED_ZERO * float(np.max(fn)))
    chans = _channels(record)
    win = _finish(
        record,
        t,
        t[0],
        t[-1] if end is None else end,
        "digitised",
        {c: float("nan") for c in chans},
        {c: Baseline() for c in chans},
        float("nan"),
        np.max(fn),
        other_pulses=tuple(later),
    )
    _warn_later_pulses(win, record.attrs.get("source"))
    return win


def _simulated(record):
    t = times(record)
    fn = record.variables["Fn"].values
    pos = np.flatnonzero(fn > 0)
    src = record.attrs.get("source")
    if pos.size == 0:
        raise InputError("simulated record has no sample with Fn > 0: no contact", path=src)
    end, later = _first_pulse(t, fn, 0.0)
    i0 = max(pos[0] - 1, 0)
    i1 = min(pos[-1] + 1, t.size - 1) if end is None else int(np.searchsorted(t, end))
    chans = _channels(record)
    win = _finish(
        record,
        t,
        t[i0],
        t[i1],
        "simulated",
        {c: float("nan") for c in chans},
        {c: Baseline() for c in chans},
        float("nan"),
        fn[: i1 + 1].max(),
        other_pulses=tuple(later),
    )
    _warn_later_pulses(win, src)
    return win


#: A digitised Fn at or below this fraction of its peak is at the baseline (the clicks'
#: error): a dip to it between two humps separates two impacts.
DIGITISED_ZERO = 0.02


def _first_pulse(t, f, level):
    """Where the first pulse of ``f`` above ``level`` ends, and the later pulses.

    A later pulse is a run of at least two samples above ``level`` after the force has come
    back to it (at least one sample at or below ``level`` in between), at least
    :data:`MINOR_PULSE` of the first pulse's peak or lasting at least half as long. Returns
    ``(t_end, later)``: the instant of the first sample back at the level after the first
    pulse (None when no later pulse follows) and ``[(t_start, t_end, peak), ...]``.
    """
    above = f > level
    edges = np.flatnonzero(np.diff(np.concatenate([[0], above.astype(np.int8), [0]])))
    runs = [(int(a), int(b) - 1) for a, b in zip(edges[::2], edges[1::2], strict=True)]
    if len(runs) < 2:
        return None, []
    a0, b0 = runs[0]
    top, length = float(np.max(f[a0 : b0 + 1])), float(t[b0] - t[a0])
    later = []
    for a, b in runs[1:]:
        peak = float(np.max(f[a : b + 1]))
        if b > a and (peak >= MINOR_PULSE * top or t[b] - t[a] >= 0.5 * length):
            later.append((float(t[a]), float(t[b]), peak))
    if not later:
        return None, []
    return float(t[b0 + 1]), later


def _warn_later_pulses(win, src):
    """The MultipleImpactWarning of the window's later pulses, if it has any."""
    if win.other_pulses:
        _warn_later(src, [(a, p) for a, _, p in win.other_pulses], win.peak)


def _centred(tt):
    """(t̄, tt − t̄, Σ(tt − t̄)²) of the instants ``tt`` [s]: the part of a least-squares
    line through samples at them that is the instants' alone (:func:`_line`)."""
    t_mean = np.add.reduce(tt) / tt.size
    x = tt - t_mean
    return t_mean, x, float(x.dot(x))  # (x @ x: the same BLAS dot, a lighter call)


def _line(tt, y, t_ref, both_sides, centred=None):
    """The least-squares line through the samples ``y`` at ``t_ref`` + ``tt`` [s] (both sides
    of the contact), else their mean (one side: a slope would extrapolate across the
    pulse). The means as numpy's (the sum over the count), without its wrapper;
    ``centred``: :func:`_centred` of ``tt`` where known (``tt`` then unused)."""
    if not both_sides:
        return Baseline(float(np.add.reduce(y) / y.size), 0.0, float(t_ref))
    # the least-squares line in closed form, about the samples' mean instant
    t_mean, x, xx = _centred(tt) if centred is None else centred
    y_mean = np.add.reduce(y) / y.size
    s = float(x.dot(y - y_mean)) / xx
    return Baseline(float(y_mean - s * t_mean), s, float(t_ref))


def _undo_discharge(y, t, tau: float):
    r"""The input of a first-order high-pass s/(s + 1/τ) — a piezo sensor's discharge — whose
    output is ``y`` (…, n) at the instants ``t`` [s] (n), from rest at the first sample.

    The exact inverse of the high-pass discretised for an input linear between the samples
    (first-order hold, as :func:`pipeline.sensor_model.to_sensor` applies it):
    :math:`x_k = x_{k-1} + (y_k - q_k y_{k-1})/c_k`, :math:`q_k = e^{-h_k/\tau}`,
    :math:`c_k = (1 - q_k)\,\tau/h_k`, :math:`h_k = t_k - t_{k-1}`, :math:`x_0 = y_0` —
    to :math:`O((h/\tau)^2)` the continuous :math:`x = y + \frac1\tau\int y\,dt`.

    Parameters
    ----------
    y : array_like — the high-pass's output [N], along the last axis
    t : array_like — its instants [s], increasing
    tau : float — the discharge time constant τ [s]

    Returns
    -------
    numpy.ndarray — the input [N], the shape of ``y``
    """
    y = np.asarray(y, dtype=float)
    h = np.diff(np.asarray(t, dtype=float)) / tau
    q = np.exp(-h)
    steps = (y[..., 1:] - q * y[..., :-1]) * (h / -np.expm1(-h))
    x = np.empty_like(y)
    x[..., :1] = y[..., :1]
    np.cumsum(steps, axis=-1, out=x[..., 1:])
    x[..., 1:] += y[..., :1]
    return x


class _Course:
    """How a baseline b(t) = offset + slope·(t − t_ref) of the record shows in the signal the
    window searches: as itself; or, where the sensor's discharge τ is stated and undone
    (:func:`_undo_discharge`, linear), as the images of its two terms — the record's offset
    leaks as the force does, so its image grows by (t − t₀)/τ."""

    def __init__(self, t, t_ref, tau=math.inf):
        self.t, self.t_ref, self.tau = t, float(t_ref), float(tau)
        self.tt = t - self.t_ref  # the instants from t_ref [s], for every line
        self.basis = None  # the images of 1 and t − t_ref, (2, n)
        self._centred = (None, None)  # the last fit's samples and _centred of their instants
        if math.isfinite(self.tau):
            self.basis = _undo_discharge(np.stack([np.ones_like(t), t - t_ref]), t, self.tau)

    def signal(self, y):
        """The samples ``y`` [N] as the window searches them (the discharge undone)."""
        return y if self.basis is None else _undo_discharge(y, self.t, self.tau)

    def __call__(self, base):
        """The baseline ``base`` in the searched signal, at every instant [N]."""
        if self.basis is None:
            if base.t_ref == self.t_ref:  # base(t), its instants' part done once
                return base.offset + base.slope * self.tt
            return base(self.t)
        return base.offset * self.basis[0] + base.slope * self.basis[1]

    def residual(self, y, base, out=None):
        """``y`` less the baseline ``base`` in the searched signal [N] (into ``out``)."""
        if self.basis is None and base.t_ref == self.t_ref and self.tt.dtype == np.float64:
            # the same numbers as y − self(base), in place
            out = np.multiply(self.tt, base.slope, out=out)
            out += base.offset
            return np.subtract(y, out, out=out)
        return np.subtract(y, self(base), out=out)

    def fit(self, y, mask, both_sides):
        """The baseline through the searched samples ``y`` where ``mask`` (:func:`_line`; the
        instants' part kept for further fits on the same mask, which is not changed)."""
        if self.basis is None:
            if not both_sides:
                return _line(None, y[mask], self.t_ref, False)
            if self._centred[0] is not mask:
                self._centred = (mask, _centred(self.tt[mask]))
            return _line(None, y[mask], self.t_ref, True, self._centred[1])
        A = self.basis[: 2 if both_sides else 1, mask].T
        coef = np.linalg.lstsq(A, y[mask], rcond=None)[0]
        return Baseline(float(coef[0]), float(coef[1]) if both_sides else 0.0, self.t_ref)


def _sides(mask, t, t0, t1):
    """The samples of ``mask`` before ``t0`` and after ``t1`` [s]: (left, right)."""
    return int(np.count_nonzero(mask & (t < t0))), int(np.count_nonzero(mask & (t > t1)))


def _ends(t, r, a, b):
    """Contact ends from the run [a, b] where r > σ.

    Each end is the zero crossing of r, linearly interpolated between the last sample
    above σ and its outward neighbour when that neighbour is ≤ 0; when the neighbour lies
    in (0, σ] the end is the neighbour's instant. Stopping the run at σ rather than 0 keeps
    noise-only positive samples from extending the window: on a Hertz pulse with σ ≈ 0.2 %
    of F_max (2 000 Monte-Carlo records) the start error has mean 0.0 and s.d. 0.6 sample
    periods, versus −0.7 ± 1.3 periods when extending while r > 0.
    """
    n = r.size
    if a == 0:
        t0 = t[0]
    elif r[a - 1] <= 0:
        t0 = t[a - 1] + (0.0 - r[a - 1]) * (t[a] - t[a - 1]) / (r[a] - r[a - 1])
    else:
        t0 = t[a - 1]
    if b == n - 1:
        t1 = t[-1]
    elif r[b + 1] <= 0:
        t1 = t[b + 1] + (0.0 - r[b + 1]) * (t[b] - t[b + 1]) / (r[b] - r[b + 1])
    else:
        t1 = t[b + 1]
    return float(t0), float(t1)


def _repair_spikes(record, t, false_alarm):
    """(the record with every channel's spikes repaired, the spikes) — the record itself
    where there are none (:func:`find_spikes`; uniformly sampled channels only; ``t``: the
    record's instants [s])."""
    if t.size < 20:
        return record, ()
    dt = t[1:] - t[:-1]  # numpy's diff, ptp and mean, without their wrappers
    if dt.max() - dt.min() > 1e-6 * (np.add.reduce(dt) / dt.size):
        return record, ()
    found, new = [], {}
    chans = {c: yc for c in _channels(record) if (yc := channel(record, c, t)[1]).size == t.size}
    if not chans:
        return record, ()
    Y = np.array(list(chans.values()), dtype=float)
    spikes = _find_spikes(Y, default_threshold(t.size, false_alarm))
    for (c, yc), (idx, rep) in zip(chans.items(), spikes, strict=True):
        if idx.size:
            fixed = yc.copy()
            fixed[idx] = rep
            new[c] = fixed
            found += [
                Spike(c, int(i), float(t[i]), float(yc[i]), float(v))
                for i, v in zip(idx, rep, strict=True)
            ]
    if not new:
        return record, ()
    out = record.copy()
    for c, fixed in new.items():
        out[c] = (record[c].dims, fixed, record[c].attrs)
    return out, tuple(sorted(found, key=lambda sp: (sp.index, sp.channel)))


def _sensor(record, *, k, false_alarm, guard, max_iter, discharge):
    src = record.attrs.get("source")
    raw_fn = record.variables["Fn"].values
    t = times(record)
    repaired, spikes = _repair_spikes(record, t, false_alarm)
    fn = raw_fn if repaired is record else repaired.variables["Fn"].values
    record = repaired
    n = t.size
    if n < 20:
        raise InputError(
            f"sensor record has only {n} samples; need pre- and post-trigger "
            "samples around the contact (or mark it kind='digitised')",
            path=src,
        )
    kk = default_threshold(n, false_alarm) if k is None else float(k)
    t_ref = 0.5 * (t[0] + t[-1])
    course = _Course(t, t_ref, discharge)
    y = course.signal(fn)
    base, outside = _initial_baseline(t, y, t_ref, course)
    span = float(y.max() - y.min())  # numpy.ptp
    found, line_both = None, None  # line_both: the line was fitted on both sides
    sigma = np.nan
    for _ in range(max_iter):
        r, r_base, r_outside = course.residual(y, base), base, outside
        sigma = _sigma(r, outside, fn, span)
        runs = _runs(r, sigma, kk)
        new = _choose(runs, r, sigma, kk, src)
        if new is None:
            found = None
            break
        t0, t1 = _ends(t, r, new.a, new.b)
        dur = t1 - t0
        # the guard margin, shortened on a side whose trigger span is short so that at
        # least half of that span is still used for the baseline
        g_left = min(guard * dur, 0.5 * (t0 - t[0]))
        g_right = min(guard * dur, 0.5 * (t[-1] - t1))
        new_outside = (t < t0 - g_left) | (t > t1 + g_right)
        for other in new.others + new.glitches:  # other impacts and spikes: not baseline
            g = max(int(guard * (other.b - other.a + 1)), 1)
            new_outside[max(other.a - g, 0) : other.b + g + 1] = False
        if new.ringing:  # the sensor's ring, and a lobe's length beyond its last
            first, last = new.ringing[0], new.ringing[-1]
            new_outside[first.a : last.b + last.size + 1] = False
        left, right = _sides(new_outside, t, t0, t1)
        ends = (t0, t1, left, right)  # the last search's, on its residuals r
        if left + right < 8:
            _check_truncated(new, t, r, sigma, kk, course, src)
            raise InputError(
                f"only {left + right} samples lie outside the contact "
                f"({t0:.6g} s to {t1:.6g} s): a sensor record needs pre- and post-trigger "
                "samples to estimate the baseline; if it is already windowed and free of "
                "offset, mark it kind='digitised'",
                path=src,
            )
        both = left >= 4 and right >= 4
        converged = found is not None and found.key == new.key
        converged = converged and bool((new_outside == outside).all())
        if not (converged and both == line_both):  # else the same samples give the same line
            base, line_both = course.fit(y, new_outside, both), both
            outside = new_outside  # (else the same samples: the mask the line was fitted on)
        found = new
        if converged:
            break
    # the last detection's residuals and noise hold unless the line or its samples changed
    if base != r_base:
        r = course.residual(y, base)
        ends = None
    if found is not None and (base != r_base or not (outside == r_outside).all()):
        sigma = _sigma(r, outside, fn, span)
    fn_spikes = [sp for sp in spikes if sp.channel == "Fn"]
    if found is None and fn_spikes:
        worst = max(fn_spikes, key=lambda sp: abs(sp.value - base(sp.t)))
        raise NoPulseError(
            f"no contact pulse found, only {len(fn_spikes)} spike(s) of 1 sample (the largest "
            f"{worst.value - float(base(worst.t)):.4g} N at sample {worst.index}, "
            f"{_in_sigma(abs(worst.value - base(worst.t)), sigma)}): a contact pulse lasts "
            "many samples. Check the trigger and that the file holds the impact",
            path=src,
        )
    if found is None:
        peak_abs = float(np.max(np.abs(r)))
        raise NoPulseError(
            f"no contact pulse found: the largest |Fn| after baseline removal is "
            f"{peak_abs:.4g} N against a noise σ = {sigma:.4g} N "
            f"({peak_abs / sigma if sigma > 0 else np.inf:.3g} σ); a pulse "
            f"needs at least 2 samples above k·σ = {kk * sigma:.4g} N (k = {kk:.3g}). "
            "Check the channel map and the trigger, or lower k",
            path=src,
        )
    _check_truncated(found, t, r, sigma, kk, course, src)
    # the last search's ends and sides where its residuals hold (its mask is ``outside``)
    t0, t1 = _ends(t, r, found.a, found.b) if ends is None else ends[:2]
    _check_clipping(record, t, found, outside, src)
    # spikes worth a word: well above the threshold, and away from the pulse's edges
    # (where the noise of a short record's σ estimate crosses k·σ now and then)
    margin = guard * (t1 - t0)

    def glitch(i, value):
        return abs(value) > 2 * kk * sigma and not t0 - margin <= t[i] <= t1 + margin

    # the repaired single samples of Fn away from the pulse are the trigger glitches of old
    r_raw = course.residual(course.signal(raw_fn), base) if fn_spikes else r
    lone = [sp for sp in fn_spikes if glitch(sp.index, r_raw[sp.index])]
    runs = [g for g in found.glitches if glitch(g.peak, r[g.peak])]
    runs += [_Run(sp.index, sp.index, int(np.sign(r_raw[sp.index])), sp.index, 1) for sp in lone]
    if runs or found.glitches:
        found = dataclasses.replace(found, glitches=tuple(sorted(runs, key=lambda g: g.a)))
    _report_events(found, t, r_raw, src)
    _report_spikes([sp for sp in spikes if sp not in lone], src)
    left, right = _sides(outside, t, t0, t1) if ends is None else ends[2:]
    noise, baseline = {"Fn": sigma}, {"Fn": base}  # Fn's: the detection's own
    # where the discharge is undone, the window's record holds the force so restored
    restored = {} if course.basis is None else {"Fn": r + base(t)}
    for c in _channels(record):
        if c != "Fn":
            yc = record.variables[c].values
            xc = course.signal(yc)
            baseline[c] = bc = course.fit(xc, outside, left >= 4 and right >= 4)
            rc = course.residual(xc, bc)
            noise[c] = _sigma(rc, outside, yc)
            if restored:
                restored[c] = rc + bc(t)
    if restored:
        record = record.copy()
        for c, xc in restored.items():
            record[c] = (record[c].dims, xc, record[c].attrs)
    peak = float(r[found.a : found.b + 1].max())
    return _finish(
        record,
        t,
        t0,
        t1,
        "sensor",
        noise,
        baseline,
        kk,
        peak,
        other_pulses=tuple((float(t[o.a]), float(t[o.b]), float(r[o.peak])) for o in found.others),
        glitches=tuple((float(t[g.peak]), float(r_raw[g.peak])) for g in found.glitches),
        spikes=spikes,
    )


# ------------------------------------------------------------- pulses, spikes and checks
#: A run of samples above the threshold this short is a spike, not a contact pulse: a real
#: pulse rises and falls over many samples (≈ 100–250 at 1–2 MHz for a steel ball), a
#: trigger glitch lasts one to three.
GLITCH_SAMPLES = 3
#: A pulse smaller than this fraction of the largest is not reported as a second impact
#: (filter ringing, a touch of the sensor) unless it lasts at least half as long as the
#: contact (a weak rebound strike); it is still kept out of the baseline fit.
MINOR_PULSE = 0.05
#: Inside a pulse, a dip below this fraction of the lower of the two humps around it
#: (and ≥ k·σ below it) separates two impacts that merged.
DIP_FRACTION = 0.5
#: Clipping: a flat run at the channel's maximum whose chance under the record's own
#: noise (the rate of equal neighbours in the baseline, to the run's length) is below this.
CLIP_CHANCE = 1e-6


@dataclass(frozen=True)
class _Run:
    """Samples a..b (inclusive) where sign·r > σ, around a core above k·σ."""

    a: int
    b: int
    sign: int
    peak: int  # index of the largest sign·r
    core: int  # samples above k·σ

    @property
    def size(self) -> int:
        return self.b - self.a + 1


@dataclass(frozen=True)
class _Found:
    """The contact pulse chosen, and what else stands above the noise."""

    a: int
    b: int
    others: tuple = ()  # later positive pulses: further impacts, reported
    glitches: tuple = ()  # spikes: reported
    split: int | None = None  # index of the dip where a second impact was cut off
    ringing: tuple = ()  # lobes of the sensor's ring after the pulse: neither

    @property
    def key(self):
        return (self.a, self.b)


#: No force sensor resolves better than about 1e-6 of its signal's range (20 bits): a noise
#: level below that is taken as that, so the rounding of a noise-free (simulated) record's
#: baseline fit is not mistaken for signal.
_RESOLUTION_FLOOR = 1e-6


def _sigma(r, mask, y, span=None) -> float:
    """Noise level of the baseline residuals ``r[mask]`` of a channel whose samples are
    ``y``: the MAD estimate; the standard deviation where the MAD is 0 (quantised, nearly
    noise-free); where both are 0 (a noise-free baseline on one ADC level) the converter's
    rounding noise q/√12, q the grid step of the whole channel
    (:func:`pipeline.record.adc_step`); never below :data:`_RESOLUTION_FLOOR` of the
    channel's range (``span`` [N], where known)."""
    # (the selection is a copy, to reorder)
    sigma = _mad_sigma(np.asarray(r[mask], dtype=float)) or float(np.std(r[mask]))
    if sigma == 0.0:
        sigma = adc_step(y) / math.sqrt(12.0)
    return max(sigma, _RESOLUTION_FLOOR * (float(y.max() - y.min()) if span is None else span))


def _end_samples(n: int) -> int:
    """The samples of each end of an ``n``-sample record its first baseline rests on: 10 %,
    at least 8 where the record has them (the MAD of 3 or 4 about their own median falls to
    a tenth of σ by chance, and the noise then passes for a pulse's ring)."""
    return max(n // 10, min(8, n // 4))


def _initial_baseline(t, y, t_ref, course):
    """The first baseline and the samples it rests on.

    Three candidates: the line through the medians of the first and last 10 % of the
    record, and the median of either end alone. The one that leaves the record's samples
    closest to it (smallest median absolute residual) wins: when both ends are baseline
    the line follows the drift; when one end lies inside a pulse the file cuts, the line
    would run through the pulse and turn it negative, and the quiet end's median wins.
    ``y`` is the signal searched and ``course`` the way a baseline shows in it
    (:class:`_Course`: where a discharge is undone, the lines are those whose images pass
    through the medians).
    """
    n = t.size
    m = _end_samples(n)
    ends = np.array([t[:m], y[:m], t[-m:], y[-m:]], dtype=float)
    ta, ya, tb, yb = _row_medians(ends, scratch=True)
    if course.basis is None:
        slope = (yb - ya) / (tb - ta)
        candidates = [  # through both ends, the first, the last
            Baseline(float(ya + slope * (t_ref - ta)), float(slope), float(t_ref)),
            Baseline(float(ya), 0.0, float(t_ref)),
            Baseline(float(yb), 0.0, float(t_ref)),
        ]
    else:  # the images of offset and slope at the ends' median instants
        (ua, va), (ub, vb) = ([np.interp(x, t, u) for u in course.basis] for x in (ta, tb))
        offset, slope = np.linalg.solve([[ua, va], [ub, vb]], [ya, yb])
        candidates = [
            Baseline(float(offset), float(slope), float(t_ref)),
            Baseline(float(ya / ua), 0.0, float(t_ref)),
            Baseline(float(yb / ub), 0.0, float(t_ref)),
        ]
    dev = np.empty((3, n))
    for row, base in zip(dev, candidates, strict=True):
        course.residual(y, base, out=row)
    best = int(_row_medians(np.abs(dev, out=dev), scratch=True).argmin())
    # the first noise estimate uses the chosen end samples: a pulse that fills most of a
    # short record would otherwise inflate the MAD past the pulse itself
    rests = np.zeros(n, dtype=bool)
    rests[:m] = best != 2
    rests[-m:] = best != 1
    return candidates[best], rests


def _in_sigma(x, sigma) -> str:
    """``x`` in units of σ for a message (a noise-free record has σ = 0)."""
    return f"{float(x) / sigma:.3g} σ" if sigma > 0 else "σ = 0"


def _runs(r, sigma, kk) -> list[_Run]:
    """Every excursion of r beyond ±k·σ, widened while it stays beyond ±σ (same sign).

    A noise-free (or coarsely quantised) baseline has σ = 0: then every sample off it
    counts."""
    if not sigma >= 0:
        return []
    runs = []
    above = np.zeros(r.size + 2, dtype=bool)  # a sample below σ on either side
    level = kk * sigma
    for sign in (1, -1):
        if sign < 0:  # most records have no excursion below −k·σ: the least value says so
            low = r.min()
            if not (low < -level or (low != low and (r < -level).any())):  # (NaN: look)
                continue
        hot = r > level if sign > 0 else r < -level  # sign·r > k·σ
        if not hot.any():
            continue
        s = r if sign > 0 else -r
        # widen each core sample to its run above σ: runs are the maximal stretches above σ
        np.greater(s, sigma, out=above[1:-1])
        edges = (above[1:] != above[:-1]).nonzero()[0]  # (flatnonzero, without its wrapper)
        starts, stops = edges[::2], edges[1::2] - 1
        at = hot.nonzero()[0]  # core samples of each stretch: those in [start, stop]
        cores = at.searchsorted(stops, "right") - at.searchsorted(starts, "left")
        for j in cores.nonzero()[0].tolist():
            a, b = int(starts[j]), int(stops[j])
            pk = a + int(s[a : b + 1].argmax())
            runs.append(_Run(a, b, sign, pk, int(cores[j])))
    return sorted(runs, key=lambda run: run.a)


def _choose(runs, r, sigma, kk, src) -> _Found | None:
    """The contact pulse: the first positive pulse of note (see the module notes)."""
    if not runs:
        return None
    spike = GLITCH_SAMPLES
    glitches, pulses = [], []
    for run in runs:
        if run.size <= spike:
            glitches.append(run)
        elif run.core >= 2:
            pulses.append(run)
    if not pulses:
        if glitches:
            g = max(glitches, key=lambda run: abs(r[run.peak]))
            raise NoPulseError(
                f"no contact pulse found, only {len(glitches)} spike(s) of at most "
                f"{spike} samples (the largest {float(r[g.peak]):.4g} N at sample "
                f"{g.peak}, {_in_sigma(abs(r[g.peak]), sigma)}): a contact pulse lasts many "
                "samples. Check the trigger and that the file holds the impact",
                path=src,
            )
        return None
    biggest = max(pulses, key=lambda run: abs(r[run.peak]))
    main_size = next((run for run in pulses if run.sign > 0), biggest).size
    ringing = _ringing(runs, r, main_size)
    glitches = [run for run in glitches if run not in ringing]
    if biggest.sign < 0:
        raise SignFlipError(
            f"the largest pulse of Fn is negative ({float(r[biggest.peak]):.4g} N from the "
            f"baseline, {biggest.size} samples from sample {biggest.a}): Fn must be "
            "compressive > 0; flip the normal axis sign when loading (axes={'Fn': '-Fz'})",
            path=src,
        )
    top = float(r[biggest.peak])
    major = [run for run in pulses if run.sign > 0 and r[run.peak] >= MINOR_PULSE * top]
    main = major[0]
    # later impacts: pulses of note, and any positive pulse lasting half the contact or more
    # however small (a weak rebound strike lasts longer than the first, t_c ∝ v^(-1/5);
    # filter ringing lasts a fraction of it)
    others = [
        run
        for run in pulses
        if run.a > main.b
        and run.sign > 0
        and run not in ringing
        and (r[run.peak] >= MINOR_PULSE * top or run.size >= 0.5 * main.size)
    ]
    # a ring after the pulse is the sensor's mode, which modulates the pulse too: its dips
    # are the mode's, not a second impact's
    after = [run for run in ringing if run.a > main.b]
    a, b, split = main.a, main.b, None if after else _dip(r, main, sigma, kk)
    if split is not None:
        rest = _Run(split, main.b, 1, split + int(np.argmax(r[split : main.b + 1])), 0)
        others.insert(0, rest)
        b = split - 1
    return _Found(a, b, tuple(others), tuple(glitches), split, tuple(ringing))


#: Two adjoining lobes of opposite sign belong to one ring where the smaller is at least this
#: fraction of the larger (a low-pass's own undershoot after a pulse is ~4 % of it).
RING_FRACTION = 0.15


def _ringing(runs, r, main_size) -> list:
    """The excursions that are lobes of a ring — the sensor's mode after the pulse, not
    another impact: three or more lobes of alternating sign, each adjoining the next
    (within the longer one's length, or three samples) and each at least
    :data:`RING_FRACTION` of its neighbour, and the lobes that follow within a period of
    it no larger than its last (where one between sank into the noise); those shorter
    than the contact pulse (a later impact lasts longer than the first, t_c ∝ v^(-1/5))."""
    if len(runs) < 3:  # (no ring: it has three lobes)
        return []
    out, chain = [], runs[:1]

    def close(chain):
        if len(chain) >= 3:
            out.extend(run for run in chain if run.size < main_size)

    def continues(chain, run):
        """A lobe of the ring past a lobe that sank into the noise: within a period of the
        ring's last, no larger than its last lobes, shorter than the pulse."""
        period = 2.0 * (chain[-1].a - chain[0].a) / (len(chain) - 1)
        top = max(abs(r[x.peak]) for x in chain[-2:])
        return (
            run.a - chain[-1].b <= period and abs(r[run.peak]) <= 1.5 * top and run.size < main_size
        )

    for prev, run in zip(runs, runs[1:], strict=False):
        a, b = abs(r[prev.peak]), abs(r[run.peak])
        linked = (
            run.sign != prev.sign
            and run.a - prev.b <= max(prev.size, run.size, 3)
            and min(a, b) >= RING_FRACTION * max(a, b)
        )
        if linked or (len(chain) >= 3 and continues(chain, run)):
            chain.append(run)
        else:
            close(chain)
            chain = [run]
    close(chain)
    return out


def _dip(r, run, sigma, kk) -> int | None:
    """Index of the bottom of the first deep dip inside a pulse (two merged impacts), or
    None: a sample below DIP_FRACTION of the lower hump around it, and ≥ k·σ below it,
    both humps ≥ 3·k·σ."""
    seg = r[run.a : run.b + 1]
    if seg.size < 3:
        return None
    before = np.maximum.accumulate(seg)
    after = np.maximum.accumulate(seg[::-1])[::-1]
    hump = np.minimum(before, after)
    deep = hump - seg >= kk * sigma  # rare: a single pulse's samples lie on their hump
    if not deep.any():
        return None
    deep &= (seg <= DIP_FRACTION * hump) & (hump >= 3 * kk * sigma)
    if not deep.any():
        return None
    i = int(np.argmax(deep))
    j = i
    while j + 1 < seg.size and deep[j + 1]:
        j += 1
    return run.a + i + int(np.argmin(seg[i : j + 1]))


def _check_truncated(found, t, r, sigma, kk, course, src):
    n = t.size
    if found.a == 0:
        head = r[: _end_samples(n)]
        h = head.size // 2
        level = abs(_median(head[:h]) - _median(head[h:])) < kk * sigma
        if course.basis is None and level and mad_sigma(head) < 2.0 * sigma:
            # a start that lies level, as noisy as the baseline, is baseline, not a pulse's
            # flank or top: the samples after the pulse lie below it, the undershoot of a
            # sensor that discharges
            raise TruncatedPulseError(
                f"the record's first samples lie level, {_median(head):.4g} N "
                f"({_in_sigma(_median(head), sigma)}) above the samples after the contact "
                "pulse, which the baseline then rests on: the force undershoots after the "
                "pulse, as a piezo sensor's discharge makes it (by about the impulse over the "
                "discharge time constant τ, recovering over τ), so the start passes for a "
                "pulse the file cuts. State the sensor's discharge τ [s] — a sidecar's "
                '\'sensor\' block {"discharge": τ}, sensor={"discharge": τ} of the fits, '
                "find_contact(..., discharge=τ) — or, if the file was cut mid-pulse, export "
                "it again with more pre-trigger samples",
                path=src,
            )
        raise TruncatedPulseError(
            f"the record starts inside the contact pulse: Fn is already {float(r[0]):.4g} N "
            f"({_in_sigma(r[0], sigma)} above the baseline) at the first sample "
            f"(t = {float(t[0]):.6g} s); the file was cut mid-pulse — export it again with "
            "more pre-trigger samples",
            path=src,
        )
    if found.b == n - 1:
        raise TruncatedPulseError(
            f"the contact pulse runs past the end of the record: Fn is still "
            f"{float(r[-1]):.4g} N ({_in_sigma(r[-1], sigma)} above the baseline) at the "
            f"last sample (t = {float(t[-1]):.6g} s); the file was cut mid-pulse — export it "
            "again with more post-trigger samples",
            path=src,
        )


def _check_clipping(record, t, found, outside, src):
    """ClippedSignalError when Fn or Ft sits at its extreme over a flat run in the pulse."""
    for c in ("Fn", "Ft"):
        if c not in record:
            continue
        raw = record.variables[c].values
        seg = raw[found.a : found.b + 1]
        for value in (seg.max(), seg.min()):
            at = seg == value
            if np.count_nonzero(at) < 3:
                continue
            at = np.flatnonzero(at)
            base = raw[outside]
            # the rate of equal neighbours in the baseline: how often the noise repeats a value
            rep = (np.count_nonzero(np.diff(base) == 0) + 1) / max(base.size, 2)
            # the longest stretch of consecutive samples at that value
            breaks = np.flatnonzero(np.diff(at) > 1)
            lengths = np.diff(np.concatenate([[-1], breaks, [at.size - 1]]))
            longest = int(lengths.max())
            flat = longest >= max(5, 0.1 * seg.size)
            if longest >= 3 and (min(rep, 1.0) ** (longest - 1) < CLIP_CHANCE or flat):
                i0 = found.a + int(at[0])
                raise ClippedSignalError(
                    f"{c} is clipped: {longest} consecutive samples inside the contact "
                    f"pulse (from t = {float(t[i0]):.6g} s) sit at {float(value):.6g} N, the "
                    f"channel's {'maximum' if value == seg.max() else 'minimum'} (equal "
                    f"neighbours occur at a rate of {rep:.2g} in the baseline): the ADC "
                    "saturated, so the peak and the impulse are lost; record again with a "
                    "larger range or lower gain",
                    path=src,
                    column=c,
                )


def _warn_later(src, pulses, peak, where=""):
    """MultipleImpactWarning listing the later pulses ``[(t_start [s], peak [N]), ...]``."""
    listing = "; ".join(
        f"t = {a:.6g} s, peak {p:.4g} N ({100 * p / peak:.0f} % of the first)" for a, p in pulses
    )
    warnings.warn(
        f"{src}: {where}{len(pulses)} further pulse(s) after the contact ({listing}): a rebound "
        "strike or a second impact; the analysis keeps to the first",
        MultipleImpactWarning,
        stacklevel=caller_level(__file__),
    )


def _report_spikes(spikes, src):
    """SpikeWarning listing the repaired samples (those not reported as trigger glitches)."""
    if not spikes:
        return
    listing = "; ".join(
        f"{sp.channel} sample {sp.index} (t = {reading('t0', sp.t)}: {sp.value:.4g} N, its "
        f"neighbours give {sp.repaired:.4g} N)"
        for sp in spikes[:8]
    ) + ("; ..." if len(spikes) > 8 else "")
    warnings.warn(
        f"{src}: {len(spikes)} isolated sample(s) no force history can make ({listing}): "
        "electrical spikes, replaced by their neighbours' curve for the window and the "
        "percussions and left out of the contact fits",
        SpikeWarning,
        stacklevel=caller_level(__file__),
    )


def _report_events(found, t, r, src):
    if found.others:
        where = (
            f"a second impact begins inside the contact (the force dips to "
            f"{float(r[found.split]):.4g} N at t = {float(t[found.split]):.6g} s and rises "
            "again): the window ends at that dip. "
            if found.split is not None
            else ""
        )
        peak = float(np.max(r[found.a : found.b + 1]))
        pulses = [(float(t[o.a]), float(r[o.peak])) for o in found.others]
        _warn_later(src, pulses, peak, where)
    if found.glitches:
        g = found.glitches
        worst = max(g, key=lambda run: abs(r[run.peak]))
        warnings.warn(
            f"{src}: {len(g)} spike(s) of at most {max(run.size for run in g)} sample(s) "
            f"outside the contact pulse (the largest {float(r[worst.peak]):.4g} N at t = "
            f"{float(t[worst.peak]):.6g} s): a trigger glitch or an electrical spike; "
            "ignored",
            TriggerGlitchWarning,
            stacklevel=caller_level(__file__),
        )
