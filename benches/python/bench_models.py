"""Bodies that change, end to end from Python: ns per RK4 step of a deployment and of a damped
body beside the free body's, and the drift of what each keeps.

    python benches/python/bench_models.py              # 10⁷ steps per run
    python benches/python/bench_models.py --steps 1e6

Every run: moments (1, 2, 3), ω₀ = (0.01, 0.01, 1), dt = 1e-3, 201 frames, `flips=False` for
the free body (the models locate none). The deployment goes to (1, 3, 2) over t ∈ [100, 110]
(diagonal knots) or to a tilted tensor; the damper is j = 0.05, c = 0.02. Times are medians
of `--repeat` runs (the machine may be shared: compare ratios).
"""

from __future__ import annotations

import argparse
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
    args = parser.parse_args()
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


if __name__ == "__main__":
    main()
