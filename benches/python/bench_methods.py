"""Long runs of every method: time per step and the drift of each invariant.

    python benches/python/bench_methods.py            # 10⁷ steps per fixed-step method
    python benches/python/bench_methods.py --steps 1e6

The case is the paper's fig. 3b (u0 = 0.01, v0 = 0.1, w0 = 0.03) at dt = 0.01 (dt·Ω ≈ 1e-3),
so 10⁷ steps span t = 10⁵ (about 170 flip periods). The adaptive methods cover the same span
at rtol = 1e-10. The issue's target: the splitting keeps |L| to 1e-13 relative over 10⁷
steps. Times are medians of `--repeat` runs (the machine may be shared: compare ratios).
"""

from __future__ import annotations

import argparse
import statistics
import time

import dzhanibekov as dz

OMEGA0 = (0.01, 0.1, 0.03)
DT = 1e-2


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=float, default=1e7)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    steps = int(args.steps)
    body = dz.Body(dz.PAPER_INERTIA)
    t_end = steps * DT
    print(f"fig. 3b, t_end = {t_end:g}, {steps:.0e} steps of dt = {DT} for fixed-step methods")
    print(f"{'method':14s} {'steps':>10s} {'ns/step':>8s} {'s/run':>7s} {'× rk4':>6s} "
          f"{'energy':>9s} {'|L|':>9s} {'L_world':>9s} {'|q|':>9s}")
    baseline = None
    for method in dz.METHODS:
        if method in ("dopri5", "dop853"):
            kwargs = dict(dt=None, rtol=1e-10)
        else:
            kwargs = dict(dt=DT)
        times, traj = [], None
        for _ in range(args.repeat):
            start = time.perf_counter()
            traj = dz.simulate(body, OMEGA0, t_end=t_end, frames=201, method=method, **kwargs)
            times.append(time.perf_counter() - start)
        assert traj is not None
        seconds = statistics.median(times)
        # the exact method takes no steps: its cost is per frame, whatever t_end
        per_step = f"{seconds / traj.n_steps * 1e9:8.1f}" if traj.n_steps else f"{'—':>8s}"
        baseline = baseline or seconds
        d = traj.drift
        print(f"{method:14s} {traj.n_steps:10d} {per_step} {seconds:7.3f} "
              f"{seconds / baseline:6.2f} {d.energy:9.2e} {d.momentum:9.2e} "
              f"{d.momentum_world:9.2e} {d.q_norm:9.2e}")


if __name__ == "__main__":
    main()
