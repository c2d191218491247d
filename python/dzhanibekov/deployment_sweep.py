"""Which deployments tumble: :func:`~dzhanibekov.sweep` over deployments.

After its last knot a deployed body is constant, so the rest of its motion is the free
rotation of the deployed body from the state it has reached, and the closed form decides
whether that tumbles: the flip period of the deployed body (in its principal axes) at that
state is finite iff the intermediate axis turns over (:func:`~dzhanibekov.flip_period`).
So a run needs only the deployment itself integrated, however long the user would watch.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
from tqdm.auto import tqdm

from . import _core
from ._args import as_float, as_int
from .deployment import Deployment
from .errors import DivergedError, DzhanibekovError, TooLargeError
from .models import _drift, _each, _rows, _runs, is_deployment_list
from .results import BatchDrift, DeploymentSweep

__all__ = ["sweep_deployments"]

_PROGRESS_DELAY = 1.0
"""Seconds before the progress bar shows (`progress=None`): quick sweeps show none."""


def sweep_deployments(
    deployments: Any,
    omega0: Any,
    q0: Any,
    t_end: Any,
    frames: Any,
    dt: Any,
    method: Any,
    *,
    rtol: Any,
    atol: Any,
    max_steps: Any,
    block: Any,
    threads: Any,
    progress: Any,
) -> DeploymentSweep:
    """`dzhanibekov.sweep` of deployments (see there); a :class:`DeploymentSweep`."""
    models = [deployments] if isinstance(deployments, Deployment) else list(deployments)
    if not is_deployment_list(models):
        raise TypeError("`body` must be a dz.Deployment or a list of them")
    if not isinstance(method, str):
        raise TypeError(f"`method` must be a string, got {type(method).__name__}")
    t_end = as_float("t_end", t_end, positive=True)
    frames = as_int("frames", frames, minimum=2)
    max_steps = as_int("max_steps", max_steps, minimum=1)
    block = as_int("block", block, minimum=1)
    dt = None if dt is None else as_float("dt", dt, positive=True)
    threads = None if threads is None else as_int("threads", threads, minimum=1)
    if progress is not None and not isinstance(progress, bool):
        raise TypeError(f"`progress` must be True, False or None, got {progress!r}")
    rtol_ = 1e-9 if rtol is None else as_float("rtol", rtol, positive=True)
    atol_ = 1e-12 if atol is None else as_float("atol", atol, positive=True)
    omega, q = _rows("omega0", omega0, 3), _rows("q0", q0, 4)
    m = _runs(deployments=models, omega0=omega, q0=q)
    models = _each(models, m)
    omega = np.ascontiguousarray(np.broadcast_to(omega, (m, 3)))
    q = np.ascontiguousarray(np.broadcast_to(q, (m, 4)))
    last = max(float(d.times[-1]) for d in models)
    if t_end < last:
        raise ValueError(f"`t_end` must reach the last knot of every deployment ({last:g}), "
                         f"got {t_end:g}: the verdict is that of the free motion after it")
    rows = _Rows([d.times.tolist() for d in models], [d.tensors.ravel().tolist() for d in models],
                 [(w[0], w[1], w[2]) for w in omega.tolist()],
                 [(p[0], p[1], p[2], p[3]) for p in q.tolist()])
    # one step for every run (with dt=None the smallest its runs would pick alone), so that
    # no run depends on the blocks it falls in
    step = _core.deployment_step(rows.times, rows.tensors, rows.omega0, rows.q0, t_end, frames,
                                 dt, method, max_steps, rtol_, atol_)
    run = _Run(t_end, frames, dt if step is None else step, method, max_steps, rtol_, atol_,
               threads)
    outs: list[_core.ModelResult | str | None] = [None] * m
    bar = tqdm(total=m, desc="sweep", unit="run", leave=False,
               disable=None if progress is None else not progress,
               delay=_PROGRESS_DELAY if progress is None else 0.0)
    with bar:
        for start in range(0, m, block):
            todo = list(range(start, min(start + block, m)))
            bar.update(_run_block(rows, run, todo, outs))
    return _summarised(models, omega, q, outs, t_end, method)


class _Rows(NamedTuple):
    """Every run's deployment and start, as the core takes them."""

    times: list[list[float]]
    tensors: list[list[float]]
    omega0: list[tuple[float, float, float]]
    q0: list[tuple[float, float, float, float]]

    def take(self, rows: list[int]) -> _Rows:
        return _Rows([self.times[i] for i in rows], [self.tensors[i] for i in rows],
                     [self.omega0[i] for i in rows], [self.q0[i] for i in rows])


