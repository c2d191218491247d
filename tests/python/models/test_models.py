"""Deployments and dampers against what the code cannot fake: the constant body's own run,
conserved quantities, independent `solve_ivp` runs of the same laws written here, the energy
balance, the major-axis rule, the energy-sink estimate."""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation
import pytest
from scipy.integrate import simpson, solve_ivp

import dzhanibekov as dz

STOWED, DEPLOYED = (1.0, 2.0, 3.0), (1.0, 3.0, 2.0)


def smootherstep(tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The documented law, written out here: s = 10τ³ − 15τ⁴ + 6τ⁵ and ds/dτ."""
    tau = np.clip(tau, 0.0, 1.0)
    return 10 * tau**3 - 15 * tau**4 + 6 * tau**5, 30 * tau**2 * (1 - tau) ** 2


def tensor_and_rate(t: float, t0: float, t1: float, a: np.ndarray, b: np.ndarray):
    s, ds = smootherstep(np.asarray((t - t0) / (t1 - t0)))
    return a + s * (b - a), ds / (t1 - t0) * (b - a)


A = np.array([[2.0, -0.3, 0.1], [-0.3, 3.0, 0.2], [0.1, 0.2, 4.0]])
B = np.array([[5.0, 0.4, -0.2], [0.4, 3.5, 0.0], [-0.2, 0.0, 2.5]])


def test_equal_knots_are_the_constant_body():
    moments = (52.0833, 27.0833, 41.6666)
    d = dz.Deployment([1.0, 2.0, 5.0], [moments, dz.Body(moments), np.diag(moments)])
    kw = dict(t_end=50.0, frames=101, dt=1e-3)
    deployed = dz.simulate(d, (0.01, 0.01, 1.0), **kw)
    constant = dz.simulate(moments, (0.01, 0.01, 1.0), **kw)
    # the paper's run crosses the separatrix: round-off grown by the motion's sensitivity
    np.testing.assert_allclose(deployed.omega, constant.omega, rtol=0, atol=1e-9)
    np.testing.assert_allclose(deployed.q, constant.q, rtol=0, atol=1e-9)
    np.testing.assert_allclose(deployed.energy, constant.energy, rtol=1e-11)
    np.testing.assert_allclose(deployed.momentum_world, constant.momentum_world, atol=1e-11)


@pytest.mark.parametrize("method, kw", [("rk4", dict(dt=1e-4)),
                                        ("dop853", dict(dt=None, rtol=1e-13, atol=1e-15)),
                                        ("rk4_projected", dict(dt=1e-2))])
def test_deployment_keeps_momentum_world(method, kw):
    d = dz.Deployment([2.0, 6.0], [A, B])
    traj = dz.simulate(d, (0.3, -0.7, 1.1), q0=(0.5, -0.1, 0.7, 0.2), t_end=20.0, frames=201,
                       method=method, **kw)
    l0 = np.linalg.norm(traj.momentum_world[0])
    assert np.abs(traj.momentum_world - traj.momentum_world[0]).max() < 1e-12 * l0
    assert traj.drift.momentum_world < 1e-12
    assert traj.drift.energy > 0.01  # the energy is not kept: the deployment works


def deployment_reference(t_eval, omega0):
    """`dL/dt = L × I⁻¹ L` with the tensor law of this file, by `solve_ivp`."""
    def rhs(t, l):
        inertia, _ = tensor_and_rate(t, 2.0, 6.0, A, B)
        return np.cross(l, np.linalg.solve(inertia, l))
    l0 = A @ np.asarray(omega0)
    sol = solve_ivp(rhs, (0, t_eval[-1]), l0, t_eval=t_eval, rtol=1e-12, atol=1e-14,
                    method="DOP853")
    return sol.y.T


def test_energy_change_is_the_internal_work():
    d = dz.Deployment([2.0, 6.0], [A, B])
    omega0 = (0.3, -0.7, 1.1)
    traj = dz.simulate(d, omega0, t_end=8.0, frames=2001, method="dop853", dt=None,
                       rtol=1e-12, atol=1e-14)
    # dE/dt = −½ ωᵀ İ ω: integrate it over the frames (Simpson) with İ from this file's law
    rate = np.array([-0.5 * w @ tensor_and_rate(t, 2.0, 6.0, A, B)[1] @ w
                     for t, w in zip(traj.t, traj.omega)])
    work = simpson(rate, x=traj.t)
    assert abs(work) > 0.05 * traj.energy[0]
    assert traj.energy[-1] - traj.energy[0] == pytest.approx(work, rel=1e-7)
    # and the independent reference of the same law gives the same momenta and energy
    l_ref = deployment_reference(traj.t, omega0)
    np.testing.assert_allclose(traj.invariants()["momentum_body"], l_ref, rtol=0, atol=1e-8)
    inertia_end, _ = tensor_and_rate(8.0, 2.0, 6.0, A, B)
    e_ref = 0.5 * l_ref[-1] @ np.linalg.solve(inertia_end, l_ref[-1])
    assert traj.energy[-1] == pytest.approx(e_ref, rel=1e-9)


def test_stowed_major_axis_spin_flips_once_deployed():
    # stowed (1, 2, 3): z is the major axis; deployed (1, 3, 2): z is intermediate
    d = dz.Deployment([100.0, 110.0], [STOWED, DEPLOYED])
    traj = dz.simulate(d, (0.01, 0.01, 1.0), t_end=300.0, frames=3001, dt=1e-3)
    share_z = dz.axis_shares(traj)[:, 2]
    assert share_z[traj.t <= 100.0].min() > 0.999  # no flip before
    assert share_z[traj.t >= 110.0].min() < -0.9  # turned over after
    # the same spin without the deployment never flips
    stowed = dz.simulate(STOWED, (0.01, 0.01, 1.0), t_end=300.0, frames=3001, dt=1e-3)
    assert stowed.flip_times is not None and len(stowed.flip_times) == 0


BODY = (10.0, 9.5, 1.0)
DAMPER = dz.Damper(0.05, 0.02)


def damper_reference(t_eval, inertia, j, c, omega0, sigma0):
    """The damper's equations as written in Hughes' form: the total momentum H = Iω + jσ
    obeys H' = H × ω, and the sphere j(σ' + ω × σ) = −c(σ − ω)."""
    inertia = np.asarray(inertia, dtype=float)

    def rhs(t, y):
        w, s = y[:3], y[3:]
        sigma_dot = -np.cross(w, s) - c / j * (s - w)
        h_dot = np.cross(inertia @ w + j * s, w)
        omega_dot = np.linalg.solve(inertia, h_dot - j * sigma_dot)
        return np.concatenate([omega_dot, sigma_dot])

    sol = solve_ivp(rhs, (0, t_eval[-1]), np.concatenate([omega0, sigma0]), t_eval=t_eval,
                    rtol=1e-12, atol=1e-14, method="DOP853")
    return sol.y.T


@pytest.mark.parametrize("method", ["rk4", "dop853"])
def test_damper_matches_an_independent_reference(method):
    omega0, sigma0 = np.array([0.1, 0.05, 2.0]), np.array([0.0, 0.2, 1.5])
    tol = dict(dt=None, rtol=1e-12, atol=1e-14) if method == "dop853" else dict(dt=2e-3)
    damped = dz.System(dz.Body(BODY), parts=[dz.Damper(0.05, 0.02, sigma0=sigma0)])
    traj = dz.simulate(damped, omega0, t_end=200.0, frames=201, method=method, **tol)
    ref = damper_reference(traj.t, np.diag(BODY), 0.05, 0.02, omega0, sigma0)
    np.testing.assert_allclose(traj.omega, ref[:, :3], rtol=0, atol=1e-8)
    np.testing.assert_allclose(traj.parts["damper"], ref[:, 3:], rtol=0, atol=1e-8)


def test_damper_goes_flat_about_the_major_axis():
    traj = dz.simulate(dz.System(BODY, parts=[DAMPER]), (0.01, 0.0, 2.0), t_end=4000.0,
                       frames=4001, dt=2e-3)
    l0 = np.linalg.norm(traj.momentum_world[0])
    assert np.abs(traj.momentum_world - traj.momentum_world[0]).max() < 1e-9 * l0
    assert np.diff(traj.energy).max() <= 1e-13 * traj.energy[0]  # never rises
    assert traj.energy[-1] < 0.2 * traj.energy[0]
    shares = dz.axis_shares(traj)
    assert abs(shares[-1, 0]) > 0.9999  # x: the major axis
    # the sphere ends co-rotating: nothing left to dissipate
    slip = np.linalg.norm(traj.parts["damper"] - traj.omega, axis=1)
    assert slip[-1] < 1e-3 * slip.max()
    # the end state's energy is the major-axis spin's at the same |H| (moment Ix + j)
    assert traj.energy[-1] == pytest.approx(l0**2 / (2 * (BODY[0] + DAMPER.inertia)), rel=1e-6)


def test_damped_major_axis_spin_stays():
    damped = dz.System(BODY, parts=[dz.Damper(0.05, 0.02, sigma0=(0.2, 0.0, 0.0))])
    traj = dz.simulate(damped, (0.2, 0.001, 0.001), t_end=2000.0, frames=201,
                       method="dopri5", dt=None, rtol=1e-12, atol=1e-14)
    assert np.abs(dz.axis_shares(traj)[:, 0]).min() > 0.9999
    # and its nutation dies out
    assert np.linalg.norm(traj.omega[-1, 1:]) < 0.02 * np.linalg.norm(traj.omega[0, 1:])


def test_time_to_flat_spin_against_the_energy_sink_estimate():
    # a symmetric top (Explorer 1: a spin about the long, minor axis); the estimate holds for
    # a damper small against the body (j = 0.05 against moments 1 and 10)
    body, omega0 = (1.0, 10.0, 10.0), (2.0, 0.01, 0.0)
    traj = dz.simulate(dz.System(body, parts=[DAMPER]), omega0, t_end=3000.0, frames=3001,
                       dt=5e-3)
    measured = dz.flat_spin_time(traj)
    estimate = dz.flat_spin_estimate(body, DAMPER, omega0)
    assert measured == pytest.approx(estimate, rel=0.01)
    assert dz.flat_spin_estimate(body, dz.Damper(0.05, 0.0), omega0) == np.inf


def _flat_reference(moments, damper, omega0, t_end, share=0.99):
    """The first time the major axis carries `share` of |H|, by scipy's DOP853 (rtol 1e-12)
    of the damper's equations as documented, I ω' = I ω × ω + c (σ − ω),
    j σ' = j σ × ω − c (σ − ω), with an event on |H_major|² − share² |H|², H = I ω + j σ."""
    i1, i2, i3 = (float(m) for m in moments)
    j, c = damper.inertia, damper.damping
    major = int(np.argmax(moments))

    def rhs(_t, y):
        # in plain floats: numpy's per-call overhead would dominate the reference
        u, v, w, a, b, d = y
        sx, sy, sz = c * (a - u), c * (b - v), c * (d - w)
        return [((i2 - i3) * v * w + sx) / i1, ((i3 - i1) * w * u + sy) / i2,
                ((i1 - i2) * u * v + sz) / i3,
                b * w - d * v - sx / j, d * u - a * w - sy / j, a * v - b * u - sz / j]

    def flat(_t, y):
        h = np.array([i1 * y[0] + j * y[3], i2 * y[1] + j * y[4], i3 * y[2] + j * y[5]])
        return h[major] ** 2 - share**2 * (h @ h)

    flat.terminal, flat.direction = True, 1.0
    sol = solve_ivp(rhs, (0.0, t_end), np.concatenate([omega0, omega0]), method="DOP853",
                    rtol=1e-12, atol=1e-14, events=flat)
    return float(sol.t_events[0][0])


