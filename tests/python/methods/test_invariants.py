"""What the exact motion keeps, kept by the runs; and why the paper's printed dV row is wrong."""

import numpy as np
import pytest
from reference import dop853, quaternion_matrix

import dzhanibekov as dz


@pytest.mark.parametrize("name", ["example", "fig3a", "fig3b", "fig3c"])
def test_invariants_are_kept_on_the_papers_scenarios(name):
    traj = dz.SCENES[name].run()
    inv = traj.invariants()
    e0, l0 = inv["energy"][0], inv["momentum_world"][0]
    # relative drift at dt = 1e-3 over the paper's spans: round-off level
    assert np.abs(inv["energy"] / e0 - 1).max() < 1e-11
    assert np.abs(np.linalg.norm(inv["momentum_body"], axis=1) / np.linalg.norm(l0) - 1).max() < 1e-11
    assert np.abs(inv["momentum_world"] - l0).max() / np.linalg.norm(l0) < 1e-11
    assert np.abs(inv["q_norm"] - 1).max() < 1e-11
    # the run's own drift summary says the same
    assert max(traj.drift) < 1e-11


def test_invariants_are_computed_from_their_definitions(paper_body, rng):
    traj = dz.simulate(paper_body, rng.normal(size=3), q0=rng.normal(size=4), t_end=5.0, frames=6,
                       dt=1e-3)
    inv = traj.invariants()
    inertia = np.array(dz.PAPER_INERTIA)
    np.testing.assert_allclose(inv["energy"], 0.5 * np.sum(inertia * traj.omega**2, axis=1), rtol=1e-14)
    l_body = inertia * traj.omega
    np.testing.assert_allclose(inv["momentum_body"], l_body, rtol=1e-14)
    l_world = np.einsum("nij,nj->ni", quaternion_matrix(traj.q), l_body)
    np.testing.assert_allclose(inv["momentum_world"], l_world, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(inv["q_norm"], np.linalg.norm(traj.q, axis=1), rtol=1e-15)


def test_drift_grows_with_the_step_as_rk4_should(paper_body):
    coarse = dz.simulate(paper_body, (0.01, 0.01, 1.0), t_end=100.0, dt=0.1)
    fine = dz.simulate(paper_body, (0.01, 0.01, 1.0), t_end=100.0, dt=0.05)
    # RK4's energy error is O(h⁴): halving the step cuts it by about 16
    assert 8 < coarse.drift.energy / fine.drift.energy < 32


def test_the_printed_dv_row_does_not_keep_the_quaternion_norm():
    # Erratum 1. As printed, dV/dt = ½(W u + Q v + U w), so d|q|²/dt = 2 V W u ≠ 0: on case 3a
    # |q| grows to about 47 by t = 100. The body-frame law keeps |q| = 1 and L_world.
    t = np.linspace(0.0, 100.0, 201)
    omega0 = np.array([0.01, 0.01, 1.0])
    _, q_printed = dop853(dz.PAPER_INERTIA, omega0, (1, 0, 0, 0), t, law="printed", rtol=1e-10)
    assert np.linalg.norm(q_printed[-1]) > 10.0

    traj = dz.SCENES["fig3a"].run()
    assert np.abs(np.linalg.norm(traj.q, axis=1) - 1).max() < 1e-11


def test_the_space_frame_law_keeps_the_norm_but_not_the_world_momentum():
    # The printed dU, dW rows match q' = ½ (0, ω) ⊗ q: unit norm, but the body's angular
    # momentum then turns in space. Only q' = ½ q ⊗ (0, ω) keeps L_world.
    inertia = np.array(dz.PAPER_INERTIA)
    omega0 = np.array([0.01, 0.01, 1.0])
    t = np.linspace(0.0, 100.0, 201)
    omega, q_space = dop853(dz.PAPER_INERTIA, omega0, (1, 0, 0, 0), t, law="space", rtol=1e-10)
    assert np.abs(np.linalg.norm(q_space, axis=1) - 1).max() < 1e-8
    l_world = np.einsum("nij,nj->ni", quaternion_matrix(q_space), inertia * omega)
    assert np.linalg.norm(l_world - l_world[0], axis=1).max() / np.linalg.norm(l_world[0]) > 0.5

    traj = dz.SCENES["fig3a"].run()
    assert traj.drift.momentum_world < 1e-11
