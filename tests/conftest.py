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



# pytest-xdist (``--dist loadgroup`` in pyproject.toml) sends each group to one worker and spreads
# the other items one by one (session 10: grouping every file kept the long files on one worker
# while the other idled; the suite took 21 min). Files that share an expensive per-process
# artefact form one group. The seed-000 dynamics model (a symbolic derivation of about 4 s, cached
# per process by seed000_model) is built by tests/dynamics and by the doctests of
# imagespace/dynamics: one group, one derivation instead of one on each worker. Without xdist the
# marks do nothing.
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
    # measured at 0.3 s or more in the not-slow lane (session 10: the lane kept under a minute)
    "imagespace.atlas.curves.correct_cusp",
    "imagespace.atlas.curves.cusp_curves",
    "imagespace.atlas.cuspidal.cusp_polynomials",
    "imagespace.atlas.cuspidal.is_cuspidal",
    "imagespace.atlas.cuspidal.verify_cusp",
    "imagespace.atlas.domains.UniquenessDomains.figure",
    "imagespace.atlas.figures.atlas_figure",
    "imagespace.cli.plot_command",
    "imagespace.core.codegen.CoefficientEnclosure.exact_sympy",
    "imagespace.core.msolve.solve_real",
    "imagespace.core.planar.PlanarMechanism.compiled",
    "imagespace.core.quadratic_field.quadratic_field_count",
    "imagespace.solve.kernel.block_modes.backsub_block",
    "imagespace.display.latex_form",
    "imagespace.dynamics.solve.consistent_acceleration",
    "imagespace.dynamics.solve.drive_singularity",
    "imagespace.dynamics.solve.inverse_dynamics",
    "imagespace.dynamics.solve.plan_consistent_law",
    "imagespace.dynamics.solve.power_balance",
    "imagespace.paths.backlash.backlash",
    "imagespace.paths.modechange.plan_mode_change",
    "imagespace.plotting.design.plot_workspaces",
    "imagespace.plotting.planar.animate_path",
    "imagespace.plotting.planar.plot_assembly_modes",
    "imagespace.plotting.planar.plot_backlash",
    "imagespace.plotting.surfaces.plot_path_singularity",
    "imagespace.singular.jacobians.PoseJacobians.homogeneous",
    "imagespace.spatial.exact.ExactStudyResult",
    "imagespace.spatial.exact.exact_real_study_points",
    "imagespace.spatial.screws.singularity_fractions",
    "imagespace.spatial.solver.exact_result",
    "imagespace.spatial.solver.exact_study_solver",
    "imagespace.widgets.explore",
    "imagespace.widgets.planar.Explorer.set_q",
    "imagespace.widgets.planar.Explorer.show_frame",
    "imagespace.widgets.spatial.SpatialExplorer.close",
    "imagespace.widgets.spatial.SpatialExplorer.set_lengths",
    "imagespace.widgets.spatial.SpatialExplorer.trace",
    "imagespace.widgets.spatial.SpatialExplorer.wait",
}


def pytest_addoption(parser):
    parser.addoption("--slow", action="store_true", default=False,
                     help="also run the slow lane (tests marked slow; CI runs it: pytest -m slow)")


def _slow_lane_wanted(config):
    """The slow tests run with ``--slow``, or when a ``-m`` expression chooses the tests
    (``-m slow``, ``-m browser``, ``-m "not slow"``)."""
    return config.getoption("--slow") or bool((config.getoption("markexpr") or "").strip())


@pytest.hookimpl(tryfirst=True)  # before pytest-xdist appends the group to the node id
def pytest_collection_modifyitems(config, items):
    for item in items:
        if isinstance(item, pytest.DoctestItem) and item.name in SLOW_DOCTESTS:
            item.add_marker(pytest.mark.slow)
        path = item.nodeid.split("::", 1)[0]
        group = next((g for prefix, g in XDIST_GROUPS.items() if path.startswith(prefix)), None)
        if group is not None:
            item.add_marker(pytest.mark.xdist_group(group))
    if not _slow_lane_wanted(config):       # the fast lane by default (README's test command)
        slow = [item for item in items if item.get_closest_marker("slow") is not None]
        if slow:
            config.hook.pytest_deselected(items=slow)
            items[:] = [item for item in items if item.get_closest_marker("slow") is None]
