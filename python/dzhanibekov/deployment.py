"""Deployments: a body whose inertia tensor changes in a prescribed, smooth way while it turns."""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _core
from ._args import as_array, as_float, check_size
from .body import Body
from .torques import knot_fraction

__all__ = ["Deployment"]


def _as_tensor(k: int, value: Any) -> np.ndarray:
    """The 3 × 3 tensor of knot `k`: a Body (its tensor, or its principal moments), three
    principal moments, or a 3 × 3 tensor."""
    if isinstance(value, Body):
        tensor = getattr(value, "tensor", None)
        return np.array(tensor if tensor is not None else np.diag(value.inertia), dtype=float)
    try:
        a = np.asarray(value, dtype=object)
    except Exception as exc:  # ragged nesting and the like
        raise TypeError(f"`inertia[{k}]` must be a Body, three moments or a 3 × 3 tensor: "
                        f"{exc}") from None
    if a.shape == (3,):
        return np.diag(as_array(f"inertia[{k}]", value, "(3,)", last=3, ndim=(1,)))
    if a.shape == (3, 3):
        return as_array(f"inertia[{k}]", value, "(3, 3)", last=3, ndim=(2,)).copy()
    raise ValueError(f"`inertia[{k}]` must be a Body, three principal moments or a 3 × 3 "
                     f"tensor, got shape {a.shape}")


BYTES_PER_KNOT = 8 * (1 + 4 * 9)
"""Memory a knot takes while a deployment is built: its time and a few copies of its tensor
(the stacked input, the core's, the arrays it returns), checked against the machine's memory
before anything is allocated."""


def _tensors(inertia: Any, n: int) -> np.ndarray:
    """The knots' tensors (n, 3, 3): an array (or a sequence) of moments (n, 3) or tensors
    (n, 3, 3) stacked at once, else item by item (Bodies, mixed kinds). The core checks them
    (symmetric, positive definite, finite) and names the first bad knot."""
    try:
        if isinstance(inertia, (str, bytes)):
            raise TypeError
        items = inertia if isinstance(inertia, np.ndarray) else list(inertia)
        knots = len(items)
    except TypeError:  # not a sequence: a number, a 0-d array
        raise TypeError(f"`inertia` must be a sequence of bodies, moments or tensors, got "
                        f"{type(inertia).__name__}") from None
    if knots != n:
        raise ValueError(f"`inertia` must give one body per knot time of `times` ({n}), got "
                         f"{knots}")
    if not knots:
        raise ValueError("`times` must hold at least one knot time")
    stacked = None
    if isinstance(items, np.ndarray) or not any(isinstance(v, Body) for v in items):
        try:
            arr = np.asarray(items)
        except (ValueError, TypeError):  # ragged: item by item says which
            arr = None
        if arr is not None and arr.dtype.kind in "iuf" and arr.shape[1:] in ((3,), (3, 3)):
            stacked = np.require(arr, dtype=np.float64, requirements=["C", "A"])
    if stacked is None:
        return np.ascontiguousarray(np.stack([_as_tensor(k, v) for k, v in enumerate(items)]))
    if stacked.ndim == 2:  # principal moments
        out = np.zeros((n, 3, 3))
        out[:, [0, 1, 2], [0, 1, 2]] = stacked
        return out
    return stacked


