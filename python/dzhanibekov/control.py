"""Closing the loop: the Earth's magnetic field along the orbit, the sensors a controller
reads, and the parts that act — a residual dipole, B-dot detumbling and momentum dumping by
magnetorquers, quaternion feedback on reaction wheels, a law of your own.

A controller runs at its own rate: at each sample time ``phase + k · period`` it reads what
its sensors measure, computes its command, and the actuators hold it until the next sample
(a zero-order hold). Every sample is a point every method ends its steps on, so the
integration step and the control rate are independent. Sensor noise is drawn by a
counter-based generator (Philox4x64-10) keyed by the part's `seed` plus the run's row: sample
``k``'s noise is the same whatever the run's length, threads or blocks; row ``i`` of a batch
draws as its single run with ``seed + i``, so the rows of a batch draw different noise. Every
sensor is noise-free by default.

The classes take their values as objects (:class:`MagneticField`, :class:`Magnetometer`,
:class:`Gyro`, :class:`StarTracker`) and store them as the core's flat parameters
(``orbit_rate``, ``magnetometer_noise``, …), which files and scenes hold.

>>> import numpy as np
>>> import dzhanibekov as dz
>>> n = dz.circular_orbit_rate(500e3)            # 500 km: 1.107e-3 rad/s
>>> field = dz.MagneticField(n, inclination=np.radians(97.4))
>>> bdot = dz.BDot(field, gain=3e-5, period=1.0, max_dipole=0.2)
>>> dz.System(dz.Body((0.042, 0.042, 0.0067)), parts=[bdot]).kinds
('bdot',)
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from . import _core
from ._args import as_array, as_float
from .parts import Param, Part

__all__ = ["MagneticField", "Magnetometer", "Gyro", "StarTracker", "ResidualDipole", "BDot",
           "MomentumDumping", "QuaternionFeedback", "Controller", "circular_orbit_rate",
           "detumble_gain", "EARTH_MU", "EARTH_RADIUS"]

EARTH_MU: float = _core.EARTH_MU
"""The Earth's gravitational parameter, m³/s² (WGS 84)."""
EARTH_RADIUS = 6378137.0
"""The Earth's equatorial radius, m (WGS 84)."""

_SCALARS = ("orbit_rate", "inclination", "moment", "mu", "tilt", "earth_rate", "longitude")
_FIELD = (*_SCALARS, "field_times", "field_values")


def circular_orbit_rate(altitude: float, mu: float = EARTH_MU,
                        radius: float = EARTH_RADIUS) -> float:
    """The rate ``n = √(μ / R³)`` of a circular orbit at `altitude` above a planet of
    gravitational parameter `mu` and radius `radius` (the Earth's by default, SI units).

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> round(2 * 3.141592653589793 / dz.circular_orbit_rate(500e3))   # the period, s
    5677
    """
    a = as_float("altitude", altitude) + as_float("radius", radius, positive=True)
    m = as_float("mu", mu, positive=True)
    if not a > 0:
        raise ValueError(f"`altitude` must put the orbit above the centre, got {altitude!r}")
    return math.sqrt(m / a**3)


def detumble_gain(orbit_rate: float, inclination: float, least_moment: float) -> float:
    """Avanzini & Giulietti's B-dot gain ``k* = 2 n (1 + sin ξ_m) J_min`` for an orbit of rate
    `orbit_rate` inclined by `inclination` (radians) to the magnetic equator and a body of least
    principal moment `least_moment` (Avanzini & Giulietti, "Magnetic detumbling of a rigid
    spacecraft", *J. Guidance, Control, and Dynamics* 35(4), 2012; Markley & Crassidis,
    *Fundamentals of Spacecraft Attitude Determination and Control*, 2014, eq. 7.55): it
    detumbles in about the least time.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> dz.detumble_gain(1e-3, 0.0, 0.01)
    2e-05
    """
    n = as_float("orbit_rate", orbit_rate, positive=True)
    j = as_float("least_moment", least_moment, positive=True)
    return 2.0 * n * (1.0 + math.sin(as_float("inclination", inclination))) * j


