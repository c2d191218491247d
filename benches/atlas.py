"""The atlas of rigid-body methods: every method of the registry on one measured chart.

    python benches/atlas.py constants       # each fixed-step method's step-rule constant C
    python benches/atlas.py chart           # error vs cost and energy vs time: draws
                                            # docs/atlas.png and docs/atlas-energy.png
    python benches/atlas.py speed           # per-step cost against the rhs-predicted cost
    python benches/atlas.py brouwer         # round-off growth (runs `cargo bench --bench
                                            # brouwer` unless --csv names its output;
                                            # draws docs/atlas-brouwer.png); --steps 1e8
                                            # for the issue's full size
    ... --quick                             # a smoke run of the same (draws nothing
                                            # unless --out is given)

Each prints its tables and, unless --quick, writes them to target/atlas/ as well: docs/atlas.md
quotes them, with the command that measured each.

**constants.** ``dt=None`` picks a fixed-step method's step from the error model
``C · ΩT · (hΩ)^p = rtol`` (``Ω = √(2E / I_min)``, the bound of ``|ω|``; ``rust/run/step_size.rs``)
with the ``C`` of the method's registry entry. This measures ``C`` as the registry's
existing entries were measured: over ``ΩT = 300`` radians at ``hΩ = 0.1, 0.2, 0.4`` on 42
orbits (seven bodies, symmetric tops and the paper's among them, spun about each axis with two
wobble sizes), the error at 31 frames against ``method="exact"`` (ω in units of Ω, q up to
sign) divided by ``ΩT (hΩ)^p``; the registry takes twice the largest.

**chart.** Error against the exact solution against cost, wall time and steps, for every method
on three problems: Hairer, Lubich & Wanner's free rigid body (``I = (2, 1, 2/3)``, angular
momentum ``(cos 1.1, 0, sin 1.1)``, ``q0 = 1``) to ``T = 100`` and ``T = 10⁴``, and the paper's
fig. 3a (its moments, ``ω0 = (0.01, 0.01, 1)``, with the attitude) to ``T = 100``. Then the
relative energy error over 10⁶ steps of ``h = 0.1`` on the HLW body, for every fixed-step method.
The declared orders beside the measured ones (the slope of log error against log h), and the
cheapest method for each accuracy.

**speed.** Each fixed-step method's time per step, as CPU time of the calling thread (the
machine is shared: wall time is not a measure here), over 10⁶ steps of the HLW body at
``h|ω| ≈ 0.07``, beside RK4 measured alternately with it; and what the method's right-hand-side
evaluations predict, ``rhs_per_step / 4`` RK4 steps.
"""

from __future__ import annotations

import argparse
import math
import statistics
import subprocess
import sys
import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

import dzhanibekov as dz
from dzhanibekov import _core

ROOT = Path(__file__).resolve().parents[1]
Array = NDArray[np.float64]

HLW_INERTIA = (2.0, 1.0, 2.0 / 3.0)
HLW_MOMENTUM = (math.cos(1.1), 0.0, math.sin(1.1))
HLW_OMEGA = tuple(m / i for m, i in zip(HLW_MOMENTUM, HLW_INERTIA))


def fixed_step_methods() -> list[str]:
    """The fixed-step methods that run the free body (the atlas's problems; the exact-flow
    splittings run a body under torques only)."""
    return [name for name, m in dz.METHODS.items()
            if m.order is not None and not m.adaptive and "free" in m.models]


def rate_bound(inertia: Sequence[float], omega0: Sequence[float]) -> float:
    """Ω = √(2E / I_min), the bound of |ω| (the package's scale for errors in ω)."""
    i, w = np.asarray(inertia, float), np.asarray(omega0, float)
    return float(np.sqrt(np.dot(i, w * w) / i.min()))


def q_error(q: Array, ref: Array) -> Array:
    """Per frame, the distance of q from ±q_ref (the same attitude)."""
    d: Array = np.minimum(np.linalg.norm(q - ref, axis=-1), np.linalg.norm(q + ref, axis=-1))
    return d


