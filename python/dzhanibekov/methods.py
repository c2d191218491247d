"""The methods on offer, as the core declares them.

:data:`METHODS` maps each method's name to what the core knows about it
(:class:`MethodInfo`): its order, whether it chooses its own steps, what it keeps to
round-off, its cost per step, whether a batch runs it in SIMD lanes and which models it runs.
The defaults of every run come from the core too.

>>> import dzhanibekov as dz
>>> dz.METHODS["splitting"].keeps
('momentum', 'momentum_world', 'q_norm')
>>> [name for name, m in dz.METHODS.items() if m.adaptive]
['dopri5', 'dop853']
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType
from typing import Any

from . import _core

__all__ = ["METHODS", "MethodInfo", "DEFAULT_METHOD", "DEFAULT_RTOL", "DEFAULT_ATOL", "DEFAULT_MAX_STEPS",
           "check_method", "is_adaptive"]

MethodInfo = _core.MethodInfo

METHODS: Mapping[str, MethodInfo] = MappingProxyType({m.name: m for m in _core.METHODS})
"""Every method by name, in the order the core lists them (read-only)."""

DEFAULT_METHOD: str = _core.DEFAULT_METHOD
"""The method a run uses unless told otherwise: the paper's."""

DEFAULT_RTOL: float = _core.DEFAULT_RTOL
"""Relative tolerance of the adaptive methods, and the accuracy ``dt=None`` aims at."""

DEFAULT_ATOL: float = _core.DEFAULT_ATOL
"""Absolute tolerance of the adaptive methods at the default `rtol`: on ``q``, and on ``ω`` in
units of ``Ω``. A run given an `rtol` and no `atol` takes ``rtol / 1000``."""

DEFAULT_MAX_STEPS: int = _core.DEFAULT_MAX_STEPS
"""Runs needing more steps are refused unless `max_steps` is raised (about 5 minutes of RK4)."""


def check_method(method: Any) -> str:
    """`method` if it names a method of :data:`METHODS`, else ValueError listing them."""
    if not isinstance(method, str) or method not in METHODS:
        raise ValueError(f"`method` must be one of {tuple(METHODS)}, got {method!r}")
    return method


def is_adaptive(method: str) -> bool:
    """Whether `method` (a name of :data:`METHODS`) chooses its own steps."""
    return METHODS[method].adaptive
