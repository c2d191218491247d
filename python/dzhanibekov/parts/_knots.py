"""Knots of tables (a tabulated torque, a wheel's schedule, a deployment): their times checked,
and the place of a time between two of them."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .._args import as_array, check_size

__all__ = ["BYTES_PER_KNOT", "knot_times", "knot_fraction", "interpolate"]

BYTES_PER_KNOT = 8 * 4 * 4
"""Memory a knot takes while a table is built: its time and vector, a few copies (64 bytes
measured: the arrays kept and the core's table)."""


def knot_times(times: Any, n_name: str = "times", bytes_per_knot: int = BYTES_PER_KNOT
               ) -> np.ndarray:
    """Knot times: a float64 array (K,) of at least two finite, strictly increasing times.

    Raises
    ------
    TypeError
        Not a sequence of real numbers.
    ValueError
        Fewer than two knots, not finite, or not strictly increasing (naming the first pair).

    Examples
    --------
    >>> from dzhanibekov.parts import knot_times
    >>> knot_times([0, 1.5]).tolist()
    [0.0, 1.5]
    """
    try:
        n = len(times)
    except TypeError:
        raise TypeError(f"`{n_name}` must be a sequence of knot times, got "
                        f"{type(times).__name__}") from None
    check_size(n * bytes_per_knot, f"a table of {n} knots", "give fewer knots")
    t = as_array(n_name, times, "(K,)", last=n, ndim=(1,))
    if len(t) < 2:
        raise ValueError(f"`{n_name}` must hold at least two knots, got {len(t)}")
    bad = np.flatnonzero(t[1:] <= t[:-1])  # (not np.diff: a gap of knots at ±1.7e308 overflows)
    if bad.size:
        k = int(bad[0])
        raise ValueError(f"`{n_name}` must be strictly increasing, got {n_name}[{k}] = "
                         f"{t[k]!r} then {n_name}[{k + 1}] = {t[k + 1]!r}")
    return t


def knot_fraction(t: float, t0: float, t1: float) -> float:
    """Where `t` lies in ``[t0, t1]``, ``(t − t0) / (t1 − t0)``, for intervals of any width:
    one wider than float64's largest number (knots at ±1.7e308) by its halves (its width
    overflowed, and the place was 0 at every `t`).

    Examples
    --------
    >>> knot_fraction(0.0, -1.7e308, 1.7e308)
    0.5
    """
    gap = t1 - t0  # (Python floats: an overflow is inf, without a warning)
    if math.isfinite(gap):
        return (t - t0) / gap
    return (0.5 * t - 0.5 * t0) / (0.5 * t1 - 0.5 * t0)


def interpolate(t: float, times: Any, values: Any) -> Any:
    """The values at knots `times` (increasing) interpolated linearly at `t`, held outside
    them (as ``numpy.interp``, for knots of any span: see :func:`knot_fraction`)."""
    k = int(np.searchsorted(times, t, side="right"))
    if k == 0:
        return values[0]
    if k == len(times):
        return values[-1]
    s = knot_fraction(float(t), float(times[k - 1]), float(times[k]))
    return values[k - 1] + s * (values[k] - values[k - 1])
