"""Machinery shared by the public-API walkers (issue 36): the public callables, a valid call of
each, the hostile values per parameter, and one guarded probe.

* :func:`public_callables` walks ``imagespace.__path__`` with pkgutil and collects every callable
  named in an ``__all__`` (functions, classes as constructors), plus the public methods of those
  classes that imagespace itself defines. Each object appears once, under its first name.
* :func:`valid_call` finds a call that works: the first call of the callable that its own doctest
  makes (the doctest runs with the callable wrapped by a recorder that stops at the first call,
  so the valid values are the documented ones), else an entry of ``VALID_CALLS``.
* :func:`hostile_values` derives the hostile values for one parameter from its valid value:
  scalars, strings that run code, wrong shapes and dtypes, sympy and mpmath numbers, and
  entry-wise replacements inside a valid vector.
* :func:`probe` runs one call in an empty temporary working directory under a ~10 s alarm and
  returns ``None`` (fine) or a short description of what went wrong.
"""

from __future__ import annotations

import contextlib
import copy
import doctest
import importlib
import inspect
import io
import numbers
import os
import re
import signal
import sys
import tempfile
import time
import uuid
import warnings
from functools import lru_cache

import mpmath
import numpy as np
import sympy as sp

import imagespace
from imagespace.exceptions import ImageSpaceError

#: a file the hostile strings create if anything evaluates them (checked after every call)
MARKER = os.path.join(tempfile.gettempdir(), f"pwned_walker_{os.getpid()}_{uuid.uuid4().hex[:10]}")
EVAL_STRING = f"__import__('os').system('touch {MARKER}')"

#: seconds one probe may take before the alarm turns it into a reported hang: a hang detector,
#: not a speed claim (a first call on a clean machine compiles kernels and solves start systems
#: for tens of seconds under load; 10 s failed CI on the spatial explorer's defaults)
ALARM_SECONDS = 120.0

# --------------------------------------------------------------------------------------------
# which callables are public


#: the public surface: the package's top level and the subpackages a user imports by name (their
#: ``__init__`` exports); helper modules' ``__all__`` lists are internal contracts, not walked
PUBLIC_MODULES = ("imagespace", "imagespace.examples", "imagespace.spatial", "imagespace.atlas",
                  "imagespace.paths", "imagespace.design", "imagespace.dynamics", "imagespace.widgets",
                  "imagespace.plotting")


def _modules():
    """The public modules, imported."""
    return [importlib.import_module(name) for name in PUBLIC_MODULES]


