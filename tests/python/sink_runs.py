"""Runs of the paper's box (with a mass) carrying one energy sink each, shared by the tests of
the frames' invariants and of the sinks' figures."""

from __future__ import annotations

import numpy as np

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
