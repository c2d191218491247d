"""Sweeps: many runs that keep one number each, on all cores or on a Dask cluster.

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
from typing import TYPE_CHECKING, Any, overload

import numpy as np
from tqdm.auto import tqdm

from . import _core, _tables
from ._args import as_array, as_int, check_size, run_options
from .deployment import Deployment
from .deployment_sweep import sweep_deployments
from .options import NAMES, RunKeywords, RunOptions, merged
from .results import Batch, BatchDrift, DeploymentSweep, Sweep, _moments
from .rows import Rows, is_system_list, row_error, rows_of
from .simulate import plan
from .system import System, Systems

if TYPE_CHECKING:
    from typing_extensions import Unpack

__all__ = ["Batch", "BatchDrift", "Sweep", "DeploymentSweep", "sweep", "grid", "DEFAULT_BLOCK"]

_TAKES = tuple(n for n in NAMES if n != "flips")
"""The run options a sweep takes: it always counts the flips."""


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
    system: Deployment | list[Deployment] | tuple[Deployment, ...],
    omega0: Any,
    q0: Any = ...,
    *,
    options: RunOptions | None = ...,
    block: int = ...,
    client: Any = ...,
    **keywords: Unpack[RunKeywords],
) -> DeploymentSweep: ...


@overload
def sweep(
    system: Any,
    omega0: Any,
    q0: Any = ...,
    *,
    options: RunOptions | None = ...,
    block: int = ...,
    client: Any = ...,
    **keywords: Unpack[RunKeywords],
) -> Sweep: ...


def sweep(
    system: Any,
    omega0: Any,
    q0: Any = (1.0, 0.0, 0.0, 0.0),
    *,
    options: RunOptions | None = None,
    block: int = DEFAULT_BLOCK,
    client: Any = None,
    **keywords: Unpack[RunKeywords],
) -> Sweep | DeploymentSweep:
    """Runs a free rotation from every start and keeps a few numbers per run, no frames.

    Each run is the one :func:`~dzhanibekov.summarize` makes of the same inputs, step for
    step: its flips, drift and step are those of ``summarize`` bit for bit. The starts are
    cut into blocks of `block` runs; each block runs in the Rust core on all cores (RK4
    several runs at once in SIMD lanes), or, with `client`, as one task on a Dask cluster.
    No result depends on the blocks, the threads or the cluster.

    A sweep over deployments (`system` a :class:`Deployment` or a list of them) asks which
    deployments tumble and returns a :class:`DeploymentSweep`: each run integrates its
    deployment over ``[0, t_end]`` (which must reach every last knot) and the closed form
    decides the free motion after it (see Notes).

    Parameters
    ----------
    system : Body, Deployment, list of Deployment, or array_like, shape (3,) or S + (3,)
        The body, or principal moments: one body for all runs, or one per start. Or a
        deployment, or one per run (then the starts have at most one batch axis, M).
    omega0 : array_like, shape (3,) or S + (3,)
        Initial body rates ``(u0, v0, w0)``: one per start (say from :func:`grid`).
    q0 : array_like, shape (4,) or S + (4,)
        Initial attitude, scalar first; shared or one per start.
    options, t_end, frames, dt, method, rtol, atol, max_steps
        As for :func:`~dzhanibekov.simulate` (a :class:`~dzhanibekov.RunOptions`, its fields
        overridden by the keywords; a sweep always counts flips): the frames only set the substeps and where
        the drift is measured (an adaptive method's step that spans more than 64 frames at
        the last of them only: frames that are not kept are not all read off its
        interpolant). With ``dt=None`` every run of a fixed-step method takes
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
    given = merged("sweep", options, keywords, _TAKES)
    t_end, frames, dt, method = given.t_end, given.frames, given.dt, given.method
    rtol, atol, max_steps = given.rtol, given.atol, given.max_steps
    progress, threads = given.progress, given.threads
    if isinstance(system, Deployment) or (is_system_list(system) and any(
            isinstance(b, Deployment) or (isinstance(b, System) and "deployment" in b.kinds)
            for b in system)) or (isinstance(system, System) and "deployment" in system.kinds):
        if client is not None:
            raise ValueError("`client` is for sweeps of the free body; a sweep of deployments "
                             "runs on this machine's cores")
        return sweep_deployments(system, omega0, q0, t_end=t_end, frames=frames, dt=dt,
                                 method=method, rtol=rtol, atol=atol, max_steps=max_steps,
                                 threads=threads, block=block, progress=progress)
    settings = dict(t_end=t_end, frames=frames, dt=dt, method=method, rtol=rtol, atol=atol,
                    max_steps=max_steps, flips=True, threads=threads)
    core = run_options(**settings)  # before the rows: a bad option is named first
    rows = rows_of(system, omega0, q0, function="sweep", max_batch_ndim=8, stacklevel=3)
    block = as_int("block", block, minimum=1)
    if progress is not None and not isinstance(progress, bool):
        raise TypeError(f"`progress` must be True, False or None, got {progress!r}")
    if len(rows) and not rows.systems.first.is_free:
        raise ValueError(f"`system` of a sweep must be a constant body without parts (a sweep "
                         f"counts the free body's flips), got a system of "
                         f"{rows.systems.first.kinds}; simulate a batch of it instead")
    submit = _dask_runner(client) if client is not None else None
    core = plan(rows, core, stacklevel=3)
    settings["dt"] = core.dt
    m = len(rows)
    blocks = [rows.take(slice(a, a + block)) for a in range(0, m, block)]
    bar = tqdm(total=m, desc="sweep", unit="run", leave=False,
               disable=None if progress is None else not progress,
               delay=_PROGRESS_DELAY if progress is None else 0.0)
    with bar:
        if submit is None:
            parts = []
            for k, part in enumerate(blocks):
                try:
                    parts.append(run_block(part.systems, part.omega, part.q, **settings))
                except ValueError as exc:
                    raise row_error(exc, rows, k * block) from None
                bar.update(len(part))
        else:
            parts = submit([(p.systems, p.omega, p.q) for p in blocks], settings,
                           lambda n: bar.update(n),
                           lambda exc, k: row_error(exc, rows, k * block))
    columns = _concatenate(parts, m)
    shape = rows.shape
    return Sweep(
        inertia=_inertia(rows.systems).reshape(shape + (3,)),
        omega0=rows.omega.reshape(shape + (3,)),
        q0=rows.q.reshape(shape + (4,)),
        flips=columns["flips"].reshape(shape),
        first_flip=columns["first_flip"].reshape(shape),
        period=columns["period"].reshape(shape),
        exact_period=columns["exact_period"].reshape(shape),
        tilt=columns["tilt"].reshape(shape),
        drift=BatchDrift.of(lambda k: columns[f"drift.{k}"]).reshape(shape),
        t_end=core.t_end,
        method=core.method,
        dt=columns["dt"].reshape(shape),
        n_steps=columns["n_steps"].reshape(shape),
        nfev=columns["nfev"].reshape(shape),
        status=np.asarray(_core.RUN_STATUSES)[columns["status"]].reshape(shape),
    )