#: public callables that are not walked, each with the reason
NOT_WALKED = {
    'imagespace.dynamics.simulate':
        'integrates an ODE for seconds per valid call (covered by tests/dynamics)',
    'imagespace.spatial.certify_endpoints':
        'a hostile array crashed the interpreter (double free or corruption)',
    'imagespace.spatial.solve_start_system':
        "a hostile value stopped the walker's process (native code, no alarm)",
    'imagespace.AssemblyMode':
        'result record built by the library, not an input boundary',
    'imagespace.DKBatchResult':
        'result record built by the library, not an input boundary',
    'imagespace.ModeChangePlan':
        'result record built by the library, not an input boundary',
    'imagespace.RealRootCertificate':
        'result record built by the library, not an input boundary',
    'imagespace.JointAtlas':
        'result record built by the library, not an input boundary',
    'imagespace.atlas.UniquenessDomains':
        'result record built by the library, not an input boundary',
    'imagespace.design.DesignTable':
        'result record built by the library, not an input boundary',
    'imagespace.spatial.FastCertificate':
        'result record built by the library, not an input boundary',
    'imagespace.spatial.QuadricFamily':
        'result record built by the library, not an input boundary',
    'imagespace.spatial.StartSystem':
        'result record built by the library, not an input boundary',
    'imagespace.CertifiedModes':
        'result record built by the library, not an input boundary',
    'imagespace.PoseJacobians':
        'result record built by the library, not an input boundary',
    'imagespace.CuspidalityResult':
        'result record built by the library, not an input boundary',
    'imagespace.atlas.AtlasRegion':
        'result record built by the library, not an input boundary',
    'imagespace.atlas.CuspWitness':
        'result record built by the library, not an input boundary',
    'imagespace.design.FuzzyResult':
        'result record built by the library, not an input boundary',
    'imagespace.dynamics.DriveSingularity':
        'result record built by the library, not an input boundary',
    'imagespace.dynamics.InverseDynamicsResult':
        'result record built by the library, not an input boundary',
    'imagespace.spatial.KrawczykResult':
        'result record built by the library, not an input boundary',
    'imagespace.solve.results.DKBatchResult.from_padded':
        'result record built by the library, not an input boundary',
    'imagespace.design.sweep.DesignTable.equals':
        'result record built by the library, not an input boundary',
    'imagespace.Quadric':
        'eight required coefficients (a leg builds them); its refusals are tested in tests/test_hardening_round3.py',
    'imagespace.ImagePath':
        'result record built by the library, not an input boundary',
    'imagespace.spatial.SpatialDKBatch':
        'result record built by the library, not an input boundary',
    'imagespace.spatial.SpatialDKResult':
        'result record built by the library, not an input boundary',
    'imagespace.spatial.ExactStudyResult':
        'result record built by the library, not an input boundary',
    'imagespace.spatial.results.SpatialDKBatch.from_results':
        'result record built by the library, not an input boundary',
    'imagespace.paths.Crossing':
        'result record built by the library, not an input boundary',
    'imagespace.spatial.gough_stewart.GoughStewart.cached':
        'cache plumbing: takes a key and a factory',
    'imagespace.manipulator.PlanarParallel.cached':
        'cache plumbing: takes a key and a factory',
    'imagespace.singular.surface.SingularitySurface.cached':
        'cache plumbing: takes a key and a factory',
    'imagespace.spatial.track_parameters':
        'numba track_many: SystemError from an exception left set by an earlier call (order-dependent)',
    'imagespace.spatial.three_rps.ThreeRPS.cached':
        'cache plumbing: takes a key and a factory',
    'imagespace.widgets.spatial.SpatialExplorer.trace':
        "a debugging hook of the explorer's own panels",
    'imagespace.core.legs.RPR.joint_difference':
        'no documented call; joint differences of checked rows',
    'imagespace.core.legs.RPR.joint_values_ok':
        'no documented call; a mask over checked rows',
    'imagespace.spatial.QuadricPlatform':
        'abstract base class',
}

#: classes whose methods are walked besides their constructor (the main result/design classes);
#: every public class is walked as a constructor
METHOD_CLASSES = (
    "imagespace.manipulator.PlanarParallel", "imagespace.solve.results.AssemblyModes",
    "imagespace.solve.results.AssemblyMode", "imagespace.solve.results.DKBatchResult",
    "imagespace.solve.results.CertifiedModes", "imagespace.singular.surface.SingularitySurface",
    "imagespace.atlas.jointspace.JointAtlas", "imagespace.atlas.domains.UniquenessDomains",
    "imagespace.paths.curves.ImagePath", "imagespace.spatial.gough_stewart.GoughStewart",
    "imagespace.spatial.three_rps.ThreeRPS", "imagespace.spatial.results.SpatialDKResult",
    "imagespace.spatial.results.SpatialDKBatch", "imagespace.widgets.spatial.SpatialExplorer",
    "imagespace.widgets.planar.Explorer", "imagespace.core.quadratic_field.QuadraticFieldForms",
    "imagespace.design.workspace.Workspace", "imagespace.core.quadrics.Quadric",
    "imagespace.core.legs.RPR", "imagespace.atlas.cuspidal.CuspidalityResult",
    "imagespace.design.sweep.DesignTable", "imagespace.paths.check.PathCheck",
)


