"""Runs that keep no frames: flip times, the invariants' drift and the run's cost only.

For scenes that ask only *when* a body flips, and for sweeps that need a few numbers per run,
:func:`summarize` integrates exactly as :func:`~dzhanibekov.simulate` does but stores no
frames: its memory does not grow with `frames` or with the run's length.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .body import Body
from .options import NAMES, RunKeywords, RunOptions, merged
from .results import Summary, run_drift
from .rows import rows_of
from .simulate import plan, run_batch, run_one

if TYPE_CHECKING:
    from typing_extensions import Unpack

__all__ = ["Summary", "summarize"]

_TAKES = tuple(n for n in NAMES if n not in ("flips", "threads", "progress"))
"""The run options a summary takes: it always locates the flips, on one thread, silently."""


def summarize(
    system: Body | Any,
    omega0: Any,
    q0: Any = (1.0, 0.0, 0.0, 0.0),
    *,
    options: RunOptions | None = None,
    **keywords: Unpack[RunKeywords],
) -> Summary | tuple[Summary, ...]:
    """Simulates like :func:`~dzhanibekov.simulate` but keeps no frames: flip times only.

    The run is the same, step for step, as ``simulate`` with the same arguments, so its
    flip times and drift are equal to a full run's; only ω and q are not stored. Use it when
    only *when* the body flips is asked (a scene that draws nothing, one run of a sweep).

    Parameters
    ----------
    system : System, Body, Deployment, list of them, or array_like, shape (3,) or (M, 3)
        What is run, as for :func:`~dzhanibekov.simulate`: one system, or one per run.
    omega0 : array_like, shape (3,) or (M, 3)
        Body rates at ``t = 0``: one start, or M starts (a batch), as for ``simulate``.
    q0, options, t_end, dt, method, rtol, atol, max_steps
        As for :func:`~dzhanibekov.simulate`.
    frames : int
        The frame grid, as for ``simulate``: between frames the run takes equal substeps no
        longer than `dt`, and the invariants' drift is measured at the frames (of an
        adaptive method's step that spans more than 64, at the last). None are stored.

    Returns
    -------
    Summary or tuple of M Summary
        One run's summary; for a batch (``omega0`` or ``q0`` of M rows, or M systems),
        a tuple of M, each the summary of its row run alone, as ``simulate`` gives a
        ``Batch`` where it would give a ``Trajectory``.

    Raises
    ------
    TypeError, ValueError, KeyboardInterrupt
        As for :func:`~dzhanibekov.simulate`.

    Examples
    --------
    >>> s = summarize((52.0833, 27.0833, 41.6666), (0.01, 0.01, 1.0))
    >>> s.flips, s.verdict
    (2, '2 flips in [0, 100]')
    >>> [s.flips for s in summarize((52.0833, 27.0833, 41.6666), [(0.01, 0.01, 1.0), (0, 0, 1)])]
    [2, 0]
    """
    given = merged("summarize", options, keywords, _TAKES)
    # the options' kinds first: a bad option is named before any guess about the arguments
    options_ = given.replace(flips=True, threads=None).core()
    rows = rows_of(system, omega0, q0, function="summarize", max_batch_ndim=1, stacklevel=3)
    if not rows.batch:
        one = run_one(rows, options_, keep_frames=False, stacklevel=3)
        assert one.flip_times is not None
        return Summary(flip_times=one.flip_times, drift=run_drift(one), t_end=options_.t_end,
                       system=rows.systems.first, method=options_.method, dt=one.dt,
                       n_steps=one.n_steps, nfev=one.nfev)
    core = plan(rows, options_, stacklevel=3)
    run = run_batch(rows, core, keep_frames=False)
    flip_times = run.flip_times
    assert flip_times is not None
    summaries = tuple(Summary(
        flip_times=flip_times[k],
        drift=run.drift.row(k),
        t_end=core.t_end,
        system=rows.systems[k],
        method=core.method,
        dt=float(run.dt[k]),
        n_steps=int(run.n_steps[k]),
        nfev=int(run.nfev[k]),
    ) for k in range(len(rows.systems)))
    return summaries if rows.batch else summaries[0]
