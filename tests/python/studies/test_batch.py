"""`simulate` with a leading batch axis: every row equals the single run of its inputs, bit
for bit (mixed bodies, random inputs, 1 and 2 threads); inputs broadcast NumPy style; bad
input and batches too large for memory are refused before anything runs."""

import warnings

import numpy as np
import pytest

import dzhanibekov as dz


def random_rows(rng, m):
    """Mixed bodies (physical ones), rates of every size and direction, random attitudes."""
    a, b = rng.uniform(0.5, 2.0, (2, m))
    inertia = np.stack([a, b, rng.uniform(np.abs(a - b) + 0.05, a + b)], axis=1)
    omega = rng.normal(size=(m, 3)) * rng.choice([0.05, 0.5, 2.0], size=(m, 1))
    q = rng.normal(size=(m, 4))
    return inertia, omega, q


def assert_same_run(row, one):
    for name in ("t", "omega", "q"):
        assert np.array_equal(getattr(row, name), getattr(one, name)), name
    if one.flip_times is None:
        assert row.flip_times is None
    else:
        assert np.array_equal(row.flip_times, one.flip_times)
    assert row.drift == one.drift
    assert (row.dt, row.n_steps, row.nfev, row.n_rejected) == (
        one.dt, one.n_steps, one.nfev, one.n_rejected)
    assert row.body == one.body


@pytest.mark.parametrize("method", ["rk4", "splitting", "dopri5", "exact", "splitting6",
                                    "implicit_midpoint", "dmv", "dmv_modified", "rkmk4",
                                    "crouch_grossman3"])
def test_rows_equal_single_runs_bit_for_bit(rng, method):
    inertia, omega, q = random_rows(rng, 37)  # two groups of 16 lanes and a part group
    kwargs = dict(t_end=30.0, frames=31, method=method, dt=1e-2)  # dopri5: the first step
    batch = dz.simulate(inertia, omega, q, **kwargs)
    assert isinstance(batch, dz.Batch) and len(batch) == 37
    assert batch.omega.shape == (37, 31, 3) and batch.q.shape == (37, 31, 4)
    for i in range(37):
        assert_same_run(batch[i], dz.simulate(inertia[i], omega[i], q[i], **kwargs))
    if method == "rk4":
        assert batch.flips.sum() > 5, "the rows should flip"


def test_one_thread_and_two_give_the_same_bits(rng):
    inertia, omega, q = random_rows(rng, 50)
    one = dz.simulate(inertia, omega, q, t_end=20.0, frames=5, dt=1e-2, threads=1)
    two = dz.simulate(inertia, omega, q, t_end=20.0, frames=5, dt=1e-2, threads=2)
    assert np.array_equal(one.omega, two.omega) and np.array_equal(one.q, two.q)
    assert all(np.array_equal(a, b) for a, b in zip(one.flip_times, two.flip_times))
    for a, b in zip(one.drift, two.drift):
        assert np.array_equal(a, b)


def test_inputs_without_a_batch_axis_are_shared(paper_body):
    omega = np.array([[0.01, 0.01, 1.0], [0.1, 0.0, 1.0], [1.0, 0.1, 0.1]])
    q0 = (0.5, 0.5, 0.5, 0.5)
    batch = dz.simulate(paper_body, omega, q0, t_end=50.0, dt=1e-3)
    assert np.array_equal(batch.inertia, np.tile(dz.PAPER_INERTIA, (3, 1)))
    for i in range(3):
        assert_same_run(batch[i], dz.simulate(paper_body, omega[i], q0, t_end=50.0, dt=1e-3))
    # one body per row, one rate for all
    bodies = np.array([dz.PAPER_INERTIA, [1.0, 2.0, 2.5]])
    batch = dz.simulate(bodies, (0.01, 0.01, 1.0), t_end=50.0, dt=1e-3)
    assert len(batch) == 2
    assert_same_run(batch[1], dz.simulate((1.0, 2.0, 2.5), (0.01, 0.01, 1.0), t_end=50.0,
                                          dt=1e-3))


