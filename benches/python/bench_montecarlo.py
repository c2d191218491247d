"""Monte Carlo studies: the coverage of their intervals, the rare-event speed-up and the
throughput, measured in one run and printed.

    python benches/python/bench_montecarlo.py             # the figures of the docs (~15 min)
    python benches/python/bench_montecarlo.py --quick     # smaller cases (~1 min)
    python benches/python/bench_montecarlo.py --only coverage|rare|throughput|deployments

**Coverage.** Moments (1, 3, I_z), I_z uniform on (2.7, 3.7), spun about z at (1e-3, 1e-3, 1):
p = 0.3 by construction (z is the intermediate axis iff I_z < 3). One study of 400 × S
samples, cut into S independent studies of 400: the share whose 95% interval covers 0.3, for
Wilson and Clopper–Pearson (exact method, t_end = 1e6), beside each interval's exact coverage
at n = 400 (the binomial sum; Wilson's dips below the level, Clopper–Pearson's stays above).

**Rare events.** Moments (1, 3, I_z), I_z normal (3.3, 0.08): p = Φ(−3.75) = 8.8e-5. A plain
study of N runs against a rare-event study of the same N draws (the same seed: the same
samples) running R of them (R = N/100 and N/500): the estimates, the interval widths and the
runs each needs, the speed-up being N/R at the same width; then a rare-event study of another
seed (independent draws) for its own interval. With the exact method every run is measured;
with RK4 at T = 1000 the rare-event study is timed and the plain one extrapolated from its
measured throughput on a subset (it would take hours).

**Throughput.** Samples per second of ``ask="tumbles"``, local on 2 threads and on a 2-worker
Dask LocalCluster (1 thread each; warm, its start-up not counted), for the exact method and
RK4 at T = 1000 (dt = 0.01, 10⁵ steps a run): the paper's box dispersed by
``InertiaDispersion(moments=0.05, axes_deg=2)`` with rates drawn normal about the
intermediate axis; and, for the exact method, a cheap draw (moments from a callable) to show
the cost of the draws themselves. Medians of the repeats.

**Deployments.** A study of a deployment (``DeploymentDispersion`` of (1, 2, 3) → (1, 3, 2)
over t ∈ [1, 2], moments dispersed 2 %, RK4 at dt = 0.01 to T = 5) against the equivalent
sweep: the same samples drawn by the same generators, then ``dz.sweep`` of them. CPU time
(process time) and wall time of each; the study checked its deployments one sample at a time
and took 1.7× the sweep's time.

The machine's load average is printed before and after: the figures are only as good as the
machine was quiet.
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import time
import warnings

import numpy as np
from scipy import stats

import dzhanibekov as dz

SPIN = (1e-3, 1e-3, 1.0)


def uniform_iz(rng: np.random.Generator) -> tuple[float, float, float]:
    return (1.0, 3.0, rng.uniform(2.7, 3.7))


def rare_iz(rng: np.random.Generator) -> tuple[float, float, float]:
    return (1.0, 3.0, rng.normal(3.3, 0.08))


P_RARE = float(stats.norm.cdf((3.0 - 3.3) / 0.08))


BOX = dz.InertiaDispersion(dz.Body.box(20, 10, 15), moments=0.05, axes_deg=2.0)


def box_spin(rng: np.random.Generator) -> np.ndarray:
    # about z, the box's intermediate axis, with a wobble: (nearly) every sample tumbles
    return np.array([rng.normal(0, 0.02), rng.normal(0, 0.02), 1.0])


def cheap_moments(rng: np.random.Generator) -> tuple[float, float, float]:
    return (27.08, rng.normal(52.08, 2.6), rng.normal(41.67, 2.1))


def timed(fn, repeat: int = 1) -> tuple[float, object]:
    times, out = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times), out


def coverage(studies: int) -> None:
    n = 400 * studies
    seconds, big = timed(lambda: dz.monte_carlo(uniform_iz, SPIN, n, seed=1, t_end=1e6,
                                                 progress=False))
    parts = [big[400 * i:400 * (i + 1)] for i in range(studies)]
    print(f"coverage: {studies} studies of 400 (one study of {n}, {seconds:.1f} s, "
          f"{n / seconds:,.0f} samples/s), p = 0.3 by construction")
    counts = np.arange(401)
    pmf = stats.binom.pmf(counts, 400, 0.3)
    for method in ("wilson", "clopper-pearson"):
        cover = sum(lo <= 0.3 <= hi for lo, hi in
                    (s.confidence_interval(method=method) for s in parts))
        share = cover / studies
        # the interval's exact coverage at n = 400, p = 0.3: the binomial sum over its counts
        lo, hi = dz.montecarlo.binomial_interval(counts, 400, 0.95, method)
        exact = float((pmf * ((lo <= 0.3) & (0.3 <= hi))).sum())
        se = math.sqrt(exact * (1 - exact) / studies)
        print(f"  {method:16s} 95% interval covers 0.3 in {cover}/{studies} = {share:.1%} "
              f"(its exact coverage at n = 400: {exact:.1%}, ± {se:.1%} over {studies})")
    print(f"  whole study: p = {big.p:.4f} {big.interval}")


def rare(n: int) -> None:
    print(f"rare events: I_z ~ N(3.3, 0.08), p = {P_RARE:.3g}; {n} draws")
    plain_s, plain = timed(lambda: dz.monte_carlo(rare_iz, SPIN, n, seed=11, t_end=1e6,
                                                   progress=False))
    width = plain.interval[1] - plain.interval[0]
    print(f"  plain  seed 11 runs {plain.runs:>9,}  p = {plain.p:.3g}  interval "
          f"[{plain.interval[0]:.3g}, {plain.interval[1]:.3g}] width {width:.3g}  "
          f"{plain_s:.1f} s")
    for runs, seed in ((n // 100, 11), (n // 500, 11), (n // 500, 12)):
        s, study = timed(lambda: dz.monte_carlo(rare_iz, SPIN, n, seed=seed, t_end=1e6,
                                                 runs=runs, progress=False))
        w = study.interval[1] - study.interval[0]
        print(f"  near-sep. seed {seed} runs {study.runs:>9,}  p = {study.p:.3g}  interval "
              f"[{study.interval[0]:.3g}, {study.interval[1]:.3g}] width {w:.3g} "
              f"({w / width:.2f}× plain)  {s:.1f} s  effective runs {study.effective_runs:,.0f}"
              f"  → {n / study.runs:.0f}× fewer runs")
    # RK4 at T = 1000: the rare-event study timed, the plain one from a subset's throughput
    runs = n // 500
    rk4 = dict(t_end=1000.0, method="rk4", dt=0.01, progress=False)
    s_rare, study = timed(lambda: dz.monte_carlo(rare_iz, SPIN, n, seed=12, runs=runs, **rk4))
    subset = 4000
    s_sub, _ = timed(lambda: dz.monte_carlo(rare_iz, SPIN, subset, seed=11, **rk4))
    w = study.interval[1] - study.interval[0]
    print(f"  RK4 T=1000:  near-separatrix {runs:,} runs of {n:,} draws: {s_rare:.1f} s, p = "
          f"{study.p:.3g}, width {w:.3g}; plain {n:,} runs: ~{s_sub / subset * n:,.0f} s "
          f"(from {subset} runs in {s_sub:.1f} s) → {s_sub / subset * n / s_rare:.0f}× "
          "less time")


def throughput(n_exact: int, n_rk4: int, repeat: int) -> None:
    rk4 = dict(t_end=1000.0, method="rk4", dt=0.01)
    cases = [("exact, InertiaDispersion", BOX, n_exact, dict(t_end=1000.0)),
             ("exact, cheap draw", cheap_moments, n_exact, dict(t_end=1000.0)),
             ("rk4 T=1000, InertiaDispersion", BOX, n_rk4, rk4)]
    print("throughput (ask='tumbles'), samples/s:")
    draws_s, _ = timed(lambda: [BOX(dz.montecarlo.sample_rng(1, k)) for k in range(2000)])
    print(f"  drawing alone (generator + InertiaDispersion): {2000 / draws_s:,.0f} /s")
    results = {}
    for name, system, n, kwargs in cases:
        s, study = timed(lambda: dz.monte_carlo(system, box_spin, n, seed=3, threads=2,
                                                progress=False, **kwargs), repeat)
        results[name] = study
        print(f"  local 2 threads  {name:32s} {n / s:>10,.0f}   (n = {n}, p = {study.p:.3f})")
    try:
        import distributed
    except ImportError:
        print("  (dask not installed: no cluster figures)")
        return
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, host="127.0.0.1",
                                           dashboard_address=None, processes=True)
    with cluster, distributed.Client(cluster) as client:
        dz.monte_carlo(BOX, box_spin, 200, seed=3, t_end=10.0, client=client)  # warm up
        for name, system, n, kwargs in cases:
            s, study = timed(lambda: dz.monte_carlo(system, box_spin, n, seed=3, client=client,
                                                    chunk=max(n // 16, 64), progress=False,
                                                    **kwargs), repeat)
            same = np.array_equal(study.outcomes, results[name].outcomes)
            print(f"  dask 2 workers   {name:32s} {n / s:>10,.0f}   (the same outcomes: {same})")


def deployments(n: int) -> None:
    deployment = dz.Deployment([1.0, 2.0], [(1.0, 2.0, 3.0), (1.0, 3.0, 2.0)])
    disperse = dz.DeploymentDispersion(deployment, moments=0.02)

    def spin(rng: np.random.Generator) -> tuple[float, float, float]:
        return (rng.normal(0, 0.05), rng.normal(0, 0.05), 1.0)

    run = dict(t_end=5.0, method="rk4", dt=1e-2)

    def equivalent() -> object:
        drawn, rates = [], []
        for k in range(n):
            rng = dz.montecarlo.sample_rng(1, k)
            drawn.append(disperse(rng))
            rates.append(spin(rng))
        return dz.sweep(drawn, np.array(rates), frames=2, progress=False, **run)

    def study() -> object:
        return dz.monte_carlo(disperse, spin, n, seed=1, progress=False, **run)

    print(f"deployments: a study of {n:,} against drawing them and sweeping them")
    for name, fn in (("sweep (draws included)", equivalent), ("monte_carlo", study)):
        cpu, wall = time.process_time(), time.perf_counter()
        fn()
        cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
        print(f"  {name:24s} CPU {cpu:7.2f} s   wall {wall:7.2f} s")


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--only", choices=["coverage", "rare", "throughput", "deployments"])
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()}")
    if args.only in (None, "coverage"):
        coverage(50 if args.quick else 1000)
    if args.only in (None, "rare"):
        rare(100_000 if args.quick else 1_000_000)
    if args.only in (None, "throughput"):
        throughput(4000 if args.quick else 40_000, 200 if args.quick else 2000,
                   1 if args.quick else 3)
    if args.only in (None, "deployments"):
        deployments(20_000 if args.quick else 200_000)
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
