"""Results as netCDF-4 files: :func:`save` (xarray and h5netcdf) and :func:`load` (h5py),
the ``io`` extra.

A file holds the layout of ``result.to_xarray()`` plus the attribute
``dzhanibekov_result`` naming the kind. Arrays round-trip bit for bit.

**Writing** is all or nothing: the file is built in memory (h5py never writes to the disk, so
a full disk cannot leave HDF5 half-closed — h5netcdf closing such a file again crashed the
interpreter), then written to a temporary file beside `path` and renamed over it
(:mod:`dzhanibekov._files`). After any failure, Ctrl-C included, the previous file is as it
was.

**Reading** checks what it reads as strictly as a run checks what it computes, against one
table per kind (:data:`LAYOUTS`): each variable's dimensions, type and values (finite, unit
quaternions to the run's own recorded drift, times that start at 0 and increase, flip
counts that match the flip times …), each attribute, and the rules that tie them together;
then each run's system is rebuilt (its wheels and torques from their tables, padded between a
batch's runs: each part's fields under its model, :mod:`dzhanibekov.parts._columns`; files of
earlier versions by :mod:`dzhanibekov._legacy_parts`;
the core checks its body, deployment, parts and torques as when
the run was made) and what the loaded result derives from it (principal moments, energy,
angular momentum) must be what the file says. Every failure is a :class:`~dzhanibekov.io.ReadError` (a ValueError) naming the file and
what is wrong. A new field of a result is one row of its table.
"""

from __future__ import annotations

import io
import math
import re
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from . import _core, _legacy_parts, _tables
from . import control  # noqa: F401  (its parts register: the layout holds every model's columns)
from ._args import check_size
from ._files import HDF5_SIGNATURE, ReadError, as_path, describe, open_regular, replacing
from .body import Body, InertiaWarning, tensor_moments
from .deployment import Deployment
from .methods import METHODS
from .parts import _columns, params_of
from . import montecarlo
from .montecarlo import MonteCarlo
from .results import Batch, BatchDrift, DeploymentSweep, Sweep, Trajectory, split_parts
from .shapes import Shape
from .system import System, Systems

__all__ = ["save", "load", "LAYOUTS", "SUFFIXES", "KIND_ATTRIBUTE", "PART_NAMES"]

KIND_ATTRIBUTE = "dzhanibekov_result"
"""The attribute naming the kind of result a file holds."""

SUFFIXES = (".nc", ".nc4", ".netcdf", ".h5", ".hdf5")
"""The suffixes :func:`save` writes (netCDF-4 is HDF5): another suffix is refused rather
than given a format it does not name."""

_OTHER_FORMATS = {
    ".aem": "for a CCSDS AEM use dz.io.write_aem",
    ".csv": "for CSV use result.to_dataframe().to_csv(path)",
    ".parquet": "for Parquet use result.to_dataframe().to_parquet(path)",
    ".html": "for the viewer use dz.viewer.write_html",
    ".json": "for a scene's summary use the CLI (`dzhanibekov run`)",
    ".toml": "for a scene use Scene.save",
    ".zarr": "for Zarr use result.to_xarray().to_zarr(path)",
}

_EPS = float(np.finfo(np.float64).eps)


# -- the table -------------------------------------------------------------------------------

Check = Callable[[np.ndarray], "str | None"]
"""A check of a variable's values: None if they are allowed, else what is wrong."""


@dataclass(frozen=True)
class Var:
    """A variable of a layout.

    `dims` are dimension names; ``"*"`` stands for the grid dimensions of a sweep (one or
    more, whatever their names). `kind` is ``"f"`` (float64), ``"i"`` (integers), ``"n"``
    (either) or ``"U"`` (text). `checks` are applied in order to the values."""

    dims: tuple[str, ...]
    kind: str
    checks: tuple[Check, ...] = ()
    optional: bool = False


@dataclass(frozen=True)
class Attr:
    """An attribute of a layout: `kind` as for :class:`Var` (a scalar, an array of `shape`,
    or for `shape` None a list of any length: a list of names), and its checks."""

    kind: str
    checks: tuple[Check, ...] = ()
    shape: tuple[int, ...] | None = ()
    optional: bool = False


Rule = Callable[["Loaded"], "str | None"]
"""A rule tying several fields together: None if they agree, else what is wrong."""


@dataclass(frozen=True)
class Layout:
    """What a file of one kind holds, and how to build the result from it."""

    variables: Mapping[str, Var]
    attrs: Mapping[str, Attr]
    rules: tuple[Rule, ...]
    build: Callable[[Loaded], Any]
    after: Callable[[Loaded, Any], str | None] | None = None
    """A check of the built result against the file (what it derives from its own system
    against what the file says it derived): None if they agree, else what is wrong."""
    sizes: Mapping[str, int] = field(default_factory=dict)
    """Dimensions of a fixed length (``axis``: 3, ``quaternion``: 4)."""
    least: Mapping[str, int] = field(default_factory=dict)
    """Dimensions of a least length (``time``: 2)."""
    state: Callable[[str], Var | None] | None = None
    """The layout of the parts' state variables, by name (any number of parts of a model:
    ``damper``, or ``damper_0``, ``damper_1``, … see :func:`state_vars`), beside
    `variables`."""
    grid_coordinates: bool = False
    """Whether 1-D coordinates of the grid dimensions (a sweep's ``u0``, ``Iz`` …, named
    for their dimension) may be there besides `variables`."""


@dataclass
class Loaded:
    """A file's variables and attributes, checked one by one, for the rules and the build."""

    values: dict[str, np.ndarray]
    attrs: dict[str, Any]

    def __getitem__(self, name: str) -> Any:
        return self.values[name] if name in self.values else self.attrs[name]

    def __contains__(self, name: str) -> bool:
        return name in self.values or name in self.attrs


# -- checks of values --------------------------------------------------------------------------


def finite(a: np.ndarray) -> str | None:
    return None if np.isfinite(a).all() else "holds NaN or infinite values"


def finite_or_nan(a: np.ndarray) -> str | None:
    return None if not np.isinf(a).any() else "holds infinite values"


def non_negative(a: np.ndarray) -> str | None:
    return None if not (a < 0).any() else f"holds negative values ({a[a < 0].flat[0].item()!r})"


def positive(a: np.ndarray) -> str | None:
    return None if (a > 0).all() else "must be positive"


def positive_or_nan(a: np.ndarray) -> str | None:
    return None if not (a <= 0).any() else "must be positive (or NaN)"


def starts_at_zero_and_increases(t: np.ndarray) -> str | None:
    if t[0] != 0.0:
        return f"must start at 0, starts at {t[0]!r}"
    if not (np.diff(t) > 0).all():
        k = int(np.argmax(~(np.diff(t) > 0)))
        return f"must increase, but t[{k + 1}] = {t[k + 1]!r} follows t[{k}] = {t[k]!r}"
    return None


def one_of(allowed: tuple[str, ...]) -> Check:
    def check(a: np.ndarray) -> str | None:
        bad = [v for v in np.ravel(a) if str(v) not in allowed]
        return None if not bad else f"must be one of {list(allowed)}, got {str(bad[0])!r}"
    return check


def flag(a: np.ndarray) -> str | None:
    return None if np.isin(a, (0, 1)).all() else "must be 0 or 1"


def labels(names: tuple[str, ...]) -> Check:
    def check(a: np.ndarray) -> str | None:
        got = [str(v) for v in np.ravel(a)]
        return None if got == list(names) else f"must be {list(names)}, got {got}"
    return check


def moments(a: np.ndarray) -> str | None:
    """Principal moments a Body takes (each row)."""
    for row in np.reshape(a, (-1, 3)):
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", InertiaWarning)
                Body(row)
        except (TypeError, ValueError) as exc:
            return f"are no body's principal moments: {exc}"
    return None


