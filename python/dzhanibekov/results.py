"""The results of runs, one family: a :class:`Trajectory` (one run's frames), a
:class:`Summary` (one run without frames), a :class:`Batch` (many runs' frames) and a
:class:`Sweep` (many runs, one number each). All tell ``flips`` (how many), ``t_end`` and a
``verdict`` in words, the same way; all pickle and copy (they are plain arrays, numbers and
the run's own :class:`System`), and whatever they derive (energy, angular momentum) they
derive from that system, in the core.

>>> import dzhanibekov as dz
>>> traj = dz.simulate(dz.Body(dz.PAPER_INERTIA), (0.01, 0.01, 1.0), t_end=100.0)
>>> traj.flips, traj.t_end, traj.verdict
(2, 100.0, '2 flips in [0, 100]')
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property
from collections.abc import Callable, Iterator
from typing import Any, overload

import numpy as np

from . import _core
from . import _tables
from ._args import check_size
from .body import Body, tensor_moments
from .rotations import to_rotation
from .system import System, Systems

__all__ = ["Drift", "Trajectory", "Summary", "BatchDrift", "Batch", "Sweep", "DeploymentSweep",
           "verdict", "observe", "run_drift", "trajectory"]


def verdict(flips: int, t_end: float) -> str:
    """A run's stability verdict in words: how often it flipped in ``[0, t_end]``."""
    if not flips:
        return f"no flip in [0, {t_end:g}]"
    return f"{flips} flip{'s' if flips > 1 else ''} in [0, {t_end:g}]"


_FREE_KEEPS = ("energy", "momentum", "momentum_world", "q_norm")


@dataclass(frozen=True)
class Drift:
    """The largest departure of each invariant from its initial value, over the frames.

    `kept` names what the run's model keeps (see :attr:`System.conserved`): the drift of
    those measures the integration error; the others change by the model's own law (a
    deployment's work and a damper's loss on the energy) and their entries say by how much.
    Iterating gives the measures (energy, momentum, momentum_world, q_norm, and the Jacobi
    integral's where the model has one), so ``max(traj.drift)`` is the worst of them.
    """

    energy: float
    """Relative: ``max |E(t) - E(0)| / E(0)``; absolute where ``E(0) = 0`` (a body started
    at rest), as is each measure below whose initial value is zero."""
    momentum: float
    """Relative change of ``|L|``."""
    momentum_world: float
    """``max |L_world(t) - L_world(0)| / |L(0)|``: the space-frame angular momentum vector."""
    q_norm: float
    """``max ||q(t)| - 1|``."""
    jacobi: float | None = None
    """Relative change of the Jacobi integral, for a model that has one; None otherwise."""
    kept: tuple[str, ...] = _FREE_KEEPS
    """What the model keeps, by the names of the fields above."""
    energy_balance: float | None = None
    """Relative change of the energy balance (the energy plus the work the parts dissipated),
    for a system whose parts dissipate; None otherwise."""

    def __iter__(self) -> Iterator[float]:
        yield from (self.energy, self.momentum, self.momentum_world, self.q_norm)
        if self.jacobi is not None:
            yield self.jacobi
        if self.energy_balance is not None:
            yield self.energy_balance

    def __getitem__(self, i: Any) -> Any:
        return tuple(self)[i]

    def __len__(self) -> int:
        return 4 + (self.jacobi is not None) + (self.energy_balance is not None)


