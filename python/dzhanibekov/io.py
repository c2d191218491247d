"""Results into files other tools read: netCDF (through xarray) and CCSDS attitude messages.

- :func:`save` / :func:`load`: a `Trajectory`, `Batch`, `Sweep` or `DeploymentSweep` as a
  netCDF-4 file (xarray with the h5netcdf engine; the ``io`` extra). Arrays round-trip bit
  for bit, and the file carries what is needed to rebuild the object: each run's system
  (the body's tensor, a deployment's knots, the parts with their parameters), every part's
  state, so that what a loaded run derives (energy, angular momentum in space) is the
  saved run's, bit for bit.
- :func:`write_aem` / :func:`read_aem`: a trajectory's attitudes as a CCSDS Attitude
  Ephemeris Message (CCSDS 504.0-B-2, KVN), the text file spacecraft attitude tools take.

**The attitude in an AEM.** The package's ``q`` is world-from-body, scalar first:
``x_world = M(q) x_body``. Read as a *coordinate transformation*, the same q takes a
vector's world coordinates to its body coordinates: ``x_body = M(q)ᵀ x_world``, and its
axis and angle are those of the rotation that carries the world axes onto the body axes.
That is the AEM's quaternion from ``REF_FRAME_A`` (the world, an inertial frame such as
``EME2000``) to ``REF_FRAME_B`` (the body, ``SC_BODY_1``), with the same four numbers:
version 2.0 (the default) writes them scalar last, ``Q1 Q2 Q3 QC`` = ``U V W Q``, as the
standard fixes; version 1.0 says ``ATTITUDE_DIR = A2B`` and ``QUATERNION_TYPE = FIRST``
and writes ``QC Q1 Q2 Q3`` = ``Q U V W``. Rates (``rates=True``) are the body's angular
velocity in body axes (``ANGVEL_FRAME``/``RATE_FRAME`` = ``REF_FRAME_B``), in degrees per
second as the standard asks.
"""

from __future__ import annotations

import datetime as _dt
import re
import warnings
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from . import _core, _tables
from .body import Body
from .damper import Damper
from .deployment import Deployment
from .results import Batch, BatchDrift, DeploymentSweep, Drift, Sweep, Trajectory, split_parts
from .system import System, Systems

__all__ = ["save", "load", "write_aem", "read_aem", "AttitudeEphemeris"]

_KIND = "dzhanibekov_result"


# -- netCDF ------------------------------------------------------------------------------


def save(result: Trajectory | Batch | Sweep | DeploymentSweep, path: str | Path) -> Path:
    """Writes a result to a netCDF-4 file (xarray, h5netcdf engine) that :func:`load` reads
    back: arrays bit for bit, and the metadata to rebuild the object.

    The file is an ordinary netCDF file with the layout of ``result.to_xarray()``: open it
    with ``xarray.open_dataset(path)``, or any netCDF tool.

    Parameters
    ----------
    result : Trajectory, Batch, Sweep or DeploymentSweep
    path : str or Path
        The file to write (replaced if it exists); ``.nc`` by convention.

    Returns
    -------
    Path

    Raises
    ------
    TypeError
        `result` is none of these.
    ImportError
        xarray or h5netcdf is missing: install the ``io`` extra.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0))
    >>> path = dz.save(traj, "run.nc")                            # doctest: +SKIP
    >>> bool((dz.load(path).q == traj.q).all())                   # doctest: +SKIP
    True
    """
    kinds = {Trajectory: "Trajectory", Batch: "Batch", Sweep: "Sweep",
             DeploymentSweep: "DeploymentSweep"}
    kind = kinds.get(type(result))
    if kind is None:
        raise TypeError(f"`result` must be a Trajectory, Batch, Sweep or DeploymentSweep, "
                        f"got {type(result).__name__}")
    _tables.require("h5netcdf", "`save`")
    _tables.require("h5py", "`save`")
    ds = result.to_xarray()
    ds.attrs[_KIND] = kind
    path = Path(path)
    ds.to_netcdf(path, engine="h5netcdf")
    return path


