"""A spacecraft in orbit: gravity gradient, constant torques and wheels against references
written here, independently of the package (scipy's solve_ivp of the body-frame equations
with their own quaternion law, and closed forms with their sources)."""

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

import dzhanibekov as dz


# ---------------------------------------------------------------- the reference, written here

def _qmul(a, b):
    a0, a1, a2, a3 = a
    b0, b1, b2, b3 = b
    return np.array([a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
                     a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
                     a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1,
                     a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0])


def _to_body(q, v):
    """World vector `v` in body axes for world-from-body `q` (scalar first), by scipy."""
    return Rotation.from_quat(q / np.linalg.norm(q), scalar_first=True).inv().apply(v)


def reference(tensor, omega0, q0, t, *, n=None, body_torque=(0, 0, 0), world_torque=(0, 0, 0),
              wheels=()):
    """solve_ivp (DOP853, rtol 1e-12) of I ω' = (I ω + Σ h a) × ω + τ_b, q' = ½ q ⊗ (0, ω),
    τ_b = 3 n² r̂_b × I r̂_b (r̂ = (cos nt, sin nt, 0)) + body torque + world torque in body
    axes."""
    tensor = np.asarray(tensor, float)
    inv = np.linalg.inv(tensor)
    h = sum((m * np.asarray(a, float) / np.linalg.norm(a) for a, m in wheels), np.zeros(3))

    def rhs(t, y):
        w, q = y[:3], y[3:]
        tau = np.asarray(body_torque, float) + _to_body(q, np.asarray(world_torque, float))
        if n is not None:
            r = _to_body(q, np.array([math.cos(n * t), math.sin(n * t), 0.0]))
            tau = tau + 3 * n * n * np.cross(r, tensor @ r)
        dw = inv @ (np.cross(tensor @ w + h, w) + tau)
        dq = 0.5 * _qmul(q, np.concatenate([[0.0], w]))
        return np.concatenate([dw, dq])

    q0 = np.asarray(q0, float) / np.linalg.norm(q0)
    sol = solve_ivp(rhs, (t[0], t[-1]), np.concatenate([omega0, q0]), method="DOP853",
                    t_eval=t, rtol=1e-12, atol=1e-14)
    assert sol.success
    return sol.y[:3].T, sol.y[3:].T


def jacobi(tensor, n, t, omega, q, h=np.zeros(3)):
    """J = ½ ωᵀIω − n ẑ_b·(Iω + h) + (3/2) n² r̂_bᵀ I r̂_b (Hughes, Spacecraft Attitude
    Dynamics, §9.1), from the frames."""
    tensor = np.asarray(tensor, float)
    out = []
    for tk, w, qk in zip(t, omega, q):
        z = _to_body(qk, np.array([0.0, 0.0, 1.0]))
        r = _to_body(qk, np.array([math.cos(n * tk), math.sin(n * tk), 0.0]))
        out.append(0.5 * w @ tensor @ w - n * z @ (tensor @ w + h) + 1.5 * n * n * r @ tensor @ r)
    return np.array(out)


def _same_attitude(q, ref):
    """About half the angle between attitudes, frame by frame (the sign of q free): the
    distance between the unit quaternions (arccos of their product loses digits near 1)."""
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    ref = ref / np.linalg.norm(ref, axis=1, keepdims=True)
    return np.minimum(np.linalg.norm(q - ref, axis=1), np.linalg.norm(q + ref, axis=1))


TENSOR = [[2.0, -0.3, 0.1], [-0.3, 3.0, 0.2], [0.1, 0.2, 4.0]]   # not principal: the edge too
W0, Q0 = np.array([0.3, -0.7, 1.1]), np.array([0.6, -0.2, 0.7, 0.3])


# ---------------------------------------------------------------- against the reference