FLAT_CASE = ((1.0, 2.0, 3.0), dz.Damper(0.05, 0.05), (1.0, 0.01, 0.01))


@pytest.fixture(scope="module")
def flat_reference() -> float:
    body, damper, omega0 = FLAT_CASE
    return _flat_reference(body, damper, np.array(omega0), 1400.0)


@pytest.mark.parametrize("frames, method", [(3, "rk4"), (301, "rk4"), (3, "dop853")])
def test_the_flat_spin_time_is_located_in_the_run_whatever_the_frames(frames, method,
                                                                      flat_reference):
    # Issue 33: read off the frames, a (1, 2, 3) body with Damper(0.05, 0.05) went flat at
    # 1258 with 3001 frames to t = 3000 and 1295 with 601 (the share's nutation crossed 0.99
    # between frames); the core now locates it inside the step: 1257.843 with any frames
    body, damper, omega0 = FLAT_CASE
    run = {"dt": 1e-3} if method == "rk4" else {"rtol": 1e-11}
    traj = dz.simulate(dz.System(body, parts=[damper]), omega0, t_end=1400.0, frames=frames,
                       method=method, **run)
    assert dz.flat_spin_time(traj) == pytest.approx(flat_reference, abs=1e-6)
    # another share is read off the frames, as before
    assert dz.flat_spin_time(traj, 0.5) in traj.t


