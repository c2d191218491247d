"""Work-precision on published test problems, the package beside scipy's solve_ivp (issue 30).

    nice -n 10 python benches/python/scipy_work_precision.py      # ~3 min on 2 shared cores
    python benches/python/scipy_work_precision.py --quick          # fewer settings, a smoke run
    python benches/python/scipy_work_precision.py --out-dir /tmp   # write elsewhere

**EULR**, the torqued rigid body of Hairer, Nørsett & Wanner's non-stiff test set (Solving
Ordinary Differential Equations I, 2nd ed., 1993, §II.10): Euler's equations

    y1' = (I2 − I3)/I1 y2 y3,   y2' = (I3 − I1)/I2 y3 y1,   y3' = (I1 − I2)/I3 y1 y2 + f(t),

``I = (0.5, 2, 3)``, ``y(0) = (1, 0, 0.9)``, ``t ∈ [0, 20]``, ``f(t) = 0.25 sin²t`` on
``[3π, 4π]`` and 0 elsewhere: a body torque ``0.25 I3 sin²t`` about the third axis. ``f`` is
C¹ at 3π and 4π (its second derivative jumps there). The error is the largest component of
``|y(20) − y_ref(20)|``; ``y_ref`` is computed here by mpmath's Taylor-series ``odefun`` at 25
digits, in three pieces that end on 3π and 4π (printed; checked against scipy's DOP853 at
``rtol = 1e-13``, the distance printed too).

The package runs the body with its attitude (seven equations; scipy runs the three of the
problem) and the torque as a ``dz.CallableTorque`` (a Python function, called at every
evaluation, as scipy calls its right-hand side), beside a zero ``dz.TabulatedTorque`` whose two
knots at 3π and 4π tell the methods where ``f`` is not smooth: every method ends a step there.
A ``dz.TabulatedTorque`` of ``f`` alone (linear between knots, no Python call) is drawn too at
two knot spacings: its error floor is the interpolation's, ``Δ²/8 · max|f''| = Δ²/16``.

**The paper's box** (Kutsenko & Zapolsky's fig. 3a): moments ``(52.0833, 27.0833, 41.6666)``,
``ω0 = (0.01, 0.01, 1)``, ``q0 = (1, 0, 0, 0)``, ``t ∈ [0, 100]`` (two flips). The error is the
largest component of ``|ω(100) − ω_ref|`` and ``|q(100) − q_ref|``, the reference from the
package's closed form (``method="exact"``: Jacobi elliptic functions and the attitude's
quadrature) checked against scipy's DOP853 at ``rtol = 1e-13`` (the distance printed). scipy
runs the same seven equations.

**Cost**: wall time and CPU (process) time of a call, the median of ``--repeat`` calls, each
side in the same run, interleaved setting by setting. Writes
``scipy-work-precision.png`` and ``scipy-work-precision.json`` into ``--out-dir`` (default:
docs/), and prints, for each method, the cheapest CPU time that reaches 1e-6 and 1e-10.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import time
import warnings
from collections.abc import Callable

import numpy as np
from scipy.integrate import solve_ivp

import dzhanibekov as dz

# EULR (Hairer, Nørsett & Wanner 1993, §II.10)
EULR_I = (0.5, 2.0, 3.0)
EULR_Y0 = (1.0, 0.0, 0.9)
EULR_T = 20.0
ON, OFF = 3 * math.pi, 4 * math.pi

# the paper's box, fig. 3a
BOX_I = (52.0833, 27.0833, 41.6666)
BOX_W0 = (0.01, 0.01, 1.0)
BOX_T = 100.0

RTOLS = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12]
QUICK_RTOLS = [1e-5, 1e-8, 1e-11]


def f_eulr(t: float) -> float:
    """The torque term of EULR's third equation."""
    return 0.25 * math.sin(t) ** 2 if ON <= t <= OFF else 0.0


def eulr_rhs(t: float, y: np.ndarray) -> list[float]:
    i1, i2, i3 = EULR_I
    return [(i2 - i3) / i1 * y[1] * y[2], (i3 - i1) / i2 * y[2] * y[0],
            (i1 - i2) / i3 * y[0] * y[1] + f_eulr(t)]


def box_rhs(t: float, y: np.ndarray) -> list[float]:
    ix, iy, iz = BOX_I
    u, v, w, q0, q1, q2, q3 = y
    return [(iy - iz) / ix * v * w, (iz - ix) / iy * u * w, (ix - iy) / iz * u * v,
            -0.5 * (q1 * u + q2 * v + q3 * w), 0.5 * (q0 * u + q2 * w - q3 * v),
            0.5 * (q0 * v + q3 * u - q1 * w), 0.5 * (q0 * w + q1 * v - q2 * u)]


