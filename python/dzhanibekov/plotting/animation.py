"""The animation: the flipping body, its inertia ellipsoid and the signal point's trail.

Every frame is drawn once with matplotlib (Agg) and handed to each writer: a GIF through
Pillow always, an MP4 through ffmpeg when an ffmpeg executable is found (on the PATH or
matplotlib's ``animation.ffmpeg_path``, else the one the optional ``imageio-ffmpeg``
package ships: ``pip install dzhanibekov[video]``). The positions of all the body's points
at all frames come from one call to the core's `rotate` (the scene's plan), before drawing.
"""

from __future__ import annotations

import shutil
import textwrap
import warnings
import subprocess
from pathlib import Path

import numpy as np
from matplotlib.animation import FFMpegWriter
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from PIL import Image
from tqdm import tqdm

from ..scenes.plan import SceneResult
from .figures import _axes3d, _limits, _title, compute, draw_body, extent
from ..scenes.scene import Scene

__all__ = ["animate", "ffmpeg_path"]

SIZE_PX = 360
"""Width and height of the animation, in pixels (even, as H.264 needs)."""


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


def animate(scene: Scene | SceneResult, path: str | Path, *, fps: int = 20,
            mp4: bool | None = None, progress: bool | None = None) -> list[Path]:
    """Renders the scene's animation: one frame per scene frame.

    Parameters
    ----------
    scene : Scene or SceneResult
        A scene with ``draw.animation = true`` (its plan rotates every drawn point for every
        frame in one call to the core).
    path : str or Path
        The GIF to write; the MP4 goes beside it with the suffix ``.mp4``.
    fps : int
        Frames per second.
    mp4 : bool, optional
        Also write an MP4: None (default) when ffmpeg is found, True to insist (ValueError
        without ffmpeg), False never.
    progress : bool, optional
        Show a progress bar (tqdm, on stderr) while frames render: None (default) only on a
        terminal.

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
    result = compute(scene)
    if not result.scene.draw.animation or result.trajectory is None:
        raise ValueError(f"scene {result.scene.name!r} does not ask for an animation; set "
                         "`draw.animation = true` in its scene file")
    gif = Path(path)
    ffmpeg = ffmpeg_path() if mp4 is not False else None
    if mp4 and ffmpeg is None:
        raise ValueError("`mp4=True` needs ffmpeg: install it, or `pip install imageio-ffmpeg`")
    n = result.scene.frames
    fig = Figure(figsize=(SIZE_PX / 100, SIZE_PX / 100), dpi=100)
    canvas = FigureCanvasAgg(fig)
    fig.subplots_adjust(0, 0, 1, 0.93)
    ax = _axes3d(fig, 1, 1, 1)
    ax.set_axis_off()
    _limits(ax, extent(result))
    fig.suptitle(textwrap.fill(_title(result), 64), fontsize=7)
    clock = fig.text(0.02, 0.02, "", fontsize=8)
    images: list[Image.Image] = []
    video = _Video(ffmpeg, gif.with_suffix(".mp4"), fps) if ffmpeg else None
    try:
        bar = tqdm(total=n, desc=f"animation {result.scene.name}", unit="frame",
                   disable=None if progress is None else not progress)
        with bar:
            for frame in range(n):
                # the artists of one frame, removed before the next: the points are precomputed
                artists = draw_body(ax, result, frame)
                clock.set_text(f"t = {result.trajectory.t[frame]:.1f}")
                canvas.draw()  # type: ignore[no-untyped-call]
                rgba = np.asarray(canvas.buffer_rgba())  # type: ignore[no-untyped-call]
                images.append(Image.fromarray(rgba[..., :3]).quantize(colors=64))
                if video is not None:
                    video.write(rgba)
                for artist in artists.values():
                    artist.remove()
                for line in list(ax.lines):
                    line.remove()
                bar.update()
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