# every method the registry says runs the free body alone (the atlas's among them)
@pytest.mark.parametrize("method", [m for m, info in dz.METHODS.items() if info.models == ("free",)])
def test_constant_body_methods_refuse_the_models_by_name(method):
    d = dz.Deployment([0.0, 1.0], [STOWED, DEPLOYED])
    with pytest.raises(ValueError, match=f"method '{method}' cannot run model 'deployment'"):
        dz.simulate(d, (0.0, 0.0, 1.0), method=method)
    with pytest.raises(ValueError, match=f"method '{method}' cannot run model 'damper'"):
        dz.simulate(dz.System(BODY, parts=[DAMPER]), (0.0, 0.0, 1.0), method=method)


@pytest.mark.parametrize("times, inertia, match", [
    ([1.0, 1.0], [STOWED, DEPLOYED], "`times` must be finite and strictly increasing"),
    ([0.0, 1.0], [STOWED], "one body per knot"),
    ([0.0], [np.array([[1.0, 2.0, 0], [2.0, 1.0, 0], [0, 0, 1.0]])], "positive definite"),
    ([0.0], [np.array([[1.0, 0.5, 0], [0.0, 1.0, 0], [0, 0, 1.0]])], "symmetric"),
    ([0.0], [(1.0, 2.0)], r"inertia\[0\]"),
    ([np.nan], [STOWED], "`times` must be finite"),
])
def test_bad_deployments_are_refused(times, inertia, match):
    with pytest.raises(ValueError, match=match):
        dz.Deployment(times, inertia)


