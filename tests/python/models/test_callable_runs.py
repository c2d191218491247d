"""A Python torque function across runs and threads, and what it may return (hardening round
4): each run keeps its own failure (and its own Ctrl-C); a return that is not three real
numbers is refused however it looks like one, and a valid array is read whatever its strides."""

from __future__ import annotations

import subprocess
import sys
import textwrap
import threading

import numpy as np
import pytest

import dzhanibekov as dz

BODY = dz.Body((1.0, 2.0, 3.0))


class Refused(Exception):
    pass


def test_a_failure_in_one_threads_run_stops_only_that_run():
    """Two Python threads run one system with a Python torque; the function raises only in
    thread A's run (its start spins about x). Thread B's run, whose calls never raised, got a
    DivergedError 6 times in 6: the failure flag was the function object's, shared by every
    run of it."""
    b_started = threading.Event()

    def torque(t, q, omega):
        if omega[0] > 0.5:  # thread A's run
            b_started.wait(10.0)
            raise Refused("only A's run fails")
        b_started.set()
        return np.zeros(3)

    system = dz.System(BODY, torques=[dz.CallableTorque(torque)])
    outcomes: dict[str, object] = {}

    def run(name: str, omega0: tuple[float, float, float]) -> None:
        try:
            traj = dz.simulate(system, omega0, t_end=200.0, frames=3, method="rk4", dt=1e-3)
            outcomes[name] = traj
        except Exception as exc:  # inspected below
            outcomes[name] = exc

    threads = [threading.Thread(target=run, args=("A", (1.0, 0.0, 0.0))),
               threading.Thread(target=run, args=("B", (0.0, 0.0, 0.3)))]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(120.0)
    assert isinstance(outcomes["A"], Refused), outcomes
    assert isinstance(outcomes["B"], dz.Trajectory), outcomes["B"]
    # B's body spins about its major axis untouched: ω stays (0, 0, 0.3)
    assert np.allclose(outcomes["B"].omega[-1], (0.0, 0.0, 0.3), atol=1e-12)


CTRL_C_IN_ONE_RUN = textwrap.dedent("""
    import os, signal, threading, time
    import numpy as np
    import dzhanibekov as dz

    calls = {"B": 0}
    def torque(t, q, omega):
        if omega[0] <= 0.5:
            calls["B"] += 1
        return np.zeros(3)

    system = dz.System(dz.Body((1.0, 2.0, 3.0)), torques=[dz.CallableTorque(torque)])
    out = {}
    def b():
        try:
            out["B"] = dz.simulate(system, (0.0, 0.0, 0.3), t_end=300.0, frames=3, method="rk4",
                                   dt=1e-3)
        except BaseException as exc:
            out["B"] = exc
    thread = threading.Thread(target=b)
    thread.start()
    while calls["B"] == 0:
        time.sleep(0.001)
    threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
    try:
        dz.simulate(system, (1.0, 0.0, 0.0), t_end=1e4, frames=3, method="rk4", dt=1e-3)
        print("main: finished")
    except KeyboardInterrupt:
        print("main: interrupted")
    thread.join()
    print("B:", type(out["B"]).__name__)
""")


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to oneself")
def test_ctrl_c_stops_only_the_run_of_the_thread_it_reached():
    """Ctrl-C stopped the function object for every run of it: another thread's run of the
    same system then stopped with a DivergedError."""
    done = subprocess.run([sys.executable, "-c", CTRL_C_IN_ONE_RUN], capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.split() == ["main:", "interrupted", "B:", "Trajectory"], done.stdout


def _run(value):
    system = dz.System(BODY, torques=[dz.CallableTorque(lambda t, q, w: value)])
    return dz.simulate(system, (0.0, 0.0, 1.0), t_end=1.0, frames=2, method="rk4", dt=0.1)


@pytest.mark.parametrize("value, what", [
    (b"abc", "bytes"),  # was read as the torque (97, 98, 99)
    (bytearray(b"abc"), "bytearray"),
    ("abc", "str"),
    (np.ma.masked_array([1.0, 2.0, 3.0], mask=[0, 1, 0]), "masked"),  # mask ignored
    (np.array([1.0 + 1j, 0.0, 0.0]), "complex"),  # imaginary part dropped, a ComplexWarning
    ([1.0 + 1j, 0.0, 0.0], "complex"),
    ((np.complex128(1.0), 0.0, 0.0), "complex"),
])
def test_a_return_that_only_looks_like_three_numbers_is_refused(value, what):
    with pytest.raises(ValueError, match=rf"the `torque` function must return three real "
                                         rf"numbers.*{what}"):
        _run(value)


def test_a_valid_non_contiguous_view_is_read_as_it_is():
    """`w[::-1]` and a column of a matrix were refused with "not contiguous"."""
    base = np.array([0.5, 0.0, 0.0, 0.0, 0.0, 0.25])
    matrix = np.array([[0.0, 1.0, 2.0], [0.0, 4.0, 5.0], [0.06, 7.0, 8.0]])
    for view, tau_z in ((base[::-2][::-1], 0.25), (matrix[:, 0], 0.06),
                        (np.array([0, 0, 3], dtype=np.int32), 3.0)):
        traj = _run(view)
        # a torque along the spin axis z of a principal body: ω_z(1) = 1 + τ_z t / I_z
        assert traj.omega[-1, 2] == pytest.approx(1.0 + tau_z / 3.0, rel=1e-12), view
        assert np.all(traj.omega[-1, :2] == 0.0)