def frame_error(traj: dz.Trajectory, ref: dz.Trajectory, rate: float) -> float:
    """The largest error over the frames: ω in units of Ω, q up to sign."""
    return max(float(np.abs(traj.omega - ref.omega).max()) / rate,
               float(q_error(traj.q, ref.q).max()))


def quiet(fn: Callable[[], Any]) -> Any:
    """`fn()` without the step-size warnings (the chart takes large steps on purpose)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", dz.StepSizeWarning)
        return fn()


def tables(args: argparse.Namespace, name: str, lines: list[str]) -> None:
    """The tables of a run, for docs/atlas.md (which quotes them with the command), in
    target/atlas/."""
    folder = ROOT / "target" / "atlas"
    folder.mkdir(parents=True, exist_ok=True)
    (folder / name).write_text("\n".join(lines) + "\n")
    print(f"wrote {folder / name}")


# ---- constants ---------------------------------------------------------------------------

BODIES = (
    dz.PAPER_INERTIA,
    (1.0, 2.0, 3.0),
    HLW_INERTIA,
    (1.0, 1.7, 2.3),
    (1.0, 1.0, 2.0),  # a prolate symmetric top
    (2.0, 2.0, 1.0),  # an oblate one
    (1.0, 2.0, 2.9),  # nearly flat: I3 close to I1 + I2
)


def separatrix_distance(inertia: Sequence[float], omega0: Sequence[float]) -> float:
    """|L² − 2E·I_mid| / L²: 0 on the separatrix, where any error grows exponentially."""
    i, w = np.asarray(inertia, float), np.asarray(omega0, float)
    l2 = float(np.sum((i * w) ** 2))
    return abs(l2 - float(np.dot(i, w * w)) * float(np.median(i))) / l2


def orbits() -> list[tuple[tuple[float, float, float], tuple[float, float, float]]]:
    """Seven bodies, each spun about each axis with a wobble of 0.01 and 0.3 of the spin."""
    out = []
    for inertia in BODIES:
        for axis in range(3):
            for wobble in (0.01, 0.3):
                w = [wobble * 0.8, wobble * -0.6, wobble * 0.7]
                w[axis] = 1.0
                out.append((inertia, (w[0], w[1], w[2])))
    return out


# The orbits the step rule's promise covers: away from the separatrix (as
# tests/python/methods/test_step_size.py draws them), where the error grows like ΩT (hΩ)^p.
WELL_CONDITIONED = 0.1


def constants(args: argparse.Namespace) -> None:
    turns, h_rates = 300.0, (0.1, 0.2, 0.4)
    todo = orbits()[:: 7 if args.quick else 1]
    print(f"C = error / (ΩT (hΩ)^p) over {len(todo)} orbits, ΩT = {turns:g}, "
          f"hΩ = {h_rates}")
    kept = sum(separatrix_distance(*o) > WELL_CONDITIONED for o in todo)
    print(f"{kept} of them away from the separatrix (|L² − 2E·I_mid| > {WELL_CONDITIONED} L²): "
          "max C over those, and over all")
    print(f"{'method':18s} {'p':>2s} {'max C':>9s} {'median C':>9s} {'2·max':>9s} "
          f"{'registry C':>10s} {'max C, all':>10s}  {'worst orbit'}")
    refs = {}
    for inertia, omega0 in todo:
        rate = rate_bound(inertia, omega0)
        refs[(inertia, omega0)] = dz.simulate(dz.Body(inertia), omega0, t_end=turns / rate,
                                              frames=31, method="exact")
    for method in fixed_step_methods():
        info = dz.METHODS[method]
        assert info.order is not None
        cs: list[tuple[float, bool, str]] = []
        for inertia, omega0 in todo:
            rate = rate_bound(inertia, omega0)
            ref = refs[(inertia, omega0)]
            for h_rate in h_rates:
                traj = quiet(lambda: dz.simulate(dz.Body(inertia), omega0, t_end=turns / rate,
                                                 frames=31, dt=h_rate / rate, method=method,
                                                 flips=False))
                err = frame_error(traj, ref, rate)
                good = separatrix_distance(inertia, omega0) > WELL_CONDITIONED
                cs.append((err / (turns * h_rate**info.order), good,
                           f"{inertia} {omega0} hΩ={h_rate}"))
        worst = max((c, orbit) for c, good, orbit in cs if good)
        median = statistics.median(c for c, good, _ in cs if good)
        every = max(c for c, _, _ in cs)
        print(f"{method:18s} {info.order:2d} {worst[0]:9.2e} {median:9.2e} {2 * worst[0]:9.2e} "
              f"{registry_constant(method):10.3g} {every:10.2e}  {worst[1]}", flush=True)


def registry_constant(method: str) -> float:
    """The C of the registry's step rule, recovered from the step the core plans (`_core.plan`): h with
    C · ΩT · (hΩ)^p = rtol."""
    system = dz.System(dz.Body((1.0, 2.0, 3.0)))
    omega0, rtol, t_end = (0.3, 0.2, 1.0), 1e-8, 1000.0
    options = _core.RunOptions(t_end, 2, None, method, rtol, None)
    dt = _core.plan([system._core], np.array([omega0]), np.array([[1.0, 0.0, 0.0, 0.0]]),
                    options).dt
    assert dt is not None
    rate = rate_bound((1.0, 2.0, 3.0), omega0)
    order = dz.METHODS[method].order
    assert order is not None
    return float(rtol / (rate * t_end * (dt * rate) ** order))


# ---- chart ---------------------------------------------------------------------------------


@dataclass(frozen=True)
class Problem:
    name: str
    title: str
    inertia: tuple[float, float, float]
    omega0: tuple[float, ...]
    t_end: float

    @property
    def rate(self) -> float:
        return rate_bound(self.inertia, self.omega0)


PROBLEMS = (
    Problem("hlw-100", "HLW body, T = 100", HLW_INERTIA, HLW_OMEGA, 100.0),
    Problem("hlw-1e4", "HLW body, T = 10⁴", HLW_INERTIA, HLW_OMEGA, 1e4),
    Problem("paper-3a", "paper fig. 3a with attitude, T = 100", dz.PAPER_INERTIA,
            (0.01, 0.01, 1.0), 100.0),
)
FRAMES = 201
ADAPTIVE_RTOLS = [10.0**-k for k in range(3, 14)]
ERROR_TARGETS = (1e-3, 1e-6, 1e-9, 1e-12)


@dataclass
class Point:
    problem: str
    method: str
    param: float  # hΩ for the fixed-step methods, rtol for the adaptive ones
    seconds: float  # CPU time of the run (process time: the machine is shared)
    n_steps: int
    nfev: int
    error: float


def cpu_seconds(fn: Callable[[], Any], repeat: int) -> tuple[float, Any]:
    """The smallest CPU time of `repeat` calls (at least 0.05 s each, calls repeated until
    then), and the last result."""
    best, result = math.inf, None
    for _ in range(repeat):
        number, elapsed = 0, 0.0
        start = time.process_time()
        while elapsed < 0.05:
            result = fn()
            number += 1
            elapsed = time.process_time() - start
        best = min(best, elapsed / number)
    return best, result


def sweep(problem: Problem, ref: dz.Trajectory, method: str, args: argparse.Namespace
          ) -> list[Point]:
    info = dz.METHODS[method]
    body = dz.Body(problem.inertia)
    points: list[Point] = []

    def one(param: float, **kwargs: Any) -> float:
        def call() -> dz.Trajectory:
            traj: dz.Trajectory = quiet(lambda: dz.simulate(
                body, problem.omega0, t_end=problem.t_end, frames=FRAMES, method=method,
                **kwargs))
            return traj
        seconds, traj = cpu_seconds(call, 1 if args.quick else args.repeat)
        if "dt" in kwargs and kwargs["dt"] is not None:
            # the step taken: at most dt, an even division of the frame interval
            param = traj.dt * problem.rate
        points.append(Point(problem.name, method, param, seconds, traj.n_steps, traj.nfev,
                            frame_error(traj, ref, problem.rate)))
        return float(seconds)

    if info.order is None:
        one(0.0)
    elif info.adaptive:
        for rtol in ADAPTIVE_RTOLS[:: 3 if args.quick else 1]:
            if one(rtol, dt=None, rtol=rtol) > args.budget:
                break
    else:
        h_rate = 0.5
        while True:
            seconds = one(h_rate, dt=h_rate / problem.rate)
            # the next (halved) step costs twice: stop before the budget, or at round-off
            if 2 * seconds > args.budget or points[-1].error < 1e-14 or h_rate < 2**-16:
                break
            h_rate /= 2 if not args.quick else 8
    return points


def measured_order(points: list[Point]) -> float | None:
    """The slope of log error against log hΩ where the error is below 1e-3 and above both
    1e-11 and a hundred times the sweep's floor (round-off, or the problem's conditioning)."""
    if not points:
        return None
    floor = 100 * min(p.error for p in points)
    pts = [(math.log(p.param), math.log(p.error)) for p in points
           if max(1e-11, floor) < p.error < 1e-3]
    if len(pts) < 3:
        return None
    x, y = np.array(pts).T
    return float(np.polyfit(x, y, 1)[0])


def cheapest(points: list[Point], target: float) -> Point | None:
    """The cheapest run reaching `target` whose tighter settings all reach it too."""
    line = sorted(points, key=lambda p: -p.param if p.method != "exact" else 0.0)
    ok = [p for k, p in enumerate(line) if all(x.error <= target for x in line[k:])]
    return min(ok, key=lambda p: p.seconds) if ok else None


def energy_over_time(args: argparse.Namespace) -> dict[str, tuple[Array, Array]]:
    """The relative energy error over 10⁶ steps of h = 0.1 on the HLW body, per method."""
    steps = 10**5 if args.quick else 10**6
    out = {}
    for method in fixed_step_methods():
        traj = quiet(lambda: dz.simulate(dz.Body(HLW_INERTIA), HLW_OMEGA, t_end=0.1 * steps,
                                         frames=1001, dt=0.1, method=method, flips=False))
        i = np.asarray(HLW_INERTIA)
        energy = np.sum(i * traj.omega**2, axis=1)
        out[method] = (traj.t[1:], np.abs(energy[1:] / energy[0] - 1))
        print(f"  energy over {steps:.0e} steps: {method} done", flush=True)
    return out


STYLE = {"rk4": ("C0", "-"), "rk4_projected": ("C9", "-"), "splitting": ("C2", "--"),
         "splitting4": ("C3", "--"), "splitting6": ("C5", "--"), "implicit_midpoint": ("C6", ":"),
         "dmv": ("C7", ":"), "dmv_modified": ("C8", ":"), "rkmk4": ("C1", "-."),
         "crouch_grossman3": ("C4", "-."), "dopri5": ("0.35", "-"), "dop853": ("0.6", "-"),
         "exact": ("k", "")}


def chart(args: argparse.Namespace) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    points: list[Point] = []
    for problem in PROBLEMS:
        ref = dz.simulate(dz.Body(problem.inertia), problem.omega0, t_end=problem.t_end,
                          frames=FRAMES, method="exact")
        for method in dz.METHODS:
            points += sweep(problem, ref, method, args)
            print(f"  {problem.name:9s} {method:18s} done", flush=True)
    energy = energy_over_time(args)
    if not args.quick:
        import json

        folder = ROOT / "target" / "atlas"
        folder.mkdir(parents=True, exist_ok=True)
        (folder / "points.json").write_text(json.dumps([p.__dict__ for p in points]))

    fig, axes = plt.subplots(2, len(PROBLEMS), figsize=(5.2 * len(PROBLEMS), 9.0),
                             squeeze=False)
    for col, problem in enumerate(PROBLEMS):
        for row, (attr, label) in enumerate((("seconds", "CPU seconds"),
                                             ("n_steps", "steps"))):
            ax = axes[row][col]
            for method in dz.METHODS:
                mine = [p for p in points if p.problem == problem.name and p.method == method]
                if not mine or (attr == "n_steps" and method == "exact"):
                    continue
                color, ls = STYLE.get(method, ("k", "-"))
                x = [max(float(getattr(p, attr)), 1e-9) for p in mine]
                y = [max(p.error, 1e-17) for p in mine]
                ax.loglog(x, y, ls or "-", marker="o" if method != "exact" else "*",
                          ms=3 if method != "exact" else 10, color=color, label=method)
            ax.set_xlabel(label)
            ax.set_ylabel("max error over 201 frames (ω/Ω, q)")
            ax.set_title(problem.title, fontsize=10)
            ax.grid(True, which="major", alpha=0.3)
    axes[0][0].legend(fontsize=7, ncol=2)
    fig.suptitle("The atlas: error against the exact solution against cost "
                 "(CPU time, steps)", fontsize=11)
    fig.tight_layout()

    efig, eax = plt.subplots(figsize=(8.0, 5.0))
    for method, (t, err) in energy.items():
        color, ls = STYLE.get(method, ("k", "-"))
        eax.loglog(t, np.maximum(err, 1e-17), ls or "-", color=color, label=method, lw=1)
    eax.set_xlabel("t (steps of h = 0.1)")
    eax.set_ylabel("|E(t)/E(0) − 1|")
    eax.set_title("HLW body, 10⁶ steps of h = 0.1: the energy error", fontsize=10)
    eax.legend(fontsize=7, ncol=2)
    eax.grid(True, which="major", alpha=0.3)
    efig.tight_layout()

    lines = report(points, energy)
    print("\n".join(lines))
    if args.out is not None:
        fig.savefig(args.out / "atlas.png", dpi=110)
        efig.savefig(args.out / "atlas-energy.png", dpi=110)
        tables(args, "atlas-tables.md", lines)
        print(f"wrote {args.out / 'atlas.png'} and atlas-energy.png")


def report(points: list[Point], energy: dict[str, tuple[Array, Array]]) -> list[str]:
    lines = ["### Declared and measured orders", "",
             "| method | declared | measured: HLW, T = 100 | HLW, T = 10⁴ | paper fig. 3a |",
             "|---|---|---|---|---|"]
    for method in fixed_step_methods():
        cells = []
        for problem in PROBLEMS:
            o = measured_order([p for p in points
                                if p.problem == problem.name and p.method == method])
            cells.append("—" if o is None else f"{o:.2f}")
        lines.append(f"| `{method}` | {dz.METHODS[method].order} | " + " | ".join(cells) + " |")
    lines += ["", "### The cheapest method for each accuracy", "",
              "CPU time of the cheapest run whose error, and every tighter setting's, is at "
              "most the target.", "",
              "| error ≤ | " + " | ".join(p.title for p in PROBLEMS) + " |",
              "|---" * (1 + len(PROBLEMS)) + "|"]
    for target in ERROR_TARGETS:
        cells = []
        for problem in PROBLEMS:
            best = []
            for method in dz.METHODS:
                if method == "exact":
                    continue
                c = cheapest([p for p in points
                              if p.problem == problem.name and p.method == method], target)
                if c is not None:
                    best.append(c)
            best.sort(key=lambda p: p.seconds)
            cells.append(", ".join(f"`{p.method}` {p.seconds * 1e3:.3g} ms"
                                   for p in best[:3]) or "none")
        lines.append(f"| {target:.0e} | " + " | ".join(cells) + " |")
    lines += ["", "### Energy error over 10⁶ steps of h = 0.1 (HLW body)", "",
              "| method | first 10 % of the run: max | last 10 %: max | growth |",
              "|---|---|---|---|"]
    for method, (_t, err) in energy.items():
        k = len(err) // 10
        first, last = float(err[:k].max()), float(err[-k:].max())
        lines.append(f"| `{method}` | {first:.2e} | {last:.2e} | {last / first:.3g}× |")
    return lines


# ---- speed ---------------------------------------------------------------------------------

# Newton corrections a step at h|ω| ≈ 0.1, as tests/atlas.rs measures them (each one evaluation
# of the method's equations, their Jacobian and a 3 × 3 solve)
NEWTON_ITERATIONS = {"implicit_midpoint": 2, "dmv": 3, "dmv_modified": 3}


def speed(args: argparse.Namespace) -> None:
    """CPU time per step of every fixed-step method beside RK4's, measured alternately."""
    steps = 10**5 if args.quick else 10**6
    h = 0.05  # h|ω| ≈ 0.07 on the HLW body
    body = dz.Body(HLW_INERTIA)

    def per_step(method: str) -> float:
        seconds, traj = cpu_seconds(lambda: quiet(lambda: dz.simulate(
            body, HLW_OMEGA, t_end=h * steps, frames=2, dt=h, method=method, flips=False)), 1)
        return float(seconds / traj.n_steps)

    rounds = 3 if args.quick else 9
    ratios: dict[str, list[float]] = {m: [] for m in fixed_step_methods()}
    rk4: list[float] = []
    for _ in range(rounds):
        for method in ratios:
            base = per_step("rk4")
            rk4.append(base)
            ratios[method].append(per_step(method) / base)
    rk4_ns = statistics.median(rk4) * 1e9
    lines = [f"Per step on the HLW body at h = {h} (h|ω| ≈ 0.07), {steps:.0e} steps a run, CPU "
             f"time, the median of {rounds} ratios to RK4 measured alternately (RK4: "
             f"{rk4_ns:.1f} ns a step).", "",
             "| method | ns / step | × RK4 | evaluations a step | predicted × RK4 | measured / "
             "predicted |", "|---|---|---|---|---|---|"]
    for method, r in ratios.items():
        ratio = statistics.median(r)
        info = dz.METHODS[method]
        if info.rhs_per_step:
            evaluations = f"{info.rhs_per_step} rhs"
            predicted = info.rhs_per_step / 4
        elif method in NEWTON_ITERATIONS:
            evaluations = f"{NEWTON_ITERATIONS[method]} Newton iterations"
            predicted = NEWTON_ITERATIONS[method] / 4
        else:
            evaluations, predicted = "no rhs (rotations)", math.nan
        lines.append(f"| `{method}` | {ratio * rk4_ns:.0f} | {ratio:.2f} | {evaluations} | "
                     f"{predicted:.2f} | {ratio / predicted:.1f} |".replace("nan", "—"))
    print("\n".join(lines))
    if args.out is not None:
        tables(args, "atlas-speed.md", lines)


