"""A run's options, typed once: :class:`RunOptions`, taken by :func:`~dzhanibekov.simulate`,
:func:`~dzhanibekov.summarize`, :func:`~dzhanibekov.sweep`, :func:`~dzhanibekov.monte_carlo`
and the maps (``map_sweep``) as ``options=``, beside their keywords (``t_end=``,
``method=``, …, typed by :class:`RunKeywords`), which override it.

>>> import dzhanibekov as dz
>>> long = dz.RunOptions(t_end=500.0, frames=11, method="dop853", rtol=1e-10)
>>> traj = dz.simulate(dz.Body((1.0, 2.0, 3.0)), (0.01, 1.0, 0.01), options=long)
>>> float(traj.t[-1]), traj.method
(500.0, 'dop853')
>>> dz.simulate(dz.Body((1.0, 2.0, 3.0)), (0.01, 1.0, 0.01), options=long, t_end=5.0).t[-1]
np.float64(5.0)
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, TypedDict

from . import _core
from ._args import run_options
from .methods import DEFAULT_MAX_STEPS, DEFAULT_METHOD

if TYPE_CHECKING:
    from typing_extensions import Unpack

__all__ = ["RunOptions", "RunKeywords", "merged"]


class RunKeywords(TypedDict, total=False):
    """The keywords of :class:`RunOptions`, as a function's ``**keywords`` takes them."""

    t_end: float
    frames: int
    dt: float | None
    method: str
    rtol: float | None
    atol: float | None
    flips: bool
    max_steps: int
    threads: int | None
    progress: bool | None


@dataclass(frozen=True, kw_only=True)
class RunOptions:
    """How a run goes: its span and frames, its method and step or tolerances, its limits.

    One value for every entry point of runs (:func:`~dzhanibekov.simulate`,
    :func:`~dzhanibekov.summarize`, :func:`~dzhanibekov.sweep`,
    :func:`~dzhanibekov.monte_carlo`, the maps): build it once, pass it as
    ``options=``, and override a field with its keyword. The fields are those entry points'
    keywords, with their defaults and meanings (see :func:`~dzhanibekov.simulate`); the core
    checks them when a run starts.

    Attributes
    ----------
    t_end : float
        End time, positive (default 100).
    frames : int
        Frames stored, at least 2 (default 201).
    dt : float or None
        A fixed-step method's largest step, an adaptive method's first; None: planned.
    method : str
        A name of ``dz.METHODS`` (default ``"rk4"``).
    rtol, atol : float or None
        Tolerances (see :func:`~dzhanibekov.simulate`).
    flips : bool
        Locate the flips (default True).
    max_steps : int
        Refuse runs needing more steps than this.
    threads : int or None
        A batch's threads (default: all cores).
    progress : bool or None
        A progress bar: None (default) for long runs, True always, False never.

    Examples
    --------
    >>> RunOptions(t_end=10.0).replace(method="dop853").method
    'dop853'
    """

    t_end: float = 100.0
    frames: int = 201
    dt: float | None = None
    method: str = DEFAULT_METHOD
    rtol: float | None = None
    atol: float | None = None
    flips: bool = True
    max_steps: int = DEFAULT_MAX_STEPS
    threads: int | None = None
    progress: bool | None = None

    def replace(self, **changes: Unpack[RunKeywords]) -> RunOptions:
        """These options with `changes` (names of :class:`RunKeywords`)."""
        return merged("replace", self, changes)

    def core(self) -> _core.RunOptions:
        """The core's options (kinds checked here, values by the core)."""
        return run_options(t_end=self.t_end, frames=self.frames, dt=self.dt,
                           method=self.method, rtol=self.rtol, atol=self.atol,
                           max_steps=self.max_steps, flips=self.flips, threads=self.threads)


NAMES = tuple(f.name for f in dataclasses.fields(RunOptions))
"""The options' names, in their order."""
assert set(NAMES) == set(RunKeywords.__annotations__), "RunOptions and RunKeywords differ"


def merged(function: str, options: Any, keywords: Mapping[str, Any],
           allowed: tuple[str, ...] = NAMES) -> RunOptions:
    """`options` (a :class:`RunOptions`, or None for the defaults) with `keywords` over it,
    for `function` (named in errors), which takes the options `allowed`."""
    if options is not None and not isinstance(options, RunOptions):
        raise TypeError(f"{function}(): `options` must be a dz.RunOptions, got "
                        f"{type(options).__name__}")
    for name in keywords:
        if name not in allowed:
            raise TypeError(f"{function}() got an unexpected keyword argument {name!r} (its "
                            f"run options: {', '.join(allowed)})")
    base = options if options is not None else _DEFAULTS
    if not keywords:
        return base
    # `dataclasses.replace` without its walk over the fields (a tenth of a short run's
    # cost): the fields hold what they are given, and are checked by `core()`
    given = object.__new__(RunOptions)
    given.__dict__.update(base.__dict__, **keywords)
    return given


_DEFAULTS = RunOptions()
