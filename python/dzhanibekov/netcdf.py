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
counts that match the flip times …), each attribute, and the rules that tie them together.
Every failure is a :class:`~dzhanibekov.io.ReadError` (a ValueError) naming the file and
what is wrong. A new field of a result is one row of its table.
"""

from __future__ import annotations

import io
import math
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from . import _core, _tables
from ._args import check_size
from ._files import HDF5_SIGNATURE, ReadError, as_path, describe, open_regular, replacing
from .body import Body, InertiaWarning
from .methods import METHODS
from .results import Batch, BatchDrift, Drift, Sweep, Trajectory

__all__ = ["save", "load", "LAYOUTS", "SUFFIXES", "KIND_ATTRIBUTE"]

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
    more, whatever their names). `kind` is ``"f"`` (float64), ``"i"`` (integers) or ``"U"``
    (text). `checks` are applied in order to the values."""

    dims: tuple[str, ...]
    kind: str
    checks: tuple[Check, ...] = ()
    optional: bool = False


@dataclass(frozen=True)
class Attr:
    """An attribute of a layout: `kind` as for :class:`Var` (a scalar, or an array of
    `shape`), and its checks."""

    kind: str
    checks: tuple[Check, ...] = ()
    shape: tuple[int, ...] = ()


Rule = Callable[["Loaded"], "str | None"]
"""A rule tying several fields together: None if they agree, else what is wrong."""


@dataclass(frozen=True)
class Layout:
    """What a file of one kind holds, and how to build the result from it."""

    variables: Mapping[str, Var]
    attrs: Mapping[str, Attr]
    rules: tuple[Rule, ...]
    build: Callable[[Loaded], Any]
    sizes: Mapping[str, int] = field(default_factory=dict)
    """Dimensions of a fixed length (``axis``: 3, ``quaternion``: 4)."""
    least: Mapping[str, int] = field(default_factory=dict)
    """Dimensions of a least length (``time``: 2)."""
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


# -- building ---------------------------------------------------------------------------------


def _body(inertia: np.ndarray) -> Body:
    with warnings.catch_warnings():  # warned about when the run was made
        warnings.simplefilter("ignore", InertiaWarning)
        ix, iy, iz = (float(i) for i in np.asarray(inertia))
        return Body((ix, iy, iz))


def build_trajectory(d: Loaded) -> Trajectory:
    return Trajectory(
        t=d["time"], omega=d["omega"], q=d["q"],
        flip_times=d["flip_times"] if int(d["flips_located"]) else None,
        body=_body(d["inertia"]), method=str(d["method"]), dt=float(d["dt"]),
        n_steps=int(d["n_steps"]), nfev=int(d["nfev"]),
        drift=Drift(*(float(d[f"drift_{k}"]) for k in _tables.DRIFTS)),
        n_rejected=int(d["n_rejected"]),
    )


def build_batch(d: Loaded) -> Batch:
    times, offsets = None, None
    if "flips" in d.values:
        counts = d["flips"].astype(np.int64)
        padded = d["flip_times"]
        times = np.concatenate([padded[i, :c] for i, c in enumerate(counts)] + [np.empty(0)])
        offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    return Batch(
        t=d["time"], omega=d["omega"], q=d["q"], _flip_times=times, _flip_offsets=offsets,
        inertia=d["inertia"], method=str(d["method"]), dt=d["dt"],
        n_steps=d["n_steps"].astype(np.int64), nfev=d["nfev"].astype(np.int64),
        n_rejected=d["n_rejected"].astype(np.int64),
        drift=BatchDrift(*(d[f"drift_{k}"] for k in _tables.DRIFTS)),
    )


