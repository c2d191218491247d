"""Stability where wheels and orbits decide it: maps computed by runs, beside their closed forms.

- :func:`dual_spin_map`: a spin about each principal axis with a wheel along it, over the
  wheel's momentum ``h``; the largest angle of the body's rate from the spin axis after a
  small nudge,
  against :func:`~dzhanibekov.dual_spin_threshold` (unstable for ``h`` strictly inside its
  interval).
- :func:`gravity_gradient_map`: a body at rest in the orbiting frame (LVLH), nudged, over the
  moment ratios ``(k1, k3)``; the largest angle from LVLH over some orbits, against the
  closed-form regions of :func:`gravity_gradient_region` (Lagrange, DeBra–Delp).

Every map is one batch of runs (:func:`~dzhanibekov.simulate` of a list of systems: all
cores, the core's speed); the figures are in :mod:`dzhanibekov.plotting.stability`.

**The moment ratios** (Hughes, *Spacecraft Attitude Dynamics*, 1986, §9.3; DeBra & Delp,
"Rigid body attitude stability and natural frequencies in a circular orbit", *J. Astronaut.
Sci.* 8, 1961). The body's principal axes at the equilibrium are along the LVLH axes of
:mod:`dzhanibekov.lvlh`: ``x`` along-track (roll, moment ``I1``), ``y`` minus the orbit
normal (pitch, ``I2``), ``z`` nadir (yaw, ``I3``); so ``Body((I1, I2, I3))`` started with
:func:`~dzhanibekov.lvlh_start` is aligned. Then

.. code-block:: text

    k1 = (I2 − I3) / I1        k3 = (I2 − I1) / I3          (|k1|, |k3| < 1 for a body)

and the linearised motion about LVLH is stable (all roots on the imaginary axis) where

.. code-block:: text

    pitch:     I2 θ'' + 3 n² (I1 − I3) θ = 0         stable iff I1 > I3, i.e. k1 > k3
    roll–yaw:  s⁴ + (1 + 3 k1 + k1 k3) n² s² + 4 k1 k3 n⁴ = 0
               stable iff k1 k3 > 0, 1 + 3 k1 + k1 k3 > 0, (1 + 3 k1 + k1 k3)² > 16 k1 k3

The **Lagrange region** (``k1 > k3 > 0``: ``I2 > I1 > I3``, the pitch axis the major one, yaw
the minor) is stable with the Jacobi integral a minimum there; the **DeBra–Delp region**
(``k3 < k1 < 0`` and the roll–yaw conditions) is stable only gyroscopically.

>>> import dzhanibekov as dz
>>> dz.gravity_gradient_region([0.5, -0.05, 0.1], [0.2, -0.5, 0.5]).tolist()
['lagrange', 'debra_delp', 'unstable']
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._args import as_float, as_int
from .body import Body
from .lvlh import lvlh_attitude, lvlh_start
from .methods import METHODS
from .orbit import GravityGradient, Wheel, dual_spin_threshold
from .results import Batch
from .simulate import rotate, simulate
from .system import System

__all__ = ["dual_spin_map", "DualSpinMap", "gravity_gradient_map", "GravityGradientMap",
           "gravity_gradient_region", "gravity_gradient_moments", "REGIONS"]

REGIONS = ("lagrange", "debra_delp", "unstable")
"""What :func:`gravity_gradient_region` calls the parts of the ``(k1, k3)`` plane."""

MAX_MAP_RUNS = 1_000_000
"""The most runs a map takes (a map is one batch: its frames are kept until measured)."""


def _values(name: str, value: Any, *, low: float = -math.inf, high: float = math.inf,
            open_: bool = False) -> np.ndarray:
    """A non-empty 1-D array of finite reals (a scalar is one value) within (low, high)."""
    if isinstance(value, (str, bytes)) or value is None:
        raise TypeError(f"`{name}` must be numbers, got {value!r}")
    try:
        a = np.asarray(value)
    except Exception as exc:
        raise TypeError(f"`{name}` must be numbers: {exc}") from None
    if a.dtype.kind == "b" or a.dtype.kind not in "iuf":
        raise TypeError(f"`{name}` must hold real numbers, got dtype {a.dtype}")
    a = np.atleast_1d(a.astype(np.float64))
    if a.ndim != 1 or a.size == 0:
        raise ValueError(f"`{name}` must be a number or a 1-D array of them, got shape "
                         f"{np.shape(value)}")
    if not np.isfinite(a).all():
        raise ValueError(f"`{name}` must be finite")
    if a.size > MAX_MAP_RUNS:
        raise ValueError(f"`{name}` must have at most {MAX_MAP_RUNS} values, got {a.size}")
    inside = (a > low) & (a < high) if open_ else (a >= low) & (a <= high)
    if not inside.all():
        bad = float(a[~inside][0])
        bounds = f"({low:g}, {high:g})" if open_ else f"[{low:g}, {high:g}]"
        raise ValueError(f"`{name}` must lie in {bounds}, got {bad!r}")
    return a


def _angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The angle between vectors (…, 3), to full precision near 0 and π."""
    angle: np.ndarray = np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1),
                                   np.einsum("...i,...i", a, b))
    return angle


