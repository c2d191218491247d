"""Animation files: the flipping body, its inertia ellipsoid and the signal point's fading
path as a GIF (always) and an MP4 (where an ffmpeg is found).

Why a GIF first: it plays wherever a picture does — a README, slides, a chat, a browser
offline — with no player, so it is the file every scene gets. It is kept small (every
shipped animation under 3 MB at the default size): at most :data:`MAX_FRAMES` frames,
evenly spread over the run (fewer when the body turns slowly: no more than one per
10° of turn), one palette of :data:`PALETTE_COLOURS` colours for all of them (from a sample
of the frames, without dithering, so unchanged pixels stay unchanged), and only the pixels
that change stored from one frame to the next (Pillow's ``optimize``). The MP4 beside it (H.264 through
ffmpeg: on the PATH or matplotlib's ``animation.ffmpeg_path``, else the one the optional
``imageio-ffmpeg`` package ships, ``pip install dzhanibekov[video]``) is smaller still and in
full colour, for a player or a web page; it is made from the same rendered frames. WebP is
not written: its animations play in browsers but not in most slide and document tools,
and they add nothing the MP4 does not.

Each frame is drawn once, by moving the artists of one figure
(:class:`~dzhanibekov.plotting.figures.BodyView`), not by rebuilding them; the body's
attitude at each frame's time comes from the run's interpolant (:mod:`dzhanibekov.dense`),
and the positions of all its drawn points at all frames from one call to the core's
`rotate`.
"""

from __future__ import annotations

import math
import shutil
import subprocess
import warnings
from collections.abc import Callable
from typing import Any
from pathlib import Path

import numpy as np
from matplotlib.animation import FFMpegWriter
from matplotlib.collections import Collection
from matplotlib.figure import Figure
from PIL import Image
from tqdm import tqdm

from .._args import as_float, as_int
from ..dense import attitudes_at
from ..results import Trajectory
from ..scenes.plan import SceneResult, body_points
from ..scenes.scene import Scene
from ..simulate import rotate
from .figures import Frames, animation_figure, compute

__all__ = ["animate", "ffmpeg_path", "frame_times", "resampled", "MAX_FRAMES", "SIZE_PX",
           "FPS", "FPS_LIMITS", "SIZE_LIMITS"]

SIZE_PX = 480
"""Default width and height of the animation, in pixels (even, as H.264 needs)."""
FPS = 20
"""Default frames per second."""
MAX_FRAMES = 200
"""The most frames an animation has by default: 10 seconds at :data:`FPS`."""
FPS_LIMITS = (1, 1000)
"""The frame rates an animation may have."""
SIZE_LIMITS = (64, 4096)
"""The sizes (pixels a side) an animation may have."""
PALETTE_COLOURS = 127
"""The GIF's colours: its pictures are lines and flat, shaded faces on white, and fewer
colours compress better (255 make the paper's example 13 % larger, no better to the eye).
They are chosen by Pillow's maximum-coverage quantizer, which keeps the white background
and the drawing's own colours exact (median cut greys the white)."""
PALETTE_SAMPLES = 6
"""Frames rendered first to choose the GIF's one palette from."""


def ffmpeg_path() -> str | None:
    """The ffmpeg executable to write MP4 with, or None if there is none."""
    if FFMpegWriter.isAvailable():
        return str(FFMpegWriter.bin_path())
    found = shutil.which("ffmpeg")
    if found:
        return found
    try:
        import imageio_ffmpeg  # type: ignore[import-untyped, import-not-found, unused-ignore]
    except ImportError:
        return None
    try:
        return str(imageio_ffmpeg.get_ffmpeg_exe())
    except RuntimeError:  # the package without its binary
        return None


def frame_times(traj: Trajectory, max_turn: float, most: int) -> np.ndarray:
    """The times of an animation's frames: evenly spaced over the run, as many as it takes
    for the body to turn at most `max_turn` radians from one to the next at its largest rate,
    but at least 2 and at most `most` (then it turns further between frames)."""
    rate = float(np.sqrt((traj.omega ** 2).sum(axis=1)).max()) if len(traj.t) else 0.0
    span = float(traj.t[-1] - traj.t[0])
    needed = math.ceil(rate * span / max_turn) + 1 if math.isfinite(rate * span) else most
    return np.linspace(float(traj.t[0]), float(traj.t[-1]), max(2, min(most, needed)))


