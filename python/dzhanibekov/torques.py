"""External torques given as data or as code: a torque tabulated at knots
(:class:`TabulatedTorque`) and a torque computed by a Python function
(:class:`CallableTorque`). They go in ``dz.System(body, torques=[...])`` with the built-in
:class:`~dzhanibekov.GravityGradient` and :class:`~dzhanibekov.ConstantTorque`, and add up.

>>> import dzhanibekov as dz
>>> pulse = dz.TabulatedTorque([0.0, 1.0, 2.0], [(0, 0, 0), (0, 0, 0.5), (0, 0, 0)])
>>> dz.System(dz.Body((1.0, 2.0, 3.0)), torques=[pulse]).conserved
('q_norm',)
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from . import _core
from ._args import as_array, check_size

__all__ = ["TabulatedTorque", "CallableTorque", "knot_times"]

_FRAMES = ("body", "world")
_OUTSIDE = ("zero", "hold")

BYTES_PER_KNOT = 8 * 4 * 4
"""Memory a knot takes while a table is built: its time and vector, a few copies (64 bytes
measured: the arrays kept and the core's table)."""


def _choice(name: str, value: Any, allowed: tuple[str, ...]) -> str:
    options = " or ".join(repr(a) for a in allowed)
    if not isinstance(value, str):
        raise TypeError(f"`{name}` must be {options}, got {type(value).__name__}")
    if value not in allowed:
        raise ValueError(f"`{name}` must be {options}, got {value!r}")
    return value


def knot_times(times: Any, n_name: str = "times", bytes_per_knot: int = BYTES_PER_KNOT
               ) -> np.ndarray:
    """Knot times: a float64 array (K,) of at least two finite, strictly increasing times.

    Raises
    ------
    TypeError
        Not a sequence of real numbers.
    ValueError
        Fewer than two knots, not finite, or not strictly increasing (naming the first pair).

    Examples
    --------
    >>> from dzhanibekov.torques import knot_times
    >>> knot_times([0, 1.5]).tolist()
    [0.0, 1.5]
    """
    try:
        n = len(times)
    except TypeError:
        raise TypeError(f"`{n_name}` must be a sequence of knot times, got "
                        f"{type(times).__name__}") from None
    check_size(n * bytes_per_knot, f"a table of {n} knots", "give fewer knots")
    t = as_array(n_name, times, "(K,)", last=n, ndim=(1,))
    if len(t) < 2:
        raise ValueError(f"`{n_name}` must hold at least two knots, got {len(t)}")
    bad = np.flatnonzero(t[1:] <= t[:-1])  # (not np.diff: a gap of knots at ±1.7e308 overflows)
    if bad.size:
        k = int(bad[0])
        raise ValueError(f"`{n_name}` must be strictly increasing, got {n_name}[{k}] = "
                         f"{t[k]!r} then {n_name}[{k + 1}] = {t[k + 1]!r}")
    return t


def knot_fraction(t: float, t0: float, t1: float) -> float:
    """Where `t` lies in ``[t0, t1]``, ``(t − t0) / (t1 − t0)``, for intervals of any width:
    one wider than float64's largest number (knots at ±1.7e308) by its halves (its width
    overflowed, and the place was 0 at every `t`).

    Examples
    --------
    >>> knot_fraction(0.0, -1.7e308, 1.7e308)
    0.5
    """
    gap = t1 - t0  # (Python floats: an overflow is inf, without a warning)
    if math.isfinite(gap):
        return (t - t0) / gap
    return (0.5 * t - 0.5 * t0) / (0.5 * t1 - 0.5 * t0)


def interpolate(t: float, times: Any, values: Any) -> Any:
    """The values at knots `times` (increasing) interpolated linearly at `t`, held outside
    them (as ``numpy.interp``, for knots of any span: see :func:`knot_fraction`)."""
    k = int(np.searchsorted(times, t, side="right"))
    if k == 0:
        return values[0]
    if k == len(times):
        return values[-1]
    s = knot_fraction(float(t), float(times[k - 1]), float(times[k]))
    return values[k - 1] + s * (values[k] - values[k - 1])


class TabulatedTorque:
    """An external torque tabulated at knots, linear between them.

    Between knots ``t_k < t_{k+1}`` the torque is ``τ_k + (t − t_k) / (t_{k+1} − t_k)
    (τ_{k+1} − τ_k)``; outside ``[t_0, t_K]`` it is zero (``outside="zero"``, the default: a
    table says nothing beyond its data, and a torque held forever would spin a body up without
    bound) or the nearest end's value (``outside="hold"``). Every run ends a step on every
    knot, fixed-step methods too, so that no step straddles a kink or the jump at an end
    (which would make that step first order); at a knot the torque is the value from the left
    and the next step starts just after it. It keeps nothing but ``|q| = 1``.

    Parameters
    ----------
    times : array_like, shape (K,)
        Knot times, at least two, finite and strictly increasing.
    vectors : array_like, shape (K, 3)
        The torque at each knot, finite.
    frame : {"body", "world"}
        The axes the vectors are given in: the body's own or space's.
    outside : {"zero", "hold"}
        The torque before the first knot and after the last.

    Raises
    ------
    ValueError
        `times` not increasing, not finite or fewer than two; `vectors` not of shape (K, 3)
        with K the number of times, or not finite; an unknown `frame` or `outside`.
    TypeError
        Arguments of the wrong kind.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> ramp = dz.TabulatedTorque([0.0, 2.0], [(0, 0, 0), (0, 0, 1.0)], outside="hold")
    >>> s = dz.System(dz.Body((2.0, 3.0, 4.0)), torques=[ramp])
    >>> traj = dz.simulate(s, (0.0, 0.0, 0.0), t_end=4.0, method="rk4", dt=0.5)
    >>> round(float(traj.omega[-1, 2]), 12)   # (∫ τ dt) / I_z = (1 + 2) / 4
    0.75
    """

    __slots__ = ("times", "vectors", "frame", "outside", "_core")

    times: np.ndarray
    """Knot times, shape (K,)."""
    vectors: np.ndarray
    """The torque at each knot, shape (K, 3)."""
    frame: str
    outside: str

    def __init__(self, times: Any, vectors: Any, frame: Any = "body",
                 outside: Any = "zero") -> None:
        t = knot_times(times)
        if isinstance(vectors, np.ndarray) and vectors.ndim and len(vectors) != len(t):
            # before any copy: a broadcast view of 2**31 rows would be copied whole first
            raise ValueError(f"`vectors` must give one torque per knot time of `times` "
                             f"({len(t)}), got {len(vectors)}")
        v = as_array("vectors", vectors, "(K, 3)", last=3, ndim=(2,))
        if len(v) != len(t):
            raise ValueError(f"`vectors` must give one torque per knot time of `times` "
                             f"({len(t)}), got {len(v)}")
        self.frame = _choice("frame", frame, _FRAMES)
        self.outside = _choice("outside", outside, _OUTSIDE)
        self.times = np.array(t, dtype=np.float64)
        self.vectors = np.array(v, dtype=np.float64)
        self.times.flags.writeable = False
        self.vectors.flags.writeable = False
        self._core = _core.Part("tabulated_torque", {
            "times": self.times, "vectors": self.vectors, "frame": self.frame,
            "outside": self.outside})

    def torque_at(self, t: float) -> np.ndarray:
        """The tabulated vector at time `t`, shape (3,), in `frame`'s axes (a convenience for
        plots: runs evaluate the law in the core). At a knot, the value from the left."""
        ts, vs = self.times, self.vectors
        if t <= ts[0] or t > ts[-1]:
            if self.outside == "zero":
                return np.zeros(3)
            return np.array(vs[0] if t <= ts[0] else vs[-1])
        k = int(np.searchsorted(ts, t, side="left"))
        s = knot_fraction(float(t), float(ts[k - 1]), float(ts[k]))
        return np.array(vs[k - 1] + s * (vs[k] - vs[k - 1]))

    def __reduce__(self) -> tuple[Any, ...]:
        return (TabulatedTorque, (self.times, self.vectors, self.frame, self.outside))

    def __repr__(self) -> str:
        return (f"TabulatedTorque(times=[{float(self.times[0])!r} … {float(self.times[-1])!r}], "
                f"knots={len(self.times)}, frame={self.frame!r}, outside={self.outside!r})")

    def __eq__(self, other: object) -> bool:
        return (isinstance(other, TabulatedTorque) and self.frame == other.frame
                and self.outside == other.outside and np.array_equal(self.times, other.times)
                and np.array_equal(self.vectors, other.vectors))

    def __hash__(self) -> int:
        return hash(("tabulated", self.times.tobytes(), self.vectors.tobytes(), self.frame,
                     self.outside))


class CallableTorque:
    """An external torque computed by your own Python function, for what the built-in torques
    do not cover (a controller, a drag model, a measured disturbance).

    ``func(t, q, omega)`` gets the time ``t`` (float), the attitude ``q`` (shape (4,),
    world-from-body, scalar first, unit) and the body rates ``omega`` (shape (3,), body axes),
    and returns the torque in body axes (three numbers). It is called at every evaluation of
    the right-hand side (four a step for ``rk4``, twelve for ``dop853``), so a run goes at
    Python speed — about a microsecond or more a call instead of a few nanoseconds (the
    models bench prints the ratio). The function should be a pure function of its arguments:
    the methods call it at trial states and times that are not on the trajectory.

    A function that raises stops the run, and its exception reaches the caller as raised; one
    that returns something else than three finite real numbers (an array of shape (3,), any
    strides, or a sequence; not bytes, a string, a masked array, complex numbers or bools)
    stops it with a ValueError naming `torque`. Either stops only the run it happened in. Ctrl-C stops a run as usual (within milliseconds: no call is made after it). A
    batch of such systems runs, its rows one after another on one thread (each call takes the
    GIL: rows on several threads would only queue for it). The model keeps nothing but ``|q| = 1``.
    ``dz.save`` refuses a run with one: a file cannot hold code.

    A plain function in ``torques=[...]`` is taken as ``CallableTorque(func)``.

    Parameters
    ----------
    func : callable
        ``func(t, q, omega) -> array_like, shape (3,)``.

    Raises
    ------
    TypeError
        A `func` that cannot be called.

    Examples
    --------
    >>> import numpy as np
    >>> import dzhanibekov as dz
    >>> def damping(t, q, omega):            # a rate damper: τ = −k ω
    ...     return -0.1 * omega
    >>> s = dz.System(dz.Body((2.0, 3.0, 4.0)), torques=[dz.CallableTorque(damping)])
    >>> traj = dz.simulate(s, (0.0, 0.0, 1.0), t_end=10.0, method="dop853", rtol=1e-10)
    >>> bool(abs(traj.omega[-1, 2] - np.exp(-0.1 * 10.0 / 4.0)) < 1e-9)
    True
    """

    __slots__ = ("func", "_core")

    func: Any

    def __init__(self, func: Any) -> None:
        if isinstance(func, CallableTorque):
            func = func.func
        if not callable(func):
            raise TypeError(f"`func` must be callable as func(t, q, omega), got "
                            f"{type(func).__name__}")
        self.func = func
        self._core = _core.Part("callable_torque", {"func": func})

    def __reduce__(self) -> tuple[Any, ...]:
        return (CallableTorque, (self.func,))

    def __repr__(self) -> str:
        name = getattr(self.func, "__qualname__", None) or repr(self.func)
        return f"CallableTorque({name})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, CallableTorque) and self.func == other.func

    def __hash__(self) -> int:
        return hash(("callable", self.func))
