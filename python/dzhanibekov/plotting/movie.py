"""Animation files: the flipping body, its inertia ellipsoid and the signal point's trail as a
GIF (and an MP4).

The frames are those of :func:`dzhanibekov.plotting.animation` (a matplotlib
``FuncAnimation``), each drawn once with Agg and handed to each writer: a GIF through
Pillow always, an MP4 through ffmpeg when an ffmpeg executable is found (on the PATH or
matplotlib's ``animation.ffmpeg_path``, else the one the optional ``imageio-ffmpeg``
package ships: ``pip install dzhanibekov[video]``). The positions of all the body's points
at all frames come from one call to the core's `rotate` (the scene's plan), before drawing.
"""

from __future__ import annotations

import shutil
import subprocess
import warnings
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.animation import AbstractMovieWriter, FFMpegWriter
from matplotlib.figure import Figure
from PIL import Image
from tqdm import tqdm

from .._args import as_float, as_int
from ..results import Trajectory
from ..scenes.plan import SceneResult, densified
from ..scenes.scene import Scene
from .figures import animation, compute

__all__ = ["animate", "ffmpeg_path"]

SIZE_PX = 560
"""Default width and height of the animation, in pixels (even, as H.264 needs)."""
FPS = 20
"""Default frames per second."""


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


def animate(scene: Scene | SceneResult | Trajectory, path: str | Path, *,
            fps: int | None = None, size: int | None = None, max_turn_deg: float = 10.0,
            mp4: bool | None = None, progress: bool | None = None) -> list[Path]:
    """Writes the scene's animation (:func:`dzhanibekov.plotting.animation`), with enough
    frames that the body turns at most 10° from one to the next (at least one per scene
    frame): the attitudes between the run's frames come from its interpolant
    (:func:`dzhanibekov.scenes.plan.densified`). Each frame is rendered once and handed to
    both writers.

    Parameters
    ----------
    scene : Scene, SceneResult or Trajectory
        A scene with ``draw.animation = true``, or a trajectory.
    path : str or Path
        The GIF to write; the MP4 goes beside it with the suffix ``.mp4``.
    fps : int, optional
        Frames per second: the scene's `draw.fps`, else 20.
    size : int, optional
        Width and height in pixels (even): the scene's `draw.animation_size`, else 560.
    max_turn_deg : float
        The most the body turns from one frame to the next, in degrees (at its fastest).
    mp4 : bool, optional
        Also write an MP4: None (default) when ffmpeg is found, True to insist (ValueError
        without ffmpeg), False never.
    progress : bool, optional
        Show a progress bar (tqdm, on stderr) while frames render: None (default) only on a
        terminal.
    size : int
        Width and height in pixels (even, as H.264 needs).

    Returns
    -------
    list of Path
        The files written: the GIF, then the MP4 if any.

    Raises
    ------
    ValueError
        The scene was not computed for an animation, or `mp4` is True without ffmpeg.
    RuntimeError
        `mp4` is True and ffmpeg failed; when `mp4` is None a failure only warns
        (RuntimeWarning) and the GIF is kept.
    """
    result = compute(scene, animation=True)
    if not result.scene.draw.animation or result.trajectory is None:
        raise ValueError(f"scene {result.scene.name!r} does not ask for an animation; set "
                         "`draw.animation = true` in its scene file")
    fps = as_int("fps", fps if fps is not None else result.scene.draw.fps or FPS, minimum=1,
                 maximum=1000)
    size = as_int("size", size if size is not None else
                  result.scene.draw.animation_size or SIZE_PX, minimum=64, maximum=4096)
    size += size % 2
    result = densified(result, np.radians(as_float("max_turn_deg", max_turn_deg,
                                                   positive=True)))
    assert result.trajectory is not None, "a densified result keeps its frames"
    gif = Path(path)
    ffmpeg = ffmpeg_path() if mp4 is not False else None
    if mp4 and ffmpeg is None:
        raise ValueError("`mp4=True` needs ffmpeg: install it, or `pip install imageio-ffmpeg`")
    anim = animation(result, size=size, fps=fps)
    video = _Video(ffmpeg, gif.with_suffix(".mp4"), fps) if ffmpeg else None
    images: list[Image.Image] = []
    try:
        bar = tqdm(total=result.scene.frames, desc=f"animation {result.scene.name}",
                   unit="frame", disable=None if progress is None else not progress)
        with bar:
            anim.save(str(gif), writer=_Frames(images, video, bar, fps))
        images[0].save(gif, save_all=True, append_images=images[1:],
                       duration=round(1000 / fps), loop=0, optimize=False)
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


class _Frames(AbstractMovieWriter):
    """A matplotlib movie writer that hands each rendered frame to the GIF's frame list and
    to the ffmpeg process, so that the animation is drawn once for both files."""

    def __init__(self, images: list[Image.Image], video: _Video | None, bar: Any,
                 fps: int) -> None:
        super().__init__(fps=fps)
        self.images, self.video, self.bar = images, video, bar

    def setup(self, fig: Figure, outfile: str | Path, dpi: float | None = None) -> None:
        super().setup(fig, outfile, dpi)

    def grab_frame(self, **savefig_kwargs: Any) -> None:
        # the animation has just drawn the frame (its draw_idle renders at once on Agg):
        # take the pixels without rendering them a second time
        rgba = np.asarray(self.fig.canvas.buffer_rgba())  # type: ignore[attr-defined]
        self.images.append(Image.fromarray(rgba[..., :3]).quantize(colors=128))
        if self.video is not None:
            self.video.write(rgba)
        self.bar.update()

    def finish(self) -> None:
        pass


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
