"""The invariants of a run's frames with energy sinks (``traj.energy``, ``momentum_body``,
``momentum_world``, from ``_core.observe``): the whole system's, through the mass matrix, as
the run's own drift measures them."""

from __future__ import annotations

import numpy as np
import pytest

import dzhanibekov as dz
from sink_runs import PARTS, run

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
