"""A damper beside parts that do work: no false divergence (hardening round 4).

The fixed-step watchdog stopped a run of a damped body whose energy grew ("a damped body only
loses energy"), which is true only when nothing else changes the energy. With a torque, the
gravity gradient or a wheel spun down beside the damper, RK4 stopped at t = 0.05 whatever `dt`
(1e-2 and 1e-3 alike: a step size cannot cause it). Since issue 29 (parts that describe
themselves) the watchdog reads what the parts declare: it watches only a system whose parts
only dissipate, and these run.

Each run is checked against what the motion must do whatever its method: a world-fixed torque
changes the angular momentum in space by exactly τ t (the damper's and the body's internal
torques cancel); a wheel spun down inside the body changes nothing outside it, so the total
angular momentum in space is kept; the gravity gradient's run is checked against dop853 at a
tight tolerance, which no watchdog stops."""

from __future__ import annotations

import numpy as np
import pytest

import dzhanibekov as dz

BODY = dz.Body((1.0, 2.0, 3.0))
DAMPER = dz.Damper(0.1, 0.05)


@pytest.mark.parametrize("dt", [1e-2, 1e-3])
def test_a_damper_and_a_world_fixed_torque(dt):
    tau = np.array([0.0, 0.0, 0.5])
    system = dz.System(BODY, parts=[DAMPER], torques=[dz.ConstantTorque(tau, "world")])
    traj = dz.simulate(system, (0.01, 0.01, 1.0), t_end=10.0, method="rk4", dt=dt)
    momentum = traj.momentum_world
    assert np.allclose(momentum[-1] - momentum[0], tau * 10.0, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("dt", [1e-2, 1e-3])
def test_a_damper_and_a_wheel_spun_down(dt):
    spin_down = dz.Wheel((0, 0, 1), ([0.0, 5.0], [2.0, 0.0]))
    system = dz.System(BODY, parts=[DAMPER, spin_down])
    traj = dz.simulate(system, (0.01, 0.01, 1.0), t_end=10.0, method="rk4", dt=dt)
    momentum = traj.momentum_world
    assert np.abs(momentum - momentum[0]).max() < 1e-9 * np.linalg.norm(momentum[0])


def test_a_damper_in_the_gravity_gradient():
    system = dz.System(BODY, parts=[DAMPER], torques=[dz.GravityGradient(0.5)])
    start = ((0.01, 0.01, 0.01), (0.9, 0.3, 0.2, 0.1))
    rk4 = dz.simulate(system, *start, t_end=10.0, frames=11, method="rk4", dt=1e-3)
    reference = dz.simulate(system, *start, t_end=10.0, frames=11, method="dop853",
                            rtol=1e-12, atol=1e-14)
    assert np.allclose(rk4.omega, reference.omega, rtol=0, atol=1e-9)
