"""An interactive viewer: one self-contained HTML file to turn the flipping body in a browser.

:func:`write_html` draws what a scene draws — the body as itself (its box, or its own shape:
a wing nut, a composite, a mesh, shaded), its inertia ellipsoid, the signal point and its
path, the angular momentum — with plotly, each labelled, and writes a single HTML file with
plotly's JavaScript embedded, so it opens anywhere without a network: drag to rotate, scroll
to zoom, play/pause and a time slider. A run (a `Trajectory`, or rows of a `Batch`) is drawn
as it is. plotly is the ``viewer`` extra: ``pip install ".[viewer]"`` from a checkout.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import numpy as np

from ._args import as_float, as_int
from ._tables import require
from .results import Batch, Trajectory
from .scenes.plan import SceneResult, execute, make_plan
from .scenes.scene import Scene, SceneError
from .scenes.staging import result_for

__all__ = ["write_html", "figure"]

EXTRA = 'the `viewer` extra: pip install ".[viewer]" from a checkout (plotly)'
DEFAULT_FRAMES = 201
"""Frames shown at most by default: each is a copy of every drawn point in the page."""


Drawable = Scene | SceneResult | Trajectory | Batch
"""What the viewer draws: a scene (run here), a scene's result, a run, or rows of a batch."""


def _result(scene: Scene | SceneResult | Trajectory) -> SceneResult:
    """What the viewer draws of one scene or run, every object at every frame (one call to
    `rotate`): the objects the scene draws (the body at least), animated."""
    if isinstance(scene, Trajectory):
        return result_for(scene, animation=True)
    if isinstance(scene, SceneResult):
        scene = scene.scene
    if not isinstance(scene, Scene):
        raise TypeError(f"`scene` must be a Scene, a Trajectory or a Batch, got "
                        f"{type(scene).__name__}")
    draw = scene.draw
    if not draw.objects:  # a scene that draws nothing in 3-D: its body and path
        draw = dataclasses.replace(draw, box=_drawable_body(scene), signal_point=True,
                                   path=True)
    return execute(make_plan(scene.replace(draw=dataclasses.replace(draw, animation=True))))


def _drawable_body(scene: Scene) -> bool:
    try:
        scene.drawn_box
        return True
    except SceneError:
        return scene.drawn_shape is not None


def _rows(scene: Drawable, rows: Any) -> list[Scene | SceneResult | Trajectory]:
    """The runs drawn: the scene or run itself, or the chosen rows of a batch (default the
    first)."""
    if not isinstance(scene, Batch):
        if rows is not None:
            raise ValueError("`rows` chooses rows of a Batch; a scene or a run is drawn whole")
        return [scene]
    chosen = [0] if rows is None else [rows] if isinstance(rows, (int, np.integer)) \
        else list(rows)
    if not chosen:
        raise ValueError("`rows` must choose at least one row of the batch")
    for k in chosen:
        if isinstance(k, bool) or not isinstance(k, (int, np.integer)):
            raise TypeError(f"`rows` must be row numbers, got {k!r}")
        if not -len(scene) <= int(k) < len(scene):
            raise ValueError(f"`rows` must be rows of the batch (0 to {len(scene) - 1}), got {k}")
    return [scene[int(k)] for k in chosen]


def _lines(points: np.ndarray, edges: np.ndarray) -> tuple[list[float | None], ...]:
    """Edges as one polyline with gaps (None) between them."""
    xs: list[float | None] = []
    ys: list[float | None] = []
    zs: list[float | None] = []
    for a, b in edges:
        for coords, k in ((xs, 0), (ys, 1), (zs, 2)):
            coords += [float(points[a, k]), float(points[b, k]), None]
    return xs, ys, zs


