"""Many runs at once: :func:`~dzhanibekov.simulate` with a leading batch axis.

``simulate(body, omega0)`` with ``omega0`` of shape (M, 3) (or ``q0`` of shape (M, 4), or
moments of shape (M, 3), one body per row) runs M free rotations over one frame grid in the
Rust core, on all cores, and returns a :class:`Batch`: ``t`` (frames,), ``omega``
(M, frames, 3), ``q`` (M, frames, 4), flip times and drift per row. Inputs of shape (3,) or
(4,) are shared by every row.

RK4 runs several rows at once in the SIMD lanes of each core (AVX-512, AVX2 or SSE2, picked
at run time). Every row performs exactly the floating-point operations of the single run of
its inputs, so ``batch[i]`` equals ``simulate`` of row i bit for bit, whatever the number of
threads. The other methods run as parallel single runs, one per row, which is trivially the
same.
"""

from __future__ import annotations

import math
import re
import warnings
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, NamedTuple

import numpy as np

from . import _core
from . import _tables
from ._checks import as_array, as_float, as_int, check_size
from .accuracy import check_tolerances, warn_step
from .body import Body, InertiaWarning
from .rotations import quaternions_of
from .trajectory import Drift, Trajectory

__all__ = ["Batch", "BatchDrift", "simulate_batch"]


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

    def __len__(self) -> int:
        return len(self.omega)

    @cached_property
    def flip_times(self) -> tuple[np.ndarray, ...] | None:
        """Each run's flip times (see :func:`~dzhanibekov.simulate`), a tuple of M arrays
        (views); None if flips were not asked for."""
        if self._flip_times is None or self._flip_offsets is None:
            return None
        bounds = self._flip_offsets.tolist()
        return tuple(self._flip_times[a:b] for a, b in zip(bounds[:-1], bounds[1:]))

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

    def __getitem__(self, i: int) -> Trajectory:
        """Run `i` as a :class:`Trajectory` (views of the batch's arrays)."""
        if not isinstance(i, (int, np.integer)) or isinstance(i, bool):
            raise TypeError(f"a batch is indexed by run number, got {type(i).__name__}")
        i = range(len(self))[i]  # negative indices, and IndexError beyond
        return Trajectory(
            t=self.t,
            omega=self.omega[i],
            q=self.q[i],
            flip_times=self._run_flip_times(i),
            body=_body(self.inertia[i]),
            method=self.method,
            dt=float(self.dt[i]),
            n_steps=int(self.n_steps[i]),
            nfev=int(self.nfev[i]),
            drift=Drift(*(float(d[i]) for d in self.drift)),
            n_rejected=int(self.n_rejected[i]),
        )

    def _run_flip_times(self, i: int) -> np.ndarray | None:
        if self._flip_times is None or self._flip_offsets is None:
            return None
        return self._flip_times[int(self._flip_offsets[i]):int(self._flip_offsets[i + 1])]

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


def _body(inertia: np.ndarray) -> Body:
    """A Body of moments the core has already accepted (no second warning)."""
    body = Body.__new__(Body)
    ix, iy, iz = (float(i) for i in inertia)
    body._core = _core.RigidBody((ix, iy, iz))
    return body


def batch_rows(
    body: Any, omega0: Any, q0: Any, *, max_batch_ndim: int | None, stacklevel: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[int, ...]]:
    """The runs of a batch: moments (M, 3), rates (M, 3) and attitudes (M, 4), each row
    checked, inputs of shape (3,) or (4,) shared by every run; and the batch's shape (the
    inputs' leading axes, broadcast together; at most `max_batch_ndim` of them)."""
    if isinstance(body, Body):
        inertia = np.array(body.inertia, dtype=np.float64)
    else:
        inertia = _array("body", body, 3, max_batch_ndim)
    omega = _array("omega0", omega0, 3, max_batch_ndim)
    q = _array("q0", quaternions_of(q0), 4, max_batch_ndim)
    try:
        shape = np.broadcast_shapes(inertia.shape[:-1], omega.shape[:-1], q.shape[:-1])
    except ValueError:
        raise ValueError(
            "the leading (batch) axes of `body`, `omega0` and `q0` must match or be absent, "
            f"got {inertia.shape[:-1]}, {omega.shape[:-1]} and {q.shape[:-1]}"
        ) from None
    # checked before broadcasting: a shared body or attitude once
    _check_moments(inertia.reshape(-1, 3), inertia.shape[:-1], stacklevel=stacklevel + 1)
    flat_q = q.reshape(-1, 4)
    zero = (flat_q[:, 0] == 0) & (flat_q[:, 1] == 0) & (flat_q[:, 2] == 0) & (flat_q[:, 3] == 0)
    if zero.any():
        raise ValueError(
            "`q0` must hold non-zero quaternions (Q, U, V, W), got (0, 0, 0, 0)"
            f"{_at(int(np.argmax(zero)), q.shape[:-1])}"
        )
    m = math.prod(shape)
    rows = [np.ascontiguousarray(np.broadcast_to(a, shape + a.shape[-1:]).reshape(m, a.shape[-1]))
            for a in (inertia, omega, q)]
    return rows[0], rows[1], rows[2], shape


