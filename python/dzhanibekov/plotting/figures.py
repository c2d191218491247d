"""The paper's figures, and more, with matplotlib.

Each function takes a computed scene (:func:`compute`; a :class:`~dzhanibekov.scene.Scene`
is computed on the fly) or a :class:`~dzhanibekov.Trajectory` (drawn as it is, with its
body's box and ellipsoid: :mod:`dzhanibekov.scenes.staging`), returns a
:class:`~matplotlib.figure.Figure` so that figures can be composed or restyled, and saves it when given a path. Single-panel figures also draw into
an existing 3-D or 2-D axes (`ax`). No pyplot state is touched: the figures are plain
``Figure`` objects, garbage-collected like any other.

>>> import dzhanibekov as dz
>>> fig = dz.plotting.path_figure(dz.SCENES["fig3a"])          # doctest: +SKIP
>>> fig.savefig("fig3a.png")                                    # doctest: +SKIP
"""

from __future__ import annotations

import math

import re
import textwrap
import warnings
from collections.abc import Callable, Mapping, Sequence
from functools import partial
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
from matplotlib.animation import FuncAnimation
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import LightSource, to_rgba
from matplotlib.figure import Figure
from mpl_toolkits.mplot3d import Axes3D  # type: ignore[import-untyped]
from mpl_toolkits.mplot3d.art3d import (  # type: ignore[import-untyped]
    Line3DCollection,
    Poly3DCollection,
)

from .._files import save_figure
from .._args import as_float, as_int
from ..body import InertiaWarning, as_body
from ..damper import axis_shares, flat_spin_time
from ..geometry import box_edges
from .. import _core
from ..scenes.parse import drawn_label
from ..scenes.plan import SceneResult, execute, make_plan, phase_frames
from ..scenes.scene import Scene
from ..scenes.staging import result_for
from ..lvlh import jacobi_values, lvlh_attitude
from ..orbit import GravityGradient, Wheel, dual_spin_threshold, pitch_libration_rate
from ..simulate import simulate
from ..system import System
from ..results import Trajectory

__all__ = [
    "compute",
    "phases_figure",
    "path_figure",
    "fig3_figure",
    "omega_figure",
    "invariants_figure",
    "polhode_figure",
    "animation",
    "shares_figure",
    "energy_figure",
    "lvlh_figure",
    "wheel_off_figure",
    "libration_period",
    "FIGURE_FUNCTIONS",
]

ISOMETRIC = (np.degrees(np.arctan(1 / np.sqrt(2))), -45.0)
"""Elevation and azimuth (degrees) of the isometric view; with the orthographic projection,
an axonometric picture as in the paper."""

AXES_ZOOM = 0.86
"""A 3-D axes' box within its panel: at 1 the z label and tick labels are clipped."""

COLORS = {
    "box": "#1f3b73",
    "faces": "#8fa6cf",
    "ellipsoid": "#f2a541",
    "signal": "#c0392b",
    "path": "#c0392b",
    "momentum": "#111111",
    "axes": ("#d62728", "#2ca02c", "#1f77b4"),
    "omega": ("#d62728", "#2ca02c", "#1f77b4"),
    "separatrix": "#c0392b",
    "polhode": "#9a9a9a",
}
DPI = 100
LIGHT = LightSource(azdeg=300, altdeg=40)
"""The light that shades a mesh's faces."""


Drawable = Scene | SceneResult | Trajectory
"""What the figures take: a scene, a computed scene, or a trajectory with its body."""


class Units(NamedTuple):
    """The units a scene's numbers are in, for axis labels; empty strings: any consistent
    set (the package assumes none, see the conventions)."""

    time: str = ""
    length: str = ""
    mass: str = ""

    def label(self, what: str, unit: str) -> str:
        """`what` with `unit` in parentheses, or "consistent units" when there is none."""
        return f"{what} ({unit})" if unit else f"{what} (consistent units)"

    @property
    def rate(self) -> str:
        """The unit of ω."""
        return f"rad/{self.time}" if self.time else ""


PRESET_UNITS = {"wing-nut": Units(time="s", length="mm", mass="g")}
"""The units of the bodies a scene names by `body.preset` (:meth:`~dzhanibekov.Body.wing_nut`:
millimetres and grams; its scene's times are seconds)."""


def units_of(scene: Scene) -> Units:
    """The units of `scene`'s numbers: its preset body's, else any consistent set."""
    spec = scene.body_spec
    if spec is not None and isinstance(spec.get("preset"), str):
        return PRESET_UNITS.get(spec["preset"], Units())
    return Units()


def compute(scene: Drawable, *, animation: bool = False) -> SceneResult:
    """The scene's computed data: its plan, executed (a result is returned as it is; a
    trajectory is staged as a scene and drawn as it is, `animation` asking for every frame's
    points)."""
    if isinstance(scene, SceneResult):
        return scene
    if isinstance(scene, Trajectory):
        return result_for(scene, animation=animation)
    if not isinstance(scene, Scene):
        raise TypeError(f"`scene` must be a Scene or a SceneResult (or a Trajectory), got "
                        f"{type(scene).__name__}")
    return execute(make_plan(scene))


def _need(result: SceneResult, what: str, *names: str) -> None:
    missing = [n for n in names if n not in result.world]
    if result.trajectory is None or missing:
        raise ValueError(
            f"scene {result.scene.name!r} was computed without what the {what} needs "
            f"({', '.join(missing) or 'frames'}); add it to the scene's `draw` table"
        )


def _figure_of(ax: Axes) -> Figure:
    fig = ax.get_figure()
    while fig is not None and not isinstance(fig, Figure):  # a SubFigure: its parent's
        fig = fig.get_figure()
    assert isinstance(fig, Figure), "the axes belongs to no figure"
    return fig


def _saved(fig: Figure, save: str | Path | None) -> Figure:
    save_figure(fig, save, dpi=DPI)  # all or nothing: the previous file kept on failure
    return fig


def _axes3d(fig: Figure, *args: Any) -> Axes3D:
    ax: Axes3D = fig.add_subplot(*args, projection="3d")
    ax.set_proj_type("ortho")
    ax.view_init(elev=ISOMETRIC[0], azim=ISOMETRIC[1])
    ax.set_box_aspect((1, 1, 1), zoom=AXES_ZOOM)  # room for the axis labels
    return ax


def _limits(ax: Axes3D, extent: float) -> None:
    for setter in (ax.set_xlim, ax.set_ylim, ax.set_zlim):
        setter(-extent, extent)


def extent(result: SceneResult) -> float:
    """Half the side of a cube that holds everything the scene draws in space."""
    sizes = [np.abs(w.points).max() for w in result.world.values() if w.points.size]
    sizes.append(math.hypot(*result.scene.signal_point))
    largest = float(max(sizes))
    return 1.08 * largest if largest > 0 else 1.0  # nothing drawn away from the centre


def _relative(values: np.ndarray, reference: float) -> np.ndarray:
    """``|values − reference|``, relative to the reference unless it is zero."""
    scale = abs(reference) if reference != 0 else 1.0
    drift: np.ndarray = np.abs(values - reference) / scale
    return drift