def _is_unit_enough(q: np.ndarray, drift: np.ndarray) -> str | None:
    """`q` (..., N, 4) unit to within its run's recorded `drift` of ``|q|`` (...,)."""
    drift = np.asarray(drift)
    if not (drift < 1.0).all():
        return "`drift_q_norm` must be below 1 (|q| between 0 and 2: a rotation)"
    norm = np.sqrt(np.einsum("...i,...i->...", q, q))
    off = np.abs(norm - 1.0).max(axis=-1, initial=0.0)
    excess = off - (drift * (1 + 1e-9) + 8 * _EPS)
    if (excess > 0).any():
        k = np.unravel_index(int(np.argmax(excess)), np.shape(excess))
        where = f" (run {k[0]})" if k else ""
        return (f"`q` must be unit quaternions to the run's recorded drift of |q|{where}: "
                f"they depart from unit norm by {float(off[k]):.3g}, the file's "
                f"`drift_q_norm` says {float(drift[k]):.3g}")
    return None


def _flip_times_within(times: np.ndarray, t_end: float) -> str | None:
    if not np.isfinite(times).all():
        return "`flip_times` holds NaN or infinite values"
    if times.size and (times.min() < 0 or times.max() > t_end):
        return f"`flip_times` must lie in [0, t_end = {t_end!r}]"
    if not (np.diff(times) >= 0).all():
        return "`flip_times` must not decrease"
    return None


# -- rules ------------------------------------------------------------------------------------


def trajectory_q_unit(d: Loaded) -> str | None:
    return _is_unit_enough(d["q"], np.asarray(d["drift_q_norm"]))


def trajectory_flips(d: Loaded) -> str | None:
    located = int(d["flips_located"])
    if located != ("flip_times" in d.values):
        return ("`flips_located` says flips were " + ("" if located else "not ")
                + "located, but `flip_times` is " + ("missing" if located else "there"))
    if located:
        return _flip_times_within(d["flip_times"], float(d["time"][-1]))
    return None


def batch_q_unit(d: Loaded) -> str | None:
    return _is_unit_enough(d["q"], d["drift_q_norm"])


def batch_flips(d: Loaded) -> str | None:
    if ("flips" in d.values) != ("flip_times" in d.values):
        return "`flips` and `flip_times` must both be there, or neither"
    if "flips" not in d.values:
        return None
    counts, padded = d["flips"], d["flip_times"]
    if padded.shape[1] != int(counts.max(initial=0)):
        return (f"`flip_times` must have as many columns as the most `flips` of a run "
                f"({int(counts.max(initial=0))}), got {padded.shape[1]}")
    t_end = float(d["time"][-1])
    for i, c in enumerate(counts):
        row = padded[i]
        if not np.isnan(row[c:]).all():
            return (f"run {i} flipped {c} times by `flips`, but `flip_times` holds more "
                    "(it must be NaN beyond each run's flips)")
        problem = _flip_times_within(row[:c], t_end)
        if problem:
            return f"run {i}: {problem} ({c} flips by `flips`)"
    return None


def run_numbers(d: Loaded) -> str | None:
    run = d["run"]
    return None if np.array_equal(run, np.arange(len(run))) else "`run` must be 0, 1, 2, …"


def sweep_outcomes(d: Loaded) -> str | None:
    """A finished run's numbers are finite and agree with its flip count; an unfinished
    run's are NaN, with flips −1."""
    ok = d["status"] == "ok"
    flips = d["flips"]
    t_end = float(d["t_end"])
    drifts = [d[f"drift_{k}"] for k in _tables.DRIFTS]
    if (flips[~ok] != -1).any():
        return "`flips` must be -1 for a run that did not finish (`status` not 'ok')"
    if (flips[ok] < 0).any():
        return "`flips` must be at least 0 for a run that finished"
    nan_when_unfinished = [("first_flip", d["first_flip"]), ("period", d["period"]),
                           ("tilt", d["tilt"]), ("dt", d["dt"])] + \
        [(f"drift_{k}", v) for k, v in zip(_tables.DRIFTS, drifts)]
    for name, v in nan_when_unfinished:
        if not np.isnan(v[~ok]).all():
            return f"`{name}` must be NaN for a run that did not finish"
    first, period = d["first_flip"][ok], d["period"][ok]
    n = flips[ok]
    if np.isnan(first[n >= 1]).any() or not np.isnan(first[n == 0]).all():
        return "`first_flip` must be a time exactly for the runs with at least one flip"
    if np.isnan(period[n >= 2]).any() or not np.isnan(period[n < 2]).all():
        return "`period` must be a time exactly for the runs with at least two flips"
    if ((first[n >= 1] < 0) | (first[n >= 1] > t_end)).any():
        return f"`first_flip` must lie in [0, t_end = {t_end!r}]"
    if (period[n >= 2] > t_end).any():
        return f"`period` must be at most t_end = {t_end!r}"
    tilt = d["tilt"][ok]
    if ((tilt < 0) | (tilt > math.pi * (1 + 4 * _EPS))).any():
        return "`tilt` must lie in [0, π]"
    for name, v in [("dt", d["dt"])] + [(f"drift_{k}", v) for k, v in
                                        zip(_tables.DRIFTS, drifts)]:
        if not np.isfinite(v[ok]).all() or (v[ok] < 0).any():
            return f"`{name}` must be finite and non-negative for a run that finished"
    q0 = d["q0"]
    if not (np.abs(q0).max(axis=-1, initial=0.0) > 0).all():
        return "`q0` must be non-zero quaternions"
    return None


# -- the system a file describes ------------------------------------------------------------------

PART_NAMES = tuple(m.name for m in _core.MODELS if m.state and not m.law)
"""The models of parts with state: a file names each such part (``parts``) as a run shows its
state (the model's name, or ``<model>_<k>`` for the ``k``-th of several,
:func:`dzhanibekov._tables.model_of_state`), with its state variables under that name."""


def state_vars(name: str) -> dict[str, tuple[str, ...]]:
    """The variables of the state of the part shown as `name` and their dims after ``time``,
    as `_tables._derived` writes them: the part's name for a state of one 3-vector (a
    damper's σ), else one variable per field, ``<name>_<field>``."""
    return {var: _tables.state_dims(var, width)
            for var, _, width, _ in _tables.state_fields(name)}


def _part_state_name(name: str) -> bool:
    """Whether `name` is how a run shows the state of a part a file can hold."""
    return _tables.model_of_state(name) in PART_NAMES


def _state_owner(variable: str) -> str | None:
    """The part (as a run shows its state) whose state variable `variable` is, if any."""
    head = variable
    while head:
        if _part_state_name(head) and variable in state_vars(head):
            return head
        head = head.rpartition("_")[0]
    return None


def _state_var(lead: tuple[str, ...]) -> Callable[[str], Var | None]:
    """The layout of a part's state variable named `variable` (whatever the part's place
    among those of its model), or None if it is no part's state variable."""
    def var(variable: str) -> Var | None:
        owner = _state_owner(variable)
        if owner is None:
            return _rate_var(lead, variable)
        return Var(lead + ("time",) + state_vars(owner)[variable], "f", (finite,),
                   optional=True)
    return var


def _moves_mass(name: str) -> bool:
    """Whether the part shown as `name` moves mass in the body (has coordinate rates)."""
    return "moving mass" in _core.model_info(_tables.model_of_state(name) or "").traits


def _rate_var(lead: tuple[str, ...], variable: str) -> Var | None:
    """The layout of `variable` if it holds the coordinates' rates of a part whose mass
    moves (``hinge_angle_rate``, see `_tables.rate_variable`), else None."""
    base, _, tail = variable.rpartition("_")
    owner = _state_owner(base) if tail == "rate" else None
    if owner is None or not _moves_mass(owner) or _tables.rate_variable(owner)[0] != variable:
        return None
    return Var(lead + ("time",) + state_vars(owner)[base], "f", (finite,), optional=True)


def _state_of(d: Loaded, name: str) -> np.ndarray:
    """Part `name`'s state, its fields side by side (..., time, width), as a run gives it."""
    return np.concatenate([d[v] if dims else d[v][..., None]
                           for v, dims in state_vars(name).items()], axis=-1)


