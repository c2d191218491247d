"""RK4 against independent references: scipy's DOP853 at tight tolerance and the exact
Jacobi-elliptic ω(t); its order; flip times against the exact flip period 2K(m)/λ."""

import numpy as np
import pytest
from reference import ExactOmega, dop853

import dzhanibekov as dz


def scaled_error(y, ref, atol, rtol=0.0):
    return np.max(np.abs(y - ref) / (atol + rtol * np.abs(ref)))


@pytest.mark.parametrize("name", ["fig3b", "fig3c"])
def test_rk4_matches_dop853_on_the_papers_well_conditioned_cases(name):
    s = dz.SCENES[name]
    traj = s.run(dt=1e-3)
    omega, q = dop853(s.inertia, np.array(s.omega0), s.q0, traj.t)
    scale = np.max(np.abs(s.omega0))
    assert scaled_error(traj.omega, omega, atol=1e-9 * scale) <= 1.0
    assert scaled_error(traj.q, q, atol=1e-9) <= 1.0


def test_rk4_matches_dop853_from_random_initial_rates(rng):
    inertia = (1.0, 1.7, 2.3)
    for omega0 in rng.normal(size=(3, 3)):
        traj = dz.simulate(dz.Body(inertia), omega0, q0=rng.normal(size=4), t_end=30.0,
                           frames=61, dt=1e-3)
        q0 = traj.q[0]
        omega, q = dop853(inertia, omega0, q0, traj.t)
        assert scaled_error(traj.omega, omega, atol=1e-9 * np.abs(omega0).max()) <= 1.0
        assert scaled_error(traj.q, q, atol=1e-9) <= 1.0


def test_papers_example_agrees_loosely_until_the_second_flip(paper_body):
    # u0 = v0 = 5e-6: the orbit hugs the separatrix, so round-off is amplified at each pass
    # near the unstable axis and every float64 method drifts apart after the second flip.
    traj = dz.simulate(paper_body, (5e-6, 5e-6, 1.0), t_end=100.0, frames=201, dt=1e-3)
    omega, q = dop853(dz.PAPER_INERTIA, np.array([5e-6, 5e-6, 1.0]), (1, 0, 0, 0), traj.t)
    assert scaled_error(traj.omega, omega, atol=1e-4) <= 1.0
    assert scaled_error(traj.q, q, atol=1e-4) <= 1.0


@pytest.mark.parametrize(
    "inertia, omega0",
    [
        (dz.PAPER_INERTIA, (0.01, 0.1, 0.03)),  # about the minor axis
        (dz.PAPER_INERTIA, (0.01, 0.01, 0.03)),  # about the major axis, flipping
        ((3.0, 1.0, 2.0), (-0.3, 0.5, -0.9)),
        ((1.0, 3.0, 2.0), (-0.7, 0.2, 0.4)),
    ],
)
def test_omega_matches_the_exact_jacobi_solution(inertia, omega0):
    exact = ExactOmega(inertia, omega0)
    t_end = 3 * exact.flip_period
    traj = dz.simulate(dz.Body(inertia), omega0, t_end=t_end, frames=301, dt=1e-3)
    assert scaled_error(traj.omega, exact(traj.t), atol=1e-9 * np.abs(omega0).max()) <= 1.0


def test_error_falls_sixteenfold_when_the_step_halves():
    inertia, omega0, q0 = (1.0, 1.7, 2.3), np.array([0.4, -0.9, 0.6]), (0.8, 0.1, -0.3, 0.5)
    t = np.linspace(0.0, 10.0, 11)
    ref_omega, ref_q = dop853(inertia, omega0, q0, t)
    errors = []
    for dt in (0.04, 0.02, 0.01, 0.005):
        traj = dz.simulate(dz.Body(inertia), omega0, q0, t_end=10.0, frames=11, dt=dt)
        errors.append(max(np.abs(traj.omega - ref_omega).max(), np.abs(traj.q - ref_q).max()))
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all((ratios > 14.0) & (ratios < 18.0)), ratios


@pytest.mark.parametrize(
    "name, inertia, omega0",
    [
        ("fig3a", dz.PAPER_INERTIA, (0.01, 0.01, 1.0)),
        ("near the minor axis side", (1.0, 2.0, 3.0), (0.05, 1.0, 0.3)),
    ],
)
def test_flip_times_are_spaced_by_the_exact_flip_period(name, inertia, omega0):
    exact = ExactOmega(inertia, omega0)
    t_end = 6.5 * exact.flip_period
    traj = dz.simulate(dz.Body(inertia), omega0, t_end=t_end, frames=11, dt=1e-3)
    # sn(λt + u0) vanishes at λt + u0 = 2Kk: the flips, exactly
    k = np.arange(1, 20)
    zeros = (k * exact.flip_period * exact.lam - exact.u_start) / exact.lam
    zeros = zeros[(zeros > 0) & (zeros < t_end)]
    assert len(traj.flip_times) == len(zeros) >= 5, (name, traj.flip_times, zeros)
    np.testing.assert_allclose(traj.flip_times, zeros, rtol=0, atol=1e-8 * exact.flip_period)