def resampled(result: SceneResult, times: np.ndarray) -> Frames:
    """The drawn point sets of `result` at `times` (within its run): attitudes from the run's
    interpolant, every set rotated at every time in one call to the core's `rotate`."""
    traj = result.trajectory
    if traj is None:
        raise ValueError(f"scene {result.scene.name!r} kept no frames to interpolate")
    q, omega = attitudes_at(traj.t, traj.omega, traj.q, times)
    names = tuple(result.world)
    sets = [body_points(result.scene, name, result.mesh) for name in names]
    points: dict[str, np.ndarray] = {}
    if sets:
        out = rotate(q, np.concatenate(sets))
        start = 0
        for name, pts in zip(names, sets):
            points[name] = out[:, start:start + len(pts)]
            start += len(pts)
    return Frames(times, np.sqrt((omega ** 2).sum(axis=1)), points)


def animate(scene: Scene | SceneResult | Trajectory, path: str | Path, *,
            fps: int | None = None, size: int | None = None, max_turn_deg: float = 10.0,
            max_frames: int = MAX_FRAMES, mp4: bool | None = None,
            progress: bool | None = None,
            on_frame: Callable[[int, int], None] | None = None) -> list[Path]:
    """Writes the scene's animation: a GIF, and an MP4 beside it where ffmpeg is found.

    The frames are evenly spread over the run (:func:`frame_times`): enough that the body
    turns at most `max_turn_deg` from one to the next, at most `max_frames`. Each is drawn
    once (:func:`~dzhanibekov.plotting.figures.animation_figure`) and handed to both files.

    Parameters
    ----------
    scene : Scene, SceneResult or Trajectory
        A scene with ``draw.animation = true``, or a trajectory.
    path : str or Path
        The GIF to write; the MP4 goes beside it with the suffix ``.mp4``.
    fps : int, optional
        Frames per second: the scene's `draw.fps`, else :data:`FPS`.
    size : int, optional
        Width and height in pixels (made even, as H.264 needs): the scene's
        `draw.animation_size`, else :data:`SIZE_PX`.
    max_turn_deg : float
        The most the body turns from one frame to the next, in degrees (at its fastest),
        while `max_frames` allows.
    max_frames : int
        The most frames, at least 2 (default :data:`MAX_FRAMES`).
    mp4 : bool, optional
        Also write an MP4: None (default) when ffmpeg is found, True to insist (ValueError
        without ffmpeg), False never.
    progress : bool, optional
        Show a progress bar (tqdm, on stderr) while frames render: None (default) only on a
        terminal.
    on_frame : callable, optional
        Called as ``on_frame(done, total)`` after each frame is rendered.

    Returns
    -------
    list of Path
        The files written: the GIF, then the MP4 if any.

    Raises
    ------
    ValueError
        The scene was not computed for an animation, an argument out of range, or `mp4` is
        True without ffmpeg.
    RuntimeError
        `mp4` is True and ffmpeg failed; when `mp4` is None a failure only warns
        (RuntimeWarning) and the GIF is kept.
    """
    result = compute(scene, animation=True)
    if not result.scene.draw.animation or result.trajectory is None:
        raise ValueError(f"scene {result.scene.name!r} does not ask for an animation; set "
                         "`draw.animation = true` in its scene file")
    fps = as_int("fps", fps if fps is not None else result.scene.draw.fps or FPS,
                 minimum=FPS_LIMITS[0], maximum=FPS_LIMITS[1])
    size = as_int("size", size if size is not None else
                  result.scene.draw.animation_size or SIZE_PX, minimum=SIZE_LIMITS[0],
                  maximum=SIZE_LIMITS[1])
    size += size % 2
    max_turn = np.radians(as_float("max_turn_deg", max_turn_deg, positive=True))
    most = as_int("max_frames", max_frames, minimum=2, maximum=100_000)
    gif = Path(path)
    ffmpeg = ffmpeg_path() if mp4 is not False else None
    if mp4 and ffmpeg is None:
        raise ValueError("`mp4=True` needs ffmpeg: install it, or `pip install imageio-ffmpeg`")
    frames = resampled(result, frame_times(result.trajectory, max_turn, most))
    n = len(frames.times)
    fig, draw = animation_figure(result, frames, size=size)
    blit = _Blitter(fig, draw(0))

    def render(k: int) -> np.ndarray:
        draw(k)
        return blit.render()

    samples = np.unique(np.linspace(0, n - 1, min(n, PALETTE_SAMPLES)).round().astype(int))
    palette = _palette([render(int(k))[..., :3] for k in samples])
    video = _Video(ffmpeg, gif.with_suffix(".mp4"), fps) if ffmpeg else None
    images: list[Image.Image] = []
    try:
        bar = tqdm(total=n, desc=f"animation {result.scene.name}", unit="frame",
                   disable=None if progress is None else not progress)
        with bar:
            for k in range(n):
                rgba = render(k)
                images.append(Image.fromarray(rgba[..., :3]).quantize(
                    palette=palette, dither=Image.Dither.NONE))
                if video is not None:
                    video.write(rgba)
                bar.update()
                if on_frame is not None:
                    on_frame(k + 1, n)
        images[0].save(gif, save_all=True, append_images=images[1:],
                       duration=round(1000 / fps), loop=0, optimize=True)
        written = [gif]
        if video is not None:
            try:
                written.append(video.close())
            except RuntimeError as exc:
                if mp4:
                    raise
                warnings.warn(f"no MP4 written: {exc}", RuntimeWarning, stacklevel=2)
    finally:
        if video is not None:
            video.kill()
    return written


