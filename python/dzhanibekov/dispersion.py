"""Dispersions: physical bodies, deployments and dampers drawn around nominal ones.

A dispersion is a callable ``rng -> value`` (``rng`` a :class:`numpy.random.Generator`),
which is what :func:`~dzhanibekov.monte_carlo` takes for its `system`. The ones here draw
what an engineer does not know exactly, with the distributions stated:

- :class:`InertiaDispersion`: a body's principal moments, each with a relative spread, and
  its principal axes turned by a small random rotation; every body drawn is physical
  (positive moments, the triangle inequality kept).
- :class:`DeploymentDispersion`: a deployment's timing (its start and its duration) and the
  body at each of its knots (as :class:`InertiaDispersion` draws them).
- :class:`DamperDispersion`: a damper's sphere inertia and viscous coefficient.
- :class:`PartDispersion`: any part's parameters by name (a hinge's damping, a spring's
  stiffness, …, every model of ``dz.MODELS``), in a whole system.

Each draws its random numbers from the generator it is given, in a fixed order, so that the
same generator state gives the same value.

>>> import numpy as np, dzhanibekov as dz
>>> disperse = dz.InertiaDispersion(dz.Body((1.0, 2.0, 2.5)), moments=0.05, axes_deg=1.0)
>>> body = disperse(np.random.default_rng(1))
>>> [round(i, 3) for i in body.inertia]
[1.017, 2.082, 2.541]
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np

from . import _core
from ._args import as_array, as_float
from .body import Body, InertiaWarning, as_body
from .damper import Damper
from .deployment import Deployment
from .parts import Part, from_fields, params_of
from .system import System

__all__ = ["InertiaDispersion", "DeploymentDispersion", "DamperDispersion", "PartDispersion",
           "MAX_REDRAWS"]

MAX_REDRAWS = 1000
"""Draws a dispersion makes for one value before it gives up: more means the nominal value
sits so near the edge of what is physical (a moment near zero, a flat plate's
``I_z = I_x + I_y``) that the spread asked for mostly leaves it."""


def _spread(name: str, value: Any) -> np.ndarray:
    """Three relative (or angular) standard deviations, non-negative and finite: one number
    for all three, or one each."""
    if np.ndim(value) == 0:
        s = as_float(name, value)
        arr = np.full(3, s)
    else:
        arr = as_array(name, value, "(3,) or a number", last=3, ndim=(1,))
    if (arr < 0).any():
        raise ValueError(f"`{name}` must be non-negative, got {arr.tolist()}")
    return arr


def _physical(moments: np.ndarray) -> bool:
    """Positive moments that keep the triangle inequality (within the core's slack): the
    moments of some mass distribution."""
    a, b, c = (float(m) for m in moments)
    total = a + b + c
    return a > 0 and b > 0 and c > 0 and 2 * max(a, b, c) <= total + _core.TRIANGLE_SLACK * total


def _rotation(rotvec: np.ndarray) -> np.ndarray:
    """The rotation matrix of a rotation vector (Rodrigues' formula)."""
    x, y, z = rotvec.tolist()
    angle = math.sqrt(x * x + y * y + z * z)
    if angle == 0.0:
        return _EYE.copy()
    x, y, z = x / angle, y / angle, z / angle
    k = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    turn: np.ndarray = _EYE + math.sin(angle) * k + (1.0 - math.cos(angle)) * (k @ k)
    return turn


_EYE = np.eye(3)


class _Moments:
    """Draws principal moments and axes around nominal ones (the law of
    :class:`InertiaDispersion`)."""

    __slots__ = ("moments", "axes", "spread", "axes_rad")

    def __init__(self, moments: np.ndarray, axes: np.ndarray, spread: np.ndarray,
                 axes_deg: np.ndarray) -> None:
        self.moments = moments
        self.axes = axes
        self.spread = spread
        self.axes_rad = np.radians(axes_deg)

    def draw(self, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
        """Moments (3,) and principal axes (columns of a proper rotation, user axes from
        principal)."""
        for _ in range(MAX_REDRAWS):
            moments = self.moments * (1.0 + self.spread * rng.standard_normal(3))
            if _physical(moments):
                break
        else:
            raise ValueError(
                f"the moments {self.moments.tolist()} dispersed by a relative spread of "
                f"{self.spread.tolist()} gave no physical body (positive moments, each at most "
                f"the sum of the other two) in {MAX_REDRAWS} draws: the nominal body sits at "
                "the edge of what is physical; take a smaller spread")
        if not self.axes_rad.any():
            return moments, self.axes
        turn = _rotation(self.axes_rad * rng.standard_normal(3))
        return moments, self.axes @ turn

    def tensor(self, rng: np.random.Generator) -> np.ndarray:
        """A drawn tensor in the user's axes, ``R diag(I) Rᵀ``."""
        moments, axes = self.draw(rng)
        tensor: np.ndarray = (axes * moments) @ axes.T
        symmetric: np.ndarray = 0.5 * (tensor + tensor.T)
        return symmetric


class InertiaDispersion:
    """Physical bodies drawn around a nominal body: its principal moments each with a
    relative spread, its principal axes turned by a small random rotation.

    The law, per draw (the random numbers taken from the generator in this order):

    - **moments**: ``I'_k = I_k (1 + s_k Z_k)``, ``Z_k`` independent standard normal, for the
      nominal principal moments ``I_k``. Draws with a moment that is not positive or that
      break the triangle inequality (``I'_k ≤ I'_i + I'_j``, which every mass distribution
      keeps) are drawn again, all three: a normal law truncated to physical bodies. For a
      body at least four spreads from those edges the truncation removes less than one
      draw in 10⁴ and leaves the mean and the spread as asked.
    - **axes** (if `axes_deg` > 0): a rotation vector ``θ`` with independent normal
      components of standard deviation `axes_deg` (in degrees), in the nominal principal
      axes; the drawn principal axes are ``A · R(θ)`` for the nominal ones ``A``. The angle
      turned, ``|θ|``, follows a Maxwell law: mean ``1.60 ·`` `axes_deg`, and below
      ``2.5 ·`` `axes_deg` in 80% of draws (a χ law with three degrees of freedom).

    Parameters
    ----------
    body : Body or array_like, shape (3,)
        The nominal body (its principal moments and axes), or its principal moments.
    moments : float or array_like, shape (3,)
        Relative standard deviation of each principal moment (one for all, or one per moment
        in the order of ``body.inertia``), non-negative; 0.05 is 5%.
    axes_deg : float
        Standard deviation of each component of the rotation vector of the axes, degrees,
        non-negative.

    Returns
    -------
    A callable ``rng -> Body``: a :class:`~dzhanibekov.Body` with the moments drawn, in the
    nominal order, when the axes are not dispersed and the nominal body is given in its
    principal axes; else the body of the drawn tensor in the nominal body's own axes
    (:meth:`Body.from_tensor`, its moments in the order of the principal axes nearest the
    nominal body's axes, as :attr:`Body.inertia` always is).

    Raises
    ------
    TypeError, ValueError
        A body that is not one, or a negative or non-finite spread. A draw raises
        ValueError when :data:`MAX_REDRAWS` draws give no physical body.

    Examples
    --------
    >>> import numpy as np, dzhanibekov as dz
    >>> disperse = dz.InertiaDispersion((1.0, 2.0, 2.5), moments=0.02)
    >>> rng = np.random.default_rng(0)
    >>> bodies = [disperse(rng) for _ in range(2000)]
    >>> inertia = np.array([b.inertia for b in bodies])
    >>> np.round(inertia.mean(axis=0), 2), np.round(inertia.std(axis=0) / (1, 2, 2.5), 3)
    (array([1. , 2. , 2.5]), array([0.02, 0.02, 0.02]))

    A body at the edge, such as ``(1, 2, 3)`` (a flat plate: ``3 = 1 + 2``), loses the draws
    beyond it: its moments come out pulled inside, their spread smaller than asked.
    """

    __slots__ = ("body", "moments", "axes_deg", "_law")

    def __init__(self, body: Any, moments: Any = 0.0, axes_deg: Any = 0.0) -> None:
        self.body = as_body(body)
        self.moments = _spread("moments", moments)
        self.axes_deg = as_float("axes_deg", axes_deg)
        if self.axes_deg < 0:
            raise ValueError(f"`axes_deg` must be non-negative, got {self.axes_deg!r}")
        self._law = _Moments(np.array(self.body.inertia, dtype=np.float64),
                             self.body.principal_axes, self.moments,
                             np.full(3, self.axes_deg))

    def __call__(self, rng: np.random.Generator) -> Body:
        moments, axes = self._law.draw(rng)
        with warnings.catch_warnings():
            # draws are physical (redrawn until they are); one that lands within
            # NEAR_SYMMETRY of a symmetric top is a sample like any other, not a mistake
            warnings.simplefilter("ignore", InertiaWarning)
            if self.axes_deg == 0.0 and self.body.is_principal:
                return Body(moments)
            tensor = (axes * moments) @ axes.T
            return Body.from_tensor(0.5 * (tensor + tensor.T))

    def __repr__(self) -> str:
        return (f"InertiaDispersion({self.body!r}, moments={self.moments.tolist()}, "
                f"axes_deg={self.axes_deg!r})")


class DeploymentDispersion:
    """Deployments drawn around a nominal one: its timing and the body at each knot.

    The law, per draw (random numbers in this order):

    - **start**: every knot time shifted by ``Δ ~ N(0, start²)`` (time units);
    - **duration**: the knots after the first stretched about it by ``S = 1 + duration · Z``,
      ``Z`` standard normal, drawn again while ``S ≤ 0``: ``t'_k = t_0 + Δ + S (t_k − t_0)``;
    - **bodies**: each knot's body, first to last, drawn as :class:`InertiaDispersion` draws
      it around the nominal knot body with `moments` and `axes_deg` (independently per knot).

    Parameters
    ----------
    deployment : Deployment
        The nominal deployment.
    start : float
        Standard deviation of the shift of the whole schedule, in time units, non-negative.
    duration : float
        Relative standard deviation of the time from the first knot to each later one,
        non-negative (0.1 is 10%).
    moments, axes_deg
        As for :class:`InertiaDispersion`, applied to every knot's body.

    Returns
    -------
    A callable ``rng -> Deployment``.

    Examples
    --------
    >>> import numpy as np, dzhanibekov as dz
    >>> nominal = dz.Deployment([100.0, 110.0], [(1, 2, 2.5), (1, 2.5, 2)])
    >>> disperse = dz.DeploymentDispersion(nominal, start=5.0, duration=0.1, moments=0.02)
    >>> d = disperse(np.random.default_rng(3))
    >>> np.round(d.times, 2)
    array([110.2 , 117.65])
    """

    __slots__ = ("deployment", "start", "duration", "moments", "axes_deg", "_laws")

    def __init__(self, deployment: Deployment, *, start: Any = 0.0, duration: Any = 0.0,
                 moments: Any = 0.0, axes_deg: Any = 0.0) -> None:
        if not isinstance(deployment, Deployment):
            raise TypeError(f"`deployment` must be a dz.Deployment, got "
                            f"{type(deployment).__name__}")
        self.deployment = deployment
        self.start = as_float("start", start)
        self.duration = as_float("duration", duration)
        for name, value in (("start", self.start), ("duration", self.duration)):
            if value < 0:
                raise ValueError(f"`{name}` must be non-negative, got {value!r}")
        self.moments = _spread("moments", moments)
        self.axes_deg = as_float("axes_deg", axes_deg)
        if self.axes_deg < 0:
            raise ValueError(f"`axes_deg` must be non-negative, got {self.axes_deg!r}")
        self._laws = []
        for tensor in deployment.tensors:
            moments_k, axes_k = np.linalg.eigh(tensor)
            if np.linalg.det(axes_k) < 0:
                axes_k[:, 0] = -axes_k[:, 0]
            self._laws.append(_Moments(moments_k, axes_k, self.moments, np.full(3, self.axes_deg)))

    def __call__(self, rng: np.random.Generator) -> Deployment:
        times = self.deployment.times
        shift = self.start * rng.standard_normal() if self.start else 0.0
        stretch = 1.0
        if self.duration:
            for _ in range(MAX_REDRAWS):
                stretch = 1.0 + self.duration * rng.standard_normal()
                if stretch > 0:
                    break
            else:
                raise ValueError(f"`duration` {self.duration!r} gave no positive stretch of the "
                                 f"schedule in {MAX_REDRAWS} draws; take a smaller one")
        drawn = times[0] + shift + stretch * (times - times[0])
        if self.moments.any() or self.axes_deg:
            tensors = [law.tensor(rng) for law in self._laws]
        else:
            tensors = list(self.deployment.tensors)
        return Deployment(drawn, tensors, self.deployment.mass)

    def __repr__(self) -> str:
        return (f"DeploymentDispersion({self.deployment!r}, start={self.start!r}, "
                f"duration={self.duration!r}, moments={self.moments.tolist()}, "
                f"axes_deg={self.axes_deg!r})")


class DamperDispersion:
    """Dampers drawn around a nominal one: ``j' = j (1 + s_j Z_1)``, ``c' = c (1 + s_c Z_2)``
    with ``Z_1, Z_2`` independent standard normal (in this order), each drawn again while the
    value is not positive (a normal law truncated to physical dampers).

    Parameters
    ----------
    damper : Damper
        The nominal damper (its sphere's start, ``sigma0``, is every drawn damper's).
    inertia, damping : float
        Relative standard deviations of the sphere's moment of inertia and of the viscous
        coefficient, non-negative.

    Returns
    -------
    A callable ``rng -> Damper``: a part of a :class:`~dzhanibekov.System`.

    Examples
    --------
    >>> import numpy as np, dzhanibekov as dz
    >>> disperse = dz.DamperDispersion(dz.Damper(0.05, 0.02), damping=0.2)
    >>> damper = disperse(np.random.default_rng(0))
    >>> damper.inertia, round(damper.damping, 6)
    (0.05, 0.020503)
    """

    __slots__ = ("damper", "inertia", "damping")

    def __init__(self, damper: Damper, *, inertia: Any = 0.0, damping: Any = 0.0) -> None:
        if not isinstance(damper, Damper):
            raise TypeError(f"`damper` must be a dz.Damper, got {type(damper).__name__}")
        self.damper = damper
        self.inertia = as_float("inertia", inertia)
        self.damping = as_float("damping", damping)
        for name, value in (("inertia", self.inertia), ("damping", self.damping)):
            if value < 0:
                raise ValueError(f"`{name}` must be non-negative, got {value!r}")

    def __call__(self, rng: np.random.Generator) -> Damper:
        return Damper(_positive(self.damper.inertia, self.inertia, rng, "inertia"),
                      _positive(self.damper.damping, self.damping, rng, "damping"),
                      self.damper.sigma0)

    def __repr__(self) -> str:
        return (f"DamperDispersion({self.damper!r}, inertia={self.inertia!r}, "
                f"damping={self.damping!r})")


class PartDispersion:
    """Systems drawn around a nominal one, with parameters of its parts dispersed by name: a
    hinged antenna's damping, a spring–mass damper's stiffness, a damper's ``c``, … any
    number parameter of any model of ``dz.MODELS``.

    The law, per draw (random numbers in this order): the system (if `system` is itself
    drawn), then for each part dispersed, in the system's order, each parameter dispersed,
    in the order of the model's parameters (``dz.MODELS[model].params``):

    - a number ``s``: ``p' = p (1 + s Z)``, ``Z`` standard normal, drawn again while ``p'``
      is not positive (a normal law truncated to positive values, as
      :class:`DamperDispersion` draws); a parameter that is 0 stays 0;
    - a callable ``rng -> value`` or a scipy.stats distribution (``.rvs(random_state=rng)``):
      the value it gives (the core checks it, as for any part).

    Parameters
    ----------
    system : System, or callable ``rng -> System``
        The nominal system, or a dispersion drawing one (its draw comes first).
    part : int or str
        Which parts: an index into ``system.parts + system.torques`` (the order of the
        system's parts in results and files), or a model's name (every part of that model:
        Explorer 1's four whips, ``"hinge"``).
    shared : bool
        With a model's name: draw each parameter once for all its parts (one design whose
        value is uncertain) rather than once per part (default: each its own).
    **spreads : float, callable or distribution
        By the parameter's name (a number parameter of the part's model): a relative
        standard deviation (non-negative), or what draws the value.

    Returns
    -------
    A callable ``rng -> System``: what :func:`~dzhanibekov.monte_carlo` takes as `system`.

    Raises
    ------
    TypeError, ValueError
        A system that is not one, a part it does not have, a parameter its model does not
        have as a number, a negative or non-finite spread. A draw raises ValueError when
        :data:`MAX_REDRAWS` draws give no positive value, or when the core refuses a drawn
        value.

    Examples
    --------
    >>> import numpy as np, dzhanibekov as dz
    >>> rod = dz.System(dz.Body.cylinder(0.3, 1.5, mass=10.0), parts=[dz.Hinge(
    ...     0.1, (1e-4, 0.01, 0.01), (0.3, 0.0, 0.0), (0.0, 1.0, 0.0), (1.0, 0.0, 0.0), 0.5,
    ...     stiffness=1.0, damping=0.05)])
    >>> disperse = dz.PartDispersion(rod, "hinge", damping=lambda rng: rng.uniform(0, 0.1))
    >>> round(disperse(np.random.default_rng(0)).parts[0].damping, 4)
    0.0637
    """

    __slots__ = ("system", "part", "spreads", "shared")

    def __init__(self, system: Any, part: Any, *, shared: bool = False, **spreads: Any) -> None:
        if not isinstance(shared, bool):
            raise TypeError(f"`shared` must be True or False, got {shared!r}")
        self.shared = shared
        if not isinstance(system, System) and not callable(system):
            raise TypeError(f"`system` must be a dz.System or a callable rng -> dz.System, got "
                            f"{type(system).__name__}")
        if isinstance(part, bool) or not isinstance(part, (int, np.integer, str)):
            raise TypeError(f"`part` must be an index of the system's parts or a model's name, "
                            f"got {type(part).__name__}")
        if not spreads:
            raise ValueError("give at least one parameter to disperse, by its name "
                             "(e.g. damping=0.2)")
        self.system = system
        self.part: int | str = part if isinstance(part, str) else int(part)
        self.spreads: dict[str, Any] = {}
        for name, value in spreads.items():
            if hasattr(value, "rvs") or callable(value):
                self.spreads[name] = value
                continue
            spread = as_float(name, value)
            if spread < 0:
                raise ValueError(f"`{name}` must be a non-negative relative spread, a callable "
                                 f"rng -> value or a distribution, got {spread!r}")
            self.spreads[name] = spread
        if isinstance(system, System):
            self._targets(system)   # the part and its parameters, checked now

    def _targets(self, system: System) -> list[int]:
        """The places of the parts dispersed in ``system.parts + system.torques``, checked
        with the parameters."""
        every = (*system.parts, *system.torques)
        if isinstance(self.part, str):
            places = [k for k, p in enumerate(every) if p.model == self.part]
            if not places:
                held = sorted({p.model for p in every}) or ["none"]
                raise ValueError(f"`part` {self.part!r} names no part of the system (its "
                                 f"models: {', '.join(held)})")
        else:
            if not -len(every) <= self.part < len(every):
                raise ValueError(f"`part` must be an index of the system's {len(every)} parts "
                                 f"(parts, then torques), got {self.part}")
            places = [self.part % len(every)]
        for k in places:
            model = every[k].model
            numbers = [p.name for p in params_of(model) if p.kind == "scalar"]
            for name in self.spreads:
                if name not in numbers:
                    raise ValueError(f"`{name}` is no number parameter of a {model} part (its "
                                     f"number parameters: {', '.join(numbers) or 'none'})")
        return places

    def __call__(self, rng: np.random.Generator) -> System:
        system = self.system
        if not isinstance(system, System):
            system = system(rng)
            if not isinstance(system, System):
                raise TypeError(f"`system` must give a dz.System, gave "
                                f"{type(system).__name__}")
        every: list[Part] = [*system.parts, *system.torques]
        drawn: dict[str, Any] = {}   # the values drawn once, for `shared`
        for k in self._targets(system):
            part = every[k]
            fields = dict(part.fields())
            for p in params_of(part.model):
                if p.name not in self.spreads:
                    continue
                how = self.spreads[p.name]
                if self.shared and p.name in drawn:
                    fields[p.name] = drawn[p.name]
                elif isinstance(how, float):
                    fields[p.name] = _positive(fields[p.name], how, rng, p.name)
                else:
                    fields[p.name] = how.rvs(random_state=rng) if hasattr(how, "rvs") \
                        else how(rng)
                drawn[p.name] = fields[p.name]
            every[k] = from_fields(part.model, fields)
        n = len(system.parts)
        return System(system.body, parts=every[:n], torques=every[n:])

    def __repr__(self) -> str:
        spreads = ", ".join(f"{k}={v!r}" for k, v in self.spreads.items())
        shared = ", shared=True" if self.shared else ""
        return f"PartDispersion({self.system!r}, {self.part!r}{shared}, {spreads})"


def _positive(nominal: float, spread: float, rng: np.random.Generator, name: str) -> float:
    """``nominal (1 + spread Z)``, drawn again while not positive (`nominal` itself if there
    is no spread)."""
    if not spread or nominal == 0:
        return nominal
    for _ in range(MAX_REDRAWS):
        value = nominal * (1.0 + spread * float(rng.standard_normal()))
        if value > 0:
            return value
    raise ValueError(f"`{name}` spread {spread!r} gave no positive value in {MAX_REDRAWS} "
                     "draws; take a smaller one")
