"""What is simulated, as one value: a body with its internal parts and external torques.

A :class:`System` is what :func:`~dzhanibekov.simulate` runs; a plain :class:`Body` or
:class:`Deployment` is a system without parts. Its parts' state (a damper's σ) appears in a
run's results under the part's name (``traj.parts["damper"]``). The core checks every value,
turns the system into its model (the free body, or the general model of a body with parts)
and says what the model keeps, which the drift, the projection and the registry read.

>>> import dzhanibekov as dz
>>> explorer = dz.System(dz.Body((1.0, 10.0, 10.0)), parts=[dz.Damper(0.05, 0.02)])
>>> explorer.kinds, explorer.conserved
(('damper',), ('momentum', 'momentum_world', 'q_norm', 'energy_balance'))
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from . import _core
from .body import Body, as_body, principal_body
from .deployment import Deployment
from .parts import SPECS, CallableTorque
from .parts import Part as AnyPart

__all__ = ["System", "as_system", "Systems"]

Part = AnyPart
"""The internal parts a system takes: any part that is not an external torque (a
:class:`Damper`, a :class:`Wheel`, …, every part model of ``dz.MODELS``)."""


def _names(where: str) -> str:
    """The part classes a System takes in `where` (``"parts"`` or ``"torques"``)."""
    names = [f"a dz.{c.__name__}" for c in dict.fromkeys(SPECS.values()) if where in c.lists]
    return ", ".join(names[:-1]) + " or " + names[-1] if len(names) > 1 else names[0]


class System:
    """A body with its internal parts and external torques: what a run simulates.

    Parameters
    ----------
    body : Body, Deployment, or array_like, shape (3,)
        The body: constant (a :class:`Body` of any kind, or its principal moments) or
        changing in a prescribed way (a :class:`Deployment`).
    parts : sequence of parts, optional
        Internal parts, in order, of any part model of ``dz.MODELS`` that is not an external
        torque: a spherical viscous :class:`Damper` (its state appears in a run's ``parts``
        under ``"damper"``), momentum :class:`Wheel` s (any number, no state of their own), …
    torques : sequence of torques, optional
        External torques, which add up: the gravity gradient of a circular orbit (a
        :class:`GravityGradient`, at most one), constant torques in body or world axes
        (:class:`ConstantTorque`), tabulated ones (:class:`TabulatedTorque`) and your own
        functions (:class:`CallableTorque`; a plain function ``f(t, q, omega)`` is taken as
        one).

    Raises
    ------
    TypeError
        A body, part or torque of the wrong kind.
    ValueError
        More than one damper or gravity gradient (checked by the core).

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> s = dz.System(dz.Deployment([0.0, 10.0], [(1, 2, 3), (1, 3, 2)]))
    >>> s.kinds, s.part_names
    (('deployment',), ())
    """

    __slots__ = ("_body", "_parts", "_torques", "_core")

    _body: Body | Deployment
    _parts: tuple[Part, ...]
    _torques: tuple[AnyPart, ...]
    _core: _core.System

    def __init__(self, body: Any, parts: Sequence[AnyPart] = (),
                 torques: Sequence[AnyPart | Callable[..., Any]] = ()) -> None:
        if isinstance(body, System):
            raise TypeError("`body` must be a Body or a Deployment, got a System (pass its "
                            "parts to it instead)")
        body = body if isinstance(body, Deployment) else as_body(body)
        parts_ = _sequence("parts", parts)
        for k, part in enumerate(parts_):
            if not isinstance(part, AnyPart) or "parts" not in part.lists:
                raise TypeError(f"`parts[{k}]` must be {_names('parts')}, got "
                                f"{type(part).__name__}")
        # a plain function is a CallableTorque
        torques_ = tuple(t if isinstance(t, AnyPart) or not callable(t)
                         else CallableTorque(t) for t in _sequence("torques", torques))
        for k, torque in enumerate(torques_):
            if not isinstance(torque, AnyPart) or "torques" not in torque.lists:
                raise TypeError(f"`torques[{k}]` must be {_names('torques')} or a function "
                                f"(dz.CallableTorque), got {type(torque).__name__}")
        object.__setattr__(self, "_body", body)
        object.__setattr__(self, "_parts", parts_)
        object.__setattr__(self, "_torques", torques_)
        # the body's mass: parts whose mass moves in it (a spring-mass damper) need it
        object.__setattr__(self, "_core", _core.System(
            body._core, [p._core for p in parts_] + [t._core for t in torques_],
            getattr(body, "mass", None)))

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError("a System is immutable")

    @property
    def body(self) -> Body | Deployment:
        """The body: a :class:`Body` or a :class:`Deployment`."""
        return self._body

    @property
    def parts(self) -> tuple[Part, ...]:
        """The internal parts, in order."""
        return self._parts

    @property
    def torques(self) -> tuple[AnyPart, ...]:
        """The external torques, in order."""
        return self._torques

    @property
    def kinds(self) -> tuple[str, ...]:
        """The registry's models the system is made of (``dz.METHODS[m].models`` says which
        methods run them)."""
        return tuple(self._core.kinds)

    @property
    def conserved(self) -> tuple[str, ...]:
        """What the system's exact motion keeps, by the names of :class:`Drift`'s fields: a
        run's drift of these measures its error."""
        return tuple(self._core.conserved)

    @property
    def part_names(self) -> tuple[str, ...]:
        """The name of each part with state of its own, as results show its state (a wheel
        has none)."""
        return tuple(name for name, _ in self._core.parts)

    @property
    def part_widths(self) -> tuple[int, ...]:
        """How many numbers of state each part has (a damper's σ: 3)."""
        return tuple(width for _, width in self._core.parts)

    @property
    def is_free(self) -> bool:
        """Whether it is a constant body without parts: the free body."""
        return self.kinds == ("free",)

    def tensor_at(self, t: float) -> np.ndarray:
        """The body's inertia tensor at time `t`, in the body's own axes, shape (3, 3)."""
        return np.array(self._core.tensor_at(float(t)))

    def __reduce__(self) -> tuple[Any, ...]:
        return (System, (self._body, self._parts, self._torques))

    def __eq__(self, other: object) -> bool:
        """Systems of the same body and the same parts (its parts, then its torques, in their
        order: which list an external part was given in does not matter) are equal; so are a
        system without parts and its body or deployment (a run's ``system`` and what was
        run, a loaded run's and what was saved)."""
        if isinstance(other, (Body, Deployment)):
            return not self._parts and not self._torques and self._body == other
        return (isinstance(other, System) and self._body == other._body
                and self._parts + self._torques == other._parts + other._torques)

    def __hash__(self) -> int:
        if not self._parts and not self._torques:
            return hash(self._body)  # equal to its body: the same hash
        return hash((self._body, self._parts + self._torques))

    def __repr__(self) -> str:
        if not self._parts and not self._torques:
            return f"System({self._body!r})"
        torques = f", torques={list(self._torques)!r}" if self._torques else ""
        return f"System({self._body!r}, parts={list(self._parts)!r}{torques})"


