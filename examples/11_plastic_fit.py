"""
A plastic fit
=============

A metal struck faster than its yield speed loses energy to plastic work, not to viscous
damping. Thornton's elastic–perfectly-plastic law (``normal="thornton"``; Thornton, J.
Appl. Mech. 64:383, 1997) is Hertz up to the yield pressure p_y, linear beyond it, and
elastic on the way back on the flatter radius of the dented contact; its restitution
depends on the yield speed over the impact speed alone, in closed form.

Here a 6 mm tungsten-carbide ball strikes a glass flat at 0.6 m/s, the contact yielding
at p_y = 1 GPa, and the record (simulated, then seen through a sensor) is fitted first with
the default Hunt–Crossley law, then with Thornton's.
"""

import warnings

from pipeline import Scene, advise, contact, fit_contact
from pipeline.sensor_model import to_sensor
from pipeline.simulate import impact

scene = Scene(radius=3e-3, density=15630.0, E=600e9, nu=0.22, target_E=72e9, target_nu=0.23,
              speed=0.6, mu=0.0, e=None)  # fmt: skip
p_y = 1e9  # the yield (limiting contact) pressure [Pa]
v_y = contact.yield_velocity(p_y, scene.E_eff, scene.R_eff, scene.m_eff)
e = contact.cor_thornton(v_y / scene.v_n0)
print(f"v_y = {v_y:.4f} m/s: the impact is {scene.v_n0 / v_y:.1f}× past it, e = {e:.3f}")

record = to_sensor(impact(scene, "thornton", "none", param=v_y / scene.v_n0), noise=0.3, seed=1)

# %%
# The default law cannot follow the pulse: the verdict names the normal law, each cause
# with its own warning, and the impulse, which says e by itself, contradicts the e the fit
# reports.

told = scene.replace(mu=None)
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    default = fit_contact(record, told, tangential="none", n_boot=0)
print(sorted({w.category.__name__ for w in caught}))
print(default.verdict["causes"])
print({law: round(row["weight"], 3) for law, row in default.alternatives.items()})
print(f"e fitted {default.values['e']:.3f}, the impulse says "
      f"{default.verdict['impulse']['Pn']['e_impulse']:.3f}")  # fmt: skip

# %%
# Thornton's law fits, and reports the yield pressure and speed it implies, with their
# intervals, beside E* and e (``fit.table()``: each rounded to its uncertainty, in GPa and
# m/s; every digit in ``fit.values`` and ``fit.ci()``).

fit = fit_contact(record, told, normal="thornton", tangential="none", n_boot=50)
print(fit.verdict["ok"], fit.verdict["causes"])
print(fit.table()[["quantity", "value", "unit", "95 % interval"]].to_string())

# %%
# Before any data: a scene that states its yield strengths gets the speed of first yield
# (Johnson's p_0 = 1.60·Y), and the advice says whether the impact yields.

steel = Scene(radius=0.0127, density=7850.0, E=210e9, nu=0.3, target_E=210e9, target_nu=0.3,
              speed=0.6, angle_deg=15.0, mu=0.13, e=0.8, yield_strength=1e9)  # fmt: skip
a = advise(steel)
print(f"yield speed {a.yield_speed:.3f} m/s; the compliant models use {a.normal!r}")
print(a.reason.split(". ")[-1])
