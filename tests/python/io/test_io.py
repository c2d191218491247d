"""Results as xarray/pandas tables, netCDF files and CCSDS attitude messages.

The AEM files are read back by an independent reader: `ccsds-ndm-py` (a CCSDS NDM parser
with a Rust core, in the `test` extra) for version 2.0, and for version 1.0 a parser
written here from the keyword list of CCSDS 504.0-B-1 (its tables 4-2 and 4-3).
"""

import os
import sys
import tracemalloc

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import dzhanibekov as dz

pytest.importorskip("xarray", reason="the `io` extra (xarray) is not installed")
pytest.importorskip("h5netcdf", reason="the `io` extra (h5netcdf) is not installed")

OMEGA = (0.01, 0.01, 1.0)


@pytest.fixture(scope="module")
def traj() -> dz.Trajectory:
    return dz.simulate(dz.PAPER_INERTIA, OMEGA, q0=Rotation.from_rotvec([0.3, 0.2, -0.1]),
                       t_end=100.0, frames=51, dt=1e-2)


@pytest.fixture(scope="module")
def batch() -> dz.Batch:
    return dz.simulate(dz.PAPER_INERTIA, [OMEGA, (0.0, 1.0, 0.01), (1.0, 0.0, 0.0)],
                       t_end=100.0, frames=21, dt=1e-2)


@pytest.fixture(scope="module")
def sweep() -> dz.Sweep:
    return dz.sweep(dz.PAPER_INERTIA, dz.grid([0.0, 0.3, 0.9], [0.0, 0.5], 1.0),
                    t_end=100.0, dt=1e-2)


# -- xarray and pandas -------------------------------------------------------------------


def test_trajectory_dataset_dims_coords_and_attrs(traj):
    ds = traj.to_xarray()
    assert ds.omega.dims == ("time", "axis") and ds.q.dims == ("time", "quaternion")
    assert list(ds.axis.values) == ["x", "y", "z"]
    assert list(ds.quaternion.values) == ["Q", "U", "V", "W"]
    assert np.array_equal(ds.time.values, traj.t)
    assert np.array_equal(ds.q.sel(quaternion="V").values, traj.q[:, 2])
    assert np.array_equal(ds.omega.sel(axis="z").values, traj.omega[:, 2])
    assert np.array_equal(ds.flip_times.values, traj.flip_times)
    assert ds.attrs["method"] == "rk4" and ds.attrs["dt"] == traj.dt
    assert ds.attrs["drift_energy"] == traj.drift.energy
    assert list(ds.attrs["inertia"]) == list(traj.body.inertia)
    assert "scalar first" in ds.q.attrs["long_name"]
    assert "user's own consistent units" in ds.attrs["unit_system"]


def test_trajectory_dataframe(traj):
    df = traj.to_dataframe()
    assert list(df.columns) == ["u", "v", "w", "Q", "U", "V", "W", "energy", "L_x", "L_y", "L_z"]
    # one name for time, as in the dataset
    assert df.index.name == "time" and np.array_equal(df.index.values, traj.t)
    assert np.array_equal(df[["Q", "U", "V", "W"]].to_numpy(), traj.q)
    assert np.array_equal(df["energy"].to_numpy(), traj.energy)
    assert np.array_equal(df[["L_x", "L_y", "L_z"]].to_numpy(), traj.momentum_world)


def test_batch_dataset_has_run_and_time(batch):
    ds = batch.to_xarray()
    assert ds.q.dims == ("run", "time", "quaternion")
    assert dict(ds.sizes) == {"run": 3, "time": 21, "axis": 3, "quaternion": 4, "axis_": 3,
                              "flip": int(batch.flips.max())}
    assert np.array_equal(ds.q.values, batch.q)
    for i, times in enumerate(batch.flip_times):
        row = ds.flip_times.values[i]
        assert np.array_equal(row[: len(times)], times) and np.isnan(row[len(times):]).all()
    df = batch.to_dataframe()
    assert df.index.names == ["run", "time"] and len(df) == 3 * 21
    assert np.array_equal(df.loc[2][["u", "v", "w"]].to_numpy(), batch.omega[2])


def test_sweep_dataset_has_the_grid_axes_as_coordinates(sweep):
    ds = sweep.to_xarray()
    assert ds.flips.dims == ("u0", "v0")
    assert np.array_equal(ds.u0.values, [0.0, 0.3, 0.9])
    assert np.array_equal(ds.v0.values, [0.0, 0.5])
    # selecting by coordinate finds the run of that start
    assert ds.flips.sel(u0=0.3, v0=0.5).item() == sweep.flips[1, 1]
    assert np.array_equal(ds.omega0.sel(u0=0.9, v0=0.0).values, [0.9, 0.0, 1.0])
    df = sweep.to_dataframe()
    assert len(df) == 6 and np.array_equal(df["u0"].to_numpy(), sweep.omega0[..., 0].ravel())
    assert np.array_equal(df["tilt"].to_numpy(), sweep.tilt.ravel())


