"""What a study takes and gives back (hardening round 4): every seed it accepts round-trips
through a file with the same samples, what is not a documented seed is refused, and an `ask`
whose answer the study cannot hold is refused naming the sample."""

from __future__ import annotations

import copy
import os
import signal
import sys
from pathlib import Path

import numpy as np
import pytest

import dzhanibekov as dz

pytest.importorskip("h5py")

SPIN = (0.01, 0.01, 1.0)


def spin(rng: np.random.Generator) -> tuple[float, float, float]:
    return (0.01 + 0.01 * rng.uniform(), 0.01, 1.0)


SEEDS = {
    "int": 7,
    "big int": 2**100,
    "list": [1, 2],  # the documented "sequence of int": dz.load refused its file
    "tuple": (3,),
    "range": range(3),
    "array": np.array([4, 5], dtype=np.uint32),
    "SeedSequence": np.random.SeedSequence([1, 2]),
    "spawned": np.random.SeedSequence(7, spawn_key=(3, 4)),
}


@pytest.mark.parametrize("name", sorted(SEEDS))
def test_every_accepted_seed_round_trips_through_a_file(name: str, tmp_path: Path) -> None:
    seed = SEEDS[name]
    study = dz.monte_carlo((1.0, 2.0, 3.0), spin, 3, seed=seed, t_end=5.0)
    dz.save(study, tmp_path / "study.nc")
    loaded = dz.load(tmp_path / "study.nc")
    assert isinstance(loaded, dz.MonteCarlo)
    # the same generators, for the samples run and beyond: the reference is NumPy's own
    # spawn of the seed as given
    def root() -> np.random.SeedSequence:  # a fresh one: `spawn` counts its children
        return copy.deepcopy(seed) if isinstance(seed, np.random.SeedSequence) \
            else np.random.SeedSequence(seed)

    for k in (0, 2, 10):
        expected = np.random.default_rng(root().spawn(k + 1)[k]).random(4)
        assert np.array_equal(loaded.rng(k).random(4), expected), k
        assert np.array_equal(study.rng(k).random(4), expected), k
    assert np.array_equal(loaded.outcomes, study.outcomes)


@pytest.mark.parametrize("seed, why", [
    ("123", "str"),  # was read as the digits (1, 2, 3)
    (b"ab", "bytes"),  # was read as the codes (97, 98)
    ({1: 2}, "dict"),  # was read as its keys
    ({1, 2}, "set"),
    ([1.5], "float"),  # was truncated to 1
    ([True], "bool"),
    (1.0, "float"),
    (np.array([[1, 2]]), "shape"),
])
def test_what_is_not_a_documented_seed_is_refused(seed, why) -> None:
    with pytest.raises(TypeError, match=rf"`seed` must be a non-negative integer.*{why}"):
        dz.monte_carlo((1.0, 2.0, 3.0), SPIN, 2, seed=seed, t_end=5.0)
    with pytest.raises(ValueError, match="`seed` must"):
        dz.monte_carlo((1.0, 2.0, 3.0), SPIN, 2, seed=[1, -1], t_end=5.0)


def _ask_on(bad_sample: int, value):
    """An `ask` answering 1.0, and `value` for the sample whose rates start at that index's
    draw (samples are told apart by their ω_x)."""
    marks = {}

    def ask(traj):
        return value if traj.omega[0, 0] == marks["bad"] else 1.0

    rng = np.random.default_rng(np.random.SeedSequence(5).spawn(bad_sample + 1)[bad_sample])
    marks["bad"] = 0.01 + 0.01 * rng.uniform()
    return ask


@pytest.mark.parametrize("value, words", [
    (float("nan"), "finite number, got nan"),
    (float("inf"), "finite number, got inf"),
    (-np.inf, "finite number, got -inf"),
    (2**70, "float64 holds, got the integer 1180591620717411303424"),
    ("1", "real number, got str"),
    (1 + 2j, "real number, got complex"),
])
def test_an_answer_the_study_cannot_hold_is_refused_naming_the_sample(value, words) -> None:
    """NaN and infinity made the study's mean NaN or infinite, and saved and loaded without
    complaint; 2**70 was rounded."""
    for chunk in (3, 100):
        with pytest.raises(dz.StudyError, match=rf"^sample 4: `ask` must return .*{words}") as e:
            dz.monte_carlo((1.0, 2.0, 3.0), spin, 8, seed=5, t_end=5.0,
                           ask=_ask_on(4, value), chunk=chunk)
        assert e.value.sample == 4
        assert np.array_equal(e.value.samples, np.arange(4))  # the samples before it kept
        assert np.array_equal(e.value.outcomes, np.ones(4))


