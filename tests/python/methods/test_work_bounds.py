"""Work the package refuses before it starts, and edge starts it solves under one rule:
frames count toward `max_steps`; divergence is reported in the user's time; a start within
1e-150 of an axis is a steady spin for every method and function; a body whose closed form
cannot reproduce its start is refused by `method="exact"`."""

from __future__ import annotations

import re
import subprocess
import sys
import warnings

import numpy as np
import pytest

import dzhanibekov as dz

BODY = dz.Body(dz.PAPER_INERTIA)


@pytest.mark.parametrize("method", ["exact", "dop853", "dopri5"])
def test_a_huge_frame_grid_is_refused_up_front_with_its_count(method):
    """These used to run until interrupted: frames were not counted as work."""
    with pytest.raises(ValueError, match=rf"needs {2**62} frames \(each is evaluated\), more "
                                         r"than the limit max_steps = 10000000000"):
        dz.summarize(BODY, (0.01, 0.01, 1.0), frames=2**62, method=method, dt=None)
    # within the limit it runs; raising the limit is the way to more frames
    with pytest.raises(ValueError, match=r"needs 1001 frames"):
        dz.summarize(BODY, (0.01, 0.01, 1.0), t_end=1.0, frames=1001, method=method,
                     dt=None, max_steps=1000)
    assert dz.summarize(BODY, (0.01, 0.01, 1.0), t_end=1.0, frames=1001, method=method,
                        dt=None, max_steps=100_000).n_steps >= 0


def test_divergence_is_reported_in_the_users_time():
    """Rates of 4e6 are integrated in units of 2^22; the divergence time came back in them
    (6.9e6, beyond t_end = 100). The check falls every 16384 steps: t = 1.6384."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(ValueError, match=r"diverged \(non-finite state\) at "
                                             r"t = 1.6384:"):
            dz.simulate(BODY, (3e5, 5e5, 4e6), t_end=100.0, frames=2, dt=1e-4)
        # a sweep keeps going past such a run (issue 11): its status says it diverged
        swept = dz.sweep(BODY, [[3e5, 5e5, 4e6]], t_end=100.0, frames=2, dt=1e-4,
                         progress=False)
        assert swept.status[0] == "diverged"


@pytest.mark.parametrize("omega0", [(1e-170, 0.0, 1.0), (0.0, 1e-200, -2.0),
                                    (1.0, 1e-160, 1e-170)])
def test_a_start_this_close_to_an_axis_is_one_motion_everywhere(omega0):
    """`flip_period` and `exact` refused these while sweep's exact_period said inf."""
    period = dz.flip_period(BODY, omega0)
    swept = dz.sweep(BODY, np.array([omega0]), t_end=10.0, frames=2, progress=False)
    assert period == swept.exact_period[0] == np.inf
    traj = dz.simulate(BODY, omega0, t_end=10.0, frames=5, method="exact")
    np.testing.assert_allclose(traj.omega[0], omega0, rtol=0,
                               atol=1e-15 * np.abs(omega0).max())
    if omega0 == (1e-170, 0.0, 1.0):
        # no wobble float64 can hold: a steady spin, the attitude turning about ω0 at |ω0|
        # (the formula of a rotation about a fixed axis)
        np.testing.assert_array_equal(traj.omega, np.tile(omega0, (5, 1)))
        w = np.asarray(omega0)
        angle = np.linalg.norm(w) * traj.t
        axis = w / np.linalg.norm(w)
        expected = np.column_stack([np.cos(angle / 2), np.sin(angle / 2)[:, None] * axis])
        np.testing.assert_allclose(traj.q, expected, atol=1e-15)
    # RK4 agrees (a wobble of 1e-150 or less grows by e^(λt) < 1e10 by t = 10)
    rk4 = dz.simulate(BODY, omega0, t_end=10.0, frames=5)
    np.testing.assert_allclose(rk4.omega, traj.omega, rtol=0, atol=1e-12)
    np.testing.assert_allclose(rk4.q, traj.q, rtol=0, atol=1e-6)


def test_exact_refuses_a_body_with_a_vanishing_moment():
    """(1, 2, 1e-30): the closed form's frame 0 was (0.3, 0.2, -0.0), not the start."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(ValueError, match=r"`inertia` must have moments the closed form "
                                             r"resolves for method='exact'"):
            dz.simulate(dz.Body((1.0, 2.0, 1e-30)), (0.3, 0.2, 0.1), method="exact",
                        t_end=10.0)
        with pytest.raises(ValueError, match=r"`inertia` must have moments"):
            dz.flip_period(dz.Body((1.0, 2.0, 1e-30)), (0.3, 0.2, 0.1))


def test_every_exact_start_of_a_sample_begins_at_the_start(rng):
    """The refusal never fires on ordinary bodies and starts: frame 0 is the start."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for _ in range(200):
            inertia = np.sort(rng.uniform(0.1, 10.0, 3))
            omega = rng.normal(size=3) * 10.0 ** rng.uniform(-3, 3)
            # a Body: random moments need not be a real body's (no swap check wanted here)
            traj = dz.simulate(dz.Body(inertia), omega, t_end=1.0, frames=2, method="exact")
            np.testing.assert_allclose(traj.omega[0], omega, rtol=1e-12,
                                       atol=1e-12 * np.abs(omega).max())