def test_sweep_of_inertia_ratios_names_its_axes():
    s = dz.sweep(dz.grid(1.0, [1.5, 1.7], [2.0, 2.2, 2.4]), (0.2, 0.2, 1.0), t_end=10.0)
    ds = s.to_xarray()
    assert ds.tilt.dims == ("Iy", "Iz") and np.array_equal(ds.Iz.values, [2.0, 2.2, 2.4])


def test_sweep_of_scattered_starts_is_indexed_by_run():
    starts = np.array([[0.1, 0.2, 1.0], [0.3, 0.1, 1.0], [0.2, 0.3, 1.0]])
    ds = dz.sweep(dz.PAPER_INERTIA, starts, t_end=10.0).to_xarray()
    assert ds.flips.dims == ("u0",)  # u0 alone varies along the one axis
    ds = dz.sweep(dz.PAPER_INERTIA, np.stack([starts, starts[::-1]]), t_end=10.0).to_xarray()
    assert ds.flips.dims == ("run_0", "run_1")


# -- netCDF --------------------------------------------------------------------------------


def _assert_same_arrays(a, b, names):
    for name in names:
        x, y = getattr(a, name), getattr(b, name)
        x, y = np.asarray(x), np.asarray(y)
        assert x.dtype == y.dtype and x.shape == y.shape, name
        assert x.tobytes() == y.tobytes(), f"{name} differs in its bits"


def test_save_load_trajectory_bit_for_bit(traj, tmp_path):
    path = dz.save(traj, tmp_path / "run.nc")
    back = dz.load(path)
    assert isinstance(back, dz.Trajectory)
    _assert_same_arrays(back, traj, ["t", "omega", "q", "flip_times"])
    assert back.drift == traj.drift and back.dt == traj.dt and back.method == traj.method
    assert (back.n_steps, back.nfev, back.n_rejected) == (traj.n_steps, traj.nfev,
                                                           traj.n_rejected)
    assert back.body.inertia == traj.body.inertia
    # an ordinary netCDF file: xarray alone opens it
    import xarray as xr

    with xr.open_dataset(path) as ds:
        assert ds.q.dims == ("time", "quaternion")


def test_save_load_without_flips_keeps_none(tmp_path):
    t = dz.simulate(dz.PAPER_INERTIA, OMEGA, t_end=10.0, frames=5, flips=False,
                    method="dop853")
    back = dz.load(dz.save(t, tmp_path / "r.nc"))
    assert back.flip_times is None and back.n_rejected == t.n_rejected


def test_save_load_batch_bit_for_bit(batch, tmp_path):
    back = dz.load(dz.save(batch, tmp_path / "b.nc"))
    assert isinstance(back, dz.Batch)
    _assert_same_arrays(back, batch, ["t", "omega", "q", "inertia", "dt", "n_steps", "nfev",
                                      "n_rejected", "flips"])
    for x, y in zip(back.flip_times, batch.flip_times):
        assert x.tobytes() == y.tobytes()
    for x, y in zip(back.drift, batch.drift):
        assert x.tobytes() == y.tobytes()
    assert back[1].q.tobytes() == batch[1].q.tobytes()


def test_save_load_sweep_bit_for_bit(sweep, tmp_path):
    back = dz.load(dz.save(sweep, tmp_path / "s.nc"))
    assert isinstance(back, dz.Sweep)
    _assert_same_arrays(back, sweep, ["inertia", "omega0", "q0", "flips", "first_flip",
                                      "period", "exact_period", "tilt", "dt", "n_steps",
                                      "nfev"])
    assert back.t_end == sweep.t_end and back.method == sweep.method
    assert np.isnan(back.period).any()  # NaN (fewer than two flips) survives as NaN


def test_save_refuses_other_objects(tmp_path):
    with pytest.raises(TypeError, match="`result` must be a Trajectory, Batch, Sweep, "
                                        "DeploymentSweep or MonteCarlo"):
        dz.save({"q": 1}, tmp_path / "x.nc")


def test_load_refuses_a_foreign_file(tmp_path):
    import xarray as xr

    path = tmp_path / "other.nc"
    xr.Dataset({"a": ("x", np.arange(3.0))}).to_netcdf(path, engine="h5netcdf")
    with pytest.raises(ValueError, match="not written by dzhanibekov.save"):
        dz.load(path)


@pytest.mark.parametrize("missing", ["xarray", "h5netcdf", "pandas"])
def test_a_missing_extra_is_named(missing, traj, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, missing, None)  # `import missing` now raises ImportError
    call = {"xarray": traj.to_xarray, "pandas": traj.to_dataframe,
            "h5netcdf": lambda: dz.save(traj, tmp_path / "x.nc")}[missing]
    with pytest.raises(ImportError, match=rf"needs {missing}.*pip install \"dzhanibekov\[io\]\""):
        call()


