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
# # Fit report of one impact record
#
# Made by `pipeline report` (or `pipeline campaign`) from the template
# `pipeline/templates/record_report.py`: the code cells compute every number below, by the
# library, from the record named in the parameters cell. The outputs saved with the
# notebook are those of the same calls, made by the command that wrote it (its analysis of
# the record, rendered without a kernel); running the notebook recomputes them. Run it with
# other parameters to report another record. Theory and conventions: the project's `docs/`
# (Ciornei et al., MATEC Web Conf. 112, 07005, 2017, doi:10.1051/matecconf/201711207005).

# %% tags=["parameters"]
record = "data_samples/gr_15deg_0.6ms.csv"  # the record file (its sidecar beside it)
scene_json = ""  # Scene fields as JSON (SI units); "" = the record's sidecar scene
n_boot = 200  # bootstrap replicates for the uncertainties
seed = 0  # bootstrap seed
analyse_options = {}  # other keyword arguments of pipeline.analyse (degree, source, ...)

# %% tags=["record"]
# %matplotlib inline
# %config InlineBackend.print_figure_kwargs = {"bbox_inches": None}
# (the figures are shown whole, as drawn: they lay themselves out)
import json
import warnings

from IPython.display import Markdown, display

from pipeline import Scene, analyse, figures, fit_contact
from pipeline.report import findings, load_sample, outcomes_frame, scene_from_sidecar

rec = load_sample(record)
scene = Scene.from_dict(json.loads(scene_json)) if scene_json else scene_from_sidecar(record)
if scene is None:
    raise ValueError(f"{record}: no scene; give scene_json or put a sidecar beside the record")
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    a = analyse(rec, scene, n_boot=n_boot, seed=seed, **analyse_options)
display(Markdown(f"## Record `{rec.attrs['source']}`"))
print(a.describe())
for w in caught:
    print(f"note: {w.category.__name__}: {w.message}")

# %% [markdown]
# ## Measured outcomes against Routh's rigid prediction
#
# e_n is Poisson's restitution of the measured percussions, e_t the tangential restitution
# of the centre, ω the spin after impact, the rebound angle is measured from the normal;
# ± is the bootstrap standard deviation (white sensor noise only: cross-talk and baseline
# errors are not in it).

# %% tags=["outcomes"]
display(outcomes_frame(a))

# %% [markdown]
# ## Forces and their polynomial fits (as the seed's Fig. 8)

# %% tags=["forces"]
display(figures.fig8_forces(a))

# %% [markdown]
# ## Measured Pt(Pn) over the rigid broken line (as the seed's Fig. 9)

# %% tags=["plane"]
display(figures.fig9_percussion_plane(a))

# %% [markdown]
# ## The seed's three findings, tested on this record

# %% tags=["findings"]
for line in findings(a).text:
    print(line)

# %% [markdown]
# ## Contact parameters fitted to the record
#
# The compliant model fitted to Fn and Ft (values with uncertainties, and the figure of
# measured against model).

# %% tags=["fit"]
with warnings.catch_warnings(record=True):
    warnings.simplefilter("always")
    fit = fit_contact(rec, scene, n_boot=n_boot, seed=seed)
print(fit.report())
display(figures.fig_contact_fit(fit))