_BODY_VARS = ("body_tensor", "body_mass", "body_center_of_mass")
_SHAPE_VARS = ("body_vertices", "body_edges", "body_faces")
_KNOT_VARS = ("knot_times", "knot_tensors")
_DERIVED = ("energy", "momentum_body", "momentum_world")
_KEPT = (*_tables.DRIFTS, *_tables.OPTIONAL_DRIFTS)


def _runs(d: Loaded) -> int | None:
    """How many runs the file holds: None for one run (no ``run`` dimension)."""
    return len(d["run"]) if "run" in d.values else None


def system_parts(d: Loaded) -> str | None:
    """The system is described once, completely: a body (tensor, mass, centre of mass) or a
    deployment's knots, and each named part's parameters and state; none for an empty
    batch."""
    runs = _runs(d)
    states = [name for name in d.values if _state_owner(name) is not None]
    present = [name for name in (*_BODY_VARS, *_KNOT_VARS, *_legacy_parts.NAMES, *_DERIVED)
               if name in d.values] + states
    present += [name for name in d.values if name.startswith("part_")]
    if runs == 0:
        return None if not present else f"`{present[0]}` must not be there: the batch is empty"
    body = [name in d.values for name in _BODY_VARS]
    knots = [name in d.values for name in _KNOT_VARS]
    if not (all(body) and not any(knots)) and not (all(knots) and not any(body)):
        return ("the system's body must be given once: `body_tensor`, `body_mass` and "
                "`body_center_of_mass`, or `knot_times` and `knot_tensors`")
    if "knot_mass" in d.values and not all(knots):
        return "`knot_mass` must come with `knot_times` and `knot_tensors` (a deployment's)"
    parts = tuple(d["parts"]) if "parts" in d.attrs else ()
    for name in parts:
        for var in state_vars(name):
            if var not in d.values:
                return (f"the attribute `parts` names the {name}, but its state `{var}` is "
                        "missing")
    for var in states:
        if _state_owner(var) not in parts:
            return (f"the attribute `parts` does not name the {_state_owner(var)}, but its "
                    f"state `{var}` is there")
    outline = [name in d.values for name in _SHAPE_VARS]
    if any(outline) and (not all(outline[:2]) or not all(body)):
        return "`body_vertices` and `body_edges` must be there together, with the body's tensor"
    if all(outline[:2]):
        v = len(d["body_vertices"])
        for name in _SHAPE_VARS[1:]:
            if name in d.values and (d[name] >= v).any():
                return f"`{name}` must be indices of `body_vertices` (0 … {v - 1})"
    missing = [name for name in _DERIVED if name not in d.values]
    if missing:
        return f"`{missing[0]}` is missing"
    if "knot_times" in d.values:
        problem = _knots_padded(d["knot_times"], d["knot_tensors"])
        if problem:
            return problem
    legacy = [name for name in _legacy_parts.NAMES if name in d.values]
    generic = [name for name in d.values if name.startswith("part_")]
    if legacy and generic:
        return (f"`{legacy[0]}` (the layout of files before dzhanibekov wrote parts by their "
                f"model) must not be there beside `{generic[0]}`")
    if legacy:
        return _legacy_parts.check(d)
    try:
        found = _columns.parts_of(d.values, runs)
    except (TypeError, ValueError):  # a part the core refuses: the build says so
        return None
    if isinstance(found, str):
        return found
    for row in found:
        named = _tables.state_names(p.model for p in (*row[0], *row[1])
                                    if p.model in PART_NAMES)
        if named != list(parts):
            return (f"the attribute `parts` names {list(parts)}, but the parts with state of "
                    f"`part_kind` are shown as {named}")
    return None


def _knots_padded(times: np.ndarray, tensors: np.ndarray) -> str | None:
    """Each run's knots first, then NaN to the common length (tensors NaN exactly there)."""
    times = times.reshape(-1, times.shape[-1])
    tensors = tensors.reshape(len(times), -1, 9)
    for i, (t, k) in enumerate(zip(times, tensors)):
        nan = np.isnan(t)
        n = int((~nan).sum())
        if n == 0 or nan[:n].any():
            return (f"`knot_times` of run {i} must hold its knots first, then NaN (at least "
                    "one knot)")
        if not np.isfinite(k[:n]).all() or not np.isnan(k[n:]).all():
            return (f"`knot_tensors` of run {i} must be finite for its {n} knots and NaN "
                    "beyond them")
    return None


def _systems(d: Loaded) -> list[System]:
    """The systems a file describes (see `_tables.system_vars`): one per run (one for a
    single run). The core checks each value, as when the run was made."""
    runs = _runs(d)
    n = 1 if runs is None else runs

    def rows(name: str) -> np.ndarray:
        a: np.ndarray = d[name]
        return a[None] if runs is None else a

    bodies: list[Any]
    if "knot_times" in d.values:
        bodies = _deployments(rows("knot_times"), rows("knot_tensors"),
                              rows("knot_mass") if "knot_mass" in d.values else None)
    else:
        tensor, mass = rows("body_tensor"), rows("body_mass")
        com = rows("body_center_of_mass")
        shape = None if "body_vertices" not in d.values else Shape(
            d["body_vertices"], d["body_edges"], d["body_faces"] if "body_faces" in d.values
            else None)
        bodies = [Body._restored(tensor[i], None if np.isnan(mass[i]) else float(mass[i]),
                                 com[i], shape) for i in range(n)]
    if "part_kind" in d.values or not any(name in d.values for name in _legacy_parts.NAMES):
        found = _columns.parts_of(d.values, runs)
        assert not isinstance(found, str)  # checked by `system_parts`
    else:
        found = _legacy_parts.parts_of(d, rows, n)
    return [System(b, parts=p, torques=t) for b, (p, t) in zip(bodies, found)]


def _deployments(times: np.ndarray, tensors: np.ndarray,
                 masses: np.ndarray | None = None) -> list[Deployment]:
    """Deployments from NaN-padded knots, one per row (with its mass, NaN: not given)."""
    mass = np.full(len(times), np.nan) if masses is None else masses
    return [Deployment(t[~np.isnan(t)], k[~np.isnan(t)], None if np.isnan(m) else float(m))
            for t, k, m in zip(times, tensors, mass)]


def _moments(system: System) -> np.ndarray:
    """A system's principal moments at ``t = 0``, as a file's ``inertia`` gives them."""
    body = system.body
    if isinstance(body, Body):
        return np.array(body.inertia)
    return np.array(tensor_moments(system.tensor_at(0.0)))


# -- building ---------------------------------------------------------------------------------


def _drift_of(d: Loaded, runs: bool) -> BatchDrift:
    def optional(name: str) -> np.ndarray | None:
        if f"drift_{name}" not in d:
            return None
        value = d[f"drift_{name}"]
        return value if runs else np.asarray([float(value)])

    if runs:
        return BatchDrift.of(lambda k: d[f"drift_{k}"], optional("jacobi"),
                             tuple(d["drift_kept"]), optional("energy_balance"))
    return BatchDrift.of(lambda k: np.asarray([float(d[f"drift_{k}"])]), optional("jacobi"),
                         tuple(d["drift_kept"]), optional("energy_balance"))


def build_trajectory(d: Loaded) -> Trajectory:
    system = _systems(d)[0]
    state = np.concatenate([_state_of(d, name) for name in system.part_names], axis=1) \
        if system.part_names else None
    return Trajectory(
        t=d["time"], omega=d["omega"], q=d["q"],
        flip_times=d["flip_times"] if int(d["flips_located"]) else None,
        system=system, method=str(d["method"]), dt=float(d["dt"]),
        n_steps=int(d["n_steps"]), nfev=int(d["nfev"]),
        drift=_drift_of(d, runs=False).row(0),
        n_rejected=int(d["n_rejected"]),
        parts=split_parts(system, state),
    )