# -- CCSDS AEM -----------------------------------------------------------------------------


def test_aem_v2_read_by_an_independent_parser(traj, tmp_path):
    ccsds = pytest.importorskip("ccsds_ndm", reason="ccsds-ndm-py (the test extra)")
    if not hasattr(ccsds, "from_file"):
        pytest.skip("another package named ccsds_ndm is installed, not ccsds-ndm-py")
    path = dz.io.write_aem(traj, tmp_path / "box.aem", "BOX", "2026-001A",
                           "2026-01-01T00:00:00", ref_frame_a="EME2000",
                           center_name="EARTH")
    message = ccsds.from_file(str(path))
    segment = message.segments[0]
    meta = segment.metadata
    assert (meta.object_name, meta.object_id) == ("BOX", "2026-001A")
    assert (meta.ref_frame_a, meta.ref_frame_b) == ("EME2000", "SC_BODY_1")
    assert meta.attitude_type == "QUATERNION" and meta.time_system == "UTC"
    assert meta.start_time.startswith("2026-01-01T00:00:00")
    assert meta.stop_time.startswith("2026-01-01T00:01:40")  # t_end = 100 s
    states = np.asarray(segment.data.attitude_states_numpy)
    # version 2.0 fixes the order Q1 Q2 Q3 QC: the package's (U, V, W, Q)
    assert np.array_equal(states, traj.q[:, [1, 2, 3, 0]])
    assert len(segment.data.attitude_states_epochs) == len(traj.t)


def test_aem_v2_rates_read_by_an_independent_parser(traj, tmp_path):
    ccsds = pytest.importorskip("ccsds_ndm", reason="ccsds-ndm-py (the test extra)")
    if not hasattr(ccsds, "from_file"):
        pytest.skip("another package named ccsds_ndm is installed, not ccsds-ndm-py")
    path = dz.io.write_aem(traj, tmp_path / "r.aem", "BOX", "2026-001A",
                           "2026-01-01T00:00:00", ref_frame_a="EME2000", rates=True,
                           time_unit=2.0)
    segment = ccsds.from_file(str(path)).segments[0]
    assert segment.metadata.attitude_type == "QUATERNION/ANGVEL"
    assert segment.metadata.angvel_frame == "SC_BODY_1"
    states = np.asarray(segment.data.attitude_states_numpy)
    assert np.allclose(states[:, 4:], np.degrees(traj.omega) / 2.0, rtol=1e-15, atol=0)
    assert segment.metadata.stop_time.startswith("2026-01-01T00:03:20")  # 100 units of 2 s


def _parse_aem_v1(text: str) -> tuple[dict, dict, list[list[str]]]:
    """An AEM 1.0 reader from the standard's keyword lists (CCSDS 504.0-B-1, 4.2):
    header, then META_START … META_STOP of `KEY = value`, then DATA_START … DATA_STOP."""
    header_keys = {"CCSDS_AEM_VERS", "CREATION_DATE", "ORIGINATOR"}
    meta_keys = {"OBJECT_NAME", "OBJECT_ID", "CENTER_NAME", "REF_FRAME_A", "REF_FRAME_B",
                 "ATTITUDE_DIR", "TIME_SYSTEM", "START_TIME", "USEABLE_START_TIME",
                 "USEABLE_STOP_TIME", "STOP_TIME", "ATTITUDE_TYPE", "QUATERNION_TYPE",
                 "EULER_ROT_SEQ", "RATE_FRAME", "INTERPOLATION_METHOD",
                 "INTERPOLATION_DEGREE"}
    lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
    i_meta, i_meta_end = lines.index("META_START"), lines.index("META_STOP")
    i_data, i_data_end = lines.index("DATA_START"), lines.index("DATA_STOP")
    assert i_meta < i_meta_end < i_data < i_data_end == len(lines) - 1

    def pairs(block, allowed):
        out = {}
        for line in block:
            if line.startswith("COMMENT"):
                continue
            key, _, value = line.partition(" = ")
            assert key in allowed, f"keyword {key!r} is not in the standard's list"
            out[key] = value
        return out

    header = pairs(lines[:i_meta], header_keys)
    meta = pairs(lines[i_meta + 1 : i_meta_end], meta_keys)
    rows = [ln.split() for ln in lines[i_data + 1 : i_data_end]]
    return header, meta, rows


