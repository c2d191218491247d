"""The inputs of runs as rows: what every entry point (one run, a batch, a sweep) turns its
arguments into before the core sees them — the systems (one shared, one per row, or rows of
principal moments), the rates (M, 3) and the attitudes (M, 4), and the shape of the starts.

Only kinds and shapes are checked here; the values are the core's to check.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from . import _core
from ._args import as_array, check_size
from ._swap import swapped_error
from .body import TENSOR_HINT, Body, InertiaWarning, _is_square
from .deployment import Deployment
from .errors import DzhanibekovError
from .rotations import quaternions_of
from .system import System, Systems, as_system

__all__ = ["Rows", "rows_of", "row_error", "is_system_list", "warn_unphysical"]


@dataclass(frozen=True)
class Rows:
    """The runs asked for: `systems` (one per row), rates `omega` (M, 3) and attitudes `q`
    (M, 4), C-contiguous float64; `shape` the starts' leading axes (``()`` for one run);
    `batch` whether the inputs had a batch axis (then results have a run axis)."""

    systems: Systems
    omega: np.ndarray
    q: np.ndarray
    shape: tuple[int, ...]
    batch: bool

    def __len__(self) -> int:
        return len(self.omega)

    def core(self) -> tuple[list[_core.System], np.ndarray | None]:
        """The systems as the core takes them: a list (one shared, or one per row), or rows
        of principal moments."""
        return self.systems.core(), self.systems.moments

    def where(self, row: int) -> str:
        """Where row `row` is among the starts, for a message."""
        if len(self.shape) <= 1:
            return f"row {row}"
        return f"index {tuple(int(i) for i in np.unravel_index(row, self.shape))}"

    def take(self, rows: slice) -> Rows:
        """The rows `rows` (a block of a batch or sweep)."""
        return Rows(self.systems[rows], self.omega[rows], self.q[rows], self.shape, True)


def is_system_list(value: Any) -> bool:
    """Whether `value` is a list (or tuple) of systems, bodies or deployments, one per run."""
    return isinstance(value, (list, tuple)) and len(value) > 0 and all(
        isinstance(v, (System, Body, Deployment)) for v in value)


def _ndim(value: Any) -> int:
    try:
        return int(np.ndim(value))
    except Exception:  # ragged, or no array at all: the checks will say so
        return 0


def rows_of(system: Any, omega0: Any, q0: Any, *, function: str,
            max_batch_ndim: int, stacklevel: int) -> Rows:
    """The rows of a run of `function` (see the module doc): `system` one System, Body,
    Deployment or principal moments (3,), a list of them, or moments S + (3,); `omega0`
    (3,) or S + (3,); `q0` (4,), S + (4,) or a scipy ``Rotation``. Inputs without the batch
    axes are shared by every row; `max_batch_ndim` batch axes at most."""
    q0 = quaternions_of(q0)
    if isinstance(omega0, (System, Body, Deployment)):
        raise TypeError(f"`omega0` must be the body rates (u0, v0, w0), got a "
                        f"{type(omega0).__name__}: the system comes first, "
                        f"{function}(system, omega0)")
    swapped = swapped_error(system, omega0, function)
    shape_of = f"(..., {{}})" if max_batch_ndim > 1 else "({0},) or (M, {0})"
    ndim = tuple(range(1, max_batch_ndim + 2))
    omega = as_array("omega0", omega0, shape_of.format(3), last=3, ndim=ndim)
    if not isinstance(q0, (list, tuple, np.ndarray)) and _ndim(q0) == 0:
        raise TypeError(f"`q0` (the third argument of `{function}`) must be a quaternion "
                        f"(Q, U, V, W), scalar first, or a scipy Rotation, got "
                        f"{type(q0).__name__}; t_end and the other options are keyword "
                        f"arguments: {function}(system, omega0, t_end=...)")
    q = as_array("q0", q0, shape_of.format(4), last=4, ndim=ndim)
    if q.ndim == 1:
        zero = None if q.any() else 0
    else:
        rows = ~np.any(q.reshape(-1, 4) != 0, axis=1)
        zero = int(np.argmax(rows)) if rows.any() else None
    if zero is not None:
        raise ValueError("`q0` must be a non-zero quaternion (Q, U, V, W), scalar first, "
                         "got (0, 0, 0, 0)" + _at(zero, q.shape[:-1]))
    if swapped is not None:  # before the moments are built into a body, which would refuse
        raise swapped
    moments: np.ndarray | None = None
    each: tuple[System, ...] | None = None
    shared: System | None = None
    if is_system_list(system):
        each = tuple(as_system(s, f"system[{k}]") for k, s in enumerate(system))
        lead: tuple[int, ...] = (len(each),)
    elif isinstance(system, (System, Body, Deployment)) or _ndim(system) <= 1:
        shared = as_system(system)
        lead = ()
        if omega.ndim == 1 and q.ndim == 1:  # one run: no axes to broadcast
            return Rows(Systems(1, shared=shared), _one_row(omega), _one_row(q), (), False)
    else:
        if _is_square(system):
            raise ValueError("`system` of shape (3, 3) is ambiguous: one body's inertia "
                             f"tensor or three bodies' principal moments? {TENSOR_HINT}")
        moments = as_array("system", system, shape_of.format(3), last=3, ndim=ndim)
        lead = moments.shape[:-1]
        rows = moments.reshape(-1, 3)
        with np.errstate(invalid="ignore"):
            bad = ~((rows > 0) & np.isfinite(rows)).all(axis=1)
        if bad.any():  # named here: the core's row error would name its `inertia`
            i = int(bad.argmax())
            raise ValueError(f"`system` must hold three positive, finite principal moments "
                             f"(Ix, Iy, Iz) in each row, got {rows[i].tolist()}{_at(i, lead)}")
    try:
        shape = np.broadcast_shapes(lead, omega.shape[:-1], q.shape[:-1])
    except ValueError:
        raise ValueError(
            "the leading (batch) axes of `system`, `omega0` and `q0` must match or be absent, "
            f"got {lead}, {omega.shape[:-1]} and {q.shape[:-1]}") from None
    m = math.prod(shape)
    check_size(m * 40 * 8, f"{m} starts", "run fewer starts at a time (split the batch)")
    flat = [np.ascontiguousarray(np.broadcast_to(a, shape + a.shape[-1:]).reshape(
        m, a.shape[-1]), dtype=np.float64) for a in (omega, q)]
    if moments is not None:
        moments = np.ascontiguousarray(
            np.broadcast_to(moments, shape + (3,)).reshape(m, 3), dtype=np.float64)
    if each is not None and len(each) == 1 and m > 1:
        shared, each = each[0], None
    if each is not None and len(set(s.kinds for s in each)) > 1:
        kinds = [s.kinds for s in each]
        k = next(i for i, kind in enumerate(kinds) if kind != kinds[0])
        raise ValueError(f"`system` must hold systems of one kind in a batch: row 0 is "
                         f"{kinds[0]}, row {k} {kinds[k]}; run them as separate batches")
    systems = Systems(m, shared=shared, each=each, moments=moments)
    batch = bool(shape) or each is not None
    return Rows(systems, flat[0], flat[1], tuple(shape), batch)


def _one_row(a: np.ndarray) -> np.ndarray:
    """A start (n,) (C-contiguous float64, as `as_array` gives it) as the one row (1, n)."""
    return a.reshape(1, len(a))


def _at(flat: int, shape: tuple[int, ...]) -> str:
    """Where in an input of leading `shape` row `flat` is, for a message ("" if shared)."""
    if not shape:
        return ""
    if len(shape) == 1:
        return f" at row {flat}"
    return f" at index {tuple(int(i) for i in np.unravel_index(flat, shape))}"


def warn_unphysical(rows: Rows, *, stacklevel: int) -> None:
    """One warning for all the rows of moments that no real body has, once the core has
    accepted them (bodies built as `Body` warned when they were built). Column by column:
    reductions over a last axis of 3 are slow."""
    inertia = rows.systems.moments
    if inertia is None:
        return
    shape = rows.shape
    a, b, c = inertia.T
    with np.errstate(invalid="ignore", over="ignore"):
        largest = np.maximum(np.maximum(a, b), c)
        total = a + b + c
        unphysical = (2 * largest > total * (1 + _core.TRIANGLE_SLACK)).nonzero()[0]
    if len(unphysical):
        i = int(unphysical[0])
        warnings.warn(
            f"{len(unphysical)} of {len(inertia)} bodies break the triangle inequality (each "
            "moment of a real body is at most the sum of the other two), the first "
            f"{inertia[i].tolist()}{_at(i, shape)}; no mass distribution has them",
            InertiaWarning,
            stacklevel=stacklevel,
        )


def row_error(exc: ValueError, rows: Rows, offset: int = 0) -> ValueError:
    """The core's error about row ``exc.row`` of a block starting at row `offset`, about that
    row among all the starts (with its index, for several axes); a single run's without a
    row."""
    if not isinstance(exc, DzhanibekovError) or exc.row is None:
        return exc
    if not rows.batch:
        return type(exc)(exc.message)
    flat = offset + exc.row
    shape = rows.shape
    index = tuple(int(i) for i in np.unravel_index(flat, shape)) if len(shape) > 1 else None
    return exc.at(flat, index)
