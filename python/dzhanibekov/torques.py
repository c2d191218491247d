"""External torques given as data or as code: a torque tabulated at knots
(:class:`TabulatedTorque`) and a torque computed by a Python function
(:class:`CallableTorque`). They go in ``dz.System(body, torques=[...])`` with the built-in
:class:`~dzhanibekov.GravityGradient` and :class:`~dzhanibekov.ConstantTorque`, and add up.

>>> import dzhanibekov as dz
>>> pulse = dz.TabulatedTorque([0.0, 1.0, 2.0], [(0, 0, 0), (0, 0, 0.5), (0, 0, 0)])
>>> dz.System(dz.Body((1.0, 2.0, 3.0)), torques=[pulse]).conserved
('q_norm',)
"""

from __future__ import annotations

from .parts import CallableTorque, TabulatedTorque
from .parts._knots import BYTES_PER_KNOT, interpolate, knot_fraction, knot_times

__all__ = ["TabulatedTorque", "CallableTorque", "knot_times", "knot_fraction", "interpolate",
           "BYTES_PER_KNOT"]