def test_aem_v1_states_order_and_direction(traj, tmp_path):
    path = dz.io.write_aem(traj, tmp_path / "v1.aem", "BOX", "2026-001A",
                           "2026-01-01T00:00:00", ref_frame_a="EME2000", version="1.0",
                           rates=True)
    header, meta, rows = _parse_aem_v1(path.read_text())
    assert header["CCSDS_AEM_VERS"] == "1.0"
    assert meta["ATTITUDE_DIR"] == "A2B" and meta["QUATERNION_TYPE"] == "FIRST"
    assert meta["ATTITUDE_TYPE"] == "QUATERNION/RATE" and meta["RATE_FRAME"] == "REF_FRAME_B"
    values = np.array([[float(x) for x in r[1:]] for r in rows])
    assert np.array_equal(values[:, :4], traj.q)
    # A2B with QC first: the transformation from A (world) to B (body) coordinates is
    # M(q)ᵀ; check it on the angular momentum, fixed in the world (textbook: L = I ω in body
    # axes must equal M(q)ᵀ L_world at every frame)
    l_body = traj.omega * np.array(traj.body.inertia)
    l_world = dz.rotate(traj.q[0], l_body[0])
    for q, lb in zip(values[:, :4], l_body):
        a_to_b = Rotation.from_quat(np.roll(q, -1)).as_matrix().T
        assert np.allclose(a_to_b @ l_world, lb, rtol=0, atol=1e-6 * np.linalg.norm(lb))


def test_read_aem_round_trip_both_versions(traj, tmp_path):
    for version in ("1.0", "2.0"):
        path = dz.io.write_aem(traj, tmp_path / f"{version}.aem", "BOX", "2026-001A",
                               "2026-01-01T00:00:00", ref_frame_a="EME2000", version=version,
                               rates=True, time_unit=0.5)
        got = dz.io.read_aem(path)
        assert np.array_equal(got.q, traj.q)
        assert np.allclose(got.omega, traj.omega / 0.5, rtol=1e-14, atol=0)
        assert np.allclose(got.t, traj.t * 0.5, atol=1e-6)
        assert got.metadata["OBJECT_NAME"] == "BOX"


def test_read_aem_turns_b2a_and_scalar_last_into_the_package_convention(tmp_path):
    r = Rotation.from_rotvec([0.2, -0.5, 0.7])  # world-from-body
    xyzw = r.as_quat()
    # the same attitude, written B2A (the inverse transformation) with QC last
    inverse = r.inv().as_quat()
    text = "\n".join([
        "CCSDS_AEM_VERS = 1.0", "CREATION_DATE = 2026-01-01T00:00:00", "ORIGINATOR = TEST",
        "META_START", "OBJECT_NAME = X", "OBJECT_ID = 2026-001A", "REF_FRAME_A = EME2000",
        "REF_FRAME_B = SC_BODY_1", "ATTITUDE_DIR = B2A", "TIME_SYSTEM = UTC",
        "START_TIME = 2026-001T00:00:00", "STOP_TIME = 2026-001T00:00:00",
        "ATTITUDE_TYPE = QUATERNION", "QUATERNION_TYPE = LAST", "META_STOP",
        "DATA_START", "2026-001T00:00:00 " + " ".join(repr(float(x)) for x in inverse),
        "DATA_STOP", ""])
    path = tmp_path / "b2a.aem"
    path.write_text(text)
    q = dz.io.read_aem(path).q[0]
    expected = np.roll(xyzw, 1)
    assert np.allclose(q * np.sign(q @ expected), expected, atol=1e-15)


def test_write_aem_refuses_bad_input(traj, tmp_path):
    with pytest.raises(TypeError, match="`traj` must be a Trajectory"):
        dz.io.write_aem("x", tmp_path / "a.aem", "B", "1", "2026-01-01T00:00:00",
                        ref_frame_a="ICRF")
    with pytest.raises(ValueError, match="`object_name` must be one printable line"):
        dz.io.write_aem(traj, tmp_path / "a.aem", "B\nMETA_STOP", "1", "2026-01-01T00:00:00",
                        ref_frame_a="ICRF")
    with pytest.raises(ValueError, match="`epoch` must be a time"):
        dz.io.write_aem(traj, tmp_path / "a.aem", "B", "1", "yesterday", ref_frame_a="ICRF")
    with pytest.raises(ValueError, match="`version` must be one of"):
        dz.io.write_aem(traj, tmp_path / "a.aem", "B", "1", "2026-01-01T00:00:00",
                        ref_frame_a="ICRF", version="3.0")


# -- systems in files (issue 20's content in the checked layout of issue 24) -----------------


def _damped(sigma0=(0.1, -0.2, 1.0)):
    body = dz.Body.from_tensor([[2.0, -0.3, 0.1], [-0.3, 3.0, 0.2], [0.1, 0.2, 4.0]], mass=2.0)
    return dz.System(body, parts=[dz.Damper(0.05, 0.02, sigma0=sigma0)])


