"""The inertia ellipsoid: a closed, single-cover quad mesh on the surface it claims, in both
conventions."""

from collections import Counter

import numpy as np
import pytest

import dzhanibekov as dz


def edges_of(quads):
    """Directed edges of the cells, skipping the collapsed pole-to-pole ones."""
    return [(int(q[k]), int(q[(k + 1) % 4])) for q in quads for k in range(4)
            if q[k] != q[(k + 1) % 4]]


@pytest.mark.parametrize("n_around, n_along", [(3, 2), (4, 3), (24, 12), (7, 9)])
def test_the_mesh_is_closed_oriented_and_covers_once(n_around, n_along):
    vertices, quads = dz.ellipsoid_mesh((7.2, 5.2, 6.45), n_around, n_along)
    assert vertices.shape == (n_around * (n_along - 1) + 2, 3)
    assert quads.shape == (n_around * n_along, 4)
    directed = edges_of(quads)
    counts = Counter(frozenset(e) for e in directed)
    # every edge is shared by exactly two cells, traversed in opposite directions
    assert set(counts.values()) == {2}
    assert len(set(directed)) == len(directed)
    v, e, f = len(vertices), len(counts), len(quads)
    assert v - e + f == 2  # Euler characteristic of the sphere
    # every vertex is used, and no two vertices coincide (no doubled seam or pole)
    assert set(quads.ravel()) == set(range(v))
    distances = np.linalg.norm(vertices[:, None] - vertices[None], axis=-1)
    assert distances[~np.eye(v, dtype=bool)].min() > 1e-6
    # degenerate cells only at the poles: the 2·n_around cells that touch a pole, each with
    # exactly one repeated corner, the pole
    poles = {0, v - 1}
    degenerate = [q for q in quads if len(set(q)) < 4]
    assert len(degenerate) == 2 * n_around
    for q in degenerate:
        repeated = [k for k, c in Counter(q.tolist()).items() if c > 1]
        assert len(set(q)) == 3 and repeated[0] in poles
    assert all(len(set(q)) == 4 for q in quads if not poles & set(q.tolist()))


def test_the_points_lie_on_the_ellipsoid_and_the_rings_span_a_full_turn():
    a, b, c = 7.2, 5.2, 6.45
    n_around, n_along = 24, 12
    vertices, _ = dz.ellipsoid_mesh((a, b, c), n_around, n_along)
    np.testing.assert_allclose(((vertices / (a, b, c)) ** 2).sum(axis=1), 1.0, rtol=1e-14)
    np.testing.assert_array_equal(vertices[[0, -1]], [[0, 0, c], [0, 0, -c]])
    rings = vertices[1:-1].reshape(n_along - 1, n_around, 3)
    for ring in rings:
        phi = np.unwrap(np.arctan2(ring[:, 1] / b, ring[:, 0] / a))
        np.testing.assert_allclose(np.diff(phi), 2 * np.pi / n_around, rtol=1e-12)
    polar = np.arccos(rings[:, 0, 2] / c)
    np.testing.assert_allclose(polar, np.pi * np.arange(1, n_along) / n_along, rtol=1e-12)


def signed_volume(vertices, quads):
    """The divergence theorem over the cells split into triangles: positive when the cells
    are oriented outward."""
    p = vertices[quads]
    total = 0.0
    for i, j, k in ((0, 1, 2), (0, 2, 3)):
        total += np.einsum("ij,ij->i", p[:, i], np.cross(p[:, j], p[:, k])).sum()
    return total / 6.0


def test_the_cells_face_outward_and_enclose_the_ellipsoids_volume():
    a, b, c = 3.0, 2.0, 1.0
    exact = 4.0 / 3.0 * np.pi * a * b * c
    errors = []
    for n in (8, 16, 32, 64):
        vertices, quads = dz.ellipsoid_mesh((a, b, c), 2 * n, n)
        volume = signed_volume(vertices, quads)
        assert 0 < volume < exact  # an inscribed polyhedron, oriented outward
        errors.append(exact - volume)
    # second order: halving the cells quarters the error
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    np.testing.assert_allclose(ratios, 4.0, rtol=0.05)


def test_the_two_conventions_are_what_they_are_named():
    inertia = np.array(dz.PAPER_INERTIA)
    gyration = dz.ellipsoid_semi_axes(inertia, "gyration")
    np.testing.assert_allclose(gyration**2, inertia, rtol=1e-15)  # radii of gyration, m = 1
    poinsot = dz.ellipsoid_semi_axes(dz.Body(inertia), "poinsot")
    # the classical ellipsoid x·I x = const: the same constant at every vertex
    vertices, _ = dz.ellipsoid_mesh(poinsot, 24, 12)
    level = np.einsum("ij,j,ij->i", vertices, inertia, vertices)
    np.testing.assert_allclose(level, level[0], rtol=1e-13)
    # drawn at the gyration ellipsoid's volume; longest where gyration's is shortest
    assert np.prod(poinsot) == pytest.approx(np.prod(gyration), rel=1e-13)
    assert np.argmax(poinsot) == np.argmin(gyration) == np.argmin(inertia)
    with pytest.raises(ValueError, match="`convention` must be one of"):
        dz.ellipsoid_semi_axes(inertia, "classical")


def test_bad_mesh_arguments_are_named():
    with pytest.raises(ValueError, match="`n_around` must be at least 3"):
        dz.ellipsoid_mesh((1, 1, 1), 2, 4)
    with pytest.raises(ValueError, match="`n_along` must be at least 2"):
        dz.ellipsoid_mesh((1, 1, 1), 3, 1)
    with pytest.raises(ValueError, match="`semi_axes` must be three positive"):
        dz.ellipsoid_mesh((1, 0, 1), 3, 2)
    with pytest.raises(TypeError, match="`n_around` must be an integer"):
        dz.ellipsoid_mesh((1, 1, 1), 3.0, 2)
    with pytest.raises(ValueError, match="the ellipsoid mesh needs .* cells"):
        dz.ellipsoid_mesh((1, 1, 1), 1 << 13, 1 << 12)
