"""The methods beyond RK4 against independent references (scipy's DOP853 at rtol 1e-13 and
the exact Jacobi-elliptic ω(t)): orders, the adaptive methods' tolerances and dense output,
the invariants each method keeps, and flips for every method."""

import numpy as np
import pytest
from reference import ExactOmega, ExactOmegaMP, dop853

import dzhanibekov as dz

BODY, OMEGA0, Q0 = (1.0, 1.7, 2.3), np.array([0.4, -0.9, 0.6]), (0.8, 0.1, -0.3, 0.5)
# every fixed-step method of the registry (the atlas's among them)
FIXED = tuple(m for m, info in dz.METHODS.items()
              if info.order is not None and not info.adaptive and "free" in info.models)
"""The fixed-step methods of the free body (splitting_exact runs bodies under torques)."""
ADAPTIVE = ("dopri5", "dop853")


def rate_bound(inertia, omega0):
    """Ω = √(2E / I_min), computed here from its definition."""
    return np.sqrt(np.dot(inertia, np.square(omega0)) / min(inertia))


def frame_error(traj, ref_omega, ref_q, rate):
    """The error the package's accuracy is stated in: ω relative to Ω, q absolute."""
    return max(np.abs(traj.omega - ref_omega).max() / rate, np.abs(traj.q - ref_q).max())


def test_methods_on_offer():
    assert set(dz.METHODS) >= set(FIXED + ADAPTIVE)


@pytest.mark.parametrize("method, order, steps", [
    ("rk4_projected", 4, (0.04, 0.02, 0.01)),
    ("splitting", 2, (0.04, 0.02, 0.01)),
    ("splitting4", 4, (0.04, 0.02, 0.01)),
])
def test_error_ratio_when_the_step_halves_is_two_to_the_order(method, order, steps):
    t = np.linspace(0.0, 10.0, 11)
    ref_omega, ref_q = dop853(BODY, OMEGA0, Q0, t)
    errors = []
    for dt in steps:
        traj = dz.simulate(dz.Body(BODY), OMEGA0, Q0, t_end=10.0, frames=11, dt=dt, method=method)
        errors.append(max(np.abs(traj.omega - ref_omega).max(), np.abs(traj.q - ref_q).max()))
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all(np.abs(np.log2(ratios) - order) < 0.2), (ratios, errors)


CASES = [
    (dz.PAPER_INERTIA, (0.01, 0.1, 0.03)),   # about the minor axis (fig. 3b)
    (dz.PAPER_INERTIA, (0.01, 0.01, 0.03)),  # about the major axis, flipping (fig. 3c)
    (BODY, tuple(OMEGA0)),
    ((3.0, 1.0, 2.0), (-0.3, 0.5, -0.9)),
]


@pytest.mark.parametrize("method", ADAPTIVE)
@pytest.mark.parametrize("inertia, omega0", CASES)
def test_adaptive_methods_meet_their_tolerance(method, inertia, omega0):
    # Local error control keeps each step's error within the tolerance; over five flip
    # periods the global error at the frames — read off the dense output, the frames fall
    # between steps — stays within a small multiple of it, and falls in proportion to it.
    exact = ExactOmega(inertia, omega0)
    t_end = 5 * exact.flip_period
    t = t_end * (np.arange(101) / 100)  # the frame times, exactly
    ref_omega, ref_q = dop853(inertia, np.array(omega0), (1, 0, 0, 0), t)
    rate = rate_bound(inertia, omega0)
    errors = {}
    for rtol in (1e-4, 1e-6, 1e-8, 1e-10, 1e-12):
        traj = dz.simulate(dz.Body(inertia), omega0, t_end=t_end, frames=101, dt=None,
                           method=method, rtol=rtol, atol=1e-3 * rtol)
        assert np.array_equal(traj.t, t)
        errors[rtol] = frame_error(traj, ref_omega, ref_q, rate)
        assert errors[rtol] <= 30 * rtol, (rtol, errors[rtol], traj)
    # tolerance proportionality: 10⁻⁴ in tolerance buys about 10⁻⁴ in error
    assert 1e3 < errors[1e-6] / errors[1e-10] < 1e5, errors


@pytest.mark.parametrize("method", ADAPTIVE)
def test_many_frames_per_step_are_interpolated_accurately(method):
    # at rtol 1e-10 DOP853 takes a few steps per flip period: most of the 2001 frames lie
    # inside steps, on the interpolant
    inertia, omega0 = dz.PAPER_INERTIA, (0.01, 0.1, 0.03)
    t = np.linspace(0.0, 100.0, 2001)
    ref_omega, ref_q = dop853(inertia, np.array(omega0), (1, 0, 0, 0), t)
    traj = dz.simulate(dz.Body(inertia), omega0, t_end=100.0, frames=2001, dt=None,
                       method=method, rtol=1e-10, atol=1e-13)
    assert traj.n_steps < 2000
    assert frame_error(traj, ref_omega, ref_q, rate_bound(inertia, omega0)) < 1e-9
    assert traj.dt == pytest.approx(100.0 / traj.n_steps)


