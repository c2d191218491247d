"""Runs of the models beyond the constant free body: deployments and damped bodies.

The core declares which methods run them (``rk4``, ``rk4_projected``, ``dopri5``,
``dop853``) and refuses the others by name; this module only coerces and wraps.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from . import _core
from ._args import as_array, as_float, as_int, check_size
from .body import Body, as_body
from .damper import Damper, warn_stiff
from .deployment import Deployment
from .methods import DEFAULT_ATOL, DEFAULT_MAX_STEPS, DEFAULT_METHOD, DEFAULT_RTOL
from .results import Batch, BatchDrift, Drift, Trajectory

__all__ = ["simulate_model", "simulate_deployments", "simulate_model_batch", "is_model_batch",
           "is_deployment_list"]


def _drift(out: _core.ModelResult) -> Drift:
    """The core's drift of what the model keeps (momentum, its norm, |q|); the energy entry is
    its largest relative change, which a model's law makes (a deployment's work, a damper's
    loss). Measured in the run's own units, so rates near the ends of float64 do not
    underflow in the norms."""
    energy, momentum, momentum_world, q_norm = out.drift
    return Drift(energy=energy, momentum=momentum, momentum_world=momentum_world,
                 q_norm=q_norm)


def simulate_model(
    model: Deployment | Body | Any,
    omega0: Any,
    q0: Any,
    t_end: Any,
    frames: Any,
    dt: Any,
    method: str,
    *,
    damper: Damper | None = None,
    sigma0: Any = None,
    rtol: float | None = None,
    atol: float | None = None,
    max_steps: Any,
    flips: bool = True,
) -> Trajectory:
    """Runs a deployment (`model` a :class:`Deployment`) or a body with a damper; see
    `dzhanibekov.simulate` for the arguments."""
    if not isinstance(model, Deployment) and not isinstance(damper, Damper):
        raise TypeError(f"`damper` must be a dz.Damper, got {type(damper).__name__}")
    omega = as_array("omega0", omega0, "(3,)", last=3, ndim=(1,))
    q = as_array("q0", q0, "(4,)", last=4, ndim=(1,))
    t_end = as_float("t_end", t_end, positive=True)
    frames = as_int("frames", frames, minimum=2)
    max_steps = as_int("max_steps", max_steps, minimum=1)
    dt = None if dt is None else as_float("dt", dt, positive=True)
    if not isinstance(method, str):
        raise TypeError(f"`method` must be a string, got {type(method).__name__}")
    rtol_ = DEFAULT_RTOL if rtol is None else as_float("rtol", rtol, positive=True)
    atol_ = DEFAULT_ATOL if atol is None else as_float("atol", atol, positive=True)
    check_size(frames * 8 * 24, f"frames={frames}", "ask for fewer frames")
    omega_t = (float(omega[0]), float(omega[1]), float(omega[2]))
    q_t = (float(q[0]), float(q[1]), float(q[2]), float(q[3]))
    sigma = None
    if isinstance(model, Deployment):
        if damper is not None:
            raise ValueError("`damper` cannot be combined with a Deployment (a damped body "
                             "has constant inertia)")
        out = _core.simulate_deployment(
            model.times, model.tensors.reshape(-1, 9), omega_t, q_t, t_end, frames, dt,
            method, max_steps, rtol_, atol_, bool(flips))
        body = _first_body(model)
    else:
        if not isinstance(damper, Damper):
            raise TypeError(f"`damper` must be a dz.Damper, got {type(damper).__name__}")
        body = as_body(model)
        tensor = getattr(body, "tensor", None)
        inertia = np.asarray(tensor if tensor is not None else np.diag(body.inertia), float)
        s = omega if sigma0 is None else as_array("sigma0", sigma0, "(3,)", last=3, ndim=(1,))
        _check_stiffness(inertia.reshape(1, 9), [damper], omega[None], s[None], q[None],
                         t_end, frames, dt, method, max_steps, rtol_, atol_)
        out = _core.simulate_damper(
            tuple(inertia.ravel().tolist()), damper.inertia, damper.damping, omega_t,
            (float(s[0]), float(s[1]), float(s[2])), q_t, t_end, frames, dt, method,
            max_steps, rtol_, atol_, bool(flips))
        sigma = out.sigma
    traj = Trajectory(
        t=out.t,
        omega=out.omega,
        q=out.q,
        flip_times=out.flip_times,
        body=body,
        method=method,
        dt=out.dt,
        n_steps=out.n_steps,
        nfev=out.nfev,
        drift=_drift(out),
        n_rejected=out.n_rejected,
        model=model if isinstance(model, Deployment) else damper,
        sigma=sigma,
    )
    return _with_invariants(traj, out)


def _check_stiffness(tensors: np.ndarray, dampers: Sequence[Damper], omega: np.ndarray,
                     sigma: np.ndarray, q: np.ndarray, t_end: float, frames: int,
                     dt: float | None, method: str, max_steps: int, rtol: float,
                     atol: float) -> None:
    """Warns of a stiff damper (see `damper.warn_stiff`) for rows of tensors (M, 9),
    dampers, rates and attitudes, at the step the core will take."""
    j = np.array([d.inertia for d in dampers])
    c = np.array([d.damping for d in dampers])
    step = _core.damper_step(tensors, j, c, omega, sigma, q, t_end, frames, dt, method,
                             max_steps, rtol, atol)
    t = tensors.reshape(-1, 3, 3)
    least = np.linalg.eigvalsh(t)[:, 0]
    rates = c * (1.0 / j + 1.0 / least)
    # Ω = √(2T / I_min): T of body and sphere never rises, so it bounds |ω| over the run;
    # taken in units of the largest rate, so that rates near the ends of float64 do not
    # overflow or underflow in the squares
    size = np.maximum(np.abs(omega).max(axis=1), np.abs(sigma).max(axis=1))
    unit = np.where(size > 0, size, 1.0)[:, None]
    w, s = omega / unit, sigma / unit
    energy = np.einsum("mi,mij,mj->m", w, t, w) + j * (s**2).sum(axis=1)
    warn_stiff(step, rates, unit[:, 0] * np.sqrt(energy / least), method, stacklevel=5)


def _with_invariants(traj: Trajectory, out: _core.ModelResult) -> Trajectory:
    traj._invariants.update(
        energy=out.energy,
        momentum_body=out.momentum_body,
        momentum_world=out.momentum_world,
        q_norm=np.linalg.norm(out.q, axis=1),
    )
    return traj


def simulate_deployments(
    deployments: Any,
    omega0: Any,
    q0: Any = (1.0, 0.0, 0.0, 0.0),
    t_end: float = 100.0,
    frames: int = 201,
    dt: float | None = 1e-3,
    method: str = DEFAULT_METHOD,
    *,
    rtol: float | None = None,
    atol: float | None = None,
    max_steps: int = DEFAULT_MAX_STEPS,
) -> list[Trajectory]:
    """Runs several deployments at once on all cores: a sweep over deployment durations,
    deployed moments or starts ("which deployments tumble?").

    Parameters
    ----------
    deployments : sequence of Deployment
        One per run.
    omega0 : array_like, shape (3,) or (M, 3)
        Initial body rates, shared or one row per run.
    q0 : array_like, shape (4,) or (M, 4)
        Initial attitudes, shared or one row per run.
    t_end, frames, dt, method, rtol, atol, max_steps
        As for :func:`~dzhanibekov.simulate`; every run shares the frame grid, and with
        ``dt=None`` a fixed-step method takes the smallest of the steps its runs would pick
        alone (an adaptive method's runs each pick their own first step, as alone).

    Returns
    -------
    list of Trajectory
        One per run, each equal to its single run.

    Raises
    ------
    TypeError, ValueError
        As :func:`~dzhanibekov.simulate`; a run's error names its row.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> runs = dz.simulate_deployments(
    ...     [dz.Deployment([10.0, 20.0], [(1, 2, 3), (1, 3, r)]) for r in (2.0, 4.0)],
    ...     (0.01, 0.01, 1.0), t_end=200.0)
    >>> [bool(dz.axis_shares(t)[:, 2].min() < 0) for t in runs]  # z turned over?
    [True, False]
    """
    if isinstance(deployments, Deployment) or not hasattr(deployments, "__len__"):
        raise TypeError("`deployments` must be a sequence of dz.Deployment")
    items = list(deployments)
    if not items or not all(isinstance(d, Deployment) for d in items):
        raise TypeError("`deployments` must be a non-empty sequence of dz.Deployment")
    m = len(items)
    omega = as_array("omega0", omega0, "(3,) or (M, 3)", last=3, ndim=(1, 2))
    q = as_array("q0", q0, "(4,) or (M, 4)", last=4, ndim=(1, 2))
    omega = np.broadcast_to(omega, (m, 3)) if omega.ndim == 1 or len(omega) == 1 else omega
    q = np.broadcast_to(q, (m, 4)) if q.ndim == 1 or len(q) == 1 else q
    if len(omega) != m or len(q) != m:
        raise ValueError(f"`omega0` and `q0` must have one row per deployment ({m}) or one "
                         f"shared row, got {len(omega)} and {len(q)}")
    t_end = as_float("t_end", t_end, positive=True)
    frames = as_int("frames", frames, minimum=2)
    max_steps = as_int("max_steps", max_steps, minimum=1)
    dt = None if dt is None else as_float("dt", dt, positive=True)
    if not isinstance(method, str):
        raise TypeError(f"`method` must be a string, got {type(method).__name__}")
    rtol_ = DEFAULT_RTOL if rtol is None else as_float("rtol", rtol, positive=True)
    atol_ = DEFAULT_ATOL if atol is None else as_float("atol", atol, positive=True)
    check_size(m * frames * 8 * 24, f"{m} runs of frames={frames}", "ask for fewer frames")
    outs = _core.simulate_deployments(
        [d.times.tolist() for d in items], [d.tensors.ravel().tolist() for d in items],
        [tuple(r) for r in omega.tolist()], [tuple(r) for r in q.tolist()], t_end, frames,
        dt, method, max_steps, rtol_, atol_)
    return [
        _with_invariants(Trajectory(
            t=out.t, omega=out.omega, q=out.q, flip_times=None, body=_first_body(d),
            method=method, dt=out.dt, n_steps=out.n_steps, nfev=out.nfev,
            drift=_drift(out), n_rejected=out.n_rejected, model=d), out)
        for d, out in zip(items, outs)
    ]


def _first_body(d: Deployment) -> Body:
    """The body at the first knot, by its principal moments."""
    m = d.tensors[0]
    return Body(np.linalg.eigvalsh(m) if _off_diagonal(m) else m.diagonal())


def _off_diagonal(m: np.ndarray) -> bool:
    return bool(np.any(m - np.diag(m.diagonal())))


def _is_list_of(value: Any, kind: type) -> bool:
    return isinstance(value, (list, tuple)) and len(value) > 0 and \
        all(isinstance(v, kind) for v in value)


def is_deployment_list(model: Any) -> bool:
    """Whether `model` is a list (or tuple) of Deployments, one per run."""
    return _is_list_of(model, Deployment)


def is_model_batch(model: Any, omega0: Any, q0: Any, damper: Any, sigma0: Any) -> bool:
    """Whether a run of a deployment or a damped body has a batch axis: rates, attitudes or
    sigma0 of shape (M, ·), or a list of deployments, bodies, moments or dampers."""
    def ndim(value: Any) -> int:
        try:
            return int(np.ndim(value))
        except Exception:  # ragged, or no array at all: the checks will say so
            return 0

    return (ndim(omega0) >= 2 or ndim(q0) >= 2 or ndim(sigma0) >= 2
            or _is_list_of(model, Deployment) or _is_list_of(damper, Damper)
            or (damper is not None and (_is_list_of(model, Body)
                                        or (not isinstance(model, Body) and ndim(model) >= 2))))


def _rows(name: str, value: Any, width: int) -> np.ndarray:
    """`value` as rows (k, width): one shared row, or one per run."""
    a = as_array(name, value, f"({width},) or (M, {width})", last=width, ndim=(1, 2))
    return a.reshape(-1, width)


def _runs(**rows: Sequence[Any] | np.ndarray) -> int:
    """The number of runs M of inputs with one shared row or M rows each."""
    counts = {len(v) for v in rows.values()} - {1}
    if len(counts) > 1:
        given = ", ".join(f"`{k}` {len(v)}" for k, v in rows.items())
        raise ValueError(f"the inputs of a batch must give one row each or the same number of "
                         f"rows M, got {given}")
    return counts.pop() if counts else 1


def _each(rows: Sequence[Any], m: int) -> list[Any]:
    return list(rows) * m if len(rows) == 1 else list(rows)


def simulate_model_batch(
    model: Any,
    omega0: Any,
    q0: Any,
    t_end: Any,
    frames: Any,
    dt: Any,
    method: str,
    *,
    damper: Any = None,
    sigma0: Any = None,
    rtol: float | None = None,
    atol: float | None = None,
    max_steps: Any,
    threads: Any = None,
    flips: bool = True,
) -> Batch:
    """Many runs of deployments or damped bodies on all cores, as a :class:`Batch` whose
    rows equal their single runs bit for bit; see `dzhanibekov.simulate`."""
    if not isinstance(method, str):
        raise TypeError(f"`method` must be a string, got {type(method).__name__}")
    t_end = as_float("t_end", t_end, positive=True)
    frames = as_int("frames", frames, minimum=2)
    max_steps = as_int("max_steps", max_steps, minimum=1)
    dt = None if dt is None else as_float("dt", dt, positive=True)
    threads = None if threads is None else as_int("threads", threads, minimum=1)
    rtol_ = DEFAULT_RTOL if rtol is None else as_float("rtol", rtol, positive=True)
    atol_ = DEFAULT_ATOL if atol is None else as_float("atol", atol, positive=True)
    omega, q = _rows("omega0", omega0, 3), _rows("q0", q0, 4)
    if not np.all(np.any(q != 0, axis=1)):
        raise ValueError("`q0` must hold non-zero quaternions (Q, U, V, W), got (0, 0, 0, 0)")
    if isinstance(model, Deployment) or _is_list_of(model, Deployment):
        if damper is not None or sigma0 is not None:
            raise ValueError("`damper` cannot be combined with a Deployment (a damped body "
                             "has constant inertia)")
        models = [model] if isinstance(model, Deployment) else list(model)
        m = _runs(deployments=models, omega0=omega, q0=q)
        check_size(m * frames * 8 * 24, f"a batch of {m} runs × {frames} frames",
                   "ask for fewer runs or frames")
        models, omega, q = _each(models, m), _broadcast(omega, m), _broadcast(q, m)
        outs = _core.simulate_deployments(
            [d.times.tolist() for d in models], [d.tensors.ravel().tolist() for d in models],
            [tuple(r) for r in omega.tolist()], [tuple(r) for r in q.tolist()], t_end, frames,
            dt, method, max_steps, rtol_, atol_, bool(flips), threads)
        bodies = tuple(_first_body(d) for d in models)
        return _batch(outs, method, bodies, tuple(models))
    dampers = [damper] if isinstance(damper, Damper) else damper
    if not _is_list_of(dampers, Damper):
        raise TypeError("`damper` must be a dz.Damper or a list of them (one per run), got "
                        f"{type(damper).__name__}")
    if _is_list_of(model, Body):
        given = list(model)
    elif isinstance(model, Body):
        given = [model]
    else:
        given = [as_body(row) for row in _rows("body", model, 3)]
    sigma = omega if sigma0 is None else _rows("sigma0", sigma0, 3)
    m = _runs(body=given, damper=dampers, omega0=omega, sigma0=sigma, q0=q)
    check_size(m * frames * 8 * 27, f"a batch of {m} runs × {frames} frames",
               "ask for fewer runs or frames")
    runs: list[Body] = _each(given, m)
    dampers = _each(dampers, m)
    omega, q = _broadcast(omega, m), _broadcast(q, m)
    sigma = omega if sigma0 is None else _broadcast(sigma, m)
    tensors = np.ascontiguousarray([b.tensor.ravel() for b in runs], dtype=np.float64)
    j = np.array([d.inertia for d in dampers])
    c = np.array([d.damping for d in dampers])
    _check_stiffness(tensors, dampers, omega, sigma, q, t_end, frames, dt, method, max_steps,
                     rtol_, atol_)
    outs = _core.simulate_dampers(tensors, j, c, omega, sigma, q, t_end, frames, dt, method,
                                  max_steps, rtol_, atol_, bool(flips), threads)
    return _batch(outs, method, tuple(runs), tuple(dampers))


def _broadcast(rows: np.ndarray, m: int) -> np.ndarray:
    return np.ascontiguousarray(np.broadcast_to(rows, (m, rows.shape[1])))


def _batch(outs: list[_core.ModelResult], method: str, bodies: tuple[Body, ...],
           models: tuple[Any, ...]) -> Batch:
    """The rows of a model batch (the core's per-run results) as one :class:`Batch`."""
    def stack(key: str) -> np.ndarray:
        return np.stack([getattr(out, key) for out in outs])

    drifts = [_drift(out) for out in outs]
    q = stack("q")
    # flips are located where every run's tensors are diagonal (else None, as for one run)
    flips = [out.flip_times for out in outs]
    located = all(f is not None for f in flips)
    counts = [len(f) if f is not None else 0 for f in flips]
    return Batch(
        t=outs[0].t,
        omega=stack("omega"),
        q=q,
        _flip_times=np.concatenate([f for f in flips if f is not None] or [np.empty(0)])
        if located else None,
        _flip_offsets=np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
        if located else None,
        inertia=np.array([b.inertia for b in bodies], dtype=np.float64),
        method=method,
        dt=np.array([out.dt for out in outs], dtype=np.float64),
        n_steps=np.array([out.n_steps for out in outs], dtype=np.int64),
        nfev=np.array([out.nfev for out in outs], dtype=np.int64),
        n_rejected=np.array([out.n_rejected for out in outs], dtype=np.int64),
        drift=BatchDrift(*(np.array(column) for column in zip(*drifts))),
        body=bodies,
        model=models,
        sigma=None if outs[0].sigma is None else stack("sigma"),
        _invariants=dict(energy=stack("energy"), momentum_body=stack("momentum_body"),
                         momentum_world=stack("momentum_world"),
                         q_norm=np.linalg.norm(q, axis=2)),
    )
