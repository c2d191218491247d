"""The table of public callables for the hostile-input tests: for each, valid (but extreme)
arguments, hostile ones per argument, and the check a result must pass.

Adding a public function to the tests is one `Entry` in `ENTRIES`: the callable, a strategy of
valid keyword arguments, a hostile strategy for each argument, and a check of the result
(shapes, finiteness and the physics it promises). `test_hostile.py` does the rest, and fails
on any name of `dz.__all__` that is neither in the table nor in `NOT_CALLED`.
"""

from __future__ import annotations

import datetime
import math
import tempfile
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import dzhanibekov as dz
from dzhanibekov.plotting import figures as plotting
from dzhanibekov.accuracy import ADAPTIVE_METHODS, MAX_PREDICTED_DRIFT
from dzhanibekov.scenes.scene import CONVENTIONS, FIGURES, MAX_DRAWN_SIZE
from hostile import (
    JUNK,
    LARGEST,
    TINY,
    as_number_types,
    directions,
    hostile_array,
    hostile_int,
    hostile_name,
    hostile_quaternion,
    hostile_real,
    hostile_vector3,
    inertias,
    layouts,
    log_uniform,
    positive_floats,
    quaternions,
    real_arrays,
    scaled,
    valid_int,
    valid_positive,
)

EPS = np.finfo(float).eps


@dataclass(frozen=True, repr=False)
class Entry:
    """One public callable under hostile input."""

    call: Callable[..., Any]
    valid: st.SearchStrategy[dict[str, Any]]
    """Keyword arguments the callable documents as allowed."""
    hostile: Mapping[str, st.SearchStrategy[Any]]
    """For each argument, values it must refuse."""
    check: Callable[[dict[str, Any], Any, list[warnings.WarningMessage]], None]
    """Asserts what a successful call returned (and the warnings it gave)."""
    covers: tuple[Any, ...] = ()
    """The public objects this entry exercises (for the coverage test)."""
    examples: int = 300
    """A third of this many draws have valid arguments (the maps and figures, which compute and
    draw, take fewer); every entry gets 300 hostile draws besides."""
    warns: tuple[type[Warning], ...] = ()
    """Warnings the call may give (others fail the test)."""
    aliases: Mapping[str, tuple[str, ...]] = field(default_factory=dict)
    """Other names an error message may use for an argument (a scene file's keys)."""
    named_by_value: tuple[str, ...] = ()
    """Arguments that a message names by quoting their value (a file's path)."""
    min_success: float = 0.1
    """The least fraction of all-valid draws that must return a result: checks that the
    valid strategy reaches the physics, not just the errors."""

    def __repr__(self) -> str:
        return f"Entry({getattr(self.call, '__qualname__', self.call)!r})"


# -- physics, independently of the package -----------------------------------------------------

def rate_bound(inertia: np.ndarray, omega: np.ndarray) -> float:
    """Ω = √(2E / I_min), scaled so that nothing overflows (inf if Ω itself does)."""
    big = float(np.max(np.abs(omega)))
    if big == 0.0:
        return 0.0
    with np.errstate(over="ignore"):
        return big * math.sqrt(float(np.sum(inertia / inertia.min() * (omega / big) ** 2)))


def euler_rate_factor(inertia: np.ndarray) -> float:
    """The largest coefficient |I_j − I_k| / I_i of Euler's equations, at least 1: the motion's
    frequencies are at most this times Ω (1 for every body that meets the triangle inequality,
    up to 9 for moments like (1, 1, 10) that no body has)."""
    return max(1.0, *(abs(float(inertia[(i + 1) % 3] - inertia[(i + 2) % 3])) / float(inertia[i])
                      for i in range(3)))


def matrices(q: np.ndarray) -> np.ndarray:
    """Rotation matrices of quaternions (scalar first), normalised first."""
    q = q / np.max(np.abs(q), axis=-1, keepdims=True)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    return Rotation.from_quat(q[..., [1, 2, 3, 0]]).as_matrix()


def invariants(inertia: np.ndarray, omega: np.ndarray, q: np.ndarray, omega0: np.ndarray) -> dict[str, np.ndarray]:
    """Energy, |L|, L_world and |q| at each frame, on moments over the largest and rates over
    the largest initial rate (relative measures are unchanged)."""
    big = float(np.max(np.abs(omega0)))
    w = omega / big if big > 0 else omega
    j = inertia / inertia.max()
    l_body = j * w
    return {
        "energy": 0.5 * np.sum(j * w * w, axis=1),
        "momentum": np.linalg.norm(l_body, axis=1),
        "momentum_world": np.einsum("nij,nj->ni", matrices(q), l_body),
        "q_norm": np.linalg.norm(q, axis=1),
    }


def relative_drift(values: np.ndarray) -> float:
    v0 = values[0]
    return float(np.max(np.abs(values - v0)) / (abs(v0) if v0 != 0 else 1.0))


def assert_finite_array(a: Any, shape: tuple[int, ...], dtype: Any = np.float64) -> None:
    assert isinstance(a, np.ndarray), type(a)
    assert a.shape == shape, (a.shape, shape)
    assert a.dtype == dtype, a.dtype
    assert np.isfinite(a).all(), a


# -- simulate and summarize ---------------------------------------------------------------------

def quiet_body(inertia: np.ndarray) -> dz.Body:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", dz.InertiaWarning)
        return dz.Body(inertia)


def bodies(inertia: np.ndarray) -> st.SearchStrategy[Any]:
    """A body as a Body or as its moments in any layout."""
    return st.one_of(st.just(inertia).map(quiet_body), layouts(inertia))


@st.composite
def run_args(draw: st.DrawFn, method: str, *, flips: bool = True) -> dict[str, Any]:
    """Arguments of a run the package accepts, as extreme as allowed: moments of any scale,
    rates from zero through subnormal to 1e150, steps up to beyond RK4's stability limit, and
    spans from a few steps to beyond `max_steps`."""
    inertia = draw(inertias())
    omega0 = scaled(draw(directions(3)), draw(st.sampled_from(
        [0, 0, 0, -1070, -1000, -500, -50, 50, 300, 490])))
    rate = rate_bound(inertia, omega0)
    fixed = method not in ADAPTIVE_METHODS and method != "exact"
    coupled = rate > 0 and draw(st.integers(0, 4)) > 0
    if coupled:  # the span and step in units of the motion's own time scale
        t_end = draw(log_uniform(1e-6, 30.0)) / rate
        h_rate = draw(st.one_of(log_uniform(1e-2, 0.5), log_uniform(0.5, 8.0)))
        dt: Any = h_rate / rate
        if not (math.isfinite(t_end) and t_end > 0 and math.isfinite(dt) and dt > 0):
            coupled = False
    if not coupled:  # anything at all, mostly refused as too long
        t_end = draw(valid_positive())
        dt = draw(valid_positive())
    else:
        dt = draw(as_number_types(dt))
        t_end = draw(as_number_types(t_end))
    kwargs: dict[str, Any] = dict(
        system=draw(bodies(inertia)),
        omega0=draw(layouts(omega0)),
        q0=draw(quaternions().flatmap(layouts)),
        t_end=t_end,
        frames=draw(valid_int(2, 24)),
        method=method,
        max_steps=draw(st.one_of(valid_int(2000, 4000), st.just(1), valid_int(1, 100))),
    )
    if draw(st.integers(0, 5)) == 0:
        kwargs["dt"] = None  # the step for an accuracy (fixed) or the automatic first step
        if draw(st.booleans()):
            kwargs["rtol"] = draw(valid_positive(2.3e-14, 0.999))
    else:
        kwargs["dt"] = dt
    if method in ADAPTIVE_METHODS:
        if draw(st.booleans()):
            kwargs["rtol"] = draw(valid_positive(1e-12, 0.999))
        if draw(st.booleans()):
            kwargs["atol"] = draw(valid_positive(1e-300, 1e3))
    if flips:
        kwargs["flips"] = draw(st.booleans())
    return kwargs


def batch_rows_of(value: Any, width: int) -> bool:
    """Whether `value` is finite real rows (M, width), M ≥ 1, non-zero if quaternions: not
    hostile to `simulate`, which runs them as a batch (the hostile reshapes draw (1, n))."""
    try:
        arr = np.asarray(value)
    except Exception:
        return False
    if arr.dtype.kind not in "iuf" or arr.ndim != 2 or arr.shape[1] != width or not arr.size:
        return False
    rows = arr.astype(float)
    return bool(np.isfinite(rows).all() and (width != 4 or rows.any(axis=1).all()))


def run_hostile(method_names: tuple[str, ...], *, flips: bool = True) -> dict[str, st.SearchStrategy[Any]]:
    hostile = {
        "system": st.one_of(hostile_vector3(positive=True, moments=True).filter(
            lambda v: not (batch_rows_of(v, 3) and bool((np.asarray(v) > 0).all()))),
            st.just(dz.SCENES["fig3a"])),
        "omega0": hostile_vector3().filter(lambda v: not batch_rows_of(v, 3)),
        "q0": hostile_quaternion().filter(lambda v: not batch_rows_of(v, 4)),
        "t_end": hostile_real(positive=True),
        "frames": hostile_int(2),
        "dt": hostile_real(positive=True).filter(lambda v: v is not None),
        "method": hostile_name(method_names),
        "rtol": st.one_of(hostile_real(positive=True).filter(lambda v: v is not None),
                          st.sampled_from([1.0, 2.0, 1e-15, 1e-300]).flatmap(as_number_types)),
        "atol": hostile_real(positive=True).filter(lambda v: v is not None),
        "max_steps": hostile_int(1),
    }
    if flips:
        hostile["flips"] = st.one_of(JUNK.filter(lambda v: v is not None and not _truthy_ok(v)),
                                     st.sampled_from(["yes", 2, 0.5, np.array([True, False])]))
    return hostile


def _truthy_ok(v: Any) -> bool:
    return isinstance(v, (bool, np.bool_))


def tolerance(method: str, kwargs: dict[str, Any], traj: Any, rate: float) -> dict[str, float]:
    """How far each invariant may drift by the method's documentation.

    Structure-preserving methods keep theirs to round-off (a few ulps a step, summed); RK4
    drifts |q| by at most its predicted dissipation when it does not warn; the adaptive
    methods keep the error within a small multiple of their tolerances; the exact solution
    has no truncation error. Anything not promised is only required to be finite.
    """
    steps = max(traj.n_steps, 1)
    # a few ulps per operation: one RK4 step, or each exact rotation of a splitting step
    per_step = {"splitting": 5, "splitting4": 21, "splitting6": 37}.get(method, 1)
    roundoff = 256 * EPS * (1 + steps * per_step)
    t_end = float(traj.t[-1])
    turns = rate * t_end
    out = {"q_norm": math.inf, "energy": math.inf, "momentum": math.inf, "momentum_world": math.inf}
    if method == "exact":
        out = dict.fromkeys(out, 1e-9)
        out["q_norm"] = 16 * EPS
    elif method == "rk4_projected":
        # the projection onto E and |L| solves a system as ill-conditioned as the moments'
        # ratio (the energy ellipsoid and the momentum sphere nearly tangent)
        inertia = np.asarray(traj.body.inertia)
        out = dict.fromkeys(out, roundoff * max(1.0, float(inertia.max() / inertia.min())))
    elif method in ("splitting", "splitting4"):
        out.update(q_norm=roundoff, momentum=roundoff, momentum_world=roundoff)
    elif method in ("splitting6", "implicit_midpoint", "dmv", "dmv_modified", "rkmk4",
                    "crouch_grossman3"):
        # the atlas's methods turn L and q by rotations at any step: what they keep by
        # rotating, they keep to round-off (the energy that Newton's method keeps is left out:
        # at steps this large the solve is not promised)
        out.update({k: roundoff for k in dz.METHODS[method].keeps if k != "energy"})
    elif method in ADAPTIVE_METHODS:
        rtol = kwargs.get("rtol") or 1e-9
        atol = kwargs.get("atol") or 1e-12
        if rtol <= 1e-3 and atol <= 1e-3:
            bound = 100 * (rtol + atol) * max(1.0, turns) + roundoff
            out = dict.fromkeys(out, bound)
    elif method == "rk4":
        step_rate = traj.dt * rate
        if step_rate <= 0.5:  # the guard's prediction holds, and the error model with it
            # (a step picked for `rtol`, dt=None, answers to the larger of the two)
            allowed = MAX_PREDICTED_DRIFT if kwargs.get("dt") is not None else max(
                MAX_PREDICTED_DRIFT, float(kwargs.get("rtol") or 0.0))
            out["q_norm"] = 1.01 * allowed + roundoff
            out["energy"] = 0.01 * max(turns, 1.0) * step_rate**4 + roundoff
    return out


def check_run(kwargs: dict[str, Any], result: Any, caught: list[warnings.WarningMessage], *,
              summary: bool = False) -> None:
    """A run's result: shapes, finiteness, the frame grid, flips, and the invariants (recomputed
    here from the frames) within the method's tolerance."""
    method = kwargs["method"]
    t_end = float(kwargs["t_end"])
    frames = int(kwargs["frames"])
    body = kwargs["system"]
    inertia = np.array(body.inertia if isinstance(body, dz.Body) else np.asarray(body, float))
    omega0 = np.asarray(kwargs["omega0"], dtype=float)
    if isinstance(body, dz.Body) and not body.is_principal:  # the rates in principal axes
        omega0 = body.principal_axes.T @ omega0
    rate = min(rate_bound(inertia, omega0) * euler_rate_factor(inertia), LARGEST)
    drift = result.drift
    assert all(isinstance(d, float) and math.isfinite(d) and d >= 0 for d in drift), drift
    assert isinstance(result.n_steps, int) and 0 <= result.n_steps <= int(kwargs["max_steps"])
    assert isinstance(result.dt, float) and math.isfinite(result.dt) and result.dt >= 0
    flips = result.flip_times
    if summary or kwargs.get("flips", True):
        assert isinstance(flips, np.ndarray) and flips.ndim == 1 and np.isfinite(flips).all()
        assert (np.diff(flips) >= 0).all() and (flips >= 0).all(), flips
        assert (flips <= t_end * (1 + 1e-12)).all(), (flips, t_end)
    else:
        assert flips is None
    if summary:
        return
    traj = result
    assert_finite_array(traj.t, (frames,))
    assert_finite_array(traj.omega, (frames, 3))
    assert_finite_array(traj.q, (frames, 4))
    assert traj.t[0] == 0.0 and traj.t[-1] == t_end and (np.diff(traj.t) >= 0).all()
    if method != "exact":
        np.testing.assert_array_equal(traj.omega[0], omega0)
    inv = invariants(inertia, traj.omega, traj.q, omega0)
    nonzero = np.abs(traj.omega[traj.omega != 0])
    subnormal = nonzero.size > 0 and nonzero.min() < 1e-290  # rates stored with few digits
    measured = {
        "energy": relative_drift(inv["energy"]),
        "momentum": relative_drift(inv["momentum"]),
        "momentum_world": float(np.max(np.linalg.norm(inv["momentum_world"] - inv["momentum_world"][0], axis=1))
                                / (inv["momentum"][0] if inv["momentum"][0] > 0 else 1.0)),
        "q_norm": float(np.max(np.abs(inv["q_norm"] - 1))),
    }
    # the run's own drift is the same measure, computed in the core (at full precision: from
    # rates stored as subnormals the measure here is coarser, and the core's is the one)
    for name, value in measured.items():
        if subnormal:
            measured[name] = getattr(drift, name)
        else:
            assert abs(getattr(drift, name) - value) <= 1e-12 + 1e-6 * value, (name, drift, measured)
    # the core's invariants() agree with these definitions
    core = traj.invariants()
    np.testing.assert_allclose(core["q_norm"], inv["q_norm"], rtol=1e-14)
    warned = any(issubclass(w.category, dz.StepSizeWarning) for w in caught)
    bounds = tolerance(method, kwargs, traj, rate)
    for name, bound in bounds.items():
        if warned and method in ("rk4", "rk4_projected"):
            continue
        assert measured[name] <= bound, (method, name, measured[name], bound, rate * traj.dt,
                                         {k: np.asarray(v).tolist() if isinstance(v, (list, tuple, np.ndarray)) else v
                                          for k, v in kwargs.items()})


