"""Every writer on hostile targets (issue 36): an existing file, a symbolic link, a FIFO, a
character device, a read-only folder, a target with special mode bits, stale temporaries, SIGTERM
during a write. The rules are imagespace._files' (README, "Security and files")."""

from __future__ import annotations

import os
import signal
import stat
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

import imagespace as isp
from imagespace._files import STALE_TEMPORARY_SECONDS, atomic_write, check_target


def _mesh():
    import trimesh

    return trimesh.Trimesh(np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]]), process=False)


def _atlas():
    m = isp.examples.general_3rpr()
    return isp.joint_atlas(m, [(9, 13), (3, 7), (8, 12)], resolution=5)


@pytest.fixture(scope="module")
def atlas():
    return _atlas()


def _writers(atlas):
    """(name, suffix, write(path)) for each public writer."""
    return [
        ("export_mesh ply", ".ply", lambda p: isp.export_mesh(_mesh(), p)),
        ("export_mesh stl", ".stl", lambda p: isp.export_mesh(_mesh(), p)),
        ("JointAtlas.write_table", ".csv", lambda p: atlas.write_table(p)),
        ("atomic_write", ".bin", lambda p: atomic_write(p, lambda f: f.write(b"data"))),
    ]


WRITER_NAMES = ["export_mesh ply", "export_mesh stl", "JointAtlas.write_table", "atomic_write"]


def _writer(atlas, name):
    return next(w for w in _writers(atlas) if w[0] == name)


def _listing(folder):
    return sorted(p.name for p in Path(folder).iterdir())


@pytest.mark.parametrize("name", WRITER_NAMES)
def test_new_file_gets_umask_mode_and_no_temporaries(tmp_path, atlas, name):
    _, suffix, write = _writer(atlas, name)
    target = tmp_path / f"out{suffix}"
    old = os.umask(0o027)
    try:
        write(target)
    finally:
        os.umask(old)
    assert stat.S_IMODE(target.stat().st_mode) == 0o666 & ~0o027
    assert _listing(tmp_path) == [target.name]


@pytest.mark.parametrize("name", WRITER_NAMES)
def test_special_mode_bits_are_never_copied(tmp_path, atlas, name):
    _, suffix, write = _writer(atlas, name)
    target = tmp_path / f"out{suffix}"
    target.write_bytes(b"old")
    os.chmod(target, 0o6777)
    write(target)
    mode = stat.S_IMODE(target.stat().st_mode)
    assert mode & 0o7000 == 0, oct(mode)              # no setuid, setgid, sticky
    assert mode == 0o777                              # the permission bits it had, nothing more
    assert target.read_bytes() != b"old"


@pytest.mark.parametrize("name", WRITER_NAMES)
def test_a_symlink_at_the_target_is_refused_and_untouched(tmp_path, atlas, name):
    _, suffix, write = _writer(atlas, name)
    victim = tmp_path / "victim"
    victim.write_bytes(b"precious")
    os.chmod(victim, 0o6777)
    link = tmp_path / f"link{suffix}"
    link.symlink_to(victim)
    with pytest.raises(isp.InputError, match="symbolic link"):
        write(link)
    assert link.is_symlink() and victim.read_bytes() == b"precious"
    assert stat.S_IMODE(victim.stat().st_mode) == 0o6777
    assert _listing(tmp_path) == sorted(["victim", link.name])


@pytest.mark.parametrize("name", WRITER_NAMES)
def test_a_fifo_at_the_target_is_refused(tmp_path, atlas, name):
    _, suffix, write = _writer(atlas, name)
    fifo = tmp_path / f"pipe{suffix}"
    os.mkfifo(fifo)
    with pytest.raises(isp.InputError, match="FIFO"):
        write(fifo)
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert _listing(tmp_path) == [fifo.name]


def test_a_character_device_at_the_target_is_refused(tmp_path):
    dev = tmp_path / "null.ply"
    try:
        os.mknod(dev, 0o666 | stat.S_IFCHR, os.makedev(1, 3))
    except (PermissionError, OSError):
        dev = None
    if dev is None:                               # not root: the system's own /dev/null
        dev = Path("/dev/null")
    with pytest.raises(isp.InputError, match="character device"):
        isp.export_mesh(_mesh(), dev)
    assert stat.S_ISCHR(os.lstat(dev).st_mode)