@lru_cache(maxsize=None)
def public_callables() -> dict:
    """``{qualified name: (kind, owner, attribute name, object)}`` of every public callable.

    ``kind`` is ``"function"``, ``"class"`` or ``"method"`` (``owner`` the class for methods,
    the module otherwise)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")     # deprecated attributes of third-party bases (ipywidgets)
        return _public_callables()


def _public_callables() -> dict:
    out: dict = {}
    seen: set = set()
    classes = []
    for mod in _modules():
        for attr in getattr(mod, "__all__", None) or ():
            obj = getattr(mod, attr, None)
            if obj is None or inspect.ismodule(obj) or not callable(obj) or id(obj) in seen:
                continue
            if inspect.isclass(obj) and issubclass(obj, BaseException):
                continue   # exception classes take a message; nothing to walk
            seen.add(id(obj))
            name = f"{mod.__name__}.{attr}"
            kind = "class" if inspect.isclass(obj) else "function"
            out[name] = (kind, mod, attr, obj)
            if inspect.isclass(obj):
                classes.append(obj)
    for cls in classes:
        home = f"{cls.__module__}.{cls.__qualname__}"
        if home not in METHOD_CLASSES:
            continue
        for mname in sorted(dir(cls)):
            if mname.startswith("_"):
                continue
            raw = inspect.getattr_static(cls, mname)
            if isinstance(raw, property) or not callable(getattr(cls, mname, None)):
                continue
            func = getattr(raw, "__func__", raw)
            if not (getattr(func, "__module__", "") or "").startswith("imagespace"):
                continue        # list methods of AssemblyModes, dataclass helpers ...
            out[f"{home}.{mname}"] = ("method", cls, mname, raw)
    return out


def walked_names() -> list:
    return [n for n in public_callables() if n not in NOT_WALKED]


# --------------------------------------------------------------------------------------------
# a valid call of each callable


class _Recorded(BaseException):
    """Raised by the recorder at the first call: stops the doctest there."""


@lru_cache(maxsize=None)
def _examples():
    import imagespace.examples as ex

    m = ex.stigger_husty()
    g = ex.general_3rpr()
    gs, L = ex.dietmaier_1998()
    return {"m": m, "g": g, "gs": gs, "L": L}


def _dk_batch():
    m = _examples()["m"]
    Q = np.array([list(map(float, m.q_example))] * 2 + [[np.nan, 1.0, 1.0]])
    return m.direct_kinematics_batch(Q)


def _atlas():
    from imagespace.atlas import joint_atlas

    return joint_atlas(_examples()["g"], [(8, 14), (2, 8), (7, 13)], resolution=8, cusps=False)


def _domains():
    from imagespace.atlas import uniqueness_domains

    return uniqueness_domains(_examples()["g"], [(8, 14), (2, 8), (7, 13)], 12)


def _recorded_init(cls, thunk):
    """``(cls, args, kwargs)`` of the first construction of ``cls`` that ``thunk`` makes."""
    holder = []
    had = "__init__" in cls.__dict__
    old = cls.__dict__.get("__init__")

    def recorder(self, *a, **k):
        holder.append((a, k))
        raise _Recorded

    cls.__init__ = recorder
    try:
        thunk()
    except _Recorded:
        pass
    finally:
        if had:
            cls.__init__ = old
        else:
            del cls.__init__
    a, k = holder[0]
    return cls, a, k


def _open_tree_model():
    # seed000_model() caches its model per process: ask for a fresh build (explicit params)
    from imagespace.dynamics import OpenTreeModel
    from imagespace.dynamics.seed000 import SEED000, seed000_model

    return _recorded_init(OpenTreeModel, lambda: seed000_model(params=dict(SEED000)))


def _front():
    import imagespace.solve.front as front

    return front


def _v():
    import imagespace._validate as v

    return v


def _spatial_method(which, name):
    if which == "gs":
        m, L = _examples()["gs"], list(map(float, _examples()["L"]))
    else:
        m, L = imagespace.ThreeRPS(np.eye(3), 0.5 * np.eye(3)), [1.0, 1.0, 1.0]
    one = {"cached": (), "clear_cache": (), "cache_keys": (), "leg_vectors": ([1, 0, 0, 0, 0, 0, 0, 0],),
           "direct_kinematics": (L,), "check_q": (L,), "reach_check": (L,), "direct_kinematics_chunks": ([L],),
           "certified_root_counts": ([L],), "direct_kinematics_batch": ([L],), "direct_kinematics_dask": ([L],),
           "joint_rows": ([L],)}[name]
    return getattr(m, name), one, {}


def _spatial_explorer():
    from imagespace.widgets import SpatialExplorer

    gs, L = _examples()["gs"], _examples()["L"]
    return SpatialExplorer(gs, L)


#: valid calls the doctests do not make: ``name -> () -> (callable, args, kwargs)``
VALID_CALLS = {
    "imagespace.solve.results.DKBatchResult.modes": lambda: (_dk_batch().modes, (0,), {}),
    "imagespace.solve.results.DKBatchResult.concatenate":
        lambda: (type(_dk_batch()).concatenate, ([_dk_batch(), _dk_batch()],), {}),
    "imagespace.solve.results.DKBatchResult.set_modes":
        lambda: (_dk_batch().set_modes, (0, list(_dk_batch().modes(0))), {}),
    "imagespace.atlas.figures.plot_atlas": lambda: (__import__("imagespace.atlas", fromlist=["x"]).plot_atlas,
                                                    (_atlas(),), {}),
    "imagespace.atlas.domains.UniquenessDomains.poses": lambda: (_domains().poses, (_domains().aspect >= 0,), {}),
    "imagespace.widgets.spatial.SpatialExplorer.wait": lambda: (_spatial_explorer().wait, (), {"timeout": 0.1}),
    "imagespace.solve.continuum.continuum_at":
        lambda: (__import__("imagespace.solve.continuum", fromlist=["x"]).continuum_at,
                 (_examples()["g"], [11, 5, 10]), {}),
    "imagespace.spatial.poses.pose_from_matrix":
        lambda: (__import__("imagespace.spatial", fromlist=["x"]).pose_from_matrix, (np.eye(4),), {}),
    "imagespace.atlas.cuspidal.verify_cusp": None,   # from its doctest; listed for the reader
    "imagespace.manipulator.PlanarParallel.direct_kinematics":
        lambda: (_examples()["g"].direct_kinematics, ([11, 5, 10],), {}),
    "imagespace.solve.front.direct_kinematics_chunks":
        lambda: (_front().direct_kinematics_chunks, (_examples()["g"], [[11, 5, 10]]), {}),
    "imagespace.solve.front.certified_root_counts":
        lambda: (_front().certified_root_counts, (_examples()["g"], [[11, 5, 10]]), {}),
    "imagespace.solve.distributed.direct_kinematics_dask":
        lambda: (__import__("imagespace.solve.distributed", fromlist=["x"]).direct_kinematics_dask,
                 (_examples()["g"], [[11, 5, 10]]), {}),
    "imagespace._validate.as_float_array": lambda: (_v().as_float_array, ([1.0, 2.0], "value"), {}),
    "imagespace._validate.as_point": lambda: (_v().as_point, ([1.0, 2.0], "value"), {}),
    "imagespace._validate.as_exact": lambda: (_v().as_exact, (0.5, "value"), {}),
    "imagespace._validate.check_positive": lambda: (_v().check_positive, (0.5, "value"), {}),
    "imagespace._validate.is_symbolic": lambda: (_v().is_symbolic, (0.5,), {}),
    "imagespace.core.exact_roots.sturm_count": None,
    "imagespace.dynamics.OpenTreeModel": lambda: _open_tree_model(),
    "imagespace.widgets.SpatialExplorer": lambda: (__import__("imagespace.widgets", fromlist=["x"]).SpatialExplorer,
                                                   (_examples()["gs"], _examples()["L"]), {}),
    "imagespace.manipulator.PlanarParallel.direct_kinematics_batch":
        lambda: (_examples()["g"].direct_kinematics_batch, ([[11, 5, 10]],), {}),
    "imagespace.widgets.Explorer": lambda: (__import__("imagespace.widgets", fromlist=["x"]).Explorer,
                                            (_examples()["g"],), {"q": [11, 5, 10]}),
    "imagespace.core.legs.RPR.joint_values_ok": None,
    **{f"imagespace.spatial.gough_stewart.GoughStewart.{n}": (lambda n=n: _spatial_method("gs", n))
       for n in ("cached", "clear_cache", "direct_kinematics", "direct_kinematics_chunks", "cache_keys",
                 "certified_root_counts", "direct_kinematics_batch", "direct_kinematics_dask", "reach_check")},
    **{f"imagespace.spatial.three_rps.ThreeRPS.{n}": (lambda n=n: _spatial_method("rps", n))
       for n in ("cache_keys", "certified_root_counts", "check_q", "direct_kinematics_batch",
                 "direct_kinematics_dask", "leg_vectors", "cached", "clear_cache", "direct_kinematics",
                 "direct_kinematics_chunks", "joint_rows")},
}
VALID_CALLS = {k: v for k, v in VALID_CALLS.items() if v is not None}


def _run_doctest_until_recorded(obj, globs, holder):
    docs = [inspect.getdoc(obj) or ""]
    if inspect.isclass(obj):
        init = obj.__dict__.get("__init__")
        if init is not None and init.__doc__:
            docs.append(init.__doc__)
    parser = doctest.DocTestParser()
    sink = io.StringIO()
    for doc in docs:
        for ex in parser.get_examples(doc):
            try:
                with contextlib.redirect_stdout(sink), warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    exec(compile(ex.source, "<walker doctest>", "exec"), globs)
            except _Recorded:
                return True
            except Exception:     # noqa: BLE001 - examples that show an error, missing extras
                pass
            if holder:
                return True
    return bool(holder)


def _modules_binding(obj):
    for mod in list(sys.modules.values()):
        name = getattr(mod, "__name__", "") or ""
        if not name.startswith("imagespace"):
            continue
        d = getattr(mod, "__dict__", {})
        for k, v in list(d.items()):
            if v is obj:
                yield mod, k


@lru_cache(maxsize=None)
def valid_call(name):
    """``(callable, args, kwargs)`` of a call of ``name`` that works, or ``None``."""
    if name in VALID_CALLS:
        return VALID_CALLS[name]()
    kind, owner, attr, obj = public_callables()[name]
    holder: list = []
    restore = []
    with tempfile.TemporaryDirectory() as tmp, _in_dir(tmp):
        try:
            if kind == "method":
                raw = obj
                func = getattr(raw, "__func__", raw)

                def recorder(*a, **k):
                    holder.append((a, k))
                    raise _Recorded

                wrapped = type(raw)(recorder) if isinstance(raw, (classmethod, staticmethod)) else recorder
                restore.append((owner, attr, raw))
                setattr(owner, attr, wrapped)
                obj_for_doc = func
            elif kind == "class":

                def recorder(self, *a, **k):
                    holder.append((a, k))
                    raise _Recorded

                restore.append((obj, "__init__", obj.__dict__.get("__init__", _MISSING)))
                obj.__init__ = recorder
                obj_for_doc = obj
            else:
                def recorder(*a, **k):
                    holder.append((a, k))
                    raise _Recorded

                for mod, k in list(_modules_binding(obj)):
                    restore.append((mod, k, obj))
                    setattr(mod, k, recorder)
                obj_for_doc = obj
            globs = dict(getattr(sys.modules.get(getattr(obj_for_doc, "__module__", "")), "__dict__", {}))
            globs.update(_doctest_namespace())
            _run_doctest_until_recorded(obj_for_doc, globs, holder)
        finally:
            for target, k, old in reversed(restore):
                if old is _MISSING:
                    delattr(target, k)
                else:
                    setattr(target, k, old)
            _close_figures()
    if not holder:
        return None
    a, k = holder[0]
    if kind == "method":
        raw = obj
        if isinstance(raw, staticmethod):
            return getattr(owner, attr), a, k
        if isinstance(raw, classmethod):
            return getattr(owner, attr), a[1:], k
        self, a = a[0], a[1:]
        return getattr(self, attr), a, k
    return obj, a, k


_MISSING = object()


def _doctest_namespace():
    return {"np": np, "sp": sp, "isp": imagespace}


# --------------------------------------------------------------------------------------------
# hostile values


def _is_number(v):
    return isinstance(v, (numbers.Number, np.number, sp.Number)) and not isinstance(v, (bool, np.bool_))


def _is_numeric(v):
    """A number or a (nested) sequence/array of numbers: the parameter is numeric."""
    if isinstance(v, (bool, np.bool_)):
        return False
    if _is_number(v):
        return True
    if isinstance(v, sp.Basic):
        return isinstance(v, sp.Expr)
    if isinstance(v, np.ndarray):
        return v.dtype.kind in "iuf" or (v.dtype.kind == "O" and v.size > 0 and all(_is_numeric(x) for x in v.ravel()))
    if isinstance(v, (list, tuple)) and v:
        return all(_is_numeric(x) for x in v)
    return False


def _length(v):
    if isinstance(v, (str, bytes, dict)) or v is None:
        return None
    if isinstance(v, np.ndarray):
        return v.shape[0] if v.ndim >= 1 else None
    if isinstance(v, (list, tuple)):
        return len(v)
    return None


def _replace_first(v, x):
    if isinstance(v, np.ndarray):
        out = np.array(v, dtype=object)
        out[(0,) * out.ndim] = x
        return out
    items = list(v)
    if items and isinstance(items[0], (list, tuple, np.ndarray)):
        items[0] = _replace_first(items[0], x)
    else:
        items[0] = x
    return type(v)(items) if isinstance(v, tuple) else items


# (kind, factory): the values any parameter may receive
SCALAR_HOSTILES = (
    ("eval_str", lambda: EVAL_STRING),
    ("num_str", lambda: "2"),
    ("True", lambda: True),
    ("False", lambda: False),
    ("complex", lambda: 1 + 2j),
    ("None", lambda: None),
    ("nan", lambda: float("nan")),
    ("inf", lambda: float("inf")),
    ("-inf", lambda: float("-inf")),
    ("1e300", lambda: 1e300),
    ("-1e300", lambda: -1e300),
    ("1e-300", lambda: 1e-300),
    ("5e-324", lambda: 5e-324),
    ("sp.Rational", lambda: sp.Rational(1, 3)),
    ("sp.sqrt2", lambda: sp.sqrt(2)),
    ("sp.Symbol", lambda: sp.Symbol("x")),
    ("mpf", lambda: mpmath.mpf("0.5")),
    ("object_array", lambda: np.array([1.0, "a", None], dtype=object)),
    ("str_array", lambda: np.array(["1", "2", "3"])),
    ("bool_array", lambda: np.array([True, False, True])),
    ("empty_array", lambda: np.empty(0)),
    ("empty_rows", lambda: np.empty((0, 3))),
    ("array_3x3", lambda: np.eye(3)),
)

# applied inside a valid vector (its first scalar entry replaced) and shape changes of it
ENTRY_HOSTILES = (
    ("entry_eval_str", lambda: EVAL_STRING),
    ("entry_nan", lambda: float("nan")),
    ("entry_True", lambda: True),
    ("entry_None", lambda: None),
    ("entry_complex", lambda: 1 + 2j),
    ("entry_Symbol", lambda: sp.Symbol("x")),
)


#: the kinds the fast lane walks (one of each family: code in a string, a bool, None, a non-finite
#: and a huge float, a complex, an object array, a wrong shape, a bad entry); the slow lane walks all
FAST_KINDS = frozenset({"eval_str", "True", "None", "nan", "1e300", "complex", "object_array",
                        "array_3x3", "entry_eval_str", "entry_nan", "one_short"})


def hostile_values(valid, has_valid: bool):
    """``[(kind, value)]`` for a parameter whose valid value is ``valid``."""
    out = []
    for kind, make in SCALAR_HOSTILES:
        v = make()
        if has_valid and _same(v, valid):
            continue
        if isinstance(valid, (bool, np.bool_)) and kind in ("True", "False"):
            continue
        out.append((kind, v))
    n = _length(valid) if has_valid else None
    if n:
        for kind, make in ENTRY_HOSTILES:
            try:
                out.append((kind, _replace_first(valid, make())))
            except Exception:      # noqa: BLE001 - an immutable or odd sequence
                break
        if _is_numeric(valid):
            try:
                arr = np.asarray(valid, dtype=float)
            except (TypeError, ValueError):
                arr = None
            if arr is not None and arr.ndim >= 1 and arr.shape[0] >= 1:
                out.append(("one_short", arr[:-1].copy()))
                out.append(("one_long", np.concatenate([arr, arr[:1]])))
                out.append(("scalar_for_vector", 0.5))
    return out


def _same(a, b):
    try:
        if type(a) is not type(b):
            return False
        if isinstance(a, np.ndarray):
            return False
        r = a == b
        return bool(r) if isinstance(r, (bool, np.bool_)) else False
    except Exception:      # noqa: BLE001
        return False


# --------------------------------------------------------------------------------------------
# one guarded call


class _Hang(BaseException):
    pass


def _alarm(signum, frame):
    raise _Hang


@contextlib.contextmanager
def _in_dir(path):
    old = os.getcwd()
    os.chdir(path)
    try:
        yield
    finally:
        os.chdir(old)


@contextlib.contextmanager
def alarm(seconds):
    """SIGALRM after ``seconds`` raises :class:`_Hang`; pytest-timeout's timer is restored."""
    old_handler = signal.signal(signal.SIGALRM, _alarm)
    old_delay, old_interval = signal.setitimer(signal.ITIMER_REAL, seconds)
    start = time.monotonic()
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old_handler)
        if old_delay:
            signal.setitimer(signal.ITIMER_REAL, max(old_delay - (time.monotonic() - start), 1e-3), old_interval)


