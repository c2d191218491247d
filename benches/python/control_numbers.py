"""Closing the loop (issue 32): the numbers its closing note and docs/guide/control.md quote.

    python benches/python/control_numbers.py            # about a minute on a shared 2-core box
    python benches/python/control_numbers.py --only gain detumble

1. momentum: L in space against the integral of the external torques (gravity gradient,
   residual dipole, B-dot), written here from their formulas and integrated by Simpson's rule
   hold by hold (600 holds of 1 s, dop853 at rtol 1e-12); and a 45° wheel slew without
   external torques, L's largest relative change.
2. gain: the orbits B-dot takes to bring |ω| to 1/100 (gyro rates) and 1/30 (magnetometer)
   of its start, at half, once and twice Avanzini & Giulietti's k* = 2 n (1 + sin ξ_m) J_min
   (moments 0.010, 0.011, 0.012; polar 500 km orbit; 1 Hz; ω₀ = (6, −5, 6)°/s).
3. second: quaternion feedback, a 0.01 rad turn about the axis of I = 4, ω_n = 0.2,
   ζ = 0.5, 1 kHz: overshoot and 2 % settling time against the closed form.
4. hold: a 0.3 rad turn (I = 4, K_p = 0.16, K_d = 0.8) sampled at 1 Hz and at 1 kHz: each
   run against the exact map of its zero-order hold, and their difference against the maps'.
5. detumble: the shipped scene `detumble` (a 3U CubeSat, 0.1 × 0.1 × 0.3405 m and 4 kg as a
   uniform box, at 10°/s in a 500 km orbit inclined 97.4°; B-dot from the magnetometer at
   1 Hz, coils of 0.2 A·m², gain k*): the orbits to fall below 0.5°/s and stay there.
6. caught: the shipped scene `caught` (the paper's box, moments 52.0833, 27.0833, 41.6666,
   ω₀ = (0.01, 0.01, 1) about its intermediate axis z, under quaternion feedback toward its
   start attitude on three wheels: K_p = 10, K_d = 30, 10 Hz, gyroscopic feedforward, 5 N·m
   and 60 N·m·s limits) and the same box free: flips in 100 s, the angle from the target, the
   wheels' final momentum against |L₀| (the body at rest holds none).
7. slew: the shipped scene `slew` (the same CubeSat turned 90° about (1, 1, 0)/√2 from rest
   by three wheels of 0.015 N·m·s and 0.004 N·m under quaternion feedback at 10 Hz, ω_n = 1,
   ζ = 0.9): the overshoot, the times to within 2 %, 0.1° and 0.001°, how long each limit
   cut the command, against the torque limit's least time for the turn.
8. study: the probability that the CubeSat of 5 is detumbled (below 0.5°/s to the end)
   within three orbits, with its 95 % Wilson interval: 400 samples (seed 7, sample k's
   generator dz.montecarlo.sample_rng(7, k)) of a box of 4 kg ± 10 % and sides 0.10, 0.10,
   0.3405 m ± 5 % each, its magnetometer biased by N(0, 1 µT) per axis with 0.5 µT white
   noise seeded from the sample's generator (each sample draws its own noise), its start
   10°/s about a random axis.
"""

from __future__ import annotations

import argparse
import math

import numpy as np
from scipy.optimize import brentq
from scipy.spatial.transform import Rotation

import dzhanibekov as dz

MU, MOMENT = dz._core.EARTH_MU, dz._core.EARTH_MOMENT


def matrices(q: np.ndarray) -> np.ndarray:
    return Rotation.from_quat(q, scalar_first=True).as_matrix()