def build_batch(d: Loaded) -> Batch:
    times, offsets = None, None
    if "flips" in d.values:
        counts = d["flips"].astype(np.int64)
        padded = d["flip_times"]
        times = np.concatenate([padded[i, :c] for i, c in enumerate(counts)] + [np.empty(0)])
        offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    m = len(d["run"])
    systems = Systems(m, each=tuple(_systems(d))) if m else Systems(0, each=())
    return Batch(
        t=d["time"], omega=d["omega"], q=d["q"], _flip_times=times, _flip_offsets=offsets,
        systems=systems, method=str(d["method"]), dt=d["dt"],
        n_steps=d["n_steps"].astype(np.int64), nfev=d["nfev"].astype(np.int64),
        n_rejected=d["n_rejected"].astype(np.int64),
        drift=_drift_of(d, runs=True),
        parts={name: _state_of(d, name) for name in d["parts"]},
    )


def build_sweep(d: Loaded) -> Sweep:
    return Sweep(
        inertia=d["inertia"], omega0=d["omega0"], q0=d["q0"],
        flips=d["flips"].astype(np.int64), first_flip=d["first_flip"], period=d["period"],
        exact_period=d["exact_period"], tilt=d["tilt"],
        drift=BatchDrift.of(lambda k: d[f"drift_{k}"]),
        t_end=float(d["t_end"]), method=str(d["method"]), dt=d["dt"],
        n_steps=d["n_steps"].astype(np.int64), nfev=d["nfev"].astype(np.int64),
        status=d["status"].astype(np.asarray(_core.RUN_STATUSES).dtype),
    )


def build_deployment_sweep(d: Loaded) -> DeploymentSweep:
    m = len(d["run"])
    deployments = _deployments(d["knot_times"], d["knot_tensors"]) if m else []
    return DeploymentSweep(
        deployments=tuple(deployments), omega0=d["omega0"], q0=d["q0"],
        inertia=d["inertia"], omega_deployed=d["omega_deployed"],
        flip_period=d["flip_period"], tumbles=d["tumbles"].astype(bool),
        energy_change=d["energy_change"],
        drift=BatchDrift.of(lambda k: d[f"drift_{k}"], None, tuple(d["drift_kept"])),
        t_end=float(d["t_end"]), method=str(d["method"]), dt=d["dt"],
        n_steps=d["n_steps"].astype(np.int64), nfev=d["nfev"].astype(np.int64),
        status=d["status"].astype(np.asarray(_core.RUN_STATUSES).dtype),
    )


# -- what a loaded result derives, against what the file says ------------------------------------


def _agrees(stored: np.ndarray, computed: np.ndarray, runs: bool) -> bool:
    """`stored` equals `computed` to round-off of each run's largest value (they are the same
    computation on the same numbers, so in practice bit for bit)."""
    lead = 1 if runs else 0
    axes = tuple(range(lead, computed.ndim))
    scale = np.abs(computed).max(axis=axes, keepdims=True, initial=0.0) if axes else \
        np.abs(computed)
    return bool((np.abs(stored - computed) <= 1e-12 * scale).all())


def _derived_agree(d: Loaded, result: Any, runs: bool) -> str | None:
    if runs and not len(result):
        return None
    moments = result.inertia if runs else _moments(result.system)
    if not _agrees(d["inertia"], moments, runs):
        return "`inertia` is not the principal moments of the file's own system"
    for name in _DERIVED:
        if not _agrees(d[name], getattr(result, name), runs):
            return (f"`{name}` is not what the file's own system and frames give (the energy "
                    "and angular momentum a run of that system has)")
    for name, rate in result.part_rates.items():
        var, width, _ = _tables.rate_variable(name)
        if var in d and not _agrees(d[var], rate[..., 0] if width == 1 else rate, runs):
            return (f"`{var}` is not what the file's own system and frames give (the rates "
                    "a run of that system has)")
    return None


def trajectory_derived(d: Loaded, traj: Any) -> str | None:
    return _derived_agree(d, traj, runs=False)


def batch_derived(d: Loaded, batch: Any) -> str | None:
    return _derived_agree(d, batch, runs=True)


def deployment_sweep_rules(d: Loaded) -> str | None:
    """Knots for every run; `tumbles` says whether `flip_period` is finite; a finished run
    has its deployed rates and period, an unfinished one NaN."""
    m = len(d["run"])
    knots = [name in d.values for name in _KNOT_VARS]
    if any(knots) != bool(m) or any(knots) != all(knots):
        return ("`knot_times` and `knot_tensors` must be there exactly when there are runs"
                if m else "`knot_times` must not be there: the sweep is empty")
    if m:
        problem = _knots_padded(d["knot_times"], d["knot_tensors"])
        if problem:
            return problem
    period, ok = d["flip_period"], d["status"] == "ok"
    if (d["tumbles"].astype(bool) != np.isfinite(period)).any():
        return "`tumbles` must say whether `flip_period` is finite"
    if np.isnan(period[ok]).any() or not np.isfinite(d["omega_deployed"][ok]).all():
        return "`flip_period` and `omega_deployed` must be numbers for a run that finished"
    if not np.isnan(period[~ok]).all() or not np.isnan(d["omega_deployed"][~ok]).all():
        return "`flip_period` and `omega_deployed` must be NaN for a run that did not finish"
    return None


class _StudyView:
    """What :meth:`MonteCarlo.from_xarray` reads of a dataset, over a checked file."""

    def __init__(self, d: Loaded) -> None:
        self.attrs = d.attrs
        self._values = d.values

    def __contains__(self, name: str) -> bool:
        return name in self._values

    def __getitem__(self, name: str) -> Any:
        return _Values(self._values[name])

    @property
    def data_vars(self) -> list[str]:
        return list(self._values)


_PART_INPUT = re.compile(r"[a-z][a-z0-9_]*_[0-9]+\.[a-z][a-z0-9_]*")
"""A study's input that is a part's parameter (``hinge_0.damping``)."""


def _study_part_input(name: str) -> Var | None:
    """The layout of a study's part parameter, by its name (see
    :meth:`MonteCarlo.inputs <dzhanibekov.MonteCarlo>`), or None for another name."""
    return Var(("sample",), "f") if _PART_INPUT.fullmatch(name) else None


@dataclass(frozen=True)
class _Values:
    values: np.ndarray


def build_study(d: Loaded) -> MonteCarlo:
    return MonteCarlo.from_xarray(_StudyView(d))


def _parses(parse: Callable[[str], Any]) -> Check:
    """A check that each text is one `parse` reads (its ValueError says why not)."""
    def check(a: np.ndarray) -> str | None:
        for text in np.ravel(a):
            try:
                parse(str(text))
            except ValueError as exc:
                return str(exc)
        return None
    return check


def _within(lower: float, upper: float) -> Check:
    def check(a: np.ndarray) -> str | None:
        return None if ((a > lower) & (a < upper)).all() else \
            f"must lie in ({lower:g}, {upper:g}), got {np.ravel(a)[0].item()!r}"
    return check


def _at_least(least: int) -> Check:
    def check(a: np.ndarray) -> str | None:
        return None if (a >= least).all() else \
            f"must be at least {least}, got {np.ravel(a)[0].item()!r}"
    return check


_ASK_TYPES = {"tumbles": "bool", "flat_spin": "bool", "flips": "int"}
"""The outcome type of each question a study asks by name."""


