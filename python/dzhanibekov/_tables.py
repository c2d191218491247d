"""Results as labelled tables: xarray datasets and pandas data frames (the ``io`` extra).

It reads the results' attributes and imports of the package only the bodies and the parts'
declarations (no result class), so the result classes can offer ``to_xarray()`` and
``to_dataframe()`` by calling in here. xarray and
pandas are imported on first use, with an error naming the extra when they are missing.

Layout (names follow the package; units are the user's own, consistent set, so variables in
them carry no CF ``units`` and the attribute ``unit_system`` says so; quaternions carry
``"1"`` and angles ``"rad"``):

- ``Trajectory``: dims ``time``, ``axis`` (x, y, z), ``quaternion`` (Q, U, V, W);
  ``omega(time, axis)``, ``q(time, quaternion)``, ``flip_times(flip)``; each part's state
  under the name the run shows it (``damper(time, axis)``, ``hinge_angle(time)``; the
  ``k``-th of several parts of a model as ``<model>_<k>``: ``damper_1(time, axis)``,
  ``hinge_3_angle(time)``, the part on row ``k`` of ``part_<model>``); ``energy(time)``, ``momentum_body(time, axis)`` and
  ``momentum_world(time, axis)`` as the run's system defines them; and the system itself
  (see :func:`system_vars`): the body, and each part's fields under its model
  (``part_kind(part)``, ``part_<model>_<parameter>(part_<model>, …)``, see
  :mod:`dzhanibekov.parts._columns`).
- ``Batch``: the same with a leading ``run``; ``flip_times(run, flip)`` padded with NaN
  beyond each run's ``flips``.
- ``DeploymentSweep``: per run (dim ``run``) its verdict, the deployed moments and rates,
  and each run's deployment (its knots).
- ``Sweep``: one dim per axis of the starts, named for the parameter that varies along it
  alone (``u0``, ``v0``, ``w0``, ``Ix``, ``Iy``, ``Iz``, as from ``dz.grid``) with its values
  as the coordinate, else ``run`` (``run_0``, ``run_1``, … for several axes).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from typing import Any

import numpy as np

from . import _core
from .body import tensor_moments
from .parts import _columns

__all__ = ["require", "trajectory_dataset", "batch_dataset", "sweep_dataset",
           "deployment_sweep_dataset", "trajectory_frame", "batch_frame", "sweep_frame",
           "system_vars", "knot_vars", "unstorable", "DRIFTS", "OPTIONAL_DRIFTS",
           "QUATERNION", "AXIS", "model_of_state", "state_names",
           "state_fields", "state_dims"]

AXIS = ("x", "y", "z")
QUATERNION = ("Q", "U", "V", "W")
DRIFTS = ("energy", "momentum", "momentum_world", "q_norm")
OPTIONAL_DRIFTS = ("jacobi", "energy_balance")
"""The drift's measures a model may have (an orbit's Jacobi integral, the energy balance of
a system whose parts dissipate): stored only when the run has them."""
PARAMETERS = (("u0", "omega0", 0), ("v0", "omega0", 1), ("w0", "omega0", 2),
              ("Ix", "inertia", 0), ("Iy", "inertia", 1), ("Iz", "inertia", 2))
"""Sweep parameters a grid axis may vary: name, attribute, component."""

EXTRA = ('the `io` extra: pip install "dzhanibekov[io]" (xarray, pandas, h5netcdf, h5py; '
         'by the package\'s name it installs only those, without rebuilding the core)')

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


unstorable = _columns.unstorable


def system_vars(systems: Any, lead: tuple[str, ...]) -> dict[str, Any]:
    """The variables that describe the systems run (`systems` a sequence of `System`, one per
    index of the leading dims `lead`: ``()`` for one run, ``("run",)`` for a batch), so that
    a file rebuilds each run's own system (`dzhanibekov.io`): the body's tensor in its own
    axes (with its mass and centre of mass), or a deployment's knots (NaN-padded between
    runs); and every part's fields under its model, whatever the model
    (:mod:`dzhanibekov.parts._columns`)."""
    items = list(systems)
    first = items[0]
    kinds = tuple(first.kinds)
    squeeze = _squeeze(lead)
    out: dict[str, Any] = {}
    if "deployment" in kinds:
        out |= knot_vars([s.body for s in items], lead)
        masses = [s.body.mass for s in items]
        if any(m is not None for m in masses):  # it carries parts whose mass moves
            out["knot_mass"] = (lead, squeeze(np.array([np.nan if m is None else m
                                                        for m in masses])),
                                {"long_name": "the deploying body's mass (NaN: not given)"})
    else:
        tensor = np.stack([s.body.tensor for s in items])
        mass = np.array([np.nan if s.body.mass is None else s.body.mass for s in items])
        com = np.stack([s.body.center_of_mass for s in items])
        out["body_tensor"] = (lead + ("axis", "axis_"), squeeze(tensor),
                              {"long_name": "inertia tensor about the centre of mass, body "
                               "axes (L = T omega)"})
        out["body_mass"] = (lead, squeeze(mass), {"long_name": "mass (NaN: not given)"})
        out["body_center_of_mass"] = (lead + ("axis",), squeeze(com),
                                      {"long_name": "centre of mass, body coordinates"})
        out |= shape_vars([s.body for s in items])
    for name, (dims, values, about) in _columns.columns(items).items():
        out[name] = (lead + dims, squeeze(values), {"long_name": about})
    return out


def shape_vars(bodies: list[Any]) -> dict[str, Any]:
    """The outline the pictures draw of the bodies (a box's edges, an ellipsoid's sections, a
    composite's or a mesh's own), when every run's body has the same one: its points
    ``body_vertices(body_vertex, axis)`` about the centre of mass in the body's own axes, the
    lines ``body_edges(body_edge, body_edge_end)`` joining them and, for a surface, the
    triangles ``body_faces(body_face, body_face_corner)``. None for a body given only by its
    moments or tensor (drawn as a box of its moments), or when the runs' outlines differ."""
    shape = bodies[0].shape
    if shape is None or any(b.shape is not shape and not _same_shape(b.shape, shape)
                            for b in bodies[1:]):
        return {}
    out = {"body_vertices": (("body_vertex", "axis"), np.asarray(shape.vertices, np.float64),
                             {"long_name": "points of the body's outline, body axes about "
                              "the centre of mass"}),
           "body_edges": (("body_edge", "body_edge_end"), np.asarray(shape.edges, np.int64),
                          {"long_name": "lines of the outline: indices of body_vertices"})}
    if shape.faces is not None:
        out["body_faces"] = (("body_face", "body_face_corner"),
                             np.asarray(shape.faces, np.int64),
                             {"long_name": "triangles of the surface: indices of "
                              "body_vertices"})
    return out


