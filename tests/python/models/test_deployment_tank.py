"""A deployment carrying a slosh tank (issue 31): ``dz.Deployment(..., mass=m)`` gives the
deploying body the mass that parts whose mass moves need, and the run is the whole system's
about its moving mass centre. Checked against what the code cannot fake: the angular momentum
in space, the energy balance written here from the frames (the deployment's work
``−½ ∫ ωᵀ İ ω dt`` from the quintic law written here, the tank's ``c ∫ |ṅ|² dt`` from finite
differences of the kept directions), and the plain deployment as the tank's mass goes to
zero."""

from __future__ import annotations

import numpy as np
import pytest

import dzhanibekov as dz

STOWED, DEPLOYED = np.diag([1.0, 2.0, 3.0]), np.diag([1.0, 3.0, 2.0])
KNOTS = (1.0, 3.0)
START = (0.01, 0.01, 1.0)


def deployment(mass=1.0):
    return dz.Deployment(list(KNOTS), [STOWED, DEPLOYED], mass=mass)


def tank(mass=0.05, damping=0.02):
    return dz.Slosh(mass, (0.0, 0.0, 0.5), 0.3, damping, (1.0, 0.0, 0.0))


def idot(t: np.ndarray) -> np.ndarray:
    """İ(t) (frames, 3, 3) of the quintic ``s(τ) = 10τ³ − 15τ⁴ + 6τ⁵`` between the knots."""
    span = KNOTS[1] - KNOTS[0]
    tau = np.clip((t - KNOTS[0]) / span, 0.0, 1.0)
    rate = 30 * tau**2 * (1 - tau) ** 2 / span
    return rate[:, None, None] * (DEPLOYED - STOWED)[None]


def cumulative(t: np.ndarray, y: np.ndarray) -> np.ndarray:
    """∫₀ᵗ y by the trapezoids, at every frame."""
    return np.concatenate([[0.0], np.cumsum(0.5 * np.diff(t) * (y[1:] + y[:-1]))])


def rates(t: np.ndarray, y: np.ndarray) -> np.ndarray:
    """dy/dt by the five-point central difference (second-order one-sided at the ends)."""
    out = np.gradient(y, t, axis=0, edge_order=2)
    h = t[1] - t[0]
    out[2:-2] = (y[:-4] - 8 * y[1:-3] + 8 * y[3:-1] - y[4:]) / (12 * h)
    return out


@pytest.fixture(scope="module")
def run():
    return dz.simulate(dz.System(deployment(), parts=[tank()]), START, t_end=6.0,
                       frames=6001, dt=1e-3)


def test_angular_momentum_in_space_is_kept(run):
    world = run.momentum_world
    drift = np.abs(world - world[0]).max() / np.linalg.norm(world[0])
    assert drift < 1e-12  # 8e-15 measured
    # the tank did move, and the deployment did change the body
    assert np.ptp(run.parts["slosh"][:, :3], axis=0).max() > 1e-3


def test_energy_changes_by_the_deployment_s_work_less_the_dissipated(run):
    t, omega = run.t, run.omega
    work = cumulative(t, -0.5 * np.einsum("fi,fij,fj->f", omega, idot(t), omega))
    n = run.parts["slosh"][:, :3]
    dissipated = cumulative(t, 0.02 * np.sum(rates(t, n) ** 2, axis=1))
    e = run.energy
    # both matter: the work is half the energy, the dissipated work 1.1e-4 of it, 1000 times
    # the balance's error (7.9e-8 of it measured: the trapezoids')
    assert abs(work[-1]) > 0.4 * e[0] and dissipated[-1] > 5e-5 * e[0]
    np.testing.assert_allclose(e - e[0], work - dissipated, rtol=0, atol=2e-7 * e[0])


def test_a_tank_of_no_mass_is_the_plain_deployment():
    plain = dz.simulate(dz.Deployment(list(KNOTS), [STOWED, DEPLOYED]), START, t_end=6.0,
                        frames=61, dt=1e-3)
    # the same tank scaled down: its damping with its mass (a massless damper is rigid)
    light = dz.simulate(dz.System(deployment(), parts=[tank(1e-12, 0.02 * 1e-12 / 0.05)]),
                        START, t_end=6.0, frames=61, dt=1e-3)
    np.testing.assert_allclose(light.omega, plain.omega, rtol=0, atol=1e-10)  # 4e-12 measured
    np.testing.assert_allclose(light.q, plain.q, rtol=0, atol=1e-10)


def test_a_deployment_needs_its_mass_to_carry_a_tank():
    massless = dz.System(dz.Deployment(list(KNOTS), [STOWED, DEPLOYED]), parts=[tank()])
    with pytest.raises(ValueError, match="must have a mass"):
        dz.simulate(massless, START, t_end=1.0)
    with pytest.raises(ValueError, match="mass"):
        dz.Deployment(list(KNOTS), [STOWED, DEPLOYED], mass=-1.0)
    d = deployment(2.0)
    assert d.mass == 2.0 and d != deployment(1.0) and d == deployment(2.0)
    assert "mass=2.0" in repr(d)
    import pickle

    assert pickle.loads(pickle.dumps(d)) == d


def test_the_mass_goes_through_a_file(tmp_path):
    pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    traj = dz.simulate(dz.System(deployment(), parts=[tank()]), START, t_end=2.0, frames=5)
    loaded = dz.load(dz.save(traj, tmp_path / "tank.nc"))
    assert loaded.system.body == deployment()
    np.testing.assert_array_equal(loaded.energy, traj.energy)
