import os
import sys

import matplotlib
import numpy as np
import pytest
from hypothesis import settings

matplotlib.use("Agg")

# the shared test helpers (bruteforce.py, msolve_ref.py) live here; the tests in the package
# folders (tests/core, tests/solve, ...) import them by name
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

# reproducible property tests: hypothesis draws from a fixed seed, no example database
settings.register_profile("imagespace", derandomize=True, database=None, deadline=None)
settings.load_profile("imagespace")


@pytest.fixture
def rng():
    """A seeded generator: every random test is reproducible."""
    return np.random.default_rng(20261121)
