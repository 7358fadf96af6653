"""The public surface is typed (py.typed ships; mypy sees the numeric and symbolic faces of the
kinematic map as different return types)."""

import importlib.resources
import shutil
import subprocess
import sys
import textwrap

import pytest


def test_py_typed_marker_ships():
    assert importlib.resources.files("imagespace").joinpath("py.typed").is_file()


_NO_MYPY = shutil.which("mypy") is None and subprocess.run(
    [sys.executable, "-m", "mypy", "--version"], capture_output=True).returncode != 0

# what each snippet asks of mypy; one mypy run checks them all (the slow part is reading the package)
_SNIPPETS = {
    # the numeric face of the kinematic map returns an ndarray: numpy methods type-check ...
    "good": """
        import imagespace.core.kinematic_map as km
        X = km.image_point([1.0, 2.0, 0.3])
        print(X.shape, X.mean())
    """,
    # ... and a sympy attribute on it is an error a user sees before running anything
    "bad": """
        import imagespace.core.kinematic_map as km
        X = km.image_point([1.0, 2.0, 0.3])
        print(X.free_symbols)
    """,
    # the lazy top-level package, through its stub: names keep their types
    "surface": """
        import imagespace as isp
        reveal_type(isp.PlanarParallel)
        reveal_type(isp.examples.general_3rpr)
        reveal_type(isp.examples.general_3rpr().direct_kinematics)
        reveal_type(isp.GoughStewart)
        reveal_type(isp.Mechanism)
        reveal_type(isp.cusps)
        reveal_type(isp.screws.reciprocal_system)
        reveal_type(isp.constraints.rr_quadric)
        reveal_type(isp.TOLERANCES)
        reveal_type(isp.image_point)
    """,
    # a misspelt name is an error, not Any (the stub has no catch-all __getattr__)
    "typo": """
        import imagespace as isp
        isp.PlanarParalel
    """,
}


@pytest.fixture(scope="module")
def mypy_lines(tmp_path_factory):
    """mypy's messages on the snippets, ``{snippet: [message, ...]}``."""
    import os
    from pathlib import Path

    import imagespace

    folder = tmp_path_factory.mktemp("mypy")
    for name, code in _SNIPPETS.items():
        (folder / f"{name}.py").write_text(textwrap.dedent(code))
    # an editable install is an import hook mypy cannot follow: point it at the source tree
    env = dict(os.environ, MYPYPATH=str(Path(imagespace.__file__).resolve().parents[1]))
    out = subprocess.run([sys.executable, "-m", "mypy", "--ignore-missing-imports", "--follow-imports=silent",
                          "--no-incremental", *[f"{n}.py" for n in _SNIPPETS]],
                         capture_output=True, text=True, env=env, cwd=folder).stdout
    lines: dict = {name: [] for name in _SNIPPETS}
    for line in out.splitlines():
        head = line.split(".py:", 1)[0]
        if head in lines:
            lines[head].append(line)
    return lines


@pytest.mark.slow
@pytest.mark.skipif(_NO_MYPY, reason="mypy not installed")
def test_overloads_give_each_face_its_type(mypy_lines):
    """mypy knows the numeric face returns an ndarray: numpy methods type-check, a sympy
    attribute on it is an error a user sees before running anything."""
    assert mypy_lines["good"] == []
    assert any("error" in m and "free_symbols" in m for m in mypy_lines["bad"]), mypy_lines["bad"]


@pytest.mark.slow
@pytest.mark.skipif(_NO_MYPY, reason="mypy not installed")
def test_the_lazy_package_is_typed_through_its_stub(mypy_lines):
    """``isp.<name>`` is what it is to a type checker, not ``Any``: the classes, the examples and
    what they return, the function ``isp.cusps`` (not its module), the module aliases; and a
    misspelt name is an error."""
    revealed = [m.split('Revealed type is "', 1)[1].rstrip('"') for m in mypy_lines["surface"]
                if "Revealed type is" in m]
    assert not [m for m in mypy_lines["surface"] if "error" in m], mypy_lines["surface"]
    expected = ["-> imagespace.manipulator.PlanarParallel",           # isp.PlanarParallel (its constructor)
                "def () -> imagespace.manipulator.PlanarParallel",    # isp.examples.general_3rpr
                "def (",                                              # a bound method of the result
                "-> imagespace.spatial.gough_stewart.GoughStewart",
                "imagespace.core.mechanism.Mechanism",
                "def (manipulator",                                   # isp.cusps: a function
                "def (",                                              # isp.screws.reciprocal_system
                "-> imagespace.core.quadrics.Quadric",                # isp.constraints.rr_quadric
                "imagespace.tolerances.Tolerances",
                "def ("]                                              # isp.image_point (overloaded)
    assert len(revealed) == len(expected), mypy_lines["surface"]
    for got, want in zip(revealed, expected):
        assert got != "Any" and want in got, (got, want)
    assert any('has no attribute "PlanarParalel"' in m for m in mypy_lines["typo"]), mypy_lines["typo"]

# -- the stub of the lazy package: imagespace/__init__.pyi --------------------------------------------

def _stub_names():
    """What the stub declares, read with this test's own walk of its syntax tree (not lazy_loader's):
    ``{name: ("module", "imagespace.x")}`` for a submodule or a module alias, ``{name: ("attr",
    "imagespace.x")}`` for a name re-exported from a module."""
    import ast
    from pathlib import Path

    import imagespace

    tree = ast.parse((Path(imagespace.__file__).parent / "__init__.pyi").read_text())
    names, hidden = {}, {}
    for node in tree.body:
        if isinstance(node, ast.ImportFrom):
            assert node.level == 1, ast.unparse(node)   # the loader reads relative imports only
            for a in node.names:
                # ``x as x``: the form a type checker re-exports from a stub
                assert a.asname == a.name, f"{ast.unparse(node)}: write {a.name} as {a.name}"
                if node.module is None:
                    names[a.name] = ("module", f"imagespace.{a.name}")
                else:
                    names[a.name] = ("attr", f"imagespace.{node.module}")
        elif isinstance(node, ast.Import):
            for a in node.names:
                assert a.asname and a.asname.startswith("_"), ast.unparse(node)
                hidden[a.asname] = a.name
        elif isinstance(node, ast.Assign):
            (target,), value = node.targets, node.value
            names[target.id] = ("module", hidden[value.id])
        elif isinstance(node, ast.AnnAssign):
            names[node.target.id] = ("value", None)
    return names


def test_the_stub_and_the_package_name_the_same_things():
    """Every name of the stub is the runtime object it claims to be (a submodule, a module alias,
    a name of the module it is imported from), and every public name of the package (``dir``,
    ``__all__``) is in the stub: the two cannot drift."""
    import importlib
    import types

    import imagespace as isp

    names = _stub_names()
    for name, (kind, home) in names.items():
        value = getattr(isp, name)
        if kind == "module":
            assert value is importlib.import_module(home), name
        elif kind == "attr":
            assert not isinstance(value, types.ModuleType), name   # isp.cusps stays the function
            assert value is getattr(importlib.import_module(home), name), name
    public = {n for n in dir(isp) if not n.startswith("_")} | {"__version__"}
    assert public == set(names), (sorted(public - set(names)), sorted(set(names) - public))
    assert set(isp.__all__) <= set(names)
