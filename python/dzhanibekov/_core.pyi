"""Type stubs of the Rust core. Call it through the package's functions, which coerce input."""

from collections.abc import Callable
from typing import Any, final, overload

import numpy as np
import numpy.typing as npt

__all__ = [
    "BatchPlan",
    "BatchResult",
    "DEFAULT_ATOL",
    "DEFAULT_MAX_STEPS",
    "DEFAULT_METHOD",
    "DEFAULT_RTOL",
    "Deployment",
    "EARTH_MOMENT",
    "EARTH_MU",
    "ENERGY_GROWTH_TOL",
    "FLAT_SHARE",
    "MAX_MOMENT_RATIO",
    "METHODS",
    "MODELS",
    "ModelInfo",
    "NEAR_SYMMETRY",
    "MethodInfo",
    "Part",
    "RUN_STATUSES",
    "RigidBody",
    "Run",
    "RunColumns",
    "RunOptions",
    "StepPlan",
    "SYMMETRY_TOLERANCE",
    "SweepResult",
    "System",
    "TRIANGLE_SLACK",
    "__version__",
    "_finalizing",
    "ellipj",
    "ellipk",
    "ellipsoid_mesh",
    "flip_period",
    "instruction_sets",
    "method_info",
    "model_info",
    "observe",
    "part_rates",
    "plan",
    "rotate",
    "simulate",
    "simulate_batch",
    "sweep",
]
__version__: str
METHODS: tuple[MethodInfo, ...]
MODELS: tuple[ModelInfo, ...]
DEFAULT_METHOD: str
DEFAULT_RTOL: float
DEFAULT_ATOL: float
DEFAULT_MAX_STEPS: int
ENERGY_GROWTH_TOL: float
FLAT_SHARE: float
MAX_MOMENT_RATIO: float
TRIANGLE_SLACK: float
SYMMETRY_TOLERANCE: float
NEAR_SYMMETRY: float
EARTH_MOMENT: float
EARTH_MU: float
RUN_STATUSES: tuple[str, ...]

_Rows3 = list[list[float]]

def _finalizing() -> None:
    """The `atexit` hook that keeps daemon threads' calls out of a finalising interpreter."""

@final
class RigidBody:
    def __new__(cls, inertia: tuple[float, float, float]) -> RigidBody: ...
    @staticmethod
    def from_tensor(tensor: _Rows3) -> RigidBody: ...
    @staticmethod
    def from_box(a: float, b: float, c: float, mass: float = 1.0) -> RigidBody: ...
    @property
    def inertia(self) -> tuple[float, float, float]: ...
    @property
    def tensor(self) -> _Rows3: ...
    @property
    def principal_axes(self) -> _Rows3: ...
    @property
    def is_principal(self) -> bool: ...
    @property
    def satisfies_triangle_inequality(self) -> bool: ...
    @property
    def intermediate_axis(self) -> int | None: ...
    @property
    def asymmetry(self) -> float: ...
    def __reduce__(self) -> tuple[Any, tuple[_Rows3]]: ...

@final
class Deployment:
    def __new__(
        cls, times: npt.NDArray[np.float64], tensors: npt.NDArray[np.float64]
    ) -> Deployment: ...
    @property
    def times(self) -> npt.NDArray[np.float64]: ...
    @property
    def tensors(self) -> npt.NDArray[np.float64]: ...

@final
class Part:
    def __new__(cls, kind: str, fields: dict[str, Any]) -> Part: ...
    @property
    def kind(self) -> str: ...
    @property
    def width(self) -> int: ...

@final
class System:
    def __new__(
        cls, body: RigidBody | Deployment, parts: list[Part] = ..., mass: float | None = None
    ) -> System: ...
    @property
    def kinds(self) -> tuple[str, ...]: ...
    @property
    def conserved(self) -> tuple[str, ...]: ...
    @property
    def parts(self) -> list[tuple[str, int]]: ...
    def tensor_at(self, t: float) -> _Rows3: ...

