"""The closed loop (issue 32) checked against what the code cannot fake: the change of the
angular momentum in space against the integral of the torques, written here from the
dipole's and the gravity gradient's formulas; Avanzini & Giulietti's gain against half and
twice it; quaternion feedback against the closed-form second-order response; sampled runs
against the exact discrete map of the zero-order hold."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.spatial.transform import Rotation

import dzhanibekov as dz

MU, MOMENT = 3.986004418e14, 7.708e15


def dipole_world(t: np.ndarray, n: float, inclination: float) -> np.ndarray:
    """The untilted dipole's field along the orbit, world axes (Wertz App. H.2): the north
    axis d = (0, sin i, cos i), B = B_eq (d − 3 (d·r) r), B_eq = moment n² / μ."""
    d = np.array([0.0, math.sin(inclination), math.cos(inclination)])
    r = np.stack([np.cos(n * t), np.sin(n * t), np.zeros_like(t)], axis=-1)
    return MOMENT * n * n / MU * (d - 3.0 * (r @ d)[:, None] * r)


def matrices(q: np.ndarray) -> np.ndarray:
    return Rotation.from_quat(q, scalar_first=True).as_matrix()


def state(traj: dz.Trajectory, kind: str) -> dict[str, np.ndarray]:
    """A part's state by field, from the core's declaration."""
    out, at = {}, 0
    block = traj.parts[kind]
    for name, width, _, _ in dz._core.model_info(kind).state:
        out[name] = block[:, at:at + width]
        at += width
    return out


def test_momentum_in_space_changes_by_the_integral_of_the_external_torques() -> None:
    n, inclination = dz.circular_orbit_rate(500e3), 1.2
    inertia = np.array([0.03, 0.04, 0.02])
    field = dz.MagneticField(n, inclination)
    residual = (0.02, -0.01, 0.03)
    sat = dz.System(dz.Body(tuple(inertia)), torques=[
        dz.GravityGradient(n), dz.ResidualDipole(field, residual),
        dz.BDot(field, gain=4e-4, period=1.0, max_dipole=0.05)])
    per_hold, holds = 4, 600
    traj = dz.simulate(sat, (0.05, -0.03, 0.04), t_end=float(holds), frames=per_hold * holds + 1,
                       method="dop853", rtol=1e-12)
    t, m = traj.t, matrices(traj.q)
    # the dipole held over hold k, as the frames inside it show it (a frame at a sample time
    # shows the state before that sample's update)
    held = state(traj, "bdot")["dipole"]
    inside = held[1::per_hold][:holds]
    assert np.abs(inside).max() <= 0.05 and np.abs(inside).max() > 1e-3
    # the torques in world axes, from the formulas, hold by hold (the held dipole jumps at
    # each sample: each hold's ends take its own dipole)
    idx = np.arange(holds)[:, None] * per_hold + np.arange(per_hold + 1)
    tt, mm = t[idx], m[idx]
    b = dipole_world(tt.ravel(), n, inclination).reshape(holds, per_hold + 1, 3)
    dipole = inside[:, None, :] + np.array(residual)
    magnetic = np.cross(np.einsum("hfij,hfj->hfi", mm, np.broadcast_to(dipole, b.shape)), b)
    r = np.stack([np.cos(n * tt), np.sin(n * tt), np.zeros_like(tt)], axis=-1)
    r_body = np.einsum("hfji,hfj->hfi", mm, r)
    gravity = np.einsum("hfij,hfj->hfi", mm, 3 * n * n * np.cross(r_body, inertia * r_body))
    w = np.ones(per_hold + 1)
    w[1:-1:2], w[2:-1:2] = 4.0, 2.0
    h = t[1] - t[0]
    integral = np.cumsum(h / 3.0 * np.einsum("f,hfi->hi", w, magnetic + gravity), axis=0)
    momentum = np.einsum("fij,fj->fi", m, inertia * traj.omega)
    change = momentum[per_hold::per_hold] - momentum[0]
    scale = np.abs(change).max()
    assert scale > 1e-4 * np.abs(momentum[0]).max()   # the torques did change it
    assert np.abs(change - integral).max() < 1e-9 * scale


def test_wheels_alone_keep_the_momentum_in_space() -> None:
    qf = dz.QuaternionFeedback(kp=0.04, kd=0.4, period=0.5, torque_limit=0.02,
                               momentum_limit=0.2)
    sat = dz.System(dz.Body((2.0, 3.0, 4.0)), parts=[qf])
    half = math.pi / 4
    traj = dz.simulate(sat, (0.01, -0.02, 0.03), (math.cos(half), 0.0, math.sin(half), 0.0),
                       t_end=200.0, frames=401, method="dop853", rtol=1e-12)
    wheels = state(traj, "quaternion_feedback")["wheel_momentum"]
    assert np.abs(wheels).max() > 0.05                  # the wheels did take the momentum
    body = np.array([2.0, 3.0, 4.0]) * traj.omega + wheels   # body axes = the wheels' axes
    world = np.einsum("fij,fj->fi", matrices(traj.q), body)
    assert np.abs(world - world[0]).max() < 1e-10 * np.linalg.norm(world[0])


def time_to(traj: dz.Trajectory, fraction: float) -> float:
    rate = np.linalg.norm(traj.omega, axis=1)
    below = np.flatnonzero(rate < fraction * rate[0])
    return float(traj.t[below[0]]) if below.size else math.inf


@pytest.mark.parametrize("rates, fraction", [("gyro", 0.01), ("magnetometer", 1 / 30)])
def test_avanzini_and_giuliettis_gain_detumbles_faster_than_half_or_twice_it(
        rates: str, fraction: float) -> None:
    # a nearly spherical body (every axis near J_min), a polar orbit (ξ_m = 90°), 10°/s
    n, xi = dz.circular_orbit_rate(500e3), math.pi / 2
    inertia = (0.010, 0.011, 0.012)
    k = dz.detumble_gain(n, xi, min(inertia))
    field = dz.MagneticField(n, xi)
    times = {}
    for factor in (0.5, 1.0, 2.0):
        sat = dz.System(dz.Body(inertia), torques=[
            dz.BDot(field, gain=factor * k, period=1.0, rates=rates)])
        traj = dz.simulate(sat, np.radians([6.0, -5.0, 6.0]), t_end=2.5 * 2 * math.pi / n,
                           frames=2001, method="dop853")
        rate = np.linalg.norm(traj.omega, axis=1)
        assert np.all(np.diff(rate[::100]) < 0) or rates == "magnetometer"
        times[factor] = time_to(traj, fraction)
    assert times[1.0] < 0.9 * min(times[0.5], times[2.0]), times


def test_the_magnetometers_bdot_leaves_the_body_turning_with_the_field() -> None:
    # the rates fall to about twice the orbit's rate, the field direction's own, and stay
    n, xi = dz.circular_orbit_rate(500e3), math.pi / 2
    sat = dz.System(dz.Body((0.010, 0.011, 0.012)), torques=[
        dz.BDot(dz.MagneticField(n, xi), gain=dz.detumble_gain(n, xi, 0.010), period=1.0)])
    traj = dz.simulate(sat, np.radians([6.0, -5.0, 6.0]), t_end=4 * 2 * math.pi / n,
                       frames=401, method="dop853")
    late = np.linalg.norm(traj.omega[200:], axis=1) / n
    assert 0.5 < late.min() and late.max() < 4.0


def second_order(t: np.ndarray | float, wn: float, zeta: float) -> np.ndarray | float:
    """The free response of θ'' + 2ζω_n θ' + ω_n² θ = 0 from θ = 1 at rest."""
    wd = wn * math.sqrt(1 - zeta * zeta)
    return np.exp(-zeta * wn * t) * (np.cos(wd * t) + zeta / math.sqrt(1 - zeta * zeta)
                                     * np.sin(wd * t))


