"""The spring–mass damper's part (the equations are in the guide's page on energy sinks and in
the core's ``rust/dynamics/multibody.rs``)."""

from __future__ import annotations

from ._spec import Part

__all__ = ["SpringMassDamper"]


class SpringMassDamper(Part):
    """A point mass `mass` sliding along a line of the body, ``r = anchor + x · direction``,
    on a spring `stiffness` with viscous `damping`: the classic nutation damper.

    The mass moves in the body, so the system's mass centre moves with it: the run solves the
    hub (the body's tensor and its mass, ``Body.mass``, which must be given) and the mass
    jointly, exactly. Without torques the total angular momentum stays fixed in space and the
    energy (kinetic plus the spring's) falls by exactly the work the damper dissipates
    (``drift.energy_balance``). A run shows ``traj.parts["spring_mass"]``: the displacement
    ``x`` and its conjugate momentum.

    Parameters
    ----------
    mass : float
        The moving mass, positive.
    anchor : array_like, shape (3,)
        Where the mass rests (``x = 0``), from the body's mass centre, body axes.
    direction : array_like, shape (3,)
        The line it slides along, body axes (normalised).
    stiffness, damping : float
        The spring's ``k`` and the damper's ``c``, non-negative.
    x0, rate0 : float, optional
        The displacement and its rate at the start (0).

    Raises
    ------
    TypeError, ValueError
        A parameter of the wrong kind or out of range (checked by the core).

    Examples
    --------
    >>> SpringMassDamper(0.1, (0.0, 0.0, 0.5), (1.0, 0.0, 0.0), 4.0, 0.2)
    SpringMassDamper(mass=0.1, anchor=(0.0, 0.0, 0.5), direction=(1.0, 0.0, 0.0), \
stiffness=4.0, damping=0.2)
    """

    kind = "spring_mass"
    examples = {"spring_mass": {"mass": 0.1, "anchor": (0.0, 0.0, 0.5),
                                "direction": (1.0, 0.0, 0.0), "stiffness": 4.0,
                                "damping": 0.2, "x0": 0.01}}
    mass: float
    anchor: tuple[float, float, float]
    direction: tuple[float, float, float]
    stiffness: float
    damping: float
    x0: float | None
    rate0: float | None
