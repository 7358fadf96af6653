"""Singularities: the singularity surface, its meshes, cusps.

Imports ``core`` and ``solve``.
"""
