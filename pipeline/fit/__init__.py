"""Fitting contact parameters to records (the inverse problem).

The stage a reader looks for after the percussions: what a force record says about the
contact — E*, the restitution and its damping law, μ, the tangential stiffness — with
uncertainties a paper can quote.

- :func:`fit_contact` (:mod:`.contact`) — one record → :class:`ContactFit`;
- :func:`fit_campaign` (:mod:`.campaign`) — many records, shared parameters and the
  hypotheses μ = a + b·v_t0 and constant e or constant α → :class:`CampaignFit`;
- :func:`select_model` (:mod:`.select`) — the cheapest model the record needs →
  :class:`ModelSelection`;
- :func:`fit_outcomes` (:mod:`.outcomes`) — rebound kinematics (e_t, ω, rebound angle
  against incidence) instead of forces → :class:`OutcomeFit`.

Underneath: :mod:`.pulse` (the normal impact as a master curve tabulated once),
:mod:`.tangential` (the tangential contact on it, solved piecewise), :mod:`.sensor` (filter,
cross-talk, ADC), :mod:`.forward` (a record's forward model), :mod:`.engine` (least squares
with lmfit and vectorised Gauss–Newton), :mod:`.uncertainty` (covariance, block bootstrap,
one-sided bounds) and :mod:`.result` (what every fit result shares).

Polynomial and spline smoothing of the force histories moved to :mod:`pipeline.smooth`; its
names are re-exported here so that the old imports (``from pipeline.fit import
fit_window``) keep working.
"""

from __future__ import annotations

from ..smooth import (  # noqa: F401  (backward-compatible names of pipeline.smooth)
    RUNS_ALPHA,
    PolyFit,
    PolyFitBatch,
    SplineFit,
    WindowFits,
    fit_polynomial,
    fit_polynomials_batch,
    fit_spline,
    fit_window,
    runs_test,
)
from .contact import ContactFit, fit_contact
from .sensor import CrossTalkWarning, SensorSpec

__all__ = [
    "ContactFit",
    "fit_contact",
    "SensorSpec",
    "CrossTalkWarning",
    "CampaignFit",
    "fit_campaign",
    "ModelSelection",
    "select_model",
    "OutcomeFit",
    "fit_outcomes",
]


def __getattr__(name):
    # The campaign fit, the model ladder and the outcome fit load on first use: a fit of one
    # record (a fresh process's first fit among them) does without their imports.
    if name in ("CampaignFit", "fit_campaign"):
        from . import campaign as module
    elif name in ("ModelSelection", "select_model"):
        from . import select as module
    elif name in ("OutcomeFit", "fit_outcomes"):
        from . import outcomes as module
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(module, name)