def _collect():
    import gc

    gc.collect()


def _close_figures():
    if "matplotlib.pyplot" in sys.modules:
        sys.modules["matplotlib.pyplot"].close("all")


def names_parameter(message: str, param: str) -> bool:
    return re.search(rf"(?<![A-Za-z0-9_]){re.escape(param)}(?![A-Za-z0-9_])", message) is not None


def _fresh(value):
    try:
        return copy.deepcopy(value)
    except Exception:       # noqa: BLE001 - an object that does not copy: share it
        return value


def call_with(fn, args, kwargs, param, value, sig):
    """The call of ``fn`` with ``param`` set to ``value`` (positional where it was positional)."""
    args, kwargs = list(args), dict(kwargs)
    params = list(sig.parameters.values())
    p = sig.parameters[param]
    index = params.index(p)
    if p.kind is p.POSITIONAL_ONLY or index < len(args):
        while len(args) <= index:
            q = params[len(args)]
            args.append(q.default)
        args[index] = value
    else:
        kwargs[param] = value
    return args, kwargs


def probe(fn, args, kwargs, param=None, value=None, numeric=False, tmp=None, alias=None):
    """Run one call; ``None`` if it behaved, else what happened (one line)."""
    owns_tmp = tmp is None
    tmp = tmp or tempfile.mkdtemp(prefix="walker_")
    before = set(os.listdir(tmp))
    problem = None
    try:
        with _in_dir(tmp), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                with alarm(ALARM_SECONDS):
                    result = fn(*args, **kwargs)
                if hasattr(result, "__next__"):      # a generator: run its first step
                    with alarm(ALARM_SECONDS):
                        next(result, None)
                animation = type(result).__module__.startswith("matplotlib.animation")
                del result
                if animation:    # an unrendered animation warns when collected: let it do so here
                    _collect()
            except _Hang:
                problem = f"hang: no answer within {ALARM_SECONDS:g} s"
            except ImageSpaceError as e:
                if param is not None and not names_parameter(str(e), param) and not (
                        alias and names_parameter(str(e), alias)):
                    problem = f"{type(e).__name__} not naming {param!r}: {_line(e)}"
            except (KeyboardInterrupt, _Recorded):
                raise
            except BaseException as e:      # noqa: BLE001 - the point of the walk
                problem = f"raw {type(e).__module__}.{type(e).__name__}: {_line(e)}"
            else:
                if numeric and isinstance(value, str):
                    problem = f"string {value[:20]!r} accepted for a numeric parameter"
    finally:
        _close_figures()
    if os.path.exists(MARKER):
        os.remove(MARKER)
        problem = "CODE EXECUTED: the hostile string ran (marker file created)"
    after = set(os.listdir(tmp))
    if after - before:
        problem = (problem + "; " if problem else "") + f"created {sorted(after - before)} in the working directory"
        for f in after - before:
            with contextlib.suppress(Exception):
                os.remove(os.path.join(tmp, f))
    if owns_tmp:
        import shutil

        shutil.rmtree(tmp, ignore_errors=True)
    return problem