def settling_time(wn: float, zeta: float, band: float) -> float:
    """The last time |θ| reaches `band` (of θ₀), from the closed form: a root beyond the last
    extremum whose size exceeds the band."""
    wd = wn * math.sqrt(1 - zeta * zeta)
    k = 0
    while abs(second_order((k + 1) * math.pi / wd, wn, zeta)) > band:   # type: ignore[arg-type]
        k += 1
    # between the k-th extremum (still beyond the band... or the start) and the next one
    lo, hi = k * math.pi / wd, (k + 1) * math.pi / wd
    return brentq(lambda s: abs(second_order(s, wn, zeta)) - band, lo, hi)  # type: ignore


def test_quaternion_feedback_follows_the_second_order_closed_form() -> None:
    # a small turn about a principal axis of moment I, fast sampling, noise-free:
    # I φ'' + K_d φ' + K_p φ = 0, ω_n = √(K_p / I), ζ = K_d / (2 √(K_p I))
    inertia, wn, zeta, phi0 = 4.0, 0.2, 0.5, 0.01
    kp, kd = inertia * wn * wn, 2 * zeta * math.sqrt(inertia * wn * wn * inertia)
    sat = dz.System(dz.Body((2.0, 3.0, inertia)),
                    parts=[dz.QuaternionFeedback(kp, kd, period=1e-3)])
    traj = dz.simulate(sat, (0.0, 0.0, 0.0), (math.cos(phi0 / 2), 0, 0, math.sin(phi0 / 2)),
                       t_end=60.0, frames=6001, method="dop853", rtol=1e-10)
    phi = 2 * np.arctan2(traj.q[:, 3], traj.q[:, 0]) / phi0
    overshoot = -phi.min()
    expected = math.exp(-zeta * math.pi / math.sqrt(1 - zeta * zeta))
    assert overshoot == pytest.approx(expected, rel=0.01)
    band = 0.02
    last = np.flatnonzero(np.abs(phi) >= band)[-1]
    # the crossing between the last frame beyond the band and the next, linearly
    a, b = abs(phi[last]), abs(phi[last + 1])
    settled = traj.t[last] + (a - band) / (a - b) * (traj.t[1] - traj.t[0])
    assert settled == pytest.approx(settling_time(wn, zeta, band), rel=0.01)


