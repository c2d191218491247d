"""Files written by earlier versions keep loading (issue 29): tests/data/legacy holds results
saved by dzhanibekov at main 3f80f7e, whose parts were written kind by kind (one damper,
wheels with their positions among the parts, a torque table), before parts were written by
their model. Each loads as the system that version saved (make_legacy.py beside them builds
the same systems), with what it derives from that system agreeing with what the file says."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

import dzhanibekov as dz

pytest.importorskip("h5py")
LEGACY = Path(__file__).resolve().parents[2] / "data" / "legacy"
_spec = importlib.util.spec_from_file_location("make_legacy", LEGACY / "make_legacy.py")
assert _spec is not None and _spec.loader is not None
made = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(made)


@pytest.mark.parametrize("name, system", [
    ("orbiter.nc", made.ORBITER), ("tabled.nc", made.TABLED), ("damped.nc", made.DAMPED)])
def test_a_run_saved_in_the_old_layout_loads_as_its_system(name, system):
    traj = dz.load(LEGACY / name)
    assert isinstance(traj, dz.Trajectory)
    assert traj.system == system                    # parts and torques in their order
    assert [type(p) for p in traj.system.parts] == [type(p) for p in system.parts]
    # and it runs again to the same frames (same method, same step), to round-off: the
    # damper's right-hand side was since written out as its own kernel (issue 30), which
    # orders the same arithmetic differently (last-bit differences, 1e-16 here)
    again = dz.simulate(system, traj.omega[0], traj.q[0], t_end=float(traj.t[-1]),
                        frames=len(traj.t), method=traj.method, dt=traj.dt)
    np.testing.assert_allclose(again.q, traj.q, rtol=0, atol=1e-14)


def test_a_batch_saved_in_the_old_layout_loads_each_run_with_its_system(tmp_path):
    batch = dz.load(LEGACY / "rows.nc")
    assert isinstance(batch, dz.Batch) and list(batch.systems) == made.ROWS
    # saved again, it is written in today's layout and loads as the same systems
    pytest.importorskip("h5netcdf")
    back = dz.load(dz.save(batch, tmp_path / "rows.nc"))
    assert list(back.systems) == made.ROWS and "part_kind" in back.to_xarray()
    np.testing.assert_array_equal(back.q, batch.q)


def test_the_old_layout_refuses_a_damper_without_its_parameters(tmp_path):
    xr = pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    ds = xr.load_dataset(LEGACY / "damped.nc").drop_vars("damper_damping")
    ds.to_netcdf(tmp_path / "bad.nc", engine="h5netcdf")
    with pytest.raises(dz.ReadError, match=r"`damper_inertia`, `damper_damping` and "
                                           r"`damper_sigma0` must be there exactly"):
        dz.load(tmp_path / "bad.nc")


def test_a_file_mixing_the_two_layouts_is_refused(tmp_path):
    xr = pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    ds = xr.load_dataset(LEGACY / "damped.nc")
    ds["part_kind"] = ("part", np.array(["damper"]))
    ds.to_netcdf(tmp_path / "bad.nc", engine="h5netcdf")
    with pytest.raises(dz.ReadError, match=r"`damper_inertia` \(the layout of files before"):
        dz.load(tmp_path / "bad.nc")
