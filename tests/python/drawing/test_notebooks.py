"""Notebooks: `dz.plotting.animation` is a FuncAnimation that Jupyter can show, and every
figure takes a Trajectory (drawn as it is, never run again) and an `ax`."""

import sys

import numpy as np
import pytest
from matplotlib.animation import FuncAnimation
from matplotlib.figure import Figure

import dzhanibekov as dz


@pytest.fixture(scope="module")
def traj() -> dz.Trajectory:
    return dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=60.0, frames=25, dt=1e-2)


def test_plotting_and_maps_are_reachable_after_import_without_matplotlib_at_import():
    import subprocess

    code = ("import sys, dzhanibekov as dz; assert 'matplotlib' not in sys.modules; "
            "dz.plotting.phases_figure; dz.maps.stability_map; "
            "assert 'matplotlib' in sys.modules; print('ok')")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "ok"


def test_animation_is_a_funcanimation_with_a_frame_per_frame(traj):
    anim = dz.plotting.animation(traj, size=160, fps=12.5, dpi=80)
    assert isinstance(anim, FuncAnimation)
    fig = anim._fig
    assert tuple(fig.get_size_inches() * fig.dpi) == (160.0, 160.0) and fig.dpi == 80
    assert anim._interval == 80.0  # 1000 / fps ms
    assert len(list(anim.new_saved_frame_seq())) == 25
    html = anim.to_jshtml()
    assert html.count("data:image/png;base64") == 25  # every frame rendered into the page


def test_animation_can_show_fewer_frames(traj):
    anim = dz.plotting.animation(traj, size=100, frames=5)
    frames = list(anim.new_saved_frame_seq())
    assert frames == [0, 6, 12, 18, 24]
    anim.to_jshtml()  # rendered (an animation deleted unrendered warns)


def test_animation_frames_differ_as_the_body_turns(traj):
    anim = dz.plotting.animation(traj, size=120, frames=3)
    fig = anim._fig
    pictures = []
    for frame in anim.new_saved_frame_seq():
        anim._func(frame)
        fig.canvas.draw()
        pictures.append(np.asarray(fig.canvas.buffer_rgba()).copy())
    assert (pictures[0] != pictures[1]).mean() > 0.005
    assert (pictures[1] != pictures[2]).mean() > 0.005


def test_animation_of_a_scene_that_does_not_ask_for_one_says_so():
    with pytest.raises(ValueError, match="does not ask for an animation"):
        dz.plotting.animation(dz.SCENES["fig3a"])


@pytest.mark.parametrize("bad", [{"size": 0}, {"fps": -1.0}, {"dpi": float("nan")},
                                 {"frames": 0}])
def test_animation_refuses_bad_settings(traj, bad):
    with pytest.raises(ValueError, match=f"`{next(iter(bad))}`"):
        dz.plotting.animation(traj, **bad)


@pytest.mark.parametrize("name", ["path", "omega", "invariants", "polhode", "phases"])
def test_every_figure_takes_a_trajectory(traj, name, monkeypatch):
    calls = []
    real = dz.simulate
    monkeypatch.setattr(dz.scenes.scene, "simulate", lambda *a, **k: calls.append(a) or real(*a, **k))
    fig = dz.plotting.FIGURE_FUNCTIONS[name](traj)
    assert isinstance(fig, Figure) and fig.axes
    assert calls == []  # drawn from the trajectory as it is, not run again


def test_figures_of_a_trajectory_draw_its_own_numbers(traj):
    fig = dz.plotting.omega_figure(traj)
    lines = {line.get_label(): line for line in fig.axes[0].get_lines()}
    assert np.array_equal(lines["w"].get_ydata(), traj.omega[:, 2])
    fig = dz.plotting.path_figure(traj)
    path = fig.axes[0].get_lines()[0].get_data_3d()
    signal = dz.rotate(traj.q, (0.0, 0.0, 13.0))  # the paper's box: 1.3 × half of 20
    # the path is drawn smooth from the run's interpolant, through every stored frame
    dense = np.array(path).T
    step = (len(dense) - 1) // (len(traj.t) - 1)
    assert len(dense) == step * (len(traj.t) - 1) + 1
    assert np.allclose(dense[::step], signal, atol=1e-12)


def test_figures_take_an_ax(traj):
    fig = Figure()
    ax2d = fig.add_subplot(1, 3, 1)
    ax3d = fig.add_subplot(1, 3, 2, projection="3d")
    ax3d_b = fig.add_subplot(1, 3, 3, projection="3d")
    assert dz.plotting.omega_figure(traj, ax=ax2d) is fig
    assert dz.plotting.invariants_figure(traj, ax=ax2d) is fig
    assert dz.plotting.path_figure(traj, ax=ax3d) is fig
    assert dz.plotting.polhode_figure(traj, ax=ax3d_b) is fig
    assert ax2d.get_lines() and ax3d.get_lines() and ax3d_b.get_lines()


def test_a_batch_row_and_a_loaded_run_are_drawn_too(tmp_path):
    batch = dz.simulate(dz.PAPER_INERTIA, [(0.01, 0.01, 1.0), (0.0, 1.0, 0.01)], t_end=20.0,
                        frames=11)
    assert isinstance(dz.plotting.path_figure(batch[1]), Figure)
