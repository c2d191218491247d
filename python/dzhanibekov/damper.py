"""Internal dissipation: a spherical viscous nutation damper, and the way to flat spin."""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np

from . import _core
from ._args import as_array, as_float
from .accuracy import StepSizeWarning
from .methods import DEFAULT_METHOD, METHODS
from .body import Body, as_body
from .parts import Damper

__all__ = ["Damper", "FLAT_SHARE", "axis_shares", "flat_spin_time", "flat_spin_estimate",
           "StiffDamperWarning", "STIFF_RATIO", "ENERGY_GROWTH_TOL", "damper_rate"]

FLAT_SHARE: float = _core.FLAT_SHARE
"""A spin is flat once the major axis carries this share of ``|L|``."""


ENERGY_GROWTH_TOL: float = _core.ENERGY_GROWTH_TOL
"""A fixed-step run of a damped body (no deployment) whose energy exceeds its start by this
share at a frame raises :class:`~dzhanibekov.DivergedError`: a damper only takes energy, and
a run inside the method's stability limit loses it too (measured: at most 5e-5 above the
start, at ``h·Ω = 1`` and ``hλ = 2.7``), while past the limit the slip grows geometrically
(by ``|R(−hλ)|`` a step) and RK4's growth can saturate at hundreds of times the start, a run
that ends finite but wrong. An adaptive run is not watched: it shrinks its steps to stay
stable, and its error follows its tolerance."""

STIFF_RATIO = 30.0
"""An adaptive run warns when the damper's rate ``λ`` (:func:`damper_rate`) exceeds the
body's rate bound ``Ω = √(2T / I_min)`` by this factor: its steps are then set by the
damper's stability bound (``h λ`` at about 3.3 for dopri5, 6.4 for dop853), not by the
motion, and its cost grows in proportion to ``λ`` (measured at the default tolerances: at
``λ/Ω ≈ 34`` dop853 takes 4 times, dopri5 2.3 times, the steps of the undamped body)."""


class StiffDamperWarning(StepSizeWarning):
    """The damper relaxes far faster than the step (a *stiff* damper): RK4 with a fixed step
    beyond its stability limit for the damper's decay diverges, and an adaptive method
    crawls at the damper's time scale. A :class:`~dzhanibekov.StepSizeWarning`, so the same
    filters silence both."""


def damper_rate(body: Any, damper: Damper) -> float:
    """The decay rate of the slip ``σ − ω`` between sphere and body: the stiffness of a
    damped run.

    Linearised, the slip obeys ``(σ − ω)' = −c (1/j + I⁻¹)(σ − ω)`` plus gyroscopic terms of
    the order of the body rates (subtract the two equations of :class:`Damper`); in
    principal axes its rates are ``c (1/j + 1/I_k)``, the fastest

    ``λ = c (1/j + 1/I_min)``,

    with ``I_min`` the least principal moment. An explicit method's step ``h`` is stable
    for this mode while ``h λ`` stays within its stability interval on the negative real
    axis: ``h λ ≤`` ``METHODS[method].real_limit`` (2.785 for RK4, the real root of
    ``x³ − 4x² + 12x − 24`` where ``R(−x) = 1``). When ``λ`` far exceeds the body's
    rates, the slip dies out almost at once and the body turns as if the sphere were
    rigidly attached, but an explicit method must still resolve ``1/λ``.

    Parameters
    ----------
    body : Body or array_like, shape (3,)
    damper : Damper

    Returns
    -------
    float
        ``λ``, in inverse time units.

    Examples
    --------
    >>> damper_rate((1.0, 10.0, 10.0), Damper(0.05, 0.02))  # 0.02 (1/0.05 + 1/1)
    0.42
    """
    if not isinstance(damper, Damper):
        raise TypeError(f"`damper` must be a dz.Damper, got {type(damper).__name__}")
    least = min(as_body(body).inertia)
    with np.errstate(over="ignore"):  # c/j + c/I_min: no 1/j that overflows
        rate = float(np.float64(damper.damping) / damper.inertia
                     + np.float64(damper.damping) / least)
    if not math.isfinite(rate):
        raise ValueError(f"the damper's rate c(1/j + 1/I_min) for `body` (I_min = {least!r}) "
                         f"and `damper` ({damper!r}) exceeds float64's "
                         f"{np.finfo(np.float64).max:.3g}")
    return rate


