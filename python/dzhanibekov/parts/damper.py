"""The spherical viscous nutation damper's part (the way to flat spin is in
:mod:`dzhanibekov.damper`)."""

from __future__ import annotations

from ._spec import Part

__all__ = ["Damper"]


class Damper(Part):
    """A spherical viscous nutation damper: a sphere of moment `inertia` in a spherical
    cavity of the body, the fluid between them exerting the torque ``damping · (σ − ω)``
    on the body (Hughes, *Spacecraft Attitude Dynamics*, 1986).

    With it the total angular momentum ``H = I ω + j σ`` stays fixed in space, the total
    kinetic energy ``½ ωᵀ I ω + ½ j |σ|²`` falls at the rate ``c |σ − ω|²`` (the run keeps the
    work it dissipated: ``drift.energy_balance`` measures its error), and every motion ends in a
    pure spin about the major axis with the sphere co-rotating. In body axes

    ``I ω' = I ω × ω + c (σ − ω)``,   ``σ' = σ × ω − (c / j) (σ − ω)``.

    A system may hold several; each keeps its own sphere.

    Parameters
    ----------
    inertia : float
        The sphere's moment of inertia ``j`` about its centre, positive. The body's own
        tensor counts the sphere's mass as a point at its centre.
    damping : float
        The viscous coefficient ``c`` (torque per unit relative rate), non-negative, with
        ``c / j`` (the sphere's relaxation rate) finite in float64.
    sigma0 : array_like, shape (3,), optional
        The sphere's absolute angular velocity at the start, in the body's own axes;
        co-rotating with the body (its ``omega0``) if None. A run shows the sphere's rates
        as ``traj.parts["damper"]``.

    Raises
    ------
    TypeError, ValueError
        A moment that is not positive and finite, a negative damping, or a relaxation rate
        ``c / j`` beyond float64 (checked by the core).

    Examples
    --------
    >>> Damper(0.05, 0.02)
    Damper(inertia=0.05, damping=0.02)
    """

    kind = "damper"
    examples = {"damper": {"inertia": 0.1, "damping": 0.05, "sigma0": (0.1, 0.2, 0.3)}}
    inertia: float
    damping: float
    sigma0: tuple[float, float, float] | None
