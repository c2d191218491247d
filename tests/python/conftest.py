import numpy as np
import pytest

import dzhanibekov as dz


@pytest.fixture
def paper_body() -> dz.Body:
    return dz.Body(inertia=dz.PAPER_INERTIA)


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261121)
