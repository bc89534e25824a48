"""Records with known truth for the benchmarks: the simulator, then the sensor model.

Shared by ``bench_percussion`` (chart family 1) and ``bench_stability`` (the stability maps
of the measurement chain). The truth of a scene is its dense simulated record
(:func:`pipeline.simulate.impact`, Hertz–Mindlin with Hunt–Crossley damping calibrated to
``scene.e``): the final percussions from its exact end state, the Pt maximum and the
deviation score from its cumulative Simpson integrals on ``TRUTH_SAMPLES`` samples
(quadrature error below 1e-7 of the percussions). Measured records are that history
through :func:`pipeline.sensor_model.to_sensor`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pipeline import Scene
from pipeline import rigid as _rigid
from pipeline import score as _score
from pipeline.percussion import cumulative_percussion
from pipeline.simulate import impact

#: The Garland–Rogers rig (25.4 mm steel ball on a 25.4 mm steel cap) and the bundled 15° scene.
GR_RIG = dict(
    radius=0.0127,
    density=7850.0,
    E=210e9,
    nu=0.29,
    target_E=210e9,
    target_nu=0.29,
    target_radius=0.0254,
)
BASE_SCENE = Scene(
    **GR_RIG,
    speed=0.6,
    angle_deg=15.0,
    mu=0.131,
    e=0.9,
)
TRUTH_SAMPLES = 4001

#: Errors above which a result is wrong: of Pn_f over P_ref, of Pt_f and of the Pt maximum
#: over Pt_ref (the deviation score's normalising percussions, pipeline.score.references),
#: and of the score's area (already in those units). The same tolerance as
#: pipeline.percussion.RESOLUTION_TOL, which flags records that cannot meet it.
TOL = dict.fromkeys(("Pn_f", "Pt_f", "Pt_max", "area"), 0.02)
QUANTITIES = tuple(TOL)


@dataclass(frozen=True)
class Truth:
    """Ground truth of one simulated impact (SI units)."""

    scene: Scene
    record: object  # the dense simulated record
    Pn_f: float  # [N s]
    Pt_f: float  # [N s]
    Pt_max: float  # [N s]
    area: float  # deviation score, whole impact [-]
    t_c: float  # contact duration [s]
    F_max: float  # [N]
    rigid: object  # pipeline.rigid.SphereOnPlane of the scene


def truth(scene: Scene) -> Truth:
    """The dense simulated record of ``scene`` and its exact percussions and score."""
    sim = impact(scene, samples=TRUTH_SAMPLES)
    t = sim["time"].values
    Pn, Pt = (
        cumulative_percussion(t, sim[c].values, method="simpson").values for c in ("Fn", "Ft")
    )
    rig = _rigid.sphere_on_plane(scene)
    area = _score.deviation_metrics(t, Pn, Pt, rig, scene.m_eff * scene.v_n0)["total"]["area"]
    return Truth(
        scene=scene,
        record=sim,
        Pn_f=float(sim.attrs["Pn_final"]),
        Pt_f=float(sim.attrs["Pt_final"]),
        Pt_max=float(Pt.max()),
        area=float(area),
        t_c=float(sim.attrs["t_contact"]),
        F_max=float(sim.attrs["F_max"]),
        rigid=rig,
    )


def errors(tr: Truth, time, Pn, Pt) -> dict:
    """Errors of measured percussions ``Pn``, ``Pt`` [N s] on ``time`` [s] against the truth.

    Relative errors of Pn_f and (over the true Pt maximum) of Pt_f and max Pt; absolute
    error of the deviation score's area, maximum compression at Pn = m*·v_n0 as in the
    truth. NaN percussions give NaN errors.
    """
    Pn = np.asarray(Pn, dtype=float)
    Pt = np.asarray(Pt, dtype=float)
    with np.errstate(invalid="ignore"):
        area = _score.deviation_metrics(time, Pn, Pt, tr.rigid, tr.scene.m_eff * tr.scene.v_n0)[
            "total"
        ]["area"]
        return {
            "Pn_f": float(abs(Pn[-1] / tr.Pn_f - 1.0)),
            "Pt_f": float(abs(Pt[-1] - tr.Pt_f) / tr.Pt_max),
            "Pt_max": float(abs(np.max(Pt) / tr.Pt_max - 1.0)),
            "area": float(abs(area - tr.area)),
        }


def sensor_kwargs(tr: Truth, samples_per_contact: float, **overrides) -> dict:
    """to_sensor keywords: ``samples_per_contact`` over the true contact, no cross-talk.

    ``overrides`` are to_sensor's keywords, plus ``noise_rel`` and ``full_scale_rel``: noise
    and ADC span as fractions of the scene's true peak force.

    Cross-talk is off: uncorrected, 2 % of Fn leaking into Ft is 20 % of Ft at μ ≈ 0.1 and
    would hide every other effect (decoupling it is ``pipeline.io.load(decouple=)``'s job).
    Pre- and post-trigger spans hold at least 30 and 60 samples (a slow digitiser records
    longer), so the baseline stays estimable at any rate.
    """
    rate = samples_per_contact / tr.t_c
    kw = {
        "rate": rate,
        "crosstalk": 0.0,
        "pre_trigger": max(100e-6, 30.0 / rate),
        "post_trigger": max(200e-6, 60.0 / rate),
    }
    for key in ("noise", "full_scale"):
        if f"{key}_rel" in overrides:
            overrides[key] = overrides.pop(f"{key}_rel") * tr.F_max
    kw.update(overrides)
    return kw