def _same_shape(a: Any, b: Any) -> bool:
    return (a is not None and np.array_equal(a.vertices, b.vertices)
            and np.array_equal(a.edges, b.edges)
            and (a.faces is None) == (b.faces is None)
            and (a.faces is None or np.array_equal(a.faces, b.faces)))


def _squeeze(lead: tuple[str, ...]) -> Callable[[np.ndarray], np.ndarray]:
    """A single run's values without the run axis; a batch's as they are."""
    return (lambda a: a) if lead else (lambda a: a[0])


def knot_vars(deployments: Any, lead: tuple[str, ...]) -> dict[str, Any]:
    """Deployments' knots (NaN-padded between runs), for :func:`system_vars`."""
    items = list(deployments)
    squeeze = _squeeze(lead)
    k = max(len(d.times) for d in items)
    times = np.full((len(items), k), np.nan)
    tensors = np.full((len(items), k, 3, 3), np.nan)
    for i, d in enumerate(items):
        times[i, : len(d.times)] = d.times
        tensors[i, : len(d.times)] = d.tensors
    return {"knot_times": (lead + ("knot",), squeeze(times),
                           {"long_name": "deployment knot times (NaN-padded)"}),
            "knot_tensors": (lead + ("knot", "axis", "axis_"), squeeze(tensors),
                             {"long_name": "deployment knot tensors, body axes"})}


def model_of_state(name: str) -> str | None:
    """The model of the part whose state a run shows under `name` (``run.parts``): the
    model's own name for the only part of its model with state, ``<model>_<k>`` for the
    ``k``-th of several (the core's naming, :attr:`System.part_names`; ``k`` is also the
    part's row along ``part_<model>`` of the parameters' columns). None for a name that is
    no part's."""
    models = {m.name for m in _core.MODELS}
    if name in models:
        return name
    model, _, k = name.rpartition("_")
    return model if model in models and k.isdigit() and str(int(k)) == k else None


def state_names(models: Any) -> list[str]:
    """The names a run shows the state of parts of `models` under (the models of a system's
    parts with state, in the system's order), as the core names them: the model's name for
    the only one of its model, ``<model>_<k>`` for the ``k``-th of several."""
    models = list(models)
    seen: dict[str, int] = {}
    out = []
    for m in models:
        k = seen.get(m, 0)
        seen[m] = k + 1
        out.append(m if models.count(m) == 1 else f"{m}_{k}")
    return out


def state_fields(name: str) -> list[tuple[str, str, int, str]]:
    """The variables of the state shown under `name` (see :func:`model_of_state`): (variable,
    field, width, what it holds), as :func:`_derived` writes them: `name` itself for a state
    of one 3-vector (a damper's σ), else ``<name>_<field>`` per field."""
    model = model_of_state(name)
    if model is None:
        raise ValueError(f"{name!r} names no part's state")
    fields = _core.model_info(model).state
    if len(fields) == 1 and fields[0][1] == 3:
        return [(name, fields[0][0], 3, fields[0][3])]
    return [(f"{name}_{field}", field, width, about) for field, width, _, about in fields]