def test_adaptive_counters():
    traj = dz.simulate(dz.Body(dz.PAPER_INERTIA), (0.01, 0.01, 1.0), t_end=100.0, dt=None,
                       method="dop853", rtol=1e-8)
    assert traj.n_steps > 0 and traj.n_rejected >= 0
    assert traj.nfev >= 1 + 12 * (traj.n_steps + traj.n_rejected)
    assert dz.simulate(dz.Body(dz.PAPER_INERTIA), (0.01, 0.01, 1.0), t_end=1.0).n_rejected == 0


@pytest.mark.parametrize("method, steps", [("splitting", 10**6), ("splitting4", 2 * 10**5)])
def test_splitting_keeps_momentum_and_its_energy_error_does_not_grow(method, steps):
    body, omega0 = dz.Body(dz.PAPER_INERTIA), (0.01, 0.1, 0.03)
    # |L|, |q| and L_world: kept to round-off however long the run (the target is
    # 1e-13 relative for |L|; the bench measures 10⁷ steps)
    run = dz.simulate(body, omega0, t_end=steps * 0.01, frames=1001, dt=0.01, method=method,
                      flips=False)
    l_norm = np.linalg.norm(run.invariants()["momentum_body"], axis=1)
    assert np.abs(l_norm / l_norm[0] - 1).max() < 1e-14
    assert run.drift.momentum < 1e-14 and run.drift.q_norm < 1e-14
    assert run.drift.momentum_world < 1e-12
    # the energy error is bounded: over ten times the run it is no larger than over the
    # first tenth, at a coarse step (dt·Ω ≈ 0.05) where it is well above round-off
    short = dz.simulate(body, omega0, t_end=2e3, frames=201, dt=0.5, method=method, flips=False)
    long = dz.simulate(body, omega0, t_end=2e4, frames=2001, dt=0.5, method=method, flips=False)
    assert 1e-12 < long.drift.energy < 1.5 * short.drift.energy, (short.drift, long.drift)
    # RK4's, at the same step, grows with the run
    rk4_short = dz.simulate(body, omega0, t_end=2e3, frames=201, dt=0.5, flips=False)
    rk4_long = dz.simulate(body, omega0, t_end=2e4, frames=2001, dt=0.5, flips=False)
    assert rk4_long.drift.energy > 5 * rk4_short.drift.energy


def test_projected_rk4_keeps_every_invariant_that_rk4_loses():
    body, omega0 = dz.Body(dz.PAPER_INERTIA), (0.01, 0.1, 0.03)
    plain = dz.simulate(body, omega0, t_end=2e3, frames=101, dt=0.4, flips=False)
    projected = dz.simulate(body, omega0, t_end=2e3, frames=101, dt=0.4, flips=False,
                            method="rk4_projected")
    assert min(plain.drift) > 1e-11, plain.drift
    assert max(projected.drift) < 1e-13, projected.drift
    # the phase error along the polhode remains: ω is no closer to the truth than RK4's
    t = projected.t
    ref_omega, _ = dop853(dz.PAPER_INERTIA, np.array(omega0), (1, 0, 0, 0), t)
    err_plain = np.abs(plain.omega - ref_omega).max()
    err_projected = np.abs(projected.omega - ref_omega).max()
    assert 0.1 * err_plain < err_projected < 10 * err_plain


def rk4_energy_change(inertia, omega, h):
    """The relative change of the energy over one classic RK4 step of Euler's equations
    (written here) from each row of `omega`."""
    i1, i2, i3 = inertia

    def f(w):
        u, v, x = w.T
        return np.stack([(i2 - i3) / i1 * v * x, (i3 - i1) / i2 * u * x,
                         (i1 - i2) / i3 * u * v], axis=1)

    k1 = f(omega)
    k2 = f(omega + 0.5 * h * k1)
    k3 = f(omega + 0.5 * h * k2)
    k4 = f(omega + h * k3)
    after = omega + h / 6 * (k1 + 2 * (k2 + k3) + k4)
    return np.abs(np.sum(inertia * after**2, axis=1) / np.sum(inertia * omega**2, axis=1) - 1)


