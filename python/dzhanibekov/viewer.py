"""An interactive viewer: one self-contained HTML file to turn the flipping body in a browser.

:func:`write_html` draws the body (its box), its inertia ellipsoid and the signal point's
path with plotly and writes a single HTML file with plotly's JavaScript embedded, so it
opens anywhere without a network: drag to rotate, scroll to zoom, play/pause and a time
slider. plotly is the ``viewer`` extra: ``pip install ".[viewer]"`` from a checkout.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import numpy as np

from ._args import as_float, as_int
from ._files import as_path, replacing
from ._tables import require
from .geometry import box_edges
from .results import Trajectory
from .scenes.plan import SceneResult, execute, make_plan
from .scenes.scene import Scene, SceneError
from .scenes.staging import result_for

__all__ = ["write_html", "figure"]

EXTRA = 'the `viewer` extra: pip install ".[viewer]" from a checkout (plotly)'
DEFAULT_FRAMES = 201
"""Frames shown at most by default: each is a copy of every drawn point in the page."""
MAX_FRAMES = 1000
"""The most frames the viewer shows (`frames`): each shown frame holds a copy of every drawn
point, and the signal point's trail up to it, in the page (about 0.1 MB a frame)."""
PATH_POINTS = 1000
"""The most points of the signal point's path in the page: a run of more frames is drawn
through that many of them, evenly spread (the shown frames among them)."""


def _subsampled(traj: Trajectory, count: int) -> Trajectory:
    """`traj` at `count` of its frames evenly spread (the first and last among them)."""
    n = len(traj.t)
    if count >= n:
        return traj
    kept = np.unique(np.round(np.linspace(0, n - 1, count)).astype(int))
    return dataclasses.replace(traj, t=traj.t[kept], omega=traj.omega[kept], q=traj.q[kept],
                               sigma=None if traj.sigma is None else traj.sigma[kept],
                               _invariants={})


def _frames(frames: int | None, n: int) -> int:
    """The frames shown, of a run of `n`: `frames`, checked against the viewer's bound."""
    if frames is None:
        return min(n, DEFAULT_FRAMES)
    count = as_int("frames", frames, minimum=1)
    if count > MAX_FRAMES:
        raise ValueError(f"`frames` must be at most {MAX_FRAMES} (the viewer's MAX_FRAMES: each "
                         f"shown frame is a copy of the drawn points in the page), got {count}")
    if count > n:
        raise ValueError(f"`frames` must be at most the run's {n} frames, got {count}")
    return count


def _result(scene: Scene | SceneResult | Trajectory, frames: int | None) -> tuple[SceneResult,
                                                                                    np.ndarray]:
    """What the viewer draws, every object at each of at most `PATH_POINTS` frames of the run
    (one call to `rotate`), and the indices of the shown frames among them."""
    if isinstance(scene, Trajectory):
        count = _frames(frames, len(scene.t))
        sub = _subsampled(scene, max(count, min(len(scene.t), PATH_POINTS)))
        result = result_for(sub, animation=True)
    else:
        traj = None
        if isinstance(scene, SceneResult):
            traj = scene.trajectory
            scene = scene.scene
        if not isinstance(scene, Scene):
            raise TypeError(f"`scene` must be a Scene or a Trajectory, got "
                            f"{type(scene).__name__}")
        count = _frames(frames, scene.frames)
        try:
            scene.drawn_box
            box = True
        except SceneError:
            box = False
        draw = dataclasses.replace(scene.draw, box=box, ellipsoid=True, signal_point=True,
                                   path=True, momentum=True, animation=True, phases=())
        if traj is None:
            traj = scene.run(flips=scene.flips)
        sub = _subsampled(traj, max(count, min(len(traj.t), PATH_POINTS)))
        staged = scene.replace(draw=draw, frames=len(sub.t))
        result = execute(make_plan(staged), trajectory=sub)
    n = len(sub.t)
    shown = np.unique(np.round(np.linspace(0, n - 1, min(count, n))).astype(int))
    return result, shown


def _edges(corners: np.ndarray) -> tuple[list[float | None], ...]:
    """The box's 12 edges as one polyline with gaps (None) between edges."""
    xs: list[float | None] = []
    ys: list[float | None] = []
    zs: list[float | None] = []
    for a, b in box_edges():
        for coords, k in ((xs, 0), (ys, 1), (zs, 2)):
            coords += [float(corners[a, k]), float(corners[b, k]), None]
    return xs, ys, zs


