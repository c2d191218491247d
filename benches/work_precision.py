"""Work-precision of every method: error against the exact solution, drift and wall time.

    python benches/work_precision.py            # the full bench (a few minutes); writes
                                                # docs/work_precision.md and .png
    python benches/work_precision.py --quick    # a smoke run (under a minute); writes nothing
                                                # unless --out is given
    python benches/work_precision.py --projection   # only rk4_projected's drift at large
                                                    # steps: its figure and section

Every method of `dz.METHODS` that runs the free body runs on each case over a range of settings: the fixed-step
methods over steps ``dt = (hΩ) / Ω`` (``Ω = √(2E / I_min)``, the bound of ``|ω|``) and with
``dt=None`` over `rtol`; the adaptive ones over `rtol`; scipy's ``solve_ivp`` DOP853 beside
them as a baseline. Each run is scored against ``method="exact"`` on the same frames:

- error at T = 100 (201 frames), the largest over the frames of ``max_k |ω_k − ω_k,ref| / Ω``
  and of ``min(|q − q_ref|, |q + q_ref|)`` (q and −q are the same attitude);
- the invariants' drift over a run of the same setting to T = 10⁴ (201 frames; `Trajectory.drift`:
  energy and ``|L|`` relative, ``L_world`` relative to ``|L|``, ``||q| − 1|``), skipped where it
  would take longer than ``--drift-budget`` seconds;
- what ``rk4_projected`` keeps at large steps: its drift of E and ``|L|`` for hΩ up to the
  stability limit beside the square of RK4's energy change per step, the documented bound
  ``((hΩ)⁵/120)²`` and round-off (docs/projection_drift.png);
- wall time of the T = 100 run, end to end from Python (the median of ``--repeat`` repeats,
  each repeat long enough to time; flips located, as by default).

The cases: the paper's fig. 3b and 3c, a generic body with ``|ω| ~ 1`` (well conditioned),
and the paper's example (fig. 2, ``u0 = v0 = 5e-6``, ``1 − m ≈ 1.5e-11``), where every
float64 stepper loses accuracy at each flip; the last section measures why.
"""

from __future__ import annotations

import argparse
import datetime
import math
import os
import platform
import statistics
import time
import warnings
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np

import dzhanibekov as dz

ROOT = Path(__file__).resolve().parents[1]
T_ERROR = 100.0
T_DRIFT = 1e4
FRAMES = 201
ERROR_TARGETS = (1e-6, 1e-10)


@dataclass(frozen=True)
class Case:
    name: str
    title: str
    inertia: tuple[float, float, float]
    omega0: tuple[float, float, float]
    q0: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    ill_conditioned: bool = False

    @cached_property
    def body(self) -> dz.Body:
        return dz.Body(self.inertia)

    @property
    def rate(self) -> float:
        """Ω = √(2E / I_min), the bound of |ω| (the package's scale for errors in ω)."""
        i, w = np.array(self.inertia), np.array(self.omega0)
        return float(np.sqrt(np.dot(i, w * w) / i.min()))


CASES = (
    Case("fig3b", "paper fig. 3b: ω0 = (0.01, 0.1, 0.03)", dz.PAPER_INERTIA, (0.01, 0.1, 0.03)),
    Case("fig3c", "paper fig. 3c: ω0 = (0.01, 0.01, 0.03)", dz.PAPER_INERTIA, (0.01, 0.01, 0.03)),
    Case("generic", "generic: I = (1, 1.7, 2.3), ω0 = (0.4, −0.9, 0.6)", (1.0, 1.7, 2.3),
         (0.4, -0.9, 0.6), (0.9, 0.1, -0.3, 0.2)),
    Case("example", "paper fig. 2 (ill-conditioned): ω0 = (5e-6, 5e-6, 1)", dz.PAPER_INERTIA,
         (5e-6, 5e-6, 1.0), ill_conditioned=True),
)

# Step sweeps in units of hΩ (powers of two from 0.5 down), and tolerance sweeps.
FIXED_STEPS = {
    "rk4": [2.0**-k for k in range(1, 11)],
    "rk4_projected": [2.0**-k for k in range(1, 11)],
    "splitting": [2.0**-k for k in range(1, 13)],
    "splitting4": [2.0**-k for k in range(1, 9)],
    # the atlas's methods (issue 22; benches/atlas.py draws their own chart)
    "splitting6": [2.0**-k for k in range(1, 7)],
    "implicit_midpoint": [2.0**-k for k in range(1, 13)],
    "dmv": [2.0**-k for k in range(1, 13)],
    "dmv_modified": [2.0**-k for k in range(1, 9)],
    "rkmk4": [2.0**-k for k in range(1, 11)],
    "crouch_grossman3": [2.0**-k for k in range(1, 11)],
}
# the methods that run the free body (the torque methods splitting_exact(4) need a torque)
FREE_METHODS = tuple(dz.MODELS["free"].methods)
ADAPTIVE_RTOLS = [10.0**-k for k in range(3, 14)]
DT_NONE_RTOLS = [1e-4, 1e-6, 1e-8, 1e-10, 1e-12]
SCIPY_RTOLS = [1e-4, 1e-7, 1e-10, 1e-13]
DT_NONE_MAX_STEPS = 5e6  # dt=None runs predicted to take more steps are left out
COLORS = {"rk4": "C0", "rk4_projected": "C9", "splitting": "C2", "splitting4": "C3",
          "dopri5": "C1", "dop853": "C4", "scipy DOP853": "0.55", "splitting6": "C5",
          "implicit_midpoint": "C6", "dmv": "C7", "dmv_modified": "C8", "rkmk4": "#8c564b",
          "crouch_grossman3": "#bcbd22"}