# ---- brouwer ------------------------------------------------------------------------------

QUANTITIES = ("energy", "momentum", "momentum_world", "q_norm")
QUANTITY_LABELS = {"energy": "energy", "momentum": "|L|", "momentum_world": "L_world",
                   "q_norm": "|q|"}


def brouwer(args: argparse.Namespace) -> None:
    """Runs `cargo bench --bench brouwer` (or reads its CSV) and fits the growth of the
    round-off: the slope of log RMS error against log n from n = 10³ on."""
    import csv

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    steps = args.steps if not args.quick else 1e5
    starts = args.starts if not args.quick else 8
    out_csv = args.csv or ROOT / "target" / f"brouwer-{steps:.0e}-{starts}.csv"
    if not Path(out_csv).exists():
        cmd = ["cargo", "bench", "--bench", "brouwer", "--", "--steps", f"{steps:g}",
               "--starts", str(starts), "--out", str(out_csv)]
        print(" ".join(cmd), flush=True)
        subprocess.run(cmd, cwd=ROOT, check=True)
    data: dict[tuple[str, str], dict[str, list[float]]] = {}
    with open(out_csv) as f:
        for row in csv.DictReader(f):
            d = data.setdefault((row["method"], row["variant"]), {k: [] for k in ("n", *QUANTITIES)})
            d["n"].append(float(row["n"]))
            for q in QUANTITIES:
                d[q].append(float(row[q]))
    n_max = max(max(d["n"]) for d in data.values())

    def slope(n: list[float], e: list[float], start: float = 1e3) -> float:
        pts = [(math.log(a), math.log(b)) for a, b in zip(n, e) if a >= start and b > 0]
        if len(pts) < 3:
            return math.nan
        x, y = np.array(pts).T
        return float(np.polyfit(x, y, 1)[0])

    kept = {"splitting": ("momentum", "momentum_world", "q_norm"),
            "splitting4": ("momentum", "momentum_world", "q_norm"),
            "rk4_projected": QUANTITIES, "dmv": QUANTITIES,
            "implicit_midpoint": ("energy", "momentum", "q_norm")}
    lines = [f"RMS over {starts} perturbed starts of the HLW body, h = 0.1, up to n = "
             f"{n_max:.0e} steps: the slope of log error against log n fitted from n = 10³ / "
             "from n = 10⁵ (a random walk: 0.5; a bias: 1), and the error at the end, for each "
             "invariant the method keeps in exact arithmetic.", "",
             "| method | variant | " + " | ".join(QUANTITY_LABELS[q].replace("|", "\\|")
                                                  for q in QUANTITIES) + " |",
             "|---|---|" + "---|" * len(QUANTITIES)]
    for (method, variant), d in data.items():
        cells = []
        for q in QUANTITIES:
            if q not in kept.get(method, ()):
                cells.append("—")
                continue
            late = slope(d["n"], d[q], 1e5)
            cells.append(f"{slope(d['n'], d[q]):.2f} / {late:.2f} ({d[q][-1]:.1e})")
        lines.append(f"| `{method}` | {variant} | " + " | ".join(cells) + " |")
    print("\n".join(lines))

    fig, axes = plt.subplots(1, len(QUANTITIES), figsize=(4.4 * len(QUANTITIES), 4.2))
    for ax, q in zip(axes, QUANTITIES):
        for (method, variant), d in data.items():
            if q not in kept.get(method, ()):
                continue
            ls = {"plain": "-", "compensated": "--"}.get(variant, ":")
            ax.loglog(d["n"], np.maximum(d[q], 1e-18), ls, lw=1.2, label=f"{method}, {variant}",
                      color=STYLE.get(method, ("k", "-"))[0] if "no pull-back" not in variant
                      else ("C3" if "compensated" in variant else "C1"))
        n = np.array([1e2, n_max])
        ax.loglog(n, 1e-16 * np.sqrt(n), "k", lw=0.6, alpha=0.5, label="ε √n")
        ax.loglog(n, 1e-16 * n / 10, "k", lw=0.6, alpha=0.25, label="ε n / 10")
        ax.set_title(f"{QUANTITY_LABELS[q]}: RMS relative error", fontsize=10)
        ax.set_xlabel("steps n")
        ax.grid(True, which="major", alpha=0.3)
    axes[0].legend(fontsize=6)
    fig.tight_layout()
    if args.out is not None:
        fig.savefig(args.out / "atlas-brouwer.png", dpi=110)
        tables(args, "atlas-brouwer.md", lines)
        print(f"wrote {args.out / 'atlas-brouwer.png'}")


