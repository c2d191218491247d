"""Everything drawn, with matplotlib: the figures of a scene or a trajectory (:mod:`.figures`),
stability maps of a sweep (:mod:`.maps`), the dual-spin and gravity-gradient maps
(:mod:`.stability`), a Monte Carlo study's figure (:mod:`.study`), the
animation (:func:`animation`, a ``FuncAnimation`` for notebooks) and its GIF/MP4 files
(:mod:`.movie`), the energy sinks' figures (:mod:`.sinks`, :mod:`.capture`)."""

from . import maps, movie, stability, study
from .figures import (
    FIGURE_FUNCTIONS,
    animation,
    compute,
    fig3_figure,
    invariants_figure,
    lvlh_figure,
    omega_figure,
    path_figure,
    phases_figure,
    polhode_figure,
    wheel_off_figure,
)
from .control import detumble_figure, pointing_figure
from .stability import dual_spin_figure, gravity_gradient_figure
from . import capture, sinks
from .capture import capture_figure
from .sinks import energy_balance_figure, part_motion_figure
from .study import study_figure

__all__ = [
    "animation",
    "maps",
    "movie",
    "study",
    "study_figure",
    "stability",
    "dual_spin_figure",
    "gravity_gradient_figure",
    "compute",
    "phases_figure",
    "path_figure",
    "fig3_figure",
    "omega_figure",
    "invariants_figure",
    "polhode_figure",
    "lvlh_figure",
    "wheel_off_figure",
    "detumble_figure",
    "pointing_figure",
    "FIGURE_FUNCTIONS",
    "sinks",
    "capture",
    "energy_balance_figure",
    "part_motion_figure",
    "capture_figure",
]

FIGURE_FUNCTIONS.update(energy_balance=energy_balance_figure, part_motion=part_motion_figure,
                        capture=capture_figure)
