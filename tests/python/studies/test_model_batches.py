"""Batches and sweeps of bodies that change, and the stiff damper's warning, against what the
code cannot fake: each row's own single run (bit for bit), conserved quantities, an
independent `solve_ivp` of the deployment law written here, RK4's stability polynomial."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import dzhanibekov as dz

STOWED = (1.0, 2.0, 3.0)
BODY = (10.0, 9.5, 1.0)
DAMPER = dz.Damper(0.05, 0.02)
TILTED = dz.Body.from_tensor([[10.0, 0.3, 0.0], [0.3, 9.5, -0.2], [0.0, -0.2, 1.0]])


def damped(body, damper=DAMPER):
    """`body` (a Body or its moments) with `damper`."""
    return dz.System(body, parts=[damper])


def assert_same_run(row: dz.Trajectory, single: dz.Trajectory) -> None:
    """Bit for bit: frames, parts' state, invariants, cost, drift, system."""
    for name in ("t", "omega", "q", "momentum_world", "energy", "flip_times"):
        np.testing.assert_array_equal(getattr(row, name), getattr(single, name), err_msg=name)
    np.testing.assert_array_equal(row.invariants()["momentum_body"],
                                  single.invariants()["momentum_body"])
    assert row.parts.keys() == single.parts.keys()
    for name in single.parts:
        np.testing.assert_array_equal(row.parts[name], single.parts[name])
    assert (row.dt, row.n_steps, row.nfev, row.n_rejected, row.drift) == \
        (single.dt, single.n_steps, single.nfev, single.n_rejected, single.drift)
    assert row.system == single.system


# -- batches -----------------------------------------------------------------------------


@pytest.mark.parametrize("method, kw", [("rk4", dict(dt=1e-3)),
                                        ("dop853", dict(rtol=1e-10, atol=1e-12))])
def test_deployment_batch_rows_are_their_single_runs(method, kw):
    deployments = [dz.Deployment([5.0, 15.0], [STOWED, (1.0, 3.0, r)]) for r in (2.0, 4.0)]
    deployments.append(dz.Deployment([2.0, 6.0], [np.diag(STOWED),
                                                  [[5.0, 0.4, -0.2], [0.4, 3.5, 0.0],
                                                   [-0.2, 0.0, 2.5]]]))
    omega0 = np.array([[0.01, 0.01, 1.0], [0.2, -0.1, 0.9], [0.3, -0.7, 1.1]])
    q0 = np.array([[1.0, 0.0, 0.0, 0.0], [0.5, -0.1, 0.7, 0.2], [0.0, 1.0, 0.0, 0.0]])
    common = dict(t_end=30.0, frames=61, method=method, **kw)
    batch = dz.simulate(deployments, omega0, q0, **common)
    assert isinstance(batch, dz.Batch) and len(batch) == 3
    assert batch.momentum_world.shape == (3, 61, 3) and batch.energy.shape == (3, 61)
    assert batch.flip_times is not None  # located for every tensor, diagonal or not
    for i, d in enumerate(deployments):
        assert_same_run(batch[i], dz.simulate(d, omega0[i], q0[i], **common))
    # one deployment, a batch of starts
    shared = dz.simulate(deployments[0], omega0, **common)
    for i in range(3):
        assert_same_run(shared[i], dz.simulate(deployments[0], omega0[i], **common))
    # and every row keeps its angular momentum in space while its energy changes
    l0 = np.linalg.norm(batch.momentum_world[:, :1], axis=2, keepdims=True)
    tol = 1e-10 if method == "rk4" else 1e-8
    assert (np.abs(batch.momentum_world - batch.momentum_world[:, :1]) < tol * l0).all()
    assert (batch.drift.energy > 1e-3).all()


def test_a_batch_of_diagonal_deployments_locates_each_runs_flips():
    deployments = [dz.Deployment([10.0, 20.0], [STOWED, (1.0, 3.0, r)]) for r in (2.0, 4.0)]
    common = dict(t_end=120.0, frames=13, dt=1e-3)
    batch = dz.simulate(deployments, (0.01, 0.01, 1.0), **common)
    assert batch.flip_times is not None
    for i, d in enumerate(deployments):
        single = dz.simulate(d, (0.01, 0.01, 1.0), **common)
        np.testing.assert_array_equal(batch.flip_times[i], single.flip_times)
        np.testing.assert_array_equal(batch[i].flip_times, single.flip_times)
    assert batch.flips[0] > 0 and batch.flips[1] == 0  # z intermediate, then major
    # a run whose tensors are not diagonal has them located too, each as its single run
    tilted = dz.Deployment([1.0, 2.0], [np.diag(STOWED), TILTED.tensor])
    mixed = dz.simulate([deployments[0], tilted], (0.01, 0.01, 1.0), **common)
    single = dz.simulate(tilted, (0.01, 0.01, 1.0), **common)
    assert single.flip_times is not None
    np.testing.assert_array_equal(mixed[1].flip_times, single.flip_times)


