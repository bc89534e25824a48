r"""The forward model of a record: contact parameters → what the sensor would have recorded.

For each set of parameters (a *column*: E* [Pa], e [-], μ [-], ``kt_scale`` [-], speed
[m/s], onset t0 [s]) the model is built from three pieces, none of which integrates an ODE:

1. the **normal pulse** of the chosen law at restitution e, a master curve tabulated once
   (:mod:`pipeline.fit.pulse`) and scaled by
   :math:`\delta^* = (m^* v_0^2/K)^{2/5}` (K = (4/3)E*√R*, v0 = speed·cos α): time by
   δ*/v0 and force by m*·v0²/δ* (so E* and the speed only stretch and scale it);
2. the **tangential force** on that pulse (:mod:`pipeline.fit.tangential`), which in these
   units depends on e, μ, ``kt_scale`` (through k_c = 6·(G*/E*)·``kt_scale``, G*/E* from the
   scene's Poisson ratios), the initial slip s0 = slip/v0 and λ = m*/m_t only — so E*
   and t0 never require a new tangential solution, and the columns of a Jacobian that
   differ only in them share one;
3. the **sensor** (:mod:`pipeline.fit.sensor`): cross-talk, then the low-pass filter on a
   grid ``oversample`` times finer than the samples (first-order hold), then sampling.

Between the pulse's nodes the forces are cubic Hermite interpolants (values and rates at
the nodes), so the 128 default steps per contact keep the interpolation error near 1e-8
of the peak. All columns of all records are solved together: one table lookup and one
tangential solve per call, a few numpy operations per record after that.

The data a fit uses (:func:`prepare`): every sample of each force channel (or those of the
contact window of :func:`pipeline.window.find_contact` widened by ``margin``, a fraction of
the contact duration, on each side), less the window's baseline; saturated samples left
out; weights 1/σ from each channel's noise measured outside the contact
(:attr:`pipeline.window.ContactWindow.noise`, floored at the ADC step's q/√12), or, where a
record has no trigger margins (digitised, simulated), from
:func:`pipeline.smooth.noise_level`.

**The baseline is fitted with the contact.** The window's baseline (offset and drift of each
channel, from the samples outside the contact) is an estimate: its error, ~σ/√n_outside,
is common to every sample and shifts the integral of the pulse, hence e (at 0.4 % noise,
as much as the noise does through the pulse itself). Ignoring it makes the intervals of e
too narrow. So a sensor record's fit carries each channel's residual offset and drift
(a + b·(t − t̄)) as nuisance parameters, eliminated exactly by projection (they enter
linearly: the residuals and the Jacobian are projected onto the complement of
{1, t − t̄} per channel; Golub & Pereyra 1973), so the covariance and the bootstrap are
those of the contact parameters with the baseline refitted. The fit then uses all the
samples, the trigger margins included.

References
----------
G. H. Golub, V. Pereyra, SIAM J. Numer. Anal. 10:413 (1973), doi:10.1137/0710036.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy.signal import lfilter, sosfilt

from ..errors import InputError, SpikeWarning
from ..record import channel, times
from ..scene import Scene
from ..simulate import tangential_history
from ..smooth import noise_level
from ..window import _centred, find_contact, mad_sigma
from .noise import WHITE, NoiseModel, measure_noise
from .pulse import E_MIN, check_elastic, pulse_table, shape_of
from .sensor import SensorSpec, sensor_spec
from .tangential import HISTORY_RULES, TANGENTIAL_MODELS, TangentialResponse, tangential_response

__all__ = [
    "PARAMS",
    "SYSTEMATIC_PARAMS",
    "ANALYTIC",
    "UNITS",
    "param_scales",
    "Channel",
    "RecordData",
    "ForwardModel",
    "prepare",
    "weighted_residuals",
]

#: The local parameters of one record's model, in column order: the contact's, then the
#: inputs a lab knows only to a tolerance (the systematics of :func:`pipeline.fit_contact`;
#: fixed at their stated values unless the fit varies them).
PARAMS = (
    "E_eff",
    "e",
    "mu",
    "kt_scale",
    "speed",
    "t0",
    "mass",
    "radius",
    "gain_n",
    "gain_t",
    "leak",
    "leak_tn",
    "time_base",
    "bandwidth",
    "resonance",
    "damping_ratio",
    "discharge",
    "shift_n",
    "shift_t",
    "shift_at",
    "shift_width",
)
#: The inputs known to a tolerance, among :data:`PARAMS`: every one after the contact's
#: four but the onset t0.
SYSTEMATIC_PARAMS = tuple(p for p in PARAMS[4:] if p != "t0")
#: The zero shift's parameters, among :data:`SYSTEMATIC_PARAMS` (fitted where the record
#: shows one, no prior): its size on Fn and Ft [N], the instant it is half done and the time
#: it takes [s] (:func:`zero_shift`).
SHIFT_PARAMS = ("shift_n", "shift_t", "shift_at", "shift_width")
#: The parameter of each channel's zero shift, among :data:`SHIFT_PARAMS`.
SHIFT_OF = {"Fn": "shift_n", "Ft": "shift_t"}
#: The sensor chain's parameters, among :data:`PARAMS` (each column filtered with its own).
CHAIN_PARAMS = ("bandwidth", "resonance", "damping_ratio", "discharge")
UNITS = {
    "E_eff": "Pa",
    "e": "1",
    "alpha": "s/m",
    "mu": "1",
    "mu_a": "1",
    "mu_b": "s/m",
    "kt_scale": "1",
    "speed": "m/s",
    "t0": "s",
    "mass": "kg",
    "radius": "m",
    "gain_n": "1",
    "gain_t": "1",
    "leak": "1",
    "leak_tn": "1",
    "time_base": "1",
    "bandwidth": "Hz",
    "p_y": "Pa",
    "v_y": "m/s",
    "resonance": "Hz",
    "damping_ratio": "1",
    "discharge": "s",
    "shift_n": "N",
    "shift_t": "N",
    "shift_at": "s",
    "shift_width": "s",
}
_I = {name: i for i, name in enumerate(PARAMS)}
#: The columns of :data:`CHAIN_PARAMS` and of the zero shift's sizes among :data:`PARAMS`
#: (adjacent: slices, so that a model's columns of them are views).
_CHAIN = slice(_I[CHAIN_PARAMS[0]], _I[CHAIN_PARAMS[0]] + len(CHAIN_PARAMS))
_SHIFT = slice(_I["shift_n"], _I["shift_n"] + 2)
assert PARAMS[_CHAIN] == CHAIN_PARAMS and PARAMS[_SHIFT] == ("shift_n", "shift_t")
#: The analytic parameters that mix the axes (their derivatives: :meth:`ForwardModel._dmix`).
_MIXING = ("gain_n", "gain_t", "leak", "leak_tn")
#: Their columns among :data:`PARAMS` (adjacent), and their values where the axes do not mix.
_AXES = slice(_I["gain_n"], _I["gain_n"] + len(_MIXING))
assert PARAMS[_AXES] == _MIXING
_AXES_NONE = np.array([1.0, 1.0, 0.0, 0.0])
#: Local parameters whose derivatives the forward model gives in closed form (they scale,
#: stretch, shift or mix the pulse: no new tangential solution); the others by differences.
ANALYTIC = ("E_eff", "t0", "mass", "radius", "gain_n", "gain_t", "leak", "leak_tn", "time_base")


@dataclass(frozen=True, eq=False)
class Channel:
    """One force channel's fitted samples.

    Attributes
    ----------
    name : str — ``"Fn"`` or ``"Ft"``
    t : numpy.ndarray — sample instants [s]
    y : numpy.ndarray — measured force less the baseline [N]
    sigma : float or numpy.ndarray — noise standard deviation [N] (the weights are 1/σ; one
        per point for a digitised record weighed by its effective variance)
    basis : numpy.ndarray or None — orthonormal basis (n, 2) of {1, t − t̄}: the residual
        baseline fitted with the contact (module notes); None: no baseline fitted
    n_noise : int — samples σ was measured on (0: not measured, e.g. given)
    noise : pipeline.fit.noise.NoiseModel — the noise's correlation, measured before the
        trigger (white where none shows)
    index : numpy.ndarray or None — the samples' places on the record's common grid
        (:attr:`RecordData.n_grid`): None where the channel has every sample of it, else
        those left after the spikes and saturated samples are left out
    """

    name: str
    t: np.ndarray
    y: np.ndarray
    sigma: float
    basis: np.ndarray | None = None
    n_noise: int = 0
    noise: NoiseModel = WHITE
    index: np.ndarray | None = None

    def __post_init__(self):
        wb = None
        if self.basis is not None:
            wb = (
                self.basis
                if self.noise.white
                else np.linalg.qr(self.noise.whiten(self.basis.T).T)[0]
            )
        object.__setattr__(self, "_wbasis", wb)

    @property
    def sigma_rms(self) -> float:
        """The noise level [N]: σ, or the RMS of the points' σ where each has its own."""
        return float(np.sqrt(np.mean(np.square(self.sigma))))

    def project(self, r):
        """``r`` (…, n) less its least-squares baseline a + b·(t − t̄)."""
        if self.basis is None:
            return r
        return r - (r @ self.basis) @ self.basis.T

    def rows(self, r, out=None):
        """The fit's residual rows of ``r`` (…, n) = (y − model)/σ: whitened by the
        channel's noise model (:mod:`pipeline.fit.noise`) and less their fitted baseline
        (generalised least squares: the baseline basis whitened alike); ``out``: where to
        write them (else a new array, or ``r`` itself where there is nothing to do)."""
        w = self.noise.whiten(r)
        if self._wbasis is None:
            if out is None:
                return w
            out[...] = w
            return out
        return np.subtract(w, (w @ self._wbasis) @ self._wbasis.T, out=out)


