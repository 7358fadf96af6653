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


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("mypy") is None and subprocess.run(
    [sys.executable, "-m", "mypy", "--version"], capture_output=True).returncode != 0, reason="mypy not installed")
def test_overloads_give_each_face_its_type(tmp_path):
    """mypy knows the numeric face returns an ndarray: numpy methods type-check, a sympy
    attribute on it is an error a user sees before running anything."""
    good = tmp_path / "good.py"
    good.write_text(textwrap.dedent("""
        import imagespace.core.kinematic_map as km
        X = km.image_point([1.0, 2.0, 0.3])
        print(X.shape, X.mean())
    """))
    bad = tmp_path / "bad.py"
    bad.write_text(textwrap.dedent("""
        import imagespace.core.kinematic_map as km
        X = km.image_point([1.0, 2.0, 0.3])
        print(X.free_symbols)
    """))
    import os
    from pathlib import Path

    import imagespace

    # an editable install is an import hook mypy cannot follow: point it at the source tree
    env = dict(os.environ, MYPYPATH=str(Path(imagespace.__file__).resolve().parents[1]))
    run = lambda f: subprocess.run([sys.executable, "-m", "mypy", "--ignore-missing-imports",  # noqa: E731
                                    "--follow-imports=silent", "--no-incremental", str(f)],
                                   capture_output=True, text=True, env=env, cwd=tmp_path)
    assert run(good).returncode == 0, run(good).stdout
    out = run(bad)
    assert out.returncode == 1 and "free_symbols" in out.stdout, out.stdout
