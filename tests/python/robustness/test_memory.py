"""Memory: repeated calls do not grow the process, and requests beyond the memory the machine
can give are refused before anything is allocated, saying how large they were."""

from __future__ import annotations

import _thread
import gc
import os
import threading

import numpy as np
import pytest

import dzhanibekov as dz
from dzhanibekov._args import memory_available

BODY = dz.Body(dz.PAPER_INERTIA)
W = (0.01, 0.01, 1.0)
BATCH = dz.grid([0.01, 0.05, 0.1], [0.01, 0.2], 1.0).reshape(-1, 3)


def rss() -> int:
    """Resident memory of this process, from /proc/self/statm (bytes)."""
    with open("/proc/self/statm", encoding="ascii") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def interrupted_run() -> None:
    """A run of 10⁸ steps stopped by Ctrl-C 20 ms in (as the terminal would send it)."""
    timer = threading.Timer(0.02, _thread.interrupt_main)
    timer.start()
    try:
        dz.summarize(BODY, W, t_end=1e5, dt=1e-3)
    except KeyboardInterrupt:
        pass
    timer.join()


def workload(i: int) -> None:
    """One of everything: runs of each method keeping 2001 frames (a leak of their buffers
    would be 100 kB a call), the other public functions, and errors raised in Python and in
    the core."""
    free = tuple(name for name, info in dz.METHODS.items() if "free" in info.models)
    method = free[i % len(free)]
    traj = dz.simulate(BODY, W, t_end=5.0, frames=2001, method=method, dt=1e-3)
    traj.invariants()
    dz.summarize(BODY, W, t_end=5.0, method=method, dt=1e-3)
    dz.rotate(traj.q[:200], dz.box_vertices())
    out = np.empty((50, 8, 3))
    dz.rotate(traj.q[:50], dz.box_vertices(), out=out)
    batch = dz.simulate(BODY, BATCH, t_end=5.0, frames=201, method=method, dt=1e-3)
    batch[1].invariants()
    dz.sweep(BODY, BATCH, t_end=5.0, frames=11, method=method, dt=1e-3, progress=False)
    dz.flip_period(BODY, W)
    dz.ellipsoid_mesh((1.0, 2.0, 3.0), 24, 12)
    dz.Body.box(20, 10, 15)
    for bad in (lambda: dz.simulate(BODY, (np.nan, 0, 1)),                 # refused in Python
                lambda: dz.simulate(BODY, (3.0, 5.0, 40.0), t_end=1e3, frames=2, dt=10.0,
                                    method="splitting4"),                  # diverges in the core
                lambda: dz.rotate(np.zeros((3, 4)), np.ones((2, 3))),
                lambda: dz.ellipsoid_mesh((1.0, 1.0, 1.0), 2**20, 2**20)):
        try:
            bad()
        except ValueError:
            pass


@pytest.mark.skipif(not os.path.exists("/proc/self/statm"), reason="reads /proc (Linux)")
def test_repeated_calls_do_not_grow_the_process():
    for i in range(100):  # warm-up: allocator pools, caches, lazily created objects
        workload(i)
    interrupted_run()
    gc.collect()
    start = rss()
    for i in range(1500):
        workload(i)
    for _ in range(10):
        interrupted_run()
    gc.collect()
    grown = rss() - start
    # a leaked frame buffer alone would be 1500 × 112 kB = 168 MB
    assert grown < 24e6, f"the process grew by {grown / 1e6:.1f} MB over 1500 rounds"


def test_a_request_beyond_available_memory_is_refused_before_allocation():
    room, what = memory_available()
    side = int(np.sqrt(room / 24)) + 1000  # side² points × 3 × 8 bytes > room
    q = np.tile([1.0, 0.0, 0.0, 0.0], (side, 1))
    points = np.ones((side, 3))
    before = rss()
    with pytest.raises(ValueError, match=r"rotating \d+ points by \d+ quaternions would need "
                                         r"[\d.]+ GB \(\d+ bytes\), more than this machine's"):
        dz.rotate(q, points)
    assert rss() - before < 16e6, "memory was touched before the refusal"
    frames = int(room / 64) + 10**6
    with pytest.raises(ValueError, match=rf"frames={frames} would need [\d.]+ GB"):
        dz.simulate(BODY, W, frames=frames, method="exact")
    runs = 1000
    frames = int(room / (runs * 56)) + 10**4
    with pytest.raises(ValueError, match=rf"a batch of {runs} runs × {frames} frames would need "
                                         r"[\d.]+ GB \(\d+ bytes\), more than this machine's"):
        dz.simulate(BODY, np.tile(W, (runs, 1)), frames=frames, method="exact")
    with pytest.raises(ValueError, match=r"a grid of shape \(\d+, \d+, 2\) would need [\d.]+ GB"):
        side = int(np.sqrt(room / 16)) + 1000
        dz.grid(np.arange(side, dtype=float), np.arange(side, dtype=float))
    assert rss() - before < 16e6, "memory was touched before the refusals"
    with pytest.raises(ValueError, match=r"n_around × n_along = 1048576 × 1048576 cells"):
        dz.ellipsoid_mesh((1.0, 1.0, 1.0), 2**20, 2**20)


def test_available_memory_is_at_most_the_machine_and_more_than_nothing():
    room, what = memory_available()
    total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    assert 0 < room <= total and what
