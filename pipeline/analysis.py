"""One record to the seed paper's verdict: :func:`analyse` bundles every stage.

record → :mod:`~pipeline.window` (contact, baseline, noise) → :mod:`~pipeline.smooth`
(quartic fits as in the seed) → :mod:`~pipeline.percussion`
(Pn(t), Pt(t) from the fit and from the samples; maximum compression; Poisson, Newton and
Stronge restitution) → :mod:`~pipeline.rigid` (Routh's broken line for the scene) →
:mod:`~pipeline.score` (how far the measured Pt(Pn) is from it, with bootstrap
uncertainties).

Which percussions are scored (``source``): ``"simpson"`` integrates the samples themselves
(no model error; the default whenever each channel has at least ``MIN_SAMPLES`` = 3
samples in the window), ``"fit"`` integrates the fitted polynomial (the seed's method).
Both are always computed, and the seed's quartic-based score is reported beside the
primary one, so the cost of the quartic is visible. The samples win even on sparse
records: at 12 samples per contact the quartic's percussions stay within tolerance on
22 % of simulated sensor records, the samples' integrals on 81–86 %
(``benchmarks/bench_percussion.py``); sparse records are flagged by
:func:`pipeline.percussion.resolution` whatever is scored.
"""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass

import numpy as np
import xarray as xr

from . import percussion as _perc
from . import rigid as _rigid
from . import score as _score
from . import smooth as _smooth
from . import window as _window
from ._json import json_ready
from .errors import InputError
from .fit import select_model
from .fit.sensor import sensor_spec
from .percussion import estimate_mu
from .plausibility import Plausibility, check_outcomes, check_plausible
from .precision import pdg, plain
from .record import channel
from .scene import Scene
from .smooth import noise_level

__all__ = ["Analysis", "Outcomes", "analyse", "estimate_mu", "noise_level", "MIN_SAMPLES"]

#: Fewest samples per channel in the window for scoring the samples themselves (Simpson's
#: rule needs three); sparser records are scored from the polynomial fit.
MIN_SAMPLES = 3


#: Units of the measured outcomes (:class:`Outcomes`).
OUTCOME_UNITS = {
    "e_n": "1",
    "e_t": "1",
    "omega": "rad/s",
    "rebound_deg": "deg",
    "Pn_f": "N s",
    "Pt_f": "N s",
}


@dataclass(frozen=True)
class Outcomes:
    r"""What the record says the impact did: restitution, spin and rebound, measured.

    From the final percussions of the scored source and the scene's mass, radius and
    approach (``docs/theory.md``, sign conventions):

    .. math::

        e_n = \frac{P_{nf} - P_{nc}}{P_{nc}}, \quad
        e_t = 1 - \frac{\sigma P_{tf}}{m\,v_{t0}}, \quad
        \omega = \sigma\omega_0 + \frac{P_{tf}}{\kappa m R}, \quad
        \theta_r = \arctan\frac{v_{t0} - \sigma P_{tf}/m}{P_{nf}/m^* - v_{n0}}

    (Poisson's restitution, the tangential restitution of the centre, the spin after impact
    positive in the sense Pt > 0 produces, the rebound angle from the normal on the scene's
    axis). Pt opposes the *initial* slip s0 = v_t0 − ω0·R, so where a spin or a moving
    surface makes s0 < 0 it acts along −t: σ = sign(s0) (+1 for s0 = 0), and ω is on the
    slip's axis as :func:`pipeline.rigid.sphere_on_plane` and
    :func:`pipeline.simulate.impact` report it. ``std`` holds the standard deviation over
    the analysis' bootstrap replicates (NaN without).

    Attributes
    ----------
    values, std : dict
        ``{"e_n", "e_t", "omega", "rebound_deg", "Pn_f", "Pt_f"}`` → float, units in
        :data:`OUTCOME_UNITS` ([-], [-], [rad/s], [deg], [N·s], [N·s]).
    """

    values: dict
    std: dict

    def __getitem__(self, name: str) -> float:
        return self.values[name]

    def summary(self) -> dict:
        """JSON-ready ``{name: {"value", "std", "units"}}``."""
        return json_ready(
            {
                k: {"value": v, "std": self.std[k], "units": OUTCOME_UNITS[k]}
                for k, v in self.values.items()
            }
        )


