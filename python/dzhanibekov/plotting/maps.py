"""Stability maps: what a sweep measured over a grid of two parameters, with the separatrix.

A map is drawn from a :class:`~dzhanibekov.Sweep` of shape ``(n_x, n_y)`` whose starts vary
one parameter along each axis (as :func:`~dzhanibekov.grid` makes them): initial rates
``u0, v0, w0`` or inertia ratios ``iy = Iy/Ix, iz = Iz/Ix``. The colour is the measured flip
period, the largest tilt of the spin axis, the flip count or the exact period; the red line
is the separatrix, where the start lies on the motion that divides the wobbles about one
stable axis from those about the other: ``L² = 2E I_mid``, i.e.
``Σ_k I_k (I_k − I_mid) ω_k² = 0``, computed from the formula on a fine grid.

>>> import numpy as np, dzhanibekov as dz
>>> from dzhanibekov.plotting.maps import stability_map
>>> s = dz.sweep(dz.PAPER_INERTIA, dz.grid(np.linspace(0, 1, 5), np.linspace(0, 1, 5), 1.0),
...              t_end=50.0, dt=1e-2)
>>> fig = stability_map(s, quantity="tilt", save="map.png")               # doctest: +SKIP
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.colors import LogNorm, Normalize, TwoSlopeNorm
from matplotlib.figure import Figure

from .._args import as_array, as_int, check_size
from .._files import save_figure
from ..body import PAPER_INERTIA
from ..ensemble import Sweep, grid, sweep
from ..options import NAMES, RunKeywords, RunOptions, merged

if TYPE_CHECKING:
    from typing_extensions import Unpack
from .figures import _figure_of

__all__ = [
    "stability_map", "separatrix_gap", "map_sweep", "map_figure", "render_maps", "QUANTITIES",
    "PARAMETERS", "MAPS", "MAP_OPTIONS",
]

PARAMETERS: dict[str, tuple[str, Callable[[np.ndarray, np.ndarray], np.ndarray]]] = {
    "u0": ("u₀, initial rate about x (rad per unit of time)",
           lambda inertia, omega: omega[..., 0]),
    "v0": ("v₀, initial rate about y (rad per unit of time)",
           lambda inertia, omega: omega[..., 1]),
    "w0": ("w₀, initial rate about z (rad per unit of time)",
           lambda inertia, omega: omega[..., 2]),
    "iy": ("iy = Iy / Ix", lambda inertia, omega: inertia[..., 1] / inertia[..., 0]),
    "iz": ("iz = Iz / Ix", lambda inertia, omega: inertia[..., 2] / inertia[..., 0]),
}
"""The parameters a map's axes can show: a label and how to read it off the starts."""

QUANTITIES = ("period", "tilt", "flips", "exact_period")
"""What a map can colour by."""

NO_VALUE = "#d9d9d9"
"""The colour of a start without a value (grey)."""
NO_VALUE_MEANS = {
    "period": "no period: fewer than two flips by t_end",
    "exact_period": "no period: the motion never flips",
    "tilt": "no tilt measured",
    "flips": "no flip count",
}
"""What a grey start means on each map, as its legend says."""


