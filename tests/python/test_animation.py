"""The animation: a GIF always, an MP4 with ffmpeg, one rotation call, a progress bar."""

import numpy as np
import pytest
from PIL import Image

import dzhanibekov as dz
from dzhanibekov import _core
from dzhanibekov.plotting import animation
from dzhanibekov.scenes.scene import Draw


@pytest.fixture
def short():
    """The paper's example, cut to 21 frames around its flip (at t ≈ 46)."""
    draw = Draw(box=True, ellipsoid=True, signal_point=True, path=True, body_axes=True,
                momentum=True, animation=True)
    return dz.SCENES["example"].replace(t_end=60.0, frames=21, draw=draw)


def test_the_gif_has_a_frame_per_scene_frame_and_they_move(short, tmp_path, monkeypatch):
    calls = []
    real = _core.rotate
    monkeypatch.setattr(_core, "rotate", lambda *a: calls.append(a) or real(*a))
    written = animation.animate(short, tmp_path / "flip.gif", mp4=False, progress=False)
    assert written == [tmp_path / "flip.gif"]
    # every point of every frame came from one call into the core
    ((q, points),) = calls
    assert q.shape == (21, 4) and points.shape == (8 + 24 * 11 + 2 + 3 + 1, 3)
    frames = []
    with Image.open(tmp_path / "flip.gif") as gif:
        assert gif.n_frames == 21
        for k in (0, 10, 20):
            gif.seek(k)
            frames.append(np.asarray(gif.convert("RGB")))
    for f in frames:
        assert len(np.unique(f.reshape(-1, 3), axis=0)) > 8  # a picture, not a blank
    # the body turns: frames 0, 10 and 20 differ
    assert (frames[0] != frames[1]).mean() > 0.01 and (frames[1] != frames[2]).mean() > 0.01


def test_a_progress_bar_counts_the_frames(short, tmp_path, capsys):
    animation.animate(short, tmp_path / "a.gif", mp4=False, progress=True)
    err = capsys.readouterr().err
    assert "animation example" in err and "21/21" in err


@pytest.mark.skipif(animation.ffmpeg_path() is None, reason="no ffmpeg here")
def test_an_mp4_is_written_beside_the_gif_when_ffmpeg_is_there(short, tmp_path):
    written = animation.animate(short, tmp_path / "flip.gif", progress=False)
    assert written == [tmp_path / "flip.gif", tmp_path / "flip.mp4"]
    head = (tmp_path / "flip.mp4").read_bytes()[:12]
    assert head[4:8] == b"ftyp"  # an MP4 container
    assert (tmp_path / "flip.mp4").stat().st_size > 10_000


def test_without_ffmpeg_only_the_gif(short, tmp_path, monkeypatch):
    monkeypatch.setattr(animation, "ffmpeg_path", lambda: None)
    assert animation.animate(short, tmp_path / "a.gif", progress=False) == [tmp_path / "a.gif"]
    assert not (tmp_path / "a.mp4").exists()
    with pytest.raises(ValueError, match="`mp4=True` needs ffmpeg"):
        animation.animate(short, tmp_path / "b.gif", mp4=True, progress=False)


def test_a_scene_without_an_animation_is_refused(tmp_path):
    with pytest.raises(ValueError, match="does not ask for an animation"):
        animation.animate(dz.SCENES["fig3a"], tmp_path / "a.gif")


def test_a_failing_ffmpeg_costs_the_mp4_not_the_gif(short, tmp_path, monkeypatch):
    monkeypatch.setattr(animation, "ffmpeg_path", lambda: "false")  # exits at once, status 1
    with pytest.warns(RuntimeWarning, match="no MP4 written: ffmpeg failed"):
        written = animation.animate(short, tmp_path / "a.gif", progress=False)
    assert written == [tmp_path / "a.gif"] and (tmp_path / "a.gif").stat().st_size > 0
    with pytest.raises(RuntimeError, match="ffmpeg failed"):
        animation.animate(short, tmp_path / "b.gif", mp4=True, progress=False)
