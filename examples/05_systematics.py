"""
Inputs known to a tolerance
===========================

A lab knows the impact speed as "0.60 ± 0.02 m/s", a gain or a mass to a calibration's
tolerance. :func:`~pipeline.fit.fit_contact` takes these as ``systematics=``: each input
named there is fitted with the contact under a Gaussian constraint of that width, and its
share of each parameter's uncertainty is a term of ``fit.budget``. ``None`` (the default)
applies the documented defaults (:data:`pipeline.fit.systematics.DEFAULT_SYSTEMATICS`,
:doc:`/uncertainty`); ``{}`` takes every input as exact.
"""

from pipeline import fit_contact
from pipeline.fit.systematics import DEFAULT_SYSTEMATICS
from pipeline.io import load
from pipeline.report import read_sidecar, scene_from_sidecar

path = "../data_samples/gr_15deg_0.6ms.csv"
rec = load(path)
sensor = read_sidecar(path)["sensor"]
unknown = scene_from_sidecar(path).replace(mu=None, e=None)
print(DEFAULT_SYSTEMATICS)

# %%
# The speed told to ±0.02 m/s (a float is relative to the stated value; ``(0.02, "abs")``
# would be absolute). The record corrects what it can: the impulse and the pulse's shape
# pin the speed, and the interval includes what remains.

told = fit_contact(rec, unknown, sensor=sensor, n_boot=50,
                   systematics={**DEFAULT_SYSTEMATICS, "speed": 0.02})
E = told.values["E_eff"]
print(f"fitted speed {told.values['speed']:.4f} m/s")
print(f"E* = {E / 1e9:.2f} GPa; its speed term {100 * told.budget['E_eff']['speed'] / E:.3f} %,"
      f" total {100 * told.budget['E_eff']['total'] / E:.3f} %")

# %%
# Every input exact: the interval is the data's part alone, narrower, and wrong by as
# much as the inputs are.

exact = fit_contact(rec, unknown, sensor=sensor, n_boot=50, systematics={})
print(f"E* = {exact.values['E_eff'] / 1e9:.2f} GPa; "
      f"total {100 * exact.budget['E_eff']['total'] / exact.values['E_eff']:.3f} %")