def draw_body(ax: Axes3D, result: SceneResult, frame: int, *, trail: bool = True) -> dict[str, Any]:
    """Draws the scene's objects at frame index `frame` into `ax`; returns the artists by name
    (the animation moves them)."""
    scene, d = result.scene, result.scene.draw
    artists: dict[str, Any] = {}
    if "ellipsoid" in result.world:
        assert result.mesh is not None
        verts = result.at("ellipsoid", frame)[result.mesh[1]]
        artists["ellipsoid"] = ax.add_collection3d(Poly3DCollection(
            verts, facecolor=COLORS["ellipsoid"], edgecolor="#8a5a12", linewidths=0.3,
            alpha=0.35, label="inertia ellipsoid"))
    if "box" in result.world:
        corners = result.at("box", frame)
        shape = scene.drawn_shape
        if shape is not None and shape.faces is not None:
            artists["faces"] = ax.add_collection3d(Poly3DCollection(
                corners[shape.faces], facecolors=COLORS["faces"], edgecolors=COLORS["faces"],
                linewidths=0.0,
                alpha=0.45, shade=True, lightsource=LIGHT))
        edges = shape.edges if shape is not None else box_edges()
        artists["box"] = ax.add_collection3d(Line3DCollection(
            corners[edges], colors=COLORS["box"], linewidths=1.4 if len(edges) < 60 else 0.8,
            label=drawn_label(scene.body, scene.body_spec)))
    if "body_axes" in result.world:
        tips = result.at("body_axes", frame)
        segments = np.stack([np.zeros_like(tips), tips], axis=1)
        artists["body_axes"] = ax.add_collection3d(Line3DCollection(
            segments, colors=COLORS["axes"], linewidths=1.0, label="body axes"))
    if d.momentum and result.trajectory is not None:
        tip = _unit(result.momentum_world) * extent(result)
        (artists["momentum"],) = ax.plot(*np.stack([-tip, tip]).T, color=COLORS["momentum"],
                                         lw=0.8, ls="--", label="L (angular momentum)")
    if "signal" in result.world and (d.path or d.signal_point):
        whole = len(result.world["signal"].frames) == scene.frames
        if d.path and whole and trail and result.trajectory is not None:
            times, path = result.dense_path
            now = times <= result.trajectory.t[frame]
            (artists["trail"],) = ax.plot(*path[now].T, color=COLORS["path"], lw=1.0,
                                          label="signal point's path")
            ax.plot(*path.T, color=COLORS["path"], lw=0.4, alpha=0.25)
        if d.signal_point:
            p = result.at("signal", frame)[0]
            (artists["mast"],) = ax.plot(*np.stack([np.zeros(3), p]).T, color=COLORS["signal"],
                                         lw=1.0)
            (artists["signal"],) = ax.plot(*p[:, None], "o", color=COLORS["signal"], ms=4,
                                           label="signal point")
    return artists


def _unit(v: np.ndarray) -> np.ndarray:
    """`v` over its length (scaled first, so that no square overflows); z for a zero `v`."""
    largest = float(np.abs(v).max())
    if not largest > 0:
        return np.array([0.0, 0.0, 1.0])
    w = v / largest
    unit: np.ndarray = w / np.linalg.norm(w)
    return unit


TRAIL_TURNS = 3.0
"""An animation's path fades over the last three turns of the body (at its rate then)…"""
TRAIL_SPAN = 0.25
"""… and over at most a quarter of the run: the path shows where the point has just been,
not a tangle of the whole run."""
TRAIL_SEGMENTS = 400
"""The most line segments a fading path is drawn with in one frame…"""
TRAIL_SHADES = 24
"""… in this many shades, from transparent (oldest) to opaque (now)."""


class Frames(NamedTuple):
    """The drawn body's points at an animation's frames."""

    times: np.ndarray
    """(N,) the frames' times."""
    rates: np.ndarray
    """(N,) ``|ω|`` at each frame (how far back the fading path reaches)."""
    points: Mapping[str, np.ndarray]
    """Point set name → (N, P, 3) world points (see :data:`~dzhanibekov.scenes.plan.POINT_SETS`)."""


def stored_frames(result: SceneResult, frames: np.ndarray | None = None) -> Frames:
    """The scene's own frames (indices `frames`, default all) as :class:`Frames`; the scene
    must have been computed for an animation (every point set rotated at every frame)."""
    traj = result.trajectory
    assert traj is not None, "an animation needs frames"
    index = np.arange(len(traj.t)) if frames is None else np.asarray(frames)
    points = {}
    for name, w in result.world.items():
        if len(w.frames) != len(traj.t):
            raise ValueError(f"scene {result.scene.name!r} was not computed for an animation "
                             f"(point set {name!r} is rotated at {len(w.frames)} of its "
                             f"{len(traj.t)} frames)")
        points[name] = w.points[index]
    rates = np.sqrt((traj.omega[index] ** 2).sum(axis=1))
    return Frames(traj.t[index], rates, points)


