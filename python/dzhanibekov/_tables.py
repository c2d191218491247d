"""Results as labelled tables: xarray datasets and pandas data frames (the ``io`` extra).

A leaf: it reads the results' attributes and imports none of the package, so the result
classes can offer ``to_xarray()`` and ``to_dataframe()`` by calling in here. xarray and
pandas are imported on first use, with an error naming the extra when they are missing.

Layout (names follow the package; units are the user's own, consistent set, so variables in
them carry no CF ``units`` and the attribute ``unit_system`` says so; quaternions carry
``"1"`` and angles ``"rad"``):

- ``Trajectory``: dims ``time``, ``axis`` (x, y, z), ``quaternion`` (Q, U, V, W);
  ``omega(time, axis)``, ``q(time, quaternion)``, ``flip_times(flip)``.
- ``Batch``: the same with a leading ``run``; ``flip_times(run, flip)`` padded with NaN
  beyond each run's ``flips``.
- ``Sweep``: one dim per axis of the starts, named for the parameter that varies along it
  alone (``u0``, ``v0``, ``w0``, ``Ix``, ``Iy``, ``Iz``, as from ``dz.grid``) with its values
  as the coordinate, else ``run`` (``run_0``, ``run_1``, … for several axes).
"""

from __future__ import annotations

import importlib
from typing import Any

import numpy as np

__all__ = ["require", "trajectory_dataset", "batch_dataset", "sweep_dataset",
           "trajectory_frame", "batch_frame", "sweep_frame", "DRIFTS", "QUATERNION", "AXIS"]

AXIS = ("x", "y", "z")
QUATERNION = ("Q", "U", "V", "W")
DRIFTS = ("energy", "momentum", "momentum_world", "q_norm")
PARAMETERS = (("u0", "omega0", 0), ("v0", "omega0", 1), ("w0", "omega0", 2),
              ("Ix", "inertia", 0), ("Iy", "inertia", 1), ("Iz", "inertia", 2))
"""Sweep parameters a grid axis may vary: name, attribute, component."""

EXTRA = 'the `io` extra: pip install ".[io]" from a checkout (xarray, pandas, h5netcdf, h5py)'

Q_DOC = ("attitude world-from-body, unit quaternion scalar first (Q, U, V, W): "
         "x_world = M(q) x_body")
UNIT_SYSTEM = ("the user's own consistent units, not named in the file: times in a time unit T "
               "(time, flip_times, periods), angular velocities in rad/T, moments of inertia "
               "in M L^2; quaternions and angles (rad) carry CF units")
"""The global attribute ``unit_system``: the runs' units are the user's own, so the variables
measured in them carry no CF ``units`` (a CF reader would misread any invented one)."""


def require(module: str, what: str, extra: str = EXTRA) -> Any:
    """Imports optional `module` for `what`, or raises ImportError naming the `extra`."""
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise ImportError(f"{what} needs {module}, which is not installed; install {extra}") \
            from exc


def _attrs(run: Any) -> dict[str, Any]:
    return {"method": run.method, "dzhanibekov_conventions": Q_DOC + "; omega in body axes",
            "unit_system": UNIT_SYSTEM}


def _vars(prefix: tuple[str, ...], omega: np.ndarray, q: np.ndarray) -> dict[str, Any]:
    return {
        "omega": (prefix + ("time", "axis"), omega,
                  {"long_name": "body-frame angular velocity (u, v, w)"}),
        "q": (prefix + ("time", "quaternion"), q, {"long_name": Q_DOC, "units": "1"}),
    }


def _coords(t: np.ndarray) -> dict[str, Any]:
    return {"time": ("time", t, {"long_name": "time"}),
            "axis": ("axis", list(AXIS)), "quaternion": ("quaternion", list(QUATERNION))}


def trajectory_dataset(traj: Any) -> Any:
    """A ``Trajectory`` as an ``xarray.Dataset`` (see the module's docs)."""
    xr = require("xarray", "`to_xarray`")
    data = _vars((), traj.omega, traj.q)
    attrs = _attrs(traj) | {
        "inertia": np.array(traj.body.inertia, dtype=np.float64), "dt": traj.dt,
        "n_steps": traj.n_steps, "nfev": traj.nfev, "n_rejected": traj.n_rejected,
        "flips_located": int(traj.flip_times is not None),
    } | {f"drift_{k}": float(v) for k, v in zip(DRIFTS, traj.drift)}
    if traj.flip_times is not None:
        data["flip_times"] = ("flip", traj.flip_times, {"long_name": "flip times"})
    return xr.Dataset(data, coords=_coords(traj.t), attrs=attrs)


def batch_dataset(batch: Any) -> Any:
    """A ``Batch`` as an ``xarray.Dataset``: dims ``run`` and ``time`` (see the module)."""
    xr = require("xarray", "`to_xarray`")
    m = len(batch)
    data = _vars(("run",), batch.omega, batch.q)
    data["inertia"] = (("run", "axis"), batch.inertia, {"long_name": "principal moments"})
    for name in ("dt", "n_steps", "nfev", "n_rejected"):
        data[name] = ("run", np.asarray(getattr(batch, name)))
    for name, values in zip(DRIFTS, batch.drift):
        data[f"drift_{name}"] = ("run", np.asarray(values))
    if batch.flip_times is not None:
        counts = np.asarray(batch.flips)
        padded = np.full((m, int(counts.max(initial=0))), np.nan)
        for i, times in enumerate(batch.flip_times):
            padded[i, : len(times)] = times
        data["flips"] = ("run", counts, {"long_name": "flips counted"})
        data["flip_times"] = (("run", "flip"), padded,
                              {"long_name": "flip times, NaN beyond each run's flips"})
    coords = _coords(batch.t) | {"run": ("run", np.arange(m))}
    return xr.Dataset(data, coords=coords, attrs=_attrs(batch))


