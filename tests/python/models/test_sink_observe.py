"""The invariants of a run's frames with energy sinks (``traj.energy``, ``momentum_body``,
``momentum_world``, from ``_core.observe``): the whole system's, through the mass matrix, as
the run's own drift measures them."""

from __future__ import annotations

import numpy as np
import pytest

import dzhanibekov as dz

BODY = dz.Body.from_tensor(np.diag([52.0833, 27.0833, 41.6666]), mass=1.0)
PARTS = {
    "spring_mass": dz.SpringMassDamper(0.05, (0.0, 0.0, 3.0), (1.0, 0.0, 0.0), 0.5, 0.02),
    "hinge": dz.Hinge(0.05, (1e-4, 0.01, 0.01), (0.0, 0.0, 3.0), (0.0, 1.0, 0.0),
                      (1.0, 0.0, 0.0), 1.0, 0.5, 0.02),
    "slosh": dz.Slosh(0.05, (0.0, 0.0, 3.0), 2.0, 0.02, (1.0, 0.0, 0.0)),
}


def run(part, frames=2001):
    return dz.simulate(dz.System(BODY, parts=[part]), (0.01, 0.01, 1.0), t_end=100.0,
                       frames=frames, dt=1e-2)


@pytest.mark.parametrize("kind", sorted(PARTS))
def test_the_frames_invariants_are_the_whole_systems(kind):
    # the angular momentum in space, from each frame's hub rates and parts' state through the
    # mass matrix, is the one the run keeps; the energy T + V never rises (the parts only
    # dissipate) and falls by as much as the run's own drift measure says
    traj = run(PARTS[kind])
    lw = traj.momentum_world
    assert np.abs(lw - lw[0]).max() / np.linalg.norm(lw[0]) < 1e-10
    e = traj.energy
    assert np.diff(e).max() <= 1e-12 * e[0]
    assert e[-1] < (1 - 1e-6) * e[0]
    assert abs((e[0] - e.min()) / e[0] - traj.drift.energy) < 1e-12


def test_undamped_the_frames_energy_is_kept():
    part = dz.Slosh(0.05, (0.0, 0.0, 3.0), 2.0, 0.0, (1.0, 0.0, 0.0))
    traj = run(part)
    e = traj.energy
    assert np.abs(e - e[0]).max() / e[0] <= traj.drift.energy * (1 + 1e-6) + 1e-15
    assert traj.drift.energy < 1e-9
