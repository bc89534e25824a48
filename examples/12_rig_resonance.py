"""
A record from a rig with a stated resonance
===========================================

A piezo force transducer bolted under the target is a mass on a stiff spring: it has a
mounted resonance, and a short pulse makes it ring. In series with the amplifier's
low-pass the mode sharpens the pulse (E* comes out high) and leaves a ring after it. The
sensor's description may state the mode — ``sensor={"resonance": f_n, "damping_ratio":
ζ}``, a tap test on the mount gives both — and :func:`pipeline.fit_contact
<pipeline.fit.fit_contact>` then models it in series with the low-pass, its values known to
their tolerances (10 % and 50 % by default, ``systematics=``). Where it is not stated, the
fit finds the ring in its residuals, fits the mode and names ``sensor_dynamics`` in its
verdict; where none shows, it bounds what a mode the record allows could do and carries
that into the budget (:doc:`/uncertainty`).

Here a 25.4 mm steel ball strikes the Garland–Rogers cap at 0.6 m/s and 15°; its
~100 µs contact is recorded through a 300 kHz low-pass and a 40 kHz mode of ζ = 0.03
(:func:`pipeline.sensor_model.to_sensor`).
"""

import warnings

from pipeline import Scene, fit_contact
from pipeline.errors import PipelineWarning
from pipeline.sensor_model import to_sensor
from pipeline.simulate import impact

scene = Scene(radius=0.0127, density=7850.0, E=210e9, nu=0.29, target_E=210e9,
              target_nu=0.29, target_radius=0.0254, speed=0.6, angle_deg=15.0,
              mu=0.15, e=0.9)  # fmt: skip
record = to_sensor(impact(scene), resonance=40e3, damping_ratio=0.03, full_scale=10_000.0,
                   seed=1)  # fmt: skip
unknown = scene.replace(mu=None, e=None)
true_E = scene.E_eff
low_pass = {"bandwidth": 300e3, "filter_order": 2, "bits": 16, "full_scale": 10_000.0}

# %%
# The mode stated (as a tap test would give it, a few per cent off): the fit models the
# chain and its intervals include the mode's tolerance.

def fit(**options):
    """fit_contact on the record, its warnings named rather than printed."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", PipelineWarning)
        out = fit_contact(record, unknown, n_boot=50, **options)
    print("  warned:", sorted({w.category.__name__ for w in caught}) or "nothing")
    return out


stated = fit(sensor={**low_pass, "resonance": 41e3, "damping_ratio": 0.03})
lo, hi = stated.ci()["E_eff"]
print(f"stated:     E* = {stated.values['E_eff'] / 1e9:.1f} GPa [{lo / 1e9:.1f}, {hi / 1e9:.1f}]"
      f" (true {true_E / 1e9:.1f}), e = {stated.values['e']:.3f} (true 0.900); "
      f"fitted f_n = {stated.values['resonance'] / 1e3:.2f} kHz")  # fmt: skip
print("E*'s budget [GPa]:", {k: round(u / 1e9, 2) for k, u in stated.budget["E_eff"].items()})

# %%
# Not stated: the record rings after the pulse, and the fit says so and fits the mode —
# its frequency from the ring, its damping from the logarithmic decrement of the peaks.

found = fit(sensor=low_pass)
print(f"not stated: E* = {found.values['E_eff'] / 1e9:.1f} GPa, verdict {found.verdict['causes']}")
print(found.verdict["messages"]["sensor_dynamics"])

# %%
# Inputs taken as exact (``systematics={}``): no mode is looked for — the fit of old, whose
# E* the mode pulls high under an interval that does not hold it.

blind = fit(sensor=low_pass, systematics={})
lo, hi = blind.ci()["E_eff"]
print(f"blind:      E* = {blind.values['E_eff'] / 1e9:.1f} GPa [{lo / 1e9:.1f}, {hi / 1e9:.1f}],"
      f" χ²_ν = {blind.redchi:.1f}")  # fmt: skip
