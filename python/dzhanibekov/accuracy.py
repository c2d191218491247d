"""Speed against accuracy: the methods' tolerances and the guard on RK4's step.

RK4 on this problem does not blow up at first, it silently dissipates. The quaternion law
``q' = ½ q ⊗ (0, ω)`` has eigenvalues ``±i|ω|/2``; one RK4 step multiplies such a mode by
``R(iy)``, ``y = h|ω|/2``, with ``|R(iy)|² = 1 − y⁶/72 + y⁸/576 < 1`` below ``y = 2√2``. With
``|ω| ≤ Ω = √(2E / I_min)`` (known before the run) the run's predicted drift of ``|q|`` is
``|1 − |R(iy)|ⁿ|`` over its ``n`` steps: 3.3 % per 10⁴ radians at ``dt·Ω = 0.5``, 65 % at
``dt·Ω = 1`` (exact for a spin about the axis of least inertia, an upper bound otherwise).
Beyond ``dt·Ω = 4√2 ≈ 5.66`` the quaternion grows until it overflows; a wobble about a
stable axis, whose frequency is at most ``Ω``, already goes unstable at ``h·Ω_wobble = 2√2``.
`simulate` warns with `StepSizeWarning` when that prediction exceeds `MAX_PREDICTED_DRIFT`.
"""

from __future__ import annotations

import warnings
from typing import Any

from . import _core
from ._args import as_float
from .methods import DEFAULT_ATOL, DEFAULT_MAX_STEPS, DEFAULT_RTOL, METHODS, is_adaptive

__all__ = [
    "ADAPTIVE_METHODS",
    "DEFAULT_ATOL",
    "DEFAULT_MAX_STEPS",
    "DEFAULT_RTOL",
    "MAX_PREDICTED_DRIFT",
    "StepSizeWarning",
]

ADAPTIVE_METHODS = tuple(name for name, m in METHODS.items() if m.adaptive)
"""Methods that choose their own steps under `rtol` and `atol`."""


MAX_PREDICTED_DRIFT = 1e-6
"""`StepSizeWarning` is raised when RK4's predicted relative drift of ``|q|`` over the run
exceeds this (or `rtol`, if larger, for a step chosen with ``dt=None``). Silence it with
:mod:`warnings` filters, or lower ``dt``."""

class StepSizeWarning(UserWarning):
    """The step is too large for the method over this run: RK4 will visibly dissipate the
    motion (``|q|`` and with it the attitude decay), or diverge beyond its stability limit."""


def _tolerance(name: str, value: Any, default: float) -> float:
    if value is None:
        return default
    x = as_float(name, value, positive=True)
    return _core.check_rtol(x) if name == "rtol" else x


def plan_step(
    body: _core.RigidBody,
    omega0: tuple[float, float, float],
    t_end: float,
    frames: int,
    dt: Any,
    method: str,
    rtol: Any,
    atol: Any,
    *,
    stacklevel: int = 3,
) -> tuple[float | None, float, float]:
    """Resolves ``dt`` (None: from `rtol`) and the tolerances, and warns on a step that
    RK4 would silently dissipate. Returns ``(dt, rtol, atol)`` for the core."""
    dt_, rtol_, atol_ = check_tolerances(method, dt, rtol, atol)
    plan = _core.step_plan(body, omega0, t_end, frames, dt_, method, rtol_, atol_)
    warn_step(plan, method, dt is not None, rtol_, stacklevel=stacklevel + 1)
    return core_step(plan.dt, dt_, method), rtol_, atol_


def core_step(planned: float, dt: float | None, method: str) -> float | None:
    """The `dt` the core is given: None for an adaptive method without a `dt`, which then
    picks its first step in the run itself (so each run of a batch or sweep picks its own,
    as it would alone); otherwise the planned step."""
    return None if dt is None and method in ADAPTIVE_METHODS else planned


def check_tolerances(
    method: str, dt: Any, rtol: Any, atol: Any
) -> tuple[float | None, float, float]:
    """``(dt, rtol, atol)`` checked against each other and `method`, defaults filled in."""
    adaptive = is_adaptive(method)
    if not adaptive:
        if atol is not None:
            raise ValueError(f"`atol` applies to the adaptive methods {ADAPTIVE_METHODS} only")
        if rtol is not None and dt is not None:
            raise ValueError(
                "`rtol` sets the step of a fixed-step method only with dt=None; "
                f"got dt={dt!r} as well"
            )
    rtol_ = _tolerance("rtol", rtol, DEFAULT_RTOL)
    atol_ = _tolerance("atol", atol, DEFAULT_ATOL)
    dt_ = None if dt is None else as_float("dt", dt, positive=True)
    return dt_, rtol_, atol_


def warn_step(plan: _core.StepPlan, method: str, dt_given: bool, rtol: float, *,
              stacklevel: int, where: str = "") -> None:
    """Warns with `StepSizeWarning` when `plan` (of `_core.step_plan`) predicts that RK4
    dissipates the run; `where` names the run (a batch's worst row). `stacklevel` counts
    from this function."""
    drift = plan.predicted_drift
    # a step chosen for an accuracy answers to that accuracy
    tolerance = MAX_PREDICTED_DRIFT if dt_given else max(rtol, MAX_PREDICTED_DRIFT)
    # the core predicts RK4's dissipation for the methods it threatens, 0 for the others
    if drift > tolerance:
        h_rate = plan.step * plan.rate_bound
        limit = METHODS[method].imaginary_limit
        if limit is not None and h_rate >= limit:
            why = (
                "at or beyond RK4's stability limit (dt·Ω = 2√2 ≈ 2.83 for a wobble at the "
                "rate bound, 4√2 ≈ 5.66 for the quaternion): the run may diverge"
            )
        else:
            why = (
                f"RK4 would lose a fraction {drift:.2g} of |q| over this run, more than "
                f"{'MAX_PREDICTED_DRIFT' if dt_given else 'rtol'} = {tolerance:g}"
            )
        warnings.warn(
            f"{where}step {plan.step:.4g} (dt·Ω = {h_rate:.3g}, Ω = {plan.rate_bound:.4g} "
            f"the bound of |ω|) is too large for {method!r}: {why}. Take a smaller dt, dt=None "
            "to pick the step for an accuracy, or method='splitting'.",
            StepSizeWarning,
            stacklevel=stacklevel,
        )
