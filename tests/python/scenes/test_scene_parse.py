"""A scene is parsed, then constructed: `Scene(...)`, `replace` and files go through the same
pure checks (`dzhanibekov.scenes.parse`), and a Scene holds only checked values."""

import inspect
import re

import pytest

import dzhanibekov as dz
from dzhanibekov.scenes import parse
from dzhanibekov.scenes.scene import Draw, EllipsoidStyle


def test_python_values_are_normalised_as_a_files_are():
    s = dz.Scene("mine", "mine", [1, 2, 3], [0, 1, 0], 10, 3, q0=[2, 0, 0, 0],
                 draw={"path": True, "figures": ["path"], "phases": [0, 5]},
                 ellipsoid={"mesh": [8, 4]})
    assert s.inertia == (1.0, 2.0, 3.0) and all(type(x) is float for x in s.inertia)
    assert s.omega0 == (0.0, 1.0, 0.0) and type(s.omega0) is tuple
    assert s.q0 == (2.0, 0.0, 0.0, 0.0) and type(s.t_end) is float and s.t_end == 10.0
    assert s.draw == Draw(path=True, figures=("path",), phases=(0.0, 5.0))
    assert s.ellipsoid == EllipsoidStyle("gyration", (8, 4))
    text = """
        title = "mine"
        [body]
        inertia = [1, 2, 3]
        [start]
        omega = [0, 1, 0]
        q = [2, 0, 0, 0]
        [run]
        t_end = 10
        frames = 3
        [draw]
        path = true
        figures = ["path"]
        phases = [0, 5]
        [ellipsoid]
        mesh = [8, 4]
    """
    assert dz.Scene.from_toml(text, "mine") == s


def test_checked_leaves_its_input_alone_and_fills_the_defaults():
    values = dict(name="x", title="x", inertia=[1, 2, 3], omega0=(0, 0, 1), t_end=1, frames=2,
                  q0=(1, 0, 0, 0), dt="none", method="rk4", box=None, signal_point=None,
                  flips=True, draw={}, ellipsoid=EllipsoidStyle(), about="", deployment=None,
                  damper=None, sigma0=None, source="", rtol=None, atol=None, body_spec=None,
                  given=None)
    before = dict(values)
    fields, body = parse.checked(values)
    assert values == before
    assert fields["dt"] is None and fields["draw"] == Draw() and fields["t_end"] == 1.0
    assert body.inertia == (1.0, 2.0, 3.0)
    # the signal point left out: on the intermediate (y) axis, beyond the body
    x, y, z = fields["signal_point"]
    assert x == 0.0 and z == 0.0 and y != 0.0