def grid_axes(sweep: Any) -> list[tuple[str, np.ndarray | None]]:
    """Per axis of the sweep's starts: the name of the parameter that varies along it alone
    and its values, or ``("run…", None)``."""
    shape = sweep.shape
    found: list[tuple[str, np.ndarray | None]] = []
    for axis in range(len(shape)):
        others = tuple(k for k in range(len(shape)) if k != axis)
        for name, attr, comp in PARAMETERS:
            values = np.asarray(getattr(sweep, attr))[..., comp]
            if shape[axis] < 2 or any(name == n for n, _ in found):
                continue
            varies = np.ptp(values, axis=axis).max() > 0
            constant = not others or np.ptp(values, axis=others).max() == 0
            if varies and constant:
                index = tuple(slice(None) if k == axis else 0 for k in range(len(shape)))
                found.append((name, values[index]))
                break
        else:
            found.append(("run" if len(shape) == 1 else f"run_{axis}", None))
    return found


def sweep_dataset(sweep: Any) -> Any:
    """A ``Sweep`` as an ``xarray.Dataset``, one dim per axis of its starts (see the module)."""
    xr = require("xarray", "`to_xarray`")
    axes = grid_axes(sweep)
    dims = tuple(name for name, _ in axes)
    data: dict[str, Any] = {
        "inertia": (dims + ("axis",), sweep.inertia, {"long_name": "principal moments"}),
        "omega0": (dims + ("axis",), sweep.omega0,
                   {"long_name": "initial body-frame angular velocity"}),
        "q0": (dims + ("quaternion",), sweep.q0, {"long_name": "initial " + Q_DOC}),
        "flips": (dims, sweep.flips, {"long_name": "flips counted"}),
        "first_flip": (dims, sweep.first_flip, {"long_name": "time of the first flip"}),
        "period": (dims, sweep.period, {"long_name": "measured flip period"}),
        "exact_period": (dims, sweep.exact_period,
                         {"long_name": "exact flip period 2K(m)/lambda"}),
        "tilt": (dims, sweep.tilt, {"long_name": "largest tilt of the spin axis",
                                    "units": "rad"}),
        "dt": (dims, sweep.dt), "n_steps": (dims, sweep.n_steps), "nfev": (dims, sweep.nfev),
        "status": (dims, sweep.status.astype(str),
                   {"long_name": "how the run ended (ok, diverged, too many steps, ...)"}),
    }
    for name, values in zip(DRIFTS, sweep.drift):
        data[f"drift_{name}"] = (dims, values)
    coords: dict[str, Any] = {"axis": ("axis", list(AXIS)),
                              "quaternion": ("quaternion", list(QUATERNION))}
    for name, values in axes:
        if values is not None:
            coords[name] = (name, values)
    attrs = {"method": sweep.method, "t_end": sweep.t_end,
             "dzhanibekov_conventions": Q_DOC + "; omega in body axes",
             "unit_system": UNIT_SYSTEM}
    return xr.Dataset(data, coords=coords, attrs=attrs)


def _frame(index: Any, omega: np.ndarray, q: np.ndarray) -> Any:
    pd = require("pandas", "`to_dataframe`")
    columns = np.concatenate([omega, q], axis=1)
    return pd.DataFrame(columns, index=index, columns=["u", "v", "w", *QUATERNION])


def trajectory_frame(traj: Any) -> Any:
    """A ``Trajectory`` as a ``pandas.DataFrame``: index ``t``, columns u v w Q U V W."""
    pd = require("pandas", "`to_dataframe`")
    return _frame(pd.Index(traj.t, name="t"), traj.omega, traj.q)


def batch_frame(batch: Any) -> Any:
    """A ``Batch`` as a ``pandas.DataFrame``: index (``run``, ``t``), columns u v w Q U V W."""
    pd = require("pandas", "`to_dataframe`")
    m, n = batch.omega.shape[:2]
    index = pd.MultiIndex.from_product([np.arange(m), batch.t], names=["run", "t"])
    return _frame(index, batch.omega.reshape(m * n, 3), batch.q.reshape(m * n, 4))


def sweep_frame(sweep: Any) -> Any:
    """A ``Sweep`` as a ``pandas.DataFrame``: one row per run (in the starts' C order), its
    inputs and what it measured as columns."""
    pd = require("pandas", "`to_dataframe`")
    n = len(sweep)
    columns: dict[str, np.ndarray] = {}
    for k, name in enumerate(("Ix", "Iy", "Iz")):
        columns[name] = sweep.inertia.reshape(n, 3)[:, k]
    for k, name in enumerate(("u0", "v0", "w0")):
        columns[name] = sweep.omega0.reshape(n, 3)[:, k]
    for k, name in enumerate(QUATERNION):
        columns[f"{name}0"] = sweep.q0.reshape(n, 4)[:, k]
    for name in ("flips", "first_flip", "period", "exact_period", "tilt", "dt", "n_steps",
                 "nfev"):
        columns[name] = np.asarray(getattr(sweep, name)).reshape(n)
    for name, values in zip(DRIFTS, sweep.drift):
        columns[f"drift_{name}"] = np.asarray(values).reshape(n)
    return pd.DataFrame(columns, index=pd.RangeIndex(n, name="run"))
