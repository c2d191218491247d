"""Under an address-space limit (`ulimit -v`, `prlimit --as`, as cluster schedulers set), every
request whose memory follows from its input ends in a Python error that says how much was
asked — never an abort of the interpreter (SIGABRT, exit 134) or a panic.

Each case runs in a child process with `RLIMIT_AS` set before the package is imported; the
child prints the exception's type and message."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import pytest

pytestmark = pytest.mark.skipif(sys.platform != "linux", reason="RLIMIT_AS as on Linux")

PRELUDE = """
import resource, sys
limit = int(sys.argv[1])
resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
import numpy as np
import dzhanibekov as dz
try:
{body}
except BaseException as exc:
    print("RAISED", type(exc).__name__, "|", *[c.__name__ for c in type(exc).__mro__], "|",
          str(exc).replace(chr(10), " ")[:400])
else:
    print("RETURNED")
"""


def under_limit(body: str, limit: int, timeout: float = 120.0) -> str:
    """The child's report of `body` (indented into a try block) under `limit` bytes."""
    code = PRELUDE.format(body=textwrap.indent(textwrap.dedent(body).strip(), "    "))
    done = subprocess.run([sys.executable, "-c", code, str(limit)], capture_output=True,
                          text=True, timeout=timeout)
    assert done.returncode == 0, (
        f"the child died with exit code {done.returncode} (134 is an abort):\n"
        f"{done.stdout}\n{done.stderr[-2000:]}")
    return done.stdout.strip().splitlines()[-1]


def assert_refused_with_size(report: str, *words: str) -> None:
    """A refusal (ValueError or MemoryError, not PanicException) naming the bytes asked."""
    assert report.startswith("RAISED"), report
    _, kind, rest = report.split(" ", 2)
    mro, message = rest.split("|", 2)[1:]
    assert "PanicException" not in mro, report
    assert "ValueError" in mro or "MemoryError" in mro, report
    assert "byte" in message or "GB" in message or "GiB" in message, report
    for word in words:
        assert word in message, (word, report)


GB = 1 << 30


def test_exact_flip_times_of_a_long_batch():
    """~9e7 flips per run (720 MB each), three runs, under 2 GB."""
    report = under_limit("""
        dz.simulate(dz.PAPER_INERTIA, np.tile([0.01, 0.01, 1.0], (3, 1)), t_end=3.5e9,
                    frames=2, method="exact")
    """, 2 * GB)
    assert_refused_with_size(report, "flip times")


def test_a_sweep_of_ten_million_starts():
    report = under_limit("""
        omega = np.tile([0.01, 0.01, 1.0], (10**7, 1))
        dz.sweep(dz.PAPER_INERTIA, omega, t_end=1.0, frames=2, progress=False)
    """, 2 * GB)
    assert_refused_with_size(report)


def test_the_invariants_of_twenty_million_frames():
    """The frames of a 2e7-frame run (1.1 GB, made here as zeros rather than computed, to
    keep the test short), then their invariants (1.3 GB more) under 2 GB: refused in Python
    with the size, and by the core's own fallible allocation below that check."""
    frames = """
        from dzhanibekov.results import Drift, Trajectory
        n = 2 * 10**7
        traj = Trajectory(t=np.zeros(n), omega=np.zeros((n, 3)), q=np.zeros((n, 4)),
                          flip_times=None, system=dz.System(dz.PAPER_INERTIA), method="exact",
                          dt=0.0, n_steps=0, nfev=0, drift=Drift(0.0, 0.0, 0.0, 0.0))
    """
    frames = textwrap.dedent(frames).strip() + "\n"
    report = under_limit(frames + "traj.invariants()", 2 * GB)
    assert_refused_with_size(report, "invariants")
    core = ("from dzhanibekov import _core\n"
            "_core.observe(traj.system._core, traj.t, traj.omega, traj.q, np.empty((n, 0)))")
    report = under_limit(frames + core, 2 * GB)
    assert_refused_with_size(report)


