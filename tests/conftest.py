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



# pytest-xdist (``--dist loadgroup`` in pyproject.toml) sends each group to one worker. Every item
# is grouped by its file, as ``--dist loadscope`` would (module-scoped fixtures and per-process
# caches built once per file); files that share an expensive per-process artefact form one group.
# The seed-000 dynamics model (a symbolic derivation of about 4 s, cached per process by
# seed000_model) is built by tests/dynamics and by the doctests of imagespace/dynamics: one group,
# one derivation instead of one on each worker. Without xdist the marks do nothing.
XDIST_GROUPS = {
    "tests/dynamics/": "dynamics",
    "imagespace/dynamics/": "dynamics",
}


# doctest examples that take a second or more; each behaviour is also checked by a fast test or
# by the other doctests of its module, so they run with the slow tests (CI runs everything)
SLOW_DOCTESTS = {
    "imagespace.dynamics.solve.simulate",
    "imagespace.singular.cusps.cusp_edges",
    "imagespace.singular.cusps.cusps",
    "imagespace.paths.cusp_loops.CuspLoop.certified_path",
    "imagespace.paths.cusp_loops.cusp_loop",
    "imagespace.cli.demo",
    "imagespace.singular.jacobians.symbolic_jacobians",
    "imagespace.widgets.planar.Explorer.change_mode",
}


@pytest.hookimpl(tryfirst=True)  # before pytest-xdist appends the group to the node id
def pytest_collection_modifyitems(config, items):
    for item in items:
        if isinstance(item, pytest.DoctestItem) and item.name in SLOW_DOCTESTS:
            item.add_marker(pytest.mark.slow)
        path = item.nodeid.split("::", 1)[0]
        group = next((g for prefix, g in XDIST_GROUPS.items() if path.startswith(prefix)), path)
        item.add_marker(pytest.mark.xdist_group(group))
