"""The body a scene's `[body]` table names, beyond principal moments: a tensor, a solid, a
composite of solids, a mesh file or a preset (see :mod:`dzhanibekov.scene`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..body import Body
from ..shapes import Shape

__all__ = ["BODY_KEYS", "PRESETS", "build_body", "default_signal_point"]

BODY_KEYS = ("tensor", "cylinder", "sphere", "ellipsoid", "mesh", "parts", "preset")
"""Keys of `[body]` that name a body other than by principal moments or a box."""

PRESETS = {"wing-nut": Body.wing_nut}
"""Bodies a scene names by `preset`."""

_SOLID_KEYS = ("box", "cylinder", "sphere", "ellipsoid")


def _solid(table: Mapping[str, Any], where: str) -> Body:
    """One solid from a table naming exactly one of box/cylinder/sphere/ellipsoid/mesh."""
    named = [k for k in _SOLID_KEYS + ("mesh", "tensor") if k in table]
    if len(named) != 1:
        raise ValueError(f"{where} must name one of {', '.join(_SOLID_KEYS + ('mesh', 'tensor'))}, "
                         f"got {sorted(table)}")
    key = named[0]
    value = table[key]
    mass = table.get("mass", 1.0 if key != "mesh" else None)
    if key == "mesh":
        return Body.load(str(value), mass=mass, density=table.get("density"))
    if key == "tensor":
        return Body.from_tensor(value, mass=table.get("mass"))
    if key == "sphere":
        return Body.sphere(value, mass=mass)
    size = list(value) if isinstance(value, (list, tuple)) else [value]
    expected = {"box": 3, "cylinder": 2, "ellipsoid": 3}[key]
    if len(size) != expected:
        raise ValueError(f"{where}.{key} must be a list of {expected} numbers, got {value!r}")
    if key == "cylinder":
        return Body.cylinder(size[0], size[1], mass=mass)
    factory = Body.box if key == "box" else Body.ellipsoid
    return factory(size[0], size[1], size[2], mass=mass)


def build_body(spec: Mapping[str, Any]) -> Body:
    """The Body a scene's body table names (see the module's docs).

    Raises
    ------
    ValueError, TypeError
        A table that names no body or two, or a body's own error.
    """
    extra = set(spec) - set(BODY_KEYS) - {"mass", "density"}
    if extra:
        raise ValueError(f"unknown keys {sorted(extra)}")
    if "preset" in spec:
        name = spec["preset"]
        if name not in PRESETS:
            raise ValueError(f"`preset` must be one of {list(PRESETS)}, got {name!r}")
        return PRESETS[name]()
    if "parts" in spec:
        parts = spec["parts"]
        if isinstance(parts, (str, bytes)) or not isinstance(parts, (list, tuple)) or not parts:
            raise ValueError(f"`parts` must be a list of tables, got {parts!r}")
        placed = []
        for k, part in enumerate(parts):
            if not isinstance(part, Mapping):
                raise ValueError(f"parts[{k}] must be a table, got {part!r}")
            shape_keys = {key: v for key, v in part.items() if key not in ("position", "q")}
            placed.append((_solid(shape_keys, f"parts[{k}]"), part.get("position", (0, 0, 0)),
                           part.get("q", (1.0, 0.0, 0.0, 0.0))))
        return Body.compose(placed)
    return _solid(spec, "the body")


def default_signal_point(body: Body, shape: Shape | None) -> tuple[float, float, float]:
    """A point on the body's intermediate principal axis (the spin axis of the unstable
    scenes, whose path shows the flips), a quarter beyond the outline drawn: the signal
    point scales with the body."""
    axes = body.principal_axes
    k = body.intermediate_axis
    direction = axes[:, 2 if k is None else k]
    radius = shape.radius if shape is not None else float(np.sqrt(
        2.5 * max(body.inertia) / (body.mass or 1.0)))
    x, y, z = (float(c) for c in 1.25 * radius * direction)
    return x, y, z
