"""The results of runs, one family: a :class:`Trajectory` (one run's frames), a
:class:`Summary` (one run without frames), a :class:`Batch` (many runs' frames) and a
:class:`Sweep` (many runs, one number each). All tell ``flips`` (how many), ``t_end`` and a
``verdict`` in words, the same way; all pickle and copy (they are plain arrays and numbers).

>>> import dzhanibekov as dz
>>> traj = dz.simulate(dz.Body(dz.PAPER_INERTIA), (0.01, 0.01, 1.0), t_end=100.0)
>>> traj.flips, traj.t_end, traj.verdict
(2, 100.0, '2 flips in [0, 100]')
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any, NamedTuple, overload

import numpy as np

from . import _core
from . import _tables
from ._args import check_size
from .body import Body, principal_body
from .rotations import to_rotation

__all__ = ["Drift", "Trajectory", "Summary", "BatchDrift", "Batch", "Sweep", "DeploymentSweep",
           "verdict"]


def verdict(flips: int, t_end: float) -> str:
    """A run's stability verdict in words: how often it flipped in ``[0, t_end]``."""
    if not flips:
        return f"no flip in [0, {t_end:g}]"
    return f"{flips} flip{'s' if flips > 1 else ''} in [0, {t_end:g}]"


def invariants_of(body: _core.RigidBody, omega: np.ndarray,
                  q: np.ndarray) -> dict[str, np.ndarray]:
    """The invariants (see `Trajectory.invariants`) of the core's `body` at rows of `omega`
    and `q` (its principal axes), computed in the core."""
    out = _core.invariants(body, np.ascontiguousarray(omega), np.ascontiguousarray(q))
    return {"energy": out.energy, "momentum_body": out.momentum_body,
            "momentum_world": out.momentum_world, "q_norm": out.q_norm}


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
        Body-frame angular velocity ``(u, v, w)``, in the body's own axes.
    q : ndarray, shape (frames, 4)
        Body-to-world unit quaternion of the body's own axes, scalar first
        ``(Q, U, V, W)``: ``dz.rotate(traj.q, points)`` turns points given in those axes.
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
            ``energy`` (frames,), ``momentum_body`` (frames, 3) (``T ω``, in the body's own
            axes), ``momentum_world`` (frames, 3) and ``q_norm`` (frames,).
        """
        if not self._invariants:
            check_size(len(self.t) * 8 * 8, f"the invariants at {len(self.t)} frames",
                       "compute them over fewer frames (a slice of the run)")
            omega, q = self.body.to_principal(self.omega, self.q)
            values = invariants_of(self.body._core, omega, q)
            if not self.body.is_principal:  # L = T ω in the user's axes
                values["momentum_body"] = self.body.to_user(values["momentum_body"], q)[0]
            self._invariants.update(values)
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
    def momentum_world(self) -> np.ndarray:
        """Total angular momentum in space at every frame, shape (frames, 3)."""
        return self.invariants()["momentum_world"]

    @property
    def energy(self) -> np.ndarray:
        """Total kinetic energy at every frame, shape (frames,)."""
        return self.invariants()["energy"]

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
    body : Body
    method : str
    dt : float
        The step actually taken.
    n_steps, nfev : int
        Steps taken and right-hand-side evaluations.
    """

    flip_times: np.ndarray
    drift: Drift
    t_end: float
    body: Body
    method: str
    dt: float
    n_steps: int
    nfev: int

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


class BatchDrift(NamedTuple):
    """The invariants' largest drift over the frames, one value per run (see `Drift`)."""

    energy: np.ndarray
    """Relative: ``max |E(t) - E(0)| / E(0)``."""
    momentum: np.ndarray
    """Relative change of ``|L|``."""
    momentum_world: np.ndarray
    """``max |L_world(t) - L_world(0)| / |L(0)|``."""
    q_norm: np.ndarray
    """``max ||q(t)| - 1|``."""

    def reshape(self, shape: tuple[int, ...]) -> BatchDrift:
        """The same values in `shape`."""
        return BatchDrift(*(np.reshape(v, shape) for v in self))