def check_summary(kwargs: dict[str, Any], result: Any, caught: list[warnings.WarningMessage]) -> None:
    """A summary, and the same run as `simulate` with the same arguments, step for step."""
    check_run(kwargs, result, caught, summary=True)
    assert isinstance(result.verdict, str) and str(result.flips) in result.verdict or not result.flips
    full_kwargs = dict(kwargs)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        full = dz.simulate(**full_kwargs)
    np.testing.assert_array_equal(result.flip_times, full.flip_times)
    assert tuple(result.drift) == tuple(full.drift)
    assert (result.n_steps, result.nfev) == (full.n_steps, full.nfev)


# -- rotate -----------------------------------------------------------------------------------

@st.composite
def rotate_args(draw: st.DrawFn) -> dict[str, Any]:
    n, p = draw(st.integers(1, 6)), draw(st.integers(1, 6))
    q = np.stack([draw(quaternions()) for _ in range(n)])
    magnitude = draw(st.sampled_from([1.0, 1e-300, TINY, 1e300, 4e307, 1e150]))
    points = real_arrays((p, 3), st.floats(-1, 1)).map(lambda a: a * magnitude)
    pts = draw(points)
    q_1d, p_1d = draw(st.booleans()), draw(st.booleans())
    qv = q[0] if q_1d else q
    pv = pts[0] if p_1d else pts
    kwargs: dict[str, Any] = dict(q=draw(layouts(qv)), points=draw(layouts(pv)))
    if draw(st.booleans()):
        shape = tuple(s for s, keep in zip((n, p, 3), (not q_1d, not p_1d, True)) if keep)
        kwargs["out"] = np.full(shape, np.nan)
    return kwargs


def check_rotate(kwargs: dict[str, Any], result: Any, caught: list[warnings.WarningMessage]) -> None:
    q = np.asarray(kwargs["q"], dtype=float)
    points = np.asarray(kwargs["points"], dtype=float)
    q2, p2 = q.reshape(-1, 4), points.reshape(-1, 3)
    shape = tuple(s for s, keep in zip((len(q2), len(p2), 3), (q.ndim == 2, points.ndim == 2, True)) if keep)
    assert_finite_array(result, shape)
    if kwargs.get("out") is not None:
        assert result is kwargs["out"]
    # an independent rotation (scipy's, of the normalised quaternions), and lengths kept
    expected = np.einsum("nij,pj->npi", matrices(q2), p2)
    got = result.reshape(len(q2), len(p2), 3)
    scale = np.max(np.abs(p2), axis=1)[None, :, None]
    assert (np.abs(got - expected) <= 4e-15 * scale + 1e-300).all(), (got, expected)


hostile_out = st.one_of(
    st.sampled_from([np.float32, np.int64, complex, object]).map(lambda d: np.zeros((2, 2, 3), dtype=d)),
    st.just(np.zeros((3, 3, 3))[:, ::2]),
    st.just(np.zeros((2, 2, 3)).T.copy().T),
    st.builds(lambda: _readonly(np.zeros((1, 1, 3)))),
    st.just(np.zeros((2, 2, 4))),
    st.just(np.zeros((1, 1, 1, 3))),
    st.just([[[0.0, 0.0, 0.0]]]),
    JUNK.filter(lambda v: v is not None),
)


def _readonly(a: np.ndarray) -> np.ndarray:
    a.flags.writeable = False
    return a


# -- bodies -------------------------------------------------------------------------------------

def check_body(kwargs: dict[str, Any], body: Any, caught: list[warnings.WarningMessage]) -> None:
    moments = np.asarray(kwargs["inertia"], dtype=float)
    assert isinstance(body, dz.Body)
    assert body.inertia == tuple(float(x) for x in moments)
    # two moments within the symmetry tolerance (relative) are equal: a symmetric top
    gaps = [abs(moments[k] - moments[(k + 1) % 3]) / max(moments[k], moments[(k + 1) % 3])
            for k in range(3)]
    middle = [k for k in range(3) if sorted(moments)[1] == moments[k]
              and moments[k] not in (moments.min(), moments.max())]
    symmetric = min(gaps) <= dz.SYMMETRY_TOLERANCE
    assert body.intermediate_axis == (middle[0] if middle and not symmetric else None)
    breaks = any(moments[k] > moments[(k + 1) % 3] + moments[(k + 2) % 3] + 1e-12 * moments.sum()
                 for k in range(3))
    near = dz.SYMMETRY_TOLERANCE < min(gaps) <= dz.NEAR_SYMMETRY
    assert (breaks or near) == any(issubclass(w.category, dz.InertiaWarning) for w in caught)
    assert eval(repr(body), {"Body": dz.Body}) == body and hash(body) == hash(quiet_body(moments))


def check_box(kwargs: dict[str, Any], body: Any, caught: list[warnings.WarningMessage]) -> None:
    a, b, c = (float(kwargs[k]) for k in "abc")
    mass = float(kwargs.get("mass", 1.0))
    assert isinstance(body, dz.Body) and all(math.isfinite(i) and i > 0 for i in body.inertia)
    # the formula in exact rational arithmetic, rounded once
    from fractions import Fraction as F
    fa, fb, fc, fm = F(a), F(b), F(c), F(mass)
    exact = [fm * (fb * fb + fc * fc) / 12, fm * (fa * fa + fc * fc) / 12, fm * (fa * fa + fb * fb) / 12]
    for got, want in zip(body.inertia, exact):
        assert abs(F(got) - want) <= F(8 * EPS) * want, (got, float(want))
    assert not caught, caught  # a real box never breaks the triangle inequality


def box_args() -> st.SearchStrategy[dict[str, Any]]:
    edge = st.one_of(valid_positive(1e-100, 1e100), valid_positive())
    return st.fixed_dictionaries({"a": edge, "b": edge, "c": edge},
                                 optional={"mass": st.one_of(valid_positive(1e-100, 1e100), valid_positive())})


@st.composite
def tensor_args(draw: st.DrawFn) -> dict[str, Any]:
    """R diag(I) Rᵀ for moments within a ratio of 1e4 (the eigenvalues of a tensor are known
    to its largest times the round-off) at any scale, and a random rotation R; or a diagonal
    tensor (exact) of moments within the core's ratio at the ends of float64 (1e308, a rod's
    1e-15)."""
    if draw(st.integers(0, 3)) == 0:
        diagonal = draw(st.sampled_from([(1e308, 1e308, 1e308), (1e-15, 1.0, 1.0),
                                         (1.0, 1e-15, 1.0), (LARGEST, 1e200, 1e250),
                                         (3e-300, 2e-300, 1e-300), (1e-140, 1.0, 2.0)]))
        return {"tensor": np.diag(diagonal)}
    moments = np.array([10.0 ** draw(st.floats(-2, 2)) for _ in range(3)])
    moments *= draw(st.sampled_from([1.0, 1e-150, 1e150, 1e-300, 1e300]))
    r = Rotation.from_quat(draw(directions(4)) + [1e-3, 0, 0, 0]).as_matrix()
    out: dict[str, Any] = {"tensor": r @ np.diag(moments) @ r.T}
    if draw(st.booleans()):
        out["mass"] = draw(valid_positive(1e-100, 1e100))
    return out


def check_tensor(kwargs: dict[str, Any], body: Any, caught: list[warnings.WarningMessage]) -> None:
    tensor = np.asarray(kwargs["tensor"], dtype=float)
    assert isinstance(body, dz.Body)
    axes = body.principal_axes
    np.testing.assert_allclose(axes.T @ axes, np.eye(3), atol=1e-13)
    assert abs(np.linalg.det(axes) - 1) < 1e-13
    scale = np.abs(tensor).max()
    np.testing.assert_allclose((axes @ np.diag(body.inertia) @ axes.T) / scale, tensor / scale,
                               atol=1e-12)
    # each principal moment about the principal axis nearest the user's x, y, z: a diagonal
    # tensor's own diagonal, in its order
    if not np.any(tensor - np.diag(np.diag(tensor))):
        assert list(body.inertia) == list(np.diag(tensor))


def check_solid(kwargs: dict[str, Any], body: Any, caught: list[warnings.WarningMessage]) -> None:
    r, h, m = (float(kwargs[k]) for k in ("radius", "height", "mass"))
    # Goldstein's table: Iz = m r²/2, Ix = Iy = m (3 r² + h²)/12
    want = [m * (3 * r * r + h * h) / 12, m * (3 * r * r + h * h) / 12, m * r * r / 2]
    np.testing.assert_allclose(body.inertia, want, rtol=1e-14)
    assert not caught


def check_box_mesh(kwargs: dict[str, Any], body: Any, caught: list[warnings.WarningMessage]) -> None:
    v = np.asarray(kwargs["vertices"], dtype=float)
    a, b, c = v.max(axis=0) - v.min(axis=0)  # a box mesh: the box's moments
    m = body.mass
    want = np.diag([b * b * m / 12 + c * c * m / 12, a * a * m / 12 + c * c * m / 12,
                    a * a * m / 12 + b * b * m / 12])
    np.testing.assert_allclose(body.tensor, want, atol=1e-9 * np.abs(want).max())
    np.testing.assert_allclose(body.center_of_mass, v.mean(axis=0), atol=1e-9 * np.abs(v).max())
    # a long box's two large moments may be within NEAR_SYMMETRY: then, and only then, it warns
    d = np.diag(want)
    gap = min(abs(d[k] - d[(k + 1) % 3]) / max(d[k], d[(k + 1) % 3]) for k in range(3))
    warned = any(issubclass(w.category, dz.InertiaWarning) for w in caught)
    edges = (dz.SYMMETRY_TOLERANCE, dz.NEAR_SYMMETRY)
    if all(not 0.5 * e <= gap <= 2 * e for e in edges):  # clear of the band's edges
        assert warned == (dz.SYMMETRY_TOLERANCE < gap <= dz.NEAR_SYMMETRY), (gap, warned)


BOX_MESH_FACES = np.array([(0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4),
                           (2, 6, 7), (2, 7, 3), (0, 4, 6), (0, 6, 2), (1, 3, 7), (1, 7, 5)])


@st.composite
def box_mesh_args(draw: st.DrawFn) -> dict[str, Any]:
    """A box mesh off the origin; at moderate sizes with a density, or at any size float64
    holds (1e±150) with a mass (its moments, mass × size², representable)."""
    far = draw(st.booleans())
    scale = draw(st.sampled_from([1e-150, 1e-100, 1e100, 1e150])) if far else 1.0
    size = np.array([10.0 ** draw(st.floats(-3, 3)) for _ in range(3)]) * scale
    offset = np.array([draw(st.floats(-1e3, 1e3)) for _ in range(3)]) * scale
    k = np.arange(8)
    v = (np.stack([(k >> j) & 1 for j in range(3)], axis=1) - 0.5) * size + offset
    out: dict[str, Any] = {"vertices": v, "faces": BOX_MESH_FACES.copy()}
    if far:
        out["mass"] = draw(valid_positive(1e-10, 1e10))
    elif draw(st.booleans()):
        out["density"] = draw(valid_positive(1e-10, 1e10))
    return out



# -- the flip period ----------------------------------------------------------------------------

def check_flip_period(kwargs: dict[str, Any], period: Any, caught: list[warnings.WarningMessage]) -> None:
    assert isinstance(period, float) and period > 0 and not math.isnan(period), period
    omega = np.asarray(kwargs["omega0"], dtype=float)
    if math.isfinite(period) and np.abs(omega).max() < 1e300 and period > 1e-300:
        # (ω, t) → (2ω, t/2): the period halves, exactly (powers of two scale exactly)
        half = dz.flip_period(kwargs["body"], 2 * omega)
        assert half == period / 2 or abs(half / (period / 2) - 1) < 1e-12, (half, period)


# -- the ellipsoid --------------------------------------------------------------------------------

def check_semi_axes(kwargs: dict[str, Any], axes: Any, caught: list[warnings.WarningMessage]) -> None:
    body = kwargs["body"]
    inertia = np.array(body.inertia if isinstance(body, dz.Body) else np.asarray(body, float))
    if isinstance(body, dz.Body) and body.mass is not None:
        inertia = inertia / body.mass  # the radii of gyration: √(I/m)
    assert_finite_array(axes, (3,))
    assert (axes > 0).all()
    convention = kwargs.get("convention", "gyration")
    j = inertia / inertia.max()
    if convention == "gyration":
        np.testing.assert_allclose(axes / np.sqrt(inertia.max()), np.sqrt(j), rtol=1e-14)
    else:  # ∝ 1/√I, with the gyration ellipsoid's volume
        np.testing.assert_allclose(axes * np.sqrt(inertia) / (axes * np.sqrt(inertia))[0], 1, rtol=1e-13)
        np.testing.assert_allclose(np.prod(axes / np.sqrt(inertia.max())), np.prod(np.sqrt(j)),
                                   rtol=1e-12)


@st.composite
def mesh_args(draw: st.DrawFn) -> dict[str, Any]:
    axes = scaled(draw(real_arrays((3,), st.floats(0.5, 2))),
                  draw(st.sampled_from([0, 0, -1000, -1070, 1000, 1020])))
    if not (axes > 0).all():
        axes = np.ones(3)
    kwargs: dict[str, Any] = {"semi_axes": draw(layouts(axes))}
    if draw(st.booleans()):
        kwargs["n_around"] = draw(valid_int(3, 40))
    if draw(st.booleans()):
        kwargs["n_along"] = draw(valid_int(2, 30))
    return kwargs