def warn_stiff(plan: Any, method: str, *, stacklevel: int, where: str = "") -> None:
    """Warns with `StiffDamperWarning` when the model of `plan` (a row's `_core.StepPlan`)
    has a damper whose slip decays at ``λ`` (its ``stiffness``) beyond the method's
    stability limit for the step (``step · λ >`` the method's ``real_limit``), or, for an
    adaptive method, faster than `STIFF_RATIO` times the body's rate bound. `where` names the
    run (a batch's stiffest row); `stacklevel` counts from this function."""
    rate = float(plan.stiffness)
    if not rate > 0:
        return
    if not METHODS[method].adaptive:
        step = float(plan.step)
        limit = METHODS[method].real_limit
        if limit is None or not step * rate > limit:
            return
        why = (f"beyond {method!r}'s stability limit h·c(1/j + 1/I_min) ≤ {limit:.4f} for the "
               "decay of the slip between sphere and body: the run diverges")
    else:
        bound = float(plan.rate_bound)
        ratio = rate / bound if bound > 0 else math.inf
        if not ratio > STIFF_RATIO:
            return
        step = 1.0 / rate
        why = (f"it relaxes {ratio:.3g} times faster than the body turns (more than "
               f"STIFF_RATIO = {STIFF_RATIO:g}): {method!r} must take steps of the order of "
               "1/λ and crawls at the damper's time scale")
    warnings.warn(
        f"{where}the damper is stiff for the step {step:.4g}: its slip decays at "
        f"λ = c(1/j + 1/I_min) = {rate:.4g} (time constant {1 / rate:.4g}, step·λ = "
        f"{step * rate:.3g}); {why}. Take dt below {_rk4_limit() / rate:.4g} (RK4), or a "
        "softer damper (a smaller damping c or a larger sphere j): a damper this fast is "
        "all but rigid.",
        StiffDamperWarning,
        stacklevel=stacklevel,
    )


def _major_axes(body: Body) -> list[int]:
    """The principal axes of the largest moment (both transverse axes of a symmetric top),
    as columns of `body.principal_axes`."""
    i = np.asarray(body.inertia)
    return [k for k in range(3) if i[k] >= i.max() * (1 - 1e-12)]


def flat_spin_time(traj: Any, share: float = FLAT_SHARE) -> float:
    """The first time at which the major axis carries `share` of ``|L|``.

    For a symmetric top whose two largest moments are equal, the plane of both counts.
    NaN if the run never gets there. A run of a damped body of constant inertia locates the
    time of `FLAT_SHARE` in the core, inside the step, whatever its frames (as it locates
    the flips); for another `share`, another body or a run read from a file,
    it is the first frame past it (a nutation rides on the share's slow rise, so that can be
    up to a nutation period late: take frames closer than that).

    Parameters
    ----------
    traj : Trajectory
        A run (of a damped body, typically), with `momentum_world` and `q` at the frames.
    share : float
        The share of ``|L|``, default `FLAT_SHARE` (0.99).

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> explorer = dz.System(dz.Body((1.0, 10.0, 10.0)), parts=[dz.Damper(0.05, 0.02)])
    >>> traj = dz.simulate(explorer, (2.0, 0.01, 0.0), t_end=4000.0, frames=401, dt=0.01)
    >>> 1000 < flat_spin_time(traj) < 2000
    True
    """
    share = as_float("share", share, positive=True)
    body = traj.body
    if not isinstance(body, Body):
        raise TypeError("`traj` must be a run of a constant body (a damped body), got one of "
                        f"a {type(body).__name__}")
    located = getattr(traj, "_flat_time", None)
    if located is not None and share == FLAT_SHARE:
        return float(located)
    # the shares on the principal axes: the major axis is a principal axis, whatever the
    # body's own axes
    shares = axis_shares(traj) @ body.principal_axes
    on_major = np.sqrt((shares[:, _major_axes(body)] ** 2).sum(axis=1))
    hit = np.flatnonzero(on_major >= share)
    return float(traj.t[hit[0]]) if hit.size else math.nan


def axis_shares(traj: Any) -> np.ndarray:
    """``L_k / |L|`` on each body axis at every frame, shape (frames, 3), from the total
    angular momentum in body axes (0 where there is no angular momentum)."""
    if not hasattr(traj, "momentum_body"):
        raise TypeError(f"`traj` must be a Trajectory, got {type(traj).__name__}")
    l_body = np.asarray(traj.momentum_body, dtype=np.float64)
    norm = np.linalg.norm(l_body, axis=1, keepdims=True)
    shares: np.ndarray = np.divide(l_body, norm, out=np.zeros_like(l_body), where=norm > 0)
    return shares


