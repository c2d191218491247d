"""Tabulated torques, wheel momentum schedules and Python-callable torques against references
written here, independently of the package: scipy's solve_ivp (DOP853, rtol 1e-12) of the
body-frame Euler equations in the rates, ``I ω' = (I ω + h) × ω − ḣ + τ_b``, with their own
quaternion law ``q' = ½ q ⊗ (0, ω)``, integrated piece by piece between the knots (where
the laws have kinks or jumps)."""

import math
import pickle

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


def _lerp(times, values, t, outside):
    """The piecewise-linear law through (times, values) at `t`; zero or held outside."""
    values = np.asarray(values, float)
    if t < times[0] or t > times[-1]:
        if outside == "zero":
            return np.zeros(values.shape[1:])
        return values[0] if t < times[0] else values[-1]
    return np.array([np.interp(t, times, values[:, k]) for k in range(values.shape[1])])


def _slope(times, values, t):
    """The slope of the piecewise-linear law (held outside) on the piece holding `t`."""
    values = np.asarray(values, float)
    if t < times[0] or t >= times[-1]:
        return np.zeros(values.shape[1:])
    k = np.searchsorted(times, t, side="right")
    return (values[k] - values[k - 1]) / (times[k] - times[k - 1])


def reference(tensor, omega0, q0, t, *, torque=None, wheel=None, breaks=()):
    """solve_ivp of ``I ω' = (I ω + h(t)) × ω − ḣ(t) + τ_b(t, q, ω)``, ``q' = ½ q ⊗ (0, ω)``
    over the frames `t`, restarted at each of `breaks` (the midpoint of a piece decides the
    piece's laws: at a jump, each side is integrated with its own). `wheel` is
    ``(h(t), ḣ(t))`` in body axes; `torque(t, q, ω)` in body axes."""
    tensor = np.asarray(tensor, float)
    inv = np.linalg.inv(tensor)
    edges = [t[0], *[b for b in breaks if t[0] < b < t[-1]], t[-1]]
    y = np.concatenate([omega0, np.asarray(q0, float) / np.linalg.norm(q0)])
    out = []
    for a, b in zip(edges[:-1], edges[1:]):
        mid = 0.5 * (a + b)

        def rhs(s, y, mid=mid):
            w, q = y[:3], y[3:]
            h, hdot = wheel(mid, s) if wheel else (np.zeros(3), np.zeros(3))
            tau = torque(mid, s, q, w) if torque else np.zeros(3)
            dw = inv @ (np.cross(tensor @ w + h, w) - hdot + tau)
            return np.concatenate([dw, 0.5 * _qmul(q, np.concatenate([[0.0], w]))])

        inside = t[(t >= a) & (t <= b)] if b == t[-1] else t[(t >= a) & (t < b)]
        sol = solve_ivp(rhs, (a, b), y, method="DOP853", t_eval=inside, rtol=1e-12,
                        atol=1e-14, dense_output=True)
        assert sol.success
        out.append(sol.y.T)
        y = sol.sol(b)
    y = np.concatenate(out)
    return y[:, :3], y[:, 3:]


def _same_attitude(q, ref):
    """About half the angle between attitudes, frame by frame (the sign of q free)."""
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    ref = ref / np.linalg.norm(ref, axis=1, keepdims=True)
    return np.minimum(np.linalg.norm(q - ref, axis=1), np.linalg.norm(q + ref, axis=1))


TENSOR = [[2.0, -0.3, 0.1], [-0.3, 3.0, 0.2], [0.1, 0.2, 4.0]]   # not principal: the edge too
W0, Q0 = np.array([0.3, -0.7, 1.1]), np.array([0.6, -0.2, 0.7, 0.3])
# knots off the frames and off the rk4 substeps (t_end 6, 31 frames, dt 2e-3)
TIMES = np.array([0.5013, 1.7031, 3.2507, 4.4119])
VECTORS = np.array([[0.2, -0.1, 0.05], [-0.15, 0.3, 0.1], [0.05, 0.05, -0.2],
                    [0.1, -0.2, 0.3]])


def _run(system, method, t_end=6.0, frames=31):
    opts = dict(rtol=1e-12, atol=1e-14) if method == "dop853" else dict(dt=2e-3)
    return dz.simulate(system, W0, Q0, t_end=t_end, frames=frames, method=method, **opts)


# ---------------------------------------------------------------- tabulated torques

