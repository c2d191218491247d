"""Ctrl-C during a long call, measured in a process of its own (run as a script).

    python interrupt_child.py CALL [DELAY]

Starts CALL (one of `CALLS`: runs, batches and sweeps of 10⁹ steps a run and more, a
rotation of a gigabyte), sends
this process SIGINT after DELAY seconds (0.5 by default) from another thread, as a terminal's
Ctrl-C would, and prints one line of JSON:

- ``interrupted``: KeyboardInterrupt reached the caller;
- ``inside``: it was raised from within the package's call (not between two calls);
- ``latency``: seconds from the signal to the KeyboardInterrupt;
- ``usable``: afterwards a short run gives bit for bit what it gave before, and a second
  long call is interrupted too (the signal machinery still works).
"""

from __future__ import annotations

import json
import os
import signal
import sys
import threading
import time
import traceback
from collections.abc import Callable
from typing import Any

import numpy as np

import dzhanibekov as dz

BODY = dz.Body(dz.PAPER_INERTIA)
OMEGA = (0.01, 0.01, 1.0)
BATCH_OMEGA = dz.grid([0.01, 0.02, 0.05, 0.1], [0.01, 0.2], 1.0).reshape(-1, 3)

CALLS: dict[str, Callable[[], Any]] = {
    # 10⁹ RK4 steps, about 25 s
    "simulate-rk4": lambda: dz.simulate(BODY, OMEGA, t_end=1e6, frames=201, dt=1e-3),
    # an adaptive run of about 10⁸ steps at a tight tolerance
    "simulate-dop853": lambda: dz.simulate(BODY, OMEGA, t_end=1e9, frames=201, method="dop853",
                                           rtol=1e-13, atol=1e-15, dt=None),
    "simulate-splitting": lambda: dz.simulate(BODY, OMEGA, t_end=1e6, frames=201, dt=1e-3,
                                              method="splitting"),
    # 10⁹ steps keeping no frames
    "summarize-rk4": lambda: dz.summarize(BODY, OMEGA, t_end=1e6, dt=1e-3),
    # 10⁹ evaluations of the closed form, keeping no frames
    "summarize-exact": lambda: dz.summarize(BODY, OMEGA, t_end=1e6, frames=10**9,
                                            method="exact"),
    # a batch of 8 runs of 10⁹ steps each, in SIMD lanes on all cores
    "batch-rk4": lambda: dz.simulate(BODY, BATCH_OMEGA, t_end=1e6, frames=201, dt=1e-3),
    # a batch of another method: runs one by one on all cores
    "batch-splitting": lambda: dz.simulate(BODY, BATCH_OMEGA, t_end=1e6, frames=201, dt=1e-3,
                                           method="splitting"),
    # a sweep of 8 runs of 10⁹ steps each, keeping a few numbers per run
    "sweep-rk4": lambda: dz.sweep(BODY, BATCH_OMEGA, t_end=1e6, dt=1e-3, progress=False),
    # 2³¹ frames over about 10⁸ adaptive steps, keeping none: the frames a run does not keep
    # are read off its interpolant a few a step (over 100 time units they were once 2³¹ in a
    # few hundred steps, and long; now at most 64 a step are read, and that is quick)
    "summarize-dop853-frames": lambda: dz.summarize(BODY, OMEGA, t_end=1e7, frames=2**31,
                                                    method="dop853", dt=None),
    "summarize-dopri5-frames": lambda: dz.summarize(BODY, OMEGA, t_end=1e7, frames=2**31,
                                                    method="dopri5", dt=None),
    "sweep-dop853-frames": lambda: dz.sweep(BODY, BATCH_OMEGA[:2], t_end=1e7, frames=2**31,
                                            method="dop853", dt=None, progress=False),
    # a tiny span in subnormal steps: 2·10¹³ steps once max_steps allows them
    "summarize-subnormal-dt": lambda: dz.summarize(BODY, OMEGA, t_end=1e-310, dt=5e-324,
                                                   max_steps=2**62),
    # a Monte Carlo study of 32 dispersed bodies, 10⁹ RK4 steps each, in chunks of 16
    "monte-carlo-rk4": lambda: dz.monte_carlo(
        dz.InertiaDispersion(BODY, moments=0.02), OMEGA, 32, seed=1, t_end=1e6, method="rk4",
        dt=1e-3, chunk=16, progress=False),
    # a Python-callable torque (issue 21): 10⁹ RK4 steps at Python speed, on the helper thread
    "simulate-callable-torque": lambda: dz.simulate(
        dz.System(BODY, torques=[lambda t, q, w: -1e-3 * w]), OMEGA, t_end=1e6, frames=201,
        dt=1e-3),
    # and a batch of two such runs (each call takes the GIL)
    "batch-callable-torque": lambda: dz.simulate(
        dz.System(BODY, torques=[lambda t, q, w: -1e-3 * w]), BATCH_OMEGA[:2], t_end=1e6,
        frames=201, dt=1e-3),
    # a law of the user's sampled at 1 Hz (issue 32), a run and a batch of two
    "simulate-controller": lambda: dz.simulate(
        dz.System(BODY, parts=[dz.Controller(lambda t, q, w, b, h: -1e-3 * w, 1.0)]), OMEGA,
        t_end=1e6, frames=201, dt=1e-3),
    "batch-controller": lambda: dz.simulate(
        dz.System(BODY, parts=[dz.Controller(lambda t, q, w, b, h: -1e-3 * w, 1.0)]),
        BATCH_OMEGA[:2], t_end=1e6, frames=201, dt=1e-3),
    # 4·10⁷ point-frames into a fresh gigabyte
    "rotate": lambda: dz.rotate(np.tile([0.9, 0.1, -0.3, 0.2], (1000, 1)),
                                np.random.default_rng(0).normal(size=(40_000, 3))),
}
# the atlas's methods: a run and a batch of each, 10⁹ steps a run
ATLAS = ("splitting6", "implicit_midpoint", "dmv", "dmv_modified", "rkmk4", "crouch_grossman3")
for _m in ATLAS:
    CALLS[f"simulate-{_m}"] = lambda m=_m: dz.simulate(BODY, OMEGA, t_end=1e6, frames=201,
                                                        dt=1e-3, method=m)
    CALLS[f"batch-{_m}"] = lambda m=_m: dz.simulate(BODY, BATCH_OMEGA, t_end=1e6, frames=201,
                                                     dt=1e-3, method=m)


