"""Rendering scenes into a folder, all or nothing.

Files are drawn into a temporary folder beside the destination and moved into place only
when every one of them is done, so an error or Ctrl-C leaves the destination as it was.
"""

from __future__ import annotations

import dataclasses
import contextlib
import json
import os
import shutil
import tempfile
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .plotting.movie import animate
from .scenes.plan import SceneResult
from .plotting.figures import FIGURE_FUNCTIONS, compute, fig3_figure
from .scenes.scene import PAPER_SCENES, SCENES, STORY_SCENES, Scene

__all__ = ["render_scene", "render_paper", "output_folder", "OutputError", "MAX_JSON_FLIP_TIMES"]

MAX_JSON_FLIP_TIMES = 1000
"""Flip times listed in a scene's JSON summary; longer lists are summarised there (count,
first, last, mean spacing) and written in full to ``NAME-flip-times.npy`` only when asked."""


class OutputError(OSError):
    """The output folder cannot be written, or an output cannot replace what is there; the
    message names the path and the cause, and the folder is as it was."""

    def __init__(self, path: str | Path, why: str) -> None:
        super().__init__(f"cannot write {path}: {why}; nothing was written or replaced")
        self.path, self.why = str(path), why

    def __reduce__(self) -> tuple[type[OutputError], tuple[str, str]]:
        return type(self), (self.path, self.why)


def _missing_ancestors(out: Path) -> list[Path]:
    """`out` and its ancestors that do not exist yet, deepest first."""
    missing = []
    for folder in (out, *out.parents):
        if os.path.lexists(folder):
            break
        missing.append(folder)
    return missing


def _check_destination(out: Path) -> None:
    """Refuses an `out` that cannot become a folder: a file, a dangling symbolic link, or a
    path below a file."""
    if os.path.lexists(out) and not out.exists():
        raise OutputError(out, f"it is a symbolic link to {os.readlink(out)}, which does not "
                          "exist; create that folder or give another `--out`")
    if out.exists() and not out.is_dir():
        raise OutputError(out, "it is a file; `--out` must be a folder")
    for parent in out.parents:
        if parent.exists():
            if not parent.is_dir():
                raise OutputError(out, f"{parent} is a file, not a folder")
            break


@contextlib.contextmanager
def output_folder(out: str | Path) -> Iterator[Path]:
    """A temporary folder inside `out` (created if need be) to write into; its files replace
    those of the same name in `out` when the block ends normally, and it is removed whatever
    happens. Made inside `out`, it is on the same filesystem (a mount point works) and its
    files move in by renaming.

    Every destination is checked before any is replaced: a folder named like an output
    leaves `out` untouched. Any failure to write (a read-only folder, a full disk, a file-size
    limit) raises :class:`OutputError` naming the path, and `out` is as it was; folders this
    call created are removed again.
    """
    out = Path(out)
    _check_destination(out)
    created = _missing_ancestors(out)
    done = False
    tmp: Path | None = None
    try:
        out.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=".partial-", dir=out))
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o777 & ~umask)
        yield tmp
        items = sorted(tmp.iterdir())
        for item in items:
            target = out / item.name
            if target.is_dir() and not target.is_symlink():
                raise OutputError(target, "a folder of that name is in the way of the output "
                                  "file; move it away")
        for item in items:
            os.replace(item, out / item.name)
        done = True
    except OutputError:
        raise
    except OSError as exc:
        path = exc.filename if exc.filename is not None else out
        if tmp is not None and Path(path).is_relative_to(tmp):
            path = out / Path(path).relative_to(tmp)  # the file it was to become
        raise OutputError(path, exc.strerror or str(exc)) from None
    finally:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
        if not done:
            for folder in created:  # deepest first; only those still empty
                try:
                    folder.rmdir()
                except OSError:
                    break


@contextlib.contextmanager
def _writing(path: Path) -> Iterator[None]:
    """Names `path` in an OSError raised while writing it (matplotlib's and Pillow's writes
    through file objects leave the name out)."""
    try:
        yield
    except OSError as exc:
        if exc.filename is None:
            exc.filename = str(path)
        raise