def test_bad_dampers_are_refused():
    with pytest.raises(ValueError, match=r"`inertia` \(the damper sphere's moment\) must be positive"):
        dz.Damper(0.0, 1.0)
    with pytest.raises(ValueError, match="`damping` must be non-negative"):
        dz.Damper(1.0, -1.0)
    with pytest.raises(ValueError, match="`sigma0` must be finite"):
        dz.Damper(1.0, 1.0, sigma0=(0.0, np.nan, 1.0))
    with pytest.raises(TypeError, match=r"`parts\[0\]` must be a dz.Damper"):
        dz.System(BODY, parts=[0.5])  # type: ignore[list-item]


def test_two_dampers_each_keep_their_own_state_and_the_balance_holds():
    # each damper its own sphere: results name them by their place among the dampers
    two = dz.System(BODY, parts=[DAMPER, dz.Damper(0.03, 0.05, sigma0=(0.0, 0.0, 0.0))])
    assert two.part_names == ("damper_0", "damper_1")
    assert two.conserved == ("momentum", "momentum_world", "q_norm", "energy_balance")
    traj = dz.simulate(two, (0.2, 0.01, 1.0), t_end=200.0, frames=21, dt=0.01)
    assert traj.parts["damper_0"].shape == traj.parts["damper_1"].shape == (21, 3)
    # the second sphere starts at rest, the first co-rotating
    assert np.array_equal(traj.parts["damper_1"][0], (0.0, 0.0, 0.0))
    assert np.array_equal(traj.parts["damper_0"][0], (0.2, 0.01, 1.0))
    # L in space kept to RK4's error, the energy falls, and falls by the dissipated work
    assert traj.drift.momentum_world < 1e-9
    assert traj.energy[-1] < traj.energy[0] * 0.99
    assert traj.drift.energy_balance < 1e-9


