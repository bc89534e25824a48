"""The Garland–Rogers rig the tests simulate (Garland & Rogers 2009; the bundled samples).

A 25.4 mm steel ball (R = 12.7 mm, ρ = 7850 kg/m³, E = 210 GPa, ν = 0.29) on a steel cap of
radius 25.4 mm: the ball, target and materials of a Scene; each test adds speed, angle, μ, e.
"""

from types import MappingProxyType

GR_RIG = MappingProxyType(  # read-only: shared by every test module
    dict(
        radius=0.0127,
        density=7850.0,
        E=210e9,
        nu=0.29,
        target_E=210e9,
        target_nu=0.29,
        target_radius=0.0254,
    )
)