class _Run(NamedTuple):
    """What every run shares."""

    t_end: float
    frames: int
    dt: float | None
    method: str
    max_steps: int
    rtol: float
    atol: float
    threads: int | None


def _run_block(rows: _Rows, run: _Run, todo: list[int],
               outs: list[_core.ModelResult | str | None]) -> int:
    """Runs the rows `todo` into `outs`; a row that diverges or needs too many steps gets
    its status there instead, and the others run again without it."""
    done = len(todo)
    while todo:
        try:
            part = rows.take(todo)
            results = _core.simulate_deployments(
                part.times, part.tensors, part.omega0, part.q0, run.t_end, run.frames, run.dt,
                run.method, run.max_steps, run.rtol, run.atol, False, run.threads)
        except DzhanibekovError as exc:
            status = _status(exc)
            if exc.row is None or not 0 <= exc.row < len(todo):
                raise
            if not status:  # bad input, not a run that failed: say which run
                raise exc.at(todo[exc.row]) from None
            outs[todo.pop(exc.row)] = status
            continue
        for i, out in zip(todo, results):
            outs[i] = out
        todo = []
    return done


def _status(exc: DzhanibekovError) -> str:
    """The status of a run that failed, as `Sweep.status` names it; "" for bad input."""
    if isinstance(exc, DivergedError):
        return "diverged"
    if isinstance(exc, TooLargeError):
        return "too many steps"
    return ""


def _summarised(models: list[Deployment], omega: np.ndarray, q: np.ndarray,
                outs: list[_core.ModelResult | str | None], t_end: float,
                method: str) -> DeploymentSweep:
    """The per-run numbers of the finished runs' frames (NaN for the others)."""
    m = len(models)
    inertia = np.empty((m, 3))
    deployed = np.full((m, 3), np.nan)
    period = np.full(m, np.nan)
    change = np.full(m, np.nan)
    drift = np.full((4, m), np.nan)
    dt = np.full(m, np.nan)
    n_steps = np.zeros(m, dtype=np.int64)
    nfev = np.zeros(m, dtype=np.int64)
    for i, (d, out) in enumerate(zip(models, outs)):
        moments, axes = np.linalg.eigh(d.tensors[-1])
        inertia[i] = moments
        if not isinstance(out, _core.ModelResult):
            continue
        w = axes.T @ out.omega[-1]  # in the deployed body's principal axes
        deployed[i] = w
        period[i] = _core.flip_period(_core.RigidBody((moments[0], moments[1], moments[2])),
                                      (float(w[0]), float(w[1]), float(w[2])))
        e = out.energy
        change[i] = (e[-1] - e[0]) / e[0] if e[0] > 0 else 0.0
        drift[:, i] = _drift(out)
        dt[i], n_steps[i], nfev[i] = out.dt, out.n_steps, out.nfev
    status = np.array([out if isinstance(out, str) else "ok" for out in outs], dtype=object)
    assert set(status) <= set(_core.RUN_STATUSES)
    return DeploymentSweep(
        deployments=tuple(models), omega0=omega, q0=q, inertia=inertia,
        omega_deployed=deployed, flip_period=period, tumbles=np.isfinite(period),
        energy_change=change, drift=BatchDrift(*drift), t_end=t_end, method=method, dt=dt,
        n_steps=n_steps, nfev=nfev, status=status.astype(str),
    )
