"""The spatial side: screw theory today (:mod:`imagespace.spatial.screws`); the Study quadric
and Stewart-Gough platforms grow here. Imports ``core`` only.
"""