def build_sweep(d: Loaded) -> Sweep:
    return Sweep(
        inertia=d["inertia"], omega0=d["omega0"], q0=d["q0"],
        flips=d["flips"].astype(np.int64), first_flip=d["first_flip"], period=d["period"],
        exact_period=d["exact_period"], tilt=d["tilt"],
        drift=BatchDrift(*(d[f"drift_{k}"] for k in _tables.DRIFTS)),
        t_end=float(d["t_end"]), method=str(d["method"]), dt=d["dt"],
        n_steps=d["n_steps"].astype(np.int64), nfev=d["nfev"].astype(np.int64),
        status=d["status"].astype(np.asarray(_core.RUN_STATUSES).dtype),
    )


# -- the layouts --------------------------------------------------------------------------------

_COUNT = Attr("i", (non_negative,))
_METHOD = Attr("U", (one_of(tuple(METHODS)),))
_LABELS = {"axis": Var(("axis",), "U", (labels(_tables.AXIS),)),
           "quaternion": Var(("quaternion",), "U", (labels(_tables.QUATERNION),))}
_FIXED = {"axis": 3, "quaternion": 4}

LAYOUTS: Mapping[str, Layout] = {
    "Trajectory": Layout(
        variables={
            "time": Var(("time",), "f", (finite, starts_at_zero_and_increases)),
            **_LABELS,
            "omega": Var(("time", "axis"), "f", (finite,)),
            "q": Var(("time", "quaternion"), "f", (finite,)),
            "flip_times": Var(("flip",), "f", optional=True),
        },
        attrs={
            "method": _METHOD,
            "inertia": Attr("f", (finite, positive, moments), shape=(3,)),
            "dt": Attr("f", (finite, non_negative)),
            "n_steps": _COUNT, "nfev": _COUNT, "n_rejected": _COUNT,
            "flips_located": Attr("i", (flag,)),
            **{f"drift_{k}": Attr("f", (finite, non_negative)) for k in _tables.DRIFTS},
        },
        rules=(trajectory_q_unit, trajectory_flips),
        build=build_trajectory,
        sizes=_FIXED, least={"time": 2},
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
            "flips": Var(("run",), "i", (non_negative,), optional=True),
            "flip_times": Var(("run", "flip"), "f", (finite_or_nan,), optional=True),
        },
        attrs={"method": _METHOD},
        rules=(run_numbers, batch_q_unit, batch_flips),
        build=build_batch,
        sizes=_FIXED, least={"time": 2},
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
}
"""What a file of each kind holds: its variables (dimensions, type, allowed values), its
attributes and the rules between them. The check of a file and the build of its result both
read this table."""


# -- save -------------------------------------------------------------------------------------