def state_dims(variable: str, width: int) -> tuple[str, ...]:
    """The dims of a state variable after ``time``: none for a number, ``axis`` for a
    3-vector, else ``<variable>_index``."""
    return () if width == 1 else ("axis",) if width == 3 else (f"{variable}_index",)


def rate_variable(name: str) -> tuple[str, int, str]:
    """The variable of the rates of the coordinates of the part shown as `name` (one whose
    mass moves, see ``Trajectory.part_rates``), their width and what the coordinates are:
    ``<name>_<field>_rate`` of its state's first field (``hinge_angle_rate``)."""
    var, _, width, about = state_fields(name)[0]
    return f"{var}_rate", width, about


def _derived(prefix: tuple[str, ...], run: Any) -> dict[str, Any]:
    """A run's parts' state and what its system says of each frame: each part's state under
    the name the run shows it (the model's, or ``<model>_<k>`` for the ``k``-th of several
    parts of a model, see :func:`state_fields`)."""
    out: dict[str, Any] = {}
    for name, state in run.parts.items():
        at = 0   # one variable per field, by name (a damper's σ: the part's name alone)
        for var, field, width, about in state_fields(name):
            block = state[..., at:at + width]
            at += width
            values = block[..., 0] if width == 1 else block
            out[var] = (prefix + ("time",) + state_dims(var, width), values,
                        {"long_name": f"the {name}'s {about}"})
    for name, rate in run.part_rates.items():
        var, width, about = rate_variable(name)
        out[var] = (prefix + ("time",) + state_dims(var, width),
                    rate[..., 0] if width == 1 else rate,
                    {"long_name": f"the rate of the {name}'s {about}"})
    inv = run.invariants()
    out["energy"] = (prefix + ("time",), inv["energy"],
                     {"long_name": "total kinetic energy"})
    out["momentum_body"] = (prefix + ("time", "axis"), inv["momentum_body"],
                            {"long_name": "total angular momentum, body axes"})
    out["momentum_world"] = (prefix + ("time", "axis"), inv["momentum_world"],
                             {"long_name": "total angular momentum in space"})
    return out


def _drift_attrs(drift: Any) -> dict[str, Any]:
    out: dict[str, Any] = {f"drift_{k}": float(getattr(drift, k)) for k in DRIFTS}
    out["drift_kept"] = list(drift.kept)
    for name in OPTIONAL_DRIFTS:
        if getattr(drift, name) is not None:
            out[f"drift_{name}"] = float(getattr(drift, name))
    return out


def trajectory_dataset(traj: Any) -> Any:
    """A ``Trajectory`` as an ``xarray.Dataset`` (see the module's docs)."""
    xr = require("xarray", "`to_xarray`")
    data = _vars((), traj.omega, traj.q) | _derived((), traj) | system_vars([traj.system], ())
    attrs = _attrs(traj) | {
        "inertia": np.array(traj.body.inertia if hasattr(traj.body, "inertia") else
                            tensor_moments(traj.system.tensor_at(0.0)), dtype=np.float64),
        "dt": traj.dt, "n_steps": traj.n_steps, "nfev": traj.nfev,
        "n_rejected": traj.n_rejected, "flips_located": int(traj.flip_times is not None),
        "parts": list(traj.system.part_names),
    } | _drift_attrs(traj.drift)
    if traj.flip_times is not None:
        data["flip_times"] = ("flip", traj.flip_times, {"long_name": "flip times"})
    return xr.Dataset(data, coords=_coords(traj.t), attrs=attrs)


def batch_dataset(batch: Any) -> Any:
    """A ``Batch`` as an ``xarray.Dataset``: dims ``run`` and ``time`` (see the module)."""
    xr = require("xarray", "`to_xarray`")
    m = len(batch)
    data = _vars(("run",), batch.omega, batch.q)
    if m:
        data |= _derived(("run",), batch) | system_vars(batch.systems, ("run",))
    data["inertia"] = (("run", "axis"), batch.inertia, {"long_name": "principal moments"})
    for name in ("dt", "n_steps", "nfev", "n_rejected"):
        data[name] = ("run", np.asarray(getattr(batch, name)))
    for name, values in zip(DRIFTS, batch.drift):
        data[f"drift_{name}"] = ("run", np.asarray(values))
    for name in OPTIONAL_DRIFTS:
        if getattr(batch.drift, name) is not None:
            data[f"drift_{name}"] = ("run", np.asarray(getattr(batch.drift, name)))
    padded = batch.flip_times_padded
    if padded is not None:
        counts = np.asarray(batch.flips)
        data["flips"] = ("run", counts, {"long_name": "flips counted"})
        data["flip_times"] = (("run", "flip"), padded,
                              {"long_name": "flip times, NaN beyond each run's flips"})
    coords = _coords(batch.t) | {"run": ("run", np.arange(m))}
    attrs = _attrs(batch) | {"drift_kept": list(batch.drift.kept),
                             "parts": list(batch.parts)}
    return xr.Dataset(data, coords=coords, attrs=attrs)