def check_mesh(kwargs: dict[str, Any], result: Any, caught: list[warnings.WarningMessage]) -> None:
    vertices, quads = result
    a, b, c = np.asarray(kwargs["semi_axes"], dtype=float)
    n, m = int(kwargs.get("n_around", 24)), int(kwargs.get("n_along", 12))
    v = n * (m - 1) + 2
    assert_finite_array(vertices, (v, 3))
    assert isinstance(quads, np.ndarray) and quads.shape == (n * m, 4) and quads.dtype == np.uint32
    assert quads.max() == v - 1
    # every vertex on the ellipsoid (scaled, so that subnormal semi-axes are checked too)
    assert (np.abs(vertices) <= np.array([a, b, c]) * (1 + 4 * EPS)).all()
    if min(a, b, c) > 1e-290:
        r = (vertices[:, 0] / a) ** 2 + (vertices[:, 1] / b) ** 2 + (vertices[:, 2] / c) ** 2
        np.testing.assert_allclose(r, 1.0, rtol=1e-13)
    # a closed surface: every undirected edge is shared by two cells
    edges: dict[tuple[int, int], int] = {}
    for cell in quads.tolist():
        for k in range(4):
            p, r_ = cell[k], cell[(k + 1) % 4]
            if p != r_:
                key = (min(p, r_), max(p, r_))
                edges[key] = edges.get(key, 0) + 1
    assert set(edges.values()) == {2}
    assert v - len(edges) + n * m == 2


def check_box_vertices(kwargs: dict[str, Any], v: Any, caught: list[warnings.WarningMessage]) -> None:
    half = np.array([float(kwargs.get(k, d)) for k, d in zip("abc", dz.BOX_SIZE)]) / 2
    assert_finite_array(v, (8, 3))
    assert (np.abs(v) == half).all()
    assert len({tuple(np.sign(r)) for r in v}) == 8


# -- scenes -----------------------------------------------------------------------------------------

NAME_RE = r"[A-Za-z0-9][A-Za-z0-9_.-]{0,11}"


@st.composite
def scene_fields(draw: st.DrawFn, *, figures: tuple[str, ...] | None = None, small: bool = True) -> dict[str, Any]:
    """The fields of a scene the package accepts (a small run, to keep tests fast)."""
    inertia = draw(inertias().filter(_drawable_moments))
    omega0 = scaled(draw(directions(3)), draw(st.sampled_from([0, 0, 0, -1000, -60, 60, 300])))
    # the fastest frequency, so that a scene stays a few turns long (scenes run with the
    # default max_steps: an adaptive run of a stiff body would take minutes)
    rate = min(rate_bound(inertia, omega0) * euler_rate_factor(inertia), LARGEST)
    turns = draw(log_uniform(1e-3, 20.0))
    t_end = turns / rate if rate > 0 else draw(valid_positive(1e-3, 1e3))
    if not (math.isfinite(t_end) and t_end > 0):
        t_end = 1.0
    frames = draw(st.integers(2, 12 if small else 30))
    steps = draw(st.integers(1, 60))
    dt = t_end / ((frames - 1) * steps)
    if not (math.isfinite(dt) and dt > 0):
        dt = t_end
    method = draw(st.sampled_from(FREE_METHODS))
    # (the orbit's figures need an orbit or a wheel: `figure_args` gives them one)
    chosen = figures if figures is not None else tuple(draw(st.lists(st.sampled_from(
        [f for f in FIGURES if f not in ("lvlh", "wheel_off", "pointing", *SINK_FIGURES)]),
        unique=True,
        max_size=3)))
    phases = draw(st.lists(st.floats(0.0, 1.0), max_size=4))
    fields: dict[str, Any] = dict(
        name=draw(st.from_regex(NAME_RE, fullmatch=True)),
        # plain text: a title with `$`s is mathtext, valid only if matplotlib parses it
        title=draw(st.text(min_size=1, max_size=20).filter(lambda s: s.strip() and "$" not in s)),
        inertia=tuple(inertia.tolist()),
        omega0=tuple(omega0.tolist()),
        t_end=t_end,
        frames=frames,
        q0=tuple(draw(quaternions()).tolist()),
        dt=dt,
        method=method,
        box=draw(st.one_of(st.none(), real_arrays((3,), st.floats(0.1, 30)).map(lambda a: tuple(a.tolist())))),
        signal_point=tuple(draw(real_arrays((3,), st.floats(-20, 20))).tolist()),
        flips=draw(st.booleans()),
        draw=dz.scenes.Draw(
            box=draw(st.booleans()), ellipsoid=draw(st.booleans()), signal_point=draw(st.booleans()),
            path=draw(st.booleans()), body_axes=draw(st.booleans()), momentum=draw(st.booleans()),
            figures=chosen, animation=False, phases=tuple(sorted(p * t_end for p in phases))),
        ellipsoid=dz.scenes.EllipsoidStyle(draw(st.sampled_from(CONVENTIONS)),
                                          (draw(st.integers(3, 8 if small else 40)),
                                           draw(st.integers(2, 6 if small else 30)))),
        about=draw(st.text(max_size=10)),
    )
    if fields["draw"].box and fields["box"] is None:
        fields["box"] = (1.0, 2.0, 3.0)
    return fields


def _drawable_moments(inertia: np.ndarray) -> bool:
    """Moments whose inertia ellipsoid (either convention) a scene can draw: its semi-axes
    within the documented bound of a drawing (`scenes.scene.MAX_DRAWN_SIZE`)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return all(float(np.max(dz.ellipsoid_semi_axes(inertia, c))) <= MAX_DRAWN_SIZE
                   for c in CONVENTIONS)


def quiet_scene(fields: dict[str, Any]) -> dz.Scene:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return dz.Scene(**fields)


def scene_hostile() -> dict[str, st.SearchStrategy[Any]]:
    vec3 = hostile_vector3()
    return {
        "name": st.one_of(st.sampled_from(["", "a b", "../x", "-x", "x/y", ".x", "é"]),
                          JUNK.filter(lambda v: not isinstance(v, str))),
        "title": st.one_of(st.sampled_from(["", "   ", "$" + "{" * 40 + "x" + "}" * 40 + "$",
                                            "$" + r"\frac{" * 30 + "x" + "}{2}" * 30 + "$",
                                            r"$\notacommand{x}$", "$x^$"]),
                           JUNK.filter(lambda v: not isinstance(v, str))),
        # a table of the draw's or the ellipsoid's keys (`scene.replace(draw={...})`), or not
        "draw": st.one_of(st.sampled_from([3, "box", [1], {"boxx": True}, {"figures": ["nope"]},
                                           {"phases": "x"}, {"fps": 0}, {"a": 1}]),
                          JUNK.filter(lambda v: not isinstance(v, dict))),
        "ellipsoid": st.one_of(st.sampled_from([3, "poinsot", {"convention": "x"},
                                                {"mesh": [1]}, {"meshes": [3, 2]}]),
                               JUNK.filter(lambda v: not isinstance(v, dict))),
        "inertia": hostile_vector3(positive=True, moments=True),
        "omega0": vec3,
        "t_end": hostile_real(positive=True),
        "frames": hostile_int(2, huge=False),
        "q0": hostile_quaternion(),
        "dt": hostile_real(positive=True).filter(lambda v: v is not None),  # None: "none"
        "method": hostile_name(tuple(dz.METHODS)),
        "box": hostile_vector3(positive=True).filter(lambda v: v is not None),
        "signal_point": vec3.filter(lambda v: v is not None),
        "flips": st.one_of(st.sampled_from(["yes", 1, 0.0, None])),
        "about": st.one_of(st.integers(), st.just(None), st.just(["x"])),
    }


SCENE_ALIASES = {
    "inertia": ("body.inertia",), "omega0": ("start.omega",), "q0": ("start.q",),
    "t_end": ("run.t_end",), "frames": ("run.frames",), "dt": ("run.dt",),
    "method": ("run.method",), "box": ("body.box",), "signal_point": ("body.signal_point",),
    "flips": ("ask.flips",),
}


SCENE_WORDS = tuple(f.name for f in __import__("dataclasses").fields(dz.Scene)) + tuple(
    k for keys in SCENE_ALIASES.values() for k in keys)
"""What a message about a scene's run may name: its fields and their keys in a file."""


def check_scene(kwargs: dict[str, Any], scene: Any, caught: list[warnings.WarningMessage]) -> None:
    assert isinstance(scene, dz.Scene)
    for name in ("inertia", "omega0", "q0", "signal_point"):
        value = getattr(scene, name)
        assert isinstance(value, tuple) and all(isinstance(x, float) and math.isfinite(x) for x in value)
        np.testing.assert_array_equal(value, np.asarray(kwargs[name], dtype=float))
    assert isinstance(scene.frames, int) and scene.t_end == float(kwargs["t_end"])
    # a scene survives its own TOML
    back = dz.Scene.from_toml(scene.to_toml(), scene.name)
    assert back == scene


def toml_texts() -> st.SearchStrategy[str]:
    """TOML text of valid scenes."""
    return scene_fields().map(quiet_scene).map(lambda s: s.to_toml())


def hostile_toml() -> st.SearchStrategy[str]:
    """TOML (or not) that no scene has: a valid scene with one key spoilt, or garbage."""
    import tomli_w

    def spoil(scene: dz.Scene, table: str, key: str, value: Any) -> str:
        data = scene.to_dict()
        if table:
            data[table][key] = value
        else:
            data[key] = value
        return tomli_w.dumps(data)

    spoilt = st.tuples(
        scene_fields().map(quiet_scene),
        st.sampled_from([
            ("run", "t_end", -1.0), ("run", "t_end", math.nan), ("run", "t_end", math.inf),
            ("run", "frames", 1), ("run", "frames", 2.5), ("run", "frames", "10"),
            ("run", "dt", 0.0), ("run", "method", "rk5"), ("start", "omega", [1.0, 2.0]),
            ("start", "omega", [math.nan, 0.0, 1.0]), ("start", "q", [0.0, 0.0, 0.0, 0.0]),
            ("body", "inertia", [1.0, -1.0, 1.0]), ("body", "inertia", [1e-200, 1.0, 1e200]),
            ("body", "signal_point", "up"), ("ask", "flips", "yes"), ("draw", "figures", ["pie"]),
            ("draw", "phases", [-1.0]), ("ellipsoid", "mesh", [2, 2]), ("ellipsoid", "mesh", [10**6, 3]),
            ("ellipsoid", "convention", "round"), ("draw", "box", 1), ("", "title", ""),
            ("", "extra", 1), ("run", "speed", 3.0), ("", "run", 3),
        ])).map(lambda args: spoil(args[0], *args[1]))
    garbage = st.one_of(st.text(max_size=40), st.sampled_from([
        "title = ", "[run\nt_end = 1", "title = 'x'\n[run]\nt_end = 1e999999", "= = =", "\x00",
        "title = 'x'", "title = 'x'\n[start]\nomega=[0,0,1]\n[run]\nt_end=1\nframes=2\n[[draw]]",
    ]))
    return st.one_of(spoilt, garbage)


_TMP = Path(tempfile.mkdtemp(prefix="dzhanibekov-hostile-"))


def _file(content: str | bytes, suffix: str = ".toml") -> Path:
    fd, name = tempfile.mkstemp(suffix=suffix, dir=_TMP)
    with open(fd, "wb") as f:
        f.write(content.encode("utf-8", "surrogatepass") if isinstance(content, str) else content)
    return Path(name)


def scene_paths() -> st.SearchStrategy[Any]:
    return st.one_of(
        st.sampled_from(sorted(dz.SCENES)),
        toml_texts().map(_file).flatmap(lambda p: st.sampled_from([p, str(p)])),
    )


def hostile_paths() -> st.SearchStrategy[Any]:
    return st.one_of(
        hostile_toml().map(_file),
        st.binary(max_size=30).map(_file),
        st.just(b"\xff\xfe\x00title = 'x'").map(_file),
        st.sampled_from(["no-such-scene", str(_TMP / "missing.toml"), str(_TMP), "", "a\x00b",
                         "fig3a ", "FIG3A"]),
        st.sampled_from([None, 3, 2.5, ["fig3a"], b"fig3a", Ellipsis]),
    )


def check_loaded(kwargs: dict[str, Any], scene: Any, caught: list[warnings.WarningMessage]) -> None:
    assert isinstance(scene, dz.Scene)
    assert dz.Scene.from_toml(scene.to_toml(), scene.name) == scene


def check_plan(kwargs: dict[str, Any], plan: Any, caught: list[warnings.WarningMessage]) -> None:
    from dzhanibekov.scenes.plan import POINT_SETS
    scene = kwargs["scene"]
    assert isinstance(plan, dz.scenes.Plan) and plan.scene is scene
    assert plan.keep_frames == (bool(scene.draw.figures) or scene.draw.animation)
    rotated = plan.rotated
    assert len(rotated) == len(set(rotated)) and set(rotated) <= set(POINT_SETS)
    assert ("ellipsoid" in plan.meshes) == ("ellipsoid" in rotated)


def check_result(kwargs: dict[str, Any], result: Any, caught: list[warnings.WarningMessage]) -> None:
    plan = kwargs["plan"]
    scene = plan.scene
    assert isinstance(result, dz.scenes.SceneResult)
    assert (result.trajectory is not None) == plan.keep_frames
    if result.trajectory is not None:
        assert np.isfinite(result.trajectory.omega).all() and np.isfinite(result.trajectory.q).all()
    assert all(isinstance(d, float) and math.isfinite(d) for d in result.drift)
    for name, world in result.world.items():
        assert np.isfinite(world.points).all(), name
        assert world.points.shape[0] == len(world.frames)
    if result.mesh is not None:
        assert np.isfinite(result.mesh[0]).all()
    if "signal" in result.world:
        r = np.linalg.norm(scene.signal_point)
        np.testing.assert_allclose(np.linalg.norm(result.world["signal"].points, axis=-1), r,
                                   rtol=1e-12, atol=1e-300)


# -- figures ---------------------------------------------------------------------------------------

SINK_FIGURES = ("energy_balance", "part_motion", "capture")
"""The figures of a run with an energy sink (a slosh tank for `capture`)."""


def _sink_run(damping: float, frames: int, x0: float) -> dict[str, Any]:
    body = dz.Body.from_tensor(np.diag([3.0, 1.0, 2.0]), mass=1.0)
    parts = [dz.Slosh(0.05, (0.0, 0.0, 0.5), 0.3, damping, (1.0, 0.0, 0.0)),
             dz.SpringMassDamper(0.02, (0.0, 0.4, 0.0), (1.0, 0.0, 0.0), 0.5, damping, x0=x0)]
    return {"scene": dz.simulate(dz.System(body, parts=parts), (0.01, 0.01, 1.0), t_end=5.0,
                                 frames=frames, dt=0.01)}


