"""Named numerical tolerances, in one frozen dataclass.

Every floating-point decision in imagespace reads its threshold from :data:`TOLERANCES` (or from
a :class:`Tolerances` instance passed explicitly), so the thresholds are documented in one place
and a test can tighten or loosen them deliberately.
"""

from dataclasses import dataclass

__all__ = ["Tolerances", "TOLERANCES"]


@dataclass(frozen=True)
class Tolerances:
    """Thresholds used by the numeric paths.

    Attributes
    ----------
    joint_residual : float
        A candidate assembly mode is reported only if the inverse kinematics of every leg
        reproduces the given joint value to within this, relative to the joint's scale
        (``max(1, |q|, design length scale)`` for prismatic joints, ``1`` for angles).
    real_root_imag : float
        A numeric root ``t`` of the kinematic polynomial is a real candidate when
        ``|Im t| <= real_root_imag * (1 + |t|)``; candidates are then polished and checked, so
        a loose value only costs time.
    duplicate : float
        Two polished modes closer than this (in the normalised image point) are one mode.
    degenerate : float
        A binary form whose coefficients are all below ``degenerate`` times the scale of its
        inputs is treated as identically zero (exact arithmetic then confirms).
    newton_steps : int
        Maximum Newton iterations when polishing a mode on the full constraint system.
    singular : float
        A Jacobian is singular when ``|det| / prod(row norms) <= singular`` (dimensionless);
        a float conic invariant is zero when below ``singular`` times the coefficient scale to
        the invariant's degree.
    """

    joint_residual: float = 1e-7
    real_root_imag: float = 1e-5
    duplicate: float = 1e-7
    degenerate: float = 1e-11
    newton_steps: int = 30
    singular: float = 1e-9


TOLERANCES = Tolerances()
