"""Coercion and validation of user input, before anything large is allocated.

Every failure names the argument and what is allowed: TypeError for the wrong kind of thing,
ValueError for the right kind with a bad value.
"""

from __future__ import annotations

import math
import numbers
import os
import sys
from typing import Any

import numpy as np

from . import _core
from .errors import TooLargeError

if sys.platform != "win32":
    import resource

__all__ = ["as_float", "as_int", "as_array", "check_size", "run_options", "MAX_INT"]

MAX_INT = 2**63 - 1
"""The largest integer argument: counts cross into the core as 64-bit integers."""


def _short(value: Any, limit: int = 60) -> str:
    """`repr(value)`, cut to `limit` characters (a 400-digit integer is not a message)."""
    text = repr(value)
    return text if len(text) <= limit else f"{text[: limit - 5]}…{text[-4:]}"


def _not_a_duration(name: str, value: Any, expected: str) -> None:
    """Refuses a NumPy time span or date (a ``np.timedelta64`` is registered as a NumPy
    integer): the package's times are plain numbers in the user's own unit."""
    if isinstance(value, (np.timedelta64, np.datetime64)):
        kind = "a time span" if isinstance(value, np.timedelta64) else "a date"
        raise TypeError(f"`{name}` must be {expected}, got {kind}, numpy."
                        f"{type(value).__name__} {_short(value)}; the package's times are "
                        "plain numbers in the user's own unit (for seconds: "
                        "`span / np.timedelta64(1, 's')`)")


def as_float(name: str, value: Any, *, positive: bool = False) -> float:
    """A finite real number (positive if asked)."""
    _not_a_duration(name, value, "a real number")
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"`{name}` must be a real number, got {type(value).__name__} "
                        f"{_short(value)}")
    allowed = "positive and finite" if positive else "finite"
    try:
        x = float(value)
    except OverflowError:  # an int or a Fraction beyond float64
        raise ValueError(f"`{name}` must be {allowed} in float64, got {_short(value)}") from None
    if not np.isfinite(x) or (positive and not x > 0):
        raise ValueError(f"`{name}` must be {allowed}, got {x!r}")
    return x


def as_int(name: str, value: Any, *, minimum: int, maximum: int = MAX_INT) -> int:
    """An integer in ``[minimum, maximum]`` (Python or NumPy integer; no floats, no bools)."""
    if type(value) is int and minimum <= value <= maximum:  # the common case, at once
        return value
    _not_a_duration(name, value, "an integer")
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"`{name}` must be an integer, got {type(value).__name__} "
                        f"{_short(value)}")
    n = int(value)
    if n < minimum:
        raise ValueError(f"`{name}` must be at least {minimum}, got {_short(n)}")
    if n > maximum:
        raise ValueError(f"`{name}` must be at most {maximum}, got {_short(n)}")
    return n


def as_array(name: str, value: Any, shape: str, *, last: int, ndim: tuple[int, ...]) -> np.ndarray:
    """A C-contiguous, aligned float64 array of finite values whose last axis has length
    `last`.

    `shape` is the human-readable shape for messages, e.g. "(N, 4)". No copy is made when
    `value` is already a C-contiguous, aligned float64 array; any other layout (strided,
    Fortran-ordered, unaligned, e.g. ``np.frombuffer(..., offset=1)``) is copied.
    """
    try:
        arr = np.asarray(value)
    except Exception as exc:  # ragged lists and the like
        raise TypeError(f"`{name}` must be an array of shape {shape}: {exc}") from None
    if arr.dtype.kind not in "iuf":
        raise TypeError(f"`{name}` must hold real numbers, got dtype {arr.dtype}")
    if arr.ndim not in ndim or arr.shape[-1:] != (last,):
        raise ValueError(f"`{name}` must have shape {shape}, got {arr.shape}")
    if not (arr.dtype == np.float64 and arr.flags.c_contiguous and arr.flags.aligned):
        # a copy is made: of its full size, whatever the input holds (a broadcast view of
        # 2**31 rows holds one)
        check_size(8 * arr.size, f"`{name}` as a float64 array of shape {arr.shape}",
                   f"pass a smaller `{name}`")
        arr = np.require(arr, dtype=np.float64, requirements=["C", "A"])
    # a start's few values are checked faster one by one than by NumPy
    if not (all(map(math.isfinite, arr.flat)) if arr.size <= 8 else np.isfinite(arr).all()):
        raise ValueError(f"`{name}` must be finite, got non-finite values")
    return arr


