"""The errors the core raises, as a small hierarchy of :class:`ValueError` subclasses.

Every error of the core is a :class:`DzhanibekovError` (so ``except ValueError`` still catches
it); a run that diverged raises :class:`DivergedError`, a request too large to honour
:class:`TooLargeError` (also a :class:`MemoryError`). An error in one run of a batch or a sweep
carries that run's row in ``.row`` (``None`` for a single run), so nothing needs to read it off
the message. The errors pickle (with their row), so they cross process boundaries
(multiprocessing, Dask) intact.

>>> import warnings, numpy as np, dzhanibekov as dz
>>> omega = np.array([[0.0, 0.1, 1.0], [0.0, 1e3, 1.0]])   # row 1: dt·Ω = 500
>>> try:
...     with warnings.catch_warnings():
...         warnings.simplefilter("ignore", dz.StepSizeWarning)
...         dz.simulate(dz.Body(dz.PAPER_INERTIA), omega, t_end=100.0, dt=0.5, frames=2)
... except dz.DivergedError as e:
...     print(e.row)
1
"""

from __future__ import annotations

from typing import Any

__all__ = ["DzhanibekovError", "DivergedError", "TooLargeError"]


class DzhanibekovError(ValueError):
    """An argument or request the core refused, or a run that failed.

    Parameters
    ----------
    message : str
        What went wrong, without the row.
    row : int, optional
        The row of a batch or sweep whose run failed; None for a single run.
    index : tuple of int, optional
        The row's index in starts of several leading axes (shown in the message only).
    """

    def __init__(self, message: str, row: int | None = None, index: tuple[int, ...] | None = None) -> None:
        super().__init__(message, row, index)
        self.message = message
        self.row = row
        self.index = index

    def __str__(self) -> str:
        if self.row is None:
            return self.message
        where = f"row {self.row}" if self.index is None else f"row {self.row} (index {self.index})"
        return f"{where}: {self.message}"

    def at(self, row: int, index: tuple[int, ...] | None = None) -> DzhanibekovError:
        """The same error about `row` (at `index`) of a larger set of runs."""
        return type(self)(self.message, row, index)

    def __reduce__(self) -> tuple[Any, ...]:
        return (type(self), (self.message, self.row, self.index), self.__dict__)


class DivergedError(DzhanibekovError):
    """The state stopped being finite: the step is beyond the method's stability limit, or the
    rates are too large for float64; or a fixed-step run of a damped body gained energy
    (more than :data:`~dzhanibekov.damper.ENERGY_GROWTH_TOL` of its start at a frame), which a
    damper cannot give: the step is beyond the method's stability limit for the damper."""


class TooLargeError(DzhanibekovError, MemoryError):
    """A request whose output, step count or span is too large to honour (more memory or steps
    than allowed, or a span float64 cannot hold). Both a :class:`ValueError` (as every error of
    the core) and a :class:`MemoryError`, so either ``except`` catches it."""
