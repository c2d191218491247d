"""What a closed-loop run is asked: how far the body points from its target, when its rates
fell below a threshold, and the bits of what saturated, read from a run's frames."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ._args import as_float
from ._core import model_info
from .mass import quaternion_product
from ._tables import model_of_state
from .lvlh import lvlh_frame
from .control import QuaternionFeedback
from .results import Trajectory

__all__ = ["pointing_angle", "detumbled_at", "part_state", "saturation"]


def _pointing_part(traj: Trajectory) -> QuaternionFeedback:
    if not isinstance(traj, Trajectory):
        raise TypeError(f"`traj` must be a Trajectory, got {type(traj).__name__}")
    parts: list[QuaternionFeedback] = [p for p in traj.system.parts
                                       if isinstance(p, QuaternionFeedback)]
    if not parts:
        raise ValueError("`traj` must be a run of a system with a dz.QuaternionFeedback")
    return parts[0]


def pointing_angle(traj: Trajectory) -> np.ndarray:
    """The angle between the body and its :class:`~dzhanibekov.QuaternionFeedback`'s target
    at each frame, radians in ``[0, π]``: ``2 atan2(|δq_v|, |δq₀|)``, ``δq = q_t* ⊗ q``, the
    target fixed in space or in the orbiting frame (:func:`~dzhanibekov.lvlh_frame`).

    Raises
    ------
    ValueError
        The run's system has no quaternion feedback.

    Examples
    --------
    >>> import numpy as np
    >>> import dzhanibekov as dz
    >>> sat = dz.System(dz.Body((2.0, 3.0, 4.0)), parts=[dz.QuaternionFeedback(0.5, 1.5, 0.1)])
    >>> traj = dz.simulate(sat, (0, 0, 0), (np.cos(0.25), 0, 0, np.sin(0.25)), t_end=60.0)
    >>> a = dz.pointing_angle(traj)
    >>> round(float(a[0]), 12), bool(a[-1] < 1e-3)
    (0.5, True)
    """
    part = _pointing_part(traj)
    target = np.array(part.target if part.target is not None else (1.0, 0.0, 0.0, 0.0))
    target = target / np.linalg.norm(target)
    if part.frame == "lvlh":
        assert part.orbit_rate is not None
        target = quaternion_product(lvlh_frame(traj.t, part.orbit_rate), target)
    conj = target * np.array([1.0, -1.0, -1.0, -1.0])
    dq = quaternion_product(conj, traj.q)
    angle: np.ndarray = 2 * np.arctan2(np.linalg.norm(dq[..., 1:], axis=-1), np.abs(dq[..., 0]))
    return angle


def detumbled_at(traj: Trajectory, rate: float) -> float:
    """The first frame's time from which the body's rate ``|ω|`` stays below `rate`; inf if
    it never does (by the last frame).

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> def damp(t, q, omega, field, h):
    ...     return -omega
    >>> sat = dz.System(dz.Body((1.0, 1.0, 1.0)), parts=[dz.Controller(damp, 0.01)])
    >>> traj = dz.simulate(sat, (0.0, 0.0, 1.0), t_end=10.0, frames=101, method="dop853")
    >>> round(dz.detumbled_at(traj, 0.5), 9)        # e^(−t) < 0.5 from ln 2 ≈ 0.69
    0.7
    """
    if not isinstance(traj, Trajectory):
        raise TypeError(f"`traj` must be a Trajectory, got {type(traj).__name__}")
    limit = as_float("rate", rate, positive=True)
    above = np.flatnonzero(np.linalg.norm(traj.omega, axis=1) >= limit)
    if above.size == 0:
        return float(traj.t[0])
    if above[-1] == len(traj.t) - 1:
        return math.inf
    return float(traj.t[above[-1] + 1])


def part_state(traj: Trajectory, kind: str) -> dict[str, np.ndarray]:
    """The state of the run's part of model `kind` (a name of ``dz.MODELS``, or
    ``<model>_<k>`` for the ``k``-th of several parts of one model, as ``traj.parts`` names
    them) by field, as the core declares it: each ``(frames, width)``.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> sat = dz.System(dz.Body((2.0, 3.0, 4.0)), parts=[dz.QuaternionFeedback(0.5, 1.5, 0.1)])
    >>> traj = dz.simulate(sat, (0.0, 0.0, 0.1), t_end=1.0, frames=3)
    >>> {k: v.shape for k, v in dz.part_state(traj, "quaternion_feedback").items()}
    {'wheel_momentum': (3, 3), 'wheel_torque': (3, 3), 'saturated': (3, 1)}
    """
    if not isinstance(traj, Trajectory):
        raise TypeError(f"`traj` must be a Trajectory, got {type(traj).__name__}")
    if kind not in traj.parts:
        raise ValueError(f"`kind` must be one of the run's parts with state "
                         f"({', '.join(map(repr, traj.parts)) or 'none'}), got {kind!r}")
    block, out, at = traj.parts[kind], {}, 0
    for name, width, *_ in model_info(model_of_state(kind) or kind).state:
        out[name] = block[:, at:at + width]
        at += width
    return out


_BITS = {"bdot": ("coil",), "momentum_dumping": ("coil",),
         "quaternion_feedback": ("torque", "momentum"),
         "controller": ("torque", "momentum", "coil")}


def saturation(traj: Trajectory, kind: str) -> dict[str, np.ndarray]:
    """What saturated at each frame's last sample, decoded from the part's ``saturated``
    bits: ``coil`` (magnetorquers), ``torque`` and ``momentum`` (wheels), each a boolean
    ``(frames, 3)`` array, one column per coil or wheel.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> slew = dz.QuaternionFeedback(1.0, 3.0, 0.5, torque_limit=1e-3)
    >>> sat = dz.System(dz.Body((2.0, 3.0, 4.0)), parts=[slew])
    >>> traj = dz.simulate(sat, (0.0, 0.0, 0.0), (0.8, 0.6, 0.0, 0.0), t_end=2.0, frames=3)
    >>> dz.saturation(traj, "quaternion_feedback")["torque"][-1].tolist()
    [True, False, False]
    """
    names: Any = _BITS.get(kind)
    if names is None:
        raise ValueError(f"`kind` must be one of {', '.join(map(repr, _BITS))}, got {kind!r}")
    bits = part_state(traj, kind)["saturated"][:, 0].astype(np.int64)
    return {name: ((bits[:, None] >> (3 * k + np.arange(3))) & 1).astype(bool)
            for k, name in enumerate(names)}