def _array(name: str, value: Any, width: int, max_batch_ndim: int | None) -> np.ndarray:
    most = 8 if max_batch_ndim is None else max_batch_ndim
    shape = f"({width},) or (M, {width})" if most == 1 else f"(..., {width})"
    return as_array(name, value, shape, last=width, ndim=tuple(range(1, most + 2)))


def row_error(exc: ValueError, offset: int, shape: tuple[int, ...]) -> ValueError:
    """The core's error about row ``r`` of a block starting at row `offset` of starts of
    `shape`, naming the row among all the starts (and its index, for several axes)."""
    match = re.match(r"row (\d+): (.*)", str(exc), flags=re.S)
    if match is None:
        return exc
    flat = offset + int(match.group(1))
    where = f"row {flat}" if len(shape) <= 1 else f"row {flat} ({_index(flat, shape)})"
    return ValueError(f"{where}: {match.group(2)}")


def _index(flat: int, shape: tuple[int, ...]) -> str:
    index = np.unravel_index(flat, shape) if shape else ()
    return f"row {flat}" if len(shape) <= 1 else f"index {tuple(int(i) for i in index)}"


def _at(flat: int, shape: tuple[int, ...]) -> str:
    """Where in an input of leading `shape` row `flat` is, for a message ("" if shared)."""
    return f" at {_index(flat, shape)}" if shape else ""


def _check_moments(inertia: np.ndarray, shape: tuple[int, ...], *, stacklevel: int) -> None:
    """As `Body` checks one body, for every row (of `shape`); one warning for all the
    unphysical ones. Column by column: reductions over a last axis of 3 are slow."""
    a, b, c = inertia.T
    bad = ~((a > 0) & (b > 0) & (c > 0))
    if bad.any():
        i = int(np.argmax(bad))
        raise ValueError(
            f"`body` must hold positive, finite principal moments, got {inertia[i].tolist()}"
            f"{_at(i, shape)}"
        )
    largest = np.maximum(np.maximum(a, b), c)
    with np.errstate(over="ignore"):
        ratio = largest / np.minimum(np.minimum(a, b), c)
    bad = ~(ratio <= 1e150)
    if bad.any():
        i = int(np.argmax(bad))
        raise ValueError(
            "`body` must have a ratio of largest to smallest moment of at most 1e150, got "
            f"{inertia[i].tolist()}{_at(i, shape)}"
        )
    total = a + b + c
    slack = 1e-12 * total
    unphysical = (2 * largest > total + slack).nonzero()[0]
    if len(unphysical):
        i = int(unphysical[0])
        warnings.warn(
            f"{len(unphysical)} of {len(inertia)} bodies break the triangle inequality (each "
            "moment of a real body is at most the sum of the other two), the first "
            f"{inertia[i].tolist()}{_at(i, shape)}; no mass distribution has them",
            InertiaWarning,
            stacklevel=stacklevel,
        )