def momentum() -> None:
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
    held = dz.part_state(traj, "bdot")["dipole"][1::per_hold][:holds]
    idx = np.arange(holds)[:, None] * per_hold + np.arange(per_hold + 1)
    tt, mm = t[idx], m[idx]
    d = np.array([0.0, math.sin(inclination), math.cos(inclination)])
    r = np.stack([np.cos(n * tt), np.sin(n * tt), np.zeros_like(tt)], axis=-1)
    b = MOMENT * n * n / MU * (d - 3.0 * (r @ d)[..., None] * r)
    dipole = held[:, None, :] + np.array(residual)
    magnetic = np.cross(np.einsum("hfij,hfj->hfi", mm, np.broadcast_to(dipole, b.shape)), b)
    r_body = np.einsum("hfji,hfj->hfi", mm, r)
    gravity = np.einsum("hfij,hfj->hfi", mm, 3 * n * n * np.cross(r_body, inertia * r_body))
    w = np.ones(per_hold + 1)
    w[1:-1:2], w[2:-1:2] = 4.0, 2.0
    integral = np.cumsum((t[1] - t[0]) / 3.0 * np.einsum("f,hfi->hi", w, magnetic + gravity),
                         axis=0)
    world = np.einsum("fij,fj->fi", m, inertia * traj.omega)
    change = world[per_hold::per_hold] - world[0]
    print(f"momentum: L changed by {np.abs(change).max():.3e} (|L0| {np.abs(world[0]).max():.3e});"
          f" against the torques' integral {np.abs(change - integral).max() / np.abs(change).max():.1e}"
          " of the change")
    qf = dz.QuaternionFeedback(kp=0.04, kd=0.4, period=0.5, torque_limit=0.02,
                               momentum_limit=0.2)
    half = math.pi / 8
    traj = dz.simulate(dz.System(dz.Body((2.0, 3.0, 4.0)), parts=[qf]), (0.01, -0.02, 0.03),
                       (math.cos(half), 0.0, math.sin(half), 0.0), t_end=200.0, frames=401,
                       method="dop853", rtol=1e-12)
    wheels = dz.part_state(traj, "quaternion_feedback")["wheel_momentum"]
    world = np.einsum("fij,fj->fi", matrices(traj.q), np.array([2.0, 3.0, 4.0]) * traj.omega
                      + wheels)
    print(f"momentum: a 45° wheel slew, the wheels took up to {np.abs(wheels).max():.3f}; "
          f"L in space moved {np.abs(world - world[0]).max() / np.linalg.norm(world[0]):.1e}"
          " of |L|")


def time_to(traj: dz.Trajectory, fraction: float) -> float:
    rate = np.linalg.norm(traj.omega, axis=1)
    below = np.flatnonzero(rate < fraction * rate[0])
    return float(traj.t[below[0]]) if below.size else math.inf


def gain() -> None:
    n, xi = dz.circular_orbit_rate(500e3), math.pi / 2
    inertia = (0.010, 0.011, 0.012)
    k = dz.detumble_gain(n, xi, min(inertia))
    orbit = 2 * math.pi / n
    print(f"gain: k* = {k:.4e} N·m·s (n = {n:.5e} rad/s)")
    for rates, fraction in (("gyro", 0.01), ("magnetometer", 1 / 30)):
        row = []
        for factor in (0.5, 1.0, 2.0):
            sat = dz.System(dz.Body(inertia), torques=[
                dz.BDot(dz.MagneticField(n, xi), gain=factor * k, period=1.0, rates=rates)])
            traj = dz.simulate(sat, np.radians([6.0, -5.0, 6.0]), t_end=2.5 * orbit,
                               frames=2001, method="dop853")
            row.append(time_to(traj, fraction) / orbit)
        print(f"gain: {rates:12s} orbits to 1/{round(1 / fraction)}: k*/2 {row[0]:.3f}, "
              f"k* {row[1]:.3f}, 2k* {row[2]:.3f}")


def response(t: np.ndarray | float, wn: float, zeta: float) -> np.ndarray | float:
    wd = wn * math.sqrt(1 - zeta * zeta)
    return np.exp(-zeta * wn * t) * (np.cos(wd * t) + zeta / math.sqrt(1 - zeta * zeta)
                                     * np.sin(wd * t))


def second() -> None:
    inertia, wn, zeta, phi0 = 4.0, 0.2, 0.5, 0.01
    kp, kd = inertia * wn * wn, 2 * zeta * math.sqrt(inertia * wn * wn * inertia)
    sat = dz.System(dz.Body((2.0, 3.0, inertia)),
                    parts=[dz.QuaternionFeedback(kp, kd, period=1e-3)])
    traj = dz.simulate(sat, (0.0, 0.0, 0.0), (math.cos(phi0 / 2), 0, 0, math.sin(phi0 / 2)),
                       t_end=60.0, frames=6001, method="dop853", rtol=1e-10)
    phi = 2 * np.arctan2(traj.q[:, 3], traj.q[:, 0]) / phi0
    expected = math.exp(-zeta * math.pi / math.sqrt(1 - zeta * zeta))
    band = 0.02
    last = np.flatnonzero(np.abs(phi) >= band)[-1]
    a, b = abs(phi[last]), abs(phi[last + 1])
    settled = traj.t[last] + (a - band) / (a - b) * (traj.t[1] - traj.t[0])
    wd = wn * math.sqrt(1 - zeta * zeta)
    k = 0
    while abs(response((k + 1) * math.pi / wd, wn, zeta)) > band:
        k += 1
    closed = brentq(lambda s: abs(response(s, wn, zeta)) - band, k * math.pi / wd,
                    (k + 1) * math.pi / wd)
    print(f"second: overshoot {-phi.min():.5f} against {expected:.5f} "
          f"({abs(-phi.min() / expected - 1):.1e}); 2 % settling {settled:.3f} against "
          f"{closed:.3f} ({abs(settled / closed - 1):.1e})")