def slip_sign(scene: Scene) -> float:
    """σ = sign of the initial slip s0 = v_t0 − ω0·R (+1 for none) [-]: a record's Pt, which
    opposes the initial slip, acts on the ball along σ·(−t) (docs/theory.md)."""
    return -1.0 if float(scene.slip0) < 0 else 1.0


def measured_outcomes(scene: Scene, Pn_f, Pt_f, Pn_c) -> dict:
    """e_n, e_t, ω, rebound angle (:class:`Outcomes`) from final percussions [N·s].

    ``Pn_f``, ``Pt_f``, ``Pn_c`` may be arrays (bootstrap replicates); e_t is NaN where the
    scene has no tangential approach (v_t0 = 0).
    """
    Pn_f, Pt_f, Pn_c = (np.asarray(x, dtype=float) for x in (Pn_f, Pt_f, Pn_c))
    m, m_eff = float(scene.m), float(scene.m_eff)
    v_t0, v_n0 = float(scene.v_t0), float(scene.v_n0)
    sigma = slip_sign(scene)
    v_t = v_t0 - sigma * Pt_f / m  # on the scene's axis
    v_n = Pn_f / m_eff - v_n0
    with np.errstate(divide="ignore", invalid="ignore"):
        e_t = v_t / v_t0 if v_t0 != 0 else np.full_like(Pt_f, np.nan)
    spin = sigma * float(scene.spin)  # on the slip's axis
    return {
        "e_n": (Pn_f - Pn_c) / Pn_c,
        "e_t": e_t,
        "omega": spin + Pt_f / (float(scene.kappa) * m * float(scene.radius)),
        "rebound_deg": np.degrees(np.arctan2(v_t, v_n)),
        "Pn_f": Pn_f,
        "Pt_f": Pt_f,
    }


