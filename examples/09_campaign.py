"""
A campaign: many records at once
================================

A lab measures angles × speeds × repeats. :func:`pipeline.campaign
<pipeline.campaigns.campaign>` analyses a folder, a glob or a list of records into one
``xarray.Dataset`` (dimension ``record``; coordinates angle, speed, v_t0, repeat): the
measured e_n, e_t, ω and rebound angle with their bootstrap spread beside Routh's
prediction, the deviation score, each record's fitted contact parameters, and the joint fit
of all records (μ = a + b·v_t0, both damping hypotheses compared). A record that fails is
listed with its reason and the rest goes on (:doc:`/campaigns`).

Here the bundled Garland–Rogers-style samples (four angles × two speeds), with a small
bootstrap so the example runs in seconds.
"""

from pipeline.campaigns import campaign, table_of

ds = campaign("../data_samples/gr_*.csv", n_boot=20, fit=True)
print(int((ds["status"] == "ok").sum()), "of", ds.sizes["record"], "records analysed")

# %%
# One row per record (:func:`~pipeline.campaigns.table_of`):

import pandas as pd

with pd.option_context("display.width", 120, "display.precision", 3):
    print(table_of(ds)[["record", "angle_deg", "speed_m_s", "e_t", "e_t_rigid"]])

# %%
# The joint fit of all records: a shared E*, one restitution and μ = a + b·v_t0.

for name in ["joint_E_eff", "joint_e", "joint_mu_a", "joint_mu_b"]:
    if name in ds:
        print(f"{name} = {float(ds[name]):.4g} ± {float(ds[name + '_std']):.2g}")

# %%
# The campaign's figures (:func:`pipeline.figures.campaign_figures`): the outcomes
# against incidence, μ against v_t0 with the law, restitution and the score.

from pipeline import figures

campaign_figs = list(figures.campaign_figures(ds).values())
