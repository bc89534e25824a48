r"""A fit that knows when its model is wrong, and why: the verdict of :func:`pipeline.fit_contact`.

A misfit test (:func:`pipeline.fit.procedure.misfit`) says *that* the model misses the
record; a lab needs to know *what* misses it, because each cause has its own remedy. The
verdict ``{"ok": bool, "causes": [...], "messages": {cause: text}, "misfit": {...}}``
names the causes from a fixed vocabulary, each also raised as its own warning:

====================  =================================================  =====================
cause                 found by                                           warning
====================  =================================================  =====================
``normal_law``        another force law (one per family of pulse         NormalLawWarning
                      shapes) fits decisively better: ΔAIC >
                      :data:`AIC_DECISIVE` (Burnham & Anderson 2002)
``sensor_filter``     the fitted cut-off lies beyond :data:`PULL_Z`      SensorFilterWarning
                      standard uncertainties of the stated one; or
                      another Butterworth order fits decisively better
                      (tried where the filter shapes the pulse, or the
                      fit is poor)
``crosstalk``         Fy follows Fn (the axes leak), or a fitted leak    CrossTalkWarning
                      (Fn → Ft, Ft → Fn) lies beyond its stated bound
``coloured_noise``    the noise before the trigger is correlated         ColouredNoiseWarning
                      (:mod:`pipeline.fit.noise`): not a misfit — the
                      fit whitens it — but said
``impulse_mismatch``  the model's percussion over the contact differs    ImpulseMismatchWarning
                      from the measured integral of the force by more
                      than three of its standard deviations and
                      :data:`IMPULSE_FLOOR` of it: the model trades
                      impulse for pulse shape
``ft_sign``           Ft pushes the ball along its initial slip when Fn  FrictionDirectionWarning
                      first reaches half its peak, beyond the noise and
                      :data:`SLIP_LEAK` of Pn: a passive contact's
                      friction opposes the slip there (Ft > 0), so the
                      Ft channel has the opposite sign convention
``geometry``          the contact normal turns on a curved target by     GeometryWarning
                      more than the fit's tolerance
                      (:func:`pipeline.simulate.curved.geometry_error`)
``second_impact``     the window saw a later pulse (a rebound strike)    MultipleImpactWarning
                                                                         (by the window)
``sensor_dynamics``   the record shows a transducer mode, a discharge    SensorDynamicsWarning
                      or a zero shift the sensor's description does
                      not state, and the fit models it
                      (:mod:`pipeline.fit.dynamics`): not a misfit,
                      but said, with what was fitted
``spikes``            isolated samples no force history can make (the    SpikeWarning
                      window's :func:`pipeline.window.find_spikes`),
                      left out of the fit (``ContactFit.excluded``)
====================  =================================================  =====================

``ok`` is True when the misfit test passes and no cause but ``coloured_noise``,
``sensor_dynamics``, ``spikes`` (modelled or left out) or a ``crosstalk`` within its
allowed bound stands.

**Model spread.** The laws the record cannot tell apart give the budget's ``model`` term
(:attr:`pipeline.fit.result.FitResult.budget`): with Akaike weights
:math:`w_k \propto e^{-\Delta_k/2}` over the law fitted and one law of each other family,
:math:`\sigma_{model}^2 = \sum_k w_k (\hat\theta_k - \hat\theta)^2` — the spread of the
estimates about the reported one, which widens its interval to the better law's value
when the data favour that law, and adds little when they clearly favour the law fitted
(Burnham & Anderson 2002, §4.3.2). Where the stated filter shapes the pulse (its cut-off
within :data:`FILTER_SHAPES` contact frequencies) the Butterworth orders 1–4 are weighed
the same way, a filter's order being as rarely known as a cut-off is, and their spread
adds to the laws' in quadrature.

References
----------
K. P. Burnham, D. R. Anderson, *Model Selection and Multimodel Inference*, 2nd ed.,
Springer (2002), doi:10.1007/b97636.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ..errors import (
    ColouredNoiseWarning,
    FrictionDirectionWarning,
    GeometryWarning,
    ImpulseMismatchWarning,
    NormalLawWarning,
    SensorDynamicsWarning,
    SensorFilterWarning,
    SpikeWarning,
)
from ..precision import plain_quantities, reading
from ..record import channel
from .forward import _I, SHIFT_OF
from .pulse import shape_of
from .sensor import CrossTalkWarning, fy_tracks_fn

__all__ = [
    "CAUSES",
    "AIC_DECISIVE",
    "PULL_Z",
    "IMPULSE_FLOOR",
    "FAMILY_LAWS",
    "FILTER_SHAPES",
    "akaike_weights",
    "alternative_orders",
    "model_spread",
    "diagnose",
]

CAUSES = (
    "normal_law",
    "sensor_filter",
    "crosstalk",
    "coloured_noise",
    "impulse_mismatch",
    "ft_sign",
    "geometry",
    "second_impact",
    "sensor_dynamics",
    "spikes",
)
#: ΔAIC beyond which the better model is decisively better (Burnham & Anderson 2002).
AIC_DECISIVE = 10.0
#: A systematic's fitted value this many of its standard uncertainties from the stated one
#: contradicts the statement.
PULL_Z = 3.0
#: The smallest impulse mismatch called one, of the model's own percussion (the master
#: curve and the sensor model agree to ~1e-8; a lab's mount and cable add well under this).
IMPULSE_FLOOR = 0.005
#: One law per family of pulse shapes (pipeline.fit.pulse): the alternatives a fit is
#: compared with.
FAMILY_LAWS = ("hunt_crossley", "hertz_dashpot", "viscoelastic", "thornton")
#: A stated filter shapes the pulse where its cut-off lies within this many contact
#: frequencies (f_c·t_c): there the other Butterworth orders are fitted too.
FILTER_SHAPES = 10.0
#: The causes that mean the model does not describe the record (module notes).
_FAILURES = (
    "normal_law",
    "sensor_filter",
    "impulse_mismatch",
    "ft_sign",
    "geometry",
    "second_impact",
)
#: Fn → Ft cross-talk [of Fn] an undecoupled tri-axial sensor may have (±1–3 % by its data
#: sheet): an early Pt against the slip within it may be a leak, not Ft's sign; 0.2 % for
#: a record decoupled with its calibration matrix.
SLIP_LEAK = {"sensor": 0.02, "decoupled": 0.002}


def akaike_weights(aics: dict) -> dict:
    """{key: w} with w ∝ exp(−ΔAIC/2), ΔAIC from the smallest (Burnham & Anderson 2002)."""
    best = min(aics.values())
    raw = {k: math.exp(-0.5 * (a - best)) for k, a in aics.items()}
    total = sum(raw.values())
    return {k: v / total for k, v in raw.items()}


def alternative_laws(normal: str) -> tuple:
    """The laws a fit of ``normal`` is compared with: one of each other family."""
    if normal in (None, "hertz"):
        return ()
    own = shape_of(normal)
    return tuple(law for law in FAMILY_LAWS if shape_of(law) != own)


def alternative_orders(fit) -> tuple:
    """The Butterworth orders a fit's stated filter is compared with: 1–4 but the stated,
    where the filter shapes the pulse (a stated cut-off within :data:`FILTER_SHAPES`
    contact frequencies, f_c·t_c ≤ 10: there a 4th-order filter told as 2nd moves E* by
    several per cent); none where it does not."""
    spec = fit.data.sensor
    if not spec.filtered or not math.isfinite(spec.bandwidth):
        return ()
    if spec.bandwidth * fit.data.window.duration > FILTER_SHAPES:
        return ()
    return tuple(k for k in (1, 2, 3, 4) if k != spec.filter_order)


def model_spread(fit, fits: dict, own=None) -> tuple[dict, dict]:
    """(σ_model per fitted contact parameter of ``fit``, the table) from ``fits``, the same
    record fitted by each model of one kind — each law, or each filter order — keyed by
    it, the fit's own (``own``, default its law) among them (module notes). The table:
    {key: {"aic", "delta_aic", "weight", "values"}}.

    The models are compared with the inputs taken as exact (``systematics={}``): the
    systematics move every model's estimates alike, and a wrong model's fit would otherwise
    spend them on its misfit."""
    weights = akaike_weights({k: f.aic for k, f in fits.items()})
    best = min(f.aic for f in fits.values())
    # each fit's once (a property), its parameters' alone: neither the spread nor the
    # table reads what they imply (Thornton's yield point)
    values = {k: f._parameter_values() for k, f in fits.items()}
    own = values[fit.normal if own is None else own]
    one_sided = fit.one_sided
    spread = {}
    for name in fit.vary:
        if name in fit.priors or name in one_sided or name not in own:
            continue
        s2 = sum(
            w * (values[k][name] - own[name]) ** 2
            for k, w in weights.items()
            if name in values[k] and np.isfinite(values[k][name])
        )
        spread[name] = math.sqrt(s2)
    table = {
        k: {
            "aic": f.aic,
            "delta_aic": f.aic - best,
            "weight": weights[k],
            "values": {n: values[k][n] for n in ("E_eff", "e", "mu", "kt_scale") if n in values[k]},
        }
        for k, f in fits.items()
    }
    return spread, table


def diagnose(
    fit, table=None, *, orders=None, refit_order=None, refit_law=None, geometry=None
) -> dict:
    """The verdict of a contact fit (module notes); each cause found is warned about.

    Parameters
    ----------
    fit : pipeline.fit.ContactFit
    table : dict, optional — the law table of :func:`model_spread`
    orders : dict, optional — its table of the filter orders (:func:`alternative_orders`)
    refit_order : callable, optional — ``refit_order(order, law=None) -> ContactFit``, the
        same fit with a Butterworth filter of that order (tried when the fit is poor), by
        another normal law if given
    refit_law : callable, optional — ``refit_law(law) -> ContactFit``, the same fit (with
        its systematics) by another law: where another law is decisively better, the
        sensor's filter is judged on that law's fit (a wrong law pulls the filter's
        cut-off to hide its misfit)
    geometry : dict, optional — {"e_n": Δ, "e_t": Δ, "tol": τ, "tol_t": τ_t, "theta": θ,
        "exceeds": bool} from :func:`pipeline.simulate.curved.geometry_error` with the fit's
        own tolerances
    """
    src = fit.data.record.attrs.get("source", "the record")
    causes, messages = [], {}

    def add(cause, text, category=None):
        causes.append(cause)
        messages[cause] = text
        if category is not None:
            warnings.warn(f"{src}: {text}", category, stacklevel=4)

    # ---- the normal law
    if table:
        best = min(table, key=lambda k: table[k]["aic"])
        if best != fit.normal and table[fit.normal]["delta_aic"] > AIC_DECISIVE:
            shift = plain_quantities(
                {n: table[best]["values"][n] for n in ("E_eff", "e") if n in table[best]["values"]}
            )
            add(
                "normal_law",
                f"the {best!r} law fits decisively better than {fit.normal!r} (ΔAIC = "
                f"{table[fit.normal]['delta_aic']:.1f}; it gives {shift}); the intervals "
                "include the spread between the laws (budget 'model'): fit that law, or let "
                "select_model choose",
                NormalLawWarning,
            )
    # ---- the sensor and the scene, judged on the better law's fit where that is another:
    # a wrong law pulls whatever shapes or scales the pulse (the filter's cut-off and order,
    # the leaks, the speed and gains) to hide its misfit, so those pulls say nothing of the
    # sensor until the law is right
    judged = fit
    if "normal_law" in causes and refit_law is not None:
        judged = refit_law(min(table, key=lambda k: table[k]["aic"])) or fit
    order_of, shapes = refit_order, bool(orders)
    if judged is not fit:  # the order table is the wrong law's: refit the better one
        orders = None
        if refit_order is not None:

            def order_of(k):
                return refit_order(k, judged.normal)

    bw = _pull(judged, "bandwidth")
    if bw is not None and abs(bw[0]) > PULL_Z:
        add(
            "sensor_filter",
            f"the pulse's rise says the sensor's cut-off is {bw[1]:.4g} Hz, {bw[0]:+.1f} standard "
            f"uncertainties from the stated {bw[2]:.4g} Hz: check the amplifier's filter setting",
            SensorFilterWarning,
        )
    elif (better := _better_order(judged, orders, order_of, always=shapes)) is not None:
        k, delta, e_k = better
        add(
            "sensor_filter",
            f"a Butterworth filter of order {k} fits decisively better than the stated order "
            f"{fit.data.sensor.filter_order} (ΔAIC = {delta:.1f}; E* {e_k:.4g} Pa against "
            f"{judged.values['E_eff']:.4g}): check the amplifier's filter",
            SensorFilterWarning,
        )
    # ---- Ft's sign: friction along the slip from the start (the commonest axis mistake;
    # its fit pulls the leaks and the impulse, named below, to explain it)
    early = _against_slip(fit)
    if early is not None:
        add(
            "ft_sign",
            f"when Fn first reaches half its peak (t = {early[2]:.6g} s) the tangential "
            f"percussion is {early[0]:.4g} N s (± {early[1]:.2g}): friction pushed the ball "
            "along its slip from the start, which no passive contact does. The Ft channel has "
            "the opposite sign convention (Ft > 0 must oppose the initial slip): load it with "
            "axes={'Ft': '-Fx'} (pipeline fit --axes Fn=Fz,Ft=-Fx)",
            FrictionDirectionWarning,
        )
    # ---- cross-talk
    pulls = {k: _pull(judged, k) for k in ("leak", "leak_tn")}
    pulls = {k: p for k, p in pulls.items() if p is not None}
    worst = max(pulls, key=lambda k: abs(pulls[k][0]), default=None)
    leak = pulls.get(worst)
    fy = None
    if fit.tangential != "none" and fit.data.sensor.crosstalk is None:
        fy = fy_tracks_fn(judged.data, judged.predicted()[0])
    if leak is not None and abs(leak[0]) > PULL_Z:
        way = ("Fn → Ft", "Fn") if worst == "leak" else ("Ft → Fn", "Ft")
        add(
            "crosstalk",
            f"the record puts the {way[0]} leak at {leak[1]:+.2%} of {way[1]}, {leak[0]:+.1f} "
            f"standard uncertainties beyond the allowed ±{judged.priors[worst][1]:.2%}: give the "
            "sensor's cross-talk matrix (sensor={'crosstalk_matrix': ...}) or load the record "
            "decoupled",
            CrossTalkWarning,
        )
    elif fy is not None:
        add("crosstalk", _crosstalk_text(judged, fy), CrossTalkWarning)
    # ---- coloured noise (modelled)
    coloured = {c.name: c.noise for c in fit.data.channels if not c.noise.white}
    if coloured:
        text = "; ".join(
            f"{n}: AR({m.phi.size}), lag-1 autocorrelation {m.lag1:.2f}"
            for n, m in coloured.items()
        )
        add(
            "coloured_noise",
            f"the noise before the trigger is correlated ({text}): the fit whitens the "
            "residuals by it (generalised least squares), so its χ², intervals and misfit test "
            "hold; the residuals' structure from it is no model failure",
            ColouredNoiseWarning,
        )
    # ---- the impulse
    mismatch = impulse_mismatch(fit)
    bad = {k: v for k, v in mismatch.items() if v["mismatch"]}
    if bad:
        add(
            "impulse_mismatch",
            "; ".join(_impulse_text(fit, k, v) for k, v in bad.items())
            + ": the model trades impulse for pulse shape — another normal law, a "
            "baseline that drifts under the pulse or a wrong scene"
            + (
                " (Pt: a spin of the ball before impact that the scene does not state, "
                "Scene.spin, changes the slip the tangential force follows)"
                if "Pt" in bad and float(fit.data.scene.spin) == 0.0
                else ""
            ),
            ImpulseMismatchWarning,
        )
    # ---- geometry
    if geometry is not None and geometry.get("exceeds", False):
        add(
            "geometry",
            f"the contact normal turns by {geometry.get('theta', math.nan):.3g} rad while the "
            f"ball slides over the curved target; ignoring it moves e_n by "
            f"{geometry['e_n']:.2g} and e_t by {geometry['e_t']:.2g}, beyond what the fit's "
            f"uncertainties allow ({geometry['tol']:.2g} in e_n from e's, "
            f"{geometry.get('tol_t', geometry['tol']):.2g} in e_t from the tangential "
            "parameters'): the fitted values are those of a contact whose normal stays put "
            "(pipeline.simulate.curved.turning_outcomes gives the rebound with the turn)",
            GeometryWarning,
        )
    # ---- a second impact (the window has warned), unless the sensor's modelled response
    # is what the window took for one (a mounted mode's ring)
    others = [p for p in getattr(fit.data.window, "other_pulses", ()) if not _explained(fit, p)]
    if others:
        add(
            "second_impact",
            f"{len(others)} later pulse(s) after the contact (a rebound strike); the fit keeps "
            "to the first",
        )
    # ---- the sensor's own dynamics, found in the record (modelled)
    if fit.dynamics.get("what"):
        add("sensor_dynamics", dynamics_text(fit), SensorDynamicsWarning)
    # ---- spikes, left out
    spikes = [sp for sp in getattr(fit.data.window, "spikes", ()) if sp.channel in fit.excluded]
    if spikes:
        listing = "; ".join(
            f"{ch} samples {idx}" for ch, idx in fit.data.window.spike_indices().items()
        )
        add(
            "spikes",
            f"{len(spikes)} isolated sample(s) no force history can make ({listing}): "
            "electrical spikes, left out of the fit (fit.excluded)",
            SpikeWarning,
        )
    failing = [c for c in causes if c in _FAILURES]
    if leak is not None and abs(leak[0]) > PULL_Z:
        failing.append("crosstalk")
    ok = (fit.misfit is None or fit.misfit.ok) and not failing
    misfit = {}
    if fit.misfit is not None:
        misfit = {
            "redchi": fit.misfit.redchi,
            "chi2_z": fit.misfit.chi2_z,
            "runs_z": dict(fit.misfit.runs_z),
            "reasons": list(fit.misfit.reasons),
        }
    return {
        "ok": bool(ok),
        "causes": causes,
        "messages": messages,
        "misfit": misfit,
        "impulse": mismatch,
    }


def _explained(fit, pulse) -> bool:
    """Whether the fitted model — the sensor's response included — accounts for a later
    pulse the window saw, (t_start [s], t_end [s], peak [N]): its Fn residual there stays
    within a quarter of the pulse's peak and three σ (a ring the fit's mode makes is no
    second impact)."""
    if not (fit.data.sensor.dynamic or fit.dynamics.get("what")):
        return False
    a, b, peak = pulse
    c = fit.data.channels[0]
    inside = (c.t >= a) & (c.t <= b)
    if not np.any(inside):
        return False
    res = (c.y - fit.predicted()[0])[inside]
    return bool(np.max(np.abs(res)) <= 0.25 * abs(peak) + 3.0 * c.sigma_rms)


def dynamics_text(fit) -> str:
    """What a fit found of the sensor's own dynamics and fitted (:mod:`pipeline.fit.dynamics`),
    in words."""
    v, se = fit.values, fit.stderr
    parts = []
    if "resonance" in fit.vary and "resonance" not in fit.priors:
        parts.append(
            "a mounted mode rings after the pulse: fitted f_n = "
            f"{reading('resonance', v['resonance'], se['resonance'])}, ζ = "
            f"{reading('damping_ratio', v['damping_ratio'], se['damping_ratio'])}"
            f" (state it: sensor={{'resonance': {v['resonance']:.4e}, 'damping_ratio': "
            f"{v['damping_ratio']:.2g}}})"
        )
    if "discharge" in fit.vary and "discharge" not in fit.priors:
        parts.append(
            f"the piezo discharges (the record undershoots after the pulse): fitted τ = "
            f"{reading('discharge', v['discharge'], se['discharge'])} (state it: "
            f"sensor={{'discharge': "
            f"{v['discharge']:.3e}}})"
        )
    for name, value in zero_shifts(fit).items():
        peak = fit.physics.get("F_max", math.nan)
        parts.append(
            f"{name}'s zero shifts by {value:+.4g} N ({value / peak:+.2%} of the peak) during "
            f"the contact, half done {reading('t_c', v['shift_at'] - v['t0'])} after the onset "
            f"over {reading('t_c', v['shift_width'])}: fitted"
        )
    return "; ".join(parts) + " — modelled, the parameters hold"


def zero_shifts(fit) -> dict:
    """{channel: fitted zero shift [N]} of the channels whose zero shift the fit models."""
    return {ch: fit.values[p] for ch, p in SHIFT_OF.items() if p in fit.vary}


def _better_order(fit, orders, refit_order, always=False):
    """(order, ΔAIC, its E*) of a Butterworth order decisively better than the stated one,
    or None: from the order table where the filter shapes the pulse, else — the fit being
    poor, or ``always`` — by refitting with each other order."""
    stated = fit.data.sensor.filter_order
    poor = fit.misfit is not None and not fit.misfit.ok
    if orders:
        aic = {k: v["aic"] for k, v in orders.items()}
        e_eff = {k: v["values"].get("E_eff", math.nan) for k, v in orders.items()}
    elif refit_order is not None and (always or poor):
        tried = {k: refit_order(k) for k in (1, 2, 3, 4) if k != stated}
        tried = {k: f for k, f in tried.items() if f is not None}
        aic = {stated: fit.aic, **{k: f.aic for k, f in tried.items()}}
        e_eff = {k: f.values["E_eff"] for k, f in tried.items()}
    else:
        return None
    k = min(aic, key=aic.get)
    delta = aic[stated] - aic[k]
    return (k, delta, e_eff[k]) if k != stated and delta > AIC_DECISIVE else None


def _pull(fit, name):
    """(pull, fitted, stated) of a constrained parameter: (θ − θ₀)/u, or None."""
    if name not in fit.priors:
        return None
    stated, u = fit.priors[name]
    value = float(fit.theta[fit.names.index(name)])
    return (value - stated) / u, value, stated


def _impulse_text(fit, key, v) -> str:
    """What an impulse mismatch of channel ``key`` is (row ``v`` of :func:`impulse_mismatch`)."""
    q = "Pt_final" if key == "Pt" else "Pn_final"
    if abs(v["measured_Ns"] - v["model_Ns"]) > 3.0 * v["sigma_Ns"] and (
        abs(v["relative"]) > IMPULSE_FLOOR
    ):
        return (
            f"the model's {key} over the contact is {reading(q, v['model_Ns'])} against the "
            f"measured {reading(q, v['measured_Ns'], v['sigma_Ns'])} ({v['relative']:+.2%})"
        )
    pulls = [(n, p) for n in fit.priors if (p := _pull(fit, n)) is not None and abs(p[0]) > 2.0]
    moved = ", ".join(f"{n} {p[0]:+.1f} σ" for n, p in sorted(pulls, key=lambda q: -abs(q[1][0])))
    text = (
        f"with the stated inputs the model's {key} over the contact is "
        f"{reading(q, v['stated_Ns'])} against the measured "
        f"{reading(q, v['measured_Ns'], v['stated_sigma_Ns'])} "
        f"(their tolerances included; {v['stated_relative']:+.2%})"
    )
    if "e_impulse" in v and "e" in fit.values:
        text += f": the impulse says e ≈ {v['e_impulse']:.3f}, the fit {fit.values['e']:.3f}"
    if moved:
        text += f" — it moved {moved} from the stated values to match it"
    return text


def _crosstalk_text(fit, k) -> str:
    leak = fit.priors.get("leak")
    if leak is None:
        return (
            f"Fy tracks Fn (Fy ≈ {k:+.2%} of Fn): the sensor's axes leak into each other, "
            "and a leak of Fn into Ft of that size biases μ by about the leak over μ (and e_t "
            "with it). Give the sensor's cross-talk matrix (sensor={'crosstalk_matrix': ...}) "
            "or load the record decoupled"
        )
    i = fit.vary.index("leak")
    post = math.sqrt(fit.cov[i, i]) if np.isfinite(fit.cov[i, i]) else math.inf
    if post < 0.5 * leak[1]:
        how = (
            f"the stick phases separate it from μ: the fitted leak is "
            f"{fit.values['leak']:+.2%} ± {post:.2%} of Fn"
        )
    else:
        how = (
            "the contact slides too much for the record to separate it from μ: the leak's "
            f"bound (±{leak[1]:.2%}) is carried into μ's interval"
        )
    return (
        f"Fy tracks Fn (Fy ≈ {k:+.2%} of Fn): the sensor's axes leak into each other; {how}. "
        "Give the sensor's cross-talk matrix to narrow it"
    )


def _against_slip(fit):
    """(Pt [N·s], its σ [N·s], t [s]) when the window's Fn first reaches half its peak, where
    that Pt is against the initial slip by more than three σ (the noise's) and
    :data:`SLIP_LEAK` of Pn there; None otherwise, without a slip or a tangential model."""
    win = fit.data.window
    if fit.tangential == "none" or float(fit.data.scene.slip0) == 0.0 or win.kind != "sensor":
        return None
    rec = win.record
    if rec is None or "Ft" not in rec.variables:
        return None
    tn, fn = channel(rec, "Fn")
    tt, ft = channel(rec, "Ft")
    if tn.size < 3 or tt.size < 3:
        return None
    at = float(tn[int(np.argmax(fn >= 0.5 * np.max(fn)))])
    k = int(np.searchsorted(tt, at, side="right"))
    if k < 2:
        return None
    Pt = float(np.trapezoid(ft[:k], tt[:k]))
    Pn = float(np.trapezoid(fn[tn <= at], tn[tn <= at]))
    sd = float(win.noise.get("Ft", math.nan)) * float(np.median(np.diff(tt))) * math.sqrt(k)
    decoupled = any(str(a).startswith("decouple") for a in rec.attrs)
    floor = SLIP_LEAK["decoupled" if decoupled else "sensor"] * Pn
    if not (math.isfinite(sd) and -Pt > 3.0 * sd + floor):
        return None
    return Pt, sd, at


def impulse_mismatch(fit) -> dict:
    """The model's percussion over the contact against the measured integral of the force,
    per channel: {"Pn"/"Pt": {"model_Ns", "measured_Ns", "sigma_Ns", "relative",
    "stated_Ns", "stated_sigma_Ns", "stated_relative", "e_impulse" (Pn only),
    "mismatch"}} (module notes).

    Two comparisons. The fitted model's own percussion (``model_Ns``): the span runs from
    the fitted onset to the contact's end plus the filter's ring; the measured integral is
    taken less the fit's own baseline; σ is the noise's (at its long-run variance where it
    is coloured) over the span and the baseline's error carried over it. And the same
    model with every input known to a tolerance (speed, mass, gains, leaks, ...) back at
    its stated value (``stated_Ns``), σ widened by what each tolerance moves the
    percussion by: a fit can match the impulse with a contact that contradicts it by
    pulling the speed or a gain beyond its tolerance (a wrong law whose e sticks at 1
    does), and only the stated inputs see that. ``e_impulse`` is the restitution the
    measured Pn implies at the stated inputs, (1 + e)·measured/stated − 1."""
    data = fit.data
    P = fit._P()
    stated = P[:1].copy()
    names = [n for n in fit.priors if n in _I]
    for n in names:
        stated[0, _I[n]] = fit.priors[n][0]
    rows = [P[:1], stated]
    for n in names:
        bumped = stated.copy()
        bumped[0, _I[n]] += fit.priors[n][1]
        rows.append(bumped)
    Ps = np.concatenate(rows)
    sol = fit.model.solve([data], [Ps])[0]
    preds = fit.model.predict(data, Ps, sol)
    t0 = float(P[0, 5])
    t_end = t0 + float(fit.physics["t_c"]) + data.sensor.ring_time()
    out = {}
    for c, m, key in zip(data.channels, preds, ("Pn", "Pt"), strict=False):
        span = (c.t >= t0) & (c.t <= t_end)
        n_span = int(span.sum())
        if n_span < 3:
            continue
        dt = float(np.median(np.diff(c.t)))
        integral = np.sum(m[:, span], axis=1) * dt
        model, at_stated = float(integral[0]), float(integral[1])
        diff = float(np.sum(c.project(c.y - m[0])[span]) * dt)
        nm = c.noise
        lr = 1.0 if nm.white else nm.innovation / abs(1.0 - float(np.sum(nm.phi)))
        var = float(np.sum(np.broadcast_to(c.sigma, c.t.shape)[span] ** 2))
        s = lr * dt * math.sqrt(var * (1.0 + n_span / max(c.t.size, 1)))
        measured = model + diff
        s_stated = math.sqrt(s * s + float(np.sum((integral[2:] - at_stated) ** 2)))
        rel = diff / model if model else math.nan
        rel_stated = (measured - at_stated) / at_stated if at_stated else math.nan
        row = {
            "model_Ns": model,
            "measured_Ns": measured,
            "sigma_Ns": s,
            "relative": rel,
            "stated_Ns": at_stated,
            "stated_sigma_Ns": s_stated,
            "stated_relative": rel_stated,
            "mismatch": bool(
                (abs(diff) > 3.0 * s and abs(rel) > IMPULSE_FLOOR)
                or (abs(measured - at_stated) > 3.0 * s_stated and abs(rel_stated) > IMPULSE_FLOOR)
            ),
        }
        if key == "Pn" and fit.model.normal is not None:
            row["e_impulse"] = (1.0 + float(P[0, _I["e"]])) * measured / at_stated - 1.0
        out[key] = row
    return out
