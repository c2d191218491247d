"""The paper's scenarios as named presets.

The paper's figures use its explicit moments ``Ix = 52.0833, Iy = 27.0833, Iz = 41.6666``;
the box formula gives those moments with x and y swapped (erratum 2, see the README). Either
way z is the intermediate axis, so spin about z is unstable.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from .body import Body
from .simulate import simulate
from .trajectory import Trajectory

__all__ = ["PAPER_INERTIA", "Scenario", "SCENARIOS", "scenario"]

PAPER_INERTIA = (52.0833, 27.0833, 41.6666)
"""The paper's principal moments (Ix, Iy, Iz), as printed."""


@dataclass(frozen=True)
class Scenario:
    """A body, an initial state and a time span: everything a run needs."""

    name: str
    title: str
    inertia: tuple[float, float, float]
    omega0: tuple[float, float, float]
    t_end: float
    frames: int
    q0: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    dt: float = 1e-3

    @property
    def body(self) -> Body:
        return Body(self.inertia)

    def run(self, **overrides: Any) -> Trajectory:
        """Simulates the scenario; keyword arguments override those of :func:`simulate`."""
        kwargs: dict[str, Any] = dict(
            q0=self.q0, t_end=self.t_end, frames=self.frames, dt=self.dt
        )
        kwargs.update(overrides)
        return simulate(self.body, self.omega0, **kwargs)


SCENARIOS: dict[str, Scenario] = {
    s.name: s
    for s in (
        Scenario("example", "Fig. 2: spin about the intermediate axis, perturbed by 5e-6",
                 PAPER_INERTIA, (5e-6, 5e-6, 1.0), t_end=100.0, frames=201),
        Scenario("fig3a", "Fig. 3a: u0 = v0 = 0.01, w0 = 1",
                 PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=100.0, frames=201),
        Scenario("fig3b", "Fig. 3b: u0 = 0.01, v0 = 0.1, w0 = 0.03",
                 PAPER_INERTIA, (0.01, 0.1, 0.03), t_end=100.0, frames=201),
        Scenario("fig3c", "Fig. 3c: u0 = v0 = 0.01, w0 = 0.03, T = 900",
                 PAPER_INERTIA, (0.01, 0.01, 0.03), t_end=900.0, frames=201),
    )
}
"""The paper's scenarios by name: ``example`` (Fig. 2) and ``fig3a``, ``fig3b``, ``fig3c``."""


def scenario(name: str) -> Scenario:
    """The preset called `name`; ValueError lists the names on offer."""
    try:
        return SCENARIOS[name]
    except (KeyError, TypeError):
        raise ValueError(f"no scenario {name!r}; the presets are {sorted(SCENARIOS)}") from None
