"""Arguments passed in the wrong order: the moments where the rates belong and back.

``simulate((0.01, 0.01, 1.0), (52.08, 27.08, 41.67))`` runs a body that no mass distribution
has from rates that look like moments; it ends in a divergence, an endless run or an
infinite flip period, with a message about the step. Caught before the run, it gets a
message that says what happened.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _core
from .body import Body

__all__ = ["check_not_swapped", "swapped_error"]


def _triple(value: Any) -> np.ndarray | None:
    """`value` as three finite floats, or None if it is anything else (then the ordinary
    checks speak)."""
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError):
        return None
    if arr.dtype.kind not in "iuf" or arr.shape != (3,):
        return None
    arr = arr.astype(np.float64)
    return arr if np.isfinite(arr).all() else None


def _could_be_moments(x: np.ndarray) -> bool:
    """Positive and within the triangle inequality: the moments of some real body."""
    total = float(x.sum())
    return bool((x > 0).all() and 2 * x.max() <= total * (1 + _core.TRIANGLE_SLACK))


def swapped_error(body: Any, omega0: Any, function: str) -> ValueError | None:
    """The error for a `body` that cannot be a real body's moments (one not positive, or one
    larger than the other two together) while `omega0` could be; None if they do not look
    swapped.

    A :class:`~dzhanibekov.Body` is never questioned: building one is how to run such
    moments on purpose.
    """
    if isinstance(body, Body):
        return None
    moments, rates = _triple(body), _triple(omega0)
    if moments is None or rates is None or _could_be_moments(moments):
        return None
    if not _could_be_moments(rates):
        return None
    why = ("a moment is not positive" if not (moments > 0).all() else
           "one moment exceeds the sum of the other two")
    return ValueError(
        f"the arguments of `{function}` look swapped: `body` {tuple(moments.tolist())} "
        f"cannot be the principal moments of a real body ({why}), while `omega0` "
        f"{tuple(rates.tolist())} could be; pass the moments first, "
        f"{function}(body, omega0), or pass Body({tuple(moments.tolist())}) to run these "
        "moments anyway"
    )


def check_not_swapped(body: Any, omega0: Any, function: str) -> None:
    """Raises the `swapped_error` of these arguments, if any."""
    error = swapped_error(body, omega0, function)
    if error is not None:
        raise error
