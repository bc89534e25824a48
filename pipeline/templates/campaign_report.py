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
# What a campaign of impact records says, the verdict first. A value ± its uncertainty is
# rounded to that uncertainty (as the Particle Data Group rounds) in the unit a person reads;
# every digit is in the campaign's Dataset (how this report is made: at its end).

# %% tags=["parameters"]
dataset = "build/campaign/campaign.nc"  # the campaign's netCDF file
overview = ""  # the campaign's overview page, relative to this notebook ("": none)

# %% tags=["verdict"]
# %matplotlib inline
# %config InlineBackend.print_figure_kwargs = {"bbox_inches": None}
# (the figures are shown whole, as drawn: they lay themselves out inside their canvas)
import xarray as xr
from IPython.display import Markdown, display

from pipeline import figures
from pipeline.tables import (
    beside,
    campaign_verdict,
    joint_table,
    records_table,
    trends_table,
    view,
)

ds = xr.load_dataset(dataset, engine="h5netcdf")
display(Markdown(campaign_verdict(ds)))
if overview:
    display(
        Markdown(
            f"Every record as a point to explore — hover for its values, click for its "
            f"report: [the campaign's overview]({overview})."
        )
    )

# %% [markdown]
# ## Every record
#
# The measured outcomes ± their bootstrap standard deviation, μ estimated from each record
# and the maximum distance of the measured Pt(Pn) from Routh's broken line (dimensionless);
# then each record's fitted contact parameters ± their standard uncertainties.

# %% tags=["table"]
display(view(records_table(ds), caption="Measured", uuid="records"))
fitted = records_table(ds, fits=True)
if len(fitted):
    display(view(fitted, caption="Fitted to each record's forces", uuid="fits"))

# %% [markdown]
# ## Outcomes against incidence, with rigid theory and the compliant model

# %%
display(figures.campaign_outcomes(ds))

# %% [markdown]
# ## Friction against the initial tangential speed
#
# The trend of μ estimated from each record, as a law and as a constant, compared by AIC.

# %% tags=["friction"]
display(beside(figures.campaign_friction(ds), view(trends_table(ds, "friction"), uuid="friction")))

# %% [markdown]
# ## Restitution against speed: the two damping hypotheses

# %% tags=["restitution"]
display(
    beside(
        figures.campaign_restitution(ds),
        view(trends_table(ds, "restitution"), uuid="restitution"),
    )
)

# %% [markdown]
# ## How far rigid-body theory is off

# %%
display(figures.campaign_score(ds))

# %% [markdown]
# ## The joint fit of every record's forces
#
# One fit of all the records' Fn and Ft with E* and the damping shared and μ a law of the
# initial tangential speed; the hypotheses compared by AIC and BIC (ΔAIC > 10: decisive).

# %% tags=["joint"]
joint = joint_table(ds)
display(view(joint, uuid="joint"))
if len(joint.attrs["compare"]):
    display(view(joint.attrs["compare"], caption="The hypotheses compared", uuid="compare"))

# %% [markdown]
# ## How this report is made
#
# By `pipeline campaign` from the template `pipeline/templates/campaign_report.py`: every
# number and figure is read from the campaign's Dataset named in the parameters cell
# (`campaign.nc`, written by `pipeline campaign`); in the HTML page each cell's code is folded
# under "code" (the notebook shows it). Theory: the project's `docs/`; friction law after
# Garland & Rogers, J. Appl. Mech. 76:031015 (2009), doi:10.1115/1.3086432.
