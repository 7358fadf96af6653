"""Matplotlib figures. Imported lazily: ``import imagespace`` does not import matplotlib.

Every figure function returns the :class:`matplotlib.figure.Figure` and accepts an optional
``ax`` to draw into. By topic: :mod:`~imagespace.plotting.planar` (a mechanism, its assembly
modes, joint loops, animations, backlash), :mod:`~imagespace.plotting.surfaces` (the image space:
singularity surface, constraint quadrics, conic sections, a path's det J),
:mod:`~imagespace.plotting.design` (mode-count maps, workspaces, design maps) and
:mod:`~imagespace.plotting.spatial` (Gough-Stewart platforms, singularity meshes);
:mod:`~imagespace.plotting.common` holds what they share.
"""

from .common import GUIDE_STYLE, LENGTH_UNIT, UNSOLVED_COLOUR
from .design import plot_design_map, plot_mode_count_map, plot_workspaces
from .planar import animate_path, plot_assembly_modes, plot_backlash, plot_joint_loop, plot_mechanism
from .spatial import plot_gough_stewart, plot_gough_stewart_modes, plot_singularity_mesh
from .surfaces import plot_conic_section, plot_constraint_quadrics, plot_path_singularity, plot_singularity_surface

__all__ = ["plot_mechanism", "plot_assembly_modes", "plot_singularity_surface", "plot_constraint_quadrics",
           "plot_conic_section", "plot_path_singularity", "plot_joint_loop", "animate_path", "plot_backlash",
           "plot_mode_count_map", "plot_workspaces", "plot_design_map", "plot_gough_stewart",
           "plot_gough_stewart_modes", "plot_singularity_mesh", "LENGTH_UNIT", "GUIDE_STYLE", "UNSOLVED_COLOUR"]
