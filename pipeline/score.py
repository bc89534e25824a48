r"""How far a measured percussion curve Pt(Pn) is from Routh's rigid broken line.

The rigid model (:func:`pipeline.rigid.sphere_on_plane`) predicts, in the plane of
percussions, the broken line

.. math::

    P_t^{rig}(P_n) = \min(\mu P_n,\; P_{t,S}), \qquad
    0 \le P_n \le P_{n,f}^{rig} = (1+e)\,m^* v_{n0},

while a deformable ball traces a curve :math:`(P_n(t), P_t(t))`. Every metric below compares
the two **at the same normal percussion** (the measured :math:`P_n(t)` increases
monotonically because :math:`F_n \ge 0`) and is made dimensionless so that records at
different speeds and angles compare:

- normal percussions are divided by :math:`P_{ref} = P_{n,f}^{rig}`;
- tangential percussions by :math:`P_{t,ref} = P_{t,f}^{rig}` (the rigid end point's Pt;
  :math:`\mu P_{ref}` or :math:`P_{ref}` when that is zero).

::

      Pn/P_ref
       1 ┤............T.....E        measured curve  ─── (rises, peaks, falls)
         │           ╱│   ·´         rigid broken line ··· (LF then S)
         │  area ──▶╱ │ ·´   ◀── max distance: largest horizontal gap
     C ──┤.........╱..·´.........    (the phases split at the line C, Pn = m*·v_n0)
         │       ╱ ·´
         │     ╱·´
         └───·´──────────────── Pt/Pt_ref

Metrics (each also split into the compression phase, Pn ≤ Pn_c, and restitution):

``area``
    :math:`\int |P_t - P_t^{rig}(P_n)|\,dP_n / (P_{t,ref} P_{ref})` — the area between the
    curves in the normalised plane.
``max_distance``
    :math:`\max |P_t - P_t^{rig}(P_n)| / P_{t,ref}`.
``end_Pt``, ``end_Pn``
    Signed end-point errors :math:`(P_{t}(t_e) - P_{t,f}^{rig})/P_{t,ref}` and
    :math:`(P_{n}(t_e) - P_{n,f}^{rig})/P_{ref}` (for a phase: at its end, compared with the
    rigid line at the same Pn; the compression phase ends at the last sample with
    :math:`P_n \le P_{n,c}`, so its normal error is that sample's :math:`(P_n - P_{n,c})/P_{ref}`,
    zero up to one grid step).
``Pt_max``, ``Pn_at_Pt_max``, ``Pt_drop``
    Height :math:`\max P_t / P_{t,ref}` of the measured tangential percussion, where it
    peaks (:math:`P_n / P_{ref}` there) and how far it falls after the peak,
    :math:`(\max P_t - P_t(t_e))/P_{t,ref}`. A rigid ball never lets Pt fall
    (docs/theory.md), so ``Pt_drop > 0`` is the signature of tangential compliance.

Uncertainties (:func:`deviation_score` with ``boot=``): the metrics are recomputed on
seeded bootstrap replicates of the percussions and the standard deviation over the
replicates is reported with each metric. :func:`pipeline.analyse` makes the replicates: a
residual bootstrap of the polynomial fits (fitted values plus resampled residuals, re-fitted
in one batched least-squares solve) for the fit's percussions, a parametric one (the samples
plus white noise of the estimated level) for the samples' integrals; maximum compression is
found again in each replicate by the method the record's split used.

References
----------
F.-C. Ciornei et al., MATEC Web Conf. 112:07005 (2017), doi:10.1051/matecconf/201711207005,
Fig. 9. B. Efron, R. J. Tibshirani, An Introduction to the Bootstrap, Chapman & Hall (1993),
§9.5 (bootstrapping residuals).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._json import json_ready

__all__ = [
    "METRICS",
    "PHASES",
    "NEAR_ZERO",
    "DeviationScore",
    "deviation_metrics",
    "deviation_score",
]

#: Names of the dimensionless deviation metrics.
METRICS = ("area", "max_distance", "end_Pt", "end_Pn", "Pt_max", "Pn_at_Pt_max", "Pt_drop")
#: The phases each metric is reported for.
PHASES = ("total", "compression", "restitution")
#: A deviation metric below this (dimensionless, of P_ref or Pt_ref) is "near zero": the
#: largest departure a record that follows the broken line shows in this pipeline
#: (simulated Coulomb records: < 0.001; tests/test_score.py) with a factor 20 of margin
#: for sensor effects. The findings of :mod:`pipeline.report` and the campaign figures
#: judge the score against it.
NEAR_ZERO = 0.02


@dataclass(frozen=True)
class DeviationScore:
    """Dimensionless distance of a measured Pt(Pn) curve from the rigid broken line.

    Attributes
    ----------
    values : dict
        ``values[phase][metric]`` (module notes), phases ``total``, ``compression``,
        ``restitution`` [-].
    std : dict
        Bootstrap standard deviation of each value, same layout [-] (NaN without a
        bootstrap).
    P_ref, Pt_ref : float
        The normalising percussions [N·s].
    Pn_c : float
        Normal percussion splitting the phases [N·s].
    t_Pt_max : float
        Instant of the measured Pt maximum [s].
    n_boot : int
        Bootstrap replicates behind ``std`` (0 when none).
    source : str
        Which percussions were scored (``fit``, ``trapezoid``, ``simpson``).
    """

    values: dict
    std: dict
    P_ref: float
    Pt_ref: float
    Pn_c: float
    t_Pt_max: float
    n_boot: int = 0
    source: str = "simpson"

    def __getitem__(self, metric: str) -> float:
        """The whole-impact value of a metric, e.g. ``score["area"]``."""
        return self.values["total"][metric]

    def summary(self) -> dict:
        """JSON-ready dict: values with their bootstrap standard deviations (NaN → None)."""
        return json_ready(
            {
                "source": self.source,
                "P_ref_Ns": self.P_ref,
                "Pt_ref_Ns": self.Pt_ref,
                "Pn_c_Ns": self.Pn_c,
                "t_Pt_max_s": self.t_Pt_max,
                "n_boot": self.n_boot,
                **{
                    phase: {
                        m: {"value": self.values[phase][m], "std": self.std[phase][m]}
                        for m in METRICS
                    }
                    for phase in PHASES
                },
            }
        )


def _spread(v) -> float:
    """Standard deviation (ddof 1) of the finite replicates; NaN with fewer than two."""
    v = np.asarray(v, dtype=float)
    v = v[np.isfinite(v)]
    return float(np.std(v, ddof=1)) if v.size >= 2 else float("nan")


def references(rigid) -> tuple[float, float]:
    """The normalising percussions (P_ref, Pt_ref) [N·s] of a rigid result."""
    P_ref = float(rigid.Pn_f)
    Pt_ref = float(rigid.Pt_f)
    if not Pt_ref > 0:
        Pt_ref = float(rigid.mu) * P_ref if float(rigid.mu) > 0 else P_ref
    return P_ref, Pt_ref


def deviation_metrics(time, Pn, Pt, rigid, Pn_c) -> dict:
    """All metrics for one or many percussion curves on a shared time grid.

    Parameters
    ----------
    time : array_like, shape (n,)
        Time grid [s].
    Pn, Pt : array_like, shape (..., n)
        Measured percussions [N·s] (leading axes: replicates).
    rigid : pipeline.rigid.SphereOnPlane
        The rigid prediction (scalar scene).
    Pn_c : float or array_like, shape (...)
        Normal percussion at maximum compression [N·s] (splits the phases).

    Returns
    -------
    dict
        ``{phase: {metric: array of shape (...)}}`` plus ``"t_Pt_max"`` (shape (...)).
    """
    t = np.asarray(time, dtype=float)
    Pn = np.asarray(Pn, dtype=float)
    Pt = np.asarray(Pt, dtype=float)
    P_ref, Pt_ref = references(rigid)
    pn = Pn / P_ref
    pt = Pt / Pt_ref
    pt_rig = np.asarray(rigid.broken_line(Pn), dtype=float) / Pt_ref
    gap = np.abs(pt - pt_rig)
    pn_c = np.asarray(Pn_c, dtype=float)[..., None] / P_ref
    comp = pn <= pn_c
    phases = {"total": np.ones_like(comp), "compression": comp, "restitution": ~comp}
    # the sample where the compression phase ends (last with Pn ≤ Pn_c)
    i_c = np.maximum(comp.sum(axis=-1) - 1, 0)
    out = {}
    dpn = np.diff(pn, axis=-1)
    seg_gap = 0.5 * (gap[..., 1:] + gap[..., :-1])
    seg_comp = comp[..., 1:]  # segment belongs to compression if it ends at Pn ≤ Pn_c
    pt_rig_f = float(rigid.Pt_f) / Pt_ref
    pn_rig_f = 1.0
    for phase, mask in phases.items():
        if phase == "total":
            seg = np.ones_like(seg_comp)
        elif phase == "compression":
            seg = seg_comp
        else:
            seg = ~seg_comp
        area = np.sum(np.where(seg, seg_gap * dpn, 0.0), axis=-1)
        maxd = np.max(np.where(mask, gap, -np.inf), axis=-1)
        pt_masked = np.where(mask, pt, -np.inf)
        i_max = np.argmax(pt_masked, axis=-1)
        pt_max = np.take_along_axis(pt, i_max[..., None], axis=-1)[..., 0]
        pn_at = np.take_along_axis(pn, i_max[..., None], axis=-1)[..., 0]
        if phase == "compression":
            i_end = i_c
            end_pt = np.take_along_axis(pt - pt_rig, i_end[..., None], axis=-1)[..., 0]
            end_pn = np.take_along_axis(pn, i_end[..., None], axis=-1)[..., 0] - pn_c[..., 0]
        else:
            i_end = np.full(i_c.shape, pt.shape[-1] - 1)
            end_pt = pt[..., -1] - pt_rig_f
            end_pn = pn[..., -1] - pn_rig_f
        pt_end = np.take_along_axis(pt, i_end[..., None], axis=-1)[..., 0]
        empty = ~np.any(mask, axis=-1)
        vals = {
            "area": area,
            "max_distance": maxd,
            "end_Pt": end_pt,
            "end_Pn": end_pn,
            "Pt_max": pt_max,
            "Pn_at_Pt_max": pn_at,
            "Pt_drop": pt_max - pt_end,
        }
        out[phase] = {k: np.where(empty, np.nan, v) for k, v in vals.items()}
    i_max = np.argmax(pt, axis=-1)
    out["t_Pt_max"] = t[i_max]
    return out


def deviation_score(time, Pn, Pt, rigid, Pn_c, *, boot=None, source="simpson") -> DeviationScore:
    """Score one measured percussion curve against the rigid broken line.

    Parameters
    ----------
    time : array_like, shape (n,)
        Time grid [s].
    Pn, Pt : array_like, shape (n,)
        Measured percussions [N·s].
    rigid : pipeline.rigid.SphereOnPlane
        Rigid prediction for the scene.
    Pn_c : float
        Normal percussion at maximum compression [N·s].
    boot : tuple of arrays, optional
        ``(Pn_boot, Pt_boot, Pn_c_boot)`` of shapes (B, n), (B, n), (B,): bootstrap
        replicates whose spread gives the uncertainties.
    source : str
        Label of the percussions' origin (``fit``, ``trapezoid``, ``simpson``).

    Returns
    -------
    DeviationScore
    """
    m = deviation_metrics(time, Pn, Pt, rigid, Pn_c)
    values = {p: {k: float(v) for k, v in m[p].items()} for p in PHASES}
    if boot is not None:
        mb = deviation_metrics(time, boot[0], boot[1], rigid, boot[2])
        std = {p: {k: _spread(v) for k, v in mb[p].items()} for p in PHASES}
        n_boot = int(np.shape(boot[0])[0])
    else:
        std = {p: dict.fromkeys(METRICS, float("nan")) for p in PHASES}
        n_boot = 0
    P_ref, Pt_ref = references(rigid)
    return DeviationScore(
        values=values,
        std=std,
        P_ref=P_ref,
        Pt_ref=Pt_ref,
        Pn_c=float(Pn_c),
        t_Pt_max=float(m["t_Pt_max"]),
        n_boot=n_boot,
        source=source,
    )
