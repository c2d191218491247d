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
from .methods import DEFAULT_ATOL, DEFAULT_MAX_STEPS, DEFAULT_RTOL, METHODS

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


def _warn_reach(plan: _core.StepPlan, method: str, rtol: float, *, stacklevel: int,
                where: str) -> None:
    """Warns that `rtol` is out of reach of `method` at the run's length (its round-off alone
    exceeds it), naming the method that reaches it."""
    other = plan.reached_by
    advice = (f"{other!r} reaches it (method={other!r})" if other is not None else
              "no fixed-step method reaches it over this length: shorten t_end, or loosen rtol")
    warnings.warn(
        f"{where}rtol = {rtol:g} is out of reach for {method!r} over this run: the round-off "
        f"of its steps alone (each adds a fraction of an ulp, and they add up over the run) "
        f"keeps its predicted error at {plan.predicted_error:.2g} at best; it takes the step "
        f"of least error, {plan.step:.4g}. {advice[0].upper()}{advice[1:]}.",
        StepSizeWarning,
        stacklevel=stacklevel,
    )


def warn_step(plan: _core.StepPlan, method: str, dt_given: bool, rtol: float, *,
              stacklevel: int, where: str = "") -> None:
    """Warns with `StepSizeWarning` when `plan` (a row's `_core.StepPlan`) predicts that RK4
    dissipates the run, or, for a step picked for `rtol`, that the run's length puts `rtol`
    out of the method's reach; `where` names the run (a batch's worst row). `stacklevel`
    counts from this function."""
    if not dt_given and plan.out_of_reach:
        _warn_reach(plan, method, rtol, stacklevel=stacklevel + 1, where=where)
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
            "to pick the step for an accuracy, or a method that keeps |q| (such as "
            "'splitting', for the free body).",
            StepSizeWarning,
            stacklevel=stacklevel,
        )
