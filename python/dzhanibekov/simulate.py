"""The two entry points: `simulate` a free rotation and `rotate` body points by its attitudes."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, overload

import numpy as np

from . import _core
from ._args import as_array, as_float, as_int, check_size
from ._swap import check_not_swapped
from .accuracy import check_tolerances, plan_step
from .ensemble import Batch, checked_threads, is_batch, simulate_batch
from .body import Body, as_body
from .damper import Damper
from .deployment import Deployment
from .models import is_deployment_list, is_model_batch, simulate_model, simulate_model_batch
from .methods import DEFAULT_MAX_STEPS, DEFAULT_METHOD, METHODS, check_method
from .results import Drift, Trajectory
from .rotations import quaternions_of

__all__ = ["METHODS", "simulate", "rotate"]

MAX_COORDINATE = float(np.finfo(np.float64).max / 4)
"""The largest body-point coordinate `rotate` takes: a rotated coordinate sums three terms
each at most the largest coordinate, so nothing larger than this can overflow."""

@overload
def simulate(
    body: Body | Deployment | Sequence[float],
    omega0: Sequence[float],
    q0: Sequence[float] = ...,
    t_end: float = ...,
    frames: int = ...,
    dt: float | None = ...,
    method: str = ...,
    *,
    rtol: float | None = ...,
    atol: float | None = ...,
    flips: bool = ...,
    max_steps: int = ...,
    threads: int | None = ...,
    progress: bool | None = ...,
    damper: Damper | None = ...,
    sigma0: Sequence[float] | None = ...,
) -> Trajectory: ...


@overload
def simulate(
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
    flips: bool = ...,
    max_steps: int = ...,
    threads: int | None = ...,
    progress: bool | None = ...,
    damper: Damper | Sequence[Damper] | None = ...,
    sigma0: Any = ...,
) -> Trajectory | Batch: ...


def simulate(
    body: Body | Any,
    omega0: Any,
    q0: Any = (1.0, 0.0, 0.0, 0.0),
    t_end: float = 100.0,
    frames: int = 201,
    dt: float | None = None,
    method: str = DEFAULT_METHOD,
    *,
    rtol: float | None = None,
    atol: float | None = None,
    flips: bool = True,
    max_steps: int = DEFAULT_MAX_STEPS,
    threads: int | None = None,
    progress: bool | None = None,
    damper: Damper | Sequence[Damper] | None = None,
    sigma0: Any = None,
) -> Trajectory | Batch:
    """Simulates the free rotation of a rigid body (eq. 1 of the paper, corrected).

    Euler's equations for the body-frame angular velocity and the body-frame quaternion law
    ``q' = ½ q ⊗ (0, ω)`` are integrated in the Rust core without the GIL; only the frames
    are stored, so a run of 10⁸ steps with 201 frames holds 201 frames.

    With a leading batch axis, NumPy style — `omega0` of shape (M, 3), `q0` of shape (M, 4),
    or moments of shape (M, 3) for one body per run; inputs without it are shared by every
    run — it simulates M runs over one frame grid on all cores and returns a
    :class:`~dzhanibekov.batch.Batch` (``t`` (frames,), ``omega`` (M, frames, 3), ``q``
    (M, frames, 4), flip times and drift per run). RK4 runs several at once in SIMD lanes;
    every run equals its single run bit for bit (``batch[i]``), whatever the number of
    threads. For one number per run (flips, tilt, drift) and no frames, use
    :func:`~dzhanibekov.sweep`. Deployments and damped bodies take the same batch axis (a
    list of deployments, of bodies or of dampers counts as one too): their runs go side by
    side on all cores, each row equal to its single run bit for bit, with
    ``momentum_world`` (M, frames, 3), ``energy`` (M, frames) and a damper's ``sigma``
    (M, frames, 3).

    Parameters
    ----------
    body : Body, list of Body, Deployment, list of Deployment, or array_like, shape (3,) or (M, 3)
        The body (any :class:`Body`: from a tensor, a solid, parts, a mesh), or its
        principal moments ``(Ix, Iy, Iz)``; one row (or one Body of a list) per run of a
        batch. A 3×3 array is refused (use :meth:`Body.from_tensor`). A
        :class:`Deployment` runs a body whose inertia changes in a prescribed way
        (``dL/dt = L × ω``, ``ω = I(t)⁻¹ L``) by the methods that run it (``"rk4"``,
        ``"rk4_projected"`` onto ``|L|``, ``L_world`` and ``|q|``, ``"dopri5"``,
        ``"dop853"``); ``energy`` shows the internal work. Flips are located where every
        knot is diagonal (the intermediate axis of the body as it is then coming nearest
        ``L`` on the other side), else ``flip_times`` is None.
    omega0 : array_like, shape (3,) or (M, 3)
        Initial body-frame angular velocity ``(u0, v0, w0)``, finite, in the body's own
        axes (for a body from a tensor, those of the tensor; the run changes to principal
        axes once at its start and back once at its end).
    q0 : array_like, shape (4,) or (M, 4), or scipy.spatial.transform.Rotation
        Initial attitude of the body's own axes, world-from-body
        (``x_world = M(q0)·x_body``), scalar first ``(Q, U, V, W)`` — scipy's default order
        is scalar last, so pass a scipy ``Rotation`` rather than its ``as_quat()``; a stack
        of N rotations makes a batch of N runs. Normalised here, must be non-zero.
    t_end : float
        End time, positive.
    frames : int
        Frames stored, at least 2, at times ``t_end * i / (frames - 1)`` exactly.
    dt : float or None
        Fixed-step methods: the largest step; between frames the run takes equal substeps
        no longer than `dt`. ``None`` (the default) picks the step predicted to meet `rtol`
        (default 1e-9; see Notes), so that no time scale is assumed: a day of a body turning
        at 0.2 rad/s takes as many steps as 100 s at 1 rad/s.
        Adaptive methods: the first step tried; ``None`` picks ``(rtol + atol)^(1/(q+1)) / Ω``
        for an error estimate of order ``q``.
        Ignored by ``method="exact"``, which takes no steps.
    method : str, a name of :data:`METHODS`
        ``"rk4"``: classic fixed-step fourth-order Runge–Kutta, the paper's method.
        ``"rk4_projected"``: RK4, each step projected back onto the energy and ``|L|`` of
        the start (so ω stays on its exact polhode) with ``q`` rescaled to unit norm; the
        phase along the polhode and the attitude about ``L`` keep RK4's error. The
        projection is one Gauss–Newton step: it leaves the square of RK4's relative change
        of the energy per step (at most ``((dt·Ω)⁵/120)²``), which is round-off for
        ``dt·Ω ≲ 0.25`` but not at larger steps: at ``dt·Ω = 1.73`` E and ``|L|`` drift by
        1e-8 to 2e-6 depending on the orbit, and the run warns (measured against ``dt·Ω``
        in docs/work_precision.md); ``|q|`` and the direction of ``L_world`` stay at
        round-off at any step.
        ``"splitting"``: second-order splitting of the free body into exact rotations
        about its axes (McLachlan 1993; Touma & Wisdom 1994): ``|L|``, ``|q|`` and
        ``L_world`` kept to round-off and the energy error bounded over any run length.
        ``"splitting4"``: its fourth-order composition (Suzuki 1990), 21 rotations a step.
        The atlas of classic rigid-body integrators, each declared in ``METHODS``:
        ``"splitting6"`` (Kahan & Li's sixth-order composition), ``"implicit_midpoint"``,
        ``"dmv"`` and ``"dmv_modified"`` (the discrete Moser–Veselov algorithm, plain and
        with modified moments, order 4), ``"rkmk4"`` and ``"crouch_grossman3"`` (Lie-group
        Runge–Kutta methods on the unit quaternions); docs/guide/methods.md compares them.
        ``"dopri5"``, ``"dop853"``: Dormand–Prince 5(4) and 8(5,3) with error control
        under `rtol` and `atol` and dense output at the frames (Hairer et al.).
        ``"exact"``: the closed-form solution (Jacobi elliptic functions for ω, the angle
        about the fixed angular momentum from the elliptic integral of the third kind for
        q), evaluated directly at the frame times at a cost per frame independent of
        `t_end`; its trajectory reports ``n_steps = nfev = 0`` and ``dt = 0``, and its flip
        times are found from the solution by the same definition.
    rtol : float, optional
        Adaptive methods: relative tolerance of the local error (default 1e-9), at least
        100 ulps and below 1. Fixed-step methods with ``dt=None``: the accuracy the step
        is chosen for (default 1e-9). Not allowed with a fixed-step method and a `dt`.
    atol : float, optional
        Adaptive methods only: absolute tolerance (default 1e-12) on ``q`` and on ``ω`` in
        units of ``Ω``, so that runs are invariant under ``(ω, t) → (sω, t/s)``.
    flips : bool
        Locate the flips (default). Watching every step for them costs about 8% of an RK4
        run; ``flips=False`` skips it and leaves ``flip_times`` as None.
    max_steps : int
        Refuse runs needing more steps than this (default 10¹⁰), before they start. The
        frames of ``"exact"`` (each an evaluation of the closed form) and of the adaptive
        methods (each an evaluation of the interpolant) count toward it too.
    threads : int, optional
        A batch's threads (default: all cores), capped at the number of runs and at 256
        (``MAX_THREADS`` of the core); pools are kept and reused. A single run uses one.
    progress : bool, optional
        A batch's progress bar (``tqdm.auto``: on stderr, or a widget in Jupyter), advanced
        per block of 1024 runs: None (default) shows it for batches of more than one block
        when stderr is a terminal and the batch takes more than a second; True always;
        False never. A single run shows none, nor a batch of deployments or dampers.
    damper : Damper or list of Damper, optional
        A spherical viscous nutation damper inside the body (see :class:`Damper`), or one
        per run of a batch: its three rates join the state; the trajectory gains ``sigma``
        (frames, 3), and ``momentum_world`` and ``energy`` count body and damper. Runs by
        ``"rk4"``, ``"rk4_projected"`` (onto ``|H|``, ``H_world`` and ``|q|``),
        ``"dopri5"`` and ``"dop853"``; the other methods refuse it by name. Flips (of the body's
        intermediate axis relative to the total ``L``) are located for a diagonal body
        tensor.
    sigma0 : array_like, shape (3,) or (M, 3), optional
        The damper's initial absolute rate in body axes; co-rotating (``omega0``) if None.

    Returns
    -------
    Trajectory or Batch
        A `Batch` when an input has a batch axis. With ``dt=None`` every run of a batch
        of a fixed-step method takes the smallest of the steps its runs would pick alone;
        with an adaptive method each run picks its own first step, so that every row
        equals its single run.

    Warns
    -----
    StepSizeWarning
        For ``"rk4"`` and ``"rk4_projected"``, when RK4's predicted drift of ``|q|`` over
        the run exceeds `MAX_PREDICTED_DRIFT` (see `dzhanibekov.accuracy`), and beyond its
        stability limit ``dt·Ω ≥ 4√2``, where the run diverges.
    StiffDamperWarning
        A damper whose slip decays too fast for the step (:func:`damper_rate`): a fixed
        step with ``dt·λ`` beyond RK4's limit 2.785 on the real axis, where the run
        diverges; an adaptive run with ``λ`` above `STIFF_RATIO` times the body's rates,
        which crawls at the damper's time scale. Naming the worst run of a batch.

    Raises
    ------
    TypeError
        An argument of the wrong kind (say, a string for `t_end` or a float for `frames`).
    ValueError
        An argument out of range, a run of more than `max_steps` steps (or frames, see
        `max_steps`), frames that would
        not fit in memory (say, of a batch: ask `sweep` for summaries instead), or a state
        that stopped being finite (`dt` far too large); for a batch, naming the run.
        Arguments that look swapped: moments no real body has (one larger than the other
        two together) with rates that could be moments (pass a `Body` to run them anyway).
    KeyboardInterrupt
        On Ctrl-C; the run stops within a fraction of a second.

    Notes
    -----
    ``Ω = √(2E / I_min)`` bounds ``|ω|`` over the whole run. With ``dt=None`` a method of
    order ``p`` takes ``h`` with ``C_p · Ω t_end · (hΩ)^p = rtol`` (and ``hΩ ≤ 0.5``), the
    constants ``C_p`` of `dzhanibekov._core` measured against a tight reference: on orbits
    away from the separatrix the error at the frames, in ``ω / Ω`` and in ``q``, then stays
    below `rtol`. Near the separatrix (the paper's example) every float64 method loses
    accuracy at each flip and no step rule holds.

    Examples
    --------
    >>> traj = simulate(Body(inertia=(52.0833, 27.0833, 41.6666)), (0.01, 0.01, 1.0))
    >>> traj.omega.shape, traj.q.shape, float(traj.t[-1])
    ((201, 3), (201, 4), 100.0)
    >>> batch = simulate((52.0833, 27.0833, 41.6666), [(0.01, 0.01, 1.0), (0.0, 1.0, 0.01)])
    >>> batch.omega.shape, batch.flips
    ((2, 201, 3), array([2, 0]))

    A batch of damped bodies, one spin per row:

    >>> from dzhanibekov import Damper
    >>> damped = simulate((1.0, 10.0, 10.0), [(2.0, 0.01, 0.0), (0.0, 0.2, 0.01)],
    ...                   t_end=50.0, frames=11, dt=0.01, damper=Damper(0.05, 0.02))
    >>> damped.energy.shape, damped.sigma.shape
    ((2, 11), (2, 11, 3))
    """
    q0 = quaternions_of(q0)
    if isinstance(body, Deployment) or damper is not None or is_deployment_list(body):
        threads = checked_threads(threads)
        if not isinstance(flips, (bool, np.bool_)):
            raise TypeError(f"`flips` must be True or False, got {type(flips).__name__}")
        if is_model_batch(body, omega0, q0, damper, sigma0):
            return simulate_model_batch(body, omega0, q0, t_end, frames, dt, method,
                                        damper=damper, sigma0=sigma0, rtol=rtol, atol=atol,
                                        max_steps=max_steps, threads=threads,
                                        flips=bool(flips))
        if damper is not None and not isinstance(damper, Damper):
            raise TypeError(f"`damper` must be a dz.Damper, got {type(damper).__name__}")
        return simulate_model(body, omega0, q0, t_end, frames, dt, method, damper=damper,
                              sigma0=sigma0, rtol=rtol, atol=atol, max_steps=max_steps,
                              flips=bool(flips))
    if sigma0 is not None:
        raise ValueError("`sigma0` is the damper's initial rate: pass `damper` too")
    if is_batch(body, omega0, q0):
        return simulate_batch(body, omega0, q0, t_end, frames, dt, method, rtol=rtol, atol=atol,
                              flips=flips, max_steps=max_steps, threads=threads,
                              progress=progress)
    checked_threads(threads)
    if progress is not None and not isinstance(progress, bool):
        raise TypeError(f"`progress` must be True, False or None, got {progress!r}")
    if not isinstance(flips, (bool, np.bool_)):
        raise TypeError(f"`flips` must be True or False, got {type(flips).__name__}")
    body, omega0, q0, t_end, frames, max_steps = _checked(
        body, omega0, q0, t_end, frames, method, max_steps, "simulate", dt, rtol, atol
    )
    check_size(frames * 8 * 8, f"frames={frames}", "ask for fewer frames")
    omega = (float(omega0[0]), float(omega0[1]), float(omega0[2]))
    dt, rtol_, atol_ = plan_step(body._core, omega, t_end, frames, dt, method, rtol, atol)
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
        rtol_,
        atol_,
    )
    if out.omega is None or out.q is None:
        raise RuntimeError("internal error in the dzhanibekov core: frames were not kept")
    omega_out, q_out = body.to_user(out.omega, out.q)
    return Trajectory(
        t=out.t,
        omega=omega_out,
        q=q_out,
        flip_times=out.flip_times if flips else None,
        body=body,
        method=method,
        dt=out.dt,
        n_steps=out.n_steps,
        nfev=out.nfev,
        drift=Drift(*out.drift),
        n_rejected=out.n_rejected,
    )


def _checked(
    body: Any, omega0: Any, q0: Any, t_end: Any, frames: Any, method: Any, max_steps: Any,
    function: str, dt: Any, rtol: Any, atol: Any,
) -> tuple[Body, np.ndarray, np.ndarray, float, int, int]:
    """The arguments of a run but its step, coerced and checked (shared by `simulate` and
    `summarize`, named `function` in messages; `accuracy.plan_step` settles the step and
    tolerances), with the start in the body's principal axes. Arguments that look swapped
    are refused once everything else passed."""
    omega0_given = omega0
    omega0 = as_array("omega0", omega0, "(3,)", last=3, ndim=(1,))
    q0 = as_array("q0", quaternions_of(q0), "(4,)", last=4, ndim=(1,))
    if not np.any(q0):
        raise ValueError("`q0` must be a non-zero quaternion (Q, U, V, W), got (0, 0, 0, 0)")
    t_end = as_float("t_end", t_end, positive=True)
    frames = as_int("frames", frames, minimum=2)
    max_steps = as_int("max_steps", max_steps, minimum=1)
    check_method(method)
    check_tolerances(method, dt, rtol, atol)
    check_not_swapped(body, omega0_given, function)
    body = as_body(body)
    omega0, q0 = body.to_principal(omega0, q0)  # the run's one change of axes, at its start
    return body, omega0, q0, t_end, frames, max_steps


def rotate(q: Any, points: Any, out: np.ndarray | None = None) -> np.ndarray:
    """Rotates body points into the world frame: ``M(q_i) · X_j`` for every frame and point.

    Uses the paper's trig-free matrix divided by ``|q|²`` (orthogonal for any non-zero q),
    on all cores for large inputs, without the GIL.

    Parameters
    ----------
    q : array_like, shape (N, 4) or (4,)
        Quaternions, scalar first; non-zero and finite.
    points : array_like, shape (P, 3) or (3,)
        Body-frame points, finite, of magnitude at most `MAX_COORDINATE` (f64 max / 4).
    out : ndarray, shape (N, P, 3), float64, C-contiguous, aligned, optional
        Where to write the result, for callers that rotate repeatedly: reusing a buffer
        avoids the page faults of fresh memory, which cost more than the rotation itself.
        It must not share memory with `q` or `points`.

    Returns
    -------
    ndarray, shape (N, P, 3)
        World-frame points; a leading or middle axis is dropped when `q` or `points` is 1-D.

    Raises
    ------
    TypeError
        Non-numeric input, or `out` not a float64 ndarray.
    ValueError
        Wrong shapes, non-finite values, a zero quaternion, an `out` overlapping the
        inputs, or an output larger than memory.

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
    if p2.size and np.abs(p2).max() > MAX_COORDINATE:
        raise ValueError(f"`points` must have coordinates of magnitude at most "
                         f"{MAX_COORDINATE:.3g} (larger ones overflow when rotated), got "
                         f"{np.abs(p2).max():.3g}")
    shape = (q2.shape[0], p2.shape[0], 3)
    kept = tuple(n for n, keep in zip(shape, (qa.ndim == 2, pa.ndim == 2, True)) if keep)
    if out is not None:
        if not isinstance(out, np.ndarray) or out.dtype != np.float64:
            raise TypeError("`out` must be a float64 numpy array")
        if out.shape != kept:
            raise ValueError(f"`out` must have shape {kept}, got {out.shape}")
        if not (out.flags.c_contiguous and out.flags.aligned and out.flags.writeable):
            raise ValueError("`out` must be C-contiguous, aligned and writeable")
        if np.may_share_memory(out, qa) or np.may_share_memory(out, pa):
            raise ValueError("`out` must not share memory with `q` or `points` (each output "
                             "row would overwrite inputs still to be read); pass a separate "
                             "array")
        _core.rotate(q2, p2, out.reshape(shape))
        return out
    check_size(
        8 * 3 * shape[0] * shape[1],
        f"rotating {shape[1]} points by {shape[0]} quaternions",
        "rotate fewer points or frames at a time, or pass `out`",
    )
    return _core.rotate(q2, p2).reshape(kept)
