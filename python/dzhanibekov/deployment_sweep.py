"""Which deployments tumble: :func:`~dzhanibekov.sweep` over deployments.

After its last knot a deployed body is constant, so the rest of its motion is the free
rotation of the deployed body from the state it has reached, and the closed form decides
whether that tumbles: the flip period of the deployed body (in its principal axes) at that
state is finite iff the intermediate axis turns over (:func:`~dzhanibekov.flip_period`).
So a run needs only the deployment itself integrated, however long the user would watch.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from tqdm.auto import tqdm

from . import _core, _tables
from ._args import as_int, run_options
from .errors import DivergedError, DzhanibekovError, TooLargeError
from .results import BatchDrift, DeploymentSweep, batch_drift
from .rows import Rows, row_error, rows_of
from .simulate import plan
from .system import Systems

__all__ = ["sweep_deployments"]

_PROGRESS_DELAY = 1.0
"""Seconds before the progress bar shows (`progress=None`): quick sweeps show none."""


def sweep_deployments(
    deployments: Any,
    omega0: Any,
    q0: Any,
    *,
    block: Any,
    progress: Any,
    **options: Any,
) -> DeploymentSweep:
    """`dzhanibekov.sweep` of deployments (see there); a :class:`DeploymentSweep`. The runs
    keep no frames, only where each ended."""
    rows = rows_of(deployments, omega0, q0, function="sweep", max_batch_ndim=1, stacklevel=4)
    block = as_int("block", block, minimum=1)
    if progress is not None and not isinstance(progress, bool):
        raise TypeError(f"`progress` must be True, False or None, got {progress!r}")
    opts = run_options(flips=False, **options)
    m = len(rows)
    models = [rows.systems[i].body for i in range(m)]
    last = max((float(d.times[-1]) for d in models), default=0.0)
    if opts.t_end < last:
        raise ValueError(f"`t_end` must reach the last knot of every deployment ({last:g}), "
                         f"got {opts.t_end:g}: the verdict is that of the free motion after it")
    # one step for every run (with dt=None the smallest its runs would pick alone), so that
    # no run depends on the blocks it falls in
    opts = plan(rows, opts, stacklevel=4)
    ends: list[Any] = [None] * m
    bar = tqdm(total=m, desc="sweep", unit="run", leave=False,
               disable=None if progress is None else not progress,
               delay=_PROGRESS_DELAY if progress is None else 0.0)
    with bar:
        for start in range(0, m, block):
            todo = list(range(start, min(start + block, m)))
            bar.update(_run_block(rows, opts, todo, ends))
    return _summarised(rows, ends, opts)


def _run_block(rows: Rows, options: _core.RunOptions, todo: list[int], ends: list[Any]) -> int:
    """Runs the rows `todo` into `ends` (each a row of the core's result, or the status of a
    run that did not finish); a row that diverges or needs too many steps gets its status
    there, and the others run again without it."""
    done = len(todo)
    while todo:
        each = Systems(len(todo), each=tuple(rows.systems[i] for i in todo))
        part = Rows(each, rows.omega[todo], rows.q[todo], (len(todo),), True)
        try:
            systems, _ = part.core()
            out = _core.simulate_batch(systems, part.omega, part.q, options, False)
        except DzhanibekovError as exc:
            status = _status(exc)
            if exc.row is None or not 0 <= exc.row < len(todo):
                raise
            if not status:  # bad input, not a run that failed: say which run
                raise row_error(exc.at(todo[exc.row]), rows) from None
            ends[todo.pop(exc.row)] = status
            continue
        for k, i in enumerate(todo):
            ends[i] = (out, k)
        todo = []
    return done


def _status(exc: DzhanibekovError) -> str:
    """The status of a run that failed, as `Sweep.status` names it; "" for bad input."""
    if isinstance(exc, DivergedError):
        return "diverged"
    if isinstance(exc, TooLargeError):
        return "too many steps"
    return ""


def _summarised(rows: Rows, ends: list[Any], options: _core.RunOptions) -> DeploymentSweep:
    """The per-run numbers of the finished runs' ends (NaN for the others)."""
    m = len(rows)
    inertia = np.empty((m, 3))
    deployed = np.full((m, 3), np.nan)
    period = np.full(m, np.nan)
    change = np.full(m, np.nan)
    drift = np.full((5, m), np.nan)
    dt = np.full(m, np.nan)
    n_steps = np.zeros(m, dtype=np.int64)
    nfev = np.zeros(m, dtype=np.int64)
    kept: tuple[str, ...] = ()
    for i, end in enumerate(ends):
        system = rows.systems[i]
        last = system.body.tensors[-1]
        deployed_body = _core.RigidBody.from_tensor(last.tolist())
        axes = np.array(deployed_body.principal_axes)
        inertia[i] = deployed_body.inertia
        if isinstance(end, str) or end is None:
            continue
        out, k = end
        w_end, q_end = out.end_omega[k], out.end_q[k]
        deployed[i] = axes.T @ w_end  # in the deployed body's principal axes
        period[i] = _core.flip_period(deployed_body, (float(w_end[0]), float(w_end[1]),
                                                      float(w_end[2])))
        energy, _, _ = _core.observe(
            system._core, np.array([0.0, options.t_end]), np.stack([rows.omega[i], w_end]),
            np.stack([rows.q[i] / np.linalg.norm(rows.q[i]), q_end]), np.empty((2, 0)))
        change[i] = (energy[1] - energy[0]) / energy[0] if energy[0] > 0 else 0.0
        d = batch_drift(out.runs).row(k)
        drift[:, i] = [d.energy, d.momentum, d.momentum_world, d.q_norm,
                       np.nan if d.jacobi is None else d.jacobi]
        kept = d.kept
        dt[i], n_steps[i], nfev[i] = out.runs.dt[k], out.runs.n_steps[k], out.runs.nfev[k]
    status = np.array([end if isinstance(end, str) else "ok" for end in ends], dtype=object)
    assert set(status) <= set(_core.RUN_STATUSES)
    return DeploymentSweep(
        deployments=tuple(rows.systems[i].body for i in range(m)), omega0=rows.omega,
        q0=rows.q, inertia=inertia, omega_deployed=deployed, flip_period=period,
        tumbles=np.isfinite(period), energy_change=change,
        drift=BatchDrift.of(lambda k: drift[_tables.DRIFTS.index(k)], None,
                            kept or ("momentum", "momentum_world", "q_norm")),
        t_end=options.t_end, method=options.method, dt=dt, n_steps=n_steps, nfev=nfev,
        status=status.astype(str),
    )