def test_free_runs_report_momentum_world_and_energy_too():
    traj = dz.simulate(STOWED, (0.1, 0.2, 1.0), t_end=10.0, frames=11)
    assert traj.momentum_world.shape == (11, 3) and traj.energy.shape == (11,)
    assert np.ptp(traj.energy) < 1e-9 * traj.energy[0]


def test_which_deployments_tumble():
    # stowed (1, 2, 3) about z, deployed to (1, 3, r): z is intermediate for r < 3 and tumbles,
    # major for r > 3 and stays; each row of the batch is its single run
    ratios = (2.0, 2.5, 3.5, 4.0)
    deployments = [dz.Deployment([20.0, 30.0], [STOWED, (1.0, 3.0, r)]) for r in ratios]
    runs = dz.simulate(deployments, (0.01, 0.01, 1.0), t_end=250.0, frames=251, dt=1e-3)
    tumbled = [bool(dz.axis_shares(runs[i])[:, 2].min() < 0) for i in range(len(runs))]
    assert tumbled == [r < 3 for r in ratios]
    single = dz.simulate(deployments[1], (0.01, 0.01, 1.0), t_end=250.0, frames=251, dt=1e-3)
    np.testing.assert_array_equal(runs[1].omega, single.omega)
    np.testing.assert_array_equal(runs[1].q, single.q)
    with pytest.raises(ValueError, match="systems of one kind"):
        dz.simulate([deployments[0], dz.Body(STOWED)], (0.0, 0.0, 1.0))


def test_the_story_scenes_tell_their_stories():
    deployment, explorer = dz.SCENES["deployment"], dz.SCENES["explorer-1"]
    for scene in (deployment, explorer):
        assert dz.Scene.from_toml(scene.to_toml(), scene.name) == scene
    traj = deployment.run()
    share_z = dz.axis_shares(traj)[:, 2]
    assert deployment.deployment is not None
    start, end = deployment.deployment.times[[0, -1]]
    assert share_z[traj.t <= start].min() > 0.999 and share_z[traj.t >= end].min() < -0.9
    traj = explorer.run()
    assert explorer.damper is not None
    measured = dz.flat_spin_time(traj)
    estimate = dz.flat_spin_estimate(explorer.inertia, explorer.damper, explorer.omega0)
    assert measured == pytest.approx(estimate, rel=0.01)
    # the deployment's flips are located: none while stowed, every flip period once deployed
    flips = deployment.run().flip_times
    assert flips is not None and len(flips) > 0 and flips[0] > end


