"""The energy sinks' figures and scene: the energy balance, the parts' motion, the flip that
decays (issue 31). Each checks the drawn lines against what the run or physics says."""

from __future__ import annotations

import math

import numpy as np
import pytest

import dzhanibekov as dz
from dzhanibekov.plotting import capture

from sink_runs import BODY, PARTS, run


@pytest.mark.parametrize("kind", sorted(PARTS))
def test_the_balance_line_is_flat_to_the_frames_sampling(kind):
    # T + V from each frame's state and W from the coordinates alone: their sum is the start's
    # energy to the spline's error, which falls (about 16× a halving of the spacing)
    gaps = []
    for frames in (2001, 4001):
        traj = run(PARTS[kind], frames=frames)
        fig = dz.plotting.energy_balance_figure(traj)
        lines = {line.get_label(): line for line in fig.axes[0].get_lines()}
        total = np.asarray(lines["T + V + W"].get_ydata())
        np.testing.assert_array_equal(lines["T + V"].get_ydata(), traj.energy / traj.energy[0])
        w = np.asarray(lines["W"].get_ydata())
        assert w[0] == 0 and np.all(np.diff(w) >= 0) and w[-1] > 1e-6
        gaps.append(np.abs(total - 1).max())
    assert gaps[1] < 1e-6
    assert gaps[1] < max(gaps[0] / 4, 1e-11)  # (or at round-off already)


def test_the_motion_lines_are_the_runs_state():
    parts = [PARTS["hinge"], PARTS["slosh"]]
    traj = dz.simulate(dz.System(BODY, parts=[dz.Wheel((0.0, 0.0, 1.0), 0.1), *parts]),
                       (0.01, 0.01, 1.0), t_end=20.0, frames=201, dt=1e-2)
    fig = dz.plotting.part_motion_figure(traj)
    hinge, slosh = fig.axes
    np.testing.assert_array_equal(hinge.get_lines()[0].get_ydata(),
                                  np.degrees(traj.parts["hinge"][:, 0]))
    for k, line in enumerate(slosh.get_lines()):
        np.testing.assert_array_equal(line.get_ydata(), traj.parts["slosh"][:, k])
    # the drawn direction is a unit vector
    n = np.stack([line.get_ydata() for line in slosh.get_lines()], axis=1)
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-9)


def test_the_figures_refuse_a_run_without_a_sink():
    traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=5.0, frames=11)
    for figure in (dz.plotting.energy_balance_figure, dz.plotting.part_motion_figure,
                   dz.plotting.capture_figure):
        with pytest.raises(ValueError, match="dz.S"):
            figure(traj)


def test_a_scene_names_the_figures_only_with_a_sink():
    scene = dz.SCENES["fig3a"]
    with pytest.raises(dz.scenes.SceneError, match="energy sink"):
        scene.replace(draw={"figures": ["energy_balance"]})
    assert "capture" in dz.SCENES["slosh-flip"].draw.figures


def test_a_flip_that_decays():
    # the shipped scene: with no damping the flips never stop and the energy is kept; with
    # damping they stop (captured well before the end), fewer as the damping grows
    scene = dz.SCENES["slosh-flip"]
    traj = scene.run()
    flips = capture.intermediate_flips(traj)
    assert 10 < len(flips) and flips[-1] < 0.75 * traj.t_end
    assert traj.drift.energy_balance < 1e-8
    c0 = scene.parts[0].damping
    values = [c0, 2 * c0, 10 / 3 * c0, 10 * c0, 100 / 3 * c0]
    counts = capture.capture_sweep(traj, values)
    assert counts[0] == len(flips)
    assert np.all(np.diff(counts) < 0), counts
    free = dz.Slosh(**(scene.parts[0].fields() | {"damping": 0.0}))
    undamped = dz.simulate(dz.System(traj.system.body, parts=[free]), traj.omega[0],
                           t_end=traj.t_end, frames=len(traj.t), dt=traj.dt)
    never = capture.intermediate_flips(undamped)
    assert never[-1] > 0.9 * traj.t_end and len(never) > len(flips)
    e = undamped.energy
    assert np.abs(e - e[0]).max() / e[0] <= undamped.drift.energy * (1 + 1e-6) + 1e-15
    assert undamped.drift.energy < 1e-8


def test_the_flip_count_is_the_free_bodys():
    # a free body near its intermediate axis: every sign change of the intermediate rate is a
    # whole turn over, so both counts agree; the threshold is checked
    traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=400.0, frames=4001,
                       flips=True)
    assert len(capture.intermediate_flips(traj)) == traj.flips > 3
    with pytest.raises(ValueError, match="within"):
        capture.intermediate_flips(traj, within=math.pi / 2)


def test_the_cli_renders_the_scenes_sink_figures(tmp_path):
    from dzhanibekov.cli import main

    from pictures import assert_picture

    out = tmp_path / "out"
    assert main(["run", "slosh-flip", "--out", str(out), "--no-progress"]) == 0
    figures = dz.SCENES["slosh-flip"].draw.figures
    assert {"energy_balance", "part_motion", "capture"} <= set(figures)
    assert {p.name for p in out.iterdir()} == {f"slosh-flip-{f}.png" for f in figures} | {
        "slosh-flip.json"}
    for path in out.glob("*.png"):
        assert_picture(path)
