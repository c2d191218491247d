"""Several stateful parts of one model in one system go through every result path (issues 29
and 31): the core shows the ``k``-th of several parts of a model as ``<model>_<k>`` (the part
on row ``k`` of the parameters' ``part_<model>``), and xarray, data frames and files write and
read each part's state under that name, for every model with state of ``dz.MODELS`` (not a
hand list), one instance and two; with the systems users build of them (Explorer 1's four whip
antennas, a hinge beside a slosh tank). The loaded run keeps what its physics keeps."""

from __future__ import annotations

import numpy as np
import pytest

import dzhanibekov as dz
from dzhanibekov import _tables
from dzhanibekov.parts import _columns, example, from_fields, params_of

pytest.importorskip("xarray")
pytest.importorskip("h5netcdf")

BOX = dz.Body.box(1.0, 2.0, 3.0, mass=2.0)
START = (0.3, 0.2, 1.0), (1.0, 0.0, 0.0, 0.0)
STATEFUL = [n for n, m in dz.MODELS.items() if m.state and not m.law]
RUN = dict(t_end=0.2, frames=5, method="rk4", dt=1e-2)


def second(part: dz.Part) -> dz.Part:
    """Another part of `part`'s model: its scalars 10% larger (so rows cannot be swapped
    unseen)."""
    kinds = {p.name: p.kind for p in params_of(part.model)}
    return from_fields(part.model, {k: v * 1.1 if kinds[k] == "scalar" and v is not None
                                    else v for k, v in part.fields().items()})


def system_of(name: str, count: int) -> dz.System:
    parts = [example(name)]
    if count == 2:
        parts.append(second(parts[0]))
    where = "torques" if parts[0].external else "parts"
    try:
        return dz.System(BOX, **{where: parts})
    except ValueError as exc:   # the core's bound on a system's state: said so, by name
        assert "numbers of state" in str(exc)
        pytest.skip(f"the core holds no {count} {name} parts in one system: {exc}")


def test_the_list_is_every_model_with_state():
    assert {"damper", "hinge", "spring_mass", "slosh"} <= set(STATEFUL)
    assert all(dz.MODELS[n].state for n in STATEFUL)


@pytest.mark.parametrize("count", [1, 2])
@pytest.mark.parametrize("name", STATEFUL)
def test_each_part_s_state_goes_to_xarray_and_a_frame_under_its_name(name, count):
    system = system_of(name, count)
    traj = dz.simulate(system, *START, **RUN)
    # the names the files expect are the core's own
    assert _tables.state_names([name] * count) == list(system.part_names)
    assert list(traj.parts) == ([name] if count == 1 else [f"{name}_0", f"{name}_1"])
    ds = traj.to_xarray()
    assert list(ds.attrs["parts"]) == list(traj.parts)
    for shown, state in traj.parts.items():
        at = 0
        for var, _, width, _ in _tables.state_fields(shown):
            values = ds[var].values
            block = state[:, at:at + width]
            np.testing.assert_array_equal(values if width > 1 else values[:, None], block)
            at += width
        assert at == state.shape[1]
    # its parameters' row k is the part shown as <model>_k
    if count == 2 and _columns.storable_models().count(name):
        scalar = next(p.name for p in params_of(name) if p.kind == "scalar")
        column = ds[_columns.column_name(name, scalar)].values
        assert column[1] == pytest.approx(1.1 * column[0]) and column[0] != column[1]
    frame = traj.to_dataframe()
    width = sum(s.shape[1] for s in traj.parts.values())
    rates = sum(r.shape[1] for r in traj.part_rates.values())  # a moving part's coordinates'
    assert frame.shape == (len(traj.t), 7 + width + rates + 4)


@pytest.mark.parametrize("count", [1, 2])
@pytest.mark.parametrize("name", STATEFUL)
def test_a_run_of_one_or_two_parts_of_each_model_round_trips(name, count, tmp_path):
    system = system_of(name, count)
    if _tables.unstorable(system):
        pytest.skip(f"a file cannot hold a {name} (a parameter is code)")
    traj = dz.simulate(system, *START, **RUN)
    back = dz.load(dz.save(traj, tmp_path / "run.nc"))
    assert back.system == traj.system and back.system == system
    assert [p.model for p in back.system.parts + back.system.torques] == [name] * count
    np.testing.assert_array_equal(back.q, traj.q)
    np.testing.assert_array_equal(back.omega, traj.omega)
    assert list(back.parts) == list(traj.parts)
    for shown in traj.parts:
        np.testing.assert_array_equal(back.parts[shown], traj.parts[shown])
    # a batch of two runs of it
    batch = dz.simulate([system, system], START[0], **RUN)
    again = dz.load(dz.save(batch, tmp_path / "batch.nc"))
    assert list(again.systems) == [system, system]
    assert list(again.parts) == list(batch.parts)
    for shown in batch.parts:
        np.testing.assert_array_equal(again.parts[shown], batch.parts[shown])


def whip(k: int) -> dz.Hinge:
    """Explorer 1's `k`-th whip antenna, as a rod hinged at the rim of the body's middle,
    pointing out radially (y, z, −y, −z) and flapping about the body's long axis x's normal
    tangent (a turnstile of four, 90° apart)."""
    angle = k * np.pi / 2
    radial = np.array([0.0, np.cos(angle), np.sin(angle)])
    tangent = np.array([0.0, -np.sin(angle), np.cos(angle)])
    return dz.Hinge(0.02, (1e-6, 2e-3, 2e-3), 0.08 * radial, tangent, radial, 0.3, 0.05,
                    0.002, angle0=0.01 * (k + 1))


