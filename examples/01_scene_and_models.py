"""
A scene and the models behind the analysis
==========================================

A *scene* describes one impact, in SI units. This one is the bundled 15° sample's: a
25.4 mm steel ball at 0.6 m/s striking a steel cap (radius 25.4 mm) 15° from the normal,
with friction μ = 0.131 and restitution e = 0.9. Its fields and defaults are those of
:class:`pipeline.Scene <pipeline.scene.Scene>`; the derived quantities (mass, effective
modulus, approach and slip speeds) are properties.
"""

from pipeline import Scene

scene = Scene(radius=0.0127, density=7850.0, E=210e9, nu=0.29,
              target_E=210e9, target_nu=0.29, target_radius=0.0254,
              speed=0.6, angle_deg=15.0, mu=0.131, e=0.9)
print(f"m = {scene.m * 1e3:.2f} g, v_n0 = {scene.v_n0:.3f} m/s, v_t0 = {scene.v_t0:.3f} m/s")
print(f"E* = {scene.E_eff / 1e9:.1f} GPa, R* = {scene.R_eff * 1e3:.2f} mm")

# %%
# Rigid bodies: Routh's plane of percussions
# ------------------------------------------
# :func:`pipeline.rigid.sphere_on_plane` draws the impact in the plane (Pt, Pn) (seed
# eqs. 4–7): the point moves up the friction line Pt = μ·Pn while the ball slides, and
# stays at Pt = 2/7·m·v_t0 once the slip stops. Here the slip stops: the ball *sticks*
# and leaves rolling, with e_t = 5/7.

from pipeline.rigid import sphere_on_plane

r = sphere_on_plane(scene)
print(r.regime, f"Pn_f = {r.Pn_f:.4f} N·s, Pt_f = {r.Pt_f:.5f} N·s")
print(f"e_t = {r.e_t:.4f}, ω = {r.omega:.2f} rad/s")

# %%
# The seed's Fig. 4 draws the construction for a sliding and a sticking impact.

from pipeline import figures

fig4 = figures.fig4_percussion_plane()

# %%
# Compliant contact: Hertz
# ------------------------
# :func:`pipeline.contact.hertz_impact` is the elastic closed form: the peak force, the
# contact time and the largest compression.

from pipeline.contact import hertz_impact

h = hertz_impact(scene)
print(f"F_max = {h.F_max:.0f} N, t_c = {h.t_c * 1e6:.1f} µs, δ_max = {h.delta_max * 1e6:.2f} µm")

# %%
# A scene with a field or two changed is :meth:`~pipeline.scene.Scene.replace`; a scene
# from a JSON file (``pipeline analyse --scene``) is :meth:`~pipeline.scene.Scene.from_dict`
# of the parsed object, where ``"inf"`` stands for infinity (:doc:`/scene`).

import json

steeper = scene.replace(angle_deg=60.0)
print(sphere_on_plane(steeper).regime)
text = '{"radius": 0.0127, "density": 7850, "speed": 0.6, "angle_deg": 15, "target_E": "inf"}'
print(f"{Scene.from_dict(json.loads(text)).v_t0:.3f} m/s")
