"""The standing referee of the planar direct kinematics (issue 35, section 6).

A seeded generator of cases over every class the direct kinematics must answer (``generate``),
msolve's verdict on each from a formulation of its own (``truth``: ``tests/msolve_ref.py`` on the
Euclidean pose ``(x, y, c, s)``, nothing of imagespace's elimination), and a judge of every
direct-kinematics path against it (``judge``). ``python -m tests.referee --help`` runs it from the
command line; ``tests/referee/test_referee.py`` holds the two lanes and the planted bugs.

Modules: ``spec`` (JSON form of a case, exact numbers, the design built from it), ``construct``
(exact designs through a chosen pose: half-turns, double roots, continua), ``truth``, ``generate``,
``judge``, ``run`` (the table and the command line), ``regressions`` (the issue's reproductions).
"""
