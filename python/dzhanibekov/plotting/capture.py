"""A flip that decays: a body spinning near its intermediate axis with an energy sink (a slosh
tank) flips over and over, loses energy at constant angular momentum, and is captured into a
flat spin about its major axis. :func:`intermediate_flips` counts the flips of a run;
:func:`capture_figure` draws how many there are before capture against the sink's damping.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from .. import _core
from .._args import as_float
from ..parts import Slosh
from ..results import Trajectory
from ..simulate import simulate
from ..system import System
from .figures import COLORS, Drawable, _saved, compute

__all__ = ["WITHIN", "intermediate_flips", "capture_sweep", "capture_figure"]

WITHIN = math.radians(45.0)
"""How near the angular momentum (or its opposite) the intermediate axis must come for a
flip to count: a flat spin about the major axis holds it near the plane normal to ``L``."""


def _intermediate(traj: Trajectory) -> int:
    """The hub's intermediate principal axis: the body must be given in its principal axes."""
    tensor = traj.system.tensor_at(0.0)
    diagonal = np.diag(tensor)
    if not np.allclose(tensor, np.diag(diagonal), rtol=0.0, atol=1e-12 * diagonal.max()):
        raise ValueError("`traj` must run a body given in its principal axes")
    return int(np.argsort(diagonal)[1])


def _alignment(traj: Trajectory) -> np.ndarray:
    """The cosine of the intermediate axis's angle from ``L`` at every frame (0 at rest)."""
    ell = traj.momentum_body
    size = np.linalg.norm(ell, axis=1)
    column = ell[:, _intermediate(traj)]
    out: np.ndarray = np.divide(column, size, out=np.zeros_like(column), where=size > 0)
    return out


def intermediate_flips(traj: Trajectory, *, within: float = WITHIN) -> np.ndarray:
    """The times of the run's flips: the intermediate axis passing from within `within` of
    the total angular momentum ``L`` to within `within` of ``−L``, or back (located at the
    first frame past the threshold). A free body near its intermediate axis flips forever;
    with a sink, the flips stop when the body is captured into a flat spin about its major
    axis (the intermediate axis then stays farther than `within` from both).

    Unlike ``traj.flip_times`` (every sign change of the intermediate-axis rate, which goes
    on, small, in the flat spin's nutation), this counts only whole turns over.

    Parameters
    ----------
    traj : Trajectory
        A run of a body given in its principal axes.
    within : float
        Radians, in ``(0, π/2)``; 45° by default.

    Returns
    -------
    ndarray, shape (flips,)

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=100.0, frames=1001,
    ...                    flips=True)
    >>> len(dz.plotting.capture.intermediate_flips(traj)), traj.flips  # the free body: alike
    (2, 2)
    """
    within = as_float("within", within, positive=True)
    if not within < math.pi / 2:
        raise ValueError(f"`within` must be below π/2, got {within!r}")
    c = _alignment(traj)
    side = np.where(c > math.cos(within), 1, np.where(c < -math.cos(within), -1, 0))
    held = np.nonzero(side)[0]
    turns = held[1:][np.diff(side[held]) != 0]
    out: np.ndarray = traj.t[turns]
    return out


def capture_sweep(traj: Trajectory, dampings: Sequence[float]) -> np.ndarray:
    """The number of flips (:func:`intermediate_flips`) of the run `traj` again with its
    :class:`~dzhanibekov.Slosh`'s damping set to each of `dampings`, shape (len(dampings),):
    the same body, start, span, frames, step and method."""
    parts = traj.system.parts
    if not any(isinstance(p, Slosh) for p in parts):
        raise ValueError("`scene` must run a system with a dz.Slosh for the capture figure")
    counts = []
    for c in dampings:
        c = as_float("dampings", c)
        swapped = [p if not isinstance(p, Slosh) else Slosh(
            p.mass, p.pivot, p.length, c, p.direction0, p.rate0) for p in parts]
        run = simulate(System(traj.system.body, parts=swapped, torques=traj.system.torques),
                       traj.omega[0], traj.q[0], t_end=traj.t_end, frames=len(traj.t),
                       dt=None if _core.method_info(traj.method).adaptive else traj.dt or None,
                       method=traj.method)
        assert isinstance(run, Trajectory)
        counts.append(len(intermediate_flips(run)))
    return np.array(counts, dtype=np.int64)