@dataclass
class Run:
    case: str
    method: str
    setting: str  # "hΩ = 2^-3", "rtol = 1e-08", "dt=None, rtol = 1e-08", "—"
    sweep: str  # "dt", "rtol", "dt=None", "exact", "baseline"
    param: float  # hΩ or rtol
    seconds: float
    n_steps: int
    nfev: int
    err_omega: float
    err_q: float
    warned: bool = False  # StepSizeWarning on the T = 100 or T = 10⁴ run
    drift: dz.Drift | None = None
    drift_seconds: float = math.nan
    flips: int = 0
    extra: dict = field(default_factory=dict)

    @property
    def error(self) -> float:
        return max(self.err_omega, self.err_q)


def q_error(q: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """Per frame, the distance of q from ±q_ref (the same attitude)."""
    return np.minimum(np.linalg.norm(q - ref, axis=1), np.linalg.norm(q + ref, axis=1))


def timed(fn, repeat: int, min_seconds: float) -> tuple[float, object]:
    """Median seconds per call over `repeat` repeats, each calling `fn` as many times as it
    takes to last `min_seconds` (doubled from 1 until it does); returns it and the last
    result."""
    number, result = 1, fn()  # the first call warms up
    while True:
        start = time.perf_counter()
        for _ in range(number):
            result = fn()
        elapsed = time.perf_counter() - start
        if elapsed >= min_seconds:
            break
        number *= 2
    times = [elapsed / number]
    for _ in range(repeat - 1 if elapsed < 2.0 else min(repeat, 3) - 1):
        start = time.perf_counter()
        for _ in range(number):
            result = fn()
        times.append((time.perf_counter() - start) / number)
    return statistics.median(times), result


def simulate(case: Case, t_end: float, method: str, **kwargs) -> dz.Trajectory:
    return dz.simulate(case.body, case.omega0, case.q0, t_end=t_end, frames=FRAMES,
                       method=method, **kwargs)


def simulate_warned(case: Case, t_end: float, method: str, **kwargs
                    ) -> tuple[dz.Trajectory, bool]:
    """A run, and whether it raised `StepSizeWarning`."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", dz.StepSizeWarning)
        traj = simulate(case, t_end, method, **kwargs)
    return traj, any(issubclass(w.category, dz.StepSizeWarning) for w in caught)


def score(case: Case, ref: dz.Trajectory, omega: np.ndarray, q: np.ndarray) -> tuple[float, float]:
    err_w = float(np.abs(omega - ref.omega).max() / case.rate)
    err_q = float(q_error(q, ref.q).max())
    return err_w, err_q


def run_setting(case: Case, ref: dz.Trajectory, method: str, sweep: str, param: float,
                kwargs: dict, args: argparse.Namespace) -> Run:
    traj, warned = simulate_warned(case, T_ERROR, method, **kwargs)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", dz.StepSizeWarning)
        seconds = timed(lambda: simulate(case, T_ERROR, method, **kwargs), args.repeat,
                        args.min_seconds)[0]
    err_w, err_q = score(case, ref, traj.omega, traj.q)
    if sweep == "dt":
        # the step taken: at most dt, and an even division of the frame interval
        param = traj.dt * case.rate
        kwargs = {"dt": traj.dt * (1 + 1e-12)}
        setting = f"hΩ = {param:.3g}"
    elif sweep == "exact":
        setting = "—"
    else:
        setting = ("dt=None, " if sweep == "dt=None" else "") + f"rtol = {param:.0e}"
    run = Run(case.name, method, setting, sweep, param, seconds, traj.n_steps, traj.nfev,
              err_w, err_q, warned, flips=len(traj.flip_times))
    if method == "exact":
        run.drift_seconds, long = timed(lambda: simulate(case, T_DRIFT, method), args.repeat,
                                        args.min_seconds)
        run.drift = long.drift
    elif sweep != "dt=None" and seconds * T_DRIFT / T_ERROR <= args.drift_budget:
        start = time.perf_counter()
        long, warned_long = simulate_warned(case, T_DRIFT, method, **kwargs)
        run.drift_seconds = time.perf_counter() - start
        run.drift, run.warned = long.drift, warned or warned_long
        run.extra["warned_long"] = warned_long
    return run


def scipy_runs(case: Case, ref: dz.Trajectory, args: argparse.Namespace) -> list[Run]:
    """scipy.integrate.solve_ivp DOP853 on eq. 1 (body-frame quaternion law): the baseline."""
    from scipy.integrate import solve_ivp

    ix, iy, iz = case.inertia
    a, b, c = (iy - iz) / ix, (iz - ix) / iy, (ix - iy) / iz

    def rhs(_t, y):
        u, v, w, q0, q1, q2, q3 = y
        return [a * v * w, b * u * w, c * u * v,
                -0.5 * (q1 * u + q2 * v + q3 * w), 0.5 * (q0 * u + q2 * w - q3 * v),
                0.5 * (q0 * v + q3 * u - q1 * w), 0.5 * (q0 * w + q1 * v - q2 * u)]

    q0 = np.array(case.q0) / np.linalg.norm(case.q0)
    y0 = [*case.omega0, *q0]
    runs = []
    for rtol in SCIPY_RTOLS if not args.quick else SCIPY_RTOLS[::2]:
        atol = rtol * 1e-3 * case.rate
        seconds, sol = timed(lambda rtol=rtol, atol=atol: solve_ivp(
                                 rhs, (0.0, T_ERROR), y0, method="DOP853", t_eval=ref.t,
                                 rtol=rtol, atol=atol),
                             max(1, args.repeat // 2), args.min_seconds)
        err_w, err_q = score(case, ref, sol.y[:3].T, sol.y[3:].T)
        runs.append(Run(case.name, "scipy DOP853", f"rtol = {rtol:.0e}, atol = rtol·1e-3·Ω",
                        "baseline", rtol, seconds, 0, int(sol.nfev), err_w, err_q))
    return runs


def planned_dt(case: Case, method: str, rtol: float) -> float:
    """The step the core plans for `method` at `rtol` on `case` (`dt=None`), without running."""
    from dzhanibekov import _core
    from dzhanibekov._args import run_options
    from dzhanibekov.methods import DEFAULT_MAX_STEPS

    options = run_options(t_end=T_ERROR, frames=FRAMES, dt=None, method=method, rtol=rtol,
                          atol=None, max_steps=DEFAULT_MAX_STEPS, flips=False, threads=None)
    system = _core.System(dz.Body(case.inertia)._core, [])
    plan = _core.plan([system], np.array([case.omega0], dtype=float),
                      np.array([[1.0, 0.0, 0.0, 0.0]]), options)
    assert plan.dt is not None
    return plan.dt


def measure_case(case: Case, args: argparse.Namespace) -> list[Run]:
    ref = dz.simulate(case.inertia, case.omega0, case.q0, t_end=T_ERROR, frames=FRAMES,
                      method="exact")
    thin = 3 if args.quick else 1
    runs = [run_setting(case, ref, "exact", "exact", 0.0, {}, args)]
    # the exact method's cost does not grow with t: 201 frames at T = 10⁶ (target < 50 ms)
    runs[0].extra["seconds_1e6"] = timed(
        lambda: simulate(case, 1e6, "exact"), args.repeat, args.min_seconds)[0]
    for method in FREE_METHODS:
        if method in FIXED_STEPS:
            taken: set[int] = set()
            for h_rate in FIXED_STEPS[method][::thin]:
                # the frame interval caps the step: leave out settings that repeat a step
                substeps = math.ceil(T_ERROR / (FRAMES - 1) / (h_rate / case.rate))
                if substeps not in taken:
                    taken.add(substeps)
                    runs.append(run_setting(case, ref, method, "dt", h_rate,
                                            {"dt": h_rate / case.rate}, args))
            for rtol in DT_NONE_RTOLS[::thin]:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", dz.StepSizeWarning)
                    dt = planned_dt(case, method, rtol)
                if T_ERROR / dt <= DT_NONE_MAX_STEPS:
                    runs.append(run_setting(case, ref, method, "dt=None", rtol,
                                            {"dt": None, "rtol": rtol}, args))
        elif method in ("dopri5", "dop853"):
            for rtol in ADAPTIVE_RTOLS[::thin]:
                runs.append(run_setting(case, ref, method, "rtol", rtol,
                                        {"dt": None, "rtol": rtol}, args))
        print(f"  {case.name:8s} {method:14s} done", flush=True)
    runs += scipy_runs(case, ref, args)
    return runs


# ---- the ill-conditioned example --------------------------------------------------------


def complement_parameter(inertia, omega0) -> tuple[float, float]:
    """(1 − m, λ) of the motion, from differences computed without cancellation:
    1 − m = (J3 − J1)(L² − 2E J2) / ((J3 − J2)(L² − 2E J1)) about the major axis (J sorted),
    with L² − 2E J = Σ I_k (I_k − J) ω_k²; λ linearised about the intermediate axis."""
    i, w = np.array(inertia), np.array(omega0)
    j1, j2, j3 = np.sort(i)

    def gap(j):  # L² − 2E·j
        return float(np.sum(i * (i - j) * w * w))

    g2 = gap(j2)
    if g2 > 0:  # about the major axis
        m1 = (j3 - j1) * g2 / ((j3 - j2) * gap(j1))
    else:
        m1 = (j3 - j1) * -g2 / ((j2 - j1) * -gap(j3))
    mid = int(np.argsort(i)[1])
    lam = abs(w[mid]) * math.sqrt((j3 - j2) * (j2 - j1) / (j1 * j3))
    return m1, lam


def ill_conditioned(case: Case, runs: list[Run], args: argparse.Namespace) -> dict:
    """Error of each method's most accurate setting over time, on the example, to T = 1000,
    and the exact solution's own sensitivity to one ulp of ω0."""
    t_end = 300.0 if args.quick else 1000.0
    frames = 2 * int(t_end) + 1  # the frame interval of the sweep (0.5): the same steps
    body = dz.Body(case.inertia)
    ref = dz.simulate(body, case.omega0, t_end=t_end, frames=frames, method="exact")
    m1, lam = complement_parameter(case.inertia, case.omega0)
    i, w = np.array(case.inertia), np.array(case.omega0)
    mid = float(np.sort(i)[1])
    gap, l2 = float(np.sum(i * (i - mid) * w * w)), float(np.sum(np.square(i * w)))
    period = dz.flip_period(body, case.omega0)
    flips = ref.flip_times
    windows = [t for t in (40.0, 100.0, 200.0, 1000.0) if t <= t_end]
    out = {"case": case.name, "m1": m1, "lam": lam, "gap": gap, "l2": l2, "period": period,
           "flips": flips, "windows": windows, "t_end": t_end, "rows": []}

    def errors(omega, q):
        e = np.maximum(np.abs(omega - ref.omega).max(axis=1) / case.rate, q_error(q, ref.q))
        return [float(e[: round(t * (frames - 1) / t_end) + 1].max()) for t in windows]

    # one ulp of each component of ω0, through the exact solution: the problem's own conditioning
    for k, name in enumerate("uvw"):
        w = np.array(case.omega0)
        w[k] = np.nextafter(w[k], np.inf)
        other = dz.simulate(body, w, t_end=t_end, frames=frames, method="exact")
        out["rows"].append((f"exact, {name}0 + 1 ulp", errors(other.omega, other.q),
                            other.flip_times[1] - flips[1]))
    for method in FREE_METHODS:
        if method == "exact":
            continue
        best = min((r for r in runs if r.case == case.name and r.method == method
                    and r.sweep in ("dt", "rtol")), key=lambda r: r.error)
        kwargs = {"dt": best.param / case.rate * (1 + 1e-12)} if best.sweep == "dt" else {
            "dt": None, "rtol": best.param}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", dz.StepSizeWarning)
            traj = dz.simulate(body, case.omega0, t_end=t_end, frames=frames, method=method,
                               **kwargs)
        out["rows"].append((f"{method}, {best.setting}", errors(traj.omega, traj.q),
                            traj.flip_times[1] - flips[1]))
    return out


# ---- reports -----------------------------------------------------------------------------


def fmt(x: float | None, digits: int = 1) -> str:
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "—"
    return f"{x:.{digits}e}"


def fmt_ms(seconds: float) -> str:
    ms = seconds * 1e3
    return f"{ms:.3g}" if ms < 100 else f"{ms:.0f}"


def observed_order(runs: list[Run]) -> float | None:
    """Least-squares slope of log(error) against log(hΩ) where the error is between 1e-11
    and 1e-3 (above round-off, below the pre-asymptotic range)."""
    pts = [(math.log(r.param), math.log(r.error)) for r in runs
           if r.sweep == "dt" and 1e-11 < r.error < 1e-3]
    if len(pts) < 3:
        return None
    x, y = np.array(pts).T
    return float(np.polyfit(x, y, 1)[0])


def cheapest(runs: list[Run], target: float) -> Run | None:
    """The fastest run that reaches `target` and stays there: its error and the error of
    every tighter setting of its sweep (smaller step, smaller rtol) are at most `target`.
    (On the ill-conditioned example a lucky rounding can land one run far below its
    neighbours: that is not counted.)"""
    ok = []
    for sweep in {r.sweep for r in runs}:
        line = sorted((r for r in runs if r.sweep == sweep), key=lambda r: r.param)
        for k, r in enumerate(line):
            if all(x.error <= target for x in line[: k + 1]):
                ok.append(r)
    return min(ok, key=lambda r: r.seconds) if ok else None


def machine_note(load_before, load_after) -> str:
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if "model name" in line)
    except (OSError, StopIteration):
        pass
    return (f"{cpu}, {os.cpu_count()} cores, "
            f"load average {load_before[0]:.2f} before and {load_after[0]:.2f} after the run")


