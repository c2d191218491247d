"""A spacecraft in orbit: external torques and momentum wheels.

Torques go in ``dz.System(body, torques=[...])``, wheels in ``parts=[...]``; the core adds
them to the general model's momentum law ``H' = H × ω + τ_b`` with
``ω = I⁻¹ (H − Σ h a)`` (body axes). The orbit and its frame are in
:mod:`dzhanibekov.lvlh`; see the guide page "A spacecraft in orbit".

>>> import dzhanibekov as dz
>>> sat = dz.System(dz.Body((2.0, 3.0, 1.0)), torques=[dz.GravityGradient(1.0)])
>>> sat.kinds, sat.conserved
(('gravity_gradient',), ('q_norm', 'jacobi'))
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from . import _core
from ._args import as_array, as_float
from .torques import CallableTorque, TabulatedTorque, interpolate, knot_times

__all__ = ["GravityGradient", "ConstantTorque", "Wheel", "Torque", "pitch_libration_rate",
           "dual_spin_threshold"]

_FRAMES = ("body", "world")

SCHEDULE_BYTES_PER_KNOT = 160
"""Memory a knot of a wheel's schedule takes while the wheel is built: its time and value as
Python floats in tuples (64 bytes), the arrays they come from and the core's table (129 bytes
at the peak, measured)."""


class GravityGradient:
    """The gravity gradient of a circular orbit of rate `orbit_rate` in the world x–y plane.

    The torque in body axes is ``τ = 3 n² r̂_b × (I r̂_b)``, with ``r̂_b`` the direction
    ``(cos nt, sin nt, 0)`` from the planet to the body (world axes) seen in body axes
    (Hughes, *Spacecraft Attitude Dynamics*, 1986, §8.2). The motion keeps the Jacobi
    integral ``J = T − n ẑ_b·H + (3/2) n² r̂_bᵀ I r̂_b`` (the energy seen from the orbiting
    frame plus the gradient's potential; Hughes §9.1): a run's ``drift.jacobi`` measures its
    error. ``|L|`` and ``L`` in space are not kept.

    Parameters
    ----------
    orbit_rate : float
        The orbit's rate ``n = √(μ / R³)``, radians per unit time, positive.

    Raises
    ------
    ValueError
        `orbit_rate` not positive and finite.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> sat = dz.System(dz.Body((2.0, 3.0, 1.5)), torques=[dz.GravityGradient(0.1)])
    >>> traj = dz.simulate(sat, *dz.lvlh_start(0.1, pitch=0.01), t_end=60.0, method="dop853")
    >>> traj.drift.kept
    ('q_norm', 'jacobi')
    >>> bool(traj.drift.jacobi < 1e-8)
    True
    """

    __slots__ = ("orbit_rate", "_core")

    orbit_rate: float

    def __init__(self, orbit_rate: Any) -> None:
        self.orbit_rate = as_float("orbit_rate", orbit_rate, positive=True)
        self._core = _core.Part("gravity_gradient", {"orbit_rate": self.orbit_rate})

    def __reduce__(self) -> tuple[Any, ...]:
        return (GravityGradient, (self.orbit_rate,))

    def __repr__(self) -> str:
        return f"GravityGradient(orbit_rate={self.orbit_rate!r})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, GravityGradient) and self.orbit_rate == other.orbit_rate

    def __hash__(self) -> int:
        return hash(("gravity_gradient", self.orbit_rate))


class ConstantTorque:
    """A constant external torque, fixed in body axes or in space.

    It keeps nothing but ``|q| = 1`` (``System.conserved`` says so, and a run's ``drift.kept``).
    It spins the body up without bound: the step planned for ``dt=None`` is the start's, so
    a long run wants an adaptive method (``"dop853"``) or a ``dt`` of its own.

    Parameters
    ----------
    vector : array_like, shape (3,)
        The torque, finite.
    frame : {"body", "world"}
        The axes it is fixed in: the body's own (``"body"``) or space's (``"world"``).

    Raises
    ------
    ValueError
        A `vector` not of shape (3,) or not finite; an unknown `frame`.
    TypeError
        A `frame` that is not a string.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> push = dz.System(dz.Body((1.0, 2.0, 3.0)), torques=[dz.ConstantTorque((0, 0, 0.1))])
    >>> traj = dz.simulate(push, (0.0, 0.0, 0.0), t_end=10.0, method="rk4", dt=0.01)
    >>> round(float(traj.omega[-1, 2]), 12)   # τ t / I_z
    0.333333333333
    """

    __slots__ = ("vector", "frame", "_core")

    vector: tuple[float, float, float]
    frame: str

    def __init__(self, vector: Any, frame: Any = "body") -> None:
        v = as_array("vector", vector, "(3,)", last=3, ndim=(1,))
        if not isinstance(frame, str):
            raise TypeError(f"`frame` must be 'body' or 'world', got {type(frame).__name__}")
        if frame not in _FRAMES:
            raise ValueError(f"`frame` must be 'body' or 'world', got {frame!r}")
        self.vector = (float(v[0]), float(v[1]), float(v[2]))
        self.frame = frame
        self._core = _core.Part("constant_torque", {"vector": self.vector, "frame": frame})

    def __reduce__(self) -> tuple[Any, ...]:
        return (ConstantTorque, (self.vector, self.frame))

    def __repr__(self) -> str:
        return f"ConstantTorque(vector={self.vector!r}, frame={self.frame!r})"

    def __eq__(self, other: object) -> bool:
        return (isinstance(other, ConstantTorque) and self.vector == other.vector
                and self.frame == other.frame)

    def __hash__(self) -> int:
        return hash(("constant", self.vector, self.frame))


Torque = GravityGradient | ConstantTorque | TabulatedTorque | CallableTorque
"""The external torques a system takes."""

TORQUE_TYPES = (GravityGradient, ConstantTorque, TabulatedTorque, CallableTorque)
"""The classes of :data:`Torque`, for ``isinstance``."""


class Wheel:
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
    ``traj.momentum_world`` counts it.

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
    >>> spin_up.momentum_at(25.0)
    1.0
    >>> dz.System(dz.Body((1.0, 2.0, 3.0)), parts=[spin_up]).kinds
    ('wheel_schedule',)
    """

    __slots__ = ("axis", "momentum", "_core")

    axis: tuple[float, float, float]
    momentum: float | tuple[tuple[float, ...], tuple[float, ...]]
    """The momentum: a number, or the schedule ``(times, values)`` as tuples."""

    def __init__(self, axis: Any, momentum: Any) -> None:
        a = as_array("axis", axis, "(3,)", last=3, ndim=(1,))
        if not np.any(a):
            raise ValueError("`axis` must not be zero, got (0, 0, 0)")
        self.axis = (float(a[0]), float(a[1]), float(a[2]))
        if isinstance(momentum, (tuple, list)):
            if len(momentum) != 2:
                raise ValueError(f"`momentum` must be a number or a schedule (times, values), "
                                 f"got a sequence of {len(momentum)} items")
            t = knot_times(momentum[0], "momentum times", SCHEDULE_BYTES_PER_KNOT)
            v = as_array("momentum", momentum[1], "(K,)", last=len(t), ndim=(1,))
            self.momentum = (tuple(float(x) for x in t), tuple(float(x) for x in v))
            self._core = _core.Part("wheel_schedule", {
                "axis": self.axis, "times": t, "values": np.array(v, dtype=np.float64)})
        else:
            if isinstance(momentum, np.ndarray) and momentum.ndim > 0:
                raise TypeError("`momentum` must be a number or a schedule (times, values), "
                                f"got an array of shape {momentum.shape}")
            self.momentum = as_float("momentum", momentum)
            self._core = _core.Part("wheel", {"axis": self.axis, "momentum": self.momentum})

    @property
    def is_scheduled(self) -> bool:
        """Whether the momentum follows a schedule."""
        return isinstance(self.momentum, tuple)

    def momentum_at(self, t: float) -> float:
        """The relative momentum at time `t` (a convenience for plots: runs evaluate the law
        in the core)."""
        if isinstance(self.momentum, tuple):
            return float(interpolate(t, self.momentum[0], self.momentum[1]))
        return self.momentum

    def __reduce__(self) -> tuple[Any, ...]:
        return (Wheel, (self.axis, self.momentum))

    def __repr__(self) -> str:
        if isinstance(self.momentum, tuple):
            times, values = self.momentum
            return (f"Wheel(axis={self.axis!r}, momentum=(times=[{times[0]!r} … {times[-1]!r}]"
                    f", values=[{values[0]!r} … {values[-1]!r}], knots={len(times)}))")
        return f"Wheel(axis={self.axis!r}, momentum={self.momentum!r})"

    def __eq__(self, other: object) -> bool:
        return (isinstance(other, Wheel) and self.axis == other.axis
                and self.momentum == other.momentum)

    def __hash__(self) -> int:
        return hash(("wheel", self.axis, self.momentum))


def pitch_libration_rate(inertia: Any, orbit_rate: Any) -> float:
    """The angular frequency of small pitch librations about the LVLH equilibrium,
    ``n √(3 (I_x − I_z) / I_y)``, for principal moments `inertia` ``(I_x, I_y, I_z)`` along
    along-track (roll), minus orbit normal (pitch) and nadir (yaw) (Hughes, *Spacecraft
    Attitude Dynamics*, 1986, §9.3: ``I_y θ'' + 3 n² (I_x − I_z) θ = 0``).

    Raises
    ------
    ValueError
        ``I_x ≤ I_z``: the pitch equilibrium is unstable, nothing librates.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> round(dz.pitch_libration_rate((2.0, 3.0, 1.0), 1.0), 12)
    1.0
    """
    i = as_array("inertia", inertia, "(3,)", last=3, ndim=(1,))
    n = as_float("orbit_rate", orbit_rate, positive=True)
    if not i[0] > i[2]:
        raise ValueError(f"`inertia` must have I_x > I_z for a stable pitch, got {tuple(i)}")
    return n * math.sqrt(3.0 * (i[0] - i[2]) / i[1])


def dual_spin_threshold(inertia: Any, axis: Any, rate: Any) -> tuple[float, float]:
    """The wheel momenta that leave a spin unstable: a spin at `rate` ``Ω`` about principal
    axis `axis` (``k``) with a wheel of momentum ``h`` along it is unstable for ``h`` strictly
    between ``Ω (I_i − I_k)`` and ``Ω (I_j − I_k)`` (``i``, ``j`` the other two axes), stable
    outside.

    Linearising ``I ω' = (I ω + h e_k) × ω`` about ``ω = Ω e_k`` gives
    ``I_i ω_i' = ±((I_k − I_j) Ω + h) ω_j`` and ``I_j ω_j' = ∓((I_i − I_k) Ω − h) ω_i``: the
    spin is stable when the product of the brackets is negative (the gyrostat's dual-spin
    rule; Hughes, *Spacecraft Attitude Dynamics*, 1986, ch. 6). For the intermediate axis the
    interval holds 0 (a spin without wheel flips); a wheel beyond ``Ω (I_max − I_mid)`` along
    the spin (or beyond ``Ω (I_mid − I_min)`` against it) stops the flips. For the major or
    minor axis, ``h = 0`` is outside: a plain spin is (linearly) stable.

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments.
    axis : int
        The spin axis: 0, 1 or 2.
    rate : float
        The spin rate ``Ω`` (its sign sets which way ``h`` counts as along the spin).

    Returns
    -------
    (low, high) : tuple of float
        The open interval of unstable ``h`` (empty when equal).

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> dz.dual_spin_threshold((1.0, 2.0, 3.0), axis=1, rate=1.0)
    (-1.0, 1.0)
    """
    i = as_array("inertia", inertia, "(3,)", last=3, ndim=(1,))
    if isinstance(axis, bool) or not isinstance(axis, (int, np.integer)) or axis not in (0, 1, 2):
        raise ValueError(f"`axis` must be 0, 1 or 2, got {axis!r}")
    w = as_float("rate", rate)
    k = int(axis)
    a, b = (w * (i[m] - i[k]) for m in range(3) if m != k)
    return (float(min(a, b)), float(max(a, b)))