def test_a_directory_at_the_target_is_refused(tmp_path):
    with pytest.raises(isp.InputError, match="directory"):
        atomic_write(tmp_path, lambda f: f.write(b"x"))


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_a_read_only_folder_gives_an_error_and_leaves_nothing(tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    os.chmod(ro, 0o555)
    try:
        with pytest.raises(OSError):
            isp.export_mesh(_mesh(), ro / "m.ply")
        assert _listing(ro) == []
    finally:
        os.chmod(ro, 0o755)


def test_an_existing_regular_file_is_replaced_atomically(tmp_path):
    target = tmp_path / "m.ply"
    target.write_bytes(b"old")
    os.chmod(target, 0o640)
    inode = target.stat().st_ino
    isp.export_mesh(_mesh(), target)
    assert target.read_bytes().startswith(b"ply")
    assert stat.S_IMODE(target.stat().st_mode) == 0o640
    assert target.stat().st_ino != inode               # a new file renamed over the old one


def test_a_failing_write_leaves_the_target_and_no_temporary(tmp_path):
    target = tmp_path / "f.bin"
    target.write_bytes(b"old")

    def boom(f):
        f.write(b"half")
        raise RuntimeError("disk on fire")

    with pytest.raises(RuntimeError):
        atomic_write(target, boom)
    assert target.read_bytes() == b"old" and _listing(tmp_path) == ["f.bin"]


def test_stale_temporaries_are_removed_fresh_ones_kept(tmp_path):
    target = tmp_path / "f.bin"
    stale = tmp_path / ".f.bin.abc123.tmp"
    fresh = tmp_path / ".f.bin.def456.tmp"
    other = tmp_path / ".g.bin.abc123.tmp"
    for p in (stale, fresh, other):
        p.write_bytes(b"left over")
    old = time.time() - 2 * STALE_TEMPORARY_SECONDS
    os.utime(stale, (old, old))
    os.utime(other, (old, old))
    atomic_write(target, lambda f: f.write(b"new"))
    assert _listing(tmp_path) == sorted([".f.bin.def456.tmp", ".g.bin.abc123.tmp", "f.bin"])


def test_sigterm_during_a_write_removes_the_temporary(tmp_path):
    """A process killed by SIGTERM while it writes leaves the old file and no temporary."""
    target = tmp_path / "big.bin"
    target.write_bytes(b"old")
    ready = tmp_path / "ready"
    code = textwrap.dedent(f"""
        import pathlib, time
        from imagespace._files import atomic_write
        def slow(f):
            f.write(b"x" * 1000)
            f.flush()
            pathlib.Path({str(ready)!r}).write_text("1")
            time.sleep(60)
        atomic_write({str(target)!r}, slow)
    """)
    proc = subprocess.Popen([sys.executable, "-c", code])
    try:
        t0 = time.time()
        while not ready.exists() and time.time() - t0 < 60:
            time.sleep(0.05)
        assert ready.exists()
        assert any(n.endswith(".tmp") for n in _listing(tmp_path))      # the write is under way
        proc.send_signal(signal.SIGTERM)
        proc.wait(timeout=30)
    finally:
        proc.kill()
    assert proc.returncode != 0
    assert target.read_bytes() == b"old"
    assert _listing(tmp_path) == sorted(["big.bin", "ready"])


def test_check_target_names_the_parameter(tmp_path):
    with pytest.raises(isp.InputTypeError, match="output must be a file path"):
        check_target(3.5, "output")
    with pytest.raises(isp.InputError, match="the folder .* does not exist"):
        check_target(tmp_path / "missing" / "f.ply")


def test_cli_plot_refuses_a_fifo(tmp_path):
    fifo = tmp_path / "out.ply"
    os.mkfifo(fifo)
    code = f"import sys; from imagespace.cli import main; sys.exit(main(['plot', 'conic', '-o', {str(fifo)!r}]))"
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert r.returncode != 0
    assert "FIFO" in r.stderr + r.stdout
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
