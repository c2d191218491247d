"""Bodies that change, end to end from Python: ns per RK4 step of a deployment and of a damped
body beside the free body's, and the drift of what each keeps.

    python benches/python/bench_models.py              # 10⁷ steps per run
    python benches/python/bench_models.py --steps 1e6
    python benches/python/bench_models.py --batch 256  # a damper batch against single runs

Every run: moments (1, 2, 3), ω₀ = (0.01, 0.01, 1), dt = 1e-3, 201 frames, `flips=False` for
the free body (the models locate none). The deployment goes to (1, 3, 2) over t ∈ [100, 110]
(diagonal knots) or to a tilted tensor; the damper is j = 0.05, c = 0.02. Times are medians
of `--repeat` runs (the machine may be shared: compare ratios).

With `--batch M`: M damped bodies (moments (1, 10, 10), ω₀ = (2, ε, 0) with ε spread over
[0.01, 0.1], the damper above) over `--steps` steps each, as one `dz.simulate` batch on all
cores against M single runs one after the other; the rows are checked equal to the single
runs first.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from typing import Any

import numpy as np

import dzhanibekov as dz

MOMENTS = (1.0, 2.0, 3.0)
OMEGA0 = (0.01, 0.01, 1.0)
DT = 1e-3
TILTED = np.array([[1.0, 0.1, 0.0], [0.1, 3.0, -0.2], [0.0, -0.2, 2.0]])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=float, default=1e7)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--batch", type=int, default=0, help="runs of a damper batch")
    args = parser.parse_args()
    if args.batch:
        damper_batch(args.batch, int(args.steps), args.repeat)
        return
    steps = int(args.steps)
    t_end = steps * DT
    cases: dict[str, tuple[Any, dict[str, Any]]] = {
        "free": (MOMENTS, dict(flips=False)),
        "deployment (diagonal)": (dz.Deployment([100.0, 110.0], [MOMENTS, (1.0, 3.0, 2.0)]), {}),
        "deployment (tensor)": (dz.Deployment([100.0, 110.0], [MOMENTS, TILTED]), {}),
        "damper": (MOMENTS, dict(damper=dz.Damper(0.05, 0.02))),
    }
    print(f"{steps:.0e} RK4 steps of dt = {DT}, t_end = {t_end:g}")
    print(f"{'model':24s} {'ns/step':>8s} {'× free':>7s} {'L_world':>9s} {'|q|':>9s}")
    baseline = None
    for name, (body, kwargs) in cases.items():
        times = []
        for _ in range(args.repeat):
            start = time.perf_counter()
            traj = dz.simulate(body, OMEGA0, t_end=t_end, frames=201, dt=DT, **kwargs)
            times.append(time.perf_counter() - start)
        ns = statistics.median(times) / traj.n_steps * 1e9
        baseline = baseline or ns
        print(f"{name:24s} {ns:8.2f} {ns / baseline:7.2f} {traj.drift.momentum_world:9.1e} "
              f"{traj.drift.q_norm:9.1e}")


def damper_batch(m: int, steps: int, repeat: int) -> None:
    """A batch of `m` damped runs against `m` single runs: median seconds, and the ratio."""
    body, damper = (1.0, 10.0, 10.0), dz.Damper(0.05, 0.02)
    omega0 = np.column_stack([np.full(m, 2.0), np.linspace(0.01, 0.1, m), np.zeros(m)])
    run: dict[str, Any] = dict(t_end=steps * DT, frames=201, dt=DT, damper=damper)
    batch = dz.simulate(body, omega0, **run)
    for i in (0, m // 2, m - 1):
        single = dz.simulate(body, omega0[i], **run)
        assert np.array_equal(batch[i].omega, single.omega), i
        assert np.array_equal(batch[i].sigma, single.sigma), i
    timed = {"batch": lambda: dz.simulate(body, omega0, **run),
             "singles": lambda: [dz.simulate(body, w, **run) for w in omega0]}
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
