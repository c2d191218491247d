"""Files edited by hand or damaged (hardening round 4): `dz.load` refuses a study whose
fields are not what `dz.save` writes — each as a ReadError naming the field, where a plain
ValueError, a KeyError or a broadcast error came out of the study's build, or the file loaded
with another study than the one saved — and finds damage by each array's checksum."""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any, Callable

import numpy as np
import pytest

import dzhanibekov as dz

h5py = pytest.importorskip("h5py")


def spin(rng: np.random.Generator) -> tuple[float, float, float]:
    return (rng.normal(0, 0.05), rng.normal(0, 0.05), 1.0)


def speed(traj: Any) -> float:
    return float(np.abs(traj.omega).max())


@pytest.fixture(scope="module")
def saved(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("studies")
    studies = {
        "plain": dz.monte_carlo((1.0, 2.0, 2.05), spin, 40, seed=1, t_end=50.0),
        "rare": dz.monte_carlo((1.0, 2.0, 2.05), spin, 400, seed=1, t_end=50.0, runs=20),
        "numbers": dz.monte_carlo((1.0, 2.0, 2.05), spin, 10, seed=1, t_end=5.0, ask=speed),
    }
    paths = {}
    for name, study in studies.items():
        paths[name] = dz.save(study, folder / f"{name}.nc")
    return paths


def _attr(name: str, value: Any) -> Callable[[Any], None]:
    def edit(h: Any) -> None:
        h.attrs[name] = value
    return edit


def _drop(name: str) -> Callable[[Any], None]:
    def edit(h: Any) -> None:
        del h.attrs[name]
    return edit


def _values(name: str, change: Callable[[np.ndarray], np.ndarray]) -> Callable[[Any], None]:
    def edit(h: Any) -> None:
        h[name][...] = change(h[name][...])
    return edit


EDITS = {
    # (which study, the edit, the field the ReadError names)
    "level 5": ("plain", _attr("level", 5.0), "`level` must lie in (0, 1)"),  # ValueError
    "interval banana": ("plain", _attr("interval_method", "banana"), "`interval_method`"),
    "no draws_far": ("rare", _drop("draws_far"), "`draws_near` and `draws_far`"),  # KeyError
    "stratum 7": ("rare", _values("stratum", lambda a: np.full_like(a, 7)), "`stratum`"),
    "stratum swapped": ("rare", _values("stratum", lambda a: 1 - a), "`stratum`"),
    "kind banana": ("plain", _attr("kind", "banana"), "`kind`"),
    "n 2**62": ("plain", _attr("n", 2**62), "`n`"),
    "frames 0": ("plain", _attr("frames", 0), "`frames` must be at least 2"),
    "NaN outcome": ("numbers", _values("outcome", lambda a: np.where(a == a[3], np.nan, a)),
                    "`outcome` holds NaN"),
    "weights zeroed": ("plain", _values("weight", lambda a: 0 * a), "`weight`"),
    "estimate": ("plain", _attr("estimate", 0.99), "`estimate`"),
    "seed text": ("plain", _attr("seed_entropy", "[1, x]"), "`seed_entropy`"),
    "spawn key": ("plain", _attr("seed_spawn_key", "1,-2"), "`seed_spawn_key`"),
    "dt": ("plain", _attr("dt", -1.0), "`dt`"),
    "draws_near": ("rare", _attr("draws_near", 3), "`draws_near`"),
    "flips as float": ("plain", _attr("ask", "flips"), "`outcome_type`"),
}


@pytest.mark.parametrize("edit", sorted(EDITS))
def test_an_edited_study_is_a_read_error_naming_the_field(edit: str, saved: dict[str, Path],
                                                         tmp_path: Path) -> None:
    which, change, field = EDITS[edit]
    path = tmp_path / "edited.nc"
    shutil.copy(saved[which], path)
    assert isinstance(dz.load(path), dz.MonteCarlo)  # as saved, it loads
    with h5py.File(path, "r+") as h:
        change(h)
    with pytest.raises(dz.ReadError) as caught:
        dz.load(path)
    assert field in str(caught.value), caught.value
    assert str(path) in str(caught.value)


def test_damage_to_an_array_is_found_by_its_checksum(saved: dict[str, Path],
                                                    tmp_path: Path) -> None:
    """A flipped bit in a run's or a study's array loaded as another number; every numeric
    array now carries HDF5's Fletcher-32 checksum, and `load` names the one that fails."""
    traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=10.0, frames=11, dt=1e-2)
    for path, name in ((dz.save(traj, tmp_path / "run.nc"), "omega"),
                       (saved["numbers"], "outcome")):
        with h5py.File(path, "r") as h:
            assert h[name].fletcher32
            offset = h[name].id.get_chunk_info(0).byte_offset
        damaged = tmp_path / f"damaged-{path.name}"
        data = bytearray(path.read_bytes())
        data[offset + 5] ^= 0x10
        damaged.write_bytes(data)
        with pytest.raises(dz.ReadError, match=rf"`{name}` cannot be read .*damaged"):
            dz.load(damaged)
