"""Sphinx configuration of the imagespace documentation site.

Build (from the repository root; warnings are errors)::

    python -m sphinx -W --keep-going -b html docs docs/_build/html

or ``docs/build.sh``. The notebooks in ``notebooks/`` (reached through the symbolic link
``docs/notebooks``) are executed at build time by myst-nb; they stay committed without outputs.
Set ``IMAGESPACE_DOCS_EXECUTE=off`` to skip the execution while working on the other pages.
"""

import importlib
import inspect
import os
import sys
from pathlib import Path

from docutils import nodes
from docutils.statemachine import StringList
from sphinx.util.docutils import SphinxDirective

ROOT = Path(__file__).resolve().parent.parent
# document this checkout's package even when another copy is installed; the notebook kernels
# (subprocesses) inherit PYTHONPATH, so they run this checkout too
sys.path.insert(0, str(ROOT))
os.environ["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH")) if p)

import imagespace  # noqa: E402

project = "imagespace"
author = "the imagespace authors"
copyright = "the imagespace authors, BSD-3-Clause"
release = version = imagespace.__version__

extensions = [
    "myst_nb",  # Markdown pages (MyST) and executed notebooks
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "numpydoc",
]

source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
templates_path = ["_templates"]
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store", "**/.ipynb_checkpoints", "notebooks/__pycache__"]

# --- MyST / myst-nb ---------------------------------------------------------------------------
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
# conventions.md links to its own sections ("#how-these-statements-were-checked")
myst_heading_anchors = 3
# every notebook is executed at each build: they are committed without outputs
nb_execution_mode = os.environ.get("IMAGESPACE_DOCS_EXECUTE", "force")
nb_execution_timeout = 600  # seconds per notebook (the meshing notebooks take a while on 2 cores)
nb_execution_raise_on_error = True  # a failing notebook fails the build
nb_execution_show_tb = True
nb_merge_streams = True
# plotly figures (the atlas in 3D) as HTML pages load plotly.js from its CDN when the page is viewed;
# without this the executing kernel emits only plotly's own MIME type, which a static page cannot show
os.environ.setdefault("PLOTLY_RENDERER", "notebook_connected")

# --- autodoc / autosummary / numpydoc ---------------------------------------------------------
autosummary_generate = True
autosummary_ignore_module_all = False  # a module's page lists its __all__ (or its public names)
autosummary_imported_members = False
autodoc_default_options = {"member-order": "bysource"}
autodoc_typehints = "none"  # the numpydoc "Parameters" sections carry the types
numpydoc_show_class_members = False  # the class template documents members with :members:
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

suppress_warnings = []


def shadowed(modname):
    """True if the package of ``modname`` binds the submodule's name to something else
    (``imagespace.design.sweep`` is the function ``sweep``, from ``from .sweep import *``):
    autosummary cannot reach such a module by name, so its public names are documented on
    the package's page instead."""
    package, _, short = modname.rpartition(".")
    return bool(package) and getattr(importlib.import_module(package), short, None) is not sys.modules[modname]


def scan_all():
    """``(reexported, constants, package_members)`` from the ``__all__`` of every public
    imagespace module (strings only: Sphinx caches the configuration, and a function in the
    template context would not pickle).

    * ``reexported``: ``"module.name"`` for every public name a module takes from another
      imagespace module; the autosummary module template skips those, so that an object has one
      page, at its home module (``paths.check`` re-exports ``paths.curves``' names,
      ``singular.meshing`` the implicit surfaces of ``singular.implicit``, the packages
      ``paths``, ``design`` and ``dynamics`` the names of their modules).
    * ``constants``: module -> the names in its ``__all__`` that are data (``TOLERANCES``,
      ``MAX_STEPS``...); autosummary itself lists only module attributes with a ``#:`` comment.
    * ``package_members``: package -> the names it documents itself, those whose home module it
      shadows (see :func:`shadowed`).
    """
    import pkgutil

    out, constants, package_members = [], {}, {}
    for info in pkgutil.walk_packages(imagespace.__path__, "imagespace."):
        if any(part.startswith("_") for part in info.name.split(".")) or info.name.endswith("conftest"):
            continue
        module = importlib.import_module(info.name)
        for name in getattr(module, "__all__", []):
            obj = getattr(module, name, None)
            home = getattr(obj, "__module__", None)
            if (not inspect.ismodule(obj) and isinstance(home, str) and home.startswith("imagespace")
                    and home != info.name):
                if info.ispkg and home.rpartition(".")[0] == info.name and shadowed(home):
                    package_members.setdefault(info.name, []).append(name)
                else:
                    out.append(f"{info.name}.{name}")
            elif not (inspect.ismodule(obj) or inspect.isclass(obj) or callable(obj)):
                constants.setdefault(info.name, []).append(name)
    return sorted(out), constants, package_members


_reexported, _constants, _package_members = scan_all()
autosummary_context = {"reexported": _reexported, "constants": _constants,
                       "package_members": _package_members}


# --- the table of the public top-level names --------------------------------------------------
def public_home(name):
    """The documented home of ``imagespace.<name>``: ``(target, kind)``."""
    obj = getattr(imagespace, name)
    if inspect.ismodule(obj):
        return obj.__name__, "mod"
    if inspect.isclass(obj) or inspect.isroutine(obj):
        if shadowed(obj.__module__):  # documented on its package's page
            return f"{obj.__module__.rpartition('.')[0]}.{obj.__qualname__}", "obj"
        return f"{obj.__module__}.{obj.__qualname__}", "obj"
    home = type(obj).__module__  # an instance such as TOLERANCES lives beside its class
    if getattr(importlib.import_module(home), name, None) is not obj:
        raise RuntimeError(f"cannot find the home module of imagespace.{name}")
    return f"{home}.{name}", "obj"


class PublicAPI(SphinxDirective):
    """``.. public-api::`` - an autosummary table of ``imagespace.__all__``, each name linked to
    its page in its home module (so that nothing is documented twice)."""

    def run(self):
        lines = [".. autosummary::", "   :nosignatures:", ""]
        modules = []
        for name in imagespace.__all__:
            target, kind = public_home(name)
            if kind == "mod":
                modules.append(target)
            else:
                lines.append(f"   ~{target}")
        node = nodes.container()
        self.state.nested_parse(StringList(lines, source="imagespace.__all__"), self.content_offset, node)
        if modules:
            para = ".. rubric:: Modules\n\n" + "\n".join(f"* :mod:`imagespace.{m.split('.', 1)[1]}`"
                                                       for m in modules)
            self.state.nested_parse(StringList(para.splitlines(), source="imagespace.__all__"),
                                    self.content_offset, node)
        return node.children


# --- HTML ---------------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"imagespace {release}"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
}
html_static_path = []


def setup(app):
    app.add_directive("public-api", PublicAPI)
