"""
Which model is accurate enough, before any data
===============================================

:func:`pipeline.advise <pipeline.advice.advise>` returns the cheapest model of the ladder
``"rigid"`` < ``"coulomb"`` < ``"mindlin"`` whose e_t, ω and Pt(Pn) stay within ``tol`` of
the full Hertz–Mindlin model for a scene, with the reason and the cheaper models' errors.
It needs no record: it is for planning an experiment or a simulation.
"""

import numpy as np

from pipeline import Scene, advise

scene = Scene(radius=0.0127, density=7850.0, E=210e9, nu=0.29,
              target_E=210e9, target_nu=0.29, target_radius=0.0254,
              speed=0.6, angle_deg=15.0, mu=0.131, e=0.9)
adv = advise(scene, tol=1e-3)  # the 15° scene of the other examples: it sticks
print(adv.model, {k: round(v, 4) for k, v in adv.errors["e_t"].items()})
print(adv.reason)

# %%
# At 60° the same ball slides throughout, where rigid theory is exact.

print(advise(scene.replace(angle_deg=60.0)).model)

# %%
# Across incidences: the cheaper models' error in e_t against the angle, and the model
# ``advise`` picks at each (the tolerance dotted). Rigid theory is off where the ball
# sticks, and exact once it slides throughout.

angles = np.arange(5.0, 86.0, 10.0)
advice = [advise(scene.replace(angle_deg=float(a))) for a in angles]

from pipeline.figures import COLORS, new_figure, style

with style():
    fig, ax = new_figure(width=6.0, height=3.2)
    for model, colour in [("rigid", COLORS["rigid"]), ("coulomb", COLORS["sliding"])]:
        err = [max(ad.errors["e_t"][model], 1e-12) for ad in advice]
        ax.semilogy(angles, err, "o-", color=colour, label=f"{model}: error in e_t")
    ax.axhline(1e-3, ls=":", color=COLORS["construction"], label="tol")
    for a, ad in zip(angles, advice, strict=True):
        ax.annotate(ad.model, (a, 2e-2), rotation=90, ha="center", fontsize=7)
    ax.set_xlabel("angle from the normal [deg]")
    ax.set_ylabel("|Δe_t| against Hertz–Mindlin")
    ax.legend(loc="lower left")