def load(path: str | Path) -> Trajectory | Batch | Sweep | DeploymentSweep:
    """Reads a result written by :func:`save`.

    Raises
    ------
    ValueError
        The file was not written by :func:`save`.
    ImportError
        xarray or h5netcdf is missing: install the ``io`` extra.
    """
    xr = _tables.require("xarray", "`load`")
    _tables.require("h5netcdf", "`load`")
    _tables.require("h5py", "`load`")
    with xr.open_dataset(Path(path), engine="h5netcdf") as handle:
        ds = handle.load()
    kind = ds.attrs.get(_KIND)
    if kind == "Trajectory":
        return _trajectory(ds)
    if kind == "Batch":
        return _batch(ds)
    if kind == "Sweep":
        return _sweep(ds)
    if kind == "DeploymentSweep":
        return _deployment_sweep(ds)
    raise ValueError(f"{path} was not written by dzhanibekov.save (no `{_KIND}` attribute)")


def _array(ds: Any, name: str, dtype: Any = np.float64) -> np.ndarray:
    return np.ascontiguousarray(ds[name].values, dtype=dtype)


def _systems(ds: Any, runs: int | None) -> list[System]:
    """The systems a file describes (see `_tables.system_vars`): one (`runs` None) or one
    per run."""
    def rows(name: str) -> np.ndarray:
        a = np.asarray(ds[name].values, dtype=np.float64)
        return a[None] if runs is None else a

    n = 1 if runs is None else runs
    bodies: list[Any]
    if "knot_times" in ds:
        bodies = _deployments(rows("knot_times"), rows("knot_tensors"))
    else:
        tensor, mass, com = rows("body_tensor"), rows("body_mass"), rows("body_center_of_mass")
        bodies = [Body._restored(tensor[i], None if np.isnan(mass[i]) else float(mass[i]),
                                 com[i]) for i in range(n)]
    parts: list[list[Damper]] = [[] for _ in range(n)]
    if "damper_inertia" in ds:
        j, c, s0 = rows("damper_inertia"), rows("damper_damping"), rows("damper_sigma0")
        for i in range(n):
            parts[i].append(Damper(float(j[i]), float(c[i]),
                                   None if np.isnan(s0[i]).any() else s0[i]))
    return [System(b, parts=p) for b, p in zip(bodies, parts)]


def _deployments(times: np.ndarray, tensors: np.ndarray) -> list[Deployment]:
    """Deployments from NaN-padded knots, one per row."""
    return [Deployment(t[~np.isnan(t)], k[~np.isnan(t)]) for t, k in zip(times, tensors)]


def _drift(a: Any) -> Drift:
    jacobi = a.get("drift_jacobi")
    row = BatchDrift.of(lambda k: np.asarray([float(a[f"drift_{k}"])]),
                        None if jacobi is None else np.asarray([float(jacobi)]),
                        _names(a, "drift_kept"))
    return row.row(0)


def _names(a: Any, key: str) -> tuple[str, ...]:
    """A list of names an attribute holds (netCDF keeps one as a string)."""
    value = a.get(key, ())
    return (str(value),) if isinstance(value, str) else tuple(str(v) for v in value)


def _trajectory(ds: Any) -> Trajectory:
    a = ds.attrs
    system = _systems(ds, None)[0]
    parts = np.concatenate([_array(ds, name) for name in system.part_names], axis=1) \
        if system.part_names else None
    return Trajectory(
        t=_array(ds, "time"),
        omega=_array(ds, "omega"),
        q=_array(ds, "q"),
        flip_times=_array(ds, "flip_times") if int(a["flips_located"]) else None,
        system=system,
        method=str(a["method"]),
        dt=float(a["dt"]),
        n_steps=int(a["n_steps"]),
        nfev=int(a["nfev"]),
        drift=_drift(a),
        n_rejected=int(a["n_rejected"]),
        parts=split_parts(system, parts),
    )


