"""scipy rotations in and out: `q0` as a `Rotation`, `traj.rotation`, `traj.euler`.

The package's quaternions are scalar first and world-from-body; scipy's are scalar last.
Every check goes through what scipy itself does with a rotation (its matrix applied to a
vector, its Euler angles), never through the package's own conversion alone.
"""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import dzhanibekov as dz

OMEGA = (0.3, -0.2, 0.9)


def _same_up_to_sign(a: np.ndarray, b: np.ndarray) -> bool:
    a, b = np.atleast_2d(a), np.atleast_2d(b)
    sign = np.sign(np.sum(a * b, axis=1, keepdims=True))
    return bool(np.allclose(a, sign * b, rtol=0, atol=1e-15))


def test_q0_rotation_gives_the_same_run_as_its_scalar_first_quaternion(rng):
    r = Rotation.random(random_state=1)
    xyzw = r.as_quat()
    wxyz = (xyzw[3], xyzw[0], xyzw[1], xyzw[2])  # scipy's scalar-last order, by hand
    a = dz.simulate(dz.PAPER_INERTIA, OMEGA, q0=r, t_end=5.0, frames=11)
    b = dz.simulate(dz.PAPER_INERTIA, OMEGA, q0=wxyz, t_end=5.0, frames=11)
    assert np.array_equal(a.q, b.q) and np.array_equal(a.omega, b.omega)


def test_the_start_is_the_rotation_given_up_to_sign():
    r = Rotation.from_rotvec([0.4, -1.1, 2.0])
    traj = dz.simulate(dz.PAPER_INERTIA, OMEGA, q0=r, t_end=1.0, frames=2)
    # scipy applies r to a body vector; the package's attitude must do the same
    body_vectors = np.eye(3) * 13.0
    assert np.allclose(dz.rotate(traj.q[0], body_vectors), r.apply(body_vectors), atol=1e-13)
    assert _same_up_to_sign(traj.rotation[0].as_quat(), r.as_quat())


def test_a_stack_of_rotations_is_a_batch_of_runs():
    stack = Rotation.random(5, random_state=7)
    batch = dz.simulate(dz.PAPER_INERTIA, OMEGA, q0=stack, t_end=2.0, frames=3)
    assert isinstance(batch, dz.Batch) and len(batch) == 5
    for i in range(5):
        assert np.allclose(dz.rotate(batch.q[i, 0], np.eye(3)), stack[i].apply(np.eye(3)),
                           atol=1e-14)


def test_sweep_and_summarize_take_rotations():
    stack = Rotation.random(3, random_state=3)
    s = dz.sweep(dz.PAPER_INERTIA, OMEGA, q0=stack, t_end=2.0)
    assert s.shape == (3,)
    assert _same_up_to_sign(s.q0, np.roll(stack.as_quat(), 1, axis=-1))
    single = dz.summarize(dz.PAPER_INERTIA, OMEGA, q0=stack[0], t_end=2.0)
    assert single.n_steps == s.n_steps[0]


def test_traj_rotation_applies_like_rotate():
    traj = dz.simulate(dz.PAPER_INERTIA, OMEGA, t_end=20.0, frames=41, method="exact")
    points = np.array([[0.0, 0.0, 13.0], [10.0, 5.0, 7.5]])
    world = dz.rotate(traj.q, points)                       # (frames, 2, 3)
    rot = traj.rotation
    assert len(rot) == 41
    for k in range(2):
        assert np.allclose(rot.apply(points[k]), world[:, k], atol=1e-12)


def test_round_trip_q_to_rotation_and_back_up_to_sign(rng):
    q = rng.normal(size=(200, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    traj = dz.simulate(dz.PAPER_INERTIA, OMEGA, q0=q[0], t_end=1.0, frames=2)
    # a Rotation built from the package's q, and read back as q0 of a new run
    again = dz.simulate(dz.PAPER_INERTIA, OMEGA, q0=traj.rotation[0], t_end=1.0, frames=2)
    assert _same_up_to_sign(again.q[0], traj.q[0])
    batch = dz.simulate(dz.PAPER_INERTIA, OMEGA, q0=q, t_end=1.0, frames=2)
    back = dz.simulate(dz.PAPER_INERTIA, OMEGA, q0=Rotation.from_quat(np.roll(q, -1, 1)),
                       t_end=1.0, frames=2)
    assert _same_up_to_sign(back.q[:, 0], batch.q[:, 0])


def test_euler_angles_of_a_spin_about_z_are_the_textbook_angle():
    # a steady spin about a principal axis: the attitude turns by ω t about it
    w = 0.1
    t_end = 5 * np.pi
    traj = dz.simulate(dz.PAPER_INERTIA, (0.0, 0.0, w), t_end=t_end, frames=6, method="exact")
    yaw = traj.euler("ZYX")[:, 0]
    expected = np.angle(np.exp(1j * w * traj.t))  # wrapped to (-π, π]
    assert np.allclose(yaw, expected, atol=1e-12)
    assert np.allclose(traj.euler("ZYX")[:, 1:], 0.0, atol=1e-12)
    assert np.allclose(traj.euler("zyx", degrees=True)[-1, 0], 90.0, atol=1e-10)


def test_scalar_last_four_vectors_are_not_silently_taken():
    """The trap the issue names: scipy's `as_quat()` (scalar last) handed as `q0` is a
    different rotation. The Rotation object is the unambiguous path."""
    r = Rotation.from_euler("z", 90, degrees=True)
    wrong = dz.simulate(dz.PAPER_INERTIA, OMEGA, q0=r.as_quat(), t_end=1.0, frames=2)
    right = dz.simulate(dz.PAPER_INERTIA, OMEGA, q0=r, t_end=1.0, frames=2)
    assert not _same_up_to_sign(wrong.q[0], right.q[0])
    assert np.allclose(right.rotation[0].as_matrix(), r.as_matrix(), atol=1e-15)


def test_a_zero_rotation_quaternion_cannot_arise():
    # scipy refuses a zero quaternion itself; the package refuses a zero q0 by name
    with pytest.raises(ValueError, match="q0"):
        dz.simulate(dz.PAPER_INERTIA, OMEGA, q0=(0, 0, 0, 0))
