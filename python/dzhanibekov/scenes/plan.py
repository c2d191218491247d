"""What a scene needs computed, decided before anything runs: the computation plan.

A scene names what it draws and asks; :func:`make_plan` turns that into the work: whether
frames are kept, whether flips are located, which meshes are built and which body points
are rotated at which frames. :func:`execute` does exactly that work and nothing else:

- no frames are stored when the scene asks only for flip times (:func:`summarize`);
- no ellipsoid mesh is built or rotated for a scene that does not draw one;
- the signal point alone is rotated when only its path is drawn;
- the phases panel rotates its objects at its few instants only; an animation rotates all
  its points for all frames in one call to the core.
"""

from __future__ import annotations

import math

from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np

from ..dense import attitudes_at, turn_grid
from ..geometry import ellipsoid_mesh, ellipsoid_semi_axes
from ..geometry import box_vertices
from .scene import Scene
from ..simulate import rotate
from ..summary import Summary
from ..results import Drift, Trajectory

__all__ = ["Rotation", "Plan", "WorldPoints", "SceneResult", "make_plan", "execute"]

PATH_TURN = np.radians(1.5)
"""The largest turn of the body between two points of a drawn path (a smooth curve)."""

POINT_SETS = ("box", "ellipsoid", "body_axes", "signal")
"""Body point sets a scene may rotate: the body's outline (the box's 8 corners, or the
points of its own shape), the ellipsoid mesh's vertices,
the tips of the body axes and the signal point."""


@dataclass(frozen=True)
class Rotation:
    """One call to the core's `rotate`: these point sets (concatenated) at these frames."""

    frames: tuple[int, ...] | None
    """Frame indices; None for every frame."""
    point_sets: tuple[str, ...]


@dataclass(frozen=True)
class Plan:
    """The work a scene needs; see the module's docs."""

    scene: Scene
    keep_frames: bool
    """Store ω and q at every frame (any figure or the animation needs them)."""
    keep_flips: bool
    """Locate the flips (asked, or marked on the ω(t) figure)."""
    invariants: bool
    """Compute the invariants at every frame (the drift figure, the momentum vector, the
    polhode)."""
    meshes: tuple[str, ...]
    """Meshes built: ``("ellipsoid",)`` or none."""
    rotations: tuple[Rotation, ...]
    """The calls to `rotate`, in order; each point set appears in at most one."""

    @property
    def rotated(self) -> tuple[str, ...]:
        """Every point set rotated."""
        return tuple(n for r in self.rotations for n in r.point_sets)


def phase_frames(scene: Scene) -> tuple[int, ...]:
    """The frames nearest the phases panel's instants."""
    last = scene.frames - 1
    return tuple(int(round(t / scene.t_end * last)) for t in scene.phase_times)


def make_plan(scene: Scene) -> Plan:
    """The work `scene` needs, decided from what it draws and asks (nothing runs here)."""
    if not isinstance(scene, Scene):
        raise TypeError(f"`scene` must be a Scene, got {type(scene).__name__}")
    d = scene.draw
    views = "phases" in d.figures or d.animation  # pictures of the body in 3-D
    keep_frames = bool(d.figures) or d.animation
    objects = tuple(
        name
        for name, drawn in (
            ("box", d.box),
            ("ellipsoid", d.ellipsoid),
            ("body_axes", d.body_axes),
            ("signal", d.signal_point),
        )
        if drawn and views
    )
    path = "path" in d.figures or (d.path and views)
    rotations: list[Rotation] = []
    if d.animation:
        sets = objects + (("signal",) if path and "signal" not in objects else ())
        if sets:
            rotations.append(Rotation(None, sets))
    else:
        # the path rotates the signal point at every frame; the panel takes it from there
        at_instants = tuple(n for n in objects if not (n == "signal" and path))
        if "phases" in d.figures and at_instants:
            rotations.append(Rotation(phase_frames(scene), at_instants))
        if path:
            rotations.append(Rotation(None, ("signal",)))
    return Plan(
        scene=scene,
        keep_frames=keep_frames,
        keep_flips=scene.flips or "omega" in d.figures,
        invariants="invariants" in d.figures or "polhode" in d.figures
        or (d.momentum and keep_frames),
        meshes=("ellipsoid",) if "ellipsoid" in objects else (),
        rotations=tuple(rotations),
    )


class WorldPoints(NamedTuple):
    """A point set in space: `points[k]` is the set at frame `frames[k]`."""

    frames: np.ndarray
    """(N,) frame indices."""
    points: np.ndarray
    """(N, P, 3) world-frame points."""


def body_points(scene: Scene, name: str, mesh: tuple[np.ndarray, np.ndarray] | None) -> np.ndarray:
    """The body-frame points of set `name`, shape (P, 3)."""
    if name == "box":
        shape = scene.drawn_shape
        if shape is None:
            return box_vertices(*scene.drawn_box)  # raises, naming what is missing
        return shape.vertices
    if name == "ellipsoid":
        assert mesh is not None, "the plan builds the mesh before rotating it"
        return mesh[0]
    if name == "signal":
        return np.array([scene.signal_point])
    if name == "body_axes":
        return np.eye(3) * axis_length(scene)
    raise ValueError(f"no point set {name!r}; the sets are {POINT_SETS}")


