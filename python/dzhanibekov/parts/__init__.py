"""The parts of a system, one class per family of the core's models, each following the
core's declaration of its kind (see :mod:`._spec`): :class:`Damper`, the energy sinks whose mass moves in the
body (:class:`SpringMassDamper`, :class:`Hinge`, :class:`Slosh`), :class:`Wheel` (the
models ``wheel`` and ``wheel_schedule``), and the external torques :class:`GravityGradient`,
:class:`ConstantTorque`, :class:`TabulatedTorque`, :class:`CallableTorque`.

:data:`SPECS` maps every part model of the core's registry to its class: files and scenes
build any part from its kind and fields through it, and a test checks it covers the
registry.

>>> from dzhanibekov.parts import SPECS
>>> sorted(SPECS) == sorted(m.name for m in __import__("dzhanibekov").MODELS.values()
...                         if not m.law)
True
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from typing import Any

from .. import _core
from ._knots import BYTES_PER_KNOT, interpolate, knot_fraction, knot_times
from ._spec import REGISTRY, Param, Part, choice, params_of
from .damper import Damper
from .hinge import Hinge
from .slosh import Slosh
from .spring_mass import SpringMassDamper
from .torques import CallableTorque, ConstantTorque, GravityGradient, TabulatedTorque
from .wheels import Wheel

__all__ = ["Part", "Param", "Damper", "SpringMassDamper", "Hinge", "Slosh", "Wheel", "GravityGradient", "ConstantTorque",
           "TabulatedTorque", "CallableTorque", "SPECS", "TORQUE_TYPES", "from_fields", "example",
           "knot_times", "knot_fraction", "interpolate", "choice", "params_of",
           "BYTES_PER_KNOT"]

class _Specs(Mapping[str, type[Part]]):
    """The registered part classes by model, in the order of ``dz.MODELS``, read live: a
    class defined in another module (the closed loop's, :mod:`dzhanibekov.control`)
    registers when that module loads."""

    def __getitem__(self, model: str) -> type[Part]:
        return REGISTRY[model]

    def __iter__(self) -> Iterator[str]:
        return (m.name for m in _core.MODELS if m.name in REGISTRY)

    def __len__(self) -> int:
        return len(REGISTRY)


SPECS: Mapping[str, type[Part]] = _Specs()
"""The class of each part model of the core's registry, by the model's name (each class
registers the models it makes when it is defined: importing its module is enough)."""

TORQUE_TYPES: tuple[type[Part], ...] = (GravityGradient, ConstantTorque, TabulatedTorque,
                                        CallableTorque)
"""The classes of this package's external torques, for ``isinstance``."""


def example(kind: str) -> Part:
    """A small, valid part of the core's model `kind`, from its class's ``examples``: what
    tests run through every result path, whatever models the core has.

    >>> example("wheel_schedule").model
    'wheel_schedule'
    """
    if kind not in SPECS:
        raise ValueError(f"`kind` must be one of {', '.join(map(repr, SPECS))}, got {kind!r}")
    return from_fields(kind, SPECS[kind].examples[kind])


def from_fields(kind: str, fields: Mapping[str, Any]) -> Part:
    """The part of the core's model `kind` from its parameters by name (as
    :meth:`Part.fields` gives them): what files and scenes read."""
    if kind not in SPECS:
        raise ValueError(f"`kind` must be one of {', '.join(map(repr, SPECS))}, got {kind!r}")
    return SPECS[kind].from_fields(kind, fields)
