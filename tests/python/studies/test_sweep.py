"""Sweeps: per-run summaries equal to single `summarize` runs bit for bit, against the exact
flip period on a grid and against an independent reference for the tilt; stable axes report
no flips; blocks, threads and shapes change nothing; memory stays O(runs)."""

import subprocess
import sys
import textwrap
import warnings

import numpy as np
import pytest

import dzhanibekov as dz
from reference import dop853

PAPER = np.array(dz.PAPER_INERTIA)


def test_rows_equal_summarize_bit_for_bit(rng):
    a, b = rng.uniform(0.5, 2.0, (2, 40))
    inertia = np.stack([a, b, rng.uniform(np.abs(a - b) + 0.05, a + b)], axis=1)
    omega = rng.normal(size=(40, 3))
    q = rng.normal(size=(40, 4))
    for method in ("rk4", "splitting"):
        s = dz.sweep(inertia, omega, q, t_end=40.0, frames=9, dt=2e-3, method=method)
        assert s.shape == (40,)
        for i in range(40):
            one = dz.summarize(inertia[i], omega[i], q[i], t_end=40.0, frames=9, dt=2e-3,
                               method=method)
            assert s.flips[i] == one.flips
            if one.flips:
                assert s.first_flip[i] == one.flip_times[0]
            if one.flips >= 2:
                assert s.period[i] == (one.flip_times[-1] - one.flip_times[0]) / (one.flips - 1)
            else:
                assert np.isnan(s.period[i])
            assert dz.Drift(*(float(d[i]) for d in s.drift)) == one.drift
            assert (s.dt[i], s.n_steps[i], s.nfev[i]) == (one.dt, one.n_steps, one.nfev)
            assert s.exact_period[i] == dz.flip_period(inertia[i], omega[i])
        assert s.flips.sum() > 10


def test_measured_period_is_the_exact_flip_period_on_a_grid():
    # the paper's body spun near its intermediate axis z: every start flips
    starts = dz.grid([0.005, 0.02, 0.08, 0.3], [0.005, 0.03, 0.2], 1.0)
    s = dz.sweep(PAPER, starts, t_end=600.0, frames=2, dt=2e-3)
    assert s.shape == (4, 3)
    exact = np.array([[dz.flip_period(PAPER, w) for w in row] for row in starts])
    assert np.array_equal(s.exact_period, exact)
    assert np.all(s.flips >= 5)
    assert np.allclose(s.period, exact, rtol=1e-6, atol=0)
    # the count follows from the first flip and the period (a flip under way at t_end, the
    # axis not yet nearest L on the other side, is not counted)
    crossings = np.floor((600.0 - s.first_flip) / exact) + 1
    assert np.all((s.flips == crossings) | (s.flips == crossings - 1))


def test_stable_axes_report_no_flips():
    starts = np.array([[1.0, 0.02, 0.03], [0.02, 1.0, -0.03], [-2.0, 0.1, 0.1],
                       [0.01, -3.0, 0.2]])
    s = dz.sweep(PAPER, starts, t_end=500.0, frames=2, dt=1e-3)
    assert np.all(s.flips == 0) and np.all(np.isnan(s.first_flip)) and np.all(np.isnan(s.period))
    assert np.all(s.exact_period == np.inf)
    assert np.all(s.tilt_degrees < 10.0)


def test_tilt_is_the_largest_angle_of_the_first_nearest_axis_from_l():
    # against scipy's DOP853, sampled at every step: cos(tilt) = min s I_k ω_k / |L|
    starts = np.array([[0.05, 0.1, 1.0], [1.0, 0.3, 0.2], [0.2, 1.0, 0.3], [0.6, 0.2, 1.0],
                       [0.9, 0.5, 0.6]])
    s = dz.sweep(PAPER, starts, t_end=80.0, frames=2, dt=1e-3)
    t = np.linspace(0.0, 80.0, 80_001)
    turned = 0
    for i, w in enumerate(starts):
        omega, _ = dop853(PAPER, w, (1, 0, 0, 0), t)
        momentum = PAPER * omega
        k = int(np.argmax(np.abs(momentum[0])))
        sign = np.sign(momentum[0, k])
        cos_ref = np.min(sign * momentum[:, k]) / np.linalg.norm(momentum[0])
        assert np.cos(s.tilt[i]) == pytest.approx(cos_ref, abs=2e-7), w
        turned += s.tilt[i] > np.pi / 2
    assert 0 < turned < len(starts), "both kinds of start should be seen"