def _axes(axes: Any) -> tuple[int, ...]:
    if isinstance(axes, (int, np.integer)) and not isinstance(axes, bool):
        axes = (axes,)
    if isinstance(axes, (str, bytes)) or not isinstance(axes, (tuple, list)) or not axes:
        raise TypeError(f"`axes` must be a sequence of principal axes 0, 1, 2, got {axes!r}")
    for k in axes:
        if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k not in (0, 1, 2):
            raise ValueError(f"`axes` must hold principal axes 0, 1 or 2, got {k!r}")
    if len(set(int(k) for k in axes)) != len(axes):
        raise ValueError(f"`axes` must not repeat an axis, got {tuple(axes)}")
    return tuple(int(k) for k in axes)


# -- dual spin ------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class DualSpinMap:
    """What :func:`dual_spin_map` measured: per spin axis and wheel momentum, the largest
    angle of the body's angular velocity from the spin axis.

    Attributes
    ----------
    inertia : tuple of float
        The principal moments.
    rate : float
        The spin rate ``Ω``.
    axes : tuple of int
        The spin axes, one row each.
    momenta : ndarray, shape (H,)
        The wheel momenta ``h`` (along the spin axis), one column each.
    departure : ndarray, shape (len(axes), H)
        The largest angle (rad) between the body's angular velocity ω and the spin axis
        (body axes; π when the spin reverses) over the run.
    thresholds : ndarray, shape (len(axes), 2)
        :func:`~dzhanibekov.dual_spin_threshold` of each axis: the open interval of unstable
        ``h``.
    limit : float
        The departure (rad) above which a run counts as departed (:attr:`stable`).
    nudge, t_end : float
        The transverse rates of the start, and the length of each run.
    """

    inertia: tuple[float, float, float]
    rate: float
    axes: tuple[int, ...]
    momenta: np.ndarray
    departure: np.ndarray
    thresholds: np.ndarray
    limit: float
    nudge: float
    t_end: float

    @property
    def stable(self) -> np.ndarray:
        """Whether each run's spin axis stayed within :attr:`limit` of its start."""
        return np.asarray(self.departure < self.limit)

    @property
    def predicted(self) -> np.ndarray:
        """The closed form's verdict: ``h`` outside each axis's unstable interval."""
        low, high = self.thresholds[:, :1], self.thresholds[:, 1:]
        return np.asarray((self.momenta <= low) | (self.momenta >= high))

    def __repr__(self) -> str:
        return (f"DualSpinMap(axes={self.axes}, momenta={len(self.momenta)}, "
                f"stable={int(self.stable.sum())}/{self.stable.size})")