@pytest.mark.parametrize("e", [-997, 997])
@pytest.mark.parametrize("method", ["rk4", "dop853"])
def test_rates_near_the_ends_of_float64_are_the_scaled_motion(e, method):
    """(ω, t) → (sω, t/s) is a symmetry of both laws (a damper's coefficient, a moment per
    unit time, scales with 1/t): at s = 2^±997 (1e±300) the run is the one at rates near 1,
    scaled, bit for bit; unscaled, the products of such rates underflow or overflow (the
    momentum's drift was 1.0 at 1e-300)."""
    s = 2.0**e
    w0 = np.array([0.01, 0.01, 1.0])
    kw = dict(frames=9, method=method, dt=None)
    d = dz.Deployment([10.0, 20.0], [STOWED, DEPLOYED])
    d_s = dz.Deployment([10.0 / s, 20.0 / s], [STOWED, DEPLOYED])
    unit = dz.simulate(d, w0, t_end=40.0, **kw)
    scaled = dz.simulate(d_s, w0 * s, t_end=40.0 / s, **kw)
    np.testing.assert_array_equal(scaled.omega, unit.omega * s)
    np.testing.assert_array_equal(scaled.q, unit.q)
    assert scaled.drift.momentum_world == unit.drift.momentum_world < 1e-8
    w1 = np.array([0.9, 0.1, 0.1])
    unit = dz.simulate(dz.System(STOWED, parts=[dz.Damper(0.1, 0.05)]), w1, t_end=40.0, **kw)
    scaled = dz.simulate(dz.System(STOWED, parts=[dz.Damper(0.1, 0.05 * s)]), w1 * s,
                         t_end=40.0 / s, **kw)
    np.testing.assert_array_equal(scaled.omega, unit.omega * s)
    np.testing.assert_array_equal(scaled.parts["damper"], unit.parts["damper"] * s)
    assert scaled.drift.momentum == unit.drift.momentum < 1e-8


def test_flips_of_a_deployment_follow_the_deployed_body_exactly():
    """After the last knot the body is constant and the motion free: the flips located on the
    deployment's run come every 2K(m)/λ of the deployed body at the state reached then (the
    closed form, `dz.flip_period`), and none before the spin axis became intermediate."""
    d = dz.Deployment([10.0, 20.0], [STOWED, DEPLOYED])
    w0 = (0.01, 0.01, 1.0)
    traj = dz.simulate(d, w0, t_end=200.0, frames=2001, method="dop853", rtol=1e-12, dt=None)
    flips = traj.flip_times
    assert flips is not None and len(flips) >= 3
    assert flips[0] > 20.0  # the stowed spin about z, the major axis, never flipped
    i = int(np.searchsorted(traj.t, 20.0))
    period = dz.flip_period(DEPLOYED, traj.omega[i])
    np.testing.assert_allclose(np.diff(flips), period, rtol=1e-6)
    # the same deployment keeping z major (deployed to (1, 2, 4)) shows none
    kept = dz.simulate(dz.Deployment([10.0, 20.0], [STOWED, (1.0, 2.0, 4.0)]), w0,
                       t_end=200.0, frames=201, method="dop853", rtol=1e-12, dt=None)
    assert kept.flip_times is not None and len(kept.flip_times) == 0


def test_flips_of_equal_knots_are_the_closed_form_flips():
    """A deployment whose knots are equal is the constant body: its flips are those of the
    exact solution (Jacobi elliptic functions), to the integration's accuracy."""
    moments = (52.0833, 27.0833, 41.6666)
    d = dz.Deployment([1.0, 2.0], [moments, moments])
    w0 = (0.01, 0.01, 1.0)
    deployed = dz.simulate(d, w0, t_end=200.0, frames=201, dt=1e-3)
    exact = dz.simulate(moments, w0, t_end=200.0, frames=201, method="exact")
    assert len(exact.flip_times) >= 5
    np.testing.assert_allclose(deployed.flip_times, exact.flip_times, rtol=0, atol=1e-6)


def test_flips_are_located_for_tensors_off_their_axes():
    """A deployment through turned tensors is the deployment of their principal moments, turned:
    its flips (on the intermediate eigenvector of I(t)) come at the same times."""
    rot = Rotation.from_euler("xyz", [0.3, -0.7, 1.1])
    r = rot.as_matrix()
    turned = dz.Deployment([10.0, 20.0], [r @ np.diag(STOWED) @ r.T, r @ np.diag(DEPLOYED) @ r.T])
    plain = dz.Deployment([10.0, 20.0], [STOWED, DEPLOYED])
    w0 = np.array([0.01, 0.01, 1.0])
    kw = dict(t_end=120.0, frames=121, method="dop853", rtol=1e-12, dt=None)
    a = dz.simulate(plain, w0, **kw)
    b = dz.simulate(turned, r @ w0, **kw)
    assert len(a.flip_times) >= 3 and a.flip_times[0] > 20.0
    np.testing.assert_allclose(b.flip_times, a.flip_times, rtol=0, atol=1e-5)


