"""An interactive viewer: one self-contained HTML file to turn the flipping body in a browser.

:func:`write_html` draws what a scene draws — the body as itself (its box, or its own shape:
a wing nut, a composite, a mesh, shaded), its inertia ellipsoid, the signal point and its
path, the angular momentum — with plotly, each labelled, and writes a single HTML file with
plotly's JavaScript embedded, so it opens anywhere without a network: drag to rotate, scroll
to zoom, play/pause and a time slider. A run (a `Trajectory`, or rows of a `Batch`) is drawn
as it is. plotly is the ``viewer`` extra: ``pip install "dzhanibekov[viewer]"``.
"""

from __future__ import annotations

import base64
import dataclasses
import functools
import gzip
import html
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from ._args import as_float, as_int
from ._files import as_path, replacing
from ._tables import require
from .results import Batch, Trajectory
from .scenes.parse import drawn_label
from .scenes.plan import SceneResult, execute, make_plan
from .scenes.scene import Scene, SceneError
from .scenes.staging import result_for

__all__ = ["write_html", "figure"]

EXTRA = ('the `viewer` extra: pip install "dzhanibekov[viewer]" (plotly; by the package\'s '
         'name it installs only that, without rebuilding the core)')
DEFAULT_FRAMES = 201
"""Frames shown at most by default: each is a copy of every drawn point in the page."""
MAX_FRAMES = 1000
"""The most frames the viewer shows (`frames`): each shown frame holds a copy of every drawn
point, and the signal point's trail up to it, in the page (about 3 kB a frame, packed)."""
PATH_POINTS = 1000
"""The most points of the signal point's path in the page: a run of more frames is drawn
through that many of them, evenly spread (the shown frames among them)."""
RESOLUTION = 40_000
"""The page's coordinates are rounded to a decimal step of at most ``1 / RESOLUTION`` of the
axes' span: a quarter of a pixel on a 10 000-pixel screen, nothing anyone sees, and numbers
short enough that the page of a shipped scene is about 2.5 MB, not 10."""


Drawable = Scene | SceneResult | Trajectory | Batch
"""What the viewer draws: a scene (run here), a scene's result, a run, or rows of a batch."""


def _subsampled(traj: Trajectory, count: int) -> Trajectory:
    """`traj` at `count` of its frames evenly spread (the first and last among them)."""
    n = len(traj.t)
    if count >= n:
        return traj
    kept = np.unique(np.round(np.linspace(0, n - 1, count)).astype(int))
    return dataclasses.replace(traj, t=traj.t[kept], omega=traj.omega[kept], q=traj.q[kept],
                               parts={k: v[kept] for k, v in traj.parts.items()},
                               _observed={})


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


def _result(scene: Scene | SceneResult | Trajectory,
            frames: int | None) -> tuple[SceneResult, int]:
    """What the viewer draws of one scene or run, every object at each of at most
    `PATH_POINTS` frames of the run (one call to `rotate`): the objects the scene draws (the
    body at least), animated; and how many frames are shown (`frames`, checked)."""
    if isinstance(scene, Trajectory):
        count = _frames(frames, len(scene.t))
        sub = _subsampled(scene, max(count, min(len(scene.t), PATH_POINTS)))
        return result_for(sub, animation=True), count
    traj = None
    if isinstance(scene, SceneResult):
        traj = scene.trajectory
        scene = scene.scene
    if not isinstance(scene, Scene):
        raise TypeError(f"`scene` must be a Scene, a Trajectory or a Batch, got "
                        f"{type(scene).__name__}")
    count = _frames(frames, scene.frames)
    draw = scene.draw
    if not draw.objects:  # a scene that draws nothing in 3-D: its body and path
        draw = dataclasses.replace(draw, box=_drawable_body(scene), signal_point=True,
                                   path=True)
    draw = dataclasses.replace(draw, animation=True, phases=())
    if traj is None:
        traj = scene.run(flips=scene.flips)
    # the scene's plan on the frames drawn: a long run is not refused by the bounds of an
    # animation file (a GIF's frames), which the page does not have
    sub = _subsampled(traj, max(count, min(len(traj.t), PATH_POINTS)))
    staged = scene.replace(draw=draw, frames=len(sub.t))
    return execute(make_plan(staged), trajectory=sub), count


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


