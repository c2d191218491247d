"""Studies over any system (issue 29): `dz.monte_carlo` of a body with wheels and torques,
its parts drawn per sample by a callable, checked against the dual-spin stability rule
(Hughes, *Spacecraft Attitude Dynamics*, 1986, ch. 6), which the study cannot fake."""

from __future__ import annotations

import numpy as np
import pytest

import dzhanibekov as dz

INERTIA = (1.0, 2.0, 3.0)
BODY = dz.Body(INERTIA)
SPIN = (1e-3, 1.0, 1e-3)            # about y, the intermediate axis, at Ω = 1
T_END = 200.0


def wheel_system(rng):
    """A wheel along the spin axis with momentum h uniform on (−2, 2)."""
    return dz.System(BODY, parts=[dz.Wheel((0.0, 1.0, 0.0), rng.uniform(-2.0, 2.0))])


def leaves_the_spin_axis(traj):
    """Whether the body's y axis strays more than 0.5 rad from the angular momentum."""
    y = dz.rotate(traj.q, (0.0, 1.0, 0.0))
    L = traj.momentum_world
    cos = np.sum(y * L, axis=1) / np.linalg.norm(L, axis=1)
    return bool(np.arccos(np.clip(cos, -1.0, 1.0)).max() > 0.5)


def test_a_study_of_wheel_stabilised_spins_finds_the_dual_spin_band():
    study = dz.monte_carlo(wheel_system, SPIN, 400, seed=3, t_end=T_END, method="dop853",
                           ask=leaves_the_spin_axis)
    assert study.kind == "system"
    # the linearised rule: unstable for h in (lo, hi) = (−1, 1), with growth rate
    # λ = √((1 − h²) / (I_x I_z)) here: the share of h ~ U(−2, 2) that leaves the axis lies
    # between the share whose perturbation of 1e-3 surely grows to O(1) within the run
    # (λ T > ln 1e4) and the whole band's, 1/2; a stable spin (|h| > 1) never leaves it
    lo, hi = dz.dual_spin_threshold(INERTIA, 1, 1.0)
    assert (lo, hi) == (-1.0, 1.0)
    h = np.linspace(-2.0, 2.0, 400_001)
    rate = np.sqrt(np.clip((1.0 - h**2) / (INERTIA[0] * INERTIA[2]), 0.0, None))
    surely = float(np.mean(rate * T_END > np.log(1e4)))
    band = (hi - lo) / 4.0
    low, high = study.interval
    assert 0.45 < surely < band == 0.5
    assert low <= band and surely <= high, (study.p, study.interval, surely)
    assert high - low < 0.1                      # the study is sharp enough to tell


def test_a_satellite_with_a_wheel_and_the_gravity_gradient_is_studied_and_saved(tmp_path):
    pytest.importorskip("h5netcdf")
    omega0, q0 = dz.lvlh_start(0.1)

    def satellite(rng):
        body = dz.Body((2.0, rng.uniform(2.5, 2.9), 1.0))
        return dz.System(body, parts=[dz.Wheel((0.0, 1.0, 0.0), 0.5)],
                         torques=[dz.GravityGradient(0.1)])

    def roll_rate(traj):                   # a planar pitch motion never rolls
        return float(np.abs(traj.omega[:, 0]).max())

    study = dz.monte_carlo(satellite, omega0, 20, seed=1, t_end=50.0, q0=q0, ask=roll_rate)
    assert study.kind == "system" and study.mean == 0.0
    back = dz.load(dz.save(study, tmp_path / "study.nc"))
    assert back.kind == "system" and back.mean == study.mean
    np.testing.assert_array_equal(back.inputs["inertia"], study.inputs["inertia"])


def test_a_study_refuses_systems_of_other_parts_within_a_chunk():
    def mixed(rng):
        parts = [dz.Wheel((0.0, 1.0, 0.0), 0.1)] if rng.uniform() < 0.5 else \
            [dz.Wheel((0.0, 1.0, 0.0), ([0.0, 1.0], [0.0, 0.1]))]
        return dz.System(BODY, parts=parts)

    with pytest.raises(dz.StudyError, match="a study's systems have the same kinds of parts"):
        dz.monte_carlo(mixed, SPIN, 40, seed=2, t_end=1.0, method="dop853",
                       ask=leaves_the_spin_axis)