def test_an_ask_of_bools_and_numbers_is_refused_at_the_first_of_the_other_kind() -> None:
    """Bools in one sample and numbers in another were averaged as numbers (True as 1);
    across chunks too."""
    def ask(traj):
        return True if traj.omega[0, 0] < 0.015 else 3

    xs = [0.01 + 0.01 * np.random.default_rng(c).uniform()
          for c in np.random.SeedSequence(9).spawn(12)]
    other = next(k for k, x in enumerate(xs) if (x < 0.015) != (xs[0] < 0.015))
    for chunk in (1, 5, 100):
        with pytest.raises(dz.StudyError, match=rf"^sample {other}: `ask` must return one kind"):
            dz.monte_carlo((1.0, 2.0, 3.0), spin, 12, seed=9, t_end=5.0, ask=ask, chunk=chunk)


def _killer_of(sample: int, seed: int):
    """An `ask` that kills the process it runs in when it meets `sample` (its ω_x), on every
    try."""
    rng = np.random.default_rng(np.random.SeedSequence(seed).spawn(sample + 1)[sample])
    bad = 0.01 + 0.01 * rng.uniform()

    def ask(traj):
        if traj.omega[0, 0] == bad:
            os.kill(os.getpid(), signal.SIGKILL)
        return 1.0

    return ask


@pytest.mark.skipif(sys.platform == "win32", reason="SIGKILL")
def test_a_dask_worker_killed_on_every_try_is_a_study_error_naming_the_chunk() -> None:
    """The worker running sample 30 dies each time (Dask tries a task on 4 workers, then
    gives up: KilledWorker). The study raised a raw FutureCancelledError ("already
    forgotten": the scattered spec died with the worker, and every chunk that needed it was
    cancelled). Now: a StudyError naming the chunk, with the samples of the chunks before it.
    (One task a worker at a time, so that only the killer's chunk is on a worker that dies.)"""
    distributed = pytest.importorskip("distributed")
    import dask

    with dask.config.set({"distributed.scheduler.worker-saturation": 1.0,
                          "distributed.scheduler.allowed-failures": 1}):
        cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1,
                                           host="127.0.0.1", dashboard_address=None,
                                           processes=True)
        with cluster, distributed.Client(cluster) as client:
            with pytest.raises(dz.StudyError, match=r"^sample 30: the Dask task of the chunk "
                                                    r"of samples 30–39 failed \(KilledWorker") as e:
                dz.monte_carlo((1.0, 2.0, 3.0), spin, 60, seed=5, t_end=5.0,
                               ask=_killer_of(30, 5), chunk=10, client=client)
    assert e.value.sample == 30
    assert np.array_equal(e.value.samples, np.arange(30))
    assert np.array_equal(e.value.outcomes, np.ones(30))
    assert e.value.study is not None and e.value.study.runs == 30


def test_a_deployment_with_a_knot_no_body_has_stops_the_study_at_its_sample() -> None:
    """A chunk's deployments are checked at once (one at a time made a study of deployments
    1.7 times slower than the sweep of the same deployments): the first knot no body has still
    names its sample and knot, and the samples before it are kept."""
    good = [(1.0, 2.0, 3.0), (1.0, 3.0, 2.0)]
    bad = [(1.0, 2.0, 3.0), (1.0, 1.0, 3.0)]  # 3 > 1 + 1: the triangle inequality breaks

    def deploy(rng: np.random.Generator) -> dz.Deployment:
        u = rng.uniform()
        return dz.Deployment([1.0, 2.0], bad if 0.4 < u < 0.45 else good)

    us = [np.random.default_rng(c).uniform() for c in np.random.SeedSequence(3).spawn(60)]
    first = next(k for k, u in enumerate(us) if 0.4 < u < 0.45)
    for chunk in (7, 100):
        with pytest.raises(dz.StudyError, match=rf"^sample {first}: `system` failed: "
                                                r"ValueError: knot 1: `system` gave moments "
                                                r"no body has") as e:
            dz.monte_carlo(deploy, SPIN, 60, seed=3, t_end=5.0, method="rk4", dt=0.01,
                           chunk=chunk)
        assert np.array_equal(e.value.samples, np.arange(first))
    # and what a study records of a deployment: the deployed body's moments and axes
    study = dz.monte_carlo(lambda rng: dz.Deployment([1.0, 2.0], good), SPIN, 3, seed=3,
                           t_end=5.0, method="rk4", dt=0.01)
    assert np.allclose(study.inputs["inertia"], [1.0, 2.0, 3.0])
    assert np.allclose(np.abs(study.inputs["axes"][0]), [[1, 0, 0], [0, 0, 1], [0, 1, 0]])
    assert np.all(np.linalg.det(study.inputs["axes"]) > 0)