def _sink_points(traj: Trajectory) -> list[tuple[str, np.ndarray]]:
    """Each moving part of the run (a spring's mass, a hinged panel, a slosh pendulum) as
    its name and, at every frame, two points in body axes (from the hub's mass centre): where
    it is held (the spring's rest point, the hinge, the pivot) and where its mass is (the
    spring's mass at its displacement, the panel's far end at its angle, the pendulum's bob
    on its rod), shape (frames, 2, 3)."""
    from .parts import Hinge, Slosh, SpringMassDamper

    system = traj.system
    stateful = [p for p in (*system.parts, *system.torques) if p._core.width > 0]
    out = []
    for name, part in zip(system.part_names, stateful):
        state = traj.parts[name]
        if isinstance(part, SpringMassDamper):
            held = np.asarray(part.anchor)
            d = np.asarray(part.direction) / np.linalg.norm(part.direction)
            moved = held + state[:, :1] * d
        elif isinstance(part, Hinge):
            held = np.asarray(part.hinge)
            e = np.asarray(part.axis) / np.linalg.norm(part.axis)
            s0 = np.asarray(part.arm) / np.linalg.norm(part.arm)
            beta = state[:, :1]
            # s(β) = s₀ cos β + (e × s₀) sin β, the panel's end at twice its centre's distance
            moved = held + 2 * part.length * (np.cos(beta) * s0 + np.sin(beta) * np.cross(e, s0))
        elif isinstance(part, Slosh):
            held = np.asarray(part.pivot)
            n = state[:, :3] / np.linalg.norm(state[:, :3], axis=1, keepdims=True)
            moved = held + part.length * n
        else:
            continue
        out.append((name, np.stack([np.broadcast_to(held, moved.shape), moved], axis=1)))
    return out


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
    items = [_result(r, frames) for r in _rows(scene, rows)]
    results = [r for r, _ in items]
    count = items[0][1]
    result = results[0]
    traj = result.trajectory
    assert traj is not None
    n = len(traj.t)
    shown = np.unique(np.round(np.linspace(0, n - 1, min(count, n))).astype(int))
    drawn = result.scene.draw
    shape = result.scene.drawn_shape if "box" in result.world else None
    points = [w.points for r in results for w in r.world.values() if w.points.size]
    paths = [r.path for r in results if r.scene.draw.path]
    size = 1.1 * float(max([np.abs(p).max() for p in points + paths] or [1.0]))
    body_name = drawn_label(result.scene.body, result.scene.body_spec)
    colors = ["#c0392b", "#2e86c1", "#27ae60", "#8e44ad", "#d35400", "#16a085"]
    from .simulate import rotate

    sinks = _sink_points(traj)

    def traces(frame: int) -> list[Any]:
        out = []
        for name, points in sinks:
            at = rotate(traj.q[frame:frame + 1], points[frame])[0]
            out.append(go.Scatter3d(x=at[:, 0], y=at[:, 1], z=at[:, 2], mode="lines+markers",
                                    name=name, line={"color": "#6e2c00", "width": 5},
                                    marker={"color": "#6e2c00", "size": [2, 6]}))
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
    opens offline in any browser (from 2023 on: plotly.js and the figure are stored
    gzip-compressed and unpacked by the browser's ``DecompressionStream``, which keeps a
    shipped scene's page near 2.5 MB; coordinates are rounded to :data:`RESOLUTION` of the
    axes' span, below a pixel). Drag to rotate, scroll to zoom; play, pause and a time
    slider move through the frames.

    Parameters
    ----------
    scene : Scene, SceneResult, Trajectory or Batch
        A scene (run here, drawing what it draws), a run (drawn as it is), or a batch (the
        `rows` chosen).
    path : str or Path
        The HTML file to write.
    frames : int, optional
        Frames shown, evenly spread over the run (default: every frame, at most 201; at
        most :data:`MAX_FRAMES`). The path is drawn through at most :data:`PATH_POINTS`
        frames of the run, evenly spread, whatever its length.
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
    fig = figure(scene, frames=frames, fps=fps, rows=rows)
    page = _page(fig)
    with replacing(destination) as tmp:  # all or nothing: the previous file kept on failure
        Path(tmp).write_text(page, encoding="utf-8")
    return destination


_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>{title}</title>
<style>html, body {{ height: 100%; }} #viewer {{ height: 100%; width: 100%; }}</style>
</head>
<body>
<div id="viewer"></div>
<noscript>The viewer is drawn by JavaScript: allow it for this page.</noscript>
<script>
"use strict";
// Written by dzhanibekov.viewer.write_html: plotly.js {version} and the figure, each
// gzip-compressed and base64-encoded (a page of a few MB instead of ten), unpacked here by
// the browser's own DecompressionStream; nothing is fetched from the network.
const PLOTLY = "{plotly}";
const FIGURE = "{figure}";
async function inflate(text) {{
  const bytes = Uint8Array.from(atob(text), (c) => c.charCodeAt(0));
  const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("gzip"));
  return await new Response(stream).text();
}}
(async () => {{
  const viewer = document.getElementById("viewer");
  if (typeof DecompressionStream === "undefined") {{
    viewer.textContent = "This page needs a browser from 2023 or later (Chrome 80, Firefox " +
      "113, Safari 16.4): it unpacks plotly.js with DecompressionStream.";
    return;
  }}
  const script = document.createElement("script");
  script.textContent = await inflate(PLOTLY);
  document.head.appendChild(script);
  const fig = JSON.parse(await inflate(FIGURE));
  await Plotly.newPlot(viewer, fig.data, fig.layout, {{responsive: true}});
  await Plotly.addFrames(viewer, fig.frames);
}})().catch((error) => {{
  document.getElementById("viewer").textContent = "The viewer could not start: " + error;
  throw error;
}});
</script>
</body>
</html>
"""


def _packed(text: str) -> str:
    """`text` gzip-compressed and base64-encoded, as the page unpacks it."""
    return base64.b64encode(gzip.compress(text.encode("utf-8"), 9, mtime=0)).decode("ascii")


@functools.lru_cache(maxsize=1)
def _plotly_js() -> tuple[str, str]:
    """plotly.js as the page holds it (packed once a process), and its version."""
    offline = require("plotly.offline", "the viewer", EXTRA)
    version = require("plotly", "the viewer", EXTRA).__version__
    return _packed(offline.get_plotlyjs()), str(version)


def _page(fig: Any) -> str:
    """The self-contained page of the viewer's figure `fig` (see :func:`write_html`)."""
    plotly, version = _plotly_js()
    title = fig.layout.title.text or "dzhanibekov viewer"
    return _PAGE.format(title=html.escape(str(title)), version=version, plotly=plotly,
                        figure=_packed(_figure_json(fig)))


