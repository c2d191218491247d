"""The energy sinks as the core runs them (built through the seam: ``_core.Part(kind, fields)``
and a body with a mass), against references that share nothing with it: the quasi-rigid
energy-sink estimate (dzhanibekov.energy_sink, Newton–Euler of each part on a steadily turning
body) in the small-damper limit, and (slow) Lagrange's equations derived by sympy
(tests/python/sinks_reference.py) integrated by DOP853."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from dzhanibekov import _core, energy_sink

HUB = np.diag([1.0, 1.0, 0.5])  # a minor-axis spinner about z
HUB_MASS = 10.0


def _run(part, omega0, t_end, frames, method="dop853", rtol=1e-11, dt=None):
    body = _core.RigidBody(tuple(np.diag(HUB)))
    kind, fields = part
    system = _core.System(body, [_core.Part(kind, fields)], mass=HUB_MASS)
    options = _core.RunOptions(t_end, frames, dt=dt, method=method, rtol=rtol, flips=False)
    return _core.simulate_batch([system], np.array([omega0], float),
                                np.array([[1.0, 0.0, 0.0, 0.0]]), options, True)


def _spring(s):
    return SimpleNamespace(mass=0.01 * s, anchor=[0.4, 0.0, 0.0], direction=[0.0, 0.0, 1.0],
                           stiffness=0.0144 * s, damping=0.0048 * s)


def _fields(ns):
    return {k: (list(v) if isinstance(v, list) else v) for k, v in vars(ns).items()}


def test_a_body_without_mass_is_refused_for_a_moving_part():
    part = _fields(_spring(1.0))
    body = _core.RigidBody((1.0, 1.0, 0.5))
    with pytest.raises(ValueError, match="mass"):
        _core.simulate_batch([_core.System(body, [_core.Part("spring_mass", part)])],
                             np.array([[0.0, 0.0, 1.0]]), np.array([[1.0, 0.0, 0.0, 0.0]]),
                             _core.RunOptions(1.0, 2, method="rk4", dt=0.01), False)
    with pytest.raises(ValueError, match="mass"):
        _core.System(body, [], mass=-1.0)


def test_the_nutation_grows_at_the_energy_sink_estimates_rate():
    # An axial spring–mass damper on a minor-axis spinner: the angle between H (fixed in
    # space) and the body's z axis grows as e^{t/τ}; the core's τ against the quasi-rigid
    # estimate, whose error must fall as the damper shrinks (as the sympy reference's did:
    # −0.45 % at s = 1, −0.12 % at s = ½)
    errors = []
    for s in (1.0, 0.5):
        part = _spring(s)
        w0 = [0.02, 0.0, 2.0]
        est = energy_sink.estimate(HUB, HUB_MASS, [("spring_mass", part)], w0)
        t_end = 1.6 * est.time_constant
        out = _run(("spring_mass", _fields(part)), w0, t_end, 3001)
        # H in space, from the start: the composite about the system's mass centre (the
        # mass at rest at its anchor, the reduced mass μ = m M_h / M), times ω₀
        mu = part.mass * HUB_MASS / (part.mass + HUB_MASS)
        r = np.array(part.anchor)
        h0 = (HUB + mu * (r @ r * np.eye(3) - np.outer(r, r))) @ w0
        q = out.q[0]
        z = Rotation.from_quat(q, scalar_first=True).apply([0.0, 0.0, 1.0])
        theta = np.arccos(np.clip(z @ h0 / np.linalg.norm(h0), -1.0, 1.0))
        keep = theta < 0.1
        times = out.t[keep] if out.t.ndim == 1 else out.t[0][keep]
        tau = 1.0 / np.polyfit(times, np.log(theta[keep]), 1)[0]
        errors.append(abs(est.time_constant / tau - 1))
        # the run kept H in space and the energy balance, which it says it keeps, while the
        # energy fell
        names = ("energy", "momentum", "momentum_world", "q_norm", "jacobi", "energy_balance")
        drift = dict(zip(names, [d[0] for d in out.runs.drift]))
        assert {"momentum_world", "energy_balance"} <= set(out.runs.kept), out.runs.kept
        assert drift["momentum_world"] < 1e-9 and drift["energy_balance"] < 1e-9, drift
        assert drift["energy"] > 1e-3, drift
    assert errors[0] < 0.01 and errors[1] < 0.6 * errors[0], errors


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["spring", "hinge", "slosh"])
def test_each_part_moves_as_lagranges_equations_say(kind):
    # the core (DOP853 at rtol 1e-12) against sympy's Lagrange equations (DOP853 at 1e-12),
    # both from the same start, over ten time units
    from sinks_reference import Lagrange

    inertia = np.array([[3.0, -0.2, 0.1], [-0.2, 4.0, 0.3], [0.1, 0.3, 5.0]])
    w0 = [0.3, -0.7, 1.1]
    if kind == "spring":
        part = dict(mass=0.3, anchor=[0.4, -0.3, 0.6], direction=[0.2, 0.9, -0.4],
                    stiffness=2.0, damping=0.15)
        core, configs, rates = ("spring_mass", {**part, "x0": 0.05, "rate0": 0.2}), [[0.05]], [[0.2]]
    elif kind == "hinge":
        part = dict(mass=0.25, moments=[0.01, 0.03, 0.035], hinge=[0.8, 0.5, -0.2],
                    axis=[0.1, 1.0, 0.3], arm=[1.0, -0.1, 0.2], length=0.6, stiffness=0.7,
                    damping=0.05)
        core, configs, rates = ("hinge", {**part, "angle0": 0.3, "rate0": -0.4}), [[0.3]], [[-0.4]]
    else:
        n0 = np.array([0.3, -0.8, 0.52]) / np.linalg.norm([0.3, -0.8, 0.52])
        part = dict(mass=0.35, pivot=[-0.5, 0.3, 0.7], length=0.45, damping=0.04)
        core = ("slosh", {**part, "direction0": list(n0), "rate0": [0.1, 0.2, 0.3]})
        configs, rates = [list(n0)], [[0.1, 0.2, 0.3]]
    start = {"start": configs[0]} if kind == "slosh" else {}
    reference = Lagrange(inertia, 4.0, [dict(kind=kind, **part, **start)])
    times = np.linspace(0.0, 10.0, 11)
    y = reference.solve(reference.start(w0, [1, 0, 0, 0], configs, rates), times)
    body = _core.RigidBody.from_tensor(inertia.tolist())
    system = _core.System(body, [_core.Part(*core)], mass=4.0)
    options = _core.RunOptions(10.0, 11, method="dop853", rtol=1e-12, flips=False)
    out = _core.simulate_batch([system], np.array([w0], float),
                               np.array([[1.0, 0.0, 0.0, 0.0]]), options, True)
    omega = reference.omega(y)
    # measured: 4.8e-13 (spring), 1.5e-13 (hinge), 1.7e-13 (slosh)
    assert np.abs(out.omega[0] - omega).max() < 1e-11