def dual_spin_map(inertia: Any, momenta: Any, *, axes: Any = (0, 1, 2), rate: Any = 1.0,
                  nudge: Any = 1e-4, t_end: Any = None, frames: Any = 401,
                  method: str = "dop853", dt: Any = None, limit: Any = 0.03) -> DualSpinMap:
    """The dual-spin stability map over (spin axis, wheel momentum), computed by runs.

    For each spin axis ``k`` in `axes` and each ``h`` in `momenta`, a body of principal
    moments `inertia` with a :class:`~dzhanibekov.Wheel` of momentum ``h`` along ``e_k``
    starts spinning at ``ω = Ω e_k`` plus `nudge` about each other axis (one batch of runs);
    the map is the largest angle of the body's angular velocity from the spin axis ``e_k``
    (body axes). A spin the wheel stabilises wobbles by about the nudge; an unstable one
    departs by far more than `limit` (a flip reverses the spin: π; 1 % of ``h`` inside the
    unstable interval, 0.1 rad and more for moments of order one). (The spin axis's tilt in
    space would not do: at ``h = −I_k Ω`` the total angular momentum along it vanishes and a
    stable spin's axis wanders in space.) The closed form's interval
    (:func:`~dzhanibekov.dual_spin_threshold`) goes with the map.

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments.
    momenta : array_like, shape (H,)
        Wheel momenta ``h``, finite.
    axes : sequence of int
        Spin axes (0, 1, 2), one row of the map each.
    rate : float
        The spin rate ``Ω``, not zero.
    nudge : float
        The start's transverse rates, as a fraction of ``|Ω|``: positive, below 1.
    t_end : float, optional
        Each run's length; by default 400 / ``|Ω|`` (about 64 turns), which shows a departure
        growing at 1 % of ``h`` from the threshold of a body with moments of order one.
    frames, method, dt
        As for :func:`~dzhanibekov.simulate`: the departure is measured at the frames. The
        default, ``"dop853"``, picks each run's steps (RK4's planned step, shared by the
        batch and bounded for the largest ``h``, is some hundred times shorter).
    limit : float
        The departure (rad) that counts as departed, in (0, π).

    Returns
    -------
    DualSpinMap

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> m = dz.dual_spin_map((1.0, 2.0, 3.0), [0.0, 1.5], axes=(1,), t_end=200.0, frames=101)
    >>> m.stable.tolist(), m.predicted.tolist()     # no wheel: it flips; h = 1.5 Ω: it spins
    ([[False, True]], [[False, True]])
    """
    body = Body(inertia)
    h = _values("momenta", momenta)
    axes_ = _axes(axes)
    w = as_float("rate", rate)
    if w == 0.0:
        raise ValueError("`rate` must not be zero")
    eps = as_float("nudge", nudge, positive=True)
    if eps >= 1.0:
        raise ValueError(f"`nudge` must be below 1 (a fraction of the spin), got {eps!r}")
    end = 400.0 / abs(w) if t_end is None else as_float("t_end", t_end, positive=True)
    frames_ = as_int("frames", frames, minimum=2)
    lim = as_float("limit", limit, positive=True)
    if lim >= math.pi:
        raise ValueError(f"`limit` must be below π, got {lim!r}")
    runs = len(axes_) * len(h)
    if runs > MAX_MAP_RUNS:
        raise ValueError(f"`momenta` times `axes` must make at most {MAX_MAP_RUNS} runs, "
                         f"got {runs}")
    systems, omega0 = [], []
    for k in axes_:
        e = np.zeros(3)
        e[k] = 1.0
        start = np.full(3, eps * abs(w))
        start[k] = w
        for hk in h:
            systems.append(System(body, parts=[Wheel(tuple(e), float(hk))]))
            omega0.append(start)
    batch = simulate(systems, np.array(omega0), t_end=end, frames=frames_, method=method,
                     dt=dt, flips=False, progress=False)
    assert isinstance(batch, Batch)
    departure = np.empty((len(axes_), len(h)))
    for a, k in enumerate(axes_):
        rows = batch.omega[a * len(h):(a + 1) * len(h)]
        across = np.linalg.norm(np.delete(rows, k, axis=2), axis=2)
        departure[a] = np.arctan2(across, rows[:, :, k] * math.copysign(1.0, w)).max(axis=1)
    thresholds = np.array([dual_spin_threshold(body.inertia, k, w) for k in axes_])
    return DualSpinMap(inertia=body.inertia, rate=w, axes=axes_, momenta=h, departure=departure,
                       thresholds=thresholds, limit=lim, nudge=eps, t_end=end)


# -- gravity gradient -----------------------------------------------------------------------


