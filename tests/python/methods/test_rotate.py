"""Trig-free rotation: against a direct NumPy evaluation of the paper's M(q), orthogonality,
and the signal point's path."""

import numpy as np
import pytest
from reference import quaternion_matrix

import dzhanibekov as dz


def unit(q):
    q = np.asarray(q, float)
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def test_matches_the_papers_matrix_evaluated_in_numpy(rng):
    q = unit(rng.normal(size=(50, 4)))
    points = rng.normal(size=(30, 3)) * 10
    expected = np.einsum("nij,pj->npi", quaternion_matrix(q), points)
    np.testing.assert_allclose(dz.rotate(q, points), expected, rtol=0, atol=1e-13)


def test_a_large_rotation_on_all_cores_matches_numpy(rng):
    q = unit(rng.normal(size=(40, 4)))
    points = rng.normal(size=(20_000, 3))
    expected = np.einsum("nij,pj->npi", quaternion_matrix(q), points)
    np.testing.assert_allclose(dz.rotate(q, points), expected, rtol=0, atol=1e-13)


def test_non_unit_quaternions_still_rotate_rigidly(rng):
    q = rng.normal(size=(20, 4)) * rng.uniform(1e-3, 1e3, size=(20, 1))
    box = dz.box_vertices()
    world = dz.rotate(q, box)
    # distances between vertices are kept: the matrix is orthogonal whatever |q| is
    d_body = np.linalg.norm(box[:, None] - box[None], axis=-1)
    d_world = np.linalg.norm(world[:, :, None] - world[:, None], axis=-1)
    np.testing.assert_allclose(d_world, np.broadcast_to(d_body, d_world.shape), atol=1e-12)
    # and proper: a right-handed frame stays right-handed
    e = dz.rotate(q, np.eye(3))
    np.testing.assert_allclose(np.einsum("ni,ni->n", np.cross(e[:, 0], e[:, 1]), e[:, 2]), 1.0, atol=1e-13)
    # a scaled quaternion rotates like its unit version
    np.testing.assert_allclose(world, dz.rotate(unit(q), box), atol=1e-12)


def test_shapes_follow_the_inputs():
    assert dz.rotate(np.ones((5, 4)), np.ones((7, 3))).shape == (5, 7, 3)
    assert dz.rotate(np.ones(4), np.ones((7, 3))).shape == (7, 3)
    assert dz.rotate(np.ones((5, 4)), np.ones(3)).shape == (5, 3)
    assert dz.rotate(np.ones(4), np.ones(3)).shape == (3,)
    np.testing.assert_allclose(dz.rotate((0, 0, 0, 1), (1.0, 2.0, 3.0)), (-1.0, -2.0, 3.0), atol=1e-15)


def test_out_is_written_in_place(rng):
    q, points = unit(rng.normal(size=(4, 4))), rng.normal(size=(6, 3))
    out = np.empty((4, 6, 3))
    result = dz.rotate(q, points, out=out)
    assert result is out
    np.testing.assert_array_equal(out, dz.rotate(q, points))
    with pytest.raises(ValueError, match="`out` must have shape \\(4, 6, 3\\)"):
        dz.rotate(q, points, out=np.empty((4, 6)))
    with pytest.raises(TypeError, match="`out` must be a float64"):
        dz.rotate(q, points, out=np.empty((4, 6, 3), dtype=np.float32))


def test_the_signal_point_flips_over_on_fig3a():
    traj = dz.SCENES["fig3a"].run()
    path = dz.rotate(traj.q, dz.SIGNAL_POINT)
    np.testing.assert_allclose(np.linalg.norm(path, axis=1), 13.0, rtol=1e-12)
    np.testing.assert_allclose(path[0], (0.0, 0.0, 13.0), atol=1e-15)
    # the angular momentum points along world z at t = 0 (almost): the signal point starts
    # above, goes below after the first flip and comes back after the second
    t1, t2 = traj.flip_times[:2]
    half = (t2 - t1) / 2
    assert path[traj.t < t1 - 5, 2].min() > 0
    assert path[np.abs(traj.t - (t1 + half)) < half - 5, 2].max() < 0
    assert path[np.abs(traj.t - (t2 + half)) < half - 5, 2].min() > 0