def deployment_sweep_dataset(sweep: Any) -> Any:
    """A ``DeploymentSweep`` as an ``xarray.Dataset``: dim ``run`` (see the module)."""
    xr = require("xarray", "`to_xarray`")
    data: dict[str, Any] = {
        "omega0": (("run", "axis"), sweep.omega0,
                   {"long_name": "initial body-frame angular velocity"}),
        "q0": (("run", "quaternion"), sweep.q0, {"long_name": "initial " + Q_DOC}),
        "inertia": (("run", "axis"), sweep.inertia,
                    {"long_name": "the deployed body's principal moments"}),
        "omega_deployed": (("run", "axis"), sweep.omega_deployed,
                           {"long_name": "rates at t_end, the deployed body's principal axes"}),
        "flip_period": ("run", sweep.flip_period,
                        {"long_name": "the deployed motion's flip period"}),
        "tumbles": ("run", sweep.tumbles.astype(np.int8), {"long_name": "1: tumbles"}),
        "energy_change": ("run", sweep.energy_change,
                          {"long_name": "relative change of the kinetic energy"}),
        "dt": ("run", sweep.dt), "n_steps": ("run", sweep.n_steps),
        "nfev": ("run", sweep.nfev),
        "status": ("run", sweep.status.astype(str),
                   {"long_name": "how the run ended (ok, diverged, too many steps)"}),
    }
    for name, values in zip(DRIFTS, sweep.drift):
        data[f"drift_{name}"] = ("run", np.asarray(values))
    if len(sweep):
        data |= knot_vars(sweep.deployments, ("run",))
    coords = {"run": ("run", np.arange(len(sweep))), "axis": ("axis", list(AXIS)),
              "quaternion": ("quaternion", list(QUATERNION))}
    attrs = {"method": sweep.method, "t_end": sweep.t_end,
             "drift_kept": list(sweep.drift.kept),
             "dzhanibekov_conventions": Q_DOC + "; omega in body axes",
             "unit_system": UNIT_SYSTEM}
    return xr.Dataset(data, coords=coords, attrs=attrs)


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


def _frame(index: Any, run: Any, rows: int) -> Any:
    """Columns u v w Q U V W, each part's state (``damper_x`` …, ``hinge_angle``, each of
    several of a model by its index: ``damper_0_x``), the energy and the total
    angular momentum in space (``L_x`` …), `rows` rows."""
    pd = require("pandas", "`to_dataframe`")
    columns: dict[str, np.ndarray] = {}
    for k, name in enumerate("uvw"):
        columns[name] = run.omega.reshape(rows, 3)[:, k]
    for k, name in enumerate(QUATERNION):
        columns[name] = run.q.reshape(rows, 4)[:, k]
    for part, state in run.parts.items():
        flat, at = state.reshape(rows, -1), 0
        for var, _, width, _ in state_fields(part):
            names = ([var] if width == 1 else [f"{var}_{axis}" for axis in AXIS] if width == 3
                     else [f"{var}_{i}" for i in range(width)])
            for k, column in enumerate(names):
                columns[column] = flat[:, at + k]
            at += width
    for part, rate in run.part_rates.items():
        var, width, _ = rate_variable(part)
        names = [var] if width == 1 else [f"{var}_{axis}" for axis in AXIS]
        for k, column in enumerate(names):
            columns[column] = rate.reshape(rows, width)[:, k]
    if rows:
        columns["energy"] = run.energy.reshape(rows)
        for k, axis in enumerate(AXIS):
            columns[f"L_{axis}"] = run.momentum_world.reshape(rows, 3)[:, k]
    return pd.DataFrame(columns, index=index)


def trajectory_frame(traj: Any) -> Any:
    """A ``Trajectory`` as a ``pandas.DataFrame``: index ``time`` (see :func:`_frame`)."""
    pd = require("pandas", "`to_dataframe`")
    return _frame(pd.Index(traj.t, name="time"), traj, len(traj.t))


def batch_frame(batch: Any) -> Any:
    """A ``Batch`` as a ``pandas.DataFrame``: index (``run``, ``time``) (see :func:`_frame`)."""
    pd = require("pandas", "`to_dataframe`")
    m, n = batch.omega.shape[:2]
    index = pd.MultiIndex.from_product([np.arange(m), batch.t], names=["run", "time"])
    return _frame(index, batch, m * n)


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
