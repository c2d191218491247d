"""Coercion and validation of user input, before anything large is allocated.

Every failure names the argument and what is allowed: TypeError for the wrong kind of thing,
ValueError for the right kind with a bad value.
"""

from __future__ import annotations

import numbers
import os
from typing import Any

import numpy as np

__all__ = ["as_float", "as_int", "as_array", "check_size"]


def as_float(name: str, value: Any, *, positive: bool = False) -> float:
    """A finite real number (positive if asked)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"`{name}` must be a real number, got {type(value).__name__} {value!r}")
    x = float(value)
    if not np.isfinite(x) or (positive and not x > 0):
        allowed = "positive and finite" if positive else "finite"
        raise ValueError(f"`{name}` must be {allowed}, got {x!r}")
    return x


def as_int(name: str, value: Any, *, minimum: int) -> int:
    """An integer of at least `minimum` (Python or NumPy integer; no floats, no bools)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"`{name}` must be an integer, got {type(value).__name__} {value!r}")
    n = int(value)
    if n < minimum:
        raise ValueError(f"`{name}` must be at least {minimum}, got {n}")
    return n


def as_array(name: str, value: Any, shape: str, *, last: int, ndim: tuple[int, ...]) -> np.ndarray:
    """A C-contiguous float64 array of finite values whose last axis has length `last`.

    `shape` is the human-readable shape for messages, e.g. "(N, 4)". No copy is made when
    `value` is already a C-contiguous float64 array.
    """
    try:
        arr = np.asarray(value)
    except Exception as exc:  # ragged lists and the like
        raise TypeError(f"`{name}` must be an array of shape {shape}: {exc}") from None
    if arr.dtype.kind not in "iuf":
        raise TypeError(f"`{name}` must hold real numbers, got dtype {arr.dtype}")
    if arr.ndim not in ndim or arr.shape[-1:] != (last,):
        raise ValueError(f"`{name}` must have shape {shape}, got {arr.shape}")
    arr = np.ascontiguousarray(arr, dtype=np.float64)
    if not np.isfinite(arr).all():
        raise ValueError(f"`{name}` must be finite, got non-finite values")
    return arr


def _memory_bytes() -> int | None:
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):  # not on this platform
        return None


def check_size(nbytes: int, what: str, hint: str) -> None:
    """Refuses a request for more memory than this machine has, before allocating it."""
    total = _memory_bytes()
    if total is not None and nbytes > total:
        raise ValueError(
            f"{what} would need {nbytes / 1e9:.3g} GB, more than this machine's "
            f"{total / 1e9:.3g} GB of memory; {hint}"
        )
