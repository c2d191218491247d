"""A spacecraft in orbit (issue 21): the numbers its closing note quotes.

    python benches/python/orbit_numbers.py            # about a minute on a shared 2-core box

1. Pitch libration: the frequency measured from the zero crossings of 5 periods (body
   (2, 3, 1) with x along-track, y along minus the orbit normal, z nadir; n = 1; starts
   pitched 1e-4 and 1e-2 rad at rest in LVLH; dop853 at rtol 1e-12) against Hughes's closed
   form n √(3 (I_x − I_z) / I_y) (Spacecraft Attitude Dynamics, 1986, §9.3).
2. The Jacobi integral's drift over 100 orbits (n = 0.1) of a tumbling non-principal body
   (tensor [[2, -.3, .1], [-.3, 3, .2], [.1, .2, 4]], ω₀ = (0.3, -0.7, 1.1)), RK4 and dop853.
3. ns per RK4 step (dt = 0.01, 2·10⁶ steps, medians of --repeat runs, flips off) of each model
   beside the free body's, in the same session: compare the ratios.
4. A Python-callable torque's cost per RK4 step (10⁵ steps, four calls a step) against the
   built-in ConstantTorque giving the same torque, printed as a ratio.
5. ns per step of the splittings on the exact free flow (splitting_exact, splitting_exact4) on
   the gravity gradient's system of 3, beside its RK4 step (dt = 0.01, 2·10⁵ steps).

    python benches/python/orbit_numbers.py --only cost callable   # parts 3 and 4 alone
"""

from __future__ import annotations

import argparse
import math
import statistics
import time
from collections.abc import Callable

import numpy as np

import dzhanibekov as dz

TENSOR = [[2.0, -0.3, 0.1], [-0.3, 3.0, 0.2], [0.1, 0.2, 4.0]]
W0, Q0 = (0.3, -0.7, 1.1), (0.6, -0.2, 0.7, 0.3)


def libration() -> None:
    inertia, n = (2.0, 3.0, 1.0), 1.0
    expected = dz.pitch_libration_rate(inertia, n)
    sat = dz.System(dz.Body(inertia), torques=[dz.GravityGradient(n)])
    for pitch0 in (1e-4, 1e-2):
        traj = dz.simulate(sat, *dz.lvlh_start(n, pitch=pitch0), t_end=10 * math.pi / expected,
                           frames=4001, method="dop853", rtol=1e-12, atol=1e-14)
        q = dz.lvlh_attitude(traj)
        s = 2 * np.arctan2(q[:, 2], q[:, 0])
        k = np.nonzero((s[:-1] > 0) & (s[1:] <= 0))[0]
        t = traj.t[k] + s[k] / (s[k] - s[k + 1]) * (traj.t[k + 1] - traj.t[k])
        measured = 2 * math.pi / float(np.mean(np.diff(t)))
        print(f"libration, pitch {pitch0:g} rad: measured {measured:.10f}, closed form "
              f"{expected:.10f}, relative {measured / expected - 1:+.2e}")


def jacobi() -> None:
    n = 0.1
    sat = dz.System(dz.Body.from_tensor(TENSOR), torques=[dz.GravityGradient(n)])
    t_end = 100 * 2 * math.pi / n
    for method, kw in [("rk4", {"dt": 0.01}), ("rk4", {"dt": 0.005}),
                       ("dop853", {"rtol": 1e-10}), ("dop853", {"rtol": 1e-12, "atol": 1e-14})]:
        traj = dz.simulate(sat, W0, Q0, t_end=t_end, method=method, **kw)
        print(f"Jacobi drift over 100 orbits, {method} {kw}: {traj.drift.jacobi:.2e} "
              f"({traj.n_steps} steps)")


