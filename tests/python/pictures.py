"""What the tests that write image files check of each: that it is a real picture."""

from __future__ import annotations

import numpy as np
from PIL import Image


def assert_picture(path):
    """A real image: more than a handful of colours (not one blank colour)."""
    with Image.open(path) as image:
        pixels = np.asarray(image.convert("RGB")).reshape(-1, 3)
    assert len(np.unique(pixels, axis=0)) > 16, f"{path} is (nearly) blank"
