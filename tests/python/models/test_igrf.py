"""The IGRF as a field option (issue 32): ``dz.igrf_field`` samples the International
Geomagnetic Reference Field (ppigrf, the ``igrf`` extra, which ``.ci/run`` installs with the
test extra) along the orbit and hands the core a table. Checked against what the code cannot
fake: the library's own values between the knots (to the interpolation's error, which falls
as the step squared), the dipole the library's first three coefficients make (the tilted
dipole's formula written here), and the field's size in low orbit."""

from __future__ import annotations

import datetime
import math

import numpy as np
import pytest

import dzhanibekov as dz

ppigrf = pytest.importorskip("ppigrf", reason="the `igrf` extra (ppigrf) is not installed")

EPOCH = datetime.datetime(2025, 3, 20, 12, 0, 0)
N = dz.circular_orbit_rate(500e3)
INCLINATION = math.radians(97.4)


def coefficients(epoch: datetime.datetime) -> tuple[float, float, float]:
    """g₁₀, g₁₁, h₁₁ (nT) at `epoch`, linear between the library's tabulated epochs (the
    IGRF's own rule between its five-year models)."""
    g, h = ppigrf.ppigrf.read_shc()
    years = np.array([(d - g.index[0]).total_seconds() for d in g.index])
    at = (epoch - g.index[0].to_pydatetime()).total_seconds()
    return (float(np.interp(at, years, g[(1, 0)].to_numpy())),
            float(np.interp(at, years, g[(1, 1)].to_numpy())),
            float(np.interp(at, years, h[(1, 1)].to_numpy())))


def tilted_dipole(t: np.ndarray, n: float, inclination: float, raan: float, u0: float,
                  era0: float, earth_rate: float, epoch: datetime.datetime) -> np.ndarray:
    """The dipole of g₁₀, g₁₁, h₁₁ along the orbit in world axes, tesla (Wertz, *Spacecraft
    Attitude Determination and Control*, 1978, App. H.2): ``B = B₀ (R_E/R)³ (d̂ − 3 (d̂·r̂) r̂)``
    with ``B₀ = √(g₁₀² + g₁₁² + h₁₁²)``, ``d̂`` toward the geomagnetic north pole (colatitude
    ``acos(−g₁₀/B₀)``, east longitude ``atan2(−h₁₁, −g₁₁)``), written in the orbit's node
    frame: ``x`` the ascending node, ``z`` the orbit's normal, the Earth's axis ``ê = (0, sin
    i, cos i)``, the equator's east axes ``x̂`` and ``ê × x̂``; then turned by ``−u₀`` into
    world axes (``x`` at the body at ``t = 0``)."""
    g10, g11, h11 = coefficients(epoch)
    b0 = math.sqrt(g10**2 + g11**2 + h11**2) * 1e-9
    tilt, longitude = math.acos(-g10 * 1e-9 / b0), math.atan2(-h11, -g11)
    radius = (dz.control.EARTH_MU / n**2) ** (1 / 3)
    axis = np.array([0.0, math.sin(inclination), math.cos(inclination)])
    east1, east2 = np.array([1.0, 0.0, 0.0]), np.cross(axis, [1.0, 0.0, 0.0])
    # the pole's angle along the equator from the node: its longitude, plus the Greenwich
    # meridian's angle from the equinox, less the node's
    phi = longitude + era0 + earth_rate * t - raan
    d = (math.cos(tilt) * axis + math.sin(tilt) * (np.cos(phi)[:, None] * east1
                                                   + np.sin(phi)[:, None] * east2))
    u = u0 + n * t
    r = np.stack([np.cos(u), np.sin(u), np.zeros_like(u)], axis=1)
    b = b0 * (6371.2e3 / radius) ** 3 * (d - 3 * np.sum(d * r, axis=1)[:, None] * r)
    c, s = math.cos(u0), math.sin(u0)
    return b @ np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])   # Rz(−u₀) b per row


@pytest.mark.parametrize("earth_turns", [True, False])
def test_the_librarys_dipole_alone_is_the_tilted_dipole(earth_turns: bool) -> None:
    raan, u0 = 1.1, 0.7
    f = dz.igrf_field(N, INCLINATION, epoch=EPOCH, duration=6000.0, step=100.0, raan=raan,
                      latitude=u0, degree=1, earth_turns=earth_turns)
    t = np.array(f.field_times)
    expected = tilted_dipole(t, N, INCLINATION, raan, u0, dz.earth_rotation_angle(EPOCH),
                             dz.igrf.EARTH_ROTATION_RATE if earth_turns else 0.0, EPOCH)
    got = np.array(f.field_values)
    assert np.abs(got - expected).max() < 1e-9 * np.abs(expected).max()