def held_map(phi0: float, inertia: float, kp: float, kd: float, period: float,
             times: np.ndarray) -> np.ndarray:
    phi, rate, out, k = phi0, 0.0, [], 0
    for target in times:
        while k < round(target / period):
            u = -kp * 2 * math.sin(phi / 2) - kd * rate
            phi, rate = (phi + period * rate + period**2 * u / (2 * inertia),
                         rate + period * u / inertia)
            k += 1
        out.append(phi)
    return np.array(out)


def hold() -> None:
    inertia, kp, kd, phi0 = 4.0, 0.16, 0.8, 0.3
    q0 = (math.cos(phi0 / 2), 0, 0, math.sin(phi0 / 2))
    t = np.arange(31.0)
    runs = {}
    for label, period, method, options in (("1 Hz dop853", 1.0, "dop853", {"rtol": 1e-12}),
                                           ("1 Hz rk4 dt=2.5", 1.0, "rk4", {"dt": 2.5}),
                                           ("1 kHz dop853", 1e-3, "dop853", {"rtol": 1e-12})):
        sat = dz.System(dz.Body((2.0, 3.0, inertia)),
                        parts=[dz.QuaternionFeedback(kp, kd, period=period)])
        traj = dz.simulate(sat, (0.0, 0.0, 0.0), q0, t_end=30.0, frames=31, method=method,
                           **options)  # type: ignore[arg-type]
        runs[label] = 2 * np.arctan2(traj.q[:, 3], traj.q[:, 0])
        err = np.abs(runs[label] - held_map(phi0, inertia, kp, kd, period, t)).max()
        print(f"hold: {label:16s} against its hold's exact map: {err:.1e} rad")
    predicted = held_map(phi0, inertia, kp, kd, 1.0, t) - held_map(phi0, inertia, kp, kd, 1e-3, t)
    measured = runs["1 Hz dop853"] - runs["1 kHz dop853"]
    print(f"hold: 1 Hz − 1 kHz up to {np.abs(measured).max():.3f} rad; against the maps' "
          f"difference {np.abs(measured - predicted).max():.1e} rad")


def detumble() -> None:
    scene = dz.SCENES["detumble"]
    (bdot,) = scene.torques
    orbit = 2 * math.pi / bdot.orbit_rate
    traj = scene.run()
    at = dz.detumbled_at(traj, math.radians(0.5))
    rate = np.degrees(np.linalg.norm(traj.omega, axis=1))
    saturated = dz.saturation(traj, "bdot")["coil"].any(axis=1).mean()
    print(f"detumble: the scene 'detumble', k* = {bdot.gain:.4e}; |ω| from {rate[0]:.2f}°/s "
          f"below 0.5°/s from {at / orbit:.3f} orbits on; at {traj.t[-1] / orbit:.0f} orbits "
          f"{rate[-1]:.3f}°/s ({math.radians(rate[-1]) / (2 * bdot.orbit_rate):.2f} × 2n); "
          f"coils saturated in {saturated:.0%} of the frames")


def caught() -> None:
    scene = dz.SCENES["caught"]
    inertia, omega0 = np.array(scene.body.inertia), np.array(scene.omega0)
    free = scene.replace(parts=(), draw=dz.scenes.Draw(path=True, figures=("path",))).run()
    traj = scene.run()
    angle = np.degrees(dz.pointing_angle(traj))
    h = np.linalg.norm(dz.part_state(traj, "quaternion_feedback")["wheel_momentum"][-1])
    cut = dz.saturation(traj, "quaternion_feedback")["torque"].any(axis=1)
    last_cut = traj.t[np.flatnonzero(cut)[-1]] if cut.any() else 0.0
    at25 = np.searchsorted(traj.t, 25.0)
    print(f"caught: the scene 'caught': free {free.flips} flips in 100 s, held {traj.flips}; "
          f"angle from target {angle[at25]:.2e}° at 25 s, {angle[-1]:.1e}° at 100 s; motors at "
          f"their limit until {last_cut:.1f} s; |h| at the end {h:.6f} against |L0| "
          f"{np.linalg.norm(inertia * omega0):.6f} ({h / np.linalg.norm(inertia * omega0) - 1:.1e})")


