"""Sweeps: many runs that keep one number each, on all cores or on a Dask cluster.

:func:`sweep` runs a free rotation for every start of a grid (or any array) of initial rates,
attitudes or bodies and keeps, per run, what a stability study asks: the flips counted and
their measured period, the exact period, the largest tilt of the spin axis and the
invariants' drift. No frames are kept: a sweep's memory grows with its runs, never with
their frames or steps. :func:`grid` builds the starts of a map; :mod:`dzhanibekov.maps`
draws one.

RK4 runs several starts at once in the SIMD lanes of every core; each run equals the single
run of its inputs (:func:`~dzhanibekov.summarize`) bit for bit. The runs are cut into blocks
of thousands; with ``client=`` (a ``dask.distributed.Client``) each block is one task on the
cluster, and the result is the same, bit for bit, as on one machine.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from tqdm import tqdm

from . import _core
from . import _tables
from ._checks import as_array, as_int, check_size
from .batch import (
    BatchDrift,
    batch_rows,
    checked_run,
    checked_threads,
    plan_batch_step,
    row_error,
)
from .simulate import DEFAULT_MAX_STEPS

__all__ = ["Sweep", "sweep", "grid", "DEFAULT_BLOCK"]

DEFAULT_BLOCK = 4096
"""Runs per block: per call to the core, per task on a Dask cluster."""

_PROGRESS_DELAY = 1.0
"""Seconds before the progress bar shows (`progress=None`): quick sweeps show none."""


@dataclass(frozen=True, eq=False)
class Sweep:
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
        How many times each run flipped (see :func:`~dzhanibekov.simulate`).
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
    def shape(self) -> tuple[int, ...]:
        """The shape of the starts, and of each per-run array."""
        return tuple(self.flips.shape)

    def __len__(self) -> int:
        return int(self.flips.size)

    @property
    def tilt_degrees(self) -> np.ndarray:
        """`tilt` in degrees."""
        degrees: np.ndarray = np.degrees(self.tilt)
        return degrees

    def __repr__(self) -> str:
        return (
            f"Sweep(shape={self.shape}, t_end={self.t_end:g}, method={self.method!r}, "
            f"flipped={int(np.count_nonzero(self.flips))})"
        )


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


def sweep(
    body: Any,
    omega0: Any,
    q0: Any = (1.0, 0.0, 0.0, 0.0),
    t_end: float = 100.0,
    frames: int = 201,
    dt: float | None = 1e-3,
    method: str = "rk4",
    *,
    rtol: float | None = None,
    atol: float | None = None,
    max_steps: int = DEFAULT_MAX_STEPS,
    block: int = DEFAULT_BLOCK,
    client: Any = None,
    progress: bool | None = None,
    threads: int | None = None,
) -> Sweep:
    """Runs a free rotation from every start and keeps a few numbers per run, no frames.

    Each run is the one :func:`~dzhanibekov.summarize` makes of the same inputs, step for
    step: its flips, drift and step are those of ``summarize`` bit for bit. The starts are
    cut into blocks of `block` runs; each block runs in the Rust core on all cores (RK4
    several runs at once in SIMD lanes), or, with `client`, as one task on a Dask cluster.
    No result depends on the blocks, the threads or the cluster.

    Parameters
    ----------
    body : Body or array_like, shape (3,) or S + (3,)
        The body, or principal moments: one body for all runs, or one per start.
    omega0 : array_like, shape (3,) or S + (3,)
        Initial body rates ``(u0, v0, w0)``: one per start (say from :func:`grid`).
    q0 : array_like, shape (4,) or S + (4,), or scipy.spatial.transform.Rotation
        Initial attitude, world-from-body, scalar first (or a scipy ``Rotation``); shared or
        one per start.
    t_end, frames, dt, method, rtol, atol, max_steps
        As for :func:`~dzhanibekov.simulate`: the frames only set the substeps and where
        the drift is measured. With ``dt=None`` every run takes the smallest of the steps
        its runs would pick alone.
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
    Sweep
        Per-run arrays of shape S, the starts' leading axes broadcast together.

    Raises
    ------
    TypeError
        An argument of the wrong kind, or a `client` that is not a Dask client.
    ValueError
        An argument out of range, mismatched leading axes, a run that diverged (naming it).
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

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> s = dz.sweep(dz.PAPER_INERTIA, dz.grid([0.01, 0.1], 0.01, 1.0), t_end=100.0)
    >>> s.shape, s.flips
    ((2,), array([2, 5]))
    >>> bool(abs(s.period[1] - s.exact_period[1]) < 1e-6 * s.exact_period[1])
    True
    """
    t_end, frames, max_steps = checked_run(t_end, frames, method, max_steps)
    threads = checked_threads(threads)
    block = as_int("block", block, minimum=1)
    if progress is not None and not isinstance(progress, bool):
        raise TypeError(f"`progress` must be True, False or None, got {progress!r}")
    submit = _dask_runner(client) if client is not None else None
    inertia, omega, q, shape = batch_rows(body, omega0, q0, max_batch_ndim=None, stacklevel=3)
    step, rtol_, atol_ = plan_batch_step(inertia, omega, t_end, frames, dt, method, rtol, atol,
                                         shape, stacklevel=3)
    m = len(omega)
    run: dict[str, Any] = dict(t_end=t_end, frames=frames, dt=step, method=method,
                               max_steps=max_steps, rtol=rtol_, atol=atol_, threads=threads)
    blocks = [(inertia[a:a + block], omega[a:a + block], q[a:a + block])
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
    )


def run_block(inertia: np.ndarray, omega: np.ndarray, q: np.ndarray, *, t_end: float,
              frames: int, dt: float, method: str, max_steps: int, rtol: float, atol: float,
              threads: int | None) -> dict[str, np.ndarray]:
    """One block of a sweep, in the core: flat columns of per-run values (also what a Dask
    task runs, on a worker, with arrays as its deserialiser left them)."""
    inertia, omega, q = (np.require(a, np.float64, ["C", "A"]) for a in (inertia, omega, q))
    out = _core.sweep(inertia, omega, q, t_end, frames, dt, method, max_steps, rtol, atol,
                      threads)
    drift = out.pop("drift")
    out.update({f"drift.{k}": v for k, v in drift.items()})
    return out


def _concatenate(parts: list[dict[str, np.ndarray]], m: int) -> dict[str, np.ndarray]:
    if not parts:  # no runs: empty columns of the right kinds
        return {k: np.empty(0, dtype=np.int64 if k in ("flips", "n_steps", "nfev") else float)
                for k in ("flips", "first_flip", "period", "exact_period", "tilt", "dt",
                          "n_steps", "nfev", *(f"drift.{k}" for k in BatchDrift._fields))}
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