@dataclass(frozen=True, eq=False)
class RecordData:
    """One record prepared for fitting (see the module notes).

    Attributes
    ----------
    record : xarray.Dataset — the record as given
    scene : Scene — its scene (speed, angle, masses, radii, Poisson ratios)
    window : pipeline.window.ContactWindow
    sensor : SensorSpec
    channels : tuple of Channel
    fine : numpy.ndarray or None — the filter's fine time grid [s] (uniform records), sample
        k of every channel at ``fine[k * oversample]``
    oversample : int
    sos : numpy.ndarray or None — the stated filter discretised on the fine grid (None
        without a stated bandwidth)
    notes : tuple of str — what the preparation assumed or left out
    excluded : dict — {channel: [sample indices of the record]} left out of the fit: the
        spikes the window found (:func:`pipeline.window.find_spikes`) and samples at the
        ADC's end codes
    m_eff, R_eff, lam, g_ratio, cos_a, sin_a : float — scene constants: m* [kg], R* [m],
        m*/m_t, G*/E*, cos and sin of the incidence (at the stated mass and radius; the
        model takes them per column from the ``mass`` and ``radius`` parameters)
    """

    record: object
    scene: Scene
    window: object
    sensor: SensorSpec
    channels: tuple
    fine: np.ndarray | None
    oversample: int
    sos: np.ndarray | None = None
    notes: tuple = field(default_factory=tuple)
    excluded: dict = field(default_factory=dict)

    @property
    def n_grid(self) -> int:
        """Samples of the common grid the channels index (the fine grid's sample instants)."""
        if self.fine is None:
            return self.channels[0].t.size
        return (self.fine.size - 1) // self.oversample + 1

    def at_channel(self, x, i):
        """``x`` (…, n_grid) at the samples of channel ``i``."""
        idx = self.channels[i].index
        return x if idx is None else x[..., idx]

    # ------------------------------------------------------------- scene constants
    def __post_init__(self):
        sc = self.scene
        const = {
            "m_target": float(sc.target_mass),
            "R_target": float(sc.target_radius),
            "kappa": float(sc.kappa),
            "g_ratio": float(sc.G_eff / sc.E_eff),  # G*/E* of the scene's materials
            "cos_a": math.cos(math.radians(float(sc.angle_deg))),
            "sin_a": math.sin(math.radians(float(sc.angle_deg))),
            "slip_offset": float(sc.surface_speed + sc.spin * sc.radius),
        }
        for k, v in const.items():
            object.__setattr__(self, k, v)
        m, R = float(sc.m), float(sc.radius)
        for k, v in {
            "m_eff": self.m_eff_of(m),
            "R_eff": self.R_eff_of(R),
            "lam": self.lam_of(m),
        }.items():
            object.__setattr__(self, k, float(v))
        # what the forward model works out from the record's sensor alone (its ring times
        # and its low-pass at the bandwidths asked for): kept for the record's later
        # evaluations, each as the first one computed it
        object.__setattr__(self, "_memo", {})

    def _ring_time(self, *chain) -> float:
        """:meth:`SensorSpec.ring_time` at ``chain`` (bandwidth, resonance, ζ, discharge),
        kept per chain."""
        key = ("ring",) + chain
        out = self._memo.get(key)
        if out is None:
            out = self._remember(key, self.sensor.ring_time(*chain))
        return out

    def _lowpass(self, step, bandwidth):
        """The sensor's low-pass at ``bandwidth`` [Hz] on the fine grid of step ``step`` [s]
        as :func:`_sampled` applies it: (b, a) of its one second-order section, or its
        sections (more than one); kept per bandwidth."""
        key = ("lowpass", step, bandwidth)
        out = self._memo.get(key)
        if out is None:
            sos = self.sensor.sos(step, bandwidth=bandwidth)
            out = self._remember(key, (sos[0, :3], sos[0, 3:]) if sos.shape[0] == 1 else sos)
        return out

    def _static(self, P) -> _Static:
        """:class:`_Static` of the model's columns P (C, len(PARAMS)), kept per the values
        of their columns from ``mass`` on (a fit seldom moves them)."""
        key = ("static", P.shape[0], P[:, _STATIC].tobytes())
        out = self._memo.get(key)
        if out is None:
            out = self._remember(key, _Static.of(self, P))
        return out

    def _remember(self, key, value):
        if len(self._memo) >= 256:  # a fitted bandwidth asks for new ones at every step
            self._memo.clear()
        self._memo[key] = value
        return value

    def fine_span(self, first, last) -> tuple[int, int]:
        """(lo, hi): the slice of the fine grid that holds the instants ``first`` to
        ``last`` [s] with a fine step to spare on each side, started on a sample instant."""
        fine = self.fine
        lo = max(int(fine.searchsorted(first)) - 1, 0)
        lo -= lo % self.oversample
        return lo, min(int(fine.searchsorted(last)) + 1, fine.size)

    def m_eff_of(self, mass):
        """m* [kg] for a ball of ``mass`` [kg] on this target."""
        return 1.0 / (1.0 / np.asarray(mass, dtype=float) + 1.0 / self.m_target)

    def R_eff_of(self, radius):
        """R* [m] for a ball of ``radius`` [m] on this target."""
        return 1.0 / (1.0 / np.asarray(radius, dtype=float) + 1.0 / self.R_target)

    def lam_of(self, mass):
        """λ = m*/m_t for a ball of ``mass`` [kg] (docs/theory.md; a free second sphere adds
        its own rotational term)."""
        mass = np.asarray(mass, dtype=float)
        extra = 0.0 if math.isinf(self.m_target) else (1 + 1 / self.kappa) / self.m_target
        return self.m_eff_of(mass) * ((1 + 1 / self.kappa) / mass + extra)

    def nominal(self) -> np.ndarray:
        """Every local parameter at its stated value (the scene's and the sensor's; NaN for
        the contact's own, E*, e, μ, ``kt_scale`` 1, t0, which a fit supplies)."""
        out = np.full(len(PARAMS), np.nan)
        sc = self.scene
        out[_I["kt_scale"]] = 1.0
        out[_I["speed"]] = float(sc.speed)
        out[_I["mass"]] = float(sc.m)
        out[_I["radius"]] = float(sc.radius)
        out[_I["gain_n"]] = out[_I["gain_t"]] = 1.0
        out[_I["leak"]] = out[_I["leak_tn"]] = out[_I["time_base"]] = 0.0
        out[_I["bandwidth"]] = float(self.sensor.bandwidth)
        out[_I["resonance"]] = float(self.sensor.resonance)
        out[_I["damping_ratio"]] = float(self.sensor.damping_ratio)
        out[_I["discharge"]] = float(self.sensor.discharge)
        out[_I["shift_n"]] = out[_I["shift_t"]] = 0.0
        out[_I["shift_at"]] = 0.5 * (self.window.t_start + self.window.t_end)
        out[_I["shift_width"]] = 0.5 * self.window.duration
        return out

    def with_sensor(self, spec: SensorSpec) -> RecordData:
        """The same samples seen through the sensor ``spec`` (another filter order, say):
        the filter's discretisation follows it, the window, samples and weights are
        shared (the verdict's refits use it instead of preparing the record again)."""
        sos = None
        if self.fine is not None and spec.filtered:
            sos = spec.sos(float(self.fine[1] - self.fine[0]) if self.fine.size > 1 else 1.0)
        return dataclasses.replace(self, sensor=spec, sos=sos)

    def slip0(self, speed):
        """Initial slip of the contact point [m/s] at impact speed ``speed`` (docs/theory.md)."""
        return np.asarray(speed) * self.sin_a - self.slip_offset

    @property
    def n_data(self) -> int:
        return sum(c.t.size for c in self.channels)

    @property
    def n_nuisance(self) -> int:
        """Baseline parameters fitted with the contact (two per channel where fitted)."""
        return sum(0 if c.basis is None else c.basis.shape[1] for c in self.channels)

    def y(self) -> np.ndarray:
        """The weighted data, channels concatenated (y/σ, whitened, each less its fitted
        baseline: :meth:`Channel.rows`)."""
        return np.concatenate([c.rows(c.y / c.sigma) for c in self.channels])


