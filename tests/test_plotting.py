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


# --- issue [11]: figures a reviewer would accept -------------------------------------------------

import re  # noqa: E402

from matplotlib.lines import Line2D  # noqa: E402

from imagespace import plotting  # noqa: E402
from imagespace.drawing import mechanism_lines  # noqa: E402
from imagespace.paths.check import pose_segment  # noqa: E402
from imagespace.singular.cusps import ModeCountMap  # noqa: E402

UNIT = re.compile(r"\S.*\[[^\]]+\]")


def _labels(ax):
    out = [ax.get_xlabel(), ax.get_ylabel()]
    if getattr(ax, "name", "") == "3d":
        out.append(ax.get_zlabel())
    return out


def _has_legend(fig):
    return bool(fig.legends) or any(a.get_legend() is not None for a in fig.axes)


def _figures():
    """One small instance of every figure function (name -> Figure)."""
    from imagespace.design.sweep import sweep
    from imagespace.design.workspace import dexterous_workspace, reachable_workspace
    from imagespace.paths.backlash import backlash
    from imagespace.singular.cusps import mode_count_map

    m = isp.examples.stigger_husty()
    modes = m.direct_kinematics(m.q_example)
    S = m.singularity_surface()
    g = isp.examples.general_3rpr()
    c = isp.examples.choi_3ppr()
    lim = [[-np.sqrt(3), np.sqrt(3)]] * 3
    t = sweep(lambda a, b: {"sum": float(a + b)}, {"a": [1.0, 2.0, 3.0], "b": [0.0, 1.0]}, processes=0)
    anim = plotting.animate_path(m, [modes[0].pose, modes[0].pose + [0.2, 0.1, 0.05]])
    assert "<script" in anim.to_jshtml()       # renders every frame (and keeps matplotlib from warning)
    yield "mechanism", plotting.plot_mechanism(m, modes[0].pose, m.q_example_float)
    yield "assembly_modes", plotting.plot_assembly_modes(m, m.q_example)
    yield "surface", plotting.plot_singularity_surface(S, BOX, resolution=8, q=m.q_example)
    yield "surface_pose", plotting.plot_singularity_surface(S, [(-15, 15), (-15, 15), (-3, 3)], chart="pose",
                                                            resolution=8, q=m.q_example)
    yield "quadrics", plotting.plot_constraint_quadrics(m, m.q_example, BOX, resolution=8)
    yield "conic", plotting.plot_conic_section(S, modes[2].pose[2], (-15, 15), (-15, 15), q=m.q_example, n=60)
    yield "path", plotting.plot_path_singularity(m, pose_segment([0, 0, 0.2], [3, 1, 0.5]), per_piece=20)
    yield "joint_loop", plotting.plot_joint_loop([[1.0, 2, 3], [1.5, 2, 3], [1.0, 2.5, 3], [1.0, 2, 3]],
                                                 manipulator=g)
    yield "animation", anim._fig
    yield "backlash", plotting.plot_backlash(m, backlash(m, m.q_example_float, 2, delta=0.5, samples=2000), n=40)
    yield "mode_count", plotting.plot_mode_count_map(mode_count_map(g, 2, 10.0, [(6, 16), (1, 9)], 12),
                                                     manipulator=g)
    yield "workspaces", plotting.plot_workspaces([reachable_workspace(c, (-1, 1), lim),
                                                  dexterous_workspace(c, (-1, 1), lim)])
    yield "design_map", plotting.plot_design_map(t, "sum", "a", "b", best=[0])


@pytest.mark.slow
def test_every_figure_has_unit_labels_and_a_legend():
    seen = []
    for name, fig in _figures():
        seen.append(name)
        main = [a for a in fig.axes if a.get_visible() and a.get_label() != "<colorbar>"]
        for k, ax in enumerate(main):
            labels = [ax.get_ylabel()] if (name, k) == ("path", 1) else _labels(ax)   # twin: y only
            assert labels and all(UNIT.match(lab) for lab in labels), (name, _labels(ax))
        bars = [a for a in fig.axes if a.get_label() == "<colorbar>"]
        assert all(UNIT.match(a.get_ylabel()) or "modes" in a.get_ylabel() for a in bars), name
        if name != "mode_count":                  # only the map: one kind of element, no legend
            assert _has_legend(fig), name
        plt.close(fig)
    assert len(seen) == 13


