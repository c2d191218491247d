"""One run of every model the core declares (`dz.MODELS`), for the tests that take every
model through every result path: a bare body or deployment for the inertia laws, a boxed
body (with a mass, for the parts whose mass moves) carrying the model's example part
otherwise. Built from the registry and the part classes' examples, not a hand list."""

from __future__ import annotations

import dzhanibekov as dz
from dzhanibekov.parts import example

BOX = dz.Body.box(1.0, 2.0, 3.0, mass=2.0)
DEPLOYMENT = dz.Deployment([0.0, 0.5], [(1.0, 2.0, 3.0), (1.0, 3.0, 2.0)])
START = (0.3, 0.2, 1.0), (1.0, 0.0, 0.0, 0.0)


def system_of(name: str) -> dz.System | dz.Body | dz.Deployment:
    """What a user runs for model `name`."""
    if name == "free":
        return BOX
    if name == "deployment":
        return DEPLOYMENT
    part = example(name)
    return dz.System(BOX, **{"torques" if part.external else "parts": [part]})
