"""The Earth's real field along the orbit: the International Geomagnetic Reference Field
(IGRF-14; Alken et al., *Earth, Planets and Space* 73:49, 2021, for IGRF-13) evaluated by
`ppigrf <https://github.com/IAGA-VMOD/ppigrf>`_ (the IAGA working group's pure-Python code,
MIT; the ``igrf`` extra: ``pip install "dzhanibekov[igrf]"``), sampled along the circular
orbit and handed to the core as a table (:class:`~dzhanibekov.MagneticField`'s
``field_times``, ``field_values``), which every magnetic part reads in place of the dipole.

**The geometry.** The orbit, of radius ``R = (μ / n²)^(1/3)``, inclination ``i``, right
ascension of the ascending node ``Ω`` and argument of latitude ``u₀`` at ``t = 0``, puts the
body at ``r_ECI(t) = R_z(Ω) R_x(i) R (cos u, sin u, 0)``, ``u = u₀ + n t`` (Vallado,
*Fundamentals of Astrodynamics and Applications*, 4th ed., 2013, §2.6). The Earth-fixed
position is ``r_ECEF = R_z(−θ) r_ECI`` with ``θ`` the Earth rotation angle, ``θ(t) =
2π (0.7790572732640 + 1.00273781191135448 (JD − 2451545.0))`` of the epoch's Julian date plus
``ω_E t`` when the Earth turns (IERS Conventions 2010, eq. 5.15; UT1 taken as UTC, a second
at most: 0.004°; precession and nutation left out, 0.3° a decade from J2000). ppigrf gives
``B_r, B_θ, B_φ`` at that geocentric point (the epoch's coefficients for the whole run: the
field's secular change is ~0.1 % a year); ``B_ECEF = B_r r̂ + B_θ θ̂ + B_φ φ̂`` turned back by
``R_z(θ)`` is the field in inertial axes. The package's world axes are the orbit's: ``x`` at
the body at ``t = 0``, ``z`` along the orbit's normal (``r̂ = (cos nt, sin nt, 0)``, as for the
dipole and the gravity gradient), so ``B_world = (R_z(Ω) R_x(i) R_z(u₀))ᵀ B_ECI``.

**The table.** Knots ``step`` apart from 0 to ``duration`` (and one past it), linear between:
the error is at most ``step² max|B̈| / 8``, about ``7·10⁻⁵ |B|`` at 10 s in low orbit (the
field turns at a few times the orbit's rate), and falls as ``step²``.
"""

from __future__ import annotations

import datetime as _dt
import math
from typing import Any

import numpy as np

from . import _tables
from ._args import as_float, as_int
from .control import EARTH_MU, MagneticField

__all__ = ["igrf_field", "EARTH_ROTATION_RATE", "earth_rotation_angle", "MAX_KNOTS"]

EARTH_ROTATION_RATE = 2.0 * math.pi * 1.00273781191135448 / 86400.0
"""The Earth's rate about its axis, rad/s: the rate of the Earth rotation angle (IERS
Conventions 2010, eq. 5.15), 7.2921150e-5."""

MAX_KNOTS = 10_000_000
"""The most knots a table may have (320 MB in the core): `duration` / `step` beyond it is
refused."""

_J2000 = _dt.datetime(2000, 1, 1, 12, 0, 0)
"""JD 2451545.0 (UT1 taken as UTC)."""


def _epoch(value: Any) -> _dt.datetime:
    """A naive UTC datetime from a datetime (an aware one turned to UTC) or an ISO 8601
    string."""
    if isinstance(value, str):
        try:
            value = _dt.datetime.fromisoformat(value)
        except ValueError:
            raise ValueError(f"`epoch` must be an ISO 8601 date and time "
                             f"('2025-03-20T12:00:00'), got {value!r}") from None
    if isinstance(value, _dt.date) and not isinstance(value, _dt.datetime):
        value = _dt.datetime(value.year, value.month, value.day)
    if not isinstance(value, _dt.datetime):
        raise TypeError(f"`epoch` must be a datetime or an ISO 8601 string, got "
                        f"{type(value).__name__}")
    when: _dt.datetime = value
    if when.tzinfo is not None:
        when = when.astimezone(_dt.timezone.utc).replace(tzinfo=None)
    return when


def earth_rotation_angle(epoch: Any) -> float:
    """The Earth rotation angle at `epoch` (UTC taken as UT1), radians in ``[0, 2π)``: the
    angle from the inertial x axis (the equinox of J2000) to the Greenwich meridian (IERS
    Conventions 2010, eq. 5.15).

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> round(dz.earth_rotation_angle("2000-01-01T12:00:00"), 6)   # 0.7790572732640 turns
    4.894961
    """
    days = (_epoch(epoch) - _J2000).total_seconds() / 86400.0
    turns = 0.7790572732640 + 1.00273781191135448 * days
    return 2.0 * math.pi * (turns % 1.0)


def _turn_z(angle: np.ndarray) -> np.ndarray:
    """Rotations by `angle` about z, shape angle.shape + (3, 3)."""
    c, s = np.cos(angle), np.sin(angle)
    m = np.zeros(np.shape(angle) + (3, 3))
    m[..., 0, 0], m[..., 0, 1], m[..., 1, 0], m[..., 1, 1], m[..., 2, 2] = c, -s, s, c, 1.0
    return m