@pytest.mark.parametrize("frame", ["body", "world"])
@pytest.mark.parametrize("outside", ["zero", "hold"])
@pytest.mark.parametrize("method", ["dop853", "rk4"])
def test_a_tabulated_torque_follows_an_independent_solution(frame, outside, method):
    table = dz.TabulatedTorque(TIMES, VECTORS, frame=frame, outside=outside)
    traj = _run(dz.System(dz.Body.from_tensor(TENSOR), torques=[table]), method)

    def torque(mid, s, q, w):
        v = _lerp(TIMES, VECTORS, s, outside)
        if outside == "zero" and not TIMES[0] < mid < TIMES[-1]:
            v = np.zeros(3)   # the side of an end's jump the piece lies on
        return v if frame == "body" else _to_body(q, v)

    omega, q = reference(TENSOR, W0, Q0, traj.t, torque=torque, breaks=TIMES)
    # rk4 at dt = 2e-3 over 6 time units: its own error is ~1e-11; a straddled jump would be
    # ~dt·|τ| = 1e-4, a straddled kink ~dt²
    assert np.abs(traj.omega - omega).max() < 1e-9
    assert _same_attitude(traj.q, q).max() < 1e-9
    assert traj.drift.kept == ("q_norm",)


@pytest.mark.parametrize("method", ["dop853", "rk4"])
def test_a_constant_table_is_the_constant_torque(method):
    v = (0.1, -0.2, 0.05)
    body = dz.Body.from_tensor(TENSOR)
    const = _run(dz.System(body, torques=[dz.ConstantTorque(v)]), method)
    # knots outside the run: the same torque, bit for bit
    wide = dz.TabulatedTorque([-1.0, 100.0], [v, v])
    same = _run(dz.System(body, torques=[wide]), method)
    np.testing.assert_array_equal(same.omega, const.omega)
    np.testing.assert_array_equal(same.q, const.q)
    # knots inside it (held outside): every step ends on them, the run the same to round-off
    # for rk4 (its steps split in two at a knot), to its tolerance for dop853 (other steps)
    knotted = dz.TabulatedTorque(TIMES, np.tile(v, (len(TIMES), 1)), outside="hold")
    split = _run(dz.System(body, torques=[knotted]), method)
    bound = 1e-12 if method == "rk4" else 1e-10
    assert np.abs(split.omega - const.omega).max() < bound
    assert _same_attitude(split.q, const.q).max() < bound


def test_a_pulse_gives_its_impulse_exactly_to_a_body_at_rest_about_a_principal_axis():
    # τ_z a trapezoid 0 → 1 → 1 → 0 over knots off the step grid: ω_z(T) = ∫τ dt / I_z,
    # exact for a method that ends its steps on the knots (the law is linear on each piece)
    pulse = dz.TabulatedTorque([0.31, 0.77, 1.93, 2.41], [(0, 0, 0), (0, 0, 1), (0, 0, 1),
                                                         (0, 0, 0)])
    s = dz.System(dz.Body((2.0, 3.0, 4.0)), torques=[pulse])
    impulse = 0.5 * (0.77 - 0.31) + (1.93 - 0.77) + 0.5 * (2.41 - 1.93)
    for method, opts in [("rk4", dict(dt=0.25)), ("dop853", {}), ("dopri5", {})]:
        traj = dz.simulate(s, (0.0, 0.0, 0.0), t_end=3.0, method=method, **opts)
        assert traj.omega[-1, 2] == pytest.approx(impulse / 4.0, rel=1e-13, abs=0)
    # jumps at the start, on a frame and on a substep: each step takes the side it integrates
    for times in ([0.0, 0.5], [0.5, 1.5], [0.25, 0.75], [0.125, 1.0]):
        box = dz.TabulatedTorque(times, [(0, 0, 1), (0, 0, 1)])     # zero outside: jumps
        s = dz.System(dz.Body((2.0, 3.0, 4.0)), torques=[box])
        for method, opts in [("rk4", dict(dt=0.125)), ("dop853", {}), ("dopri5", {})]:
            traj = dz.simulate(s, (0.0, 0.0, 0.0), t_end=2.0, frames=17, method=method, **opts)
            # at every frame, in and after the box (a step on the wrong side of a jump is off
            # by a fraction of h·τ/I there, at the start and the end alike)
            exact = np.clip(traj.t - times[0], 0.0, times[1] - times[0]) / 4.0
            assert np.abs(traj.omega[:, 2] - exact).max() < 1e-13, (times, method)


