"""A spacecraft in orbit: external torques and momentum wheels.

Torques go in ``dz.System(body, torques=[...])``, wheels in ``parts=[...]``; the core adds
them to the general model's momentum law ``H' = H × ω + τ_b`` with
``ω = I⁻¹ (H − Σ h a)`` (body axes). The orbit and its frame are in
:mod:`dzhanibekov.lvlh`; see the guide page "A spacecraft in orbit".

>>> import dzhanibekov as dz
>>> sat = dz.System(dz.Body((2.0, 3.0, 1.0)), torques=[dz.GravityGradient(1.0)])
>>> sat.kinds, sat.conserved
(('gravity_gradient',), ('q_norm', 'jacobi'))
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ._args import as_array, as_float
from .parts import (TORQUE_TYPES, CallableTorque, ConstantTorque, GravityGradient,
                    TabulatedTorque, Wheel)

__all__ = ["GravityGradient", "ConstantTorque", "Wheel", "Torque", "TORQUE_TYPES",
           "pitch_libration_rate", "dual_spin_threshold"]

Torque = GravityGradient | ConstantTorque | TabulatedTorque | CallableTorque
"""The external torques a system takes."""


def pitch_libration_rate(inertia: Any, orbit_rate: Any) -> float:
    """The angular frequency of small pitch librations about the LVLH equilibrium,
    ``n √(3 (I_x − I_z) / I_y)``, for principal moments `inertia` ``(I_x, I_y, I_z)`` along
    along-track (roll), minus orbit normal (pitch) and nadir (yaw) (Hughes, *Spacecraft
    Attitude Dynamics*, 1986, §9.3: ``I_y θ'' + 3 n² (I_x − I_z) θ = 0``).

    Raises
    ------
    ValueError
        ``I_x ≤ I_z``: the pitch equilibrium is unstable, nothing librates.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> round(dz.pitch_libration_rate((2.0, 3.0, 1.0), 1.0), 12)
    1.0
    """
    i = as_array("inertia", inertia, "(3,)", last=3, ndim=(1,))
    n = as_float("orbit_rate", orbit_rate, positive=True)
    if not i[0] > i[2]:
        raise ValueError(f"`inertia` must have I_x > I_z for a stable pitch, got {tuple(i)}")
    return n * math.sqrt(3.0 * (i[0] - i[2]) / i[1])


def dual_spin_threshold(inertia: Any, axis: Any, rate: Any) -> tuple[float, float]:
    """The wheel momenta that leave a spin unstable: a spin at `rate` ``Ω`` about principal
    axis `axis` (``k``) with a wheel of momentum ``h`` along it is unstable for ``h`` strictly
    between ``Ω (I_i − I_k)`` and ``Ω (I_j − I_k)`` (``i``, ``j`` the other two axes), stable
    outside.

    Linearising ``I ω' = (I ω + h e_k) × ω`` about ``ω = Ω e_k`` gives
    ``I_i ω_i' = ±((I_k − I_j) Ω + h) ω_j`` and ``I_j ω_j' = ∓((I_i − I_k) Ω − h) ω_i``: the
    spin is stable when the product of the brackets is negative (the gyrostat's dual-spin
    rule; Hughes, *Spacecraft Attitude Dynamics*, 1986, ch. 6). For the intermediate axis the
    interval holds 0 (a spin without wheel flips); a wheel beyond ``Ω (I_max − I_mid)`` along
    the spin (or beyond ``Ω (I_mid − I_min)`` against it) stops the flips. For the major or
    minor axis, ``h = 0`` is outside: a plain spin is (linearly) stable.

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments.
    axis : int
        The spin axis: 0, 1 or 2.
    rate : float
        The spin rate ``Ω`` (its sign sets which way ``h`` counts as along the spin).

    Returns
    -------
    (low, high) : tuple of float
        The open interval of unstable ``h`` (empty when equal).

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> dz.dual_spin_threshold((1.0, 2.0, 3.0), axis=1, rate=1.0)
    (-1.0, 1.0)
    """
    i = as_array("inertia", inertia, "(3,)", last=3, ndim=(1,))
    if isinstance(axis, bool) or not isinstance(axis, (int, np.integer)) or axis not in (0, 1, 2):
        raise ValueError(f"`axis` must be 0, 1 or 2, got {axis!r}")
    w = as_float("rate", rate)
    k = int(axis)
    a, b = (w * (i[m] - i[k]) for m in range(3) if m != k)
    return (float(min(a, b)), float(max(a, b)))
