"""The closed loop's cost, end to end from Python, in CPU time: per RK4 step and per sample of
a controller sampled at 1 Hz, beside the free body's step (issue 32's bar: a step at most 2×
the free body's, plus the cost per sample; a Python law at most a few µs a sample beyond its
own work).

    python benches/python/bench_control.py               # 2·10⁶ steps a run
    python benches/python/bench_control.py --steps 2e5

Each system runs twice with RK4, at dt = 0.01 and dt = 0.1 (100 and 10 steps a sample):
``cost = steps · per_step + samples · per_sample`` gives both. The body: moments (0.03,
0.04, 0.02) in a 500 km orbit; B-dot with its field (a 1 Hz magnetometer); quaternion
feedback on three wheels; a Python law (rate damping on the wheels) whose own cost is timed
alone, called as often with the same arguments. Times are the medians of `--repeat` runs
(process time: the machine may be shared).
"""

from __future__ import annotations

import argparse
import math
import statistics
import time
from collections.abc import Callable
from typing import Any

import numpy as np

import dzhanibekov as dz

BODY = dz.Body((0.03, 0.04, 0.02))
OMEGA0 = (0.05, -0.03, 0.04)
N = dz.circular_orbit_rate(500e3)


def law(t: float, q: np.ndarray, omega: np.ndarray, field: np.ndarray,
        h: np.ndarray) -> np.ndarray:
    """Rate damping: the wheels take the body's rates away."""
    return -0.01 * omega


def cpu(f: Callable[[], Any], repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.process_time()
        f()
        times.append(time.process_time() - start)
    return statistics.median(times)


def per_step_and_sample(system: Any, steps: int, repeat: int) -> tuple[float, float]:
    """Seconds per RK4 step and per sample, from runs at 100 and 10 steps a sample."""
    rows = []
    t_end = steps * 0.01                   # the same time, as many samples (at 0, 1, … < t_end)
    for dt in (0.01, 0.1):
        seconds = cpu(lambda: dz.simulate(system, OMEGA0, t_end=t_end, frames=101, dt=dt,
                                          method="rk4", flips=False), repeat)
        rows.append((round(t_end / dt), math.ceil(t_end), seconds))
    (s1, k1, c1), (s2, k2, c2) = rows
    # c = s · a + k · b, the same samples k1 = k2
    a = (c1 - c2) / (s1 - s2)
    return a, (c1 - s1 * a) / k1


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=float, default=2e6)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    steps = int(args.steps)
    free_t = cpu(lambda: dz.simulate(BODY, OMEGA0, t_end=steps * 0.01, frames=101, dt=0.01,
                                     method="rk4", flips=False), args.repeat)
    free = free_t / steps
    field = dz.MagneticField(N, 1.7)
    systems = {
        "B-dot, 1 Hz": dz.System(BODY, torques=[dz.BDot(field, gain=3e-5, period=1.0,
                                                        max_dipole=0.2)]),
        "quaternion feedback, 1 Hz": dz.System(BODY, parts=[
            dz.QuaternionFeedback(1e-3, 1e-2, period=1.0, torque_limit=1e-3)]),
        "Python law, 1 Hz": dz.System(BODY, parts=[dz.Controller(law, period=1.0)]),
    }
    print(f"{steps:.0e} RK4 steps a run, CPU time; the free body: {free * 1e9:.1f} ns a step")
    print(f"{'system':28s} {'ns/step':>8s} {'× free':>7s} {'µs/sample':>10s}")
    for name, system in systems.items():
        step, sample = per_step_and_sample(system, steps, args.repeat)
        print(f"{name:28s} {step * 1e9:8.1f} {step / free:7.2f} {sample * 1e6:10.2f}")
        if name.startswith("Python"):
            args_ = (1.0, np.array([1.0, 0, 0, 0]), np.zeros(3), np.zeros(3), np.zeros(3))
            calls = max(10_000, steps // 100)
            own = cpu(lambda: [law(*args_) for _ in range(calls)], args.repeat) / calls
            print(f"{'  the law alone':28s} {'':8s} {'':7s} {own * 1e6:10.2f}")
            print(f"{'  the loop beyond it':28s} {'':8s} {'':7s} {(sample - own) * 1e6:10.2f}")


if __name__ == "__main__":
    main()
