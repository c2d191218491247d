"""The wing nut of the paper's Fig. 1, as data: a hex nut (a triangle mesh with a bore) and
two wings (plates), with their proportions in millimetres (see :meth:`Body.wing_nut`)."""

from __future__ import annotations

import numpy as np

__all__ = ["ACROSS_FLATS", "HEIGHT", "BORE", "WING", "DENSITY", "hex_nut_mesh",
           "wing_positions"]

ACROSS_FLATS = 13.0
"""Hexagon width across flats, mm (flats facing ±x)."""
HEIGHT = 8.0
"""Nut height along the bolt axis z, mm (z from −4 to 4)."""
BORE = 8.0
"""Bore diameter, mm (the circumcircle of a 12-gon)."""
WING = (12.0, 2.5, 14.0)
"""Each wing plate's length (x, outward from a flat), thickness (y) and height (z), mm."""
WING_BOTTOM = -HEIGHT / 2
"""The wings stand on the nut's bottom face and rise above its top."""
DENSITY = 7.85e-3
"""Steel, g/mm³."""


def hex_nut_mesh(across_flats: float = ACROSS_FLATS, height: float = HEIGHT,
                 bore: float = BORE) -> tuple[np.ndarray, np.ndarray]:
    """A hexagonal prism about z with a 12-gon bore, as a closed triangle mesh oriented
    outward: vertices (36, 3) and faces (72, 3).

    The outer hexagon's corners are at 30° + 60° k (so its flats face ±x), the bore's at
    30° j; each outer edge k faces the bore's corners 2k, 2k + 1, 2k + 2, which the three
    triangles of its sector of the annulus join.
    """
    r_out = across_flats / np.sqrt(3.0)
    r_in = bore / 2
    out_phi = np.radians(30.0 + 60.0 * np.arange(6))
    in_phi = np.radians(30.0 + 30.0 * np.arange(12))
    half = height / 2
    outer = np.stack([r_out * np.cos(out_phi), r_out * np.sin(out_phi), np.zeros(6)], axis=1)
    inner = np.stack([r_in * np.cos(in_phi), r_in * np.sin(in_phi), np.zeros(12)], axis=1)
    # vertices: outer top 0-5, outer bottom 6-11, inner top 12-23, inner bottom 24-35
    vertices = np.concatenate([outer + [0, 0, half], outer - [0, 0, half],
                               inner + [0, 0, half], inner - [0, 0, half]])
    ot, ob, it, ib = 0, 6, 12, 24
    faces = []
    for k in range(6):
        k1 = (k + 1) % 6
        a, b, c = 2 * k, 2 * k + 1, (2 * k + 2) % 12
        # top annulus (normal +z: counter-clockwise seen from above)
        faces += [(ot + k, ot + k1, it + b), (ot + k, it + b, it + a),
                  (ot + k1, it + c, it + b)]
        # bottom annulus (normal −z: the same triangles reversed)
        faces += [(ob + k, ib + b, ob + k1), (ob + k, ib + a, ib + b),
                  (ob + k1, ib + b, ib + c)]
        # outer wall (normal outward)
        faces += [(ob + k, ob + k1, ot + k1), (ob + k, ot + k1, ot + k)]
    for j in range(12):
        j1 = (j + 1) % 12
        # bore wall (normal toward the axis, out of the solid)
        faces += [(ib + j, it + j1, ib + j1), (ib + j, it + j, it + j1)]
    return vertices, np.array(faces, dtype=np.int64)


def wing_positions() -> tuple[np.ndarray, np.ndarray]:
    """The centres of the two wings: against the flats at ±x, standing on the nut's bottom."""
    x = ACROSS_FLATS / 2 + WING[0] / 2
    z = WING_BOTTOM + WING[2] / 2
    return np.array([x, 0.0, z]), np.array([-x, 0.0, z])
