"""External torques: the gravity gradient of a circular orbit, a constant torque, a torque
tabulated at knots and a torque computed by a Python function. They go in
``dz.System(body, torques=[...])`` and add up.

>>> import dzhanibekov as dz
>>> pulse = dz.TabulatedTorque([0.0, 1.0, 2.0], [(0, 0, 0), (0, 0, 0.5), (0, 0, 0)])
>>> dz.System(dz.Body((1.0, 2.0, 3.0)), torques=[pulse]).conserved
('q_norm',)
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ._knots import knot_fraction
from ._spec import Part

__all__ = ["GravityGradient", "ConstantTorque", "TabulatedTorque", "CallableTorque"]


class GravityGradient(Part):
    """The gravity gradient of a circular orbit of rate `orbit_rate` in the world x–y plane.

    The torque in body axes is ``τ = 3 n² r̂_b × (I r̂_b)``, with ``r̂_b`` the direction
    ``(cos nt, sin nt, 0)`` from the planet to the body (world axes) seen in body axes
    (Hughes, *Spacecraft Attitude Dynamics*, 1986, §8.2). The motion keeps the Jacobi
    integral ``J = T − n ẑ_b·H + (3/2) n² r̂_bᵀ I r̂_b`` (the energy seen from the orbiting
    frame plus the gradient's potential; Hughes §9.1): a run's ``drift.jacobi`` measures its
    error. ``|L|`` and ``L`` in space are not kept. A system holds at most one (one orbit).

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

    kind = "gravity_gradient"
    examples = {"gravity_gradient": {"orbit_rate": 0.3}}
    orbit_rate: float


class ConstantTorque(Part):
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

    kind = "constant_torque"
    defaults = {"frame": "body"}
    examples = {"constant_torque": {"vector": (0.0, 0.0, 0.01), "frame": "world"}}
    vector: tuple[float, float, float]
    frame: str


class TabulatedTorque(Part):
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

    kind = "tabulated_torque"
    defaults = {"frame": "body", "outside": "zero"}
    examples = {"tabulated_torque": {"times": (0.0, 0.5, 1.0),
                                     "vectors": ((0.0, 0.0, 0.0), (0.0, 0.01, 0.0), (0.0, 0.0, 0.0)),
                                     "outside": "hold"}}
    times: np.ndarray
    """Knot times, shape (K,), read-only."""
    vectors: np.ndarray
    """The torque at each knot, shape (K, 3), read-only."""
    frame: str
    outside: str

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

    def __repr__(self) -> str:
        return (f"TabulatedTorque(times=[{float(self.times[0])!r} … {float(self.times[-1])!r}], "
                f"knots={len(self.times)}, frame={self.frame!r}, outside={self.outside!r})")


def _example_torque(t: float, q: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """A small rate damping, ``τ = −0.01 ω`` (the callable torque's example)."""
    return -0.01 * omega


class CallableTorque(Part):
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
    that returns something else than three finite numbers stops it with a ValueError naming
    `torque`. Ctrl-C stops a run as usual (within milliseconds: no call is made after it). A
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

    kind = "callable_torque"
    examples = {"callable_torque": {"func": _example_torque}}
    func: Any

    def __init__(self, func: Any) -> None:
        if isinstance(func, CallableTorque):
            func = func.func
        super().__init__(func)

    def __repr__(self) -> str:
        name = getattr(self.func, "__qualname__", None) or repr(self.func)
        return f"CallableTorque({name})"