def _line(e):
    text = " ".join(str(e).split())
    return text[:120]


def plan(name):
    """``(fn, args, kwargs, sig, [(param, valid, has_valid)])`` for ``name``, or ``None``."""
    call = valid_call(name)
    if call is None:
        return None
    fn, args, kwargs = call
    try:
        sig = inspect.signature(fn)
    except (TypeError, ValueError):
        return None
    try:
        bound = sig.bind_partial(*args, **kwargs)
    except TypeError:
        return None
    params = []
    for p in sig.parameters.values():
        if p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
            continue
        if p.name in bound.arguments:
            params.append((p.name, bound.arguments[p.name], True))
        elif p.default is not p.empty:
            params.append((p.name, p.default, True))
    return fn, tuple(args), dict(kwargs), sig, params


def walk_parameter(name, param, kinds=None):
    """``{kind: problem}`` for the hostile values of ``param`` (only ``kinds`` if given)."""
    pl = plan(name)
    assert pl is not None, f"{name}: no valid call (add one to VALID_CALLS or the callable to NOT_WALKED)"
    fn, args, kwargs, sig, params = pl
    entry = {p: (v, h) for p, v, h in params}
    assert param in entry, f"{name}: parameter {param} is not walked"
    valid, has_valid = entry[param]
    numeric = has_valid and _is_numeric(valid) and not isinstance(valid, (bool, np.bool_))
    # helpers that take the caller's parameter name (``as_float_array(value, name)``) must name
    # that one in their messages
    alias = entry.get("name", (None, False))[0] if param != "name" else None
    alias = alias if isinstance(alias, str) and alias else None
    problems = {}
    tmp = tempfile.mkdtemp(prefix="walker_")
    try:
        for kind, value in hostile_values(valid, has_valid):
            if kinds is not None and kind not in kinds:
                continue
            if isinstance(valid, (str, os.PathLike)) and isinstance(value, str) and kind != "eval_str":
                continue      # a path or a name: another string is a valid value
            a, k = call_with(fn, [_fresh(x) for x in args], {kk: _fresh(vv) for kk, vv in k_items(kwargs)},
                             param, value, sig)
            problem = probe(fn, a, k, param, value, numeric, tmp, alias=alias)
            if problem:
                problems[kind] = problem
    finally:
        import shutil

        shutil.rmtree(tmp, ignore_errors=True)
    return problems


def k_items(kwargs):
    return list(kwargs.items())
