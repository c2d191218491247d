"""What a body looks like: the points, edges and faces drawn for it, in its own axes.

A :class:`Shape` is drawn by rotating its points with the core's `rotate` (every frame in
one call) and joining them by its edges (and shading its faces, when it has any). Solids
give an outline (a box's 12 edges, a cylinder's rims and four generators, an ellipsoid's
three principal sections); meshes give their faces and the edges where the surface bends;
composites the union of their parts, placed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Shape", "box_shape", "cylinder_shape", "ellipsoid_shape", "mesh_shape"]


@dataclass(frozen=True, eq=False)
class Shape:
    """Points, edges and (optionally) triangular faces of a body, in its axes.

    Attributes
    ----------
    vertices : ndarray, shape (V, 3)
    edges : ndarray of int, shape (E, 2)
        Pairs of vertex indices joined by a line.
    faces : ndarray of int, shape (F, 3), or None
        Triangles shaded in the pictures (meshes and composites of meshes).
    """

    vertices: np.ndarray
    edges: np.ndarray
    faces: np.ndarray | None = None

    def placed(self, rotation: np.ndarray, position: np.ndarray) -> Shape:
        """The shape turned by `rotation` (3×3) and moved by `position`."""
        return Shape(self.vertices @ np.asarray(rotation).T + np.asarray(position),
                     self.edges, self.faces)

    @staticmethod
    def union(shapes: list[Shape]) -> Shape:
        """The shapes drawn together (indices renumbered)."""
        offsets = np.cumsum([0] + [len(s.vertices) for s in shapes])
        faces = [s.faces + o for s, o in zip(shapes, offsets) if s.faces is not None]
        return Shape(
            np.concatenate([s.vertices for s in shapes]),
            np.concatenate([s.edges + o for s, o in zip(shapes, offsets)]),
            np.concatenate(faces) if faces else None,
        )

    @property
    def radius(self) -> float:
        """The largest distance of a point from the origin (the body's centre of mass)."""
        return float(np.linalg.norm(self.vertices, axis=1).max()) if len(self.vertices) else 0.0


BOX_FACES = np.array([(0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4),
                      (2, 6, 7), (2, 7, 3), (0, 4, 6), (0, 6, 2), (1, 3, 7), (1, 7, 5)])
"""The box's 12 triangles, counter-clockwise seen from outside."""


def box_shape(a: float, b: float, c: float, faces: bool = False) -> Shape:
    """The 12 edges of the box ``(±a/2, ±b/2, ±c/2)`` (vertex ``k`` has sign ``+`` on axis
    ``j`` where bit ``j`` of ``k`` is 1), and its faces if asked (a solid box is shaded; the
    paper's box is a wireframe)."""
    k = np.arange(8)
    signs = np.stack([(k >> j) & 1 for j in range(3)], axis=1) * 2.0 - 1.0
    edges = np.array([(k, k | (1 << j)) for j in range(3) for k in range(8) if not k >> j & 1])
    return Shape(signs * (np.array([a, b, c]) / 2.0), edges,
                 BOX_FACES.copy() if faces else None)


def _ring(n: int) -> np.ndarray:
    """Edges closing a ring of `n` consecutive vertices."""
    i = np.arange(n)
    return np.stack([i, (i + 1) % n], axis=1)


def cylinder_shape(radius: float, height: float, n: int = 48) -> Shape:
    """The two rims of a cylinder about z (`n` segments each) and four generators."""
    phi = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    rim = np.stack([radius * np.cos(phi), radius * np.sin(phi), np.zeros(n)], axis=1)
    top, bottom = rim + [0, 0, height / 2], rim - [0, 0, height / 2]
    sides = np.array([(k, n + k) for k in range(0, n, n // 4)])
    return Shape(np.concatenate([top, bottom]),
                 np.concatenate([_ring(n), _ring(n) + n, sides]))


def ellipsoid_shape(a: float, b: float, c: float, n: int = 48) -> Shape:
    """The three principal sections of the ellipsoid of semi-axes `a`, `b`, `c`."""
    phi = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    cos, sin, zero = np.cos(phi), np.sin(phi), np.zeros(n)
    rings = [np.stack([a * cos, b * sin, zero], axis=1),
             np.stack([a * cos, zero, c * sin], axis=1),
             np.stack([zero, b * cos, c * sin], axis=1)]
    return Shape(np.concatenate(rings), np.concatenate([_ring(n) + k * n for k in range(3)]))


def mesh_shape(vertices: np.ndarray, faces: np.ndarray, crease_deg: float = 40.0) -> Shape:
    """A closed triangle mesh: its faces, and its edges where the faces on either side meet
    at more than `crease_deg` (the outline of a polyhedron, not the triangulation)."""
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    size = float(np.abs(v).max(initial=0.0))
    unit = np.ldexp(v, -int(np.frexp(size)[1])) if size > 0 else v  # no overflow at 1e100
    normals = np.cross(unit[f[:, 1]] - unit[f[:, 0]], unit[f[:, 2]] - unit[f[:, 0]])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-300)
    tail, head = f.reshape(-1), np.roll(f, -1, axis=1).reshape(-1)
    owner = np.repeat(np.arange(len(f)), 3)
    n = len(v)
    index = {int(t) * n + int(h): int(o) for t, h, o in zip(tail, head, owner)}
    edges = []
    cos_crease = np.cos(np.radians(crease_deg))
    for t, h, o in zip(tail.tolist(), head.tolist(), owner.tolist()):
        if t < h:
            other = index.get(h * n + t)
            if other is None or float(normals[o] @ normals[other]) < cos_crease:
                edges.append((t, h))
    return Shape(v, np.array(edges, dtype=np.int64).reshape(-1, 2), f)