def test_planning_the_steps_of_twenty_million_rows():
    report = under_limit("""
        omega = np.tile([0.01, 0.01, 1.0], (2 * 10**7, 1))
        dz.simulate(dz.PAPER_INERTIA, omega, t_end=1.0, frames=2, dt=None)
    """, 2 * GB)
    assert_refused_with_size(report)


def test_an_ellipsoid_mesh_of_4096_squared_cells():
    report = under_limit("dz.ellipsoid_mesh((1.0, 2.0, 3.0), 4096, 4096)", 700 << 20)
    assert_refused_with_size(report)


def test_rotate_into_more_than_the_limit():
    """20000 × 10000 points: 4.8 GB, under 2 GB: refused up front, never a PanicException
    (NumPy's failed allocation used to reach the core as a null pointer)."""
    report = under_limit("""
        dz.rotate(np.tile([1.0, 0.0, 0.0, 0.0], (20000, 1)), np.ones((10000, 3)))
    """, 2 * GB)
    assert_refused_with_size(report, "rotating")


def test_the_core_rotate_itself_raises_memory_error():
    """The core's own allocation of the output, below the Python check."""
    report = under_limit("""
        from dzhanibekov import _core
        _core.rotate(np.tile([1.0, 0.0, 0.0, 0.0], (20000, 1)), np.ones((10000, 3)))
    """, 2 * GB)
    assert_refused_with_size(report)


def test_grid_batch_rows_and_separatrix_gap_are_refused_with_their_size():
    side = 12000  # 1.4e8 starts: 3.5 GB of rows
    for call, words in [
        (f"dz.grid(np.arange({side}.0), np.arange({side}.0), 1.0)", ("grid",)),
        # moments along one axis, rates along the other: side² rows once broadcast
        (f"dz.sweep(np.ones(({side}, 1, 3)) + [0, 1, 2], np.ones((1, {side}, 3)), "
         "frames=2, t_end=1.0, progress=False)", ("starts",)),
        (f"from dzhanibekov.plotting.maps import separatrix_gap\n"
         f"separatrix_gap(np.ones(3) + [0, 1, 2], np.ones(({side} * 1000, 3)))",
         ("separatrix gap",)),
    ]:
        report = under_limit(call, 2 * GB)
        assert_refused_with_size(report, *words)


ROOM = """
import resource, sys
import numpy as np
import dzhanibekov as dz

def address_space():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024
    raise RuntimeError("no VmSize")

def limited(headroom, call):
    '''`call()` with the address space limited to what the process holds now plus
    `headroom` bytes: "RETURNED", or "RAISED" and the exception's classes.'''
    resource.setrlimit(resource.RLIMIT_AS, (address_space() + headroom, resource.RLIM_INFINITY))
    try:
        call()
    except BaseException as exc:
        return "RAISED " + " ".join(c.__name__ for c in type(exc).__mro__)
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (resource.RLIM_INFINITY, resource.RLIM_INFINITY))
    return "RETURNED"
"""

MB = 1 << 20


def in_child(code: str, timeout: float = 120.0) -> list[str]:
    """The lines a child prints running `ROOM` then `code`; it must not die."""
    # every large allocation a fresh mapping, one arena: the address space a call takes is
    # what it allocates, not what earlier calls left free in glibc's heaps
    env = {**os.environ, "MALLOC_MMAP_THRESHOLD_": "131072", "MALLOC_ARENA_MAX": "1"}
    done = subprocess.run([sys.executable, "-c", ROOM + textwrap.dedent(code)],
                          capture_output=True, text=True, timeout=timeout, env=env)
    assert done.returncode == 0, (
        f"the child died with exit code {done.returncode} (134 is an abort, -11 SIGSEGV):\n"
        f"{done.stdout}\n{done.stderr[-2000:]}")
    return done.stdout.strip().splitlines()


