"""Doctest collection: the short-path alias modules (``imagespace/cusps.py`` ...) *are* the modules
they name; their doctests are collected once, at the real home."""

collect_ignore = ["modechange.py", "cusps.py", "clearance.py", "mobility.py", "workspace.py", "indices.py"]