#: The columns of :data:`PARAMS` that :class:`_Static` depends on: mass on, every one after
#: the contact's own and the onset.
_STATIC = slice(_I["mass"], len(PARAMS))


@dataclass(frozen=True, eq=False)
class _Static:
    """What the forward model works out per evaluation from the columns of P that a fit
    seldom moves (:data:`_STATIC`): kept by :meth:`RecordData._static` (internal; the
    arrays are shared, never written).

    m_eff, sqrt_R, stretch : (C,) m* [kg], √R* [√m] and 1 + ``time_base`` of each column;
    finite : any column's bandwidth, resonance, ζ, discharge finite (4 bools); shifted :
    any zero shift; moved : any column's gain_n, gain_t, leak, leak_tn other than the
    axes' own (4 bools); bandwidths : the columns' bandwidths (list), one : all one;
    lam : (C,) m*/m_t; ring : the time the chain's ringing takes to decay [s]
    (:meth:`RecordData._ring_time`: the slowest column's; None without a fine grid or a
    chain)
    """

    m_eff: np.ndarray
    sqrt_R: np.ndarray
    stretch: np.ndarray
    finite: list
    shifted: bool
    moved: list
    bandwidths: list
    one: bool
    lam: np.ndarray
    ring: float | None

    @classmethod
    def of(cls, data: RecordData, P) -> _Static:
        bandwidths = P[:, _I["bandwidth"]].tolist()
        finite = np.isfinite(P[:, _CHAIN]).any(axis=0).tolist()
        ring = None
        if data.fine is None:
            pass
        elif finite[1] or finite[3]:  # a mode or a discharge: each column's whole chain
            ring = max(data._ring_time(*row) for row in _distinct_rows(P[:, _CHAIN])[0].tolist())
        elif finite[0]:  # the low-pass alone: the lowest bandwidth rings longest
            ring = data._ring_time(min(b for b in bandwidths if math.isfinite(b)))
        return cls(
            m_eff=data.m_eff_of(P[:, _I["mass"]]),
            sqrt_R=np.sqrt(data.R_eff_of(P[:, _I["radius"]])),
            stretch=1.0 + P[:, _I["time_base"]],
            finite=finite,
            shifted=bool(np.count_nonzero(P[:, _SHIFT])),
            moved=(P[:, _AXES] != _AXES_NONE).any(axis=0).tolist(),
            bandwidths=bandwidths,
            one=len(set(bandwidths)) == 1,
            lam=data.lam_of(P[:, _I["mass"]]),
            ring=ring,
        )


def param_scales(data: RecordData) -> np.ndarray:
    """A typical magnitude of each local parameter of ``data`` (:data:`PARAMS` order), for
    finite-difference steps and convergence tests."""
    sc = data.scene
    return np.array(
        [
            1e9,  # E_eff [Pa]
            0.1,  # e
            0.01,  # mu
            0.1,  # kt_scale
            0.1,  # speed [m/s]
            data.window.duration,  # t0 [s]
            float(sc.m),  # mass [kg]
            float(sc.radius),  # radius [m]
            0.01,  # gain_n
            0.01,  # gain_t
            0.001,  # leak
            0.001,  # leak_tn
            1e-5,  # time_base
            1e4,  # bandwidth [Hz]
            1e4,  # resonance [Hz]
            0.01,  # damping_ratio
            data.window.duration,  # discharge [s]
            max(0.01 * abs(float(data.window.peak)), 1e-9),  # shift_n [N]
            max(0.01 * abs(float(data.window.peak)), 1e-9),  # shift_t [N]
            data.window.duration,  # shift_at [s]
            data.window.duration,  # shift_width [s]
        ]
    )


def _repaired(record, win, name, t=None, f=None):
    """(t [s], values [N]) of channel ``name`` with the window's spikes repaired (``t``,
    ``f``: the channel as :func:`pipeline.record.channel` reads it, where read already)."""
    if t is None:
        t, f = channel(record, name)
    mine = [sp for sp in win.spikes if sp.channel == name]
    if mine and t.size == record.sizes["time"]:
        f = np.array(f, dtype=float, copy=True)
        f[[sp.index for sp in mine]] = [sp.repaired for sp in mine]
    return t, f


def _noise_model(record, win, name, t, f, uniform=None, part=False) -> NoiseModel:
    """The channel's noise model from its pre-trigger samples (sensor records; white for
    the others, and where the record is not uniformly sampled), less their own line (the
    window's baseline, fitted on both sides, tilts where the zero shifts or the charge
    leaks, and a tilt is no correlation of the noise). ``uniform``: whether the instants
    ``t`` [s] are uniformly sampled, where known; ``part``: :func:`_pre_trigger` of ``t``
    where worked out already."""
    if win.kind != "sensor" or name not in win.baseline:
        return WHITE
    if uniform is None:
        dt = np.diff(t)
        uniform = t.size >= 3 and not np.ptp(dt) > 1e-6 * np.mean(dt)
    if not uniform:
        return WHITE
    pre = _before_contact(win, t, f, part=part)
    if pre is not None:
        return measure_noise(pre)
    pre = t < win.t_start - 0.1 * win.duration
    return measure_noise(f[pre] - win.baseline[name](t[pre]))


def _noise(win, name, t, f):
    sigma = float(win.noise.get(name, float("nan")))
    if math.isfinite(sigma):
        return sigma, None
    if t.size >= 5:
        return float(noise_level(win, None, name)), (
            f"{name}: no trigger margins to measure the noise; σ estimated from the samples "
            "(second differences or a smoothing spline, pipeline.smooth.noise_level)"
        )
    raise InputError(
        f"{name} has only {t.size} samples: too few to estimate its noise; give noise= "
        "(σ per channel [N])",
        path=win.record.attrs.get("source") if win.record is not None else None,
    )


