"""The result of a run."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from . import _core
from .body import Body

__all__ = ["Drift", "Trajectory"]


class Drift(NamedTuple):
    """The largest departure of each invariant from its initial value, over the frames.

    The exact motion keeps all four; their drift measures the integration error.
    """

    energy: float
    """Relative: ``max |E(t) - E(0)| / E(0)``."""
    momentum: float
    """Relative change of ``|L|``."""
    momentum_world: float
    """``max |L_world(t) - L_world(0)| / |L(0)|``: the space-frame angular momentum vector."""
    q_norm: float
    """``max ||q(t)| - 1|``."""


@dataclass(frozen=True, eq=False)
class Trajectory:
    """Frames of a free rotation, time-major, with the run's cost and error measures.

    Attributes
    ----------
    t : ndarray, shape (frames,)
        Frame times; ``t[0] == 0`` and ``t[-1] == t_end``.
    omega : ndarray, shape (frames, 3)
        Body-frame angular velocity ``(u, v, w)``.
    q : ndarray, shape (frames, 4)
        Body-to-world unit quaternion, scalar first ``(Q, U, V, W)``.
    flip_times : ndarray, shape (n_flips,), or None
        Times of the flips: half-turns of the intermediate axis relative to the angular
        momentum, located within the step (see the README). None if not asked for.
    body : Body
    method : str
    dt : float
        The step actually taken: ``t_end / (frames - 1)`` split evenly, at most the ``dt``
        asked for; for an adaptive method, the mean accepted step.
    n_steps, nfev : int
        Steps taken (accepted) and right-hand-side evaluations (0 for the splittings,
        which evaluate none).
    drift : Drift
        The invariants' largest drift over the frames.
    n_rejected : int
        Steps an adaptive method tried and rejected; 0 for fixed-step methods.
    model : Deployment or Damper or None
        The model beyond the constant body that was run, if any (then `body` is the body at
        ``t = 0``, its principal moments).
    sigma : ndarray, shape (frames, 3), or None
        A damper's absolute angular velocity in body axes; None without a damper.
    momentum_world : ndarray, shape (frames, 3)
        Total angular momentum in space (body, plus damper where there is one); constant
        for the exact motion of every model.
    energy : ndarray, shape (frames,)
        Total kinetic energy: constant for the free body, changed by a deployment's internal
        work, never rising with a damper.
    """

    t: np.ndarray
    omega: np.ndarray
    q: np.ndarray
    flip_times: np.ndarray | None
    body: Body
    method: str
    dt: float
    n_steps: int
    nfev: int
    drift: Drift
    n_rejected: int = 0
    model: Any = None
    sigma: np.ndarray | None = None
    _invariants: dict[str, np.ndarray] = field(default_factory=dict, repr=False)

    def invariants(self) -> dict[str, np.ndarray]:
        """The invariants at every frame (computed once, in the core).

        Returns
        -------
        dict
            ``energy`` (frames,), ``momentum_body`` (frames, 3), ``momentum_world``
            (frames, 3) and ``q_norm`` (frames,).
        """
        if not self._invariants:
            self._invariants.update(_core.invariants(self.body._core, self.omega, self.q))
        return self._invariants

    @property
    def momentum_world(self) -> np.ndarray:
        """Total angular momentum in space at every frame, shape (frames, 3)."""
        return self.invariants()["momentum_world"]

    @property
    def energy(self) -> np.ndarray:
        """Total kinetic energy at every frame, shape (frames,)."""
        return self.invariants()["energy"]

    @property
    def _flip_count(self) -> int | str:
        return "?" if self.flip_times is None else len(self.flip_times)

    def __repr__(self) -> str:
        return (
            f"Trajectory(frames={len(self.t)}, t_end={self.t[-1]:g}, method={self.method!r}, "
            f"n_steps={self.n_steps}, flips={self._flip_count})"
        )
