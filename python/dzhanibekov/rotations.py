"""Attitudes as scipy rotations: the one place where quaternion order is converted.

The package's quaternions are scalar first, ``(Q, U, V, W)``, and give the attitude
world-from-body: ``x_world = M(q) · x_body``. scipy's :class:`~scipy.spatial.transform.Rotation`
stores them scalar last, ``(U, V, W, Q)``, and applies the same rotation matrix, so
``Rotation.from_quat(q[..., [1, 2, 3, 0]]).apply(x_body)`` is ``dz.rotate(q, x_body)``.
A 4-vector cannot say which order it is in: pass a ``Rotation`` where the order might be
in doubt.

scipy is imported only when a rotation is built here: a ``Rotation`` handed in by the user
means scipy is already imported, and is recognised without importing it.
"""

from __future__ import annotations

import sys
from typing import Any

import numpy as np

__all__ = ["is_rotation", "quaternions_of", "to_rotation"]

_SCIPY_ROTATION = "scipy.spatial.transform"


def is_rotation(value: Any) -> bool:
    """Whether `value` is a :class:`scipy.spatial.transform.Rotation` (without importing scipy:
    if scipy is not imported, nothing can be one)."""
    module = sys.modules.get(_SCIPY_ROTATION)
    return module is not None and isinstance(value, module.Rotation)


def quaternions_of(value: Any) -> Any:
    """`value` as scalar-first quaternions if it is a scipy ``Rotation`` — shape (4,) for a
    single rotation, (N, 4) for a stack — and `value` itself otherwise (checked later as an
    array of shape (4,) or (M, 4))."""
    if not is_rotation(value):
        return value
    xyzw = np.asarray(value.as_quat(), dtype=np.float64)
    wxyz: np.ndarray = np.ascontiguousarray(np.roll(xyzw, 1, axis=-1))
    return wxyz


def to_rotation(q: np.ndarray) -> Any:
    """Scalar-first quaternions, shape (4,) or (N, 4), as a scipy ``Rotation`` (one or a stack),
    world-from-body."""
    # scipy takes up to a second to import: only when a rotation is asked for
    from scipy.spatial.transform import Rotation  # type: ignore[import-untyped, unused-ignore]

    xyzw = np.roll(np.asarray(q, dtype=np.float64), -1, axis=-1)
    return Rotation.from_quat(xyzw)
