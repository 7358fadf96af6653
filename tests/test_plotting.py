"""Figures return a Figure, draw into a given Axes, and show what they claim (modes by aspect)."""

import matplotlib.pyplot as plt
import numpy as np
import pytest

import imagespace as isp
from imagespace.plotting import plot_conic_section, plot_constraint_quadrics, plot_singularity_surface

BOX = [(-12, 12), (-12, 12), (-3, 3)]


def test_surface_figure_colours_the_six_modes_by_aspect():
    m = isp.examples.stigger_husty()
    fig = plt.figure()
    ax = fig.add_subplot(projection="3d")
    out = plot_singularity_surface(m.singularity_surface(), BOX, resolution=16, q=m.q_example, ax=ax)
    assert out is fig
    sizes = sorted(len(c.get_offsets()) for c in ax.collections if type(c).__name__ == "Path3DCollection")
    assert sizes == [3, 3]
    plt.close(fig)


def test_quadrics_and_conic_figures():
    m = isp.examples.stigger_husty()
    fig = plot_constraint_quadrics(m, m.q_example, BOX, resolution=16)
    assert len(fig.axes) == 1
    plt.close(fig)
    mode = m.direct_kinematics(m.q_example)[2]
    fig, ax = plt.subplots()
    assert plot_conic_section(m.singularity_surface(), mode.pose[2], (-15, 15), (-15, 15),
                              q=m.q_example, ax=ax) is fig
    marked = [line for line in ax.lines if len(line.get_xdata()) == 1]
    assert len(marked) == 1 and np.isclose(marked[0].get_xdata()[0], mode.pose[0])
    plt.close(fig)


def test_a_3d_figure_needs_3d_axes():
    m = isp.examples.stigger_husty()
    fig, ax = plt.subplots()
    with pytest.raises(isp.InputError, match="3D Axes"):
        plot_singularity_surface(m.singularity_surface(), BOX, resolution=8, ax=ax)
    plt.close(fig)


def test_conic_figure_reads_plot_orientation():
    """A mode 1e-3 rad off the section's orientation is not marked with the default
    ``plot_orientation`` (1e-6 rad), and is with a loosened one."""
    base = isp.examples.stigger_husty()
    mode = base.direct_kinematics(base.q_example)[2]
    phi = mode.pose[2] + 1e-3

    def marked(m):
        fig, ax = plt.subplots()
        plot_conic_section(m.singularity_surface(), phi, (-15, 15), (-15, 15), q=base.q_example, ax=ax)
        n = sum(1 for line in ax.lines if line.get_marker() == "o" and len(line.get_xdata()))
        plt.close(fig)
        return n

    assert marked(base) == 0
    loose = isp.PlanarParallel(base.legs, tolerances=isp.Tolerances(plot_orientation=1e-2))
    assert marked(loose) >= 1