CASES = {
    "gravity_gradient": (dict(n=0.8), dict(torques=[dz.GravityGradient(0.8)])),
    "body_torque": (dict(body_torque=(0.1, -0.2, 0.05)),
                    dict(torques=[dz.ConstantTorque((0.1, -0.2, 0.05))])),
    "world_torque": (dict(world_torque=(0.0, 0.3, -0.1)),
                     dict(torques=[dz.ConstantTorque((0.0, 0.3, -0.1), frame="world")])),
    "wheels_in_orbit": (dict(n=0.5, wheels=[((0, 1, 0), 0.8), ((1, 1, 0), -0.3)]),
                        dict(parts=[dz.Wheel((0, 1, 0), 0.8), dz.Wheel((1, 1, 0), -0.3)],
                             torques=[dz.GravityGradient(0.5)])),
}


@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize("method", ["dop853", "rk4"])
def test_each_model_follows_an_independent_solution_of_its_equations(case, method):
    ref_kw, sys_kw = CASES[case]
    system = dz.System(dz.Body.from_tensor(TENSOR), **sys_kw)
    opts = dict(rtol=1e-12, atol=1e-14) if method == "dop853" else dict(dt=2e-3)
    traj = dz.simulate(system, W0, Q0, t_end=10.0, frames=51, method=method, **opts)
    omega, q = reference(TENSOR, W0, Q0, traj.t, **ref_kw)
    assert np.abs(traj.omega - omega).max() < 1e-9
    assert _same_attitude(traj.q, q).max() < 1e-9


def test_the_jacobi_integral_is_kept_to_the_methods_order():
    n = 0.8
    system = dz.System(dz.Body.from_tensor(TENSOR), torques=[dz.GravityGradient(n)])
    assert system.conserved == ("q_norm", "jacobi")
    errors = []
    for dt in (0.02, 0.01):
        traj = dz.simulate(system, W0, Q0, t_end=20.0, frames=41, method="rk4", dt=dt)
        j = jacobi(TENSOR, n, traj.t, traj.omega, traj.q)
        errors.append(np.abs(j - j[0]).max() / abs(j[0]))
        assert traj.drift.kept == ("q_norm", "jacobi")
        assert traj.drift.jacobi == pytest.approx(errors[-1], rel=1e-3)
    # RK4: the error falls as dt⁴ (ratio 16 when dt halves; a loose band for the constant)
    assert 10 < errors[0] / errors[1] < 24
    precise = dz.simulate(system, W0, Q0, t_end=20.0, frames=41, method="dop853", rtol=1e-12,
                          atol=1e-14)
    assert precise.drift.jacobi < 1e-10


def test_a_constant_torque_keeps_nothing_but_the_quaternions_norm():
    push = dz.System(dz.Body((1.0, 2.0, 3.0)), torques=[dz.ConstantTorque((0, 0.1, 0.2))])
    assert push.kinds == ("constant_torque",) and push.conserved == ("q_norm",)
    traj = dz.simulate(push, W0, t_end=5.0, method="dop853")
    assert traj.drift.kept == ("q_norm",) and traj.drift.jacobi is None
    assert traj.drift.momentum > 1e-2     # the torque's own change, not an error


# ---------------------------------------------------------------- closed forms

def test_pitch_libration_has_the_closed_form_frequency():
    # Hughes, Spacecraft Attitude Dynamics (1986), §9.3: with body x along-track, y along
    # minus the orbit normal (pitch) and z nadir, I_y θ'' + 3 n² (I_x − I_z) θ = 0
    inertia, n = (2.0, 3.0, 1.0), 1.0
    expected = n * math.sqrt(3 * (inertia[0] - inertia[2]) / inertia[1])
    assert dz.pitch_libration_rate(inertia, n) == pytest.approx(expected, rel=1e-15)
    sat = dz.System(dz.Body(inertia), torques=[dz.GravityGradient(n)])
    omega0, q0 = dz.lvlh_start(n, pitch=1e-4)
    periods = 5
    t_end = periods * 2 * math.pi / expected
    traj = dz.simulate(sat, omega0, q0, t_end=t_end, frames=4001, method="dop853",
                       rtol=1e-12, atol=1e-14)
    ql = dz.lvlh_attitude(traj)
    pitch = 2 * np.arctan2(ql[:, 2], ql[:, 0])
    assert np.abs(ql[:, [1, 3]]).max() < 1e-12        # no roll, no yaw: a pure pitch motion
    # upward zero crossings of cos-like pitch: interpolate the times of θ = 0 going down
    s = pitch
    k = np.nonzero((s[:-1] > 0) & (s[1:] <= 0))[0]
    crossings = traj.t[k] + s[k] / (s[k] - s[k + 1]) * (traj.t[k + 1] - traj.t[k])
    measured = 2 * math.pi / np.mean(np.diff(crossings))
    assert measured == pytest.approx(expected, rel=1e-5)