def figure(scene: Drawable, *, frames: int | None = None, fps: float = 20.0,
           rows: Any = None) -> Any:
    """The viewer's plotly figure (see :func:`write_html`): a ``plotly.graph_objects.Figure``
    with one animation frame per shown frame, play/pause buttons and a time slider."""
    go = require("plotly.graph_objects", "the viewer", EXTRA)
    fps = as_float("fps", fps, positive=True)
    results = [_result(r) for r in _rows(scene, rows)]
    result = results[0]
    traj = result.trajectory
    assert traj is not None
    n = len(traj.t)
    count = min(n, DEFAULT_FRAMES) if frames is None else as_int("frames", frames, minimum=1,
                                                                  maximum=n)
    shown = np.unique(np.round(np.linspace(0, n - 1, count)).astype(int))
    drawn = result.scene.draw
    shape = result.scene.drawn_shape if "box" in result.world else None
    points = [w.points for r in results for w in r.world.values() if w.points.size]
    paths = [r.path for r in results if r.scene.draw.path]
    size = 1.1 * float(max([np.abs(p).max() for p in points + paths] or [1.0]))
    body_name = "body" if result.scene.body.shape is not None else "box"
    colors = ["#c0392b", "#2e86c1", "#27ae60", "#8e44ad", "#d35400", "#16a085"]

    def traces(frame: int) -> list[Any]:
        out = []
        if shape is not None:
            corners = result.at("box", frame)
            x, y, z = _lines(corners, shape.edges)
            out.append(go.Scatter3d(x=x, y=y, z=z, mode="lines", name=body_name,
                                    line={"color": "#1f3b73", "width": 4}))
            if shape.faces is not None:
                f = shape.faces
                out.append(go.Mesh3d(x=corners[:, 0], y=corners[:, 1], z=corners[:, 2],
                                     i=f[:, 0], j=f[:, 1], k=f[:, 2], color="#9fb3d9",
                                     opacity=0.6, name=f"{body_name} (faces)",
                                     showlegend=True))
        if "ellipsoid" in result.world and result.mesh is not None:
            quads = result.mesh[1]
            tri = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
            e = result.at("ellipsoid", frame)
            out.append(go.Mesh3d(x=e[:, 0], y=e[:, 1], z=e[:, 2], i=tri[:, 0], j=tri[:, 1],
                                 k=tri[:, 2], color="#f2a541", opacity=0.35,
                                 name="inertia ellipsoid", showlegend=True))
        for k, r in enumerate(results):
            if not r.scene.draw.path:
                continue
            label = "signal point" if len(results) == 1 else f"signal point, row {k}"
            path, color = r.path, colors[k % len(colors)]
            trail = path[: frame + 1]
            out.append(go.Scatter3d(x=trail[:, 0], y=trail[:, 1], z=trail[:, 2],
                                    mode="lines", name=f"{label}'s path",
                                    line={"color": color, "width": 4}))
            out.append(go.Scatter3d(x=[path[frame, 0]], y=[path[frame, 1]],
                                    z=[path[frame, 2]], mode="markers", name=label,
                                    marker={"color": color, "size": 5}))
        return out

    first = traces(int(shown[0]))
    moving = list(range(len(first)))
    static = []
    for k, r in enumerate(results):
        if r.scene.draw.path:
            path = r.path
            static.append(go.Scatter3d(x=path[:, 0], y=path[:, 1], z=path[:, 2], mode="lines",
                                       name="whole path" if len(results) == 1 else
                                       f"whole path, row {k}",
                                       line={"color": colors[k % len(colors)], "width": 1},
                                       opacity=0.3))
    if drawn.momentum:
        ell = result.momentum_world
        ell = ell / (np.linalg.norm(ell) or 1.0) * size
        static.append(go.Scatter3d(x=[-ell[0], ell[0]], y=[-ell[1], ell[1]],
                                   z=[-ell[2], ell[2]], mode="lines",
                                   name="L (angular momentum)",
                                   line={"color": "#111111", "width": 2, "dash": "dash"}))
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


def write_html(scene: Drawable, path: str | Path, *, frames: int | None = None,
               fps: float = 20.0, rows: Any = None) -> Path:
    """Writes the interactive viewer of a scene or trajectory: one self-contained HTML file.

    The page holds what the scene draws, each labelled: the body as itself (its box, or its
    own shape, shaded where it has faces), its inertia ellipsoid (radii of gyration for a
    run; the scene's convention for a scene), the signal point and its path, and the angular
    momentum's direction, at each shown frame; plotly's JavaScript is embedded, so the file
    opens offline in any browser. Drag to rotate, scroll to zoom; play, pause and a time
    slider move through the frames.

    Parameters
    ----------
    scene : Scene, SceneResult, Trajectory or Batch
        A scene (run here, drawing what it draws), a run (drawn as it is), or a batch (the
        `rows` chosen).
    path : str or Path
        The HTML file to write.
    frames : int, optional
        Frames shown, evenly spread over the run (default: every frame, at most 201).
    fps : float
        Frames per second when playing.
    rows : int or sequence of int, optional
        A batch's rows drawn: one (default the first), or several, their paths overlaid on
        the first row's body.

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
    fig = figure(scene, frames=frames, fps=fps, rows=rows)
    path = Path(path)
    fig.write_html(path, include_plotlyjs=True, full_html=True, auto_play=False)
    return path
