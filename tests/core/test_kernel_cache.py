"""The on-disk kernel cache is not trusted code, heals itself, and is optional (issue [14]).

Every check is on the file system or on counts against the numpy path, never on the cache
code's own report: private directories (0700 whatever the umask), refused directories (foreign
owner, group/other-writable, symbolic link), planted modules never executed, planted symbolic
links never followed, corrupted numba pickles rebuilt, and ``import imagespace`` with nothing
writable.

The generated module holds the lockstep loops and the row-at-a-time loops; the cache handles them
alike (one file, one numba cache). These tests run the row loops (``lockstep=False``: compiled in
about 15 s where the lockstep loops take about 80 s) and compare their counts, DK and certified,
with the numpy path's counts computed once under the default cache.
"""

import functools
import os
import pickle
import shutil
import stat
import subprocess
import sys
import textwrap
import warnings
from pathlib import Path

import numpy as np
import pytest

import imagespace as isp
from imagespace import fastdk
from imagespace.core import codegen
from imagespace.solve.kernel import HAVE_NUMBA

pytestmark = [pytest.mark.skipif(not HAVE_NUMBA, reason="the kernel cache needs numba"),
              # these tests plant and damage numba's files in the kernel cache's __pycache__; with
              # NUMBA_CACHE_DIR set numba keeps them in that directory instead (the user's choice)
              pytest.mark.skipif(bool(os.environ.get("NUMBA_CACHE_DIR")),
                                 reason="NUMBA_CACHE_DIR moves numba's cache files out of the kernel cache")]

ROWS = 2000          # a batch of this size once failed on every later run with a broken cache


def joint_rows(m=None, n=ROWS):
    q = (m or isp.examples.general_3rpr()).q_example_float
    rng = np.random.default_rng(20261201)
    return np.asarray(q) * (1 + 0.1 * rng.standard_normal((n, 3)))


@functools.cache
def numpy_counts():
    """The numpy path's counts on :func:`joint_rows` (eigenvalues; computed once, under the cache
    in effect at the first call: the default one, see the ``template`` fixture)."""
    m = isp.examples.general_3rpr()
    return m.direct_kinematics_batch(joint_rows(m), method="numpy").count


def kernel_counts_match_numpy(m):
    """The generated module's row loops (DK and certified counts) against the numpy path."""
    from imagespace.solve.proof import batch_kernel

    Q = joint_rows(m)
    kernel = batch_kernel(m)
    count = kernel(Q, lockstep=False)[4]
    certified = kernel.certified_counts(Q, lockstep=False)[0]
    ref = numpy_counts()
    return np.array_equal(count, ref) and np.array_equal(certified, ref) and np.all(ref > 0)


def cache_warnings(record):
    return [w for w in record if issubclass(w.category, UserWarning) and "kernel cache" in str(w.message)]


@pytest.fixture(scope="module")
def template(tmp_path_factory):
    """A kernel cache with the compiled kernel of general_3rpr (built once for the module; numba
    keys its cache on the content of the generated file, so copies of it load)."""
    numpy_counts()                          # the reference, under the default cache
    root = tmp_path_factory.mktemp("template")
    old = os.environ.get("IMAGESPACE_CACHE")
    os.environ["IMAGESPACE_CACHE"] = str(root)
    try:
        # both row loops the tests use, compiled and cached once (a test that damages one file
        # then recompiles that one only)
        from imagespace.solve.proof import batch_kernel

        kernel = batch_kernel(isp.examples.general_3rpr())
        kernel(joint_rows(None, 10), lockstep=False)
        kernel.certified_counts(joint_rows(None, 300), lockstep=False)
    finally:
        if old is None:
            del os.environ["IMAGESPACE_CACHE"]
        else:
            os.environ["IMAGESPACE_CACHE"] = old
    folder = root / "kernels"
    (module,) = folder.glob("k_*.py")
    assert len(list((folder / "__pycache__").glob("*.run_rows-*.nbc"))) == 1
    assert len(list((folder / "__pycache__").glob("*.run_counts_rows-*.nbc"))) == 1
    return root, module.name, module.read_bytes()


@pytest.fixture
def cache(template, tmp_path, monkeypatch):
    """A private copy of the template cache, used by the kernels built in the test."""
    root = tmp_path / "cache"
    shutil.copytree(template[0], root)
    monkeypatch.setenv("IMAGESPACE_CACHE", str(root))
    return root / "kernels"


# --------------------------------------------------------------------------- directories

def test_cache_directories_are_created_0700_whatever_the_umask(tmp_path, monkeypatch):
    root = tmp_path / "a" / "b"
    monkeypatch.setenv("IMAGESPACE_CACHE", str(root))
    old = os.umask(0)
    try:
        codegen.kernel_cache_dir()
    finally:
        os.umask(old)
    for d in (tmp_path / "a", root, root / "kernels"):
        assert stat.S_IMODE(os.stat(d).st_mode) == 0o700, d


def _group_writable(d):
    d.mkdir(parents=True)
    d.chmod(0o770)


