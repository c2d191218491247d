"""The one entry point of every run: :func:`simulate` a system (one run, or a batch of them)
and :func:`rotate` body points by its attitudes."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, overload

import numpy as np
from tqdm.auto import tqdm

from . import _core
from ._args import as_array, check_size
from ._progress import PROGRESS_DELAY, RunProgress, resolve
from .accuracy import warn_step
from .body import Body
from .damper import warn_stiff
from .deployment import Deployment
from .methods import METHODS
from .options import RunKeywords, RunOptions, merged
from .results import Batch, Trajectory, batch_drift, split_parts, trajectory
from .rows import Rows, row_error, rows_of, warn_unphysical
from .system import System

if TYPE_CHECKING:
    from typing_extensions import Unpack

__all__ = ["METHODS", "simulate", "rotate", "plan", "run_one", "run_batch"]

MAX_COORDINATE = float(np.finfo(np.float64).max / 4)
"""The largest body-point coordinate `rotate` takes: a rotated coordinate sums three terms
each at most the largest coordinate, so nothing larger than this can overflow."""


@overload
def simulate(
    system: System | Body | Deployment | Sequence[float],
    omega0: Sequence[float],
    q0: Sequence[float] = ...,
    *,
    options: RunOptions | None = ...,
    **keywords: Unpack[RunKeywords],
) -> Trajectory: ...


@overload
def simulate(
    system: Any,
    omega0: Any,
    q0: Any = ...,
    *,
    options: RunOptions | None = ...,
    **keywords: Unpack[RunKeywords],
) -> Trajectory | Batch: ...


def simulate(
    system: Any,
    omega0: Any,
    q0: Any = (1.0, 0.0, 0.0, 0.0),
    *,
    options: RunOptions | None = None,
    **keywords: Unpack[RunKeywords],
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
    :func:`~dzhanibekov.sweep`. Systems with parts or a schedule take the same batch axis
    (a list of systems counts as one): their runs go side by side on all cores, each row
    equal to its single run bit for bit.

    Parameters
    ----------
    system : System, Body, Deployment, list of them, or array_like, shape (3,) or (M, 3)
        What is simulated: a :class:`System` (a body with its parts, such as a
        :class:`Damper`), or a body alone — any :class:`Body` (from a tensor, a solid,
        parts, a mesh), a :class:`Deployment` (a body whose inertia changes in a
        prescribed way, ``dL/dt = L × ω``, ``ω = I(t)⁻¹ L``), or principal moments
        ``(Ix, Iy, Iz)``; one per run of a batch. A 3×3 array is refused (use
        :meth:`Body.from_tensor`). A part's state appears in the result under its name
        (``traj.parts["damper"]``); ``energy`` and ``momentum_world`` count body and parts.
        Methods that cannot run a system's model refuse it by name
        (``METHODS[name].models``); flips (the intermediate axis of the body as it is then
        coming nearest the total ``L`` on the other side) are located for any tensor.
    omega0 : array_like, shape (3,) or (M, 3)
        Initial body-frame angular velocity ``(u0, v0, w0)``, finite, in the body's own
        axes (for a body from a tensor, those of the tensor; the run changes to principal
        axes once at its start and back once at its end).
    q0 : array_like, shape (4,) or (M, 4), or scipy.spatial.transform.Rotation
        Initial attitude of the body's own axes, world-from-body
        (``x_world = M(q0)·x_body``), scalar first ``(Q, U, V, W)`` — scipy's default order
        is scalar last, so pass a scipy ``Rotation`` rather than its ``as_quat()``; a stack
        of N rotations makes a batch of N runs. Normalised here, must be non-zero.
    options : RunOptions, optional
        The run's options as one value (:class:`~dzhanibekov.RunOptions`); the keywords
        below override its fields. Without it, the keywords' defaults.
    t_end : float
        End time, positive (default 100).
    frames : int
        Frames stored, at least 2, at times ``t_end * i / (frames - 1)`` exactly (default
        201).
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
        ``"splitting_exact"``: for a constant body under torques, Strang's splitting of the
        exact free motion and the torque's kicks (order 2); ``"splitting_exact4"``: its
        fourth-order composition (Suzuki 1990), five free motions and six kicks a step.
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
        Adaptive methods only: absolute tolerance on ``q`` and on ``ω`` in units of ``Ω``,
        so that runs are invariant under ``(ω, t) → (sω, t/s)``; default ``rtol / 1000``
        (1e-12 at the default `rtol`), so that a tighter `rtol` is not held back by it.
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
        A progress bar (``tqdm.auto``: on stderr, or a widget in Jupyter). A single run's
        is advanced by the core as the run goes (at no cost a step: it reads how far the run
        got when it looks for Ctrl-C); where no bar can show (stderr is not a terminal) a
        line on stderr says how far it got every ``LINE_EVERY`` (10) seconds. A batch's is
        advanced per block of 1024 runs. None (default) shows the bar for runs of more than
        a second (a batch: of more than one block), the lines for runs of more than 10
        seconds; True always; False never.

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

    >>> from dzhanibekov import Body, Damper, System
    >>> damped = System(Body((1.0, 10.0, 10.0)), parts=[Damper(0.05, 0.02)])
    >>> runs = simulate(damped, [(2.0, 0.01, 0.0), (0.0, 0.2, 0.01)], t_end=50.0, frames=11,
    ...                 dt=0.01)
    >>> runs.energy.shape, runs.parts["damper"].shape
    ((2, 11), (2, 11, 3))
    """
    given = merged("simulate", options, keywords)
    # the options' kinds first: a bad option is named before any guess about the arguments
    core = given.core()
    rows = rows_of(system, omega0, q0, function="simulate", max_batch_ndim=1, stacklevel=3)
    progress = given.progress
    if progress is not None and not isinstance(progress, bool):
        raise TypeError(f"`progress` must be True, False or None, got {progress!r}")
    if not rows.batch:
        run = run_one(rows, core, progress=progress, stacklevel=3)
        return trajectory(run, rows.systems.first, core.method)
    return run_batch(rows, plan(rows, core, stacklevel=3), progress=progress)