_COORDINATES = ("x", "y", "z")
_FACES = ("i", "j", "k")


def _figure_json(fig: Any) -> str:
    """`fig` as compact JSON for the page: every coordinate rounded to a decimal step of at
    most the axes' span over `RESOLUTION` (shortest decimals, which compress well), and the
    faces of a mesh given once, in the trace, not again in every frame (an animation frame
    changes only what it gives)."""
    spec = fig.to_plotly_json()
    span = 2 * float(spec["layout"]["scene"]["xaxis"]["range"][1])
    decimals = max(0, math.ceil(math.log10(RESOLUTION / span))) if span > 0 else 6

    def plain(trace: dict[str, Any], in_frame: bool) -> dict[str, Any]:
        out = {}
        for key, value in trace.items():
            if in_frame and trace.get("type") == "mesh3d" and key in _FACES:
                continue
            if key in _COORDINATES and value is not None:
                value = [None if v is None else round(float(v), decimals)
                         for v in _array(value)]
            elif key in _FACES:
                value = np.asarray(_array(value)).astype(int).tolist()
            out[key] = value
        return out

    data = [plain(t, False) for t in spec["data"]]
    frames = [dict(f, data=[plain(t, True) for t in f["data"]]) for f in spec["frames"]]
    page = {"data": data, "layout": spec["layout"], "frames": frames}
    return json.dumps(page, separators=(",", ":"), default=_plain_value)


def _array(value: Any) -> Any:
    """A trace's array as plotly holds it: a sequence, or a typed array ``{dtype, bdata}``."""
    if isinstance(value, dict) and "bdata" in value:
        array = np.frombuffer(base64.b64decode(value["bdata"]), dtype=value["dtype"])
        return array.reshape(value["shape"]) if "shape" in value else array
    return value


def _plain_value(value: Any) -> Any:
    """What json cannot write itself: NumPy arrays and numbers as lists and floats."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"the viewer's figure holds a {type(value).__name__}, which JSON cannot")
