"""A trajectory computed elsewhere, staged as a scene so that every figure can draw it.

``dz.plotting.path_figure(traj)`` (and every other figure, the animation and the viewer)
takes a :class:`~dzhanibekov.Trajectory` as well as a scene: the trajectory is drawn as it
is, never run again, with its own body (its shape: a wing nut, a composite, a mesh; or the
uniform box of its moments), its inertia ellipsoid (radii of gyration) and a signal point on
the body's z axis just outside it.
"""

from __future__ import annotations

import numpy as np

from ..body import Body
from ..deployment import Deployment
from ..results import Trajectory
from .plan import SceneResult, execute, make_plan
from .scene import Draw, Scene, SceneError

__all__ = ["scene_for", "result_for", "FIGURES_OF_A_TRAJECTORY", "FIGURES_OF_A_SYSTEM"]

FIGURES_OF_A_TRAJECTORY = ("phases", "path", "omega", "invariants", "polhode")
FIGURES_OF_A_SYSTEM = ("phases", "path", "omega", "shares", "energy")
"""A system with parts or a schedule: its energy ellipsoid changes, so no polhode."""
DEFAULT_DT = 1e-3
"""The scene's `dt` when the run took no steps (``method="exact"``): never used to run."""


def scene_for(traj: Trajectory, *, animation: bool = False) -> Scene:
    """The scene that draws `traj`: its body, start, span, frames and method, with the box,
    the ellipsoid, the signal point and its path, and the angular momentum drawn."""
    if not isinstance(traj, Trajectory):
        raise TypeError(f"`traj` must be a Trajectory, got {type(traj).__name__}")
    system = traj.system
    body = system.body
    deployment = body if isinstance(body, Deployment) else None
    solid = body if isinstance(body, Body) else Body._restored(
        system.tensor_at(0.0), None, np.zeros(3))
    # the moments along the body's axes: a body given in principal axes keeps its order
    inertia = tuple(float(i) for i in solid.inertia)
    probe = Scene(name="trajectory", title="probe", inertia=inertia,  # type: ignore[arg-type]
                  omega0=(0.0, 0.0, 0.0), t_end=1.0, frames=2, given=system)
    if solid.shape is not None:
        half, box = solid.shape.radius, True
    else:
        try:
            half = max(probe.drawn_box) / 2
            box = True
        except SceneError:  # moments no uniform box has: draw no box
            half = float(np.sqrt(max(inertia))) * 2
            box = False
    omega0 = tuple(float(w) for w in traj.omega[0])
    q0 = tuple(float(x) for x in traj.q[0])
    scene = Scene(
        name="trajectory",
        title=f"{traj.method}, ω0 = ({', '.join(f'{w:.3g}' for w in omega0)})",
        inertia=inertia,  # type: ignore[arg-type]
        omega0=omega0,  # type: ignore[arg-type]
        q0=q0,  # type: ignore[arg-type]
        t_end=float(traj.t[-1]),
        frames=len(traj.t),
        dt=traj.dt if traj.dt > 0 else DEFAULT_DT,
        method=traj.method,
        signal_point=(0.0, 0.0, 1.3 * half),
        flips=traj.flip_times is not None,
        deployment=deployment,
        given=system,
        draw=Draw(box=box, ellipsoid=True, signal_point=True, path=True, momentum=True,
                  figures=FIGURES_OF_A_TRAJECTORY if system.is_free else
                  FIGURES_OF_A_SYSTEM, animation=animation),
    )
    return scene


def result_for(traj: Trajectory, *, animation: bool = False) -> SceneResult:
    """`traj` drawn as :func:`scene_for` stages it: the scene's plan executed on `traj`
    itself (nothing is run again)."""
    return execute(make_plan(scene_for(traj, animation=animation)), trajectory=traj)