def test_a_deployment_sweep_allocates_no_frames():
    """A sweep keeps no frames, but the frame times of a deployment sweep were allocated
    (8 bytes a frame, infallibly: `frames=2**31` aborted the interpreter, `frames=2*10**7`
    under `prlimit --as=600M` too). Here 2·10⁶ frames (16 MB of times) with 8 MB to spare."""
    lines = in_child("""
        deployment = dz.Deployment([1, 2], [(1, 2, 3), (1, 3, 2)])
        sweep = lambda frames: dz.sweep([deployment], (0.01, 0.01, 1), t_end=10,
                                         frames=frames, method="dop853", progress=False)
        assert list(sweep(11).status) == ["ok"]
        print(limited(8 * MB, lambda: sweep(2 * 10**6)))
    """.replace("MB", str(MB)))
    assert lines == ["RETURNED"], lines


BATCH_KINDS = {
    "free": "dz.Body((1.0, 2.0, 3.0))",
    "tensor": "dz.Body.from_tensor([[2.0, 0.3, 0.0], [0.3, 1.0, 0.0], [0.0, 0.0, 3.0]])",
    "deployment": "dz.Deployment([0.5, 1.0], [(1.0, 2.0, 3.0), (1.0, 3.0, 2.0)])",
    "damper": "dz.System(dz.Body((1.0, 2.0, 3.0)), parts=[dz.Damper(0.1, 0.05)])",
    # a system with torques: each row's copy holds its list of torques (uncounted, a batch
    # of 10⁶ rows aborted under 700 MiB)
    "gravity": "dz.System(dz.Body((1.0, 2.0, 3.0)), torques=[dz.GravityGradient(0.1)])",
    "tabulated": "dz.System(dz.Body((1.0, 2.0, 3.0)), torques=[dz.TabulatedTorque([0.0, 1.0], "
                 "[(0, 0, 0), (0, 0, 1.0)])])",
    "wheels": "dz.System(dz.Body((1.0, 2.0, 3.0)), parts=[dz.Wheel((0, 1, 0), 0.5), "
              "dz.Wheel((1, 0, 0), ([0.0, 0.2], [0.0, 0.1]))])",
}


@pytest.mark.parametrize("kind", sorted(BATCH_KINDS))
def test_a_batch_of_every_kind_under_shrinking_limits(kind):
    """A batch of 2·10⁴ starts (frames=2) under address-space limits from a few MB above what
    the process holds to enough: each call returns its batch or raises a MemoryError
    (TooLargeError saying the size first) — never an abort or SIGSEGV. A damped batch of 10⁶
    starts passed the frames' size check (0.16 GB) and died under limits up to its real need
    (about 1 GB more): in the rows' collection (SIGABRT) or in rust-numpy's conversion of the
    result (SIGSEGV in PyArray_SetBaseObject)."""
    lines = in_child(f"""
        system = {BATCH_KINDS[kind]}
        omega = np.tile([0.01, 0.01, 1.0], (20000, 1)) * np.linspace(1, 2, 20000)[:, None]
        run = lambda: dz.simulate(system, omega, t_end=0.5, frames=2, dt=0.05, progress=False)
        run()  # the thread pool and NumPy's caches, outside the limits
        for headroom in (2, 3, 4, 5, 6, 8, 10, 12, 16, 20, 24, 32, 400):
            print(headroom, limited(headroom * {MB}, run))
    """)
    assert len(lines) == 13, lines
    for line in lines:
        headroom, outcome = line.split(" ", 1)
        assert outcome == "RETURNED" or ("MemoryError" in outcome and "Panic" not in outcome), line
    assert lines[-1].endswith("RETURNED"), lines
    assert any("MemoryError" in line for line in lines), lines