@pytest.mark.parametrize("h_rate", [1.0, 1.73, 2.5])
def test_projected_rk4_at_large_steps_keeps_the_invariants_to_the_square_of_rk4s_change(h_rate):
    # The docs: one Gauss–Newton step leaves the square of RK4's relative drift per step, at
    # most ((dt·Ω)⁵/120)², round-off only for small steps. Measured from the frames (one a
    # step), against RK4's energy change per step from the same states, computed here.
    inertia = np.array(BODY)
    dt = h_rate / rate_bound(inertia, OMEGA0)
    steps = 400
    with pytest.warns(dz.StepSizeWarning):
        run = dz.simulate(BODY, OMEGA0, Q0, t_end=steps * dt, frames=steps + 1, dt=dt,
                          method="rk4_projected", flips=False)
    energy = np.sum(inertia * run.omega**2, axis=1)
    l_norm = np.linalg.norm(inertia * run.omega, axis=1)
    drift_energy = np.abs(energy / energy[0] - 1).max()
    drift_momentum = np.abs(l_norm / l_norm[0] - 1).max()
    delta = rk4_energy_change(inertia, run.omega, dt).max()
    assert max(drift_energy, drift_momentum) <= (h_rate**5 / 120) ** 2
    assert max(drift_energy, drift_momentum) <= delta**2, (drift_energy, delta**2)
    # and at these steps it is not round-off, as the docs say, but it does not grow with
    # the run: each step projects onto the invariants of the start
    assert drift_energy > 1e-12
    with pytest.warns(dz.StepSizeWarning):
        longer = dz.simulate(BODY, OMEGA0, Q0, t_end=10 * steps * dt, frames=10 * steps + 1,
                             dt=dt, method="rk4_projected", flips=False)
    assert longer.drift.energy < 1.5 * run.drift.energy
    # |q| and the direction of L_world stay at round-off at any step
    assert run.drift.q_norm < 1e-14


@pytest.mark.parametrize("method", FIXED + ADAPTIVE)
@pytest.mark.parametrize("inertia, omega0", [
    (dz.PAPER_INERTIA, (0.01, 0.01, 1.0)),
    ((1.0, 2.0, 3.0), (0.05, 1.0, 0.3)),
])
def test_every_method_locates_the_flips(method, inertia, omega0):
    exact = ExactOmega(inertia, omega0)
    t_end = 6.5 * exact.flip_period
    # sn(λt + u0) vanishes at λt + u0 = 2Kk: the flips, exactly
    k = np.arange(1, 20)
    zeros = (k * exact.flip_period * exact.lam - exact.u_start) / exact.lam
    zeros = zeros[(zeros > 0) & (zeros < t_end)]
    rtol = 1e-6
    traj = dz.simulate(dz.Body(inertia), omega0, t_end=t_end, frames=11, dt=None,
                       method=method, rtol=rtol)
    assert len(traj.flip_times) == len(zeros) >= 5, (traj.flip_times, zeros)
    # (Crouch–Grossman 3's energy drifts at O(h³) with the largest constant of the atlas, and
    # near the separatrix the flip period follows the energy: on the paper's orbit its flips
    # are off by 48·rtol periods at any rtol, measured; the step rule promises rtol away from
    # the separatrix only)
    factor = 100 if method == "crouch_grossman3" else 10
    np.testing.assert_allclose(traj.flip_times, zeros, rtol=0,
                               atol=factor * rtol * exact.flip_period)


@pytest.mark.parametrize("method", ADAPTIVE)
@pytest.mark.parametrize("rtol", [1e-12, None])
def test_flips_just_past_the_dominance_threshold_are_found_by_the_adaptive_methods(method, rtol):
    # |L2| exceeds |L|/√2 by 5e-5 at the peaks of ω2 only: a long adaptive step spans each
    # stretch of dominance without its ends seeing it (dop853 at rtol=1e-12 found 3 of 36)
    inertia, omega0, t_end = (1.0, 2.0, 3.0), (0.0, 0.75 * (1 + 1e-4), 0.5), 200.0
    period = ExactOmegaMP(inertia, omega0).flip_period  # 2K(m)/λ in mpmath
    # ω1(0) = 0 puts ω2 at its peak, u0 = K: ω2 ∝ sn vanishes at t = (2j − 1)·P/2, and each
    # zero is a flip once ω2 peaks on the other side, P/2 later
    zeros = (2 * np.arange(1, 200) - 1) * period / 2
    flips = zeros[zeros + period / 2 <= t_end]
    assert np.min(np.abs(zeros + period / 2 - t_end)) > 0.05 * period  # no flip at the edge
    run = dz.summarize(inertia, omega0, t_end=t_end, method=method, dt=None, rtol=rtol)
    assert len(run.flip_times) == len(flips) > 30
    np.testing.assert_allclose(run.flip_times, flips, rtol=0, atol=1e-6 * period)
