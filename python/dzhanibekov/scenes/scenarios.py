"""The paper's scenarios by name: the shipped scenes of its figures (kept for compatibility).

The paper's figures use its explicit moments ``Ix = 52.0833, Iy = 27.0833, Iz = 41.6666``;
the box formula gives those moments with x and y swapped (erratum 2, see the README). Either
way z is the intermediate axis, so spin about z is unstable.

A scenario is a :class:`~dzhanibekov.scene.Scene`; :data:`SCENARIOS` holds the paper's, and
:func:`scenario` finds any shipped scene by name.
"""

from __future__ import annotations

from .scene import PAPER_SCENES, SCENES, Scene

__all__ = ["PAPER_INERTIA", "Scenario", "SCENARIOS", "scenario"]

PAPER_INERTIA = (52.0833, 27.0833, 41.6666)
"""The paper's principal moments (Ix, Iy, Iz), as printed."""

Scenario = Scene
"""The former name of :class:`~dzhanibekov.scene.Scene`, whose first fields it shares."""

SCENARIOS: dict[str, Scene] = {name: SCENES[name] for name in PAPER_SCENES}
"""The paper's scenarios by name: ``example`` (Fig. 2) and ``fig3a``, ``fig3b``, ``fig3c``."""


def scenario(name: str) -> Scene:
    """The shipped scene called `name`; ValueError lists the names on offer."""
    try:
        return SCENES[name]
    except (KeyError, TypeError):
        raise ValueError(f"`name` must name a shipped scene, but there is no scenario {name!r}; "
                         f"the presets are {sorted(SCENES)}") from None
