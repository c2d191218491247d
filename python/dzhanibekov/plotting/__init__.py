"""Everything drawn, with matplotlib: the figures of a scene (:mod:`.figures`), stability maps
of a sweep (:mod:`.maps`) and animations (:mod:`.animation`)."""

from . import animation, maps
from .figures import (
    FIGURE_FUNCTIONS,
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
    "compute",
    "phases_figure",
    "path_figure",
    "fig3_figure",
    "omega_figure",
    "invariants_figure",
    "polhode_figure",
    "FIGURE_FUNCTIONS",
]