class BodyView:
    """The body drawn in one 3-D axes, its artists made once and moved from frame to frame:
    what an animation draws (:func:`animation`, :func:`dzhanibekov.plotting.movie.animate`).

    The box or the body's own shape (its faces shaded for the light as they turn), the
    inertia ellipsoid, the body axes, the signal point on its mast, the angular momentum and
    the signal point's path — fading over the last :data:`TRAIL_TURNS` turns of the body (at
    most :data:`TRAIL_SPAN` of the run), drawn from the run's smooth path
    (:attr:`~dzhanibekov.scenes.plan.SceneResult.dense_path`).

    Parameters
    ----------
    ax : Axes3D
    result : SceneResult
        The computed scene (its drawing flags, mesh, shape and smooth path).
    frames : Frames
        The points at each frame (:func:`stored_frames`, or resampled).
    """

    def __init__(self, ax: Axes3D, result: SceneResult, frames: Frames) -> None:
        self.ax, self.result, self.frames = ax, result, frames
        scene, d = result.scene, result.scene.draw
        pts = frames.points
        self.artists: dict[str, Any] = {}
        if "ellipsoid" in pts:
            assert result.mesh is not None
            self._quads = result.mesh[1]
            self.artists["ellipsoid"] = ax.add_collection3d(Poly3DCollection(
                pts["ellipsoid"][0][self._quads], facecolor=COLORS["ellipsoid"],
                edgecolor="#8a5a12", linewidths=0.3, alpha=0.35, label="inertia ellipsoid"))
        self._faces = None
        if "box" in pts:
            shape = scene.drawn_shape
            if shape is not None and shape.faces is not None:
                self._faces = shape.faces
                self._face_rgba = _rgba(COLORS["faces"], 0.45)
                self.artists["faces"] = ax.add_collection3d(Poly3DCollection(
                    pts["box"][0][shape.faces], linewidths=0.0))
            self._edges = shape.edges if shape is not None else box_edges()
            self.artists["box"] = ax.add_collection3d(Line3DCollection(
                pts["box"][0][self._edges], colors=COLORS["box"],
                linewidths=1.4 if len(self._edges) < 60 else 0.8,
                label=drawn_label(scene.body, scene.body_spec)))
        if "body_axes" in pts:
            self.artists["body_axes"] = ax.add_collection3d(Line3DCollection(
                self._axis_segments(0), colors=COLORS["axes"], linewidths=1.0,
                label="body axes"))
        if d.momentum and result.trajectory is not None:
            tip = _unit(result.momentum_world) * extent(result)
            (self.artists["momentum"],) = ax.plot(*np.stack([-tip, tip]).T,
                                                  color=COLORS["momentum"], lw=0.8, ls="--",
                                                  label="L (angular momentum)")
        self._path: tuple[np.ndarray, np.ndarray] | None = None
        if "signal" in pts and d.path and result.trajectory is not None:
            self._path = result.dense_path
            self._span = TRAIL_SPAN * float(frames.times[-1] - frames.times[0])
            here = frames.points["signal"][0][0]
            self.artists["trail"] = ax.add_collection3d(Line3DCollection(
                [np.stack([here, here])], linewidths=1.3, color=COLORS["path"],
                label="signal point's path"), autolim=False)
        if "signal" in pts and d.signal_point:
            (self.artists["mast"],) = ax.plot([0.0, 0.0], [0.0, 0.0], [0.0, 0.0],
                                              color=COLORS["signal"], lw=1.0)
            (self.artists["signal"],) = ax.plot([0.0], [0.0], [0.0], "o",
                                                color=COLORS["signal"], ms=4,
                                                label="signal point")
        self.show(0)

    def _axis_segments(self, k: int) -> np.ndarray:
        tips = self.frames.points["body_axes"][k]
        return np.stack([np.zeros_like(tips), tips], axis=1)

    def trail(self, k: int) -> np.ndarray:
        """The fading path's points at frame `k`, oldest first, shape (M, 3): the smooth path
        over the window that ends at the frame's time, then the signal point itself."""
        assert self._path is not None
        times, path = self._path
        t = float(self.frames.times[k])
        rate = float(self.frames.rates[k])
        window = min(self._span, TRAIL_TURNS * 2 * math.pi / rate) if rate > 0 else self._span
        i0 = int(np.searchsorted(times, t - window, side="left"))
        i1 = int(np.searchsorted(times, t, side="right"))
        stride = max(1, -(-(i1 - i0) // TRAIL_SEGMENTS))
        here = self.frames.points["signal"][k]
        kept: np.ndarray = np.concatenate([path[i0:i1:stride], here])
        return kept

    def show(self, k: int) -> list[Any]:
        """Moves every artist to frame index `k`; returns them."""
        pts = self.frames.points
        a = self.artists
        if "ellipsoid" in a:
            a["ellipsoid"].set_verts(pts["ellipsoid"][k][self._quads])
        if "box" in a:
            corners = pts["box"][k]
            if self._faces is not None:
                tri = corners[self._faces]
                a["faces"].set_verts(tri)
                a["faces"].set_facecolor(_shaded(self._face_rgba, tri))
            a["box"].set_segments(corners[self._edges])
        if "body_axes" in a:
            a["body_axes"].set_segments(self._axis_segments(k))
        if "trail" in a:
            line = self.trail(k)
            if len(line) < 2:
                line = np.concatenate([line, line])
            # a few polylines, each a shade lighter than the next: the path fades
            cuts = np.unique(np.linspace(0, len(line) - 1, TRAIL_SHADES + 1).round().astype(int))
            pieces = [line[i:j + 1] for i, j in zip(cuts[:-1], cuts[1:])]
            colors = np.tile(_rgba(COLORS["path"]), (len(pieces), 1))
            colors[:, 3] = np.linspace(0.0, 1.0, len(pieces) + 1)[1:]
            a["trail"].set_segments(pieces)
            a["trail"].set_color(colors)
        if "signal" in a:
            p = pts["signal"][k][0]
            a["mast"].set_data_3d(*np.stack([np.zeros(3), p]).T)
            a["signal"].set_data_3d([p[0]], [p[1]], [p[2]])
        return list(a.values())


def _rgba(color: Any, alpha: float | None = None) -> np.ndarray:
    """A colour as an (4,) RGBA array."""
    rgba: np.ndarray = np.array([*to_rgba(color, alpha)])
    return rgba


def _shaded(rgba: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """`rgba` shaded for :data:`LIGHT` on each of `triangles` (F, 3, 3) as they face it now
    (the shading of matplotlib's ``shade=True``, recomputed as the body turns)."""
    normals = np.cross(triangles[:, 0] - triangles[:, 1], triangles[:, 1] - triangles[:, 2])
    length = np.linalg.norm(normals, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        light = np.where(length > 0, (normals @ LIGHT.direction) / length, 0.0)
    colors = np.tile(rgba, (len(triangles), 1))
    colors[:, :3] *= (0.3 + 0.35 * (light + 1.0))[:, None]
    return colors


def phases_figure(scene: Drawable, *, columns: int = 4,
                  save: str | Path | None = None) -> Figure:
    """Fig. 2: the body (box, inertia ellipsoid, signal point …) at the scene's instants,
    axonometric, each with the signal point's path up to that instant.

    Parameters
    ----------
    scene : Scene or SceneResult
        A scene whose `draw.figures` has ``"phases"``.
    columns : int
        Panels per row.
    save : str or Path, optional
        Where to save the figure (format from the suffix).

    Returns
    -------
    Figure
        One 3-D axes per instant, titled with its time.
    """
    columns = as_int("columns", columns, minimum=1, maximum=1000)
    result = compute(scene)
    _need(result, "phases panel")

    frames = phase_frames(result.scene)
    rows = -(-len(frames) // columns)
    cols = min(columns, len(frames))
    fig = Figure(figsize=(2.4 * cols, 2.5 * rows + 0.5), layout="constrained")
    size = extent(result)
    for k, frame in enumerate(frames):
        ax = _axes3d(fig, rows, cols, k + 1)
        draw_body(ax, result, frame)
        _limits(ax, size)
        ax.set_axis_off()
        unit = units_of(result.scene).time
        ax.set_title(f"t = {result.trajectory.t[frame]:g}{f' {unit}' if unit else ''}"
                     if result.trajectory is not None else "", fontsize=9)
    fig.suptitle(_title(result), fontsize=10)
    handles, labels = _handles(fig.axes[:1])
    if handles:  # what each drawn thing is, once for every panel, below them
        fig.legend(handles, labels, loc="outside lower center", ncols=min(len(handles), 5),
                   fontsize=8, frameon=False)
    return _saved(fig, save)


def _handles(axes: Sequence[Axes]) -> tuple[list[Any], list[str]]:
    """The labelled artists of `axes`, each label once (a legend's handles and labels)."""
    handles, labels = [], []
    for ax in axes:
        for handle, label in zip(*ax.get_legend_handles_labels()):
            if label not in labels:
                handles.append(handle)
                labels.append(label)
    return handles, labels


def _headline(result: SceneResult) -> str | None:
    """What the scene's run did, for its title: for a damped body (a scene about
    reorientation) when the spin went flat; else how often it flipped (None if flips were not
    located)."""
    traj = result.trajectory
    if traj is not None and "damper" in traj.system.kinds:  # the run's own system's parts
        t_flat = flat_spin_time(traj)
        unit = units_of(result.scene).time
        if math.isfinite(t_flat):
            return f"flat spin from t ≈ {t_flat:.0f}" + (f" {unit}" if unit else "")
        return f"not yet flat by t = {result.scene.t_end:g}"
    return result.verdict


def _width(fig: Figure) -> int:
    """The characters of a 9-point title that fit across `fig`."""
    return int(12.5 * fig.get_figwidth())


def _title(result: SceneResult, width: int = 0) -> str:
    verdict = _headline(result)
    title = result.scene.title + (f" — {verdict}" if verdict else "")
    if not width or len(title) <= width:
        return title
    # a line for the scene, a line for the verdict: no phrase broken in the middle
    head = _wrap(result.scene.title, width)
    return f"{head} —\n{verdict}" if verdict else head


_GROUPED = re.compile(r"\([^()]*\)|\[[^\[\]]*\]")
"""A parenthesised or bracketed group, such as a tuple of moments: never broken."""


def _wrap(text: str, width: int) -> str:
    """`text` filled to `width`, breaking between words but never inside a group
    ``(1, 2, 3)`` or ``[…]`` (a tuple broken over two lines reads as two numbers)."""
    glue = "\u00a0"  # textwrap breaks at ASCII whitespace only
    kept = _GROUPED.sub(lambda m: m.group(0).replace(" ", glue), text)
    return textwrap.fill(kept, width, break_long_words=False).replace(glue, " ")


def path_figure(scene: Drawable, *, ax: Axes3D | None = None, legend: bool = True,
                save: str | Path | None = None) -> Figure:
    """Fig. 3: the signal point's path in space, in 3-D, with its start and end.

    The dashed circle is the equator of the sphere the point moves on, perpendicular to the
    angular momentum L (drawn when the scene draws ``momentum``): a flip takes the point from
    one hemisphere to the other.

    Parameters
    ----------
    scene : Scene or SceneResult
        A scene that draws the path (``"path"`` in `draw.figures`).
    ax : Axes3D, optional
        Draw into this axes instead of a new figure.
    legend : bool
        Say what each line is: below the axes in a new figure, in its corner in a given
        `ax`.
    save : str or Path, optional
        Where to save the figure.

    Returns
    -------
    Figure
        The axes are labelled in the scene's units where it has them (the wing nut's mm).
    """
    result = compute(scene)
    _need(result, "path figure", "signal")
    own = ax is None
    if ax is None:
        fig = Figure(figsize=(5.2, 5.2), layout="constrained")
        ax = _axes3d(fig, 1, 1, 1)
    fig = _figure_of(ax)
    _, path = result.dense_path  # smooth, from the run's interpolant
    ax.plot(*path.T, color=COLORS["path"], lw=0.9, label="signal point's path")
    ax.plot(*path[0], "o", color="#2e8b57", ms=5, label="start")
    ax.plot(*path[-1], "s", color="#333333", ms=4, label="end")
    size = extent(result)
    radius = math.hypot(*result.scene.signal_point)
    centre = 0.5 * (path.max(axis=0) + path.min(axis=0))
    spread = float(np.abs(path - centre).max())
    zoom = spread < 0.2 * radius  # a small cone about a stable axis: draw it, not a dot
    if zoom:
        cone = math.degrees(math.asin(min(1.0, spread * 2 / radius))) if radius > 0 else 0.0
        ax.set_title(f"zoomed: the point stays within ~{cone:.2g}° of its start",
                     fontsize=7, loc="left", y=-0.02)
    if result.scene.draw.momentum and zoom:
        ell = _unit(result.momentum_world)
        ax.plot(*np.stack([centre - ell * spread, centre + ell * spread]).T,
                color=COLORS["momentum"], lw=1.2, label="L (angular momentum)")
    elif result.scene.draw.momentum:
        ell = _unit(result.momentum_world)
        ax.plot(*np.stack([np.zeros(3), ell * size]).T, color=COLORS["momentum"], lw=1.2,
                label="L (angular momentum)")
        radius = math.hypot(*result.scene.signal_point)
        a = _unit(np.cross(ell, [1.0, 0.0, 0.0] if abs(ell[0]) < 0.9 else [0.0, 1.0, 0.0]))
        b = np.cross(ell, a)
        phi = np.linspace(0, 2 * np.pi, 97)
        circle = radius * (np.outer(np.cos(phi), a) + np.outer(np.sin(phi), b))
        ax.plot(*circle.T, color="#777777", lw=0.6, ls="--", label="equator ⊥ L")
    if zoom:
        half = 1.3 * spread if spread > 0 else 0.01 * radius or 1.0
        for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre):
            setter(c - half, c + half)
    else:
        _limits(ax, size)
    length = units_of(result.scene).length
    ax.set_xlabel(f"X ({length})" if length else "X")
    ax.set_ylabel(f"Y ({length})" if length else "Y")
    ax.set_zlabel(f"Z ({length})" if length else "Z")
    # wrapped to the panel's width: a second line of a 3-D axes' title is cut off at the top
    spec = ax.get_subplotspec()
    columns = spec.get_gridspec().ncols if spec is not None else 1
    # inside the panel's top margin: constrained layout does not make room above a 3-D box
    ax.set_title(_title(result, int(13 * fig.get_figwidth() / columns)), fontsize=9, y=0.93)
    if legend and own:  # below the 3-D box, where it covers none of it
        fig.legend(*_handles([ax]), loc="outside lower center", ncols=3, fontsize=7,
                   frameon=False)
    elif legend:
        ax.legend(loc="upper left", fontsize=7)
    return _saved(fig, save)


def fig3_figure(scenes: Sequence[Drawable], *, save: str | Path | None = None) -> Figure:
    """Fig. 3 a–c side by side: :func:`path_figure` of each scene in one row, with one legend
    below them."""
    fig = Figure(figsize=(4.6 * len(scenes), 4.8), layout="constrained")
    for k, scene in enumerate(scenes):
        path_figure(scene, ax=_axes3d(fig, 1, len(scenes), k + 1), legend=False)
    handles, labels = _handles(fig.axes)
    fig.legend(handles, labels, loc="outside lower center", ncols=len(handles), fontsize=8,
               frameon=False)
    return _saved(fig, save)


def _time_axes(scene: Drawable, ax: Axes | None, what: str, *,
               span: bool) -> tuple[SceneResult, Trajectory, Figure, Axes]:
    """The set-up of a figure against time: the scene's result and trajectory (checked to
    be there for `what`), and the axes to draw in (a new figure's if `ax` is None), with a
    deployment's span shaded if `span`."""
    result = compute(scene)
    _need(result, what)
    traj = result.trajectory
    assert traj is not None
    if ax is None:
        ax = Figure(figsize=(7.0, 3.4), layout="constrained").add_subplot()
    if span:
        _model_span(ax, result)
    return result, traj, _figure_of(ax), ax


def omega_figure(scene: Drawable, *, ax: Axes | None = None,
                 save: str | Path | None = None) -> Figure:
    """The body angular velocity ``u, v, w`` against time, each flip marked by a vertical line.

    Parameters
    ----------
    scene : Scene or SceneResult
    ax : Axes, optional
        Draw into this axes instead of a new figure.
    save : str or Path, optional

    Returns
    -------
    Figure
        One line per component (labels ``u``, ``v``, ``w``) and one vertical line per flip
        (the first labelled ``flip``).
    """
    result, traj, fig, ax = _time_axes(scene, ax, "ω(t) figure", span=False)
    for k, name in enumerate("uvw"):
        ax.plot(traj.t, traj.omega[:, k], color=COLORS["omega"][k], lw=1.1, label=name)
    for k, t in enumerate(traj.flip_times if traj.flip_times is not None else ()):
        ax.axvline(float(t), color="#555555", lw=0.8, ls=":", label="flip" if k == 0 else None)
    units = units_of(result.scene)
    ax.set_xlabel(units.label("t", units.time))
    ax.set_ylabel(f"ω ({units.rate}, body frame)" if units.rate
                  else "ω (rad per unit of time, body frame)")
    ax.set_xlim(0, traj.t[-1])
    ax.set_title(_title(result, _width(fig)), fontsize=9)
    # beside the axes, where it covers no curve
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0.0)
    return _saved(fig, save)


def invariants_figure(scene: Drawable, *, ax: Axes | None = None,
                      save: str | Path | None = None) -> Figure:
    """The drift of the invariants against time, log scale: relative energy and ``|L|``, the
    space-frame angular momentum vector (relative to ``|L|``), ``|q| − 1`` and, in the
    gravity gradient, the Jacobi integral (relative to its largest term). What the run's
    model keeps (``traj.drift.kept``) is drawn solid, its drift the integration's error;
    what the model changes by its own law (a deployment's work and a damper's loss on the
    energy, a torque's on the energy and angular momentum) dashed and named a change.

    Returns
    -------
    Figure
        A line per invariant, labelled; exact zeros (the first frame) are not drawn.
    """
    result = compute(scene)
    _need(result, "invariants figure")
    traj = result.trajectory
    assert traj is not None
    inv = traj.invariants()  # the run's own system's, as the run's drift measures them
    l_body = np.linalg.norm(inv["momentum_body"], axis=1)
    l0 = float(l_body[0])
    series = {
        "energy": ("energy  |E/E₀ − 1|", _relative(inv["energy"], float(inv["energy"][0]))),
        "momentum": ("|L|  ||L|/|L₀| − 1|", _relative(l_body, l0)),
        "momentum_world": ("L in space  |L − L₀|/|L₀|", np.linalg.norm(
            inv["momentum_world"] - inv["momentum_world"][0], axis=1) / (l0 if l0 > 0 else 1.0)),
    }
    if "jacobi" in traj.system.conserved:
        j = jacobi_values(traj)
        series["jacobi"] = ("Jacobi integral  |J − J₀|/max|J|", np.abs(j - j[0]) / max(
            float(np.abs(j).max()), np.finfo(float).tiny))
    series["q_norm"] = ("|q| − 1", np.abs(inv["q_norm"] - 1))
    if ax is None:
        fig = Figure(figsize=(7.0, 3.4), layout="constrained")
        ax = fig.add_subplot()
    fig = _figure_of(ax)
    kept = traj.drift.kept
    for name, (label, values) in series.items():
        change = name not in kept
        ax.plot(traj.t, np.where(values > 0, values, np.nan), lw=0.9,
                ls="--" if change else "-",
                label=f"{label} (changed by the model)" if change else label)
    ax.set_yscale("log")
    units = units_of(result.scene)
    ax.set_xlabel(units.label("t", units.time))
    ax.set_ylabel("drift (solid) or change (dashed), relative"
                  if any(name not in kept for name in series) else "drift (relative)")
    ax.set_xlim(0, traj.t[-1])
    step = f"dt = {traj.dt:g}" if traj.n_steps > 0 else "no steps"
    ax.set_title(f"{result.scene.title}: invariants' drift ({traj.method}, {step})",
                 fontsize=9)
    ax.legend(loc="lower right", fontsize=7, ncols=2)
    return _saved(fig, save)


def polhodes(inertia: Sequence[float] | np.ndarray, energy: float, levels: int = 4,
             points: int = 121) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Polhodes on the energy ellipsoid ``ω · I ω = 2E`` of a body, in the body frame.

    A polhode is where the energy ellipsoid meets the momentum sphere ``|I ω| = |L|``; with
    ``D = |L|² / 2E`` between the smallest and largest moment, it circles the axis of the
    largest moment when ``D`` exceeds the intermediate moment and the smallest when not. At
    ``D = I_mid`` it is the separatrix: two ellipses crossing at ±(the intermediate axis),
    in the planes ``I_max (I_max − I_mid) ω_max² = I_min (I_mid − I_min) ω_min²``.

    Parameters
    ----------
    inertia : (3,) principal moments
        Positive, within a ratio of 1e150 (as for :class:`~dzhanibekov.Body`).
    energy : float
        Kinetic energy ``E = ½ ω · I ω``, non-negative (zero: every curve is the origin).
    levels : int
        Polhodes drawn about each stable axis (each a pair, one about each end), at least 0.
    points : int
        Points per curve, at least 2.

    Returns
    -------
    family : list of ndarray (points, 3)
        The polhodes about the stable axes, closed curves.
    separatrix : list of ndarray (points, 3)
        Its two ellipses; empty for a symmetric top, which has none.

    Raises
    ------
    TypeError, ValueError
        An argument of the wrong kind or out of range, naming it; an energy whose rates
        float64 cannot hold.
    """
    with warnings.catch_warnings():  # a drawing of moments no body has is still a drawing
        warnings.simplefilter("ignore", InertiaWarning)
        given = np.array(as_body(inertia, "inertia").inertia)
    energy = as_float("energy", energy)
    if energy < 0:
        raise ValueError(f"`energy` must be non-negative, got {energy!r}")
    levels = as_int("levels", levels, minimum=0, maximum=10_000)
    points = as_int("points", points, minimum=2, maximum=10_000_000)
    # In units where the largest moment is 1 and ω·Iω = 1: ω = scale · (the curves below), so
    # that moments and energies of any size neither overflow nor underflow on the way.
    top = float(given.max())
    moments = given / top
    order = np.argsort(moments)
    lo, mid, hi = order
    i_lo, i_mid, i_hi = moments[order]
    two_e = 1.0
    phi = np.linspace(0.0, 2.0 * np.pi, points)
    family: list[np.ndarray] = []
    close = partial(np.isclose, rtol=1e-9, atol=0.0)
    symmetric = close(i_lo, i_mid) or close(i_mid, i_hi)
    for a, (b, c) in ((hi, (lo, mid)), (lo, (mid, hi))):
        i_a = moments[a]
        if close(i_a, i_mid):
            continue
        for f in np.linspace(0.0, 1.0, levels + 2)[1:-1]:
            d = i_mid + f * (i_a - i_mid)  # between the intermediate moment and I_a
            # I_b (I_b − I_a) ω_b² + I_c (I_c − I_a) ω_c² = 2E (D − I_a): an ellipse in (ω_b, ω_c)
            wb = np.sqrt(two_e * (d - i_a) / (moments[b] * (moments[b] - i_a))) * np.cos(phi)
            wc = np.sqrt(two_e * (d - i_a) / (moments[c] * (moments[c] - i_a))) * np.sin(phi)
            wa = np.sqrt(np.maximum(two_e - moments[b] * wb**2 - moments[c] * wc**2, 0.0) / i_a)
            for sign in (1.0, -1.0):
                curve = np.zeros((points, 3))
                curve[:, a], curve[:, b], curve[:, c] = sign * wa, wb, wc
                family.append(curve)
    separatrix: list[np.ndarray] = []
    if not symmetric:
        k = np.sqrt(i_lo * (i_mid - i_lo) / (i_hi * (i_hi - i_mid)))
        for sign in (1.0, -1.0):
            d = np.zeros(3)
            d[lo], d[hi] = 1.0, sign * k
            d *= np.sqrt(two_e / (i_lo + i_hi * k**2))
            e_mid = np.zeros(3)
            e_mid[mid] = np.sqrt(two_e / i_mid)
            separatrix.append(np.outer(np.cos(phi), e_mid) + np.outer(np.sin(phi), d))
    with np.errstate(over="ignore", invalid="ignore"):  # checked just below
        scale = np.sqrt(2.0) * np.sqrt(energy) / np.sqrt(top)
        family, separatrix = [scale * c for c in family], [scale * c for c in separatrix]
    if not all(np.isfinite(c).all() for c in family + separatrix):
        raise ValueError(f"`energy` = {energy!r} with moments {tuple(given)} gives rates beyond "
                         "float64")
    return family, separatrix


def polhode_figure(scene: Drawable, *, ax: Axes3D | None = None,
                   save: str | Path | None = None) -> Figure:
    """The polhode: ω's path on the energy ellipsoid, where it meets the momentum sphere.

    Drawn in body-frame ω-space: the run's energy ellipsoid (wireframe), polhodes about the
    stable axes (grey), the separatrix through the intermediate axis (red) and ω(t) of the
    run (blue). A flip is a pass of ω near the separatrix, from one side of the intermediate
    axis's end to the other.

    Returns
    -------
    Figure
        Lines labelled ``ω(t)`` and ``separatrix`` (two ellipses; none for a symmetric top).
    """
    result = compute(scene)
    _need(result, "polhode")
    traj = result.trajectory
    assert traj is not None
    if not traj.system.is_free:
        raise ValueError(f"the polhode is the free body's: the run's system "
                         f"{traj.system.kinds} changes its energy ellipsoid (draw its "
                         "'shares' and 'energy' figures instead)")
    # in units of the largest moment and the largest initial rate, scaled back for drawing
    moments = np.array(traj.body.inertia)
    unit_moments = moments / moments.max()
    big = float(np.abs(traj.omega[0]).max()) or 1.0
    omega, _ = traj.body.to_principal(traj.omega, traj.q)
    w0 = omega[0] / big
    energy = 0.5 * float(w0 @ (unit_moments * w0))
    if ax is None:
        fig = Figure(figsize=(5.2, 5.2), layout="constrained")
        ax = _axes3d(fig, 1, 1, 1)
    fig = _figure_of(ax)
    semi = big * np.sqrt(2 * energy / unit_moments)
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 25), np.linspace(0, np.pi, 13))
    ax.plot_wireframe(semi[0] * np.sin(v) * np.cos(u), semi[1] * np.sin(v) * np.sin(u),
                      semi[2] * np.cos(v), color="#dddddd", lw=0.3)
    family, separatrix = polhodes(unit_moments, energy)
    family, separatrix = [big * c for c in family], [big * c for c in separatrix]
    for curve in family:
        ax.plot(*curve.T, color=COLORS["polhode"], lw=0.6)
    for k, curve in enumerate(separatrix):
        ax.plot(*curve.T, color=COLORS["separatrix"], lw=1.2,
                label="separatrix" if k == 0 else None)
    ax.plot(*omega.T, color="#1f4fd6", lw=2.0, label="ω(t)")
    ax.plot(*omega[0], "o", color="#2e8b57", ms=5, label="ω(0)")
    if len(separatrix) == 2:
        ax.view_init(*view_of_planes(separatrix))
    _limits(ax, 1.1 * float(semi.max()) if semi.max() > 0 else 1.0)
    principal = "" if traj.body.is_principal else " (principal axes)"
    rate = units_of(result.scene).rate
    unit = f" ({rate})" if rate else ""
    ax.set_xlabel(("ω₁" if principal else "u") + unit)
    ax.set_ylabel(("ω₂" if principal else "v") + unit)
    ax.set_zlabel(("ω₃" if principal else "w") + unit)
    ax.set_title(f"{result.scene.title}: polhode{principal}", fontsize=9)
    ax.legend(loc="upper left", fontsize=7)
    return _saved(fig, save)


def view_of_planes(curves: Sequence[np.ndarray]) -> tuple[float, float]:
    """Elevation and azimuth (degrees) from which each planar curve is seen as open as can
    be (none edge-on): the direction furthest from every curve's plane, the isometric view's
    nearest among the best."""
    normals = []
    for c in curves:
        centred = c - c.mean(axis=0)
        normals.append(np.linalg.svd(centred, full_matrices=False)[2][-1])
    elev, azim = np.meshgrid(np.radians(np.arange(5.0, 61.0, 1.0)),
                             np.radians(np.arange(-180.0, 180.0, 1.0)), indexing="ij")
    view = np.stack([np.cos(elev) * np.cos(azim), np.cos(elev) * np.sin(azim),
                     np.sin(elev)], axis=-1)
    # |sin| of the angle between the view and each plane; both at least 0.45 (27°) and the
    # two seen differently (not from their common bisector), nearest the isometric view
    openness = np.min([np.abs(view @ n) for n in normals], axis=0)
    apart = np.abs(np.abs(view @ normals[0]) - np.abs(view @ normals[-1]))
    near = -np.hypot(elev - np.radians(ISOMETRIC[0]),
                     (azim - np.radians(ISOMETRIC[1]) + np.pi) % (2 * np.pi) - np.pi)
    good = (openness >= 0.45) & (apart >= 0.2)
    score = np.where(good, near, openness - 10.0)
    k = np.unravel_index(int(np.argmax(score)), score.shape)
    return float(np.degrees(elev[k])), float(np.degrees(azim[k]))


def _model_span(ax: Axes, result: SceneResult) -> None:
    """Shades a deployment's span (first to last knot) on a time axis."""
    d = result.scene.deployment
    if d is not None and len(d.times) > 1:
        ax.axvspan(float(d.times[0]), float(d.times[-1]), color="#dddddd", lw=0,
                   label="deployment")


def shares_figure(scene: Scene | SceneResult, *, ax: Axes | None = None,
                  save: str | Path | None = None) -> Figure:
    """The share ``L_k / |L|`` of the total angular momentum on each body axis, over time.

    A spin about an axis shows as ±1 on it; a flip as a swing from +1 to −1; a flat spin
    as the major axis taking the whole of ``|L|``. For a damped body the time to flat spin
    (:func:`~dzhanibekov.flat_spin_time`) is marked.

    Parameters
    ----------
    scene : Scene or SceneResult
    ax : Axes, optional
    save : str or Path, optional

    Returns
    -------
    Figure
    """
    result, traj, fig, ax = _time_axes(scene, ax, "shares figure", span=True)
    shares = axis_shares(traj)
    for k, name in enumerate("xyz"):
        ax.plot(traj.t, shares[:, k], color=COLORS["omega"][k], lw=1.1, label=f"L{name} / |L|")
    if "damper" in traj.system.kinds:
        inertia = np.asarray(traj.body.inertia)
        major = inertia >= inertia.max() * (1 - 1e-12)
        principal = shares @ traj.body.principal_axes  # on the principal axes
        ax.plot(traj.t, np.sqrt((principal[:, major] ** 2).sum(axis=1)), color="#111111",
                lw=1.0, ls="--", label="on the major axes")
        t_flat = flat_spin_time(traj)
        if math.isfinite(t_flat):
            ax.axvline(t_flat, color="#555555", lw=0.8, ls=":", label=f"flat, t ≈ {t_flat:.0f}")
    units = units_of(result.scene)
    ax.set_xlabel(units.label("t", units.time))
    ax.set_ylabel("share of |L| (body axes)")
    ax.set_xlim(0, traj.t[-1])
    ax.set_ylim(-1.05, 1.05)
    ax.set_title(_title(result, _width(fig)), fontsize=9)
    # beside the axes: the shares reach ±1, and a legend inside would cover them
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0.0)
    return _saved(fig, save)


def energy_figure(scene: Scene | SceneResult, *, ax: Axes | None = None,
                  save: str | Path | None = None) -> Figure:
    """The total kinetic energy over time, relative to its start, beside the drift of the
    total angular momentum in space (which every model keeps).

    Parameters
    ----------
    scene : Scene or SceneResult
    ax : Axes, optional
    save : str or Path, optional

    Returns
    -------
    Figure
    """
    result, traj, fig, ax = _time_axes(scene, ax, "energy figure", span=True)
    energy = traj.energy
    e0 = float(energy[0])
    scale = e0 if e0 > 0 else 1.0
    ax.plot(traj.t, energy / scale, color="#1f3b73", lw=1.3,
            label="E(t) / E(0)" if e0 > 0 else "E(t)")
    units = units_of(result.scene)
    ax.set_xlabel(units.label("t", units.time))
    ax.set_ylabel("total kinetic energy / E(0)" if e0 > 0 else "total kinetic energy")
    ax.set_xlim(0, traj.t[-1])
    l_world = traj.momentum_world
    l0 = float(np.linalg.norm(l_world[0]))
    drift = np.linalg.norm(l_world - l_world[0], axis=1).max() / (l0 if l0 > 0 else 1.0)
    ax.set_title(_title(result, _width(fig))
                 + f"\n|L_world(t) − L_world(0)| / |L| ≤ {drift:.1e}", fontsize=9)
    ax.legend(loc="best", fontsize=8)
    return _saved(fig, save)


def libration_period(t: np.ndarray, angle: np.ndarray) -> float:
    """The mean period of an oscillation sampled at times `t`: the mean spacing of its
    downward zero crossings (each located linearly between frames); NaN with fewer than two."""
    k = np.nonzero((angle[:-1] > 0) & (angle[1:] <= 0))[0]
    if len(k) < 2:
        return math.nan
    crossings = t[k] + angle[k] / (angle[k] - angle[k + 1]) * (t[k + 1] - t[k])
    return float(np.mean(np.diff(crossings)))


def lvlh_figure(scene: Drawable, *, ax: Axes | None = None,
                save: str | Path | None = None) -> Figure:
    """The attitude relative to the orbiting frame (LVLH) against time: roll, pitch and yaw
    (the rotation vector's components along along-track, minus the orbit normal and nadir,
    in degrees) of the run in the gravity gradient, with the small-angle closed form of the
    pitch, ``θ₀ cos(ω_p t)`` (:func:`~dzhanibekov.pitch_libration_rate`), dashed; the title
    gives the pitch period measured from the run's zero crossings beside ``2π/ω_p``.

    Parameters
    ----------
    scene : Scene or SceneResult
        A run of a system with a :class:`~dzhanibekov.GravityGradient`.
    ax : Axes, optional
    save : str or Path, optional

    Returns
    -------
    Figure

    Raises
    ------
    ValueError
        The scene has no orbit.
    """
    result, traj, fig, ax = _time_axes(scene, ax, "LVLH figure", span=False)
    rates = [t.orbit_rate for t in traj.system.torques if isinstance(t, GravityGradient)]
    if not rates:
        raise ValueError("`scene` must run in an orbit ([orbit] in its file, a "
                         "dz.GravityGradient in its system) for the LVLH figure")
    n = rates[0]
    rel = lvlh_attitude(traj, n)
    rel = rel * np.where(rel[:, :1] < 0, -1.0, 1.0)  # the short way round
    half = np.arctan2(np.linalg.norm(rel[:, 1:], axis=1), rel[:, 0])
    scale = np.where(half > 1e-300, 2.0 * half / np.maximum(np.sin(half), 1e-300), 2.0)
    angles = np.degrees(rel[:, 1:] * scale[:, None])
    for k, (name, colour) in enumerate(zip(("roll", "pitch", "yaw"), COLORS["omega"])):
        ax.plot(traj.t, angles[:, k], color=colour, lw=1.1, label=name)
    units = units_of(result.scene)
    title = _title(result, _width(fig))
    inertia = traj.system.body.inertia if hasattr(traj.system.body, "inertia") else None
    if inertia is not None and inertia[0] > inertia[2]:
        w_p = pitch_libration_rate(inertia, n)
        theta0 = angles[0, 1]
        ax.plot(traj.t, theta0 * np.cos(w_p * traj.t), color="0.2", lw=0.9, ls="--",
                label="θ₀ cos(ω_p t), ω_p = n √(3 (I_x − I_z) / I_y)")
        measured = libration_period(traj.t, angles[:, 1])
        closed = 2.0 * math.pi / w_p
        title += (f"\npitch period: {measured:.5g} from the run, 2π/ω_p = {closed:.5g} "
                  f"(closed form; {measured / closed - 1:+.1e})")
    ax.set_xlabel(units.label("t", units.time))
    ax.set_ylabel("angle from LVLH (degrees)")
    ax.set_xlim(0, traj.t[-1])
    ax.set_title(title, fontsize=9)
    ax.legend(loc="upper right", fontsize=7)
    return _saved(fig, save)


def wheel_off_figure(scene: Drawable, *, ax: Axes | None = None,
                     save: str | Path | None = None) -> Figure:
    """The angle of the spin axis in space from its start, for the scene's run with its wheel
    and for the same run with the wheel off (its momentum 0): the body that the wheel holds
    steady flips without it. The spin axis is the body axis of the largest initial rate;
    the title gives the closed-form threshold (:func:`~dzhanibekov.dual_spin_threshold`). For
    a wheel that follows a schedule (a spin-up) the span of its knots is shaded and the
    threshold is that of the last frame's momentum and spin rate.

    Parameters
    ----------
    scene : Scene or SceneResult
        A run of a system with a :class:`~dzhanibekov.Wheel`.
    ax : Axes, optional
    save : str or Path, optional

    Returns
    -------
    Figure

    Raises
    ------
    ValueError
        The scene's system has no wheel.
    """
    result, traj, fig, ax = _time_axes(scene, ax, "wheel-off figure", span=False)
    system = traj.system
    if not any(isinstance(p, Wheel) for p in system.parts):
        raise ValueError("`scene` must run a system with a wheel ([wheel] in its file) for the "
                         "wheel-off figure")
    off = System(system.body, parts=[Wheel(p.axis, 0.0) if isinstance(p, Wheel) else p
                                     for p in system.parts], torques=system.torques)
    s = result.scene
    other = simulate(off, s.omega0, s.q0, t_end=s.t_end, frames=s.frames, dt=s.dt,
                     method=s.method, rtol=s.rtol, atol=s.atol, flips=True)
    assert isinstance(other, Trajectory)
    k = int(np.argmax(np.abs(traj.omega[0])))
    e = np.zeros(3)
    e[k] = 1.0
    wheels = [p for p in system.parts if isinstance(p, Wheel)]
    knots = [t for p in wheels if isinstance(p.momentum, tuple) for t in p.momentum[0]]
    labels = {True: "wheel spun up" if knots else "wheel on", False: "wheel off (h = 0)"}
    if knots:
        ax.axvspan(min(knots), max(knots), color="#f4d03f", alpha=0.3, lw=0,
                   label="the wheel spins up")
    for run, on, colour in ((traj, True, "#1f3b73"), (other, False, "#c0392b")):
        axis = _core.rotate(np.ascontiguousarray(run.q), e.reshape(1, 3)).reshape(-1, 3)
        tilt = np.degrees(np.arctan2(np.linalg.norm(np.cross(axis, axis[0]), axis=1),
                                     axis @ axis[0]))
        flips = run.flip_times
        count = "" if flips is None else f": {len(flips)} flip{'s' if len(flips) != 1 else ''}"
        ax.plot(run.t, tilt, color=colour, lw=1.2, label=labels[on] + count)
    units = units_of(s)
    name = "xyz"[k]
    title = f"{s.title}: the spin axis {name} in space, with the wheel and without"
    body = system.body
    if hasattr(body, "inertia") and all(p.axis == tuple(e) for p in wheels):
        at = -1 if knots else 0
        rate = float(traj.omega[at, k])
        low, high = dual_spin_threshold(body.inertia, k, rate)
        h = sum(p.momentum_at(float(traj.t[at])) for p in wheels)
        where = f"at t = {traj.t[at]:g} (Ω = {rate:.3g})" if knots else ""
        title += (f"\nh = {h:g} {where}; the closed form: unstable for h in "
                  f"({low:.4g}, {high:.4g})").replace("  ", " ")
    ax.set_xlabel(units.label("t", units.time))
    ax.set_ylabel("angle from its start (degrees)")
    ax.set_ylim(-5, 185)
    ax.set_xlim(0, traj.t[-1])
    ax.set_title(title, fontsize=9)
    ax.legend(loc="center right", fontsize=8)
    return _saved(fig, save)


FIGURE_FUNCTIONS: dict[str, Callable[..., Figure]] = {
    "phases": phases_figure,
    "path": path_figure,
    "omega": omega_figure,
    "invariants": invariants_figure,
    "polhode": polhode_figure,
    "shares": shares_figure,
    "energy": energy_figure,
    "lvlh": lvlh_figure,
    "wheel_off": wheel_off_figure,
}
"""The figure function of each name a scene's `draw.figures` may hold."""


def animation(scene: Drawable, *, size: int = 480, fps: float = 20.0, dpi: float = 100.0,
              frames: int | None = None) -> FuncAnimation:
    """The flipping body as a matplotlib animation, for a notebook or a file.

    ``HTML(anim.to_jshtml())`` shows it in Jupyter; ``anim.save("flip.gif")`` writes it
    (``dzhanibekov paper`` writes its GIF and MP4 from it). No pyplot state is touched.

    Parameters
    ----------
    scene : Scene, SceneResult or Trajectory
        A scene with ``draw.animation = true`` (its plan rotates every drawn point for every
        frame in one call to the core), or a trajectory (drawn with its body's box,
        ellipsoid and signal point).
    size : int
        Width and height in pixels.
    fps : float
        Frames per second (the interval between frames is ``1000 / fps`` ms).
    dpi : float
        Dots per inch of the figure (``size / dpi`` inches a side).
    frames : int, optional
        Show this many of the run's frames, evenly spread (default: every frame).

    Returns
    -------
    matplotlib.animation.FuncAnimation
        Over a plain :class:`~matplotlib.figure.Figure` with an Agg canvas.

    Raises
    ------
    ValueError
        A scene not computed for an animation, or a size, rate or frame count out of range.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), frames=41)
    >>> anim = dz.plotting.animation(traj, size=200, fps=10)
    >>> html = anim.to_jshtml()          # in Jupyter: IPython.display.HTML(html)
    >>> html.count("<img") >= 1 and anim._save_count       # doctest: +SKIP
    """
    size = as_int("size", size, minimum=16, maximum=8192)
    fps = as_float("fps", fps, positive=True)
    dpi = as_float("dpi", dpi, positive=True)
    result = compute(scene, animation=True)
    if not result.scene.draw.animation or result.trajectory is None:
        raise ValueError(f"scene {result.scene.name!r} does not ask for an animation; set "
                         "`draw.animation = true` in its scene file")
    n = result.scene.frames
    count = n if frames is None else as_int("frames", frames, minimum=1, maximum=n)
    indices = np.unique(np.round(np.linspace(0, n - 1, count)).astype(int))
    fig, draw = animation_figure(result, stored_frames(result, indices), size=size, dpi=dpi)
    position = {int(frame): k for k, frame in enumerate(indices)}
    # its frames are the run's frame indices, as it has always said
    return FuncAnimation(fig, lambda frame: draw(position[int(frame)]),
                         frames=[int(i) for i in indices], init_func=lambda: [],
                         interval=1000.0 / fps, blit=False, cache_frame_data=False)


def animation_figure(result: SceneResult, frames: Frames, *, size: int, dpi: float = 100.0
                     ) -> tuple[Figure, Callable[[int], list[Any]]]:
    """The figure of an animation (an Agg canvas, `size` pixels a side) with the body at
    `frames` (:class:`BodyView`) and a clock, and the function that moves everything to frame
    index ``k`` (returning the artists it moved); draw the canvas to render it."""
    fig = Figure(figsize=(size / dpi, size / dpi), dpi=dpi)
    FigureCanvasAgg(fig)
    fig.subplots_adjust(0, 0, 1, 0.93)
    ax = _axes3d(fig, 1, 1, 1)
    ax.set_axis_off()
    _limits(ax, extent(result))
    fig.suptitle(_title(result, max(20, int(size / 5.5))), fontsize=8)
    clock = fig.text(0.02, 0.02, "", fontsize=8)
    view = BodyView(ax, result, frames)
    unit = units_of(result.scene).time

    def draw(k: int) -> list[Any]:
        moved = view.show(int(k))
        clock.set_text(f"t = {frames.times[k]:.1f}{f' {unit}' if unit else ''}")
        return moved + [clock]

    return fig, draw
