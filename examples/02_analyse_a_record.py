"""
Analyse a record
================

Read a record and analyse it: the contact window and the baseline, the seed's quartic
fits, the percussions Pn(t) and Pt(t), the maximum compression, Routh's rigid broken line
and the deviation score (dimensionless, per phase, ± its bootstrap standard deviation).

The record is the bundled 15° sample, a synthetic Garland–Rogers-style record made by the
package's simulator and sensor model (``data_samples/README.md``); the exact scene it was
made with is stored beside it, in its *sidecar* ``gr_15deg_0.6ms.json``.
"""

import warnings

from pipeline import analyse
from pipeline.io import load
from pipeline.report import scene_from_sidecar

path = "../data_samples/gr_15deg_0.6ms.csv"
rec = load(path)  # an xarray.Dataset: time [s], Fn, Ft, Fy [N]
scene = scene_from_sidecar(path)
print(rec.attrs["format"], rec.sizes["time"], "samples")

# %%
# The seed's quartic cannot follow this record's tangential force, and says so with a
# :class:`~pipeline.errors.PoorFitWarning`; the score integrates the samples, not the
# quartic, so it is not affected.

with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    a = analyse(rec, scene, n_boot=50)
for w in caught:
    print(f"{w.category.__name__}: {str(w.message)[:90]}...")

# %%
# The rigid prediction, the measured restitution and the score: whole impact, then per
# phase (compression, restitution).

print(a.rigid.regime, f"e (Poisson) = {a.split.e_poisson:.3f}")
print("area", a.score["area"], "max distance", a.score["max_distance"])
print("compression", a.score.values["compression"]["area"],
      "restitution", a.score.values["restitution"]["area"])

# %%
# The seed paper's three findings, stated for this record with their numbers.

from pipeline.report import findings

for line in findings(a).text:
    print(line)

# %%
# Every number is in :meth:`~pipeline.analysis.Analysis.summary` (a JSON-ready dict) and
# the percussions, fits and rigid line in :meth:`~pipeline.analysis.Analysis.to_dataset`
# (netCDF-ready).

summary = a.summary()
ds = a.to_dataset()
print(sorted(summary)[:8], "...")
print(list(ds.data_vars)[:6], "...")

# %%
# The figures
# -----------
# The seed's Fig. 8 (the forces, their quartic fits and the residuals) and Fig. 9 (the
# measured Pt(Pn) over Routh's broken line). Every figure is a matplotlib ``Figure``
# made without pyplot; :func:`pipeline.figures.save` writes one atomically
# (``figures.save(fig8, "fig8.png")``).

from pipeline import figures

fig8 = figures.fig8_forces(a)
fig9 = figures.fig9_percussion_plane(a)
