"""The energy-sink estimate of the time to flat spin (Kaplan 1976) against the damped body's
simulated motion.

Issue 24: the estimate left the damper's own moment ``j`` out of the body's (1280 for
Explorer 1 against 1365 simulated); with the sphere counted as co-rotating, ``I + j``, it is
1361.5.
"""

from __future__ import annotations

import pytest

import dzhanibekov as dz

BODY, OMEGA0 = (1.0, 10.0, 10.0), (2.0, 0.01, 0.0)


def simulated(damper: dz.Damper, estimate: float) -> float:
    """The flat-spin time of the damped body's run, read at frames 0.1 apart."""
    t_end = 1.3 * estimate
    traj = dz.simulate(dz.System(BODY, parts=[damper]), OMEGA0, t_end=t_end,
                       frames=int(10 * t_end) + 1, dt=0.01)
    return dz.flat_spin_time(traj)


def test_the_estimate_is_the_small_damper_limit_of_the_motion():
    # j and c → 0 at a fixed j / c (the sphere's lag τ): the estimate's error is first order
    # in the damper (measured 1.8e-3, 9.3e-4, 4.6e-4: it halves with the damper)
    errors = []
    for s in (1.0, 0.5, 0.25):
        damper = dz.Damper(0.05 * s, 0.02 * s)
        estimate = dz.flat_spin_estimate(BODY, damper, OMEGA0)
        errors.append(abs(estimate / simulated(damper, estimate) - 1))
    assert errors[0] < 3e-3, errors
    assert errors[1] < 0.6 * errors[0] and errors[2] < 0.6 * errors[1], errors


def test_explorer_1s_numbers():
    scene = dz.SCENES["explorer-1"]
    assert scene.damper is not None
    estimate = dz.flat_spin_estimate(scene.inertia, scene.damper, scene.omega0)
    measured = dz.flat_spin_time(scene.run())
    # the issue's own computation with I + j: 1361.5, against 1365 at the scene's frames
    # (7.5 apart); without j it was 1280, 6 % short
    assert estimate == pytest.approx(1361.5, abs=0.1)
    assert measured == pytest.approx(estimate, rel=0.01)
