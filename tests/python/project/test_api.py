"""The public API: shapes, the frame grid, presets, the command line, threads."""

import threading

import numpy as np
import pytest

import dzhanibekov as dz
from dzhanibekov.cli import main


def test_trajectory_shapes_and_the_exact_frame_grid(paper_body):
    traj = dz.simulate(paper_body, omega0=(0.01, 0.01, 1.0), q0=(1, 0, 0, 0), t_end=100.0,
                       frames=201, dt=1e-3, method="rk4")
    assert traj.t.shape == (201,) and traj.omega.shape == (201, 3) and traj.q.shape == (201, 4)
    assert traj.t[0] == 0.0 and traj.t[-1] == 100.0
    assert np.array_equal(traj.t, 100.0 * (np.arange(201) / 200))
    assert traj.n_steps == 100_000 and traj.nfev == 4 * traj.n_steps
    np.testing.assert_array_equal(traj.omega[0], (0.01, 0.01, 1.0))
    np.testing.assert_array_equal(traj.q[0], (1, 0, 0, 0))


def test_substeps_are_equal_and_no_longer_than_dt(paper_body):
    traj = dz.simulate(paper_body, (0.0, 0.0, 1.0), t_end=1.0, frames=4, dt=0.1)
    # 1/3 per frame interval in ceil(3.33) = 4 substeps of 1/12
    assert traj.n_steps == 12
    assert traj.dt == pytest.approx(1.0 / 12.0) and traj.dt <= 0.1


def test_memory_is_set_by_frames_not_steps(paper_body):
    traj = dz.simulate(paper_body, (0.01, 0.01, 1.0), t_end=10.0, frames=3, dt=1e-5)
    assert traj.n_steps == 1_000_000
    assert traj.q.shape == (3, 4)


def test_a_non_unit_q0_is_normalised(paper_body):
    traj = dz.simulate(paper_body, (0.1, 0.2, 0.3), q0=(2.0, 0.0, 0.0, 0.0), t_end=1.0, frames=2)
    np.testing.assert_array_equal(traj.q[0], (1.0, 0.0, 0.0, 0.0))


def test_inertia_may_be_given_directly_and_as_a_box():
    a = dz.simulate((1.0, 2.0, 3.0), (0.1, 0.2, 0.3), t_end=1.0, frames=2)
    b = dz.simulate(dz.Body(inertia=(1.0, 2.0, 3.0)), (0.1, 0.2, 0.3), t_end=1.0, frames=2)
    np.testing.assert_array_equal(a.q, b.q)
    box = dz.Body.box(20, 10, 15)
    np.testing.assert_allclose(box.inertia, (325 / 12, 625 / 12, 500 / 12))
    # erratum 2: the paper's moments are the box's with x and y swapped
    np.testing.assert_allclose(dz.PAPER_INERTIA, np.array(box.inertia)[[1, 0, 2]], rtol=1e-5)
    assert box.intermediate_axis == 2 and dz.Body(dz.PAPER_INERTIA).intermediate_axis == 2
    assert dz.Body.box(10, 20, 30, mass=2.0).inertia[0] == pytest.approx(2 * (400 + 900) / 12)


def test_box_data():
    v = dz.box_vertices()
    assert v.shape == (8, 3) and set(map(tuple, np.abs(v))) == {(10.0, 5.0, 7.5)}
    edges = dz.box_edges()
    assert edges.shape == (12, 2)
    lengths = sorted(np.linalg.norm(v[edges[:, 0]] - v[edges[:, 1]], axis=1))
    assert lengths == [10.0] * 4 + [15.0] * 4 + [20.0] * 4


def test_presets_are_the_papers():
    assert set(dz.PAPER_SCENES) == {"example", "fig3a", "fig3b", "fig3c"}
    assert dz.SCENES["stable-smallest"].omega0 == (0.01, 1.0, 0.01)
    assert dz.SCENES["fig3c"].t_end == 900 and dz.SCENES["fig3b"].omega0 == (0.01, 0.1, 0.03)
    assert all(dz.SCENES[n].inertia == dz.PAPER_INERTIA for n in dz.PAPER_SCENES)
    with pytest.raises(KeyError):
        dz.SCENES["fig4"]
    # the aliases of the unreleased 0.1.0 are gone
    assert not any(hasattr(dz, n) for n in ("Scenario", "SCENARIOS", "scenario"))


@pytest.mark.parametrize("inertia, omega0", [
    ((3.0, 2.0, 1.0), (1.0, 0.01, 0.01)),  # about the largest moment
    ((3.0, 2.0, 1.0), (0.01, 0.01, 1.0)),  # about the smallest
    ((2.0, 2.0, 1.0), (0.01, 0.01, 1.0)),  # a symmetric top, about its symmetry axis
])
def test_stable_spins_do_not_flip(inertia, omega0):
    traj = dz.simulate(inertia, omega0, t_end=500.0, frames=11, dt=1e-2)
    assert len(traj.flip_times) == 0
    # the spin axis stays within a few degrees of where it started
    axis = np.argmax(np.abs(omega0))
    e = np.zeros(3)
    e[axis] = 1.0
    start = dz.rotate(traj.q[0], e)
    assert np.min(dz.rotate(traj.q, e) @ start) > np.cos(np.radians(5))