def _other_writable(d):
    d.mkdir(parents=True)
    d.chmod(0o707)


def _symlink(d):
    target = d.parent / "elsewhere"
    target.mkdir(parents=True, mode=0o700)
    d.symlink_to(target, target_is_directory=True)


def _foreign_owner(d):
    if os.geteuid() != 0:
        pytest.skip("changing a directory's owner needs root")
    d.mkdir(parents=True, mode=0o700)
    os.chown(d, 65534, 65534)


@pytest.mark.parametrize("make, reason", [(_group_writable, "writable by group or others"),
                                          (_other_writable, "writable by group or others"),
                                          (_symlink, "symbolic link"),
                                          (_foreign_owner, "owned by uid 65534")])
def test_unsafe_cache_directory_is_refused_with_one_warning(tmp_path, monkeypatch, make, reason):
    monkeypatch.setenv("IMAGESPACE_CACHE", str(tmp_path))
    d = tmp_path / "kernels"
    make(d)
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        first, second = codegen.kernel_cache_dir(), codegen.kernel_cache_dir()
    assert first is None and second is None
    (w,) = cache_warnings(rec)
    assert issubclass(w.category, fastdk.KernelCacheWarning)
    assert reason in str(w.message) and str(d) in str(w.message)


@pytest.mark.parametrize("make, reason", [(_symlink, "symbolic link"),
                                          (_foreign_owner, "owned by uid 65534")])
def test_unsafe_numba_pycache_is_refused(tmp_path, monkeypatch, make, reason):
    """numba's index files in kernels/__pycache__ are pickles, read before they are checked: that
    folder is held to the cache directory's rules (issue 36)."""
    monkeypatch.setenv("IMAGESPACE_CACHE", str(tmp_path))
    kernels = tmp_path / "kernels"
    kernels.mkdir(mode=0o700)
    make(kernels / "__pycache__")
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        assert codegen.kernel_cache_dir() is None
    (w,) = cache_warnings(rec)
    assert reason in str(w.message) and "__pycache__" in str(w.message)


def _writable_parent(root):
    root.chmod(0o777)                       # anyone could rename "kernels" away and plant theirs


def _foreign_parent(root):
    if os.geteuid() != 0:
        pytest.skip("changing a directory's owner needs root")
    os.chown(root, 65534, 65534)


@pytest.mark.parametrize("make, reason", [(_writable_parent, "writable by group or others"),
                                          (_foreign_parent, "owned by uid 65534")])
def test_unsafe_parent_directory_is_refused(tmp_path, monkeypatch, make, reason):
    root = tmp_path / "cacheroot"
    root.mkdir(mode=0o700)
    monkeypatch.setenv("IMAGESPACE_CACHE", str(root))
    make(root)
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        assert codegen.kernel_cache_dir() is None
    (w,) = cache_warnings(rec)
    assert reason in str(w.message) and str(root) in str(w.message)


def test_sticky_world_writable_parent_is_accepted(tmp_path, monkeypatch):
    root = tmp_path / "shared"
    root.mkdir()
    root.chmod(0o1777)                      # like /tmp: others cannot rename our entries
    monkeypatch.setenv("IMAGESPACE_CACHE", str(root / "mine"))
    assert codegen.kernel_cache_dir() == str(root / "mine" / "kernels")


@pytest.mark.slow
def test_refused_directory_gets_no_files_and_the_kernel_still_works(tmp_path, monkeypatch):
    numpy_counts()                          # the reference, under the default cache
    monkeypatch.setenv("IMAGESPACE_CACHE", str(tmp_path))
    d = tmp_path / "kernels"
    _group_writable(d)
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        assert kernel_counts_match_numpy(isp.examples.general_3rpr())
    assert len(cache_warnings(rec)) == 1
    assert list(d.iterdir()) == []


# --------------------------------------------------------------------------- planted files

PLANTED = """\
import pathlib
pathlib.Path({marker!r}).write_text("planted code ran")

def run(Q, layout, nbuf, X, P, R, A, cnt, flag):
    cnt[:] = 0
    flag[:] = 0
"""


@pytest.mark.slow
def test_planted_module_is_never_executed(cache, template, tmp_path):
    marker = tmp_path / "marker"
    module = cache / template[1]
    module.write_text(PLANTED.format(marker=str(marker)))
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        assert kernel_counts_match_numpy(isp.examples.general_3rpr())
    assert not marker.exists()
    assert module.read_bytes() == template[2]          # rewritten with the generated source
    assert len(cache_warnings(rec)) == 1


