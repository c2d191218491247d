"""Figures of the stability maps of :mod:`dzhanibekov.stability`: what the runs measured,
with the closed form's boundaries drawn over it.

>>> import numpy as np, dzhanibekov as dz
>>> from dzhanibekov.plotting.stability import dual_spin_figure, gravity_gradient_figure
>>> m = dz.dual_spin_map((1.0, 2.0, 3.0), np.linspace(-3, 3, 7), t_end=100.0, frames=51)
>>> fig = dual_spin_figure(m)
>>> len(fig.axes)
1
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.axes import Axes
from matplotlib.colors import LogNorm
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from ..stability import DualSpinMap, GravityGradientMap, gravity_gradient_region
from .figures import _figure_of, _saved

__all__ = ["dual_spin_figure", "gravity_gradient_figure"]

_AXIS_NAMES = ("x", "y", "z")
_COLOURS = ("tab:blue", "tab:orange", "tab:green")


def dual_spin_figure(result: DualSpinMap, *, ax: Axes | None = None,
                     save: str | Path | None = None) -> Figure:
    """The dual-spin map: per spin axis, the largest angle of the body's rate from the spin
    axis against the wheel's momentum ``h`` (log scale), with the closed form's unstable
    interval of ``h`` shaded in the axis's colour and the angle that counts as departed
    dashed.

    Parameters
    ----------
    result : DualSpinMap
        From :func:`~dzhanibekov.dual_spin_map`.
    ax : matplotlib Axes, optional
        Draw into it; by default a new figure.
    save : str or Path, optional
        Write the figure there (all or nothing).

    Returns
    -------
    Figure
    """
    if not isinstance(result, DualSpinMap):
        raise TypeError(f"`result` must be a DualSpinMap (from dz.dual_spin_map), got "
                        f"{type(result).__name__}")
    if ax is None:
        fig = Figure(figsize=(7.0, 3.6), layout="constrained")
        ax = fig.add_subplot()
    fig = _figure_of(ax)
    tiny = max(float(np.min(result.departure[result.departure > 0], initial=np.inf)), 1e-16) \
        if (result.departure > 0).any() else 1e-16
    for row, k in enumerate(result.axes):
        colour = _COLOURS[k]
        low, high = result.thresholds[row]
        if high > low:
            ax.axvspan(low, high, color=colour, alpha=0.12, lw=0)
            for edge in (low, high):
                ax.axvline(edge, color=colour, lw=0.8, ls=":")
        moment = result.inertia[k]
        ax.plot(result.momenta, np.maximum(result.departure[row], tiny), "o-", ms=3, lw=1.0,
                color=colour, label=f"spin about {_AXIS_NAMES[k]} (I = {moment:g})")
    ax.axhline(result.limit, color="0.3", lw=0.8, ls="--",
               label=f"departed: > {result.limit:g} rad")
    ax.set_yscale("log")
    ax.set_xlabel("wheel momentum h along the spin axis")
    ax.set_ylabel("largest angle of ω from the spin axis (rad)")
    ax.set_title(f"dual spin, Ω = {result.rate:g}, nudge {result.nudge:g}·Ω, t = "
                 f"{result.t_end:g}: shaded, the closed form's unstable h", fontsize=9)
    ax.legend(loc="lower right", fontsize=7)
    return _saved(fig, save)


def gravity_gradient_figure(result: GravityGradientMap, *, ax: Axes | None = None,
                            save: str | Path | None = None) -> Figure:
    """The gravity-gradient map: the largest angle from LVLH over the runs, coloured over the
    moment ratios ``(k1, k3)`` (log scale), with the closed form's stable regions outlined
    (Lagrange: ``k1 > k3 > 0``; DeBra–Delp: the sliver with ``k3 < k1 < 0``).

    Parameters
    ----------
    result : GravityGradientMap
        From :func:`~dzhanibekov.gravity_gradient_map`.
    ax : matplotlib Axes, optional
        Draw into it; by default a new figure.
    save : str or Path, optional
        Write the figure there (all or nothing).

    Returns
    -------
    Figure
    """
    if not isinstance(result, GravityGradientMap):
        raise TypeError(f"`result` must be a GravityGradientMap (from "
                        f"dz.gravity_gradient_map), got {type(result).__name__}")
    if ax is None:
        fig = Figure(figsize=(6.0, 5.0), layout="constrained")
        ax = fig.add_subplot()
    fig = _figure_of(ax)
    deviation = np.maximum(result.deviation, 1e-6)
    mesh = ax.pcolormesh(result.k1, result.k3, deviation, shading="nearest", cmap="viridis",
                         norm=LogNorm(vmin=max(float(deviation.min()), 1e-6),
                                      vmax=max(float(deviation.max()), 1e-5)))
    fig.colorbar(mesh, ax=ax, label="largest angle from LVLH (rad)")
    # the closed form, on a fine grid of its own
    lo1, hi1 = float(result.k1.min()), float(result.k1.max())
    lo3, hi3 = float(result.k3.min()), float(result.k3.max())
    fine1 = np.linspace(lo1, hi1, 601) if hi1 > lo1 else np.array([lo1])
    fine3 = np.linspace(lo3, hi3, 601) if hi3 > lo3 else np.array([lo3])
    if len(fine1) > 1 and len(fine3) > 1:
        grid1, grid3 = np.meshgrid(fine1, fine3)
        regions = gravity_gradient_region(grid1, grid3)
        for region, colour in (("lagrange", "red"), ("debra_delp", "magenta")):
            inside = (regions == region).astype(float)
            if 0 < inside.mean() < 1:
                ax.contour(grid1, grid3, inside, levels=[0.5], colors=colour, linewidths=1.2)
    handles = [Line2D([], [], color="red", lw=1.2, label="Lagrange region (closed form)"),
               Line2D([], [], color="magenta", lw=1.2, label="DeBra–Delp region (closed form)")]
    ax.legend(handles=handles, loc="upper left", fontsize=7, framealpha=0.8)
    ax.set_xlabel("k1 = (I2 − I3) / I1   (roll x along-track, pitch y, yaw z nadir)")
    ax.set_ylabel("k3 = (I2 − I1) / I3")
    ax.set_title(f"gravity gradient: {result.orbits:g} orbits from {result.perturbation:g} "
                 f"rad about each LVLH axis; departed above {result.limit:g} rad", fontsize=9)
    return _saved(fig, save)