@dataclass(frozen=True)
class MagneticField:
    """The Earth's magnetic field along a circular orbit, as a tilted dipole (Wertz,
    *Spacecraft Attitude Determination and Control*, 1978, App. H; Markley & Crassidis 2014,
    §3.3): ``B = B_eq (d̂ − 3 (d̂·r̂) r̂)`` with ``B_eq = moment · n² / mu`` the field on the
    magnetic equator at the orbit's radius ``R = (mu / n²)^(1/3)``, ``d̂`` toward the
    geomagnetic north pole, ``r̂ = (cos nt, sin nt, 0)`` the orbit's radial direction (world
    axes; the orbit crosses the equator northward at ``t = 0``).

    Parameters
    ----------
    orbit_rate : float
        The orbit's rate ``n`` (:func:`circular_orbit_rate`), the gravity gradient's too.
    inclination : float
        The orbit's inclination to the equator of the Earth's spin axis, radians in
        ``[0, π]``; to the magnetic equator (``ξ_m``) when `tilt` is 0.
    moment : float, optional
        ``B₀ R_E³``; by default the IGRF-13 dipole at 2020.0, 7.708e15 T·m³ (the field in
        tesla).
    mu : float, optional
        The planet's gravitational parameter; by default the Earth's, 3.986004418e14 m³/s².
    tilt : float
        The dipole's tilt from the spin axis, radians (the Earth's: 0.1642, 9.41°); 0 by
        default, when the field repeats every orbit.
    earth_rate : float
        The Earth's rate about its spin axis (7.2921159e-5 rad/s); 0 (at rest) by default.
    longitude : float
        The dipole's longitude from the orbit's ascending node at ``t = 0``, radians.
    field_times, field_values : array_like, shapes (K,) and (K, 3), optional
        A field tabulated along the orbit in world axes, in place of the dipole's: linear
        between the knots (strictly increasing times, at least two), the ends' values
        outside them; its knots are kinks every step ends on. :func:`~dzhanibekov.igrf_field`
        makes one from the IGRF (the ``igrf`` extra).
    """

    orbit_rate: float
    inclination: float
    moment: float | None = None
    mu: float | None = None
    tilt: float = 0.0
    earth_rate: float = 0.0
    longitude: float = 0.0
    field_times: tuple[float, ...] | None = None
    field_values: tuple[tuple[float, float, float], ...] | None = None

    def __post_init__(self) -> None:
        # the core checks these again when a part is built (a file's, a scene's)
        for name in _SCALARS:
            value = getattr(self, name)
            if value is not None or name not in ("moment", "mu"):   # None: the Earth's
                object.__setattr__(self, name, as_float(
                    name, value, positive=name in ("orbit_rate", "moment", "mu")))
        for name in ("inclination", "tilt"):
            if not 0.0 <= getattr(self, name) <= math.pi:
                raise ValueError(f"`{name}` must be an angle in [0, π] (radians), got "
                                 f"{getattr(self, name)!r}")
        if (self.field_times is None) != (self.field_values is None):
            raise ValueError("`field_times` and `field_values` go together: give both or "
                             "neither")
        if self.field_times is not None:
            times = as_array("field_times", self.field_times, "(K,)",
                             last=int(np.size(self.field_times)), ndim=(1,))
            if len(times) < 2 or not np.all(np.diff(times) > 0):
                raise ValueError("`field_times` must hold at least two strictly increasing "
                                 f"times, got {len(times)} knots")
            values = as_array("field_values", self.field_values, "(K, 3)", last=3, ndim=(2,))
            if len(values) != len(times):
                raise ValueError(f"`field_values` must hold one vector per knot of "
                                 f"`field_times` ({len(times)}), got {len(values)}")
            object.__setattr__(self, "field_times", tuple(times.tolist()))
            object.__setattr__(self, "field_values", tuple(map(tuple, values.tolist())))

    @property
    def tabulated(self) -> bool:
        """Whether the field is tabulated (:func:`~dzhanibekov.igrf_field`), not the dipole."""
        return self.field_times is not None

    def fields(self) -> dict[str, Any]:
        """The parameters by name, as parts store them."""
        return {name: getattr(self, name) for name in _FIELD}