def slew() -> None:
    scene = dz.SCENES["slew"]
    (qf,) = scene.parts
    traj = scene.run()
    angle = np.degrees(dz.pointing_angle(traj))
    # the signed turn about the slew's axis (1, 1, 0)/√2: below zero past the target
    axis = np.array([1.0, 1.0, 0.0]) / math.sqrt(2)
    turn = np.degrees(Rotation.from_quat(traj.q, scalar_first=True).as_rotvec() @ axis)
    within = [traj.t[np.flatnonzero(angle >= a)[-1] + 1] for a in (1.8, 0.1, 1e-3)]
    cut = dz.saturation(traj, "quaternion_feedback")
    dt = traj.t[1] - traj.t[0]
    h = np.abs(dz.part_state(traj, "quaternion_feedback")["wheel_momentum"]).max()
    j = scene.body.inertia[0]
    least = 2 * math.sqrt(math.pi / 2 * j / (math.sqrt(2) * qf.torque_limit))
    wn = math.sqrt(qf.kp[0] / j)
    zeta = qf.kd[0] / (2 * math.sqrt(qf.kp[0] * j))
    linear = math.exp(-zeta * math.pi / math.sqrt(1 - zeta * zeta))
    print(f"slew: the scene 'slew' (ω_n = {wn:.3f}, ζ = {zeta:.3f}): overshoot "
          f"{-turn.min():.3f}° ({-turn.min() / 90:.2%}; unlimited, the closed form's "
          f"{linear:.2%}) at t = {traj.t[turn.argmin()]:.2f}; within 2 % (1.8°) from "
          f"{within[0]:.2f}, 0.1° from {within[1]:.2f}, 0.001° from {within[2]:.2f} s "
          f"(the torque limit's least time {least:.2f} s); torque limit cut "
          f"{cut['torque'].any(axis=1).sum() * dt:.2f} s, momentum limit "
          f"{cut['momentum'].any(axis=1).sum() * dt:.2f} s; largest wheel momentum {h:.4f} of "
          f"{qf.momentum_limit}")


def study() -> None:
    from dzhanibekov.montecarlo import binomial_interval, sample_rng

    n, inclination = dz.circular_orbit_rate(500e3), math.radians(97.4)
    orbit = 2 * math.pi / n
    field = dz.MagneticField(n, inclination)
    samples, hits, times = 400, 0, []
    for k in range(samples):
        rng = sample_rng(7, k)
        mass = 4.0 * (1 + 0.1 * rng.standard_normal())
        a, b, c = np.array([0.10, 0.10, 0.3405]) * (1 + 0.05 * rng.standard_normal(3))
        inertia = mass / 12 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])
        magnetometer = dz.Magnetometer(5e-7, tuple(rng.normal(0.0, 1e-6, 3)))
        axis = rng.standard_normal(3)
        # the sensors' seed from the sample's own generator: sample k's white noise is its own
        bdot = dz.BDot(field, gain=dz.detumble_gain(n, inclination, inertia.min()),
                       period=1.0, max_dipole=0.2, magnetometer=magnetometer,
                       seed=int(rng.integers(2**53)))
        traj = dz.simulate(dz.System(dz.Body(tuple(inertia)), torques=[bdot]),
                           math.radians(10.0) * axis / np.linalg.norm(axis), t_end=3 * orbit,
                           frames=3001, method="dop853")
        times.append(dz.detumbled_at(traj, math.radians(0.5)) / orbit)
        hits += times[-1] <= 3.0
    lo, hi = binomial_interval(hits, samples)
    q = np.percentile(times, [50, 90, 100])
    print(f"study: detumbled within 3 orbits in {hits} of {samples} samples, P in "
          f"[{float(lo):.4f}, {float(hi):.4f}] (95 %); orbits taken: median {q[0]:.2f}, "
          f"90 % {q[1]:.2f}, most {q[2]:.2f}")


PARTS = {"slew": slew, "momentum": momentum, "gain": gain, "second": second, "hold": hold,
         "detumble": detumble, "caught": caught, "study": study}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", nargs="*", choices=list(PARTS), default=list(PARTS))
    for name in parser.parse_args().only:
        PARTS[name]()


if __name__ == "__main__":
    main()
