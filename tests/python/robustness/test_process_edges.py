"""The process around a call: Ctrl-C in a process's very first long call, the interpreter
exiting while a daemon thread is inside a long call, and `threads=` far beyond the runs."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import dzhanibekov as dz


def test_ctrl_c_in_the_first_long_call_is_a_keyboard_interrupt():
    """The first call of a process converts its results into NumPy's first arrays; a Ctrl-C
    still pending there surfaced as a PanicException ("Failed to access NumPy array API
    capsule"). The exact run keeps no frames to watch but finds ~1e8 flips."""
    code = textwrap.dedent("""
        import sys
        import dzhanibekov as dz
        print("ready", flush=True)
        try:
            dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=3.5e9, method="exact")
        except BaseException as exc:
            print("RAISED", type(exc).__name__, flush=True)
        else:
            print("RETURNED", flush=True)
    """)
    child = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    assert child.stdout is not None
    assert child.stdout.readline().strip() == "ready"
    time.sleep(0.3)
    child.send_signal(signal.SIGINT)
    out, err = child.communicate(timeout=120)
    assert out.strip() == "RAISED KeyboardInterrupt", (out, err[-1500:])


DAEMON = textwrap.dedent("""
    import sys, threading, time
    import numpy as np
    import dzhanibekov as dz
    kind, delay = sys.argv[1], float(sys.argv[2])
    body = dz.Body(dz.PAPER_INERTIA)
    omega = np.tile([0.01, 0.01, 1.0], (32, 1)) * np.linspace(1.0, 2.0, 32)[:, None]
    MODELS = {
        "tensor": dz.Body.from_tensor([[2.0, 0.3, 0.0], [0.3, 1.0, 0.0], [0.0, 0.0, 3.0]]),
        "deployment": dz.Deployment([1.0, 5.0], [dz.PAPER_INERTIA, (52.0833, 41.6666, 27.0833)]),
        "damper": dz.System(body, parts=[dz.Damper(0.5, 0.2)]),
    }
    started = threading.Event()
    def work():
        started.set()
        while True:
            if kind == "batch":
                dz.simulate(body, omega, t_end=100.0, frames=501, dt=1e-3)
            elif kind in MODELS:
                dz.simulate(MODELS[kind], omega, t_end=20.0, frames=501, dt=1e-3)
            elif kind == "sweep":
                dz.sweep(body, omega, t_end=100.0, dt=1e-3, progress=False)
            else:
                dz.rotate(np.tile([0.9, 0.1, -0.3, 0.2], (3000, 1)), np.ones((3000, 3)))
    threading.Thread(target=work, daemon=True).start()
    started.wait()
    time.sleep(delay)
""")


def exits_cleanly(runs: int) -> None:
    """`runs` interpreters, each leaving while a daemon thread is inside a batch (of every
    kind: free, tensor, deployment, damper), a sweep or a rotation, at exit times spread over the calls' phases; all must exit with code 0."""
    rng = np.random.default_rng(15)
    failures = []
    procs: list[tuple[str, float, subprocess.Popen[str]]] = []
    # every batch kind (free, tensor, deployment, damper), a sweep and a rotation
    kinds = ["batch", "sweep", "rotate", "tensor", "deployment", "damper"]
    for i in range(runs):
        kind, delay = kinds[i % len(kinds)], float(rng.uniform(0.0, 0.3))
        procs.append((kind, delay, subprocess.Popen(
            [sys.executable, "-c", DAEMON, kind, str(delay)], stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE, text=True)))
        if len(procs) == 4 or i == runs - 1:  # four at a time
            for kind, delay, proc in procs:
                _, err = proc.communicate(timeout=120)
                if proc.returncode != 0:
                    failures.append((kind, delay, proc.returncode, err[-500:]))
            procs = []
    assert not failures, failures


def test_interpreter_exit_during_a_daemon_threads_call():
    """The short version: ~1 run in 70-100 used to end in SIGSEGV (exit code -11)."""
    exits_cleanly(24)


@pytest.mark.slow
def test_interpreter_exit_during_a_daemon_threads_call_many_times():
    """Enough runs (400) to have caught the old failure with probability > 99 %."""
    exits_cleanly(400)


def test_threads_far_beyond_the_runs_are_capped_and_pools_reused():
    """`threads=4000` built 4000 OS threads for 3 tiny runs (10-30 s); `threads=10**6` ran
    for minutes. Capped at the runs (and at `MAX_THREADS`), pools kept: fast, and the same
    numbers as one thread."""
    body = dz.Body(dz.PAPER_INERTIA)
    omega = np.tile([0.01, 0.01, 1.0], (3, 1)) * [[1.0], [1.5], [2.0]]
    one = dz.sweep(body, omega, t_end=10.0, frames=2, threads=1, progress=False)
    tasks = "/proc/self/task"
    before = len(os.listdir(tasks)) if os.path.exists(tasks) else None
    for threads in (4000, 10**6, 4000):
        batch = dz.simulate(body, omega, t_end=10.0, frames=11, threads=threads)
        many = dz.sweep(body, omega, t_end=10.0, frames=2, threads=threads, progress=False)
        np.testing.assert_array_equal(many.tilt, one.tilt)
        np.testing.assert_array_equal(batch.omega[2], dz.simulate(body, omega[2], t_end=10.0,
                                                                  frames=11).omega)
    if before is not None:  # the threads built are capped at the 3 runs (a pool of at most 3)
        assert len(os.listdir(tasks)) <= before + 3


@pytest.mark.skipif(not os.path.exists("/proc/self/task"), reason="counts threads in /proc")
def test_repeated_calls_with_threads_do_not_pile_up_threads():
    body = dz.Body(dz.PAPER_INERTIA)
    omega = np.tile([0.01, 0.01, 1.0], (8, 1))
    dz.simulate(body, omega, t_end=1.0, frames=2, threads=2)
    before = len(os.listdir("/proc/self/task"))
    for _ in range(20):
        dz.simulate(body, omega, t_end=1.0, frames=2, threads=2)
        dz.simulate(body, omega, t_end=1.0, frames=2, threads=3)
    assert len(os.listdir("/proc/self/task")) <= before + 3