def _read_int(path: str, field: str | None = None) -> int | None:
    """An integer from a /proc or /sys file: the whole file, or the line `field: N kB`."""
    try:
        with open(path, encoding="ascii") as f:
            text = f.read()
    except (OSError, ValueError):
        return None
    if field is None:
        text = text.strip()
        return int(text) if text.isdigit() else None
    for line in text.splitlines():
        key, _, rest = line.partition(":")
        if key == field:
            number, _, unit = rest.strip().partition(" ")
            return int(number) * (1024 if unit == "kB" else 1) if number.isdigit() else None
    return None


def _address_space_room() -> int | None:
    """Bytes of address space left under the process's ``RLIMIT_AS`` (``ulimit -v``,
    ``prlimit --as``, as batch schedulers set), or None without such a limit."""
    if sys.platform == "win32":  # pragma: no cover - no such limit there
        return None
    soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    if soft == resource.RLIM_INFINITY:
        return None
    used = _read_int("/proc/self/status", "VmSize")
    return max(soft - (used or 0), 0)


def memory_available() -> tuple[int, str] | None:
    """The memory a new allocation can still get, in bytes, and what bounds it: on Linux the
    kernel's estimate of available memory (free plus reclaimable) or the room left under the
    process's cgroup limit or under its address-space limit (``RLIMIT_AS``), whichever is
    smallest; elsewhere the physical memory."""
    limits: list[tuple[int, str]] = []
    available = _read_int("/proc/meminfo", "MemAvailable")
    if available is not None:
        limits.append((available, "available memory"))
    for limit_file, usage_file in (("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory.current"),
                                   ("/sys/fs/cgroup/memory/memory.limit_in_bytes",
                                    "/sys/fs/cgroup/memory/memory.usage_in_bytes")):
        limit, usage = _read_int(limit_file), _read_int(usage_file)
        if limit is not None and usage is not None and limit < 2**60:
            limits.append((max(limit - usage, 0), "room under the memory limit (cgroup)"))
            break
    address_space = _address_space_room()
    if address_space is not None:
        limits.append((address_space, "room under the address-space limit (ulimit -v)"))
    if not limits:
        try:
            limits.append((os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"),
                           "physical memory"))
        except (ValueError, OSError, AttributeError):  # not on this platform
            return None
    return min(limits)


SMALL_REQUEST = 1 << 24
"""Bytes below which `check_size` does not ask the kernel (five file reads, ~0.1 ms, more
than a short run): the core's own allocations are fallible and refuse what cannot be had."""


def check_size(nbytes: int, what: str, hint: str) -> None:
    """Refuses a request for more memory than this machine can give now, before allocating
    it: the allocation itself would succeed (memory is committed lazily) and the process
    would be killed when it touched the pages."""
    if nbytes < SMALL_REQUEST:
        return
    room = memory_available()
    if room is not None and nbytes > room[0]:
        raise TooLargeError(
            f"{what} would need {nbytes / 1e9:.3g} GB ({nbytes} bytes), more than this "
            f"machine's {room[0] / 1e9:.3g} GB of {room[1]}; {hint}"
        )


def as_real(name: str, value: Any) -> float:
    """A real number as a float, whatever its value (infinities and NaN pass: the core says
    what values are allowed)."""
    if type(value) is float:  # the common case, at once
        return value
    _not_a_duration(name, value, "a real number")
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"`{name}` must be a real number, got {type(value).__name__} "
                        f"{_short(value)}")
    try:
        return float(value)
    except OverflowError:  # an int or a Fraction beyond float64
        raise ValueError(f"`{name}` must be finite in float64, got {_short(value)}") from None


def _optional(kind: Any, name: str, value: Any) -> Any:
    return None if value is None else kind(name, value)


def _integer(name: str, value: Any) -> int:
    return as_int(name, value, minimum=-MAX_INT)


def run_options(*, t_end: Any, frames: Any, dt: Any, method: Any, rtol: Any, atol: Any,
                max_steps: Any, flips: Any, threads: Any) -> _core.RunOptions:
    """A run's options: their kinds checked here, their values (ranges, and what goes with
    what: `atol` for adaptive methods only, `rtol` with `dt` for none) by the core, once."""
    if not isinstance(method, str):
        raise TypeError(f"`method` must be a string naming a method, got "
                        f"{type(method).__name__} {_short(method)}")
    if not isinstance(flips, (bool, np.bool_)):
        raise TypeError(f"`flips` must be True or False, got {type(flips).__name__}")
    return _core.RunOptions(
        as_real("t_end", t_end), _integer("frames", frames),
        dt=_optional(as_real, "dt", dt), method=method,
        rtol=_optional(as_real, "rtol", rtol), atol=_optional(as_real, "atol", atol),
        max_steps=_integer("max_steps", max_steps), flips=bool(flips),
        threads=_optional(_integer, "threads", threads))
