"""Type stubs of the Rust core. Call it through the package's functions, which coerce input."""

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
    "Invariants",
    "MAX_MOMENT_RATIO",
    "METHODS",
    "MethodInfo",
    "ModelResult",
    "RUN_STATUSES",
    "RigidBody",
    "RunColumns",
    "RunResult",
    "StepPlan",
    "SweepResult",
    "TRIANGLE_SLACK",
    "__version__",
    "_finalizing",
    "check_rtol",
    "damper_step",
    "deployment_step",
    "ellipj",
    "ellipk",
    "ellipsoid_mesh",
    "flip_period",
    "instruction_sets",
    "invariants",
    "method_info",
    "plan_batch",
    "rotate",
    "simulate",
    "simulate_batch",
    "simulate_damper",
    "simulate_dampers",
    "simulate_deployment",
    "simulate_deployments",
    "step_plan",
    "sweep",
]
__version__: str
METHODS: tuple[MethodInfo, ...]
DEFAULT_METHOD: str
DEFAULT_RTOL: float
DEFAULT_ATOL: float
DEFAULT_MAX_STEPS: int
MAX_MOMENT_RATIO: float
TRIANGLE_SLACK: float

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
class RunResult:
    @property
    def t(self) -> npt.NDArray[np.float64]: ...
    @property
    def omega(self) -> npt.NDArray[np.float64] | None: ...
    @property
    def q(self) -> npt.NDArray[np.float64] | None: ...
    @property
    def flip_times(self) -> npt.NDArray[np.float64]: ...
    @property
    def drift(self) -> tuple[float, float, float, float]: ...
    @property
    def nfev(self) -> int: ...
    @property
    def n_steps(self) -> int: ...
    @property
    def n_rejected(self) -> int: ...
    @property
    def dt(self) -> float: ...

@final
class StepPlan:
    @property
    def dt(self) -> float: ...
    @property
    def step(self) -> float: ...
    @property
    def rate_bound(self) -> float: ...
    @property
    def predicted_drift(self) -> float: ...

@final
class BatchPlan:
    @property
    def dt(self) -> float | None: ...
    @property
    def worst_row(self) -> int | None: ...
    @property
    def worst(self) -> StepPlan | None: ...

@final
class Invariants:
    @property
    def energy(self) -> npt.NDArray[np.float64]: ...
    @property
    def momentum_body(self) -> npt.NDArray[np.float64]: ...
    @property
    def momentum_world(self) -> npt.NDArray[np.float64]: ...
    @property
    def q_norm(self) -> npt.NDArray[np.float64]: ...

@final
class RunColumns:
    @property
    def drift(self) -> list[npt.NDArray[np.float64]]: ...
    @property
    def nfev(self) -> npt.NDArray[np.int64]: ...
    @property
    def n_steps(self) -> npt.NDArray[np.int64]: ...
    @property
    def n_rejected(self) -> npt.NDArray[np.int64]: ...
    @property
    def dt(self) -> npt.NDArray[np.float64]: ...

@final
class BatchResult:
    @property
    def t(self) -> npt.NDArray[np.float64]: ...
    @property
    def omega(self) -> npt.NDArray[np.float64] | None: ...
    @property
    def q(self) -> npt.NDArray[np.float64] | None: ...
    @property
    def flip_offsets(self) -> npt.NDArray[np.int64]: ...
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

@final
class ModelResult:
    @property
    def t(self) -> npt.NDArray[np.float64]: ...
    @property
    def omega(self) -> npt.NDArray[np.float64]: ...
    @property
    def q(self) -> npt.NDArray[np.float64]: ...
    @property
    def momentum_world(self) -> npt.NDArray[np.float64]: ...
    @property
    def momentum_body(self) -> npt.NDArray[np.float64]: ...
    @property
    def energy(self) -> npt.NDArray[np.float64]: ...
    @property
    def sigma(self) -> npt.NDArray[np.float64] | None: ...
    @property
    def flip_times(self) -> npt.NDArray[np.float64] | None: ...
    @property
    def drift(self) -> tuple[float, float, float, float]: ...
    @property
    def nfev(self) -> int: ...
    @property
    def n_steps(self) -> int: ...
    @property
    def n_rejected(self) -> int: ...
    @property
    def dt(self) -> float: ...

RUN_STATUSES: tuple[str, ...]

def _finalizing() -> None:
    """The `atexit` hook that keeps daemon threads' calls out of a finalising interpreter."""

@final
class RigidBody:
    def __new__(cls, inertia: tuple[float, float, float]) -> RigidBody: ...
    @staticmethod
    def from_box(a: float, b: float, c: float, mass: float = 1.0) -> RigidBody: ...
    @property
    def inertia(self) -> tuple[float, float, float]: ...
    @property
    def satisfies_triangle_inequality(self) -> bool: ...
    @property
    def intermediate_axis(self) -> int | None: ...
    def __reduce__(self) -> tuple[Any, tuple[tuple[float, float, float]]]: ...