def _assert_same_run(back, run, derived=("energy", "momentum_body", "momentum_world")):
    _assert_same_arrays(back, run, ["t", "omega", "q"])
    assert back.parts.keys() == run.parts.keys()
    for name in run.parts:
        assert back.parts[name].tobytes() == run.parts[name].tobytes(), name
    for name in derived:  # derived by the loaded system: the saved run's, bit for bit
        assert getattr(back, name).tobytes() == getattr(run, name).tobytes(), name


def test_save_load_a_damped_body_of_a_full_tensor(tmp_path):
    traj = dz.simulate(_damped(), (0.3, 0.2, 1.0), t_end=20.0, frames=21)
    back = dz.load(dz.save(traj, tmp_path / "damped.nc"))
    assert back.system == traj.system and back.system.part_names == ("damper",)
    assert back.body.tensor.tobytes() == traj.body.tensor.tobytes() and back.body.mass == 2.0
    assert back.system.parts[0].sigma0 == (0.1, -0.2, 1.0)
    _assert_same_run(back, traj)
    assert back.drift == traj.drift and back.drift.kept == traj.drift.kept
    co_rotating = dz.simulate(_damped(None), (0.3, 0.2, 1.0), t_end=5.0, frames=6)
    again = dz.load(dz.save(co_rotating, tmp_path / "co.nc"))
    assert again.system.parts[0].sigma0 is None and again.system == co_rotating.system


def test_save_load_deployments_and_a_batch_of_damped_systems(tmp_path):
    d = dz.Deployment([1.0, 2.0, 4.0], [(1.0, 2.0, 3.0), (1.5, 2.0, 3.0), (1.0, 3.0, 2.0)])
    traj = dz.simulate(d, (0.01, 0.01, 1.0), t_end=6.0, frames=7)
    back = dz.load(dz.save(traj, tmp_path / "deployment.nc"))
    assert isinstance(back.body, dz.Deployment) and back.system == traj.system
    _assert_same_run(back, traj)
    assert back.drift == traj.drift
    # runs of different knot counts (NaN-padded in the file)
    two = dz.Deployment([1.0, 2.0], [(1.0, 2.0, 3.0), (1.0, 3.0, 2.0)])
    batch = dz.simulate([d, two], (0.01, 0.01, 1.0), t_end=6.0, frames=7)
    again = dz.load(dz.save(batch, tmp_path / "deployments.nc"))
    assert [s.body for s in again.systems] == [d, two]
    _assert_same_run(again, batch)
    damped = dz.simulate(_damped(None), [(0.3, 0.2, 1.0), (1.0, 0.1, 0.2)], t_end=5.0,
                         frames=6)
    loaded = dz.load(dz.save(damped, tmp_path / "damped-batch.nc"))
    assert list(loaded.systems) == list(damped.systems)
    _assert_same_run(loaded, damped)
    for x, y in zip(loaded.drift, damped.drift):
        assert x.tobytes() == y.tobytes()
    assert loaded.drift.kept == damped.drift.kept
    assert loaded[1].parts["damper"].tobytes() == damped[1].parts["damper"].tobytes()


def test_save_load_a_deployment_sweep(tmp_path):
    deployments = [dz.Deployment([1.0, 2.0], [(1.0, 2.0, 3.0), (1.0, 3.0, r)])
                   for r in (2.0, 4.0)] + [dz.Deployment([0.5, 1.0, 2.0], [(1.0, 2.0, 3.0)] * 3)]
    s = dz.sweep(deployments, (0.01, 0.01, 1.0), t_end=3.0, frames=2, dt=1e-2)
    back = dz.load(dz.save(s, tmp_path / "dsweep.nc"))
    assert isinstance(back, dz.DeploymentSweep) and back.deployments == s.deployments
    _assert_same_arrays(back, s, ["omega0", "q0", "inertia", "omega_deployed", "flip_period",
                                  "tumbles", "energy_change", "dt", "n_steps", "nfev"])
    assert list(back.status) == list(s.status) and back.t_end == s.t_end
    assert back.drift.kept == s.drift.kept
    for x, y in zip(back.drift, s.drift):
        assert x.tobytes() == y.tobytes()


@pytest.mark.parametrize("mutation, field", [
    ("energy edited", "`energy` is not what the file's own system and frames give"),
    ("momentum_world edited", "`momentum_world` is not what"),
    ("inertia not the system's", "`inertia` is not the principal moments of the file's own"),
    ("body_tensor missing", "the system's body must be given once"),
    ("knots beside the body", "the system's body must be given once"),
    ("parts names a damper", "the attribute `parts` names the damper, but its state"),
    ("drift_kept unknown", "the attribute `drift_kept` must be one of"),
])
def test_load_refuses_a_system_a_save_never_writes(traj, tmp_path, mutation, field):
    path = _spoilt(traj, "Trajectory", mutation, tmp_path)
    with pytest.raises(dz.ReadError, match=rf"bad\.nc holds a Trajectory that dz\.save never "
                                           rf"writes: {field}"):
        dz.load(path)


