"""The parts of files written before parts were saved generically (dzhanibekov at main
3f80f7e and earlier, issue 29): one damper as ``damper_inertia``, ``damper_damping``,
``damper_sigma0``; wheels over dim ``wheel`` with ``wheel_position`` (their index among the
parts, the damper taking the one left free) and a schedule in ``wheel_times`` /
``wheel_values``; torques over dim ``torque`` by ``torque_kind`` (``gravity_gradient``,
``constant``, ``tabulated``) with a column per kind's parameter. Read only: :func:`save` writes
the generic layout (:mod:`dzhanibekov.parts._columns`). tests/data/legacy holds files of this
layout written by that version.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .parts import ConstantTorque, Damper, GravityGradient, Part, TabulatedTorque, Wheel

__all__ = ["NAMES", "TORQUE_KINDS", "TORQUE_FRAMES", "TORQUE_OUTSIDE", "check", "parts_of"]

DAMPER_VARS = ("damper_inertia", "damper_damping", "damper_sigma0")
_WHEEL_VARS = ("wheel_axis", "wheel_momentum", "wheel_position")
_SCHEDULE_VARS = ("wheel_times", "wheel_values")
_TORQUE_VARS = ("torque_kind", "torque_orbit_rate", "torque_vector", "torque_frame")
_TABLE_VARS = ("torque_outside", "torque_times", "torque_vectors")
NAMES = (*DAMPER_VARS, *_WHEEL_VARS, *_SCHEDULE_VARS, *_TORQUE_VARS, *_TABLE_VARS)
"""Every variable of the old layout's parts."""

TORQUE_KINDS = ("gravity_gradient", "constant", "tabulated")
"""What ``torque_kind`` named."""
TORQUE_FRAMES = ("body", "world")
TORQUE_OUTSIDE = ("zero", "hold")


def check(d: Any) -> str | None:
    """What is wrong with the old layout's parts of the loaded file `d`, or None."""
    parts = tuple(d["parts"]) if "parts" in d.attrs else ()
    damper = [name in d.values for name in DAMPER_VARS]
    if any(damper) and not all(damper) or all(damper) != ("damper" in parts):
        return ("a damper's `damper_inertia`, `damper_damping` and `damper_sigma0` must be "
                "there exactly when `parts` names the damper")
    if "damper_sigma0" in d.values:
        s0 = np.isnan(d["damper_sigma0"]).reshape(-1, 3)
        if (s0.any(axis=1) != s0.all(axis=1)).any():
            return "`damper_sigma0` must be three rates, or NaN for each (co-rotating)"
    return _wheels_padded(d) or _torques_padded(d)


def _first_then(valid: np.ndarray) -> bool:
    """Whether each row of `valid` (runs, k) is True first, then False."""
    n = valid.sum(axis=1)
    return bool((valid == (np.arange(valid.shape[1]) < n[:, None])).all())


def _wheels_padded(d: Any) -> str | None:
    """Each run's wheels first, then padding; their positions and the damper's (if any)
    number the parts 0, 1, …"""
    have = [name in d.values for name in _WHEEL_VARS]
    schedule = [name in d.values for name in _SCHEDULE_VARS]
    if not any(have):
        return None if not any(schedule) else "`wheel_times` needs the wheels' `wheel_axis`"
    if not all(have):
        return "`wheel_axis`, `wheel_momentum` and `wheel_position` must be there together"
    if any(schedule) != all(schedule):
        return "`wheel_times` and `wheel_values` must be there together"
    position = d["wheel_position"].reshape(-1, d["wheel_position"].shape[-1])
    axis = d["wheel_axis"].reshape(len(position), -1, 3)
    momentum = d["wheel_momentum"].reshape(len(position), -1)
    valid = position >= 0
    if not _first_then(valid) or (position[~valid] != -1).any():
        return "`wheel_position` must hold each run's wheels first, then -1"
    constant = np.isfinite(momentum)
    scheduled = np.zeros_like(valid)
    if all(schedule):
        times = d["wheel_times"].reshape(valid.shape + (-1,))
        values = d["wheel_values"].reshape(times.shape)
        given = ~np.isnan(times)
        scheduled = given.any(axis=2)
        if not _first_then(given.reshape(-1, given.shape[-1])) or \
                (scheduled & (given.sum(axis=2) < 2)).any() or \
                not (np.isfinite(times) == given).all() or \
                not (np.isfinite(values) == given).all():
            return ("`wheel_times` and `wheel_values` must hold a scheduled wheel's knots (at "
                    "least two, finite) first, then NaN, and NaN in any other row")
    if not (np.isfinite(axis).all(axis=2) == valid).all() or \
            not np.isnan(axis[~valid]).all() or (constant & scheduled).any() or \
            not ((constant | scheduled) == valid).all():
        return ("`wheel_axis` must be finite for each run's wheels and NaN beyond them, and "
                "each wheel must have either a finite `wheel_momentum` or a schedule "
                "(`wheel_times`), not both")
    damper = 1 if "damper_inertia" in d.values else 0
    for i, row in enumerate(position):
        taken = sorted(row[row >= 0].tolist())
        parts = len(taken) + damper
        if len(set(taken)) != len(taken) or any(k >= parts for k in taken):
            return (f"`wheel_position` of run {i} must number its wheels among its {parts} "
                    f"parts (0 … {parts - 1}, each once), got {taken}")
    return None


