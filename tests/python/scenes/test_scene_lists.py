"""Scenes take lists (issue 29): ``[[parts]]`` and ``[[torques]]`` arrays of tables, each with
the ``kind`` of a model and that model's parameters, hold any number of parts of every model a
file can hold (enumerated from `dz.MODELS`); the single tables of before are aliases of one
entry; errors name the entry and its key."""

from __future__ import annotations

import numpy as np
import pytest

import dzhanibekov as dz
from dzhanibekov.parts import SPECS, example
from dzhanibekov.parts._columns import storable_models
from dzhanibekov.scenes import Scene
from dzhanibekov.scenes.parse import SceneError, part_table

HEAD = """title = "lists"

[body]
inertia = [2.0, 3.0, 1.5]

[start]
omega = [0.3, 0.2, 1.0]

[run]
t_end = 1.0
frames = 3
method = "dop853"
"""


def _toml(value):
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return repr(float(value))


def _entry(key, table):
    return f"\n[[{key}]]\n" + "".join(f"{k} = {_toml(v)}\n" for k, v in table.items())


@pytest.mark.parametrize("kind", storable_models())
def test_every_model_a_file_can_hold_a_scene_can(kind):
    part = example(kind)
    key = "torques" if part.external else "parts"
    twice = not dz.MODELS[kind].unique          # (a system holds one gravity gradient)
    head = HEAD
    if "moving mass" in dz.MODELS[kind].traits:  # (its hub needs the body's mass)
        head = HEAD.replace("inertia = [2.0, 3.0, 1.5]",
                            "tensor = [[2.0, 0.0, 0.0], [0.0, 3.0, 0.0], [0.0, 0.0, 1.5]]\n"
                            "mass = 2.0")
    text = head + _entry(key, part_table(part)) * (1 + twice)
    scene = Scene.from_toml(text, "lists", source="lists.toml")
    listed = scene.system.torques if part.external else scene.system.parts
    assert listed == (part,) * (1 + twice) and scene.system.kinds == (kind,)
    if not twice:
        with pytest.raises(SceneError, match=rf"`{key}\[1\]\.kind` is a second {kind!r}"):
            Scene.from_toml(text + _entry(key, part_table(part)), "lists")
    again = Scene.from_toml(scene.to_toml(), "lists")          # written and read back
    assert again == scene and again.system == scene.system
    assert scene.run().system == scene.system


def test_a_scene_keeps_the_order_of_its_parts_after_the_single_tables():
    text = HEAD + """
[wheel]
axis = [0.0, 0.0, 1.0]
momentum = 0.1

[[parts]]
kind = "damper"
inertia = 0.05
damping = 0.02

[[parts]]
kind = "wheel"
axis = [0.0, 1.0, 0.0]
momentum = 0.2

[[torques]]
kind = "constant_torque"
vector = [0.0, 0.0, 0.001]
"""
    scene = Scene.from_toml(text, "order", source="order.toml")
    assert scene.system == dz.System(
        dz.Body((2.0, 3.0, 1.5)),
        parts=[dz.Wheel((0, 0, 1), 0.1), dz.Damper(0.05, 0.02), dz.Wheel((0, 1, 0), 0.2)],
        torques=[dz.ConstantTorque((0.0, 0.0, 0.001))])


def test_a_single_table_is_an_alias_of_one_entry():
    alias = Scene.from_toml(HEAD + '\n[torque]\nvector = [0.0, 0.001, 0.0]\nframe = "world"\n'
                            '\n[orbit]\nrate = 0.1\n', "a")
    listed = Scene.from_toml(HEAD + _entry("torques", {"kind": "gravity_gradient",
                                                       "orbit_rate": 0.1})
                             + _entry("torques", {"kind": "constant_torque",
                                                  "vector": [0.0, 0.001, 0.0],
                                                  "frame": "world"}), "a")
    assert alias.system == listed.system
    np.testing.assert_array_equal(alias.run().q, listed.run().q)


def test_an_lvlh_start_takes_its_rate_from_a_listed_gravity_gradient():
    text = HEAD.replace('omega = [0.3, 0.2, 1.0]', 'omega = [0.0, 0.0, 0.0]\nframe = "lvlh"') \
        + _entry("torques", {"kind": "gravity_gradient", "orbit_rate": 0.1})
    scene = Scene.from_toml(text, "lvlh")
    omega0, q0 = dz.lvlh_start(0.1)
    np.testing.assert_allclose(scene.omega0, omega0)
    np.testing.assert_allclose(scene.q0, q0)


@pytest.mark.parametrize("entries, key, message", [
    (_entry("parts", {"kind": "wheel", "axis": [0, 0, 0], "momentum": 1.0}),
     r"parts\[0\]\.axis", "must not be zero"),
    (_entry("parts", {"kind": "damper", "inertia": 0.1, "damping": 0.1})
     + _entry("parts", {"kind": "wheel", "axle": [0, 0, 1]}),
     r"parts\[1\]\.axle", "is not a known key; allowed in a 'wheel': kind, axis, momentum"),
    (_entry("parts", {"kind": "gravity_gradient", "orbit_rate": 1.0}),
     r"parts\[0\]\.kind", r"is 'gravity_gradient', which goes in \[\[torques\]\]"),
    (_entry("torques", {"kind": "callable_torque"}), r"torques\[0\]\.kind",
     "which a scene cannot hold"),
    (_entry("torques", {"kind": "spin"}), r"torques\[0\]\.kind", "must be one of"),
    (_entry("parts", {"axis": [1, 0, 0]}), r"parts\[0\]\.kind", "is missing; one of"),
    (_entry("torques", {"kind": "constant_torque", "vector": [1.0, 2.0]}),
     r"torques\[0\]\.vector", r"must have shape \(3,\)"),
    (_entry("parts", {"kind": "damper", "inertia": -1.0, "damping": 0.1}),
     r"parts\[0\]\.inertia", "positive"),
    ('\nparts = 3\n', "parts", "must be an array of tables"),
])
def test_a_bad_entry_is_refused_naming_it_and_its_key(entries, key, message):
    text = HEAD.replace("[body]", entries.replace("\n[[", "\n[[", 1) + "\n[body]", 1) \
        if entries.startswith("\nparts") else HEAD + entries
    with pytest.raises(SceneError, match=rf"bad\.toml: `{key}` .*{message}"):
        Scene.from_toml(text, "bad", source="bad.toml")


def test_every_part_model_a_scene_takes_is_a_registry_model():
    kinds = set(storable_models())
    assert kinds <= set(SPECS) and "callable_torque" in set(SPECS) - kinds
    assert all(any(p.kind == "function" for p in SPECS[n].params) for n in set(SPECS) - kinds)