def test_load_refuses_a_body_the_core_refuses(traj, tmp_path):
    path = _spoilt(traj, "Trajectory", "body_tensor not positive definite", tmp_path)
    with pytest.raises(dz.ReadError, match=r"bad\.nc holds a Trajectory whose system dz cannot "
                                           r"build: .*positive definite"):
        dz.load(path)


def test_load_refuses_a_damper_state_without_its_parameters(tmp_path):
    traj = dz.simulate(_damped(), (0.3, 0.2, 1.0), t_end=5.0, frames=6)
    ds = traj.to_xarray().drop_vars("part_damper_damping")
    ds.attrs["dzhanibekov_result"] = "Trajectory"
    path = tmp_path / "bad.nc"
    ds.to_netcdf(path, engine="h5netcdf")
    with pytest.raises(dz.ReadError, match=r"`part_damper_damping` is missing"):
        dz.load(path)
    ds = traj.to_xarray().drop_vars("damper")                   # the state without the part
    ds.attrs["dzhanibekov_result"] = "Trajectory"
    ds.to_netcdf(path, engine="h5netcdf")
    with pytest.raises(dz.ReadError, match=r"the attribute `parts` names the damper, but its "
                                           r"state `damper` is missing"):
        dz.load(path)


# -- units (issue 24) ------------------------------------------------------------------------

CF_UNITS = {"1", "rad"}
"""The only `units` the files carry: UDUNITS strings (CF 1.11, 3.1). "consistent units" was
no unit any CF reader parses; the user's own units are said in `unit_system` instead."""


@pytest.mark.parametrize("name", ["traj", "batch", "sweep"])
def test_every_unit_is_cf_and_the_unit_system_is_said(name, request):
    ds = request.getfixturevalue(name).to_xarray()
    units = {v: ds[v].attrs["units"] for v in ds.variables if "units" in ds[v].attrs}
    assert set(units.values()) <= CF_UNITS, units
    assert "time" not in units and "rad/T" in ds.attrs["unit_system"]


# -- netCDF: formats and paths (issues 24, 25) ---------------------------------------------------


@pytest.mark.parametrize("suffix, hint", [(".csv", "to_dataframe"), (".aem", "write_aem"),
                                          (".txt", ""), ("", "")])
def test_save_refuses_a_suffix_of_another_format(traj, tmp_path, suffix, hint):
    """`save(traj, "run.csv")` wrote netCDF into a file named .csv."""
    with pytest.raises(ValueError, match=rf"`path` .* must end in one of \.nc.*{hint}"):
        dz.save(traj, tmp_path / f"run{suffix}")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("suffix", [".nc", ".nc4", ".h5", ".NC"])
def test_save_writes_netcdf_suffixes(traj, tmp_path, suffix):
    assert isinstance(dz.load(dz.save(traj, tmp_path / f"run{suffix}")), dz.Trajectory)


def test_load_of_an_aem_says_what_it_is(traj, tmp_path):
    """`dz.load("box.aem")` raised h5py's raw OSError."""
    path = dz.io.write_aem(traj, tmp_path / "box.aem", "B", "1", "2026-01-01T00:00:00",
                           ref_frame_a="ICRF")
    with pytest.raises(dz.ReadError, match=r"box\.aem is a CCSDS AEM .*read_aem.*not a "
                                           r"netCDF-4 file written by dzhanibekov\.save"):
        dz.load(path)


def test_read_aem_of_a_netcdf_file_says_what_it_is(traj, tmp_path):
    """`read_aem("run.nc")` raised UnicodeDecodeError."""
    path = dz.save(traj, tmp_path / "run.nc")
    with pytest.raises(dz.ReadError, match=r"run\.nc is an HDF5 file .*dz\.load.*not a "
                                           r"CCSDS AEM"):
        dz.io.read_aem(path)


def test_load_turns_missing_files_and_folders_into_read_errors(tmp_path):
    """`KeyError`, `OSError` and `IsADirectoryError` escaped instead of the documented
    ValueError subclass."""
    for path, why in ((tmp_path / "missing.nc", "No such file"), (tmp_path, "a folder")):
        with pytest.raises(dz.ReadError, match=why) as caught:
            dz.load(path)
        assert caught.value.path == str(path) and isinstance(caught.value, ValueError)


# -- netCDF: what a save never writes (issue 25) ---------------------------------------------------


def _spoilt(result, kind, mutation, tmp_path):
    from hostile import _netcdf_mutations, _spoilt as spoil

    ds = result.to_xarray()
    ds.attrs["dzhanibekov_result"] = kind
    image = dz.save(result, tmp_path / "valid.nc").read_bytes()
    path = tmp_path / "bad.nc"
    path.write_bytes(spoil(image, _netcdf_mutations(kind, ds)[mutation]))
    return path


