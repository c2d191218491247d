"""``traj.part_rates`` (issue 31): the rates of the coordinates of the parts whose mass moves,
which the run's state holds only through their conjugate momenta. Checked against finite
differences of the coordinates the run kept (nothing of the solve that gives the rates), for
each part alone (its closed form), for three together (the joint solve) and on a deploying
body; and the same numbers in xarray, a data frame and a file."""

from __future__ import annotations

import numpy as np
import pytest

import dzhanibekov as dz
from sink_runs import BODY, PARTS

TOGETHER = [dz.SpringMassDamper(0.05, (0.0, 0.0, 3.0), (1.0, 0.0, 0.0), 0.5, 0.02),
            dz.Hinge(0.05, (1e-4, 0.01, 0.01), (0.0, 3.0, 0.0), (1.0, 0.0, 0.0),
                     (0.0, 1.0, 0.0), 1.0, 0.5, 0.02),
            dz.Slosh(0.05, (0.0, 0.0, -3.0), 2.0, 0.02, (0.0, 1.0, 0.0))]
DEPLOYING = dz.Deployment([1.0, 3.0], [np.diag([52.0833, 27.0833, 41.6666]),
                                       np.diag([52.0833, 41.6666, 27.0833])], mass=1.0)
START = (0.3, 0.2, 1.0)


def differences(t: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The five-point central difference of `y` (frames, n) on the even grid `t`, at the
    frames 2 … −3: exact for quartics, its error ``h⁴ y⁽⁵⁾ / 30``."""
    h = t[1] - t[0]
    return (y[:-4] - 8 * y[1:-3] + 8 * y[3:-1] - y[4:]) / (12 * h)


def check_rates(traj: dz.Trajectory) -> list[str]:
    """Every moving part's rates against the differences of its coordinates; their names."""
    names = []
    for name, rate in traj.part_rates.items():
        width = rate.shape[1]
        coordinates = traj.parts[name][:, :width]
        fd = differences(traj.t, coordinates)
        scale = np.abs(rate).max()
        assert scale > 1e-3, name  # the part does move
        # 3e-13 to 5e-10 of the largest rate measured (the differences' own error)
        np.testing.assert_allclose(rate[2:-2], fd, rtol=0, atol=1e-8 * scale, err_msg=name)
        names.append(name)
    return names


@pytest.mark.parametrize("kind", list(PARTS))
def test_each_part_s_rates_are_its_coordinates_derivatives(kind):
    traj = dz.simulate(dz.System(BODY, parts=[PARTS[kind]]), START, t_end=4.0, frames=4001,
                       dt=1e-3)
    assert check_rates(traj) == [kind]
    width = {"slosh": 3}.get(kind, 1)
    assert traj.part_rates[kind].shape == (4001, width)
    if kind == "slosh":  # ṅ ⊥ n: the rod keeps its length
        n = traj.parts[kind][:, :3]
        assert np.abs(np.sum(n * traj.part_rates[kind], axis=1)).max() < 1e-12


def test_three_parts_together_and_on_a_deploying_body():
    for body in (BODY, DEPLOYING):
        traj = dz.simulate(dz.System(body, parts=TOGETHER), START, t_end=4.0, frames=4001,
                           dt=1e-3)
        assert check_rates(traj) == ["spring_mass", "hinge", "slosh"]


def test_no_moving_part_no_rates():
    traj = dz.simulate(dz.System(BODY, parts=[dz.Damper(0.05, 0.02)]), START, t_end=1.0,
                       frames=3)
    assert traj.part_rates == {}
    batch = dz.simulate(dz.System(BODY, parts=[PARTS["hinge"]]), [START, (0.1, 1.0, 0.1)],
                        t_end=1.0, frames=5)
    assert batch.part_rates["hinge"].shape == (2, 5, 1)
    np.testing.assert_array_equal(batch.part_rates["hinge"][1], batch[1].part_rates["hinge"])


def test_rates_in_xarray_a_frame_and_a_file(tmp_path):
    pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    traj = dz.simulate(dz.System(BODY, parts=TOGETHER), START, t_end=1.0, frames=11)
    rates = traj.part_rates
    ds = traj.to_xarray()
    np.testing.assert_array_equal(ds["hinge_angle_rate"].values, rates["hinge"][:, 0])
    np.testing.assert_array_equal(ds["slosh_direction_rate"].values, rates["slosh"])
    assert ds["slosh_direction_rate"].dims == ("time", "axis")
    frame = traj.to_dataframe()
    np.testing.assert_array_equal(frame["spring_mass_displacement_rate"].values,
                                  rates["spring_mass"][:, 0])
    np.testing.assert_array_equal(frame["slosh_direction_rate_z"].values, rates["slosh"][:, 2])
    path = tmp_path / "run.nc"
    dz.save(traj, path)
    loaded = dz.load(path)
    for name, rate in rates.items():
        np.testing.assert_array_equal(loaded.part_rates[name], rate)
    # a file whose rates are not its own frames' is refused, by name
    h5py = pytest.importorskip("h5py")
    with h5py.File(path, "r+") as h:
        h["hinge_angle_rate"][...] = h["hinge_angle_rate"][...] * 1.001
    with pytest.raises(dz.ReadError, match="hinge_angle_rate"):
        dz.load(path)