@final
class RunOptions:
    def __new__(
        cls,
        t_end: float,
        frames: int,
        dt: float | None = None,
        method: str | None = None,
        rtol: float | None = None,
        atol: float | None = None,
        max_steps: int | None = None,
        flips: bool = True,
        threads: int | None = None,
    ) -> RunOptions: ...
    @property
    def t_end(self) -> float: ...
    @property
    def frames(self) -> int: ...
    @property
    def dt(self) -> float | None: ...
    @property
    def method(self) -> str: ...
    @property
    def rtol(self) -> float: ...
    @property
    def atol(self) -> float: ...
    @property
    def max_steps(self) -> int: ...
    @property
    def flips(self) -> bool: ...
    @property
    def threads(self) -> int | None: ...
    def with_dt(self, dt: float | None) -> RunOptions: ...

@final
class MethodInfo:
    @property
    def name(self) -> str: ...
    @property
    def order(self) -> int | None: ...
    @property
    def adaptive(self) -> bool: ...
    @property
    def keeps(self) -> tuple[str, ...]: ...
    @property
    def rhs_per_step(self) -> int: ...
    @property
    def batch(self) -> bool: ...
    @property
    def models(self) -> tuple[str, ...]: ...
    @property
    def imaginary_limit(self) -> float | None: ...
    @property
    def real_limit(self) -> float | None: ...
    @property
    def about(self) -> str: ...
    def __reduce__(self) -> tuple[Any, tuple[str]]: ...

def method_info(name: str) -> MethodInfo: ...

@final
class ModelInfo:
    @property
    def name(self) -> str: ...
    @property
    def about(self) -> str: ...
    @property
    def law(self) -> bool: ...
    @property
    def params(self) -> list[tuple[str, str, bool, str, list[str]]]: ...
    @property
    def state(self) -> list[tuple[str, int, bool, str]]: ...
    @property
    def keeps(self) -> list[str]: ...
    @property
    def defines(self) -> list[str]: ...
    @property
    def energy(self) -> str: ...
    @property
    def external(self) -> bool: ...
    @property
    def unique(self) -> bool: ...
    @property
    def traits(self) -> list[str]: ...
    @property
    def methods(self) -> list[str]: ...
    def __reduce__(self) -> tuple[Any, tuple[str]]: ...

def model_info(name: str) -> ModelInfo: ...

@final
class StepPlan:
    @property
    def dt(self) -> float | None: ...
    @property
    def step(self) -> float: ...
    @property
    def rate_bound(self) -> float: ...
    @property
    def predicted_drift(self) -> float: ...
    @property
    def stiffness(self) -> float: ...
    @property
    def predicted_error(self) -> float: ...
    @property
    def out_of_reach(self) -> bool: ...
    @property
    def reached_by(self) -> str | None: ...

@final
class BatchPlan:
    @property
    def dt(self) -> float | None: ...
    @property
    def worst_row(self) -> int | None: ...
    @property
    def worst(self) -> StepPlan | None: ...
    @property
    def stiffest_row(self) -> int | None: ...
    @property
    def stiffest(self) -> StepPlan | None: ...

_DriftTuple = tuple[float, float, float, float, float | None, list[str]]

@final
class RunColumns:
    @property
    def drift(self) -> list[npt.NDArray[np.float64]]: ...
    @property
    def kept(self) -> list[str]: ...
    @property
    def nfev(self) -> npt.NDArray[np.int64]: ...
    @property
    def n_steps(self) -> npt.NDArray[np.int64]: ...
    @property
    def n_rejected(self) -> npt.NDArray[np.int64]: ...
    @property
    def dt(self) -> npt.NDArray[np.float64]: ...

@final
class Run:
    @property
    def t(self) -> npt.NDArray[np.float64]: ...
    @property
    def omega(self) -> npt.NDArray[np.float64]: ...
    @property
    def q(self) -> npt.NDArray[np.float64]: ...
    @property
    def parts(self) -> npt.NDArray[np.float64]: ...
    @property
    def flip_times(self) -> npt.NDArray[np.float64] | None: ...
    @property
    def flat_time(self) -> float | None: ...
    @property
    def drift(
        self,
    ) -> tuple[float, float, float, float, float | None, float | None]: ...
    @property
    def kept(self) -> list[str]: ...
    @property
    def dt(self) -> float: ...
    @property
    def n_steps(self) -> int: ...
    @property
    def nfev(self) -> int: ...
    @property
    def n_rejected(self) -> int: ...

