"""The paper's body as data: the 20 × 10 × 15 box, its edges and the signal point."""

from __future__ import annotations

import numpy as np

from ._checks import as_float

__all__ = ["BOX_SIZE", "box_vertices", "box_edges", "SIGNAL_POINT"]

BOX_SIZE = (20.0, 10.0, 15.0)
"""Edge lengths along x, y, z of the paper's box."""

SIGNAL_POINT = np.array([0.0, 0.0, 13.0])
"""The paper's signal point on the body z axis; its path in space shows the flips."""


def box_vertices(a: float = BOX_SIZE[0], b: float = BOX_SIZE[1], c: float = BOX_SIZE[2]) -> np.ndarray:
    """The 8 corners ``(±a/2, ±b/2, ±c/2)`` of a box centred on the origin, shape (8, 3).

    Vertex ``k`` has sign ``-`` on axis ``j`` where bit ``j`` of ``k`` is 0. The edges must
    be positive and finite.
    """
    edges = [as_float(n, v, positive=True) for n, v in (("a", a), ("b", b), ("c", c))]
    k = np.arange(8)
    signs = np.stack([(k >> j) & 1 for j in range(3)], axis=1) * 2.0 - 1.0
    return signs * (np.array(edges) / 2.0)


def box_edges() -> np.ndarray:
    """The 12 edges of :func:`box_vertices` as pairs of vertex indices, shape (12, 2)."""
    return np.array([(k, k | (1 << j)) for j in range(3) for k in range(8) if not k >> j & 1])
