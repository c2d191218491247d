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


def _result(scene: Scene | SceneResult | Trajectory) -> SceneResult:
    """What the viewer draws, every object at every frame (one call to `rotate`)."""
    if isinstance(scene, Trajectory):
        return result_for(scene, animation=True)
    if isinstance(scene, SceneResult):
        scene = scene.scene
    if not isinstance(scene, Scene):
        raise TypeError(f"`scene` must be a Scene or a Trajectory, got {type(scene).__name__}")
    try:
        scene.drawn_box
        box = True
    except SceneError:
        box = False
    draw = dataclasses.replace(scene.draw, box=box, ellipsoid=True, signal_point=True,
                               path=True, momentum=True, animation=True)
    return execute(make_plan(scene.replace(draw=draw)))


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
    result = _result(scene)
    traj = result.trajectory
    assert traj is not None
    n = len(traj.t)
    count = min(n, DEFAULT_FRAMES) if frames is None else as_int("frames", frames, minimum=1,
                                                                  maximum=n)
    shown = np.unique(np.round(np.linspace(0, n - 1, count)).astype(int))
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
        Frames shown, evenly spread over the run (default: every frame, at most 201).
    fps : float
        Frames per second when playing.

    Returns
    -------
    Path

    Raises
    ------
    ImportError
        plotly is missing: install the ``viewer`` extra.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> dz.viewer.write_html(dz.SCENES["example"], "flip.html")    # doctest: +SKIP
    PosixPath('flip.html')
    """
    fig = figure(scene, frames=frames, fps=fps)
    path = Path(path)
    fig.write_html(path, include_plotlyjs=True, full_html=True, auto_play=False)
    return path
