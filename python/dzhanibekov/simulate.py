"""The two entry points: `simulate` a free rotation and `rotate` body points by its attitudes."""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _core
from ._checks import as_array, as_float, as_int, check_size
from .body import Body
from .trajectory import Drift, Trajectory

__all__ = ["METHODS", "simulate", "rotate"]

METHODS = ("rk4", "exact")
"""The methods on offer: integrators, and the closed-form solution."""

DEFAULT_MAX_STEPS = 10**10
"""Runs needing more steps are refused unless `max_steps` is raised (about 5 minutes of RK4)."""


def simulate(
    body: Body | Any,
    omega0: Any,
    q0: Any = (1.0, 0.0, 0.0, 0.0),
    t_end: float = 100.0,
    frames: int = 201,
    dt: float = 1e-3,
    method: str = "rk4",
    *,
    flips: bool = True,
    max_steps: int = DEFAULT_MAX_STEPS,
) -> Trajectory:
    """Simulates the free rotation of a rigid body (eq. 1 of the paper, corrected).

    Euler's equations for the body-frame angular velocity and the body-frame quaternion law
    ``q' = ½ q ⊗ (0, ω)`` are integrated in the Rust core without the GIL; only the frames
    are stored, so a run of 10⁸ steps with 201 frames holds 201 frames.

    Parameters
    ----------
    body : Body or array_like, shape (3,)
        The body, or its principal moments ``(Ix, Iy, Iz)``.
    omega0 : array_like, shape (3,)
        Initial body-frame angular velocity ``(u0, v0, w0)``, finite.
    q0 : array_like, shape (4,)
        Initial attitude, scalar first ``(Q, U, V, W)``; normalised here, must be non-zero.
    t_end : float
        End time, positive.
    frames : int
        Frames stored, at least 2, at times ``t_end * i / (frames - 1)`` exactly.
    dt : float
        Largest step: between frames the run takes equal substeps no longer than `dt`.
        Ignored by ``method="exact"``, which takes no steps.
    method : {"rk4", "exact"}
        ``"rk4"``: classic fixed-step fourth-order Runge–Kutta, the paper's method.
        ``"exact"``: the closed-form solution (Jacobi elliptic functions for ω, the angle
        about the fixed angular momentum from the elliptic integral of the third kind for
        q), evaluated directly at the frame times at a cost per frame independent of
        `t_end`; its trajectory reports ``n_steps = nfev = 0`` and ``dt = 0``, and its flip
        times are found from the solution by the same definition.
    flips : bool
        Locate the flips (default). Watching every step for them costs about 8% of an RK4
        run; ``flips=False`` skips it and leaves ``flip_times`` as None.
    max_steps : int
        Refuse runs needing more steps than this (default 10¹⁰).

    Returns
    -------
    Trajectory

    Raises
    ------
    TypeError
        An argument of the wrong kind (say, a string for `t_end` or a float for `frames`).
    ValueError
        An argument out of range, a run of more than `max_steps` steps, frames that would
        not fit in memory, or a state that stopped being finite (`dt` far too large).
    KeyboardInterrupt
        On Ctrl-C; the run stops within a fraction of a second.

    Examples
    --------
    >>> traj = simulate(Body(inertia=(52.0833, 27.0833, 41.6666)), (0.01, 0.01, 1.0))
    >>> traj.omega.shape, traj.q.shape, traj.t[-1]
    ((201, 3), (201, 4), 100.0)
    """
    body, omega0, q0, t_end, frames, dt, max_steps = _checked(
        body, omega0, q0, t_end, frames, dt, method, max_steps
    )
    check_size(frames * 8 * 8, f"frames={frames}", "ask for fewer frames")
    out = _core.simulate(
        body._core,
        tuple(omega0),
        tuple(q0),
        t_end,
        frames,
        dt,
        method,
        max_steps,
        True,
        bool(flips),
    )
    return Trajectory(
        t=t_end * (np.arange(frames) / (frames - 1)),
        omega=out["omega"],
        q=out["q"],
        flip_times=out["flip_times"] if flips else None,
        body=body,
        method=method,
        dt=out["dt"],
        n_steps=out["n_steps"],
        nfev=out["nfev"],
        drift=Drift(**out["drift"]),
    )


