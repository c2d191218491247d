"""Sweeps on a Dask cluster (two local worker processes on 127.0.0.1): one task per block,
gathered in order, equal bit for bit to the sweep on this machine."""

import numpy as np
import pytest

import dzhanibekov as dz

distributed = pytest.importorskip("distributed")

FIELDS = ("flips", "first_flip", "period", "exact_period", "tilt", "dt", "n_steps", "nfev")


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, host="127.0.0.1",
                                       dashboard_address=None, processes=True)
    with cluster, distributed.Client(cluster) as client:
        yield client


def test_cluster_sweep_equals_the_local_sweep_bit_for_bit(client):
    rng = np.random.default_rng(7)
    starts = rng.normal(size=(15, 20, 3))
    bodies = np.stack([np.ones(20), rng.uniform(0.6, 1.4, 20), rng.uniform(0.6, 1.4, 20)], -1)
    local = dz.sweep(bodies, starts, t_end=25.0, frames=3, dt=5e-3)
    with distributed.get_task_stream(client) as tasks:
        remote = dz.sweep(bodies, starts, t_end=25.0, frames=3, dt=5e-3, block=64, client=client)
    assert remote.shape == local.shape == (15, 20)
    for name in FIELDS:
        assert np.array_equal(getattr(remote, name), getattr(local, name), equal_nan=True), name
    for a, b in zip(remote.drift, local.drift):
        assert np.array_equal(a, b)
    assert local.flips.sum() > 20
    # one task per block of 64 runs: 300 runs, 5 tasks
    blocks = [t for t in tasks.data if "run_block" in str(t["key"])]
    assert len(blocks) == 5, [t["key"] for t in tasks.data]


def test_a_diverging_run_on_the_cluster_is_recorded_and_the_sweep_goes_on(client):
    omega = np.array([[0.0, 0.1, 1.0]] * 5 + [[0.0, 1e3, 1.0]])
    kwargs = dict(t_end=100.0, dt=0.5, frames=2, block=2)
    with pytest.warns(dz.StepSizeWarning):
        remote = dz.sweep(dz.PAPER_INERTIA, omega, client=client, **kwargs)
    with pytest.warns(dz.StepSizeWarning):
        local = dz.sweep(dz.PAPER_INERTIA, omega, progress=False, **kwargs)
    assert remote.status.tolist() == ["ok"] * 5 + ["diverged"]
    assert np.array_equal(remote.status, local.status)
    assert np.array_equal(remote.flips, local.flips) and remote.flips[5] == -1
    assert np.array_equal(remote.tilt, local.tilt, equal_nan=True)

def test_a_study_on_the_cluster_draws_and_runs_the_same_samples(client):
    # the draws happen on the workers (a task per chunk): the same outcomes and inputs, bit
    # for bit, as on this machine, for a fixed-step method in SIMD lanes and the exact one
    disperse = dz.InertiaDispersion((1.0, 2.0, 2.05), moments=0.03, axes_deg=1.0)

    def spin(rng: np.random.Generator) -> np.ndarray:
        return np.array([rng.normal(0, 0.05), rng.normal(0, 0.05), 1.0])

    for kwargs in (dict(method="rk4", dt=0.02, t_end=60.0, ask="flips"),
                   dict(t_end=1e4, runs=40)):
        local = dz.monte_carlo(disperse, spin, 150, seed=17, chunk=64, **kwargs)
        remote = dz.monte_carlo(disperse, spin, 150, seed=17, chunk=23, client=client,
                                **kwargs)
        assert np.array_equal(local.samples, remote.samples)
        assert np.array_equal(local.outcomes, remote.outcomes)
        for name, values in local.inputs.items():
            assert np.array_equal(remote.inputs[name], values), name
    assert local.outcomes.any() and not local.outcomes.all()


def test_a_failing_sample_on_the_cluster_keeps_the_ones_before(client):
    def flaky(rng: np.random.Generator) -> tuple[float, float, float]:
        if rng.uniform() < 0.01:
            raise RuntimeError("no such body")
        return (1.0, 2.0, 3.0)

    bad = next(k for k, c in enumerate(np.random.SeedSequence(3).spawn(2000))
               if np.random.default_rng(c).uniform() < 0.01)
    with pytest.raises(dz.StudyError, match=f"sample {bad}: `system` failed: RuntimeError"):
        dz.monte_carlo(flaky, (0.01, 0.01, 1.0), 2000, seed=3, t_end=10.0, chunk=50,
                       client=client)
    try:
        dz.monte_carlo(flaky, (0.01, 0.01, 1.0), 2000, seed=3, t_end=10.0, chunk=50,
                       client=client)
    except dz.StudyError as error:
        assert np.array_equal(error.samples, np.arange(bad))