@pytest.mark.parametrize("kind, mutation, field", [
    ("Trajectory", "NaN in q", "`q` holds NaN"),
    ("Trajectory", "q of norm 1.5", "`q` must be unit quaternions"),
    ("Trajectory", "(11, 3) q", "`q` must have dims \\('time', 'quaternion'\\)"),
    ("Trajectory", "time reversed", "`time` must start at 0"),
    ("Trajectory", "flip time beyond t_end", "`flip_times` must lie in"),
    ("Trajectory", "flips_located without flip_times", "`flips_located` says"),
    ("Trajectory", "quaternion labels reversed", "`quaternion` must be \\['Q', 'U', 'V', 'W'\\]"),
    ("Trajectory", "method missing", "the attribute `method` is missing"),
    ("Trajectory", "q as float32", "`q` must hold float64"),
    ("Batch", "flips one more", "`flip_times` must have as many columns"),
    ("Batch", "flips one fewer", "`flips` holds negative values \\(-1\\)"),
    ("Batch", "q of norm 1.5", "`q` must be unit quaternions .*\\(run \\d\\)"),
    ("Sweep", "status unknown", "`status` must be one of"),
    ("Sweep", "flips mismatch first_flip", "`first_flip` must be a time exactly"),
    ("Sweep", "tilt beyond pi", "`tilt` must lie in"),
])
def test_load_refuses_what_a_save_never_writes(traj, batch, sweep, tmp_path, kind, mutation,
                                               field):
    """`dz.load` returned NaN and non-unit q, an (11, 3) "q", reversed time and flip counts
    that did not match the flip times, silently."""
    result = {"Trajectory": traj, "Batch": batch, "Sweep": sweep}[kind]
    path = _spoilt(result, kind, mutation, tmp_path)
    with pytest.raises(dz.ReadError, match=rf"bad\.nc holds a {kind} that dz\.save never "
                                           rf"writes: {field}"):
        dz.load(path)


