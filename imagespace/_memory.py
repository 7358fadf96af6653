"""How much memory a large computation may take: one estimate, checked before allocating."""

from __future__ import annotations

import os

from .exceptions import InputError

__all__ = ["available_memory", "check_memory"]


def available_memory() -> float:
    """Bytes this process can still allocate: the smaller of the system's available memory
    (``MemAvailable`` in ``/proc/meminfo``, else free physical pages) and the address-space limit
    (``RLIMIT_AS``, minus what is mapped already). ``inf`` when nothing can be read.

    Examples
    --------
    >>> from imagespace._memory import available_memory
    >>> available_memory() > 0
    True
    """
    limits = []
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    limits.append(int(line.split()[1]) * 1024)
                    break
    except OSError:
        try:
            limits.append(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
        except (ValueError, OSError, AttributeError):
            pass
    try:
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_AS)
        if soft != resource.RLIM_INFINITY:
            used = 0
            try:
                with open("/proc/self/statm") as fh:
                    used = int(fh.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
            except (OSError, ValueError):
                pass
            limits.append(max(soft - used, 0))
    except (ImportError, ValueError, OSError):
        pass
    return float(min(limits)) if limits else float("inf")


def check_memory(need: float, what: str, advice: str) -> None:
    """Raise :class:`~imagespace.InputError` if ``need`` bytes exceed :func:`available_memory`.

    Examples
    --------
    >>> from imagespace._memory import check_memory
    >>> check_memory(1024, "a tiny array", "none needed")
    """
    have = available_memory()
    if need > have:
        raise InputError(f"{what} needs about {need / 1e9:.3g} GB at peak, but about "
                         f"{have / 1e9:.3g} GB is available; {advice}")