@pytest.mark.parametrize("method, kw", [("rk4", dict(dt=2e-3)), ("rk4", {}),
                                        ("dopri5", dict(rtol=1e-10, atol=1e-12))])
def test_damper_batch_rows_are_their_single_runs(method, kw):
    bodies = [dz.Body(BODY), TILTED, dz.Body(BODY)]
    omega0 = np.array([[0.1, 0.05, 2.0], [0.01, 0.0, 2.0], [0.3, 0.2, 1.0]])
    sigma0 = np.array([[0.0, 0.2, 1.5], [0.0, 0.0, 2.0], [0.3, 0.2, 1.0]])
    dampers = [dz.Damper(0.05, 0.02, sigma0[0]), dz.Damper(0.1, 0.05, sigma0[1]),
               dz.Damper(0.05, 0.02, sigma0[2])]
    systems = [damped(b, d) for b, d in zip(bodies, dampers)]
    common = dict(t_end=100.0, frames=51, method=method, **kw)
    batch = dz.simulate(systems, omega0, **common)
    assert batch.parts["damper"].shape == (3, 51, 3)
    if not kw:  # dt=None: every row takes the smallest of the steps its runs would pick
        alone = [dz.simulate(s, w, **common).dt for s, w in zip(systems, omega0)]
        np.testing.assert_array_equal(batch.dt, min(alone))
        common["dt"] = float(batch.dt[0])
    for i in range(3):
        single = dz.simulate(systems[i], omega0[i], **common)
        if kw or i == int(np.argmin(alone)):  # the run that set the step is itself
            assert_same_run(batch[i], single)
    # one damped body, a batch of starts with co-rotating spheres
    shared = dz.simulate(damped(BODY), omega0[:2], t_end=50.0, frames=11, dt=2e-3)
    for i in range(2):
        assert_same_run(shared[i], dz.simulate(damped(BODY), omega0[i], t_end=50.0,
                                               frames=11, dt=2e-3))
    assert shared[1:].parts["damper"].shape == (1, 11, 3)


def test_damper_batch_physics_per_row():
    omega0 = np.array([[0.01, 0.0, 2.0], [0.02, 0.01, 2.0], [0.2, 0.001, 0.001]])
    batch = dz.simulate(damped(BODY), omega0, t_end=3000.0, frames=301, dt=2e-3, threads=2)
    l0 = np.linalg.norm(batch.momentum_world[:, 0], axis=1)
    assert (np.linalg.norm(batch.momentum_world - batch.momentum_world[:, :1], axis=2).max(1)
            < 1e-9 * l0).all()
    assert (np.diff(batch.energy, axis=1) <= 1e-13 * batch.energy[:, :1]).all()
    # every row ends spinning about the major axis x
    assert (np.abs(dz.axis_shares(batch[0])[-1, 0]) > 0.999)
    assert all(abs(dz.axis_shares(batch[i])[-1, 0]) > 0.999 for i in range(3))


def test_free_batches_report_momentum_world_and_energy():
    omega0 = np.array([[0.1, 0.2, 1.0], [1.0, 0.0, 0.01]])
    batch = dz.simulate(TILTED, omega0, t_end=10.0, frames=11, dt=1e-3)
    for i in range(2):
        single = dz.simulate(TILTED, omega0[i], t_end=10.0, frames=11, dt=1e-3)
        np.testing.assert_array_equal(batch.momentum_world[i], single.momentum_world)
        np.testing.assert_array_equal(batch.energy[i], single.energy)


def test_model_batch_errors_name_the_row():
    omega0 = np.array([[0.01, 0.0, 0.2], [0.01, 0.0, 0.2]])
    systems = [damped(BODY), damped(BODY, dz.Damper(0.01, 500.0))]  # row 1: λ h ≫ 2.79
    with pytest.warns(dz.StiffDamperWarning, match="row 1: the damper is stiff"):
        with pytest.raises(dz.DivergedError) as info:
            dz.simulate(systems, omega0, t_end=10.0, frames=3, dt=1e-2)
    assert info.value.row == 1
    with pytest.raises(ValueError, match="must match or be absent"):
        dz.simulate([damped(BODY)] * 3, omega0, t_end=1.0)
    with pytest.raises(TypeError, match=r"`parts\[0\]`"):
        dz.System(BODY, parts=[0.5])  # type: ignore[list-item]
    with pytest.raises(ValueError, match="systems of one kind"):
        dz.simulate([damped(BODY), dz.Body(BODY)], omega0)


