"""The closed loop's cost, end to end from Python, in CPU time: per RK4 step and per sample of
a controller sampled at 1 Hz, beside the free body's step (issue 32's bar: a step at most 2×
the free body's, plus the cost per sample; a Python law at most a few µs a sample beyond its
own work).

    python benches/python/bench_control.py               # 10⁶ steps a run at dt = 0.01
    python benches/python/bench_control.py --steps 2e5

Each system runs with RK4 over the same time (the same samples) at dt = 0.01, 0.02, 0.05 and
0.1 (100, 50, 20 and 10 steps a sample); the least-squares line ``cost = steps · per_step +
samples · per_sample`` through the four gives both, and the largest residual says how well
that model holds. The body: moments (0.03, 0.04, 0.02) in a 500 km orbit; B-dot with its
field (a 1 Hz magnetometer); quaternion feedback on three wheels; two Python laws on three
wheels: one that does nothing (its sample is all overhead: the binding's call, the sensors,
the wheels' command) and rate damping, whose own cost is timed alone, called as often with
the same arguments. Times are the medians of `--repeat` runs in process time (the machine
may be shared), wall time beside them.

    python benches/python/bench_control.py --baseline /work/main/python   # beside another build

With `--baseline DIR` (a directory holding another build's `dzhanibekov` package), each repeat
runs both builds one after the other in fresh processes, so that both see the same load.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time
import warnings
from collections.abc import Callable
from typing import Any

# before numpy starts its OpenBLAS thread, which spins a while after it starts and would be
# counted in this process's CPU time (see bench_models.py's ONE_BLAS_THREAD)
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import dzhanibekov as dz  # noqa: E402

BODY = dz.Body((0.03, 0.04, 0.02))
OMEGA0 = (0.05, -0.03, 0.04)
N = dz.circular_orbit_rate(500e3)


def law(t: float, q: np.ndarray, omega: np.ndarray, field: np.ndarray,
        h: np.ndarray) -> np.ndarray:
    """Rate damping: the wheels take the body's rates away."""
    return -0.01 * omega


NOTHING = (0.0, 0.0, 0.0)


def empty(t: float, q: np.ndarray, omega: np.ndarray, field: np.ndarray,
          h: np.ndarray) -> tuple[float, float, float]:
    """A law that does nothing: its sample is the closed loop's overhead alone."""
    return NOTHING


def cpu(f: Callable[[], Any], repeat: int) -> tuple[float, float]:
    """Median (CPU, wall) seconds of `repeat` calls."""
    times = []
    for _ in range(repeat):
        start, wall = time.process_time(), time.perf_counter()
        f()
        times.append((time.process_time() - start, time.perf_counter() - wall))
    return statistics.median(c for c, _ in times), statistics.median(w for _, w in times)


DTS = (0.01, 0.02, 0.05, 0.1)
"""The step sizes of each system's runs. A Python law's sample may cost some µs more at some
of them than at others, whatever the steps (under CPython 3.11 a call whose frame lands at
the end of the interpreter's frame-stack chunk maps a chunk and unmaps it again at every
call), which the fit's residual shows; its figure at one step a sample is then the surer."""


def per_step_and_sample(system: Any, steps: int, repeat: int) -> list[float]:
    """[s/step CPU, wall; s/sample CPU, wall; the fit's largest residual, relative] from runs
    over the same time at each of `DTS` (see the module doc)."""
    t_end = steps * DTS[0]
    samples = math.ceil(t_end)             # at 0, 1, … < t_end
    counts = np.array([round(t_end / dt) for dt in DTS], dtype=float)
    times = np.array([cpu(lambda: dz.simulate(system, OMEGA0, t_end=t_end, frames=101, dt=dt,
                                              method="rk4", flips=False), repeat)
                      for dt in DTS])
    design = np.column_stack([counts, np.full(len(DTS), float(samples))])
    out, worst = [], 0.0
    for which in (0, 1):
        (a, b), *_ = np.linalg.lstsq(design, times[:, which], rcond=None)
        if which == 0:
            worst = float(np.max(np.abs(design @ (a, b) - times[:, 0]) / times[:, 0]))
        out += [float(a), float(b)]
    return [out[0], out[2], out[1], out[3], worst]