def test_a_wheel_without_momentum_is_the_free_body():
    body = dz.Body((1.0, 2.0, 3.0))
    free = dz.simulate(body, (0.01, 1.0, 0.01), t_end=30.0, method="rk4", dt=0.01)
    wheel = dz.simulate(dz.System(body, parts=[dz.Wheel((0.3, 1, 0), 0.0)]), (0.01, 1.0, 0.01),
                        t_end=30.0, method="rk4", dt=0.01)
    # round-off apart: the free body's RK4 steps ω, the general model's H = I ω (+ Σ h a);
    # the differences of a few ulps grow ~1000× through the flip near the separatrix
    assert np.abs(wheel.omega[:50] - free.omega[:50]).max() < 1e-13
    assert np.abs(wheel.omega - free.omega).max() < 1e-10
    assert np.abs(wheel.q - free.q).max() < 1e-10
    np.testing.assert_array_equal(wheel.flip_times.shape, free.flip_times.shape)


def _transverse_growth(h, h_star):
    """The largest transverse rate of a spin Ω = 1 about the intermediate axis (y) with a
    wheel of momentum h along it, from a 1e-6 nudge."""
    body = dz.System(dz.Body((1.0, 2.0, 3.0)), parts=[dz.Wheel((0, 1, 0), h)])
    traj = dz.simulate(body, (1e-6, 1.0, 1e-6), t_end=400.0, frames=401, method="rk4",
                       dt=0.02, flips=False)
    return np.abs(traj.omega[:, [0, 2]]).max()


def test_a_wheel_on_the_intermediate_axis_stabilises_it_above_the_closed_form_threshold():
    # linearising I ω' = (I ω + h e_y) × ω about ω = Ω e_y: I_x ω_x' = ((I_y − I_z) Ω + h) ω_z,
    # I_z ω_z' = ((I_x − I_y) Ω − h) ω_x; stable iff the product of the brackets is negative,
    # i.e. h > Ω (I_z − I_y) or h < −Ω (I_y − I_x) (the gyrostat; Hughes ch. 6)
    low, high = dz.dual_spin_threshold((1.0, 2.0, 3.0), axis=1, rate=1.0)
    assert (low, high) == pytest.approx((-1.0, 1.0), rel=1e-15)
    assert _transverse_growth(1.01 * high, high) < 1e-4
    assert _transverse_growth(0.99 * high, high) > 1e-1
    assert _transverse_growth(1.01 * low, low) < 1e-4
    assert _transverse_growth(0.99 * low, low) > 1e-1


def test_wheels_keep_the_total_momentum_in_space():
    system = dz.System(dz.Body.from_tensor(TENSOR),
                       parts=[dz.Wheel((0, 1, 0), 0.8), dz.Wheel((1, 0, 1), -0.4)])
    traj = dz.simulate(system, W0, Q0, t_end=20.0, method="dop853", rtol=1e-12, atol=1e-14)
    assert traj.drift.kept == ("momentum", "momentum_world", "q_norm")
    assert traj.drift.momentum_world < 1e-11
    lw = traj.momentum_world
    assert np.abs(lw - lw[0]).max() < 1e-10 * np.linalg.norm(lw[0])
    omega, q = reference(TENSOR, W0, Q0, traj.t, wheels=[((0, 1, 0), 0.8), ((1, 0, 1), -0.4)])
    assert np.abs(traj.omega - omega).max() < 1e-9
    projected = dz.simulate(system, W0, Q0, t_end=20.0, method="rk4_projected", dt=0.01)
    assert projected.drift.momentum_world < 1e-12