# ---- main ----------------------------------------------------------------------------------


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("what", choices=["constants", "chart", "speed", "brouwer"])
    parser.add_argument("--quick", action="store_true", help="a smoke run")
    parser.add_argument("--repeat", type=int, default=3, help="timings: the best of this many")
    parser.add_argument("--budget", type=float, default=2.0,
                        help="chart: CPU seconds a run may take (the step sweeps stop there)")
    parser.add_argument("--steps", type=float, default=1e7,
                        help="brouwer: steps a run (the issue's full size: 1e8)")
    parser.add_argument("--starts", type=int, default=64, help="brouwer: perturbed starts")
    parser.add_argument("--csv", type=Path, default=None,
                        help="brouwer: the bench's CSV (run it when absent)")
    parser.add_argument("--out", type=Path, default=None,
                        help="where the docs' figures and tables go (default: docs/, "
                             "or nowhere with --quick)")
    args = parser.parse_args(argv)
    # HLW's moments (2, 1, 2/3) break the triangle inequality: a mathematical test problem
    # (no mass distribution has them), which the package warns about
    warnings.simplefilter("ignore", dz.InertiaWarning)
    if args.out is None and not args.quick:
        args.out = ROOT / "docs"
    {"constants": constants, "chart": chart, "speed": speed, "brouwer": brouwer}[args.what](args)


if __name__ == "__main__":
    main()