@final
class BatchResult:
    @property
    def t(self) -> npt.NDArray[np.float64]: ...
    @property
    def omega(self) -> npt.NDArray[np.float64] | None: ...
    @property
    def q(self) -> npt.NDArray[np.float64] | None: ...
    @property
    def parts(self) -> npt.NDArray[np.float64] | None: ...
    @property
    def end_omega(self) -> npt.NDArray[np.float64]: ...
    @property
    def end_q(self) -> npt.NDArray[np.float64]: ...
    @property
    def end_parts(self) -> npt.NDArray[np.float64]: ...
    @property
    def flip_offsets(self) -> npt.NDArray[np.int64]: ...
    @property
    def flat_time(self) -> npt.NDArray[np.float64]: ...
    @property
    def flip_times(self) -> npt.NDArray[np.float64]: ...
    @property
    def runs(self) -> RunColumns: ...

@final
class SweepResult:
    @property
    def flips(self) -> npt.NDArray[np.int64]: ...
    @property
    def status(self) -> npt.NDArray[np.uint8]: ...
    @property
    def first_flip(self) -> npt.NDArray[np.float64]: ...
    @property
    def period(self) -> npt.NDArray[np.float64]: ...
    @property
    def exact_period(self) -> npt.NDArray[np.float64]: ...
    @property
    def tilt(self) -> npt.NDArray[np.float64]: ...
    @property
    def runs(self) -> RunColumns: ...

def plan(
    systems: list[System],
    omega0: npt.NDArray[np.float64],
    q0: npt.NDArray[np.float64],
    options: RunOptions,
    inertia: npt.NDArray[np.float64] | None = None,
) -> BatchPlan: ...
def simulate(
    system: System,
    omega0: npt.NDArray[np.float64],
    q0: npt.NDArray[np.float64],
    options: RunOptions,
    keep_frames: bool = True,
    warn: Callable[[StepPlan], object] | None = None,
    progress: Callable[[float], object] | None = None,
) -> Run: ...
def simulate_batch(
    systems: list[System],
    omega0: npt.NDArray[np.float64],
    q0: npt.NDArray[np.float64],
    options: RunOptions,
    keep_frames: bool,
    isa: str | None = None,
    inertia: npt.NDArray[np.float64] | None = None,
    first_row: int = 0,
) -> BatchResult: ...
def sweep(
    systems: list[System],
    omega0: npt.NDArray[np.float64],
    q0: npt.NDArray[np.float64],
    options: RunOptions,
    isa: str | None = None,
    inertia: npt.NDArray[np.float64] | None = None,
) -> SweepResult: ...
def observe(
    system: System,
    t: npt.NDArray[np.float64],
    omega: npt.NDArray[np.float64],
    q: npt.NDArray[np.float64],
    parts: npt.NDArray[np.float64],
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
def part_rates(
    system: System,
    t: npt.NDArray[np.float64],
    omega: npt.NDArray[np.float64],
    q: npt.NDArray[np.float64],
    parts: npt.NDArray[np.float64],
) -> npt.NDArray[np.float64]: ...
@overload
def rotate(
    q: npt.NDArray[np.float64], points: npt.NDArray[np.float64], out: None = None
) -> npt.NDArray[np.float64]: ...
@overload
def rotate(
    q: npt.NDArray[np.float64], points: npt.NDArray[np.float64], out: npt.NDArray[np.float64]
) -> None: ...
def ellipsoid_mesh(
    semi_axes: tuple[float, float, float], n_around: int, n_along: int
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.uint32]]: ...
def flip_period(body: RigidBody, omega0: tuple[float, float, float]) -> float: ...
def ellipj(
    u: npt.NDArray[np.float64], m: float, m1: float
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
def ellipk(m: float, m1: float) -> float: ...
def instruction_sets() -> list[str]: ...
