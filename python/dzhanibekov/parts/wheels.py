"""Momentum wheels: one class for a wheel of constant momentum (the core's ``wheel``) and one
whose momentum follows a schedule (``wheel_schedule``)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from .._args import as_array, as_float
from ._knots import interpolate, knot_times
from ._spec import Part

__all__ = ["Wheel"]

_SCHEDULE = "wheel_schedule"

SCHEDULE_BYTES_PER_KNOT = 160
"""Memory a knot of a wheel's schedule takes while the wheel is built: its time and value as
Python floats in tuples (64 bytes), the arrays they come from and the core's table (129 bytes
at the peak, measured)."""


class Wheel(Part):
    """A momentum wheel: a rotor spinning about a fixed body `axis` with relative angular
    momentum `momentum`, constant or following a schedule (a gyrostat; Hughes, *Spacecraft
    Attitude Dynamics*, ch. 6).

    The body's tensor counts the rotor as a rigid part. In body axes
    ``I ω' = (I ω + Σ h a) × ω − Σ ḣ a`` (plus the external torque): without torques the total
    angular momentum ``H = I ω + Σ h a`` is fixed in space (``|L|`` and ``L`` in space kept).
    With constant momenta the body's energy ``½ ωᵀ I ω`` is kept too; a schedule
    ``momentum=(times, values)`` (a spin-up or spin-down: linear between the knots, held
    outside them) changes it by the wheels' work, ``dT/dt = −Σ ḣ (a · ω)``, and every run ends
    a step on each of its knots (as for a :class:`~dzhanibekov.TabulatedTorque`). Several
    wheels, any axes, add up. A wheel has no state of its own (nothing in ``traj.parts``);
    ``traj.momentum_world`` counts it. A constant wheel is the core's model ``wheel``, a
    scheduled one ``wheel_schedule`` (:attr:`model`).

    Parameters
    ----------
    axis : array_like, shape (3,)
        The spin axis in the body's own axes, finite and not zero (normalised).
    momentum : float or (times, values)
        The rotor's angular momentum relative to the body along `axis`, finite: a number, or
        a schedule of at least two knot times (finite, strictly increasing) and as many
        values.

    Raises
    ------
    ValueError
        An `axis` of the wrong shape, not finite or zero; a `momentum` not finite; a schedule
        whose times are not increasing or whose values do not match them.
    TypeError
        A `momentum` that is neither a number nor a pair ``(times, values)``.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> dual = dz.System(dz.Body((1.0, 2.0, 3.0)), parts=[dz.Wheel((0, 1, 0), 2.0)])
    >>> dual.kinds, dual.conserved
    (('wheel',), ('momentum', 'momentum_world', 'q_norm'))
    >>> spin_up = dz.Wheel((0, 1, 0), ([0.0, 50.0], [0.0, 2.0]))
    >>> spin_up.momentum_at(25.0), spin_up.model
    (1.0, 'wheel_schedule')
    >>> dz.System(dz.Body((1.0, 2.0, 3.0)), parts=[spin_up]).kinds
    ('wheel_schedule',)
    """

    kind = "wheel"
    examples = {"wheel": {"axis": (0.0, 1.0, 0.0), "momentum": 0.5},
                "wheel_schedule": {"axis": (1.0, 0.0, 0.0), "times": (0.0, 1.0),
                                   "values": (0.0, 0.2)}}
    axis: tuple[float, float, float]
    momentum: float | tuple[tuple[float, ...], tuple[float, ...]]
    """The momentum: a number, or the schedule ``(times, values)`` as tuples."""

    def __init__(self, axis: Any, momentum: Any) -> None:
        v = as_array("axis", axis, "(3,)", last=3, ndim=(1,))
        if not (v[0] or v[1] or v[2]):
            raise ValueError("`axis` must not be zero, got (0, 0, 0)")
        a = (float(v[0]), float(v[1]), float(v[2]))
        if isinstance(momentum, (tuple, list)):
            if len(momentum) != 2:
                raise ValueError(f"`momentum` must be a number or a schedule (times, values), "
                                 f"got a sequence of {len(momentum)} items")
            t = knot_times(momentum[0], "momentum times", SCHEDULE_BYTES_PER_KNOT)
            v = as_array("momentum", momentum[1], "(K,)", last=len(t), ndim=(1,))
            self._store(_SCHEDULE, {"axis": a, "times": t, "values": v})
            return
        if isinstance(momentum, np.ndarray) and momentum.ndim > 0:
            raise TypeError("`momentum` must be a number or a schedule (times, values), "
                            f"got an array of shape {momentum.shape}")
        self._store(self.kind, {"axis": a, "momentum": as_float("momentum", momentum)})

    def _public(self, kind: str, values: dict[str, Any]) -> dict[str, Any]:
        if kind == _SCHEDULE:
            times, values_ = values["times"], values["values"]
            return {"axis": values["axis"],
                    "momentum": (tuple(float(x) for x in times),
                                 tuple(float(x) for x in values_))}
        return values

    @property
    def is_scheduled(self) -> bool:
        """Whether the momentum follows a schedule."""
        return isinstance(self.momentum, tuple)

    def momentum_at(self, t: float) -> float:
        """The relative momentum at time `t` (a convenience for plots: runs evaluate the law
        in the core)."""
        if isinstance(self.momentum, tuple):
            return float(interpolate(t, np.array(self.momentum[0]), np.array(self.momentum[1])))
        return self.momentum

    def fields(self) -> dict[str, Any]:
        if isinstance(self.momentum, tuple):
            return {"axis": self.axis, "times": np.array(self.momentum[0]),
                    "values": np.array(self.momentum[1])}
        return {"axis": self.axis, "momentum": self.momentum}

    @classmethod
    def from_fields(cls, kind: str, fields: Mapping[str, Any]) -> Part:
        if kind not in (cls.kind, _SCHEDULE):
            raise ValueError(f"a Wheel makes a 'wheel' or a {_SCHEDULE!r}, not a {kind!r}")
        cls._require(kind, fields)
        if kind == _SCHEDULE:
            return cls(fields["axis"], (fields["times"], fields["values"]))
        return cls(fields["axis"], fields["momentum"])

    def _key(self) -> tuple[Any, ...]:
        return (self.axis, self.momentum)

    def __repr__(self) -> str:
        if isinstance(self.momentum, tuple):
            times, values = self.momentum
            return (f"Wheel(axis={self.axis!r}, momentum=(times=[{times[0]!r} … {times[-1]!r}]"
                    f", values=[{values[0]!r} … {values[-1]!r}], knots={len(times)}))")
        return f"Wheel(axis={self.axis!r}, momentum={self.momentum!r})"