def test_a_body_at_rest_does_not_tilt():
    s = dz.sweep(PAPER, np.zeros((2, 3)), t_end=1.0)
    assert np.all(s.tilt == 0) and np.all(s.flips == 0)


def test_blocks_threads_and_shapes_change_nothing(rng):
    omega = rng.normal(size=(7, 9, 3))
    whole = dz.sweep(PAPER, omega, t_end=30.0, frames=3, dt=5e-3)
    assert whole.shape == (7, 9) and whole.inertia.shape == (7, 9, 3)
    for kwargs in (dict(block=5), dict(block=1, threads=1), dict(threads=2)):
        other = dz.sweep(PAPER, omega, t_end=30.0, frames=3, dt=5e-3, **kwargs)
        for name in ("flips", "first_flip", "period", "exact_period", "tilt", "dt", "n_steps"):
            assert np.array_equal(getattr(whole, name), getattr(other, name), equal_nan=True)
    flat = dz.sweep(PAPER, omega.reshape(-1, 3), t_end=30.0, frames=3, dt=5e-3)
    assert np.array_equal(flat.tilt, whole.tilt.reshape(-1))


def test_grid_builds_every_combination():
    g = dz.grid([0.1, 0.2], [0.0, 0.5, 1.0], 1.0)
    assert g.shape == (2, 3, 3)
    assert np.array_equal(g[1, 2], [0.2, 1.0, 1.0])
    assert np.array_equal(g[:, :, 2], np.ones((2, 3)))
    assert dz.grid(1.0, [2.0, 3.0], 4.0).shape == (2, 3)
    assert dz.grid(1.0, 2.0, 3.0).shape == (3,)
    with pytest.raises(ValueError, match="at least one"):
        dz.grid()
    with pytest.raises(ValueError, match=r"`axes\[1\]` must be a number or a 1-D array"):
        dz.grid(1.0, [[1.0, 2.0]], 3.0)
    with pytest.raises(ValueError, match=r"`axes\[0\]` must be finite"):
        dz.grid([np.inf], 1.0)
    with pytest.raises(TypeError, match=r"`axes\[2\]` must hold real numbers"):
        dz.grid(1.0, 2.0, "z")


@pytest.mark.parametrize(
    "kwargs, error, match",
    [
        (dict(block=0), ValueError, "`block` must be at least 1"),
        (dict(progress="yes"), TypeError, "`progress`"),
        (dict(client=object()), TypeError, "`client` must be a dask.distributed.Client"),
        (dict(threads=0), ValueError, "`threads`"),
        (dict(omega0=np.zeros((2, 3)), q0=np.ones((3, 4))), ValueError, "leading"),
        (dict(omega0=[[0, 0, 1], [0, 0, np.nan]]), ValueError, "`omega0` must be finite"),
        (dict(t_end=0.0), ValueError, "`t_end`"),
    ],
)
def test_bad_sweeps_are_refused(kwargs, error, match):
    kwargs = {"system": PAPER, "omega0": [[0.0, 0.1, 1.0]], **kwargs}
    with pytest.raises(error, match=match):
        dz.sweep(**kwargs)


