"""Threads: every loop of the core runs without the GIL, and calls from many threads at once
give the bits that serial calls give."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np
import pytest

import dzhanibekov as dz

BODY = dz.Body(dz.PAPER_INERTIA)
W = (0.01, 0.01, 1.0)
BATCH = dz.grid([0.01, 0.05, 0.1, 0.3], [0.01, 0.2], 1.0).reshape(-1, 3)


def ticks_during(call: Callable[[], Any]) -> tuple[int, float]:
    """How often a Python thread woke up (each wake-up needs the GIL) while `call` ran, and
    how long it ran."""
    ticks = 0
    stop, started = threading.Event(), threading.Event()

    def tick() -> None:
        nonlocal ticks
        started.set()
        while not stop.is_set():
            time.sleep(0.001)
            ticks += 1

    ticker = threading.Thread(target=tick, daemon=True)
    ticker.start()
    try:
        started.wait()
        time.sleep(0.01)
        before, start = ticks, time.perf_counter()
        call()
        elapsed, during = time.perf_counter() - start, ticks - before
    finally:  # a call that raises must not leave the ticker running (pytest would wait on it)
        stop.set()
        ticker.join()
    return during, elapsed


LONG_TRAJECTORY = dz.simulate(BODY, W, t_end=3e3, frames=3_000_001, dt=1e-3, flips=False)

LONG_CALLS: dict[str, Callable[[], Any]] = {
    "simulate-rk4": lambda: dz.simulate(BODY, W, t_end=1e4, frames=2, dt=1e-3),
    "simulate-rk4_projected": lambda: dz.simulate(BODY, W, t_end=3e3, frames=2, dt=1e-3,
                                                  method="rk4_projected"),
    "simulate-splitting": lambda: dz.simulate(BODY, W, t_end=3e3, frames=2, dt=1e-3,
                                              method="splitting"),
    "simulate-splitting4": lambda: dz.simulate(BODY, W, t_end=1e3, frames=2, dt=1e-3,
                                               method="splitting4"),
    "simulate-dopri5": lambda: dz.simulate(BODY, W, t_end=1e5, frames=2, method="dopri5",
                                           dt=None, rtol=1e-12),
    "simulate-dop853": lambda: dz.simulate(BODY, W, t_end=1e6, frames=2, method="dop853",
                                           dt=None, rtol=1e-13),
    "simulate-exact": lambda: dz.simulate(BODY, W, t_end=1e3, frames=10**6, method="exact"),
    "summarize": lambda: dz.summarize(BODY, W, t_end=1e4, dt=1e-3),
    "rotate": lambda: dz.rotate(np.tile([1.0, 0.2, 0.0, 1.0], (100, 1)), np.ones((100_000, 3))),
    "batch-rk4": lambda: dz.simulate(BODY, BATCH, t_end=2e3, frames=2, dt=1e-3),
    "batch-splitting": lambda: dz.simulate(BODY, BATCH[:2], t_end=1e3, frames=2, dt=1e-3,
                                           method="splitting"),
    "sweep-rk4": lambda: dz.sweep(BODY, BATCH, t_end=2e3, frames=2, dt=1e-3, progress=False),
    "sweep-dopri5": lambda: dz.sweep(BODY, BATCH[:2], t_end=1e4, frames=2, method="dopri5",
                                     dt=None, rtol=1e-12, progress=False),
    "ellipsoid_mesh": lambda: dz.ellipsoid_mesh((1.0, 2.0, 3.0), 4096, 2048),
    "Trajectory.invariants": lambda: dz.Trajectory(**{
        **{f: getattr(LONG_TRAJECTORY, f) for f in ("t", "omega", "q", "flip_times", "system",
                                                    "method", "dt", "n_steps", "nfev",
                                                    "drift")}}).invariants(),
}


@pytest.mark.parametrize("name", sorted(LONG_CALLS))
def test_the_gil_is_released_while_the_core_works(name):
    during, elapsed = ticks_during(LONG_CALLS[name])
    # a thread sleeping 1 ms at a time wakes about once a millisecond when it can get the
    # GIL; while a call held it, it could not wake at all
    assert elapsed > 0.03, f"{name} took only {elapsed:.3f} s: too short to tell"
    assert during >= max(3, 0.1 * elapsed / 1e-3), (name, during, elapsed)


def run(task: tuple[str, Any]) -> Any:
    kind, args = task
    if kind == "rotate":
        return dz.rotate(*args)
    if kind == "batch":
        method, omegas = args
        b = dz.simulate(BODY, omegas, t_end=50.0, frames=11, method=method,
                        dt=None if method in ("dopri5", "dop853") else 1e-2)
        return b.omega, b.q, b.flip_times, tuple(b.drift), b.n_steps
    if kind == "sweep":
        method, omegas = args
        sw = dz.sweep(BODY, omegas, t_end=50.0, frames=11, method=method, progress=False,
                      dt=None if method in ("dopri5", "dop853") else 1e-2)
        return sw.flips, sw.first_flip, sw.tilt, tuple(sw.drift), sw.n_steps
    if kind == "summarize":
        s = dz.summarize(BODY, *args, t_end=200.0, frames=11)
        return s.flip_times, tuple(s.drift), s.n_steps
    method, omega = args
    traj = dz.simulate(BODY, omega, t_end=100.0, frames=51, method=method,
                       dt=None if method in ("dopri5", "dop853") else 1e-2)
    return traj.omega, traj.q, traj.flip_times, tuple(traj.drift), traj.n_steps, traj.nfev


def same(a: Any, b: Any) -> bool:
    if isinstance(a, tuple):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    if isinstance(a, np.ndarray):
        return a.dtype == b.dtype and a.shape == b.shape and bytes(a.data) == bytes(b.data)
    return bool(a == b)


def test_threads_at_once_get_the_serial_bits():
    rng = np.random.default_rng(6)
    omegas = [tuple(rng.normal(size=3)) for _ in range(3)] + [W]
    free = [m for m, info in dz.METHODS.items() if "free" in info.models]  # the body's methods
    tasks: list[tuple[str, Any]] = [("simulate", (m, w)) for m in free for w in omegas]
    tasks += [("summarize", (w,)) for w in omegas]
    batches = np.array(omegas[:3] + [(1e-25, 2e-26, 1e-26)])  # a row far from 1 runs alone
    tasks += [(kind, (m, batches if m != "rk4" else np.array(omegas)))
              for kind in ("batch", "sweep") for m in ("rk4", "splitting", "dop853")]
    # small rotations on the caller's thread, large ones on all cores
    tasks += [("rotate", (rng.normal(size=(n, 4)), rng.normal(size=(p, 3))))
              for n, p in ((7, 5), (300, 1000), (64, 300_000))]
    serial = [run(t) for t in tasks]
    with ThreadPoolExecutor(max_workers=8) as pool:
        concurrent = list(pool.map(run, tasks * 3))
    for k, result in enumerate(concurrent):
        assert same(result, serial[k % len(tasks)]), tasks[k % len(tasks)][0]