def test_a_bad_value_reads_the_same_from_python_and_from_a_file(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(dz.SCENES["fig3a"].to_toml().replace("frames = 201", "frames = 1"))
    with pytest.raises(dz.SceneError) as from_file:
        dz.load_scene(path)
    with pytest.raises(dz.SceneError) as from_python:
        dz.SCENES["fig3a"].replace(frames=1)
    assert from_file.value.key == from_python.value.key == "run.frames"
    assert from_file.value.detail == from_python.value.detail == "must be at least 2, got 1"


def test_a_deployment_table_is_built_when_the_file_is_read():
    table = dz.SCENES["deployment"].to_dict()
    del table["deployment"]["times"]
    with pytest.raises(dz.SceneError, match="`deployment.times` is missing"):
        dz.Scene.from_dict(table, "deployment")
    with pytest.raises(dz.SceneError, match="`deployment` must be a Deployment"):
        dz.SCENES["fig3a"].replace(deployment={"times": [0, 1], "inertia": [[1, 2, 3]] * 2})


def test_the_body_is_built_once_when_the_scene_is_checked(monkeypatch):
    calls = []
    real = parse.build_body
    monkeypatch.setattr(parse, "build_body", lambda spec: calls.append(spec) or real(spec))
    scene = dz.Scene.from_toml(dz.SCENES["wing-nut"].to_toml(), "wing-nut")
    assert scene.body.shape is not None and scene.body is scene.body
    assert len(calls) == 1


def test_the_signature_is_the_fields():
    params = list(inspect.signature(dz.Scene).parameters)
    assert params[:6] == ["name", "title", "inertia", "omega0", "t_end", "frames"]
    with pytest.raises(TypeError, match="Scene\\(\\): .*unexpected keyword argument 'colour'"):
        dz.Scene("x", "x", (1, 2, 3), (0, 0, 1), 1.0, 2, colour="red")


SCENE = """
    title = "t"
    [body]
    {body}
    [start]
    omega = [0.01, 1.0, 0.01]
    [run]
    t_end = 1
    frames = 3
"""


@pytest.mark.parametrize(("body", "key", "says"), [
    # 0.5 + 2 < 3: no mass distribution has these moments
    ("inertia = [0.5, 2, 3]", "body.inertia", "triangle inequality"),
    # two moments within 1e-7 of each other, above the tolerance that makes them equal
    ("inertia = [1, 2, 2.0000002]", "body.inertia", "nearly symmetric top"),
    ("tensor = [[0.5, 0, 0], [0, 2, 0], [0, 0, 3]]", "body", "triangle inequality"),
])
def test_a_scene_warns_of_an_unphysical_body_as_python_does(body, key, says, tmp_path):
    """Issue 33: moments no body has, and a nearly symmetric top, warned in Python
    (`InertiaWarning`) but passed silently through a TOML scene; now the scene warns, once,
    naming its file and key, and `run` prints it."""
    path = tmp_path / "odd.toml"
    path.write_text(SCENE.format(body=body))
    with pytest.warns(dz.InertiaWarning) as caught:
        dz.load_scene(path)
    odd = [w for w in caught if issubclass(w.category, dz.InertiaWarning)]
    assert len(odd) == 1, [str(w.message) for w in odd]
    assert str(odd[0].message).startswith(f"{path}: `{key}`: ") and says in str(odd[0].message)


def test_a_scene_of_a_real_body_does_not_warn(tmp_path):
    import warnings

    path = tmp_path / "box.toml"
    path.write_text(SCENE.format(body="inertia = [1, 2, 3]"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        dz.load_scene(path)


ORBITING = """
    title = "t"
    [body]
    inertia = [3.0, 3.5, 1.0]
    [orbit]
    rate = 0.001
    [start]
    frame = "lvlh"
    omega = {omega}
    q = {q}
    [run]
    t_end = 3000
    frames = 7
    method = "dop853"
    rtol = 1e-13
"""


def test_a_start_relative_to_lvlh_is_that_attitude_in_the_orbiting_frame():
    """Issue 33: a TOML start can be given relative to the orbiting frame. Aligned with LVLH
    and at rest in it, a body whose moments are in the Lagrange region stays there (the
    gravity gradient's relative equilibrium: Hughes, Spacecraft Attitude Dynamics, §9.3); a
    start turned by 0.3 rad about LVLH's third axis reads back as that turn, and rates relative
    to the frame read back as themselves (LVLH-relative rates = ω − n ẑ_b)."""
    import numpy as np

    rest = dz.Scene.from_toml(ORBITING.format(omega=[0, 0, 0], q=[1, 0, 0, 0]), "rest")
    traj = rest.run()
    # 1 − |q0| = θ²/8 for a turn θ away from LVLH: at most 1e-12 (θ < 3e-6 rad; the
    # integration's error at rtol 1e-13 over half an orbit, measured 2e-14, falling with rtol)
    np.testing.assert_allclose(np.abs(dz.lvlh_attitude(traj)[:, 0]), 1.0, rtol=0, atol=1e-12)
    turned = [float(np.cos(0.15)), 0.0, 0.0, float(np.sin(0.15))]
    spun = dz.Scene.from_toml(ORBITING.format(omega=[0.01, 0.0, 0.0], q=turned), "spun")
    first = dz.lvlh_attitude(spun.run())[0]
    np.testing.assert_allclose(first * np.sign(first[0]), turned, rtol=0, atol=1e-15)
    # the orbit normal (world z) in the turned body: turned about LVLH's z by 0.3, o2 = -z_w
    # lies along -(sin 0.3, cos 0.3, 0) in body axes, and the body turns at n about it
    normal = np.array([-np.sin(0.3), -np.cos(0.3), 0.0])
    np.testing.assert_allclose(np.array(spun.omega0) - 0.001 * normal, [0.01, 0.0, 0.0],
                               rtol=0, atol=1e-15)


@pytest.mark.parametrize(("text", "key", "says"), [
    (ORBITING.replace("[orbit]\n    rate = 0.001\n", ""), "start.frame", "no [orbit]"),
    (ORBITING.replace('"lvlh"', '"body"'), "start.frame", "must be one of ['world', 'lvlh']"),
    (ORBITING.replace("q = {q}", "q = [0, 0, 0, 0]"), "start.q", "non-zero quaternion"),
])
def test_a_bad_lvlh_start_names_its_key(text, key, says):
    with pytest.raises(dz.SceneError, match=rf"`{key}`.*{re.escape(says)}"):
        dz.Scene.from_toml(text.format(omega=[0, 0, 0], q=[1, 0, 0, 0]), "bad")