"""A free body's drift columns."""


def _inertia(systems: Systems) -> np.ndarray:
    """Each row's principal moments, (M, 3)."""
    if systems.moments is not None:
        return systems.moments
    if systems.shared is not None:
        return np.broadcast_to(np.array(_moments(systems.shared)), (len(systems), 3)).copy()
    return np.array([_moments(systems[i]) for i in range(len(systems))]).reshape(-1, 3)


def run_block(systems: Systems, omega: np.ndarray, q: np.ndarray,
              **settings: Any) -> dict[str, np.ndarray]:
    """One block of a sweep, in the core: flat columns of per-run values (also what a Dask
    task runs, on a worker, with arrays as its deserialiser left them)."""
    omega, q = (np.require(a, np.float64, ["C", "A"]) for a in (omega, q))
    moments = systems.moments
    if moments is not None:
        moments = np.require(moments, np.float64, ["C", "A"])
    out = _core.sweep(systems.core(), omega, q, run_options(**settings), inertia=moments)
    columns = {k: getattr(out, k) for k in ("flips", "status", "first_flip", "period",
                                            "exact_period", "tilt")}
    columns.update({k: getattr(out.runs, k) for k in ("nfev", "n_steps", "n_rejected", "dt")})
    columns.update({f"drift.{k}": v for k, v in zip(_tables.DRIFTS, out.runs.drift)})
    return columns  # plain arrays: a Dask task sends them between machines


def _concatenate(parts: list[dict[str, np.ndarray]], m: int) -> dict[str, np.ndarray]:
    if not parts:  # no runs: empty columns of the right kinds
        return {k: np.empty(0, dtype=np.int64 if k in ("flips", "n_steps", "nfev", "status")
                            else float)
                for k in ("flips", "first_flip", "period", "exact_period", "tilt", "dt",
                          "n_steps", "nfev", "status",
                          *(f"drift.{k}" for k in _tables.DRIFTS))}
    columns = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
    assert all(len(v) == m for v in columns.values())
    return columns


Runner = Callable[[list[tuple[Systems, np.ndarray, np.ndarray]], dict[str, Any],
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

    def submit(blocks: list[tuple[Systems, np.ndarray, np.ndarray]], run: dict[str, Any],
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
                advance(len(blocks[k][1]))
            parts: list[dict[str, np.ndarray]] = cluster.gather(futures)
        except BaseException:
            cluster.cancel(futures)
            raise
        return parts

    return submit
