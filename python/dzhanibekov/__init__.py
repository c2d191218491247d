"""Free rotation of rigid bodies in weightlessness: the Dzhanibekov effect.

A Rust core integrates Euler's equations with the body-frame quaternion law and rotates
point arrays without trigonometry; this package is the thin Python side.

>>> import dzhanibekov as dz
>>> traj = dz.simulate(dz.Body.box(20, 10, 15), omega0=(0.01, 0.01, 1.0), t_end=10.0)
>>> world = dz.rotate(traj.q, dz.box_vertices())   # (frames, 8, 3)

Submodules that import matplotlib or plotly (``dz.plotting``, ``dz.maps`` — that is
``dz.plotting.maps`` —, ``dz.viewer``) are imported on first use, so ``import dzhanibekov``
stays light.
"""

import importlib
from typing import Any

from . import io
from ._core import __version__
from .accuracy import MAX_PREDICTED_DRIFT, StepSizeWarning
from .body import NEAR_SYMMETRY, PAPER_INERTIA, SYMMETRY_TOLERANCE, Body, InertiaWarning, MeshError
from .damper import (FLAT_SHARE, Damper, StiffDamperWarning, axis_shares, damper_rate,
                     flat_spin_estimate, flat_spin_time)
from .deployment import Deployment
from .dispersion import DamperDispersion, DeploymentDispersion, InertiaDispersion, PartDispersion
from .system import System
from .parts import Hinge, Slosh, SpringMassDamper
from .control import (BDot, Controller, Gyro, MagneticField, Magnetometer, MomentumDumping,
                      QuaternionFeedback, ResidualDipole, StarTracker, circular_orbit_rate,
                      detumble_gain)
from .igrf import earth_rotation_angle, igrf_field
from .pointing import detumbled_at, part_state, pointing_angle, saturation
from .torques import CallableTorque, TabulatedTorque
from .orbit import ConstantTorque, GravityGradient, Wheel, pitch_libration_rate, dual_spin_threshold
from .ensemble import Batch, BatchDrift, DeploymentSweep, Sweep, grid, sweep
from .errors import DivergedError, DzhanibekovError, TooLargeError
from .flips import flip_period
from .io import ReadError, load, save
from .geometry import BOX_SIZE, SIGNAL_POINT, box_edges, box_vertices, ellipsoid_mesh, ellipsoid_semi_axes
from .results import Drift, Trajectory
from .lvlh import lvlh_angles, lvlh_attitude, lvlh_frame, lvlh_start, nadir_angles
from . import scenes
from .scenes import PAPER_SCENES, SCENES, Scene, SceneError, load_scene
from .methods import METHODS, MethodInfo
from .models import MODELS, ModelInfo
from .montecarlo import MonteCarlo, StudyError, monte_carlo
from .options import RunKeywords, RunOptions
from .simulate import rotate, simulate
from .stability import (DualSpinMap, GravityGradientMap, dual_spin_map, gravity_gradient_map,
                        gravity_gradient_moments, gravity_gradient_region)
from .summary import Summary, summarize

__all__ = [
    "__version__",
    "Body",
    "InertiaWarning",
    "SYMMETRY_TOLERANCE",
    "NEAR_SYMMETRY",
    "MeshError",
    "Deployment",
    "System",
    "Damper",
    "SpringMassDamper",
    "Hinge",
    "Slosh",
    "Wheel",
    "GravityGradient",
    "ConstantTorque",
    "TabulatedTorque",
    "CallableTorque",
    "MagneticField",
    "Magnetometer",
    "Gyro",
    "StarTracker",
    "ResidualDipole",
    "BDot",
    "MomentumDumping",
    "QuaternionFeedback",
    "Controller",
    "circular_orbit_rate",
    "earth_rotation_angle",
    "igrf_field",
    "detumble_gain",
    "pointing_angle",
    "detumbled_at",
    "part_state",
    "saturation",
    "lvlh_frame",
    "lvlh_attitude",
    "lvlh_start",
    "lvlh_angles",
    "nadir_angles",
    "pitch_libration_rate",
    "dual_spin_threshold",
    "dual_spin_map",
    "DualSpinMap",
    "gravity_gradient_map",
    "GravityGradientMap",
    "gravity_gradient_region",
    "gravity_gradient_moments",
    "StiffDamperWarning",
    "damper_rate",
    "FLAT_SHARE",
    "axis_shares",
    "flat_spin_time",
    "flat_spin_estimate",
    "DzhanibekovError",
    "DivergedError",
    "TooLargeError",
    "Trajectory",
    "Drift",
    "simulate", "RunOptions", "RunKeywords",
    "rotate",
    "flip_period",
    "METHODS",
    "MethodInfo",
    "MODELS",
    "ModelInfo",
    "StepSizeWarning",
    "MAX_PREDICTED_DRIFT",
    "BOX_SIZE",
    "SIGNAL_POINT",
    "box_vertices",
    "box_edges",
    "PAPER_INERTIA",
    "summarize",
    "Summary",
    "Scene",
    "SceneError",
    "SCENES",
    "PAPER_SCENES",
    "load_scene",
    "ellipsoid_mesh",
    "ellipsoid_semi_axes",
    "Batch",
    "BatchDrift",
    "sweep",
    "Sweep",
    "DeploymentSweep",
    "grid",
    "save",
    "load",
    "ReadError",
    "io",
    "monte_carlo",
    "MonteCarlo",
    "StudyError",
    "InertiaDispersion",
    "DeploymentDispersion",
    "DamperDispersion",
    "PartDispersion",
]

_LAZY = {"plotting": ".plotting", "maps": ".plotting.maps", "viewer": ".viewer"}
"""Submodules imported on first access (they import matplotlib or plotly)."""


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return importlib.import_module(_LAZY[name], __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
