"""Every model the core has goes through a file and comes back as itself (issue 29): a run of
each model kind, enumerated from `dz.MODELS` (the parts from their classes' examples, not a
hand list), saved and loaded compares `==` to the run's system, draws the same outline, and a
loaded bare body or deployment compares `==` to the body or deployment that was run."""

from __future__ import annotations

import numpy as np
import pytest

import dzhanibekov as dz
from dzhanibekov.parts import example
from every_model import BOX, DEPLOYMENT, START, system_of

pytest.importorskip("xarray")
pytest.importorskip("h5netcdf")

STORABLE = [n for n, m in dz.MODELS.items()
            if m.law or all(kind != "function" for _, kind, _, _, _ in m.params)]


def _outline(body):
    shape = getattr(body, "shape", None)  # (a deployment has none)
    return None if shape is None else (shape.vertices, shape.edges, shape.faces)


def _same_outline(a, b):
    if a is None or b is None:
        return a is b
    return all((x is None and y is None) or np.array_equal(x, y) for x, y in zip(a, b))


def test_the_list_covers_every_model_but_those_a_file_cannot_hold():
    # only the models that hold code are left out
    left_out = set(dz.MODELS) - set(STORABLE)
    assert "callable_torque" in left_out and "damper" not in left_out
    assert all(any(kind == "function" for _, kind, _, _, _ in dz.MODELS[n].params)
               for n in left_out)


@pytest.mark.parametrize("name", STORABLE)
def test_a_run_of_every_model_round_trips_through_a_file(name, tmp_path):
    ran = system_of(name)
    traj = dz.simulate(ran, *START, t_end=1.0, frames=3, method="rk4", dt=0.01)
    back = dz.load(dz.save(traj, tmp_path / "run.nc"))
    assert back.system == traj.system and back.system == ran and ran == back.system
    assert hash(back.system) == hash(traj.system)
    assert back.system.kinds == (name,)
    assert _same_outline(_outline(back.body), _outline(traj.body))
    np.testing.assert_array_equal(back.q, traj.q)
    # a batch of it too (its rows share the system)
    batch = dz.simulate([ran, ran], START[0], t_end=1.0, frames=3, method="rk4", dt=0.01)
    again = dz.load(dz.save(batch, tmp_path / "batch.nc"))
    assert list(again.systems) == list(batch.systems)
    assert _same_outline(_outline(again.systems[1].body), _outline(BOX)) or name == "deployment"


def test_a_run_with_code_is_refused_by_name():
    traj = dz.simulate(system_of("callable_torque"), *START, t_end=0.1, frames=2)
    with pytest.raises(ValueError, match=r"CallableTorque \(callable_torque\)"):
        dz.save(traj, "never.nc")


@pytest.mark.parametrize("body", [
    dz.Body.box(1.0, 2.0, 3.0), dz.Body.ellipsoid(1.0, 2.0, 3.0), dz.Body.cylinder(1.0, 3.0),
    dz.Body.wing_nut(),                                               # a composite
    dz.Body.from_mesh([(0, 0, 0), (2, 0, 0), (0, 3, 0), (0, 0, 4)],
                      [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)], mass=1.0),
], ids=["box", "ellipsoid", "cylinder", "composite", "mesh"])
def test_a_loaded_body_keeps_its_outline_and_is_the_body_saved(body, tmp_path):
    traj = dz.simulate(body, *START, t_end=0.5, frames=2)
    back = dz.load(dz.save(traj, tmp_path / "body.nc"))
    assert back.system == body and back.body == body
    assert back.body.mass == body.mass
    np.testing.assert_array_equal(back.body.center_of_mass, body.center_of_mass)
    assert back.body.shape is not None
    assert _same_outline(_outline(back.body), _outline(body))
    # what the pictures draw of it is the live run's outline, not the box of its moments
    from dzhanibekov.scenes.parse import drawn_shape
    drawn, live = drawn_shape(back.body, None, back.body.inertia), \
        drawn_shape(body, None, body.inertia)
    np.testing.assert_array_equal(drawn.vertices, live.vertices)


def test_a_body_given_by_its_moments_has_no_outline_to_keep(tmp_path):
    body = dz.Body((1.0, 2.0, 3.0))
    back = dz.load(dz.save(dz.simulate(body, *START, t_end=0.5, frames=2), tmp_path / "m.nc"))
    assert back.body.shape is None and back.system == body
    assert "body_vertices" not in dz.simulate(body, *START, t_end=0.5, frames=2).to_xarray()


def test_systems_compare_by_what_defines_them():
    sys_ = dz.System(BOX)
    assert sys_ == BOX and BOX == sys_ and hash(sys_) == hash(BOX)
    assert dz.System(DEPLOYMENT) == DEPLOYMENT and DEPLOYMENT == dz.System(DEPLOYMENT)
    assert dz.System(BOX, parts=[example("wheel")]) != BOX
    assert BOX != dz.System(BOX, torques=[example("gravity_gradient")])
    assert dz.System(BOX) != dz.System(dz.Body((1.0, 2.0, 3.0)))