def _vector(name: str, value: Any) -> tuple[float, float, float]:
    v = as_array(name, value, "(3,)", last=3, ndim=(1,))
    return (float(v[0]), float(v[1]), float(v[2]))


def _deviation(name: str, value: Any) -> float:
    """A standard deviation: finite, not negative."""
    x = as_float(name, value)
    if x < 0:
        raise ValueError(f"`{name}` must be finite and not negative, got {x!r}")
    return x


def _seed(value: Any) -> int:
    """A sensors' seed: a whole number in ``[0, 2**53)`` (a float64 holds each exactly)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"`seed` must be an int in [0, 2**53), got {type(value).__name__}")
    if not 0 <= value < 2**53:
        raise ValueError(f"`seed` must be an int in [0, 2**53), got {value}")
    return int(value)


@dataclass(frozen=True)
class Magnetometer:
    """A three-axis magnetometer: the field in body axes plus a constant `bias` and white
    `noise` per axis (field units). Noise-free by default."""

    noise: float = 0.0
    bias: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "noise", _deviation("noise", self.noise))
        object.__setattr__(self, "bias", _vector("bias", self.bias))

    def fields(self) -> dict[str, Any]:
        return {"magnetometer_bias": self.bias, "magnetometer_noise": self.noise}


@dataclass(frozen=True)
class Gyro:
    """A rate gyro: each sample of period ``T`` measures ``ω + bias + (σ_v / √T) N`` with the
    angle random walk `angle_random_walk` ``σ_v`` (rad/√time; Farrenkopf's model without the
    bias's own walk, as Crassidis & Markley, *J. Guidance* 26(4), 2003, discretise it) and a
    constant `bias` (body axes). Noise-free by default."""

    angle_random_walk: float = 0.0
    bias: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "angle_random_walk",
                           _deviation("angle_random_walk", self.angle_random_walk))
        object.__setattr__(self, "bias", _vector("bias", self.bias))

    def fields(self) -> dict[str, Any]:
        return {"gyro_bias": self.bias, "gyro_angle_random_walk": self.angle_random_walk}


@dataclass(frozen=True)
class StarTracker:
    """A star tracker: the attitude turned by a small random rotation of `noise` radians per
    body axis, ``q̃ = q ⊗ exp(σ N / 2)``. Noise-free by default."""

    noise: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "noise", _deviation("noise", self.noise))

    def fields(self) -> dict[str, Any]:
        return {"star_tracker_noise": self.noise}


class _Loop(Part):
    """A part of the closed loop: a :class:`~dzhanibekov.parts.Part` whose constructor takes
    objects (a field, sensors) and plain values and stores them as the core's flat parameters
    of its kind (``dz.MODELS``); coercion, ``==``, ``hash``, ``repr``, pickling, files and
    scenes follow from the declaration as for every part."""

    declares_types = False
    lists = ("parts", "torques")  # on board, some acting from outside: either list

    def _build(self, values: Mapping[str, Any], *objects: Any) -> None:
        flat = dict(values)
        for obj in objects:
            if obj is not None:
                flat.update(obj.fields())
        unknown = set(flat) - {p.name for p in self.params}
        assert not unknown, f"{self.kind} has no parameters {sorted(unknown)}"
        if "seed" in flat:   # given by the constructors (0 by default): None is refused
            flat["seed"] = _seed(flat["seed"])
        self._store(self.kind, flat)

    def _coerce(self, param: Param, value: Any, knots: int | None) -> Any:
        if param.name == "seed":   # a whole number, kept exactly (a file's column: a float)
            if isinstance(value, (float, np.floating)) and float(value).is_integer():
                value = int(value)
            return _seed(value)
        return super()._coerce(param, value, knots)

    @classmethod
    def from_fields(cls, kind: str, fields: Mapping[str, Any]) -> Part:
        if kind != cls.kind:
            raise ValueError(f"a {cls.__name__} makes a {cls.kind!r}, not a {kind!r}")
        cls._require(kind, fields)
        part = cls.__new__(cls)
        part._store(kind, {k: v for k, v in fields.items() if v is not None})
        return part

    # the objects the flat parameters make, for reading back

    @property
    def field(self) -> MagneticField | None:
        """The magnetic field, if the part has one."""
        values = {name: getattr(self, name, None) for name in _FIELD}
        if values["orbit_rate"] is None:
            return None
        return MagneticField(**{k: v for k, v in values.items() if v is not None})

    @property
    def magnetometer(self) -> Magnetometer:
        """The magnetometer."""
        return Magnetometer(getattr(self, "magnetometer_noise") or 0.0,
                            getattr(self, "magnetometer_bias") or (0.0, 0.0, 0.0))

    @property
    def gyro(self) -> Gyro:
        """The gyro."""
        return Gyro(getattr(self, "gyro_angle_random_walk") or 0.0,
                    getattr(self, "gyro_bias") or (0.0, 0.0, 0.0))

    @property
    def star_tracker(self) -> StarTracker:
        """The star tracker."""
        return StarTracker(getattr(self, "star_tracker_noise") or 0.0)


def _limits(name: str, value: Any) -> tuple[float, float, float] | None:
    """A per-axis limit: None, a number for all three axes, or three numbers."""
    if value is None:
        return None
    if np.ndim(value) == 0:
        v = as_float(name, value)
        return (v, v, v)
    return _vector(name, value)


def _gains(name: str, value: Any) -> tuple[float, float, float]:
    """Gains: a number for all three axes, or three numbers."""
    if np.ndim(value) == 0:
        v = as_float(name, value)
        return (v, v, v)
    return _vector(name, value)


class ResidualDipole(_Loop):
    """A constant magnetic dipole of the body (its wiring, its magnets) in the Earth's field:
    the external torque ``τ = m × B`` (body axes). It keeps nothing but ``|q|``.

    Parameters
    ----------
    field : MagneticField
    dipole : array_like, shape (3,)
        The dipole in body axes (A·m² with the field in tesla).

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> field = dz.MagneticField(dz.circular_orbit_rate(500e3), inclination=0.9)
    >>> dz.System(dz.Body((1.0, 2.0, 3.0)), torques=[dz.ResidualDipole(field, (0, 0, 1e-3))]
    ...           ).conserved
    ('q_norm',)
    """

    kind = "residual_dipole"
    examples = {"residual_dipole": {"orbit_rate": 1.1e-3, "inclination": 1.2, "dipole": (0.0, 0.0, 1e-3)}}

    def __init__(self, field: MagneticField, dipole: Any) -> None:
        _need("field", field, MagneticField)
        self._build({"dipole": dipole}, field)


def _need(name: str, value: Any, kind: type) -> None:
    if not isinstance(value, kind):
        raise TypeError(f"`{name}` must be a dz.{kind.__name__}, got {type(value).__name__}")


def _optional(name: str, value: Any, kind: type) -> Any:
    if value is not None:
        _need(name, value, kind)
    return value


class BDot(_Loop):
    """B-dot detumbling: three magnetorquers along the body's axes, commanded at each sample
    by Avanzini & Giulietti's law and held (see the module doc).

    With ``rates="magnetometer"`` (the default) the law reads the change of the measured
    field's direction ``b = B/|B|`` since the last sample, ``m = −(k / |B|) (b_k − b_{k−1}) /
    T``: for a body turning fast against the field's own motion ``ḃ ≈ −ω × b``, so the torque
    ``m × B ≈ −k ω⊥`` takes the rates across the field away; the first sample commands
    nothing. With ``rates="gyro"`` it reads a gyro, ``m = (k / |B|) ω̃ × b``, whose torque is
    ``−k ω⊥`` exactly. Each coil is clipped to its limit (`max_dipole`), the direction not
    kept. :func:`detumble_gain` gives the gain that detumbles in about the least time.

    The body's rates do not reach zero with the magnetometer's law: the body ends turning with
    the field's direction, at about twice the orbit's rate; with the gyro's, they do.

    Parameters
    ----------
    field : MagneticField
    gain : float
        ``k``, a moment times a rate (N·m·s), not negative.
    period : float
        The time between samples.
    phase : float
        The first sample's time (0).
    max_dipole : float or array_like, shape (3,), optional
        Each coil's largest dipole (body axes); none by default.
    rates : {"magnetometer", "gyro"}
    magnetometer : Magnetometer, optional
    gyro : Gyro, optional
        Used with ``rates="gyro"``.
    seed : int
        The sensors' noise seed, in ``[0, 2**53)`` (0); row ``i`` of a batch draws as the
        single run of the part with ``seed + i``.

    Notes
    -----
    The run's ``parts["bdot"]`` holds, at each frame, the dipole held since the last sample
    (after saturation; ``dipole``), the field measured then (``field``) and which coils
    saturated (``saturated``, bit ``k`` for coil ``k``; :func:`~dzhanibekov.saturation`
    decodes it); a frame at a sample time shows the state before that sample's update.
    """

    kind = "bdot"
    examples = {"bdot": {"orbit_rate": 1.1e-3, "inclination": 1.2, "gain": 1e-5, "period": 0.05}}

    def __init__(self, field: MagneticField, gain: float, period: float, *,
                 phase: float = 0.0, max_dipole: Any = None, rates: str = "magnetometer",
                 magnetometer: Magnetometer | None = None, gyro: Gyro | None = None,
                 seed: int = 0) -> None:
        _need("field", field, MagneticField)
        self._build({"gain": gain, "period": period, "phase": phase,
                     "max_dipole": _limits("max_dipole", max_dipole), "rates": rates,
                     "seed": seed},
                    field, _optional("magnetometer", magnetometer, Magnetometer),
                    _optional("gyro", gyro, Gyro))


class MomentumDumping(_Loop):
    """Momentum dumping: three magnetorquers commanded at each sample ``m = k (h × B̃) / |B̃|²``
    from the momentum ``h`` the system's parts store (its wheels', from their tachometers) and
    the measured field, clipped per coil and held. The body feels ``m × B = −k h⊥``: the
    wheels' momentum across the field drains while a pointing law holds the body (Markley &
    Crassidis 2014, §7.6).

    Parameters
    ----------
    field : MagneticField
    gain : float
        ``k``, a rate, not negative.
    period : float
    phase : float
    max_dipole : float or array_like, shape (3,), optional
    magnetometer : Magnetometer, optional
    seed : int
        The sensors' noise seed, in ``[0, 2**53)`` (0); row ``i`` of a batch draws as the
        single run of the part with ``seed + i``.
    """

    kind = "momentum_dumping"
    examples = {"momentum_dumping": {"orbit_rate": 1.1e-3, "inclination": 1.2, "gain": 1e-3, "period": 0.05}}

    def __init__(self, field: MagneticField, gain: float, period: float, *,
                 phase: float = 0.0, max_dipole: Any = None,
                 magnetometer: Magnetometer | None = None, seed: int = 0) -> None:
        _need("field", field, MagneticField)
        self._build({"gain": gain, "period": period, "phase": phase,
                     "max_dipole": _limits("max_dipole", max_dipole), "seed": seed},
                    field, _optional("magnetometer", magnetometer, Magnetometer))


class QuaternionFeedback(_Loop):
    """Pointing by quaternion feedback on three reaction wheels (Wie, Weiss & Arapostathis,
    *J. Guidance* 12(3), 1989; Markley & Crassidis 2014, §7.2): at each sample the wheels are
    commanded to give the body

    ``τ = −K_p e − K_d (ω̃ − ω_t)``,  ``e = 2 sgn(δq₀) δq_{1:3}``,  ``δq = q_t* ⊗ q̃``

    toward a target fixed in space (``frame="inertial"``, `target` world-from-target) or in the
    orbiting frame (``frame="lvlh"``, `target` LVLH-from-target, with `orbit_rate`), the
    shorter way round, from a star tracker's attitude ``q̃`` and a gyro's rates ``ω̃``. About
    a principal axis of moment ``I``, small errors follow ``I φ̈ + K_d φ̇ + K_p φ = 0``:
    ``ω_n = √(K_p/I)``, ``ζ = K_d / (2√(K_p I))``. ``feedforward="gyroscopic"`` adds
    ``ω̃ × H`` (``H = I ω + Σ h a``, the total momentum in body axes), which cancels the
    gyroscopic coupling of wheels holding much momentum.

    The wheels (`axes`, default the body's x, y, z) share the torque at the least norm; each
    motor gives at most `torque_limit`, each wheel holds at most `momentum_limit` (a command
    is cut at the sample so that the wheel lands on its limit at the hold's end). The wheels'
    torque is internal: ``L`` in space is kept.

    Parameters
    ----------
    kp, kd : float or array_like, shape (3,)
        The gains, body axes (torque per radian, torque per rate).
    period : float
    target : array_like, shape (4,)
        The target's attitude, scalar first; identity by default.
    frame : {"inertial", "lvlh"}
    orbit_rate : float, optional
        For ``frame="lvlh"``.
    feedforward : {"none", "gyroscopic"}
    axes : array_like, shape (3, 3), optional
        The wheels' spin axes (rows), body axes.
    momentum : array_like, shape (3,), optional
        The wheels' relative momenta at the start.
    torque_limit, momentum_limit : float, optional
    phase : float
    star_tracker : StarTracker, optional
    gyro : Gyro, optional
    seed : int
        The sensors' noise seed, in ``[0, 2**53)`` (0); row ``i`` of a batch draws as the
        single run of the part with ``seed + i``.

    Notes
    -----
    The run's ``parts["quaternion_feedback"]`` holds each wheel's momentum
    (``wheel_momentum``) and held command (``wheel_torque``) and the limits that cut it
    (``saturated``: bit ``k`` wheel ``k``'s torque limit, bit ``3 + k`` its momentum limit;
    :func:`~dzhanibekov.saturation` decodes it).
    """

    kind = "quaternion_feedback"
    examples = {"quaternion_feedback": {"kp": (0.1, 0.1, 0.1), "kd": (0.3, 0.3, 0.3), "period": 0.05,
                                   "target": (1.0, 0.0, 0.0, 0.0),
                                   "axes": ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))}}
    target: np.ndarray | None
    frame: str
    orbit_rate: float | None
    torque_limit: float | None
    momentum_limit: float | None

    def __init__(self, kp: Any, kd: Any, period: float, *, target: Any = None,
                 frame: str = "inertial", orbit_rate: float | None = None,
                 feedforward: str = "none", axes: Any = None, momentum: Any = None,
                 torque_limit: float | None = None, momentum_limit: float | None = None,
                 phase: float = 0.0, star_tracker: StarTracker | None = None,
                 gyro: Gyro | None = None, seed: int = 0) -> None:
        self._build({"kp": _gains("kp", kp), "kd": _gains("kd", kd), "period": period,
                     "seed": seed,
                     "phase": phase, "target": target, "frame": frame,
                     "orbit_rate": orbit_rate, "feedforward": feedforward, "axes": axes,
                     "momentum": momentum, "torque_limit": torque_limit,
                     "momentum_limit": momentum_limit},
                    _optional("star_tracker", star_tracker, StarTracker),
                    _optional("gyro", gyro, Gyro))


def _example_law(t: float, q: np.ndarray, omega: np.ndarray, field: np.ndarray,
                 momentum: np.ndarray) -> np.ndarray:
    """A rate damper, ``τ = −0.1 ω`` (the controller's example)."""
    return -0.1 * omega


class Controller(_Loop):
    """A control law of your own, called once per sample (not at every stage of a step) on
    what the sensors measure:

    ``law(t, q, omega, field, wheel_momentum) -> torque`` or ``-> (torque, dipole)``

    with the time ``t``, the star tracker's attitude ``q`` (shape (4,), world-from-body,
    scalar first), the gyro's rates ``omega`` and the magnetometer's ``field`` (shape (3,),
    body axes; zeros without a `field`), the wheels' momenta (shape (3,)); it returns the
    torque three reaction wheels are to give the body (body axes) and, optionally, the dipole
    three magnetorquers are to hold (ignored without a `field`). Both are limited as in
    :class:`QuaternionFeedback` and :class:`BDot` and held until the next sample.

    A function that raises stops the run and its exception reaches the caller as raised; one
    that returns something else than three or six finite numbers stops it with a ValueError.
    Ctrl-C stops a run as usual; a batch of such systems runs its rows one after another on
    one thread (each call takes the GIL). ``dz.save`` refuses a run with one: a file cannot
    hold code.

    Parameters
    ----------
    law : callable
    period : float
    field : MagneticField, optional
    axes, momentum, torque_limit, momentum_limit
        The wheels, as for :class:`QuaternionFeedback`.
    max_dipole : float or array_like, shape (3,), optional
    phase : float
    star_tracker, gyro, magnetometer : optional
        The sensors (noise-free by default).
    seed : int
        The sensors' noise seed, in ``[0, 2**53)`` (0); row ``i`` of a batch draws as the
        single run of the part with ``seed + i``.

    Examples
    --------
    >>> import numpy as np
    >>> import dzhanibekov as dz
    >>> def damp(t, q, omega, field, h):       # a rate damper, 10 times a second
    ...     return -0.5 * omega
    >>> s = dz.System(dz.Body((2.0, 3.0, 4.0)), parts=[dz.Controller(damp, period=0.1)])
    >>> traj = dz.simulate(s, (0.0, 0.0, 1.0), t_end=20.0, method="dop853")
    >>> bool(traj.omega[-1, 2] < np.exp(-0.5 * 20.0 / 4.0) * 1.05)
    True
    """

    kind = "controller"
    examples = {"controller": {"law": _example_law, "period": 0.05}}

    def __init__(self, law: Any, period: float, *, field: MagneticField | None = None,
                 axes: Any = None, momentum: Any = None, torque_limit: float | None = None,
                 momentum_limit: float | None = None, max_dipole: Any = None,
                 phase: float = 0.0, star_tracker: StarTracker | None = None,
                 gyro: Gyro | None = None, magnetometer: Magnetometer | None = None,
                 seed: int = 0) -> None:
        if not callable(law):
            raise TypeError(f"`law` must be callable as law(t, q, omega, field, "
                            f"wheel_momentum), got {type(law).__name__}")
        self._build({"law": law, "period": period, "phase": phase, "axes": axes, "seed": seed,
                     "momentum": momentum, "torque_limit": torque_limit,
                     "momentum_limit": momentum_limit,
                     "max_dipole": _limits("max_dipole", max_dipole)},
                    _optional("field", field, MagneticField),
                    _optional("star_tracker", star_tracker, StarTracker),
                    _optional("gyro", gyro, Gyro),
                    _optional("magnetometer", magnetometer, Magnetometer))