def gravity_gradient_moments(k1: Any, k3: Any) -> np.ndarray:
    """Principal moments ``(I1, I2, I3)`` (roll, pitch, yaw; ``I2 = 1``) of the moment ratios
    ``k1 = (I2 − I3)/I1`` and ``k3 = (I2 − I1)/I3`` (see the module doc), broadcast.

    ``I1 = (1 − k3)/(1 − k1 k3)`` and ``I3 = (1 − k1)/(1 − k1 k3)``.

    Parameters
    ----------
    k1, k3 : array_like
        In the open interval (−1, 1).

    Returns
    -------
    ndarray, shape broadcast(k1, k3).shape + (3,)

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> dz.gravity_gradient_moments(0.5, 0.2).round(12).tolist()
    [0.888888888889, 1.0, 0.555555555556]
    """
    a = _values("k1", np.ravel(k1) if np.ndim(k1) else k1, low=-1.0, high=1.0, open_=True)
    b = _values("k3", np.ravel(k3) if np.ndim(k3) else k3, low=-1.0, high=1.0, open_=True)
    shape = np.broadcast_shapes(np.shape(k1), np.shape(k3))
    a, b = (np.broadcast_to(v.reshape(np.shape(k)), shape) for v, k in ((a, k1), (b, k3)))
    d = 1.0 - a * b
    return np.stack([(1.0 - b) / d, np.ones(shape), (1.0 - a) / d], axis=-1)


def gravity_gradient_region(k1: Any, k3: Any) -> np.ndarray:
    """The closed form's verdict on the LVLH equilibrium at moment ratios ``(k1, k3)``:
    ``"lagrange"``, ``"debra_delp"`` or ``"unstable"`` (see the module doc for the
    conditions and their sources), broadcast.

    Parameters
    ----------
    k1, k3 : array_like
        In the open interval (−1, 1).

    Returns
    -------
    ndarray of str

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> str(dz.gravity_gradient_region(0.5, 0.2))        # I2 > I1 > I3
    'lagrange'
    """
    moments = gravity_gradient_moments(k1, k3)  # checks them
    a = np.broadcast_to(np.asarray(k1, dtype=np.float64), moments.shape[:-1])
    b = np.broadcast_to(np.asarray(k3, dtype=np.float64), moments.shape[:-1])
    c = 1.0 + 3.0 * a + a * b
    roll_yaw = (a * b > 0) & (c > 0) & (c * c > 16.0 * a * b)
    pitch = a > b
    stable = roll_yaw & pitch
    return np.where(stable & (a > 0), "lagrange", np.where(stable, "debra_delp", "unstable"))


@dataclass(frozen=True, eq=False)
class GravityGradientMap:
    """What :func:`gravity_gradient_map` measured: per moment ratios ``(k1, k3)``, the largest
    angle from LVLH over the runs.

    Attributes
    ----------
    k1 : ndarray, shape (N1,)
        ``(I2 − I3)/I1``, along the map's second axis.
    k3 : ndarray, shape (N3,)
        ``(I2 − I1)/I3``, along its first.
    deviation : ndarray, shape (N3, N1)
        The largest angle (rad) of the body from LVLH over the run.
    inertia : ndarray, shape (N3, N1, 3)
        The moments run (:func:`gravity_gradient_moments`).
    region : ndarray of str, shape (N3, N1)
        :func:`gravity_gradient_region`.
    limit : float
        The deviation (rad) above which a run counts as departed (:attr:`stable`).
    orbit_rate, perturbation, orbits : float
        The orbit, the start's angle from LVLH and the runs' length in orbits.
    """

    k1: np.ndarray
    k3: np.ndarray
    deviation: np.ndarray
    inertia: np.ndarray
    region: np.ndarray
    limit: float
    orbit_rate: float
    perturbation: float
    orbits: float

    @property
    def stable(self) -> np.ndarray:
        """Whether each run stayed within :attr:`limit` of LVLH."""
        return np.asarray(self.deviation < self.limit)

    def __repr__(self) -> str:
        return (f"GravityGradientMap(k1={len(self.k1)}, k3={len(self.k3)}, "
                f"stable={int(self.stable.sum())}/{self.stable.size})")


