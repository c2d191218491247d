"""The registry of models (`dz.MODELS`) is the core's declaration of every model, and the
Python side follows it: each part class makes the core's model of its kind, the methods each
model lists run it and the others refuse it, and what a system keeps is what its models'
declarations say (issue 29: a part declares itself once)."""

from __future__ import annotations

import numpy as np
import pytest

import dzhanibekov as dz

BODY = dz.Body((1.0, 2.0, 3.0))

# one instance of every part class, the systems the core's models come from
PARTS = {
    "damper": dz.Damper(0.1, 0.05),
    "wheel": dz.Wheel((0.0, 1.0, 0.0), 0.5),
    "wheel_schedule": dz.Wheel((1.0, 0.0, 0.0), ([0.0, 1.0], [0.0, 0.2])),
    "quaternion_feedback": dz.QuaternionFeedback(0.1, 0.3, period=0.05),
}
FIELD = dz.MagneticField(dz.circular_orbit_rate(500e3), inclination=1.2)
TORQUES = {
    "gravity_gradient": dz.GravityGradient(0.3),
    "constant_torque": dz.ConstantTorque((0.0, 0.0, 0.01)),
    "tabulated_torque": dz.TabulatedTorque([0.0, 1.0], [(0.0, 0.0, 0.0), (0.0, 0.01, 0.0)]),
    "callable_torque": dz.CallableTorque(lambda t, q, w: np.zeros(3)),
    "residual_dipole": dz.ResidualDipole(FIELD, (0.0, 0.0, 1e-3)),
    "bdot": dz.BDot(FIELD, gain=1e-5, period=0.05),
    "momentum_dumping": dz.MomentumDumping(FIELD, gain=1e-3, period=0.05),
    "controller": dz.Controller(lambda t, q, w, b, h: np.zeros(3), period=0.05),
}


def system_of(name: str) -> dz.System:
    if name == "free":
        return dz.System(BODY)
    if name == "deployment":
        return dz.System(dz.Deployment([0.0, 1.0], [(1.0, 2.0, 3.0), (1.0, 3.0, 2.0)]))
    if name in PARTS:
        return dz.System(BODY, parts=[PARTS[name]])
    return dz.System(BODY, torques=[TORQUES[name]])


def test_every_model_of_the_core_has_a_python_class_that_makes_it():
    assert list(dz.MODELS)[:2] == ["free", "deployment"]
    assert all(dz.MODELS[n].law for n in ("free", "deployment"))
    parts = [n for n, m in dz.MODELS.items() if not m.law]
    assert sorted(parts) == sorted([*PARTS, *TORQUES])
    for name in dz.MODELS:
        assert system_of(name).kinds == (name,), name
    for name in parts:
        info = dz.MODELS[name]
        # an external torque goes in `torques`, an internal part in `parts`
        assert info.external == (name in TORQUES), name
        # a part's state is what its runs report beside the body's (none: nothing)
        width = sum(w for _, w, _, _ in info.state)
        assert system_of(name)._core.parts == ([(name, width)] if width else [])


@pytest.mark.parametrize("name", list(dz.MODELS))
def test_the_methods_a_model_lists_run_it_and_the_others_refuse_it(name):
    system = system_of(name)
    runs = set(dz.MODELS[name].methods)
    assert runs == {m for m, info in dz.METHODS.items() if name in info.models}
    assert "rk4" in runs and "dop853" in runs  # the general methods run every model
    start = (0.3, 0.2, 1.0), (1.0, 0.0, 0.0, 0.0)
    for method in dz.METHODS:
        if method in runs:
            continue
        with pytest.raises(ValueError, match=method):
            dz.simulate(system, *start, t_end=0.1, frames=2, method=method)


@pytest.mark.parametrize("name", list(dz.MODELS))
def test_a_system_keeps_what_its_models_declare(name):
    system = system_of(name)
    info = dz.MODELS[name]
    assert set(system.conserved) <= set(info.keeps) | set(info.defines) | {"energy_balance"}
    # a part that dissipates makes the energy plus the dissipated work the kept quantity
    assert ("energy_balance" in system.conserved) == (info.energy == "dissipates")
    # what does work keeps no energy; what neither gives nor takes does not stop a free
    # body keeping it
    if info.energy == "does work":
        assert "energy" not in system.conserved