def test_a_batch_of_one_is_a_batch_and_one_dimensional_input_is_a_single_run(paper_body):
    single = dz.simulate(paper_body, (0.01, 0.01, 1.0))
    assert isinstance(single, dz.Trajectory)
    batch = dz.simulate(paper_body, [(0.01, 0.01, 1.0)])
    assert isinstance(batch, dz.Batch) and batch.omega.shape == (1, 201, 3)
    assert_same_run(batch[0], single)
    assert_same_run(batch[-1], single)
    with pytest.raises(IndexError):
        batch[1]
    # a slice of runs is a batch (issue 10); other keys are refused by name
    one = batch[0:1]
    assert isinstance(one, dz.Batch) and len(one) == 1
    assert_same_run(one[0], single)
    with pytest.raises(TypeError, match="run number"):
        batch[0.5]


def test_empty_batch(paper_body):
    batch = dz.simulate(paper_body, np.empty((0, 3)), t_end=1.0, frames=3)
    assert len(batch) == 0 and batch.omega.shape == (0, 3, 3) and batch.flip_times == ()


def test_flips_can_be_left_out(paper_body):
    batch = dz.simulate(paper_body, [(0.01, 0.01, 1.0)] * 3, flips=False)
    assert batch.flip_times is None and batch.flips is None
    assert np.array_equal(batch.q[0], dz.simulate(paper_body, (0.01, 0.01, 1.0)).q)


def test_dt_none_takes_the_smallest_step_of_the_rows(paper_body):
    omega = np.array([[0.01, 0.01, 1.0], [0.0, 3.0, 0.1]])  # the second is faster
    batch = dz.simulate(paper_body, omega, t_end=20.0, dt=None)
    alone = [dz.simulate(paper_body, w, t_end=20.0, dt=None) for w in omega]
    assert np.all(batch.dt == min(a.dt for a in alone))
    assert np.all(batch.n_steps == max(a.n_steps for a in alone))


@pytest.mark.parametrize(
    "kwargs, error, match",
    [
        (dict(omega0=np.zeros((3, 3)), q0=np.ones((2, 4))), ValueError, "leading"),
        (dict(omega0=np.zeros((2, 2, 3))), ValueError, r"`omega0` must have shape \(3,\) or"),
        (dict(omega0=[[0, 0, 1], [0, np.nan, 1]]), ValueError, "`omega0` must be finite"),
        (dict(omega0=[[0, 0, 1], [0, 1, 1]], q0=[[1, 0, 0, 0], [0, 0, 0, 0]]), ValueError,
         "row 1"),
        (dict(system=[[1, 2, 3], [1, -2, 3]], omega0=[0, 0, 1]), ValueError, "row 1"),
        (dict(system=[[1, 2, 3], [1, 1e200, 1e-200]], omega0=[0, 0, 1]), ValueError, "1e150"),
        (dict(omega0=[["a", "b", "c"]]), TypeError, "`omega0` must hold real numbers"),
        (dict(omega0=[[0, 0, 1]], threads=0), ValueError, "`threads` must be at least 1"),
        (dict(omega0=[[0, 0, 1]], threads=1.5), TypeError, "`threads` must be an integer"),
        (dict(omega0=[[0, 0, 1]], frames=1), ValueError, "`frames` must be at least 2"),
        (dict(omega0=[[0, 0, 1]], method="rk5"), ValueError, "`method` must be one of"),
        (dict(omega0=[[0, 0, 1]], dt=-1.0), ValueError, "`dt` must be positive"),
    ],
)
def test_bad_batches_are_refused_naming_the_argument(kwargs, error, match):
    kwargs = {"system": dz.PAPER_INERTIA, **kwargs}
    with pytest.raises(error, match=match):
        dz.simulate(**kwargs)


def test_threads_are_checked_for_a_single_run_too(paper_body):
    with pytest.raises(ValueError, match="`threads`"):
        dz.simulate(paper_body, (0, 0, 1), threads=0)


def test_a_batch_too_large_for_memory_is_refused_before_it_runs(paper_body):
    omega = np.zeros((100_000, 3))
    with pytest.raises(ValueError, match="sweep") as info:
        dz.simulate(paper_body, omega, t_end=1.0, frames=10**7, dt=1.0)
    assert "100000 runs × 10000000 frames" in str(info.value)


