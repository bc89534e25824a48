"""
A scene and the models behind the analysis
==========================================

A *scene* describes one impact in SI units.
"""

from pipeline import Scene, figures
from pipeline.rigid import sphere_on_plane

scene = Scene(radius=0.0127, density=7850.0, E=210e9, nu=0.29, speed=0.6, angle_deg=15.0,
              mu=0.131, e=0.9)
r = sphere_on_plane(scene)
print(r.regime)
fig = figures.fig4_percussion_plane()
