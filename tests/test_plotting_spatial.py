"""Spatial figures (Agg backend): the Gough-Stewart drawing shows its anchors and legs where the
geometry puts them, mode panels carry the aspect of det J computed here, meshes are drawn."""

from types import SimpleNamespace

import matplotlib.pyplot as plt
import numpy as np
import pytest
import trimesh

import imagespace as isp
from imagespace.exceptions import InputError
from imagespace.plotting import plot_gough_stewart, plot_gough_stewart_modes, plot_singularity_mesh
from imagespace.spatial.gough_stewart import GoughStewart
from imagespace.spatial.study import study_point


def design(rng):
    return GoughStewart(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)))


def landed(gs, q, t):
    """Platform anchors in the base frame, from the quaternion directly (``q b q~ / |q|^2``)."""
    q = np.asarray(q, dtype=float) / np.linalg.norm(q)
    w, v = q[0], q[1:]
    B = gs.platform_points
    RB = (w * w - v @ v) * B + 2 * np.outer(B @ v, v) + 2 * w * np.cross(v, B)
    return RB + t


@pytest.mark.slow
def test_platform_drawing_puts_legs_between_the_anchors(rng, tmp_path):
    gs = design(rng)
    q, t = rng.normal(size=4), rng.normal(size=3) + [0, 0, 2]
    fig = plot_gough_stewart(gs, study_point(q, t))
    ax = fig.axes[0]
    assert ax.name == "3d" and len(ax.lines) == 8          # base and platform outlines, six legs
    X = landed(gs, q, t)
    legs = [line for line in ax.lines if line.get_label().startswith("leg")]
    assert len(legs) == 6
    for i, line in enumerate(legs):
        x, y, z = line.get_data_3d()
        assert np.allclose([x[0], y[0], z[0]], gs.base_points[i])
        assert np.allclose([x[1], y[1], z[1]], X[i])
        L = float(line.get_label().split("L = ")[1])
        assert np.isclose(L, np.linalg.norm(X[i] - gs.base_points[i]), rtol=1e-3)
    polys = [c for c in ax.collections if type(c).__name__ == "Poly3DCollection"]
    assert len(polys) == 2
    fig.savefig(tmp_path / "pose.png")
    assert (tmp_path / "pose.png").stat().st_size > 0
    plt.close(fig)


def test_platform_drawing_into_given_axes_and_refuses_2d_axes(rng):
    gs = design(rng)
    fig = plt.figure()
    ax = fig.add_subplot(projection="3d")
    assert plot_gough_stewart(gs, [1, 0, 0, 0, 0, 0, 0, 1.0], ax=ax, legend=False) is fig
    plt.close(fig)
    fig, ax = plt.subplots()
    with pytest.raises(InputError, match="3D Axes"):
        plot_gough_stewart(gs, [1, 0, 0, 0, 0, 0, 0, 1.0], ax=ax)
    with pytest.raises(InputError, match="shape"):
        plot_gough_stewart(gs, [1, 0, 0, 0])
    plt.close(fig)


@pytest.mark.slow
def test_mode_panels_are_titled_with_the_aspect_of_det_j(rng, tmp_path):
    gs = design(rng)
    Q, T = rng.normal(size=(5, 4)), rng.normal(size=(5, 3))
    S = study_point(Q, T)
    expected = []
    for q, t in zip(Q, T):
        s_vec = landed(gs, q, t) - gs.base_points
        J = np.hstack([s_vec, np.cross(gs.base_points, s_vec)])
        expected.append(int(np.sign(np.linalg.det(J))))
    fig = plot_gough_stewart_modes(gs, S, ncols=3)
    panels = [a for a in fig.axes if a.get_visible()]
    assert len(panels) == 5
    assert [a.get_title() for a in panels] == [f"mode {k + 1} (aspect {e:+d})" for k, e in enumerate(expected)]
    # every panel names its axes; the unit is in the figure's title (issue [16])
    for a in panels:
        assert (a.get_xlabel(), a.get_ylabel(), a.get_zlabel()) == ("x", "y", "z")
        assert a.xaxis.label.get_visible() and a.zaxis.label.get_visible()
    assert "length units" in fig._suptitle.get_text()
    fig.savefig(tmp_path / "modes.png")
    plt.close(fig)
    # a direct-kinematics-like result: its Study points and its aspects are used as given
    result = SimpleNamespace(study_points=S[:2], aspects=np.array([-1, 1], dtype=np.int8))
    fig = plot_gough_stewart_modes(gs, result)
    assert [a.get_title() for a in fig.axes] == ["mode 1 (aspect -1)", "mode 2 (aspect +1)"]
    plt.close(fig)
    with pytest.raises(InputError, match="no assembly mode"):
        plot_gough_stewart_modes(gs, np.zeros((0, 8)))
    with pytest.raises(InputError, match="aspects"):
        plot_gough_stewart_modes(gs, S, aspects=[1])


@pytest.mark.slow
def test_singularity_mesh_figure(rng, tmp_path):
    from imagespace.spatial_surfaces import mesh_constant_orientation_singularity

    gs = design(rng)
    box = [(-2.0, 2.0), (-2.0, 2.0), (-1.0, 3.0)]
    mesh = mesh_constant_orientation_singularity(gs, np.eye(3), box, resolution=16)
    fig = plot_singularity_mesh(mesh, points=[[0, 0, 1], [0.5, 0, 1]], aspects=[1, -1])
    ax = fig.axes[0]
    fig.canvas.draw()                   # 3D collections project their paths when drawn
    polys = [c for c in ax.collections if type(c).__name__ == "Poly3DCollection"]
    assert len(polys) == 1 and len(polys[0].get_paths()) == len(mesh.faces)
    assert len([c for c in ax.collections if type(c).__name__ == "Path3DCollection"]) == 2
    assert np.allclose(ax.get_zlim(), box[2])
    fig.savefig(tmp_path / "mesh.png")
    plt.close(fig)
    fig = plot_singularity_mesh(trimesh.creation.icosphere(subdivisions=1))
    plt.close(fig)
    with pytest.raises(TypeError, match="trimesh"):
        plot_singularity_mesh(mesh.vertices)
    with pytest.raises(InputError, match="aspects"):
        plot_singularity_mesh(mesh, points=[[0, 0, 1]], aspects=[1, 1])
    plt.close("all")


def test_the_figures_are_reachable_from_the_package():
    assert isp.plotting.plot_gough_stewart is plot_gough_stewart
    assert {"plot_gough_stewart", "plot_gough_stewart_modes", "plot_singularity_mesh"} <= set(isp.plotting.__all__)