def flat_spin_estimate(body: Any, damper: Damper, omega0: Any, sigma0: Any = None,
                       share: float = FLAT_SHARE) -> float:
    """The energy-sink estimate of the time to flat spin of a symmetric top spun about its
    minor (symmetry) axis with a spherical damper.

    The damper is treated as a small perturbation of the torque-free motion of a body with
    axial moment ``Ia`` and transverse moment ``It > Ia`` (Kaplan, *Modern Spacecraft Dynamics
    and Control*, 1976, §5; Hughes 1986). The sphere nearly co-rotates with the body, so
    the rigid motion the damper perturbs is that of the body *with* the sphere: its moment
    ``j`` is added to each of the body's (whose tensor counts only the sphere's mass, as a
    point at its centre), as the model's total momentum ``H = I ω + j σ`` does; leaving it out
    gave 1280 for the example below against 1364 simulated. The nutation angle θ between
    ``H`` and the symmetry axis obeys ``T = ½ H² (sin²θ / It + cos²θ / Ia)``. In space the body rate is a
    constant part plus a part of size ``ω_r sin θ``, ``ω_r = H cos θ (It − Ia) / (Ia It)``,
    turning at the precession rate ``ω_p = H / It``; the sphere, a first-order lag of time
    constant ``τ = j / c``, misses the turning part by ``|σ − ω|² = ω_r² sin²θ f``,
    ``f = (ω_p τ)² / (1 + (ω_p τ)²)``. Equating ``dT/dt = −c |σ − ω|²`` with the rigid-body
    ``dT/dt`` gives ``θ' = κ sin θ cos θ``, ``κ = c f (It − Ia) / (Ia It)``, so
    ``tan θ = tan θ₀ e^{κ t}`` and the time to ``sin θ = share`` is
    ``ln(tan θ_f / tan θ₀) / κ``.

    The approximations: the energy loss averaged over a nutation period as if the motion were
    the rigid one (first order in ``c``), the sphere's lag as if it followed the body's rate
    in space at a fixed precession rate, and the two transverse moments averaged. The
    relative error vanishes with the damper (``j, c → 0`` at a fixed ``j / c``); for
    Explorer 1 below (``j`` 5 % of the least moment) it is within 1 % of the simulated 1364.

    Parameters
    ----------
    body : Body or array_like, shape (3,)
        Principal moments, the sphere's mass counted as a point (as :class:`Damper` wants);
        with the sphere's ``j`` added, the axis of least inertia is the spin axis, the mean
        of the other two the transverse moment ``It``.
    damper : Damper
    omega0, sigma0 : array_like, shape (3,)
        The start (``sigma0`` defaults to co-rotation).
    share : float
        The share of ``|L|`` that makes the spin flat.

    Returns
    -------
    float
        The estimated time; ``inf`` for a spin that does not go flat (no damping, or the spin
        already about the major axis).

    Examples
    --------
    >>> t = flat_spin_estimate((1.0, 10.0, 10.0), Damper(0.05, 0.02), (2.0, 0.01, 0.0))
    >>> round(t, -1)
    1360.0
    """
    b = as_body(body)
    if not isinstance(damper, Damper):
        raise TypeError(f"`damper` must be a dz.Damper, got {type(damper).__name__}")
    w = as_array("omega0", omega0, "(3,)", last=3, ndim=(1,))
    s = w if sigma0 is None else as_array("sigma0", sigma0, "(3,)", last=3, ndim=(1,))
    share = as_float("share", share, positive=True)
    if not share < 1:
        raise ValueError(f"`share` must lie in (0, 1), got {share!r}")
    with np.errstate(all="ignore"):
        return _estimate(np.asarray(b.inertia, dtype=np.float64), damper, w, s, share)


def _estimate(i: np.ndarray, damper: Damper, w: np.ndarray, s: np.ndarray,
              share: float) -> float:
    """`flat_spin_estimate` in float64 throughout (an overflow is infinity, not an error)."""
    j, c = np.float64(damper.inertia), np.float64(damper.damping)
    h = i * w + j * s
    i = i + j  # the body with its sphere, co-rotating: the rigid motion the damper perturbs
    axis = int(np.argmin(i))
    ia = i[axis]
    it = np.delete(i, axis).mean()
    hn = np.sqrt(np.sum((h / np.abs(h).max()) ** 2)) * np.abs(h).max() if h.any() else 0.0
    if c == 0 or not it > ia or not 0 < hn < np.inf:
        return math.inf
    transverse = np.hypot(*np.delete(h, axis))
    theta0 = np.arctan2(transverse, abs(h[axis]))
    theta_f = np.arcsin(share)
    if theta0 >= theta_f:
        return 0.0
    wp_tau = hn / it * (j / c)
    f = 1.0 / (1.0 + 1.0 / wp_tau**2)
    kappa = c * f * ((it - ia) / ia / it)
    t = np.log(np.tan(theta_f) / np.tan(theta0)) / kappa
    return float(t) if np.isfinite(t) and t >= 0 else math.inf


def _rk4_limit() -> float:
    """The paper's method's real-axis stability limit, from the registry."""
    limit = METHODS[DEFAULT_METHOD].real_limit
    assert limit is not None, "the default method is RK4, a fixed-step method"
    return limit
