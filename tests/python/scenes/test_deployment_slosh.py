"""The scene ``deployment-slosh`` (issue 31): the scene ``deployment`` with a slosh tank,
carried by the deploying body's mass. Stable while stowed, it tumbles once deployed while the
tank takes energy at constant angular momentum, and ends in a flat spin about the deployed
major axis y; without the tank's damping it tumbles to the end."""

from __future__ import annotations

import numpy as np
import pytest

import dzhanibekov as dz

SCENE = dz.SCENES["deployment-slosh"]


def share_on_y(traj: dz.Trajectory) -> np.ndarray:
    h = traj.momentum_body
    return np.abs(h[:, 1]) / np.linalg.norm(h, axis=1)


@pytest.fixture(scope="module")
def run():
    return SCENE.run()  # 0.1 s of CPU


def test_it_is_the_deployment_scene_with_a_tank():
    plain = dz.SCENES["deployment"]
    d = SCENE.deployment
    assert d.mass == 1.0
    np.testing.assert_array_equal(d.times, plain.deployment.times)
    np.testing.assert_array_equal(d.tensors, plain.deployment.tensors)
    assert SCENE.omega0 == plain.omega0 and SCENE.q0 == plain.q0
    (tank,) = SCENE.system.parts
    assert isinstance(tank, dz.Slosh) and tank.mass == 0.05 * d.mass


def test_it_tumbles_once_deployed_and_ends_flat(run):
    flips = run.flip_times
    assert flips.min() > 110.0 and len(flips) >= 5  # none while stowed: z is its major axis
    share = share_on_y(run)
    tumbling = run.t > 115.0
    assert share[tumbling].min() < 0.3  # L passes far from y while it tumbles (0.20)
    last = flips.max()
    assert last < 0.3 * run.t_end and (share[run.t > last + 200.0] > 0.9).all()
    assert share[-1] > 0.99
    # L fixed in space; the deployment's work raises the energy by half (z's moment 3 → 2 at
    # constant |L|: 1.48 measured, the tank's share of the moments aside), the tank takes it
    # back down to a spin about y (3 again: 1.02 of the start's, the last nutation aside)
    assert run.drift.momentum_world < 1e-8
    deployed = run.energy[np.searchsorted(run.t, 115.0)]
    assert deployed == pytest.approx(1.5 * run.energy[0], rel=0.02)
    assert run.energy[-1] == pytest.approx(run.energy[0], rel=0.03)


def test_without_damping_it_tumbles_to_the_end():
    tank = SCENE.system.parts[0]
    free = dz.Slosh(tank.mass, tank.pivot, tank.length, 0.0, tank.direction0)
    traj = dz.simulate(dz.System(SCENE.deployment, parts=[free]), SCENE.omega0,
                       t_end=SCENE.t_end, frames=901, dt=SCENE.dt)
    assert traj.flip_times.max() > 0.9 * SCENE.t_end
    after = traj.t > 115.0
    # no sink: after the deployment the energy stays (to RK4's error at this step)
    e = traj.energy[after]
    assert np.ptp(e) < 1e-6 * e[0]


def test_a_deployment_in_a_scene_carries_only_parts_whose_mass_moves():
    text = SCENE.to_toml()
    assert "mass = 1.0" in text and dz.Scene.from_toml(text, "x").deployment.mass == 1.0
    damper = text + '\n[[parts]]\nkind = "damper"\ninertia = 0.05\ndamping = 0.02\n'
    with pytest.raises(dz.SceneError, match=r"parts\[1\].*cannot be combined with a \[deployment\]"):
        dz.Scene.from_toml(damper, "x")
    torque = text + '\n[[torques]]\nkind = "constant_torque"\nvector = [0.0, 0.0, 0.01]\n'
    with pytest.raises(dz.SceneError, match=r"torques\[0\].*cannot be combined"):
        dz.Scene.from_toml(torque, "x")
    with pytest.raises(dz.SceneError, match=r"deployment.mass"):
        dz.Scene.from_toml(text.replace("mass = 1.0", "mass = -1.0", 1), "x")
