"""Rigid bodies: principal moments of inertia."""

from __future__ import annotations

import warnings
from typing import Any

from . import _core
from ._args import as_array, as_float

__all__ = ["Body", "InertiaWarning", "as_body"]


PAPER_INERTIA = (52.0833, 27.0833, 41.6666)
"""The paper's principal moments (Ix, Iy, Iz), as printed. The box formula gives them with x
and y swapped (erratum 2, see the README); either way z is the intermediate axis."""


class InertiaWarning(UserWarning):
    """Principal moments that no real mass distribution has (the triangle inequality fails)."""


class Body:
    """A rigid body given by its principal moments of inertia about body axes x, y, z.

    Parameters
    ----------
    inertia : array_like, shape (3,)
        ``(Ix, Iy, Iz)``, positive and finite, in any consistent units.

    Raises
    ------
    TypeError
        If `inertia` is not three real numbers.
    ValueError
        If a moment is not positive and finite, or the moments differ by more than 1e150.

    Warns
    -----
    InertiaWarning
        If one moment exceeds the sum of the other two: every real body has
        ``Ix <= Iy + Iz`` (and likewise for y, z), so such moments describe no body, though
        Euler's equations still run.

    Examples
    --------
    >>> Body(inertia=(52.0833, 27.0833, 41.6666)).intermediate_axis
    2
    >>> Body.box(20, 10, 15).inertia[0]  # m (b² + c²) / 12
    27.083333333333332
    """

    __slots__ = ("_core",)

    def __init__(self, inertia: Any) -> None:
        ix, iy, iz = as_array("inertia", inertia, "(3,)", last=3, ndim=(1,)).tolist()
        self._core = _core.RigidBody((ix, iy, iz))
        _warn_if_unphysical(self._core)

    @classmethod
    def box(cls, a: float, b: float, c: float, mass: float = 1.0) -> Body:
        """A solid box with edges `a`, `b`, `c` along x, y, z: ``Ix = m (b² + c²) / 12``, etc."""
        body = cls.__new__(cls)
        body._core = _core.RigidBody.from_box(
            as_float("a", a, positive=True),
            as_float("b", b, positive=True),
            as_float("c", c, positive=True),
            as_float("mass", mass, positive=True),
        )
        return body

    @property
    def inertia(self) -> tuple[float, float, float]:
        """The principal moments ``(Ix, Iy, Iz)``."""
        return self._core.inertia

    @property
    def intermediate_axis(self) -> int | None:
        """The axis (0, 1, 2 for x, y, z) of the intermediate moment, about which spin is
        unstable; None for a symmetric top (two equal moments)."""
        return self._core.intermediate_axis

    def __repr__(self) -> str:
        return f"Body(inertia={self.inertia!r})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Body) and self.inertia == other.inertia

    def __hash__(self) -> int:
        return hash(self.inertia)


def as_body(value: Any, name: str = "body") -> Body:
    """`value` if a Body, else the Body of the principal moments it holds; a failure names
    `name` as well as the moments."""
    if isinstance(value, Body):
        return value
    try:
        return Body(value)
    except (TypeError, ValueError) as exc:
        raise type(exc)(f"`{name}` must be a Body or its principal moments (Ix, Iy, Iz): "
                        f"{exc}") from None


def _warn_if_unphysical(core: _core.RigidBody) -> None:
    if not core.satisfies_triangle_inequality:
        warnings.warn(
            f"principal moments {core.inertia} break the triangle inequality "
            "(each moment of a real body is at most the sum of the other two); "
            "no mass distribution has them",
            InertiaWarning,
            stacklevel=3,
        )
