"""Every headline ratio of the core's speed beside its target, in CPU time and wall time.

    python benches/python/ratios.py --quick     # under 30 s on a loaded 2-core machine
    python benches/python/ratios.py             # the full sizes (1e7 steps; about a minute)
    python benches/python/ratios.py --json out.json
    python benches/python/ratios.py --quick --builds before/ after/ --rounds 3

Each row times the package beside its baseline in the same run, interleaved (one repeat of
every case, then the next), and prints medians over the repeats:

- one RK4 run of the paper's box (1e7 steps, 201 frames, dt = 1e-3), flips located and not,
  against the plain C loop of benches/c/rk4.c (built here: cc -O3 -march=native);
- a batch of 4096 runs x 1000 RK4 steps on 2 threads against the structure-of-arrays C loop
  of benches/c/rk4_soa.c on one thread (the batch's time is its critical path: the most CPU
  time any one thread spent, which is the wall time of an unloaded machine);
- a 10-step `dz.simulate` call, in microseconds;
- the gravity gradient, a damper and a full-tensor deployment per RK4 step against the free
  body (moments (1, 2, 3), 201 frames, flips off).

CPU time is the process's (or, for the batch, the busiest thread's) and is what the ratios and
targets use: on a shared machine the wall time of both sides stretches with the load, and of
the two, only CPU time measures the code. The load average is printed before and after.

`--builds DIR ...` runs this script once per build (with `PYTHONPATH=DIR`, a directory holding
a `dzhanibekov` package with its compiled core), interleaved over `--rounds` rounds, and
prints each row's median per build side by side: before/after figures from one run.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
INERTIA = (52.0833, 27.0833, 41.6666)  # the paper's box (dz.PAPER_INERTIA)
OMEGA0 = (0.01, 0.01, 1.0)
DT = 1e-3
MOMENTS = (1.0, 2.0, 3.0)
TILTED = [[1.0, 0.1, 0.0], [0.1, 3.0, -0.2], [0.0, -0.2, 2.0]]


def thread_cpu() -> dict[str, int]:
    """Nanoseconds each thread of this process has run (Linux's schedstat); empty elsewhere."""
    out = {}
    try:
        for tid in os.listdir("/proc/self/task"):
            with open(f"/proc/self/task/{tid}/schedstat") as f:
                out[tid] = int(f.read().split()[0])
    except OSError:
        return {}
    return out


def timed(fn: Callable[[], object], threads: bool = False) -> tuple[float, float]:
    """(wall, CPU) seconds of one call. With `threads`, CPU is the critical path: the calling
    thread's CPU time plus the busiest other thread's (the calling thread waits while the
    pool works), which is the wall time of a machine that has a core for each thread."""
    before = thread_cpu() if threads else {}
    wall, cpu = time.perf_counter(), time.process_time()
    fn()
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    if threads and before:
        after = thread_cpu()
        main = str(os.getpid())
        spent = {t: after[t] - before.get(t, 0) for t in after}
        cpu = (spent.pop(main, 0) + max(spent.values(), default=0)) * 1e-9
    return wall, cpu


class C:
    """The C baselines, built once with cc -O3 -march=native; each call runs one repeat."""

    def __init__(self, tmp: Path) -> None:
        cc = shutil.which("cc") or shutil.which("gcc")
        if cc is None:
            raise SystemExit("ratios.py needs a C compiler (cc) for its baselines")
        self.exe = {}
        for name in ("rk4", "rk4_soa"):
            exe = tmp / name
            subprocess.run([cc, "-O3", "-march=native", "-o", str(exe),
                            str(HERE.parent / "c" / f"{name}.c")], check=True)
            self.exe[name] = str(exe)

    def run(self, name: str, *args: object) -> tuple[float, float]:
        """(wall, CPU) seconds per step (or run-step) of one repeat, as the program times it."""
        out = subprocess.run([self.exe[name], *map(str, args), "1"], check=True,
                             capture_output=True, text=True).stdout.split()
        return float(out[0]), float(out[2])


def cases(quick: bool, c: C) -> dict[str, tuple[Callable[[], tuple[float, float]], float]]:
    """Each case: one timed repeat giving (wall, CPU) seconds, and the units it is divided by
    (the steps or run-steps it did; 1 for a call)."""
    import dzhanibekov as dz

    steps = 3 * 10**6 if quick else 10**7
    model_steps = 10**6 if quick else 3 * 10**6
    body = dz.Body(INERTIA)
    runs, batch_steps = 4096, 1000
    omega = np.random.default_rng(0).normal(size=(runs, 3)) * [0.3, 0.3, 1.0]
    moments = dz.Body(MOMENTS)
    models = {
        "free body (1, 2, 3)": moments,
        "gravity gradient": dz.System(moments, torques=[dz.GravityGradient(0.1)]),
        "damper": dz.System(moments, parts=[dz.Damper(0.05, 0.02)]),
        "deployment (full tensor)": dz.System(dz.Deployment([100.0, 110.0], [MOMENTS, TILTED])),
    }
    calls = 200

    def per_step(fn: Callable[[], object], n: float, threads: bool = False):
        def one() -> tuple[float, float]:
            wall, cpu = timed(fn, threads)
            return wall / n, cpu / n
        return one

    out: dict[str, tuple[Callable[[], tuple[float, float]], float]] = {
        "C RK4 loop": (lambda: c.run("rk4", steps, 201, *INERTIA, DT), 1e9),
        "RK4 run, flips located": (per_step(lambda: dz.simulate(
            body, OMEGA0, t_end=steps * DT, frames=201, dt=DT), steps), 1e9),
        "RK4 run, flips=False": (per_step(lambda: dz.simulate(
            body, OMEGA0, t_end=steps * DT, frames=201, dt=DT, flips=False), steps), 1e9),
        "C SoA RK4 loop, 1 thread": (lambda: c.run("rk4_soa", runs, batch_steps, DT), 1e9),
        "batch, 2 threads": (per_step(lambda: dz.simulate(
            INERTIA, omega, t_end=batch_steps * DT, frames=2, dt=DT, flips=False, threads=2),
            runs * batch_steps, threads=True), 1e9),
        "batch, 2 threads, flips located": (per_step(lambda: dz.simulate(
            INERTIA, omega, t_end=batch_steps * DT, frames=2, dt=DT, threads=2),
            runs * batch_steps, threads=True), 1e9),
        "10-step dz.simulate call": (per_step(lambda: [dz.simulate(
            body, OMEGA0, t_end=10 * DT, frames=11, dt=DT) for _ in range(calls)], calls), 1e6),
    }
    for name, system in models.items():
        out[f"RK4 step, {name}"] = (per_step(lambda s=system: dz.simulate(
            s, OMEGA0, t_end=model_steps * DT, frames=201, dt=DT, flips=False),
            model_steps), 1e9)
    return out


# (row, figure, baseline or None, target, what the target bounds)
ROWS = [
    ("one RK4 run, 1e7 steps, flips located", "RK4 run, flips located", "C RK4 loop", 1.0, "x C"),
    ("the same, flips=False", "RK4 run, flips=False", "C RK4 loop", 0.95, "x C"),
    ("4096 runs x 1000 steps, 2 threads", "batch, 2 threads", "C SoA RK4 loop, 1 thread", 0.5,
     "x C SoA"),
    ("  (the same in ns per run-step)", "batch, 2 threads", None, 2.0, "ns"),
    ("  (flips located)", "batch, 2 threads, flips located", "C SoA RK4 loop, 1 thread", None,
     "x C SoA"),
    ("a 10-step dz.simulate call", "10-step dz.simulate call", None, 40.0, "us"),
    ("gravity gradient per RK4 step", "RK4 step, gravity gradient", "RK4 step, free body (1, 2, 3)",
     2.0, "x free"),
    ("damper per RK4 step", "RK4 step, damper", "RK4 step, free body (1, 2, 3)", 1.5, "x free"),
    ("full-tensor deployment per RK4 step", "RK4 step, deployment (full tensor)",
     "RK4 step, free body (1, 2, 3)", 1.5, "x free"),
]


def measure(quick: bool, repeat: int) -> dict[str, object]:
    import dzhanibekov as dz
    from dzhanibekov import _core

    load_before = os.getloadavg()
    with tempfile.TemporaryDirectory() as tmp:
        c = C(Path(tmp))
        timers = cases(quick, c)
        # warm up: the thread pool, page faults
        dz.simulate(INERTIA, np.ones((64, 3)), t_end=0.01, dt=DT, frames=2, threads=2)
        samples: dict[str, list[tuple[float, float]]] = {k: [] for k in timers}
        for _ in range(repeat):
            for name, (fn, _) in timers.items():
                samples[name].append(fn())
    figures = {}
    for name, (_, unit) in timers.items():
        wall = statistics.median(s[0] for s in samples[name]) * unit
        cpu = statistics.median(s[1] for s in samples[name]) * unit
        figures[name] = {"wall": wall, "cpu": cpu, "unit": "us" if unit == 1e6 else "ns"}
    return {
        "load": [load_before[0], os.getloadavg()[0]],
        "isa": list(_core.instruction_sets()),
        "package": str(Path(dz.__file__).parent),
        "repeat": repeat,
        "quick": quick,
        "figures": figures,
        "rows": rows(figures),
    }


def rows(figures: dict[str, dict[str, float]]) -> list[dict[str, object]]:
    out = []
    for row, figure, base, target, unit in ROWS:
        f = figures[figure]
        if base is None:
            cpu, wall = f["cpu"], f["wall"]
        else:
            cpu, wall = f["cpu"] / figures[base]["cpu"], f["wall"] / figures[base]["wall"]
        out.append({"row": row, "cpu": cpu, "wall": wall, "target": target, "unit": unit,
                    "met": None if target is None else cpu <= target})
    return out


def cpu_model() -> str:
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown CPU"


def report(result: dict[str, object]) -> None:
    load = result["load"]
    print(f"{cpu_model()}, {os.cpu_count()} cores; SIMD kernels: {', '.join(result['isa'])}; "
          f"load average {load[0]:.2f} before, {load[1]:.2f} after; medians of "
          f"{result['repeat']} interleaved repeats{' (--quick sizes)' if result['quick'] else ''}")
    print(f"  {'figure':<40} {'CPU':>10} {'wall':>10}")
    for name, f in result["figures"].items():
        print(f"  {name:<40} {f['cpu']:>10.3f} {f['wall']:>10.3f} {f['unit']}/step"
              if f["unit"] == "ns" else
              f"  {name:<40} {f['cpu']:>10.3f} {f['wall']:>10.3f} us/call")
    print(f"  {'ratio (CPU time decides)':<40} {'CPU':>10} {'wall':>10} {'target':>14}")
    for r in result["rows"]:
        target = "" if r["target"] is None else f"<= {r['target']:g} {r['unit']}"
        mark = {None: "", True: "  ok", False: "  MISSED"}[r["met"]]
        print(f"  {r['row']:<40} {r['cpu']:>10.3f} {r['wall']:>10.3f} {target:>14}{mark}")


def compare(builds: list[str], rounds: int, quick: bool, repeat: int) -> None:
    """Runs this script once per build per round, interleaved; prints medians side by side."""
    results: dict[str, list[dict[str, object]]] = {b: [] for b in builds}
    for _ in range(rounds):
        for b in builds:
            with tempfile.NamedTemporaryFile(suffix=".json") as f:
                env = dict(os.environ, PYTHONPATH=os.path.abspath(b))
                cmd = [sys.executable, __file__, "--repeat", str(repeat), "--json", f.name]
                subprocess.run(cmd + (["--quick"] if quick else []), env=env, check=True,
                               stdout=subprocess.DEVNULL, cwd=tempfile.gettempdir())
                results[b].append(json.load(open(f.name)))
    loads = [x for b in builds for r in results[b] for x in r["load"]]
    print(f"{cpu_model()}; {rounds} rounds of {repeat} repeats per build, interleaved; load "
          f"average {min(loads):.2f} to {max(loads):.2f}")
    head = "".join(f" {Path(b).name[:20]:>21}" for b in builds)
    print(f"  {'median over rounds: CPU (wall)':<40}{head}")
    for name in results[builds[0]][0]["figures"]:
        cells = ""
        for b in builds:
            cpu = statistics.median(r["figures"][name]["cpu"] for r in results[b])
            wall = statistics.median(r["figures"][name]["wall"] for r in results[b])
            cells += f" {cpu:>9.3f} ({wall:>9.3f})"
        print(f"  {name:<40}{cells}")
    for k, (row, *_rest, target, unit) in enumerate(ROWS):
        cells = ""
        for b in builds:
            cpu = statistics.median(r["rows"][k]["cpu"] for r in results[b])
            wall = statistics.median(r["rows"][k]["wall"] for r in results[b])
            cells += f" {cpu:>9.3f} ({wall:>9.3f})"
        t = "" if target is None else f"  target <= {target:g} {unit}"
        print(f"  {row:<40}{cells}{t}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="smaller sizes: under 30 s")
    parser.add_argument("--repeat", type=int, default=None, help="repeats (5 quick, 7 full)")
    parser.add_argument("--json", help="also write the figures to this file")
    parser.add_argument("--builds", nargs="+", help="package directories to compare")
    parser.add_argument("--rounds", type=int, default=3, help="rounds of --builds")
    args = parser.parse_args()
    repeat = args.repeat or (5 if args.quick else 7)
    if args.builds:
        compare(args.builds, args.rounds, args.quick, repeat)
        return
    result = measure(args.quick, repeat)
    report(result)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=1)


if __name__ == "__main__":
    main()