def figure_args(figure: str) -> st.SearchStrategy[dict[str, Any]]:
    if figure in SINK_FIGURES:  # a short run with a slosh tank and a spring
        return st.builds(_sink_run, st.floats(0.0, 0.1), st.integers(2, 60),
                         st.floats(-0.1, 0.1))
    needs = {"phases": {}, "path": {"path": True}}.get(figure, {})
    # the orbit's figures draw what only a run in orbit, or with a wheel, has
    # (by a method that runs them: the scenes' own may be the free body's exact solution)
    system = {"lvlh": {"orbit": dz.GravityGradient(0.7), "method": "rk4"},
              "wheel_off": {"wheel": dz.Wheel((0.0, 0.0, 1.0), 2.0), "method": "rk4"},
              "pointing": {"method": "rk4"}}.get(figure, {})

    def build(fields: dict[str, Any]) -> dz.Scene:
        d = fields["draw"]
        fields["draw"] = dz.scenes.Draw(**{**d.__dict__, **needs})
        fields.update(system)
        if figure == "pointing":   # wheels under feedback, sampled 8 times a run
            fields["parts"] = (dz.QuaternionFeedback(1.0, 2.0, fields["t_end"] / 8,
                                                     torque_limit=1.0, momentum_limit=2.0),)
        if system:
            fields.pop("deployment", None)
            fields.pop("damper", None)
            fields.pop("sigma0", None)
        return quiet_scene(fields)

    return scene_fields(figures=(figure,)).map(build).map(lambda s: {"scene": s})


def check_figure(kwargs: dict[str, Any], fig: Any, caught: list[warnings.WarningMessage]) -> None:
    from matplotlib.figure import Figure
    assert isinstance(fig, Figure)
    fig.canvas.draw()  # the drawing itself must not fail or warn
    for ax in fig.axes:  # NaN are gaps left on purpose (exact zeros on a log scale); inf is not
        for line in ax.lines:
            data = np.asarray(line.get_xydata(), dtype=float)
            assert not np.isinf(data).any(), line.get_label()


def hostile_scene_objects() -> st.SearchStrategy[Any]:
    return st.one_of(JUNK, st.just(np.zeros(3)), st.just(dz.Body((1.0, 2.0, 3.0))), st.just("fig3a"))


@st.composite
def polhode_args(draw: st.DrawFn) -> dict[str, Any]:
    inertia = draw(inertias())
    energy = draw(st.one_of(st.just(0.0), valid_positive(1e-300, 1e300)))
    kwargs: dict[str, Any] = {"inertia": draw(layouts(inertia)), "energy": energy}
    if draw(st.booleans()):
        kwargs["levels"] = draw(valid_int(1, 5))
    if draw(st.booleans()):
        kwargs["points"] = draw(valid_int(2, 50))
    return kwargs


def check_polhodes(kwargs: dict[str, Any], result: Any, caught: list[warnings.WarningMessage]) -> None:
    family, separatrix = result
    inertia = np.asarray(kwargs["inertia"], dtype=float)
    energy = float(kwargs["energy"])
    top = float(inertia.max())
    for curve in family + separatrix:
        assert np.isfinite(curve).all()
        size = float(np.abs(curve).max())
        with np.errstate(all="ignore"):
            expected = 2 * (energy / top) / size / size if size > 0 else 0.0
        if energy > 0 and size > 0 and 1e-250 < expected < 1e250:
            # on the energy ellipsoid ω·Iω = 2E, in units of the largest moment and rate
            two_e = np.sum(inertia / top * (curve / size) ** 2, axis=1)
            np.testing.assert_allclose(two_e, expected, rtol=1e-9)


# -- bodies that change: deployments and dampers -------------------------------------------------------

MODEL_METHODS = ("rk4", "rk4_projected", "dopri5", "dop853")
STOWED_HOSTILE = (1.0, 2.0, 3.0)
ORBIT_RUN = dz.simulate(dz.System(dz.Body((2.0, 3.0, 1.0)), torques=[dz.GravityGradient(1.0)]),
                        *dz.lvlh_start(1.0), t_end=1.0, frames=5, method="rk4", dt=0.01)
"""A short run in orbit, for the LVLH helpers' entries."""

LOOP_FIELD = dz.MagneticField(dz.circular_orbit_rate(500e3), inclination=1.2)
"""The field of the closed loop's entries (a 500 km orbit)."""
NOT_A_FIELD = st.sampled_from([None, 1e-3, "B", (1e-3, 1.2), dz.Magnetometer()])
LOOP_RUN = dz.simulate(
    dz.System(dz.Body((2.0, 3.0, 4.0)), torques=[dz.BDot(LOOP_FIELD, 1e-5, 0.5)],
              parts=[dz.QuaternionFeedback(0.5, 1.5, 0.5, torque_limit=1e-3)]),
    (0.0, 0.1, 0.0), (0.8, 0.6, 0.0, 0.0), t_end=2.0, frames=5, method="rk4", dt=0.05)
"""A short closed-loop run, for the readers' entries."""
LOOP_KINDS = ("bdot", "quaternion_feedback")
PERIODS = st.floats(0.01, 10.0)
SEEDS = st.integers(0, 2**53 - 1)
BAD_PERIODS = st.sampled_from([0.0, -1.0, math.nan, math.inf, "1 s", None])
BAD_PHASES = st.sampled_from([-1.0, math.nan, math.inf, "0"])
BAD_SEEDS = st.sampled_from([-1, 2**53, 0.5, True, "1", None, np.float64(3.0)])
BAD_LIMITS = st.sampled_from([0.0, -1.0, (0.1, 0.0, 0.1), math.nan, "m", (1.0, 2.0)])
MAGNETOMETERS = st.builds(dz.Magnetometer, st.floats(0.0, 1e-6),
                          real_arrays((3,), st.floats(-1e-6, 1e-6)))
GYROS = st.builds(dz.Gyro, st.floats(0.0, 1e-4), real_arrays((3,), st.floats(-1e-3, 1e-3)))
STAR_TRACKERS = st.builds(dz.StarTracker, st.floats(0.0, 1e-3))
WHEEL_AXES = st.sampled_from([((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)),
                              ((1.0, 1.0, 0.0), (0.0, 1.0, 1.0), (1.0, 0.0, 1.0))])
