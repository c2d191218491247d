"""The atlas of rigid-body methods: every method of the registry on one measured chart.

    python benches/atlas.py constants       # each fixed-step method's step-rule constant C
    python benches/atlas.py chart           # error vs cost and energy vs time: writes
                                            # docs/atlas.png, docs/atlas-energy.png and the
                                            # tables of docs/atlas.md
    python benches/atlas.py speed           # per-step cost against the rhs-predicted cost
    python benches/atlas.py brouwer         # round-off growth (runs `cargo bench --bench
                                            # brouwer`, plots docs/atlas-brouwer.png)
    ... --quick                             # a smoke run of the same (writes nothing unless
                                            # --out is given)

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

ROOT = Path(__file__).resolve().parents[1]
Array = NDArray[np.float64]

HLW_INERTIA = (2.0, 1.0, 2.0 / 3.0)
HLW_MOMENTUM = (math.cos(1.1), 0.0, math.sin(1.1))
HLW_OMEGA = tuple(m / i for m, i in zip(HLW_MOMENTUM, HLW_INERTIA))


def fixed_step_methods() -> list[str]:
    return [name for name, m in dz.METHODS.items() if m.order is not None and not m.adaptive]


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
# tests/python/test_step_size.py draws them), where the error grows like ΩT (hΩ)^p.
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
    """The C of the registry's step rule, recovered from the step `plan_step` takes: h with
    C · ΩT · (hΩ)^p = rtol."""
    body, omega0, rtol, t_end = dz.Body((1.0, 2.0, 3.0)), (0.3, 0.2, 1.0), 1e-8, 1000.0
    dt = dz.accuracy.plan_step(body._core, omega0, t_end, 2, None, method, rtol, None)[0]
    assert dt is not None
    rate = rate_bound((1.0, 2.0, 3.0), omega0)
    order = dz.METHODS[method].order
    assert order is not None
    return float(rtol / (rate * t_end * (dt * rate) ** order))


# ---- main ----------------------------------------------------------------------------------


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("what", choices=["constants"])
    parser.add_argument("--quick", action="store_true", help="a smoke run")
    parser.add_argument("--out", type=Path, default=None,
                        help="where the docs' figures and tables go (default: docs/, "
                             "or nowhere with --quick)")
    args = parser.parse_args(argv)
    # HLW's moments (2, 1, 2/3) break the triangle inequality: a mathematical test problem
    # (no mass distribution has them), which the package warns about
    warnings.simplefilter("ignore", dz.InertiaWarning)
    if args.out is None and not args.quick:
        args.out = ROOT / "docs"
    {"constants": constants}[args.what](args)


if __name__ == "__main__":
    main()