def separatrix_gap(inertia: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """``L² − 2E I_mid = Σ_k I_k (I_k − I_mid) ω_k²``, relative to ``L²``: zero on the
    separatrix, positive for motions about the axis of the largest moment, negative about
    the smallest.

    Parameters
    ----------
    inertia, omega : ndarray, shape (..., 3)
        Principal moments and body rates (broadcast together).

    Returns
    -------
    ndarray, shape (...)
    """

    inertia = as_array("inertia", inertia, "(..., 3)", last=3, ndim=tuple(range(1, 10)))
    omega = as_array("omega", omega, "(..., 3)", last=3, ndim=tuple(range(1, 10)))
    if not (inertia > 0).all():
        raise ValueError("`inertia` must hold positive principal moments")
    try:
        inertia, omega = np.broadcast_arrays(inertia, omega)
    except ValueError:
        raise ValueError(f"`inertia` and `omega` must broadcast together, got shapes "
                         f"{inertia.shape} and {omega.shape}") from None
    # about ten temporaries of the broadcast shape
    check_size(10 * inertia.size * 8, f"the separatrix gap of {inertia.size // 3} starts",
               "ask for fewer starts at a time")
    # Σ x_k² (I_k − I_mid) / I_k over Σ x_k², x = I ω in units of a power of two near the
    # row's largest |I_k ω_k| (from the exponents of I and ω apart, so no product over- or
    # underflows before the scaling); I_k − I_mid is exact for nearly equal moments.
    mid = np.median(inertia, axis=-1, keepdims=True)
    mi, ei = np.frexp(inertia)
    mw, ew = np.frexp(omega)
    mantissa = mi * mw
    exponent = np.where(mantissa != 0, ei + ew, np.iinfo(np.int32).min // 2)
    x = np.ldexp(mantissa, exponent - exponent.max(axis=-1, keepdims=True))
    l2 = np.sum(x * x, axis=-1)
    gap = np.sum(x * x * ((inertia - mid) / inertia), axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(l2 > 0, gap / l2, 0.0)


def _axes_of(result: Sweep) -> tuple[str, str]:
    """The parameter that varies along each axis of a 2-D sweep (and not along the other)."""
    if len(result.shape) != 2 or min(result.shape) < 2:
        raise ValueError(
            f"a stability map needs a sweep over a 2-D grid of at least 2 × 2 starts (see "
            f"`dz.grid`), got shape {result.shape}"
        )
    names = []
    for axis in (0, 1):
        for name, (_, read) in PARAMETERS.items():
            values = read(result.inertia, result.omega0)
            varies = np.ptp(values, axis=axis).max() > 0
            constant_across = np.ptp(values, axis=1 - axis).max() == 0
            if varies and constant_across and name not in names:
                names.append(name)
                break
        else:
            raise ValueError(
                f"the sweep's axis {axis} varies none of {', '.join(PARAMETERS)} alone; "
                "build the starts with `dz.grid`"
            )
    return names[0], names[1]


def _values(result: Sweep, quantity: str) -> tuple[np.ndarray, str, Normalize, str]:
    if quantity == "tilt":
        return (result.tilt_degrees, "largest tilt of the spin axis (°)",
                TwoSlopeNorm(vcenter=90.0, vmin=0.0, vmax=180.0), "coolwarm")
    if quantity == "flips":
        flips = result.flips.astype(float)
        return flips, "flips", Normalize(0, max(1.0, float(flips.max()))), "viridis"
    if quantity in ("period", "exact_period"):
        values = np.where(np.isfinite(getattr(result, quantity)), getattr(result, quantity),
                          np.nan)
        finite = values[np.isfinite(values)]
        norm: Normalize = (LogNorm(float(finite.min()), float(finite.max()))
                           if finite.size and finite.min() > 0 and finite.max() > finite.min()
                           else Normalize())
        label = ("flip period (measured" if quantity == "period" else "flip period (exact") \
            + ", units of time)"
        return values, label, norm, "viridis"
    raise ValueError(f"`quantity` must be one of {QUANTITIES}, got {quantity!r}")


def stability_map(result: Sweep, *, quantity: str = "period", separatrix: bool = True,
                  ax: Axes | None = None, save: str | Path | None = None) -> Figure:
    """The stability map of a sweep over a 2-D grid: a quantity per start, and the separatrix.

    Parameters
    ----------
    result : Sweep
        A sweep of shape ``(n_x, n_y)``, ``n_x, n_y ≥ 2``, whose starts vary one of ``u0,
        v0, w0, iy, iz`` along each axis (see :func:`~dzhanibekov.grid`).
    quantity : {"period", "tilt", "flips", "exact_period"}
        The colour: the measured flip period (log scale; blank where a run flipped fewer
        than twice), the largest tilt of the spin axis (degrees, white at 90°), the flip
        count, or the exact period (blank where the motion never flips).
    separatrix : bool
        Draw the separatrix (red), from the formula on a grid 4 times finer than the
        sweep's, with the other parameters as in the sweep.
    ax : Axes, optional
        Draw into this axes instead of a new figure.
    save : str or Path, optional
        Where to save the figure (format from the suffix).

    Returns
    -------
    Figure
        One mesh of colours (with a colour bar) and, if asked, the separatrix as a contour
        labelled ``separatrix``; starts without a value (a period where fewer than two flips
        came) are grey, and the legend says so.

    Raises
    ------
    TypeError
        `result` not a Sweep.
    ValueError
        A sweep that is not over a 2-D grid of one parameter per axis, or an unknown
        `quantity`.
    """
    if not isinstance(result, Sweep):
        raise TypeError(f"`result` must be a Sweep, got {type(result).__name__}")
    if quantity not in QUANTITIES:
        raise ValueError(f"`quantity` must be one of {QUANTITIES}, got {quantity!r}")
    x_name, y_name = _axes_of(result)
    (x_label, read_x), (y_label, read_y) = PARAMETERS[x_name], PARAMETERS[y_name]
    x = read_x(result.inertia, result.omega0)[:, 0]
    y = read_y(result.inertia, result.omega0)[0, :]
    values, label, norm, cmap = _values(result, quantity)
    if ax is None:
        fig = Figure(figsize=(6.4, 5.0), layout="constrained")
        ax = fig.add_subplot()
    fig = _figure_of(ax)
    ax.set_facecolor(NO_VALUE)  # runs without a value show grey, and the legend says why
    mesh = ax.pcolormesh(x, y, np.ma.masked_invalid(values).T, shading="nearest", norm=norm,
                         cmap=cmap)
    fig.colorbar(mesh, ax=ax, label=label)
    handles = []
    if separatrix and _draw_separatrix(ax, result, (x_name, x), (y_name, y)):
        handles.append(_line("separatrix"))
    if not np.isfinite(values).all():
        from matplotlib.patches import Patch

        handles.append(Patch(facecolor=NO_VALUE, edgecolor="#999999", lw=0.5,
                             label=NO_VALUE_MEANS[quantity]))
    if handles:  # below the map, where it covers none of it
        ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.13),
                  ncols=len(handles), fontsize=8, frameon=False)
    ax.set_xlabel(x_label)
    ax.set_ylabel(y_label)
    ax.set_title(_title(result, (x_name, y_name)), fontsize=9)
    save_figure(fig, save, dpi=100)
    return fig


def _draw_separatrix(ax: Axes, result: Sweep, x: tuple[str, np.ndarray],
                     y: tuple[str, np.ndarray]) -> bool:
    """Draws the separatrix where it crosses the map; returns whether it does."""
    fine_x = np.linspace(x[1].min(), x[1].max(), 4 * len(x[1]))
    fine_y = np.linspace(y[1].min(), y[1].max(), 4 * len(y[1]))
    gx, gy = np.meshgrid(fine_x, fine_y, indexing="ij")
    inertia = np.broadcast_to(result.inertia[0, 0], gx.shape + (3,)).copy()
    omega = np.broadcast_to(result.omega0[0, 0], gx.shape + (3,)).copy()
    for name, grid in ((x[0], gx), (y[0], gy)):
        if name in ("u0", "v0", "w0"):
            omega[..., "uvw".index(name[0])] = grid
        else:
            inertia[..., "xyz".index(name[1])] = grid * inertia[..., 0]
    gap = separatrix_gap(inertia, omega)
    if np.nanmin(gap) < 0 < np.nanmax(gap):
        lines = ax.contour(gx, gy, gap, levels=[0.0], colors="#c0392b", linewidths=1.4)
        lines.set_label("separatrix")
        return True
    return False


def _line(label: str) -> Any:
    from matplotlib.lines import Line2D

    return Line2D([], [], color="#c0392b", lw=1.4, label=label)


def _title(result: Sweep, names: tuple[str, str]) -> str:
    fixed = []
    inertia, omega = result.inertia[0, 0], result.omega0[0, 0]
    if not {"iy", "iz"} & set(names):
        fixed.append("I = (" + ", ".join(f"{i:.4g}" for i in inertia) + ")")
    else:
        fixed.append(f"Ix = {inertia[0]:.4g}")
    rates = [f"{c}₀ = {w:.3g}" for c, w in zip("uvw", omega) if f"{c}0" not in names]
    fixed += rates
    return (f"Stability map: {', '.join(fixed)}; {result.method}, t_end = {result.t_end:g}, "
            f"{len(result)} runs")


MAPS = ("rates", "inertia")
"""The maps `render_maps` draws: over initial rates, and over inertia ratios."""


_TAKES = tuple(n for n in NAMES if n not in ("flips", "frames"))
"""The run options a map takes: its sweep counts the flips and keeps no frames."""
MAP_OPTIONS = RunOptions(t_end=200.0, dt=1e-2, frames=2)
"""A map's runs without `options`: 200 time units at a step of 0.01 (its keywords override
these)."""


def _map_options(function: str, options: RunOptions | None, keywords: Any) -> RunOptions:
    """`options` (else :data:`MAP_OPTIONS`) with `keywords` over it, two frames per run."""
    base = MAP_OPTIONS if options is None else options
    return merged(function, base, keywords, _TAKES).replace(frames=2)


def map_sweep(kind: str, *, size: int = 81, options: RunOptions | None = None,
              **keywords: Unpack[RunKeywords]) -> Sweep:
    """The sweep behind a shipped map.

    ``"rates"``: the paper's body (z intermediate) from ``ω0 = (u0, v0, 1)``, ``u0, v0`` in
    ``[0, 1.5]``: near the origin the spin is about the intermediate axis and flips; the
    separatrix is the line ``Ix (Ix − Iz) u0² = Iy (Iz − Iy) v0²``. ``"inertia"``: bodies
    ``(1, iy, iz)``, ``iy, iz`` in ``[0.5, 1.5]`` (all physical: each moment at most the sum of
    the others), from ``ω0 = (0.2, 0.2, 1)``: z is intermediate between the lines ``iz = 1``
    and ``iz = iy``, y and x in the other wedges, and each has its own separatrix.

    Parameters
    ----------
    kind : {"rates", "inertia"}
    size : int
        Starts per axis (at least 2).
    options : RunOptions, optional
        The runs' options (default :data:`MAP_OPTIONS`: ``t_end=200``, ``dt=0.01``), each
        overridden by its keyword; a map's runs keep two frames.
    t_end, dt, method, rtol, atol, max_steps, threads, progress
        As for :func:`~dzhanibekov.sweep`.
    """

    given = _map_options("map_sweep", options, keywords)
    size = as_int("size", size, minimum=2)
    if kind == "rates":
        rates = np.linspace(0.0, 1.5, size)
        return sweep(PAPER_INERTIA, grid(rates, rates, 1.0), options=given)
    if kind == "inertia":
        ratios = np.linspace(0.5, 1.5, size)
        return sweep(grid(1.0, ratios, ratios), (0.2, 0.2, 1.0), options=given)
    raise ValueError(f"`kind` must be one of {MAPS}, got {kind!r}")


def map_figure(result: Sweep, *, save: str | Path | None = None) -> Figure:
    """A sweep's map twice, side by side: the measured flip period and the largest tilt."""
    fig = Figure(figsize=(12.0, 4.8), layout="constrained")
    for k, quantity in enumerate(("period", "tilt")):
        stability_map(result, quantity=quantity, ax=fig.add_subplot(1, 2, k + 1))
    save_figure(fig, save, dpi=100)
    return fig


def render_maps(folder: str | Path, kinds: tuple[str, ...] = MAPS, *, size: int = 81,
                options: RunOptions | None = None, **keywords: Unpack[RunKeywords]
                ) -> tuple[list[Path], list[Sweep]]:
    """Writes ``map-KIND.png`` (:func:`map_figure`) and ``map-KIND.npz`` (the sweep's
    per-run arrays) for each kind into `folder`, the runs' options as for
    :func:`map_sweep`. Returns the files and the sweeps."""
    given = _map_options("render_maps", options, keywords)
    folder = Path(folder)
    files: list[Path] = []
    results = []
    for kind in kinds:
        result = map_sweep(kind, size=size, options=given)
        path = folder / f"map-{kind}.png"
        map_figure(result, save=path)
        data = folder / f"map-{kind}.npz"
        np.savez_compressed(
            data, inertia=result.inertia, omega0=result.omega0, flips=result.flips,
            first_flip=result.first_flip, period=result.period,
            exact_period=result.exact_period, tilt=result.tilt,
            drift_energy=result.drift.energy, t_end=result.t_end, dt=result.dt)
        files += [path, data]
        results.append(result)
    return files, results
