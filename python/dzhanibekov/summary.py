"""Runs that keep no frames: flip times, the invariants' drift and the run's cost only.

For scenes that ask only *when* a body flips, and for sweeps that need a few numbers per run,
:func:`summarize` integrates exactly as :func:`~dzhanibekov.simulate` does but stores no
frames: its memory does not grow with `frames` or with the run's length.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _core
from .accuracy import plan_step
from .body import Body
from .methods import DEFAULT_MAX_STEPS, DEFAULT_METHOD
from .simulate import _checked
from .results import Drift, Summary

__all__ = ["Summary", "summarize"]


def summarize(
    body: Body | Any,
    omega0: Any,
    q0: Any = (1.0, 0.0, 0.0, 0.0),
    t_end: float = 100.0,
    frames: int = 201,
    dt: float | None = 1e-3,
    method: str = DEFAULT_METHOD,
    *,
    rtol: float | None = None,
    atol: float | None = None,
    max_steps: int = DEFAULT_MAX_STEPS,
) -> Summary:
    """Simulates like :func:`~dzhanibekov.simulate` but keeps no frames: flip times only.

    The run is the same, step for step, as ``simulate`` with the same arguments, so its
    flip times and drift are equal to a full run's; only ω and q are not stored. Use it when
    only *when* the body flips is asked (a scene that draws nothing, one run of a sweep).

    Parameters
    ----------
    body, omega0, q0, t_end, dt, method, rtol, atol, max_steps
        As for :func:`~dzhanibekov.simulate`.
    frames : int
        The frame grid, as for ``simulate``: between frames the run takes equal substeps no
        longer than `dt`, and the invariants' drift is measured at the frames. None are stored.

    Returns
    -------
    Summary

    Raises
    ------
    TypeError, ValueError, KeyboardInterrupt
        As for :func:`~dzhanibekov.simulate`.

    Examples
    --------
    >>> s = summarize((52.0833, 27.0833, 41.6666), (0.01, 0.01, 1.0))
    >>> s.flips, s.verdict
    (2, '2 flips in [0, 100]')
    """
    body, omega0, q0, t_end, frames, max_steps = _checked(
        body, omega0, q0, t_end, frames, method, max_steps
    )
    omega = (float(omega0[0]), float(omega0[1]), float(omega0[2]))
    dt, rtol_, atol_ = plan_step(body._core, omega, t_end, frames, dt, method, rtol, atol)
    out = _core.simulate(
        body._core, tuple(omega0), tuple(q0), t_end, frames, dt, method, max_steps, False, True,
        rtol_, atol_,
    )
    return Summary(
        flip_times=out.flip_times,
        drift=Drift(*out.drift),
        t_end=t_end,
        body=body,
        method=method,
        dt=out.dt,
        n_steps=out.n_steps,
        nfev=out.nfev,
    )
