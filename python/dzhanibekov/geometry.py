"""Shapes drawn with a body: the paper's 20 × 10 × 15 box, its edges and the signal point;
the inertia ellipsoid, in both conventions, as a closed quad mesh built in the core.

Two ellipsoids go by that name, and they are not the same shape:

- ``gyration`` — semi-axes ``√(Ix/m), √(Iy/m), √(Iz/m)``, the radii of gyration, in units of
  length whatever the mass (a body given by its moments alone counts as ``m = 1``: the
  paper's ``√Ix, √Iy, √Iz``; erratum 3). Longest along the axis of the *largest* moment.
- ``poinsot`` — the classical inertia ellipsoid ``x · I x = const`` of Poinsot's construction,
  semi-axes ∝ ``1/√I``: longest along the axis of the *smallest* moment. Its size is a free
  constant; it is drawn with ``const = (Ix Iy Iz)^(2/3)``, which gives semi-axes
  ``(Ix Iy Iz)^(1/3) / √I`` and the same volume as the gyration ellipsoid, so the two are
  drawn at comparable sizes (with ``I/m`` for ``I`` where the body has a mass).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _core
from ._args import as_array, as_float, as_int
from .body import Body, as_body

__all__ = ["BOX_SIZE", "box_vertices", "box_edges", "SIGNAL_POINT", "CONVENTIONS", "ellipsoid_semi_axes",
           "ellipsoid_mesh"]

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



CONVENTIONS = ("gyration", "poinsot")
"""The two conventions, see the module's docs."""


def ellipsoid_semi_axes(body: Body | Any, convention: str = "gyration") -> np.ndarray:
    """The semi-axes of `body`'s inertia ellipsoid, along its principal axes in the order of
    :attr:`Body.inertia` (the columns of :attr:`Body.principal_axes`).

    Parameters
    ----------
    body : Body or array_like, shape (3,)
        The body (its mass, if it has one, divides the moments) or its principal moments
        (taken with a unit mass: the paper's convention).
    convention : {"gyration", "poinsot"}
        ``gyration``: ``√(I/m)``, the radii of gyration (``√I`` for the paper's moments,
        ``m = 1``); ``poinsot``: ``(Ix Iy Iz)^(1/3) / √I`` of the same ``I/m``, the
        classical ellipsoid at the gyration one's volume.

    Returns
    -------
    ndarray, shape (3,)
        In the body's units of length (mm for the wing nut's g and g·mm²).

    Examples
    --------
    >>> ellipsoid_semi_axes((4.0, 9.0, 9.0))
    array([2., 3., 3.])
    >>> ellipsoid_semi_axes((4.0, 9.0, 9.0), "poinsot").round(3)  # longest along the smallest I
    array([3.434, 2.289, 2.289])

    A ball of radius r has the radius of gyration ``r √(2/5)`` whatever its mass:

    >>> ellipsoid_semi_axes(Body.sphere(2.0, mass=7.0)).round(6)
    array([1.264911, 1.264911, 1.264911])
    """
    if not (isinstance(convention, str) and convention in CONVENTIONS):
        raise ValueError(f"`convention` must be one of {CONVENTIONS}, got {convention!r}")
    solid = as_body(body)
    inertia = np.array(solid.inertia)
    if solid.mass is not None:
        inertia = inertia / solid.mass
    semi_axes: np.ndarray = np.sqrt(inertia)
    if convention == "poinsot":
        # (Ix Iy Iz)^(1/3) / √I, from ratios to the largest moment: the product of the
        # moments themselves over- or underflows long before the semi-axes do
        top = inertia.max()
        semi_axes = np.sqrt(top) * np.prod(np.cbrt(inertia / top)) / np.sqrt(inertia / top)
    return semi_axes


def ellipsoid_mesh(semi_axes: Any, n_around: int = 24, n_along: int = 12) -> tuple[np.ndarray, np.ndarray]:
    """The ellipsoid with `semi_axes` along body x, y, z as a closed quad mesh (Rust core).

    The azimuth φ about z runs over a full turn in `n_around` cells and the polar angle θ
    over a half turn in `n_along` cells, so the surface is covered once: no seam is doubled
    and each pole is a single vertex, shared by the `n_around` cells that touch it (quads
    with two corners on the pole). Every edge joins exactly two cells; V − E + F = 2.

    Parameters
    ----------
    semi_axes : array_like, shape (3,)
        Positive semi-axes ``(a, b, c)``, e.g. from :func:`ellipsoid_semi_axes`.
    n_around, n_along : int
        The paper's ``eN`` (at least 3) and ``eM`` (at least 2).

    Returns
    -------
    vertices : ndarray, shape (n_around * (n_along - 1) + 2, 3)
        Body-frame points: the north pole ``(0, 0, c)``, the rings of latitude from north
        to south (``n_around`` points each, from φ = 0), the south pole.
    quads : ndarray of uint32, shape (n_around * n_along, 4)
        Vertex indices of each cell, counter-clockwise seen from outside.

    Raises
    ------
    ValueError
        Semi-axes not positive and finite, too few cells, or more than 2²⁴ cells.
    """
    a, b, c = as_array("semi_axes", semi_axes, "(3,)", last=3, ndim=(1,)).tolist()
    return _core.ellipsoid_mesh(
        (a, b, c), as_int("n_around", n_around, minimum=3), as_int("n_along", n_along, minimum=2)
    )