def _turn_x(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def igrf_field(orbit_rate: float, inclination: float, *, epoch: Any, duration: float,
               raan: float = 0.0, latitude: float = 0.0, earth_turns: bool = True,
               step: float = 10.0, degree: int = 13, mu: float | None = None) -> MagneticField:
    """The IGRF along a circular orbit from `epoch` for `duration` seconds, as a
    :class:`~dzhanibekov.MagneticField` tabulated in world axes (tesla) that any magnetic
    part takes in place of the dipole (see the module doc for the geometry; the ``igrf``
    extra).

    Parameters
    ----------
    orbit_rate : float
        The orbit's rate ``n``, rad/s (:func:`~dzhanibekov.circular_orbit_rate`).
    inclination : float
        The orbit's inclination to the Earth's equator, radians in ``[0, π]``.
    epoch : datetime or str
        The time of ``t = 0``, UTC (ISO 8601 string or datetime; IGRF-14 covers 1900–2030).
    duration : float
        How long to tabulate, s (the run's ``t_end`` or more): past the last knot the field
        is held at its last value.
    raan : float
        The right ascension of the ascending node, radians (from the J2000 equinox).
    latitude : float
        The argument of latitude at ``t = 0``, radians: the angle from the ascending node
        to the body along the orbit (0: the body crosses the equator northward at ``t = 0``).
    earth_turns : bool
        Whether the Earth turns under the orbit (True), or stays as at `epoch`.
    step : float
        The knots' spacing, s (10 by default: ~7e-5 of the field).
    degree : int
        The highest degree of the expansion, 1 (the dipole: ``g₁₀, g₁₁, h₁₁``) to 13.
    mu : float, optional
        The Earth's gravitational parameter (``dz.control.EARTH_MU``, WGS 84, by default).

    Raises
    ------
    ImportError
        Without ppigrf (install ``dzhanibekov[igrf]``).
    TypeError, ValueError
        A parameter out of its range, by name; more knots than
        :data:`MAX_KNOTS`.

    Examples
    --------
    >>> import numpy as np, dzhanibekov as dz
    >>> n = dz.circular_orbit_rate(500e3)
    >>> field = dz.igrf_field(n, np.radians(97.4), epoch="2025-03-20T12:00:00",
    ...                       duration=6000.0)
    >>> field.tabulated, len(field.field_times)
    (True, 601)
    >>> bool(15e-6 < np.linalg.norm(field.field_values, axis=1).min() < 60e-6)  # tesla
    True
    """
    n = as_float("orbit_rate", orbit_rate, positive=True)
    i = as_float("inclination", inclination)
    if not 0.0 <= i <= math.pi:
        raise ValueError(f"`inclination` must be an angle in [0, π] (radians), got {i!r}")
    when = _epoch(epoch)
    span = as_float("duration", duration, positive=True)
    h = as_float("step", step, positive=True)
    node, u0 = as_float("raan", raan), as_float("latitude", latitude)
    if not isinstance(earth_turns, bool):
        raise TypeError(f"`earth_turns` must be True or False, got {earth_turns!r}")
    top = as_int("degree", degree, minimum=1)
    if top > 13:
        raise ValueError(f"`degree` must be in 1..13 (the IGRF's), got {top}")
    m = EARTH_MU if mu is None else as_float("mu", mu, positive=True)
    knots = math.ceil(span / h) + 1
    if knots > MAX_KNOTS:
        raise ValueError(f"`duration` / `step` gives {knots} knots, more than {MAX_KNOTS}: "
                         "take a larger `step` or a shorter `duration`")
    ppigrf = _tables.require("ppigrf", "`dz.igrf_field`", "dzhanibekov[igrf]")
    t = h * np.arange(knots, dtype=np.float64)
    radius = (m / (n * n)) ** (1.0 / 3.0)
    orbit = _turn_z(np.array(node)) @ _turn_x(i)                 # node frame -> ECI
    world = orbit @ _turn_z(np.array(u0))                        # world axes -> ECI
    u = n * t
    r_world = np.stack([np.cos(u), np.sin(u), np.zeros_like(u)], axis=1) * radius
    r_eci = r_world @ world.T
    theta = earth_rotation_angle(when) + (EARTH_ROTATION_RATE * t if earth_turns else 0.0 * t)
    to_ecef = np.swapaxes(_turn_z(theta), -1, -2)                # R_z(−θ)
    r_ecef = np.einsum("kij,kj->ki", to_ecef, r_eci)
    r = np.linalg.norm(r_ecef, axis=1)
    colat = np.arccos(np.clip(r_ecef[:, 2] / r, -1.0, 1.0))
    lon = np.arctan2(r_ecef[:, 1], r_ecef[:, 0])
    b_r, b_th, b_ph = (np.asarray(b, dtype=np.float64).reshape(-1) for b in ppigrf.igrf_gc(
        r / 1e3, np.degrees(colat), np.degrees(lon), when, max_degree=top))
    st, ct, sp, cp = np.sin(colat), np.cos(colat), np.sin(lon), np.cos(lon)
    r_hat = np.stack([st * cp, st * sp, ct], axis=1)
    th_hat = np.stack([ct * cp, ct * sp, -st], axis=1)
    ph_hat = np.stack([-sp, cp, np.zeros_like(sp)], axis=1)
    b_ecef = b_r[:, None] * r_hat + b_th[:, None] * th_hat + b_ph[:, None] * ph_hat
    b_eci = np.einsum("kji,kj->ki", to_ecef, b_ecef)             # R_z(θ) = R_z(−θ)ᵀ
    b_world = b_eci @ world * 1e-9                               # nT -> T, Aᵀ b per row
    return MagneticField(n, i, mu=mu, field_times=t, field_values=b_world)  # type: ignore[arg-type]

