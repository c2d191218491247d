"""The closed loop's figures: a detumble (the body's rate against orbits) and a pointing
(the angle from the target, the wheels' momenta and torques against their limits)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from ..orbit import GravityGradient
from ..control import QuaternionFeedback
from ..pointing import detumbled_at, part_state, pointing_angle
from ..results import Trajectory
from .figures import (FIGURE_FUNCTIONS, COLORS, Drawable, _saved, _time_axes, _title, _width,
                      compute)

__all__ = ["detumble_figure", "pointing_figure"]


def _orbit_rate(traj: Trajectory) -> float | None:
    """The orbit's rate of the run's magnetic parts or gravity gradient, if any."""
    for p in (*traj.system.parts, *traj.system.torques):
        field = getattr(p, "field", None)
        if field is not None:
            return float(field.orbit_rate)
        if isinstance(p, GravityGradient):
            return float(p.orbit_rate)
    return None


def detumble_figure(scene: Drawable, *, threshold: float = math.radians(0.5),
                    ax: Axes | None = None, save: str | Path | None = None) -> Figure:
    """The body's rate ``|ω|`` (degrees per unit time, log scale) against orbits — against
    time when the system has no orbit — with `threshold` (rad per unit time, 0.5°/s by
    default) and the time the rate stays below it from.

    Parameters
    ----------
    scene : Scene, SceneResult or Trajectory
    threshold : float
    ax : Axes, optional
    save : str or Path, optional

    Returns
    -------
    Figure

    Examples
    --------
    >>> import numpy as np
    >>> import dzhanibekov as dz
    >>> n = dz.circular_orbit_rate(500e3)
    >>> bdot = dz.BDot(dz.MagneticField(n, 1.7), gain=3e-5, period=1.0, max_dipole=0.2)
    >>> sat = dz.System(dz.Body((0.042, 0.042, 0.0067)), torques=[bdot])
    >>> traj = dz.simulate(sat, np.radians([6, -5, 6]), t_end=2 * 2 * np.pi / n, frames=401,
    ...                    method="dop853")
    >>> fig = dz.plotting.detumble_figure(traj)
    """
    result, traj, fig, ax = _time_axes(scene, ax, "detumble figure", span=False)
    n = _orbit_rate(traj)
    x = traj.t * n / (2 * math.pi) if n else traj.t
    rate = np.degrees(np.linalg.norm(traj.omega, axis=1))
    # a body at rest has no place on a log scale: gaps there
    ax.plot(x, np.where(rate > 0, rate, np.nan), color=COLORS["box"], lw=1.2, label="|ω|")
    limit = float(threshold)
    ax.axhline(math.degrees(limit), color="#c0392b", lw=0.9, ls="--",
               label=f"{math.degrees(limit):g}°")
    done = detumbled_at(traj, limit)
    if math.isfinite(done):
        at = done * n / (2 * math.pi) if n else done
        ax.axvline(at, color="#555555", lw=0.8, ls=":",
                   label=f"below from {at:.2f} orbits" if n else f"below from t = {at:g}")
    if n:
        ax.axhline(math.degrees(2 * n), color="#9a9a9a", lw=0.8, ls="-.",
                   label="2n (the field's turn)")
    ax.set_yscale("log")   # after the threshold's line: a scale with something positive
    ax.set_xlabel("orbits" if n else "t")
    ax.set_ylabel("|ω| (degrees per unit time)")
    ax.set_xlim(0, x[-1])
    ax.set_title(_title(result, _width(fig)), fontsize=9)
    ax.legend(loc="upper right", fontsize=8)
    return _saved(fig, save)


def pointing_figure(scene: Drawable, *, save: str | Path | None = None) -> Figure:
    """A pointing run in three panels against time: the angle from the
    :class:`~dzhanibekov.QuaternionFeedback`'s target (degrees, log scale), each wheel's
    momentum and each wheel's held torque, with their limits dashed.

    Parameters
    ----------
    scene : Scene, SceneResult or Trajectory
    save : str or Path, optional

    Returns
    -------
    Figure

    Raises
    ------
    ValueError
        The run's system has no quaternion feedback.

    Examples
    --------
    >>> import numpy as np
    >>> import dzhanibekov as dz
    >>> qf = dz.QuaternionFeedback(0.03, 0.5, 0.5, torque_limit=0.02, momentum_limit=0.1)
    >>> sat = dz.System(dz.Body((10.0, 12.0, 8.0)), parts=[qf])
    >>> traj = dz.simulate(sat, (0, 0, 0), (np.cos(np.pi / 4), 0, 0, np.sin(np.pi / 4)),
    ...                    t_end=300.0, frames=301)
    >>> fig = dz.plotting.pointing_figure(traj)
    """
    result = compute(scene)
    traj = result.trajectory
    if traj is None:
        raise ValueError("`scene` must keep its frames for the pointing figure")
    part: QuaternionFeedback | None = next(
        (p for p in traj.system.parts if isinstance(p, QuaternionFeedback)), None)
    if part is None:
        raise ValueError("`scene` must run a system with a dz.QuaternionFeedback for the "
                         "pointing figure")
    fig = Figure(figsize=(7.0, 7.0), layout="constrained")
    angle_ax, momentum_ax, torque_ax = fig.subplots(3, 1, sharex=True)
    angle = np.degrees(pointing_angle(traj))
    angle_ax.semilogy(traj.t, np.maximum(angle, 1e-12), color=COLORS["box"], lw=1.2)
    angle_ax.set_ylabel("angle from target (°)")
    s = part_state(traj, "quaternion_feedback")
    for rows, ax, limit, what in ((s["wheel_momentum"], momentum_ax, part.momentum_limit,
                                   "wheel momentum"),
                                  (s["wheel_torque"], torque_ax, part.torque_limit,
                                   "wheel torque")):
        for k in range(3):
            ax.plot(traj.t, rows[:, k], color=COLORS["omega"][k], lw=1.1, label=f"wheel {k}")
        if limit is not None and math.isfinite(limit):
            for sign in (1, -1):
                ax.axhline(sign * limit, color="#555555", lw=0.8, ls="--",
                           label="limit" if sign == 1 else None)
        ax.set_ylabel(what)
        ax.legend(loc="upper right", fontsize=8, ncols=4)
    torque_ax.set_xlabel("t")
    torque_ax.set_xlim(0, traj.t[-1])
    angle_ax.set_title(_title(result, _width(fig)), fontsize=9)
    return _saved(fig, save)


# the names a scene's `draw.figures` gives them (figures.py cannot import this module: it
# imports figures.py's helpers)
FIGURE_FUNCTIONS["detumble"] = detumble_figure
FIGURE_FUNCTIONS["pointing"] = pointing_figure