class Deployment:
    """A body whose inertia tensor moves smoothly between knots while it turns freely.

    Between knots ``t_k < t_{k+1}`` the tensor is ``I_k + s(τ) (I_{k+1} − I_k)`` with
    ``τ = (t − t_k) / (t_{k+1} − t_k)`` and the quintic ``s(τ) = 10τ³ − 15τ⁴ + 6τ⁵`` (zero rate
    and acceleration at every knot); before the first knot and after the last it is constant.
    With no external torque, ``dL/dt = L × ω`` with ``ω = I(t)⁻¹ L`` in body axes: the angular
    momentum is fixed in space and the energy changes by the internal work,
    ``dE/dt = −½ ωᵀ İ ω``. The moving parts are assumed to carry no angular momentum of their
    own relative to the body (symmetric deployments), and its mass centre stays where it is
    in the body.

    Parameters
    ----------
    times : array_like, shape (K,)
        Knot times, finite and strictly increasing.
    inertia : sequence of K items
        The body at each knot: a :class:`Body`, its principal moments ``(Ix, Iy, Iz)``, or a
        symmetric positive definite 3 × 3 tensor in body axes (products of inertia with a
        minus sign off the diagonal).
    mass : float, optional
        The deploying body's mass, constant while it deploys: parts whose mass moves in it
        (a :class:`SpringMassDamper`, a :class:`Hinge`, a :class:`Slosh`) need it, as they
        need a :class:`Body`'s. The tensors are then the body's own about its mass centre,
        without those parts; the system's mass centre moves in the body as they move.

    Raises
    ------
    TypeError
        Knots or bodies of the wrong kind.
    ValueError
        Knots that are not increasing, tensors that are not symmetric positive definite, or
        as many bodies as times not given (checked by the core).

    Examples
    --------
    >>> d = Deployment([10.0, 20.0], [(1.0, 2.0, 3.0), (1.0, 3.0, 2.0)])
    >>> d.inertia_at(15.0).diagonal().tolist()
    [1.0, 2.5, 2.5]

    A tank on a body that deploys: the body's mass carries it.

    >>> import dzhanibekov as dz
    >>> body = Deployment([10.0, 20.0], [(1.0, 2.0, 3.0), (1.0, 3.0, 2.0)], mass=1.0)
    >>> tank = dz.Slosh(0.05, (0.0, 0.0, 0.5), 0.3, 0.01, (1.0, 0.0, 0.0))
    >>> dz.System(body, parts=[tank]).kinds
    ('deployment', 'slosh')
    """

    __slots__ = ("times", "tensors", "mass", "_core")

    times: np.ndarray
    """Knot times, shape (K,)."""
    tensors: np.ndarray
    """Knot tensors, shape (K, 3, 3)."""
    mass: float | None
    """The body's mass (None: not given)."""

    def __init__(self, times: Any, inertia: Any, mass: float | None = None) -> None:
        try:
            n = len(times)
        except TypeError:
            raise TypeError(f"`times` must be a sequence of knot times, got "
                            f"{type(times).__name__}") from None
        check_size(n * BYTES_PER_KNOT, f"a deployment of {n} knots", "give fewer knots")
        t = as_array("times", times, "(K,)", last=n, ndim=(1,))
        tensors = _tensors(inertia, len(t))
        self._core = _core.Deployment(np.ascontiguousarray(t, dtype=np.float64), tensors)
        self.times = np.ascontiguousarray(self._core.times)
        self.tensors = np.ascontiguousarray(self._core.tensors)
        self.mass = None if mass is None else as_float("mass", mass, positive=True)

    def __reduce__(self) -> tuple[Any, ...]:
        return (Deployment, (self.times, self.tensors, self.mass))

    def inertia_at(self, t: float) -> np.ndarray:
        """The tensor ``I(t)``, shape (3, 3) (a convenience for plots: runs evaluate the
        law in the core)."""
        k = int(np.searchsorted(self.times, t, side="right"))
        tensors: np.ndarray = self.tensors
        if k == 0:
            return np.array(tensors[0])
        if k == len(self.times):
            return np.array(tensors[-1])
        tau = knot_fraction(float(t), float(self.times[k - 1]), float(self.times[k]))
        s = tau**3 * (10 - 15 * tau + 6 * tau**2)
        return np.array(tensors[k - 1] + s * (tensors[k] - tensors[k - 1]))

    def __repr__(self) -> str:
        mass = "" if self.mass is None else f", mass={self.mass!r}"
        return f"Deployment(times={self.times.tolist()}, knots={len(self.times)}{mass})"

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Deployment):
            return NotImplemented  # a System without parts compares with its deployment
        return (np.array_equal(self.times, other.times)
                and np.array_equal(self.tensors, other.tensors) and self.mass == other.mass)

    def __hash__(self) -> int:
        return hash((self.times.tobytes(), self.tensors.tobytes(), self.mass))

