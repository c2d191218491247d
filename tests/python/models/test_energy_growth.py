"""A damped body (no torque, no deployment) can only lose kinetic energy: a fixed-step run
whose energy (with the work its damper dissipated) grows is past the method's stability limit
for the damper, and raises. A damper with anything that does work is not watched: its energy
may rise (issue 29: it raised a false DivergedError at any dt).

Issue 24: beyond the stiffness limit an RK4 run could finish normally with 1122 times its
starting energy; the warning fired before the run, but with warnings filtered the result was
silently wrong.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import dzhanibekov as dz

BODY, J, DT = np.array([1.0, 2.0, 3.0]), 0.1, 0.01
OMEGA0 = np.array([0.3, 0.2, 0.5])


def damping_for(h_lambda: float) -> float:
    """The c at which the slip's rate λ = c (1/j + 1/I_min) makes `h_lambda` for the step."""
    return h_lambda / DT / (1 / J + 1 / BODY.min())


def rk4_energy(c: float, steps: int) -> float:
    """E / E₀ after `steps` RK4 steps of the damper's law written here (Hughes's spherical
    damper: ω = I⁻¹ (H − j σ), H' = H × ω, σ' = σ × ω − (c/j)(σ − ω)), in numpy."""
    def f(y: np.ndarray) -> np.ndarray:
        h, s = y[:3], y[3:]
        w = (h - J * s) / BODY
        return np.concatenate([np.cross(h, w), np.cross(s, w) - c / J * (s - w)])

    def energy(y: np.ndarray) -> float:
        w = (y[:3] - J * y[3:]) / BODY
        return float(0.5 * w @ (BODY * w) + 0.5 * J * y[3:] @ y[3:])

    y = np.concatenate([BODY * OMEGA0 + J * OMEGA0, OMEGA0])  # the sphere co-rotating
    e0 = energy(y)
    for _ in range(steps):
        k1 = f(y)
        k2 = f(y + DT / 2 * k1)
        k3 = f(y + DT / 2 * k2)
        k4 = f(y + DT * k3)
        y = y + DT / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return energy(y) / e0


def test_an_rk4_run_past_the_dampers_limit_that_would_end_finite_raises():
    c = damping_for(2.8)  # RK4's real-axis limit is 2.785: the slip grows 2.2 % a step
    # the reference: RK4 saturates, finite, at hundreds of times the start's energy
    assert 500 < rk4_energy(c, 2000) < 1e4
    system = dz.System(BODY, parts=[dz.Damper(J, c)])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the user filtered the StiffDamperWarning
        with pytest.raises(dz.DivergedError, match=r"the run diverged at t = \d.*the energy "
                           r"grew to 1\.0\d* times its start.*a body whose parts only "
                           r"dissipate only loses energy: take a smaller dt") as info:
            dz.simulate(system, OMEGA0, t_end=20.0, frames=201, dt=DT)
    # it names the first frame past the threshold, early in the run (not its end)
    assert "t = 20" not in str(info.value)
    # and a batch row says which row
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(dz.DivergedError, match="energy grew") as info:
            dz.simulate([dz.System(BODY, parts=[dz.Damper(J, c / 10)]), system],
                        OMEGA0, t_end=20.0, frames=201, dt=DT)
    assert info.value.row == 1


@pytest.mark.parametrize("h_lambda", [0.1, 1.0, 2.7])
@pytest.mark.parametrize("h_omega", [0.1, 1.0])
def test_stable_damped_runs_are_unaffected_even_coarse(h_lambda, h_omega):
    # coarser than any planned step (h·Ω up to 1), inside the damper's limit
    omega0 = OMEGA0 / np.linalg.norm(OMEGA0) * h_omega / DT
    system = dz.System(BODY, parts=[dz.Damper(J, damping_for(h_lambda))])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        traj = dz.simulate(system, omega0, t_end=500 * DT, frames=101, dt=DT)
    # far within the tolerance of the start (measured: 4.9e-5 at most, at h·Ω = 1 and
    # h·λ = 2.7; at most round-off elsewhere)
    assert traj.energy.max() <= traj.energy[0] * (1 + 1e-4)
    assert dz.damper.ENERGY_GROWTH_TOL >= 100 * 1e-4


def test_adaptive_runs_and_undamped_models_are_not_watched():
    # a deployment's internal forces can give energy: a spin-up is no divergence
    spin_up = dz.Deployment([1.0, 2.0], [(1.0, 2.0, 3.0), (1.0, 2.0, 1.5)])
    traj = dz.simulate(spin_up, (0.0, 0.0, 1.0), t_end=3.0, frames=4, dt=1e-3)
    assert traj.energy[-1] > 1.9 * traj.energy[0]
    # an adaptive method shrinks its steps below the damper's limit by itself
    system = dz.System(BODY, parts=[dz.Damper(J, damping_for(2.8))])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        traj = dz.simulate(system, OMEGA0, t_end=5.0, frames=6, method="dopri5")
    assert np.diff(traj.energy).max() <= 1e-9 * traj.energy[0]


def _work_and_damper(other: object) -> dz.System:
    return dz.System(BODY, parts=[dz.Damper(J, damping_for(0.5))] + (
        [other] if isinstance(other, dz.Wheel) else []),
        torques=[] if isinstance(other, dz.Wheel) else [other])


@pytest.mark.parametrize("other", [
    dz.ConstantTorque((0.0, 0.0, 0.5)),                            # spins the body up
    dz.GravityGradient(2.0),                                       # trades energy with the orbit
    dz.Wheel((0.0, 0.0, 1.0), ([0.0, 2.0], [0.0, -2.0])),          # a wheel spun up against z
])
def test_a_damper_with_anything_that_does_work_runs_at_a_fine_step(other):
    # issue 29's reproducers: the watchdog assumed "a damped body only loses energy" and
    # stopped these at any dt; their energy rises by the work done, the runs are fine
    system = _work_and_damper(other)
    assert "energy_balance" not in system.conserved
    traj = dz.simulate(system, OMEGA0, t_end=4.0, frames=41, dt=1e-3)
    fine = dz.simulate(system, OMEGA0, t_end=4.0, frames=41, dt=5e-4)
    assert traj.energy.max() > traj.energy[0] * (1 + 1e-3)   # the work done: the energy rose
    # and the run converged (RK4: halving the step shrinks the difference 16-fold)
    assert np.abs(traj.omega - fine.omega).max() < 1e-9


def test_a_dampers_energy_balance_is_kept_to_the_runs_error():
    # E + W (the energy plus the work dissipated) is what a damped body keeps: its drift
    # measures the run's error, falling as RK4's fourth order says
    system = dz.System(BODY, parts=[dz.Damper(J, damping_for(0.5))])
    drifts = [dz.simulate(system, OMEGA0 * 20, t_end=2.0, frames=11, dt=dt).drift
              for dt in (4e-3, 2e-3)]
    assert drifts[0].energy > 1e-2                 # the damper's own loss, not an error
    ratio = drifts[0].energy_balance / drifts[1].energy_balance
    assert 12 < ratio < 20, ratio