def summary_table(runs: list[Run], cases: tuple[Case, ...], settings: bool = False) -> list[str]:
    """Per method and case, the wall time of the cheapest run reaching each error target
    (with that run's setting if `settings`)."""
    targets = " / ".join(f"≤ {t:.0e}" for t in ERROR_TARGETS)
    lines = ["| method |" + "".join(f" {c.name}: ms to {targets} |" for c in cases),
             "|---" * (1 + len(cases)) + "|"]
    for method in (*FREE_METHODS, "scipy DOP853"):
        row = f"| `{method}` |" if method != "scipy DOP853" else f"| {method} (baseline) |"
        for c in cases:
            mine = [r for r in runs if r.case == c.name and r.method == method]
            if method == "exact":
                row += f" {fmt_ms(mine[0].seconds)} (the reference) |"
                continue
            cells = []
            for target in ERROR_TARGETS:
                best = cheapest(mine, target)
                if best is None:
                    cells.append("not reached")
                elif settings:
                    cells.append(f"{fmt_ms(best.seconds)} ({best.setting.split(', atol')[0]})")
                else:
                    cells.append(fmt_ms(best.seconds))
            row += " " + " / ".join(cells) + " |"
        lines.append(row)
    return lines


def ms2(seconds: float) -> str:
    """Milliseconds to two significant digits, as the README shows them."""
    ms = float(f"{seconds * 1e3:.2g}")
    return f"{ms:.0f}" if ms >= 10 else f"{ms:g}"