def figure(scene: Scene | SceneResult | Trajectory, *, frames: int | None = None,
           fps: float = 20.0) -> Any:
    """The viewer's plotly figure (see :func:`write_html`): a ``plotly.graph_objects.Figure``
    with one animation frame per shown frame, play/pause buttons and a time slider."""
    go = require("plotly.graph_objects", "the viewer", EXTRA)
    fps = as_float("fps", fps, positive=True)
    result, shown = _result(scene, frames)
    traj = result.trajectory
    assert traj is not None
    path = result.path
    mesh = result.mesh
    assert mesh is not None
    quads = mesh[1]
    triangles = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    size = 1.1 * float(max(np.abs(w.points).max() for w in result.world.values()))

    def traces(frame: int) -> list[Any]:
        out = []
        if "box" in result.world:
            x, y, z = _edges(result.at("box", frame))
            out.append(go.Scatter3d(x=x, y=y, z=z, mode="lines", name="box",
                                    line={"color": "#1f3b73", "width": 5}))
        e = result.at("ellipsoid", frame)
        out.append(go.Mesh3d(x=e[:, 0], y=e[:, 1], z=e[:, 2], i=triangles[:, 0],
                             j=triangles[:, 1], k=triangles[:, 2], color="#f2a541",
                             opacity=0.35, name="inertia ellipsoid", showlegend=True))
        trail = path[: frame + 1]
        out.append(go.Scatter3d(x=trail[:, 0], y=trail[:, 1], z=trail[:, 2], mode="lines",
                                name="signal point's path",
                                line={"color": "#c0392b", "width": 4}))
        out.append(go.Scatter3d(x=[path[frame, 0]], y=[path[frame, 1]], z=[path[frame, 2]],
                                mode="markers", name="signal point",
                                marker={"color": "#c0392b", "size": 5}))
        return out

    first = traces(int(shown[0]))
    moving = list(range(len(first)))
    ell = result.momentum_world
    ell = ell / (np.linalg.norm(ell) or 1.0) * size
    static = [
        go.Scatter3d(x=path[:, 0], y=path[:, 1], z=path[:, 2], mode="lines",
                     name="whole path", line={"color": "#c0392b", "width": 1}, opacity=0.3),
        go.Scatter3d(x=[-ell[0], ell[0]], y=[-ell[1], ell[1]], z=[-ell[2], ell[2]],
                     mode="lines", name="L (angular momentum)",
                     line={"color": "#111111", "width": 2, "dash": "dash"}),
    ]
    fig = go.Figure(data=first + static)
    fig.frames = [go.Frame(data=traces(int(k)), traces=moving, name=str(int(k)))
                  for k in shown]
    step = 1000.0 / fps
    play = {"frame": {"duration": step, "redraw": True}, "fromcurrent": True,
            "transition": {"duration": 0}}
    pause = {"frame": {"duration": 0, "redraw": False}, "mode": "immediate",
             "transition": {"duration": 0}}
    axis = {"range": [-size, size], "title": ""}
    fig.update_layout(
        title=result.scene.title,
        scene={"xaxis": dict(axis, title="X"), "yaxis": dict(axis, title="Y"),
               "zaxis": dict(axis, title="Z"), "aspectmode": "cube",
               "domain": {"y": [0.12, 1.0]}},
        margin={"l": 0, "r": 0, "t": 40, "b": 0},
        legend={"x": 0.0, "y": 0.95},
        updatemenus=[{"type": "buttons", "direction": "left", "x": 0.05, "y": 0.02,
                      "xanchor": "left", "yanchor": "bottom",
                      "buttons": [{"label": "▶ play", "method": "animate",
                                   "args": [None, play]},
                                  {"label": "❚❚ pause", "method": "animate",
                                   "args": [[None], pause]}]}],
        sliders=[{"active": 0, "x": 0.25, "len": 0.7, "y": 0.02, "yanchor": "bottom",
                  "currentvalue": {"prefix": "t = "},
                  "steps": [{"label": f"{traj.t[k]:.3g}", "method": "animate",
                             "args": [[str(int(k))], pause]} for k in shown]}],
    )
    return fig


def write_html(scene: Scene | SceneResult | Trajectory, path: str | Path, *,
               frames: int | None = None, fps: float = 20.0) -> Path:
    """Writes the interactive viewer of a scene or trajectory: one self-contained HTML file.

    The page holds the body's box, its inertia ellipsoid (radii of gyration for a
    trajectory; the scene's convention for a scene), the signal point and its path, and the
    angular momentum's direction, at each shown frame; plotly's JavaScript is embedded, so
    the file opens offline in any browser. Drag to rotate, scroll to zoom; play, pause and
    a time slider move through the frames.

    Parameters
    ----------
    scene : Scene, SceneResult or Trajectory
        A scene (run here, drawing everything) or a trajectory (drawn as it is).
    path : str or Path
        The HTML file to write.
    frames : int, optional
        Frames shown, evenly spread over the run (default: every frame, at most 201; at
        most :data:`MAX_FRAMES`). The path is drawn through at most :data:`PATH_POINTS`
        frames of the run, evenly spread, whatever its length.
    fps : float
        Frames per second when playing.

    Returns
    -------
    Path

    Raises
    ------
    ImportError
        plotly is missing: install the ``viewer`` extra.
    ValueError
        `frames` beyond the run's frames or :data:`MAX_FRAMES`.
    OSError
        The file cannot be written (its folder is missing, the disk is full): the previous
        file is as it was (it is replaced only once the new one is complete).

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> dz.viewer.write_html(dz.SCENES["example"], "flip.html")    # doctest: +SKIP
    PosixPath('flip.html')
    """
    destination = as_path(path)
    fig = figure(scene, frames=frames, fps=fps)
    with replacing(destination) as tmp:  # all or nothing: the previous file kept on failure
        fig.write_html(tmp, include_plotlyjs=True, full_html=True, auto_play=False)
    return destination