BAD_AXES = st.sampled_from([((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (1.0, 1.0, 0.0)), "a",
                            np.ones(3), ((math.nan, 0.0, 0.0), (0.0, 1.0, 0.0), (0, 0, 1))])
BAD_MOMENTA = st.sampled_from([(math.nan, 0.0, 0.0), (1.0, 0.0), "h"])


def _loop_part(kw: dict[str, Any], part: Any, kind: str, external: bool) -> None:
    """A closed-loop part keeps what it was given and makes its model in a system."""
    for name in ("gain", "period", "phase"):
        if name in kw:
            _assert(getattr(part, name) == kw[name])
    _assert(getattr(part, "seed", 0) == kw.get("seed", 0))
    if "field" in kw and kw["field"] is not None:
        _assert(part.field == kw["field"])
    system = dz.System(dz.Body((1.0, 2.0, 3.0)),
                       **{"torques" if external else "parts": [part]})
    _assert(system.kinds == (kind,))


def _assert(condition: bool) -> None:
    assert condition
FREE_METHODS = tuple(m for m, info in dz.METHODS.items() if "free" in info.models)
"""The methods that run the free body (splitting_exact runs bodies under torques only)."""
STOWED_DEPLOYMENT = dz.Deployment([0.0, 1.0], [STOWED_HOSTILE, (1.0, 3.0, 2.0)])
"""Moments where a Deployment is wanted."""


@st.composite
def deployment_args(draw: st.DrawFn) -> dict[str, Any]:
    """Knot times (increasing, of any scale) and the body at each: moments, tensors, Bodies."""
    k = draw(st.integers(1, 4))
    start = draw(st.floats(-1e6, 1e6))
    gaps = draw(st.lists(log_uniform(1e-6, 1e6), min_size=k - 1, max_size=k - 1))
    times = np.cumsum([start, *gaps])
    if np.any(np.diff(times) <= 0):
        times = start + np.arange(k, dtype=float)
    knots: list[Any] = []
    for _ in range(k):
        moments = draw(inertias())
        kind = draw(st.integers(0, 2))
        knots.append(moments if kind == 0 else np.diag(moments) if kind == 1 else quiet_body(moments))
    return {"times": draw(layouts(times)), "inertia": knots}


def check_deployment(kwargs: dict[str, Any], d: Any, caught: list[warnings.WarningMessage]) -> None:
    assert isinstance(d, dz.Deployment)
    assert d.tensors.shape == (len(d.times), 3, 3) and np.isfinite(d.tensors).all()
    assert (np.diff(d.times) > 0).all()
    np.testing.assert_array_equal(d.inertia_at(float(d.times[0]) - 1.0), d.tensors[0])


def check_damper(kwargs: dict[str, Any], d: Any, caught: list[warnings.WarningMessage]) -> None:
    assert isinstance(d, dz.Damper) and d.inertia > 0 and d.damping >= 0
    assert d.sigma0 is None or np.isfinite(d.sigma0).all()


def check_system(kwargs: dict[str, Any], s: Any, caught: list[warnings.WarningMessage]) -> None:
    assert isinstance(s, dz.System) and s.parts == tuple(kwargs.get("parts", ()))
    assert s.kinds == (("damper",) if s.parts else ("free",))
    assert set(s.conserved) <= {"energy", "momentum", "momentum_world", "q_norm",
                                "energy_balance"}


@st.composite
def model_run_args(draw: st.DrawFn, kind: str) -> dict[str, Any]:
    """A moderate run of a deployment or a damped body (the models are run in the user's
    units: no extreme rates)."""
    inertia = draw(inertias().filter(lambda i: i.max() / i.min() < 1e6 and i.max() < 1e100
                                     and i.min() > 1e-100))
    omega0 = scaled(draw(directions(3)), draw(st.sampled_from([0, -10, 0, 3])))
    if not 1e-6 < rate_bound(inertia, omega0) < 1e6:
        omega0 = np.array([0.3, -0.4, 1.0])
    rate = rate_bound(inertia, omega0)
    method = draw(st.sampled_from(MODEL_METHODS))
    kwargs: dict[str, Any] = dict(
        omega0=draw(layouts(omega0)), q0=draw(quaternions().flatmap(layouts)),
        t_end=draw(log_uniform(1e-3, 20.0)) / rate, frames=draw(valid_int(2, 50)),
        dt=draw(log_uniform(1e-2, 0.5)) / rate, method=method)
    if kind == "deployment":
        second = draw(inertias().filter(lambda i: i.max() / i.min() < 1e6))
        second = second / second.max() * inertia.max()
        span = float(kwargs["t_end"])
        kwargs["system"] = dz.Deployment([0.2 * span, 0.6 * span], [inertia, second])
    else:
        # the damper's own time j / c stays above the step: explicit methods past their
        # stability limit on it (h c / j ≈ 2.8 for RK4) are not what this entry tests
        j = float(inertia.min()) * draw(log_uniform(1e-3, 1.0))
        sigma0 = draw(layouts(scaled(draw(directions(3)), 0) * rate)) \
            if draw(st.booleans()) else None
        damper = dz.Damper(j, j * rate * draw(log_uniform(1e-3, 1.0)), sigma0=sigma0)
        with warnings.catch_warnings():  # moments no real body has: warned of, and run
            warnings.simplefilter("ignore", dz.InertiaWarning)
            kwargs["system"] = dz.System(draw(bodies(inertia)), parts=[damper])
    if method in ADAPTIVE_METHODS:
        kwargs.update(rtol=draw(log_uniform(1e-12, 1e-4)), dt=None)
    return kwargs


def check_model_run(kwargs: dict[str, Any], traj: Any, caught: list[warnings.WarningMessage]) -> None:
    frames = int(kwargs["frames"])
    for name, shape in (("omega", (frames, 3)), ("q", (frames, 4)), ("momentum_world", (frames, 3)),
                        ("energy", (frames,))):
        value = getattr(traj, name)
        assert value.shape == shape and np.isfinite(value).all(), name
    l_world = traj.momentum_world
    scale = np.abs(l_world[0]).max()
    if scale > 0 and kwargs["method"] != "rk4":
        # kept by the law; projected runs keep it closely, adaptive ones to a multiple of the
        # rtol that holds each of their (up to thousands of) steps
        # (each step's error within rtol: at most rtol times the steps taken, for a fast
        # deployment's tens of thousands of steps at a loose rtol)
        rtol = kwargs.get("rtol")
        allowed = 1e-3 if rtol is None else max(1e-3, max(1e3, traj.n_steps) * float(rtol))
        assert np.abs(l_world - l_world[0]).max() <= allowed * scale
    if "damper" in traj.system.kinds:
        assert traj.parts["damper"].shape == (frames, 3)
        energy = traj.energy
        assert energy.max() <= energy[0] * (1 + 1e-3) + 1e-300
        shares = dz.axis_shares(traj) if scale > 0 else None
        assert shares is None or np.isfinite(shares).all()
        t_flat = dz.flat_spin_time(traj)
        assert math.isnan(t_flat) or 0 <= t_flat <= float(kwargs["t_end"])


def dampers() -> st.SearchStrategy[Any]:
    """Dampers the core takes: positive sphere, non-negative coefficient, their ratio c / j
    (the slip's rate) finite in float64."""
    return st.tuples(valid_positive(), positive_floats()).filter(
        lambda jc: math.isfinite(float(jc[1]) / float(jc[0]))).map(lambda jc: dz.Damper(*jc))


@st.composite
def estimate_args(draw: st.DrawFn) -> dict[str, Any]:
    inertia = draw(inertias())
    return {"body": draw(bodies(inertia)),
            "damper": draw(dampers()),
            "omega0": draw(layouts(scaled(draw(directions(3)), draw(st.sampled_from([0, -100, 100]))))),
            **({"share": draw(st.floats(0.01, 0.999))} if draw(st.booleans()) else {})}


def check_damper_rate(kwargs: dict[str, Any], rate: Any, caught: list[warnings.WarningMessage]) -> None:
    # c (1/j + 1/I_min): at least c / j, at most c (1/j + 1/I) for every moment I
    d = kwargs["damper"]
    assert isinstance(rate, float) and math.isfinite(rate) and rate >= 0
    assert rate >= d.damping / d.inertia * (1 - 1e-15)


def check_estimate(kwargs: dict[str, Any], t: Any, caught: list[warnings.WarningMessage]) -> None:
    assert isinstance(t, float) and (t >= 0 or math.isnan(t)), t


def _model_entry(kind: str) -> Entry:
    hostile = {k: v for k, v in run_hostile(tuple(dz.METHODS), flips=False).items()
               if k in ("omega0", "q0", "t_end", "frames", "method", "max_steps")}
    hostile["method"] = st.sampled_from(["exact", "splitting", "splitting4", "RK4", ""])
    return Entry(
        call=dz.simulate,
        valid=model_run_args(kind),
        hostile=hostile,
        check=check_model_run,
        covers=(dz.simulate, dz.axis_shares, dz.flat_spin_time, dz.FLAT_SHARE),
        warns=(dz.InertiaWarning, dz.StepSizeWarning),
        examples=60,
        min_success=0.5,
    )


@st.composite
def deployments_args(draw: st.DrawFn) -> dict[str, Any]:
    runs = [draw(model_run_args("deployment")) for _ in range(draw(st.integers(1, 3)))]
    first = runs[0]
    kwargs = {k: v for k, v in first.items() if k not in ("system", "omega0", "q0")}
    kwargs["system"] = [r["system"] for r in runs]
    kwargs["omega0"] = first["omega0"] if draw(st.booleans()) else np.stack(
        [np.asarray(r["omega0"], float) for r in runs])
    return kwargs


def _rate_rows(v: Any) -> bool:
    """(M, 3) finite real rates: one start per deployment, valid for `simulate_deployments`."""
    try:
        arr = np.asarray(v)
    except Exception:
        return False
    return (arr.ndim == 2 and arr.shape[-1] == 3 and arr.shape[0] > 0
            and arr.dtype.kind in "iuf" and bool(np.isfinite(arr).all()))


def check_deployments(kwargs: dict[str, Any], batch: Any, caught: list[warnings.WarningMessage]) -> None:
    assert isinstance(batch, dz.Batch) and len(batch) == len(kwargs["system"])
    for i in range(len(batch)):
        check_model_run(kwargs, batch[i], caught)


# -- composites and mesh files -------------------------------------------------------------------------

@st.composite
def compose_args(draw: st.DrawFn) -> dict[str, Any]:
    """One to three boxes with masses, at positions and turned by quaternions of any norm
    float64 holds (5e-324 … 1e300: non-zero, so normalisable), or left unturned."""
    parts = []
    for _ in range(draw(st.integers(1, 3))):
        edges = [10.0 ** draw(st.floats(-2, 2)) for _ in range(3)]
        box = dz.Body.box(*edges, mass=10.0 ** draw(st.floats(-3, 3)))
        position = tuple(draw(st.floats(-10, 10)) for _ in range(3))
        if draw(st.booleans()):
            parts.append((box, draw(layouts(np.array(position)))))
        else:
            parts.append((box, position, draw(quaternions().flatmap(layouts))))
    return {"parts": parts}


def check_compose(kwargs: dict[str, Any], body: Any, caught: list[warnings.WarningMessage]) -> None:
    """The mass is the sum; the tensor about the composite centre of mass is each part's
    tensor turned (scipy's Rotation of the normalised quaternion) plus its parallel-axis
    term (Huygens–Steiner, written out here)."""
    parts = kwargs["parts"]
    masses = [p[0].mass for p in parts]
    positions = [np.asarray(p[1], dtype=float) for p in parts]
    com = sum(m * x for m, x in zip(masses, positions)) / sum(masses)
    want = np.zeros((3, 3))
    for part, m, x in zip(parts, masses, positions):
        q = np.asarray(part[2], dtype=float) if len(part) == 3 else np.array([1.0, 0, 0, 0])
        q = q / np.abs(q).max()
        turn = Rotation.from_quat(np.roll(q / np.linalg.norm(q), -1)).as_matrix()
        d = x - com
        want += turn @ part[0].tensor @ turn.T + m * (d @ d * np.eye(3) - np.outer(d, d))
    assert body.mass == pytest_approx(sum(masses))
    np.testing.assert_allclose(body.tensor, want, atol=1e-12 * np.abs(want).max())


def pytest_approx(x: float) -> Any:
    import pytest

    return pytest.approx(x, rel=1e-14)


def hostile_parts() -> st.SearchStrategy[Any]:
    box = dz.Body.box(1.0, 2.0, 3.0, mass=2.0)
    return st.one_of(
        JUNK, st.just([]), st.just(()), st.just("box"), st.just([box]), st.just(box),
        st.just([(dz.Body((1.0, 2.0, 3.0)), (0.0, 0.0, 0.0))]),  # no mass
        st.just([(box,)]), st.just([(box, (0.0, 0.0, 0.0), (1, 0, 0, 0), 1.0)]),
        st.just([((1.0, 2.0, 3.0), (0.0, 0.0, 0.0))]),  # moments where a Body belongs
        hostile_vector3().map(lambda p: [(box, p)]),
        hostile_quaternion().map(lambda q: [(box, (0.0, 0.0, 0.0), q)]),
    )


BOX_STL = _file("", ".stl")


def _write_box_stl() -> Path:
    from hostile import BOX_FACES, ascii_stl, box_vertices

    BOX_STL.write_text(ascii_stl(box_vertices((1.0, 2.0, 3.0)), BOX_FACES))
    return BOX_STL


def load_args() -> st.SearchStrategy[dict[str, Any]]:
    return st.fixed_dictionaries({"path": st.sampled_from([_write_box_stl(), str(BOX_STL)])},
                                 optional={"mass": valid_positive(1e-100, 1e100)})


def check_load(kwargs: dict[str, Any], body: Any, caught: list[warnings.WarningMessage]) -> None:
    m = float(kwargs.get("mass", 6.0))  # unit density: the volume, 1 × 2 × 3
    want = np.diag([4.0 * m / 12 + 9.0 * m / 12, 1.0 * m / 12 + 9.0 * m / 12,
                    1.0 * m / 12 + 4.0 * m / 12])
    np.testing.assert_allclose(body.tensor, want, atol=1e-12 * want.max())


def hostile_mesh_paths() -> st.SearchStrategy[Any]:
    return st.one_of(
        st.sampled_from([str(_TMP / "missing.stl"), str(_TMP), "", "a\x00b.stl",
                         "/dev/zero", "README.md"]),
        st.binary(max_size=200).map(lambda b: _file(b, ".stl")),
        st.sampled_from([".obj", ".ply", ".off", ".3mf", ".glb", ".xyz"]).map(
            lambda suffix: _file(b"solid x\nfacet normal 0 0 1\n", suffix)),
        st.sampled_from([None, 3, 2.5, b"box.stl", ["box.stl"]]),
    )


# -- the table -----------------------------------------------------------------------------------------

def _simulate_entry(method: str) -> Entry:
    return Entry(
        call=dz.simulate,
        valid=run_args(method),
        hostile=run_hostile(tuple(dz.METHODS)),
        check=check_run,
        covers=(dz.simulate, dz.Trajectory, dz.Drift, dz.METHODS, dz.MethodInfo),
        warns=(dz.StepSizeWarning, dz.InertiaWarning),
        min_success=0.2,
    )


SINK_VECTOR = st.sampled_from([(math.nan, 0.0, 0.0), (1.0, 0.0), "v", None, np.ones((2, 3))])
"""Vectors the energy sinks' classes refuse (issue 31)."""

ENTRIES: dict[str, Entry] = {
    "Body": Entry(
        call=dz.Body,
        valid=inertias().flatmap(layouts).map(lambda v: {"inertia": v}),
        hostile={"inertia": hostile_vector3(positive=True, moments=True)},
        check=check_body,
        covers=(dz.Body, dz.InertiaWarning),
        warns=(dz.InertiaWarning,),
        min_success=0.9,
    ),
    "Body.box": Entry(
        call=dz.Body.box,
        valid=box_args(),
        hostile={k: hostile_real(positive=True) for k in ("a", "b", "c", "mass")},
        check=check_box,
        covers=(dz.Body,),
        aliases={"a": ("a, b, c",), "b": ("a, b, c",), "c": ("a, b, c",)},
        min_success=0.3,  # edges 1e-100 to 1e100 apart make moments beyond the 1e150 ratio
    ),
    "Body.from_tensor": Entry(
        call=dz.Body.from_tensor,
        valid=tensor_args(),
        hostile={"tensor": hostile_array((3, 3), tensor_args().map(lambda k: k["tensor"]),
                                         extra=[st.just(np.diag([1.0, -1.0, 1.0])),
                                                st.just(np.array([[1.0, 0.5, 0], [0, 1, 0],
                                                                  [0, 0, 1]]))]),
                 "mass": hostile_real(positive=True).filter(lambda x: x is not None)},
        check=check_tensor,
        covers=(dz.Body,),
        warns=(dz.InertiaWarning,),
        min_success=0.9,
    ),
    "Body.cylinder": Entry(
        call=dz.Body.cylinder,
        valid=st.fixed_dictionaries({k: valid_positive(1e-50, 1e50)
                                     for k in ("radius", "height", "mass")}),
        hostile={k: hostile_real(positive=True) for k in ("radius", "height", "mass")},
        check=check_solid,
        covers=(dz.Body,),
        min_success=0.3,
    ),
    "Body.from_mesh": Entry(
        call=dz.Body.from_mesh,
        valid=box_mesh_args(),
        hostile={"vertices": hostile_array((None, 3), box_mesh_args().map(lambda k: k["vertices"])),
                 "faces": st.one_of(JUNK, st.just(BOX_MESH_FACES[:-1]),
                                    st.just(BOX_MESH_FACES[:, ::-1]),
                                    st.just(BOX_MESH_FACES + 8), st.just(BOX_MESH_FACES * 1.0)),
                 "density": hostile_real(positive=True).filter(lambda x: x is not None),
                 "mass": hostile_real(positive=True).filter(lambda x: x is not None)},
        check=check_box_mesh,
        covers=(dz.Body, dz.MeshError),
        warns=(dz.InertiaWarning,),
        min_success=0.9,
    ),
    "Body.compose": Entry(
        call=dz.Body.compose,
        valid=compose_args(),
        hostile={"parts": hostile_parts()},
        check=check_compose,
        covers=(dz.Body,),
        aliases={"parts": ("parts[0]",)},
        warns=(dz.InertiaWarning,),
        min_success=0.9,
    ),
    "Body.load": Entry(
        call=dz.Body.load,
        valid=load_args(),
        hostile={"path": hostile_mesh_paths(),
                 "mass": hostile_real(positive=True).filter(lambda x: x is not None)},
        check=check_load,
        covers=(dz.Body, dz.MeshError),
        named_by_value=("path",),
        examples=60,
        min_success=0.9,
    ),
    **{f"simulate[{m}]": _simulate_entry(m) for m in dz.METHODS
       if "free" in dz.METHODS[m].models},  # splitting_exact runs bodies under torques only
    "simulate[deployment]": _model_entry("deployment"),
    "simulate[damper]": _model_entry("damper"),
    "simulate[deployments]": Entry(
        call=dz.simulate,
        valid=deployments_args(),
        # a list that mixes a deployment with what is no system (a list of moments alone is
        # a valid batch of bodies)
        hostile={"system": st.sampled_from([[], [STOWED_DEPLOYMENT, STOWED_HOSTILE, "x"], "x",
                                            None, 1.0]),
                 "omega0": hostile_vector3().filter(lambda v: not _rate_rows(v)),
                 "t_end": hostile_real(positive=True),
                 "frames": hostile_int(2),
                 "method": st.sampled_from(["exact", "splitting", "splitting4", "RK4", ""])},
        check=check_deployments,
        covers=(dz.Deployment,),
        warns=(dz.InertiaWarning, dz.StepSizeWarning),
        examples=30,
        min_success=0.5,
    ),
    # -- in orbit (issue 21) ----------------------------------------------------------------
    "GravityGradient": Entry(
        call=dz.GravityGradient,
        valid=st.fixed_dictionaries({"orbit_rate": st.floats(1e-6, 10.0)}),
        hostile={"orbit_rate": st.sampled_from([0.0, -1.0, math.nan, math.inf, "1", None,
                                                (1.0,), True])},
        check=lambda kw, g, _: _assert(g.orbit_rate == kw["orbit_rate"]),
        covers=(dz.GravityGradient,),
        min_success=0.9,
    ),
    "ConstantTorque": Entry(
        call=dz.ConstantTorque,
        valid=st.fixed_dictionaries({"vector": real_arrays((3,), st.floats(-10.0, 10.0)),
                                     "frame": st.sampled_from(["body", "world"])}),
        hostile={"vector": st.sampled_from([(1.0, 2.0), (math.nan, 0.0, 0.0), "x", None,
                                            np.ones((2, 3)), (math.inf, 0.0, 0.0)]),
                 "frame": st.sampled_from(["Body", "orbit", "", None, 1, ("body",)])},
        check=lambda kw, c, _: _assert(np.array_equal(c.vector, kw["vector"])
                                       and c.frame == kw["frame"]),
        covers=(dz.ConstantTorque,),
        min_success=0.9,
    ),
    "Wheel": Entry(
        call=dz.Wheel,
        valid=st.fixed_dictionaries({
            "axis": real_arrays((3,), st.floats(0.5, 2.0)),
            # a constant momentum, or a schedule (times, values)
            "momentum": st.one_of(st.floats(-10.0, 10.0), st.integers(2, 5).flatmap(
                lambda k: st.tuples(
                    st.lists(st.floats(0.01, 10.0), min_size=k, max_size=k).map(
                        lambda d: [float(x) for x in np.cumsum(d)]),
                    st.lists(st.floats(-10.0, 10.0), min_size=k, max_size=k))))}),
        hostile={"axis": st.sampled_from([(0.0, 0.0, 0.0), (math.nan, 1.0, 0.0), (1.0, 0.0),
                                          "x", None, np.ones((2, 3))]),
                 "momentum": st.sampled_from([math.nan, math.inf, "1", None, (1.0,),
                                              ([1.0, 0.0], [0.0, 1.0]),
                                              ([0.0, 1.0], [0.0, math.nan]),
                                              ([0.0, 1.0], [0.0, 1.0, 2.0]), ([0.0], [1.0]),
                                              np.ones(2)])},
        # the axis is kept as given, or as its unit vector: either way along the same line
        check=lambda kw, w, _: _assert(
            (w.momentum == kw["momentum"] if not isinstance(kw["momentum"], tuple) else
             w.momentum == (tuple(kw["momentum"][0]), tuple(kw["momentum"][1])))
            and np.allclose(np.cross(np.asarray(w.axis, dtype=float), kw["axis"]), 0.0,
                            atol=1e-12)),
        covers=(dz.Wheel,),
        min_success=0.9,
    ),
    "TabulatedTorque": Entry(
        call=dz.TabulatedTorque,
        valid=st.integers(2, 6).flatmap(lambda k: st.fixed_dictionaries(
            {"times": st.lists(st.floats(0.01, 10.0), min_size=k, max_size=k).map(
                lambda d: np.cumsum(d) - 1.0),
             "vectors": real_arrays((k, 3), st.floats(-10.0, 10.0))},
            optional={"frame": st.sampled_from(["body", "world"]),
                      "outside": st.sampled_from(["zero", "hold"])})),
        hostile={"times": st.sampled_from([[0.0], [1.0, 0.0, 2.0], [0.0, math.nan], "x", None,
                                           [[0.0, 1.0]], [0.0, 0.0]]),
                 "vectors": st.sampled_from([np.full((2, 3), math.nan), np.ones((2, 2)), "x",
                                             None, np.ones(3), np.ones((50, 3))]),
                 "frame": st.sampled_from(["Body", "orbit", "", None, 1]),
                 "outside": st.sampled_from(["Zero", "extrapolate", "", None, 0])},
        check=lambda kw, c, _: _assert(np.array_equal(c.times, kw["times"])
                                       and np.array_equal(c.vectors, kw["vectors"])),
        covers=(dz.TabulatedTorque,),
        min_success=0.9,
    ),
    "CallableTorque": Entry(
        call=dz.CallableTorque,
        valid=st.fixed_dictionaries({"func": st.sampled_from([
            lambda t, q, omega: -0.1 * omega, lambda t, q, omega: (0.0, 0.0, t), print])}),
        hostile={"func": st.one_of(st.sampled_from([None, (1.0, 2.0, 3.0), np.ones(3)]),
                                   st.floats(), st.integers(), st.text())},
        check=lambda kw, c, _: _assert(c.func is kw["func"]),
        covers=(dz.CallableTorque,),
        min_success=0.9,
    ),
    "lvlh_frame": Entry(
        call=dz.lvlh_frame,
        valid=st.fixed_dictionaries({"t": st.floats(0.0, 100.0),
                                     "orbit_rate": st.floats(1e-3, 10.0)}),
        hostile={"t": st.sampled_from([math.nan, "1", None, math.inf]),
                 "orbit_rate": st.sampled_from([0.0, -1.0, math.nan, "1", None])},
        check=lambda kw, q, _: _assert(np.shape(q) == (4,)
                                       and abs(np.linalg.norm(q) - 1.0) < 1e-12),
        covers=(dz.lvlh_frame,),
        min_success=0.9,
    ),
    "lvlh_attitude": Entry(
        call=dz.lvlh_attitude,
        valid=st.fixed_dictionaries({"traj": st.just(ORBIT_RUN), "orbit_rate": st.just(1.0)}),
        hostile={"traj": st.one_of(st.sampled_from([None, "traj", np.ones((3, 4))]),
                                   st.floats(), st.integers()),
                 "orbit_rate": st.one_of(st.sampled_from([math.nan, "1"]),
                                         st.floats(max_value=0.0))},
        check=lambda kw, q, _: _assert(np.shape(q) == np.shape(ORBIT_RUN.q) and np.allclose(
            np.linalg.norm(q, axis=-1), 1.0, atol=1e-12)),
        covers=(dz.lvlh_attitude,),
        examples=30,
        min_success=0.9,
    ),
    **{f.__name__: Entry(
        call=f,
        valid=st.fixed_dictionaries({"traj": st.just(ORBIT_RUN)},
                                    optional={"orbit_rate": st.floats(1e-3, 10.0)}),
        hostile={"traj": st.one_of(st.sampled_from([None, "traj", np.ones((3, 4))]),
                                   st.floats(), st.integers()),
                 "orbit_rate": st.one_of(st.sampled_from([math.nan, "1"]),
                                         st.floats(max_value=0.0))},
        check=lambda kw, a, _: _assert(np.shape(a) == np.shape(ORBIT_RUN.t) and bool(
            np.all((a >= 0.0) & (a <= math.pi)))),
        covers=(f,),
        examples=30,
        min_success=0.9,
    ) for f in (dz.lvlh_angles, dz.nadir_angles)},
    "lvlh_start": Entry(
        call=dz.lvlh_start,
        valid=st.fixed_dictionaries({"orbit_rate": st.floats(1e-3, 10.0)},
                                    optional={"pitch": st.floats(-1.0, 1.0)}),
        hostile={"orbit_rate": st.sampled_from([0.0, -1.0, math.nan, "1", None]),
                 "q_rel": st.sampled_from([(0.0, 0.0, 0.0, 0.0), (1.0, 0.0), "q", None]),
                 "omega_rel": st.sampled_from([(math.nan, 0.0, 0.0), (1.0,), "w", None]),
                 "pitch": st.sampled_from([math.nan, "0", None, math.inf])},
        check=lambda kw, start, _: _assert(
            np.shape(start[0]) == (3,) and abs(np.linalg.norm(start[1]) - 1.0) < 1e-12),
        covers=(dz.lvlh_start,),
        min_success=0.9,
    ),
    "pitch_libration_rate": Entry(
        call=dz.pitch_libration_rate,
        valid=st.fixed_dictionaries({"inertia": st.just((2.0, 3.0, 1.0)),
                                     "orbit_rate": st.floats(1e-3, 10.0)}),
        hostile={"inertia": st.sampled_from([(1.0, 3.0, 2.0), (1.0, 2.0), "I", None,
                                             (math.nan, 1.0, 1.0)]),
                 "orbit_rate": st.sampled_from([0.0, -1.0, math.nan, "1", None])},
        # Hughes §9.3: I_y θ'' + 3 n² (I_x − I_z) θ = 0, so ω_p = n √(3 (2 − 1) / 3) = n
        check=lambda kw, rate, _: _assert(abs(rate - kw["orbit_rate"])
                                          <= 1e-12 * kw["orbit_rate"]),
        covers=(dz.pitch_libration_rate,),
        min_success=0.9,
    ),
    "circular_orbit_rate": Entry(
        call=dz.circular_orbit_rate,
        valid=st.fixed_dictionaries({"altitude": st.floats(0.0, 1e8)}),
        hostile={"altitude": st.sampled_from([-7e6, math.nan, math.inf, "500 km", None]),
                 "mu": st.sampled_from([0.0, -1.0, math.nan, "mu"]),
                 "radius": st.sampled_from([0.0, -1.0, math.inf, "R"])},
        # Kepler: n² R³ = μ (WGS 84: μ = 3.986004418e14 m³/s², R_E = 6378137 m)
        check=lambda kw, n, _: _assert(abs(n * n * (6378137.0 + kw["altitude"]) ** 3
                                           / 3.986004418e14 - 1) < 1e-12),
        covers=(dz.circular_orbit_rate,),
        min_success=0.9,
    ),
    "detumble_gain": Entry(
        call=dz.detumble_gain,
        valid=st.fixed_dictionaries({"orbit_rate": st.floats(1e-5, 1e-2),
                                     "inclination": st.floats(0.0, math.pi),
                                     "least_moment": st.floats(1e-4, 1e4)}),
        hostile={"orbit_rate": st.sampled_from([0.0, -1e-3, math.nan, "n", None]),
                 "inclination": st.sampled_from([math.nan, math.inf, "polar", None]),
                 "least_moment": st.sampled_from([0.0, -1.0, math.inf, "J", None])},
        # Avanzini & Giulietti (JGCD 35(4), 2012): k* = 2 n (1 + sin ξ_m) J_min
        check=lambda kw, k, _: _assert(abs(k - 2 * kw["orbit_rate"] * (
            1 + math.sin(kw["inclination"])) * kw["least_moment"]) <= 1e-14 * abs(k)),
        covers=(dz.detumble_gain,),
        min_success=0.9,
    ),
    "MagneticField": Entry(
        call=dz.MagneticField,
        valid=st.fixed_dictionaries(
            {"orbit_rate": st.floats(1e-5, 1e-2), "inclination": st.floats(0.0, math.pi)},
            optional={"moment": st.floats(1e14, 1e17), "mu": st.floats(1e13, 1e15),
                      "tilt": st.floats(0.0, math.pi), "earth_rate": st.floats(-1e-4, 1e-4),
                      "longitude": st.floats(-10.0, 10.0)}),
        hostile={"orbit_rate": st.sampled_from([0.0, -1e-3, math.nan, math.inf, "n", None]),
                 "inclination": st.sampled_from([-0.1, 4.0, math.nan, "i", None]),
                 "moment": st.sampled_from([0.0, -1.0, math.inf, "m"]),
                 "mu": st.sampled_from([0.0, -1.0, math.nan, "mu"]),
                 "tilt": st.sampled_from([-0.1, 3.5, math.nan, "t", None]),
                 "earth_rate": st.sampled_from([math.nan, math.inf, "w", None]),
                 "longitude": st.sampled_from([math.nan, -math.inf, "l", None])},
        # kept as given, and a part in that field is made (the core checks it again)
        check=lambda kw, f, _: _assert(
            all(getattr(f, k) == v for k, v in kw.items())
            and dz.ResidualDipole(f, (0.0, 0.0, 1e-3)).field == f),
        covers=(dz.MagneticField,),
        min_success=0.9,
    ),
    "igrf_field": Entry(
        call=dz.igrf_field,
        valid=st.fixed_dictionaries(
            {"orbit_rate": st.floats(1e-3, 1.2e-3), "inclination": st.floats(0.0, math.pi),
             "epoch": st.sampled_from(["2020-06-01T00:00:00", "2025-03-20T12:00:00"]),
             "duration": st.floats(1.0, 600.0)},
            optional={"raan": st.floats(-7.0, 7.0), "latitude": st.floats(-7.0, 7.0),
                      "earth_turns": st.booleans(), "step": st.floats(5.0, 60.0),
                      "degree": st.integers(1, 13)}),
        hostile={"orbit_rate": st.sampled_from([0.0, -1e-3, math.nan, "n", None]),
                 "inclination": st.sampled_from([-0.1, 4.0, math.nan, "i", None]),
                 "epoch": st.sampled_from(["yesterday", 2025, None]),
                 "duration": st.sampled_from([0.0, -1.0, math.inf, "d", None]),
                 "raan": st.sampled_from([math.nan, "r", None]),
                 "latitude": st.sampled_from([math.inf, "u", None]),
                 "earth_turns": st.sampled_from([1, "yes", None]),
                 "step": st.sampled_from([0.0, -10.0, math.nan, 1e-9, "h"]),
                 "degree": st.sampled_from([0, 14, 1.5, "13", None])},
        # a table from 0 past `duration`, of a field of 10–70 µT (orbits at 150–990 km; the
        # weakest field at the ground is 22 µT, the strongest 67 µT)
        check=lambda kw, f, _: _assert(
            f.tabulated and f.field_times[0] == 0.0
            and f.field_times[-1] >= kw["duration"]
            and all(1e-5 < math.dist(v, (0.0, 0.0, 0.0)) < 7e-5 for v in f.field_values)),
        covers=(dz.igrf_field,),
        examples=30,
        min_success=0.9,
    ),
    "earth_rotation_angle": Entry(
        call=dz.earth_rotation_angle,
        valid=st.fixed_dictionaries({"epoch": st.datetimes(
            min_value=datetime.datetime(1900, 1, 1), max_value=datetime.datetime(2100, 1, 1))}),
        hostile={"epoch": st.sampled_from(["noon", 2000.0, None])},
        # IERS 2010 eq. 5.15: the angle in [0, 2π), and the same a stellar day (86164.0989 s)
        # later
        check=lambda kw, a, _: _assert(0.0 <= a < 2 * math.pi and abs(math.remainder(
            dz.earth_rotation_angle(kw["epoch"] + datetime.timedelta(seconds=86164.0989)) - a,
            2 * math.pi)) < 1e-6),
        covers=(dz.earth_rotation_angle,),
        examples=30,
        min_success=0.9,
    ),
    "Magnetometer": Entry(
        call=dz.Magnetometer,
        valid=st.fixed_dictionaries({}, optional={
            "noise": st.floats(0.0, 1e-5), "bias": real_arrays((3,), st.floats(-1e-5, 1e-5))}),
        hostile={"noise": st.sampled_from([-1e-7, math.nan, math.inf, "s", None]),
                 "bias": st.sampled_from([(math.nan, 0.0, 0.0), (1.0, 0.0), "b", None])},
        check=lambda kw, m, _: _assert(m.noise == kw.get("noise", 0.0) and np.array_equal(
            m.bias, kw.get("bias", np.zeros(3)))),
        covers=(dz.Magnetometer,),
        min_success=0.9,
    ),
    "Gyro": Entry(
        call=dz.Gyro,
        valid=st.fixed_dictionaries({}, optional={
            "angle_random_walk": st.floats(0.0, 1e-3),
            "bias": real_arrays((3,), st.floats(-1e-3, 1e-3))}),
        hostile={"angle_random_walk": st.sampled_from([-1e-7, math.nan, math.inf, "s", None]),
                 "bias": st.sampled_from([(math.nan, 0.0, 0.0), (1.0, 0.0), "b", None])},
        check=lambda kw, g, _: _assert(
            g.angle_random_walk == kw.get("angle_random_walk", 0.0)
            and np.array_equal(g.bias, kw.get("bias", np.zeros(3)))),
        covers=(dz.Gyro,),
        min_success=0.9,
    ),
    "StarTracker": Entry(
        call=dz.StarTracker,
        valid=st.fixed_dictionaries({}, optional={"noise": st.floats(0.0, 1e-2)}),
        hostile={"noise": st.sampled_from([-1e-7, math.nan, math.inf, "s", None])},
        check=lambda kw, t, _: _assert(t.noise == kw.get("noise", 0.0)),
        covers=(dz.StarTracker,),
        min_success=0.9,
    ),
    "ResidualDipole": Entry(
        call=dz.ResidualDipole,
        valid=st.fixed_dictionaries({"field": st.just(LOOP_FIELD),
                                     "dipole": real_arrays((3,), st.floats(-1.0, 1.0))}),
        hostile={"field": NOT_A_FIELD,
                 "dipole": st.sampled_from([(math.nan, 0.0, 0.0), (1.0, 0.0), "m", None,
                                            np.ones((2, 3))])},
        check=lambda kw, r, _: (_assert(np.array_equal(r.dipole, kw["dipole"])),
                                _loop_part(kw, r, "residual_dipole", True)) and None,
        covers=(dz.ResidualDipole,),
        min_success=0.9,
    ),
    "BDot": Entry(
        call=dz.BDot,
        valid=st.fixed_dictionaries(
            {"field": st.just(LOOP_FIELD), "gain": st.floats(0.0, 1e-3), "period": PERIODS},
            optional={"phase": st.floats(0.0, 10.0), "max_dipole": st.floats(1e-3, 1.0),
                      "rates": st.sampled_from(["magnetometer", "gyro"]),
                      "magnetometer": MAGNETOMETERS, "gyro": GYROS, "seed": SEEDS}),
        hostile={"field": NOT_A_FIELD,
                 "gain": st.sampled_from([-1.0, math.nan, math.inf, "k", None]),
                 "period": BAD_PERIODS, "phase": BAD_PHASES, "max_dipole": BAD_LIMITS,
                 "rates": st.sampled_from(["sun sensor", "", 1]),
                 "magnetometer": st.sampled_from([dz.Gyro(), "m", 1e-6]),
                 "gyro": st.sampled_from([dz.Magnetometer(), "g", 1e-6]),
                 "seed": BAD_SEEDS},
        check=lambda kw, b, _: _loop_part(kw, b, "bdot", True),
        covers=(dz.BDot,),
        min_success=0.9,
    ),
    "MomentumDumping": Entry(
        call=dz.MomentumDumping,
        valid=st.fixed_dictionaries(
            {"field": st.just(LOOP_FIELD), "gain": st.floats(0.0, 1.0), "period": PERIODS},
            optional={"phase": st.floats(0.0, 10.0), "max_dipole": st.floats(1e-3, 1.0),
                      "magnetometer": MAGNETOMETERS, "seed": SEEDS}),
        hostile={"field": NOT_A_FIELD,
                 "gain": st.sampled_from([-1.0, math.nan, math.inf, "k", None]),
                 "period": BAD_PERIODS, "phase": BAD_PHASES, "max_dipole": BAD_LIMITS,
                 "magnetometer": st.sampled_from([dz.Gyro(), "m", 1e-6]),
                 "seed": BAD_SEEDS},
        check=lambda kw, m, _: _loop_part(kw, m, "momentum_dumping", True),
        covers=(dz.MomentumDumping,),
        min_success=0.9,
    ),
    "QuaternionFeedback": Entry(
        call=dz.QuaternionFeedback,
        valid=st.fixed_dictionaries(
            {"kp": st.floats(1e-3, 10.0), "kd": st.floats(0.0, 10.0), "period": PERIODS},
            optional={"target": quaternions(), "phase": st.floats(0.0, 10.0),
                      "feedforward": st.sampled_from(["none", "gyroscopic"]),
                      "axes": WHEEL_AXES, "momentum": real_arrays((3,), st.floats(-1.0, 1.0)),
                      "torque_limit": st.floats(1e-3, 10.0),
                      "momentum_limit": st.floats(1.0, 100.0),
                      "star_tracker": STAR_TRACKERS, "gyro": GYROS, "seed": SEEDS}),
        hostile={"kp": st.sampled_from([-1.0, math.nan, "k", None, (1.0, 2.0)]),
                 "kd": st.sampled_from([-1.0, math.inf, "k", None]),
                 "period": BAD_PERIODS, "phase": BAD_PHASES,
                 "target": st.sampled_from([(0.0, 0.0, 0.0, 0.0), (1.0, 0.0), "q",
                                            (math.nan, 0.0, 0.0, 1.0)]),
                 "frame": st.sampled_from(["orbit", "", 1, "lvlh"]),
                 "feedforward": st.sampled_from(["all", "", 1]),
                 "axes": BAD_AXES, "momentum": BAD_MOMENTA,
                 "torque_limit": st.sampled_from([0.0, -1.0, math.nan, "t"]),
                 "momentum_limit": st.sampled_from([0.0, -1.0, math.nan, "h"]),
                 "star_tracker": st.sampled_from([dz.Gyro(), "s", 1e-3]),
                 "gyro": st.sampled_from([dz.StarTracker(), "g", 1e-3]),
                 "seed": BAD_SEEDS},
        # "lvlh" without an orbit rate is refused naming the rate
        aliases={"frame": ("orbit_rate",)},
        check=lambda kw, p, _: _loop_part(kw, p, "quaternion_feedback", False),
        covers=(dz.QuaternionFeedback,),
        min_success=0.9,
    ),
    "Controller": Entry(
        call=dz.Controller,
        valid=st.fixed_dictionaries(
            {"law": st.sampled_from([lambda t, q, w, b, h: -w,
                                     lambda t, q, w, b, h: (np.zeros(3), np.ones(3)),
                                     print]),
             "period": PERIODS},
            optional={"field": st.just(LOOP_FIELD), "phase": st.floats(0.0, 10.0),
                      "axes": WHEEL_AXES, "torque_limit": st.floats(1e-3, 10.0),
                      "momentum_limit": st.floats(1.0, 100.0),
                      "max_dipole": st.floats(1e-3, 1.0), "star_tracker": STAR_TRACKERS,
                      "gyro": GYROS, "magnetometer": MAGNETOMETERS, "seed": SEEDS}),
        hostile={"law": st.sampled_from([None, 3.0, "law", (1.0, 2.0, 3.0)]),
                 "period": BAD_PERIODS, "phase": BAD_PHASES,
                 "field": st.sampled_from([1e-3, "B", dz.Gyro()]),
                 "axes": BAD_AXES, "momentum": BAD_MOMENTA,
                 "torque_limit": st.sampled_from([0.0, -1.0, math.nan, "t"]),
                 "momentum_limit": st.sampled_from([0.0, -1.0, math.nan, "h"]),
                 "max_dipole": BAD_LIMITS,
                 "star_tracker": st.sampled_from([dz.Gyro(), "s"]),
                 "gyro": st.sampled_from([dz.StarTracker(), "g"]),
                 "magnetometer": st.sampled_from([dz.Gyro(), "m"]),
                 "seed": BAD_SEEDS},
        check=lambda kw, c, _: (_assert(c.law is kw["law"]),
                                _loop_part(kw, c, "controller", True)) and None,
        covers=(dz.Controller,),
        min_success=0.9,
    ),
    "pointing_angle": Entry(
        call=dz.pointing_angle,
        valid=st.fixed_dictionaries({"traj": st.just(LOOP_RUN)}),
        hostile={"traj": st.one_of(st.sampled_from([None, "traj", np.ones((3, 4)), ORBIT_RUN]),
                                   st.floats(), st.integers())},
        # the start is 2 atan2(0.6, 0.8) from the identity target (the initial attitude's)
        check=lambda kw, a, _: _assert(a.shape == LOOP_RUN.t.shape and abs(
            a[0] - 2 * math.atan2(0.6, 0.8)) < 1e-12 and bool(np.all((a >= 0) & (a <= math.pi)))),
        covers=(dz.pointing_angle,),
        min_success=0.9,
    ),
    "detumbled_at": Entry(
        call=dz.detumbled_at,
        valid=st.fixed_dictionaries({"traj": st.just(LOOP_RUN), "rate": st.floats(1e-6, 10.0)}),
        hostile={"traj": st.one_of(st.sampled_from([None, "traj", np.ones((3, 3))]),
                                   st.floats(), st.integers()),
                 "rate": st.one_of(st.sampled_from([math.nan, math.inf, "fast", None]),
                                   st.floats(max_value=0.0))},
        # the first frame's time from which |ω| stays below `rate` (inf: never), recomputed
        check=lambda kw, t, _: _assert(
            t == next((float(LOOP_RUN.t[k]) for k in range(len(LOOP_RUN.t))
                       if np.all(np.linalg.norm(LOOP_RUN.omega[k:], axis=1) < kw["rate"])),
                      math.inf)),
        covers=(dz.detumbled_at,),
        min_success=0.9,
    ),
    "part_state": Entry(
        call=dz.part_state,
        valid=st.fixed_dictionaries({"traj": st.just(LOOP_RUN),
                                     "kind": st.sampled_from(LOOP_KINDS)}),
        hostile={"traj": st.one_of(st.sampled_from([None, "traj", np.ones((3, 3))]),
                                   st.floats(), st.integers()),
                 "kind": st.one_of(st.sampled_from(["damper", "", None, "BDot"]), st.text(),
                                   st.integers())},
        # the fields side by side are the run's state of the part
        check=lambda kw, s, _: _assert(np.array_equal(
            np.concatenate(list(s.values()), axis=1), LOOP_RUN.parts[kw["kind"]])),
        covers=(dz.part_state,),
        min_success=0.9,
    ),
    "saturation": Entry(
        call=dz.saturation,
        valid=st.fixed_dictionaries({"traj": st.just(LOOP_RUN),
                                     "kind": st.sampled_from(LOOP_KINDS)}),
        hostile={"traj": st.one_of(st.sampled_from([None, "traj", np.ones((3, 3))]),
                                   st.floats(), st.integers()),
                 "kind": st.one_of(st.sampled_from(["damper", "", None, "residual_dipole"]),
                                   st.text(), st.integers())},
        # each flag is its bit of the saturated field, decoded here
        check=lambda kw, s, _: _assert(all(
            np.array_equal(v, (LOOP_RUN.parts[kw["kind"]][:, -1:].astype(int)
                               >> (3 * k + np.arange(3)) & 1).astype(bool))
            for k, v in enumerate(s.values()))),
        covers=(dz.saturation,),
        min_success=0.9,
    ),
    "dual_spin_threshold": Entry(
        call=dz.dual_spin_threshold,
        valid=st.fixed_dictionaries({"inertia": st.just((1.0, 2.0, 3.0)),
                                     "axis": st.sampled_from([0, 1, 2]),
                                     "rate": st.floats(0.1, 10.0)}),
        hostile={"inertia": st.sampled_from([(1.0, 2.0), "I", None, (math.nan, 1.0, 1.0)]),
                 "axis": st.sampled_from([3, -1, (0, 0, 1), "z", None, 1.5]),
                 "rate": st.sampled_from([math.nan, "1", None, math.inf])},
        check=lambda kw, pair, _: _assert(len(pair) == 2 and all(map(math.isfinite, pair))),
        covers=(dz.dual_spin_threshold,),
        min_success=0.9,
    ),
    # the maps run a batch each: few, short runs
    "dual_spin_map": Entry(
        call=dz.dual_spin_map,
        valid=st.fixed_dictionaries({
            "inertia": st.sampled_from([(1.0, 2.0, 3.0), (1e-3, 2e-3, 3e-3), (5.0, 1.0, 3.0)]),
            "momenta": st.lists(st.floats(-5.0, 5.0), min_size=1, max_size=3),
            "t_end": st.floats(1.0, 30.0), "frames": st.integers(2, 20)},
            optional={"axes": st.sampled_from([(0,), (1, 2), [2, 0, 1]]),
                      "rate": st.sampled_from([1.0, -2.0, 0.5]),
                      "nudge": st.floats(1e-8, 0.5), "limit": st.floats(1e-3, 3.0)}),
        hostile={"inertia": st.sampled_from([(1.0, 2.0), "I", None, (math.nan, 1.0, 1.0),
                                             (-1.0, 2.0, 3.0)]),
                 "momenta": st.sampled_from([[math.nan], "h", None, [], [[1.0]], [True],
                                             np.ones(2 * 10**6)]),
                 "axes": st.sampled_from([(3,), (1, 1), (), "y", None, (1.5,), (True,)]),
                 "rate": st.sampled_from([0.0, math.nan, "1", None, math.inf]),
                 "nudge": st.sampled_from([0.0, -1.0, 1.0, math.nan, "1", None]),
                 "t_end": st.sampled_from([0.0, -1.0, math.nan, "1"]),
                 "frames": st.sampled_from([1, 0, -3, 2.5, "10", None]),
                 "limit": st.sampled_from([0.0, 4.0, math.nan, "1", None])},
        check=lambda kw, m, _: _assert(
            m.departure.shape == m.predicted.shape == (len(m.axes), len(kw["momenta"]))
            and bool(np.isfinite(m.departure).all()) and bool((m.departure >= 0).all())
            and bool((m.departure <= math.pi + 1e-12).all())),
        covers=(dz.dual_spin_map, dz.DualSpinMap),
        warns=(dz.InertiaWarning, dz.StepSizeWarning),
        examples=30,
        min_success=0.5,
    ),
    "gravity_gradient_map": Entry(
        call=dz.gravity_gradient_map,
        valid=st.fixed_dictionaries({
            "k1": st.lists(st.floats(-0.9, 0.9), min_size=1, max_size=3),
            "k3": st.lists(st.floats(-0.9, 0.9), min_size=1, max_size=3),
            "orbits": st.floats(0.1, 3.0), "frames": st.integers(2, 20)},
            optional={"orbit_rate": st.floats(1e-3, 1e3), "perturbation": st.floats(1e-9, 0.4),
                      "limit": st.floats(1e-3, 3.0)}),
        hostile={"k1": st.sampled_from([[1.0], [-1.0], [math.nan], "k", None, [], [[0.1]]]),
                 "k3": st.sampled_from([[1.5], [math.inf], "k", None, [], [True]]),
                 "orbit_rate": st.sampled_from([0.0, -1.0, math.nan, "1", None]),
                 "perturbation": st.sampled_from([0.0, 0.5, -0.1, math.nan, "1"]),
                 "orbits": st.sampled_from([0.0, -1.0, math.inf, "1"]),
                 "frames": st.sampled_from([1, 0, 2.5, "10"]),
                 "limit": st.sampled_from([0.0, 4.0, math.nan, "1"])},
        check=lambda kw, m, _: _assert(
            m.deviation.shape == m.region.shape == (len(kw["k3"]), len(kw["k1"]))
            and bool(np.isfinite(m.deviation).all()) and bool((m.deviation >= 0).all())),
        covers=(dz.gravity_gradient_map, dz.GravityGradientMap),
        warns=(dz.InertiaWarning, dz.StepSizeWarning),
        examples=30,
        min_success=0.5,
    ),
    "gravity_gradient_region": Entry(
        call=dz.gravity_gradient_region,
        valid=st.fixed_dictionaries({"k1": st.floats(-0.999, 0.999),
                                     "k3": st.floats(-0.999, 0.999)}),
        hostile={"k1": st.sampled_from([1.0, -1.0, math.nan, "k", None, 2.0]),
                 "k3": st.sampled_from([1.0, math.inf, "k", None, -3.0])},
        # Hughes §9.3: pitch needs k1 > k3, roll–yaw k1 k3 > 0 (written out in test_stability)
        check=lambda kw, r, _: _assert(
            str(r) in ("lagrange", "debra_delp", "unstable")
            and (str(r) == "unstable" or (kw["k1"] > kw["k3"] and kw["k1"] * kw["k3"] > 0))),
        covers=(dz.gravity_gradient_region,),
        min_success=0.9,
    ),
    "gravity_gradient_moments": Entry(
        call=dz.gravity_gradient_moments,
        valid=st.fixed_dictionaries({"k1": st.floats(-0.999, 0.999),
                                     "k3": st.floats(-0.999, 0.999)}),
        hostile={"k1": st.sampled_from([1.0, -1.0, math.nan, "k", None, 2.0]),
                 "k3": st.sampled_from([1.0, math.inf, "k", None, -3.0])},
        check=lambda kw, i, _: _assert(
            i.shape == (3,) and bool((i > 0).all())
            and abs((i[1] - i[2]) / i[0] - kw["k1"]) < 1e-9
            and abs((i[1] - i[0]) / i[2] - kw["k3"]) < 1e-9),
        covers=(dz.gravity_gradient_moments,),
        min_success=0.9,
    ),
    "System": Entry(
        call=dz.System,
        valid=inertias().flatmap(lambda i: st.fixed_dictionaries(
            {"body": bodies(i)}, optional={"parts": dampers().map(lambda d: [d])})),
        hostile={"body": st.one_of(hostile_vector3(positive=True, moments=True),
                                   st.sampled_from(["box", None, dz.Damper(1.0, 1.0),
                                                    [[1.0, 0.0], [0.0, 1.0]], math.nan])),
                 "parts": st.sampled_from([[0.5], "damper", [dz.Damper(1.0, 1.0)] * 6, 3,
                                           [None], [dz.Body((1.0, 2.0, 3.0))],
                                           [dz.Damper(1.0, 1.0), None], {"damper": 1},
                                           np.array([1.0]), [dz.Damper(1.0, 1.0)] * 10**5,
                                           (dz.Damper(1.0, 1.0) for _ in range(1))]),
                 "torques": st.sampled_from([[0.5], "g", 1.0, [None], [dz.Damper(1.0, 1.0)],
                                             np.ones(3), {"x": 1.0}])},
        check=check_system,
        covers=(dz.System,),
        warns=(dz.InertiaWarning,),
        min_success=0.9,
    ),
    "Deployment": Entry(
        call=dz.Deployment,
        valid=deployment_args(),
        hostile={"times": st.one_of(JUNK.filter(lambda v: v is not None), st.sampled_from(
                     [[1.0, 1.0], [2.0, 1.0], [math.nan], [math.inf], [], 1.0, np.array(1.0),
                      ["a"], [[1.0]], [True], np.array([1, 2], dtype=complex)])),
                 "inertia": st.one_of(hostile_vector3(positive=True),
                                      st.just([np.array([[1.0, 2.0, 0.0], [2.0, 1.0, 0.0],
                                                         [0.0, 0.0, 1.0]])]),
                                      st.just(["x"]), st.just([[1.0, 2.0]]))},
        check=check_deployment,
        covers=(dz.Deployment,),
        warns=(dz.InertiaWarning,),
        min_success=0.9,
    ),
    "Damper": Entry(
        call=dz.Damper,
        valid=st.fixed_dictionaries({"inertia": valid_positive(),
                                     "damping": st.one_of(valid_positive(), st.just(0.0))},
                                    optional={"sigma0": layouts(np.array([0.1, -0.2, 1.0]))}
                                    ).filter(lambda k: math.isfinite(
                                        float(k["damping"]) / float(k["inertia"]))),
        hostile={"inertia": st.one_of(hostile_real(positive=True),
                                      st.sampled_from([True, 10**400, "0.1", -5e-324])),
                 "damping": st.one_of(hostile_real(positive=False),
                                      st.sampled_from([-1.0, -1e-300, 10**400, "1"])),
                 "sigma0": st.one_of(hostile_vector3().filter(lambda v: v is not None),
                                     st.sampled_from(["abc", [[1.0, 2.0, 3.0]], (1, 2, 3, 4),
                                                      np.array([1e308, -1e308, np.inf])]))},
        check=check_damper,
        covers=(dz.Damper,),
        min_success=1.0,
    ),
    "SpringMassDamper": Entry(
        call=dz.SpringMassDamper,
        valid=st.fixed_dictionaries(
            {"mass": st.floats(1e-3, 1.0), "anchor": real_arrays((3,), st.floats(-1.0, 1.0)),
             "direction": st.just((0.0, 0.0, 1.0)), "stiffness": st.floats(0.0, 10.0),
             "damping": st.floats(0.0, 1.0)},
            optional={"x0": st.floats(-0.1, 0.1), "rate0": st.floats(-0.1, 0.1)}),
        hostile={"mass": st.sampled_from([0.0, -1.0, math.nan, math.inf, "m", None]),
                 "anchor": SINK_VECTOR, "direction": SINK_VECTOR,
                 "stiffness": st.sampled_from([-1.0, math.nan, math.inf, "k", None]),
                 "damping": st.sampled_from([-1.0, math.nan, math.inf, "c", None]),
                 "x0": st.sampled_from([math.nan, math.inf, "x"])},
        check=lambda kw, p, _: _assert(p.mass == kw["mass"] and p.model == "spring_mass"),
        covers=(dz.SpringMassDamper,),
        min_success=0.9,
    ),
    "Hinge": Entry(
        call=dz.Hinge,
        valid=st.fixed_dictionaries(
            {"mass": st.floats(1e-3, 1.0), "moments": st.just((1e-4, 0.01, 0.01)),
             "hinge": real_arrays((3,), st.floats(-1.0, 1.0)), "axis": st.just((0.0, 0.0, 1.0)),
             "arm": st.just((1.0, 0.0, 0.0)), "length": st.floats(0.01, 1.0),
             "stiffness": st.floats(0.0, 10.0), "damping": st.floats(0.0, 1.0)},
            optional={"angle0": st.floats(-0.5, 0.5), "rate0": st.floats(-0.1, 0.1)}),
        hostile={"mass": st.sampled_from([0.0, -1.0, math.nan, math.inf, "m", None]),
                 "hinge": SINK_VECTOR, "axis": SINK_VECTOR, "arm": SINK_VECTOR,
                 "length": st.sampled_from([math.nan, math.inf, "l", None]),
                 "stiffness": st.sampled_from([-1.0, math.nan, math.inf, "k", None]),
                 "damping": st.sampled_from([-1.0, math.nan, math.inf, "c", None])},
        check=lambda kw, p, _: _assert(p.mass == kw["mass"] and p.model == "hinge"),
        covers=(dz.Hinge,),
        min_success=0.9,
    ),
    "Slosh": Entry(
        call=dz.Slosh,
        valid=st.fixed_dictionaries(
            {"mass": st.floats(1e-3, 1.0), "pivot": real_arrays((3,), st.floats(-1.0, 1.0)),
             "length": st.floats(0.01, 1.0), "damping": st.floats(0.0, 1.0),
             "direction0": st.just((1.0, 0.0, 0.0))}),
        hostile={"mass": st.sampled_from([0.0, -1.0, math.nan, math.inf, "m", None]),
                 "pivot": SINK_VECTOR, "direction0": SINK_VECTOR,
                 "length": st.sampled_from([0.0, -1.0, math.nan, math.inf, "l", None]),
                 "damping": st.sampled_from([-1.0, math.nan, math.inf, "c", None])},
        check=lambda kw, p, _: _assert(p.mass == kw["mass"] and p.model == "slosh"),
        covers=(dz.Slosh,),
        min_success=0.9,
    ),
    "damper_rate": Entry(
        call=dz.damper_rate,
        valid=inertias().flatmap(lambda i: st.fixed_dictionaries(
            {"body": bodies(i), "damper": dampers().filter(
                # a rate c (1/j + 1/I_min) float64 holds (else it is refused, naming both)
                lambda d, i=i: float(d.damping) / float(d.inertia)
                + float(d.damping) / float(min(i)) < LARGEST)})),
        hostile={"body": hostile_vector3(positive=True, moments=True),
                 "damper": st.sampled_from([0.5, "d", None, (0.1, 0.2)])},
        check=check_damper_rate,
        covers=(dz.damper_rate,),
        warns=(dz.InertiaWarning,),
        min_success=0.9,
    ),
    "flat_spin_estimate": Entry(
        call=dz.flat_spin_estimate,
        valid=estimate_args(),
        hostile={"body": hostile_vector3(positive=True, moments=True),
                 "damper": st.sampled_from([0.5, "d", None]),
                 "omega0": hostile_vector3(), "sigma0": hostile_vector3().filter(lambda v: v is not None),
                 "share": st.one_of(hostile_real(positive=True), st.sampled_from([1.0, 2.0]))},
        check=check_estimate,
        covers=(dz.flat_spin_estimate,),
        warns=(dz.InertiaWarning,),
        min_success=0.9,
    ),
    "summarize": Entry(
        call=dz.summarize,
        valid=st.sampled_from(FREE_METHODS).flatmap(lambda m: run_args(m, flips=False)),
        hostile=run_hostile(tuple(dz.METHODS), flips=False),
        check=check_summary,
        covers=(dz.summarize, dz.Summary),
        warns=(dz.StepSizeWarning, dz.InertiaWarning),
        min_success=0.2,
    ),
    "rotate": Entry(
        call=dz.rotate,
        valid=rotate_args(),
        # (N, 4) rows of quaternions are what rotate takes: not hostile to it
        hostile={"q": hostile_quaternion().filter(lambda v: not batch_rows_of(v, 4)),
                 "points": hostile_array((None, 3), real_arrays((2, 3), st.floats(-1, 1)),
                                                                    extra=[st.just(np.full((2, 3), 1e308))]),
                 "out": hostile_out},
        check=check_rotate,
        covers=(dz.rotate,),
        min_success=0.9,
    ),
    "flip_period": Entry(
        call=dz.flip_period,
        valid=st.tuples(inertias(), directions(3), st.sampled_from([0, 0, -1000, -60, 60, 500, 1010]))
        .flatmap(lambda a: st.fixed_dictionaries({"body": bodies(a[0]), "omega0": layouts(scaled(a[1], a[2]))})),
        hostile={"body": hostile_vector3(positive=True, moments=True),
                 # (M, 3) rows are M starts (test_body_conventions.py), not hostile
                 "omega0": hostile_vector3().filter(lambda v: not batch_rows_of(v, 3))},
        check=check_flip_period,
        covers=(dz.flip_period,),
        warns=(dz.InertiaWarning,),
        min_success=0.5,
    ),
    "ellipsoid_semi_axes": Entry(
        call=dz.ellipsoid_semi_axes,
        valid=inertias().flatmap(lambda i: st.fixed_dictionaries(
            {"body": bodies(i)}, optional={"convention": st.sampled_from(CONVENTIONS)})),
        hostile={"body": hostile_vector3(positive=True, moments=True), "convention": hostile_name(CONVENTIONS)},
        check=check_semi_axes,
        covers=(dz.ellipsoid_semi_axes,),
        warns=(dz.InertiaWarning,),
        min_success=0.9,
    ),
    "ellipsoid_mesh": Entry(
        call=dz.ellipsoid_mesh,
        valid=mesh_args(),
        hostile={"semi_axes": hostile_vector3(positive=True), "n_around": hostile_int(3),
                 "n_along": hostile_int(2)},
        check=check_mesh,
        covers=(dz.ellipsoid_mesh,),
        min_success=0.9,
    ),
    "box_vertices": Entry(
        call=dz.box_vertices,
        valid=st.fixed_dictionaries({}, optional={k: valid_positive(1e-300, 1e300) for k in "abc"}),
        hostile={k: hostile_real(positive=True) for k in "abc"},
        check=check_box_vertices,
        covers=(dz.box_vertices, dz.BOX_SIZE),
        min_success=0.9,
    ),
    "Scene": Entry(
        call=dz.Scene,
        valid=scene_fields(),
        hostile=scene_hostile(),
        check=check_scene,
        covers=(dz.Scene, dz.SceneError),
        warns=(dz.InertiaWarning,),
        aliases=SCENE_ALIASES,
        min_success=0.9,
    ),
    "Scene.from_toml": Entry(
        call=dz.Scene.from_toml,
        valid=toml_texts().flatmap(lambda t: st.fixed_dictionaries(
            {"text": st.just(t), "name": st.from_regex(NAME_RE, fullmatch=True)})),
        hostile={"text": hostile_toml(), "name": scene_hostile()["name"]},
        check=check_loaded,
        covers=(dz.Scene,),
        aliases={"text": ("TOML", "title", "about", "body", "start", "run", "ask", "draw",
                          "ellipsoid")},
        warns=(dz.InertiaWarning,),
        min_success=0.9,
    ),
    "load_scene": Entry(
        call=dz.load_scene,
        valid=scene_paths().map(lambda p: {"path": p}),
        hostile={"path": hostile_paths()},
        check=check_loaded,
        covers=(dz.load_scene, dz.SCENES, dz.PAPER_SCENES, dz.PAPER_INERTIA),
        named_by_value=("path",),
        warns=(dz.InertiaWarning,),
        min_success=0.9,
    ),
    "make_plan": Entry(
        call=dz.scenes.make_plan,
        valid=scene_fields().map(quiet_scene).map(lambda s: {"scene": s}),
        hostile={"scene": hostile_scene_objects()},
        check=check_plan,
        covers=(dz.scenes.make_plan, dz.scenes.Plan),
        min_success=1.0,
    ),
    "execute": Entry(
        call=dz.scenes.execute,
        valid=scene_fields().map(quiet_scene).map(lambda s: {"plan": dz.scenes.make_plan(s)}),
        hostile={"plan": st.one_of(hostile_scene_objects(), st.just(dz.SCENES["fig3a"]))},
        check=check_result,
        covers=(dz.scenes.execute, dz.scenes.SceneResult),
        aliases={"plan": SCENE_WORDS},
        warns=(dz.StepSizeWarning, dz.InertiaWarning),
        min_success=0.3,
    ),
    "plotting.polhodes": Entry(
        call=plotting.polhodes,
        valid=polhode_args(),
        hostile={"inertia": hostile_vector3(positive=True, moments=True), "energy": hostile_real(positive=False),
                 "levels": hostile_int(0), "points": hostile_int(2)},
        check=check_polhodes,
        min_success=0.9,
    ),
    **{
        f"plotting.{name}": Entry(
            call=plotting.FIGURE_FUNCTIONS[name],
            valid=figure_args(name),
            hostile={"scene": hostile_scene_objects()},
            check=check_figure,
            examples=12,
            aliases={"scene": SCENE_WORDS},
            warns=(dz.StepSizeWarning, dz.InertiaWarning),
            min_success=0.3,
        )
        for name in plotting.FIGURE_FUNCTIONS
    },
}

NOT_CALLED = {
    "__version__": "a string",
    "StepSizeWarning": "a warning class, raised by simulate (allowed in its entries)",
    "MAX_PREDICTED_DRIFT": "a constant, used by the simulate checks",
    "SIGNAL_POINT": "a constant array",
    "box_edges": "takes no arguments: test_hostile calls it once",
    "Scenario": "another name of Scene",
    "FLAT_SHARE": "a constant, the default of flat_spin_time",
    "SYMMETRY_TOLERANCE": "a constant, the core's (test_bodies.py: symmetric tops)",
    "NEAR_SYMMETRY": "a constant, the core's (test_bodies.py: the near-symmetry warning)",
    "StiffDamperWarning": "a warning class, raised by simulate of a stiff damper "
                          "(test_model_batches.py)",
    "DzhanibekovError": "an exception class, raised by the core (test_errors.py)",
    "DivergedError": "an exception class, raised by the core (test_errors.py)",
    "TooLargeError": "an exception class, raised by the core (test_errors.py)",
    "io": "a module: its functions' bad input is tested in test_io.py and by the file corpus",
    "save": "writes a file: test_io.py and test_files.py (all or nothing)",
    "load": "reads a file: every file of the corpus (test_hostile.py::"
            "test_every_reader_on_every_file) and test_io.py",
    "ReadError": "an exception class, raised by the readers (the file corpus)",
    "MODELS": "a read-only mapping of the core's declarations (test_model_registry.py)",
    "ModelInfo": "the class of MODELS' values, made by the core only",
    "RunOptions": "a frozen record of run options, checked when a run starts: simulate's, "
                  "summarize's and sweep's entries pass every option (test_run_options.py: "
                  "options= and the keywords agree)",
    "RunKeywords": "a TypedDict, for typing only",
}