def study_rules(d: Loaded) -> str | None:
    """The fields of a study that go together: its samples with `n` and `runs` as its design
    draws and runs them, the strata of a rare-event design, the outcomes' type with `ask`."""
    samples = d["sample"]
    if samples.size and (samples.min() < 0 or samples.max() >= int(d["n"])):
        return f"`sample` must index the study's n = {int(d['n'])} samples"
    if len(np.unique(samples)) != samples.size:
        return "`sample` must not repeat a sample"
    if int(d["runs"]) != samples.size:
        return f"`runs` ({int(d['runs'])}) must count the samples ({samples.size})"
    if str(d["outcome_type"]) == "bool" and not np.isin(d["outcome"], (0, 1)).all():
        return "`outcome` must be 0 or 1 for a yes/no question"
    if ("stratum" in d) != (str(d["design"]) == "near-separatrix"):
        return "`stratum` goes with the near-separatrix design, and only with it"
    drawn = [name for name in ("draws_near", "draws_far") if name in d]
    ask, kind = str(d["ask"]), str(d["outcome_type"])
    if ask in _ASK_TYPES and kind != _ASK_TYPES[ask]:
        return f"`outcome_type` must be {_ASK_TYPES[ask]!r} for `ask` {ask!r}, got {kind!r}"
    n, runs = int(d["n"]), int(d["runs"])
    if "stratum" not in d:
        if drawn:
            return f"`{drawn[0]}` goes with the near-separatrix design, and only with it"
        if n != runs or not np.array_equal(samples, np.arange(runs)):
            return (f"a plain study runs its samples 0 … n − 1: `n` ({n}) must equal `runs` "
                    f"({runs}) and `sample` must be 0 … {runs - 1}")
        return None
    if len(drawn) != 2:
        return "the near-separatrix design needs `draws_near` and `draws_far`"
    near, far = int(d["draws_near"]), int(d["draws_far"])
    stratum = d["stratum"]
    if near + far != n or not runs < n:
        return (f"`draws_near` + `draws_far` ({near} + {far}) must be `n` ({n}), and `runs` "
                f"({runs}) below it")
    if not np.isin(stratum, (0, 1)).all():
        return "`stratum` must be 0 (near the separatrix) or 1 (the others)"
    if int((stratum == 0).sum()) != near:
        return (f"`stratum` must mark the {near} samples near the separatrix (`draws_near`), "
                f"every one run, with 0; it marks {int((stratum == 0).sum())}")
    if "separatrix" in d and near and runs > near:  # the nearest are those marked near
        distance = np.abs(d["separatrix"])
        if distance[stratum == 0].max() > distance[stratum == 1].min():
            return ("`stratum` must mark with 0 the samples nearest the separatrix (by "
                    "`separatrix`)")
    return None


def study_derived(d: Loaded, study: Any) -> str | None:
    """The weights and the estimate the file holds against those its outcomes give."""
    if not np.allclose(d["weight"], study.weights, rtol=1e-12, atol=0.0):
        return "`weight` must be what the design gives each sample"
    derived = {"estimate": study.mean}
    if study.is_boolean and study.runs:
        derived["lower"], derived["upper"] = study.interval
    for name, value in derived.items():
        if not np.isclose(float(d[name]), value, rtol=1e-12, atol=1e-15):
            return f"the attribute `{name}` ({float(d[name])!r}) must be what the outcomes give ({value!r})"
    return None


# -- the layouts --------------------------------------------------------------------------------

_COUNT = Attr("i", (non_negative,))
_METHOD = Attr("U", (one_of(tuple(METHODS)),))
_KEPT_NAMES = Attr("U", (one_of(_KEPT),), shape=None)
def _state_names(a: np.ndarray) -> str | None:
    bad = [str(v) for v in np.ravel(a) if not _part_state_name(str(v))]
    return None if not bad else (f"must name parts with state as a run shows them (a model "
                                 f"of {list(PART_NAMES)}, or <model>_<k> for the k-th of "
                                 f"several), got {bad[0]!r}")


_PARTS = Attr("U", (_state_names,), shape=None)
_LABELS = {"axis": Var(("axis",), "U", (labels(_tables.AXIS),)),
           "quaternion": Var(("quaternion",), "U", (labels(_tables.QUATERNION),))}
_FIXED = {"axis": 3, "axis_": 3, "quaternion": 4, "body_edge_end": 2, "body_face_corner": 3}
_OPT = True


def _system_vars(lead: tuple[str, ...]) -> dict[str, Var]:
    """The variables of `_tables.system_vars` and `_tables._derived` (all optional here:
    the rule `system_parts` says which go together)."""
    return {
        "body_tensor": Var(lead + ("axis", "axis_"), "f", (finite,), optional=_OPT),
        "body_mass": Var(lead, "f", (finite_or_nan, positive_or_nan), optional=_OPT),
        "body_vertices": Var(("body_vertex", "axis"), "f", (finite,), optional=_OPT),
        "body_edges": Var(("body_edge", "body_edge_end"), "i", (non_negative,), optional=_OPT),
        "body_faces": Var(("body_face", "body_face_corner"), "i", (non_negative,),
                          optional=_OPT),
        "body_center_of_mass": Var(lead + ("axis",), "f", (finite,), optional=_OPT),
        "knot_times": Var(lead + ("knot",), "f", (finite_or_nan,), optional=_OPT),
        "knot_mass": Var(lead, "f", (finite_or_nan, positive_or_nan), optional=_OPT),
        "knot_tensors": Var(lead + ("knot", "axis", "axis_"), "f", (finite_or_nan,),
                            optional=_OPT),
        **_legacy_vars(lead),
        **_part_vars(lead),
        "energy": Var(lead + ("time",), "f", (finite,), optional=_OPT),
        "momentum_body": Var(lead + ("time", "axis"), "f", (finite,), optional=_OPT),
        "momentum_world": Var(lead + ("time", "axis"), "f", (finite,), optional=_OPT),
    }


def _part_vars(lead: tuple[str, ...]) -> dict[str, Var]:
    """Every column a part of any model a file can hold may have (see
    :mod:`dzhanibekov.parts._columns`; the rule `system_parts` checks their rows)."""
    out = {_columns.KIND: Var(lead + ("part",), "U", (one_of(("", *_columns.storable_models())),),
                              optional=_OPT)}
    for model in _columns.storable_models():
        for p in params_of(model):
            word = p.kind == "choice"
            out[_columns.column_name(model, p.name)] = Var(
                lead + _columns.column_dims(model, p.kind), "U" if word else "f",
                (one_of(("", *p.choices)),) if word else (), optional=_OPT)
    return out


def _legacy_vars(lead: tuple[str, ...]) -> dict[str, Var]:
    """The parts' variables of files before parts were written by their model
    (:mod:`dzhanibekov._legacy_parts`), read only."""
    legacy = _legacy_parts
    return {
        "damper_inertia": Var(lead, "f", (finite, positive), optional=_OPT),
        "damper_damping": Var(lead, "f", (finite, non_negative), optional=_OPT),
        "damper_sigma0": Var(lead + ("axis",), "f", (finite_or_nan,), optional=_OPT),
        "wheel_axis": Var(lead + ("wheel", "axis"), "f", (finite_or_nan,), optional=_OPT),
        "wheel_momentum": Var(lead + ("wheel",), "f", (finite_or_nan,), optional=_OPT),
        "wheel_position": Var(lead + ("wheel",), "i", optional=_OPT),
        "torque_kind": Var(lead + ("torque",), "U", (one_of(("", *legacy.TORQUE_KINDS)),),
                           optional=_OPT),
        "torque_orbit_rate": Var(lead + ("torque",), "f", (finite_or_nan,), optional=_OPT),
        "torque_vector": Var(lead + ("torque", "axis"), "f", (finite_or_nan,), optional=_OPT),
        "torque_frame": Var(lead + ("torque",), "U", (one_of(("", *legacy.TORQUE_FRAMES)),),
                            optional=_OPT),
        "wheel_times": Var(lead + ("wheel", "wheel_knot"), "f", (finite_or_nan,),
                           optional=_OPT),
        "wheel_values": Var(lead + ("wheel", "wheel_knot"), "f", (finite_or_nan,),
                            optional=_OPT),
        "torque_outside": Var(lead + ("torque",), "U",
                              (one_of(("", *legacy.TORQUE_OUTSIDE)),), optional=_OPT),
        "torque_times": Var(lead + ("torque", "torque_knot"), "f", (finite_or_nan,),
                            optional=_OPT),
        "torque_vectors": Var(lead + ("torque", "torque_knot", "axis"), "f", (finite_or_nan,),
                              optional=_OPT),
    }


