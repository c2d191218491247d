"""Attitudes between a run's frames, for drawing: the run's own cubic Hermite interpolant.

A run stores ``q`` and ``ω`` at its frames, and with them the attitude's rate
``q' = ½ q ⊗ (0, ω)``; the cubic Hermite interpolant of ``q`` through those values and rates,
normalised, is within ``(|ω| Δt)⁴ / 1500`` of the motion (about 1e-4 for the paper's 0.5 rad
between frames), far below what an eye sees, and it costs nothing like a second run. Paths
and animations are drawn from it at the resolution the eye needs, whatever the number of
stored frames.
"""

from __future__ import annotations

import math

import numpy as np

from .mass import quaternion_product

__all__ = ["attitudes_at", "turn_grid", "MAX_POINTS"]

MAX_POINTS = 200_000
"""The most points a drawn path or animation is given."""


def turn_grid(t: np.ndarray, omega: np.ndarray, max_turn: float,
              most: int = MAX_POINTS) -> np.ndarray:
    """Evenly spaced times over ``[t[0], t[-1]]`` with the body turning at most `max_turn`
    radians from one to the next (at its largest rate): each interval between the frames `t`
    (evenly spaced) cut into the same number of parts, so the frames are among the times.
    At most `most` times (then the body turns further between them), never fewer than `t`."""
    rate = float(np.sqrt((omega * omega).sum(axis=1)).max()) if len(omega) else 0.0
    intervals = len(t) - 1
    step = float(t[-1] - t[0]) / intervals
    parts = max(1, math.ceil(rate * step / max_turn))
    parts = max(1, min(parts, (most - 1) // intervals))
    return np.linspace(t[0], t[-1], parts * intervals + 1)


def attitudes_at(t: np.ndarray, omega: np.ndarray, q: np.ndarray, times: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray]:
    """The attitudes (unit quaternions, (N, 4)) and rates (linear between frames, (N, 3)) at
    `times` within ``[t[0], t[-1]]``, from frames `t`, `omega`, `q` (scalar first)."""
    rate = 0.5 * quaternion_product(q, np.concatenate([np.zeros((len(q), 1)), omega], axis=1))
    i = np.clip(np.searchsorted(t, times, side="right") - 1, 0, len(t) - 2)
    h = t[i + 1] - t[i]
    s = ((times - t[i]) / h)[:, None]
    s2, s3 = s * s, s * s * s
    q0, q1 = q[i], q[i + 1]
    q1 = np.where((q0 * q1).sum(axis=1, keepdims=True) < 0, -q1, q1)  # the same hemisphere
    r1 = np.where((q[i] * q[i + 1]).sum(axis=1, keepdims=True) < 0, -rate[i + 1], rate[i + 1])
    out = ((2 * s3 - 3 * s2 + 1) * q0 + (s3 - 2 * s2 + s) * h[:, None] * rate[i]
           + (-2 * s3 + 3 * s2) * q1 + (s3 - s2) * h[:, None] * r1)
    out /= np.linalg.norm(out, axis=1, keepdims=True)
    w = (1 - s) * omega[i] + s * omega[i + 1]
    return out, w