def measure(steps: int, repeat: int) -> dict[str, list[float]]:
    """Each row's [ns/step CPU, wall; µs/sample CPU, wall; the fit's residual]."""
    field = dz.MagneticField(N, 1.7)
    systems = {
        "free body": BODY,
        "B-dot, 1 Hz": dz.System(BODY, torques=[dz.BDot(field, gain=3e-5, period=1.0,
                                                        max_dipole=0.2)]),
        "quaternion feedback, 1 Hz": dz.System(BODY, parts=[
            dz.QuaternionFeedback(1e-3, 1e-2, period=1.0, torque_limit=1e-3)]),
        "Python law, empty, 1 Hz": dz.System(BODY, parts=[dz.Controller(empty, period=1.0)]),
        "Python law, damping, 1 Hz": dz.System(BODY, parts=[dz.Controller(law, period=1.0)]),
    }
    out = {}
    for name, system in systems.items():
        step, step_wall, sample, sample_wall, worst = per_step_and_sample(system, steps, repeat)
        out[name] = [step * 1e9, step_wall * 1e9, sample * 1e6, sample_wall * 1e6, worst]
    args_ = (1.0, np.array([1.0, 0, 0, 0]), np.zeros(3), np.zeros(3), np.zeros(3))
    calls = max(10_000, steps // 100)
    for name, f in (("empty", empty), ("damping", law)):
        own = cpu(lambda: [f(*args_) for _ in range(calls)], repeat)
        out[f"  the {name} law alone"] = [0.0, 0.0, own[0] / calls * 1e6,
                                          own[1] / calls * 1e6, 0.0]
        # one step a sample: the sample's cost read off directly (less a step's, from the
        # fit); the fit's per-sample figure is the less sure one for a Python law (see
        # `python_sample`)
        system = systems[f"Python law, {name}, 1 Hz"]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", dz.StepSizeWarning)
            whole = cpu(lambda: dz.simulate(system, OMEGA0, t_end=float(calls), frames=11,
                                            dt=1.0, method="rk4", flips=False), repeat)
        row = out[f"Python law, {name}, 1 Hz"]
        out[f"  {name} law, 1 step/sample"] = [
            0.0, 0.0, whole[0] / calls * 1e6 - row[0] * 1e-3,
            whole[1] / calls * 1e6 - row[1] * 1e-3, 0.0]
    return out


def in_process(path: str | None, steps: int) -> dict[str, list[float]]:
    """`measure` once in a fresh process importing the build at `path` (None: this one)."""
    env = dict(os.environ)
    if path is not None:
        env["PYTHONPATH"] = path
    code = f"import json, sys; sys.path.insert(0, {os.path.dirname(__file__)!r}); " \
           f"import bench_control as b; print(json.dumps(b.measure({steps}, 1)))"
    run = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, check=True)
    return dict(json.loads(run.stdout.strip().splitlines()[-1]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=float, default=1e6)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--baseline", help="a directory with another build's package")
    args = parser.parse_args()
    steps = int(args.steps)
    load = os.getloadavg()
    if args.baseline:
        builds: dict[str, str | None] = {"baseline": args.baseline, "this": None}
        runs: dict[str, list[dict[str, list[float]]]] = {b: [] for b in builds}
        for _ in range(args.repeat):
            for build, path in builds.items():
                runs[build].append(in_process(path, steps))
        figures = {b: {name: [statistics.median(r[name][k] for r in runs[b]) for k in range(5)]
                       for name in runs[b][0]} for b in builds}
    else:
        figures = {"this": measure(steps, args.repeat)}
    print(f"{steps:.0e} RK4 steps a run at dt = {DTS[0]} (and as many samples at dt = "
          f"{', '.join(map(str, DTS[1:]))}), medians of {args.repeat}; load average "
          f"{load[0]:.1f} before, {os.getloadavg()[0]:.1f} after")
    head = "".join(f" | {b:>8s} ns/step cpu (wall) × free  µs/sample cpu (wall) fit"
                   for b in figures)
    print(f"{'system':28s}{head}")
    for name in figures["this"]:
        line = f"{name:28s}"
        for rows in figures.values():
            step, step_wall, sample, sample_wall, worst = rows[name]
            free = rows["free body"][0]
            ratio = f"{step / free:7.2f}" if step else f"{'':7s}"
            fit = f"{worst:4.0%}" if step else f"{'':4s}"
            line += (f" | {step:11.1f} ({step_wall:7.1f}) {ratio} "
                     f"{sample:10.2f} ({sample_wall:7.2f}) {fit}")
        print(line)
    for build, rows in figures.items():
        for name in ("empty", "damping"):
            own = rows[f"  the {name} law alone"][2]
            fitted = rows[f"Python law, {name}, 1 Hz"][2] - own
            direct = rows[f"  {name} law, 1 step/sample"][2] - own
            print(f"{build}: the {name} Python law's sample beyond the law's own work: "
                  f"{direct:.2f} µs at one step a sample ({fitted:.2f} µs from the fit)")


if __name__ == "__main__":
    main()
