"""
Fit the contact parameters of a record
======================================

The record also says what the contact is. :func:`pipeline.fit_contact
<pipeline.fit.fit_contact>` fits the compliant model — the simulator's normal law and
tangential model, seen through the record's sensor (its filter, cross-talk and ADC) — to
both force channels at once, and returns E*, e, μ, the tangential stiffness over
Mindlin's (``kt_scale``) and the onset t0.

Its intervals hold when the record is imperfect: the inputs a lab knows only to a
tolerance (speed, mass, radius, each channel's gain, the cross-talk, the filter's
bandwidth, the clock) are fitted with the contact under Gaussian constraints, so each
interval adds the data's part (block bootstrap), every systematic's and the spread
between damping laws the record cannot tell apart (:doc:`/uncertainty`). No ODE is
integrated per iteration: the normal impact is a master curve tabulated once and
stretched by E* and the speed.

Here the scene's μ and e are left unknown, and the sensor's calibration comes from the
sample's sidecar.
"""

from pipeline import fit_contact
from pipeline.io import load
from pipeline.report import read_sidecar, scene_from_sidecar

path = "../data_samples/gr_15deg_0.6ms.csv"
rec = load(path)
sensor = read_sidecar(path)["sensor"]  # the rig's calibration: bandwidth, filter, ADC, ...
unknown = scene_from_sidecar(path).replace(mu=None, e=None)

fit = fit_contact(rec, unknown, sensor=sensor, n_boot=50)  # Hunt–Crossley + Mindlin
v = fit.values
print(f"E* = {v['E_eff'] / 1e9:.1f} GPa, e = {v['e']:.3f}, μ = {v['mu']:.4f}, "
      f"kt_scale = {v['kt_scale']:.3f}")

# %%
# The 95 % intervals, and whether each parameter is identifiable from this record (μ is
# bounded only from below when the contact sticks throughout, and is then reported so).

lo, hi = fit.ci()["mu"]
print(f"μ in [{lo:.4f}, {hi:.4f}], identifiable: {fit.identifiable['mu']}")

# %%
# The uncertainty budget: each term's standard uncertainty, here as a share of E*.

for term, sigma in fit.budget["E_eff"].items():
    print(f"{term:>10}: {100 * sigma / v['E_eff']:.3f} %")

# %%
# The verdict: does the model describe the record? Each cause it can name (a wrong
# normal law, the sensor's filter, cross-talk, coloured noise, ...) is also raised as its
# own warning. Then what the fit implies: the regime and e_t.

print(fit.verdict["ok"], fit.verdict["causes"])
print(fit.physics["regime"], f"e_t = {fit.physics['e_t']:.3f}")

# %%
# ``fit.report()`` is the whole text: the verdict, the parameters, the budget, the inputs
# and the laws compared (the first lines shown here); ``fit.summary()`` is the same as
# strict JSON, every digit kept.

print("\n".join(fit.report().splitlines()[:12]))

# %%
# The figure: the measured forces, the fitted model as the sensor records it, the contact
# force before the sensor, Routh's rigid Ft on the fitted Fn, and the weighted residuals.

from pipeline import figures

fig = figures.fig_contact_fit(fit)