# -- which deployments tumble -------------------------------------------------------------


def smootherstep(tau):
    """The documented law, written out here: s = 10τ³ − 15τ⁴ + 6τ⁵."""
    tau = np.clip(tau, 0.0, 1.0)
    return 10 * tau**3 - 15 * tau**4 + 6 * tau**5


def reference_tumbles(stowed, deployed, t0, t1, omega0, watch):
    """`dL/dt = L × I(t)⁻¹ L` by `solve_ivp`, through the deployment and `watch` time units of
    the free motion after it: the body tumbles iff the intermediate axis of the deployed
    body, at the instants it carries most of |L|, points both ways along L (a sign change
    of its rate there). Returns (tumbles, relative energy change)."""
    a, b = np.diag(stowed), np.diag(deployed)

    def inertia(t):
        return a + smootherstep((t - t0) / (t1 - t0)) * (b - a)

    def rhs(t, l):
        return np.cross(l, np.linalg.solve(inertia(t), l))

    l0 = a @ np.asarray(omega0)
    t = np.linspace(0.0, t1 + watch, 40001)
    sol = solve_ivp(rhs, (0.0, t[-1]), l0, t_eval=t, rtol=1e-11, atol=1e-13, method="DOP853")
    after = sol.y[:, t >= t1].T
    middle = int(np.argsort(deployed)[1])
    leads = np.abs(after[:, middle]) >= np.abs(after).max(axis=1)
    signs = np.sign(after[leads, middle])
    energy = [0.5 * l @ np.linalg.solve(inertia(s), l) for s, l in ((0.0, l0), (t[-1], after[-1]))]
    return bool(len(np.unique(signs)) > 1), energy[1] / energy[0] - 1


def test_which_deployments_tumble_against_an_independent_reference():
    # stowed (1, 2, 3) spun about z, deployed over [10, 20] to (1, 3, r): z intermediate for
    # r < 3 (it tumbles), major for r > 3 (it does not); and (1, 2, 4), z still major
    deployed = [(1.0, 3.0, 2.0), (1.0, 3.0, 2.6), (1.0, 3.0, 3.4), (1.0, 3.0, 4.0),
                (1.0, 2.0, 4.0)]
    deployments = [dz.Deployment([10.0, 20.0], [STOWED, d]) for d in deployed]
    omega0 = (0.01, 0.01, 1.0)
    s = dz.sweep(deployments, omega0, t_end=20.0, frames=2, dt=1e-3)
    assert isinstance(s, dz.DeploymentSweep) and s.shape == (5,) and s.ok.all()
    assert s.tumbles.tolist() == [True, True, False, False, False]
    assert np.isfinite(s.flip_period[:2]).all() and np.isinf(s.flip_period[2:]).all()
    for k, d in enumerate(deployed):
        tumbles, change = reference_tumbles(STOWED, d, 10.0, 20.0, omega0, watch=400.0)
        assert tumbles == s.tumbles[k], d
        assert s.energy_change[k] == pytest.approx(change, rel=1e-6, abs=1e-9)
        # the deployed body's principal moments, about the axes nearest x, y, z
        assert list(d) == s.inertia[k].tolist()
    assert s.verdict[0].startswith("tumbles: a flip every") and s.verdict[3] == "does not tumble"


def test_deployment_sweep_runs_are_their_single_runs():
    deployments = [dz.Deployment([1.0, 1.0 + dur], [STOWED, (1.0, 3.0, 2.0)])
                   for dur in (1.0, 5.0, 20.0)]
    s = dz.sweep(deployments, (0.01, 0.01, 1.0), t_end=25.0, frames=6, dt=1e-3, block=2)
    for k, d in enumerate(deployments):
        single = dz.simulate(d, (0.01, 0.01, 1.0), t_end=25.0, frames=6, dt=1e-3)
        assert (s.n_steps[k], s.dt[k]) == (single.n_steps, single.dt)
        assert s.energy_change[k] == (single.energy[-1] - single.energy[0]) / single.energy[0]
        body = dz.Body(np.diag(d.tensors[-1]))
        assert s.flip_period[k] == pytest.approx(dz.flip_period(body, single.omega[-1]),
                                                 rel=1e-12)
    assert (s[1:].flip_period == s.flip_period[1:]).all() and len(s[0]) == 1
    assert s.tumbles.all()  # z ends intermediate however fast it got there


