"""The methods as the core declares them: dz.METHODS is the core's registry, read-only, and
what it says about each method holds when the method runs."""

import copy
import pickle

import numpy as np
import pytest

import dzhanibekov as dz
from dzhanibekov import _core

PAPER = dz.Body(dz.PAPER_INERTIA)


def test_the_mapping_is_the_cores_registry_and_read_only():
    assert list(dz.METHODS) == [m.name for m in _core.METHODS]
    assert all(isinstance(m, dz.MethodInfo) for m in dz.METHODS.values())
    with pytest.raises(TypeError):
        dz.METHODS["rk5"] = dz.METHODS["rk4"]  # type: ignore[index]
    with pytest.raises(AttributeError):
        dz.METHODS["rk4"].order = 5  # type: ignore[misc]


def test_method_infos_pickle_and_copy_to_the_same_entry():
    for name, info in dz.METHODS.items():
        for back in (pickle.loads(pickle.dumps(info)), copy.deepcopy(info), copy.copy(info)):
            assert (back.name, back.order, back.adaptive, back.keeps, back.rhs_per_step, back.batch,
                    back.models) == (name, info.order, info.adaptive, info.keeps, info.rhs_per_step,
                                     info.batch, info.models)


def _subject(info):
    """The paper's body for a method that runs the free body; for one made for torques (such
    as ``splitting_exact``), the same body under a zero torque: the same motion."""
    if "free" in info.models:
        return PAPER
    return dz.System(PAPER, torques=[dz.ConstantTorque((0.0, 0.0, 0.0))])


def test_what_a_method_keeps_it_keeps_to_round_off():
    """Over 4000 steps of the paper's flipping motion each listed invariant stays within a few
    thousand ulps; RK4 (which keeps nothing) drifts far more at the same step."""
    for name, info in dz.METHODS.items():
        traj = dz.simulate(_subject(info), (0.01, 0.01, 1.0), t_end=200.0, frames=11, dt=0.05,
                           method=name, **({"rtol": 1e-6} if info.adaptive else {}))
        for invariant in info.keeps:
            assert getattr(traj.drift, invariant) < 1e-12, (name, invariant, traj.drift)
    rk4 = dz.simulate(PAPER, (0.01, 0.01, 1.0), t_end=200.0, frames=11, dt=0.05)
    assert min(rk4.drift) > 1e-11


def test_the_cost_per_step_is_what_a_run_counts():
    for name, info in dz.METHODS.items():
        if info.order is None:
            continue  # no steps
        traj = dz.simulate(_subject(info), (0.01, 0.01, 1.0), t_end=20.0, frames=5, dt=0.01,
                           method=name, **({"rtol": 1e-6} if info.adaptive else {}))
        if info.adaptive:
            # accepted and rejected attempts each cost rhs_per_step; the first f and the
            # interpolants add a few more
            attempts = traj.n_steps + traj.n_rejected
            assert info.rhs_per_step * attempts <= traj.nfev <= (info.rhs_per_step + 3) * attempts + 1
        else:
            assert traj.nfev == info.rhs_per_step * traj.n_steps, name


def test_the_methods_a_batch_runs_in_lanes_equal_single_runs_bit_for_bit():
    omega = np.array([[0.01, 0.01, 1.0], [0.3, 0.02, 0.9], [0.0, 1.0, 0.01]])
    for name, info in dz.METHODS.items():
        if not info.batch:
            continue
        batch = dz.simulate(PAPER, omega, t_end=10.0, frames=5, dt=0.01, method=name)
        for i, w in enumerate(omega):
            one = dz.simulate(PAPER, w, t_end=10.0, frames=5, dt=0.01, method=name)
            np.testing.assert_array_equal(batch.omega[i], one.omega)
            np.testing.assert_array_equal(batch.q[i], one.q)


def test_orders_are_what_halving_the_step_shows():
    """The error against the closed form falls by 2^order when the step halves."""
    body = dz.Body((1.0, 2.0, 3.0))
    omega0 = (0.3, 0.1, 1.0)
    exact = dz.simulate(body, omega0, t_end=10.0, frames=3, method="exact")
    for name, info in dz.METHODS.items():
        if info.adaptive or info.order is None or "free" not in info.models:
            continue  # a method made for torques is exact on the free body: its order is
            # shown against a torque in test_orbit.py
        err = []
        # steps whose errors stay well above round-off (order 6 at dt = 0.02 is already there)
        for dt in (0.02, 0.01) if info.order <= 4 else (0.2, 0.1):
            run = dz.simulate(body, omega0, t_end=10.0, frames=3, dt=dt, method=name)
            err.append(np.abs(run.omega - exact.omega).max())
        observed = np.log2(err[0] / err[1])
        assert abs(observed - info.order) < 0.3, (name, observed)


def test_defaults_come_from_the_core():
    import inspect

    sig = inspect.signature(dz.RunOptions)        # simulate's run options
    assert sig.parameters["method"].default == _core.DEFAULT_METHOD in dz.METHODS
    assert sig.parameters["max_steps"].default == _core.DEFAULT_MAX_STEPS
    assert 0 < _core.DEFAULT_ATOL < _core.DEFAULT_RTOL < 1
