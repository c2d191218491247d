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