# ---
# jupyter:
#   jupytext:
#     formats: py:percent
#     text_representation:
#       extension: .py
#       format_name: percent
#       format_version: '1.3'
#   kernelspec:
#     display_name: Python 3 (ipykernel)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Campaign report
#
# Made by `pipeline campaign` from the template `pipeline/templates/campaign_report.py`:
# every number and figure below is read from the campaign's Dataset named in the
# parameters cell (`campaign.nc`, written by `pipeline campaign`). Theory: the project's
# `docs/`; friction law after Garland & Rogers, J. Appl. Mech. 76:031015 (2009),
# doi:10.1115/1.3086432.

# %% tags=["parameters"]
dataset = "build/campaign/campaign.nc"  # the campaign's netCDF file

# %%
# %matplotlib inline
import json

import xarray as xr
from IPython.display import Markdown, display

from pipeline import figures
from pipeline.campaigns import table_of

ds = xr.load_dataset(dataset, engine="h5netcdf")
ok = int((ds["status"] == "ok").sum())
display(
    Markdown(
        f"## {ds.attrs.get('source', 'campaign')}: {ok} of {ds.sizes['record']} records analysed"
    )
)
failed = ds.where(ds["status"] != "ok", drop=True)
for name, reason in zip(failed["record"].values, failed["reason"].values, strict=True):
    print(f"failed: {name}: {reason}")

# %% [markdown]
# ## Every record

# %% tags=["table"]
cols = ["record", "status", "angle_deg", "speed_m_s", "repeat", "regime", "e_n", "e_t"]
cols += ["omega_rad_s", "rebound_deg_deg", "mu_record", "score_max_distance"]
display(table_of(ds)[cols])

# %% [markdown]
# ## Outcomes against incidence, with rigid theory and the compliant model

# %%
display(figures.campaign_outcomes(ds))

# %% [markdown]
# ## Friction against the initial tangential speed

# %%
display(figures.campaign_friction(ds))

# %% [markdown]
# ## Restitution against speed: the two damping hypotheses

# %%
display(figures.campaign_restitution(ds))

# %% [markdown]
# ## How far rigid-body theory is off

# %%
display(figures.campaign_score(ds))

# %% [markdown]
# ## The campaign's trends (numbers)

# %% tags=["trends"]
print(json.dumps(json.loads(ds.attrs["trends_json"]), indent=1))
