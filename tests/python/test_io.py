"""Results as xarray/pandas tables, netCDF files and CCSDS attitude messages.

The AEM files are read back by an independent reader: `ccsds-ndm-py` (a CCSDS NDM parser
with a Rust core, in the `test` extra) for version 2.0, and for version 1.0 a parser
written here from the keyword list of CCSDS 504.0-B-1 (its tables 4-2 and 4-3).
"""

import sys

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
    assert ds.time.attrs["units"] == "consistent units"


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
    with pytest.raises(TypeError, match="`result` must be a Trajectory, Batch, Sweep or "):
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
    with pytest.raises(ImportError, match=rf"needs {missing}.*pip install \"\.\[io\]\""):
        call()


# -- CCSDS AEM -----------------------------------------------------------------------------


def test_aem_v2_read_by_an_independent_parser(traj, tmp_path):
    ccsds = pytest.importorskip("ccsds_ndm", reason="ccsds-ndm-py (the test extra)")
    if not hasattr(ccsds, "from_file"):
        pytest.skip("another package named ccsds_ndm is installed, not ccsds-ndm-py")
    path = dz.io.write_aem(traj, tmp_path / "box.aem", "BOX", "2026-001A",
                           "2026-01-01T00:00:00", center_name="EARTH")
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
                           "2026-01-01T00:00:00", rates=True, time_unit=2.0)
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
                           "2026-01-01T00:00:00", version="1.0", rates=True)
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
                               "2026-01-01T00:00:00", version=version, rates=True,
                               time_unit=0.5)
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
        dz.io.write_aem("x", tmp_path / "a.aem", "B", "1", "2026-01-01T00:00:00")
    with pytest.raises(ValueError, match="`object_name` must be one printable line"):
        dz.io.write_aem(traj, tmp_path / "a.aem", "B\nMETA_STOP", "1", "2026-01-01T00:00:00")
    with pytest.raises(ValueError, match="`epoch` must be a time"):
        dz.io.write_aem(traj, tmp_path / "a.aem", "B", "1", "yesterday")
    with pytest.raises(ValueError, match="`version` must be one of"):
        dz.io.write_aem(traj, tmp_path / "a.aem", "B", "1", "2026-01-01T00:00:00",
                        version="3.0")
