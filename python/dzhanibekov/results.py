"""The result of a run."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from . import _core
from . import _tables
from .body import Body
from .rotations import to_rotation

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

    def to_xarray(self) -> Any:
        """The frames as an ``xarray.Dataset`` (dims ``time``, ``axis``, ``quaternion``; the ``io`` extra).

        Examples
        --------
        >>> import dzhanibekov as dz
        >>> traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), frames=5)
        >>> dict(traj.to_xarray().sizes)
        {'time': 5, 'axis': 3, 'quaternion': 4, 'flip': 2}
        """
        return _tables.trajectory_dataset(self)

    def to_dataframe(self) -> Any:
        """The frames as a ``pandas.DataFrame`` (index ``t``, columns u v w Q U V W; the ``io`` extra)."""
        return _tables.trajectory_frame(self)

    @property
    def rotation(self) -> Any:
        """The attitude at every frame as one scipy ``Rotation`` stack of ``frames`` rotations,
        world-from-body: ``traj.rotation.apply(x_body)`` is ``dz.rotate(traj.q, x_body)``.

        Examples
        --------
        >>> import dzhanibekov as dz
        >>> traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=10.0, frames=3)
        >>> len(traj.rotation)
        3
        """
        return to_rotation(self.q)

    def euler(self, seq: str, degrees: bool = False) -> np.ndarray:
        """Euler angles of the attitude at every frame, shape (frames, 3), through scipy's
        ``Rotation.as_euler(seq, degrees)``: `seq` of three of ``xyz`` (extrinsic) or ``XYZ``
        (intrinsic), angles of the world-from-body rotation.

        Examples
        --------
        >>> import dzhanibekov as dz
        >>> traj = dz.simulate(dz.PAPER_INERTIA, (0.0, 0.0, 0.1), t_end=5 * 3.141592653589793,
        ...                    frames=2, method="exact")
        >>> traj.euler("ZYX", degrees=True)[-1].round(6).tolist()  # 0.1 rad/s for 5π: 90° about z
        [90.0, 0.0, 0.0]
        """
        angles: np.ndarray = self.rotation.as_euler(seq, degrees=degrees)
        return angles

    @property
    def _flip_count(self) -> int | str:
        return "?" if self.flip_times is None else len(self.flip_times)

    def __repr__(self) -> str:
        return (
            f"Trajectory(frames={len(self.t)}, t_end={self.t[-1]:g}, method={self.method!r}, "
            f"n_steps={self.n_steps}, flips={self._flip_count})"
        )