@dataclass(frozen=True, eq=False)
class Batch:
    """Frames of M free rotations over one frame grid, run-major.

    ``batch[i]`` is run i as a :class:`Trajectory`, equal bit for bit to ``simulate`` of
    its inputs alone (with the same ``dt``).

    Attributes
    ----------
    t : ndarray, shape (frames,)
        Frame times, shared by every run.
    omega : ndarray, shape (M, frames, 3)
        Body-frame angular velocity ``(u, v, w)`` of each run.
    q : ndarray, shape (M, frames, 4)
        Body-to-world unit quaternion, scalar first, of each run.
    flip_times : tuple of M ndarrays, or None
        Each run's flip times (see :func:`~dzhanibekov.simulate`); None if not asked for.
    inertia : ndarray, shape (M, 3)
        Each run's principal moments.
    method : str
    dt : ndarray, shape (M,)
        The step each run took (for an adaptive method, its mean accepted step).
    n_steps, nfev, n_rejected : ndarray of int64, shape (M,)
        Steps, right-hand-side evaluations and rejected steps of each run.
    drift : BatchDrift
        The invariants' largest drift over the frames, per run.
    model : tuple or None
        A batch of deployments or damped bodies: each run's :class:`Deployment` or
        :class:`Damper`; flips are located when every run's tensors are diagonal (else
        `flip_times` is None).
    sigma : ndarray, shape (M, frames, 3), or None
        A damper batch's sphere rates in body axes.
    momentum_world : ndarray, shape (M, frames, 3)
        Each run's total angular momentum in space (see :attr:`Trajectory.momentum_world`).
    energy : ndarray, shape (M, frames)
        Each run's total kinetic energy (see :attr:`Trajectory.energy`).
    """

    t: np.ndarray
    omega: np.ndarray
    q: np.ndarray
    _flip_times: np.ndarray | None = field(repr=False)
    """Every run's flip times, one after the other; run i's are
    ``_flip_times[_flip_offsets[i]:_flip_offsets[i + 1]]``."""
    _flip_offsets: np.ndarray | None = field(repr=False)
    inertia: np.ndarray
    method: str
    dt: np.ndarray
    n_steps: np.ndarray
    nfev: np.ndarray
    n_rejected: np.ndarray
    drift: BatchDrift
    body: Body | tuple[Body, ...] | None = field(default=None, repr=False)
    """The body shared by every run, or one per run, when given as Bodies (their axes are
    the ones `omega` and `q` are in); None for moments. For a batch of deployments, each
    run's body at ``t = 0`` (its principal moments)."""
    model: tuple[Any, ...] | None = field(default=None, repr=False)
    """Each run's model beyond the constant body (its Deployment or Damper), or None."""
    sigma: np.ndarray | None = field(default=None, repr=False)
    """A damper batch's sphere rates in body axes, shape (M, frames, 3); None otherwise."""
    _invariants: dict[str, np.ndarray] = field(default_factory=dict, repr=False)
    """A model batch's invariants at every frame, each with a leading run axis."""

    def to_xarray(self) -> Any:
        """Every run's frames as an ``xarray.Dataset`` (dims ``run``, ``time``, ``axis``, ``quaternion``; the ``io`` extra).

        Examples
        --------
        >>> import dzhanibekov as dz
        >>> batch = dz.simulate(dz.PAPER_INERTIA, [(0.01, 0.01, 1.0), (0, 1, 0.01)], frames=5)
        >>> batch.to_xarray().q.dims
        ('run', 'time', 'quaternion')
        """
        return _tables.batch_dataset(self)

    def to_dataframe(self) -> Any:
        """Every run's frames as a ``pandas.DataFrame`` (index (``run``, ``t``), columns u v w Q U V W; the ``io`` extra)."""
        return _tables.batch_frame(self)

    def __len__(self) -> int:
        return len(self.omega)

    def _row_body(self, i: int) -> Body:
        if isinstance(self.body, Body):
            return self.body
        if self.body is not None:
            return self.body[i]
        return trusted_body(self.inertia[i])

    @cached_property
    def flip_times(self) -> tuple[np.ndarray, ...] | None:
        """Each run's flip times (see :func:`~dzhanibekov.simulate`), a tuple of M arrays
        (views); None if flips were not asked for."""
        if self._flip_times is None or self._flip_offsets is None:
            return None
        bounds = self._flip_offsets.tolist()
        return tuple(self._flip_times[a:b] for a, b in zip(bounds[:-1], bounds[1:]))

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
            body=self._row_body(i),
            method=self.method,
            dt=float(self.dt[i]),
            n_steps=int(self.n_steps[i]),
            nfev=int(self.nfev[i]),
            drift=Drift(*(float(d[i]) for d in self.drift)),
            n_rejected=int(self.n_rejected[i]),
            model=None if self.model is None else self.model[i],
            sigma=None if self.sigma is None else self.sigma[i],
            _invariants={k: v[i] for k, v in self._invariants.items()},
        )

    @property
    def momentum_world(self) -> np.ndarray:
        """Each run's total angular momentum in space at every frame, shape (M, frames, 3)."""
        return self._invariant("momentum_world")

    @property
    def energy(self) -> np.ndarray:
        """Each run's total kinetic energy at every frame, shape (M, frames)."""
        return self._invariant("energy")

    def _invariant(self, name: str) -> np.ndarray:
        """An invariant of every run: a model batch's own, or each run's, computed once."""
        if name not in self._invariants:
            runs = [self[i].invariants() for i in range(len(self))]
            for key in ("energy", "momentum_body", "momentum_world", "q_norm"):
                self._invariants[key] = np.stack([r[key] for r in runs]) if runs else \
                    np.empty((0, len(self.t)) + ((3,) if key.startswith("momentum") else ()))
        return self._invariants[name]

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
                       _flip_offsets=offsets, inertia=self.inertia[take], dt=self.dt[take],
                       n_steps=self.n_steps[take], nfev=self.nfev[take],
                       n_rejected=self.n_rejected[take],
                       drift=BatchDrift(*(d[take] for d in self.drift)),
                       body=self.body if not isinstance(self.body, tuple) else
                       tuple(self.body[i] for i in rows),
                       model=None if self.model is None else tuple(self.model[i] for i in rows),
                       sigma=None if self.sigma is None else self.sigma[take],
                       _invariants={k: v[take] for k, v in self._invariants.items()})

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


def trusted_body(inertia: np.ndarray) -> Body:
    """A Body of moments the core has already accepted (no second warning)."""
    return principal_body(inertia)


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
        return replace(self, drift=BatchDrift(*(d[key] for d in self.drift)), **per_run)

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
                       drift=BatchDrift(*(d[rows] for d in self.drift)), **per_run)

    def __repr__(self) -> str:
        return (
            f"DeploymentSweep(runs={len(self)}, t_end={self.t_end:g}, method={self.method!r}, "
            f"tumbling={int(np.count_nonzero(self.tumbles))}"
            + (f", not finished={int(np.count_nonzero(~self.ok))})" if not self.ok.all() else ")")
        )