UNBOUNDED = """
import sys, time
import dzhanibekov as dz
body = dz.Body((1.0, 2.0, 3.0))
torque = lambda frame: dz.System(body, torques=[dz.ConstantTorque((0.0, 0.0, 1e15), frame)])
cases = {
    "rates 1e20": (body, (1e20, 1e19, 1e18), 100.0),
    "rates 1e300": (body, (1e300, 1e299, 1e298), 100.0),
    "t_end 1e300": (body, (0.01, 0.01, 1.0), 1e300),
    "torque 1e15 body": (torque("body"), (0.01, 0.01, 1.0), 100.0),
    "torque 1e15 world": (torque("world"), (0.01, 0.01, 1.0), 100.0),
}
for method in ("dop853", "dopri5"):
    for name, (system, omega0, t_end) in cases.items():
        start = time.process_time()
        try:
            dz.simulate(system, omega0, t_end=t_end, method=method, frames=2)
            outcome = "returned"
        except dz.TooLargeError as exc:
            outcome = "refused: " + str(exc)
        print(f"{method} {name} | {time.process_time() - start:.3f} | {outcome}", flush=True)
"""


def test_an_adaptive_run_that_cannot_finish_is_refused_at_once():
    """dop853 and dopri5 at rates of 1e20 or 1e300, to t_end = 1e300, or under a torque of
    1e15 ran toward max_steps = 1e10 for hours (Ctrl-C worked); RK4 is refused by its planned
    step in well under a second. Now the free body's runs are refused up front from the
    fewest steps they need (the rates never fall below 2E/|L|, and no accepted step turns the
    attitude by more than MAX_TURN_PER_STEP: tests/adaptive_bounds.rs), and a run whose steps
    shrink without bound (the torque spins the body up) as soon as its pace cannot reach
    t_end within max_steps. Run in a child with a timeout: before, the first case hung."""
    done = subprocess.run([sys.executable, "-c", UNBOUNDED], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    lines = done.stdout.strip().splitlines()
    assert len(lines) == 10, lines
    for line in lines:
        case, cpu, outcome = line.split(" | ")
        assert outcome.startswith("refused: the adaptive run needs"), line
        assert "more than the limit max_steps = 10000000000" in outcome, line
        assert float(cpu) < 0.5, line
        if "torque" in case:
            assert "at its present step" in outcome, line
        else:
            assert re.search(r"needs at least [\d.]+e\d+ steps \(its attitude turns", outcome), line


FRAMES_NOT_KEPT = """
import time
import numpy as np
import dzhanibekov as dz
deployment = dz.Deployment([1.0, 2.0], [(1.0, 2.0, 3.0), (1.0, 3.0, 2.0)])
for method in ("dop853", "dopri5"):
    system = [deployment]
    out = {}
    for frames in (11, 2**31):
        start = time.process_time()
        s = dz.sweep(system, [(0.01, 0.01, 1.0)], t_end=10.0, frames=frames, method=method,
                     progress=False)
        out[frames] = (time.process_time() - start, s)
    (_, few), (cpu, many) = out[11], out[2**31]
    # what the frames do not change: where the runs end, so the verdict
    ends = ("omega_deployed", "flip_period")
    same = all(np.array_equal(getattr(few, e), getattr(many, e), equal_nan=True) for e in ends)
    small = all(np.all(np.asarray(d) < 1e-6) for d in many.drift[1:4])  # (|L|, L, |q|)
    print(method, f"{cpu:.3f}", str(many.status.tolist()), same and small, flush=True)
"""


def test_frames_a_sweep_never_keeps_are_not_evaluated():
    """A deployment sweep with frames=2**31 ran past 600 s interpolating frames it never
    keeps. A run that keeps no frames now reads, of a step that spans more than 64 frames,
    the last only, whatever `frames` is: the runs end where they did (the frames never moved
    a step) and their drift is measured all the same, at fewer points. In a child with a
    timeout: before, it ran past it."""
    done = subprocess.run([sys.executable, "-c", FRAMES_NOT_KEPT], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    lines = done.stdout.strip().splitlines()
    assert len(lines) == 2, lines
    for line in lines:
        method, cpu, status, same = line.split(" ", 3)
        assert float(cpu) < 0.5 and status == "['ok']", line
        assert same == "True", line
