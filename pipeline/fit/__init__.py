"""Fitting contact parameters to records (the inverse problem).

This package is where the word *fit* lives: forward models, one record, campaigns,
kinematic outcomes and model selection. Polynomial and spline smoothing of the force
histories moved to :mod:`pipeline.smooth`; its names are re-exported here so that the old
imports (``from pipeline.fit import fit_window``) keep working.
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

__all__: list[str] = []