# ---------------------------------------------------------------- the orbiting frame

def test_the_lvlh_frame_is_along_track_minus_normal_nadir():
    n, t = 0.3, np.array([0.0, 1.7, 5.0])
    m = Rotation.from_quat(dz.lvlh_frame(t, n), scalar_first=True).as_matrix()
    c, s = np.cos(n * t), np.sin(n * t)
    np.testing.assert_allclose(m[:, :, 0], np.stack([-s, c, 0 * t], 1), atol=1e-15)
    np.testing.assert_allclose(m[:, :, 1], np.stack([0 * t, 0 * t, -1 + 0 * t], 1), atol=1e-15)
    np.testing.assert_allclose(m[:, :, 2], np.stack([-c, -s, 0 * t], 1), atol=1e-15)


def test_a_body_at_rest_in_lvlh_stays_there_in_its_equilibrium():
    n = 0.5
    sat = dz.System(dz.Body((2.0, 3.0, 1.0)), torques=[dz.GravityGradient(n)])
    omega0, q0 = dz.lvlh_start(n)
    np.testing.assert_allclose(omega0, [0.0, -n, 0.0])
    traj = dz.simulate(sat, omega0, q0, t_end=30.0, method="dop853", rtol=1e-12)
    ql = dz.lvlh_attitude(traj)
    assert np.abs(np.abs(ql[:, 0]) - 1).max() < 1e-11


def test_a_start_relative_to_lvlh_has_those_relative_rates():
    n, w_rel = 0.4, np.array([0.01, 0.02, -0.03])
    q_rel = np.array([0.9, 0.1, -0.3, 0.2])
    omega0, q0 = dz.lvlh_start(n, q_rel, w_rel)
    # the orbit normal, world +z, in body axes, by scipy
    z_b = _to_body(q0, np.array([0.0, 0.0, 1.0]))
    np.testing.assert_allclose(omega0, w_rel + n * z_b, atol=1e-15)
    expected = _qmul(dz.lvlh_frame(0.0, n), q_rel / np.linalg.norm(q_rel))
    np.testing.assert_allclose(q0, expected, atol=1e-15)


# ---------------------------------------------------------------- bad input

@pytest.mark.parametrize("make, error, match", [
    (lambda: dz.GravityGradient(-1.0), ValueError, "orbit_rate"),
    (lambda: dz.GravityGradient(float("nan")), ValueError, "orbit_rate"),
    (lambda: dz.GravityGradient("fast"), TypeError, "orbit_rate"),
    (lambda: dz.ConstantTorque((1, 2)), ValueError, "vector"),
    (lambda: dz.ConstantTorque((1, np.nan, 2)), ValueError, "vector"),
    (lambda: dz.ConstantTorque((1, 2, 3), frame="space"), ValueError, "frame"),
    (lambda: dz.ConstantTorque((1, 2, 3), frame=1), TypeError, "frame"),
    (lambda: dz.Wheel((0, 0, 0), 1.0), ValueError, "axis"),
    (lambda: dz.Wheel((np.nan, 0, 1), 1.0), ValueError, "axis"),
    (lambda: dz.Wheel((0, 0, 1, 0), 1.0), ValueError, "axis"),
    (lambda: dz.Wheel((0, 0, 1), np.inf), ValueError, "momentum"),
    (lambda: dz.System(dz.Body((1, 2, 3)), torques=[dz.Wheel((0, 0, 1), 1.0)]), TypeError,
     "torques"),
    (lambda: dz.System(dz.Body((1, 2, 3)), parts=[dz.GravityGradient(1.0)]), TypeError, "parts"),
    (lambda: dz.System(dz.Body((1, 2, 3)), torques=[dz.GravityGradient(1.0)] * 2), ValueError,
     "at most one gravity_gradient"),
    (lambda: dz.lvlh_start(0.0), ValueError, "orbit_rate"),
    (lambda: dz.lvlh_start(1.0, q_rel=(0, 0, 0, 0)), ValueError, "q_rel"),
    (lambda: dz.pitch_libration_rate((1.0, 2.0, 3.0), 1.0), ValueError, "inertia"),
    (lambda: dz.dual_spin_threshold((1.0, 2.0, 3.0), axis=3, rate=1.0), ValueError, "axis"),
])
def test_bad_input_is_refused_by_name(make, error, match):
    with pytest.raises(error, match=match):
        make()