@dataclass(frozen=True, eq=False)
class Analysis:
    """Everything :func:`analyse` found for one record.

    Attributes
    ----------
    scene : Scene
        The scene as given.
    rigid_scene : Scene
        The scene the rigid prediction used (μ and e possibly taken from the record).
    window : pipeline.window.ContactWindow
    fits : pipeline.smooth.WindowFits
        Polynomial fits (degree ``options["degree"]``, 4 by default: the seed's quartics).
    percussions : pipeline.percussion.Percussions
    split : pipeline.percussion.CompressionSplit
        Maximum compression and the restitution coefficients from ``source``.
    rigid : pipeline.rigid.SphereOnPlane
    score : pipeline.score.DeviationScore
        Deviation of the ``source`` percussions from the broken line.
    score_fit : pipeline.score.DeviationScore
        The same for the polynomial fit's percussions (the seed's method).
    mu_record : float
        Friction coefficient estimated from the record (:func:`estimate_mu`) [-].
    source : str
    options : dict
    sources : dict
        Where the rigid model's μ and e came from: ``"scene"``, ``"fit"`` (fitted to the
        record by :func:`pipeline.select_model`; value, uncertainty and model in
        :attr:`fitted`), ``"record"`` (estimated from the record without a contact model: μ
        by :func:`estimate_mu`, e by Poisson's coefficient) or ``"given"`` (a number passed
        to :func:`analyse`).
    model_selection : pipeline.fit.ModelSelection or None
        The contact models fitted to the record when μ or e came from a fit.
    resolution : pipeline.percussion.Resolution
        What the record's sampling, noise, ADC, bandwidth and baseline let the percussions
        resolve; ``resolution.flags`` names every failure region it is in (each also a
        :class:`~pipeline.percussion.ResolutionWarning`; docs/stability.md).
    outcomes : Outcomes
        Restitution, spin and rebound angle measured from the ``source`` percussions, with
        bootstrap standard deviations.
    plausibility : pipeline.plausibility.Plausibility
        The record's contact duration, peak force and impulse against the scene's Hertz
        and momentum estimates (:func:`pipeline.plausibility.check_plausible`), checked
        before any physics, then the measured outcomes against the bounds of a passive
        impact (:func:`pipeline.plausibility.check_outcomes`).
    """

    scene: Scene
    rigid_scene: Scene
    window: object
    fits: object
    percussions: object
    split: object
    rigid: object
    score: object
    score_fit: object
    mu_record: float
    source: str
    options: dict
    sources: dict = dataclasses.field(default_factory=dict)
    resolution: object = None
    model_selection: object = None
    outcomes: Outcomes | None = None
    plausibility: object = None

    @property
    def fitted(self) -> dict:
        """For μ and e taken from the fit: ``{name: {"value", "stderr", "ci95",
        "identifiable", "model"}}`` (the chosen model's; a μ the data bound only from below
        has its lower bound as value and ci95 (bound, inf))."""
        sel = self.model_selection
        if sel is None:
            return {}
        f = sel.fit
        ci = f.ci(0.95)
        out = {}
        for name, src in self.sources.items():
            if src != "fit":
                continue
            model = f"{sel.chosen}" + (f"+{sel.chosen_normal}" if sel.chosen_normal else "")
            if name in f.vary:
                out[name] = {
                    "value": f.values[name],
                    "stderr": f.stderr[name],
                    "ci95": list(ci[name]),
                    "identifiable": bool(f.identifiable[name]),
                    "model": model,
                }
            else:  # the elastic law: e = 1 by the model, not by the data
                out[name] = {
                    "value": f.values[name],
                    "stderr": 0.0,
                    "ci95": [f.values[name]] * 2,
                    "identifiable": True,
                    "model": model,
                }
        return out

    @property
    def record(self) -> xr.Dataset:
        """The windowed, baseline-corrected record."""
        return self.window.record

    def summary(self) -> dict:
        """JSON-ready dict of every number (units in key names).

        Strict JSON (``json.dumps(..., allow_nan=False)`` works): NaN becomes None and ±inf
        the strings ``"inf"``/``"-inf"`` (an infinite scene field such as a rigid target's
        ``target_E`` reads back through :meth:`pipeline.Scene.from_dict` after ``float``).
        """
        rs = self.rigid
        return json_ready(
            {
                "source": self.record.attrs.get("source", ""),
                "sha256": self.record.attrs.get("sha256", ""),
                "scene": self.scene.to_dict(),
                "rigid_scene": self.rigid_scene.to_dict(),
                "rigid_scene_sources": self.sources,
                "fitted": self.fitted,
                "options": {k: v for k, v in self.options.items() if _jsonable(v)},
                "window": self.window.summary(),
                "repaired": {"spikes": self.window.spike_indices()},
                "fits": {
                    k: getattr(self.fits, k).summary()
                    for k in ("Fn", "Ft")
                    if getattr(self.fits, k) is not None
                },
                "percussions": self.percussions.summary(),
                "split": self.split.summary(),
                "mu_record": self.mu_record,
                "rigid": {
                    "regime": str(rs.regime),
                    "beta_rad": float(rs.beta),
                    "Pn_c_Ns": float(rs.Pn_c),
                    "Pn_f_Ns": float(rs.Pn_f),
                    "Pt_f_Ns": float(rs.Pt_f),
                    "Pt_S_Ns": float(rs.Pt_S),
                    "e_t": float(rs.e_t),
                    "omega_rad_per_s": float(rs.omega),
                },
                "score": self.score.summary(),
                "score_fit": self.score_fit.summary(),
                "resolution": None if self.resolution is None else self.resolution.summary(),
                "outcomes": None if self.outcomes is None else self.outcomes.summary(),
                "plausibility": None if self.plausibility is None else self.plausibility.summary(),
            }
        )

    def describe(self) -> str:
        """A readable summary for a person: the record, the scene and where its μ and e
        came from, the measured outcomes with their bootstrap std beside the rigid
        prediction, the regime and the deviation score (what ``pipeline analyse`` prints).
        A value with its std is rounded to it (the Particle Data Group's rule,
        :mod:`pipeline.precision`); every digit is in :meth:`summary`.
        """
        sc, rs, o = self.scene, self.rigid, self.outcomes
        src = self.record.attrs.get("source", "record")
        lines = [
            f"{src}: {self.record.attrs.get('format', '?')}, "
            f"{self.window.n_samples} samples in the contact window "
            f"({(self.window.t_end - self.window.t_start) * 1e6:.1f} µs)",
            f"scene: ball R = {sc.radius * 1e3:.3g} mm, m = {float(sc.m) * 1e3:.4g} g; "
            f"v = {sc.speed:g} m/s at {sc.angle_deg:g}° (v_n0 = {float(sc.v_n0):.4g} m/s, "
            f"v_t0 = {float(sc.v_t0):.4g} m/s)",
            f"rigid model: μ = {self.rigid_scene.mu:.4g} (from the {self.sources.get('mu')}), "
            f"e = {self.rigid_scene.e:.4g} (from the {self.sources.get('e')}); "
            f"μ estimated from the record = {self.mu_record:.4g}",
            f"regime (Routh): {rs.regime}",
        ]
        if self.window.spikes:
            spikes = "; ".join(
                f"{ch} samples {idx}" for ch, idx in self.window.spike_indices().items()
            )
            lines.append(
                f"repaired: {len(self.window.spikes)} isolated sample(s) no force history can "
                f"make ({spikes}), replaced by their neighbours' curve before the percussions"
            )
        lines += ["", f"{'':14s}{'measured':>22s}{'rigid':>12s}"]
        rigid = {
            "e_n": float(self.rigid_scene.e),
            "e_t": float(rs.e_t),
            "omega": float(rs.omega),
            "rebound_deg": float(np.degrees(np.arctan2(float(rs.v_t_scene), float(rs.v_n)))),
        }
        names = {"e_n": "e_n [-]", "e_t": "e_t [-]", "omega": "ω [rad/s]"}
        names["rebound_deg"] = "rebound [deg]"
        for k, label in names.items():
            pm = pdg(o.values[k], o.std[k])
            lines.append(f"{label:14s}{pm:>22s}{plain(rigid[k]):>12s}")
        lines.append("")
        n = self.score.n_boot
        spread = f"± the std of {n} bootstrap replicates" if n else "no bootstrap"
        lines.append(f"deviation from the rigid line ({self.score.source} percussions, {spread}):")
        for phase in ("total", "compression", "restitution"):
            parts = []
            for m in ("area", "max_distance"):
                v, s = self.score.values[phase][m], self.score.std[phase][m]
                parts.append(f"{m} {pdg(v, s)}")
            lines.append(f"  {phase:12s}" + ", ".join(parts))
        return "\n".join(lines)

    def to_dataset(self) -> xr.Dataset:
        """Percussions, fitted forces and the rigid line on the percussion grid (netCDF-ready).

        The full :meth:`summary` is stored as JSON in ``attrs["summary_json"]``.
        """
        perc = self.percussions
        ds = perc.to_dataset()
        t = ds["time"].values
        for name in ("Fn", "Ft"):
            f = getattr(self.fits, name)
            if f is not None:
                ds[f"{name}_fit"] = (
                    "time",
                    np.asarray(f(t), dtype=float),
                    {"units": "N", "long_name": f"{name} polynomial fit"},
                )
        Pn = perc.Pn(self.source)
        ds["Pt_rigid"] = (
            "time",
            np.asarray(self.rigid.broken_line(Pn), dtype=float),
            {"units": "N s", "long_name": "rigid broken line Pt(Pn) at the measured Pn"},
        )
        ds.attrs.update(
            {
                "record_source": self.record.attrs.get("source", ""),
                "record_sha256": self.record.attrs.get("sha256", ""),
                "score_source": self.source,
                "regime": str(self.rigid.regime),
                "area": self.score["area"],
                "max_distance": self.score["max_distance"],
                "Pt_drop": self.score["Pt_drop"],
                "e_poisson": self.split.e_poisson,
                "summary_json": json.dumps(self.summary(), allow_nan=False),
            }
        )
        return ds