def capture_figure(scene: Drawable, *, dampings: Sequence[float] | None = None,
                   save: str | Path | None = None) -> Figure:
    """A flip that decays, in two panels: the scene's run (the intermediate axis's alignment
    with ``L`` against time, each counted flip marked), and the number of flips before
    capture against the slosh damping (:func:`capture_sweep` of the scene's run), the
    scene's own damping marked.

    Parameters
    ----------
    scene : Scene, SceneResult or Trajectory
        A run of a body (in its principal axes) with a :class:`~dzhanibekov.Slosh`.
    dampings : sequence of float, optional
        The dampings of the sweep; by default 0 and five from the scene's to 33 times it
        (beyond, the pendulum locks to the body and dissipates less again). Zero damping
        is drawn as a level: the flips in the window of a run that is never captured.
    save : str or Path, optional

    Returns
    -------
    Figure

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> fig = dz.plotting.capture_figure(dz.SCENES["slosh-flip"], dampings=[0.0, 0.1])
    >>> fig.axes[1].get_lines()[0].get_ydata().tolist()[0] > 0
    True
    """
    result = compute(scene)
    traj = result.trajectory
    if traj is None:
        raise ValueError("`scene` must keep its frames for the capture figure")
    tank = next((p for p in traj.system.parts if isinstance(p, Slosh)), None)
    if tank is None:
        raise ValueError("`scene` must run a system with a dz.Slosh for the capture figure")
    c0 = tank.damping
    values = ([0.0] + [c0 * f for f in (1.0, 2.0, 10 / 3, 10.0, 100 / 3)] if dampings is None
              else [as_float("dampings", c) for c in dampings])
    counts = capture_sweep(traj, values)
    axis = _intermediate(traj)
    alignment = _alignment(traj)
    flips = intermediate_flips(traj)
    fig = Figure(figsize=(7.0, 6.0), layout="constrained")
    run_ax, sweep_ax = fig.subplots(2, 1, height_ratios=(1, 1))
    run_ax.plot(traj.t, alignment, color=COLORS["box"], lw=0.9,
                label=f"cos of the {'xyz'[axis]} axis's angle from L")
    for k, t in enumerate(flips):
        run_ax.axvline(float(t), color="#9a9a9a", lw=0.6, ls=":",
                       label="flip" if k == 0 else None)
    for sign in (1, -1):
        run_ax.axhline(sign * math.cos(WITHIN), color=COLORS["signal"], lw=0.8, ls="--",
                       label="within 45° of ±L" if sign == 1 else None)
    end = f"captured by t = {flips[-1]:.0f}" if len(flips) else "no flip"
    run_ax.set_title(f"{result.scene.title}\n{len(flips)} flips, {end} (damping {c0:g})",
                     fontsize=9)
    run_ax.set_xlabel("t")
    run_ax.set_xlim(0, traj.t[-1])
    run_ax.set_ylim(-1.05, 1.05)
    run_ax.legend(loc="lower right", fontsize=7, ncols=3)
    x = np.array(values)
    damped = x > 0
    sweep_ax.plot(x[damped], counts[damped], "o-", color=COLORS["signal"], lw=1.2,
                  label="flips before capture")
    for n in counts[~damped][:1]:
        sweep_ax.axhline(float(n), color="#555555", lw=0.9, ls="--",
                         label=f"no damping: {n} flips, never captured")
    sweep_ax.axvline(c0, color="#555555", lw=0.8, ls=":", label="the scene's damping")
    if np.count_nonzero(damped) > 1:
        sweep_ax.set_xscale("log")
    sweep_ax.set_xlabel("slosh damping c (torque per rate at the pivot)")
    sweep_ax.set_ylabel(f"flips in [0, {traj.t_end:g}]")
    sweep_ax.set_ylim(bottom=0)
    sweep_ax.legend(loc="upper right", fontsize=8)
    return _saved(fig, save)