def run_one(rows: Rows, options: _core.RunOptions, *, progress: bool | None = None,
            keep_frames: bool = True, stacklevel: int) -> _core.Run:
    """The one run of `rows` (no batch axis), planned and run in one call into the core,
    which builds its model once; the warnings its plan calls for (RK4's dissipation, a stiff
    damper) before it starts. `stacklevel` counts from this function."""
    system = rows.systems.first
    frames, method = options.frames, options.method
    dt_given, rtol = options.dt is not None, options.rtol

    def planned(p: _core.StepPlan) -> None:  # called by the core before the run starts
        warn_step(p, method, dt_given, rtol, stacklevel=stacklevel + 2)
        warn_stiff(p, method, stacklevel=stacklevel + 2)
        if keep_frames:  # ω, q and parts a frame, and the frame times
            check_size((8 + sum(system.part_widths)) * frames * 8, f"frames={frames}",
                       "ask for fewer runs or frames, or use `dz.sweep` (or a Monte Carlo "
                       "study) for per-run outcomes, which keep no frames")

    progress = resolve(progress)
    # the core reports how far the run got
    report = RunProgress(options.t_end, progress is True) if progress is not False else None
    try:
        return _core.simulate(system._core, rows.omega[0], rows.q[0], options, keep_frames,
                              warn=planned, progress=report)
    finally:
        if report is not None:
            report.close()


def plan(rows: Rows, options: _core.RunOptions, *, stacklevel: int) -> _core.RunOptions:
    """The step of every run planned in the core (one shared by a batch), with the
    warnings it calls for (RK4's dissipation, a stiff damper) naming the worst run; `options`
    with that step. `stacklevel` counts from this function."""
    systems, moments = rows.core()
    try:
        p = _core.plan(systems, rows.omega, rows.q, options, inertia=moments)
    except ValueError as exc:
        raise row_error(exc, rows) from None
    warn_unphysical(rows, stacklevel=stacklevel + 1)
    method = options.method

    def where(row: int) -> str:
        return f"{rows.where(row)}: " if rows.batch and len(rows) > 1 else ""

    if p.worst is not None and p.worst_row is not None:
        warn_step(p.worst, method, options.dt is not None, options.rtol,
                  stacklevel=stacklevel + 1, where=where(p.worst_row))
    if p.stiffest is not None and p.stiffest_row is not None:
        warn_stiff(p.stiffest, method, stacklevel=stacklevel + 1, where=where(p.stiffest_row))
    return options.with_dt(p.dt)


