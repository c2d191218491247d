"""Knots at the edges of float64, and tables whose size is only apparent (hardening round 4).

A table's law between knots `t0 < t1` takes `(t − t0) / (t1 − t0)`: with knots at ±1.7e308 the
width overflowed to infinity and the place was 0 at every `t` — a TabulatedTorque was silently
the first knot's value (0) for the whole run, a wheel's schedule and a deployment likewise. The
references are the interpolation written out in halves, which cannot overflow."""

from __future__ import annotations

import time
import warnings

import numpy as np
import pytest

import dzhanibekov as dz

WIDE = (-1.7e308, 1.7e308)


def test_a_tabulated_torque_between_knots_at_the_edges_of_float64():
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow along the way
        table = dz.TabulatedTorque(WIDE, [(0.0, 0.0, 0.0), (0.0, 0.0, 2.0)])
        # at t the torque is 2 (t − t0) / (t1 − t0) = (t/2 − t0/2) / (t1/2 − t0/2) · 2 ≈ 1
        assert table.torque_at(0.0)[2] == 1.0
        system = dz.System(dz.Body((1.0, 2.0, 3.0)), torques=[table])
        for method in ("rk4", "dop853"):
            traj = dz.simulate(system, (0.0, 0.0, 0.0), t_end=3.0, method=method, dt=0.1)
            # about the principal axis z from rest: ω_z(3) = τ_z t / I_z = 1 · 3 / 3
            assert traj.omega[-1, 2] == pytest.approx(1.0, rel=1e-12), method


def test_a_wheel_schedule_and_a_deployment_between_knots_at_the_edges_of_float64():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        wheel = dz.Wheel((0, 1, 0), (WIDE, (0.0, 1.0)))
        assert wheel.momentum_at(0.0) == 0.5
        deployment = dz.Deployment(WIDE, [(1.0, 2.0, 3.0), (1.0, 3.0, 2.0)])
        # the smootherstep at the middle is 1/2: halfway between the tensors
        assert np.array_equal(np.diag(deployment.inertia_at(0.0)), (1.0, 2.5, 2.5))
        # the run sees I = diag(1, 2.5, 2.5): a spin about x keeps its rate
        traj = dz.simulate(deployment, (0.3, 0.0, 0.0), t_end=1.0, method="rk4", dt=0.01)
        assert np.allclose(traj.omega[-1], (0.3, 0.0, 0.0), atol=1e-15)
        # a spun-up wheel's momentum of 1/2 about y, seen as L = I ω + h in space
        system = dz.System(dz.Body((1.0, 2.0, 3.0)), parts=[wheel])
        traj = dz.simulate(system, (0.0, 0.0, 0.0), t_end=1.0, method="rk4", dt=0.01)
        assert np.allclose(traj.omega, 0.0)  # the momentum is held, not changed


def test_vectors_broadcast_to_billions_of_rows_are_refused_before_any_copy():
    """Two knot times with vectors broadcast to (2**31, 3): the vectors were copied whole
    (48 GiB) before their count was compared with the times'."""
    vectors = np.broadcast_to([0.0, 0.0, 1.0], (2**31, 3))
    start = time.process_time()
    with pytest.raises(ValueError, match=r"one vector per knot time of `times` \(2\), got "
                                         r"2147483648"):
        dz.TabulatedTorque([0.0, 1.0], vectors)
    assert time.process_time() - start < 1.0
    # any argument taken as an array: a copy of a broadcast view is sized before it is made
    with pytest.raises(dz.TooLargeError, match=r"`q` as a float64 array of shape "
                                               r"\(2147483648, 4\)"):
        dz.rotate(np.broadcast_to(np.float32([1.0, 0.0, 0.0, 0.0]), (2**31, 4)),
                  (1.0, 0.0, 0.0))


@pytest.mark.parametrize("method", ["dop853", "dopri5", "rk4"])
@pytest.mark.parametrize(("a", "b"), [(1e-300, 1e-200), (1e300, 1e-200), (1e-300, 1e200)])
def test_a_deployment_at_the_edges_of_float64_moves_as_at_unit_scale(method, a, b):
    """Euler's equations are unchanged by I → aI, and ω → bω with t → t/b: a deployment at
    moments 1e-300 spinning at 1e-200 moves as the unit one, scaled (it was refused under
    dop853 with a false "step below round-off")."""
    moments = np.array([[1.0, 2.0, 3.0], [1.5, 2.5, 3.0]])
    w = np.array([0.01, 1.0, 0.01])
    unit = dz.simulate(dz.Deployment([0.0, 5.0], moments), w, t_end=10.0, frames=5,
                       method=method, dt=0.01)
    scaled = dz.simulate(dz.Deployment([0.0, 5.0 / b], a * moments), b * w, t_end=10.0 / b,
                         frames=5, method=method, dt=0.01 / b)
    np.testing.assert_allclose(scaled.omega / b, unit.omega, rtol=0, atol=1e-12)
    np.testing.assert_allclose(scaled.q, unit.q, rtol=0, atol=1e-12)