def gravity_gradient_map(k1: Any, k3: Any, *, orbit_rate: Any = 1.0,
                         perturbation: Any = 0.01, orbits: Any = 10.0, frames: Any = 401,
                         method: str = "dop853", dt: Any = None,
                         limit: Any = 0.3) -> GravityGradientMap:
    """The gravity-gradient stability map over the moment ratios ``(k1, k3)``, by runs.

    For each pair (a grid: `k3` along the rows, `k1` along the columns) a body of the moments
    :func:`gravity_gradient_moments` gives, in the :class:`~dzhanibekov.GravityGradient` of
    a circular orbit, starts at rest in LVLH turned by `perturbation` (rad) about each of
    roll, pitch and yaw (:func:`~dzhanibekov.lvlh_start`); the map is its largest angle from
    LVLH over `orbits` orbits (one batch of runs). Near LVLH in the stable regions, departed
    in the others; the closed form's regions (:func:`gravity_gradient_region`) go with it.

    Parameters
    ----------
    k1, k3 : array_like, shape (N1,) and (N3,)
        Moment ratios in (−1, 1) (see the module doc).
    orbit_rate : float
        The orbit's rate ``n``, positive.
    perturbation : float
        The start's turn about each LVLH axis (rad), positive, below 0.5.
    orbits : float
        Each run's length in orbits (``2π/n`` each), positive.
    frames, method
        As for :func:`~dzhanibekov.simulate`: the deviation is measured at the frames
        (``"dop853"``, the default, picks each run's steps).
    dt : float, optional
        The step; by default 256 steps an orbit for a fixed-step method (the linear
        motions about LVLH are at most 2.3 n fast, n√(1 + 3k1 + k1k3), whatever the
        moments; a body that departs is followed less closely, which its verdict does not
        need), and the method's own choice for an adaptive one.
    limit : float
        The deviation (rad) that counts as departed, in (0, π).

    Returns
    -------
    GravityGradientMap

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> m = dz.gravity_gradient_map([0.5], [0.2, 0.8], orbits=5.0, frames=101)
    >>> m.region[:, 0].tolist(), m.stable[:, 0].tolist()  # k1 > k3 > 0; k1 < k3: I1 < I3
    (['lagrange', 'unstable'], [True, False])
    """
    a = _values("k1", k1, low=-1.0, high=1.0, open_=True)
    b = _values("k3", k3, low=-1.0, high=1.0, open_=True)
    n = as_float("orbit_rate", orbit_rate, positive=True)
    angle = as_float("perturbation", perturbation, positive=True)
    if angle >= 0.5:
        raise ValueError(f"`perturbation` must be below 0.5 rad (a small angle), got {angle!r}")
    length = as_float("orbits", orbits, positive=True)
    frames_ = as_int("frames", frames, minimum=2)
    lim = as_float("limit", limit, positive=True)
    if lim >= math.pi:
        raise ValueError(f"`limit` must be below π, got {lim!r}")
    if a.size * b.size > MAX_MAP_RUNS:
        raise ValueError(f"`k1` times `k3` must make at most {MAX_MAP_RUNS} runs, got "
                         f"{a.size * b.size}")
    grid1, grid3 = np.meshgrid(a, b)
    inertia = gravity_gradient_moments(grid1, grid3)
    torque = GravityGradient(n)
    systems = [System(Body(i), torques=[torque]) for i in inertia.reshape(-1, 3)]
    # a turn of `angle` about each LVLH axis: the rotation vector angle·(1, 1, 1)
    half = 0.5 * angle * math.sqrt(3.0)
    axis = np.ones(3) / math.sqrt(3.0)
    q_rel = np.concatenate([[math.cos(half)], math.sin(half) * axis])
    omega0, q0 = lvlh_start(n, q_rel)
    if dt is None and isinstance(method, str) and method in METHODS and \
            not METHODS[method].adaptive:
        dt = 2.0 * math.pi / n / 256.0
    batch = simulate(systems, omega0, q0, t_end=length * 2.0 * math.pi / n, frames=frames_,
                     method=method, dt=dt, flips=False, progress=False)
    assert isinstance(batch, Batch)
    rel = lvlh_attitude(batch, n)
    deviation = 2.0 * np.arctan2(np.linalg.norm(rel[..., 1:], axis=-1), np.abs(rel[..., 0]))
    return GravityGradientMap(
        k1=a, k3=b, deviation=deviation.max(axis=1).reshape(grid1.shape), inertia=inertia,
        region=gravity_gradient_region(grid1, grid3), limit=lim, orbit_rate=n,
        perturbation=angle, orbits=length)