def readme_tables(runs: list[Run], cases: tuple[Case, ...]) -> list[str]:
    """The README's two tables: time to 1e-6 / 1e-10 per case, and the generic drift."""
    lines = ["| method | " + " | ".join(c.name + (" (ill-conditioned)" if c.ill_conditioned
                                                   else "") for c in cases) + " |",
             "|---" * (1 + len(cases)) + "|"]
    for method in (*FREE_METHODS, "scipy DOP853"):
        row = f"| `{method}` |" if method != "scipy DOP853" else f"| {method} (baseline) |"
        for c in cases:
            mine = [r for r in runs if r.case == c.name and r.method == method]
            if method == "exact":
                row += f" {ms2(mine[0].seconds)} |"
                continue
            best = [cheapest(mine, t) for t in ERROR_TARGETS]
            row += " " + " / ".join(ms2(b.seconds) if b else "not reached" for b in best) + " |"
        lines.append(row)
    generic = next(c for c in cases if c.name == "generic")
    lines += ["", "| method | setting | energy | \\|L\\| | L_world | \\|q\\| | ms |",
              "|---|---|---|---|---|---|---|"]
    for method in FREE_METHODS:
        mine = [r for r in runs if r.case == generic.name and r.method == method and r.drift]
        best = cheapest(mine, 1e-10) or min(mine, key=lambda r: r.error)
        d = best.drift
        setting = ("—" if method == "exact" else f"`rtol = {best.param:.0e}`"
                   if best.sweep != "dt" else f"`dt·Ω = {best.param:.2g}`")
        lines.append(f"| `{method}` | {setting} | {fmt(d.energy)} | {fmt(d.momentum)} | "
                     f"{fmt(d.momentum_world)} | {fmt(d.q_norm)} | {ms2(best.drift_seconds)} |")
    return lines


def drift_table(runs: list[Run], case: Case) -> list[str]:
    lines = ["| method | setting | error at T = 100 | energy | \\|L\\| | L_world | \\|q\\| "
             "| ms to T = 10⁴ |", "|---|---|---|---|---|---|---|---|"]
    for method in FREE_METHODS:
        mine = [r for r in runs if r.case == case.name and r.method == method and r.drift]
        if not mine:
            continue
        best = cheapest(mine, 1e-10) or min(mine, key=lambda r: r.error)
        d = best.drift
        lines.append(f"| `{method}` | {best.setting} | {fmt(best.error)} | {fmt(d.energy)} | "
                     f"{fmt(d.momentum)} | {fmt(d.momentum_world)} | {fmt(d.q_norm)} | "
                     f"{fmt_ms(best.drift_seconds)} |")
    return lines


# What rk4_projected keeps at large steps: steps in units of hΩ up to just below the
# wobble's stability limit 2√2, each run PROJECTION_STEPS steps long with a frame at each.
PROJECTION_RATES = (0.125, 0.177, 0.25, 0.354, 0.5, 0.707, 1.0, 1.25, 1.5, 1.73, 2.0, 2.25,
                    2.5, 2.75)