def _batch(ds: Any) -> Batch:
    times, offsets = None, None
    if "flips" in ds:
        counts = _array(ds, "flips", np.int64)
        padded = _array(ds, "flip_times").reshape(len(counts), -1)
        times = np.concatenate([padded[i, :c] for i, c in enumerate(counts)] + [np.empty(0)])
        offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    m = int(ds.sizes["run"])
    systems = Systems(m, each=tuple(_systems(ds, m))) if m else Systems(0, each=())
    names = _names(ds.attrs, "parts")
    parts = {name: _array(ds, name) for name in names}
    jacobi = _array(ds, "drift_jacobi") if "drift_jacobi" in ds else None
    return Batch(
        t=_array(ds, "time"),
        omega=_array(ds, "omega"),
        q=_array(ds, "q"),
        _flip_times=times,
        _flip_offsets=offsets,
        systems=systems,
        method=str(ds.attrs["method"]),
        dt=_array(ds, "dt"),
        n_steps=_array(ds, "n_steps", np.int64),
        nfev=_array(ds, "nfev", np.int64),
        n_rejected=_array(ds, "n_rejected", np.int64),
        drift=BatchDrift.of(lambda k: _array(ds, f"drift_{k}"), jacobi,
                            _names(ds.attrs, "drift_kept")),
        parts=parts,
    )


def _deployment_sweep(ds: Any) -> DeploymentSweep:
    m = int(ds.sizes["run"])
    deployments = _deployments(_array(ds, "knot_times").reshape(m, -1),
                               _array(ds, "knot_tensors").reshape(m, -1, 3, 3)) if m else []
    return DeploymentSweep(
        deployments=tuple(deployments),
        omega0=_array(ds, "omega0"),
        q0=_array(ds, "q0"),
        inertia=_array(ds, "inertia"),
        omega_deployed=_array(ds, "omega_deployed"),
        flip_period=_array(ds, "flip_period"),
        tumbles=_array(ds, "tumbles", np.int8).astype(bool),
        energy_change=_array(ds, "energy_change"),
        drift=BatchDrift.of(lambda k: _array(ds, f"drift_{k}"), None,
                            _names(ds.attrs, "drift_kept")),
        t_end=float(ds.attrs["t_end"]),
        method=str(ds.attrs["method"]),
        dt=_array(ds, "dt"),
        n_steps=_array(ds, "n_steps", np.int64),
        nfev=_array(ds, "nfev", np.int64),
        status=_array(ds, "status", np.asarray(_core.RUN_STATUSES).dtype),
    )


def _sweep(ds: Any) -> Sweep:
    return Sweep(
        inertia=_array(ds, "inertia"),
        omega0=_array(ds, "omega0"),
        q0=_array(ds, "q0"),
        flips=_array(ds, "flips", np.int64),
        first_flip=_array(ds, "first_flip"),
        period=_array(ds, "period"),
        exact_period=_array(ds, "exact_period"),
        tilt=_array(ds, "tilt"),
        drift=BatchDrift.of(lambda k: _array(ds, f"drift_{k}")),
        t_end=float(ds.attrs["t_end"]),
        method=str(ds.attrs["method"]),
        dt=_array(ds, "dt"),
        n_steps=_array(ds, "n_steps", np.int64),
        nfev=_array(ds, "nfev", np.int64),
        status=_array(ds, "status", np.asarray(_core.RUN_STATUSES).dtype),
    )


# -- CCSDS Attitude Ephemeris Message ----------------------------------------------------

AEM_VERSIONS = ("1.0", "2.0")