def _sequence(name: str, value: Any) -> tuple[Any, ...]:
    if isinstance(value, (str, bytes)) or not isinstance(value, Sequence):
        raise TypeError(f"`{name}` must be a sequence, got {type(value).__name__}")
    return tuple(value)


def as_system(value: Any, name: str = "system") -> System:
    """`value` as a System: itself, or a Body, Deployment or principal moments without parts."""
    if isinstance(value, System):
        return value
    if isinstance(value, Deployment):
        return System(value)
    global _last_system
    last = _last_system
    if last is not None and last[0] is value:
        return last[1]
    system = System(as_body(value, name))
    if isinstance(value, Body):  # a body never changes: its system serves its next run too
        _last_system = (value, system)
    return system


_last_system: tuple[Body, System] | None = None
"""The system of the last body `as_system` was given, and that body."""


class Systems(Sequence[System]):
    """The systems of a batch's rows: one shared by every row, one per row, or bodies given
    as rows of principal moments (built only when a row is asked for)."""

    __slots__ = ("shared", "each", "moments", "_m")

    def __init__(self, m: int, *, shared: System | None = None,
                 each: tuple[System, ...] | None = None,
                 moments: np.ndarray | None = None) -> None:
        self.shared, self.each, self.moments, self._m = shared, each, moments, m

    def __len__(self) -> int:
        return self._m

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, slice):
            rows = range(self._m)[i]
            return Systems(len(rows), shared=self.shared,
                           each=None if self.each is None else tuple(self.each[k] for k in rows),
                           moments=None if self.moments is None else self.moments[i])
        i = range(self._m)[i]
        if self.shared is not None:
            return self.shared
        if self.each is not None:
            return self.each[i]
        assert self.moments is not None
        return System(principal_body(self.moments[i]))

    @property
    def first(self) -> System:
        """The first row's system (every row's kinds are the same)."""
        first: System = self[0]
        return first

    def core(self) -> list[_core.System]:
        """The core's systems: one shared, or one per row (for moments, built by the core)."""
        if self.shared is not None:
            return [self.shared._core]
        if self.each is not None:
            return [s._core for s in self.each]
        return []

    def __reduce__(self) -> tuple[Any, ...]:
        return (_rebuild_systems, (self._m, self.shared, self.each, self.moments))

    def __eq__(self, other: object) -> bool:
        return (isinstance(other, Systems) and len(self) == len(other)
                and all(self[i] == other[i] for i in range(len(self))))

    def __hash__(self) -> int:
        return hash(self._m)

    def __repr__(self) -> str:
        return f"Systems(runs={self._m})"


def _rebuild_systems(m: int, shared: System | None, each: tuple[System, ...] | None,
                     moments: np.ndarray | None) -> Systems:
    return Systems(m, shared=shared, each=each, moments=moments)