@pytest.mark.slow
def test_assembly_modes_are_numbered_wherever_drawn():
    m = isp.examples.stigger_husty()
    fig = plotting.plot_assembly_modes(m, m.q_example)
    titles = [a.get_title() for a in fig.axes if a.get_visible()]
    assert [t.split(" (")[0] for t in titles] == [f"mode {k}" for k in range(1, 7)]
    assert all("deg" in t and "rad" not in t for t in titles)
    plt.close(fig)
    fig, ax = plt.subplots()
    plotting.plot_assembly_modes(m, m.q_example, ax=ax)
    assert sorted(t.get_text() for t in ax.texts) == [f"mode {k}" for k in range(1, 7)]
    plt.close(fig)
    fig = plotting.plot_singularity_surface(m.singularity_surface(), BOX, resolution=8, q=m.q_example)
    assert sorted(t.get_text().strip() for t in fig.axes[0].texts) == [f"mode {k}" for k in range(1, 7)]
    plt.close(fig)
    modes = m.direct_kinematics(m.q_example)
    fig = plotting.plot_conic_section(m.singularity_surface(), modes[2].pose[2], (-15, 15), (-15, 15),
                                      modes=modes, n=40)
    assert [t.get_text() for t in fig.axes[0].texts] == ["mode 3"]
    plt.close(fig)


def test_prismatic_guides_are_dashed_lines_from_mechanism_lines():
    for m, pose in [(isp.examples.choi_3ppr(), [0.1, 0.05, 0.2]),
                    (isp.examples.stigger_husty(), None)]:
        if pose is None:
            pose = m.direct_kinematics(m.q_example)[0].pose
        n = len(mechanism_lines(m, pose).guides)
        assert n > 0
        fig = plotting.plot_mechanism(m, pose)
        dashed = [ln for ln in fig.axes[0].get_lines() if isinstance(ln, Line2D) and ln.get_linestyle() == "--"]
        assert len(dashed) == n
        for ln, seg in zip(dashed, mechanism_lines(m, pose).guides):
            assert np.allclose(np.column_stack([ln.get_xdata(), ln.get_ydata()]), seg)
        plt.close(fig)


def test_assembly_mode_grid_draws_the_guides_of_each_mode():
    m = isp.examples.stigger_husty()
    modes = m.direct_kinematics(m.q_example)
    fig = plotting.plot_assembly_modes(m, m.q_example, modes=modes[:2])
    for ax, mode in zip(fig.axes, modes[:2]):
        dashed = [ln for ln in ax.get_lines() if ln.get_linestyle() == "--"]
        assert len(dashed) == len(mechanism_lines(m, mode.pose, m.q_example_float).guides)
    plt.close(fig)


def test_mode_count_map_is_discrete_with_integer_ticks():
    counts = np.array([[0, 2], [2, 4], [-1, 6]])
    cm = ModeCountMap(fixed=2, value=10.0, free=(0, 1), axes=(np.arange(3.0), np.arange(2.0)), counts=counts)
    fig = plotting.plot_mode_count_map(cm)
    ax = fig.axes[0]
    mesh = ax.collections[0]
    values = np.unique(counts)
    assert mesh.cmap.N == len(values)
    ticks = np.asarray(mesh.colorbar.get_ticks())
    assert np.array_equal(ticks, values) and np.all(ticks == np.round(ticks))
    assert len({tuple(mesh.cmap(mesh.norm(v))) for v in values}) == len(values)     # one colour per count
    assert ax.get_xlabel() == "q1 [length units or rad]" and ax.get_legend() is None
    plt.close(fig)
    from types import SimpleNamespace

    cusp = SimpleNamespace(q=np.array([1.0, 0.5, 10.0]))
    loops = [SimpleNamespace(q=np.array([[0.5, 0.2, 10], [1.5, 0.8, 10], [0.5, 0.2, 10]]), changed=c)
             for c in (True, False)]
    fig = plotting.plot_mode_count_map(cm, [cusp], loops, manipulator=isp.examples.general_3rpr())
    texts = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert texts == ["cusps", "loop that changes the mode", "loop, mode unchanged"]
    assert fig.axes[0].get_title() == "section q3 = 10 length units"
    plt.close(fig)


@pytest.mark.slow
def test_path_singularity_title_names_the_modes():
    m = isp.examples.stigger_husty()
    path = pose_segment([0, 0, 0.2], [3, 1, 0.5])
    fig = plotting.plot_path_singularity(m, path, per_piece=10, modes=(1, 4))
    assert "mode 1 -> mode 4" in fig.axes[0].get_title()
    plt.close(fig)
    fig = plotting.plot_path_singularity(m, path, per_piece=10)
    assert "start -> end" in fig.axes[0].get_title()
    plt.close(fig)
    fig = plotting.plot_path_singularity(m, path, per_piece=10, modes=("A", "B"))
    assert "A -> B" in fig.axes[0].get_title()
    plt.close(fig)
    with pytest.raises(isp.InputError, match="modes must be a pair"):
        plotting.plot_path_singularity(m, path, per_piece=10, modes=(1,))
