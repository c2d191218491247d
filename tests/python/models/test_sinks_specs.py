"""The energy sinks' Python classes (issue 31 through the seam of issue 29): each is a spec of
its core model, and what the spec layer gives every part holds for them: their state in a run
and in xarray under the part's name, a file round trip, a scene's ``[[parts]]``; a body
without a mass is refused by name (the hub of a moving mass needs it)."""

from __future__ import annotations

import numpy as np
import pytest

import dzhanibekov as dz
from dzhanibekov.scenes import Scene

BOX = dz.Body.box(1.0, 2.0, 3.0, mass=2.0)
START = (0.3, 0.2, 1.0), (1.0, 0.0, 0.0, 0.0)


def rod(y: float) -> dz.Hinge:
    """A rod hinged at (0.5, y, 0), flapping about z."""
    return dz.Hinge(0.2, (1e-4, 0.01, 0.01), (0.5, y, 0.0), (0.0, 0.0, 1.0), (1.0, 0.0, 0.0),
                    0.3, 2.0, 0.05, angle0=0.05)


SINKS = {
    "spring_mass": dz.SpringMassDamper(0.1, (0.0, 0.0, 0.5), (1.0, 0.0, 0.0), 4.0, 0.2,
                                       x0=0.01),
    "hinge": rod(0.0),
    "slosh": dz.Slosh(0.1, (0.0, 0.0, 0.2), 0.1, 0.01, (1.0, 0.0, 0.0)),
}


@pytest.mark.parametrize("name", list(SINKS))
def test_a_sink_is_the_spec_of_its_core_model(name):
    part = SINKS[name]
    assert part.model == name and type(part).__name__ in dz.__all__
    assert list(part.fields()) == [p[0] for p in dz.MODELS[name].params]
    traj = dz.simulate(dz.System(BOX, parts=[part]), *START, t_end=1.0, frames=5,
                       method="rk4", dt=0.01)
    # its state under its name, as wide as the core declares, and the same in xarray
    width = sum(w for _, w, _, _ in dz.MODELS[name].state)
    assert traj.parts[name].shape == (5, width)
    ds = traj.to_xarray()
    columns = np.column_stack([ds[f"{name}_{field}"].values.reshape(5, -1)
                               for field, _, _, _ in dz.MODELS[name].state])
    np.testing.assert_array_equal(columns, traj.parts[name])
    # the part moves: its state changes over the run
    assert not np.allclose(traj.parts[name][0], traj.parts[name][-1])


def test_sinks_round_trip_through_a_file(tmp_path):
    # (one of each: a file holds the state of one part of each kind, see the report)
    system = dz.System(BOX, parts=list(SINKS.values()))
    traj = dz.simulate(system, *START, t_end=1.0, frames=3, method="rk4", dt=0.01)
    back = dz.load(dz.save(traj, tmp_path / "sinks.nc"))
    assert back.system == system and back.system.parts == system.parts
    assert back.body.mass == BOX.mass
    for name, state in traj.parts.items():
        np.testing.assert_array_equal(back.parts[name], state)


def test_a_scene_takes_sinks_in_its_parts_list():
    text = """title = "sinks"

[body]
tensor = [[2.0, 0.0, 0.0], [0.0, 3.0, 0.0], [0.0, 0.0, 1.5]]
mass = 2.0

[start]
omega = [0.3, 0.2, 1.0]

[run]
t_end = 1.0
frames = 3
method = "rk4"
dt = 0.01

[[parts]]
kind = "spring_mass"
mass = 0.1
anchor = [0.0, 0.0, 0.5]
direction = [1.0, 0.0, 0.0]
stiffness = 4.0
damping = 0.2
x0 = 0.01

[[parts]]
kind = "slosh"
mass = 0.1
pivot = [0.0, 0.0, 0.2]
length = 0.1
damping = 0.01
direction0 = [1.0, 0.0, 0.0]
"""
    scene = Scene.from_toml(text, "sinks", source="sinks.toml")
    assert scene.system.parts == (SINKS["spring_mass"], SINKS["slosh"])
    assert scene.system.body.mass == 2.0
    traj = scene.run()
    assert set(traj.parts) == {"spring_mass", "slosh"}
    assert traj.drift.energy_balance < 1e-3 * traj.drift.energy


@pytest.mark.parametrize("name", list(SINKS))
def test_a_body_without_a_mass_is_refused_by_name(name):
    system = dz.System(dz.Body((1.0, 2.0, 3.0)), parts=[SINKS[name]])
    with pytest.raises(ValueError, match="mass"):
        dz.simulate(system, *START, t_end=0.1, frames=2, method="rk4", dt=0.01)


def test_several_hinges_on_one_body_each_keep_their_state():
    system = dz.System(BOX, parts=[rod(0.0), rod(0.2)])
    traj = dz.simulate(system, *START, t_end=1.0, frames=3, method="rk4", dt=0.01)
    assert set(traj.parts) == {"hinge_0", "hinge_1"}
    # the same start, different places: different motions; the energy falls and the balance
    # (energy plus the dissipated work) is kept a thousand times better, H to round-off
    assert not np.array_equal(traj.parts["hinge_0"], traj.parts["hinge_1"])
    assert traj.drift.energy_balance < 1e-3 * traj.drift.energy
    assert traj.drift.momentum_world < 1e-9
