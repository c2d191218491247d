"""Every model per RK4 step beside the free body's, in CPU time, end to end from Python:

    python benches/python/bench_models.py                      # 10⁶ steps a run, 5 repeats
    python benches/python/bench_models.py --steps 1e7 --repeat 7
    python benches/python/bench_models.py --baseline /tmp/old  # beside another build
    python benches/python/bench_models.py --batch 256          # a damper batch vs singles

Every run: moments (1, 2, 3), ω₀ = (0.01, 0.01, 1), dt = 1e-3, 201 frames, `flips=False`
(RK4, one thread: the process's CPU time is the run's). The systems: a deployment to (1, 3, 2)
over t ∈ [100, 110] (diagonal knots) or to a tilted tensor; a damper (j = 0.05, c = 0.02); a
wheel (h = 0.5 along y); the gravity gradient (n = 0.1), with the wheel too; constant torques
in body and world axes; a tabulated body torque and a wheel schedule of 101 knots over the
run; in builds with the energy sinks, each sink alone on a hub of mass 5 and a spring–mass
damper with a constant torque (the general joint solve of parts whose mass moves). Each figure is the median of `--repeat` runs of ns per step in CPU time (wall time
beside it): CPU time holds on a loaded machine where wall time does not.

With `--baseline DIR` (a directory holding another build's `dzhanibekov` package, say a copy
of an installed one), each repeat runs both builds one after the other in fresh processes,
so the two columns see the same load: compare the ratios to the free body, like with like.

With `--batch M`: M damped bodies (moments (1, 10, 10), ω₀ = (2, ε, 0) with ε spread over
[0.01, 0.1], the damper above) over `--steps` steps each, as one `dz.simulate` batch on all
cores against M single runs one after the other; the rows are checked equal to the single
runs first.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from typing import Any

import numpy as np

MOMENTS = (1.0, 2.0, 3.0)
OMEGA0 = (0.01, 0.01, 1.0)
DT = 1e-3
TILTED = np.array([[1.0, 0.1, 0.0], [0.1, 3.0, -0.2], [0.0, -0.2, 2.0]])
# The timed processes' numpy and scipy each start an OpenBLAS thread (one per extra core) as
# they are imported (`import dzhanibekov` imports scipy), and it spins (busy-waits for work)
# a while after it starts: on a quiet machine over the first rows timed after the import (the
# free body, the deployments and the damper, ~0.1 s of runs), which read CPU time ≈ 2× wall
# time. No run calls BLAS (no row starts a thread, imports scipy or numpy.linalg work); with
# one BLAS thread there is no such thread at all (`perf record` of a run: samples in numpy's
# OpenBLAS `blas_thread_server` just after the import, none later).
ONE_BLAS_THREAD = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}


def systems(dz: Any, t_end: float) -> dict[str, Any]:
    """The systems timed, by name (built with the public API every build has)."""
    body = dz.Body(MOMENTS)
    knots = np.linspace(0.0, t_end, 101)
    vectors = np.column_stack([np.zeros(101), np.zeros(101), 1e-4 * np.sin(knots)])
    wheel = dz.Wheel((0.0, 1.0, 0.0), 0.5)
    gravity = dz.GravityGradient(0.1)
    return {
        "free": body,
        "deployment_diagonal": dz.Deployment([100.0, 110.0], [MOMENTS, (1.0, 3.0, 2.0)]),
        "deployment_tensor": dz.Deployment([100.0, 110.0], [MOMENTS, TILTED]),
        "damper": dz.System(body, parts=[dz.Damper(0.05, 0.02)]),
        "wheel": dz.System(body, parts=[wheel]),
        "gravity_gradient": dz.System(body, torques=[gravity]),
        "wheel_gravity_gradient": dz.System(body, parts=[wheel], torques=[gravity]),
        "torque_body": dz.System(body, torques=[dz.ConstantTorque((0, 0, 1e-4), "body")]),
        "torque_world": dz.System(body, torques=[dz.ConstantTorque((0, 0, 1e-4), "world")]),
        "tabulated_torque": dz.System(body, torques=[dz.TabulatedTorque(knots, vectors)]),
        "wheel_schedule": dz.System(body, parts=[
            dz.Wheel((0.0, 1.0, 0.0), (knots, 0.5 + 0.1 * np.sin(knots)))]),
        **sinks(dz),
    }


def sinks(dz: Any) -> dict[str, Any]:
    """The energy sinks (issue 31), in builds that have them: each alone on a hub of mass 5
    (a closed form each), and a spring with a constant torque (the general joint solve)."""
    if not hasattr(dz, "SpringMassDamper"):
        return {}
    hub = dz.Body.from_tensor(np.diag(MOMENTS), mass=5.0)
    spring = dz.SpringMassDamper(0.1, (0.5, 0.0, 0.0), (0.0, 0.0, 1.0), 2.0, 0.05)
    return {
        "spring_mass": dz.System(hub, parts=[spring]),
        "hinge": dz.System(hub, parts=[dz.Hinge(0.1, (0.0, 0.003, 0.003), (0.5, 0.0, 0.0),
                                                (0.0, 1.0, 0.0), (1.0, 0.0, 0.0), 0.3, 0.5,
                                                0.01)]),
        "slosh": dz.System(hub, parts=[dz.Slosh(0.1, (0.5, 0.0, 0.0), 0.3, 0.01,
                                                (1.0, 0.1, 0.0))]),
        "spring_mass_torque": dz.System(hub, parts=[spring], torques=[
            dz.ConstantTorque((0, 0, 1e-4), "body")]),
    }


def measure(steps: int) -> dict[str, tuple[float, float]]:
    """ns per step (CPU, wall) of one run of each system, in this process."""
    import dzhanibekov as dz

    t_end = steps * DT
    out = {}
    for name, system in systems(dz, t_end).items():
        dz.simulate(system, OMEGA0, t_end=10 * DT, frames=2, dt=DT, flips=False)  # warm up
        cpu, wall = time.process_time(), time.perf_counter()
        traj = dz.simulate(system, OMEGA0, t_end=t_end, frames=201, dt=DT, flips=False)
        cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
        out[name] = (cpu / traj.n_steps * 1e9, wall / traj.n_steps * 1e9)
    return out


def in_process(path: str | None, steps: int) -> dict[str, tuple[float, float]]:
    """`measure` in a fresh process importing the build at `path` (None: this one)."""
    env = dict(os.environ, **ONE_BLAS_THREAD)
    if path is not None:
        env["PYTHONPATH"] = path
    code = f"import json, sys; sys.path.insert(0, {os.path.dirname(__file__)!r}); " \
           f"import bench_models as b; print(json.dumps(b.measure({steps})))"
    run = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, check=True)
    return {k: tuple(v) for k, v in json.loads(run.stdout.strip().splitlines()[-1]).items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=float, default=1e6)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--baseline", help="a directory with another build's package")
    parser.add_argument("--batch", type=int, default=0, help="runs of a damper batch")
    args = parser.parse_args()
    if args.batch:
        damper_batch(args.batch, int(args.steps), args.repeat)
        return
    steps = int(args.steps)
    builds: dict[str, str | None] = {"this": None}
    if args.baseline:
        builds = {"baseline": args.baseline, "this": None}
    runs: dict[str, list[dict[str, tuple[float, float]]]] = {b: [] for b in builds}
    load = os.getloadavg()
    for _ in range(args.repeat):
        for build, path in builds.items():
            runs[build].append(in_process(path, steps))
    names = list(runs["this"][0])
    print(f"{steps:.0e} RK4 steps of dt = {DT} a run, medians of {args.repeat}; load average "
          f"{load[0]:.1f} before, {os.getloadavg()[0]:.1f} after")
    head = "".join(f" {b + ' ns/step':>22s} {'× free':>7s}" for b in builds)
    print(f"{'model':24s}{head}")
    for name in names:
        line = f"{name:24s}"
        for build in builds:
            if name not in runs[build][0]:   # (a model that build does not have)
                line += f" {'—':>22s} {'':>7s}"
                continue
            cpu = statistics.median(r[name][0] for r in runs[build])
            wall = statistics.median(r[name][1] for r in runs[build])
            free = statistics.median(r["free"][0] for r in runs[build])
            line += f" {cpu:9.2f} cpu {wall:7.2f} wall {cpu / free:7.2f}"
        print(line)


def damper_batch(m: int, steps: int, repeat: int) -> None:
    """A batch of `m` damped runs against `m` single runs: median seconds, and the ratio."""
    import dzhanibekov as dz

    system = dz.System(dz.Body((1.0, 10.0, 10.0)), parts=[dz.Damper(0.05, 0.02)])
    omega0 = np.column_stack([np.full(m, 2.0), np.linspace(0.01, 0.1, m), np.zeros(m)])
    run: dict[str, Any] = dict(t_end=steps * DT, frames=201, dt=DT)
    batch = dz.simulate(system, omega0, **run)
    for i in (0, m // 2, m - 1):
        single = dz.simulate(system, omega0[i], **run)
        assert np.array_equal(batch[i].omega, single.omega), i
        assert np.array_equal(batch[i].parts["damper"], single.parts["damper"]), i
    timed = {"batch": lambda: dz.simulate(system, omega0, **run),
             "singles": lambda: [dz.simulate(system, w, **run) for w in omega0]}
    seconds = {}
    for name, call in timed.items():
        times = []
        for _ in range(repeat):
            start = time.perf_counter()
            call()
            times.append(time.perf_counter() - start)
        seconds[name] = statistics.median(times)
    per_step = {k: v / (m * steps) * 1e9 for k, v in seconds.items()}
    print(f"{m} damped runs of {steps:.0e} RK4 steps (dt = {DT}), {os.cpu_count()} cores")
    for name in timed:
        print(f"{name:8s} {seconds[name]:8.3f} s  {per_step[name]:7.2f} ns per run-step")
    print(f"singles / batch = {seconds['singles'] / seconds['batch']:.2f}")


if __name__ == "__main__":
    main()
