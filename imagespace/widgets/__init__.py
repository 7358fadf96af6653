"""Interactive explorers for Jupyter: drag the joint values, watch the assembly modes move.

:func:`explore` opens the explorer that fits the design: the planar one
(:class:`~imagespace.widgets.planar.Explorer`: pose view, image space with the singularity surface,
section view, certified mode changes played in the browser) or the Gough-Stewart one
(:class:`~imagespace.widgets.spatial.SpatialExplorer`: six leg-length sliders, the certified and the
fast count, the platform in every real mode, a constant-orientation singularity section).

Modules: :mod:`~imagespace.widgets.inputs` (exact values typed as text, slider ranges),
:mod:`~imagespace.widgets.tracking` (stable mode numbers), :mod:`~imagespace.widgets.view` (the
plot panels in the browser), :mod:`~imagespace.widgets.planar`, :mod:`~imagespace.widgets.spatial`.
Needs the ``imagespace[jupyter]`` extra.
"""

from __future__ import annotations

from .inputs import joint_ranges, parse_joint_value
from .planar import (DRAG_RESOLUTION, FRAME_RATE, REST_DELAY, REST_RESOLUTION, SECTION_GRID, SLIDER_STEPS,
                     Explorer)

__all__ = ["explore", "Explorer", "SpatialExplorer", "joint_ranges", "parse_joint_value", "REST_DELAY",
           "DRAG_RESOLUTION", "REST_RESOLUTION", "SECTION_GRID", "SLIDER_STEPS", "FRAME_RATE"]


def explore(manipulator, q=None, box=None, resolution=REST_RESOLUTION, atlas=None):
    """Open the interactive explorer on a manipulator.

    Parameters
    ----------
    manipulator : PlanarParallel or GoughStewart
    q : array_like, optional
        Starting joint values (three for a planar design, six leg lengths for a Gough-Stewart
        platform); default the design's example (planar ``q_example``; for a platform, the leg
        lengths of a pose above the base).
    box : (3, 2) float, optional
        The 3D view's box: for a planar design the image-space chart ``(x2/x0, x3/x0, x1/x0)``
        (default around the starting modes, ``|x1/x0| <= 3``); for a platform the box of the
        singularity section around the chosen mode.
    resolution : int
        Grid points per axis of the planar surface mesh at rest (planar designs).
    atlas : JointAtlas or bool, optional
        Planar designs: add the joint-space atlas panel (the count-change surface, cusp curves and
        joint box in 3D, a marker at ``q`` that follows the sliders with the certified count at
        ``q``, the atlas region in the status line). A :class:`~imagespace.atlas.JointAtlas` of
        the design (:func:`imagespace.atlas.joint_atlas`), or True to compute one in the background
        (:func:`~imagespace.widgets.planar_atlas.default_atlas_box` around ``q``,
        :data:`~imagespace.widgets.planar_atlas.ATLAS_RESOLUTION` nodes per axis). None or False
        (default): no atlas panel, and no cost.

    Returns
    -------
    Explorer or SpatialExplorer
        An ``ipywidgets.VBox``; display it (last expression of a cell).

    Raises
    ------
    InputError
        No ``q`` given for a design without an example; a bad ``q``, ``box`` or ``resolution``; an
        ``atlas`` of another design, or one asked for a Gough-Stewart platform.
    TypeError
        A design that is neither planar nor a Gough-Stewart platform; ``atlas`` neither a
        JointAtlas nor True/False/None.

    Examples
    --------
    >>> import imagespace as isp
    >>> ex = isp.widgets.explore(isp.examples.stigger_husty())
    >>> ex.status["count"], ex.status["certified"]
    (6, True)
    """
    import sys

    from ..exceptions import InputError

    # a GoughStewart exists only if its module is loaded: planar designs do not import the spatial side
    gough_stewart = sys.modules.get("imagespace.spatial.gough_stewart")
    if gough_stewart is not None and isinstance(manipulator, gough_stewart.GoughStewart):
        from .spatial import SpatialExplorer

        if atlas is not None and atlas is not False:
            raise InputError(f"atlas is for planar designs (the joint-space atlas of three actuated "
                             f"joints); a Gough-Stewart platform has six legs, got atlas={atlas!r:.60}")

        return SpatialExplorer(manipulator, L=q, box=box)
    from .planar import explore_planar

    return explore_planar(manipulator, q=q, box=box, resolution=resolution, atlas=atlas)


def __getattr__(name):
    if name == "SpatialExplorer":
        from .spatial import SpatialExplorer

        return SpatialExplorer
    raise AttributeError(f"module 'imagespace.widgets' has no attribute {name!r}")