class AttitudeEphemeris(NamedTuple):
    """What :func:`read_aem` read: the attitudes in the package's convention."""

    header: dict[str, str]
    """The header's keywords (``CCSDS_AEM_VERS``, ``CREATION_DATE``, ``ORIGINATOR`` …)."""
    metadata: dict[str, str]
    """The segment's metadata keywords (``OBJECT_NAME``, ``REF_FRAME_A`` …)."""
    epochs: list[str]
    """The data lines' epochs as written."""
    t: np.ndarray
    """Seconds since the first epoch, shape (N,)."""
    q: np.ndarray
    """Unit quaternions (N, 4), scalar first, world-from-body (``REF_FRAME_A``-from-
    ``REF_FRAME_B``), whatever order and direction the file used."""
    omega: np.ndarray | None
    """Angular velocity (N, 3) in body axes (``REF_FRAME_B``), rad/s; None without rates."""


def _epoch(value: Any) -> _dt.datetime:
    if isinstance(value, _dt.datetime):
        if value.tzinfo is not None:
            return value.astimezone(_dt.timezone.utc).replace(tzinfo=None)
        return value
    if isinstance(value, str):
        return _parse_epoch(value, "epoch")
    raise TypeError(f"`epoch` must be a datetime or an ISO 8601 string, got "
                    f"{type(value).__name__}")


_EPOCH = re.compile(r"^(\d{4})-(?:(\d{2})-(\d{2})|(\d{3}))T(\d{2}):(\d{2}):(\d{2}(?:\.\d*)?)Z?$")


def _parse_epoch(text: str, what: str) -> _dt.datetime:
    """A CCSDS epoch ``YYYY-MM-DDThh:mm:ss[.d…]`` or ``YYYY-DDDThh:mm:ss[.d…]`` (to the µs)."""
    match = _EPOCH.match(text.strip())
    if match is None:
        raise ValueError(f"`{what}` must be a time like 2026-01-01T00:00:00.000, got {text!r}")
    year, month, day, doy, hour, minute, second = match.groups()
    whole, _, fraction = second.partition(".")
    micro = int((fraction + "000000")[:6])
    base = (_dt.datetime(int(year), int(month), int(day)) if doy is None
            else _dt.datetime(int(year), 1, 1) + _dt.timedelta(days=int(doy) - 1))
    return base + _dt.timedelta(hours=int(hour), minutes=int(minute), seconds=int(whole),
                                microseconds=micro)


def _format_epoch(t: _dt.datetime) -> str:
    return t.strftime("%Y-%m-%dT%H:%M:%S.%f")


def _keyword(name: str, value: Any) -> str:
    text = str(value)
    if not text or "\n" in text or not text.isprintable():
        raise ValueError(f"`{name}` must be one printable line of text, got {value!r}")
    return text


