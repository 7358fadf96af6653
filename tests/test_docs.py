"""The documentation site builds with warnings as errors (docs/build.sh), executes the notebooks
and holds the API pages generated from the docstrings."""

import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS_PACKAGES = ("sphinx", "myst_nb", "numpydoc", "pydata_sphinx_theme", "ipykernel", "plotly", "anywidget")


@pytest.mark.slow
@pytest.mark.docs
def test_docs_build_with_warnings_as_errors(tmp_path):
    # a full build executes every notebook (minutes): .ci/run sets IMAGESPACE_DOCS=1 for its docs step
    if os.environ.get("IMAGESPACE_DOCS") != "1":
        pytest.skip("the docs build runs when IMAGESPACE_DOCS=1 (as in .ci/run's docs step)")
    missing = [name for name in DOCS_PACKAGES if importlib.util.find_spec(name) is None]
    if missing:
        pytest.fail(f"the docs extra is not installed (missing {', '.join(missing)}): "
                    'python -m pip install -e ".[docs]"')
    out = tmp_path / "html"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]))
    env.pop("IMAGESPACE_DOCS_EXECUTE", None)  # the notebooks are executed
    proc = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-b", "html",
         "-d", str(tmp_path / "doctrees"), str(ROOT / "docs"), str(out)],
        cwd=ROOT, env=env, capture_output=True, text=True, timeout=3600)
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-8000:]

    api = out / "api" / "generated" / "imagespace.solve.front.direct_kinematics.html"
    assert api.is_file()
    assert 'id="imagespace.solve.front.direct_kinematics"' in api.read_text(encoding="utf-8")

    # an executed notebook: its page shows a figure the build produced
    page = out / "notebooks" / "01_direct_kinematics.html"
    assert page.is_file()
    images = re.findall(r'<img[^>]+src="([^"]+\.png)"', page.read_text(encoding="utf-8"))
    assert images, "no output image on the executed notebook page"
    assert all((page.parent / src).resolve().is_file() for src in images)


def _summary_sentence(doc):
    """The first sentence autosummary shows: the first paragraph up to the first '. ' (as Sphinx
    splits it when the sentence parses)."""
    paragraph = " ".join(doc.strip().split("\n\n")[0].split())
    match = re.search(r"\.(\s|$)", paragraph)
    return paragraph[: match.start() + 1] if match else paragraph


def test_summary_sentences_keep_their_inline_literals_whole():
    # an autosummary table shows each public object's first sentence; a ``literal`` cut at a '. '
    # inside it is a docutils warning, which fails the docs build (-W) only in the slow docs step
    import inspect
    import pkgutil

    import imagespace

    broken = []
    for info in pkgutil.walk_packages(imagespace.__path__, "imagespace."):
        if ".kernels." in info.name or info.name.endswith("__main__"):
            continue
        module = importlib.import_module(info.name)
        for name, obj in vars(module).items():
            if name.startswith("_") or getattr(obj, "__module__", None) != module.__name__:
                continue
            doc = inspect.getdoc(obj) if callable(obj) or inspect.isclass(obj) else None
            if doc and _summary_sentence(doc).count("``") % 2:
                broken.append(f"{info.name}.{name}: {_summary_sentence(doc)!r}")
    assert not broken, "\n".join(broken)


def test_summary_check_sees_a_cut_literal():
    assert _summary_sentence("Checked: an int in ``8 ..\nMAX``.\n\nMore.").count("``") % 2
    assert not _summary_sentence("Checked: ``a.b`` and more. Then.").count("``") % 2