PROJECTION_STEPS = 2000
PROJECTION_HEADING = "## What `rk4_projected` keeps at large steps"
ROUND_OFF = 2.0**-52


def projection_drift(case: Case) -> list[dict]:
    """Per hΩ of `PROJECTION_RATES`: rk4_projected's drift of E and |L| over its run (every
    step a frame), the largest relative energy change δ one RK4 step makes from the run's
    states (the projection leaves about δ²), the documented bound ((hΩ)⁵/120)², and plain
    RK4's energy drift over the same run."""
    rows = []
    for h_rate in PROJECTION_RATES:
        dt = h_rate / case.rate
        kwargs = dict(t_end=PROJECTION_STEPS * dt, frames=PROJECTION_STEPS + 1, dt=dt,
                      flips=False)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", dz.StepSizeWarning)
            projected = dz.simulate(case.body, case.omega0, case.q0, method="rk4_projected",
                                    **kwargs)
            plain = dz.simulate(case.body, case.omega0, case.q0, method="rk4", **kwargs)
            # one RK4 step from each state of the projected run: what it asks to undo
            one = dz.simulate(case.body, projected.omega, projected.q, t_end=dt, frames=2,
                              dt=dt, flips=False)
        energy = np.sum(np.array(case.inertia) * one.omega**2, axis=2)
        delta = float(np.abs(energy[:, 1] / energy[:, 0] - 1).max())
        rows.append(dict(h_rate=h_rate, energy=projected.drift.energy,
                         momentum=projected.drift.momentum, delta=delta,
                         bound=(h_rate**5 / 120) ** 2, rk4=plain.drift.energy))
    return rows


def projection_table(rows: list[dict]) -> list[str]:
    lines = ["| hΩ | energy | \\|L\\| | δ² (RK4's energy change per step, squared) | "
             "((hΩ)⁵/120)² | `rk4`'s energy drift |", "|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['h_rate']:.3g} | {fmt(r['energy'])} | {fmt(r['momentum'])} | "
                     f"{fmt(r['delta'] ** 2)} | {fmt(r['bound'])} | {fmt(r['rk4'])} |")
    return lines


def projection_text(rows: list[dict], case: Case) -> list[str]:
    large = [r for r in rows if r["h_rate"] >= 1.0]
    ratio = [r["energy"] / r["delta"] ** 2 for r in large]
    of_bound = [r["energy"] / r["bound"] for r in large]
    floor = max(r["energy"] for r in rows if r["h_rate"] <= 0.25)
    return [
        PROJECTION_HEADING,
        "",
        "The drift table above is of accurate settings. At large steps `rk4_projected` "
        "moves ω back onto the energy and `|L|` of the start after every RK4 "
        "step with one Gauss–Newton step, which leaves the square of what the step changed. "
        "So it keeps E and `|L|` to round-off only while RK4's relative energy change per "
        "step, δ, is below about 1e-8 (here up to hΩ ≈ 0.25: drift at most "
        f"{floor:.1e}); beyond, the drift is about δ², at most the documented "
        "((hΩ)⁵/120)², and it does not grow with the run (each step projects onto the "
        "invariants of the start; a run ten times longer drifts as much). `|q|` and the direction of `L_world` are kept to round-off "
        f"at any step. Measured on the {case.name} body over {PROJECTION_STEPS} steps, a "
        "frame at each, with δ the largest relative energy change one `rk4` step makes from "
        "the run's states (a batch of one-step runs): at hΩ ≥ 1 the drift is "
        f"{min(ratio):.2f}–{max(ratio):.2f} δ², and {min(of_bound):.1e}–{max(of_bound):.1e} "
        "of the bound ((hΩ)⁵/120)² (RK4's energy error per step is far below its local "
        "error on this problem). Runs at such steps warn (`StepSizeWarning`): RK4's phase "
        "error along the polhode and about `L`, which no projection restores, is large.",
        "",
        "![rk4_projected's drift against hΩ](projection_drift.png)",
        "",
        "(`python benches/work_precision.py --projection` remakes this section and figure "
        "alone: no timings, so no dependence on the machine's load.)",
        "",
        *projection_table(rows),
    ]


def update_projection_section(path: Path, rows: list[dict], case: Case) -> None:
    """Replaces (or adds, before the ill-conditioned example) the section of
    `projection_text` in an existing work_precision.md: its figures do not depend on the
    machine's load, unlike the timings around it."""
    text = path.read_text()
    section = "\n".join(projection_text(rows, case)) + "\n\n"
    start = text.find(PROJECTION_HEADING)
    if start < 0:
        start = end = text.index("## The ill-conditioned example")
    else:
        end = text.index("\n## ", start + len(PROJECTION_HEADING)) + 1
    path.write_text(text[:start] + section + text[end:])


