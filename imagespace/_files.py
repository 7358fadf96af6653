"""Files written safely: atomically, only over a regular file (or none), never through a symbolic
link, never with special mode bits (used by every writer: mesh exports, the atlas's table and PLY,
the explorer's HTML, the command line's pictures, the kernel cache).

Rules (the README's "Security and files"):

* the target must be missing or a regular file; a FIFO, a character or block device, a socket, a
  directory or a **symbolic link** at the target is refused with an
  :class:`~imagespace.exceptions.InputError` naming it (a link is not followed: the message says
  where it points, so the caller can write there on purpose);
* the data goes to a temporary file in the target's folder (``O_EXCL``, mode 0o600 while it is
  written), is flushed and synced, gets its mode and is renamed over the target: a reader sees the
  old file or the new one, never half of one;
* the new file's mode is ``0o666 & ~umask`` (an existing regular file keeps its permission bits),
  **never** setuid, setgid or sticky;
* on any error, and on SIGTERM or SIGINT during the write (main thread), the temporary file is
  removed; temporaries of the same target left by a killed process (older than
  :data:`STALE_TEMPORARY_SECONDS`, owned by this user) are removed by the next write.
"""

from __future__ import annotations

import os
import signal
import stat
import tempfile
import threading
import time
from contextlib import contextmanager
from pathlib import Path

from .exceptions import InputError, InputTypeError

__all__ = ["atomic_write", "new_file_mode", "check_target", "STALE_TEMPORARY_SECONDS"]

#: A temporary file of the same target older than this (seconds) was left by a killed writer.
STALE_TEMPORARY_SECONDS = 600.0

_UMASK_LOCK = threading.Lock()
_PERMISSION_BITS = 0o777             # rwx for user, group, others; never 0o7000 (suid, sgid, sticky)


def _umask():
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except OSError:
        pass
    with _UMASK_LOCK:                 # os.umask can only be read by setting it
        mask = os.umask(0o022)
        os.umask(mask)
    return mask


