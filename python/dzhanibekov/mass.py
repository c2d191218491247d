"""Mass properties: inertia tensors of solids, composites and closed triangle meshes, and
their principal axes.

Conventions (see :class:`~dzhanibekov.Body`): the inertia tensor ``T`` about a point has the
moments on its diagonal and the *negated* products of inertia off it,

    T = [[ Ixx, -Ixy, -Ixz],      Ixx = ∫ (y² + z²) dm,   Ixy = ∫ x y dm, …
         [-Ixy,  Iyy, -Iyz],
         [-Ixz, -Iyz,  Izz]]

so that ``L = T ω``. In terms of the second moments ``C = ∫ r rᵀ dm``, ``T = tr(C) 𝟙 − C``.

Sources of the formulas:

- solids: the uniform box, circular cylinder, sphere and ellipsoid, e.g. the table of
  moments in Goldstein, Poole & Safko, *Classical Mechanics* (3rd ed.), or
  https://en.wikipedia.org/wiki/List_of_moments_of_inertia;
- parallel-axis theorem (Huygens–Steiner): ``T_O = T_G + m (|d|² 𝟙 − d dᵀ)`` for a body of
  mass ``m`` whose centre of mass ``G`` sits at ``d`` from ``O``;
- meshes: the divergence theorem turns the volume integrals into sums over the faces; for a
  triangle mesh this is the sum over its faces of the signed tetrahedra (origin, a, b, c),
  whose second moments are exact: ``∫ r rᵀ dV = V/20 (a aᵀ + b bᵀ + c cᵀ + s sᵀ)`` with
  ``s = a + b + c`` and ``V = a·(b×c)/6`` (B. Mirtich, "Fast and accurate computation of
  polyhedral mass properties", J. Graphics Tools 1(2), 1996; D. Eberly, "Polyhedral Mass
  Properties (Revisited)", Geometric Tools, 2002; F. Tonon, J. Math. Stat. 1(1), 2004).
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = [
    "box_tensor",
    "cylinder_tensor",
    "ellipsoid_tensor",
    "parallel_axis",
    "mesh_properties",
    "principal",
    "quaternion_of",
    "MeshError",
]


class MeshError(ValueError):
    """A mesh whose volume is not defined: open, non-manifold, inconsistently oriented or
    wound inward."""


def box_tensor(a: float, b: float, c: float, mass: float) -> np.ndarray:
    """Uniform box of edges `a`, `b`, `c` along x, y, z: ``Ixx = m (b² + c²) / 12``, …"""
    return np.diag([b * b + c * c, a * a + c * c, a * a + b * b]) * (mass / 12.0)


def cylinder_tensor(radius: float, height: float, mass: float) -> np.ndarray:
    """Uniform solid circular cylinder, axis z: ``Izz = m r² / 2``,
    ``Ixx = Iyy = m (3 r² + h²) / 12``."""
    side = mass * (3 * radius * radius + height * height) / 12.0
    return np.diag([side, side, mass * radius * radius / 2.0])


def ellipsoid_tensor(a: float, b: float, c: float, mass: float) -> np.ndarray:
    """Uniform solid ellipsoid of semi-axes `a`, `b`, `c` along x, y, z:
    ``Ixx = m (b² + c²) / 5``, … (a sphere of radius r: ``2 m r² / 5``)."""
    return np.diag([b * b + c * c, a * a + c * c, a * a + b * b]) * (mass / 5.0)


def parallel_axis(tensor: np.ndarray, mass: float, offset: np.ndarray) -> np.ndarray:
    """The tensor about a point at ``-offset`` from the centre of mass: the tensor about the
    centre of mass `tensor` plus ``m (|d|² 𝟙 − d dᵀ)`` (Huygens–Steiner)."""
    d = np.asarray(offset, dtype=np.float64)
    shifted: np.ndarray = tensor + mass * (np.dot(d, d) * np.eye(3) - np.outer(d, d))
    return shifted


def check_mesh(faces: np.ndarray, n_vertices: int) -> None:
    """Refuses a triangle mesh that is not closed and consistently oriented: every directed
    edge must occur exactly once, and its reverse exactly once (a closed, oriented
    2-manifold, where each edge joins two faces that traverse it in opposite directions)."""
    if faces.size == 0:
        raise MeshError("`faces` is empty; a closed mesh has at least 4 triangles")
    if faces.min() < 0 or faces.max() >= n_vertices:
        raise MeshError(f"`faces` must index the {n_vertices} vertices (0 to {n_vertices - 1}), "
                        f"got indices from {faces.min()} to {faces.max()}")
    if np.any((faces[:, 0] == faces[:, 1]) | (faces[:, 1] == faces[:, 2])
              | (faces[:, 0] == faces[:, 2])):
        raise MeshError("`faces` has a triangle with a repeated vertex")
    tail = faces.reshape(-1)
    head = np.roll(faces, -1, axis=1).reshape(-1)
    key = tail.astype(np.int64) * n_vertices + head
    reverse = head.astype(np.int64) * n_vertices + tail
    unique, counts = np.unique(key, return_counts=True)
    if np.any(counts > 1):
        k = int(unique[np.argmax(counts > 1)])
        raise MeshError(
            f"`faces` make a mesh that is non-manifold or inconsistently oriented: the edge {k // n_vertices}"
            f" -> {k % n_vertices} is traversed in the same direction by "
            f"{int(counts.max())} faces (each edge must join two faces, traversed once each "
            "way)")
    missing = ~np.isin(reverse, unique)
    if np.any(missing):
        i = int(np.argmax(missing))
        raise MeshError(
            f"`faces` make a mesh that is open (or non-manifold): the edge {tail[i]} -> {head[i]} has no "
            "face on its other side; give a closed, watertight mesh")


def mesh_properties(vertices: np.ndarray, faces: np.ndarray) -> tuple[float, np.ndarray,
                                                                         np.ndarray]:
    """Volume, centroid and the tensor about the centroid of unit density, of a closed,
    consistently oriented triangle mesh (faces counter-clockwise seen from outside), exact
    for polyhedra up to round-off.

    The integrals are taken about the mean vertex (so that a mesh far from the origin loses
    no digits) as the sum of the signed tetrahedra (mean, a, b, c) over the faces, and moved
    to the centroid by the parallel-axis theorem.

    Raises
    ------
    MeshError
        An open, non-manifold or inconsistently oriented mesh, or one wound inward
        (negative volume) or with no volume.
    """
    check_mesh(faces, len(vertices))
    origin = vertices.mean(axis=0)
    p = vertices - origin
    a, b, c = p[faces[:, 0]], p[faces[:, 1]], p[faces[:, 2]]
    six_v = np.einsum("ij,ij->i", a, np.cross(b, c))  # 6 × signed volume of each tetrahedron
    volume = float(six_v.sum() / 6.0)
    scale = float(np.abs(six_v).sum() / 6.0)
    if not volume > 1e-12 * scale or not volume > 0:
        if volume < 0:
            raise MeshError(
                f"`faces` are wound inward (signed volume {volume:.6g} < 0): its faces must "
                "run counter-clockwise seen from outside; reverse each face's vertex order")
        raise MeshError(f"`faces` enclose no volume (signed volume {volume:.3g})")
    s = a + b + c
    centroid_rel = (six_v[:, None] * s).sum(axis=0) / (24.0 * volume)
    # ∫ r rᵀ dV over each tetrahedron: V/20 (a aᵀ + b bᵀ + c cᵀ + s sᵀ)
    second = np.einsum("i,ij,ik->jk", six_v / 120.0, a, a)
    second += np.einsum("i,ij,ik->jk", six_v / 120.0, b, b)
    second += np.einsum("i,ij,ik->jk", six_v / 120.0, c, c)
    second += np.einsum("i,ij,ik->jk", six_v / 120.0, s, s)
    second = 0.5 * (second + second.T)
    # about the centroid: C_G = C_O − V g gᵀ
    second_g = second - volume * np.outer(centroid_rel, centroid_rel)
    tensor = np.trace(second_g) * np.eye(3) - second_g
    return volume, origin + centroid_rel, tensor


def quaternion_of(rotation: np.ndarray) -> np.ndarray:
    """The unit quaternion (scalar first, ``Q ≥ 0``) of a rotation matrix, by Shepperd's
    method (the largest of ``4Q², 4U², 4V², 4W²`` is taken first, for accuracy)."""
    m = np.asarray(rotation, dtype=np.float64)
    t = np.trace(m)
    candidates = [t, m[0, 0], m[1, 1], m[2, 2]]
    k = int(np.argmax(candidates))
    if k == 0:
        r = np.sqrt(1.0 + t)
        q = [r, (m[2, 1] - m[1, 2]) / r, (m[0, 2] - m[2, 0]) / r, (m[1, 0] - m[0, 1]) / r]
    elif k == 1:
        r = np.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        q = [(m[2, 1] - m[1, 2]) / r, r, (m[0, 1] + m[1, 0]) / r, (m[0, 2] + m[2, 0]) / r]
    elif k == 2:
        r = np.sqrt(1.0 - m[0, 0] + m[1, 1] - m[2, 2])
        q = [(m[0, 2] - m[2, 0]) / r, (m[0, 1] + m[1, 0]) / r, r, (m[1, 2] + m[2, 1]) / r]
    else:
        r = np.sqrt(1.0 - m[0, 0] - m[1, 1] + m[2, 2])
        q = [(m[1, 0] - m[0, 1]) / r, (m[0, 2] + m[2, 0]) / r, (m[1, 2] + m[2, 1]) / r, r]
    out = np.array(q) / 2.0
    out /= np.linalg.norm(out)
    return out if out[0] >= 0 else -out


def quaternion_product(p: np.ndarray, q: Any) -> np.ndarray:
    """``p ⊗ q`` for quaternions of shape (..., 4) (scalar first), written out component by
    component so that every row is computed with the same operations (no BLAS)."""
    p0, p1, p2, p3 = (p[..., k] for k in range(4))
    q0, q1, q2, q3 = (np.asarray(q)[..., k] for k in range(4))
    return np.stack([
        p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3,
        p0 * q1 + p1 * q0 + p2 * q3 - p3 * q2,
        p0 * q2 - p1 * q3 + p2 * q0 + p3 * q1,
        p0 * q3 + p1 * q2 - p2 * q1 + p3 * q0,
    ], axis=-1)


def apply(matrix: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``matrix · v`` for vectors of shape (..., 3), component by component (no BLAS: every
    row gets the same operations, so batches equal single runs bit for bit)."""
    return np.stack([matrix[k, 0] * v[..., 0] + matrix[k, 1] * v[..., 1]
                     + matrix[k, 2] * v[..., 2] for k in range(3)], axis=-1)
