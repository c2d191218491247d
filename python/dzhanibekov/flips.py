"""The flip period of a free rotation, from the exact solution."""

from __future__ import annotations

from typing import Any, overload

import numpy as np

from . import _core
from ._args import as_array
from ._swap import check_not_swapped
from .body import Body, as_body

__all__ = ["flip_period"]


@overload
def flip_period(body: Body | Any, omega0: tuple[float, float, float]) -> float: ...
@overload
def flip_period(body: Body | Any, omega0: Any) -> float | np.ndarray: ...


def flip_period(body: Body | Any, omega0: Any) -> float | np.ndarray:
    """The time between two flips of a body spinning freely from body rates `omega0`.

    A flip is a half-turn of the intermediate axis relative to the angular momentum (see
    :func:`dzhanibekov.simulate`, ``flip_times``). The intermediate-axis rate of the exact
    solution is proportional to ``sn(λt + u0 | m)``, which changes sign every ``2K(m)/λ``;
    that is the period returned when the motion flips. ``K`` is computed from the
    complementary parameter ``1 - m`` (AGM), which stays accurate as the motion nears the
    separatrix, where the period grows like ``(2/λ) ln(4 / √(1 - m))``.

    Parameters
    ----------
    body : Body or array_like, shape (3,)
        The body, or its principal moments ``(Ix, Iy, Iz)``.
    omega0 : array_like, shape (3,) or (M, 3)
        Body-frame angular velocity ``(u0, v0, w0)`` at any instant of the motion, in the
        body's own axes (for a body from a tensor, those of the tensor); M rows for M
        starts of the same body, as :func:`~dzhanibekov.simulate` takes them.

    Returns
    -------
    float, or ndarray of shape (M,) for M starts
        ``2K(m)/λ``, or ``inf`` when the motion never flips: on the separatrix
        (``L² = 2E I_mid``: at most one flip, taking forever to start and to end), for spin
        exactly about a principal axis, for a symmetric top (two moments equal within
        :data:`~dzhanibekov.SYMMETRY_TOLERANCE`, 1e-9 relative: there is no
        intermediate axis, so nothing flips; its rates turn in the body at
        ``Ω = (I3 - I) ω3 / I`` instead), and for wobbles about a stable axis that never
        bring the intermediate axis nearest to the angular momentum (its rate still changes
        sign every ``2K/λ``, but those sign changes are not flips).

    Raises
    ------
    TypeError
        If `omega0` is not real numbers of shape (3,) or (M, 3).
    ValueError
        If `omega0` is not finite, or the arguments look swapped: moments that no real body
        has (one larger than the other two together) with rates that could be moments.

    References
    ----------
    L. D. Landau, E. M. Lifshitz, *Mechanics*, §37 (the free asymmetric top).

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> round(flip_period(dz.Body(dz.PAPER_INERTIA), (0.01, 0.01, 1.0)), 6)
    38.156808
    >>> flip_period(dz.Body(dz.PAPER_INERTIA), (0.0, 0.0, 1.0))
    inf
    >>> flip_period(dz.Body(dz.PAPER_INERTIA), [(0.01, 0.01, 1.0), (0.0, 0.0, 1.0)]).round(6)
    array([38.156808,       inf])
    """
    w = as_array("omega0", omega0, "(3,) or (M, 3)", last=3, ndim=(1, 2))
    check_not_swapped(body, w, "flip_period")
    core = as_body(body)._core
    if w.ndim == 1:
        return _core.flip_period(core, (float(w[0]), float(w[1]), float(w[2])))
    periods = np.empty(len(w))
    for k, (a, b, c) in enumerate(w.tolist()):
        try:
            periods[k] = _core.flip_period(core, (a, b, c))
        except ValueError as exc:
            raise type(exc)(f"`omega0` at row {k}: {exc}") from None
    return periods