def eulr_reference() -> np.ndarray:
    """y(20) of EULR by mpmath's Taylor series at 25 digits, in pieces ending on 3π and 4π."""
    import mpmath as mp

    mp.mp.dps = 25
    i1, i2, i3 = mp.mpf("0.5"), mp.mpf(2), mp.mpf(3)

    def rhs(torque: bool) -> Callable:
        def f(t, y):
            g = mp.mpf("0.25") * mp.sin(t) ** 2 if torque else 0
            return [(i2 - i3) / i1 * y[1] * y[2], (i3 - i1) / i2 * y[2] * y[0],
                    (i1 - i2) / i3 * y[0] * y[1] + g]
        return f

    y = [mp.mpf(1), mp.mpf(0), mp.mpf("0.9")]
    for a, b, torque in ((0, 3 * mp.pi, False), (3 * mp.pi, 4 * mp.pi, True),
                         (4 * mp.pi, mp.mpf(20), False)):
        y = mp.odefun(rhs(torque), a, y)(b)
    return np.array([float(v) for v in y])


def timed(fn: Callable[[], np.ndarray], repeat: int) -> tuple[np.ndarray, float, float]:
    """The result of `fn` and the median wall and CPU seconds of `repeat` calls."""
    walls, cpus = [], []
    for _ in range(repeat):
        w, c = time.perf_counter(), time.process_time()
        y = fn()
        walls.append(time.perf_counter() - w)
        cpus.append(time.process_time() - c)
    return y, statistics.median(walls), statistics.median(cpus)


def eulr_system(kind: str) -> dz.System:
    body = dz.Body(EULR_I)
    torque = lambda t, q, w: (0.0, 0.0, EULR_I[2] * f_eulr(t))  # noqa: E731
    knots = dz.TabulatedTorque([ON, OFF], np.zeros((2, 3)))  # zero: only the knots
    if kind == "callable":
        return dz.System(body, torques=[dz.CallableTorque(torque), knots])
    k = int(kind.split(":")[1])  # a table of f with k knots over [3π, 4π]
    t = np.linspace(ON, OFF, k)
    v = np.zeros((k, 3))
    v[:, 2] = 0.25 * EULR_I[2] * np.sin(t) ** 2
    return dz.System(body, torques=[dz.TabulatedTorque(t, v)])


def cases(quick: bool) -> list[dict]:
    """Every (problem, solver, setting) to run."""
    rtols = QUICK_RTOLS if quick else RTOLS
    dts = [0.02, 0.01, 0.005, 0.0025, 0.00125] if not quick else [0.01, 0.0025]
    out = []
    for problem in ("eulr", "box"):
        for m in ("dop853", "dopri5"):
            out += [dict(problem=problem, solver=f"dz {m}", method=m, rtol=r) for r in rtols]
        out += [dict(problem=problem, solver="dz rk4", method="rk4", dt=dt) for dt in dts]
        for m in ("DOP853", "RK45"):
            out += [dict(problem=problem, solver=f"scipy {m}", method=m, rtol=r)
                    for r in rtols if not (m == "RK45" and r < 1e-10)]
    if not quick:
        for k in (101, 1001):
            out += [dict(problem="eulr", solver=f"dz dop853, table of {k} knots",
                         method="dop853", rtol=r, table=k) for r in rtols[::2]]
    return out