@pytest.mark.parametrize("block", [1, 4096])
def test_a_diverging_run_is_recorded_and_the_sweep_goes_on(block):
    # one run of the four is far beyond RK4's stability limit at dt = 0.5 (|ω| = 1000); the
    # others run in the same group of SIMD lanes (block 4096) or alone (block 1)
    omega = np.array([[[0.0, 0.1, 1.0], [0.1, 0.0, 1.0]], [[0.1, 0.1, 1.0], [0.0, 1e3, 1.0]]])
    kwargs = dict(t_end=100.0, dt=0.5, frames=2)
    with pytest.warns(dz.StepSizeWarning, match=r"index \(1, 1\)"):
        swept = dz.sweep(PAPER, omega, block=block, progress=False, **kwargs)
    warnings.simplefilter("ignore", dz.StepSizeWarning)  # for the single runs below
    assert swept.status.tolist() == [["ok", "ok"], ["ok", "diverged"]]
    assert swept.ok.tolist() == [[True, True], [True, False]]
    assert swept.flips[1, 1] == -1 and swept.n_steps[1, 1] == 0
    for name in ("first_flip", "period", "tilt", "dt"):
        assert np.isnan(getattr(swept, name)[1, 1]), name
    assert np.isnan(swept.drift.energy[1, 1])
    assert swept.exact_period[1, 1] == dz.flip_period(PAPER, omega[1, 1])
    with pytest.raises(ValueError, match="the run diverged"):  # as a single run says
        dz.summarize(PAPER, omega[1, 1], **kwargs)
    for index in [(0, 0), (0, 1), (1, 0)]:  # the others keep their numbers, bit for bit
        one = dz.summarize(PAPER, omega[index], **kwargs)
        assert swept.flips[index] == one.flips and swept.n_steps[index] == one.n_steps
        assert swept.drift.energy[index] == one.drift.energy
    assert "not finished=1" in repr(swept)


def test_an_adaptive_run_over_max_steps_is_recorded_and_the_sweep_goes_on():
    omega = np.array([[0.0, 0.1, 1.0], [0.0, 50.0, 1.0]])  # the second needs far more steps
    kwargs = dict(t_end=100.0, frames=2, method="dopri5", max_steps=2000)
    swept = dz.sweep(PAPER, omega, progress=False, **kwargs)
    assert swept.status.tolist() == ["ok", "too many steps"]
    with pytest.raises(ValueError, match="max_steps"):
        dz.summarize(PAPER, omega[1], **kwargs)
    assert swept.n_steps[0] == dz.summarize(PAPER, omega[0], **kwargs).n_steps


def test_progress_bar_shows_when_asked(capsys):
    dz.sweep(PAPER, np.zeros((10, 3)), t_end=1.0, block=4, progress=True)
    assert "sweep" in capsys.readouterr().err
    dz.sweep(PAPER, np.zeros((10, 3)), t_end=1.0, block=4, progress=False)
    dz.sweep(PAPER, np.zeros((10, 3)), t_end=1.0, block=4)  # stderr is not a terminal
    assert capsys.readouterr().err == ""


def test_memory_grows_with_runs_not_frames():
    # 256 runs × 20001 frames would be 287 MB of frames; a sweep keeps none. In a fresh
    # process, the peak memory of the sweep stays near that of importing the package.
    script = textwrap.dedent("""
        import resource, numpy as np, dzhanibekov as dz
        before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        s = dz.sweep(dz.PAPER_INERTIA, np.random.default_rng(1).normal(size=(256, 3)),
                     t_end=20.0, frames=20_001, dt=1e-3)
        after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        print((after - before) / 1024, s.n_steps[0])
    """)
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         check=True).stdout.split()
    grown_mb, steps = float(out[0]), int(out[1])
    assert steps == 20_000
    assert grown_mb < 30, f"the sweep grew the process by {grown_mb:.0f} MB"


def test_the_default_path_imports_no_dask():
    script = textwrap.dedent("""
        import sys, dzhanibekov as dz
        dz.sweep(dz.PAPER_INERTIA, [[0.0, 0.1, 1.0]], t_end=1.0)
        print(sorted(m for m in sys.modules if m.split(".")[0] in ("dask", "distributed")))
    """)
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "[]"