def test_spin_about_the_intermediate_axis_flips():
    traj = dz.simulate((3.0, 2.0, 1.0), (0.01, 1.0, 0.01), t_end=100.0, frames=11, dt=1e-2)
    assert len(traj.flip_times) >= 3


def test_the_command_line_rejects_a_bad_step(capsys, tmp_path):
    # named by its option (issue 24: it said `run.dt`), before anything runs
    with pytest.raises(SystemExit) as exit_:
        main(["paper", "--out", str(tmp_path / "figures"), "--dt", "-1"])
    assert exit_.value.code == 2
    assert "argument --dt: must be a positive number" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_the_gil_is_released_during_a_run(paper_body):
    ticks = 0
    done = threading.Event()

    def run():
        dz.simulate(paper_body, (0.01, 0.01, 1.0), t_end=2e4, frames=2, dt=1e-3)
        done.set()

    worker = threading.Thread(target=run)
    worker.start()
    while not done.is_set():
        ticks += 1
        done.wait(0.001)
    worker.join()
    # 2·10⁷ steps take a good fraction of a second; with the GIL held this loop could not run
    assert ticks > 20


def test_threads_get_the_same_results_as_serial_calls(rng):
    inputs = [rng.normal(size=3) for _ in range(4)]
    serial = [dz.simulate((1.0, 2.0, 3.0), w, t_end=50.0, frames=5).q for w in inputs]
    results = [None] * 4

    def run(i):
        results[i] = dz.simulate((1.0, 2.0, 3.0), inputs[i], t_end=50.0, frames=5).q

    threads = [threading.Thread(target=run, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(serial, results):
        np.testing.assert_array_equal(a, b)


# --- traps a new user fell into (issue 11) --------------------------------------------------


def test_dt_none_is_the_default_and_assumes_no_time_scale(paper_body):
    # a tenth of a day at 0.2 rad/s: dt=1e-3 took 8.6e6 steps for an accuracy it did not
    # need; the default step is the one picked for rtol, scaled with the rates
    omega0 = (0.002, 0.002, 0.2)
    run = dz.summarize(paper_body, omega0, t_end=8640.0)
    assert run.n_steps == dz.summarize(paper_body, omega0, t_end=8640.0, dt=None).n_steps
    fast = dz.summarize(paper_body, [10 * w for w in omega0], t_end=864.0)
    assert fast.n_steps == run.n_steps  # (ω, t) → (sω, t/s): the same run
    assert run.n_steps < 2e6 < 8640.0 / 1e-3
    exact = dz.summarize(paper_body, omega0, t_end=8640.0, method="exact")
    assert run.flips == exact.flips > 10
    np.testing.assert_allclose(run.flip_times, exact.flip_times, rtol=0, atol=1e-3)
    traj = dz.simulate(paper_body, omega0, t_end=864.0, frames=5)
    same = dz.simulate(paper_body, omega0, t_end=864.0, frames=5, dt=None)
    assert np.array_equal(traj.q, same.q) and traj.dt == same.dt
    swept = dz.sweep(paper_body, [omega0], t_end=864.0, frames=5, progress=False)
    assert swept.dt[0] == traj.dt
    assert dz.simulate(paper_body, omega0, t_end=1.0, frames=2, dt=1e-3).dt == 1e-3


PAPER_RATES = (0.01, 0.01, 1.0)


@pytest.mark.parametrize("call", [
    lambda: dz.simulate(PAPER_RATES, dz.PAPER_INERTIA),
    lambda: dz.summarize(PAPER_RATES, dz.PAPER_INERTIA),
    lambda: dz.sweep(PAPER_RATES, dz.PAPER_INERTIA),
    lambda: dz.flip_period((0.8660254037844394, 0.2, 0.5), (1.0, 2.0, 3.0)),
    lambda: dz.simulate((1.0, -2.0, 3.0), (1.0, 2.0, 3.0)),  # "moments" not all positive
])
def test_swapped_arguments_are_named_as_such(call):
    with pytest.raises(ValueError, match=r"look swapped: `body` .* could be; pass the moments "
                                         r"first"):
        call()


def test_moments_no_body_has_still_run_when_asked_for_by_a_body():
    with pytest.warns(dz.InertiaWarning):
        body = dz.Body((0.5, 0.6, 2.0))
    assert dz.flip_period(body, (1.0, 1.0, 1.0)) > 0  # no swap is suspected
    traj = dz.simulate(body, (0.1, 1.0, 0.1), t_end=5.0, frames=3)
    assert np.isfinite(traj.omega).all()
    # rates that could not be moments: nothing is suspected either
    with pytest.warns(dz.InertiaWarning):
        dz.simulate((0.5, 0.6, 2.0), (0.1, 1.0, 0.1), t_end=5.0, frames=3)