def test_the_real_field_at_500_km_is_20_to_50_microtesla_and_not_the_dipoles() -> None:
    # a day of a sun-synchronous orbit, the Earth turning under it: every latitude and longitude
    f = dz.igrf_field(N, INCLINATION, epoch=EPOCH, duration=86400.0, step=30.0)
    size = np.linalg.norm(f.field_values, axis=1)
    # the field at 500 km: 17–20 µT over the South Atlantic Anomaly (22–24 µT at the ground,
    # times (R_E / R)³ = 0.80), about 50 µT near the magnetic poles (60–66 µT at the ground)
    assert 15e-6 < size.min() < 20e-6 and 45e-6 < size.max() < 55e-6
    assert 20e-6 < np.median(size) < 50e-6
    dipole = dz.igrf_field(N, INCLINATION, epoch=EPOCH, duration=86400.0, step=30.0, degree=1)
    # the degrees above the dipole matter: the dipole alone overstates the field over the
    # anomaly, where the higher degrees change it by a large share of its size
    change = np.linalg.norm(np.subtract(f.field_values, dipole.field_values), axis=1) / size
    assert 0.2 < change.max() < 1.0


def read_back(field: dz.MagneticField, period: float, t_end: float) -> np.ndarray:
    """The field the core gives a magnetometer on a body at rest in world axes, at the samples
    ``0, period, 2 period, …`` before `t_end` (a B-dot of no gain: nothing turns it)."""
    bdot = dz.BDot(field, gain=1e-300, period=period)
    traj = dz.simulate(dz.System(dz.Body((1.0, 2.0, 3.0)), torques=[bdot]), (0.0, 0.0, 0.0),
                       t_end=t_end, frames=int(round(2 * t_end / period)) + 1, method="rk4",
                       dt=period / 2)
    assert np.abs(traj.omega).max() < 1e-200
    names = [(name, width) for name, width, _, _ in dz._core.model_info("bdot").state]
    start = sum(width for name, width in names[:[n for n, _ in names].index("field")])
    # the frames halfway through each hold hold the field measured at its sample
    return traj.parts["bdot"][1::2, start:start + 3]


def test_the_core_holds_the_librarys_values_at_the_knots_and_interpolates_between() -> None:
    t_end, errors = 1200.0, []
    for step in (40.0, 20.0):
        coarse = dz.igrf_field(N, INCLINATION, epoch=EPOCH, duration=t_end, step=step,
                               raan=0.3, latitude=2.0)
        fine = dz.igrf_field(N, INCLINATION, epoch=EPOCH, duration=t_end, step=step / 2,
                             raan=0.3, latitude=2.0)
        seen = read_back(coarse, step / 2, t_end)       # at the knots and halfway between
        library = np.array(fine.field_values)[:len(seen)]
        scale = np.abs(library).max()
        # at the knots, the library's values themselves
        assert np.abs(seen[0::2] - library[0::2]).max() <= 1e-14 * scale
        # halfway, the interpolation's error: at most h² max|B̈| / 8, B̈ estimated from the
        # library's own second differences
        second = np.abs(np.diff(library, 2, axis=0)).max() / (step / 2) ** 2
        error = np.abs(seen[1::2] - library[1::2]).max()
        assert 0 < error <= 1.1 * step**2 * second / 8
        errors.append(error)
    # halving the step quarters the error (second order)
    assert 3.5 < errors[0] / errors[1] < 4.5


def test_a_tabulated_field_reads_back_from_a_part_and_round_trips() -> None:
    f = dz.igrf_field(N, 0.9, epoch="2024-01-01T00:00:00", duration=100.0, step=50.0)
    part = dz.ResidualDipole(f, (0.0, 0.0, 1e-3))
    assert part.field == f and part.field is not None and part.field.tabulated
    assert not dz.MagneticField(N, 0.9).tabulated


@pytest.mark.parametrize("kwargs, error, match", [
    (dict(field_times=(0.0, 1.0)), ValueError, "field_values"),
    (dict(field_times=(0.0, 0.0), field_values=[(0.0, 0.0, 1e-5)] * 2), ValueError,
     "field_times"),
    (dict(field_times=(0.0, 1.0, 2.0), field_values=[(0.0, 0.0, 1e-5)] * 2), ValueError,
     "field_values"),
    (dict(field_times=(0.0, 1.0), field_values=[(0.0, math.nan, 1e-5)] * 2), ValueError,
     "field_values"),
])
def test_a_bad_table_is_refused_by_name(kwargs, error, match) -> None:
    with pytest.raises(error, match=match):
        dz.MagneticField(N, 0.9, **kwargs)


def test_igrf_field_refuses_bad_input_by_name() -> None:
    with pytest.raises(ValueError, match="epoch"):
        dz.igrf_field(N, 0.9, epoch="soon", duration=10.0)
    with pytest.raises(ValueError, match="degree"):
        dz.igrf_field(N, 0.9, epoch=EPOCH, duration=10.0, degree=14)
    with pytest.raises(ValueError, match="step"):
        dz.igrf_field(N, 0.9, epoch=EPOCH, duration=1e6, step=1e-3)
