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

Sweeps: many runs that keep one number each, on all cores or on a Dask cluster.

:func:`sweep` runs a free rotation for every start of a grid (or any array) of initial rates,
attitudes or bodies and keeps, per run, what a stability study asks: the flips counted and
their measured period, the exact period, the largest tilt of the spin axis and the
invariants' drift. No frames are kept: a sweep's memory grows with its runs, never with
their frames or steps. :func:`grid` builds the starts of a map; :mod:`dzhanibekov.plotting.maps`
draws one.

RK4 runs several starts at once in the SIMD lanes of every core; each run equals the single
run of its inputs (:func:`~dzhanibekov.summarize`) bit for bit. The runs are cut into blocks
of thousands; with ``client=`` (a ``dask.distributed.Client``) each block is one task on the
cluster, and the result is the same, bit for bit, as on one machine.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, overload

import numpy as np
from tqdm.auto import tqdm

from . import _core
from ._args import as_array, as_float, as_int, check_size
from ._swap import swapped_error
from .accuracy import check_tolerances, warn_step
from .body import TENSOR_HINT, Body, InertiaWarning, _is_square
from .deployment import Deployment
from .deployment_sweep import sweep_deployments
from .errors import DzhanibekovError
from .methods import DEFAULT_MAX_STEPS, DEFAULT_METHOD, check_method
from .models import is_deployment_list
from .results import Batch, BatchDrift, DeploymentSweep, Sweep, trusted_body
from .rotations import quaternions_of

__all__ = ["Batch", "BatchDrift", "simulate_batch", "Sweep", "DeploymentSweep", "sweep", "grid",
           "DEFAULT_BLOCK"]


def batch_rows(
    body: Any, omega0: Any, q0: Any, *, max_batch_ndim: int | None, stacklevel: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[int, ...]]:
    """The runs of a batch: moments (M, 3), rates (M, 3) and attitudes (M, 4), each row
    checked, inputs of shape (3,) or (4,) shared by every run; and the batch's shape (the
    inputs' leading axes, broadcast together; at most `max_batch_ndim` of them)."""
    if isinstance(body, Body):
        inertia = np.array(body.inertia, dtype=np.float64)
    elif is_body_list(body):
        inertia = np.array([b.inertia for b in body], dtype=np.float64)
    else:
        if _is_square(body):
            raise ValueError("`body` of shape (3, 3) is ambiguous: one body's inertia tensor "
                             f"or three bodies' principal moments? {TENSOR_HINT}")
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
    # the rows, the core's starts and its per-run results: about 40 float64 values a run
    check_size(m * 40 * 8, f"a batch of {m} starts",
               "run fewer starts at a time (split the batch)")
    rows = [np.ascontiguousarray(np.broadcast_to(a, shape + a.shape[-1:]).reshape(m, a.shape[-1]))
            for a in (inertia, omega, q)]
    return rows[0], rows[1], rows[2], shape


def is_body_list(body: Any) -> bool:
    """Whether `body` is a list (or tuple) of Bodies, one per run."""
    return isinstance(body, (list, tuple)) and len(body) > 0 and \
        all(isinstance(b, Body) for b in body)


def principal_rows(body: Any, omega: np.ndarray, q: np.ndarray) -> tuple[np.ndarray,
                                                                           np.ndarray]:
    """Rows of starts in the user's axes turned into principal axes (see
    :meth:`Body.to_principal`): once, at the edge of the run; unchanged for moments."""
    return _change_axes(body, omega, q, Body.to_principal)


