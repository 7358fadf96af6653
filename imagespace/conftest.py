"""Doctest collection: the short-path modules (``imagespace/cusps.py`` ...) are the modules they
name (or re-export them); their doctests are collected once, at the real home."""

collect_ignore = ["modechange.py", "screws.py", "cusps.py", "clearance.py", "mobility.py", "workspace.py", "indices.py"]
