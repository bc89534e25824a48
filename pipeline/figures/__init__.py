r"""Figures, redrawn from the pipeline's results (matplotlib), grouped by what they show.

Every ``fig*`` function returns a :class:`matplotlib.figure.Figure` built without pyplot
(no global state, no ``plt.show``, nothing printed); save it with :func:`save`, which
writes atomically. All functions draw inside :func:`style`, the one place that sets fonts,
line widths and sizes, so the figures of one report look alike. To add a figure:

.. code-block:: python

    def fig8_forces(record, fits) -> Figure:
        with style():
            fig, ax = new_figure(width=SINGLE)
            ...
            return fig

Artists that tests (or a caller) need to find carry a ``gid`` (see each docstring), so a
test can check the plotted data, e.g. ``[a for a in fig.findobj() if a.get_gid() == "kink"]``.

The modules: :mod:`.style` (sizes, colours, :func:`style`, :func:`new_figure`,
:func:`save`), :mod:`.seed` (the seed paper's figures), :mod:`.fits` (fitted contact
parameters), :mod:`.campaigns` (many records). Every name is importable from
``pipeline.figures`` itself. The benchmarks draw their own charts beside their data
(``benchmarks/``).

The seed paper's figures and the fits:

- :func:`fig4_percussion_plane` — seed Fig. 4: Routh's plane of percussions for a ball on
  a tilted plane, lines LF, S, C, T, corner A, end points E1 (sliding) and E2 (sticking),
  friction angles and the angle β of seed eq. 6.
- :func:`fig6_disc_velocity` — analogue of seed Fig. 6: rigid-theory post-impact
  horizontal velocity of a ball dropped on a rotating disc against the disc's surface
  speed, with the kink u* between the sticking and sliding regimes.
- :func:`fig8_forces` — seed Fig. 8: a record's Fn, Ft samples, their polynomial fits and
  the fits' residuals.
- :func:`fig9_percussion_plane` — seed Fig. 9: the measured Pt(Pn) over Routh's broken
  line (LF, A, S, E1/E2; lines C and T), compression and restitution marked.
- :func:`fig_contact_fit` — a contact-parameter fit (:func:`pipeline.fit_contact`): the
  measured forces, the fitted model as the sensor records it, the contact force before the
  sensor, Routh's rigid Ft on the fitted Fn, and the weighted residuals.

Campaign figures (:func:`pipeline.campaign`; :func:`campaign_figures` draws them all):

- :func:`campaign_outcomes` — e_t, ω and rebound angle against incidence, measured, with
  rigid theory and the compliant model overlaid;
- :func:`campaign_friction` — μ against the initial tangential speed with the fitted law;
- :func:`campaign_restitution` — e against speed with both damping hypotheses;
- :func:`campaign_score` — the deviation from rigid theory against incidence.

References
----------
F.-C. Ciornei et al., MATEC Web Conf. 112, 07005 (2017), doi:10.1051/matecconf/201711207005,
Figs. 4, 6, 8 and 9. S. Alaci, F. C. Ciornei, C. Filote, J. Balkan Tribol. Assoc. 22(2), 1552 (2016)
(the rotating-disc rig).
"""

from __future__ import annotations

from .campaigns import (
    CAMPAIGN_FIGURES,
    campaign_figures,
    campaign_friction,
    campaign_outcomes,
    campaign_restitution,
    campaign_score,
)
from .fits import fig_contact_fit
from .seed import (
    default_scenes,
    disc_kinks,
    fig4_percussion_plane,
    fig6_disc_velocity,
    fig8_forces,
    fig9_percussion_plane,
)
from .style import COLORS, DOUBLE, SINGLE, STYLE, new_figure, panel_label, save, style

__all__ = [
    "STYLE",
    "SINGLE",
    "DOUBLE",
    "COLORS",
    "style",
    "new_figure",
    "save",
    "panel_label",
    "fig4_percussion_plane",
    "fig6_disc_velocity",
    "fig8_forces",
    "fig9_percussion_plane",
    "fig_contact_fit",
    "default_scenes",
    "disc_kinks",
    "campaign_outcomes",
    "campaign_friction",
    "campaign_restitution",
    "campaign_score",
    "campaign_figures",
    "CAMPAIGN_FIGURES",
]
