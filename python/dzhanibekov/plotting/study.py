"""The figure of a Monte Carlo study: the outcome over the two inputs that tell most about it,
and the estimate with its interval as the samples come in.

>>> import dzhanibekov as dz
>>> from dzhanibekov.plotting.study import study_figure
>>> study = dz.monte_carlo(lambda rng: (1.0, 3.0, rng.uniform(2.7, 3.7)), (1e-3, 1e-3, 1.0),
...                        500, seed=1, t_end=1e6)
>>> fig = study_figure(study, save="study.png")                    # doctest: +SKIP
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from ..montecarlo import MonteCarlo

__all__ = ["study_figure", "MAX_POINTS", "LABELS"]

MAX_POINTS = 20_000
"""Samples drawn in the scatter at most (the first that ran)."""

_YES, _NO = "#d62728", "#1f77b4"

LABELS = {
    "separatrix": "distance to the separatrix, (L²/2E − I_mid) / (I_max − I_min)",
    "I1": "I₁ (principal moment)", "I2": "I₂ (principal moment)",
    "I3": "I₃ (principal moment)", "Ix": "I_x", "Iy": "I_y", "Iz": "I_z",
    "u0": "u₀ (initial rate about x)", "v0": "v₀ (initial rate about y)",
    "w0": "w₀ (initial rate about z)", "j": "damper sphere inertia j",
    "c": "damping coefficient c", "su0": "damper sphere's initial rate about x",
    "sv0": "damper sphere's initial rate about y", "sw0": "damper sphere's initial rate about z",
}
"""Axis labels of the inputs (others are shown by name)."""


def study_figure(study: MonteCarlo, *, inputs: tuple[str, str] | None = None,
                 save: str | Path | None = None) -> Figure:
    """Two panels: each sample's outcome over the two inputs that tell most about it
    (:meth:`MonteCarlo.telling`, or `inputs`), and the estimate against the number of
    samples with its confidence interval (for a rare-event study: the outcomes against the
    distance to the separatrix, per stratum).

    Parameters
    ----------
    study : MonteCarlo
    inputs : (str, str), optional
        The inputs on the scatter's axes (names of :meth:`MonteCarlo.columns`).
    save : str or Path, optional
        Where to save the figure (format from the suffix).

    Returns
    -------
    Figure

    Raises
    ------
    TypeError
        `study` not a MonteCarlo.
    ValueError
        A study with no samples, or an `inputs` name it does not have.
    """
    if not isinstance(study, MonteCarlo):
        raise TypeError(f"`study` must be a MonteCarlo, got {type(study).__name__}")
    if study.runs == 0:
        raise ValueError("`study` has no samples to draw")
    fig = Figure(figsize=(11.0, 4.6), layout="constrained")
    left, right = fig.subplots(1, 2)
    _scatter(left, study, inputs)
    if study.stratum is not None:
        _strata(right, study)
    else:
        _running(right, study)
    if save is not None:
        fig.savefig(save, dpi=100)
    return fig


def _scatter(ax: Axes, study: MonteCarlo, inputs: tuple[str, str] | None) -> None:
    columns = study.columns(MAX_POINTS)
    if inputs is None:
        names = study.telling(2, MAX_POINTS)
    else:
        names = list(inputs)
        unknown = [name for name in names if name not in columns]
        if len(names) != 2 or unknown:
            raise ValueError(f"`inputs` must name two of {sorted(columns)}, got {inputs!r}")
    count = min(study.runs, MAX_POINTS)
    y = study.outcomes[:count]
    if len(names) == 0:  # nothing varies: the outcomes in sample order
        x_values, y_values = study.samples[:count].astype(float), np.zeros(count)
        names = ["sample", ""]
    elif len(names) == 1:
        x_values, y_values = columns[names[0]], np.zeros(count)
        names = [names[0], ""]
    else:
        x_values, y_values = columns[names[0]], columns[names[1]]
    if study.is_boolean:
        for value, colour, label in ((False, _NO, f"not {study.ask}"), (True, _YES, study.ask)):
            pick = y == value
            ax.scatter(x_values[pick], y_values[pick], s=6, c=colour, label=label,
                       alpha=0.7, linewidths=0)
        ax.legend(loc="best", fontsize=8, markerscale=2)
    else:
        points = ax.scatter(x_values, y_values, s=6, c=y, cmap="viridis", linewidths=0)
        ax.get_figure().colorbar(points, ax=ax, label=study.ask)  # type: ignore[union-attr]
    ax.set_xlabel(LABELS.get(names[0], names[0]))
    ax.set_ylabel(LABELS.get(names[1], names[1]))
    shown = f"the first {count} of {study.runs}" if count < study.runs else f"{count}"
    ax.set_title(f"{study.ask}: {shown} samples over the inputs that tell most", fontsize=9)


def _running(ax: Axes, study: MonteCarlo) -> None:
    if study.is_boolean:
        run = study.running()
        n, estimate, lower, upper = run.n, run.estimate, run.lower, run.upper
        label = "p"
        lo, hi = study.interval
        title = (f"p = {study.p:.4g}, {study.level:.0%} {study.interval_method} interval "
                 f"[{lo:.4g}, {hi:.4g}], n = {study.runs}")
    else:
        y = study.outcomes.astype(np.float64)
        n = np.unique(np.geomspace(2, max(study.runs, 2), 200).round().astype(np.int64))
        n = n[n <= study.runs]
        sums, squares = np.cumsum(y)[n - 1], np.cumsum(y * y)[n - 1]
        estimate = sums / n
        spread = np.sqrt(np.maximum(squares / n - estimate**2, 0.0) * n / np.maximum(n - 1, 1))
        lower, upper = estimate - 1.96 * spread / np.sqrt(n), estimate + 1.96 * spread / np.sqrt(n)
        label = f"mean {study.ask}"
        title = f"mean = {study.mean:.4g} ± {1.96 * study.standard_error:.2g} (95%), n = {study.runs}"
    ax.fill_between(n, lower, upper, color="#9ecae1", label="interval")
    ax.plot(n, estimate, color="k", lw=1.2, label="estimate")
    ax.axhline(estimate[-1], color="k", lw=0.6, ls="--")
    ax.set_xscale("log")
    ax.set_xlabel("samples n")
    ax.set_ylabel(label)
    ax.legend(loc="best", fontsize=8)
    ax.set_title(title, fontsize=9)


def _strata(ax: Axes, study: MonteCarlo) -> None:
    """A rare-event study: each run's outcome against its distance to the separatrix."""
    columns: dict[str, Any] = study.columns()
    distance = np.abs(columns.get("separatrix", np.full(study.runs, np.nan)))
    y = study.outcomes.astype(np.float64)
    stratum = study.stratum if study.stratum is not None else np.zeros(study.runs, np.int8)
    for h, (colour, name) in enumerate((("#ff7f0e", "nearest (all run)"),
                                        ("#7f7f7f", "others (a random share run)"))):
        pick = stratum == h
        ax.scatter(np.maximum(distance[pick], 1e-16), y[pick], s=8, c=colour, label=name,
                   alpha=0.6, linewidths=0)
    ax.set_xscale("log")
    ax.set_xlabel("|distance to the separatrix|  (L²/2E − I_mid) / (I_max − I_min)")
    ax.set_ylabel(study.ask)
    ax.legend(loc="best", fontsize=8)
    if study.is_boolean:
        lo, hi = study.interval
        ax.set_title(f"p = {study.p:.3g} [{lo:.3g}, {hi:.3g}]: {study.runs} runs of "
                     f"{study.n} draws, as {study.effective_runs:.3g} plain runs", fontsize=9)