def test_deployment_sweep_statuses_and_bad_input():
    deployments = [dz.Deployment([1.0, 2.0], [STOWED, (1.0, 3.0, 2.0)])] * 2
    omega0 = np.array([[0.01, 0.01, 1.0], [0.01, 0.01, 40.0]])  # row 1: dt·Ω = 40
    with pytest.warns(dz.StepSizeWarning, match="row 1: .*stability limit"):
        s = dz.sweep(deployments, omega0, t_end=4.0, frames=2, dt=1.0)
    assert s.status.tolist() == ["ok", "diverged"] and s.ok.tolist() == [True, False]
    assert np.isnan(s.flip_period[1]) and not s.tumbles[1]
    assert s.verdict[1] == "did not finish (diverged)"
    with pytest.raises(ValueError, match="`t_end` must reach the last knot"):
        dz.sweep(deployments, omega0, t_end=1.5)
    with pytest.raises(ValueError, match="`client`"):
        dz.sweep(deployments, omega0, t_end=4.0, client=object())


# -- stiff dampers --------------------------------------------------------------------------


def rk4_real_limit() -> float:
    """Where RK4's amplification |1 + z + z²/2 + z³/6 + z⁴/24| = 1 on the negative real axis."""
    roots = np.roots([1 / 24, 1 / 6, 1 / 2, 1.0, 0.0])  # R(z) − 1 = z (…)
    real = roots[np.abs(roots.imag) < 1e-12].real
    return float(-real[real < 0].min() if (real < 0).any() else np.nan)


@pytest.mark.parametrize("factor", [0.9, 0.99, 1.01, 1.1])
def test_stiff_damper_warns_exactly_beyond_rk4s_limit(factor):
    # a slow body (|ω| < 1) and a damper of rate λ = c (1/j + 1/I_min) at `factor` times the
    # limit for the step 0.01: the slip's mode is multiplied by R(−hλ) per step
    limit = rk4_real_limit()
    assert limit == pytest.approx(2.785293563, abs=1e-9)
    j, h = 0.1, 0.01
    c = factor * limit / h / (1 / j + 1 / STOWED[0])
    run = dict(t_end=50.0, frames=51, dt=h)
    system = damped(STOWED, dz.Damper(j, c))
    if factor < 1:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            traj = dz.simulate(system, (0.3, 0.2, 0.5), **run)
        assert np.diff(traj.energy).max() <= 0  # the damper only dissipates
        return
    with pytest.warns(dz.StiffDamperWarning, match=r"stiff for the step 0.01.*diverges"):
        try:
            traj = dz.simulate(system, (0.3, 0.2, 0.5), **run)
        except dz.DivergedError:
            return
    assert np.diff(traj.energy).max() > 0  # energy from nowhere: RK4 unstable


def test_stiff_damper_warns_where_an_adaptive_run_crawls():
    # Ω of the undamped start; the damper's rate λ against it, for dopri5 and dop853
    body, omega0, j = np.array(STOWED), np.array([0.3, 0.2, 0.5]), 0.1
    omega_bound = np.sqrt((omega0 @ (body * omega0) + j * omega0 @ omega0) / body.min())
    for method in ("dopri5", "dop853"):
        base = dz.simulate(damped(STOWED, dz.Damper(j, 0.0)), omega0, t_end=50.0, frames=51,
                           method=method).n_steps
        steps = {}
        for ratio in (3.0, 10.0, 100.0, 1000.0):
            c = ratio * omega_bound / (1 / j + 1 / body.min())
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                traj = dz.simulate(damped(STOWED, dz.Damper(j, c)), omega0, t_end=50.0,
                                   frames=51, method=method)
            warned = any(issubclass(w.category, dz.StiffDamperWarning) for w in caught)
            assert warned == (ratio > dz.damper.STIFF_RATIO), (method, ratio)
            steps[ratio] = traj.n_steps
        # unwarned: steps set by the motion; warned: set by the damper, growing with λ
        assert steps[3.0] < 1.5 * base and steps[10.0] < 2.5 * base
        assert steps[100.0] > 3 * base and steps[1000.0] > 5 * steps[100.0]


def test_the_shipped_damper_scene_is_not_stiff():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        traj = dz.SCENES["explorer-1"].run()
    assert traj.dt * dz.damper.damper_rate(dz.SCENES["explorer-1"].inertia,
                                           dz.SCENES["explorer-1"].damper) < 0.01
