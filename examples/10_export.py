"""
Export the contact to a simulator
=================================

:func:`pipeline.export.export` writes a fitted (or given) contact — E*, e, μ, the
tangential stiffness — as the input lines of LAMMPS, LIGGGHTS, YADE or MuJoCo, with the
conversions' limits as notes (:doc:`/exports` derives every one). From the shell:
``pipeline export fit.json --to lammps``.
"""

from pipeline.export import export
from pipeline.report import scene_from_sidecar

scene = scene_from_sidecar("../data_samples/gr_30deg_0.6ms.csv")
ex = export(scene, "lammps")
print(ex.text)

# %%
# The notes say what each conversion keeps and what it cannot:

for note in ex.notes:
    print("-", note)

# %%
# The same contact for MuJoCo:

print(export(scene, "mujoco").text)
