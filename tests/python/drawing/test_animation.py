"""The animation: a GIF always, an MP4 with ffmpeg, one rotation call, a progress bar."""

import math

import numpy as np
import pytest
from PIL import Image

import dzhanibekov as dz
from dzhanibekov import _core
from dzhanibekov.plotting import movie
from dzhanibekov.scenes.scene import Draw


FAST = {"size": 128, "max_turn_deg": 180.0}
"""Small frames, few of them: for tests of the files written, not of the frames' count."""


@pytest.fixture
def short():
    """The paper's example, cut to 21 frames around its flip (at t ≈ 46)."""
    draw = Draw(box=True, ellipsoid=True, signal_point=True, path=True, body_axes=True,
                momentum=True, animation=True)
    return dz.SCENES["example"].replace(t_end=60.0, frames=21, draw=draw)


def test_the_frames_are_evenly_spread_and_the_body_turns_at_most_max_turn_between_them(
        short, tmp_path, monkeypatch):
    calls = []
    real = _core.rotate
    monkeypatch.setattr(_core, "rotate", lambda *a: calls.append(a) or real(*a))
    written = movie.animate(short, tmp_path / "flip.gif", mp4=False, progress=False,
                            size=200, max_turn_deg=45.0)
    assert written == [tmp_path / "flip.gif"]
    # every point of every animation frame came from one call into the core (the others:
    # the scene's plan at its frames, and the trail's smooth path, the signal point alone)
    (q, points), = [c for c in calls if len(c[1]) > 1 and len(c[0]) != short.frames]
    assert points.shape == (8 + 24 * 11 + 2 + 3 + 1, 3)
    rate = np.linalg.norm(short.run().omega, axis=1).max()
    frames = []
    with Image.open(tmp_path / "flip.gif") as gif:
        n = gif.n_frames
        assert gif.size == (200, 200)
        # as few frames as keep each turn within 45° at the body's largest rate
        assert q.shape == (n, 4) and n == math.ceil(rate * short.t_end / np.radians(45.0)) + 1
        assert rate * short.t_end / (n - 1) <= np.radians(45.0)
        for k in (0, (n - 1) // 2, n - 1):
            gif.seek(k)
            frames.append(np.asarray(gif.convert("RGB")))
    for f in frames:
        assert len(np.unique(f.reshape(-1, 3), axis=0)) > 8  # a picture, not a blank
    # the body turns: the frames differ
    assert (frames[0] != frames[1]).mean() > 0.01 and (frames[1] != frames[2]).mean() > 0.01
    # the attitudes are the run's at evenly spaced times (its interpolant through the frames)
    traj = short.run()
    times = np.linspace(0.0, short.t_end, n)
    on_frames = np.flatnonzero(np.isclose(times[:, None], traj.t[None, :]).any(axis=1))
    for k in on_frames:
        j = int(np.argmin(np.abs(traj.t - times[k])))
        assert min(np.abs(q[k] - traj.q[j]).max(), np.abs(q[k] + traj.q[j]).max()) < 1e-12


def test_a_long_run_gets_at_most_max_frames(short, tmp_path):
    """The paper's example turns 60 radians: 10° a frame would be 345 frames; the GIF keeps
    its budget, evenly spread."""
    movie.animate(short, tmp_path / "a.gif", mp4=False, progress=False, size=96,
                  max_frames=40)
    with Image.open(tmp_path / "a.gif") as gif:
        assert gif.n_frames == 40
    movie.animate(short, tmp_path / "b.gif", mp4=False, progress=False, size=96)
    with Image.open(tmp_path / "b.gif") as gif:
        assert gif.n_frames == movie.MAX_FRAMES
    with pytest.raises(ValueError, match="max_frames"):
        movie.animate(short, tmp_path / "c.gif", mp4=False, max_frames=1)


def test_every_frame_of_the_gif_shares_one_small_palette(short, tmp_path):
    """One palette, no dithering: a pixel that does not change keeps its index, so the GIF
    stores only what moves (the paper's animations under 3 MB; measured by benches/paper.py)."""
    movie.animate(short, tmp_path / "a.gif", mp4=False, progress=False, size=160,
                  max_frames=12)
    with Image.open(tmp_path / "a.gif") as gif:
        first = gif.getpalette()
        colours = set()
        for k in range(gif.n_frames):
            gif.seek(k)
            # no frame of its own palette: the first (global) one serves them all
            assert gif.getpalette() in (None, first)
            rgb = np.asarray(gif.convert("RGB")).reshape(-1, 3)
            colours |= {tuple(c) for c in np.unique(rgb, axis=0)}
    assert len(colours) <= movie.PALETTE_COLOURS
    assert (255, 255, 255) in colours  # the white background kept white


def test_the_path_fades_over_the_last_turns(short):
    """The animation's path is the run's smooth path over the last TRAIL_TURNS turns of the
    body (at its rate then), at most TRAIL_SPAN of the run, ending at the signal point, its
    oldest part the most transparent."""
    from matplotlib.figure import Figure

    from dzhanibekov.plotting.figures import (TRAIL_SPAN, TRAIL_TURNS, BodyView, _axes3d,
                                              compute)

    result = compute(short)
    times = np.linspace(0.0, short.t_end, 31)
    frames = movie.resampled(result, times)
    view = BodyView(_axes3d(Figure(), 1, 1, 1), result, frames)
    dense_t, dense = result.dense_path
    for k in (0, 10, 20, 30):
        trail = view.trail(k)
        np.testing.assert_allclose(trail[-1], frames.points["signal"][k][0], atol=1e-12)
        window = min(TRAIL_SPAN * short.t_end, TRAIL_TURNS * 2 * np.pi / frames.rates[k])
        first = int(np.argmin(np.linalg.norm(dense - trail[0], axis=1)))
        assert times[k] - window - 1e-9 <= dense_t[first] <= times[k]
        if k:  # the window reaches back as far as it may
            assert dense_t[first] <= max(0.0, times[k] - window) + 2 * (dense_t[1] - dense_t[0])
        view.show(k)
        alpha = view.artists["trail"].get_colors()[:, 3]
        assert np.all(np.diff(alpha) > 0) and alpha[-1] == 1.0


def test_a_progress_bar_counts_the_frames(short, tmp_path, capsys):
    movie.animate(short, tmp_path / "a.gif", mp4=False, progress=True, size=128,
                      max_turn_deg=180.0)
    err = capsys.readouterr().err
    with Image.open(tmp_path / "a.gif") as gif:
        n = gif.n_frames
    assert "animation example" in err and f"{n}/{n}" in err


@pytest.mark.skipif(movie.ffmpeg_path() is None, reason="no ffmpeg here")
def test_an_mp4_is_written_beside_the_gif_when_ffmpeg_is_there(short, tmp_path):
    written = movie.animate(short, tmp_path / "flip.gif", progress=False, size=360)
    assert written == [tmp_path / "flip.gif", tmp_path / "flip.mp4"]
    head = (tmp_path / "flip.mp4").read_bytes()[:12]
    assert head[4:8] == b"ftyp"  # an MP4 container
    assert (tmp_path / "flip.mp4").stat().st_size > 10_000


def test_without_ffmpeg_only_the_gif(short, tmp_path, monkeypatch):
    monkeypatch.setattr(movie, "ffmpeg_path", lambda: None)
    written = movie.animate(short, tmp_path / "a.gif", progress=False, **FAST)
    assert written == [tmp_path / "a.gif"]
    assert not (tmp_path / "a.mp4").exists()
    with pytest.raises(ValueError, match="`mp4=True` needs ffmpeg"):
        movie.animate(short, tmp_path / "b.gif", mp4=True, progress=False, **FAST)


def test_a_scene_without_an_animation_is_refused(tmp_path):
    with pytest.raises(ValueError, match="does not ask for an animation"):
        movie.animate(dz.SCENES["fig3a"], tmp_path / "a.gif")


def test_a_failing_ffmpeg_costs_the_mp4_not_the_gif(short, tmp_path, monkeypatch):
    monkeypatch.setattr(movie, "ffmpeg_path", lambda: "false")  # exits at once, status 1
    with pytest.warns(RuntimeWarning, match="no MP4 written: ffmpeg failed"):
        written = movie.animate(short, tmp_path / "a.gif", progress=False, **FAST)
    assert written == [tmp_path / "a.gif"] and (tmp_path / "a.gif").stat().st_size > 0
    with pytest.raises(RuntimeError, match="ffmpeg failed"):
        movie.animate(short, tmp_path / "b.gif", mp4=True, progress=False, **FAST)