def new_file_mode(path):
    """The permission bits the file written at ``path`` gets: an existing regular file's own
    permission bits, else ``0o666`` less the process umask; never setuid, setgid or sticky.

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
        st = os.lstat(path)
    except FileNotFoundError:
        st = None
    if st is not None and stat.S_ISREG(st.st_mode):
        return stat.S_IMODE(st.st_mode) & _PERMISSION_BITS
    return 0o666 & ~_umask() & _PERMISSION_BITS


def check_target(path, name="path"):
    """``path`` as a :class:`~pathlib.Path` a writer may write: missing or a regular file, not a
    symbolic link, in an existing folder; otherwise an
    :class:`~imagespace.exceptions.InputError` naming ``name`` and what is there.

    Examples
    --------
    >>> import os, tempfile, pathlib
    >>> from imagespace._files import check_target
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> check_target(d / "new.ply").name
    'new.ply'
    >>> os.mkfifo(d / "pipe")
    >>> check_target(d / "pipe")
    Traceback (most recent call last):
    ...
    imagespace.exceptions.InputError: path .../pipe exists and is a FIFO (a named pipe), not a regular file: imagespace writes only regular files (give a new file name)
    """
    if isinstance(path, (bytes, bytearray)) or not isinstance(path, (str, os.PathLike)):
        raise InputTypeError(f"{name} must be a file path (str or os.PathLike), got {type(path).__name__}")
    p = Path(os.fspath(path))
    if not str(p) or str(p) == ".":
        raise InputError(f"{name} must name a file, got {str(path)!r}")
    try:
        st = os.lstat(p)
    except FileNotFoundError:
        st = None
    except OSError as e:
        raise InputError(f"{name} {p} cannot be examined: {e.strerror}") from None
    if st is not None:
        if stat.S_ISLNK(st.st_mode):
            raise InputError(f"{name} {p} is a symbolic link (to {os.readlink(p)}): imagespace does not write "
                             "through links nor replace them; give the file the link points to "
                             "(os.path.realpath) to write there")
        if not stat.S_ISREG(st.st_mode):
            raise InputError(f"{name} {p} exists and is {_kind(st.st_mode)}, not a regular file: imagespace "
                             "writes only regular files (give a new file name)")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise InputError(f"{name} {p}: the folder {parent} does not exist")
    return p


def _kind(mode):
    for test, what in ((stat.S_ISFIFO, "a FIFO (a named pipe)"), (stat.S_ISCHR, "a character device"),
                       (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"),
                       (stat.S_ISDIR, "a directory")):
        if test(mode):
            return what
    return "a special file"


def _remove_stale(path):
    """Temporaries ``.<name>.*.tmp`` of ``path`` older than STALE_TEMPORARY_SECONDS, owned by us."""
    now = time.time()
    try:
        entries = list(os.scandir(path.parent if str(path.parent) else "."))
    except OSError:
        return
    prefix = f".{path.name}."
    uid = os.getuid() if hasattr(os, "getuid") else None
    for e in entries:
        if not (e.name.startswith(prefix) and e.name.endswith(".tmp")):
            continue
        try:
            st = e.stat(follow_symlinks=False)
            if (stat.S_ISREG(st.st_mode) and (uid is None or st.st_uid == uid)
                    and now - st.st_mtime > STALE_TEMPORARY_SECONDS):
                os.unlink(e.path)
        except OSError:
            pass


class _Terminated(SystemExit):
    pass


@contextmanager
def _signals_raise():
    """In the main thread, SIGTERM (and SIGINT if it has Python's default handler) raise while
    the block runs, so the temporary file is removed; the handlers are restored after."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    saved = {}

    def handler(signum, frame):
        raise _Terminated(128 + signum)

    for sig in (signal.SIGTERM,):
        try:
            if signal.getsignal(sig) in (signal.SIG_DFL, None):
                saved[sig] = signal.signal(sig, handler)
        except (ValueError, OSError):
            pass
    try:
        yield
    finally:
        for sig, old in saved.items():
            try:
                signal.signal(sig, old)
            except (ValueError, OSError):
                pass


def atomic_write(path, write, mode=None, name="path"):
    """Write a file safely: ``write(f)`` fills a temporary file in the same folder, which is
    flushed, synced, given its mode and renamed over ``path``; on any error (SIGTERM included) the
    temporary file is removed and ``path`` is untouched.

    Parameters
    ----------
    path : str or os.PathLike
        Missing, or a regular file (see :func:`check_target`: FIFOs, devices, directories and
        symbolic links are refused).
    write : callable
        Called with the binary file object.
    mode : int, optional
        Permission bits (default :func:`new_file_mode`); only the ``0o777`` bits are used.
    name : str
        The parameter name used in error messages.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from imagespace._files import atomic_write
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "f.bin"
    >>> atomic_write(p, lambda f: f.write(b"abc"))
    >>> p.read_bytes(), sorted(x.name for x in p.parent.iterdir())
    (b'abc', ['f.bin'])
    """
    path = check_target(path, name)
    final_mode = (new_file_mode(path) if mode is None else int(mode)) & _PERMISSION_BITS
    _remove_stale(path)
    with _signals_raise():
        fd, tmp = tempfile.mkstemp(dir=path.parent if str(path.parent) else ".", prefix=f".{path.name}.",
                                   suffix=".tmp")
        try:
            with os.fdopen(fd, "wb") as f:
                write(f)
                f.flush()
                os.fsync(f.fileno())
            os.chmod(tmp, final_mode)
            check_target(path, name)          # still not a link or a special file
            os.replace(tmp, path)
        except BaseException:
            try:
                os.unlink(tmp)
            except FileNotFoundError:
                pass
            raise
    try:                              # make the rename itself durable (POSIX)
        dfd = os.open(path.parent if str(path.parent) else ".", os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(dfd)
    except OSError:
        pass
    finally:
        os.close(dfd)
