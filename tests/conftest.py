import matplotlib
import numpy as np
import pytest
from hypothesis import settings

matplotlib.use("Agg")

# reproducible property tests: hypothesis draws from a fixed seed, no example database
settings.register_profile("imagespace", derandomize=True, database=None, deadline=None)
settings.load_profile("imagespace")


@pytest.fixture
def rng():
    """A seeded generator: every random test is reproducible."""
    return np.random.default_rng(20261121)
