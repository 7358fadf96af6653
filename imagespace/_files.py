"""Files written atomically, with the permissions a plain ``open`` would give (used by the mesh
exports and the command line's pictures)."""

from __future__ import annotations

import os
import tempfile
import threading
from pathlib import Path

__all__ = ["atomic_write", "new_file_mode"]

_UMASK_LOCK = threading.Lock()


def new_file_mode(path):
    """The permission bits a plain ``open(path, "w")`` would give: the existing file's, else
    ``0o666`` less the process umask.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from imagespace._files import new_file_mode
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "f"
    >>> _ = p.write_text("x")
    >>> new_file_mode(p) == (p.stat().st_mode & 0o777)
    True
    """
    try:
        import stat

        return stat.S_IMODE(os.stat(path).st_mode)
    except FileNotFoundError:
        pass
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return 0o666 & ~int(line.split()[1], 8)
    except OSError:
        pass
    with _UMASK_LOCK:                 # os.umask can only be read by setting it
        mask = os.umask(0o022)
        os.umask(mask)
    return 0o666 & ~mask


def atomic_write(path, write, mode=None):
    """Write a file atomically: ``write(f)`` fills a temporary file in the same folder, which is
    flushed, synced and renamed over ``path``; on any error the temporary file is removed and
    ``path`` is untouched. The file gets ``mode`` (default: what a plain ``open`` would give, see
    :func:`new_file_mode`); ``os.replace`` replaces a symbolic link at ``path``, never follows it.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from imagespace._files import atomic_write
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "f.bin"
    >>> atomic_write(p, lambda f: f.write(b"abc"))
    >>> p.read_bytes(), sorted(x.name for x in p.parent.iterdir())
    (b'abc', ['f.bin'])
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, new_file_mode(path) if mode is None else mode)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise
    try:                              # make the rename itself durable (POSIX)
        dfd = os.open(path.parent, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(dfd)
    except OSError:
        pass
    finally:
        os.close(dfd)