EXPLORER = dz.System(dz.Body.cylinder(0.08, 2.0, mass=14.0), parts=[whip(k) for k in range(4)])
TANKED = dz.System(BOX, parts=[example("hinge"),
                               dz.Slosh(0.1, (0.0, 0.0, 0.2), 0.1, 0.01, (1.0, 0.0, 0.0))])
MIXED = dz.System(BOX, parts=[dz.Damper(0.05, 0.02), example("spring_mass"),
                              dz.Damper(0.03, 0.01), second(example("spring_mass"))])


DAMPERS = dz.System(dz.Body((1.0, 10.0, 10.0)),
                    parts=[dz.Damper(0.05, 0.02), dz.Damper(0.03, 0.05, (0.1, 0.0, 0.0))])
SEVERAL = {"explorer-whips": (EXPLORER, ["hinge_0", "hinge_1", "hinge_2", "hinge_3"]),
           "hinge-and-slosh": (TANKED, ["hinge", "slosh"]),
           "dampers-and-springs": (MIXED, ["damper_0", "spring_mass_0", "damper_1",
                                           "spring_mass_1"]),
           "two-dampers": (DAMPERS, ["damper_0", "damper_1"])}
SPIN = (2.0, 0.01, 0.02)


def _loaded(system, tmp_path):
    traj = dz.simulate(system, SPIN, t_end=2.0, frames=41, method="rk4", dt=1e-3)
    return traj, dz.load(dz.save(traj, tmp_path / "run.nc"))


@pytest.mark.parametrize("key", list(SEVERAL))
def test_systems_of_several_sinks_round_trip(key, tmp_path):
    system, shown = SEVERAL[key]
    traj, back = _loaded(system, tmp_path)
    assert list(traj.parts) == shown and list(back.parts) == shown
    assert back.system == traj.system and back.system == system
    for name in shown:
        np.testing.assert_array_equal(back.parts[name], traj.parts[name])
    # the loaded run's frames are unit quaternions, and the run kept what it keeps: the
    # angular momentum in space and the energy balance (its own drift, to round-off)
    np.testing.assert_allclose(np.linalg.norm(back.q, axis=1), 1.0, rtol=0, atol=1e-12)
    assert back.drift.momentum_world < 1e-12 and back.drift.energy_balance < 1e-12
    # the hinge angles are each whip's own (their starts differ)
    if system is EXPLORER:
        starts = [back.parts[n][0, 0] for n in shown]
        assert starts == pytest.approx([0.01, 0.02, 0.03, 0.04], abs=1e-15)


@pytest.mark.parametrize("key", list(SEVERAL))
def test_a_loaded_run_s_frames_keep_the_angular_momentum_in_space(key, tmp_path):
    # what the loaded run's own (loaded) system derives of its frames: the angular momentum
    # fixed in space (no external torque), the energy falling (the sinks only dissipate)
    system, _ = SEVERAL[key]
    _, back = _loaded(system, tmp_path)
    L = back.momentum_world
    assert np.abs(L - L[0]).max() <= 1e-10 * np.linalg.norm(L[0])
    assert (np.diff(back.energy) <= 1e-12 * back.energy[0]).all()
    assert back.energy[-1] < back.energy[0]


def test_a_file_that_misses_one_part_s_state_is_refused(tmp_path):
    xr = pytest.importorskip("xarray")
    traj = dz.simulate(MIXED, *START, **RUN)
    ds = xr.load_dataset(dz.save(traj, tmp_path / "good.nc"))
    ds.drop_vars("damper_1").to_netcdf(tmp_path / "bad.nc", engine="h5netcdf")
    with pytest.raises(dz.ReadError, match=r"names the damper_1, but its state `damper_1` is "
                                           r"missing"):
        dz.load(tmp_path / "bad.nc")
    # a part named that the system does not hold
    ds["damper_2"] = ds["damper_1"]
    ds.attrs["parts"] = [*ds.attrs["parts"], "damper_2"]
    ds.to_netcdf(tmp_path / "more.nc", engine="h5netcdf")
    with pytest.raises(dz.ReadError, match=r"the parts with state of `part_kind` are shown as"):
        dz.load(tmp_path / "more.nc")


def test_part_state_reads_the_kth_of_several_parts_of_one_model_by_its_state_name():
    hinges = [dz.Hinge(0.2, (1e-4, 0.01, 0.01), (0.5, 0.0, 0.0), (0.0, 0.0, 1.0),
                       (1.0, 0.0, 0.0), 0.3, 2.0, 0.05, angle0=a) for a in (0.05, -0.1)]
    sat = dz.System(BOX, parts=hinges)
    traj = dz.simulate(sat, (0.0, 0.0, 0.5), t_end=0.5, frames=3, method="rk4", dt=1e-3)
    for k, start in enumerate((0.05, -0.1)):
        state = dz.part_state(traj, f"hinge_{k}")
        assert state["angle"][0, 0] == start          # each part's own start, by its place
        np.testing.assert_array_equal(state["angle"][:, 0], traj.parts[f"hinge_{k}"][:, 0])