def short_run() -> np.ndarray:
    q: np.ndarray = dz.simulate(BODY, OMEGA, t_end=10.0, frames=3).q
    return q


def interrupt(call: Callable[[], Any], delay: float) -> dict[str, Any]:
    """Calls `call` over and over until SIGINT, sent `delay` seconds from now, stops it."""
    sent: list[float] = []

    def send() -> None:
        sent.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)

    timer = threading.Timer(delay, send)
    completed = 0
    timer.start()
    try:
        while True:  # the signal lands in a call: each takes seconds, the loop microseconds
            call()
            completed += 1
    except KeyboardInterrupt as exc:
        caught = time.perf_counter()
        frames = traceback.extract_tb(exc.__traceback__)
        inside = any(f"{os.sep}dzhanibekov{os.sep}" in frame.filename for frame in frames)
    timer.join()
    return {"latency": caught - sent[0], "inside": inside, "completed": completed}


def main(argv: list[str]) -> None:
    name = argv[1]
    delay = float(argv[2]) if len(argv) > 2 else 0.5
    before = short_run()
    first = interrupt(CALLS[name], delay)
    usable = bool(np.array_equal(short_run(), before))
    second = interrupt(CALLS[name], min(delay, 0.2))
    usable = usable and bool(np.array_equal(short_run(), before))
    print(json.dumps({
        "call": name,
        "interrupted": True,
        "inside": first["inside"] and second["inside"],
        "latency": first["latency"],
        "latency_second": second["latency"],
        "completed_before_signal": first["completed"],
        "usable": usable,
    }))


if __name__ == "__main__":
    signal.signal(signal.SIGINT, signal.default_int_handler)
    main(sys.argv)
