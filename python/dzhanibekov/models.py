"""The models on offer, as the core declares them: the inertia laws (the free body, a
deployment) and the parts (dampers, wheels, external torques, ...).

:data:`MODELS` maps each model's name to its declaration (:class:`ModelInfo`): one line
about it, whether it is an inertia law, its parameters ``(name, kind, optional, about,
choices)``, its own state ``(name, width, body-axes vector, about)``, what a system with it
keeps, its energy role (``"neither"``, ``"does work"``, ``"dissipates"``), whether it is an
external torque, what it asks of a method and which methods run it. A system's ``kinds`` are
names of :data:`MODELS`; a method's ``models`` too.

>>> import dzhanibekov as dz
>>> dz.MODELS["damper"].energy, dz.MODELS["damper"].state[0][:2]
('dissipates', ('sigma', 3))
>>> "splitting_exact" in dz.MODELS["gravity_gradient"].methods
True
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

from . import _core

__all__ = ["MODELS", "ModelInfo"]

ModelInfo = _core.ModelInfo

MODELS: Mapping[str, ModelInfo] = MappingProxyType({m.name: m for m in _core.MODELS})
"""Every model by name, in the order the core lists them: the inertia laws, then the parts
(read-only)."""