def test_methods_that_cannot_run_a_torque_refuse_it_by_name_before_running():
    sat = dz.System(dz.Body((2.0, 3.0, 1.0)), torques=[dz.GravityGradient(1.0)])
    for method in ("rk4_projected", "splitting", "splitting4", "exact"):
        with pytest.raises(dz.DzhanibekovError, match=f"'{method}' cannot run model "
                                                      "'gravity_gradient'"):
            dz.simulate(sat, (0.0, -1.0, 0.0), method=method)
    assert "gravity_gradient" in dz.METHODS["dop853"].models
    assert "gravity_gradient" not in dz.METHODS["rk4_projected"].models


# ---------------------------------------------------------------- files

ORBITER = dz.System(dz.Body((2.0, 3.0, 1.0)),
                    parts=[dz.Wheel((0, 2, 0), 0.1), dz.Damper(0.05, 0.02), dz.Wheel((1, 0, 1), -0.3)],
                    torques=[dz.ConstantTorque((0.0, 0.0, 1e-3), frame="world"),
                             dz.GravityGradient(1.0), dz.ConstantTorque((1e-3, 0.0, 0.0))])


def test_a_run_with_wheels_and_torques_loads_as_the_same_system(tmp_path):
    pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    traj = dz.simulate(ORBITER, *dz.lvlh_start(1.0), t_end=1.0, frames=5, method="dop853")
    back = dz.load(dz.save(traj, tmp_path / "orbit.nc"))
    assert back.system == ORBITER            # parts and torques in their order
    assert [type(p) for p in back.system.parts] == [dz.Wheel, dz.Damper, dz.Wheel]
    np.testing.assert_array_equal(back.q, traj.q)
    np.testing.assert_array_equal(back.momentum_world, traj.momentum_world)
    assert back.drift == traj.drift and back.drift.kept == ("q_norm",)


def test_a_batch_of_systems_with_different_numbers_of_wheels_and_torques_round_trips(tmp_path):
    pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    body = dz.Body((2.0, 3.0, 1.0))
    systems = [dz.System(body, parts=[dz.Wheel((0, 1, 0), 0.2)],
                         torques=[dz.ConstantTorque((0.0, 1e-3, 0.0))]),
               dz.System(body, parts=[dz.Wheel((0, 1, 0), 0.2), dz.Wheel((0, 0, 1), 0.1)],
                         torques=[dz.ConstantTorque((0.0, 1e-3, 0.0)),
                                  dz.ConstantTorque((0.0, 0.0, 1e-3), frame="world")])]
    batch = dz.simulate(systems, (0.1, 1.0, 0.0), t_end=1.0, frames=3, method="rk4", dt=0.01)
    ds = batch.to_xarray()
    assert ds.sizes["part_wheel"] == 2 and ds.sizes["part_constant_torque"] == 2
    assert list(ds["part_kind"].values[0]) == ["wheel", "constant_torque", "", ""]
    assert np.isnan(ds["part_wheel_momentum"].values[0, 1])      # run 0's padding
    back = dz.load(dz.save(batch, tmp_path / "batch.nc"))
    assert list(back.systems) == systems
    np.testing.assert_array_equal(back.momentum_world, batch.momentum_world)