def observe(system: System, t: np.ndarray, omega: np.ndarray, q: np.ndarray,
            parts: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The energy and the total angular momentum in body axes and in space at every frame,
    as the run's own system defines them (computed in the core)."""
    check_size(len(t) * 8 * 8, f"the invariants at {len(t)} frames",
               "compute them over fewer frames (a slice of the run)")
    state = (np.concatenate([parts[name] for name in system.part_names], axis=1)
             if system.part_names else np.empty((len(t), 0)))
    energy, body, world = _core.observe(system._core, np.ascontiguousarray(t, dtype=np.float64),
                                        np.ascontiguousarray(omega), np.ascontiguousarray(q),
                                        np.ascontiguousarray(state, dtype=np.float64))
    return {"energy": energy, "momentum_body": body, "momentum_world": world,
            "q_norm": np.linalg.norm(q, axis=-1)}


def part_rates(system: System, t: np.ndarray, omega: np.ndarray, q: np.ndarray,
               parts: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The rates of the coordinates of each part whose mass moves (its state's first field:
    a spring's displacement, a hinge's angle, a pendulum's direction) at every frame, by the
    part's name: what the run's right-hand side gives them there, from the mass-matrix solve
    :func:`observe` makes (computed in the core)."""
    moving = [name for name in system.part_names
              if "moving mass" in _core.model_info(_tables.model_of_state(name) or "").traits]
    if not moving:
        return {}
    check_size(len(t) * 8 * 2 * sum(system.part_widths),
               f"the parts' rates at {len(t)} frames",
               "compute them over fewer frames (a slice of the run)")
    state = np.concatenate([parts[name] for name in system.part_names], axis=1)
    rates = split_parts(system, _core.part_rates(
        system._core, np.ascontiguousarray(t, dtype=np.float64), np.ascontiguousarray(omega),
        np.ascontiguousarray(q), np.ascontiguousarray(state, dtype=np.float64)))
    return {name: np.ascontiguousarray(rates[name][:, :_tables.state_fields(name)[0][2]])
            for name in moving}


def split_parts(system: System, state: np.ndarray | None) -> dict[str, np.ndarray]:
    """The parts' state (..., k) split by part name."""
    if state is None or not system.part_names:
        return {}
    out, at = {}, 0
    for name, width in zip(system.part_names, system.part_widths):
        out[name] = state[..., at:at + width]
        at += width
    return out


@dataclass(frozen=True, eq=False)
class Trajectory:
    """The frames of one run, time-major, with its system, cost and error measures.

    Attributes
    ----------
    t : ndarray, shape (frames,)
        Frame times; ``t[0] == 0`` and ``t[-1] == t_end``.
    omega : ndarray, shape (frames, 3)
        Body-frame angular velocity ``(u, v, w)``, in the body's own axes.
    q : ndarray, shape (frames, 4)
        Body-to-world unit quaternion of the body's own axes, scalar first
        ``(Q, U, V, W)``: ``dz.rotate(traj.q, points)`` turns points given in those axes.
    flip_times : ndarray, shape (n_flips,), or None
        Times of the flips: half-turns of the intermediate axis relative to the angular
        momentum, located within the step (see the README). None if not asked for.
    system : System
        What was run: the body with its parts.
    method : str
    dt : float
        The step actually taken: ``t_end / (frames - 1)`` split evenly, at most the ``dt``
        asked for; for an adaptive method, the mean accepted step; 0 for ``"exact"``, which
        takes none.
    n_steps, nfev : int
        Steps taken (accepted) and right-hand-side evaluations (0 for the splittings,
        which evaluate none).
    drift : Drift
        The invariants' largest drift over the frames, and what the model keeps.
    n_rejected : int
        Steps an adaptive method tried and rejected; 0 for fixed-step methods.
    parts : dict of str to ndarray
        Each part's state at every frame, by the part's name: a damper's sphere rates in body
        axes, ``parts["damper"]`` of shape (frames, 3). Empty for a body without parts.
    """

    t: np.ndarray
    omega: np.ndarray
    q: np.ndarray
    flip_times: np.ndarray | None
    system: System
    method: str
    dt: float
    n_steps: int
    nfev: int
    drift: Drift
    n_rejected: int = 0
    parts: dict[str, np.ndarray] = field(default_factory=dict)
    _observed: dict[str, np.ndarray] = field(default_factory=dict, repr=False)
    _flat_time: float | None = field(default=None, repr=False)
    """The time the spin went flat, located in the run (NaN: not by the end; see
    :func:`~dzhanibekov.flat_spin_time`); None for a run that did not watch for it."""

    @property
    def body(self) -> Any:
        """The system's body: a :class:`Body` or a :class:`Deployment`."""
        return self.system.body

    def invariants(self) -> dict[str, np.ndarray]:
        """The invariants at every frame, as the run's own system defines them (computed once,
        in the core).

        Returns
        -------
        dict
            ``energy`` (frames,), ``momentum_body`` (frames, 3) (the total angular momentum
            in the body's own axes), ``momentum_world`` (frames, 3) and ``q_norm`` (frames,).
        """
        if not self._observed:
            self._observed.update(observe(self.system, self.t, self.omega, self.q, self.parts))
        return self._observed

    def to_xarray(self) -> Any:
        """The run as an ``xarray.Dataset`` (dims ``time``, ``axis``, ``quaternion``; the
        ``io`` extra): frames, parts' state, energy and angular momentum, the system.

        Examples
        --------
        >>> import dzhanibekov as dz
        >>> traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), frames=5)
        >>> dict(traj.to_xarray().sizes)
        {'time': 5, 'axis': 3, 'quaternion': 4, 'axis_': 3, 'flip': 2}
        """
        return _tables.trajectory_dataset(self)

    def to_dataframe(self) -> Any:
        """The frames as a ``pandas.DataFrame`` (index ``time``; columns u v w Q U V W, the
        parts' state, energy and L in space; the ``io`` extra)."""
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

    @cached_property
    def part_rates(self) -> dict[str, np.ndarray]:
        """The rates of the coordinates of each part whose mass moves, by the part's name, at
        every frame: a spring-mass's ``ẋ`` and a hinge's ``β̇``, shape (frames, 1); a slosh
        pendulum's ``ṅ``, shape (frames, 3) (its angular velocity relative to the body is
        ``ν = n × ṅ``). :attr:`parts` holds their coordinates and conjugate momenta; these
        are what the run's own equations give from them (the mass-matrix solve, computed
        once, in the core). Empty without such parts.

        Examples
        --------
        >>> import dzhanibekov as dz
        >>> body = dz.Body.from_tensor([[3, 0, 0], [0, 1, 0], [0, 0, 2]], mass=1.0)
        >>> spring = dz.SpringMassDamper(0.1, (0.0, 0.0, 0.5), (1.0, 0.0, 0.0), 2.0, 0.1)
        >>> traj = dz.simulate(dz.System(body, parts=[spring]), (0.01, 0.01, 1.0),
        ...                    t_end=1.0, frames=3)
        >>> traj.part_rates["spring_mass"].shape
        (3, 1)
        """
        return part_rates(self.system, self.t, self.omega, self.q, self.parts)

    @property
    def energy(self) -> np.ndarray:
        """Total kinetic energy at every frame, shape (frames,): constant for the free body,
        changed by a deployment's internal work, never rising with a damper."""
        return self.invariants()["energy"]

    @property
    def momentum_body(self) -> np.ndarray:
        """Total angular momentum (body and parts) in the body's own axes, shape (frames, 3)."""
        return self.invariants()["momentum_body"]

    @property
    def momentum_world(self) -> np.ndarray:
        """Total angular momentum in space at every frame, shape (frames, 3); constant for
        the exact motion of every torque-free system."""
        return self.invariants()["momentum_world"]

    @property
    def t_end(self) -> float:
        """The end of the run: the last frame's time."""
        return float(self.t[-1])

    @property
    def flips(self) -> int | None:
        """How many times the body flipped; None if flips were not asked for."""
        return None if self.flip_times is None else len(self.flip_times)

    @property
    def verdict(self) -> str | None:
        """The run's stability verdict in words (None if flips were not asked for)."""
        return None if self.flips is None else verdict(self.flips, self.t_end)

    @property
    def _flip_count(self) -> int | str:
        return "?" if self.flips is None else self.flips

    def __repr__(self) -> str:
        return (
            f"Trajectory(frames={len(self.t)}, t_end={self.t[-1]:g}, method={self.method!r}, "
            f"n_steps={self.n_steps}, flips={self._flip_count})"
        )


@dataclass(frozen=True, eq=False)
class Summary:
    """What a run measured, without its frames.

    Attributes
    ----------
    flip_times : ndarray, shape (n_flips,)
        Times of the flips (half-turns of the intermediate axis relative to the angular
        momentum; see the README), located within the step.
    drift : Drift
        The invariants' largest drift over the frame times.
    t_end : float
    system : System
    method : str
    dt : float
        The step actually taken.
    n_steps, nfev : int
        Steps taken and right-hand-side evaluations.
    """

    flip_times: np.ndarray
    drift: Drift
    t_end: float
    system: System
    method: str
    dt: float
    n_steps: int
    nfev: int

    @property
    def body(self) -> Any:
        """The system's body."""
        return self.system.body

    @property
    def flips(self) -> int:
        """How many times the body flipped."""
        return len(self.flip_times)

    @property
    def verdict(self) -> str:
        """The run's stability verdict in words: how often it flipped in ``[0, t_end]``."""
        return verdict(self.flips, self.t_end)

    def __repr__(self) -> str:
        return (
            f"Summary(flips={self.flips}, t_end={self.t_end:g}, method={self.method!r}, "
            f"n_steps={self.n_steps})"
        )


@dataclass(frozen=True, eq=False)
class BatchDrift:
    """The invariants' largest drift over the frames, one value per run (see `Drift`);
    iterating gives the measures, as `Drift` does."""

    energy: np.ndarray
    """Relative: ``max |E(t) - E(0)| / E(0)``; absolute where ``E(0) = 0`` (a body started
    at rest), as is each measure below whose initial value is zero."""
    momentum: np.ndarray
    """Relative change of ``|L|``."""
    momentum_world: np.ndarray
    """``max |L_world(t) - L_world(0)| / |L(0)|``."""
    q_norm: np.ndarray
    """``max ||q(t)| - 1|``."""
    jacobi: np.ndarray | None = None
    """Relative change of the Jacobi integral (NaN for a run whose model has none); None when
    no run's model has one."""
    kept: tuple[str, ...] = _FREE_KEEPS
    """What the runs' model keeps."""
    energy_balance: np.ndarray | None = None
    """Relative change of the energy balance (NaN for a run whose model has none); None when
    no run's model has one."""

    def __iter__(self) -> Iterator[np.ndarray]:
        yield from (self.energy, self.momentum, self.momentum_world, self.q_norm)
        if self.jacobi is not None:
            yield self.jacobi
        if self.energy_balance is not None:
            yield self.energy_balance

    def __getitem__(self, i: Any) -> Any:
        return tuple(self)[i]

    def __len__(self) -> int:
        return 4 + (self.jacobi is not None) + (self.energy_balance is not None)

    @classmethod
    def of(cls, measure: Callable[[str], np.ndarray], jacobi: np.ndarray | None = None,
           kept: tuple[str, ...] = _FREE_KEEPS,
           energy_balance: np.ndarray | None = None) -> BatchDrift:
        """The drift whose four always-present measures `measure(name)` gives."""
        return cls(measure("energy"), measure("momentum"), measure("momentum_world"),
                   measure("q_norm"), jacobi, kept, energy_balance)

    def _map(self, f: Callable[[np.ndarray], np.ndarray]) -> BatchDrift:
        """`f` applied to every measure."""
        return BatchDrift.of(lambda k: f(getattr(self, k)),
                             None if self.jacobi is None else f(self.jacobi), self.kept,
                             None if self.energy_balance is None else f(self.energy_balance))

    def reshape(self, shape: tuple[int, ...]) -> BatchDrift:
        """The same values in `shape`."""
        return self._map(lambda a: np.reshape(a, shape))

    def take(self, key: Any) -> BatchDrift:
        """The runs at `key`."""
        return self._map(lambda a: a[key])

    def row(self, i: int) -> Drift:
        """Run `i`'s drift."""
        def optional(a: np.ndarray | None) -> float | None:
            return None if a is None or np.isnan(a[i]) else float(a[i])

        return Drift(float(self.energy[i]), float(self.momentum[i]),
                     float(self.momentum_world[i]), float(self.q_norm[i]),
                     optional(self.jacobi), self.kept, optional(self.energy_balance))


def batch_drift(columns: Any) -> BatchDrift:
    """The core's per-run drift columns as a :class:`BatchDrift`."""
    energy, momentum, momentum_world, q_norm, jacobi, balance = columns.drift
    kept = tuple(columns.kept) or _FREE_KEEPS

    def optional(name: str, a: np.ndarray) -> np.ndarray | None:
        return a if name in kept or not np.isnan(a).all() else None

    return BatchDrift(energy, momentum, momentum_world, q_norm, optional("jacobi", jacobi),
                      kept, optional("energy_balance", balance))


def run_drift(run: Any) -> Drift:
    """The drift of the core's one run (`_core.Run`)."""
    energy, momentum, momentum_world, q_norm, jacobi, balance = run.drift
    return Drift(energy, momentum, momentum_world, q_norm, jacobi,
                 tuple(run.kept) or _FREE_KEEPS, balance)


def trajectory(run: Any, system: System, method: str) -> Trajectory:
    """The core's one run (`_core.Run`) of `system` by `method` as a :class:`Trajectory`."""
    return Trajectory(t=run.t, omega=run.omega, q=run.q, flip_times=run.flip_times,
                      system=system, method=method, dt=run.dt, n_steps=run.n_steps,
                      nfev=run.nfev, drift=run_drift(run), n_rejected=run.n_rejected,
                      parts=split_parts(system, run.parts), _flat_time=run.flat_time)


@dataclass(frozen=True, eq=False)
class Batch:
    """Frames of M runs over one frame grid, run-major.

    ``batch[i]`` is run i as a :class:`Trajectory`, equal bit for bit to ``simulate`` of
    its inputs alone (with the same ``dt``).

    Attributes
    ----------
    t : ndarray, shape (frames,)
        Frame times, shared by every run.
    omega : ndarray, shape (M, frames, 3)
        Body-frame angular velocity ``(u, v, w)`` of each run, in its body's own axes.
    q : ndarray, shape (M, frames, 4)
        Body-to-world unit quaternion, scalar first, of each run.
    flip_times : tuple of M ndarrays, or None
        Each run's flip times (see :func:`~dzhanibekov.simulate`), as many as it has; None if
        not asked for. :attr:`flip_times_padded` is the same as one (M, F) array padded
        with NaN, as :meth:`to_xarray` and files keep it.
    systems : Systems
        Each run's system (``systems[i]``).
    method : str
    dt : ndarray, shape (M,)
        The step each run took (for an adaptive method, its mean accepted step).
    n_steps, nfev, n_rejected : ndarray of int64, shape (M,)
        Steps, right-hand-side evaluations and rejected steps of each run.
    drift : BatchDrift
        The invariants' largest drift over the frames, per run.
    parts : dict of str to ndarray
        Each part's state, by name, with a leading run axis: ``parts["damper"]`` of shape
        (M, frames, 3).
    """

    t: np.ndarray
    omega: np.ndarray
    q: np.ndarray
    _flip_times: np.ndarray | None = field(repr=False)
    """Every run's flip times, one after the other; run i's are
    ``_flip_times[_flip_offsets[i]:_flip_offsets[i + 1]]``."""
    _flip_offsets: np.ndarray | None = field(repr=False)
    systems: Systems
    method: str
    dt: np.ndarray
    n_steps: np.ndarray
    nfev: np.ndarray
    n_rejected: np.ndarray
    drift: BatchDrift
    parts: dict[str, np.ndarray] = field(default_factory=dict)
    _observed: dict[str, np.ndarray] = field(default_factory=dict, repr=False)
    _flat_times: np.ndarray | None = field(default=None, repr=False)
    """Each run's :attr:`Trajectory._flat_time`, shape (M,); None where not watched."""

    def to_xarray(self) -> Any:
        """Every run as an ``xarray.Dataset`` (dims ``run``, ``time``, ``axis``, ``quaternion``;
        the ``io`` extra).

        Examples
        --------
        >>> import dzhanibekov as dz
        >>> batch = dz.simulate(dz.PAPER_INERTIA, [(0.01, 0.01, 1.0), (0, 1, 0.01)], frames=5)
        >>> batch.to_xarray().q.dims
        ('run', 'time', 'quaternion')
        """
        return _tables.batch_dataset(self)

    def to_dataframe(self) -> Any:
        """Every run's frames as a ``pandas.DataFrame`` (index (``run``, ``time``), columns as
        :meth:`Trajectory.to_dataframe`; the ``io`` extra)."""
        return _tables.batch_frame(self)

    def __len__(self) -> int:
        return len(self.omega)

    @property
    def inertia(self) -> np.ndarray:
        """Each run's principal moments at ``t = 0``, shape (M, 3), in the body frame's
        order as :attr:`Body.inertia` (a deployment's, of its first knot)."""
        if self.systems.moments is not None:
            return self.systems.moments
        return np.array([_moments(self.systems[i]) for i in range(len(self))]).reshape(-1, 3)

    @cached_property
    def flip_times(self) -> tuple[np.ndarray, ...] | None:
        """Each run's flip times (see :func:`~dzhanibekov.simulate`), a tuple of M arrays
        (views) of each run's own length; None if flips were not asked for. The same times
        as one array are :attr:`flip_times_padded`."""
        if self._flip_times is None or self._flip_offsets is None:
            return None
        bounds = self._flip_offsets.tolist()
        return tuple(self._flip_times[a:b] for a, b in zip(bounds[:-1], bounds[1:]))

    @property
    def flip_times_padded(self) -> np.ndarray | None:
        """:attr:`flip_times` as one array of shape (M, F), F the most flips of any run, each
        row padded with NaN beyond its run's flips: what :meth:`to_xarray` (``flip_times``,
        dims ``run``, ``flip``) and files hold; None if flips were not asked for.

        Examples
        --------
        >>> import dzhanibekov as dz
        >>> batch = dz.simulate(dz.PAPER_INERTIA, [(0.01, 0.01, 1.0), (0, 0, 1.0)])
        >>> [len(f) for f in batch.flip_times], batch.flip_times_padded.shape
        ([2, 0], (2, 2))
        >>> bool(np.isnan(batch.flip_times_padded[1]).all())
        True
        """
        times = self.flip_times
        if times is None:
            return None
        padded = np.full((len(times), max((len(f) for f in times), default=0)), np.nan)
        for i, row in enumerate(times):
            padded[i, : len(row)] = row
        return padded

    @overload
    def __getitem__(self, i: int) -> Trajectory: ...

    @overload
    def __getitem__(self, i: slice) -> Batch: ...

    def __getitem__(self, i: int | slice) -> Trajectory | Batch:
        """Run `i` as a :class:`Trajectory` (views of the batch's arrays); a slice of runs as a
        :class:`Batch`."""
        if isinstance(i, slice):
            return self._runs(range(len(self))[i])
        if not isinstance(i, (int, np.integer)) or isinstance(i, bool):
            raise TypeError(f"a batch is indexed by run number or a slice, got {type(i).__name__}")
        i = range(len(self))[i]  # negative indices, and IndexError beyond
        return Trajectory(
            t=self.t,
            omega=self.omega[i],
            q=self.q[i],
            flip_times=self._run_flip_times(i),
            system=self.systems[i],
            method=self.method,
            dt=float(self.dt[i]),
            n_steps=int(self.n_steps[i]),
            nfev=int(self.nfev[i]),
            drift=self.drift.row(i),
            n_rejected=int(self.n_rejected[i]),
            parts={k: v[i] for k, v in self.parts.items()},
            _observed={k: v[i] for k, v in self._observed.items()},
            _flat_time=None if self._flat_times is None else float(self._flat_times[i]),
        )

    def invariants(self) -> dict[str, np.ndarray]:
        """Each run's invariants at every frame (see :meth:`Trajectory.invariants`), with a
        leading run axis; computed once, in the core."""
        if not self._observed and len(self):
            runs = [observe(self.systems[i], self.t, self.omega[i], self.q[i],
                            {k: v[i] for k, v in self.parts.items()}) for i in range(len(self))]
            self._observed.update({k: np.stack([r[k] for r in runs]) for k in runs[0]})
        return self._observed

    @cached_property
    def part_rates(self) -> dict[str, np.ndarray]:
        """Each run's :attr:`Trajectory.part_rates`, with a leading run axis."""
        if not len(self):
            return {}
        runs = [part_rates(self.systems[i], self.t, self.omega[i], self.q[i],
                           {k: v[i] for k, v in self.parts.items()}) for i in range(len(self))]
        return {k: np.stack([r[k] for r in runs]) for k in runs[0]}

    @property
    def energy(self) -> np.ndarray:
        """Each run's total kinetic energy at every frame, shape (M, frames)."""
        return self.invariants()["energy"]

    @property
    def momentum_body(self) -> np.ndarray:
        """Each run's total angular momentum in its body's axes, shape (M, frames, 3)."""
        return self.invariants()["momentum_body"]

    @property
    def momentum_world(self) -> np.ndarray:
        """Each run's total angular momentum in space at every frame, shape (M, frames, 3)."""
        return self.invariants()["momentum_world"]

    @property
    def rotation(self) -> Any:
        """Every run's attitude at every frame as one scipy ``Rotation`` stack, run-major
        (``M · frames`` rotations, world-from-body).

        Examples
        --------
        >>> import dzhanibekov as dz
        >>> batch = dz.simulate(dz.PAPER_INERTIA, [(0.01, 0.01, 1.0), (0, 1, 0.01)], frames=3)
        >>> len(batch.rotation)
        6
        """
        return to_rotation(self.q.reshape(-1, 4))

    def euler(self, seq: str, degrees: bool = False) -> np.ndarray:
        """Euler angles of every run's attitude at every frame, shape (M, frames, 3) (see
        :meth:`Trajectory.euler`)."""
        angles: np.ndarray = self.rotation.as_euler(seq, degrees=degrees)
        return angles.reshape(self.q.shape[:2] + (3,))

    def _run_flip_times(self, i: int) -> np.ndarray | None:
        if self._flip_times is None or self._flip_offsets is None:
            return None
        return self._flip_times[int(self._flip_offsets[i]):int(self._flip_offsets[i + 1])]

    def _runs(self, rows: range) -> Batch:
        """The runs `rows` (a range with a step) as a batch of their own."""
        take = slice(rows.start, rows.stop, rows.step) if len(rows) else slice(0, 0)
        times, offsets = self._flip_times, self._flip_offsets
        if times is not None and offsets is not None:
            kept = [times[int(offsets[i]):int(offsets[i + 1])] for i in rows]
            times = np.concatenate(kept) if kept else times[:0]
            offsets = np.concatenate([[0], np.cumsum([len(k) for k in kept], dtype=np.int64)])
        return replace(self, omega=self.omega[take], q=self.q[take], _flip_times=times,
                       _flip_offsets=offsets, systems=self.systems[take], dt=self.dt[take],
                       n_steps=self.n_steps[take], nfev=self.nfev[take],
                       n_rejected=self.n_rejected[take], drift=self.drift.take(take),
                       parts={k: v[take] for k, v in self.parts.items()},
                       _observed={k: v[take] for k, v in self._observed.items()},
                       _flat_times=None if self._flat_times is None else self._flat_times[take])

    @property
    def t_end(self) -> float:
        """The end of the runs: the last frame's time."""
        return float(self.t[-1])

    @property
    def verdict(self) -> tuple[str, ...] | None:
        """Each run's stability verdict in words; None if flips were not asked for."""
        flips = self.flips
        return None if flips is None else tuple(verdict(int(n), self.t_end) for n in flips)

    @property
    def flips(self) -> np.ndarray | None:
        """How many times each run flipped, shape (M,); None if flips were not asked for."""
        if self._flip_offsets is None:
            return None
        counts: np.ndarray = np.diff(self._flip_offsets)
        return counts

    def __repr__(self) -> str:
        return (
            f"Batch(runs={len(self)}, frames={len(self.t)}, t_end={self.t[-1]:g}, "
            f"method={self.method!r})"
        )


def _moments(system: System) -> tuple[float, float, float]:
    """A system's principal moments at ``t = 0``."""
    body = system.body
    if isinstance(body, Body):
        return body.inertia
    return tensor_moments(system.tensor_at(0.0))


class _Statuses:
    """What a sweep's runs share: a `status` per run, and which runs finished."""

    status: np.ndarray

    @property
    def ok(self) -> np.ndarray:
        """Which runs finished (`status` ``"ok"``)."""
        finished: np.ndarray = self.status == "ok"
        return finished

    @property
    def shape(self) -> tuple[int, ...]:
        """The shape of the starts, and of each per-run array (``(M,)`` for deployments)."""
        return tuple(self.status.shape)

    def __len__(self) -> int:
        return int(self.status.size)


@dataclass(frozen=True, eq=False)
class Sweep(_Statuses):
    """What every run of a sweep measured, shaped as the sweep's starts.

    With starts of shape ``S + (3,)`` (say ``(n_u, n_v, 3)`` from :func:`grid`), each
    per-run array has shape ``S``.

    Attributes
    ----------
    inertia, omega0 : ndarray, shape S + (3,)
        Each run's principal moments and initial body rates.
    q0 : ndarray, shape S + (4,)
        Each run's initial attitude, as given.
    flips : ndarray of int64, shape S
        How many times each run flipped (see :func:`~dzhanibekov.simulate`); −1 for a run
        that did not finish (see `status`).
    first_flip : ndarray, shape S
        The time of the first flip; NaN if none.
    period : ndarray, shape S
        The measured flip period, the mean time between consecutive flips; NaN with fewer
        than two flips.
    exact_period : ndarray, shape S
        The exact flip period ``2K(m)/λ`` (:func:`~dzhanibekov.flip_period`); ``inf`` for
        motions that never flip.
    tilt : ndarray, shape S
        The largest tilt of the spin axis, radians in ``[0, π]``: the largest angle, over
        the initial state and every step, between the angular momentum ``L`` and the body
        axis nearest ``L`` at ``t = 0`` (directed to its side): ``arccos(min_t s I_k ω_k(t)
        / |L(0)|)``. Below 90° that axis only wobbles about ``L``; above, it turned over
        (every start nearest the intermediate axis, and starts beyond the separatrix that
        circulate the other stable axis). 0 for a body at rest. For ``method="exact"``,
        measured at the frames.
    drift : BatchDrift
        Each run's largest drift of the invariants over the frames.
    t_end : float
    method : str
    dt : ndarray, shape S
        The step each run took (its mean accepted step for an adaptive method).
    n_steps, nfev : ndarray of int64, shape S
    status : ndarray of str, shape S
        How each run ended: ``"ok"``, or why it did not finish — ``"diverged"`` (the state
        stopped being finite: a step beyond the method's stability limit), ``"too many
        steps"`` (an adaptive run needing more than `max_steps` attempts), ``"too many
        flips"``. A sweep keeps going past such runs; their numbers are NaN (flips −1,
        n_steps 0), all but `exact_period`, which is the start's.
    """

    inertia: np.ndarray
    omega0: np.ndarray
    q0: np.ndarray
    flips: np.ndarray
    first_flip: np.ndarray
    period: np.ndarray
    exact_period: np.ndarray
    tilt: np.ndarray
    drift: BatchDrift
    t_end: float
    method: str
    dt: np.ndarray
    n_steps: np.ndarray
    nfev: np.ndarray
    status: np.ndarray

    def to_xarray(self) -> Any:
        """What every run measured as an ``xarray.Dataset`` (one dim per axis of the starts, named ``u0``… ``Iz`` with their values when from :func:`grid`; the ``io`` extra).

        Examples
        --------
        >>> import dzhanibekov as dz
        >>> s = dz.sweep(dz.PAPER_INERTIA, dz.grid([0.1, 0.2], [0.0, 0.5, 1.0], 1.0), t_end=10.0)
        >>> s.to_xarray().flips.dims
        ('u0', 'v0')
        """
        return _tables.sweep_dataset(self)

    def to_dataframe(self) -> Any:
        """What every run measured as a ``pandas.DataFrame`` (one row per run; the ``io`` extra)."""
        return _tables.sweep_frame(self)


    @property
    def verdict(self) -> np.ndarray:
        """Each run's stability verdict in words, shape S."""
        words = [verdict(int(n), self.t_end) if status == "ok" else f"did not finish ({status})"
                 for n, status in zip(self.flips.ravel(), self.status.ravel())]
        return np.array(words, dtype=object).reshape(self.shape)

    def __getitem__(self, key: Any) -> Sweep:
        """The runs at `key` (NumPy indexing over the starts' shape S) as a sweep."""
        if isinstance(key, tuple) and len(key) > len(self.shape) or self.shape == ():
            raise IndexError(f"too many indices for a sweep of shape {self.shape}")
        per_run = {name: getattr(self, name)[key] for name in
                   ("flips", "first_flip", "period", "exact_period", "tilt", "dt", "n_steps",
                    "nfev", "inertia", "omega0", "q0", "status")}
        return replace(self, drift=self.drift.take(key), **per_run)

    @property
    def tilt_degrees(self) -> np.ndarray:
        """`tilt` in degrees."""
        degrees: np.ndarray = np.degrees(self.tilt)
        return degrees

    def __repr__(self) -> str:
        return (
            f"Sweep(shape={self.shape}, t_end={self.t_end:g}, method={self.method!r}, "
            f"flipped={int(np.count_nonzero(self.flips > 0))}"
            + (f", not finished={int(np.count_nonzero(~self.ok))})" if not self.ok.all() else ")")
        )


@dataclass(frozen=True, eq=False)
class DeploymentSweep(_Statuses):
    """Which deployments tumble: what every run of a sweep over deployments measured, one
    value per run (see :func:`~dzhanibekov.sweep`).

    Each run integrates its deployment over ``[0, t_end]``, past its last knot; after that
    knot the body is constant, so the rest of the motion is the free rotation of the
    deployed body from the state at ``t_end``, whose tumbling the closed form decides: it
    tumbles iff its flip period (:func:`~dzhanibekov.flip_period`) is finite.

    Attributes
    ----------
    deployments : tuple of Deployment, length M
    omega0 : ndarray, shape (M, 3)
        Each run's initial body rates, in the deployment's own axes.
    q0 : ndarray, shape (M, 4)
        Each run's initial attitude.
    inertia : ndarray, shape (M, 3)
        The deployed body's principal moments, ascending (of the last knot's tensor).
    omega_deployed : ndarray, shape (M, 3)
        The body rates at ``t_end`` in those principal axes (NaN for a run that did not
        finish).
    flip_period : ndarray, shape (M,)
        The deployed motion's time between flips, ``2K(m)/λ``; ``inf`` where it does not
        tumble, NaN for a run that did not finish.
    tumbles : ndarray of bool, shape (M,)
        Whether the deployed body flips (its period is finite).
    energy_change : ndarray, shape (M,)
        The relative change of the kinetic energy, ``(E(t_end) − E(0)) / E(0)``: the work
        of the internal forces of the deployment (0 for a body at rest).
    drift : BatchDrift
        Each run's largest drift of what the deployment keeps, over the frames (its energy
        entry is the relative change the deployment makes).
    t_end : float
    method : str
    dt : ndarray, shape (M,)
        The step each run took (its mean accepted step for an adaptive method).
    n_steps, nfev : ndarray of int64, shape (M,)
    status : ndarray of str, shape (M,)
        How each run ended: ``"ok"``, ``"diverged"`` or ``"too many steps"`` (as in
        :class:`Sweep`); the sweep goes on past such runs.
    """

    deployments: tuple[Any, ...]
    omega0: np.ndarray
    q0: np.ndarray
    inertia: np.ndarray
    omega_deployed: np.ndarray
    flip_period: np.ndarray
    tumbles: np.ndarray
    energy_change: np.ndarray
    drift: BatchDrift
    t_end: float
    method: str
    dt: np.ndarray
    n_steps: np.ndarray
    nfev: np.ndarray
    status: np.ndarray

    def to_xarray(self) -> Any:
        """Every run's verdict, inputs and deployment as an ``xarray.Dataset`` (dim ``run``;
        the ``io`` extra), savable with :func:`~dzhanibekov.save`."""
        return _tables.deployment_sweep_dataset(self)

    @property
    def verdict(self) -> np.ndarray:
        """Each run's verdict in words, shape (M,)."""
        words = [
            f"did not finish ({status})" if status != "ok" else
            f"tumbles: a flip every {period:.4g}" if tumbles else "does not tumble"
            for period, tumbles, status in zip(self.flip_period, self.tumbles, self.status)
        ]
        return np.array(words, dtype=object)

    def __getitem__(self, key: Any) -> DeploymentSweep:
        """The runs at `key` (NumPy indexing of the run axis) as a sweep."""
        rows = np.arange(len(self))[key]
        if np.ndim(rows) == 0:
            rows = np.array([rows])
        per_run = {name: getattr(self, name)[rows] for name in
                   ("omega0", "q0", "inertia", "omega_deployed", "flip_period", "tumbles",
                    "energy_change", "dt", "n_steps", "nfev", "status")}
        return replace(self, deployments=tuple(self.deployments[int(i)] for i in rows),
                       drift=self.drift.take(rows), **per_run)

    def __repr__(self) -> str:
        return (
            f"DeploymentSweep(runs={len(self)}, t_end={self.t_end:g}, method={self.method!r}, "
            f"tumbling={int(np.count_nonzero(self.tumbles))}"
            + (f", not finished={int(np.count_nonzero(~self.ok))})" if not self.ok.all() else ")")
        )