def simulate(
    body: RigidBody,
    omega0: tuple[float, float, float],
    q0: tuple[float, float, float, float],
    t_end: float,
    frames: int,
    dt: float | None,
    method: str,
    max_steps: int,
    keep_frames: bool,
    keep_flips: bool,
    rtol: float = ...,
    atol: float = ...,
) -> RunResult: ...
def simulate_deployment(
    times: npt.NDArray[np.float64],
    tensors: npt.NDArray[np.float64],
    omega0: tuple[float, float, float],
    q0: tuple[float, float, float, float],
    t_end: float,
    frames: int,
    dt: float | None,
    method: str,
    max_steps: int,
    rtol: float = ...,
    atol: float = ...,
    flips: bool = False,
) -> ModelResult: ...
def simulate_deployments(
    times: list[list[float]],
    tensors: list[list[float]],
    omega0: list[tuple[float, float, float]],
    q0: list[tuple[float, float, float, float]],
    t_end: float,
    frames: int,
    dt: float | None,
    method: str,
    max_steps: int,
    rtol: float = ...,
    atol: float = ...,
    flips: bool = False,
    threads: int | None = None,
) -> list[ModelResult]: ...
def simulate_damper(
    inertia: tuple[float, float, float, float, float, float, float, float, float],
    sphere: float,
    damping: float,
    omega0: tuple[float, float, float],
    sigma0: tuple[float, float, float],
    q0: tuple[float, float, float, float],
    t_end: float,
    frames: int,
    dt: float | None,
    method: str,
    max_steps: int,
    rtol: float = ...,
    atol: float = ...,
    flips: bool = False,
) -> ModelResult: ...
def simulate_dampers(
    inertia: npt.NDArray[np.float64],
    sphere: npt.NDArray[np.float64],
    damping: npt.NDArray[np.float64],
    omega0: npt.NDArray[np.float64],
    sigma0: npt.NDArray[np.float64],
    q0: npt.NDArray[np.float64],
    t_end: float,
    frames: int,
    dt: float | None,
    method: str,
    max_steps: int,
    rtol: float = ...,
    atol: float = ...,
    flips: bool = False,
    threads: int | None = None,
) -> list[ModelResult]: ...
def deployment_step(
    times: list[list[float]],
    tensors: list[list[float]],
    omega0: list[tuple[float, float, float]],
    q0: list[tuple[float, float, float, float]],
    t_end: float,
    frames: int,
    dt: float | None,
    method: str,
    max_steps: int,
    rtol: float = ...,
    atol: float = ...,
) -> float | None: ...
def damper_step(
    inertia: npt.NDArray[np.float64],
    sphere: npt.NDArray[np.float64],
    damping: npt.NDArray[np.float64],
    omega0: npt.NDArray[np.float64],
    sigma0: npt.NDArray[np.float64],
    q0: npt.NDArray[np.float64],
    t_end: float,
    frames: int,
    dt: float | None,
    method: str,
    max_steps: int,
    rtol: float = ...,
    atol: float = ...,
) -> float | None: ...
def step_plan(
    body: RigidBody,
    omega0: tuple[float, float, float],
    t_end: float,
    frames: int,
    dt: float | None,
    method: str,
    rtol: float = ...,
    atol: float = ...,
) -> StepPlan: ...
def check_rtol(rtol: float) -> float: ...
@overload
def rotate(
    q: npt.NDArray[np.float64], points: npt.NDArray[np.float64], out: None = None
) -> npt.NDArray[np.float64]: ...
@overload
def rotate(
    q: npt.NDArray[np.float64], points: npt.NDArray[np.float64], out: npt.NDArray[np.float64]
) -> None: ...
def invariants(
    body: RigidBody, omega: npt.NDArray[np.float64], q: npt.NDArray[np.float64]
) -> Invariants: ...
def ellipsoid_mesh(
    semi_axes: tuple[float, float, float], n_around: int, n_along: int
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.uint32]]: ...
def flip_period(body: RigidBody, omega0: tuple[float, float, float]) -> float: ...
def ellipj(
    u: npt.NDArray[np.float64], m: float, m1: float
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
def ellipk(m: float, m1: float) -> float: ...
def simulate_batch(
    inertia: npt.NDArray[np.float64],
    omega0: npt.NDArray[np.float64],
    q0: npt.NDArray[np.float64],
    t_end: float,
    frames: int,
    dt: float | None,
    method: str,
    max_steps: int,
    keep_frames: bool,
    keep_flips: bool,
    rtol: float = ...,
    atol: float = ...,
    threads: int | None = None,
    isa: str | None = None,
) -> BatchResult: ...
def sweep(
    inertia: npt.NDArray[np.float64],
    omega0: npt.NDArray[np.float64],
    q0: npt.NDArray[np.float64],
    t_end: float,
    frames: int,
    dt: float | None,
    method: str,
    max_steps: int,
    rtol: float = ...,
    atol: float = ...,
    threads: int | None = None,
    isa: str | None = None,
) -> SweepResult: ...
def plan_batch(
    inertia: npt.NDArray[np.float64],
    omega0: npt.NDArray[np.float64],
    t_end: float,
    frames: int,
    dt: float | None,
    method: str,
    rtol: float = ...,
    atol: float = ...,
) -> BatchPlan: ...
def instruction_sets() -> list[str]: ...
