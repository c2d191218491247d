"""Model only what a scene requires: the plan's contents, and the calls into the core that
executing it makes (counted by wrapping the core's functions), never timings."""

import numpy as np
import pytest

import dzhanibekov as dz
from dzhanibekov import _core
from dzhanibekov.scenes.plan import Rotation
from dzhanibekov.scenes.scene import Draw


@pytest.fixture
def core_calls(monkeypatch):
    """Records every call into the core's simulate (one run), rotate and ellipsoid_mesh."""
    calls = {"simulate": [], "rotate": [], "ellipsoid_mesh": []}

    def spy(name):
        real = getattr(_core, name)

        def wrapper(*args, **kwargs):
            calls[name].append(args)
            return real(*args, **kwargs)

        monkeypatch.setattr(_core, name, wrapper)

    for name in calls:
        spy(name)
    return calls


def keep_frames(call):  # _core.simulate(system, omega0, q0, options, keep_frames)
    return call[4]


def test_a_path_only_scene_rotates_the_signal_point_alone(core_calls):
    scene = dz.SCENES["fig3a"]
    plan = dz.scenes.make_plan(scene)
    assert plan.rotations == (Rotation(None, ("signal",)),) and plan.meshes == ()
    result = dz.scenes.execute(plan)
    assert len(core_calls["simulate"]) == 1 and keep_frames(core_calls["simulate"][0])
    assert core_calls["ellipsoid_mesh"] == []
    ((q, points),) = core_calls["rotate"]
    assert q.shape == (201, 4) and points.shape == (1, 3)
    np.testing.assert_array_equal(points, [scene.signal_point])
    assert set(result.world) == {"signal"} and result.mesh is None
    assert result.path.shape == (201, 3)


def test_a_scene_asking_only_for_flip_times_keeps_no_frames(core_calls):
    full = dz.SCENES["fig3a"]
    scene = full.replace(draw=Draw())
    plan = dz.scenes.make_plan(scene)
    assert not plan.keep_frames and plan.keep_flips
    assert plan.rotations == () and plan.meshes == () and not plan.invariants
    result = dz.scenes.execute(plan)
    (call,) = core_calls["simulate"]
    assert keep_frames(call) is False
    assert core_calls["rotate"] == [] and core_calls["ellipsoid_mesh"] == []
    assert result.trajectory is None and result.world == {}
    # the same steps as a full run: the same flips, to the bit
    np.testing.assert_array_equal(result.flip_times, full.run().flip_times)
    assert result.verdict == "2 flips in [0, 100]"


def test_an_animation_rotates_every_point_for_every_frame_in_one_call(core_calls):
    scene = dz.SCENES["example"]
    plan = dz.scenes.make_plan(scene)
    assert plan.rotations == (Rotation(None, ("box", "ellipsoid", "signal")),)
    assert plan.meshes == ("ellipsoid",)
    result = dz.scenes.execute(plan)
    (mesh_call,) = core_calls["ellipsoid_mesh"]
    np.testing.assert_allclose(mesh_call[0], np.sqrt(dz.PAPER_INERTIA))  # the paper's
    assert mesh_call[1:] == (24, 12)
    ((q, points),) = core_calls["rotate"]
    n_mesh = 24 * 11 + 2
    assert q.shape == (201, 4) and points.shape == (8 + n_mesh + 1, 3)
    assert result.world["ellipsoid"].points.shape == (201, n_mesh, 3)
    # each set's slice is that set rotated: check against rotating it alone
    for name, body_points in (("box", dz.box_vertices(20, 10, 15)),
                              ("ellipsoid", result.mesh[0]),
                              ("signal", np.array([scene.signal_point]))):
        np.testing.assert_array_equal(result.world[name].points,
                                      dz.rotate(result.trajectory.q, body_points))


def test_the_phases_panel_alone_rotates_its_objects_at_its_instants_only(core_calls):
    scene = dz.SCENES["example"].replace(
        draw=Draw(box=True, ellipsoid=True, signal_point=True, figures=("phases",),
                  phases=(0.0, 46.0, 100.0)))
    plan = dz.scenes.make_plan(scene)
    assert plan.rotations == (Rotation((0, 92, 200), ("box", "ellipsoid", "signal")),)
    dz.scenes.execute(plan)
    ((q, points),) = core_calls["rotate"]
    assert q.shape == (3, 4) and points.shape == (8 + 24 * 11 + 2 + 1, 3)


def test_with_its_path_the_panel_takes_the_signal_point_from_the_path(core_calls):
    scene = dz.SCENES["stable-largest"]
    plan = dz.scenes.make_plan(scene)
    assert plan.rotations == (Rotation((0, 50, 100, 150), ("box", "ellipsoid")),
                              Rotation(None, ("signal",)))
    result = dz.scenes.execute(plan)
    assert [(q.shape, p.shape) for q, p in core_calls["rotate"]] == [
        ((4, 4), (8 + 266, 3)), ((201, 4), (1, 3))]
    np.testing.assert_array_equal(result.at("signal", 50), result.path[50][None])


def test_no_ellipsoid_is_built_or_rotated_for_a_scene_without_one(core_calls):
    scene = dz.SCENES["example"].replace(draw=Draw(box=True, path=True, animation=True))
    plan = dz.scenes.make_plan(scene)
    assert plan.meshes == () and "ellipsoid" not in plan.rotated
    dz.scenes.execute(plan)
    assert core_calls["ellipsoid_mesh"] == []
    ((q, points),) = core_calls["rotate"]
    assert points.shape == (8 + 1, 3)


def test_plots_of_omega_alone_need_frames_but_no_rotation(core_calls):
    scene = dz.SCENES["fig3a"].replace(draw=Draw(figures=("omega",)))
    plan = dz.scenes.make_plan(scene)
    assert plan.keep_frames and plan.keep_flips and plan.rotations == ()
    dz.scenes.execute(plan)
    assert core_calls["rotate"] == [] and core_calls["ellipsoid_mesh"] == []


def test_flips_are_located_only_when_asked_or_drawn(core_calls):
    scene = dz.SCENES["fig3a"].replace(flips=False, draw=Draw(figures=("path",)))
    assert not dz.scenes.make_plan(scene).keep_flips
    result = dz.scenes.execute(dz.scenes.make_plan(scene))
    assert core_calls["simulate"][0][3].flips is False
    assert result.flip_times is None and result.verdict is None


def test_summarize_is_a_run_without_frames():
    body = dz.Body(dz.PAPER_INERTIA)
    full = dz.simulate(body, (0.01, 0.01, 1.0), t_end=100.0, frames=201)
    s = dz.summarize(body, (0.01, 0.01, 1.0), t_end=100.0, frames=201)
    np.testing.assert_array_equal(s.flip_times, full.flip_times)
    assert s.drift == full.drift and (s.n_steps, s.nfev, s.dt) == (full.n_steps, full.nfev,
                                                                   full.dt)
    assert s.flips == 2 and s.verdict == "2 flips in [0, 100]"
    stable = dz.summarize(body, (1.0, 0.01, 0.01))
    assert stable.flips == 0 and stable.verdict == "no flip in [0, 100]"
    with pytest.raises(ValueError, match="`method` must be one of"):
        dz.summarize(body, (1.0, 0.0, 0.0), method="euler")
    with pytest.raises(ValueError, match="`frames` must be at least 2"):
        dz.summarize(body, (1.0, 0.0, 0.0), frames=1)