def test_one_warning_for_all_unphysical_bodies():
    # four rows: a square (3, 3) array is refused as ambiguous (a tensor or three bodies?)
    bodies = np.array([[1.0, 2.0, 2.5], [1.0, 1.0, 5.0], [1.0, 1.0, 6.0], [2.0, 2.0, 2.0]])
    with pytest.warns(dz.InertiaWarning, match="2 of 4 bodies") as caught:
        dz.simulate(bodies, (0.1, 0.1, 1.0), t_end=1.0)
    assert len(caught) == 1 and caught[0].filename == __file__


def test_step_warning_names_the_worst_row(paper_body):
    omega = np.array([[0.01, 0.01, 1.0], [0.0, 0.0, 1.0], [0.0, 40.0, 0.0]])
    with pytest.warns(dz.StepSizeWarning, match="row 2: step") as caught:
        dz.simulate(paper_body, omega, t_end=1000.0, dt=0.05, frames=2)
    assert caught[0].filename == __file__
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        dz.simulate(paper_body, omega[:2], t_end=100.0, frames=2)


def test_a_diverging_row_is_named(paper_body):
    omega = np.array([[0.01, 0.01, 1.0], [0.0, 1e3, 1e3]])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", dz.StepSizeWarning)
        with pytest.raises(ValueError, match="row 1: the run diverged"):
            dz.simulate(paper_body, omega, t_end=100.0, dt=0.5, frames=2)


@pytest.mark.parametrize("method", ["dopri5", "dop853"])
def test_adaptive_rows_with_dt_none_equal_single_runs_bit_for_bit(rng, method):
    # each row picks its own first step, as alone (every row took the smallest before)
    inertia, omega, q = random_rows(rng, 9)
    omega[::2] *= 40.0  # rates far apart: first steps far apart
    kwargs = dict(t_end=20.0, frames=11, method=method, dt=None)
    batch = dz.simulate(inertia, omega, q, **kwargs)
    for i in range(len(omega)):
        assert_same_run(batch[i], dz.simulate(inertia[i], omega[i], q[i], **kwargs))
    swept = dz.sweep(inertia, omega, q, progress=False, **kwargs)
    for i in range(len(omega)):
        one = dz.summarize(inertia[i], omega[i], q[i], **kwargs)
        assert swept.flips[i] == one.flips and swept.n_steps[i] == one.n_steps
        assert swept.dt[i] == one.dt


def test_a_large_batch_without_a_bar_is_one_call_to_the_core(rng, capsys, monkeypatch):
    # progress=None off a terminal (pytest captures stderr): tqdm shows no bar, so the batch
    # is not cut into blocks for one
    from dzhanibekov import ensemble

    calls = []
    core = ensemble._core.simulate_batch

    def counted(*args, **kwargs):
        calls.append(len(args[1]))
        return core(*args, **kwargs)

    monkeypatch.setattr(ensemble._core, "simulate_batch", counted)
    inertia, omega, q = random_rows(rng, 2 * 1024 + 37)
    dz.simulate(inertia, omega, q, t_end=2.0, frames=3, dt=1e-2)
    assert calls == [2 * 1024 + 37]
    assert capsys.readouterr().err == ""


def test_a_large_batch_shows_its_progress_and_keeps_its_bits(rng, capsys):
    inertia, omega, q = random_rows(rng, 2 * 1024 + 37)  # three blocks, the last a part
    kwargs = dict(t_end=2.0, frames=3, dt=1e-2)
    shown = dz.simulate(inertia, omega, q, progress=True, **kwargs)
    assert "batch" in capsys.readouterr().err
    whole = dz.simulate(inertia, omega, q, progress=False, **kwargs)
    assert capsys.readouterr().err == ""
    for name in ("omega", "q", "dt", "n_steps", "nfev"):
        assert np.array_equal(getattr(shown, name), getattr(whole, name)), name
    for a, b in zip(shown.drift, whole.drift):
        assert np.array_equal(a, b)
    for i in (0, 1023, 1024, 2084):
        assert np.array_equal(shown[i].flip_times, whole[i].flip_times)
    with pytest.raises(TypeError, match="`progress` must be True, False or None"):
        dz.simulate(inertia[:2], omega[:2], progress="yes")