def test_a_tabulated_torque_is_a_value_and_refuses_bad_tables_by_name():
    t = dz.TabulatedTorque(TIMES, VECTORS, frame="world", outside="hold")
    assert pickle.loads(pickle.dumps(t)) == t
    assert hash(pickle.loads(pickle.dumps(t))) == hash(t)
    assert t != dz.TabulatedTorque(TIMES, VECTORS, frame="world")
    assert "TabulatedTorque" in repr(t) and "knots=4" in repr(t)
    np.testing.assert_allclose(t.torque_at(1.1), 0.5 * (VECTORS[0] + VECTORS[1]), atol=0.02)
    with pytest.raises(ValueError, match="`times` must be strictly increasing"):
        dz.TabulatedTorque([0.0, 2.0, 1.0], np.zeros((3, 3)))
    with pytest.raises(ValueError, match="`times` must hold at least two"):
        dz.TabulatedTorque([0.0], np.zeros((1, 3)))
    with pytest.raises(ValueError, match="`times` must be finite"):
        dz.TabulatedTorque([0.0, np.nan], np.zeros((2, 3)))
    with pytest.raises(ValueError, match="`vectors` must give one vector per knot"):
        dz.TabulatedTorque([0.0, 1.0], np.zeros((3, 3)))
    with pytest.raises(ValueError, match=r"`vectors` must have shape \(K, 3\)"):
        dz.TabulatedTorque([0.0, 1.0], np.zeros((2, 2)))
    with pytest.raises(ValueError, match="`vectors` must be finite"):
        dz.TabulatedTorque([0.0, 1.0], [[0, 0, 0], [0, np.inf, 0]])
    with pytest.raises(ValueError, match="`outside` must be 'zero' or 'hold'"):
        dz.TabulatedTorque([0.0, 1.0], np.zeros((2, 3)), outside="extrapolate")
    with pytest.raises(ValueError, match="`frame` must be 'body' or 'world'"):
        dz.TabulatedTorque([0.0, 1.0], np.zeros((2, 3)), frame="lvlh")


def test_methods_that_cannot_run_a_tabulated_torque_refuse_it_by_name():
    s = dz.System(dz.Body((2.0, 3.0, 4.0)), torques=[dz.TabulatedTorque(TIMES, VECTORS)])
    for method in ("rk4_projected", "splitting", "exact"):
        with pytest.raises(dz.DzhanibekovError, match=f"'{method}' cannot run model "
                                                      "'tabulated_torque'"):
            dz.simulate(s, W0, method=method)


def test_a_batch_of_tabulated_systems_runs_each_row_as_alone():
    body = dz.Body((2.0, 3.0, 4.0))
    systems = [dz.System(body, torques=[dz.TabulatedTorque(TIMES, VECTORS * k)])
               for k in (1.0, -0.5)]
    batch = dz.simulate(systems, [W0, W0], t_end=6.0, frames=31, method="rk4", dt=2e-3)
    for k, s in enumerate(systems):
        one = dz.simulate(s, W0, t_end=6.0, frames=31, method="rk4", dt=2e-3)
        np.testing.assert_array_equal(batch.omega[k], one.omega)


# ---------------------------------------------------------------- wheel momentum schedules

AXES = [np.array([0.0, 1.0, 0.0]), np.array([1.0, 0.0, 1.0]) / math.sqrt(2.0)]
SPIN = [(np.array([0.7, 2.3, 4.1]), np.array([0.0, 1.5, -0.5])),       # spin-up then down
        (np.array([1.1, 3.9]), np.array([0.4, -0.6]))]


def _wheels_law(mid, s):
    """Σ h(s) a and Σ ḣ a, the slope of the piece holding `mid` (held outside)."""
    h = sum(a * np.interp(s, t, v) for a, (t, v) in zip(AXES, SPIN))
    hdot = sum(a * _slope(t, v[:, None], mid)[0] for a, (t, v) in zip(AXES, SPIN))
    return h, hdot


