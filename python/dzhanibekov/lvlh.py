"""The orbiting (LVLH) frame: where a body in a circular orbit is, and its attitude
relative to the frame that follows the orbit.

**The orbit.** A circular orbit of rate ``n`` in the world x–y plane: the body's centre is
at ``r̂(t) = (cos nt, sin nt, 0)`` from the planet (``t = 0`` at world +x), the orbit normal
is world +z. **The orbiting frame** (LVLH, Hughes's ``F_o``) has its axes, in world axes,

- ``o1 = (−sin nt, cos nt, 0)``: along-track (the velocity),
- ``o2 = (0, 0, −1)``: minus the orbit normal,
- ``o3 = (−cos nt, −sin nt, 0)``: nadir (toward the planet),

and turns at ``n`` about the orbit normal (``−o2``). A body aligned with it and at rest in it
has body rates ``ω = (0, −n, 0)``; :func:`lvlh_start` gives the start of any attitude and
rates relative to it. Roll, pitch and yaw are the turns about ``o1``, ``o2``, ``o3``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ._args import as_array, as_float
from .mass import quaternion_product
from .orbit import GravityGradient
from .results import Batch, Trajectory

__all__ = ["lvlh_frame", "lvlh_attitude", "lvlh_start", "lvlh_angles", "nadir_angles"]


# world-from-LVLH at t = 0: columns o1 = +y, o2 = −z, o3 = −x
_Q_LVLH0 = np.array([0.5, -0.5, -0.5, 0.5])


def lvlh_frame(t: Any, orbit_rate: Any) -> np.ndarray:
    """The orbiting frame's attitude at times `t`: world-from-LVLH quaternions, scalar first.

    Parameters
    ----------
    t : array_like
        Times, any shape.
    orbit_rate : float
        The orbit's rate ``n``, positive.

    Returns
    -------
    ndarray, shape t.shape + (4,)
        ``q_o(t) = q_z(nt) ⊗ q_o(0)``, whose rotation has the columns along-track, minus the
        orbit normal and nadir (see the module doc).

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> dz.lvlh_frame(0.0, 1.0).tolist()
    [0.5, -0.5, -0.5, 0.5]
    """
    n = as_float("orbit_rate", orbit_rate, positive=True)
    if isinstance(t, (str, bytes)) or t is None:
        raise TypeError(f"`t` must be times (a number or an array of them), got {t!r}")
    try:
        times = np.asarray(t, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"`t` must be times (a number or an array of them), got {t!r}") from None
    if not np.isfinite(times).all():
        raise ValueError("`t` must hold finite times")
    half = 0.5 * n * times
    turn = np.stack([np.cos(half), np.zeros_like(half), np.zeros_like(half), np.sin(half)],
                    axis=-1)
    return quaternion_product(turn, _Q_LVLH0)


def lvlh_attitude(traj: Any, orbit_rate: Any | None = None) -> np.ndarray:
    """The attitude relative to the orbiting frame: LVLH-from-body quaternions
    ``q_o(t)* ⊗ q(t)``, scalar first, one a frame.

    Parameters
    ----------
    traj : Trajectory
        A run (its ``t`` and ``q``); a :class:`Batch` too (quaternions ``(runs, frames, 4)``).
    orbit_rate : float, optional
        The orbit's rate; by default the run's system's :class:`GravityGradient`'s.

    Returns
    -------
    ndarray, shape q.shape
        Identity where the body's axes are along-track, minus orbit normal and nadir.

    Raises
    ------
    ValueError
        No `orbit_rate` given and the run's system has no gravity gradient.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> sat = dz.System(dz.Body((2.0, 3.0, 1.0)), torques=[dz.GravityGradient(1.0)])
    >>> traj = dz.simulate(sat, *dz.lvlh_start(1.0), t_end=5.0, method="dop853", rtol=1e-10)
    >>> bool(abs(dz.lvlh_attitude(traj)[:, 0]).min() > 1 - 1e-9)   # stays aligned
    True
    """
    if not isinstance(traj, (Trajectory, Batch)):
        raise TypeError(f"`traj` must be a Trajectory or a Batch, got {type(traj).__name__}")
    if orbit_rate is None:
        rates = [t.orbit_rate for t in getattr(getattr(traj, "system", None), "torques", ())
                 if isinstance(t, GravityGradient)]
        if not rates:
            raise ValueError("`orbit_rate` must be given: the run's system has no "
                             "dz.GravityGradient")
        orbit_rate = rates[0]
    q = np.asarray(traj.q, dtype=np.float64)
    frame = lvlh_frame(traj.t, orbit_rate)
    conj = frame * np.array([1.0, -1.0, -1.0, -1.0])
    return quaternion_product(conj, q)


def lvlh_angles(traj: Any, orbit_rate: Any | None = None) -> np.ndarray:
    """How far the body is turned from the orbiting frame: the angle (radians, in
    ``[0, π]``) of the rotation :func:`lvlh_attitude` gives, one a frame.

    Parameters
    ----------
    traj : Trajectory or Batch
        A run (or runs) in orbit.
    orbit_rate : float, optional
        The orbit's rate; by default the run's system's :class:`GravityGradient`'s.

    Returns
    -------
    ndarray, shape q.shape[:-1]
        ``2 atan2(|v|, |w|)`` of each LVLH-from-body quaternion ``(w, v)``: the shorter way.

    Examples
    --------
    >>> import math
    >>> import dzhanibekov as dz
    >>> sat = dz.System(dz.Body((2.0, 3.0, 1.0)), torques=[dz.GravityGradient(1.0)])
    >>> yawed = (math.cos(0.1), 0.0, 0.0, math.sin(0.1))   # 0.2 rad about nadir
    >>> traj = dz.simulate(sat, *dz.lvlh_start(1.0, yawed), t_end=1.0, frames=2)
    >>> round(float(dz.lvlh_angles(traj)[0]), 12)
    0.2
    """
    q = lvlh_attitude(traj, orbit_rate)
    angles: np.ndarray = 2.0 * np.arctan2(np.linalg.norm(q[..., 1:], axis=-1), np.abs(q[..., 0]))
    return angles


def nadir_angles(traj: Any, orbit_rate: Any | None = None) -> np.ndarray:
    """The angle (radians, in ``[0, π]``) of the body's z axis from nadir, one a frame.

    A body aligned with the orbiting frame has its z axis on nadir (``o3``; see the module
    doc). The gravity gradient holds a body with z on nadir or on zenith, so an angle past
    ``π/2`` means the body has left nadir's basin: what ``ask="leaves_nadir"`` of
    :func:`~dzhanibekov.monte_carlo` asks. A turn about nadir (yaw) leaves it at 0.

    Parameters
    ----------
    traj : Trajectory or Batch
        A run (or runs) in orbit.
    orbit_rate : float, optional
        The orbit's rate; by default the run's system's :class:`GravityGradient`'s.

    Returns
    -------
    ndarray, shape q.shape[:-1]
        The angle between the body's z axis and ``o3``, from its components in LVLH axes.

    Examples
    --------
    >>> import math
    >>> import dzhanibekov as dz
    >>> sat = dz.System(dz.Body((2.0, 3.0, 1.0)), torques=[dz.GravityGradient(1.0)])
    >>> rolled = (math.cos(0.15), math.sin(0.15), 0.0, 0.0)   # 0.3 rad about along-track
    >>> traj = dz.simulate(sat, *dz.lvlh_start(1.0, rolled), t_end=1.0, frames=2)
    >>> round(float(dz.nadir_angles(traj)[0]), 12)
    0.3
    """
    q = lvlh_attitude(traj, orbit_rate)
    q0, q1, q2, q3 = np.moveaxis(q / np.linalg.norm(q, axis=-1, keepdims=True), -1, 0)
    # the body's z in LVLH axes is the rotation's third column; atan2 keeps small angles exact
    across = np.hypot(2.0 * (q1 * q3 + q0 * q2), 2.0 * (q2 * q3 - q0 * q1))
    angles: np.ndarray = np.arctan2(across, 1.0 - 2.0 * (q1 * q1 + q2 * q2))
    return angles


def lvlh_start(orbit_rate: Any, q_rel: Any = (1.0, 0.0, 0.0, 0.0), omega_rel: Any = (0.0, 0.0, 0.0),
               *, pitch: Any = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """The start ``(omega0, q0)`` at ``t = 0`` of a body with attitude `q_rel` and rates
    `omega_rel` relative to the orbiting frame, for :func:`~dzhanibekov.simulate`.

    ``q0 = q_o(0) ⊗ q_rel`` and ``ω0 = ω_rel + n ẑ_b``, with ``ẑ_b`` the orbit normal in
    body axes: at rest in LVLH a body still turns at ``n`` about the orbit normal.

    Parameters
    ----------
    orbit_rate : float
        The orbit's rate ``n``, positive.
    q_rel : array_like, shape (4,)
        LVLH-from-body attitude, scalar first (normalised); identity: aligned.
    omega_rel : array_like, shape (3,)
        Rates relative to the orbiting frame, in body axes.
    pitch : float, optional
        A pitch angle (radians, about ``o2``, minus the orbit normal) applied after `q_rel`.

    Returns
    -------
    omega0 : ndarray, shape (3,)
    q0 : ndarray, shape (4,)

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> omega0, q0 = dz.lvlh_start(0.5)
    >>> omega0.tolist(), q0.tolist()
    ([0.0, -0.5, 0.0], [0.5, -0.5, -0.5, 0.5])
    """
    n = as_float("orbit_rate", orbit_rate, positive=True)
    q = as_array("q_rel", q_rel, "(4,)", last=4, ndim=(1,))
    norm = float(np.linalg.norm(q))
    if norm == 0.0:
        raise ValueError("`q_rel` must not be zero")
    w = as_array("omega_rel", omega_rel, "(3,)", last=3, ndim=(1,))
    angle = as_float("pitch", pitch)
    turn = np.array([math.cos(angle / 2), 0.0, math.sin(angle / 2), 0.0])
    q = quaternion_product(q / norm, turn)
    q0 = quaternion_product(_Q_LVLH0, q)
    # the orbit normal, world +z, is −o2: in body axes −M(q)ᵀ e2 (M's second row)
    u0, u1, u2, u3 = q
    o2 = np.array([2 * (u1 * u2 + u0 * u3), u0 * u0 - u1 * u1 + u2 * u2 - u3 * u3,
                   2 * (u2 * u3 - u0 * u1)])
    return w - n * o2, q0


def jacobi_values(traj: Trajectory) -> np.ndarray:
    """The Jacobi integral ``J = T − n ẑ_b·H + (3/2) n² r̂_bᵀ I r̂_b`` at every frame of a run in
    the gravity gradient (Hughes, *Spacecraft Attitude Dynamics*, 1986, §9.1; ``T`` and
    ``H`` the run's own energy and total angular momentum in body axes, wheels included;
    ``ẑ_b`` the orbit normal and ``r̂_b`` the direction from the planet, in body axes):
    what a figure draws of the run's ``drift.jacobi``. For the figures; the run's drift is
    the core's own measure.

    Raises
    ------
    ValueError
        The run's system has no :class:`GravityGradient`.
    """
    rates = [t.orbit_rate for t in traj.system.torques if isinstance(t, GravityGradient)]
    if not rates:
        raise ValueError("`traj` must be a run in the gravity gradient (dz.GravityGradient)")
    n = rates[0]
    inv = traj.invariants()
    q = np.asarray(traj.q, dtype=np.float64)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    q0, q1, q2, q3 = np.moveaxis(q, -1, 0)
    # rows of M(q) (world-from-body): a world vector v in body axes is Mᵀ v
    m = np.stack([np.stack([1 - 2 * (q2 * q2 + q3 * q3), 2 * (q1 * q2 - q0 * q3),
                            2 * (q1 * q3 + q0 * q2)], -1),
                  np.stack([2 * (q1 * q2 + q0 * q3), 1 - 2 * (q1 * q1 + q3 * q3),
                            2 * (q2 * q3 - q0 * q1)], -1),
                  np.stack([2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1),
                            1 - 2 * (q1 * q1 + q2 * q2)], -1)], -2)
    z_b = m[..., 2, :]
    r_b = np.cos(n * traj.t)[:, None] * m[..., 0, :] + np.sin(n * traj.t)[:, None] * m[..., 1, :]
    if traj.system.kinds.count("deployment"):
        tensors = np.stack([traj.system.tensor_at(float(t)) for t in traj.t])
        potential = np.einsum("fi,fij,fj->f", r_b, tensors, r_b)
    else:  # a constant body
        potential = np.einsum("fi,ij,fj->f", r_b, traj.system.tensor_at(0.0), r_b)
    h_dot = np.einsum("fi,fi->f", z_b, inv["momentum_body"])
    values: np.ndarray = inv["energy"] - n * h_dot + 1.5 * n * n * potential
    return values