@pytest.mark.slow
def test_planted_symlinks_are_never_followed(cache, template, tmp_path):
    marker = tmp_path / "marker"
    outside = tmp_path / "outside.py"                  # code outside the cache ...
    outside.write_text(PLANTED.format(marker=str(marker)))
    victims = {name: tmp_path / f"victim{i}" for i, name in enumerate(
        [".probe", f"{template[1]}.{os.getpid()}.tmp"])}
    for name, victim in victims.items():               # ... and files a write must not reach
        victim.write_text("precious")
        (cache / name).symlink_to(victim)
    module = cache / template[1]
    module.unlink()
    module.symlink_to(outside)
    with warnings.catch_warnings(record=True):
        warnings.simplefilter("always")
        assert kernel_counts_match_numpy(isp.examples.general_3rpr())
    assert not marker.exists()
    assert outside.read_text() == PLANTED.format(marker=str(marker))
    for victim in victims.values():
        assert victim.read_text() == "precious"
    assert not module.is_symlink() and module.read_bytes() == template[2]
    assert stat.S_IMODE(module.stat().st_mode) & 0o022 == 0


@pytest.mark.slow
def test_temporaries_are_unpredictable_and_cleaned_up(cache, template):
    (cache / template[1]).unlink()
    with warnings.catch_warnings(record=True):
        warnings.simplefilter("always")
        from imagespace.solve.proof import batch_kernel
        assert batch_kernel(isp.examples.general_3rpr()) is not None
    leftovers = [p.name for p in cache.iterdir() if p.name.endswith(".tmp") or p.name == ".probe"]
    assert leftovers == []


# --------------------------------------------------------------------------- corrupted pickles

def _truncate(p):
    data = p.read_bytes()
    p.write_bytes(data[:len(data) // 2])


def _garbage(p):
    """Garbage after the numba version an index starts with (a wrong version is merely stale);
    a data file: a pickle of something else entirely."""
    head = b""
    if p.suffix == ".nbi":
        with open(p, "rb") as fh:
            pickle.load(fh)
            head = p.read_bytes()[:fh.tell()]
    p.write_bytes(head + b"\x80\x05garbage\x00" * 8 if head else pickle.dumps(("not", "numba")))


@pytest.mark.slow
# one damage per file kind (each case recompiles the kernel, ~50 s): an index with garbage after
# its version, a truncated data file. The other damages (truncated index, garbage or empty data)
# reach the same guarded load and were checked when it was written (session 5)
@pytest.mark.parametrize("pattern, damage", [("*.run_rows-*.nbi", _garbage), ("*.run_rows-*.nbc", _truncate)])
def test_corrupted_numba_cache_heals_itself(cache, pattern, damage):
    (victim,) = (cache / "__pycache__").glob(pattern)
    damage(victim)
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        assert kernel_counts_match_numpy(isp.examples.general_3rpr())
    (w,) = cache_warnings(rec)
    assert "corrupted" in str(w.message)
    # healed: the next run loads without a warning (and gives the same counts)
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        assert kernel_counts_match_numpy(isp.examples.general_3rpr())
    assert cache_warnings(rec) == []
    for f in (cache / "__pycache__").iterdir():
        with open(f, "rb") as fh:
            pickle.load(fh)                           # every index and data file is whole again


# --------------------------------------------------------------------------- nothing writable

SCRIPT = """
import sys
import numpy as np
import imagespace as isp
from imagespace import fastdk
assert fastdk.__file__.startswith({site!r}), fastdk.__file__
# the environment really is unwritable: numba found no cache locator for the helpers
assert type(fastdk._horner._cache).__name__ == "NullCache", fastdk._horner._cache
m = isp.examples.general_3rpr()
rng = np.random.default_rng(20261201)
Q = np.asarray(m.q_example_float) * (1 + 0.1 * rng.standard_normal(({rows}, 3)))
from imagespace.solve.proof import batch_kernel
kernel = batch_kernel(m)
ref = np.array({reference})                  # the numpy path's counts, from the test's process
count = kernel(Q, lockstep=False)[4]
certified = kernel.certified_counts(Q, lockstep=False)[0]
assert np.array_equal(count, ref) and np.array_equal(certified, ref) and np.all(ref > 0), (count, certified)
print("OK")
"""


@pytest.mark.slow
def test_import_and_kernel_work_when_nothing_is_writable(tmp_path):
    """A read-only install: the package's own __pycache__ cannot be created (a file is in the
    way, which stops root too), HOME and IMAGESPACE_CACHE lie under a regular file, and
    NUMBA_CACHE_DIR is empty: numba has no locator at all."""
    site = tmp_path / "site"
    src = Path(isp.__file__).parent
    shutil.copytree(src, site / "imagespace", ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    for d in [site / "imagespace", *(p for p in (site / "imagespace").rglob("*") if p.is_dir())]:
        (d / "__pycache__").write_text("in the way")
    blocker = tmp_path / "blocker"
    blocker.write_text("a regular file: nothing can be created beneath it")
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("NUMBA_", "IMAGESPACE_", "XDG_", "PYTHON"))}
    env.update(HOME=str(blocker / "home"), IMAGESPACE_CACHE=str(blocker / "x"), NUMBA_CACHE_DIR="",
               PYTHONPATH=str(site), PYTHONDONTWRITEBYTECODE="1", MPLCONFIGDIR=str(tmp_path / "mpl"))
    script = textwrap.dedent(SCRIPT.format(site=str(site), rows=ROWS, reference=numpy_counts().tolist()))
    proc = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert proc.stdout.strip().endswith("OK")