def held_map(phi0: float, inertia: float, kp: float, kd: float, period: float,
             times: np.ndarray) -> np.ndarray:
    """The exact motion of a single-axis turn under a law sampled every `period` and held:
    between samples the torque u_k = −K_p 2 sin(φ_k/2) − K_d φ'_k is constant, so φ is a
    parabola; at `times` (multiples of the period)."""
    phi, rate, out, k = phi0, 0.0, [], 0
    for target in times:
        while k < round(target / period):
            u = -kp * 2 * math.sin(phi / 2) - kd * rate
            phi, rate = (phi + period * rate + period**2 * u / (2 * inertia),
                         rate + period * u / inertia)
            k += 1
        out.append(phi)
    return np.array(out)


@pytest.mark.parametrize("method, dt", [("dop853", None), ("rk4", 2.5)])
def test_sampling_at_1_hz_and_1_khz_differ_by_what_the_hold_predicts(method: str,
                                                                      dt: float | None) -> None:
    inertia, kp, kd, phi0 = 4.0, 0.16, 0.8, 0.3
    q0 = (math.cos(phi0 / 2), 0, 0, math.sin(phi0 / 2))
    t = np.arange(31.0)
    runs = {}
    for period in (1.0, 1e-3):
        sat = dz.System(dz.Body((2.0, 3.0, inertia)),
                        parts=[dz.QuaternionFeedback(kp, kd, period=period)])
        step = dt if period == 1.0 else None
        options = {"dt": step} if step else {"rtol": 1e-12}
        traj = dz.simulate(sat, (0.0, 0.0, 0.0), q0, t_end=30.0, frames=31,
                           method=method if period == 1.0 else "dop853", **options)
        runs[period] = 2 * np.arctan2(traj.q[:, 3], traj.q[:, 0])
        # each run is its own hold's exact motion: steps end on every sample (with dt = 2.5
        # a step crossing a sample would hold the old command past it)
        tol = 1e-8 if step else 1e-10
        assert np.abs(runs[period] - held_map(phi0, inertia, kp, kd, period, t)).max() < tol
    predicted = held_map(phi0, inertia, kp, kd, 1.0, t) - held_map(phi0, inertia, kp, kd, 1e-3, t)
    measured = runs[1.0] - runs[1e-3]
    assert np.abs(predicted).max() > 1e-3              # the hold matters at 1 Hz
    assert np.abs(measured - predicted).max() < 1e-6 * np.abs(predicted).max() + 1e-8