@pytest.mark.parametrize("method", ["dop853", "rk4", "rk4_projected"])
def test_a_wheel_schedule_follows_an_independent_solution(method):
    parts = [dz.Wheel(a, (t, v)) for a, (t, v) in zip(AXES, SPIN)]
    system = dz.System(dz.Body.from_tensor(TENSOR), parts=parts)
    assert system.kinds == ("wheel_schedule",)
    traj = _run(system, method)
    breaks = np.unique(np.concatenate([t for t, _ in SPIN]))
    omega, q = reference(TENSOR, W0, Q0, traj.t, wheel=_wheels_law, breaks=breaks)
    assert np.abs(traj.omega - omega).max() < 1e-9
    assert _same_attitude(traj.q, q).max() < 1e-9


def test_a_spin_up_keeps_the_momentum_in_space_and_changes_the_energy_by_the_wheels_work():
    up = dz.Wheel((0, 1, 0), ([1.0, 5.0], [0.0, 2.0]))
    system = dz.System(dz.Body.from_tensor(TENSOR), parts=[up])
    assert system.conserved == ("momentum", "momentum_world", "q_norm")
    traj = dz.simulate(system, W0, Q0, t_end=8.0, frames=801, method="dop853", rtol=1e-12,
                       atol=1e-14)
    assert traj.drift.kept == ("momentum", "momentum_world", "q_norm")
    assert traj.drift.momentum_world < 1e-11
    lw = traj.momentum_world
    assert np.abs(lw - lw[0]).max() < 1e-10 * np.linalg.norm(lw[0])
    # the body's energy ½ ωᵀIω changes at −ḣ (a·ω): 0.5 (a·ω) on (1, 5), nothing elsewhere
    tensor = np.asarray(TENSOR)
    energy = 0.5 * np.einsum("ni,ij,nj->n", traj.omega, tensor, traj.omega)
    # (ḣ constant on each frame interval: the knots are frames)
    mid = 0.5 * (traj.t[1:] + traj.t[:-1])
    hdot = np.where((mid > 1.0) & (mid < 5.0), 0.5, 0.0)
    wy = 0.5 * (traj.omega[1:, 1] + traj.omega[:-1, 1])
    work = np.concatenate([[0.0], np.cumsum(-hdot * wy * np.diff(traj.t))])
    assert np.abs(energy - energy[0] - work).max() < 1e-4      # the trapezoid's own error
    assert abs(energy[-1] - energy[0]) > 1e-2                  # and the change is real


@pytest.mark.parametrize("method", ["dop853", "rk4"])
def test_a_constant_schedule_is_the_constant_wheel(method):
    body = dz.Body.from_tensor(TENSOR)
    const = _run(dz.System(body, parts=[dz.Wheel(AXES[1], 0.8)]), method)
    wide = _run(dz.System(body, parts=[dz.Wheel(AXES[1], ([-1.0, 100.0], [0.8, 0.8]))]),
                method)
    # knots outside the run: the same law, to the last bit of ω = I⁻¹ (H − h a)
    assert np.abs(wide.omega - const.omega).max() < 1e-14
    knotted = _run(dz.System(body, parts=[dz.Wheel(AXES[1], (TIMES, np.full(4, 0.8)))]),
                   method)
    bound = 1e-12 if method == "rk4" else 1e-10
    assert np.abs(knotted.omega - const.omega).max() < bound
    assert _same_attitude(knotted.q, const.q).max() < bound


def test_a_scheduled_wheel_is_a_value_and_refuses_bad_schedules_by_name():
    w = dz.Wheel((0, 2, 0), ([0.0, 10.0], [0.0, 1.0]))
    assert w.is_scheduled and w.momentum_at(5.0) == 0.5 and w.momentum_at(20.0) == 1.0
    assert pickle.loads(pickle.dumps(w)) == w and hash(pickle.loads(pickle.dumps(w))) == hash(w)
    assert w != dz.Wheel((0, 2, 0), 1.0)
    assert "knots=2" in repr(w)
    with pytest.raises(ValueError, match="`momentum times` must be strictly increasing"):
        dz.Wheel((0, 1, 0), ([1.0, 0.0], [0.0, 1.0]))
    with pytest.raises(ValueError, match="`momentum` must be finite"):
        dz.Wheel((0, 1, 0), ([0.0, 1.0], [0.0, math.nan]))
    with pytest.raises(ValueError, match=r"`momentum` must have shape \(K,\)"):
        dz.Wheel((0, 1, 0), ([0.0, 1.0], [0.0, 1.0, 2.0]))
    with pytest.raises(ValueError, match="`momentum` must be a number or a schedule"):
        dz.Wheel((0, 1, 0), ([0.0, 1.0],))
    with pytest.raises(TypeError, match="`momentum`"):
        dz.Wheel((0, 1, 0), np.ones(2))


