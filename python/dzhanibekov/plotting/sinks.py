"""The energy sinks' figures: the energy balance of a run with parts whose mass moves (a
:class:`~dzhanibekov.SpringMassDamper`, a :class:`~dzhanibekov.Hinge`, a
:class:`~dzhanibekov.Slosh`), and those parts' motion against time.

The balance is checked two independent ways: the energy ``T + V`` of each frame comes from
its state (the hub's rates, the parts' coordinates and momenta, through the mass matrix), the
dissipated work ``W`` from the parts' coordinates alone (``∫ c |ẏ|² dt``, ``ẏ`` the rate of a
cubic spline through the frames), so ``T + V + W`` is flat to the frames' sampling error,
beside which the figure states the run's own balance drift (``traj.drift.energy_balance``,
measured at every step).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from ..parts import Hinge, Slosh, SpringMassDamper
from ..results import Trajectory
from .figures import COLORS, Drawable, _saved, _title, _width, compute, units_of

__all__ = ["SINKS", "sink_parts", "dissipated_work", "energy_balance_figure",
           "part_motion_figure"]

SINKS = (SpringMassDamper, Hinge, Slosh)
"""The parts whose mass moves in the body and whose damper dissipates: what these figures
draw."""

_GAUSS = (np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)]), np.array([5.0, 8.0, 5.0]) / 9.0)
"""Three-point Gauss–Legendre nodes and weights on [-1, 1]: exact for the square of a spline's
quadratic rate."""


def sink_parts(traj: Trajectory) -> list[tuple[str, SpringMassDamper | Hinge | Slosh]]:
    """The run's parts whose mass moves, with their names in ``traj.parts``.

    Raises
    ------
    ValueError
        The run has none.
    """
    system = traj.system
    stateful = [p for p in (*system.parts, *system.torques) if p._core.width > 0]
    found = [(name, p) for name, p in zip(system.part_names, stateful) if isinstance(p, SINKS)]
    if not found:
        raise ValueError("`scene` must run a system with a dz.SpringMassDamper, dz.Hinge or "
                         "dz.Slosh for the energy-sink figures")
    return found


def _coordinate(traj: Trajectory, name: str, part: object) -> np.ndarray:
    """The part's coordinates at every frame, (frames, n): a displacement, an angle, or the
    pendulum's direction."""
    state = traj.parts[name]
    return state[:, :3] if isinstance(part, Slosh) else state[:, :1]


def dissipated_work(traj: Trajectory) -> np.ndarray:
    """The work the run's sinks dissipated from the start to each frame, shape (frames,),
    from the parts' coordinates alone: ``Σ c ∫ |ẏ|² dt`` with ``ẏ`` the rate of the
    not-a-knot cubic spline through the frames (a spring's ``ẋ``, a hinge's ``β̇``, the
    pendulum's ``|ṅ| = |ν|``), integrated exactly between frames. Its error is the spline's,
    falling as the fourth power of the frames' spacing for a smooth motion.

    Examples
    --------
    >>> import numpy as np
    >>> import dzhanibekov as dz
    >>> body = dz.Body.from_tensor(np.diag([3.0, 1.0, 2.0]), mass=1.0)
    >>> tank = dz.Slosh(0.05, (0.0, 0.0, 0.5), 0.3, 0.01, (1.0, 0.0, 0.0))
    >>> traj = dz.simulate(dz.System(body, parts=[tank]), (0.01, 0.01, 1.0), t_end=50.0,
    ...                    frames=2001)
    >>> e, w = traj.energy, dz.plotting.sinks.dissipated_work(traj)
    >>> bool(abs(e[-1] + w[-1] - e[0]) < 1e-6 * e[0] and w[-1] > 0)
    True
    """
    from scipy.interpolate import CubicSpline  # type: ignore[import-untyped, unused-ignore]

    t = traj.t
    nodes, weights = _GAUSS
    h = np.diff(t)
    mid = 0.5 * (t[:-1] + t[1:])
    at = mid[:, None] + 0.5 * h[:, None] * nodes[None, :]
    power = np.zeros_like(at)
    for name, part in sink_parts(traj):
        rate = CubicSpline(t, _coordinate(traj, name, part), axis=0).derivative()(at)
        power += part.damping * np.sum(rate * rate, axis=-1)
    steps = 0.5 * h * (power @ weights)
    out: np.ndarray = np.concatenate([[0.0], np.cumsum(steps)])
    return out


