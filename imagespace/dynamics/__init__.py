"""Inverse dynamics of planar parallel mechanisms through drive singularities (seed 000).

* :mod:`~imagespace.dynamics.model` - the open-tree formalism and the Lagrangian equations of motion;
* :mod:`~imagespace.dynamics.timelaw` - polynomial time laws (the seed's cubic and sixth-degree laws);
* :mod:`~imagespace.dynamics.solve` - kinematics along a trajectory, drive singularities, the
  consistency condition, inverse dynamics with the modified equation, power balance, simulation;
* :mod:`~imagespace.dynamics.seed000` - the seed's 2-RPR example with chosen data.
"""

from .model import Body, OpenTreeModel
from .seed000 import SEED000, seed000_model, seed000_path
from .solve import (DriveSingularity, InverseDynamicsResult, LinePath, consistent_acceleration, drive_singularity,
                    inverse_dynamics, plan_consistent_law, power_balance, simulate, state)
from .timelaw import TimeLaw, cubic_rest_to_rest, sextic_through

__all__ = ["Body", "OpenTreeModel", "SEED000", "seed000_model", "seed000_path", "LinePath", "state",
           "DriveSingularity", "drive_singularity", "consistent_acceleration", "plan_consistent_law",
           "InverseDynamicsResult", "inverse_dynamics", "power_balance", "simulate", "TimeLaw",
           "cubic_rest_to_rest", "sextic_through"]
