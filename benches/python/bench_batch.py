"""Times batched RK4 beside its baselines in one run and prints medians and ratios.

    python benches/python/bench_batch.py            # 4096 runs x 1000 RK4 steps (a few seconds)
    python benches/python/bench_batch.py --quick    # 1024 runs x 200 steps

Figures are nanoseconds per run-step (one RK4 step of one trajectory), end to end from
Python (conversion, step planning and allocation included), the median of several repeats:
the batch on 1 and on 2 threads (their ratio is the scaling), with and without flip
detection, each SIMD kernel on one thread, a sweep (flips, tilt, drift and exact period per
run), a plain Python loop of single `dz.simulate` runs, a NumPy RK4 vectorised over the
batch, and a structure-of-arrays C loop on one core (benches/c/rk4_soa.c, built here with
cc -O3 -march=native). The machine's load average is printed before and after: the figures
are only as good as the machine was quiet.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

import dzhanibekov as dz
from dzhanibekov import _core

HERE = Path(__file__).resolve().parent
INERTIA = np.array(dz.PAPER_INERTIA)


def median_seconds(fn, repeat: int) -> float:
    fn()  # warm up: page faults, thread pool
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def starts(runs: int) -> np.ndarray:
    """Rates near each axis and between, a mix that flips and wobbles."""
    return np.random.default_rng(0).normal(size=(runs, 3)) * [0.3, 0.3, 1.0]


def numpy_rk4(omega: np.ndarray, steps: int, h: float) -> np.ndarray:
    """Classic RK4 of eq. 1, vectorised over the runs: one array per component."""
    ix, iy, iz = INERTIA
    a, b, c = (iy - iz) / ix, (iz - ix) / iy, (ix - iy) / iz
    x = [omega[:, 0].copy(), omega[:, 1].copy(), omega[:, 2].copy(), np.ones(len(omega)),
         np.zeros(len(omega)), np.zeros(len(omega)), np.zeros(len(omega))]

    def f(u, v, w, q0, q1, q2, q3):
        return (a * v * w, b * u * w, c * u * v, -0.5 * (q1 * u + q2 * v + q3 * w),
                0.5 * (q0 * u + q2 * w - q3 * v), 0.5 * (q0 * v + q3 * u - q1 * w),
                0.5 * (q0 * w + q1 * v - q2 * u))

    for _ in range(steps):
        k1 = f(*x)
        k2 = f(*(xi + 0.5 * h * ki for xi, ki in zip(x, k1)))
        k3 = f(*(xi + 0.5 * h * ki for xi, ki in zip(x, k2)))
        k4 = f(*(xi + h * ki for xi, ki in zip(x, k3)))
        x = [xi + h / 6 * (p + 2 * (q + r) + s) for xi, p, q, r, s in zip(x, k1, k2, k3, k4)]
    return np.stack(x, axis=1)


def c_soa_seconds(runs: int, steps: int) -> float | None:
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        return None
    with tempfile.TemporaryDirectory() as tmp:
        exe = Path(tmp) / "rk4_soa"
        subprocess.run([cc, "-O3", "-march=native", "-o", str(exe),
                        str(HERE.parent / "c" / "rk4_soa.c")], check=True)
        out = subprocess.run([str(exe), str(runs), str(steps), "1e-3"], check=True,
                             capture_output=True, text=True).stdout
    return float(out.split()[0])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="smaller sizes, for a smoke run")
    parser.add_argument("--repeat", type=int, default=9, help="repeats per figure (median)")
    args = parser.parse_args()
    runs, steps = (1024, 200) if args.quick else (4096, 1000)
    omega = starts(runs)
    t_end = steps * 1e-3
    work = runs * steps
    print(f"load average before: {os.getloadavg()[0]:.2f} (2 cores); "
          f"SIMD kernels here: {', '.join(_core.instruction_sets())}")

    def batch(threads: int, flips: bool) -> None:
        dz.simulate(INERTIA, omega, t_end=t_end, frames=2, dt=1e-3, flips=flips, threads=threads)

    rows: list[tuple[str, float]] = []
    for flips in (False, True):
        for threads in (1, 2):
            seconds = median_seconds(lambda: batch(threads, flips), args.repeat)
            label = f"batch, {threads} thread{'s' if threads > 1 else ''}" + (
                ", flips located" if flips else "")
            rows.append((label, seconds / work * 1e9))
    q = np.tile([1.0, 0.0, 0.0, 0.0], (len(omega), 1))
    system = [dz.System(dz.Body(INERTIA))._core]
    options = _core.RunOptions(t_end, 2, dt=1e-3, method="rk4", flips=False, threads=1)
    for isa in _core.instruction_sets():
        seconds = median_seconds(lambda: _core.simulate_batch(
            system, omega, q, options, True, isa), args.repeat)
        rows.append((f"core batch, 1 thread, {isa} kernel", seconds / work * 1e9))
    seconds = median_seconds(lambda: dz.sweep(INERTIA, omega, t_end=t_end, frames=2, dt=1e-3),
                             args.repeat)
    rows.append(("sweep, 2 threads (flips, tilt, drift, exact period)", seconds / work * 1e9))

    loop_runs = 256
    seconds = median_seconds(lambda: [dz.simulate(INERTIA, w, t_end=t_end, frames=2, dt=1e-3,
                                                  flips=False) for w in omega[:loop_runs]], 3)
    rows.append((f"Python loop of single dz.simulate ({loop_runs} runs)",
                 seconds / (loop_runs * steps) * 1e9))
    np_steps = max(steps // 10, 20)
    seconds = median_seconds(lambda: numpy_rk4(omega, np_steps, 1e-3), 3)
    rows.append((f"NumPy RK4 vectorised over the batch ({np_steps} steps)",
                 seconds / (runs * np_steps) * 1e9))
    c = c_soa_seconds(runs, steps)
    if c is not None:
        rows.append(("C structure-of-arrays RK4, 1 core, cc -O3 -march=native", c * 1e9))

    reference = rows[1][1]
    print(f"{runs} runs x {steps} RK4 steps, ns per run-step (ratio = time / batch on 2 threads)")
    for name, ns in rows:
        print(f"  {name:<58} {ns:>9.2f} ns {ns / reference:>8.2f}x")
    one, two = rows[0][1], rows[1][1]
    print(f"  scaling 1 -> 2 threads: {one / two:.2f}x (flips located: "
          f"{rows[2][1] / rows[3][1]:.2f}x); target <= 3 ns per run-step and >= 1.8x")
    print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