def _jsonable(v):
    return isinstance(v, (int, float, str, bool, type(None)))


def analyse(
    record: xr.Dataset,
    scene: Scene,
    *,
    degree: int = 4,
    end_constraints: bool = False,
    source: str = "auto",
    mu="scene",
    e="scene",
    split_method: str = "auto",
    n_boot: int = 200,
    seed: int = 0,
    window_options: dict | None = None,
    fit_options: dict | None = None,
) -> Analysis:
    """Analyse one record against Routh's rigid model: window, fits, percussions, score.

    Parameters
    ----------
    record : xarray.Dataset
        A record (:func:`pipeline.io.load` or :func:`pipeline.simulate.impact`).
    scene : Scene
        The impact: mass, speed and angle give m*·v_n0 and the rigid prediction.
    degree : int
        Degree of the polynomial fits (4: the seed's quartics).
    end_constraints : bool
        Impose F = 0 at the window's ends in the polynomial fits.
    source : {"auto", "simpson", "trapezoid", "fit"}
        Which percussions are scored and split (module notes).
    mu, e : "scene", "fit", "record" or float
        Friction coefficient and restitution of the rigid prediction: the scene's; fitted
        to the record (``"fit"``: the cheapest adequate contact model,
        :func:`pipeline.select_model`, with its uncertainty); estimated from the record
        without a contact model (``"record"``: μ by :func:`estimate_mu`, e by Poisson's
        coefficient); or a number. A scene that does not give one (``Scene(mu=None)``)
        sends ``"scene"`` to the fit when it has the elastic constants E and ν, else to the
        record's estimate. Where each came from is in ``Analysis.sources`` (and the fitted
        values with their uncertainty in ``Analysis.fitted``).
    split_method : str
        How maximum compression is found (:func:`pipeline.percussion.compression_split`).
    n_boot : int
        Bootstrap replicates for the score's uncertainties (0: none): residual bootstrap of
        the fits, parametric (noise) bootstrap of the samples (see ``_bootstrap``).
    seed : int
        Seed of the bootstrap.
    window_options : dict, optional
        Passed to :func:`pipeline.window.find_contact` (its ``discharge`` by default the
        one the sensor states: ``fit_options``' ``sensor``, else the record's metadata).
    fit_options : dict, optional
        Passed to :func:`pipeline.select_model` when μ or e come from the fit, e.g.
        ``{"sensor": sidecar["sensor"]}`` for a rig whose cross-talk matrix is known (an
        uncorrected Fn → Ft leak biases μ by about the leak over μ).

    Returns
    -------
    Analysis

    Raises
    ------
    InputError
        No Scene, a record without an ``Ft`` channel, an unknown ``source``, or any stage's
        bad-input error (no contact pulse, too few samples, ...); a
        :class:`~pipeline.errors.UnitMismatchError` when the record's duration, peak or
        impulse is off the scene's by a power of 10³ (:mod:`pipeline.plausibility`).

    Warns
    -----
    ContactTimeWarning, PeakForceWarning, ImpulseWarning
        A record implausible for its scene, but not by a unit factor.
    NormalRestitutionWarning, TangentialRestitutionWarning, EnergyGainWarning,
    FrictionBoundWarning, FrictionDirectionWarning
        A measured outcome that breaks an energy or momentum bound of a passive impact, with
        its likeliest cause (:func:`pipeline.plausibility.check_outcomes`); the checks are in
        :attr:`Analysis.plausibility` with the others.
    """
    if not isinstance(scene, Scene):
        raise InputError("analyse needs a pipeline.Scene describing the impact")
    if source != "auto" and source not in _perc.SOURCES:
        raise InputError(f"source {source!r} is unknown; use 'auto' or one of {_perc.SOURCES}")
    # the record's own checks; a discharge its sensor states is undone for the window (the
    # samples after the pulse lie on its undershoot)
    stated = sensor_spec(record, (fit_options or {}).get("sensor"))
    win = _window.find_contact(record, **{"discharge": stated.discharge, **(window_options or {})})
    plausibility = check_plausible(record, scene, window=win)  # against the scene
    if "Ft" not in record:
        raise InputError(
            "the record has no tangential channel Ft: nothing to score against "
            "the rigid broken line (pipeline.percussion still gives Pn and e)",
            path=record.attrs.get("source"),
        )
    fits = _smooth.fit_window(
        win, method="polynomial", degree=degree, end_constraints=end_constraints
    )
    n_min = min(channel(win.record, c)[0].size for c in ("Fn", "Ft"))
    if source == "auto":
        source = "simpson" if n_min >= MIN_SAMPLES else "fit"
    perc = _perc.percussions(win, fits)
    split = _perc.compression_split(perc, scene, method=split_method, source=source)
    mu_rec = estimate_mu(win, split.t_c)
    selection = None
    if _wants_fit(mu, scene.mu, scene) or _wants_fit(e, scene.e, scene):
        selection = select_model(
            record,
            scene,
            n_boot=n_boot,
            seed=seed,
            window_options=window_options,
            **(fit_options or {}),
        )
    (mu_v, mu_src), (e_v, e_src) = (
        _choose(mu, scene.mu, mu_rec, "mu", selection),
        _choose(e, scene.e, split.e_poisson, "e", selection),
    )
    rigid_scene = scene.replace(mu=mu_v, e=e_v)
    rigid = _rigid.sphere_on_plane(rigid_scene)
    res = _perc.resolution(win, perc, record=record, scale=_score.references(rigid))
    boot = _bootstrap(win, perc, fits, n_boot, seed)
    boot_src = _boot_for(split, boot, perc)
    score = _score.deviation_score(
        perc.time,
        perc.Pn(source),
        perc.Pt(source),
        rigid,
        split.Pn_c,
        boot=boot_src,
        source=source,
    )
    outcomes = _outcomes(scene, perc, split, source, boot_src)
    bounds = check_outcomes(
        scene,
        perc,
        outcomes,
        split,
        win,
        source=source,
        sigma={c: noise_level(win, fits, c) for c in ("Fn", "Ft")},
        n_baseline=record.sizes["time"] - win.n_samples if win.kind == "sensor" else 0,
        mu=mu_v if mu_src in ("scene", "given") else None,
    )
    plausibility = Plausibility(plausibility.checks + bounds)
    if source == "fit":
        score_fit = score
    else:
        split_fit = _perc.compression_split(perc, scene, method=split_method, source="fit")
        score_fit = _score.deviation_score(
            perc.time,
            perc.Pn_fit,
            perc.Pt_fit,
            rigid,
            split_fit.Pn_c,
            boot=_boot_for(split_fit, boot, perc),
            source="fit",
        )
    options = dict(
        degree=degree,
        end_constraints=end_constraints,
        source=source,
        mu=mu if isinstance(mu, str) else float(mu),
        e=e if isinstance(e, str) else float(e),
        split_method=split_method,
        n_boot=n_boot,
        seed=seed,
    )
    return Analysis(
        scene=scene,
        rigid_scene=rigid_scene,
        window=win,
        fits=fits,
        percussions=perc,
        split=split,
        rigid=rigid,
        score=score,
        score_fit=score_fit,
        mu_record=mu_rec,
        source=source,
        options=options,
        sources={"mu": mu_src, "e": e_src},
        resolution=res,
        model_selection=selection,
        outcomes=outcomes,
        plausibility=plausibility,
    )


