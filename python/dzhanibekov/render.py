"""Rendering scenes into a folder, all or nothing.

Files are drawn into a temporary folder beside the destination and moved into place only
when every one of them is done, so an error or Ctrl-C leaves the destination as it was.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import tempfile
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

from .plotting.animation import animate
from .scenes.plan import SceneResult
from .plotting.figures import FIGURE_FUNCTIONS, compute, fig3_figure
from .scenes.scene import PAPER_SCENES, SCENES, STORY_SCENES, Scene

__all__ = ["render_scene", "render_paper", "output_folder"]


@contextlib.contextmanager
def output_folder(out: str | Path) -> Iterator[Path]:
    """A temporary folder beside `out` to write into; its files replace those of the same
    name in `out` (created if need be) when the block ends normally, and it is removed
    whatever happens."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise ValueError(f"`--out` must be a folder, but {out} is a file")
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.partial-", dir=out.parent))
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o777 & ~umask)  # mkdtemp's 0700 would become the folder's mode
    try:
        yield tmp
        if not out.exists():
            os.rename(tmp, out)
        else:
            for item in sorted(tmp.iterdir()):
                os.replace(item, out / item.name)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def summary(result: SceneResult) -> dict[str, Any]:
    """What the run measured, for a JSON file."""
    run = result.trajectory if result.trajectory is not None else result.summary
    assert run is not None
    flips = result.flip_times
    return {
        "scene": result.scene.name,
        "title": result.scene.title,
        "verdict": result.verdict,
        "flip_times": None if flips is None else [float(t) for t in flips],
        "drift": run.drift._asdict(),
        "method": run.method,
        "dt": run.dt,
        "n_steps": run.n_steps,
    }


def render_scene(scene: Scene | SceneResult, folder: str | Path, *,
                 progress: bool | None = None) -> list[Path]:
    """Writes what `scene` draws into `folder`: ``NAME-FIGURE.png`` for each of its figures,
    ``NAME.gif`` (and ``NAME.mp4`` with ffmpeg) for its animation, and ``NAME.json`` with its
    flip times, verdict and drift. Returns the files written.

    Write into a folder from :func:`output_folder` for all-or-nothing output.
    """
    result = compute(scene)
    folder = Path(folder)
    name = result.scene.name
    written = []
    for figure in result.scene.draw.figures:
        path = folder / f"{name}-{figure}.png"
        FIGURE_FUNCTIONS[figure](result, save=path)
        written.append(path)
    if result.scene.draw.animation:
        written += animate(result, folder / f"{name}.gif", progress=progress)
    path = folder / f"{name}.json"
    path.write_text(json.dumps(summary(result), indent=2) + "\n", encoding="utf-8")
    written.append(path)
    return written


def render_paper(folder: str | Path, *, dt: float | None = None,
                 progress: bool | None = None) -> tuple[list[Path], list[SceneResult]]:
    """Writes every figure of the paper and its animation into `folder`, and those of the
    stable counter-examples and of the bodies that change (:data:`STORY_SCENES`: a
    deployment, Explorer 1): each shipped scene's files (:func:`render_scene`), plus
    ``fig3.png`` (Fig. 3 a–c side by side) and ``stable.png`` (the counter-examples' paths).

    `dt` overrides the scenes' step. Returns the files written and the computed scenes.
    """
    folder = Path(folder)
    names: Sequence[str] = (list(PAPER_SCENES) + [n for n in SCENES if n.startswith("stable-")]
                            + list(STORY_SCENES))
    results = {}
    written: list[Path] = []
    for name in names:
        scene = SCENES[name] if dt is None else SCENES[name].replace(dt=dt)
        results[name] = compute(scene)
        written += render_scene(results[name], folder, progress=progress)
    path = folder / "fig3.png"
    fig3_figure([results[n] for n in ("fig3a", "fig3b", "fig3c")], save=path)
    written.append(path)
    stable = [results[n] for n in names if n.startswith("stable-")]
    if stable:
        path = folder / "stable.png"
        fig3_figure(stable, save=path)
        written.append(path)
    return written, list(results.values())