def prepare(
    record,
    scene: Scene,
    *,
    channels=("Fn", "Ft"),
    sensor=None,
    margin: float | None = None,
    oversample: int = 4,
    noise=None,
    window_options=None,
    baseline: bool | None = None,
    noise_model: bool = True,
    quiet_after: bool | None = None,
) -> RecordData:
    """The samples, weights and sensor model a fit of ``record`` uses (module notes).

    Parameters
    ----------
    record : xarray.Dataset — a record (:func:`pipeline.io.load`, :mod:`pipeline.simulate`)
    scene : Scene — needs ``E`` and ``nu`` (for G*/E* and a starting E*)
    channels : tuple of str — the force channels fitted
    sensor : SensorSpec or mapping, optional — see :func:`pipeline.fit.sensor.sensor_spec`
    margin : float, optional — samples kept on each side of the contact window [fraction
        of its duration]; None (default): every sample
    oversample : int — fine-grid factor of the filter model
    noise : mapping, optional — σ per channel [N], overriding the measured noise
    window_options : dict, optional — passed to :func:`pipeline.window.find_contact` (its
        ``discharge`` by default the sensor's)
    baseline : bool, optional — fit each channel's residual offset and drift with the
        contact (module notes); default: for sensor records (whose baseline the window
        estimated from trigger margins)
    noise_model : bool — measure each channel's noise correlation before the trigger and
        whiten the fit's residuals by it (:mod:`pipeline.fit.noise`; default True)
    quiet_after : bool, optional — measure the noise on the samples before the contact only
        (the samples after it carry the sensor's own response: a ring, an undershoot, a
        shifted zero); default: where the sensor states a mode or a discharge, else on both
        sides, as the window does

    Returns
    -------
    RecordData
    """
    if not isinstance(scene, Scene):
        raise InputError("a fit needs a pipeline.Scene describing the impact")
    scene._need_elastic()
    for name in channels:
        if name not in record:
            raise InputError(
                f"the record has no {name} channel to fit; fit tangential='none' for a record "
                "with only Fn",
                path=record.attrs.get("source"),
            )
    if margin is not None and not (margin >= 0):
        raise InputError(f"margin must be ≥ 0 (a fraction of the contact duration), got {margin}")
    spec = sensor_spec(record, sensor)
    t_all = times(record)
    with warnings.catch_warnings():  # a fit says what it leaves out (its verdict)
        warnings.simplefilter("ignore", SpikeWarning)
        # a stated discharge is undone for the window: the samples after the pulse lie on
        # its undershoot, no baseline (pipeline.window)
        win = find_contact(record, **{"discharge": spec.discharge, **(window_options or {})})
    notes = list(spec.notes)
    if quiet_after is None:
        quiet_after = spec.dynamic
    dur = win.duration
    if margin is None:
        lo, hi = -math.inf, math.inf
    else:
        lo, hi = win.t_start - margin * dur, win.t_end + margin * dur
    if baseline is None:
        baseline = win.kind == "sensor"
    half = None if not math.isfinite(spec.full_scale) else 0.5 * spec.full_scale
    spikes = win.spike_indices()
    grid, raw = None, []
    for name in channels:
        t, f = channel(record, name, t_all)
        keep = t == t if margin is None else (t >= lo) & (t <= hi)  # (−∞ ≤ t ≤ ∞: not NaN)
        if half is not None:  # the ADC's end codes, left out
            drop = np.abs(f) >= half - 0.5 * spec.quantum - 1e-12 * half
            if (drop & keep).any():
                notes.append(
                    f"{name}: {int(np.sum(drop & keep))} saturated samples (ADC end codes) left out"
                )
        else:
            drop = np.zeros(t.size, dtype=bool)
        if name in spikes and t.size == t_all.size:  # (the record's samples)
            drop[spikes[name]] = True
            notes.append(
                f"{name}: samples {spikes[name]} left out: isolated spikes no force history "
                "can make (pipeline.window.find_spikes)"
            )
        raw.append((name, t, f, keep, drop))
        if grid is None:
            grid = t[keep]
        elif grid is not False and not np.array_equal(grid, t[keep]):
            grid = False  # the channels do not share one clock
    uniform, step = False, None
    if grid is not False and grid.size > 2:
        dt = grid[1:] - grid[:-1]  # numpy's diff
        step = np.add.reduce(dt) / dt.size  # numpy's mean and ptp, without their wrappers
        uniform = dt.max() - dt.min() <= 1e-6 * step
    chans, excluded = [], {}
    shared = []  # _pre_trigger of the record's own instants, once worked out
    grid_basis = None  # the baseline basis at the grid's instants, shared by its channels

    def pre_trigger(t, spikes=None):
        if spikes or t is not t_all:
            return _pre_trigger(win, t, spikes)
        if not shared:
            shared.append(_pre_trigger(win, t))
        return shared[0]

    for name, t, f, keep, drop in raw:
        any_left = (drop & keep).any()  # any sample kept is left out
        if any_left:
            where = keep.nonzero()[0]  # (flatnonzero, without its wrapper)
            left = drop[where]
            excluded[name] = where[left].tolist()
        if not uniform:  # without a common grid, a left-out sample is simply dropped
            keep = keep & ~drop
            left = np.zeros(np.count_nonzero(keep), dtype=bool)
            any_left = False
        tc = t[keep]
        yc = f[keep] - win.baseline[name](tc) if name in win.baseline else f[keep]
        index = (~left).nonzero()[0] if any_left else None
        if index is not None:
            tc, yc = tc[index], yc[index]
        if tc.size < 5:
            raise InputError(
                f"{name} has {tc.size} samples in the contact window: too few to fit",
                path=record.attrs.get("source"),
            )
        if noise is not None and name in noise:
            sigma, n_noise = float(noise[name]), 0
        elif (
            quiet_after
            and (pre := _before_contact(win, t, f, part=pre_trigger(t, spikes.get(name))))
            is not None
        ):
            sigma, n_noise = mad_sigma(pre), pre.size
        else:
            sigma, note = _noise(win, name, tc, yc)
            n_noise = t_all.size - win.n_samples if note is None else tc.size
            if note:
                notes.append(note)
        floor = max(spec.quantum / math.sqrt(12.0), 1e-9 * float(np.abs(yc).max()), 1e-300)
        sigma = max(sigma, floor)
        if not baseline:
            basis = None
        elif index is None and grid is not False and tc.size == grid.size:  # the grid's
            if grid_basis is None:  # instants (as a stored record's channels share it)
                grid_basis = baseline_basis(tc)
            basis = grid_basis
        else:
            basis = baseline_basis(tc)
        model = WHITE
        if noise_model:
            # every channel's instants are the grid's where it is one (no margin cuts them)
            known = uniform if margin is None and grid is not False else None
            tr, fr = _repaired(record, win, name, t, f)
            model = _noise_model(record, win, name, tr, fr, known, pre_trigger(tr))
        chans.append(Channel(name, tc, yc, sigma, basis, int(max(n_noise, 0)), model, index))
    fine, sos, os_ = None, None, 1
    if uniform:
        # a uniform record gets the filter's fine grid even without a stated bandwidth:
        # a fit may then find the bandwidth (pipeline.fit.contact, systematics)
        os_ = int(oversample)
        fine, h = _fine_grid(grid, os_, float(step))
        sos = spec.sos(h) if spec.filtered else None
    elif spec.filtered or spec.dynamic:
        notes.append(
            "the record is not sampled uniformly on one clock: its sensor's filter is not modelled"
        )
    return RecordData(
        record=record,
        scene=scene,
        window=win,
        sensor=spec,
        channels=tuple(chans),
        fine=fine,
        oversample=os_,
        sos=sos,
        notes=tuple(notes),
        excluded=excluded,
    )


