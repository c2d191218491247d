"""The orbit asks of a study (issue 29): ``"lvlh_angle"`` and ``"leaves_nadir"`` of a
satellite in the gravity gradient, against the pitch pendulum's closed forms (Hughes,
*Spacecraft Attitude Dynamics*, 1986, §9.3): ``I_y θ'' + 3 n² (I_x − I_z) sin θ cos θ = 0``
keeps ``½ I_y θ'² + (3/2) n² (I_x − I_z) sin² θ``, so a pitch released at rest from ``θ₀``
swings to ``±θ₀`` and no further, and a pitch rate ``θ'₀`` from the equilibrium carries the
body's z axis past 90° from nadir (over the top) exactly when ``|θ'₀|`` exceeds the small
libration rate ``n √(3 (I_x − I_z) / I_y)``."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import dzhanibekov as dz

N = 1.0
INERTIA = (2.0, 3.0, 1.0)        # roll, pitch, yaw: Lagrange's stable ordering
SAT = dz.System(dz.Body(INERTIA), torques=[dz.GravityGradient(N)])
LIBRATION = math.sqrt(3.0 * (INERTIA[0] - INERTIA[2]) / INERTIA[1]) * N
# world-from-LVLH at t = 0, from the frame's definition (columns along-track = +y, minus
# orbit normal = −z, nadir = −x), written here apart from the package
LVLH0 = Rotation.from_matrix([[0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])


def pitched(rng):
    return dz.lvlh_start(N, pitch=rng.uniform(0.05, 1.2))[1]


def test_the_largest_angle_from_lvlh_is_each_samples_released_pitch():
    study = dz.monte_carlo(SAT, (0.0, -N, 0.0), 12, seed=5, t_end=2 * math.pi / LIBRATION,
                           q0=pitched, ask="lvlh_angle", method="dop853", rtol=1e-11,
                           atol=1e-12)
    q0 = study.inputs["q0"]
    released = (LVLH0.inv() * Rotation.from_quat(q0[:, [1, 2, 3, 0]])).magnitude()
    assert released.min() > 0.05 and released.max() < 1.2
    np.testing.assert_allclose(study.outcomes, released, rtol=0.0, atol=1e-8)


def test_a_pitch_rate_above_the_libration_rate_leaves_nadir_and_one_below_does_not(tmp_path):
    def rates(rng):
        return dz.lvlh_start(N, omega_rel=(0.0, rng.uniform(0.0, 2.0) * LIBRATION, 0.0))[0]

    study = dz.monte_carlo(SAT, rates, 40, seed=9, t_end=6 * 2 * math.pi / LIBRATION,
                           q0=dz.lvlh_start(N)[1],
                           ask="leaves_nadir", method="dop853", rtol=1e-10, atol=1e-12)
    rate = study.inputs["omega0"][:, 1] + N       # ω0 = ω_rel + n ẑ_b, ẑ_b = −y here
    clear = np.abs(rate / LIBRATION - 1.0) > 0.05  # away from the separatrix's slow swing
    assert clear.sum() >= 30
    np.testing.assert_array_equal(study.outcomes[clear], rate[clear] > LIBRATION)
    assert study.outcomes.dtype == np.bool_ and 0.0 < study.p < 1.0
    pytest.importorskip("h5netcdf")
    back = dz.load(dz.save(study, tmp_path / "nadir.nc"))
    assert back.ask == "leaves_nadir" and back.outcomes.dtype == np.bool_
    np.testing.assert_array_equal(back.outcomes, study.outcomes)


@pytest.mark.parametrize("ask", ["lvlh_angle", "leaves_nadir"])
def test_an_orbit_ask_of_a_system_without_the_gravity_gradient_is_refused_by_name(ask):
    with pytest.raises(ValueError, match=f"`ask='{ask}'` needs a system in the gravity"):
        dz.monte_carlo(dz.Body(INERTIA), (0.0, 1.0, 0.0), 4, seed=1, t_end=1.0, ask=ask)