def _outcomes(scene, perc, split, source, boot) -> Outcomes:
    """Measured outcomes of the ``source`` percussions; std over the bootstrap replicates."""
    values = measured_outcomes(scene, perc.Pn(source)[-1], perc.Pt(source)[-1], split.Pn_c)
    if boot is None:
        std = dict.fromkeys(values, float("nan"))
    else:
        reps = measured_outcomes(scene, boot[0][:, -1], boot[1][:, -1], boot[2])
        std = {k: _score._spread(v) for k, v in reps.items()}
    return Outcomes({k: float(v) for k, v in values.items()}, std)


def _wants_fit(how, from_scene, scene) -> bool:
    """Whether μ or e is to come from a contact fit (see :func:`analyse`)."""
    if isinstance(how, str) and how == "fit":
        return True
    can_fit = scene.E is not None and scene.nu is not None
    return isinstance(how, str) and how == "scene" and from_scene is None and can_fit


def _choose(how, from_scene, from_record, name, selection=None) -> tuple[float, str]:
    """The value of μ or e for the rigid model, and where it came from ("scene", "fit",
    "record" or "given"). A scene that does not give the value (None) sends "scene" to the
    fit (or, without elastic constants, to the record): the rigid model is never fed a
    value nobody gave."""
    if isinstance(how, str):
        if how == "scene" and from_scene is not None:
            return float(from_scene), "scene"
        if how in ("scene", "fit") and selection is not None:
            f = selection.fit
            if name not in f.values:
                raise InputError(f"the fitted model has no {name}; give it")
            return float(f.values[name]), "fit"
        if how in ("scene", "record"):
            if not np.isfinite(from_record):
                raise InputError(
                    f"{name} is not in the scene and cannot be estimated from this record; "
                    f"give it (Scene({name}=...) or {name}=<number>)"
                )
            return float(np.clip(from_record, 0.0, 1.0 if name == "e" else np.inf)), "record"
        raise InputError(f"{name}={how!r}: use 'scene', 'fit', 'record' or a number")
    return float(how), "given"