def runner(case: dict) -> Callable[[], np.ndarray]:
    """A call running `case`, returning the end state compared with the reference."""
    p, m = case["problem"], case["method"]
    if case["solver"].startswith("scipy"):
        rtol = case["rtol"]
        if p == "eulr":
            y0, t_end, rhs = EULR_Y0, EULR_T, eulr_rhs
        else:
            y0, t_end, rhs = (*BOX_W0, 1.0, 0.0, 0.0, 0.0), BOX_T, box_rhs
        return lambda: solve_ivp(rhs, (0.0, t_end), y0, method=m, rtol=rtol,
                                 atol=rtol * 1e-3).y[:, -1]
    settings = {"dt": case["dt"]} if "dt" in case else {"rtol": case["rtol"],
                                                         "atol": case["rtol"] * 1e-3}
    if p == "eulr":
        system = eulr_system(f"table:{case['table']}" if "table" in case else "callable")
        return lambda: dz.simulate(system, EULR_Y0, t_end=EULR_T, frames=2, method=m,
                                   flips=False, **settings).omega[-1]
    body = dz.Body(BOX_I)

    def run() -> np.ndarray:
        traj = dz.simulate(body, BOX_W0, t_end=BOX_T, frames=2, method=m, flips=False,
                           **settings)
        return np.concatenate([traj.omega[-1], traj.q[-1]])
    return run


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--out-dir", default=os.path.join(os.path.dirname(__file__), "..", "..",
                                                          "docs"))
    args = parser.parse_args()
    warnings.simplefilter("ignore", dz.InertiaWarning)  # EULR's moments: 0.5 + 2 < 3
    warnings.simplefilter("ignore", dz.StepSizeWarning)
    load = [os.getloadavg()[0]]

    start = time.perf_counter()
    eulr_ref = eulr_reference()
    print(f"EULR y(20) by mpmath odefun, 25 digits ({time.perf_counter() - start:.0f} s): "
          f"{eulr_ref.tolist()}")
    check = solve_ivp(eulr_rhs, (0, EULR_T), EULR_Y0, method="DOP853", rtol=1e-13,
                      atol=1e-16).y[:, -1]
    print(f"  scipy DOP853 at rtol 1e-13 differs by {np.abs(check - eulr_ref).max():.1e}")
    exact = dz.simulate(dz.Body(BOX_I), BOX_W0, t_end=BOX_T, frames=2, method="exact")
    box_ref = np.concatenate([exact.omega[-1], exact.q[-1]])
    check = solve_ivp(box_rhs, (0, BOX_T), (*BOX_W0, 1.0, 0.0, 0.0, 0.0), method="DOP853",
                      rtol=1e-13, atol=1e-16).y[:, -1]
    print(f"box at t = 100 by the closed form; scipy DOP853 at rtol 1e-13 differs by "
          f"{np.abs(check - box_ref).max():.1e}")
    refs = {"eulr": eulr_ref, "box": box_ref}

    points = []
    for case in cases(args.quick):
        y, wall, cpu = timed(runner(case), args.repeat)
        err = float(np.abs(np.asarray(y) - refs[case["problem"]]).max())
        points.append({**case, "error": err, "wall": wall, "cpu": cpu})
    load.append(os.getloadavg()[0])

    out = os.path.abspath(args.out_dir)
    with open(os.path.join(out, "scipy-work-precision.json"), "w") as f:
        json.dump({"load": load, "eulr_reference": eulr_ref.tolist(),
                   "box_reference": box_ref.tolist(), "points": points}, f, indent=1)
    print(f"load average {load[0]:.2f} before, {load[1]:.2f} after; CPU ms of the cheapest "
          f"setting reaching 1e-6 / 1e-10 (error at the end)")
    for problem in ("eulr", "box"):
        solvers = dict.fromkeys(p["solver"] for p in points if p["problem"] == problem)
        for s in solvers:
            mine = [p for p in points if p["problem"] == problem and p["solver"] == s]
            cells = []
            for goal in (1e-6, 1e-10):
                ok = [p["cpu"] for p in mine if p["error"] <= goal]
                cells.append(f"{min(ok) * 1e3:8.2f}" if ok else "    none")
            print(f"  {problem:4s} {s:32s} {' / '.join(cells)}")
    draw(points, os.path.join(out, "scipy-work-precision.png"))


def draw(points: list[dict], path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(11, 8.5), sharey="row")
    styles = {"dz dop853": ("C0", "o-"), "dz dopri5": ("C1", "s-"), "dz rk4": ("C2", "^-"),
              "scipy DOP853": ("C3", "o--"), "scipy RK45": ("C4", "s--")}
    titles = {"eulr": "EULR (Hairer, Nørsett & Wanner): error of y(20)",
              "box": "the paper's box, fig. 3a: error of ω, q at t = 100"}
    for row, problem in enumerate(("eulr", "box")):
        for col, cost in enumerate(("cpu", "wall")):
            ax = axes[row, col]
            solvers = dict.fromkeys(p["solver"] for p in points if p["problem"] == problem)
            for s in solvers:
                mine = [p for p in points if p["problem"] == problem and p["solver"] == s]
                color, style = styles.get(s, ("0.5", "x:"))
                ax.loglog([p[cost] * 1e3 for p in mine],
                          [max(p["error"], 1e-17) for p in mine], style, color=color,
                          label=s, ms=4)
            ax.set_xlabel(f"{'CPU' if cost == 'cpu' else 'wall'} time per call (ms)")
            ax.set_title(titles[problem], fontsize=9)
            ax.grid(True, which="both", alpha=0.3)
        axes[row, 0].set_ylabel("largest error at the end")
        axes[row, 1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
