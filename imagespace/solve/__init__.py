"""Direct kinematics: the certified per-root path and the compiled batch kernel.

Imports ``core`` (and the package's base modules) only.
"""
