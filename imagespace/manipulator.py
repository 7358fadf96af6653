"""PlanarParallel: a planar :class:`~imagespace.core.mechanism.Mechanism` with its back ends bound.

A thin facade: the legs, quadrics, polynomials and inverse kinematics come from
:class:`~imagespace.core.planar.PlanarMechanism`; the direct kinematics is the one front end
(:mod:`imagespace.solve.front`) over the planar back ends (:mod:`imagespace.solve.planar`;
results in :mod:`imagespace.solve.results`); the singularity surfaces come from
:mod:`imagespace.singular`.
"""

from __future__ import annotations

from .core.planar import PlanarMechanism
from .solve import distributed, front, planar
from .solve.results import AssemblyMode, AssemblyModes, CertifiedModes, DKBatchResult

__all__ = ["PlanarParallel", "AssemblyMode", "AssemblyModes", "DKBatchResult", "CertifiedModes"]


class PlanarParallel(PlanarMechanism):
    """A planar 3-DOF parallel manipulator: a base and a platform joined by three legs.

    Parameters
    ----------
    legs : sequence of three Leg
        E.g. ``[isp.RPR(...), isp.RPR(...), isp.PPR(...)]``; each leg's actuated joint is one
        input of the manipulator.
    name : str, optional
    tolerances : Tolerances, optional

    Examples
    --------
    >>> import imagespace as isp
    >>> m = isp.PlanarParallel([isp.RPR(base=(0, 0), platform=(0, 0)),
    ...                         isp.RPR(base=(4, 0), platform=(2, 0)),
    ...                         isp.RPR(base=(0, 4), platform=(0, 2))])
    >>> q = m.inverse_kinematics([1.0, 1.0, 0.2])
    >>> modes = m.direct_kinematics(q)
    >>> any(abs(mode.pose - [1.0, 1.0, 0.2]).max() < 1e-9 for mode in modes)
    True
    """

    #: the planar back ends (imagespace.solve.planar); the front end reads them
    backends = planar.BACKENDS
    # the direct kinematics: the one front end (docstrings and examples at imagespace.solve.front)
    direct_kinematics = front.direct_kinematics
    direct_kinematics_batch = front.direct_kinematics_batch
    direct_kinematics_chunks = front.direct_kinematics_chunks
    certified_root_counts = front.certified_root_counts
    direct_kinematics_dask = distributed.direct_kinematics_dask    # dask imported on first call

    def __repr__(self):
        return f"PlanarParallel({self.name!r}, legs={list(self.legs)!r})"

    def singularity_surface(self, q=None, working_modes=None):
        """The singularity surface, compiled and labelled; see :func:`imagespace.singularity_surface`.

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.examples.general_3rpr().singularity_surface().kind
        'joint-free'
        """
        from .singular.surface import singularity_surface

        return singularity_surface(self, q=q, working_modes=working_modes)

    def singularity_surfaces(self):
        """Every image-space singularity surface, one per working mode; see
        :func:`imagespace.singularity_surfaces`.

        Examples
        --------
        >>> import imagespace as isp
        >>> [S.kind for S in isp.examples.general_3rpr().singularity_surfaces()]
        ['joint-free']
        """
        from .singular.surface import singularity_surfaces

        return singularity_surfaces(self)

    def jacobians(self, pose, q=None, working_modes=None):
        """Seed 003's ``Jx``, ``Jq``, ``J`` and the singularity type; see :func:`imagespace.jacobians`.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.stigger_husty()
        >>> m.jacobians(m.direct_kinematics(m.q_example)[0].pose).kind
        'regular'
        """
        from .singular.jacobians import jacobians

        return jacobians(self, pose, q=q, working_modes=working_modes)


    # .. internals ..............................................................