def test_saving_a_run_with_a_table_or_a_schedule_loads_the_same_system_and_a_callable_is_refused(
        tmp_path):
    pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    body = dz.Body((2.0, 3.0, 4.0))
    table = dz.TabulatedTorque(TIMES, VECTORS, frame="world", outside="hold")
    short = dz.TabulatedTorque([0.0, 0.5], [(0, 0, 0.1), (0.2, 0, 0)])   # fewer knots: padded
    schedule = dz.Wheel((0, 1, 0), ([0.0, 1.0], [0, 1]))
    for system in [dz.System(body, torques=[table]),
                   dz.System(body, parts=[schedule]),
                   dz.System(body, parts=[dz.Wheel((1, 0, 0), 0.5), schedule],
                             torques=[dz.ConstantTorque((0, 0, 0.1)), short, table])]:
        traj = dz.simulate(system, W0, t_end=1.0, method="dop853")
        back = dz.load(dz.save(traj, tmp_path / "run.nc"))
        assert back.system == system and back.system.kinds == system.kinds
        assert np.array_equal(back.omega, traj.omega) and np.array_equal(back.q, traj.q)
        assert np.array_equal(back.energy, traj.energy)
    callable_ = dz.System(body, torques=[table, dz.CallableTorque(lambda t, q, w: np.zeros(3))])
    traj = dz.simulate(callable_, W0, t_end=1.0, method="dop853")
    (tmp_path / "run.nc").unlink()
    with pytest.raises(ValueError, match=r"CallableTorque \(callable_torque\), which a file "
                                         "cannot hold"):
        dz.save(traj, tmp_path / "run.nc")
    assert not (tmp_path / "run.nc").exists()


# ---------------------------------------------------------------- Python-callable torques

def _feedback(t, q, omega):
    """A torque of all three arguments: a rate damper, a world-fixed push, a time ramp."""
    return -0.05 * omega + _to_body(q, np.array([0.0, 0.1, -0.05])) + 0.01 * t


@pytest.mark.parametrize("method", ["dop853", "rk4"])
def test_a_callable_torque_follows_an_independent_solution(method):
    calls = []

    def torque(t, q, omega):
        calls.append((q.shape, omega.shape, abs(np.linalg.norm(q) - 1.0)))
        return _feedback(t, q, omega)

    system = dz.System(dz.Body.from_tensor(TENSOR), torques=[torque])   # a plain function
    assert system.kinds == ("callable_torque",) and system.conserved == ("q_norm",)
    traj = _run(system, method, t_end=2.0, frames=11)
    assert traj.drift.kept == ("q_norm",)
    # the function saw the user's time, a unit q (4,) and body rates (3,), at every evaluation
    assert calls and all(c[:2] == ((4,), (3,)) and c[2] < 1e-15 for c in calls)
    omega, q = reference(TENSOR, W0, Q0, traj.t,
                         torque=lambda mid, s, q, w: _feedback(s, q, w))
    assert np.abs(traj.omega - omega).max() < 1e-9
    assert _same_attitude(traj.q, q).max() < 1e-9


@pytest.mark.parametrize("method", ["dop853", "rk4"])
def test_a_callable_that_is_the_constant_torque_gives_the_same_run(method):
    v = np.array([0.1, -0.2, 0.05])
    body = dz.Body.from_tensor(TENSOR)   # not principal: the function sees the user's axes
    const = _run(dz.System(body, torques=[dz.ConstantTorque(v)]), method, t_end=2.0)
    mine = _run(dz.System(body, torques=[dz.CallableTorque(lambda t, q, w: v)]), method,
                t_end=2.0)
    # the principal axes' turn there and back: round-off
    assert np.abs(mine.omega - const.omega).max() < 1e-13
    assert _same_attitude(mine.q, const.q).max() < 1e-13


class Boom(Exception):
    pass