def _checked(
    body: Any, omega0: Any, q0: Any, t_end: Any, frames: Any, dt: Any, method: Any, max_steps: Any
) -> tuple[Body, np.ndarray, np.ndarray, float, int, float, int]:
    """The arguments of a run, coerced and checked (shared by `simulate` and `summarize`)."""
    if not isinstance(body, Body):
        body = Body(body)
    omega0 = as_array("omega0", omega0, "(3,)", last=3, ndim=(1,))
    q0 = as_array("q0", q0, "(4,)", last=4, ndim=(1,))
    if not np.any(q0):
        raise ValueError("`q0` must be a non-zero quaternion (Q, U, V, W), got (0, 0, 0, 0)")
    t_end = as_float("t_end", t_end, positive=True)
    frames = as_int("frames", frames, minimum=2)
    dt = as_float("dt", dt, positive=True)
    max_steps = as_int("max_steps", max_steps, minimum=1)
    if method not in METHODS:
        raise ValueError(f"`method` must be one of {METHODS}, got {method!r}")
    return body, omega0, q0, t_end, frames, dt, max_steps


def rotate(q: Any, points: Any, out: np.ndarray | None = None) -> np.ndarray:
    """Rotates body points into the world frame: ``M(q_i) · X_j`` for every frame and point.

    Uses the paper's trig-free matrix divided by ``|q|²`` (orthogonal for any non-zero q),
    on all cores for large inputs, without the GIL.

    Parameters
    ----------
    q : array_like, shape (N, 4) or (4,)
        Quaternions, scalar first; non-zero and finite.
    points : array_like, shape (P, 3) or (3,)
        Body-frame points, finite.
    out : ndarray, shape (N, P, 3), float64, C-contiguous, optional
        Where to write the result, for callers that rotate repeatedly: reusing a buffer
        avoids the page faults of fresh memory, which cost more than the rotation itself.

    Returns
    -------
    ndarray, shape (N, P, 3)
        World-frame points; a leading or middle axis is dropped when `q` or `points` is 1-D.

    Raises
    ------
    TypeError
        Non-numeric input, or `out` not a float64 ndarray.
    ValueError
        Wrong shapes, non-finite values, a zero quaternion, or an output larger than memory.

    Examples
    --------
    >>> rotate((1, 0, 0, 1), (1.0, 0.0, 0.0))  # a quarter turn about z
    array([0., 1., 0.])
    """
    qa = as_array("q", q, "(N, 4)", last=4, ndim=(1, 2))
    pa = as_array("points", points, "(P, 3)", last=3, ndim=(1, 2))
    q2, p2 = qa.reshape(-1, 4), pa.reshape(-1, 3)
    if not (q2 != 0).any(axis=1).all():
        raise ValueError("`q` rows must be non-zero quaternions, got a zero row")
    shape = (q2.shape[0], p2.shape[0], 3)
    kept = tuple(n for n, keep in zip(shape, (qa.ndim == 2, pa.ndim == 2, True)) if keep)
    if out is not None:
        if not isinstance(out, np.ndarray) or out.dtype != np.float64:
            raise TypeError("`out` must be a float64 numpy array")
        if out.shape != kept:
            raise ValueError(f"`out` must have shape {kept}, got {out.shape}")
        if not out.flags.c_contiguous or not out.flags.writeable:
            raise ValueError("`out` must be C-contiguous and writeable")
        _core.rotate(q2, p2, out.reshape(shape))
        return out
    check_size(
        8 * 3 * shape[0] * shape[1],
        f"rotating {shape[1]} points by {shape[0]} quaternions",
        "rotate fewer points or frames at a time, or pass `out`",
    )
    return _core.rotate(q2, p2).reshape(kept)