def save(result: Trajectory | Batch | Sweep, path: str | Path) -> Path:
    """Writes a result to a netCDF-4 file (xarray, h5netcdf engine) that :func:`load` reads
    back: arrays bit for bit, and the metadata to rebuild the object. All or nothing: the
    previous file is replaced only once the new one is complete, and is as it was after
    any failure (a full disk, Ctrl-C).

    The file is an ordinary netCDF file with the layout of ``result.to_xarray()``: open it
    with ``xarray.open_dataset(path)``, or any netCDF tool.

    Parameters
    ----------
    result : Trajectory, Batch or Sweep
    path : str or Path
        The file to write (replaced if it exists), ending in one of :data:`SUFFIXES`
        (``.nc`` by convention).

    Returns
    -------
    Path

    Raises
    ------
    TypeError
        `result` is none of the three, or `path` not a path.
    ValueError
        `path` ends in another suffix (the message says what writes that format).
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
    kinds = {Trajectory: "Trajectory", Batch: "Batch", Sweep: "Sweep"}
    kind = kinds.get(type(result))
    if kind is None:
        raise TypeError(f"`result` must be a Trajectory, Batch or Sweep, got "
                        f"{type(result).__name__}")
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
    with replacing(p) as tmp:
        image = io.BytesIO()
        ds.to_netcdf(image, engine="h5netcdf")  # in memory: see the module's docs
        with open(tmp, "wb") as f:
            f.write(image.getbuffer())
        del image
    return p


# -- load -------------------------------------------------------------------------------------


def load(path: str | Path) -> Trajectory | Batch | Sweep:
    """Reads a result written by :func:`save`, checking it as strictly as a run checks
    what it computes (see the module's docs and :data:`LAYOUTS`).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    Trajectory, Batch or Sweep

    Raises
    ------
    ReadError
        (a ValueError) The file is missing or not a regular file (a FIFO or a device is
        refused at once), is of another format (named: an AEM, a netCDF-3 file, …), is a
        damaged HDF5 file, was not written by :func:`save`, or holds what a save never
        writes (NaN, quaternions off unit norm, times that run backwards, flip counts that
        do not match the flip times, a variable of the wrong shape); the message names the
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
            except (MemoryError, KeyboardInterrupt, ReadError):
                raise
            except Exception as exc:
                raise ReadError(f"{p} cannot be read (damaged or truncated?): "
                                f"{type(exc).__name__}: {exc}", path=str(p)) from None
    problem = next((msg for rule in layout.rules if (msg := rule(loaded))), None)
    if problem:
        raise ReadError(f"{p} holds a {kind} that dz.save never writes: {problem}",
                        path=str(p))
    result: Trajectory | Batch | Sweep = layout.build(loaded)
    return result


class _Bad(Exception):
    """A field of the file that is not what the layout allows."""


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


_KIND_WORDS = {"f": "float64", "i": "integers", "U": "text"}


def _check_structure(ds: Any, layout: Layout) -> dict[str, tuple[int, ...]]:
    """Each variable's dimensions and type against the layout, before any value is read;
    returns the variables' shapes."""
    grid: tuple[str, ...] | None = None
    sizes: dict[str, int] = {}
    shapes: dict[str, tuple[int, ...]] = {}
    for name, spec in layout.variables.items():
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
        if kind != spec.kind or (kind == "f" and var.dtype != np.float64):
            raise _Bad(f"`{name}` must hold {_KIND_WORDS[spec.kind]}, got {var.dtype}")
        shapes[name] = tuple(var.shape)
    for name in sorted(set(ds.variables) - set(layout.variables)):
        var = ds.variables[name]
        if not (layout.grid_coordinates and grid is not None and name in grid
                and tuple(var.dimensions) == (name,) and _kind_of(var.dtype) in "fi"):
            raise _Bad(f"a variable `{name}` that no save writes (it writes "
                       f"{', '.join(layout.variables)})")
    return shapes


def _read_values(ds: Any, layout: Layout, shapes: dict[str, tuple[int, ...]]) -> Loaded:
    values: dict[str, np.ndarray] = {}
    for name, spec in layout.variables.items():
        if name not in shapes:
            continue
        raw = np.asarray(ds.variables[name][...])
        a = (np.ascontiguousarray(raw, dtype=np.float64) if spec.kind == "f" else
             np.ascontiguousarray(raw, dtype=np.int64) if spec.kind == "i" else
             np.array([v.decode() if isinstance(v, bytes) else str(v) for v in raw.ravel()],
                      dtype=str).reshape(raw.shape))
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
        raise _Bad(f"the attribute `{name}` is missing")
    raw = np.asarray(ds.attrs[name])
    if raw.shape != spec.shape and not (spec.shape == () and raw.shape == (1,)):
        raise _Bad(f"the attribute `{name}` must have shape {spec.shape}, got {raw.shape}")
    kind = _kind_of(raw.dtype)
    if kind != spec.kind and not (spec.kind == "f" and kind == "i"):
        raise _Bad(f"the attribute `{name}` must be {_KIND_WORDS[spec.kind]}, got "
                   f"{raw.dtype}")
    a = raw.astype(np.float64) if spec.kind == "f" else raw
    if spec.kind == "U":
        a = np.asarray([v.decode() if isinstance(v, bytes) else str(v)
                        for v in np.ravel(raw)]).reshape(raw.shape)
    for check in spec.checks:
        if problem := check(np.atleast_1d(a)):
            raise _Bad(f"the attribute `{name}` {problem}")
    attrs[name] = a.reshape(spec.shape) if spec.shape else a.reshape(()).item()