def _torques_padded(d: Any) -> str | None:
    """Each run's torques first, then padding; each row has its kind's parameters and
    nothing in the columns of the other kinds."""
    have = [name in d.values for name in _TORQUE_VARS]
    table = [name in d.values for name in _TABLE_VARS]
    if not any(have):
        return None if not any(table) else "`torque_times` needs the torques' `torque_kind`"
    if not all(have):
        return f"`{'`, `'.join(_TORQUE_VARS)}` must be there together"
    if any(table) != all(table):
        return f"`{'`, `'.join(_TABLE_VARS)}` must be there together"
    kind = d["torque_kind"].reshape(-1, d["torque_kind"].shape[-1])
    frame = d["torque_frame"].reshape(kind.shape)
    rate = d["torque_orbit_rate"].reshape(kind.shape)
    vector = d["torque_vector"].reshape(kind.shape + (3,))
    if not _first_then(kind != ""):
        return "`torque_kind` must hold each run's torques first, then ''"
    gradient, constant = kind == "gravity_gradient", kind == "constant"
    tabulated = kind == "tabulated"
    if tabulated.any() and not all(table):
        return "a tabulated torque needs `torque_outside`, `torque_times` and `torque_vectors`"
    if all(table):
        outside = d["torque_outside"].reshape(kind.shape)
        times = d["torque_times"].reshape(kind.shape + (-1,))
        vectors = d["torque_vectors"].reshape(times.shape + (3,))
        given = ~np.isnan(times)
        if not _first_then(given.reshape(-1, given.shape[-1])) or \
                not (given.any(axis=2) == tabulated).all() or \
                (tabulated & (given.sum(axis=2) < 2)).any() or \
                not (np.isfinite(times) == given).all() or \
                not (np.isfinite(vectors).all(axis=3) == given).all() or \
                not np.isnan(vectors[~given]).all():
            return ("`torque_times` and `torque_vectors` must hold a tabulated torque's knots "
                    "(at least two, finite) first, then NaN, and NaN in any other row")
        if not np.isin(outside[tabulated], TORQUE_OUTSIDE).all() or \
                (outside[~tabulated] != "").any():
            return ("`torque_outside` must be 'zero' or 'hold' for a tabulated torque, '' for "
                    "any other")
    finite_vector = np.isfinite(vector).all(axis=2)
    if not (np.isfinite(rate) == gradient).all() or not np.isnan(rate[~gradient]).all():
        return "`torque_orbit_rate` must be a number exactly for a gravity gradient, else NaN"
    if not (finite_vector == constant).all() or not np.isnan(vector[~constant]).all():
        return "`torque_vector` must be a vector exactly for a constant torque, else NaN"
    framed = constant | tabulated
    if not (np.isin(frame[framed], TORQUE_FRAMES)).all() or \
            (frame[~framed] != "").any():
        return ("`torque_frame` must be 'body' or 'world' for a constant or tabulated torque, "
                "'' for any other")
    return None


def parts_of(d: Any, rows: Any, n: int) -> list[tuple[list[Part], list[Part]]]:
    """Each run's (internal parts in their order, torques in theirs) from the old layout."""
    parts: list[dict[int, Part]] = [{} for _ in range(n)]
    if "wheel_position" in d.values:
        position, axis = rows("wheel_position"), rows("wheel_axis")
        momentum = rows("wheel_momentum")
        shape = position.shape + (0,)
        times = rows("wheel_times") if "wheel_times" in d.values else np.zeros(shape)
        values = rows("wheel_values") if "wheel_values" in d.values else np.zeros(shape)
        for i in range(n):
            for k, a, h, t, v in zip(position[i], axis[i], momentum[i], times[i], values[i]):
                if k >= 0:
                    given = ~np.isnan(t)
                    parts[i][int(k)] = Wheel(tuple(a.tolist()), float(h)) if np.isfinite(h) \
                        else Wheel(tuple(a.tolist()), (t[given], v[given]))
    if "damper_inertia" in d.values:
        j, c, s0 = rows("damper_inertia"), rows("damper_damping"), rows("damper_sigma0")
        for i in range(n):
            free = next(k for k in range(len(parts[i]) + 1) if k not in parts[i])
            parts[i][free] = Damper(float(j[i]), float(c[i]),
                                    None if np.isnan(s0[i]).any() else s0[i])
    torques: list[list[Part]] = \
        [[] for _ in range(n)]
    if "torque_kind" in d.values:
        kind, rate = rows("torque_kind"), rows("torque_orbit_rate")
        vector, frame = rows("torque_vector"), rows("torque_frame")
        for i in range(n):
            for k, kd in enumerate(kind[i]):
                if kd == "gravity_gradient":
                    torques[i].append(GravityGradient(float(rate[i, k])))
                elif kd == "constant":
                    torques[i].append(ConstantTorque(tuple(vector[i, k].tolist()),
                                                     str(frame[i, k])))
                elif kd == "tabulated":
                    t = rows("torque_times")[i, k]
                    given = ~np.isnan(t)
                    torques[i].append(TabulatedTorque(
                        t[given], rows("torque_vectors")[i, k][given], str(frame[i, k]),
                        str(rows("torque_outside")[i, k])))
    return [([p[k] for k in sorted(p)], t) for p, t in zip(parts, torques)]
