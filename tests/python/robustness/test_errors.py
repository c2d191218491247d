"""The error hierarchy and results that travel: every result type and every exception
survives pickle and deepcopy (multiprocessing, joblib, Dask need it), rows and arrays intact;
a batch or sweep names the failing row in `.row`, not only in its message."""

import copy
import dataclasses
import pickle
import warnings

import numpy as np
import pytest

import dzhanibekov as dz

PAPER = dz.Body(dz.PAPER_INERTIA)


def test_the_hierarchy_keeps_existing_except_clauses():
    assert issubclass(dz.DzhanibekovError, ValueError)
    assert issubclass(dz.DivergedError, dz.DzhanibekovError)
    assert issubclass(dz.TooLargeError, dz.DzhanibekovError)
    assert issubclass(dz.TooLargeError, MemoryError)


def test_a_diverging_batch_row_raises_diverged_error_with_its_row():
    omega = np.tile([0.01, 0.01, 1.0], (6, 1))
    omega[4] = [0.0, 3.0, 20.0]  # dt·Ω = 20 · 0.5: far past RK4's stability limit
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", dz.StepSizeWarning)
        with pytest.raises(dz.DivergedError) as caught:
            dz.simulate(PAPER, omega, t_end=50.0, frames=3, dt=0.5)
    assert caught.value.row == 4
    assert str(caught.value).startswith("row 4: the run diverged")


def test_a_diverging_sweep_row_is_named_by_its_row_across_blocks():
    # a sweep keeps going past a run that diverged (issue 11): the row's status says so
    omega = np.tile([0.01, 0.01, 1.0], (10, 1))
    omega[7] = [0.0, 1e3, 1.0]  # dt·Ω = 500
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", dz.StepSizeWarning)
        s = dz.sweep(PAPER, omega, t_end=100.0, dt=0.5, block=3, progress=False)
    assert [i for i, st in enumerate(s.status) if st != "ok"] == [7]
    assert s.status[7] == "diverged" and np.isnan(s.period[7]) and s.flips[7] == -1


def test_a_single_run_error_has_no_row():
    with pytest.raises(dz.DivergedError) as caught:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", dz.StepSizeWarning)
            dz.simulate(PAPER, (0.0, 3.0, 20.0), t_end=50.0, frames=3, dt=0.5)
    assert caught.value.row is None


def test_too_large_requests_raise_too_large_error():
    with pytest.raises(dz.TooLargeError) as caught:
        dz.simulate(PAPER, (0.01, 0.01, 1.0), t_end=1e6, dt=1e-6, max_steps=10**6)
    assert caught.value.row is None and "max_steps" in str(caught.value)


def _round_trips(value):
    return pickle.loads(pickle.dumps(value)), copy.deepcopy(value)


@pytest.mark.parametrize("error", [
    dz.DzhanibekovError("bad"),
    dz.DivergedError("the run diverged", 3),
    dz.TooLargeError("too many steps", 5, (1, 2)),
    dz.SceneError("scene.toml", "run.t_end", "must be positive"),
])
def test_exceptions_pickle_and_copy_with_their_row(error):
    for back in _round_trips(error):
        assert type(back) is type(error) and str(back) == str(error)
        assert getattr(back, "row", None) == getattr(error, "row", None)


def _assert_same(a, b):
    """Field by field: arrays equal, everything else equal or recursively the same."""
    assert type(a) is type(b)
    if isinstance(a, np.ndarray):
        np.testing.assert_array_equal(a, b)
    elif dataclasses.is_dataclass(a):
        for f in dataclasses.fields(a):
            _assert_same(getattr(a, f.name), getattr(b, f.name))
    elif isinstance(a, tuple):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            _assert_same(x, y)
    elif isinstance(a, dict):
        assert a.keys() == b.keys()
        for k in a:
            _assert_same(a[k], b[k])
    elif isinstance(a, float) and np.isnan(a):
        assert np.isnan(b)
    else:
        assert a == b


def _results():
    traj = dz.simulate(PAPER, (0.01, 0.01, 1.0), t_end=40.0, frames=11)
    traj.invariants  # filled lazily: travels filled too
    batch = dz.simulate(PAPER, [[0.01, 0.01, 1.0], [0.2, 0.0, 1.0]], t_end=40.0, frames=11)
    sweep = dz.sweep(PAPER, dz.grid([0.0, 0.1], 0.01, 1.0), t_end=40.0, progress=False)
    summary = dz.summarize(PAPER, (0.01, 0.01, 1.0), t_end=40.0)
    scene = dz.SCENES["fig3a"]
    result = dz.scenes.execute(dz.scenes.make_plan(dataclasses.replace(scene, t_end=20.0, frames=21)))
    deployments = [dz.Deployment([1.0, 2.0], [(1, 2, 3), (1, 3, r)]) for r in (2.0, 4.0)]
    model_batch = dz.simulate(deployments, (0.01, 0.01, 1.0), t_end=5.0, frames=6, dt=1e-2)
    model_batch.momentum_world  # the invariants travel with it
    damper_batch = dz.simulate(dz.System(PAPER, parts=[dz.Damper(1.0, 0.5)]),
                               [[0.01, 0.01, 1.0], [0.2, 0.0, 1.0]], t_end=5.0, frames=6,
                               dt=1e-2)
    deployment_sweep = dz.sweep(deployments, (0.01, 0.01, 1.0), t_end=2.0, frames=2, dt=1e-2)
    return {"Body": PAPER, "box": dz.Body.box(20, 10, 15), "Trajectory": traj, "Batch": batch,
            "Sweep": sweep, "Summary": summary, "Scene": scene, "SceneResult": result,
            "Batch of deployments": model_batch, "Batch of dampers": damper_batch,
            "DeploymentSweep": deployment_sweep}