LEGACY = Path(__file__).resolve().parents[2] / "data" / "legacy"
"""Files written by dzhanibekov at main 3f80f7e, in the layout before parts were written by
their model (tests/data/legacy/make_legacy.py): their reader is checked on them."""


def _spoil(traj, tmp_path, change):
    """`traj`'s file (a Trajectory, or the name of a legacy file) changed by `change`."""
    xr = pytest.importorskip("xarray")
    ds = xr.load_dataset(LEGACY / traj) if isinstance(traj, str) else traj.to_xarray()
    change(ds)
    ds.attrs["dzhanibekov_result"] = "Trajectory"
    path = tmp_path / "bad.nc"
    ds.to_netcdf(path, engine="h5netcdf")
    return path


def _set(name, index, value):
    def change(ds):
        a = ds[name].values.copy()
        a[index] = value
        ds[name] = (ds[name].dims, a)
    return change


@pytest.mark.parametrize("change, message", [
    (_set("wheel_position", 1, 5), r"`wheel_position` of run 0 must number its wheels"),
    (_set("wheel_position", 0, -1), r"`wheel_position` must hold each run's wheels first"),
    (_set("wheel_axis", (0, 1), np.nan), r"`wheel_axis` must be finite for each run's wheels"),
    (_set("wheel_axis", 0, 0.0), r"whose system dz cannot build: .*axis"),
    (_set("torque_kind", 0, "spinning"), r"`torque_kind` must be one of"),
    (_set("torque_kind", 0, "tabulated"), r"a tabulated torque needs `torque_outside`"),
    (_set("torque_kind", 0, ""), r"`torque_kind` must hold each run's torques first"),
    (_set("torque_orbit_rate", 1, -1.0), r"whose system dz cannot build: .*orbit_rate"),
    (_set("torque_orbit_rate", 0, 1.0), r"`torque_orbit_rate` must be a number exactly"),
    (_set("torque_frame", 0, "orbit"), r"`torque_frame` must be one of"),
    (_set("torque_frame", 1, "body"), r"`torque_frame` must be 'body' or 'world' for a"),
    (lambda ds: ds.__delitem__("torque_vector"), r"must be there together"),
    (lambda ds: ds.__delitem__("wheel_momentum"), r"must be there together"),
    # the loaded wheel's momentum must give the momentum the file says the run had
    (_set("wheel_momentum", 0, 0.2), r"`momentum_body` is not what the file's own system"),
])
def test_load_refuses_wheels_and_torques_of_the_old_layout_a_save_never_wrote(
        tmp_path, change, message):
    pytest.importorskip("h5netcdf")
    assert dz.load(LEGACY / "orbiter.nc").system == ORBITER
    with pytest.raises(dz.ReadError, match=message):
        dz.load(_spoil("orbiter.nc", tmp_path, change))


TABLED = dz.System(dz.Body((2.0, 3.0, 1.0)),
                   parts=[dz.Wheel((0, 2, 0), 0.1), dz.Wheel((1, 0, 1), ([0.0, 0.5, 1.0],
                                                                        [0.0, 0.2, 0.1]))],
                   torques=[dz.TabulatedTorque([0.0, 0.5, 1.0], [(0, 0, 1e-3)] * 3),
                            dz.GravityGradient(1.0),
                            dz.TabulatedTorque([0.2, 0.4], [(1e-3, 0, 0), (0, 1e-3, 0)],
                                               frame="world", outside="hold")])