PROGRESS_BLOCK = 1024
"""Rows per call to the core when a batch shows its progress (a multiple of the SIMD
lanes' 16, so that the lanes are grouped as in one call; rows never depend on it)."""

def run_batch(rows: Rows, options: _core.RunOptions, *, progress: bool | None = None,
              keep_frames: bool = True) -> Batch:
    """The runs of `rows` (planned) over one frame grid, as a :class:`Batch`; with a progress
    bar, in blocks of `PROGRESS_BLOCK` rows."""
    m, width = len(rows), sum(rows.systems.first.part_widths) if len(rows) else 0
    if keep_frames:
        # each run's ω, q and parts a frame, and the frame times
        check_size((m * (7 + width) + 1) * options.frames * 8,
                   f"a batch of {m} runs × {options.frames} frames",
                   "ask for fewer runs or frames, or use `dz.sweep` (or a Monte Carlo study) "
                   "for per-run outcomes, which keep no frames")

    progress = resolve(progress)

    def run(block: slice) -> Any:
        part = rows.take(block)
        systems, moments = part.core()
        try:
            # row i of the whole batch is seeded i (its parts' noise), whatever the blocks
            return _core.simulate_batch(systems, part.omega, part.q, options, keep_frames,
                                        inertia=moments, first_row=block.start or 0)
        except ValueError as exc:
            raise row_error(exc, rows, block.start or 0) from None

    out = _in_blocks(run, m, progress)
    system = rows.systems.first if m else None
    return Batch(
        t=out.t,
        omega=out.omega if out.omega is not None else np.empty((m, 0, 3)),
        q=out.q if out.q is not None else np.empty((m, 0, 4)),
        _flip_times=out.flip_times if options.flips else None,
        _flip_offsets=out.flip_offsets if options.flips else None,
        systems=rows.systems,
        method=options.method,
        dt=out.runs.dt,
        n_steps=out.runs.n_steps,
        nfev=out.runs.nfev,
        n_rejected=out.runs.n_rejected,
        drift=batch_drift(out.runs),
        parts={} if system is None else split_parts(system, out.parts),
        _flat_times=out.flat_time if len(out.flat_time) == m else None,
    )


def _in_blocks(run: Callable[[slice], Any], m: int, progress: bool | None) -> Any:
    """`run` over all `m` rows in one call, or, when a progress bar shows (tqdm decides:
    with ``progress=None`` only on a terminal), in blocks of `PROGRESS_BLOCK` rows joined as
    one call returns them."""
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
    return _Joined.of(parts)


@dataclass(frozen=True)
class _Columns:
    """As `_core.RunColumns`: per-run drift, what is kept, cost and step."""

    drift: list[np.ndarray]
    kept: list[str]
    nfev: np.ndarray
    n_steps: np.ndarray
    n_rejected: np.ndarray
    dt: np.ndarray


@dataclass(frozen=True)
class _Joined:
    """The core's results of a batch's blocks joined into one, as one call returns it."""

    t: np.ndarray
    omega: np.ndarray | None
    q: np.ndarray | None
    parts: np.ndarray | None
    flip_offsets: np.ndarray
    flip_times: np.ndarray
    flat_time: np.ndarray
    runs: _Columns

    @staticmethod
    def of(parts: list[Any]) -> _Joined:
        def joined(values: list[Any]) -> Any:
            return None if values[0] is None else np.concatenate(values)

        starts = np.cumsum([0] + [p.flip_offsets[-1] for p in parts[:-1]])
        offsets = np.concatenate([parts[0].flip_offsets[:1]] + [
            p.flip_offsets[1:] + s for p, s in zip(parts, starts)])
        runs = [p.runs for p in parts]
        return _Joined(
            t=parts[0].t, omega=joined([p.omega for p in parts]),
            q=joined([p.q for p in parts]), parts=joined([p.parts for p in parts]),
            flip_offsets=offsets, flip_times=joined([p.flip_times for p in parts]),
            flat_time=np.concatenate([p.flat_time for p in parts]),
            runs=_Columns(
                drift=[np.concatenate(c) for c in zip(*(r.drift for r in runs))],
                kept=runs[0].kept,
                **{k: joined([getattr(r, k) for r in runs])
                   for k in ("nfev", "n_steps", "n_rejected", "dt")}))


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