def test_every_result_type_pickles_and_copies_with_equal_arrays():
    for name, value in _results().items():
        for back in _round_trips(value):
            _assert_same(value, back)
    traj = _results()["Trajectory"]
    back = pickle.loads(pickle.dumps(traj))
    assert back.body == traj.body and back.flip_times.tolist() == traj.flip_times.tolist()


def test_the_result_family_tells_flips_t_end_and_verdict_alike():
    omega = [[0.01, 0.01, 1.0], [1.0, 0.01, 0.01], [0.2, 0.01, 1.0], [0.01, 0.3, 1.0]]
    batch = dz.simulate(PAPER, omega, t_end=100.0, frames=11)
    sweep = dz.sweep(PAPER, omega, t_end=100.0, frames=11, progress=False)
    for i, w in enumerate(omega):
        traj = dz.simulate(PAPER, w, t_end=100.0, frames=11)
        summary = dz.summarize(PAPER, w, t_end=100.0, frames=11)
        assert traj.flips == len(traj.flip_times) == summary.flips == batch.flips[i] == sweep.flips[i]
        assert traj.t_end == summary.t_end == batch.t_end == sweep.t_end == 100.0
        assert traj.verdict == summary.verdict == batch.verdict[i] == sweep.verdict[i]
    assert batch.verdict[0] == "2 flips in [0, 100]" and batch.verdict[1] == "no flip in [0, 100]"


def test_slices_of_a_batch_and_indices_of_a_sweep_keep_their_runs():
    omega = np.random.default_rng(1).normal(size=(7, 3))
    batch = dz.simulate(PAPER, omega, t_end=30.0, frames=5)
    part = batch[2:7:2]
    assert isinstance(part, dz.Batch) and len(part) == 3
    for k, i in enumerate(range(2, 7, 2)):
        np.testing.assert_array_equal(part[k].omega, batch[i].omega)
        np.testing.assert_array_equal(part[k].flip_times, batch[i].flip_times)
        assert part[k].drift == batch[i].drift
    assert len(batch[5:2]) == 0
    grid = dz.sweep(PAPER, dz.grid([0.0, 0.1, 0.2], [0.01, 0.3], 1.0), t_end=30.0, progress=False)
    row = grid[1]
    assert row.shape == (2,) and row.flips.tolist() == grid.flips[1].tolist()
    np.testing.assert_array_equal(row.omega0, grid.omega0[1])
    assert grid[1, 0].shape == () and grid[1, 0].tilt == grid.tilt[1, 0]


def test_the_sharper_messages_of_round_4(tmp_path):
    """Issue 33: what a new user met."""
    traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=1.0, frames=3)
    # a run's file given as a scene says what it is, as the other readers do
    dz.save(traj, tmp_path / "sat.nc")
    with pytest.raises(dz.SceneError, match=r"it is an HDF5 file \(a netCDF-4 file, such as "
                                            r"dz.save writes: read it with dz.load\)"):
        dz.load_scene(tmp_path / "sat.nc")
    # a table's repr shows its times as numbers, not as NumPy's reprs
    table = dz.TabulatedTorque(np.array([1.0, 2.0]), [(0, 0, 0), (0, 0, 1)])
    assert repr(table).startswith("TabulatedTorque(times=[1.0 … 2.0], knots=2")
    # a torque function returning two numbers is told it returned two
    two = dz.System(dz.Body((1, 2, 3)), torques=[dz.CallableTorque(lambda t, q, w: (1.0, 2.0))])
    with pytest.raises(ValueError, match=r"must return three real numbers .*, "
                                         r"got tuple of shape \(2,\) at "):
        dz.simulate(two, (0.1, 0.2, 0.3), t_end=1.0, frames=3, dt=0.1)
    # an AEM file without its frame says which frame and why
    with pytest.raises(TypeError, match=r"write_aem\(\) needs `ref_frame_a`: the inertial frame "
                                        r"the run's world axes are \('EME2000', 'ICRF'"):
        dz.io.write_aem(traj, tmp_path / "x.aem", "SAT", "2000-001A", "2026-01-01T00:00:00")
