"""RK4's silent dissipation and its stability limit, measured against the prediction.

    python benches/python/bench_rk4_guard.py

For several orbits, with Ω = √(2E / I_min) the bound of |ω|: the fraction of |q| lost over
10⁴ radians (Ω t = 10⁴) at dt·Ω = 0.5 and 1, beside 1 − |R(iy)|ⁿ (y = dt·Ω/2,
|R(iy)|² = 1 − y⁶/72 + y⁸/576); then, scanning dt·Ω from 2 to 6, where runs of 10⁴ radians
diverge ("D": the core's error; "x": finite but blown up; ".": fine).
"""

from __future__ import annotations

import warnings

import numpy as np

import dzhanibekov as dz

ORBITS = [
    ("spin about the minor axis", (1.0, 2.0, 3.0), (1.0, 0.0, 0.0)),
    ("  ... with a wobble of 1e-3", (1.0, 2.0, 3.0), (1.0, 1e-3, 1e-3)),
    ("spin about the major axis", (1.0, 2.0, 3.0), (0.0, 0.0, 1.0)),
    ("  ... with a wobble of 1e-3", (1.0, 2.0, 3.0), (1e-3, 1e-3, 1.0)),
    ("paper fig. 3a", dz.PAPER_INERTIA, (0.01, 0.01, 1.0)),
    ("paper fig. 3b", dz.PAPER_INERTIA, (0.01, 0.1, 0.03)),
    ("generic", (1.0, 1.7, 2.3), (0.4, -0.9, 0.6)),
]


def predicted(h_rate: float, n: int) -> float:
    y = h_rate / 2
    return 1 - (1 - y**6 / 72 + y**8 / 576) ** (n / 2)


def main() -> None:
    warnings.simplefilter("ignore", dz.StepSizeWarning)
    np.seterr(over="ignore")  # |q| of a blown-up run
    print("fraction of |q| lost over 10⁴ radians")
    print(f"{'orbit':30s} {'Ω':>7s} {'dt·Ω=0.5':>9s} {'predicted':>9s} {'dt·Ω=1':>9s} "
          f"{'predicted':>9s}")
    for name, inertia, omega0 in ORBITS:
        rate = np.sqrt(np.dot(inertia, np.square(omega0)) / min(inertia))
        row = f"{name:30s} {rate:7.4f}"
        for h_rate in (0.5, 1.0):
            traj = dz.simulate(dz.Body(inertia), omega0, t_end=1e4 / rate, frames=2,
                               dt=h_rate / rate, flips=False)
            lost = 1 - np.linalg.norm(traj.q[-1])
            row += f" {lost:9.4f} {predicted(h_rate, traj.n_steps):9.4f}"
        print(row)
    scan = np.arange(2.0, 6.01, 0.2)
    print(f"\ndivergence over 10⁴ radians, dt·Ω = {scan[0]:g} to {scan[-1]:g} by 0.2")
    for name, inertia, omega0 in ORBITS:
        rate = np.sqrt(np.dot(inertia, np.square(omega0)) / min(inertia))
        marks = ""
        for h_rate in scan:
            try:
                traj = dz.simulate(dz.Body(inertia), omega0, t_end=1e4 / rate, frames=2,
                                   dt=h_rate / rate, flips=False)
                blown = np.linalg.norm(traj.q[-1]) > 10 or np.abs(traj.omega).max() > 10 * rate
                marks += "x" if blown else "."
            except ValueError:
                marks += "D"
        first = next((f"{h:.1f}" for h, m in zip(scan, marks) if m != "."), "none")
        print(f"{name:30s} {marks}  first at dt·Ω = {first}")


if __name__ == "__main__":
    main()