def test_a_long_single_run_reports_its_progress_from_the_core(capsys, monkeypatch):
    # Issue 33: a single run showed nothing, however long. Off a terminal (pytest captures
    # stderr) a line says how far it got, every LINE_EVERY seconds (here every report)
    import dzhanibekov._progress as progress

    shares = []
    monkeypatch.setattr(progress, "LINE_EVERY", 0.0)
    monkeypatch.setattr(progress.RunProgress, "__call__",
                        lambda self, share, call=progress.RunProgress.__call__:
                        (shares.append(share), call(self, share))[1])
    run = dict(t_end=400.0, dt=2e-5, flips=False)  # 2·10⁷ RK4 steps, about 0.5 s
    shown = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), progress=None, **run)
    lines = capsys.readouterr().err.splitlines()
    assert any(line.startswith("dzhanibekov: run at t = ") for line in lines), lines
    # the core reports the share of the span reached, growing, below 1 until the end
    assert len(shares) > 2 and shares == sorted(shares) and 0 < shares[0] < 1, shares
    # the run is the same, bit for bit, and --no-progress's default silences it
    with progress.progress_default(False):
        quiet = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), **run)
    assert capsys.readouterr().err == ""
    np.testing.assert_array_equal(shown.q, quiet.q)


def _systems_with_parts():
    body = dz.Body((1.0, 2.0, 3.0))
    return {
        "damper": dz.System(dz.Body((1.0, 10.0, 10.0)), parts=[dz.Damper(0.05, 0.02)]),
        "wheel and gravity gradient": dz.System(
            body, parts=[dz.Wheel((0.0, 0.0, 1.0), 0.5)], torques=[dz.GravityGradient(0.1)]),
        "Python torque": dz.System(body, torques=[dz.CallableTorque(
            lambda t, q, w: np.array([0.0, 0.01 * np.sin(t), 0.0]))]),
        "deployment": dz.System(dz.Deployment([0.0, 5.0], [(1.0, 2.0, 3.0), (1.5, 2.5, 3.0)])),
    }


@pytest.mark.parametrize("name", list(_systems_with_parts()))
def test_a_single_run_of_a_system_is_its_batch_row_in_every_field(name):
    # the single run goes through its own call into the core (planned and run on one model);
    # a batch of one row of the same inputs through the batch's: every field the same bits
    system = _systems_with_parts()[name]
    kwargs = dict(t_end=10.0, frames=11, dt=1e-2)
    one = dz.simulate(system, (0.3, 0.02, 1.0), **kwargs)
    row = dz.simulate([system], [(0.3, 0.02, 1.0)], **kwargs)[0]
    assert_same_run(row, one)
    assert row.parts.keys() == one.parts.keys()
    for part in one.parts:
        assert np.array_equal(row.parts[part], one.parts[part]), part
    assert (row._flat_time is None) == (one._flat_time is None)
    if one._flat_time is not None:
        assert np.array_equal(row._flat_time, one._flat_time)
    summary = dz.summarize(system, (0.3, 0.02, 1.0), **kwargs)
    assert np.array_equal(summary.flip_times, one.flip_times) and summary.drift == one.drift
    assert (summary.dt, summary.n_steps, summary.nfev) == (one.dt, one.n_steps, one.nfev)


def test_a_single_runs_warnings_come_before_it_runs_and_point_at_the_caller(paper_body):
    # the core calls back with the plan before the run: a run refused as an error by the
    # warning filter never starts, and the warning names the caller's line
    with pytest.warns(dz.StepSizeWarning, match="step") as caught:
        dz.simulate(paper_body, (0.0, 40.0, 0.0), t_end=1000.0, dt=0.05, frames=2)
    assert caught[0].filename == __file__
    with pytest.warns(dz.StepSizeWarning) as caught:
        dz.summarize(paper_body, (0.0, 40.0, 0.0), t_end=1000.0, dt=0.05, frames=2)
    assert caught[0].filename == __file__
    progressed = []
    with warnings.catch_warnings():
        warnings.simplefilter("error", dz.StepSizeWarning)
        with pytest.raises(dz.StepSizeWarning):
            dz.simulate(dz.System(paper_body, torques=[dz.CallableTorque(
                lambda t, q, w: progressed.append(t) or np.zeros(3))]),
                (0.0, 40.0, 0.0), t_end=1000.0, dt=0.05, frames=2)
    assert progressed == []