class _Blitter:
    """Renders an animation's frames by drawing its moving artists only: the rest of the
    figure (the title: its text is the costliest thing to draw) is drawn once and its pixels
    restored for every frame."""

    def __init__(self, fig: Figure, moving: list[Any]) -> None:
        self.fig, self.moving = fig, moving
        for artist in moving:
            artist.set_animated(True)
        fig.canvas.draw()
        self.background = fig.canvas.copy_from_bbox(fig.bbox)  # type: ignore[attr-defined]

    def render(self) -> np.ndarray:
        """The figure's pixels (RGBA, a view of the canvas' buffer) with every moving artist
        where it is now: 3-D collections back to front (as a 3-D axes sorts them), then
        lines and text."""
        canvas = self.fig.canvas
        canvas.restore_region(self.background)  # type: ignore[attr-defined]
        collections: list[Any] = [a for a in self.moving if isinstance(a, Collection)]
        for artist in sorted(collections, key=lambda a: a.do_3d_projection(), reverse=True):
            artist.axes.draw_artist(artist)
        for artist in self.moving:
            if not isinstance(artist, Collection):
                (artist.axes or self.fig).draw_artist(artist)
        rgba: np.ndarray = np.asarray(canvas.buffer_rgba())  # type: ignore[attr-defined]
        return rgba


def _palette(samples: list[np.ndarray]) -> Image.Image:
    """One palette of :data:`PALETTE_COLOURS` colours for every frame, from sample frames
    (RGB) stacked: an index stays free for the GIF's "unchanged" pixels."""
    return Image.fromarray(np.concatenate(samples, axis=0)).quantize(
        colors=PALETTE_COLOURS, method=Image.Quantize.MAXCOVERAGE, dither=Image.Dither.NONE)


class _Video:
    """An ffmpeg process turning raw RGBA frames on its stdin into an H.264 MP4."""

    def __init__(self, ffmpeg: str, path: Path, fps: int) -> None:
        self.path = path
        self.size: tuple[int, int] | None = None
        self.cmd = [ffmpeg, "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgba",
                    "-framerate", str(fps)]
        self.tail = ["-i", "pipe:0", "-an", "-vcodec", "libx264", "-pix_fmt", "yuv420p",
                     "-movflags", "+faststart", str(path)]
        self.proc: subprocess.Popen[bytes] | None = None
        self.broken = False

    def write(self, rgba: np.ndarray) -> None:
        if self.proc is None:
            h, w = rgba.shape[:2]
            self.proc = subprocess.Popen(self.cmd + ["-s", f"{w}x{h}"] + self.tail,
                                         stdin=subprocess.PIPE, stderr=subprocess.PIPE)
        assert self.proc.stdin is not None
        if not self.broken:
            try:
                self.proc.stdin.write(np.ascontiguousarray(rgba).tobytes())
            except BrokenPipeError:  # ffmpeg quit; close() reports why
                self.broken = True

    def close(self) -> Path:
        assert self.proc is not None and self.proc.stdin is not None
        try:
            self.proc.stdin.close()
        except BrokenPipeError:
            self.broken = True
        err = b""
        if self.proc.stderr is not None:
            err = self.proc.stderr.read()
            self.proc.stderr.close()
        if self.proc.wait() != 0 or self.broken:
            raise RuntimeError(f"ffmpeg failed writing {self.path}: {err.decode(errors='replace')}")
        self.proc = None
        return self.path

    def kill(self) -> None:
        if self.proc is not None:
            self.proc.kill()
            for pipe in (self.proc.stdin, self.proc.stderr):
                if pipe is not None and not pipe.closed:
                    try:
                        pipe.close()
                    except BrokenPipeError:
                        pass
            self.proc.wait()
            self.proc = None
