"""Pure mathematics of the planar image space: the kinematic map, the dyad quadrics, the legs,
binary forms and their elimination, real roots, exact/arb isolation and the sympy -> numpy bridge.

Imports nothing above ``core`` (ARCHITECTURE.md rule 1; ``tests/test_layers.py``).
"""