def user_rows(body: Any, omega: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A batch's frames (M, frames, 3|4) turned back into the user's axes."""
    return _change_axes(body, omega, q, Body.to_user)


def _change_axes(body: Any, omega: np.ndarray, q: np.ndarray, how: Any) -> tuple[np.ndarray,
                                                                                  np.ndarray]:
    if isinstance(body, Body):
        if body.is_principal:
            return omega, q
        omega, q = how(body, omega, q)
        return np.ascontiguousarray(omega), np.ascontiguousarray(q)
    if not is_body_list(body) or all(b.is_principal for b in body):
        return omega, q
    omega, q = omega.copy(), q.copy()
    for i, b in enumerate(body):  # one row per body: a list is short
        omega[i], q[i] = how(b, omega[i], q[i])
    return omega, q


def _array(name: str, value: Any, width: int, max_batch_ndim: int | None) -> np.ndarray:
    most = 8 if max_batch_ndim is None else max_batch_ndim
    shape = f"({width},) or (M, {width})" if most == 1 else f"(..., {width})"
    return as_array(name, value, shape, last=width, ndim=tuple(range(1, most + 2)))


def row_error(exc: ValueError, offset: int, shape: tuple[int, ...]) -> ValueError:
    """The core's error about row ``exc.row`` of a block starting at row `offset` of starts of
    `shape`, about that row among all the starts (with its index, for several axes)."""
    if not isinstance(exc, DzhanibekovError) or exc.row is None:
        return exc
    flat = offset + exc.row
    index = tuple(int(i) for i in np.unravel_index(flat, shape)) if len(shape) > 1 else None
    return exc.at(flat, index)


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
    bad = ~(ratio <= _core.MAX_MOMENT_RATIO)
    if bad.any():
        i = int(np.argmax(bad))
        most = f"{_core.MAX_MOMENT_RATIO:.0e}".replace("e+", "e")
        raise ValueError(
            f"`body` must have a ratio of largest to smallest moment of at most {most}, got "
            f"{inertia[i].tolist()}{_at(i, shape)}"
        )
    total = a + b + c
    slack = _core.TRIANGLE_SLACK * total
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
) -> tuple[float | None, float, float]:
    """One step for every run of a batch: `dt`, or with ``dt=None`` the smallest of the steps
    the runs would pick alone (an adaptive method's runs each pick their own: None); warns
    (once, naming the worst run) when RK4 would dissipate a run. Returns ``(dt, rtol, atol)``
    for the core."""
    dt_, rtol_, atol_ = check_tolerances(method, dt, rtol, atol)
    plan = _core.plan_batch(inertia, omega, t_end, frames, dt_, method, rtol_, atol_)
    if plan.worst is not None and plan.worst_row is not None:
        where = f"{_index(plan.worst_row, shape)}: " if len(inertia) > 1 else ""
        warn_step(plan.worst, method, dt is not None, rtol_, stacklevel=stacklevel + 1,
                  where=where)
    return plan.dt, rtol_, atol_


def checked_run(t_end: Any, frames: Any, method: Any, max_steps: Any) -> tuple[float, int, int]:
    """The arguments shared by every run of a batch or sweep, checked."""
    t_end_ = as_float("t_end", t_end, positive=True)
    frames_ = as_int("frames", frames, minimum=2)
    max_steps_ = as_int("max_steps", max_steps, minimum=1)
    check_method(method)
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
    progress: bool | None = None,
    stacklevel: int = 3,
) -> Batch:
    """`simulate` for a batch (see :func:`~dzhanibekov.simulate`, whose inputs have a
    leading batch axis)."""
    t_end, frames, max_steps = checked_run(t_end, frames, method, max_steps)
    threads = checked_threads(threads)
    if not isinstance(flips, (bool, np.bool_)):
        raise TypeError(f"`flips` must be True or False, got {type(flips).__name__}")
    if progress is not None and not isinstance(progress, bool):
        raise TypeError(f"`progress` must be True, False or None, got {progress!r}")
    inertia, omega, q, shape = batch_rows(body, omega0, q0, max_batch_ndim=1,
                                          stacklevel=stacklevel + 1)
    m = len(omega)
    check_size(
        m * frames * 7 * 8,
        f"a batch of {m} runs × {frames} frames",
        "ask for fewer runs or frames, or use `dz.sweep` (or `dz.summarize`) for per-run "
        "summaries, which keep no frames",
    )
    omega, q = principal_rows(body, omega, q)
    step, rtol_, atol_ = plan_batch_step(inertia, omega, t_end, frames, dt, method, rtol, atol,
                                         shape, stacklevel=stacklevel + 1)

    def run(rows: slice) -> _core.BatchResult:
        try:
            return _core.simulate_batch(inertia[rows], omega[rows], q[rows], t_end, frames, step,
                                        method, max_steps, True, bool(flips), rtol_, atol_,
                                        threads)
        except ValueError as exc:
            raise row_error(exc, rows.start or 0, shape) from None

    out = _in_blocks(run, m, progress)
    if out.omega is None or out.q is None:
        raise RuntimeError("internal error in the dzhanibekov core: frames were not kept")
    omega_out, q_out = user_rows(body, out.omega, out.q)
    return Batch(
        t=out.t,
        omega=omega_out,
        q=q_out,
        _flip_times=out.flip_times if flips else None,
        _flip_offsets=out.flip_offsets if flips else None,
        inertia=inertia,
        method=method,
        dt=out.runs.dt,
        n_steps=out.runs.n_steps,
        nfev=out.runs.nfev,
        n_rejected=out.runs.n_rejected,
        drift=BatchDrift(*out.runs.drift),
        body=body if isinstance(body, Body) else tuple(body) if is_body_list(body) else None,
    )


PROGRESS_BLOCK = 1024
"""Rows per call to the core when a batch shows its progress (a multiple of the SIMD
lanes' 16, so that the lanes are grouped as in one call; rows never depend on it)."""

PROGRESS_DELAY = 1.0
"""Seconds before a progress bar shows (``progress=None``): quick calls show none."""


def _in_blocks(run: Callable[[slice], _core.BatchResult], m: int,
               progress: bool | None) -> _BlockResult | _core.BatchResult:
    """`run` over all `m` rows in one call, or, when a progress bar shows (tqdm decides:
    with ``progress=None`` only on a terminal), in blocks of `PROGRESS_BLOCK` rows written
    into the whole batch's arrays as they come."""
    if progress is False or m <= PROGRESS_BLOCK:
        return run(slice(0, m))
    bar = tqdm(total=m, desc="batch", unit="run", leave=False,
               disable=None if progress is None else False,
               delay=PROGRESS_DELAY if progress is None else 0.0)
    if bar.disable:  # no bar will show: one call, no copies
        return run(slice(0, m))
    parts = []
    with bar:
        for start in range(0, m, PROGRESS_BLOCK):
            rows = slice(start, min(start + PROGRESS_BLOCK, m))
            parts.append(run(rows))
            bar.update(rows.stop - rows.start)
    return _BlockResult.join(parts)


@dataclass(frozen=True)
class _RunColumns:
    """As `_core.RunColumns`: per-run drift, cost and step."""

    drift: list[np.ndarray]
    nfev: np.ndarray
    n_steps: np.ndarray
    n_rejected: np.ndarray
    dt: np.ndarray


@dataclass(frozen=True)
class _BlockResult:
    """The core's results of a batch's blocks joined into one, as one call returns it."""

    t: np.ndarray
    omega: np.ndarray | None
    q: np.ndarray | None
    flip_offsets: np.ndarray
    flip_times: np.ndarray
    runs: _RunColumns

    @staticmethod
    def join(parts: list[_core.BatchResult]) -> _BlockResult:
        def joined(values: list[Any]) -> Any:
            return None if values[0] is None else np.concatenate(values)

        starts = np.cumsum([0] + [p.flip_offsets[-1] for p in parts[:-1]])
        offsets = np.concatenate([parts[0].flip_offsets[:1]] + [
            p.flip_offsets[1:] + s for p, s in zip(parts, starts)])
        runs = [p.runs for p in parts]
        return _BlockResult(
            t=parts[0].t, omega=joined([p.omega for p in parts]),
            q=joined([p.q for p in parts]), flip_offsets=offsets,
            flip_times=joined([p.flip_times for p in parts]),
            runs=_RunColumns(
                drift=[np.concatenate(c) for c in zip(*(r.drift for r in runs))],
                **{k: joined([getattr(r, k) for r in runs])
                   for k in ("nfev", "n_steps", "n_rejected", "dt")}))


def is_batch(body: Any, omega0: Any, q0: Any) -> bool:
    """Whether any input has a leading batch axis (bad input is left to the checks)."""
    def ndim(value: Any) -> int:
        try:
            return int(np.ndim(value))
        except Exception:  # ragged, or no array at all: the checks will say so
            return 0

    return ndim(omega0) >= 2 or ndim(q0) >= 2 or is_body_list(body) or (
        not isinstance(body, Body) and ndim(body) >= 2)



DEFAULT_BLOCK = 4096
"""Runs per block: per call to the core, per task on a Dask cluster."""

_PROGRESS_DELAY = 1.0
"""Seconds before the progress bar shows (`progress=None`): quick sweeps show none."""


def grid(*axes: Any) -> np.ndarray:
    """Every combination of the given values: the starts of a map.

    Each argument is a number (held fixed) or a 1-D array of values (an axis of the grid);
    the result has one axis per array argument, in order, and a last axis with one entry per
    argument. ``grid(u, v, 1.0)`` gives body rates ``(u_i, v_j, 1)`` of shape
    ``(len(u), len(v), 3)``; ``grid(1.0, iy, iz)`` gives moments ``(1, iy_i, iz_j)``.

    Parameters
    ----------
    *axes : float or array_like, shape (n,)
        Finite values.

    Returns
    -------
    ndarray, shape (n_1, ..., n_k, len(axes))

    Raises
    ------
    TypeError
        An argument that is not numbers.
    ValueError
        No arguments, a value that is not finite, an array of other than one axis or with
        no values.

    Examples
    --------
    >>> grid([0.1, 0.2], [0.0, 0.5, 1.0], 1.0).shape
    (2, 3, 3)
    >>> grid([0.1, 0.2], [0.0, 0.5, 1.0], 1.0)[1, 2]
    array([0.2, 1. , 1. ])
    """
    if not axes:
        raise ValueError("`axes` of `grid` must hold at least one axis or value, got none")
    values = []
    for k, axis in enumerate(axes):
        name = f"axes[{k}]"
        try:
            arr = np.asarray(axis)
        except Exception:
            raise TypeError(f"`{name}` must be a number or a 1-D array of numbers") from None
        if arr.dtype.kind not in "iuf":
            raise TypeError(f"`{name}` must hold real numbers, got dtype {arr.dtype}")
        if arr.ndim > 1 or arr.size == 0:
            raise ValueError(f"`{name}` must be a number or a 1-D array of values, got shape "
                             f"{arr.shape}")
        values.append(as_array(name, arr.reshape(-1), "(n,)", last=arr.size, ndim=(1,)))
    varying = [v for v, a in zip(values, axes) if np.ndim(a) == 1]
    shape = tuple(len(v) for v in varying)
    check_size(math.prod(shape) * len(axes) * 8, f"a grid of shape {shape + (len(axes),)}",
               "give shorter `axes`")
    out = np.empty(shape + (len(axes),))
    k = 0
    for j, (v, a) in enumerate(zip(values, axes)):
        if np.ndim(a) == 1:
            index: list[Any] = [np.newaxis] * len(shape)
            index[k] = slice(None)
            out[..., j] = v[tuple(index)]
            k += 1
        else:
            out[..., j] = v[0]
    return out


@overload
def sweep(
    body: Deployment | list[Deployment] | tuple[Deployment, ...],
    omega0: Any,
    q0: Any = ...,
    t_end: float = ...,
    frames: int = ...,
    dt: float | None = ...,
    method: str = ...,
    *,
    rtol: float | None = ...,
    atol: float | None = ...,
    max_steps: int = ...,
    block: int = ...,
    client: Any = ...,
    progress: bool | None = ...,
    threads: int | None = ...,
) -> DeploymentSweep: ...


@overload
def sweep(
    body: Any,
    omega0: Any,
    q0: Any = ...,
    t_end: float = ...,
    frames: int = ...,
    dt: float | None = ...,
    method: str = ...,
    *,
    rtol: float | None = ...,
    atol: float | None = ...,
    max_steps: int = ...,
    block: int = ...,
    client: Any = ...,
    progress: bool | None = ...,
    threads: int | None = ...,
) -> Sweep: ...


def sweep(
    body: Any,
    omega0: Any,
    q0: Any = (1.0, 0.0, 0.0, 0.0),
    t_end: float = 100.0,
    frames: int = 201,
    dt: float | None = None,
    method: str = DEFAULT_METHOD,
    *,
    rtol: float | None = None,
    atol: float | None = None,
    max_steps: int = DEFAULT_MAX_STEPS,
    block: int = DEFAULT_BLOCK,
    client: Any = None,
    progress: bool | None = None,
    threads: int | None = None,
) -> Sweep | DeploymentSweep:
    """Runs a free rotation from every start and keeps a few numbers per run, no frames.

    Each run is the one :func:`~dzhanibekov.summarize` makes of the same inputs, step for
    step: its flips, drift and step are those of ``summarize`` bit for bit. The starts are
    cut into blocks of `block` runs; each block runs in the Rust core on all cores (RK4
    several runs at once in SIMD lanes), or, with `client`, as one task on a Dask cluster.
    No result depends on the blocks, the threads or the cluster.

    A sweep over deployments (`body` a :class:`Deployment` or a list of them) asks which
    deployments tumble and returns a :class:`DeploymentSweep`: each run integrates its
    deployment over ``[0, t_end]`` (which must reach every last knot) and the closed form
    decides the free motion after it (see Notes).

    Parameters
    ----------
    body : Body, Deployment, list of Deployment, or array_like, shape (3,) or S + (3,)
        The body, or principal moments: one body for all runs, or one per start. Or a
        deployment, or one per run (then the starts have at most one batch axis, M).
    omega0 : array_like, shape (3,) or S + (3,)
        Initial body rates ``(u0, v0, w0)``: one per start (say from :func:`grid`).
    q0 : array_like, shape (4,) or S + (4,)
        Initial attitude, scalar first; shared or one per start.
    t_end, frames, dt, method, rtol, atol, max_steps
        As for :func:`~dzhanibekov.simulate`: the frames only set the substeps and where
        the drift is measured. With ``dt=None`` every run of a fixed-step method takes
        the smallest of the steps its runs would pick alone; the adaptive methods' runs each
        pick their own first step, as alone.
    block : int
        Runs per block (default 4096): per call to the core, per task on a cluster.
    client : dask.distributed.Client, optional
        Run the blocks on this cluster (``pip install dzhanibekov[dask]``), mapped as one
        task per block and gathered in order.
    progress : bool, optional
        A progress bar (tqdm, on stderr) advanced per block: None (default) shows it when
        stderr is a terminal and the sweep takes more than a second; True always; False
        never.
    threads : int, optional
        Threads per block (default: all cores of the machine that runs it).

    Returns
    -------
    Sweep or DeploymentSweep
        Per-run arrays of shape S, the starts' leading axes broadcast together; for
        deployments, per-run arrays of shape (M,): whether each tumbles, its flip period
        after the deployment and the energy the deployment changed.

    Raises
    ------
    TypeError
        An argument of the wrong kind, or a `client` that is not a Dask client.
    ValueError
        An argument out of range, mismatched leading axes, a start that no run can take
        (naming it), arguments that look swapped. A run that diverges or needs too many
        steps does not raise: the sweep goes on, and that run's `status` says why.
    ImportError
        `client` given but dask.distributed not installed.
    KeyboardInterrupt
        On Ctrl-C, within a fraction of a second on this machine.

    Warns
    -----
    StepSizeWarning
        Once, naming the worst run, as :func:`~dzhanibekov.simulate` warns for one.
    InertiaWarning
        Once, for moments that break the triangle inequality.

    Notes
    -----
    After its last knot a deployed body is constant, so the motion from the state reached
    there is a free rotation: it tumbles iff the flip period of the deployed body (in its
    principal axes) at that state is finite (:func:`~dzhanibekov.flip_period`). The verdict
    is exact for the integrated state, whatever the length of the motion watched. The runs
    are those of :func:`~dzhanibekov.simulate` of each deployment over ``[0, t_end]`` (bit
    for bit, with the same `dt`: with ``dt=None`` a fixed-step method takes the smallest of
    the steps its runs would pick alone); a block of runs keeps their frames until it is
    summarised, so ask for few `frames`.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> s = dz.sweep(dz.PAPER_INERTIA, dz.grid([0.01, 0.1], 0.01, 1.0), t_end=100.0)
    >>> s.shape, s.flips
    ((2,), array([2, 5]))
    >>> bool(abs(s.period[1] - s.exact_period[1]) < 1e-6 * s.exact_period[1])
    True

    Stowed (1, 2, 3) spinning about z, deployed over t ∈ [10, 20] to (1, 3, r): z becomes
    the intermediate axis for r < 3, the major one for r > 3.

    >>> deployments = [dz.Deployment([10.0, 20.0], [(1, 2, 3), (1, 3, r)]) for r in (2, 4)]
    >>> s = dz.sweep(deployments, (0.01, 0.01, 1.0), t_end=20.0, frames=2, dt=1e-3)
    >>> s.tumbles, s.verdict[1]
    (array([ True, False]), 'does not tumble')
    """
    if isinstance(body, Deployment) or is_deployment_list(body):
        if client is not None:
            raise ValueError("`client` is for sweeps of the free body; a sweep of deployments "
                             "runs on this machine's cores")
        return sweep_deployments(body, omega0, q0, t_end, frames, dt, method, rtol=rtol,
                                 atol=atol, max_steps=max_steps, block=block, threads=threads,
                                 progress=progress)
    swapped = swapped_error(body, omega0, "sweep")
    t_end, frames, max_steps = checked_run(t_end, frames, method, max_steps)
    threads = checked_threads(threads)
    block = as_int("block", block, minimum=1)
    if progress is not None and not isinstance(progress, bool):
        raise TypeError(f"`progress` must be True, False or None, got {progress!r}")
    submit = _dask_runner(client) if client is not None else None
    with warnings.catch_warnings():
        if swapped is not None:  # the error says more than the warning about the moments
            warnings.simplefilter("ignore", InertiaWarning)
        inertia, omega, q, shape = batch_rows(body, omega0, q0, max_batch_ndim=None,
                                              stacklevel=3)
    check_tolerances(method, dt, rtol, atol)
    if swapped is not None:  # refused once every other argument passed
        raise swapped
    omega_p, q_p = principal_rows(body, omega, q)
    step, rtol_, atol_ = plan_batch_step(inertia, omega_p, t_end, frames, dt, method, rtol, atol,
                                         shape, stacklevel=3)
    m = len(omega)
    run: dict[str, Any] = dict(t_end=t_end, frames=frames, dt=step, method=method,
                               max_steps=max_steps, rtol=rtol_, atol=atol_, threads=threads)
    blocks = [(inertia[a:a + block], omega_p[a:a + block], q_p[a:a + block])
              for a in range(0, m, block)]
    bar = tqdm(total=m, desc="sweep", unit="run", leave=False,
               disable=None if progress is None else not progress,
               delay=_PROGRESS_DELAY if progress is None else 0.0)
    with bar:
        if submit is None:
            parts = []
            for k, rows in enumerate(blocks):
                try:
                    parts.append(run_block(*rows, **run))
                except ValueError as exc:
                    raise row_error(exc, k * block, shape) from None
                bar.update(len(rows[0]))
        else:
            parts = submit(blocks, run, lambda n: bar.update(n), lambda exc, k: row_error(
                exc, k * block, shape))
    columns = _concatenate(parts, m)
    return Sweep(
        inertia=inertia.reshape(shape + (3,)),
        omega0=omega.reshape(shape + (3,)),
        q0=q.reshape(shape + (4,)),
        flips=columns["flips"].reshape(shape),
        first_flip=columns["first_flip"].reshape(shape),
        period=columns["period"].reshape(shape),
        exact_period=columns["exact_period"].reshape(shape),
        tilt=columns["tilt"].reshape(shape),
        drift=BatchDrift(*(columns[f"drift.{k}"] for k in BatchDrift._fields)).reshape(shape),
        t_end=t_end,
        method=method,
        dt=columns["dt"].reshape(shape),
        n_steps=columns["n_steps"].reshape(shape),
        nfev=columns["nfev"].reshape(shape),
        status=np.asarray(_core.RUN_STATUSES)[columns["status"]].reshape(shape),
    )


def run_block(inertia: np.ndarray, omega: np.ndarray, q: np.ndarray, *, t_end: float,
              frames: int, dt: float | None, method: str, max_steps: int, rtol: float, atol: float,
              threads: int | None) -> dict[str, np.ndarray]:
    """One block of a sweep, in the core: flat columns of per-run values (also what a Dask
    task runs, on a worker, with arrays as its deserialiser left them)."""
    inertia, omega, q = (np.require(a, np.float64, ["C", "A"]) for a in (inertia, omega, q))
    out = _core.sweep(inertia, omega, q, t_end, frames, dt, method, max_steps, rtol, atol,
                      threads)
    columns = {k: getattr(out, k) for k in ("flips", "status", "first_flip", "period",
                                            "exact_period", "tilt")}
    columns.update({k: getattr(out.runs, k) for k in ("nfev", "n_steps", "n_rejected", "dt")})
    columns.update({f"drift.{k}": v for k, v in zip(BatchDrift._fields, out.runs.drift)})
    return columns  # plain arrays: a Dask task sends them between machines


def _concatenate(parts: list[dict[str, np.ndarray]], m: int) -> dict[str, np.ndarray]:
    if not parts:  # no runs: empty columns of the right kinds
        return {k: np.empty(0, dtype=np.int64 if k in ("flips", "n_steps", "nfev", "status")
                            else float)
                for k in ("flips", "first_flip", "period", "exact_period", "tilt", "dt",
                          "n_steps", "nfev", "status",
                          *(f"drift.{k}" for k in BatchDrift._fields))}
    columns = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
    assert all(len(v) == m for v in columns.values())
    return columns


Runner = Callable[[list[tuple[np.ndarray, np.ndarray, np.ndarray]], dict[str, Any],
                   Callable[[int], Any], Callable[[ValueError, int], ValueError]],
                  list[dict[str, np.ndarray]]]


def _dask_runner(client: Any) -> Runner:
    """Maps blocks on a Dask cluster, one task each, and gathers them in order."""
    try:
        import distributed
    except ImportError:
        raise ImportError(
            "`client` needs dask.distributed: pip install dzhanibekov[dask]"
        ) from None
    if not isinstance(client, distributed.Client):
        raise TypeError(
            f"`client` must be a dask.distributed.Client, got {type(client).__name__}"
        )
    cluster: Any = client  # distributed is untyped

    def submit(blocks: list[tuple[np.ndarray, np.ndarray, np.ndarray]], run: dict[str, Any],
               advance: Callable[[int], Any],
               renamed: Callable[[ValueError, int], ValueError]) -> list[dict[str, np.ndarray]]:
        columns = [[rows[k] for rows in blocks] for k in range(3)]
        futures = cluster.map(run_block, *columns, pure=False, **run)
        index = {f.key: k for k, f in enumerate(futures)}
        try:
            completed: Any = distributed.as_completed
            for done in completed(futures):
                k = index[done.key]
                if done.status == "error":
                    exc = done.exception()
                    if isinstance(exc, ValueError):
                        raise renamed(exc, k) from None
                    raise exc
                advance(len(blocks[k][0]))
            parts: list[dict[str, np.ndarray]] = cluster.gather(futures)
        except BaseException:
            cluster.cancel(futures)
            raise
        return parts

    return submit