def test_load_accepts_the_drift_its_run_recorded(tmp_path):
    """A run's q departs from unit norm by its recorded drift (RK4 at a large step): that is
    what a save writes, and it loads."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", dz.StepSizeWarning)
        rough = dz.simulate(dz.PAPER_INERTIA, (0.3, 0.2, 1.0), t_end=100.0, frames=11, dt=0.4)
    assert rough.drift.q_norm > 1e-6
    back = dz.load(dz.save(rough, tmp_path / "rough.nc"))
    assert back.q.tobytes() == rough.q.tobytes()


# -- CCSDS AEM (issues 24, 25) -------------------------------------------------------------------


def test_write_aem_needs_the_inertial_frame(traj, tmp_path):
    """REF_FRAME_A = EME2000 was asserted by default for whatever inertial frame the run's
    world axes were."""
    with pytest.raises(TypeError, match="ref_frame_a"):
        dz.io.write_aem(traj, tmp_path / "a.aem", "B", "1", "2026-01-01T00:00:00")
    path = dz.io.write_aem(traj, tmp_path / "a.aem", "B", "1", "2026-01-01T00:00:00",
                           ref_frame_a="ICRF")
    assert dz.io.read_aem(path).metadata["REF_FRAME_A"] == "ICRF"


def test_a_batch_is_written_as_segments_and_every_segment_is_read(batch, tmp_path):
    """`read_aem` read one segment only."""
    path = dz.io.write_aem(batch, tmp_path / "b.aem", "BOX", ["2026-001A", "2026-001B",
                                                             "2026-001C"],
                           "2026-01-01T00:00:00", ref_frame_a="EME2000", rates=True)
    aem = dz.io.read_aem(path)
    assert len(aem.segments) == len(batch)
    for k, segment in enumerate(aem.segments):
        assert np.array_equal(segment.q, batch.q[k])
        assert np.allclose(segment.omega, batch.omega[k], rtol=1e-14, atol=0)
        assert np.allclose(segment.t, batch.t, atol=1e-6)
        assert segment.metadata["OBJECT_ID"] == f"2026-001{'ABC'[k]}"
    with pytest.raises(ValueError, match="3 segments: take each from `.segments`"):
        aem.q
    # the independent parser reads the segments too
    ccsds = pytest.importorskip("ccsds_ndm", reason="ccsds-ndm-py (the test extra)")
    if hasattr(ccsds, "from_file"):
        segments = ccsds.from_file(str(path)).segments
        assert len(segments) == 3
        for k, segment in enumerate(segments):
            states = np.asarray(segment.data.attitude_states_numpy)
            assert np.array_equal(states[:, :4], batch.q[k][:, [1, 2, 3, 0]])


def _aem_text(traj, tmp_path):
    path = dz.io.write_aem(traj, tmp_path / "v.aem", "BOX", "2026-001A",
                           "2026-01-01T00:00:00", ref_frame_a="EME2000")
    return path.read_text()


@pytest.mark.parametrize("mutation, message", [
    ("nan quaternion", "nan is not a finite number"),
    ("non-unit quaternion", "has norm 1.8, not 1"),
    ("time backwards", "is not after the line before's"),
    ("month 13", "is not a date: month must be in 1..12"),
    ("february 30", "is not a date: day is out of range"),
    ("day of year 366 in 2026", "day of year 366 is not in 001 to 365"),
    ("hour 25", "is not a time of day"),
    ("year 10000", "is not an epoch like"),
    ("year 9999 day 400", "day of year 400 is not in 001 to 365"),
    ("missing DATA_START", "after META_STOP, with no DATA_START"),
    ("missing DATA_STOP", "ends inside DATA_START … DATA_STOP, no DATA_STOP"),
    ("missing REF_FRAME_A", "lacks REF_FRAME_A"),
    ("version 3.0", "CCSDS_AEM_VERS '3.0' is not read"),
    ("a field short", "has 5 fields"),
    ("non-ASCII byte", "is not ASCII text"),
    ("epochs after STOP_TIME", "are not inside its START_TIME"),
    ("no data lines", "a segment without data lines"),
])
def test_read_aem_refuses_what_is_no_attitude_ephemeris(traj, tmp_path, mutation, message):
    """`read_aem` returned NaN and non-unit quaternions, times running backwards, impossible
    epochs and an empty ephemeris when DATA_START was missing, without error; an epoch past
    year 9999 escaped as OverflowError."""
    from hostile import _aem_mutations

    path = tmp_path / "bad.aem"
    path.write_bytes(_aem_mutations(_aem_text(traj, tmp_path))[mutation].encode("utf-8"))
    with pytest.raises(dz.ReadError, match=rf"bad\.aem.*({message})"):
        dz.io.read_aem(path)


def test_read_aem_refuses_epochs_outside_the_segments_span(traj, tmp_path):
    text = _aem_text(traj, tmp_path)
    start = next(ln for ln in text.splitlines() if ln.startswith("START_TIME"))
    path = tmp_path / "late.aem"
    path.write_text(text.replace(start, "START_TIME = 2026-01-01T00:00:01.000000"))
    with pytest.raises(dz.ReadError, match="are not inside its START_TIME"):
        dz.io.read_aem(path)


def test_write_aem_refuses_what_it_could_not_write_faithfully(traj, tmp_path):
    with pytest.raises(ValueError, match="past 9999-12-31"):
        dz.io.write_aem(traj, tmp_path / "a.aem", "B", "1", "9999-12-31T23:59:00",
                        ref_frame_a="ICRF")
    with pytest.raises(ValueError, match="same epoch at the microsecond"):
        dz.io.write_aem(traj, tmp_path / "a.aem", "B", "1", "2026-01-01T00:00:00",
                        ref_frame_a="ICRF", time_unit=1e-9)
    import dataclasses

    skewed = dataclasses.replace(traj, q=traj.q * 1.01)
    with pytest.raises(ValueError, match="departs from unit norm by 0.01"):
        dz.io.write_aem(skewed, tmp_path / "a.aem", "B", "1", "2026-01-01T00:00:00",
                        ref_frame_a="ICRF")
    assert list(tmp_path.iterdir()) == []


def test_read_aem_streams_its_rows(tmp_path):
    """A 100 MB file took 11 s and 932 MB: the whole text, its lines and their fields were
    held at once. Now the rows are kept in typed arrays as they are read: the memory is that
    of the rows kept (about 150 bytes each), not a multiple of the file's size."""
    traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=1000.0, frames=40001,
                       dt=1e-2)
    path = dz.io.write_aem(traj, tmp_path / "long.aem", "BOX", "2026-001A",
                           "2026-01-01T00:00:00", ref_frame_a="EME2000", rates=True)
    size = path.stat().st_size
    tracemalloc.start()
    try:
        aem = dz.io.read_aem(path)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    rows = len(aem.t)
    assert rows == 40001 and np.array_equal(aem.q, traj.q)
    # the old reader held ~9 times the file, some 1500 bytes a row here
    assert peak < 2 * dz.aem.BYTES_PER_ROW * rows, (peak, size, rows)


def test_read_aem_checks_the_size_first(tmp_path, monkeypatch):
    path = tmp_path / "big.aem"
    with open(path, "wb") as f:
        f.truncate(dz.io.MAX_AEM_BYTES + 1)  # sparse: no disk taken
    with pytest.raises(dz.ReadError, match="more than the .* \\(MAX_AEM_BYTES\\)"):
        dz.io.read_aem(path)