def baseline_basis(t) -> np.ndarray:
    """Orthonormal basis (n, 2) of {1, t − t̄} at the instants ``t`` [s] (two or more
    distinct): a channel's residual baseline, fitted with the contact (module notes). The
    two functions are orthogonal over the samples: each is normalised."""
    _, x, xx = _centred(t)
    basis = np.empty((t.size, 2))
    basis[:, 0] = 1.0 / math.sqrt(t.size)
    basis[:, 1] = x / math.sqrt(xx)
    return basis


def fine_grid(t, oversample: int) -> tuple:
    """The filter's fine grid of uniformly sampled instants ``t`` [s], ``oversample`` points
    a sample (sample k at ``fine[k * oversample]``), and its step [s]."""
    return _fine_grid(t, oversample, float(np.mean(np.diff(t))))


def _fine_grid(t, oversample, step):
    """:func:`fine_grid` of the instants ``t`` [s] whose mean step ``step`` [s] is known."""
    h = step / oversample
    fine = np.arange((t.size - 1) * oversample + 1, dtype=float)  # k·h + t₀, in place
    fine *= h
    fine += t[0]
    return fine, h


#: Residuals of a line below this fraction of the samples' magnitude are its rounding [-].
_ROUNDING = 1e-12


def _pre_trigger(win, t, spikes=None):
    """The samples of instants ``t`` [s] before the contact (less a tenth of its duration and
    the ``spikes``' indices) and their instants' part of a least-squares line: (mask,
    x = t − t̄, Σx²) — None where there are fewer than 20 (or no sensor record)."""
    if win.kind != "sensor":
        return None
    pre = t < win.t_start - 0.1 * win.duration
    if spikes:
        pre[spikes] = False
    if np.count_nonzero(pre) < 20:
        return None
    return (pre, *_centred(t[pre])[1:])


def _before_contact(win, t, f, spikes=None, part=False):
    """The channel's samples before the contact (less a tenth of its duration), less their
    own least-squares line (zeros where they lie on it to :data:`_ROUNDING`); None where
    there are fewer than 20. ``part``: :func:`_pre_trigger` of ``t`` and ``spikes`` where
    worked out already (channels on one clock share it)."""
    part = _pre_trigger(win, t, spikes) if part is False else part
    if part is None:
        return None
    pre, x, xx = part
    yy = f[pre]
    # the least-squares line in closed form: 1 and t − t̄ are orthogonal over the samples
    r = yy - (np.add.reduce(yy) / yy.size + x * (float(x.dot(yy)) / xx))
    if np.abs(r).max() <= _ROUNDING * np.abs(yy).max():
        # samples on their line to the rounding (one ADC level, a noise-free record) carry
        # no noise: the rounding's own correlation would pass for the noise's
        r[:] = 0.0
    return r


def zero_shift(t, at, width):
    """The zero shift's course [-] at instants ``t`` [s] (…, n): 0 before, 1 after, rising
    linearly over ``width`` [s] centred on ``at`` [s] (both (…, 1) against ``t``)."""
    w = np.maximum(np.asarray(width, dtype=float), 1e-300)
    return np.clip((t - (np.asarray(at) - 0.5 * w)) / w, 0.0, 1.0)


def weighted_residuals(data: RecordData, pred, derivative=False):
    """(y − model)/σ of every channel as the fit's rows (:meth:`Channel.rows`: whitened,
    less the fitted baseline), concatenated along the last axis; with ``derivative`` the
    model's derivatives ``pred`` give those of the residuals, −(∂model)/σ, alike."""
    parts = []
    for c, m in zip(data.channels, pred, strict=True):
        r = -m / c.sigma if derivative else (c.y - m) / c.sigma
        parts.append(c.rows(r))
    return np.concatenate(parts, axis=-1)


def _weighted_with_derivatives(data: RecordData, pred, der):
    """:func:`weighted_residuals` of the model ``pred`` (C, n_c per channel) and of its
    derivatives ``der`` (nderiv, na, n_c per channel) at once: each channel's residual and
    derivative rows stacked, whitened and projected in one pass (the rows are independent,
    so each is what :func:`weighted_residuals` gives it alone)."""
    ncol = pred[0].shape[0]
    shape = der[0].shape[:-1]
    n_rows = ncol + der[0][..., 0].size
    # the channels side by side: each writes its rows into its own columns
    out = None if len(pred) == 1 else np.empty((n_rows, sum(m.shape[-1] for m in pred)))
    start = 0
    for c, m, d in zip(data.channels, pred, der, strict=True):
        n = m.shape[-1]
        r = np.empty((n_rows, n))
        np.subtract(c.y, m, out=r[:ncol])
        np.negative(d.reshape(-1, n), out=r[ncol:])
        r /= c.sigma
        if out is None:
            out = c.rows(r)
        else:
            c.rows(r, out=out[:, start : start + n])
        start += n
    return out[:ncol], out[ncol:].reshape(shape + (out.shape[-1],))


@dataclass(frozen=True)
class Solution:
    """Dimensionless solutions of the unique problems among the columns (internal)."""

    pulse: object
    tang: object
    index: np.ndarray  # column → unique problem

    def head(self, n: int) -> Solution:
        """The solution of the first ``n`` columns."""
        return Solution(self.pulse, self.tang, self.index[:n])