def write_aem(
    traj: Trajectory,
    path: str | Path,
    object_name: str,
    object_id: str,
    epoch: _dt.datetime | str,
    *,
    time_unit: float = 1.0,
    ref_frame_a: str = "EME2000",
    ref_frame_b: str = "SC_BODY_1",
    center_name: str | None = None,
    time_system: str = "UTC",
    originator: str = "DZHANIBEKOV",
    rates: bool = False,
    version: str = "2.0",
    comment: str | None = None,
) -> Path:
    """Writes a trajectory's attitudes as a CCSDS Attitude Ephemeris Message (KVN text).

    One data line per frame: its epoch and quaternion (and with `rates`, the body rates).
    The quaternion is the package's ``q`` unchanged in value: the transformation from
    `ref_frame_a` (the world) to `ref_frame_b` (the body) — see the module's docs.

    Parameters
    ----------
    traj : Trajectory
    path : str or Path
        The file to write (``.aem`` by convention).
    object_name, object_id : str
        The spacecraft's name and its international designator (``YYYY-NNNP{PP}``).
    epoch : datetime or str
        The time of the first frame (``t = 0``), in `time_system`; a string like
        ``"2026-01-01T00:00:00"``. Epochs are written to the microsecond.
    time_unit : float
        Seconds per time unit of the run (the package's units are the user's own).
    ref_frame_a, ref_frame_b : str
        The world (inertial) frame and the body frame, by their CCSDS names.
    center_name : str, optional
        Written as ``CENTER_NAME`` when given.
    time_system : str
        ``TIME_SYSTEM``, e.g. UTC, TAI, TT, GPS.
    originator : str
    rates : bool
        Also write the body rates: ``QUATERNION/ANGVEL`` (version 2.0) or
        ``QUATERNION/RATE`` (version 1.0), in degrees per second, in body axes.
    version : {"2.0", "1.0"}
        ``CCSDS_AEM_VERS``: 2.0 (CCSDS 504.0-B-2) fixes the order ``Q1 Q2 Q3 QC`` and the
        direction A to B; 1.0 (504.0-B-1) states them (``QUATERNION_TYPE = FIRST``,
        ``ATTITUDE_DIR = A2B``).
    comment : str, optional
        A ``COMMENT`` line in the metadata.

    Returns
    -------
    Path

    Raises
    ------
    TypeError
        `traj` is not a Trajectory, or `epoch` not a time.
    ValueError
        A keyword value that is empty or not one line, a bad `version` or `time_unit`.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), frames=3)
    >>> dz.io.write_aem(traj, "box.aem", "BOX", "2026-001A", "2026-01-01T00:00:00")
    ... # doctest: +SKIP
    """
    if not isinstance(traj, Trajectory):
        raise TypeError(f"`traj` must be a Trajectory, got {type(traj).__name__}")
    if version not in AEM_VERSIONS:
        raise ValueError(f"`version` must be one of {AEM_VERSIONS}, got {version!r}")
    if (isinstance(time_unit, bool) or not isinstance(time_unit, (int, float))
            or not np.isfinite(time_unit) or time_unit <= 0):
        raise ValueError(f"`time_unit` must be a positive number of seconds, got {time_unit!r}")
    start = _epoch(epoch)
    epochs = [_format_epoch(start + _dt.timedelta(seconds=float(t) * time_unit))
              for t in traj.t]
    header = [f"CCSDS_AEM_VERS = {version}",
              f"CREATION_DATE = {_format_epoch(_dt.datetime.now(_dt.timezone.utc))}",
              f"ORIGINATOR = {_keyword('originator', originator)}"]
    meta = ["META_START"]
    if comment is not None:
        meta.append(f"COMMENT {_keyword('comment', comment)}")
    meta += [f"OBJECT_NAME = {_keyword('object_name', object_name)}",
             f"OBJECT_ID = {_keyword('object_id', object_id)}"]
    if center_name is not None:
        meta.append(f"CENTER_NAME = {_keyword('center_name', center_name)}")
    meta += [f"REF_FRAME_A = {_keyword('ref_frame_a', ref_frame_a)}",
             f"REF_FRAME_B = {_keyword('ref_frame_b', ref_frame_b)}"]
    if version == "1.0":
        meta.append("ATTITUDE_DIR = A2B")
    meta += [f"TIME_SYSTEM = {_keyword('time_system', time_system)}",
             f"START_TIME = {epochs[0]}", f"STOP_TIME = {epochs[-1]}"]
    if version == "1.0":
        meta.append(f"ATTITUDE_TYPE = {'QUATERNION/RATE' if rates else 'QUATERNION'}")
        meta.append("QUATERNION_TYPE = FIRST")
        if rates:
            meta.append("RATE_FRAME = REF_FRAME_B")
    else:
        meta.append(f"ATTITUDE_TYPE = {'QUATERNION/ANGVEL' if rates else 'QUATERNION'}")
        if rates:
            meta.append(f"ANGVEL_FRAME = {ref_frame_b}")
    meta.append("META_STOP")
    q = traj.q if version == "1.0" else traj.q[:, [1, 2, 3, 0]]
    columns = [q] + ([np.degrees(traj.omega) / time_unit] if rates else [])
    values = np.concatenate(columns, axis=1)
    data = ["DATA_START"] + [
        " ".join([e] + [repr(float(x)) for x in row]) for e, row in zip(epochs, values)
    ] + ["DATA_STOP"]
    path = Path(path)
    path.write_text("\n".join(header + [""] + meta + [""] + data) + "\n", encoding="ascii")
    return path


