"""Angles from the orbiting frame (issue 29's orbit asks), against scipy's rotations: the
angle of the rotation LVLH-from-body and the angle of the body's z axis from nadir."""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import dzhanibekov as dz

N = 1.0
SAT = dz.System(dz.Body((2.0, 3.0, 1.0)), torques=[dz.GravityGradient(N)])


def _start(rotation: Rotation) -> tuple[np.ndarray, np.ndarray]:
    x, y, z, w = rotation.as_quat()
    return dz.lvlh_start(N, (w, x, y, z))


@pytest.mark.parametrize("seed", range(6))
def test_the_angles_at_the_start_are_scipys(seed):
    rng = np.random.default_rng(seed)
    turn = Rotation.from_rotvec(rng.normal(size=3) * 0.9)
    traj = dz.simulate(SAT, *_start(turn), t_end=0.5, frames=2)
    assert dz.lvlh_angles(traj)[0] == pytest.approx(turn.magnitude(), abs=1e-12)
    z = turn.apply([0.0, 0.0, 1.0])   # the body's z in LVLH axes; nadir is LVLH z
    assert dz.nadir_angles(traj)[0] == pytest.approx(math.acos(z[2]), abs=1e-12)


def test_a_yaw_turns_from_lvlh_but_keeps_nadir_and_a_roll_past_a_right_angle_leaves_it():
    yaw = dz.simulate(SAT, *_start(Rotation.from_euler("z", 2.5)), t_end=0.5, frames=2)
    assert dz.lvlh_angles(yaw)[0] == pytest.approx(2.5, abs=1e-12)
    assert dz.nadir_angles(yaw)[0] < 1e-12
    roll = dz.simulate(SAT, *_start(Rotation.from_euler("x", 2.0)), t_end=0.5, frames=2)
    assert dz.nadir_angles(roll)[0] == pytest.approx(2.0, abs=1e-12) and 2.0 > math.pi / 2


def test_a_body_at_rest_in_lvlh_stays_at_zero_and_batches_give_one_row_a_run():
    start = dz.lvlh_start(N)
    traj = dz.simulate(SAT, *start, t_end=20.0, frames=41, method="dop853", rtol=1e-11)
    assert np.abs(dz.lvlh_angles(traj)).max() < 1e-8
    batch = dz.simulate(SAT, np.stack([start[0]] * 3), np.stack([start[1]] * 3), t_end=2.0,
                        frames=5)
    assert dz.lvlh_angles(batch, N).shape == (3, 5) == dz.nadir_angles(batch, N).shape


def test_a_system_without_the_gravity_gradient_needs_the_orbit_rate_by_name():
    traj = dz.simulate(dz.Body((1.0, 2.0, 3.0)), (0.0, 0.0, 1.0), t_end=1.0, frames=3)
    with pytest.raises(ValueError, match="`orbit_rate`"):
        dz.lvlh_angles(traj)
    assert dz.nadir_angles(traj, orbit_rate=0.5).shape == (3,)