class ForwardModel:
    """A contact model of records: normal law, tangential model, history rule (module notes).

    Parameters
    ----------
    normal : str — a key of :data:`pipeline.contact.NORMAL_LAWS`
    tangential : {"mindlin", "coulomb", "none"}
    history : {"total", "incremental"}
    n_steps : int — steps of the tabulated pulse per contact duration
    solver : {"piecewise", "rk4"}
        The tangential solver: :func:`pipeline.fit.tangential.tangential_response`
        (default), or the simulator's batch path :func:`pipeline.simulate.tangential_history`
        (fixed-step RK4, n_steps/2 steps; one Python iteration per step, kept to compare).
    """

    def __init__(
        self,
        normal="hunt_crossley",
        tangential="mindlin",
        history="total",
        n_steps=128,
        solver="piecewise",
    ):
        shape_of(normal)  # InputError naming the laws
        if tangential not in TANGENTIAL_MODELS:
            raise InputError(
                f"unknown tangential model {tangential!r}; choose one of {TANGENTIAL_MODELS}"
            )
        if history not in HISTORY_RULES:
            raise InputError(
                f"unknown Mindlin history rule {history!r}; choose one of {HISTORY_RULES}"
            )
        if solver not in ("piecewise", "rk4"):
            raise InputError(f"solver must be 'piecewise' or 'rk4', got {solver!r}")
        self.normal, self.tangential, self.history = normal, tangential, history
        self.n_steps = int(n_steps)
        self.solver = solver

    @property
    def channels(self) -> tuple:
        return ("Fn",) if self.tangential == "none" else ("Fn", "Ft")

    @property
    def name(self) -> str:
        return f"{self.normal}+{self.tangential}"

    # -------------------------------------------------------------- scales
    def scales(self, data: RecordData, P):
        """δ* [m], time scale δ*/v0 [s], force scale m*·v0²/δ* [N], v0 [m/s] per column (at
        each column's E*, speed, mass and radius; the time scale as the record's clock
        reads it, stretched by 1 + ``time_base``)."""
        return self._scales(data, P, data._static(P))

    @staticmethod
    def _scales(data, P, st):
        """:meth:`scales` with the columns' :class:`_Static` ``st``."""
        E, v = P[:, _I["E_eff"]], P[:, _I["speed"]]
        m = st.m_eff
        v0 = v * data.cos_a
        K = 4.0 / 3.0 * E * st.sqrt_R
        mvv = m * v0 * v0
        ds = (mvv / K) ** 0.4
        return ds, ds / v0 * st.stretch, mvv / ds, v0

    # -------------------------------------------------------------- solve
    def solve(self, datas, Ps) -> list:
        """The dimensionless normal and tangential solutions of every column of every record.

        Columns that differ only in the analytic parameters (E*, t0, gains, ...) share one
        solution (module notes).
        """
        rows = []
        for d, P in zip(datas, Ps, strict=True):
            if self.tangential == "none":  # the normal pulse depends on e alone
                rows.append(P[:, _I["e"], None])
                continue
            v0 = P[:, _I["speed"]] * d.cos_a
            row = np.empty((P.shape[0], 5))  # e, μ, kc, s0, λ
            row[:, 0] = P[:, _I["e"]]
            row[:, 1] = P[:, _I["mu"]]
            row[:, 2] = 6.0 * d.g_ratio * P[:, _I["kt_scale"]]
            row[:, 3] = np.abs(d.slip0(P[:, _I["speed"]])) / v0
            row[:, 4] = d._static(P).lam
            rows.append(row)
        allrows = np.concatenate(rows)
        if self.tangential == "coulomb":
            allrows[:, 2] = 0.0
        uniq, inv = _distinct_rows(allrows)
        e = uniq[:, 0]
        if not all(E_MIN <= x <= 1.0 for x in e.tolist()):  # NaN fails both
            raise InputError(f"restitution outside [{E_MIN}, 1]: {e[(e < E_MIN) | (e > 1)]}")
        check_elastic(self.normal, e)
        # e is checked (the table's own check and clip would change nothing)
        pulse = pulse_table(self.normal, self.n_steps).pulses(e)
        tang = None
        if self.tangential != "none" and self.solver == "rk4":
            tang = _rk4_response(pulse, uniq, self.tangential, self.history)
        elif self.tangential != "none":
            tang = tangential_response(
                pulse,
                uniq[:, 3],
                uniq[:, 4],
                uniq[:, 1],
                uniq[:, 2],
                tangential=self.tangential,
                history=self.history,
            )
        out, start = [], 0
        for P in Ps:
            out.append(Solution(pulse, tang, inv[start : start + P.shape[0]]))
            start += P.shape[0]
        return out

    # -------------------------------------------------------------- predict
    def _true_forces(self, sol: Solution, tau, need_t, nderiv=0, table=None):
        """Fn, Ft (dimensionless) at τ (C, n) by cubic Hermite on the nodes, 0 out of contact;
        with ``nderiv`` > 0 also their rates d/dτ at the first ``nderiv`` columns.

        Each step's cubic is worked out once on the nodes (:func:`_cubic_steps`), so an
        instant costs one gather of its step's coefficients and Horner's rule; the instants
        out of contact take the zero step after the last. ``table``: :func:`_force_table` of
        ``sol`` and ``need_t``, kept by a caller that asks at several sets of instants."""
        pul = sol.pulse
        k = sol.index
        n = pul.n_steps
        step = pul.tau_c[:, None] / n  # (U, 1) of the unique problems
        if table is None:
            table = _force_table(sol, need_t, step)
        h = step[k]
        s = tau / h
        j = s.astype(int)
        np.minimum(np.maximum(j, 0, out=j), n - 1, out=j)  # np.clip's checks cost more
        inside = (s >= 0) & (s <= n)  # else out of contact (or no instant): the zero step
        th = np.where(inside, s - j, 0.0)
        j = np.where(inside, j, n)
        c = table.take(k[:, None] * (n + 1) + j, axis=1)  # (4·S, C, n)
        out, rates = [], []
        d = slice(0, nderiv)
        for i in range(0, c.shape[0], 4):
            c0, c1, c2, c3 = c[i : i + 4]
            out.append(c0 + th * (c1 + th * (c2 + th * c3)))
            if nderiv:
                t = th[d]
                rates.append((c1[d] + t * (2.0 * c2[d] + 3.0 * t * c3[d])) / h[d])
        out[0] = np.maximum(out[0], 0.0)
        if len(out) == 1:
            out.append(None)
            rates.append(None)
        return (out[0], out[1], rates[0], rates[1]) if nderiv else (out[0], out[1])

    def _forces(self, data, P, sol, t, names, nderiv, analytic=ANALYTIC, scales=None, static=None):
        """Measured-axis forces at instants ``t`` (before the filter), one (C, n) array per
        name, and for the first ``nderiv`` columns their derivatives with respect to the
        ``analytic`` parameters (of :data:`ANALYTIC`), one (nderiv, len(analytic), n) array
        per name; ``scales``, ``static``: :meth:`scales` and the :class:`_Static` of ``P``
        where already worked out."""
        static = data._static(P) if static is None else static
        ds, T, Fs, v0 = self._scales(data, P, static) if scales is None else scales
        t0 = P[:, _I["t0"]][:, None]
        tau = (t[None, :] - t0) / T[:, None]
        # Ft is asked for, or reaches Fn: through the cross-talk matrix or the Ft → Fn leak
        # (where a column moves it, or its derivative is asked for: at a leak of 0 too)
        need_t = "Ft" in names or (
            self.tangential != "none"
            and (
                data.sensor.crosstalk is not None
                or static.moved[3]
                or (nderiv > 0 and "leak_tn" in analytic)
            )
        )
        res = self._true_forces(sol, tau, need_t, nderiv)
        fn, ft = res[0] * Fs[:, None], None if res[1] is None else res[1] * Fs[:, None]
        C = data.sensor.crosstalk
        # which of gain_n, gain_t, leak, leak_tn differ anywhere from the axes' own values
        moved = static.moved
        # the axes as the forces are (no cross-talk, gains 1, leaks 0): nothing to mix
        same = C is None and (ft is not None or "Ft" not in names) and not any(moved)
        unit = (not moved[0], not moved[1])  # gain_n, gain_t 1 in every column
        if same:
            mixed = [fn if n == "Fn" else ft for n in names]
        else:
            mixed = self._mix(C, P, fn, ft, names, unit)
        if not nderiv:
            return mixed, None
        b = slice(0, nderiv)
        Pb = P[b]
        Tb, Fb, tb = T[b, None], Fs[b, None], tau[b]
        want = [a for a in analytic if a not in _MIXING]
        parts = {}
        for key, f, r in (("n", fn, res[2]), ("t", ft, res[3])):
            if f is None:
                parts[key] = None
                continue
            rate = Fb * r  # dF/dτ [N]
            stretch = rate * tb  # the response to stretching the time scale
            # F = Fs·f((t − t0)/T) with Fs ∝ m*^{3/5} v0^{6/5} K^{2/5} and T ∝ m*^{2/5}
            # v0^{-1/5} K^{-2/5} (module notes), K ∝ E*·√R*; only the ones asked for
            dlnK = 0.4 * (f[b] + stretch) if "E_eff" in want or "radius" in want else None
            part = {}
            for a in want:
                if a == "E_eff":
                    part[a] = dlnK / Pb[:, _I["E_eff"], None]
                elif a == "t0":
                    part[a] = -rate / Tb
                elif a == "mass":
                    mass = Pb[:, _I["mass"], None]
                    part[a] = (0.6 * f[b] - 0.4 * stretch) * (data.m_eff_of(mass) / mass) / mass
                elif a == "radius":  # ∂ln R*/∂ln R = R*/R
                    radius = Pb[:, _I["radius"], None]
                    part[a] = dlnK * 0.5 * (data.R_eff_of(radius) / radius) / radius
                else:  # time_base
                    part[a] = -stretch / (1.0 + Pb[:, _I["time_base"], None])
            parts[key] = part
        out = []
        for name in names:
            der = np.empty((nderiv, len(analytic), tau.shape[1]))
            for i, a in enumerate(analytic):
                if a in _MIXING:
                    der[:, i] = self._dmix(C, Pb, fn[b], ft, name, a)
                    continue
                dn, dt = parts["n"][a], None if parts["t"] is None else parts["t"][a]
                if same:
                    der[:, i] = dn if name == "Fn" else dt
                else:
                    self._mix(C, Pb, dn, dt, [name], unit, out=der[:, i])
            out.append(der)
        return mixed, out

    def predict(self, data: RecordData, P, sol: Solution, nderiv: int = 0, analytic=ANALYTIC):
        """The model at every fitted sample of ``data``: one (C, n_c) array per channel [N];
        with ``nderiv`` > 0 also the derivatives of the first ``nderiv`` columns with
        respect to the ``analytic`` parameters (default every one of :data:`ANALYTIC`), one
        (nderiv, len(analytic), n_c) array per channel."""
        names = [c.name for c in data.channels]
        chain = P[:, _CHAIN]  # (C, 4): bandwidth, fn, ζ, τ
        static = data._static(P)
        # whether any column states a bandwidth, a mode or a discharge (ζ aside)
        finite = static.finite
        shift = P[:, _SHIFT]
        shifted = static.shifted
        if shifted:
            at, width = P[:, _I["shift_at"], None], P[:, _I["shift_width"], None]
        if data.fine is None or not (finite[0] or finite[1] or finite[3]):
            out, der = [], []
            for ch in data.channels:
                m, d = self._forces(data, P, sol, ch.t, [ch.name], nderiv, analytic, static=static)
                if shifted:
                    k = 0 if ch.name == "Fn" else 1
                    m[0] = m[0] + shift[:, k, None] * zero_shift(ch.t[None, :], at, width)
                out.append(m[0])
                der.append(None if d is None else d[0])
            return (out, der) if nderiv else out
        # the forces vanish outside the contact: evaluate from the earliest onset to the
        # latest end of any column, and filter on until the filter's ringing has decayed
        # below 1e-16 (after that the record is the model's exact zero)
        ds, T, Fs, v0 = self._scales(data, P, static)
        t0 = P[:, _I["t0"]]
        tc = sol.pulse.tau_c[sol.index] * T
        fine = data.fine
        first = t0.min() if not shifted else min(t0.min(), float(np.min(at - 0.5 * width)))
        lo, hi = data.fine_span(first, (t0 + tc).max())
        step = fine[1] - fine[0] if fine.size > 1 else 1.0
        plain = not (finite[1] or finite[3])  # the low-pass alone: rows grouped by bandwidth
        col_bw = static.bandwidths
        end = fine.size if shifted else min(fine.size, hi + int(math.ceil(static.ring / step)) + 1)
        m, d = self._forces(
            data, P, sol, fine[lo:hi], names, nderiv, analytic, (ds, T, Fs, v0), static
        )
        ncol, nch, na = P.shape[0], len(names), len(analytic)
        # rows: every channel's columns, then every channel's derivative rows; each row
        # keeps the bandwidth of its column
        rows = list(m) + ([x.reshape(-1, x.shape[-1]) for x in d] if nderiv else [])
        n_rows = nch * (ncol + (nderiv * na if nderiv else 0))
        full = np.zeros((n_rows, end - lo))
        np.concatenate(rows, axis=0, out=full[:, : hi - lo])
        if shifted:  # a charge the crystal keeps: it passes the chain as the force does
            ramp = zero_shift(fine[None, lo:end], at, width)
            for i, name in enumerate(names):
                full[i * ncol : (i + 1) * ncol] += shift[:, 0 if name == "Fn" else 1, None] * ramp
        if plain:
            if static.one:  # every row at one bandwidth
                filt = _sampled(data, step, col_bw[0], full, full.shape[1])
            else:
                row_bw = col_bw * nch + ([b for b in col_bw[:nderiv] for _ in range(na)] * nch)
                groups = {}  # the rows of each bandwidth
                for i, b in enumerate(row_bw):
                    groups.setdefault(b, []).append(i)
                filt = np.empty((full.shape[0], full[:, :: data.oversample].shape[1]))
                for b, rows_b in groups.items():
                    filt[rows_b] = _sampled(data, step, b, full[rows_b], full.shape[1])
        else:  # each row through its column's chain (bandwidth, mode, discharge)
            row_chain = np.concatenate(
                [chain] * nch + ([np.repeat(chain[:nderiv], na, axis=0)] * nch if nderiv else [])
            )
            filt = np.empty((n_rows, full[:, :: data.oversample].shape[1]))
            uniq, which = _distinct_rows(row_chain)
            for j, value in enumerate(uniq):
                sel = which == j
                f = data.sensor.chain(step, *value)
                x = full[sel] if f is None else f(full[sel], axis=-1)
                filt[sel] = x[:, :: data.oversample]
        out = np.zeros((filt.shape[0], data.n_grid))
        k0 = lo // data.oversample
        out[:, k0 : k0 + filt.shape[1]] = filt
        pred = [data.at_channel(out[i * ncol : (i + 1) * ncol], i) for i in range(nch)]
        if not nderiv:
            return pred
        base = nch * ncol
        der = [
            data.at_channel(
                out[base + i * na * nderiv : base + (i + 1) * na * nderiv].reshape(nderiv, na, -1),
                i,
            )
            for i in range(nch)
        ]
        return pred, der

    @staticmethod
    def _mix(C, P, fn, ft, names, unit=(False, False), out=None):
        """The sensor's axes: gains, the known cross-talk matrix C (None: none) and the
        fitted leaks Fn → Ft and Ft → Fn, ``Ft_meas = g_t·(C10·Fn + C11·Ft + leak·Fn)``,
        ``Fn_meas = g_n·(C00·Fn + C01·Ft + leak_tn·Ft)``. ``unit``: whether g_n, g_t are 1
        in every column (a factor of 1, like a C00 or C11 of 1, is left out: x·1 is x to
        the bit); ``out``: where to write the one name's forces."""
        Q = P[: fn.shape[0]]
        res = []
        for n in names:
            if n == "Fn":
                base = fn if C is None or C[0, 0] == 1.0 else C[0, 0] * fn
                if ft is not None:
                    base = base + (Q[:, _I["leak_tn"], None] + (0.0 if C is None else C[0, 1])) * ft
                gain = None if unit[0] else Q[:, _I["gain_n"], None]
            else:
                base = Q[:, _I["leak"], None] * fn
                if C is not None:
                    base = base + C[1, 0] * fn
                if ft is not None:
                    base = base + (ft if C is None or C[1, 1] == 1.0 else C[1, 1] * ft)
                gain = None if unit[1] else Q[:, _I["gain_t"], None]
            if out is None:
                res.append(base if gain is None else gain * base)
            elif gain is None:
                out[...] = base
            else:
                np.multiply(gain, base, out=out)
        return res

    @staticmethod
    def _dmix(C, P, fn, ft, name, which):
        """∂(measured ``name``)/∂(``which`` of gain_n, gain_t, leak, leak_tn) for the
        columns of P."""
        gt = P[:, _I["gain_t"]][:, None]
        ft0 = np.zeros_like(fn) if ft is None else ft[: fn.shape[0]]
        if name == "Fn":
            if which == "leak_tn":
                return P[:, _I["gain_n"]][:, None] * ft0
            if which != "gain_n":
                return np.zeros_like(fn)
            base = fn if C is None else C[0, 0] * fn + C[0, 1] * ft0
            return base + P[:, _I["leak_tn"]][:, None] * ft0
        if which in ("gain_n", "leak_tn"):
            return np.zeros_like(fn)
        if which == "leak":
            return gt * fn
        leak = P[:, _I["leak"]][:, None]
        return (ft0 if C is None else C[1, 0] * fn + C[1, 1] * ft0) + leak * fn

    def residuals(self, datas, Ps, nderiv=None, analytic=None):
        """Weighted residuals (y − model)/σ, (C, n_data) per record, and the solutions; with
        ``nderiv`` (one count per record) also the residuals' derivatives with respect to
        the ``analytic`` parameters of each record (default every one of
        :data:`ANALYTIC`) at its leading columns, (nderiv, len(analytic), n_data) per
        record."""
        sols = self.solve(datas, Ps)
        out, ders = [], []
        for i, (d, P, s) in enumerate(zip(datas, Ps, sols, strict=True)):
            nd = 0 if nderiv is None else nderiv[i]
            pred = self.predict(d, P, s, nd, ANALYTIC if analytic is None else analytic[i])
            if nd:
                r, dr = _weighted_with_derivatives(d, *pred)
                out.append(r)
                ders.append(dr)
            else:
                out.append(weighted_residuals(d, pred))
        return (out, sols, ders) if nderiv is not None else (out, sols)

    # -------------------------------------------------------------- physics
    def physics(self, data: RecordData, P, sol: Solution) -> dict:
        """What one column's parameters imply: contact duration, peaks, outcomes, regime."""
        P1 = P[:1].copy()
        P1[:, _I["time_base"]] = 0.0  # the contact's own clock
        ds, T, Fs, v0 = (float(a[0]) for a in self.scales(data, P1))
        k = int(sol.index[0])
        pul = sol.pulse
        sc = data.scene
        m = float(P[0, _I["mass"]])
        m_eff = float(data.m_eff_of(m))
        R = float(P[0, _I["radius"]])
        vt0 = float(data.slip0(P[0, _I["speed"]]) + sc.spin * sc.radius)
        out = {
            "t_c": float(pul.tau_c[k] * T),
            "F_max": float(pul.f[k].max() * Fs),
            "delta_max": float(pul.x[k].max() * ds),
            "e_n": float(-pul.u[k, -1]),
            "Pn_final": float(pul.pn[k, -1] * m_eff * v0),
        }
        if sol.tang is not None:
            tg = sol.tang
            Pt = float(tg.p[k, -1] * m_eff * v0)
            sign = -1.0 if data.slip0(P[0, _I["speed"]]) < 0 else 1.0
            out.update(
                {
                    "Pt_final": Pt,
                    "e_t": (sign * vt0 - Pt / m_eff) / (sign * vt0) if vt0 else math.nan,
                    "omega": sign * float(sc.spin) + Pt / (float(sc.kappa) * m * R),
                    "regime": "sticking" if bool(tg.slip_stops[k]) else "sliding",
                    "slide_share": float(tg.slide_share[k]),
                    "Ft_max": float(tg.ft[k].max() * Fs),
                    "Ft_min": float(tg.ft[k].min() * Fs),
                }
            )
        return out

    def curves(self, data: RecordData, P, sol: Solution, t) -> dict:
        """The true (unfiltered) model forces of column 0 at instants ``t`` [s]."""
        ds, T, Fs, v0 = self.scales(data, P[:1])
        tau = (np.asarray(t, dtype=float)[None, :] - P[0, _I["t0"]]) / T[:, None]
        fn, ft = self._true_forces(Solution(sol.pulse, sol.tang, sol.index[:1]), tau, True)
        return {
            "Fn": fn[0] * Fs[0],
            "Ft": None if ft is None else ft[0] * Fs[0],
        }