_STUDY_INPUT = {
    "inertia": ("axis",), "tensor": ("axis", "axis2"), "axes": ("axis", "axis2"),
    "omega0": ("axis",), "q0": ("quaternion",), "separatrix": (), "knot_times": ("knot",),
    "knot_tensors": ("knot", "axis", "axis2"), "damper_inertia": (), "damping": (),
    "damper_sigma0": ("axis",),
}
_TEXT = Attr("U")
_NUMBER = Attr("f")
_STUDY = Layout(
    variables={
        "sample": Var(("sample",), "i", (non_negative,)),
        **_LABELS,
        "axis2": Var(("axis2",), "U", (labels(_tables.AXIS),)),
        "outcome": Var(("sample",), "n", (finite,)),
        "weight": Var(("sample",), "f", (finite, non_negative)),
        "stratum": Var(("sample",), "i", (non_negative,), optional=True),
        **{name: Var(("sample",) + dims, "f", optional=True)
           for name, dims in _STUDY_INPUT.items()},
    },
    attrs={
        "ask": _TEXT, "n": _COUNT, "runs": _COUNT,
        "kind": Attr("U", (one_of(tuple(montecarlo.STUDY_KINDS)),)),
        "seed_entropy": Attr("U", (_parses(montecarlo.entropy_of_text),)),
        "seed_spawn_key": Attr("U", (_parses(montecarlo.spawn_key_of_text),)),
        "t_end": Attr("f", (finite, positive)), "frames": Attr("i", (_at_least(2),)),
        "method": _METHOD, "dt": Attr("f", (finite_or_nan, positive_or_nan)),
        "level": Attr("f", (finite, _within(0.0, 1.0))),
        "interval_method": Attr("U", (one_of(montecarlo.INTERVALS),)),
        "estimate": _NUMBER, "lower": _NUMBER, "upper": _NUMBER,
        "design": Attr("U", (one_of(("plain", "near-separatrix")),)),
        "outcome_type": Attr("U", (one_of(("bool", "int", "float")),)),
        "draws_near": Attr("i", (non_negative,), optional=True),
        "draws_far": Attr("i", (non_negative,), optional=True),
    },
    rules=(study_rules,),
    build=build_study,
    after=study_derived,
    state=_study_part_input,
    sizes={**_FIXED, "axis2": 3},
)


LAYOUTS: Mapping[str, Layout] = {
    "Trajectory": Layout(
        variables={
            "time": Var(("time",), "f", (finite, starts_at_zero_and_increases)),
            **_LABELS,
            "omega": Var(("time", "axis"), "f", (finite,)),
            "q": Var(("time", "quaternion"), "f", (finite,)),
            "flip_times": Var(("flip",), "f", optional=True),
            **_system_vars(()),
        },
        attrs={
            "method": _METHOD,
            "inertia": Attr("f", (finite, positive, moments), shape=(3,)),
            "dt": Attr("f", (finite, non_negative)),
            "n_steps": _COUNT, "nfev": _COUNT, "n_rejected": _COUNT,
            "flips_located": Attr("i", (flag,)),
            **{f"drift_{k}": Attr("f", (finite, non_negative)) for k in _tables.DRIFTS},
            **{f"drift_{k}": Attr("f", (finite, non_negative), optional=True)
               for k in _tables.OPTIONAL_DRIFTS},
            "drift_kept": _KEPT_NAMES,
            "parts": _PARTS,
        },
        rules=(trajectory_q_unit, trajectory_flips, system_parts),
        build=build_trajectory, state=_state_var(()),
        after=trajectory_derived,
        sizes=_FIXED, least={"time": 2, "knot": 1},
    ),
    "Batch": Layout(
        variables={
            "time": Var(("time",), "f", (finite, starts_at_zero_and_increases)),
            "run": Var(("run",), "i"),
            **_LABELS,
            "omega": Var(("run", "time", "axis"), "f", (finite,)),
            "q": Var(("run", "time", "quaternion"), "f", (finite,)),
            "inertia": Var(("run", "axis"), "f", (finite, positive, moments)),
            "dt": Var(("run",), "f", (finite, non_negative)),
            "n_steps": Var(("run",), "i", (non_negative,)),
            "nfev": Var(("run",), "i", (non_negative,)),
            "n_rejected": Var(("run",), "i", (non_negative,)),
            **{f"drift_{k}": Var(("run",), "f", (finite, non_negative))
               for k in _tables.DRIFTS},
            **{f"drift_{k}": Var(("run",), "f", (finite_or_nan, non_negative), optional=True)
               for k in _tables.OPTIONAL_DRIFTS},
            "flips": Var(("run",), "i", (non_negative,), optional=True),
            "flip_times": Var(("run", "flip"), "f", (finite_or_nan,), optional=True),
            **_system_vars(("run",)),
        },
        attrs={"method": _METHOD, "drift_kept": _KEPT_NAMES, "parts": _PARTS},
        rules=(run_numbers, batch_q_unit, batch_flips, system_parts),
        build=build_batch, state=_state_var(("run",)),
        after=batch_derived,
        sizes=_FIXED, least={"time": 2, "knot": 1},
    ),
    "Sweep": Layout(
        variables={
            **_LABELS,
            "inertia": Var(("*", "axis"), "f", (finite, positive, moments)),
            "omega0": Var(("*", "axis"), "f", (finite,)),
            "q0": Var(("*", "quaternion"), "f", (finite,)),
            "flips": Var(("*",), "i"),
            "first_flip": Var(("*",), "f", (finite_or_nan,)),
            "period": Var(("*",), "f", (finite_or_nan, positive_or_nan)),
            "exact_period": Var(("*",), "f", (positive_or_nan,)),
            "tilt": Var(("*",), "f", (finite_or_nan,)),
            "dt": Var(("*",), "f"),
            "n_steps": Var(("*",), "i", (non_negative,)),
            "nfev": Var(("*",), "i", (non_negative,)),
            "status": Var(("*",), "U", (one_of(tuple(_core.RUN_STATUSES)),)),
            **{f"drift_{k}": Var(("*",), "f") for k in _tables.DRIFTS},
        },
        attrs={"method": _METHOD, "t_end": Attr("f", (finite, positive))},
        rules=(sweep_outcomes,),
        build=build_sweep,
        sizes=_FIXED, grid_coordinates=True,
    ),
    "DeploymentSweep": Layout(
        variables={
            "run": Var(("run",), "i"),
            **_LABELS,
            "omega0": Var(("run", "axis"), "f", (finite,)),
            "q0": Var(("run", "quaternion"), "f", (finite,)),
            "inertia": Var(("run", "axis"), "f", (finite, positive, moments)),
            "omega_deployed": Var(("run", "axis"), "f", (finite_or_nan,)),
            "flip_period": Var(("run",), "f", (positive_or_nan,)),
            "tumbles": Var(("run",), "i", (flag,)),
            "energy_change": Var(("run",), "f", (finite_or_nan,)),
            "dt": Var(("run",), "f"),
            "n_steps": Var(("run",), "i", (non_negative,)),
            "nfev": Var(("run",), "i", (non_negative,)),
            "status": Var(("run",), "U", (one_of(tuple(_core.RUN_STATUSES)),)),
            **{f"drift_{k}": Var(("run",), "f") for k in _tables.DRIFTS},
            "knot_times": Var(("run", "knot"), "f", (finite_or_nan,), optional=True),
            "knot_tensors": Var(("run", "knot", "axis", "axis_"), "f", (finite_or_nan,),
                                optional=True),
        },
        attrs={"method": _METHOD, "t_end": Attr("f", (finite, positive)),
               "drift_kept": _KEPT_NAMES},
        rules=(run_numbers, deployment_sweep_rules),
        build=build_deployment_sweep,
        sizes=_FIXED, least={"knot": 1},
    ),
    "MonteCarlo": _STUDY,
}
"""What a file of each kind holds: its variables (dimensions, type, allowed values), its
attributes, the rules between them, and what the built result must agree with (its own
system's moments, energy and angular momentum). The check of a file and the build of its
result both read this table."""


# -- save -------------------------------------------------------------------------------------


