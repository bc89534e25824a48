"""
Simulate a record with known truth
==================================

:func:`pipeline.simulate.impact` integrates the compliant contact: Hertz, with
Hunt–Crossley damping calibrated to the scene's ``e`` when e < 1, and a tangential model,
``"mindlin"`` (the default: tangential compliance), ``"coulomb"`` (rigid-like friction)
or ``"none"``. :func:`pipeline.sensor_model.to_sensor` turns the result into what a
tri-axial piezo rig would export: sampling, the filter, cross-talk, offsets, drift, noise
and the ADC. Records made this way have a known truth, which is how the fits are tested.
"""

import warnings

from pipeline import Scene, analyse
from pipeline.sensor_model import to_sensor
from pipeline.simulate import impact

scene = Scene(radius=0.0127, density=7850.0, E=210e9, nu=0.29,
              target_E=210e9, target_nu=0.29, target_radius=0.0254,
              speed=0.6, angle_deg=15.0, mu=0.131, e=0.9)

coulomb = impact(scene, tangential="coulomb")
mindlin = impact(scene)
for name, sim in [("coulomb", coulomb), ("mindlin", mindlin)]:
    at = sim.attrs
    print(f"{name}: e_n = {at['e_n']:.3f}, e_t = {at['e_t']:.3f}, "
          f"t_contact = {at['t_contact'] * 1e6:.1f} µs")

# %%
# Rigid-like friction follows Routh's broken line, so its deviation score is near zero;
# tangential compliance makes Pt peak and fall, which the score measures.

with warnings.catch_warnings():
    warnings.simplefilter("ignore")  # the quartic's PoorFitWarning, as in the last example
    for name, sim in [("coulomb", coulomb), ("mindlin", mindlin)]:
        print(name, "max distance", analyse(sim, scene, n_boot=20).score["max_distance"])

# %%
# The same Mindlin impact as the rig records it (sampled at 2 MHz, filtered at 300 kHz,
# 2 N of noise, 16-bit ADC), drawn over the simulated contact forces.

raw = to_sensor(mindlin, seed=1)

from pipeline.figures import COLORS, new_figure, style

with style():
    fig, (ax_n, ax_t) = new_figure(2, 1, width=6.0, height=4.0, sharex=True)
    for ax, ch in [(ax_n, "Fn"), (ax_t, "Ft")]:
        ax.plot(raw["time"] * 1e6, raw[ch], ".", ms=2, color=COLORS["measured"],
                label="as the sensor records it")
        ax.plot(mindlin["time"] * 1e6, mindlin[ch], color=COLORS["fit"],
                label="contact force (simulated)")
        ax.set_ylabel(f"{ch} [N]")
    ax_t.set_xlabel("time [µs]")
    ax_t.set_xlim(-20, 140)
    ax_n.legend(loc="upper right")