def energy_balance_figure(scene: Drawable, *, save: str | Path | None = None) -> Figure:
    """The energy balance of a run with energy sinks, in two panels against time: the energy
    ``T + V`` (the kinetic energy of the hub and every moving part, and the springs'
    potential), the work ``W`` the dampers dissipated (:func:`dissipated_work`) and their
    sum, relative to the energy at the start; below, how far the sum departs from its start,
    log scale, beside the run's own balance drift (``traj.drift.energy_balance``, dashed).

    Parameters
    ----------
    scene : Scene, SceneResult or Trajectory
        A run of a system with a :class:`~dzhanibekov.SpringMassDamper`,
        :class:`~dzhanibekov.Hinge` or :class:`~dzhanibekov.Slosh`.
    save : str or Path, optional

    Returns
    -------
    Figure
        Its first axes holds the lines labelled ``T + V``, ``W`` and ``T + V + W``.

    Raises
    ------
    ValueError
        The run has no such part, or keeps no frames.

    Examples
    --------
    >>> import numpy as np
    >>> import dzhanibekov as dz
    >>> body = dz.Body.from_tensor(np.diag([3.0, 1.0, 2.0]), mass=1.0)
    >>> spring = dz.SpringMassDamper(0.05, (0.0, 0.0, 0.5), (1.0, 0.0, 0.0), 0.5, 0.02)
    >>> traj = dz.simulate(dz.System(body, parts=[spring]), (0.01, 0.01, 1.0), t_end=50.0,
    ...                    frames=1001)
    >>> fig = dz.plotting.energy_balance_figure(traj)
    >>> [line.get_label() for line in fig.axes[0].get_lines()]
    ['T + V', 'W', 'T + V + W']
    """
    result = compute(scene)
    traj = result.trajectory
    if traj is None:
        raise ValueError("`scene` must keep its frames for the energy-balance figure")
    sink_parts(traj)
    energy = traj.energy
    work = dissipated_work(traj)
    e0 = float(energy[0])
    scale = e0 if e0 > 0 else 1.0
    fig = Figure(figsize=(7.0, 5.0), layout="constrained")
    top, low = fig.subplots(2, 1, sharex=True, height_ratios=(3, 2))
    top.plot(traj.t, energy / scale, color=COLORS["box"], lw=1.3, label="T + V")
    top.plot(traj.t, work / scale, color=COLORS["signal"], lw=1.3, label="W")
    top.plot(traj.t, (energy + work) / scale, color="#111111", lw=1.0, ls="--",
             label="T + V + W")
    top.set_ylabel("energy / E(0)")
    top.legend(loc="center right", fontsize=8)
    gap = np.abs(energy + work - e0) / scale
    low.semilogy(traj.t, np.where(gap > 0, gap, np.nan), color="#555555", lw=0.9,
                 label="|T + V + W − E(0)| / E(0), W from the frames")
    model = traj.drift.energy_balance
    if model is not None and model > 0:
        low.axhline(model, color=COLORS["signal"], lw=0.9, ls="--",
                    label=f"the run's balance drift, every step: {model:.1e}")
    units = units_of(result.scene)
    low.set_xlabel(units.label("t", units.time))
    low.set_ylabel("balance (relative)")
    low.set_xlim(0, traj.t[-1])
    low.legend(loc="lower right", fontsize=7)
    top.set_title(_title(result, _width(fig)) + f"\nE(t_end)/E(0) = {energy[-1] / scale:.4g}",
                  fontsize=9)
    return _saved(fig, save)


def part_motion_figure(scene: Drawable, *, save: str | Path | None = None) -> Figure:
    """Each moving part's motion against time, one panel a part: a spring's displacement
    ``x``, a hinge's angle ``β`` from rest (degrees), a pendulum's direction ``n`` in body
    axes (three lines), as the run's state holds them (``traj.parts``).

    Parameters
    ----------
    scene : Scene, SceneResult or Trajectory
        A run of a system with a :class:`~dzhanibekov.SpringMassDamper`,
        :class:`~dzhanibekov.Hinge` or :class:`~dzhanibekov.Slosh`.
    save : str or Path, optional

    Returns
    -------
    Figure
        One axes a part, titled with the part's name.

    Raises
    ------
    ValueError
        The run has no such part, or keeps no frames.

    Examples
    --------
    >>> import numpy as np
    >>> import dzhanibekov as dz
    >>> body = dz.Body.from_tensor(np.diag([3.0, 1.0, 2.0]), mass=1.0)
    >>> tank = dz.Slosh(0.05, (0.0, 0.0, 0.5), 0.3, 0.01, (1.0, 0.0, 0.0))
    >>> traj = dz.simulate(dz.System(body, parts=[tank]), (0.01, 0.01, 1.0), t_end=20.0,
    ...                    frames=201)
    >>> fig = dz.plotting.part_motion_figure(traj)
    >>> [line.get_label() for line in fig.axes[0].get_lines()]
    ['n_x', 'n_y', 'n_z']
    """
    result = compute(scene)
    traj = result.trajectory
    if traj is None:
        raise ValueError("`scene` must keep its frames for the part-motion figure")
    found = sink_parts(traj)
    fig = Figure(figsize=(7.0, 1.2 + 2.0 * len(found)), layout="constrained")
    axes = np.atleast_1d(fig.subplots(len(found), 1, sharex=True, squeeze=False)[:, 0])
    units = units_of(result.scene)
    for ax, (name, part) in zip(axes, found):
        y = _coordinate(traj, name, part)
        if isinstance(part, Slosh):
            for k in range(3):
                ax.plot(traj.t, y[:, k], color=COLORS["omega"][k], lw=1.1, label=f"n_{'xyz'[k]}")
            ax.set_ylabel("rod direction (body axes)")
            ax.set_ylim(-1.05, 1.05)
            ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0.0)
        elif isinstance(part, Hinge):
            ax.plot(traj.t, np.degrees(y[:, 0]), color=COLORS["box"], lw=1.1, label="β")
            ax.set_ylabel("hinge angle β (°)")
        else:
            ax.plot(traj.t, y[:, 0], color=COLORS["box"], lw=1.1, label="x")
            ax.set_ylabel(units.label("displacement x", units.length))
        ax.set_title(name, fontsize=9, loc="left")
    axes[-1].set_xlabel(units.label("t", units.time))
    axes[-1].set_xlim(0, traj.t[-1])
    fig.suptitle(_title(result, _width(fig)), fontsize=9)
    return _saved(fig, save)
