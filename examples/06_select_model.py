"""
Choose the contact model from the data
======================================

:func:`pipeline.select_model <pipeline.fit.select_model>` fits the ladder rigid →
compliant Coulomb → Hertz–Mindlin (and the normal laws), ranks each rung's laws by AIC
with Akaike weights, keeps the simplest rung whose best law passes the misfit test every
fit uses, and averages that rung's laws by their weights. :func:`pipeline.analyse
<pipeline.analysis.analyse>` uses it when the scene leaves μ or e unknown, and says so.
"""

import pandas as pd

from pipeline import select_model
from pipeline.io import load
from pipeline.report import read_sidecar, scene_from_sidecar

path = "../data_samples/gr_15deg_0.6ms.csv"
rec = load(path)
sensor = read_sidecar(path)["sensor"]
unknown = scene_from_sidecar(path).replace(mu=None, e=None)

sel = select_model(rec, unknown, sensor=sensor, n_boot=0)
print(sel.chosen, sel.chosen_normal)  # Ft reverses: only Mindlin's compliance follows it

# %%
# The table: one row per candidate, with its AIC, BIC, Akaike weight within its rung,
# verdict, RMS against the noise and cost.

with pd.option_context("display.width", 120, "display.max_columns", 20,
                       "display.precision", 3):
    print(sel.table[["model", "normal", "aic", "weight", "verdict", "rms", "noise",
                     "chosen"]].to_string(index=False))

# %%
# ``sel.averaged``: values, intervals and budget that span the laws the data cannot tell
# apart, with the Akaike weights of the chosen rung's laws.

print(sel.averaged.weights)
print(f"e = {sel.averaged.values['e']:.4f}")
