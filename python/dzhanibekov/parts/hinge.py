"""The hinged appendage's part (the equations are in the guide's page on energy sinks and in
the core's ``rust/dynamics/multibody.rs``)."""

from __future__ import annotations

from ._spec import Part

__all__ = ["Hinge"]


class Hinge(Part):
    """A rigid panel or rod on a one-axis hinge of the body, with a torsional spring
    `stiffness` and damper `damping`: a deployed antenna or solar panel. A body may hold
    several.

    The panel (mass `mass`, `moments` about its own centre) turns about `axis` through the
    `hinge` point; its centre lies `length` from the hinge along `arm` at rest (angle 0). The
    run solves the hub (the body's tensor and its mass, ``Body.mass``, which must be given)
    and every moving part jointly, exactly. Without torques the total angular momentum stays
    fixed in space and the energy falls by exactly the dissipated work
    (``drift.energy_balance``). A run shows ``traj.parts["hinge"]``: the angle from rest and
    its conjugate momentum.

    Parameters
    ----------
    mass : float
        The panel's mass, positive.
    moments : array_like, shape (3,)
        Its moments about its own centre: about the arm, the hinge axis and their normal.
    hinge, axis, arm : array_like, shape (3,)
        The hinge point from the body's mass centre, the hinge axis, and the direction from
        the hinge towards the panel's centre at rest (normal to the axis), body axes.
    length : float
        The distance of the panel's centre from the hinge.
    stiffness, damping : float
        The torsional spring's ``k`` and the damper's ``c``, non-negative.
    angle0, rate0 : float, optional
        The hinge angle and its rate at the start (0).

    Raises
    ------
    TypeError, ValueError
        A parameter of the wrong kind or out of range (checked by the core).

    Examples
    --------
    >>> Hinge(0.2, (1e-4, 0.01, 0.01), (0.5, 0.0, 0.0), (0.0, 0.0, 1.0), (1.0, 0.0, 0.0),
    ...       0.3, 2.0, 0.05).length
    0.3
    """

    kind = "hinge"
    examples = {"hinge": {"mass": 0.2, "moments": (1e-4, 0.01, 0.01), "hinge": (0.5, 0.0, 0.0),
                          "axis": (0.0, 0.0, 1.0), "arm": (1.0, 0.0, 0.0), "length": 0.3,
                          "stiffness": 2.0, "damping": 0.05, "angle0": 0.05}}
    mass: float
    moments: tuple[float, float, float]
    hinge: tuple[float, float, float]
    axis: tuple[float, float, float]
    arm: tuple[float, float, float]
    length: float
    stiffness: float
    damping: float
    angle0: float | None
    rate0: float | None