def plot_projection(path: Path, rows: list[dict], case: Case) -> None:
    import matplotlib
    import matplotlib.ticker

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from PIL import Image

    h = np.array([r["h_rate"] for r in rows])
    fine = np.geomspace(h.min(), 2 * math.sqrt(2), 200)
    fig, ax = plt.subplots(figsize=(7.5, 5.2))
    ax.loglog(fine, (fine**5 / 120) ** 2, "k--", lw=1.2,
              label="((hΩ)⁵/120)², the documented bound")
    ax.loglog(h, [r["delta"] ** 2 for r in rows], ":", color="C1", lw=1.5,
              label="δ²: RK4's energy change per step, squared")
    ax.loglog(h, [r["energy"] for r in rows], "o", color="C9", ms=6,
              label="rk4_projected: energy drift")
    ax.loglog(h, [r["momentum"] for r in rows], "s", mfc="none", color="C9", ms=6,
              label="rk4_projected: |L| drift")
    ax.loglog(h, [r["rk4"] for r in rows], "-", color="0.6", lw=1.2,
              label="rk4 (no projection): energy drift")
    ax.axhline(ROUND_OFF, color="C3", lw=1.0, label="round-off (2⁻⁵² ≈ 2.2e-16)")
    ax.axvline(2 * math.sqrt(2), color="k", lw=0.8, ls="-.")
    ax.annotate("stability limit\nhΩ = 2√2", (2 * math.sqrt(2), 1e-15), xytext=(-4, 0),
                textcoords="offset points", ha="right", fontsize=8)
    ticks = [0.125, 0.25, 0.5, 1.0, 2.0]
    ax.set_xticks(ticks, [f"{t:g}" for t in ticks])
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax.set_xlabel("step hΩ (Ω = √(2E / I_min), the bound of |ω|)")
    ax.set_ylabel(f"largest relative drift over {PROJECTION_STEPS} steps")
    ax.set_ylim(1e-17, 10)
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    ax.set_title(f"What rk4_projected keeps at large steps\n{case.title}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)
    with Image.open(path) as image:
        image.convert("RGB").quantize(colors=64, dither=Image.Dither.NONE).save(
            path, optimize=True)


def checks(runs: list[Run], cases: tuple[Case, ...]) -> list[str]:
    """Observed orders, adaptive global error against rtol, and the dt=None promise."""
    lines = ["| case | " + " | ".join(f"{m} order" for m in FIXED_STEPS)
             + " | dopri5 error / rtol | dop853 error / rtol | dopri5 / dop853 best error "
             "| `dt=None` error / rtol, worst down to 1e-10 | … at 1e-12 |",
             "|---" * (6 + len(FIXED_STEPS)) + "|"]
    for c in cases:
        mine = [r for r in runs if r.case == c.name]
        row = f"| {c.name} |"
        for m in FIXED_STEPS:
            order = observed_order([r for r in mine if r.method == m])
            if c.ill_conditioned:
                row += " (round-off) |"
            else:
                row += f" {order:.2f} |" if order is not None else " — |"
        for m in ("dopri5", "dop853"):
            ratios = [r.error / r.param for r in mine if r.method == m and r.param >= 1e-11]
            row += f" {min(ratios):.2g} – {max(ratios):.2g} |"
        row += " " + " / ".join(fmt(min(r.error for r in mine if r.method == m))
                                for m in ("dopri5", "dop853")) + " |"
        auto = [r for r in mine if r.sweep == "dt=None"]
        for part in ([r for r in auto if r.param >= 1e-10], [r for r in auto if r.param < 1e-10]):
            worst = max(part, key=lambda r: r.error / r.param, default=None)
            row += (f" {worst.error / worst.param:.2g} ({worst.method}) |" if worst
                    else " — |")
        lines.append(row)
    return lines


def guard_check(runs: list[Run]) -> str:
    """RK4's StepSizeWarning against the measured drift of |q| on the T = 10⁴ runs."""
    rk4 = [r for r in runs if r.method == "rk4" and r.drift is not None]
    over = [r for r in rk4 if r.drift.q_norm > dz.MAX_PREDICTED_DRIFT]
    missed = [r for r in over if not r.extra["warned_long"]]
    warned = [r for r in rk4 if r.extra["warned_long"]]
    text = (f"The RK4 guard on the {len(rk4)} `rk4` runs to T = 10⁴: {len(over)} lost more "
            f"than MAX_PREDICTED_DRIFT = {dz.MAX_PREDICTED_DRIFT:g} of |q|, "
            f"{len(over) - len(missed)} of them with a `StepSizeWarning`; {len(warned)} runs "
            "warned in all (the prediction is an upper bound: exact for a spin about the "
            "axis of least inertia, pessimistic elsewhere).")
    if missed:
        text += " Missed: " + ", ".join(f"{r.case} {r.setting} (|q| drift "
                                        f"{r.drift.q_norm:.1e})" for r in missed) + "."
    return text


def case_table(runs: list[Run], case: Case) -> list[str]:
    lines = [f"### {case.title}", "",
             f"Ω = {case.rate:.4g}; errors at T = 100 over {FRAMES} frames; drift over a run of "
             "the same setting to T = 10⁴ (— : skipped, longer than the budget); "
             "W: `StepSizeWarning` raised.", "",
             "| method | setting | steps | ms | ω error / Ω | q error | energy | \\|L\\| | "
             "L_world | \\|q\\| | |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in runs:
        if r.case != case.name:
            continue
        d = r.drift
        drift = (f"{fmt(d.energy)} | {fmt(d.momentum)} | {fmt(d.momentum_world)} | "
                 f"{fmt(d.q_norm)}") if d else "— | — | — | —"
        steps = f"{r.nfev} rhs" if r.sweep == "baseline" else str(r.n_steps)
        lines.append(f"| {r.method} | {r.setting} | {steps} | {fmt_ms(r.seconds)} | "
                     f"{fmt(r.err_omega)} | {fmt(r.err_q)} | {drift} | "
                     f"{'W' if r.warned else ''} |")
    return lines + [""]


def ill_table(ill: dict) -> list[str]:
    head = "| run | " + " | ".join(f"error to T = {t:g}" for t in ill["windows"]) + \
        " | 2nd flip time − exact |"
    lines = [head, "|---" * (2 + len(ill["windows"])) + "|"]
    for name, errs, shift in ill["rows"]:
        lines.append(f"| {name} | " + " | ".join(fmt(e) for e in errs) + f" | {shift:.1e} |")
    return lines


def write_markdown(path: Path, runs, cases, ill, projection, note, command, elapsed) -> str:
    m1, lam, period, gap, l2 = (ill[k] for k in ("m1", "lam", "period", "gap", "l2"))
    shift = 1e-16 * l2 / abs(gap)  # relative change of 1 − m from one rounding of L²
    steppers = [errs for name, errs, _ in ill["rows"] if not name.startswith("exact")]
    ulps = [errs for name, errs, _ in ill["rows"] if name.startswith("exact")]
    k100, k_last = ill["windows"].index(100.0), len(ill["windows"]) - 1
    rk4 = sorted((r for r in runs if r.case == ill["case"] and r.method == "rk4"
                  and r.sweep == "dt"), key=lambda r: r.param)[:5][::-1]
    floor = min(r.seconds for r in runs if r.sweep != "baseline")
    text = [
        "# Work-precision of the methods",
        "",
        f"Made by `{command}` on {datetime.date.today()} in {elapsed / 60:.1f} minutes; "
        f"{note}. Times are wall-clock per run, end to end from Python (the median of several "
        "repeats), so they carry the machine's noise: compare ratios within a column.",
        "",
        f"Error: the largest over {FRAMES} frames to T = 100 of `max_k |ω_k − ω_k,exact| / Ω` "
        "(Ω = √(2E / I_min), the bound of |ω|) and of `min(|q − q_exact|, |q + q_exact|)`, "
        "against `method=\"exact\"` on the same frames. Fixed-step methods run at "
        "`dt = hΩ / Ω` and with `dt=None` at an `rtol`; the adaptive ones at an `rtol` "
        "(`atol` its default); scipy's `solve_ivp(method=\"DOP853\")` on the same equations "
        "is the baseline.",
        "",
        "![work-precision](work_precision.png)",
        "",
        "## Time to reach an error",
        "",
        "Wall time (ms) of the cheapest run of each method whose error at T = 100 is at "
        "most 1e-6 / 1e-10, and stays so at every tighter setting of its sweep (its setting "
        "in the second table). On the paper's fig. 3b and 3c "
        "(Ω·T = 11 and 4 radians) every run costs about the floor of a call (Python, "
        f"checks, {FRAMES} frames: about {floor * 1e3:.2g} ms, the fastest run measured); "
        "the generic body (Ω·T = 154) separates the methods.",
        "",
        *summary_table(runs, cases),
        "",
        *summary_table(runs, cases, settings=True),
        "",
        "The exact method's cost does not grow with t: 201 frames at T = 10⁶ (flips located) "
        "take " + ", ".join(f"{fmt_ms(r.extra['seconds_1e6'])} ms ({r.case})" for r in runs
                            if r.method == "exact") + " (the issue's target: under 50 ms).",
        "",
        "## Orders and tolerances",
        "",
        "Observed order: the slope of log(error) against log(hΩ) where 1e-11 < error < 1e-3 "
        "(— : fewer than three such runs; on the example the error at T = 100 is amplified "
        "round-off, see below, and has no order). "
        "Adaptive methods: the range of (global error at T = 100) / rtol over rtol = 1e-3 "
        "… 1e-11, and the smallest error of the sweep (down to rtol = 1e-13). `dt=None`: "
        "the worst error / rtol of the fixed-step methods (which promise at most 1 away "
        "from the separatrix), down to rtol = 1e-10 and at 1e-12.",
        "",
        *checks(runs, cases),
        "",
        guard_check(runs),
        "",
        "## Drift of the invariants to T = 10⁴",
        "",
        "For each method the cheapest setting with error ≤ 1e-10 at T = 100 (else its most "
        "accurate), on the generic body:",
        "",
        *drift_table(runs, next(c for c in cases if c.name == "generic")),
        "",
        *projection_text(projection, next(c for c in cases if c.name == "generic")),
        "",
        "## The ill-conditioned example",
        "",
        f"The paper's fig. 2 starts 5e-6 off the intermediate axis: 1 − m = {m1:.2e}, "
        f"λ = {lam:.3f} (the growth rate near the axis), {period:.2f} time units between "
        f"flips (the first at t = {ill['flips'][0]:.2f}). The parameter is set by the "
        f"invariants through `L² − 2E·I_mid = Σ I_k (I_k − I_mid) ω_k²` = {gap:.2e}, "
        f"against L² = {l2:.0f}. During a flip every component of ω is O(1), and a "
        "stepper's round-off (1e-16 relative, at every step) moves `L² − 2E·I_mid` by "
        f"about 1e-16·L², which changes 1 − m by about {shift:.0e} of itself and the time "
        f"to the next flip, `(2/λ) ln(4/√(1 − m))`, by about {shift / lam:.0e}. Seen from "
        "the state: a perturbation grows as e^(λt) during the slow pass near the axis, "
        f"e^(λ·{period:.1f}) = {math.exp(lam * period):.1e} (≈ 16 / (1 − m)) over one pass, "
        f"so a round-off of 1e-16 has become about {1e-16 * math.exp(lam * period):.0e} by "
        "the next flip, whatever the method and its step. The exact method evaluates the "
        "closed form at each t from ω0 itself: nothing accumulates, and one ulp of any "
        "component of ω0 (the small ones carry their information relative to their own "
        "size) moves the solution by round-off only.",
        "",
        f"Measured to T = {ill['t_end']:g} ({len(ill['flips'])} flips), each method at its "
        "most accurate setting of the sweep (error as above, the largest over [0, T]):",
        "",
        *ill_table(ill),
        "",
        f"To T = 100 (one flip) the steppers' errors are {min(e[k100] for e in steppers):.0e} "
        f"to {max(e[k100] for e in steppers):.0e}; to T = {ill['windows'][k_last]:g} they "
        f"are {min(e[k_last] for e in steppers):.0e} to {max(e[k_last] for e in steppers):.0e}"
        f", while one ulp of ω0 moves the exact solution by at most "
        f"{max(e[k_last] for e in ulps):.0e}. Past the second flip of the paper's example "
        "only `method=\"exact\"` is accurate, and the work-precision curves of this case "
        "flatten at T = 100 at the error the first flip's round-off has grown to by then, "
        "scattered by the last bits of the step rather than ordered by it: `rk4` at hΩ = "
        + ", ".join(f"{r.param:.2g}" for r in rk4) + " scores "
        + ", ".join(f"{r.error:.1e}" for r in rk4) + ".",
        "",
        "## Every run",
        "",
    ]
    for c in cases:
        text += case_table(runs, c)
    body = "\n".join(text)
    path.write_text(body)
    return body


def plot(path: Path, runs: list[Run], cases: tuple[Case, ...], note: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from PIL import Image

    fig, axes = plt.subplots(2, 2, figsize=(11, 8.2), sharey=True)
    for ax, case in zip(axes.flat, cases, strict=True):
        mine = [r for r in runs if r.case == case.name]
        for method, color in COLORS.items():
            line = [r for r in mine if r.method == method and r.sweep in ("dt", "rtol",
                                                                          "baseline")]
            line.sort(key=lambda r: -r.param)  # from the largest step or tolerance down
            style = "--" if method == "scipy DOP853" else "-"
            marker = "s" if method in ("dopri5", "dop853") else "o"
            ax.loglog([r.seconds * 1e3 for r in line], [max(r.error, 1e-17) for r in line],
                      style, marker=marker, ms=3.5, color=color, lw=1.2, label=method)
            auto = [r for r in mine if r.method == method and r.sweep == "dt=None"]
            if auto:
                ax.loglog([r.seconds * 1e3 for r in auto], [r.error for r in auto], "o",
                          mfc="none", ms=6, color=color)
        exact = next(r for r in mine if r.method == "exact")
        ax.axvline(exact.seconds * 1e3, color="k", ls=":", lw=1.2)
        ax.annotate(f"exact: {exact.seconds * 1e3:.2f} ms\n(the reference)",
                    (exact.seconds * 1e3, 3e-16), xytext=(4, 0), textcoords="offset points",
                    fontsize=8)
        ax.set_title(f"{case.title}; ΩT = {case.rate * T_ERROR:.0f}", fontsize=10)
        ax.set_ylim(1e-16, 2)
        ax.grid(True, which="major", alpha=0.3)
    for ax in axes[1]:
        ax.set_xlabel("wall time per run to T = 100, 201 frames (ms, median)")
    for ax in axes[:, 0]:
        ax.set_ylabel("error over [0, 100]: max(|Δω|/Ω, |Δq|)")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    handles.append(plt.Line2D([], [], ls="none", marker="o", mfc="none", color="0.3"))
    labels.append("fixed step, dt=None at an rtol")
    fig.legend(handles, labels, loc="lower center", ncol=5, fontsize=8, frameon=False)
    fig.suptitle("Work-precision of dz.simulate's methods against the exact solution\n"
                 f"{note}", fontsize=10)
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    fig.savefig(path, dpi=80)
    plt.close(fig)
    from PIL.PngImagePlugin import PngInfo

    info = PngInfo()
    info.add_text("Description", note)  # the subtitle, for the docs' test to compare
    with Image.open(path) as image:
        image.convert("RGB").quantize(colors=64, dither=Image.Dither.NONE).save(
            path, optimize=True, pnginfo=info)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help="a smoke run: every third setting, short timings, under a minute")
    parser.add_argument("--out", type=Path, default=None,
                        help="folder for work_precision.md and .png (default: docs/, or "
                             "nothing with --quick)")
    parser.add_argument("--repeat", type=int, default=None, help="timing repeats (default 5)")
    parser.add_argument("--drift-budget", type=float, default=None,
                        help="skip T = 10⁴ runs predicted longer than this (s, default 3)")
    parser.add_argument("--projection", action="store_true",
                        help="only what rk4_projected keeps at large steps (seconds): "
                             "projection_drift.png and its section of work_precision.md")
    args = parser.parse_args()
    if args.projection:
        generic = next(c for c in CASES if c.name == "generic")
        rows = projection_drift(generic)
        print("\n".join(projection_table(rows)))
        out = args.out if args.out is not None else ROOT / "docs"
        update_projection_section(out / "work_precision.md", rows, generic)
        plot_projection(out / "projection_drift.png", rows, generic)
        print(f"wrote {out / 'projection_drift.png'} and its section of "
              f"{out / 'work_precision.md'}")
        return
    args.repeat = args.repeat or (3 if args.quick else 5)
    args.drift_budget = args.drift_budget or (0.2 if args.quick else 3.0)
    args.min_seconds = 0.003 if args.quick else 0.02
    out = args.out if args.out is not None else (None if args.quick else ROOT / "docs")
    command = "python benches/work_precision.py" + (" --quick" if args.quick else "")

    load_before = os.getloadavg()
    print(f"load average {load_before[0]:.2f}; {len(CASES)} cases", flush=True)
    start = time.perf_counter()
    runs: list[Run] = []
    for case in CASES:
        runs += measure_case(case, args)
    ill = ill_conditioned(next(c for c in CASES if c.name == "example"), runs, args)
    generic = next(c for c in CASES if c.name == "generic")
    projection = projection_drift(generic)
    elapsed = time.perf_counter() - start
    note = machine_note(load_before, os.getloadavg())

    print("\nTime to reach an error (ms, cheapest setting that does)")
    print("\n".join(summary_table(runs, CASES)))
    print("\nOrders and tolerances")
    print("\n".join(checks(runs, CASES)))
    print(guard_check(runs))
    print("\nDrift to T = 1e4, generic body")
    print("\n".join(drift_table(runs, CASES[2])))
    print("\nWhat rk4_projected keeps at large steps, generic body")
    print("\n".join(projection_table(projection)))
    print("\nIll-conditioned example")
    print(f"1 - m = {ill['m1']:.3e}, lambda = {ill['lam']:.4f}, period = {ill['period']:.3f}")
    print("\n".join(ill_table(ill)))
    print("\nFor the README")
    print("\n".join(readme_tables(runs, CASES)))
    print(f"\n{note}; {elapsed:.0f} s")
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
        write_markdown(out / "work_precision.md", runs, CASES, ill, projection, note, command,
                       elapsed)
        plot(out / "work_precision.png", runs, CASES, note)
        plot_projection(out / "projection_drift.png", projection, generic)
        size = (out / "work_precision.png").stat().st_size / 1024
        print(f"wrote {out / 'work_precision.md'}, {out / 'work_precision.png'} "
              f"({size:.0f} KB) and {out / 'projection_drift.png'}")


if __name__ == "__main__":
    main()