def _bootstrap(win, perc, fits, n_boot, seed) -> dict:
    """Bootstrap replicates ``(Pn, Pt)`` [N·s], each (n_boot, grid), on the percussion grid.

    Fit source (residual bootstrap): the polynomial's values plus its resampled residuals,
    re-fitted in one batched least-squares solve. The residuals are centred and inflated by
    √(n/dof) (Davison & Hinkley 1997, §6.2.3: least-squares residuals are smaller than
    the errors, by (n − p)/n in variance), so the replicates' coefficient covariance is
    σ̂²(AᵀA)⁻¹, the fit's own; a fit without residual degrees of freedom has nothing to
    resample and gets no replicates (its score's std stays NaN rather than a false 0).
    Sample sources (parametric bootstrap): the samples plus white noise of the channel's
    :func:`noise_level`, integrated as :func:`pipeline.percussion.percussions` integrates
    the samples themselves — the spread of an integral of noisy samples, which is what the
    score's uncertainty is (none where the noise level cannot be estimated).

    References
    ----------
    A. C. Davison, D. V. Hinkley, Bootstrap Methods and their Application, CUP (1997),
    doi:10.1017/CBO9780511802843.
    """
    if n_boot <= 0:
        return {}
    rng = np.random.default_rng(seed)
    grid = perc.time
    ts, te = perc.t_start, perc.t_end
    reps = {src: {} for src in _perc.SOURCES}
    for name in ("Fn", "Ft"):
        t, f = channel(win.record, name)
        pf = getattr(fits, name)
        base = np.asarray(pf(t))
        resid = f - base
        if pf.dof > 0:
            resid = (resid - resid.mean()) * np.sqrt(t.size / pf.dof)
        F_b = base + resid[rng.integers(0, t.size, size=(n_boot, t.size))]
        batch = _smooth.fit_polynomials_batch(
            t,
            F_b,
            degree=pf.degree,
            end_constraints=pf.end_constraints,
            t_start=ts,
            t_end=te,
            warn=False,
        )
        reps["fit"][name] = batch.antiderivative(grid)
        sigma = noise_level(win, fits, name)
        S_b = f + sigma * rng.standard_normal((n_boot, t.size))
        for src in ("trapezoid", "simpson"):
            ok = np.isfinite(sigma)
            reps[src][name] = _perc._raw_on_grid(t, S_b, grid, ts, te, src) if ok else None
        if not pf.dof > 0:
            reps["fit"][name] = None
    return {
        src: (d["Fn"], d["Ft"])
        for src, d in reps.items()
        if d["Fn"] is not None and d["Ft"] is not None
    }


def _boot_for(split, boot, perc) -> tuple | None:
    """``(Pn_b, Pt_b, Pn_c_b)`` for :func:`pipeline.score.deviation_score`: the replicates of
    ``split.source`` with maximum compression re-found in each by ``split.method``."""
    if split.source not in boot:
        return None
    Pn_b, Pt_b = boot[split.source]
    grid = perc.time
    if split.method == "momentum":  # Pn_c = m*·v_n0 from the scene: fixed
        Pn_c_b = np.full(Pn_b.shape[0], split.Pn_c)
    elif split.method == "closure":  # the mean of Pn over the window
        Pn_c_b = np.trapezoid(Pn_b, grid, axis=-1) / (perc.t_end - perc.t_start)
    else:  # peak_force: Pn where dPn/dt = Fn peaks
        i = np.argmax(np.gradient(Pn_b, grid, axis=-1), axis=-1)
        Pn_c_b = np.take_along_axis(Pn_b, i[:, None], axis=-1)[:, 0]
    return Pn_b, Pt_b, Pn_c_b