def summary(result: SceneResult) -> dict[str, Any]:
    """What the run measured, for a JSON file."""
    run = result.trajectory if result.trajectory is not None else result.summary
    assert run is not None
    flips = result.flip_times
    listed = flips is not None and len(flips) <= MAX_JSON_FLIP_TIMES
    return {
        "scene": result.scene.name,
        "title": result.scene.title,
        "verdict": result.verdict,
        "flip_times": [float(t) for t in flips] if listed and flips is not None else None,
        "flips": None if flips is None else {
            "count": len(flips),
            "first": float(flips[0]) if len(flips) else None,
            "last": float(flips[-1]) if len(flips) else None,
            "mean_spacing": float((flips[-1] - flips[0]) / (len(flips) - 1))
            if len(flips) > 1 else None,
        },
        "drift": dataclasses.asdict(run.drift),
        "method": run.method,
        "dt": run.dt,
        "n_steps": run.n_steps,
    }


def render_scene(scene: Scene | SceneResult, folder: str | Path, *,
                 progress: bool | None = None, flip_times: bool = False,
                 fps: int | None = None, size: int | None = None) -> list[Path]:
    """Writes what `scene` draws into `folder`: ``NAME-FIGURE.png`` for each of its figures,
    ``NAME.gif`` (and ``NAME.mp4`` with ffmpeg) for its animation, and ``NAME.json`` with its
    flip times (at most :data:`MAX_JSON_FLIP_TIMES`; more are summarised), verdict and drift;
    with `flip_times`, every flip time in ``NAME-flip-times.npy``. Returns the files written.

    Write into a folder from :func:`output_folder` for all-or-nothing output. `fps` and
    `size` override the scene's animation settings (see :func:`~dzhanibekov.plotting.movie.animate`).
    """
    result = compute(scene)
    folder = Path(folder)
    name = result.scene.name
    written = []
    for figure in result.scene.draw.figures:
        path = folder / f"{name}-{figure}.png"
        with _writing(path):
            FIGURE_FUNCTIONS[figure](result, save=path)
        written.append(path)
    if result.scene.draw.animation:
        with _writing(folder / f"{name}.gif"):
            written += animate(result, folder / f"{name}.gif", progress=progress, fps=fps,
                               size=size)
    about = summary(result)
    if flip_times and result.flip_times is not None:
        path = folder / f"{name}-flip-times.npy"
        with _writing(path):
            np.save(path, result.flip_times)
        written.append(path)
        about["flip_times_file"] = path.name
    path = folder / f"{name}.json"
    path.write_text(json.dumps(about, indent=2) + "\n", encoding="utf-8")
    written.append(path)
    return written


def render_paper(folder: str | Path, *, dt: float | None = None,
                 progress: bool | None = None, fps: int | None = None,
                 size: int | None = None) -> tuple[list[Path], list[SceneResult]]:
    """Writes every figure of the paper and its animation into `folder`, those of the wing
    nut of its Fig. 1, those of the stable counter-examples and of the bodies that change
    (:data:`STORY_SCENES`: a deployment, Explorer 1): each shipped scene's files
    (:func:`render_scene`), plus
    ``fig3.png`` (Fig. 3 a–c side by side) and ``stable.png`` (the counter-examples' paths).

    `dt` overrides the scenes' step. Returns the files written and the computed scenes.
    """
    folder = Path(folder)
    names: Sequence[str] = (list(PAPER_SCENES) + ["wing-nut"]
                            + [n for n in SCENES if n.startswith("stable-")]
                            + list(STORY_SCENES))
    results = {}
    written: list[Path] = []
    for name in names:
        scene = SCENES[name] if dt is None else SCENES[name].replace(dt=dt)
        results[name] = compute(scene)
        written += render_scene(results[name], folder, progress=progress, fps=fps, size=size)
    path = folder / "fig3.png"
    with _writing(path):
        fig3_figure([results[n] for n in ("fig3a", "fig3b", "fig3c")], save=path)
    written.append(path)
    stable = [results[n] for n in names if n.startswith("stable-")]
    if stable:
        path = folder / "stable.png"
        with _writing(path):
            fig3_figure(stable, save=path)
        written.append(path)
    return written, list(results.values())