def axis_length(scene: Scene) -> float:
    """Length of the body axes drawn: a little beyond the largest object."""
    sizes = [math.hypot(*scene.signal_point)]
    shape = scene.drawn_shape
    if scene.draw.box and shape is not None:
        sizes.append(shape.radius)
    if scene.draw.ellipsoid:
        sizes.append(float(ellipsoid_semi_axes(scene.body, scene.ellipsoid.convention).max()))
    return 1.15 * max(sizes)


@dataclass(frozen=True, eq=False)
class SceneResult:
    """A scene's computed data: what its plan asked for and nothing else."""

    scene: Scene
    plan: Plan
    trajectory: Trajectory | None
    """The frames, or None when the plan keeps none."""
    summary: Summary | None
    """The run without frames, when the plan keeps none."""
    mesh: tuple[np.ndarray, np.ndarray] | None
    """The ellipsoid's ``(vertices, quads)`` in the body frame, if drawn."""
    world: Mapping[str, WorldPoints]
    """Rotated point sets by name."""

    @property
    def flip_times(self) -> np.ndarray | None:
        """Flip times, or None if the plan did not locate flips."""
        if self.trajectory is not None:
            return self.trajectory.flip_times
        assert self.summary is not None
        return self.summary.flip_times

    @property
    def drift(self) -> Drift:
        """The invariants' largest drift over the frame times."""
        run = self.trajectory if self.trajectory is not None else self.summary
        assert run is not None
        return run.drift

    @property
    def verdict(self) -> str | None:
        """How often the body flipped in ``[0, t_end]``, or None if flips were not located."""
        times = self.flip_times
        if times is None:
            return None
        n, t_end = len(times), self.scene.t_end
        return f"no flip in [0, {t_end:g}]" if n == 0 else \
            f"{n} flip{'s' if n > 1 else ''} in [0, {t_end:g}]"

    def at(self, name: str, frame: int) -> np.ndarray:
        """Point set `name` in space at frame index `frame`, shape (P, 3)."""
        w = self.world[name]
        k = np.flatnonzero(w.frames == frame)
        if not len(k):
            raise ValueError(f"point set {name!r} was not rotated at frame {frame}")
        points: np.ndarray = w.points[k[0]]
        return points

    @property
    def path(self) -> np.ndarray:
        """The signal point's path in space at every frame, shape (frames, 3)."""
        return self.world["signal"].points[:, 0, :]

    @cached_property
    def dense_path(self) -> tuple[np.ndarray, np.ndarray]:
        """The signal point's path drawn smooth: times (N,) and points (N, 3) with the body
        turning at most `PATH_TURN` between points, from the run's interpolant
        (:mod:`dzhanibekov.dense`), whatever the number of stored frames."""
        traj = self.trajectory
        assert traj is not None, "a path needs frames"
        times = turn_grid(traj.t, traj.omega, PATH_TURN)
        q, _ = attitudes_at(traj.t, traj.omega, traj.q, times)
        return times, rotate(q, np.array(self.scene.signal_point))

    @property
    def momentum_world(self) -> np.ndarray:
        """The angular momentum in space at the start (it is conserved), shape (3,)."""
        assert self.trajectory is not None
        momentum: np.ndarray = self.trajectory.invariants()["momentum_world"][0]
        return momentum


def execute(plan: Plan, trajectory: Trajectory | None = None) -> SceneResult:
    """Does the work of `plan`: one run, the meshes it names, one `rotate` per rotation.

    A `trajectory` of the plan's scene, computed elsewhere, is used instead of the run."""
    if not isinstance(plan, Plan):
        raise TypeError(f"`plan` must be a Plan (from make_plan), got {type(plan).__name__}")
    scene = plan.scene
    traj, summary = None, None
    if trajectory is not None and len(trajectory.t) != scene.frames:
        raise ValueError(f"`trajectory` has {len(trajectory.t)} frames, the scene "
                         f"{scene.frames}")
    if plan.keep_frames:
        traj = trajectory if trajectory is not None else scene.run(flips=plan.keep_flips)
        if plan.invariants:
            traj.invariants()
    else:
        summary = scene.summarize()
    mesh = None
    if "ellipsoid" in plan.meshes:
        semi_axes = ellipsoid_semi_axes(scene.body, scene.ellipsoid.convention)
        mesh = ellipsoid_mesh(semi_axes, *scene.ellipsoid.mesh)
        if not scene.body.is_principal:  # built in principal axes, drawn in the user's
            mesh = (mesh[0] @ scene.body.principal_axes.T, mesh[1])
    world: dict[str, WorldPoints] = {}
    for rotation in plan.rotations:
        assert traj is not None, "rotations need frames"
        sets = [body_points(scene, name, mesh) for name in rotation.point_sets]
        frames = np.arange(scene.frames) if rotation.frames is None else np.array(rotation.frames)
        q = traj.q if rotation.frames is None else traj.q[frames]
        out = rotate(q, np.concatenate(sets))
        start = 0
        for name, pts in zip(rotation.point_sets, sets):
            world[name] = WorldPoints(frames, out[:, start : start + len(pts)])
            start += len(pts)
    return SceneResult(scene, plan, traj, summary, mesh, world)