def plan_batch_step(
    inertia: np.ndarray, omega: np.ndarray, t_end: float, frames: int, dt: Any, method: str,
    rtol: Any, atol: Any, shape: tuple[int, ...], *, stacklevel: int,
) -> tuple[float, float, float]:
    """One step for every run of a batch: `dt`, or with ``dt=None`` the smallest of the steps
    the runs would pick alone; warns (once, naming the worst run) when RK4 would dissipate a
    run. Returns ``(dt, rtol, atol)`` for the core."""
    dt_, rtol_, atol_ = check_tolerances(method, dt, rtol, atol)
    if len(inertia) == 0:
        return (1.0 if dt_ is None else dt_), rtol_, atol_
    plans = _core.step_plan_batch(inertia, omega, t_end, frames, dt_, method, rtol_, atol_)
    step = float(np.min(plans["dt"]))
    if dt_ is None and not np.all(plans["dt"] == step):
        plans = _core.step_plan_batch(inertia, omega, t_end, frames, step, method, rtol_, atol_)
    worst = int(np.argmax(plans["predicted_drift"]))
    plan = {key: float(values[worst]) for key, values in plans.items()}
    where = f"{_index(worst, shape)}: " if len(inertia) > 1 else ""
    warn_step(plan, method, dt is not None, rtol_, stacklevel=stacklevel + 1, where=where)
    return step, rtol_, atol_


def checked_run(t_end: Any, frames: Any, method: Any, max_steps: Any) -> tuple[float, int, int]:
    """The arguments shared by every run of a batch or sweep, checked."""
    from .simulate import METHODS

    t_end_ = as_float("t_end", t_end, positive=True)
    frames_ = as_int("frames", frames, minimum=2)
    max_steps_ = as_int("max_steps", max_steps, minimum=1)
    if method not in METHODS:
        raise ValueError(f"`method` must be one of {METHODS}, got {method!r}")
    return t_end_, frames_, max_steps_


def checked_threads(threads: Any) -> int | None:
    """`threads`: None (all cores) or a positive integer."""
    return None if threads is None else as_int("threads", threads, minimum=1)


def simulate_batch(
    body: Any,
    omega0: Any,
    q0: Any,
    t_end: Any,
    frames: Any,
    dt: Any,
    method: str,
    *,
    rtol: Any,
    atol: Any,
    flips: bool,
    max_steps: Any,
    threads: Any,
    stacklevel: int = 3,
) -> Batch:
    """`simulate` for a batch (see :func:`~dzhanibekov.simulate`, whose inputs have a
    leading batch axis)."""
    t_end, frames, max_steps = checked_run(t_end, frames, method, max_steps)
    threads = checked_threads(threads)
    if not isinstance(flips, (bool, np.bool_)):
        raise TypeError(f"`flips` must be True or False, got {type(flips).__name__}")
    inertia, omega, q, shape = batch_rows(body, omega0, q0, max_batch_ndim=1,
                                          stacklevel=stacklevel + 1)
    m = len(omega)
    check_size(
        m * frames * 7 * 8,
        f"a batch of {m} runs × {frames} frames",
        "ask for fewer runs or frames, or use `dz.sweep` (or `dz.summarize`) for per-run "
        "summaries, which keep no frames",
    )
    step, rtol_, atol_ = plan_batch_step(inertia, omega, t_end, frames, dt, method, rtol, atol,
                                         shape, stacklevel=stacklevel + 1)
    out = _core.simulate_batch(inertia, omega, q, t_end, frames, step, method, max_steps, True,
                               bool(flips), rtol_, atol_, threads)
    offsets, times = out["flip_offsets"], out["flip_times"]
    return Batch(
        t=t_end * (np.arange(frames) / (frames - 1)),
        omega=out["omega"],
        q=out["q"],
        _flip_times=times if flips else None,
        _flip_offsets=offsets if flips else None,
        inertia=inertia,
        method=method,
        dt=out["dt"],
        n_steps=out["n_steps"],
        nfev=out["nfev"],
        n_rejected=out["n_rejected"],
        drift=BatchDrift(**out["drift"]),
    )


def is_batch(body: Any, omega0: Any, q0: Any) -> bool:
    """Whether any input has a leading batch axis (bad input is left to the checks)."""
    def ndim(value: Any) -> int:
        try:
            return int(np.ndim(value))
        except Exception:  # ragged, or no array at all: the checks will say so
            return 0

    return ndim(omega0) >= 2 or ndim(q0) >= 2 or (not isinstance(body, Body) and ndim(body) >= 2)
