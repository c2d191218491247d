"""The sensors' seeds: a part's `seed` plus the run's row key its noise (Philox, counter-based),
so the rows of a batch draw different noise, row ``i`` draws as its single run seeded
``seed + i``, the same whatever the threads or blocks (issue 32)."""

from __future__ import annotations

import importlib
import math

import numpy as np
import pytest

import dzhanibekov as dz

simulate_module = importlib.import_module("dzhanibekov.simulate")   # not dz.simulate, the function

SIGMA = 2e-7
N = dz.circular_orbit_rate(500e3)
BODY = dz.Body((0.042, 0.042, 0.0067))
OMEGA0 = np.radians([3.0, -2.0, 4.0])


def listening(seed: int = 0) -> dz.System:
    """B-dot with no gain: its magnetometer samples the field once a second (with noise) and
    commands nothing, so every run moves alike and the measured fields differ by the noise."""
    bdot = dz.BDot(dz.MagneticField(N, 1.2), gain=0.0, period=1.0,
                   magnetometer=dz.Magnetometer(SIGMA), seed=seed)
    return dz.System(BODY, torques=[bdot])


def run(system: object, rows: int | None = None, **kw: object) -> dz.Trajectory | dz.Batch:
    omega0 = OMEGA0 if rows is None else np.tile(OMEGA0, (rows, 1))
    return dz.simulate(system, omega0, t_end=60.0, frames=121, method="rk4", dt=0.25,
                       **kw)  # type: ignore[arg-type]


def measured(parts: np.ndarray) -> np.ndarray:
    """The field measured at each sample (held in the state from it: the frames halfway
    through each hold), from a run's `bdot` state (..., frames, 7)."""
    return parts[..., 1::2, 3:6]


def test_the_rows_of_a_batch_draw_different_noise_of_the_same_law() -> None:
    rows = 8
    batch = run(listening(), rows)
    assert isinstance(batch, dz.Batch)
    # no gain: every row moves alike, bit for bit
    assert all(np.array_equal(batch.q[i], batch.q[0]) for i in range(rows))
    fields = measured(batch.parts["bdot"])                    # (rows, 60, 3)
    noise = fields - fields.mean(axis=0)
    assert np.abs(fields[1] - fields[0]).min() > 0.0          # every sample, every axis
    # pooled over the rows: the deviation asked for, rows uncorrelated with one another
    samples = noise.shape[1] * noise.shape[2]
    assert noise.std() * math.sqrt(rows / (rows - 1)) == pytest.approx(SIGMA, rel=0.1)
    z = noise.reshape(rows, -1) / SIGMA
    corr = np.corrcoef(z)[np.triu_indices(rows, 1)]
    assert np.abs(corr).max() < 5 / math.sqrt(samples)


def test_a_seed_reproduces_its_runs_bit_for_bit_and_another_seed_draws_anew() -> None:
    a, again, other = (run(listening(seed), 3) for seed in (7, 7, 8))
    assert np.array_equal(a.parts["bdot"], again.parts["bdot"])
    # seed 8's row 0 draws as seed 7's row 1 (seed + row), and nothing else of seed 7's
    assert np.array_equal(measured(other.parts["bdot"][0]), measured(a.parts["bdot"][1]))
    assert np.abs(measured(other.parts["bdot"][2]) - measured(a.parts["bdot"][2])).min() > 0


def test_a_batch_row_is_its_single_run_seeded_seed_plus_its_row() -> None:
    # with gain, so that the noise moves the body: rows differ in their motion too
    def detumbling(seed: int) -> dz.System:
        bdot = dz.BDot(dz.MagneticField(N, 1.2), gain=3e-5, period=1.0,
                       magnetometer=dz.Magnetometer(5e-7), seed=seed)
        return dz.System(BODY, torques=[bdot])

    batch = run(detumbling(40), 4)
    for i in (0, 3):
        single = run(detumbling(40 + i))
        assert np.array_equal(batch.parts["bdot"][i], single.parts["bdot"])
        assert np.array_equal(batch.omega[i], single.omega)
        assert np.array_equal(batch.q[i], single.q)
    assert not np.array_equal(batch.omega[0], batch.omega[3])


def test_the_noise_is_the_same_whatever_the_threads_or_blocks(
        monkeypatch: pytest.MonkeyPatch) -> None:
    rows = 5
    one = run(listening(3), rows, threads=1)
    two = run(listening(3), rows, threads=2)
    assert np.array_equal(one.parts["bdot"], two.parts["bdot"])
    # a batch shown with a progress bar runs in blocks of rows: row i is still row i
    monkeypatch.setattr(simulate_module, "PROGRESS_BLOCK", 2)
    blocks = run(listening(3), rows, progress=True)
    assert np.array_equal(one.parts["bdot"], blocks.parts["bdot"])


@pytest.mark.parametrize("seed, error", [
    (-1, ValueError), (2**53, ValueError), (0.5, TypeError), (True, TypeError),
    ("1", TypeError),
])
def test_a_seed_must_be_an_int_in_range(seed: object, error: type) -> None:
    field = dz.MagneticField(N, 1.2)
    for make in (lambda: dz.BDot(field, 1e-5, 1.0, seed=seed),  # type: ignore[arg-type]
                 lambda: dz.MomentumDumping(field, 1e-3, 1.0, seed=seed),  # type: ignore
                 lambda: dz.QuaternionFeedback(1.0, 1.0, 1.0, seed=seed),  # type: ignore
                 lambda: dz.Controller(lambda *a: np.zeros(3), 1.0, seed=seed)):  # type: ignore
        with pytest.raises(error, match="`seed`"):
            make()


def test_the_seed_is_kept_compared_and_shown() -> None:
    field = dz.MagneticField(N, 1.2)
    a, b = dz.BDot(field, 1e-5, 1.0, seed=3), dz.BDot(field, 1e-5, 1.0, seed=4)
    assert a != b and a == dz.BDot(field, 1e-5, 1.0, seed=np.int64(3))
    assert a.seed == 3 and "seed=3" in repr(a)
    assert dz.BDot(field, 1e-5, 1.0).seed == 0
