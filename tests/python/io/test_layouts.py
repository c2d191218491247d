"""Odd but valid array layouts are copied like any other (unaligned C-contiguous buffers
included), and an `out=` that overlaps the inputs of `rotate` is refused."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import dzhanibekov as dz


def unaligned(a: np.ndarray) -> np.ndarray:
    """A C-contiguous float64 copy of `a` one byte off alignment (as `np.frombuffer` with an
    odd offset gives)."""
    raw = np.zeros(a.nbytes + 1, dtype=np.uint8)
    view = np.frombuffer(raw.data, dtype=np.float64, count=a.size, offset=1).reshape(a.shape)
    view[...] = a
    assert view.flags.c_contiguous and not view.flags.aligned
    return view


def test_unaligned_inputs_are_copied_and_give_the_right_rotation(rng):
    q = rng.normal(size=(5, 4))
    points = rng.normal(size=(7, 3))
    got = dz.rotate(unaligned(q), unaligned(points))
    # scipy's rotation of the normalised quaternions (scalar last there)
    unit = q / np.linalg.norm(q, axis=1, keepdims=True)
    expected = np.stack([Rotation.from_quat(u[[1, 2, 3, 0]]).apply(points) for u in unit])
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-14)


def test_unaligned_starts_simulate_like_aligned_ones():
    body = dz.Body(dz.PAPER_INERTIA)
    omega = np.array([0.01, 0.01, 1.0])
    q0 = np.array([1.0, 0.0, 0.0, 0.0])
    a = dz.simulate(body, unaligned(omega), unaligned(q0), t_end=5.0, frames=11)
    b = dz.simulate(body, omega, q0, t_end=5.0, frames=11)
    np.testing.assert_array_equal(a.omega, b.omega)
    batch = dz.simulate(body, unaligned(np.tile(omega, (3, 1))), t_end=5.0, frames=11)
    np.testing.assert_array_equal(batch.omega[2], b.omega)
    assert np.all(np.isfinite(dz.flip_period(body, unaligned(omega))))


def test_an_unaligned_out_is_refused_clearly():
    q = np.array([[1.0, 0.0, 0.0, 0.0]])
    points = np.ones((2, 3))
    with pytest.raises(ValueError, match="`out` must be C-contiguous, aligned and writeable"):
        dz.rotate(q, points, out=unaligned(np.zeros((1, 2, 3))))


def test_out_overlapping_the_inputs_is_refused():
    buffer = np.zeros(12 + 6)
    q = buffer[:4].reshape(1, 4)
    q[0] = (1.0, 0.0, 0.0, 1.0)
    points = buffer[4:10].reshape(2, 3)
    points[...] = 1.0
    out = buffer[:6].reshape(1, 2, 3)   # overlaps q and the first point
    with pytest.raises(ValueError, match="`out` must not share memory with `q` or `points`"):
        dz.rotate(q, points, out=out)
    separate = np.empty((1, 2, 3))
    assert dz.rotate(q, points, out=separate) is separate
    np.testing.assert_allclose(separate[0, 0], [-1.0, 1.0, 1.0], atol=1e-15)