def cost(repeat: int) -> None:
    body = dz.Body.from_tensor(TENSOR)
    gg = dz.GravityGradient(0.1)
    systems = {
        "free body": body,
        "wheel": dz.System(body, parts=[dz.Wheel((0, 1, 0), 0.5)]),
        "gravity gradient": dz.System(body, torques=[gg]),
        "wheel + gravity gradient": dz.System(body, parts=[dz.Wheel((0, 1, 0), 0.5)],
                                              torques=[gg]),
        "constant torque (body)": dz.System(body, torques=[dz.ConstantTorque((0, 0, 1e-4))]),
        "constant torque (world)": dz.System(body, torques=[
            dz.ConstantTorque((0, 0, 1e-4), "world")]),
        "damper": dz.System(body, parts=[dz.Damper(0.05, 0.02)]),
        # 101 knots over the run: a step split in two at each
        "tabulated torque (body)": dz.System(body, torques=[dz.TabulatedTorque(
            np.linspace(0.0, 2e4, 101), np.tile((0.0, 0.0, 1e-4), (101, 1)))]),
        "wheel schedule": dz.System(body, parts=[dz.Wheel((0, 1, 0), (
            np.linspace(0.0, 2e4, 101), np.linspace(0.0, 0.5, 101)))]),
    }
    times: dict[str, list[float]] = {name: [] for name in systems}
    for _ in range(repeat):
        for name, system in systems.items():
            start = time.perf_counter()
            traj = dz.simulate(system, W0, t_end=2e4, dt=0.01, frames=11, method="rk4",
                               flips=False)
            times[name].append((time.perf_counter() - start) / traj.n_steps * 1e9)
    base = statistics.median(times["free body"])
    for name, ns in times.items():
        m = statistics.median(ns)
        print(f"RK4 per step, {name}: {m:.0f} ns ({m / base:.2f}× the free body)")


def splittings(repeat: int) -> None:
    system = dz.System(dz.Body.from_tensor(TENSOR), torques=[dz.GravityGradient(0.1)])
    times: dict[str, list[float]] = {m: [] for m in ("rk4", "splitting_exact", "splitting_exact4")}
    for _ in range(repeat):
        for method in times:
            start = time.perf_counter()
            traj = dz.simulate(system, W0, t_end=2e3, dt=0.01, frames=11, method=method,
                               flips=False)
            times[method].append((time.perf_counter() - start) / traj.n_steps * 1e9)
    base = statistics.median(times["rk4"])
    for method, ns in times.items():
        m = statistics.median(ns)
        print(f"gravity gradient, {method} per step: {m:.0f} ns ({m / base:.1f}× RK4's)")


def callable_cost(repeat: int) -> None:
    body = dz.Body.from_tensor(TENSOR)
    tau = np.array([0.0, 0.0, 1e-4])
    systems = {
        "ConstantTorque": dz.System(body, torques=[dz.ConstantTorque(tau)]),
        "CallableTorque": dz.System(body, torques=[dz.CallableTorque(lambda t, q, w: tau)]),
    }
    times: dict[str, list[float]] = {name: [] for name in systems}
    for _ in range(repeat):
        for name, system in systems.items():
            start = time.perf_counter()
            traj = dz.simulate(system, W0, t_end=1000.0, dt=0.01, frames=11, method="rk4",
                               flips=False)
            times[name].append((time.perf_counter() - start) / traj.n_steps * 1e9)
    built_in, python = (statistics.median(times[k]) for k in systems)
    print(f"RK4 per step, Python-callable torque: {python:.0f} ns, ConstantTorque "
          f"{built_in:.0f} ns: {python / built_in:.0f}× (about {(python - built_in) / 4:.0f} ns "
          f"a call, four calls a step)")


PARTS: dict[str, Callable[[int], None]] = {
    "libration": lambda repeat: libration(), "jacobi": lambda repeat: jacobi(),
    "cost": cost, "callable": callable_cost, "splittings": splittings}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--only", nargs="+", choices=sorted(PARTS), default=list(PARTS))
    args = parser.parse_args()
    for name in args.only:
        PARTS[name](args.repeat)


if __name__ == "__main__":
    main()