def read_aem(path: str | Path) -> AttitudeEphemeris:
    """Reads a CCSDS Attitude Ephemeris Message (KVN) of quaternions, one segment.

    Versions 1.0 and 2.0; ``QUATERNION`` and ``QUATERNION/ANGVEL`` (2.0) or
    ``QUATERNION/RATE`` (1.0). The quaternions are returned in the package's convention
    (scalar first, world-from-body), turned from the file's order and direction.

    Raises
    ------
    ValueError
        Not an AEM, several segments, an attitude type other than quaternions, or a data
        line of the wrong length, naming the line.
    """
    header: dict[str, str] = {}
    metadata: dict[str, str] = {}
    rows: list[list[str]] = []
    section, segments = "header", 0
    lines = Path(path).read_text(encoding="ascii").splitlines()
    for number, raw in enumerate(lines, 1):
        line = raw.strip()
        if not line or line.startswith("COMMENT"):
            continue
        if line in ("META_START", "META_STOP", "DATA_START", "DATA_STOP"):
            if line == "META_START":
                segments += 1
                if segments > 1:
                    raise ValueError(f"{path}:{number}: several segments; read_aem reads one")
            section = {"META_START": "meta", "DATA_START": "data"}.get(line, "between")
            continue
        if section == "data":
            rows.append(line.split())
        elif section in ("header", "meta"):
            key, eq, value = line.partition("=")
            if not eq:
                raise ValueError(f"{path}:{number}: expected KEYWORD = value, got {line!r}")
            (header if section == "header" else metadata)[key.strip()] = value.strip()
    version = header.get("CCSDS_AEM_VERS")
    if version is None:
        raise ValueError(f"{path} is not an AEM: no CCSDS_AEM_VERS")
    kind = metadata.get("ATTITUDE_TYPE", "").upper()
    rates = kind in ("QUATERNION/ANGVEL", "QUATERNION/RATE")
    if kind != "QUATERNION" and not rates:
        raise ValueError(f"{path}: ATTITUDE_TYPE {kind!r} is not read; read_aem reads "
                         "QUATERNION, QUATERNION/ANGVEL and QUATERNION/RATE")
    width = 1 + 4 + (3 if rates else 0)
    for row in rows:
        if len(row) != width:
            raise ValueError(f"{path}: a data line of {kind} has {width} fields, got {row}")
    values = np.array([[float(x) for x in row[1:]] for row in rows], dtype=np.float64)
    values = values.reshape(len(rows), width - 1)
    first = version.startswith("1") and metadata.get("QUATERNION_TYPE", "").upper() == "FIRST"
    q = values[:, :4] if first else values[:, [3, 0, 1, 2]]
    if version.startswith("1") and metadata.get("ATTITUDE_DIR", "A2B").upper() == "B2A":
        q = q * np.array([1.0, -1.0, -1.0, -1.0])  # the inverse transformation
    omega = None
    if rates:
        omega = np.radians(values[:, 4:7])
        frame = metadata.get("ANGVEL_FRAME", metadata.get("RATE_FRAME", "REF_FRAME_B"))
        if frame in ("REF_FRAME_A", metadata.get("REF_FRAME_A")):  # world axes: into body
            omega = np.einsum("nji,nj->ni", _matrices(q), omega)
    epochs = [row[0] for row in rows]
    times = [_parse_epoch(e, "epoch") for e in epochs]
    t = np.array([(x - times[0]).total_seconds() for x in times]) if times else np.empty(0)
    return AttitudeEphemeris(header, metadata, epochs, t, np.ascontiguousarray(q), omega)


def _matrices(q: np.ndarray) -> np.ndarray:
    """``M(q)`` for unit scalar-first quaternions, shape (N, 3, 3)."""
    w, x, y, z = (q / np.linalg.norm(q, axis=1, keepdims=True)).T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
    ], axis=1)
