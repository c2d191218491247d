"""Runs of the models beyond the constant free body: deployments and damped bodies.

The core declares which methods run them (``rk4``, ``rk4_projected``, ``dopri5``,
``dop853``) and refuses the others by name; this module only coerces and wraps.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _core
from ._args import as_array, as_float, as_int, check_size
from .body import Body, as_body
from .damper import Damper
from .deployment import Deployment
from .methods import DEFAULT_ATOL, DEFAULT_MAX_STEPS, DEFAULT_METHOD, DEFAULT_RTOL
from .results import Drift, Trajectory

__all__ = ["simulate_model", "simulate_deployments"]


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
        ``dt=None`` the step planned for the first run.

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
