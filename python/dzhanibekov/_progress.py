"""The progress of a single long run, reported by the core (``run::progress``): a bar on a
terminal (or in Jupyter), otherwise a line on stderr now and then; and the default that the
command line's ``--no-progress`` sets for everything it runs."""

from __future__ import annotations

import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any

from tqdm.auto import tqdm

__all__ = ["LINE_EVERY", "PROGRESS_DELAY", "RunProgress", "progress_default", "resolve"]

PROGRESS_DELAY = 1.0
"""Seconds before a progress bar shows (``progress=None``): quick calls show none."""

LINE_EVERY = 10.0
"""Seconds between the lines of a run's progress where no bar can show (stderr is not a
terminal: a log, a pipe, CI); a run shorter than this prints none."""

_DEFAULT: ContextVar[bool | None] = ContextVar("dzhanibekov_progress", default=None)


@contextmanager
def progress_default(value: bool | None) -> Iterator[None]:
    """Within the block, ``progress=None`` means `value` (``False``: the command line's
    ``--no-progress``)."""
    token = _DEFAULT.set(value)
    try:
        yield
    finally:
        _DEFAULT.reset(token)


def resolve(progress: bool | None) -> bool | None:
    """`progress`, or the default set by :func:`progress_default` where it is None."""
    return _DEFAULT.get() if progress is None else progress


class RunProgress:
    """What the core calls with the share of a single run's span done (about every 50 ms of
    a long run): a bar over the run's time on a terminal, else a line on stderr every
    `LINE_EVERY` seconds. `always` (``progress=True``) shows the bar at once and the first
    line at the first report; otherwise (``progress=None``) the bar after `PROGRESS_DELAY`,
    the first line after `LINE_EVERY`."""

    def __init__(self, t_end: float, always: bool, desc: str = "run") -> None:
        self.t_end, self.desc, self.always = t_end, desc, always
        self.start = time.monotonic()
        self.next_line = self.start + (0.0 if always else LINE_EVERY)
        # the bar is made at the core's first report (a long run's): a quick run, which the
        # core never reports, makes none (tqdm's set-up cost a 10-step run more than the
        # run itself)
        self.bar: Any = None
        self.started = False

    def _start(self) -> None:
        self.started = True
        waited = time.monotonic() - self.start
        bar: Any = tqdm(total=self.t_end, desc=self.desc, unit="t", leave=False, disable=None,
                        delay=0.0 if self.always else max(0.0, PROGRESS_DELAY - waited),
                        bar_format="{desc}: {percentage:3.0f}%|{bar}| t = {n:.4g} of "
                        "{total:.4g} [{elapsed}<{remaining}]")
        self.bar = None if bar.disable else bar

    def __call__(self, share: float) -> None:
        if not self.started:
            self._start()
        t = share * self.t_end
        if self.bar is not None:
            self.bar.update(t - self.bar.n)
            return
        now = time.monotonic()
        if now >= self.next_line:
            self.next_line = now + LINE_EVERY
            print(f"dzhanibekov: {self.desc} at t = {t:.6g} of {self.t_end:.6g} "
                  f"({100 * share:.0f}%) after {now - self.start:.0f} s", file=sys.stderr,
                  flush=True)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
