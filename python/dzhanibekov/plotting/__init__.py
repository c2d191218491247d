"""Everything drawn, with matplotlib: the figures of a scene or a trajectory (:mod:`.figures`),
stability maps of a sweep (:mod:`.maps`), the animation (:func:`animation`, a
``FuncAnimation`` for notebooks) and its GIF/MP4 files (:mod:`.movie`)."""

from . import maps, movie
from .figures import (
    FIGURE_FUNCTIONS,
    animation,
    compute,
    fig3_figure,
    invariants_figure,
    omega_figure,
    path_figure,
    phases_figure,
    polhode_figure,
)

__all__ = [
    "animation",
    "maps",
    "movie",
    "compute",
    "phases_figure",
    "path_figure",
    "fig3_figure",
    "omega_figure",
    "invariants_figure",
    "polhode_figure",
    "FIGURE_FUNCTIONS",
]