def test_a_callable_that_fails_stops_the_run_with_its_own_error():
    body = dz.Body((2.0, 3.0, 4.0))

    def raises(t, q, omega):
        if t > 0.5:
            raise Boom("the controller gave up")
        return np.zeros(3)

    for method in ("rk4", "dop853"):
        with pytest.raises(Boom, match="gave up"):
            dz.simulate(dz.System(body, torques=[raises]), W0, t_end=2.0, method=method)
    # the same system runs again once the failure is past (nothing kept between runs)
    ok = dz.System(body, torques=[dz.CallableTorque(lambda t, q, w: np.zeros(3))])
    assert np.isfinite(dz.simulate(ok, W0, t_end=1.0).omega).all()
    for bad, match in [(lambda t, q, w: np.zeros(2), r"three real numbers.*shape \(2,\)"),
                       (lambda t, q, w: np.zeros((3, 1)), r"three real numbers.*\(3, 1\)"),
                       (lambda t, q, w: "abc", "three real numbers"),
                       (lambda t, q, w: None, "three real numbers"),
                       (lambda t, q, w: (0.0, math.nan, 0.0), "finite")]:
        with pytest.raises(ValueError, match=f"`torque` function must return .*{match}"):
            dz.simulate(dz.System(body, torques=[bad]), W0, t_end=1.0, method="rk4")
    with pytest.raises(TypeError, match="`func` must be callable"):
        dz.CallableTorque(3.0)
    with pytest.raises(TypeError, match=r"`torques\[0\]`"):
        dz.System(body, torques=["not a function"])


def test_a_batch_of_callable_systems_runs_each_row_as_alone_and_a_failure_names_its_row():
    body = dz.Body((2.0, 3.0, 4.0))
    systems = [dz.System(body, torques=[lambda t, q, w, k=k: -k * w]) for k in (0.1, 0.3)]
    batch = dz.simulate(systems, [W0, W0], t_end=2.0, frames=5, method="rk4", dt=1e-2)
    for k, s in enumerate(systems):
        one = dz.simulate(s, W0, t_end=2.0, frames=5, method="rk4", dt=1e-2)
        np.testing.assert_array_equal(batch.omega[k], one.omega)

    def raises(t, q, w):
        raise Boom("row 1")

    with pytest.raises(Boom):
        dz.simulate([systems[0], dz.System(body, torques=[raises])], [W0, W0], t_end=1.0,
                    method="rk4", dt=1e-2)


def test_a_callable_torque_is_a_value():
    t = dz.CallableTorque(_feedback)
    assert pickle.loads(pickle.dumps(t)) == t and hash(pickle.loads(pickle.dumps(t))) == hash(t)
    assert dz.CallableTorque(t) == t and repr(t) == "CallableTorque(_feedback)"
    s = dz.System(dz.Body((2.0, 3.0, 4.0)), torques=[_feedback])
    assert s.torques == (t,) and pickle.loads(pickle.dumps(s)) == s


@pytest.mark.parametrize("rate, moment", [(2.0**300, 1.0), (1.0, 2.0**900),
                                          (2.0**-400, 2.0**-500)])
def test_the_new_models_scale_like_the_built_ins_at_the_edges_of_float64(rate, moment):
    # a run at rates ×s, moments ×m, times /s is the unit run scaled: each new model gives the
    # run of its built-in twin (a constant torque, a constant wheel), the function seeing the
    # user's own time and rates
    body = dz.Body.from_tensor(np.asarray(TENSOR) * moment)
    v = np.array([0.1, -0.2, 0.05]) * moment * rate**2
    run = dict(t_end=2.0 / rate, method="rk4", dt=0.01 / rate)
    const = dz.simulate(dz.System(body, torques=[dz.ConstantTorque(v)]), W0 * rate, **run)
    seen = []

    def f(t, q, omega):
        seen.append((t * rate, np.linalg.norm(omega) / rate))
        return v

    table = dz.TabulatedTorque([0.5 / rate, 1.5 / rate], [v, v], outside="hold")
    for twin in (dz.System(body, torques=[f]), dz.System(body, torques=[table])):
        traj = dz.simulate(twin, W0 * rate, **run)
        assert np.abs(traj.omega - const.omega).max() <= 1e-14 * rate
    assert max(t for t, _ in seen) == pytest.approx(2.0)
    assert 1.0 < max(w for _, w in seen) < 2.0
    h = 0.8 * moment * rate
    wheel = dz.simulate(dz.System(body, parts=[dz.Wheel((0, 1, 0), h)]), W0 * rate, **run)
    scheduled = dz.simulate(dz.System(body, parts=[dz.Wheel((0, 1, 0), (
        [0.5 / rate, 1.5 / rate], [h, h]))]), W0 * rate, **run)
    assert np.abs(scheduled.omega - wheel.omega).max() <= 1e-12 * rate
