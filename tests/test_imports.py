"""``import imagespace`` is cheap: no heavy dependency is imported until a feature needs it, and
every public name and subpackage is reachable from the top-level module (issue [10])."""

import pytest
import subprocess
import sys

import imagespace as isp

HEAVY = ("sympy", "numba", "llvmlite", "scipy", "skimage", "trimesh", "matplotlib", "dask", "flint")


def _modules_after(code):
    out = subprocess.run([sys.executable, "-c", code + "\nimport sys\nprint(' '.join(sorted(sys.modules)))"],
                         capture_output=True, text=True, check=True).stdout.split()
    return {m.split(".")[0] for m in out}


def test_import_loads_no_heavy_dependency():
    loaded = _modules_after("import imagespace")
    assert not loaded & set(HEAVY), sorted(loaded & set(HEAVY))


@pytest.mark.slow
def test_direct_kinematics_does_not_load_the_plotting_stack():
    """The per-call DK needs sympy, flint and (since issue [14]: the float path proves its count
    on rigorous bounds in the compiled kernel) numba; nothing graphical and no dask. Importing the
    package alone loads none of them."""
    loaded = _modules_after("import imagespace as isp\nm = isp.examples.general_3rpr()\n"
                            "assert len(m.direct_kinematics(m.q_example_float)) == 6")
    assert not loaded & {"matplotlib", "trimesh", "skimage", "dask"}
    assert "numba" in loaded                  # the proof kernel, loaded on the first call
    bare = _modules_after("import imagespace as isp")
    assert not bare & {"numba", "llvmlite", "matplotlib", "trimesh", "skimage", "dask"}


def test_every_public_name_and_subpackage_is_reachable():
    for name in isp.__all__:
        assert getattr(isp, name) is not None, name
    homes = {"plotting": "plotting", "screws": "spatial.screws", "workspace": "design.workspace",
             "indices": "design.indices", "dynamics": "dynamics", "examples": "examples",
             "fastdk": "solve.kernel", "meshing": "singular.meshing", "core": "core", "solve": "solve"}
    for sub, home in homes.items():
        assert getattr(isp, sub).__name__ == f"imagespace.{home}"
    assert isp.InputError.__module__ == "imagespace.exceptions"


@pytest.mark.slow
def test_cusps_stays_the_function_after_its_module_is_loaded():
    loaded = subprocess.run([sys.executable, "-c", "import imagespace as isp\nimport imagespace.singular.cusps\n"
                             "from imagespace.singular.cusps import Cusp\nprint(callable(isp.cusps), type(isp.cusps).__name__)"],
                            capture_output=True, text=True, check=True).stdout.split()
    assert loaded == ["True", "function"]


def test_short_module_names_are_attributes_of_the_package_not_files():
    """``isp.screws``, ``isp.workspace`` ... are the modules of the layered packages, reached through
    the lazy loader of ``imagespace/__init__``; no top-level file re-exports them any more (issue [15]:
    the former shims ``imagespace/screws.py`` ... were removed, the notebooks import the canonical paths)."""
    import importlib
    import pathlib

    expected = {"screws": ("spatial.screws", "reciprocal_system"), "modechange": ("paths.modechange", "plan_mode_change"),
                "clearance": ("paths.backlash", "backlash"), "mobility": ("design.mobility", "gruebler"),
                "workspace": ("design.workspace", "reachable_workspace"), "indices": ("design.indices", "local_indices"),
                "paths": ("paths", "check_path"), "design": ("design", "fuzzy_minmax")}
    for short, (home, name) in expected.items():
        module = getattr(isp, short)
        assert module is importlib.import_module(f"imagespace.{home}"), short
        assert callable(getattr(module, name)), short
    package = pathlib.Path(isp.__file__).parent
    shims = [n for n in ("screws", "cusps", "clearance", "indices", "mobility", "modechange", "workspace")
             if (package / f"{n}.py").exists()]
    assert shims == []


def test_a_function_using_the_package_pickles_by_reference():
    """cloudpickle (dask workers, process pools) sends the package by name, not by value."""
    import pickle

    import cloudpickle

    import imagespace as isp

    def name():
        return isp.examples.general_3rpr().name

    assert pickle.loads(cloudpickle.dumps(isp)) is isp
    assert pickle.loads(cloudpickle.dumps(name))() == "general 3-RPR"


def test_names_of_split_modules_stay_importable_where_they_were():
    """Issue [15] split core/certify.py, singular/implicit.py and singular/meshing.py by topic; every
    name imported from the former module is the object of its new home."""
    import importlib

    moved = {"imagespace.core.certify": ("imagespace.core.exact_roots", [
                 "ISOLATION_WIDTH", "fmpq_of", "roots_in_unit_interval", "sturm_sequence", "sturm_count",
                 "float_down", "float_up", "as_fraction"]),
             "imagespace.singular.implicit": ("imagespace.singular.proven_sign", [
                 "TRIG_ULPS", "UNIT_ROUNDOFF", "ArbBudget"]),
             "imagespace.singular.meshing": ("imagespace.singular.mesh_export", [
                 "export_mesh", "EXPORT_FORMATS", "EXPORT_PRECISION"])}
    for old, (new, names) in moved.items():
        a, b = importlib.import_module(old), importlib.import_module(new)
        for name in names:
            assert getattr(a, name) is getattr(b, name), (old, name)
    meshing = importlib.import_module("imagespace.singular.meshing")
    for name in meshing.__all__:
        assert getattr(meshing, name) is not None, name