@pytest.mark.parametrize("change, message", [
    (_set("torque_times", (2, 2), 5.0), r"`torque_times` and `torque_vectors` must hold"),
    (_set("torque_times", (1, 0), 0.5), r"`torque_times` and `torque_vectors` must hold"),
    (_set("torque_times", (2, 1), np.nan), r"`torque_times` and `torque_vectors` must hold"),
    (_set("torque_vectors", (0, 1, 0), np.nan), r"`torque_times` and `torque_vectors` must"),
    (_set("torque_vectors", (2, 2, 0), 0.0), r"`torque_times` and `torque_vectors` must hold"),
    (_set("torque_times", (0, 1), 0.0), r"whose system dz cannot build: .*times"),
    (_set("torque_outside", 0, ""), r"`torque_outside` must be 'zero' or 'hold' for a"),
    (_set("torque_outside", 1, "hold"), r"`torque_outside` must be 'zero' or 'hold' for a"),
    (_set("torque_outside", 0, "wrap"), r"`torque_outside` must be one of"),
    (_set("torque_frame", 0, ""), r"`torque_frame` must be 'body' or 'world' for a"),
    (lambda ds: ds.__delitem__("torque_outside"), r"must be there together"),
    (_set("wheel_momentum", 1, 0.3), r"either a finite `wheel_momentum` or a schedule"),
    (lambda ds: (_set("wheel_times", 1, np.nan)(ds), _set("wheel_values", 1, np.nan)(ds)),
     r"either a finite `wheel_momentum` or a schedule"),                 # neither
    (_set("wheel_times", 1, np.nan), r"`wheel_times` and `wheel_values` must hold"),
    (_set("wheel_times", (0, 0), 0.0), r"`wheel_times` and `wheel_values` must hold"),
    (_set("wheel_values", (1, 2), np.nan), r"`wheel_times` and `wheel_values` must hold"),
    (lambda ds: ds.__delitem__("wheel_values"), r"must be there together"),
    # the loaded schedule must give the momentum the file says the run had
    (_set("wheel_values", (1, 2), 0.3), r"`momentum_body` is not what the file's own system"),
])
def test_load_refuses_tables_and_schedules_of_the_old_layout_a_save_never_wrote(
        tmp_path, change, message):
    pytest.importorskip("h5netcdf")
    assert dz.load(LEGACY / "tabled.nc").system == TABLED
    with pytest.raises(dz.ReadError, match=message):
        dz.load(_spoil("tabled.nc", tmp_path, change))


@pytest.mark.parametrize("change, message", [
    (_set("part_kind", 0, "spinning"), r"`part_kind` must be one of"),
    (_set("part_kind", 0, "callable_torque"), r"`part_kind` must be one of"),
    (_set("part_kind", 0, ""), r"`part_kind` must hold each run's parts first"),
    (_set("part_kind", 3, "tabulated_torque"),
     r"`part_gravity_gradient_orbit_rate` is there, but no part of its model is"),
    (lambda ds: ds.__delitem__("part_wheel_axis"), r"`part_wheel_axis` is missing"),
    (lambda ds: ds.__delitem__("part_kind"), r"`part_\w+` needs `part_kind`"),
    (_set("part_wheel_axis", (0, 1), np.nan), r"`part_wheel_axis` must be finite for each part"),
    (_set("part_wheel_axis", 0, 0.0), r"whose system dz cannot build: .*axis"),
    (_set("part_gravity_gradient_orbit_rate", 0, -1.0),
     r"whose system dz cannot build: .*orbit_rate"),
    (_set("part_tabulated_torque_frame", 0, "orbit"), r"must be one of"),
    (_set("part_tabulated_torque_times", (0, 1), 0.0), r"whose system dz cannot build: .*times"),
    (_set("part_tabulated_torque_times", (1, 0), np.nan),
     r"`part_tabulated_torque_times` must hold a part's knots first, then NaN"),
    (_set("part_tabulated_torque_times", (1, 2), 0.5),
     r"`part_tabulated_torque_vectors` must be finite at a part's 3 knots"),
    (_set("part_tabulated_torque_vectors", (1, 2, 0), 0.0),
     r"`part_tabulated_torque_vectors` must be finite at a part's 2 knots and NaN beyond"),
    (_set("part_wheel_schedule_values", (0, 2), np.nan), r"must be finite at a part's 3 knots"),
    # the loaded parts must give the momentum the file says the run had
    (_set("part_wheel_momentum", 0, 0.2), r"`momentum_body` is not what the file's own system"),
    (_set("part_wheel_schedule_values", (0, 2), 0.3), r"`momentum_body` is not what the file"),
])
def test_load_refuses_parts_a_save_never_writes(tmp_path, change, message):
    pytest.importorskip("h5netcdf")
    traj = dz.simulate(TABLED, *dz.lvlh_start(1.0), t_end=1.0, frames=3, method="rk4", dt=0.01)
    assert dz.load(dz.save(traj, tmp_path / "good.nc")).system == TABLED
    with pytest.raises(dz.ReadError, match=message):
        dz.load(_spoil(traj, tmp_path, change))