@pytest.mark.parametrize("method", ["dopri5", "dop853", "rk4"])
def test_an_undamped_damper_at_rest_runs(method):
    """A body at rest with `Damper(0.1, 0.0)` and dopri5 or dop853 raised ZeroDivisionError
    in the stiffness check (`step = 1.0 / rate` with a rate of 0)."""
    system = dz.System(BODY, parts=[dz.Damper(0.1, 0.0)])
    traj = dz.simulate(system, (0.0, 0.0, 0.0), method=method, t_end=1.0, frames=3)
    assert not traj.omega.any() and not traj.parts["damper"].any()


def test_the_damper_rate_is_finite_or_the_damper_refused():
    """`damper_rate` returned inf for `Damper(5e-324, c)`: 1/j overflowed though c/j need
    not. The rate is c/j + c/I_min; a relaxation rate c/j beyond float64 is refused when the
    damper is built, naming both arguments."""
    tiny = dz.Damper(5e-324, 1e-310)
    rate = dz.damper_rate((1.0, 2.0, 3.0), tiny)
    assert rate == pytest.approx(1e-310 / 5e-324 + 1e-310, rel=1e-12)
    with pytest.raises(ValueError, match=r"`damping` over the damper's inertia must be finite"):
        dz.Damper(5e-324, 0.02)
    with pytest.raises(ValueError, match=r"`body` .* and `damper` .* exceeds float64"):
        dz.damper_rate((1e-300, 1e-300, 1e-300), dz.Damper(1.0, 1e10))


def test_a_deployment_of_many_knots_is_checked_all_at_once(monkeypatch):
    """10⁶ knots took ~40 s, checked one by one in Python: an array of moments or tensors is
    checked in one pass (the per-knot path is not taken), and the first bad knot named."""
    from dzhanibekov import deployment

    def per_knot(*args):
        raise AssertionError("checked knot by knot")

    monkeypatch.setattr(deployment, "_as_tensor", per_knot)
    k = 100_000
    times = np.arange(k, dtype=float)
    moments = np.tile([1.0, 2.0, 3.0], (k, 1))
    d = dz.Deployment(times, moments)
    assert d.tensors.shape == (k, 3, 3) and np.array_equal(d.tensors[7], np.diag([1, 2, 3]))
    listed = dz.Deployment(times.tolist(), moments.tolist())  # lists are stacked at once too
    assert np.array_equal(listed.tensors, d.tensors)
    tensors = np.tile(np.diag([1.0, 2.0, 3.0]), (k, 1, 1))
    tensors[k - 3, 0, 1] = tensors[k - 3, 1, 0] = 5.0
    with pytest.raises(ValueError, match=rf"`inertia` must hold symmetric, positive definite.* "
                                         rf"got \"?inertia\[{k - 3}\] = "):
        dz.Deployment(times, tensors)
    times[k - 2] = times[k - 3]
    with pytest.raises(ValueError, match=rf"times\[{k - 3}\] = {k - 3} then "
                                         rf"times\[{k - 2}\] = {k - 3}\b"):
        dz.Deployment(times, moments)


def test_a_deployment_too_large_for_memory_is_refused_before_it_is_built(monkeypatch):
    from dzhanibekov import _args

    monkeypatch.setattr(_args, "memory_available", lambda: (10 << 20, "available memory"))
    with pytest.raises(dz.TooLargeError, match="a deployment of 1000000 knots"):
        dz.Deployment(range(10**6), [(1.0, 2.0, 3.0)] * 10**6)
