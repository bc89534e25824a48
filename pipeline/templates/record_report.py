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
# What one force record says about its impact, the verdict first. A value ± its uncertainty
# is rounded to that uncertainty (as the Particle Data Group rounds) in the unit a person
# reads; every digit is in the results' `summary()` (how this report is made: at its end).

# %% tags=["parameters"]
record = "data_samples/gr_15deg_0.6ms.csv"  # the record file (its sidecar beside it)
scene_json = ""  # Scene fields as JSON (SI units); "" = the record's sidecar scene
n_boot = 200  # bootstrap replicates for the uncertainties
seed = 0  # bootstrap seed
analyse_options = {}  # other keyword arguments of pipeline.analyse (degree, source, ...)
load_options = {}  # keyword arguments of pipeline.io.load over the sidecar's (sensitivity, ...)

# %% tags=["verdict"]
# %matplotlib inline
# %config InlineBackend.print_figure_kwargs = {"bbox_inches": None}
# (the figures are shown whole, as drawn: they lay themselves out inside their canvas)
import json
import warnings

from IPython.display import Markdown, display

from pipeline import Scene, analyse, figures, fit_contact
from pipeline.report import findings, load_sample, scene_from_sidecar, sensor_from_sidecar
from pipeline.tables import (
    fit_notes,
    implied_table,
    notes_markdown,
    outcomes_table,
    record_table,
    record_verdict,
    score_table,
    view,
)

rec = load_sample(record, **load_options)
scene = Scene.from_dict(json.loads(scene_json)) if scene_json else scene_from_sidecar(record)
if scene is None:
    raise ValueError(f"{record}: no scene; give scene_json or put a sidecar beside the record")
sensor = sensor_from_sidecar(record)  # the rig's sensor as its sidecar states it, or None
options = dict(analyse_options)
fit_options = {"sensor": sensor, **options.pop("fit_options", {})}
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    a = analyse(rec, scene, n_boot=n_boot, seed=seed, fit_options=fit_options, **options)
with warnings.catch_warnings(record=True):  # the fit's warnings are in its verdict
    warnings.simplefilter("always")
    fit = fit_contact(rec, scene, n_boot=n_boot, seed=seed, sensor=sensor)
display(Markdown(record_verdict(a, fit)))

# %% [markdown]
# ## The record and its scene

# %% tags=["record"]
display(view(record_table(a), caption="", uuid="record"))
notes = [f"{w.category.__name__}: {w.message}" for w in caught]
if notes:
    display(Markdown(notes_markdown("Notes on the analysis", notes)))

# %% [markdown]
# ## Measured outcomes against Routh's rigid prediction
#
# e_n is Poisson's restitution of the measured percussions, e_t the tangential restitution
# of the centre, ω the spin after impact, θ_r the rebound angle from the normal; ± is the
# bootstrap standard deviation (white sensor noise only: cross-talk and baseline errors are
# not in it). The deviation score measures how far the measured Pt(Pn) runs from Routh's
# broken line, in units of the rigid percussions.

# %% tags=["outcomes"]
display(view(outcomes_table(a), caption="", uuid="outcomes"))
display(view(score_table(a), caption="Deviation from Routh's broken line", uuid="score"))

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
display(Markdown("\n".join(f"- {line}" for line in findings(a).text)))

# %% [markdown]
# ## Contact parameters fitted to the record
#
# The compliant model fitted to Fn and Ft. Each value ± its combined standard uncertainty:
# the data's (block bootstrap), the inputs known only to a tolerance (speed, mass, radius,
# gains, cross-talk, filter, clock) and the spread between the force laws the record cannot
# tell apart; the 95 % interval; and each of these terms' share of the parameter's variance
# [%] (k_t/k_M is the tangential stiffness over Mindlin's 8·G*·a). Then the figure of
# measured against model, and what the fitted values imply.

# %% tags=["fit"]
table = fit.table()
display(view(table, uuid="fit"))
display(figures.fig_contact_fit(fit))
display(view(implied_table(fit), caption="What the fitted parameters imply", uuid="implied"))
if table.attrs["details"] or fit.notes:
    display(Markdown(notes_markdown("Notes on the fit", fit_notes(fit, table))))

# %% [markdown]
# ## How this report is made
#
# By `pipeline report` (or `pipeline campaign`) from the template
# `pipeline/templates/record_report.py`: the code cells compute every number, by the library,
# from the record named in the parameters cell (in the HTML page each cell's code is folded
# under "code"; the notebook shows it). The outputs saved with the notebook are those of the
# same calls, made by the command that wrote it; running the notebook recomputes them, and
# with other parameters it reports another record. Theory and conventions: the project's
# `docs/` (Ciornei et al., MATEC Web Conf. 112, 07005, 2017, doi:10.1051/matecconf/201711207005).