def _sampled(data, step, bandwidth, x, length):
    """``x`` (rows, m) on the fine grid of step ``step`` [s], zero after its m instants,
    through the low-pass of ``data``'s sensor at ``bandwidth`` [Hz] (none where infinite),
    at every ``data.oversample``-th of the first ``length`` instants (rows, ⌈length/os⌉).
    One second-order section goes through :func:`scipy.signal.lfilter` as its transfer
    function (the same recursion, a third of :func:`~scipy.signal.sosfilt`'s overhead),
    more sections through ``sosfilt``."""
    if x.shape[-1] < length:
        x = np.concatenate([x, np.zeros((x.shape[0], length - x.shape[-1]))], axis=-1)
    if math.isfinite(bandwidth):
        f = data._lowpass(step, bandwidth)
        x = lfilter(*f, x, axis=-1) if isinstance(f, tuple) else sosfilt(f, x, axis=-1)
    return x[:, :: data.oversample]


def _force_table(sol: Solution, need_t, step):
    """The cubic steps (:func:`_cubic_steps`) of ``sol``'s Fn, and of its Ft where
    ``need_t``, side by side, (4·S, U·(n + 1)): one gather serves them all. ``step``: the
    steps τ_c/n_steps, (U, 1)."""
    pul = sol.pulse
    both = need_t and sol.tang is not None
    table = np.empty((8 if both else 4,) + pul.f.shape)
    _cubic_steps(pul.f, pul.df, step, None, table[:4])
    if both:
        _cubic_steps(sol.tang.ft, sol.tang.dft, step, sol.tang.kink, table[4:])
    return table.reshape(table.shape[0], -1)


