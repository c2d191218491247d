"""Processes made by `fork()` after the parent ran parallel work (a batch, a sweep, a large
rotation) run parallel work of their own: the core's thread pool is rebuilt in the child,
which inherits none of the parent's threads. Each scenario runs in a fresh interpreter under
a timeout, so that a hang fails its test instead of stalling the suite."""

import subprocess
import sys
import textwrap

import pytest

SETUP = """
import multiprocessing as mp, os, sys
import numpy as np
import dzhanibekov as dz

OMEGA = dz.grid(np.linspace(0.01, 0.2, 40), [0.01, 0.1], 1.0).reshape(-1, 3)

def parallel_work():
    batch = dz.simulate(dz.PAPER_INERTIA, OMEGA, t_end=20.0, frames=3, dt=1e-2)
    swept = dz.sweep(dz.PAPER_INERTIA, OMEGA, t_end=20.0, frames=3, dt=1e-2, progress=False)
    turned = dz.rotate(np.tile([0.9, 0.1, -0.3, 0.2], (200, 1)), np.ones((2000, 3)))
    return int(batch.flips.sum()), int(swept.flips.sum()), float(turned.sum())

def child(queue):
    queue.put(parallel_work())
"""

SCENARIOS = {
    "os.fork": """
expected = parallel_work()
pid = os.fork()
if pid == 0:
    os._exit(0 if parallel_work() == expected else 3)
_, status = os.waitpid(pid, 0)
assert os.waitstatus_to_exitcode(status) == 0, status
""",
    "fork": """
expected = parallel_work()
ctx = mp.get_context("fork")
queue = ctx.Queue()
p = ctx.Process(target=child, args=(queue,))
p.start()
assert queue.get(timeout=60) == expected
p.join()
""",
    "spawn": """
if __name__ == "__main__":
    expected = parallel_work()
    ctx = mp.get_context("spawn")
    queue = ctx.Queue()
    p = ctx.Process(target=child, args=(queue,))
    p.start()
    assert queue.get(timeout=60) == expected
    p.join()
""",
    # a child of a child: the pool is rebuilt again
    "fork twice": """
expected = parallel_work()
pid = os.fork()
if pid == 0:
    ok = parallel_work() == expected
    grandchild = os.fork()
    if grandchild == 0:
        os._exit(0 if parallel_work() == expected else 3)
    _, status = os.waitpid(grandchild, 0)
    os._exit(0 if ok and os.waitstatus_to_exitcode(status) == 0 else 4)
_, status = os.waitpid(pid, 0)
assert os.waitstatus_to_exitcode(status) == 0, status
""",
}


@pytest.mark.parametrize("scenario", list(SCENARIOS))
def test_parallel_work_after_fork_and_spawn(scenario, tmp_path):
    script = tmp_path / "forked.py"
    script.write_text(textwrap.dedent(SETUP) + textwrap.dedent(SCENARIOS[scenario]))
    try:
        done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                              timeout=120, cwd=tmp_path)
    except subprocess.TimeoutExpired:
        pytest.fail(f"{scenario}: the child hung on its first parallel call")
    assert done.returncode == 0, done.stderr
