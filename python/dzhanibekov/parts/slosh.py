"""The pendulum slosh part (the equations are in the guide's page on energy sinks and in the
core's ``rust/dynamics/multibody.rs``)."""

from __future__ import annotations

from ._spec import Part

__all__ = ["Slosh"]


class Slosh(Part):
    """A tank's first sloshing mode as its equivalent pendulum (Abramson 1966; Dodge 2000): a
    point mass `mass` on a massless rod of length `length` from a `pivot` of the body, free to
    swing in every direction, with a viscous torque ``−damping · ν`` at the pivot (``ν`` the
    rod's rate relative to the body).

    The rod's direction is a unit vector in the state (no two angles, no singularity). The
    run solves the hub (the body's tensor and its mass, ``Body.mass``, which must be given)
    and the pendulum jointly, exactly. Without torques the total angular momentum stays fixed
    in space and the energy falls by exactly the dissipated work (``drift.energy_balance``).
    A run shows ``traj.parts["slosh"]``: the rod's direction and its conjugate momentum, body
    axes.

    Parameters
    ----------
    mass : float
        The sloshing mass, positive.
    pivot : array_like, shape (3,)
        The pivot, from the body's mass centre, body axes.
    length : float
        The rod's length, positive.
    damping : float
        The pivot's viscous coefficient (torque per relative rate), non-negative.
    direction0 : array_like, shape (3,)
        The rod's direction at the start, body axes (normalised).
    rate0 : array_like, shape (3,), optional
        The rod's angular velocity relative to the body at the start (0).

    Raises
    ------
    TypeError, ValueError
        A parameter of the wrong kind or out of range (checked by the core).

    Examples
    --------
    >>> Slosh(0.1, (0.0, 0.0, 0.2), 0.1, 0.01, (1.0, 0.0, 0.0)).pivot
    (0.0, 0.0, 0.2)
    """

    kind = "slosh"
    examples = {"slosh": {"mass": 0.1, "pivot": (0.0, 0.0, 0.2), "length": 0.1,
                          "damping": 0.01, "direction0": (1.0, 0.0, 0.0)}}
    mass: float
    pivot: tuple[float, float, float]
    length: float
    damping: float
    direction0: tuple[float, float, float]
    rate0: tuple[float, float, float] | None
