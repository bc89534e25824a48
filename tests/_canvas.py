"""Does a figure lie inside its own canvas? (issue 21: the reports show figures as drawn.)"""

from __future__ import annotations

from matplotlib.backends.backend_agg import FigureCanvasAgg

#: How far an artist may reach past the canvas [pt]: under one pixel at 150 dpi.
TOLERANCE_PT = 0.4


def outside_canvas(fig) -> dict:
    """{side: how far [pt] the figure's artists reach past that side of its canvas} for the
    sides they cross, after one draw at the figure's own size and dpi (as a notebook and
    the reports show it): the renderer's tight box of every artist against the figure's."""
    renderer = FigureCanvasAgg(fig).get_renderer()
    fig.draw(renderer)
    tight = fig.get_tightbbox(renderer)  # inches
    width, height = fig.get_size_inches()
    reach = {
        "left": -tight.x0,
        "bottom": -tight.y0,
        "right": tight.x1 - width,
        "top": tight.y1 - height,
    }
    return {side: round(72.0 * v, 1) for side, v in reach.items() if 72.0 * v > TOLERANCE_PT}
