"""Results as labelled tables: xarray datasets and pandas data frames (the ``io`` extra).

A leaf: it reads the results' attributes and imports none of the package, so the result
classes can offer ``to_xarray()`` and ``to_dataframe()`` by calling in here. xarray and
pandas are imported on first use, with an error naming the extra when they are missing.

Layout (names follow the package; units are the user's own, consistent set, so variables in
them carry no CF ``units`` and the attribute ``unit_system`` says so; quaternions carry
``"1"`` and angles ``"rad"``):

- ``Trajectory``: dims ``time``, ``axis`` (x, y, z), ``quaternion`` (Q, U, V, W);
  ``omega(time, axis)``, ``q(time, quaternion)``, ``flip_times(flip)``; each part's state
  (``damper(time, axis)``); ``energy(time)``, ``momentum_body(time, axis)`` and
  ``momentum_world(time, axis)`` as the run's system defines them; and the system itself
  (see :func:`system_vars`).
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

from ._core import model_info
from .body import tensor_moments
from .control import _Loop
from .damper import Damper
from .orbit import ConstantTorque, GravityGradient, Wheel
from .torques import TabulatedTorque

__all__ = ["require", "trajectory_dataset", "batch_dataset", "sweep_dataset",
           "deployment_sweep_dataset", "trajectory_frame", "batch_frame", "sweep_frame",
           "system_vars", "knot_vars", "wheel_vars", "torque_vars", "unstorable", "DRIFTS",
           "OPTIONAL_DRIFTS",
           "QUATERNION", "AXIS", "TORQUE_KINDS", "TORQUE_FRAMES", "TORQUE_OUTSIDE"]

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


TORQUE_KINDS = ("gravity_gradient", "constant", "tabulated")
"""What ``torque_kind`` names: one row of the torque table per torque, its parameters in the
columns of its kind (NaN, or ``""`` for text, in the others'; see :func:`system_vars`)."""

TORQUE_FRAMES = ("body", "world")
TORQUE_OUTSIDE = ("zero", "hold")
"""What ``torque_outside`` names for a tabulated torque (its value outside its knots)."""


def unstorable(system: Any) -> list[str]:
    """What of `system` a file cannot hold (its parameters would be lost, and the file would
    load as another system): the parts and torques of kinds the layout has no columns for
    (a :class:`~dzhanibekov.CallableTorque`: a file cannot hold code), by their type's name
    and the model they make (``system.kinds``). Empty when the whole system can be saved."""
    out: list[str] = []
    for part in getattr(system, "parts", ()):
        if not isinstance(part, (Damper, Wheel)):
            out.append(type(part).__name__)
    for torque in getattr(system, "torques", ()):
        if type(torque) not in (GravityGradient, ConstantTorque, TabulatedTorque):
            name = type(torque).__name__
            out.append(f"{name} (callable_torque)" if name == "CallableTorque" else name)
    return out


def system_vars(systems: Any, lead: tuple[str, ...]) -> dict[str, Any]:
    """The variables that describe the systems run (`systems` a sequence of `System`, one per
    index of the leading dims `lead`: ``()`` for one run, ``("run",)`` for a batch), so that
    a file rebuilds each run's own system (`dzhanibekov.io`): the body's tensor in its own
    axes (with its mass and centre of mass), or a deployment's knots (NaN-padded between
    runs); each damper's sphere, coefficient and start (NaN: co-rotating); the wheels (dim
    ``wheel``) and the torques (dim ``torque``), see :func:`wheel_vars` and
    :func:`torque_vars`."""
    items = list(systems)
    first = items[0]
    kinds = tuple(first.kinds)
    squeeze = _squeeze(lead)
    out: dict[str, Any] = {}
    if "deployment" in kinds:
        out |= knot_vars([s.body for s in items], lead)
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
    if "damper" in kinds:
        dampers = [next(p for p in s.parts if type(p).__name__ == "Damper") for s in items]
        sigma0 = np.array([(np.nan,) * 3 if d.sigma0 is None else d.sigma0 for d in dampers])
        out["damper_inertia"] = (lead, squeeze(np.array([d.inertia for d in dampers])),
                                 {"long_name": "damper sphere's moment of inertia"})
        out["damper_damping"] = (lead, squeeze(np.array([d.damping for d in dampers])),
                                 {"long_name": "damper's viscous coefficient"})
        out["damper_sigma0"] = (lead + ("axis",), squeeze(sigma0),
                                {"long_name": "damper sphere's initial rate, body axes (NaN: "
                                 "co-rotating)"})
    out |= wheel_vars(items, lead) | torque_vars(items, lead)
    return out


def wheel_vars(systems: list[Any], lead: tuple[str, ...]) -> dict[str, Any]:
    """The wheels of each system, one row per wheel (dim ``wheel``, padded between runs):
    ``wheel_axis`` as given (not normalised), ``wheel_momentum`` (a constant momentum; NaN
    for a wheel with a schedule), and ``wheel_position``, the wheel's index in
    ``System.parts`` (the damper, if any, takes the index left free), so that the loaded
    system has its parts in their order. Padding: NaN, position −1. When a wheel has a
    momentum schedule, also ``wheel_times`` and ``wheel_values`` (dims ``wheel``,
    ``wheel_knot``): each scheduled wheel's knots first, then NaN; all NaN in the rows of
    constant wheels. None when no system has a wheel."""
    wheels = [[(k, p) for k, p in enumerate(s.parts) if isinstance(p, Wheel)] for s in systems]
    w = max(len(row) for row in wheels)
    if not w:
        return {}
    squeeze = _squeeze(lead)
    axis = np.full((len(systems), w, 3), np.nan)
    momentum = np.full((len(systems), w), np.nan)
    position = np.full((len(systems), w), -1, dtype=np.int64)
    knots = max((len(p.momentum[0]) for row in wheels for _, p in row
                 if isinstance(p.momentum, tuple)), default=0)
    times = np.full((len(systems), w, knots), np.nan)
    values = np.full((len(systems), w, knots), np.nan)
    for i, row in enumerate(wheels):
        for j, (k, wheel) in enumerate(row):
            axis[i, j], position[i, j] = wheel.axis, k
            if isinstance(wheel.momentum, tuple):
                t, v = wheel.momentum
                times[i, j, : len(t)], values[i, j, : len(t)] = t, v
            else:
                momentum[i, j] = wheel.momentum
    out = {
        "wheel_axis": (lead + ("wheel", "axis"), squeeze(axis),
                       {"long_name": "wheel's spin axis, body axes, as given (NaN-padded)"}),
        "wheel_momentum": (lead + ("wheel",), squeeze(momentum),
                           {"long_name": "wheel's constant angular momentum relative to the "
                            "body along its axis (NaN: padding, or a schedule)"}),
        "wheel_position": (lead + ("wheel",), squeeze(position),
                           {"long_name": "wheel's index among the system's parts (-1: "
                            "padding)"}),
    }
    if knots:
        out["wheel_times"] = (lead + ("wheel", "wheel_knot"), squeeze(times),
                              {"long_name": "knot times of a wheel's momentum schedule "
                               "(NaN-padded; all NaN: a constant momentum)"})
        out["wheel_values"] = (lead + ("wheel", "wheel_knot"), squeeze(values),
                               {"long_name": "a wheel's scheduled momentum at each knot, "
                                "linear between them (NaN-padded)"})
    return out


def torque_vars(systems: list[Any], lead: tuple[str, ...]) -> dict[str, Any]:
    """The external torques of each system, one row per torque in their order (dim
    ``torque``, padded between runs): ``torque_kind`` (one of :data:`TORQUE_KINDS`, ``""``
    for padding) and the columns of each kind, NaN (or ``""``) in the rows of the others:
    ``torque_orbit_rate`` (a gravity gradient's), ``torque_vector`` (a constant torque's),
    ``torque_frame`` (a constant or a tabulated torque's), and, when a torque is tabulated,
    ``torque_outside`` (one of :data:`TORQUE_OUTSIDE`), ``torque_times`` (dims ``torque``,
    ``torque_knot``) and ``torque_vectors`` (``torque``, ``torque_knot``, ``axis``), its knots
    first, then NaN. None when no system has a torque. A new kind of torque is a new value
    of ``torque_kind`` and its own columns."""
    rows = [list(s.torques) for s in systems]
    m = max(len(row) for row in rows)
    if not m:
        return {}
    squeeze = _squeeze(lead)
    knots = max((len(t.times) for row in rows for t in row if isinstance(t, TabulatedTorque)),
                default=0)
    kind = np.full((len(systems), m), "", dtype=object)
    frame = np.full((len(systems), m), "", dtype=object)
    outside = np.full((len(systems), m), "", dtype=object)
    rate = np.full((len(systems), m), np.nan)
    vector = np.full((len(systems), m, 3), np.nan)
    times = np.full((len(systems), m, knots), np.nan)
    vectors = np.full((len(systems), m, knots, 3), np.nan)
    for i, row in enumerate(rows):
        for j, torque in enumerate(row):
            if isinstance(torque, GravityGradient):
                kind[i, j], rate[i, j] = "gravity_gradient", torque.orbit_rate
            elif isinstance(torque, TabulatedTorque):
                n = len(torque.times)
                kind[i, j], frame[i, j], outside[i, j] = "tabulated", torque.frame, \
                    torque.outside
                times[i, j, :n], vectors[i, j, :n] = torque.times, torque.vectors
            elif isinstance(torque, _Loop):   # the closed loop's: no columns (not saved)
                kind[i, j] = torque.kind
            else:
                kind[i, j], vector[i, j], frame[i, j] = "constant", torque.vector, torque.frame
    out = {
        "torque_kind": (lead + ("torque",), squeeze(kind.astype(str)),
                        {"long_name": "kind of external torque ('' : padding)"}),
        "torque_orbit_rate": (lead + ("torque",), squeeze(rate),
                              {"long_name": "gravity gradient's orbit rate (NaN: another "
                               "kind)"}),
        "torque_vector": (lead + ("torque", "axis"), squeeze(vector),
                          {"long_name": "constant torque (NaN: another kind)"}),
        "torque_frame": (lead + ("torque",), squeeze(frame.astype(str)),
                         {"long_name": "axes a constant or tabulated torque is given in: body "
                          "or world ('' : another kind)"}),
    }
    if knots:
        out["torque_outside"] = (lead + ("torque",), squeeze(outside.astype(str)),
                                 {"long_name": "a tabulated torque outside its knots: zero or "
                                  "hold ('' : another kind)"})
        out["torque_times"] = (lead + ("torque", "torque_knot"), squeeze(times),
                               {"long_name": "a tabulated torque's knot times (NaN-padded)"})
        out["torque_vectors"] = (lead + ("torque", "torque_knot", "axis"), squeeze(vectors),
                                 {"long_name": "a tabulated torque at its knots, in its frame "
                                  "(NaN-padded)"})
    return out


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


def _derived(prefix: tuple[str, ...], run: Any) -> dict[str, Any]:
    """A run's parts' state and what its system says of each frame."""
    out: dict[str, Any] = {}
    for name, state in run.parts.items():
        fields = model_info(name).state
        if len(fields) == 1 and fields[0][1] == 3:   # one vector, a damper's: the part's name
            out[name] = (prefix + ("time", "axis"), state,
                         {"long_name": f"the {name}'s state (its sphere's rates, body axes)"})
            continue
        at = 0   # a part of several fields (the closed loop's): one variable each, by name
        for field, width, _, about in fields:
            block = state[..., at:at + width]
            at += width
            dims, values = ((prefix + ("time", "axis"), block) if width == 3 else
                            (prefix + ("time",), block[..., 0]) if width == 1 else
                            (prefix + ("time", f"{name}_{field}_index"), block))
            out[f"{name}_{field}"] = (dims, values, {"long_name": f"the {name}'s {about}"})
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
    """Columns u v w Q U V W, each part's state (``damper_x`` …), the energy and the total
    angular momentum in space (``L_x`` …), `rows` rows."""
    pd = require("pandas", "`to_dataframe`")
    columns: dict[str, np.ndarray] = {}
    for k, name in enumerate("uvw"):
        columns[name] = run.omega.reshape(rows, 3)[:, k]
    for k, name in enumerate(QUATERNION):
        columns[name] = run.q.reshape(rows, 4)[:, k]
    for part, state in run.parts.items():
        for k, axis in enumerate(AXIS):
            columns[f"{part}_{axis}"] = state.reshape(rows, -1)[:, k]
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