def _cubic_steps(y, dy, step, kink, out):
    """The cubic Hermite interpolant of node values ``y`` and rates ``dy`` (U, n + 1) on
    steps of ``step`` (U, 1), as each step's power series in θ = (τ − τ_j)/step ∈ [0, 1]:
    ``c0 + θ·(c1 + θ·(c2 + θ·c3))``, shape (4, U, n + 1) — the steps, then a zero one (the
    instants out of contact). Steps flagged in ``kink`` (U, n + 1: a stick/slide switch
    inside; None: none) are linear between their nodes. ``out``: the array to fill."""
    y0, y1 = y[:, :-1], y[:, 1:]
    sd = step * dy
    a, b = sd[:, :-1], sd[:, 1:]
    rise = y1 - y0
    c = out
    c[:, :, -1] = 0.0
    c[0, :, :-1] = y0
    c[1, :, :-1] = a
    c[2, :, :-1] = 3.0 * rise - 2.0 * a - b
    c[3, :, :-1] = a + b - 2.0 * rise
    if kink is not None and kink.any():
        lin = kink[:, :-1]
        c[1, :, :-1][lin] = rise[lin]
        c[2, :, :-1][lin] = 0.0
        c[3, :, :-1][lin] = 0.0
    return c


def _distinct_rows(a):
    """The distinct rows of ``a`` (in order of first appearance) and, for each row, the index
    of its copy among them: ``a == uniq[inv]``. A dictionary keyed by the rows' values, cheaper
    than :func:`numpy.unique` (a sort of the rows) for the few columns of a fit's call."""
    rows = list(map(tuple, a.tolist()))
    first = {}  # row → where it first appears
    for i, row in enumerate(rows):
        first.setdefault(row, i)
    if len(first) == len(rows):
        return a, np.arange(len(rows))
    number = {row: k for k, row in enumerate(first)}
    inv = np.array([number[row] for row in rows])
    return a[list(first.values())], inv


def _rk4_response(pulse, uniq, tangential, history):
    """The tangential response by :func:`pipeline.simulate.tangential_history` (RK4 over
    n_steps/2 steps of each pulse, the nodes as its half steps), on the pulse's nodes."""
    th = tangential_history(
        np.sqrt(pulse.x).T,
        pulse.f.T,
        2.0 * pulse.tau_c / pulse.n_steps,  # one step per two nodes, per pulse
        uniq[:, 3],
        uniq[:, 4],
        uniq[:, 1],
        uniq[:, 2],
        tangential=tangential,
        history=history,
    )
    J = pulse.n_steps + 1
    p, ft = np.empty((pulse.e.size, J)), np.empty((pulse.e.size, J))
    p[:, ::2], ft[:, ::2] = th.p.T, th.ft.T
    p[:, 1::2] = 0.5 * (p[:, :-1:2] + p[:, 2::2])
    ft[:, 1::2] = 0.5 * (ft[:, :-1:2] + ft[:, 2::2])
    dft = np.gradient(ft, axis=1) / pulse.h
    stops = np.any(uniq[:, 3, None] - uniq[:, 4, None] * p <= 0, axis=1)
    n = pulse.e.size
    return TangentialResponse(p, ft, dft, stops, np.full(n, np.nan), np.zeros(n, int))