@pytest.mark.parametrize("kind", ["gravity", "tabulated"])
def test_a_million_rows_with_a_torque_under_limits_near_their_need(kind):
    """10⁶ rows of a system with a torque (frames=2) under limits from what the process holds
    plus 300 MB (below the starts' own size) to 420 MB: each call returns or raises a
    TooLargeError naming its size. The rows' copies of the system were counted without their
    list of torques, and the helper thread that watches for Ctrl-C was started without
    checking for its room: the batch aborted the interpreter ("memory allocation of 136 bytes
    failed" under `prlimit --as` 700 MiB; "cannot allocate memory for thread-local data")."""
    lines = in_child(f"""
        system = {BATCH_KINDS[kind]}
        omega = np.tile([0.01, 0.01, 1.0], (10**6, 1))
        run = lambda omega: dz.simulate(system, omega, t_end=0.5, frames=2, dt=0.05,
                                        progress=False)
        run(omega[:1000])  # the thread pool and NumPy's caches, outside the limits
        for headroom in (300, 306, 312, 318, 324, 336, 360, 400):
            print(headroom, limited(headroom * {MB}, lambda: run(omega)))
    """)
    assert len(lines) == 8, lines
    for line in lines:
        headroom, outcome = line.split(" ", 1)
        assert outcome == "RETURNED" or ("MemoryError" in outcome and "Panic" not in outcome), line


def test_rotate_allocates_nothing_beside_its_output():
    """2·10⁶ quaternions rotating 3 points (an output of 144 MB) with a few MB more than the
    output to spare: the core made a table of every frame's matrix besides (72 bytes a frame,
    infallibly), which aborted the interpreter past the output's size check (10⁷ frames under
    1.3 GB; `dzhanibekov run spin-up --frames 10000000` under 3 GB, in its figure's
    `rotate`)."""
    lines = in_child(f"""
        n = 2 * 10**6
        q = np.tile([1.0, 0.1, -0.2, 0.3], (n, 1))
        points = np.eye(3)
        dz.rotate(q[:10], points)
        for headroom in (150, 160, 200, 300):
            print(headroom, limited(headroom * {MB}, lambda: dz.rotate(q, points)))
    """)
    assert len(lines) == 4, lines
    for line in lines:
        headroom, outcome = line.split(" ", 1)
        assert outcome == "RETURNED" or ("MemoryError" in outcome and "Panic" not in outcome), line
    assert lines[-1].endswith("RETURNED"), lines


def test_a_wheel_schedule_of_many_knots_under_limits_near_its_need():
    """A wheel's schedule of 10⁶ knots built and run under limits from 60 MB to 300 MB
    above what the process holds (its arrays made before): each returns or raises a
    MemoryError. The run's model copied the schedule infallibly (10⁷ knots aborted under 2.2
    and 2.6 GB, on a 240 MB allocation: the table cloned whole, then its values mapped); the
    knots are now shared by the copies, the copies a run makes counted
    (`System::model_bytes`, checked against measured peaks in tests/heap_bytes.rs) and
    allocated fallibly."""
    lines = in_child(f"""
        n = 10**6
        t, h = np.arange(n) * 1e-6, np.linspace(0.0, 1.0, n)
        dz.simulate(dz.Body((1.0, 2.0, 3.0)), (0.01, 0.01, 1.0), t_end=0.5, frames=2, dt=0.05)

        def run():
            wheel = dz.Wheel((0, 1, 0), (t, h))
            system = dz.System(dz.Body((1.0, 2.0, 3.0)), parts=[wheel])
            dz.simulate(system, (0.01, 0.01, 1.0), t_end=0.5, frames=2, dt=0.05)

        for headroom in range(60, 301, 20):
            print(headroom, limited(headroom * {MB}, run))
    """)
    assert len(lines) == 13, lines
    for line in lines:
        headroom, outcome = line.split(" ", 1)
        assert outcome == "RETURNED" or ("MemoryError" in outcome and "Panic" not in outcome), line
    assert lines[-1].endswith("RETURNED"), lines