def save(result: Trajectory | Batch | Sweep | DeploymentSweep | MonteCarlo,
         path: str | Path) -> Path:
    """Writes a result to a netCDF-4 file (xarray, h5netcdf engine) that :func:`load` reads
    back: arrays bit for bit, and the metadata to rebuild the object (each run's system: the
    body's tensor, mass, centre of mass and the outline the pictures draw (a box's, an
    ellipsoid's, a composite's or a mesh's), a deployment's knots, the parts with their
    parameters, so that the loaded system ``==`` the saved one; every part's
    state, so that what a loaded run derives is the saved run's, bit for bit). All or nothing: the
    previous file is replaced only once the new one is complete, and is as it was after
    any failure (a full disk, Ctrl-C).

    The file is an ordinary netCDF file with the layout of ``result.to_xarray()``: open it
    with ``xarray.open_dataset(path)``, or any netCDF tool.

    Parameters
    ----------
    result : Trajectory, Batch, Sweep, DeploymentSweep or MonteCarlo
    path : str or Path
        The file to write (replaced if it exists), ending in one of :data:`SUFFIXES`
        (``.nc`` by convention).

    Returns
    -------
    Path

    Raises
    ------
    TypeError
        `result` is none of these, or `path` not a path.
    ValueError
        `path` ends in another suffix (the message says what writes that format); `result`
        is a run of a system with a :class:`~dzhanibekov.CallableTorque` (a file cannot hold
        code: the message names it).
    ImportError
        xarray or h5netcdf is missing: install the ``io`` extra.
    OSError
        The file cannot be written (its folder is missing, the disk is full): the error
        names `path`, which is as it was.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0))
    >>> path = dz.save(traj, "run.nc")                            # doctest: +SKIP
    >>> bool((dz.load(path).q == traj.q).all())                   # doctest: +SKIP
    True
    """
    kinds = {Trajectory: "Trajectory", Batch: "Batch", Sweep: "Sweep",
             DeploymentSweep: "DeploymentSweep", MonteCarlo: "MonteCarlo"}
    kind = kinds.get(type(result))
    if kind is None:
        raise TypeError(f"`result` must be a Trajectory, Batch, Sweep, DeploymentSweep or "
                        f"MonteCarlo, got {type(result).__name__}")
    systems: Any = (result.system,) if isinstance(result, Trajectory) else \
        (result.systems.shared,) if isinstance(result, Batch) and result.systems.shared \
        else result.systems.each or () if isinstance(result, Batch) else ()
    for system in systems:  # (a batch of principal moments is of free bodies)
        if unsaved := _tables.unstorable(system):
            raise ValueError(f"`result` is a run of a system with {', '.join(unsaved)}, "
                             "which a file cannot hold (a file cannot hold code, and its parameters "
                             "would be lost): "
                             "keep its arrays with result.to_xarray().to_netcdf(path) or "
                             "numpy.savez")
    p = as_path(path)
    suffix = p.suffix.lower()
    if suffix not in SUFFIXES:
        other = _OTHER_FORMATS.get(suffix, "")
        raise ValueError(f"`path` {str(p)!r} must end in one of {', '.join(SUFFIXES)}: "
                         f"`save` writes netCDF-4 only" + (f"; {other}" if other else ""))
    _tables.require("h5netcdf", "`save`")
    _tables.require("h5py", "`save`")
    ds = result.to_xarray()
    ds.attrs[KIND_ATTRIBUTE] = kind
    check_size(2 * int(ds.nbytes), f"the netCDF image of this {kind} (built in memory)",
               "save fewer frames or runs")
    # a checksum of every numeric array (HDF5's Fletcher-32 filter): damage to the file is
    # found by `load` (a ReadError), not read as numbers
    checked = {name: {"fletcher32": True} for name, v in ds.variables.items()
               if v.size and v.dtype.kind in "biuf"}
    with replacing(p) as tmp:
        image = io.BytesIO()
        ds.to_netcdf(image, engine="h5netcdf", encoding=checked)  # in memory: see the module's docs
        with open(tmp, "wb") as f:
            f.write(image.getbuffer())
        del image
    return p


# -- load -------------------------------------------------------------------------------------


def load(path: str | Path) -> Trajectory | Batch | Sweep | DeploymentSweep | MonteCarlo:
    """Reads a result written by :func:`save`, checking it as strictly as a run checks
    what it computes (see the module's docs and :data:`LAYOUTS`).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    Trajectory, Batch, Sweep, DeploymentSweep or MonteCarlo
        (a study without its dispersions: it cannot rerun a sample)

    Raises
    ------
    ReadError
        (a ValueError) The file is missing or not a regular file (a FIFO or a device is
        refused at once), is of another format (named: an AEM, a netCDF-3 file, …), is a
        damaged HDF5 file, was not written by :func:`save`, or holds what a save never
        writes (NaN, quaternions off unit norm, times that run backwards, flip counts that
        do not match the flip times, a variable of the wrong shape, a system the core refuses,
        energies or angular momenta its own system does not give); the message names the
        file and the field.
    TooLargeError
        Its arrays would need more memory than the machine has now.
    ImportError
        h5py is missing: install the ``io`` extra.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> dz.load("run.nc")                                         # doctest: +SKIP
    Trajectory(frames=201, t_end=100, method='rk4', n_steps=100000, flips=2)
    """
    h5py = _tables.require("h5py", "`load`")
    p = as_path(path)
    expected = "a netCDF-4 file written by dzhanibekov.save"
    with open_regular(p, expected) as f:
        head = f.read(len(HDF5_SIGNATURE))
        if head != HDF5_SIGNATURE:
            head += f.read(56)
            raise ReadError(f"{p} is {describe(head)}, not {expected}", path=str(p))
        f.seek(0)
        try:
            h5 = h5py.File(f, "r")
        except (MemoryError, KeyboardInterrupt):
            raise
        except Exception as exc:
            raise ReadError(f"{p} is an HDF5 file that cannot be read (damaged or "
                            f"truncated?): {type(exc).__name__}: {exc}; expected {expected}",
                            path=str(p)) from None
        with h5:
            kind = "result"
            try:
                kind = h5.attrs.get(KIND_ATTRIBUTE)
                if not isinstance(kind, str) or kind not in LAYOUTS:
                    raise ReadError(f"{p} is HDF5 but was not written by dzhanibekov.save (its "
                                    f"`{KIND_ATTRIBUTE}` attribute is {kind!r}, not one of "
                                    f"{list(LAYOUTS)})", path=str(p))
                layout = LAYOUTS[kind]
                handle = _File(h5)
                shapes = _check_structure(handle, layout)
                check_size(sum(int(np.prod(shape)) * 8 for shape in shapes.values()),
                           f"the arrays of {p}", "it is larger than this machine can hold")
                loaded = _read_values(handle, layout, shapes)
            except _Bad as bad:
                raise ReadError(f"{p} holds a {kind} that dz.save never writes: {bad}",
                                path=str(p)) from None
            except _Damaged as damaged:
                raise ReadError(f"{p} holds a {kind} that cannot be read: {damaged}",
                                path=str(p)) from None
            except (MemoryError, KeyboardInterrupt, ReadError):
                raise
            except Exception as exc:
                raise ReadError(f"{p} cannot be read (damaged or truncated?): "
                                f"{type(exc).__name__}: {exc}", path=str(p)) from None
    problem = next((msg for rule in layout.rules if (msg := rule(loaded))), None)
    if problem:
        raise ReadError(f"{p} holds a {kind} that dz.save never writes: {problem}",
                        path=str(p))
    try:
        result: Trajectory | Batch | Sweep | DeploymentSweep | MonteCarlo = layout.build(loaded)
    except (TypeError, ValueError) as exc:  # a body, part or deployment the core refuses
        raise ReadError(f"{p} holds a {kind} whose system dz cannot build: {exc}",
                        path=str(p)) from None
    problem = layout.after(loaded, result) if layout.after is not None else None
    if problem:
        raise ReadError(f"{p} holds a {kind} that dz.save never writes: {problem}",
                        path=str(p))
    return result


class _Bad(Exception):
    """A field of the file that is not what the layout allows."""


class _Damaged(Exception):
    """A variable of the file that HDF5 cannot read back (its checksum fails)."""


_PHONY = b"This is a netCDF dimension but not a netCDF variable"
"""How netCDF-4 names the HDF5 dataset of a dimension without a coordinate variable."""