def test_saving_a_schedule_round_trips_and_what_a_file_cannot_hold_is_refused(tmp_path):
    pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    wheel = dz.Wheel((0, 1, 0), ([0.0, 1.0], [0.0, 0.1]))
    sat = dz.System(dz.Body((2.0, 3.0, 1.0)), parts=[wheel], torques=[dz.GravityGradient(1.0)])
    traj = dz.simulate(sat, *dz.lvlh_start(1.0), t_end=1.0, method="dop853")
    back = dz.load(dz.save(traj, tmp_path / "orbit.nc"))
    assert back.system == sat and back.system.parts[0].momentum == ((0.0, 1.0), (0.0, 0.1))
    assert np.array_equal(back.q, traj.q)
    code = dz.System(dz.Body((2.0, 3.0, 1.0)), parts=[wheel],
                     torques=[dz.GravityGradient(1.0), lambda t, q, w: (0.0, 0.0, 0.0)])
    traj = dz.simulate(code, *dz.lvlh_start(1.0), t_end=1.0, method="dop853")
    with pytest.raises(ValueError, match=r"CallableTorque \(callable_torque\), "
                                         "which a file cannot hold"):
        dz.save(traj, tmp_path / "code.nc")
    assert not (tmp_path / "code.nc").exists()


def test_strang_on_the_exact_free_flow_is_of_order_two_and_keeps_the_quaternions_norm():
    # the splitting's error against solve_ivp, written here, falls 4× when dt halves
    n = 0.8
    system = dz.System(dz.Body((2.0, 3.0, 4.0)), torques=[dz.GravityGradient(n)])
    errors = []
    for dt in (0.02, 0.01):
        traj = dz.simulate(system, W0, Q0, t_end=5.0, frames=11, method="splitting_exact", dt=dt)
        omega, q = reference(np.diag([2.0, 3.0, 4.0]), W0, Q0, traj.t, n=n)
        errors.append(np.abs(traj.omega - omega).max())
        assert traj.drift.q_norm < 1e-14
    assert 3.5 < errors[0] / errors[1] < 4.5
    assert dz.METHODS["splitting_exact"].order == 2


def test_strang_on_the_exact_free_flow_is_the_exact_solution_without_a_torque():
    # a constant torque of zero: the kicks do nothing, the free flow is the closed form
    zero = dz.System(dz.Body((1.0, 2.0, 3.0)), torques=[dz.ConstantTorque((0, 0, 0))])
    split = dz.simulate(zero, (0.01, 1.0, 0.01), t_end=20.0, method="splitting_exact", dt=0.5)
    exact = dz.simulate(dz.Body((1.0, 2.0, 3.0)), (0.01, 1.0, 0.01), t_end=20.0, method="exact")
    assert np.abs(split.omega - exact.omega).max() < 1e-11


def test_strang_on_the_exact_free_flow_refuses_what_its_free_part_is_not():
    wheeled = dz.System(dz.Body((1.0, 2.0, 3.0)), parts=[dz.Wheel((0, 1, 0), 1.0)],
                        torques=[dz.GravityGradient(1.0)])
    with pytest.raises(dz.DzhanibekovError, match="'splitting_exact' cannot run model 'wheel'"):
        dz.simulate(wheeled, (0.0, 1.0, 0.0), method="splitting_exact")