class _Variable:
    """A netCDF-4 variable of an open HDF5 file: its dimensions' names and its dataset."""

    def __init__(self, dimensions: tuple[str, ...], dataset: Any) -> None:
        self.dimensions = dimensions
        self.dataset = dataset
        self.dtype = dataset.dtype
        self.shape = tuple(dataset.shape)

    def __getitem__(self, key: Any) -> Any:
        return self.dataset[key]


class _File:
    """The netCDF-4 view of an open HDF5 file (h5py, no h5netcdf: ten times faster on a
    file of a few variables): its variables by name, with their dimensions from the HDF5
    dimension scales (netCDF-4's own layout), and its global attributes."""

    def __init__(self, h5: Any) -> None:
        import h5py  # type: ignore[import-untyped, unused-ignore]

        self.attrs = h5.attrs
        self.variables: dict[str, _Variable] = {}
        for name in h5:
            obj = h5.get(name)
            if not isinstance(obj, h5py.Dataset):
                raise _Bad(f"`{name}` is an HDF5 group or link, not a netCDF variable")
            attrs = obj.attrs
            if attrs.get("CLASS") == b"DIMENSION_SCALE":
                label = attrs.get("NAME", b"")
                if isinstance(label, bytes) and label.startswith(_PHONY):
                    continue  # a dimension without a variable
                dims: tuple[str, ...] = (name,)
            elif obj.ndim == 0:
                dims = ()
            else:
                refs = attrs.get("DIMENSION_LIST")
                if refs is None or len(refs) != obj.ndim:
                    raise _Bad(f"`{name}` has no named dimensions")
                dims = tuple(str(h5[r[0]].name).lstrip("/") for r in refs)
            self.variables[name] = _Variable(dims, obj)


def _kind_of(dtype: np.dtype[Any]) -> str:
    if dtype.kind == "f":
        return "f"
    if dtype.kind in "iu":
        return "i"
    if dtype.kind in "USO":
        return "U"
    return dtype.kind


_KIND_WORDS = {"f": "float64", "i": "integers", "U": "text", "n": "integers or float64"}


def _specs(ds: Any, layout: Layout) -> dict[str, Var]:
    """The layout's variables, with those of the parts' state the file holds."""
    specs = dict(layout.variables)
    if layout.state is not None:
        for name in ds.variables:
            if name not in specs and (var := layout.state(name)) is not None:
                specs[name] = var
    return specs


def _check_structure(ds: Any, layout: Layout) -> dict[str, tuple[int, ...]]:
    """Each variable's dimensions and type against the layout, before any value is read;
    returns the variables' shapes."""
    grid: tuple[str, ...] | None = None
    sizes: dict[str, int] = {}
    shapes: dict[str, tuple[int, ...]] = {}
    specs = _specs(ds, layout)
    for name, spec in specs.items():
        if name not in ds.variables:
            if spec.optional:
                continue
            raise _Bad(f"`{name}` is missing")
        var = ds.variables[name]
        dims = tuple(var.dimensions)
        if "*" in spec.dims:
            lead = len(dims) - (len(spec.dims) - 1)
            if lead < 0 or dims[lead:] != spec.dims[1:]:
                raise _Bad(f"`{name}` must have dims (grid…, {', '.join(spec.dims[1:])}), "
                           f"got {dims}")
            if grid is None:
                grid = dims[:lead]
            elif dims[:lead] != grid:
                raise _Bad(f"`{name}` has grid dims {dims[:lead]}, others {grid}")
        elif dims != spec.dims:
            raise _Bad(f"`{name}` must have dims {spec.dims}, got {dims}")
        for dim, n in zip(dims, var.shape):
            if dim in layout.sizes and n != layout.sizes[dim]:
                raise _Bad(f"`{name}` has {n} along `{dim}`, which must hold "
                           f"{layout.sizes[dim]}")
            if dim in layout.least and n < layout.least[dim]:
                raise _Bad(f"`{name}` has {n} along `{dim}`, which must hold at least "
                           f"{layout.least[dim]}")
            if sizes.setdefault(dim, n) != n:
                raise _Bad(f"`{name}` has {n} along `{dim}`, other variables {sizes[dim]}")
        kind = _kind_of(var.dtype)
        if (kind != spec.kind and not (spec.kind == "n" and kind in "if")) or (
                kind == "f" and var.dtype != np.float64):
            raise _Bad(f"`{name}` must hold {_KIND_WORDS[spec.kind]}, got {var.dtype}")
        shapes[name] = tuple(var.shape)
    for name in sorted(set(ds.variables) - set(specs)):
        var = ds.variables[name]
        if not (layout.grid_coordinates and grid is not None and name in grid
                and tuple(var.dimensions) == (name,) and _kind_of(var.dtype) in "fi"):
            raise _Bad(f"a variable `{name}` that no save writes (it writes "
                       f"{', '.join(layout.variables)})")
    return shapes


def _read_values(ds: Any, layout: Layout, shapes: dict[str, tuple[int, ...]]) -> Loaded:
    values: dict[str, np.ndarray] = {}
    for name, spec in _specs(ds, layout).items():
        if name not in shapes:
            continue
        try:
            raw = np.asarray(ds.variables[name][...])
        except OSError as exc:  # HDF5's checksum (Fletcher-32) of the variable fails, ...
            raise _Damaged(f"`{name}` cannot be read ({exc}): the file is damaged") from None
        number = spec.kind == "n"
        a = (np.ascontiguousarray(raw, dtype=np.float64)
             if spec.kind == "f" or (number and raw.dtype.kind == "f") else
             np.ascontiguousarray(raw, dtype=np.int64) if spec.kind == "i" or number else
             np.array([v.decode() if isinstance(v, bytes) else str(v) for v in raw.ravel()],
                      dtype=str).reshape(raw.shape))
        a = a.reshape(raw.shape)  # ascontiguousarray makes a 0-d variable 1-d
        for check in spec.checks:
            if problem := check(a):
                raise _Bad(f"`{name}` {problem}")
        values[name] = a
    attrs: dict[str, Any] = {}
    for name, attr in layout.attrs.items():
        _read_attribute(ds, name, attr, attrs)
    return Loaded(values, attrs)


def _read_attribute(ds: Any, name: str, spec: Attr, attrs: dict[str, Any]) -> None:
    """Attribute `name` of `ds`, checked against `spec`, into `attrs`."""
    if name not in ds.attrs:
        if spec.optional:
            return
        raise _Bad(f"the attribute `{name}` is missing")
    raw = np.asarray(ds.attrs[name])
    if spec.shape is None:  # a list of names: netCDF keeps one as a string, none as []
        if raw.shape == (0,):
            raw = np.array([], dtype=str)
        if raw.ndim == 0:
            raw = raw.reshape(1)
        if raw.ndim != 1:
            raise _Bad(f"the attribute `{name}` must be a list of names, got shape "
                       f"{raw.shape}")
    elif raw.shape != spec.shape and not (spec.shape == () and raw.shape == (1,)):
        raise _Bad(f"the attribute `{name}` must have shape {spec.shape}, got {raw.shape}")
    kind = _kind_of(raw.dtype)
    if kind != spec.kind and not (spec.kind == "f" and kind == "i"):
        raise _Bad(f"the attribute `{name}` must be {_KIND_WORDS[spec.kind]}, got "
                   f"{raw.dtype}")
    a = raw.astype(np.float64) if spec.kind == "f" else raw
    if spec.kind == "U":
        a = np.asarray([v.decode() if isinstance(v, bytes) else str(v)
                        for v in np.ravel(raw)], dtype=str).reshape(raw.shape)
    for check in spec.checks:
        if a.size and (problem := check(np.atleast_1d(a))):
            raise _Bad(f"the attribute `{name}` {problem}")
    if spec.shape is None:
        names = tuple(str(v) for v in a)
        if len(set(names)) != len(names):
            raise _Bad(f"the attribute `{name}` names one twice: {list(names)}")
        attrs[name] = names
    else:
        attrs[name] = a.reshape(spec.shape) if spec.shape else a.reshape(()).item()
