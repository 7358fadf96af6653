"""The API's small frictions of issue [16], each as a user met it (every test failed before the fix)."""

import ast
import io
import json
import re
import tempfile
import warnings
from pathlib import Path

import numpy as np
import pytest

import imagespace as isp
from imagespace.cli import main

ROOT = Path(__file__).resolve().parents[1]


def _rrr_design():
    return isp.PlanarParallel([isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3, 2), actuated=0),
                               isp.RPR(base=(6, 0), platform=(1, 0)), isp.RPR(base=(2, 5), platform=(0, 1))])


def test_mesh_surface_has_the_command_lines_default_box():
    m = isp.examples.stigger_husty()
    mesh = isp.mesh_surface(m.singularity_surface(), resolution=12)
    box = np.array(mesh.metadata["imagespace"]["box"])
    out = io.StringIO()
    with tempfile.TemporaryDirectory() as tmp:
        assert main(["mesh", "--resolution", "12", "-o", str(Path(tmp) / "s.ply")], stream=out) == 0
    printed = json.loads(re.search(r"box (\[\[.*?\]\])", out.getvalue()).group(1))
    assert np.allclose(box, printed, rtol=1e-5)
    # the scale is the design's: 0.8 x its largest anchor coordinate or example leg length (here q2)
    L = max(abs(float(v)) for v in m.q_example[:2])
    assert np.allclose(box, [[-0.8 * L, 0.8 * L]] * 2 + [[-3, 3]])
    V = np.asarray(mesh.vertices)
    assert len(V) and np.all((V >= box[:, 0] - 1e-9) & (V <= box[:, 1] + 1e-9))


def test_jacobians_of_one_pose_is_one_matrix():
    m = isp.examples.general_3rpr()
    pose = np.array([0.5, 1.0, 0.2])
    one = isp.jacobians(m, pose)
    batch = isp.jacobians(m, np.array([pose, pose + 0.1]))
    assert one.Jx.shape == one.Jq.shape == one.J.shape == (3, 3) and batch.Jx.shape == (2, 3, 3)
    assert np.allclose(one.Jx, batch.Jx[0]) and one.kind == batch.kind[0] == "regular"
    assert np.isclose(one.det_Jx, np.linalg.det(one.Jx))             # a number, the matrix's determinant
    # J = Jq^-1 Jx, and the wrench of one tau is one vector: F = J^T tau
    assert np.allclose(one.Jq @ one.J, one.Jx)
    tau = np.array([1.0, -2.0, 0.5])
    assert np.allclose(one.wrench(tau), one.J.T @ tau) and one.homogeneous(2.0).shape == (3, 3)


def test_plan_mode_change_takes_mode_indices():
    m = isp.examples.stigger_husty()
    q = m.q_example_float
    modes = m.direct_kinematics(q)
    by_index = isp.plan_mode_change(m, q, 0, 3)
    by_mode = isp.plan_mode_change(m, q, modes[0], modes[3])
    assert by_index.found and by_mode.found
    assert np.allclose(by_index.poses[0], modes[0].pose) and np.allclose(by_index.poses[-1], modes[3].pose)
    assert not isp.plan_mode_change(m, q, 0, 1).found          # opposite aspects, as with the modes
    with pytest.raises(isp.InputError, match=r"mode_b must be in 0\.\.5.*direct_kinematics\(q\)"):
        isp.plan_mode_change(m, q, 0, 6)
    with pytest.raises(TypeError):
        isp.plan_mode_change(m, q, 0, True)


def test_segment_of_poses_points_to_pose_segment_and_image_point():
    with pytest.raises(isp.InputError, match=r"pose_segment.*image_point") as info:
        isp.segment([1.0, 2.0, 0.1], [2.0, 1.0, 0.3])
    assert "looks like a pose" in str(info.value)
    with pytest.raises(isp.InputError, match="pose_segment"):
        isp.segment(np.zeros((2, 4)), [1.0, 0, 0, 0])
    path = isp.pose_segment([1.0, 2.0, 0.1], [2.0, 1.0, 0.3])          # what the message offers works
    assert len(path) >= 1


def test_actuated_angles_outside_two_pi_warn_about_degrees():
    m = _rrr_design()
    with pytest.warns(isp.AngleUnitWarning, match=r"radians.*numpy\.radians\(90\) = 1\.5708"):
        m.direct_kinematics([90.0, 4.0, 4.0])
    with pytest.warns(isp.AngleUnitWarning, match=r"Q\[0\] = 90 \(1 row\)"):
        m.direct_kinematics_batch(np.array([[90.0, 4.0, 4.0], [0.3, 4.0, 4.0]]))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m.direct_kinematics([0.3, 4.0, 4.0])                 # radians: silent
        m.direct_kinematics([-6.0, 4.0, 4.0])
        isp.examples.stigger_husty().direct_kinematics([10.0, 15.0, 13.25])   # lengths: any size


def test_direct_kinematics_shows_a_table_in_jupyter():
    m = isp.examples.general_3rpr()
    modes = m.direct_kinematics(m.q_example)
    assert isinstance(modes, list) and len(modes) == 6
    page = modes._repr_html_()
    assert page.count("<tr>") == 1 + len(modes)                 # a header and one row a mode
    for mode in modes:                                          # each pose in the table, as printed
        assert f"{mode.pose[0]:.6g}"[:5] in page
    assert "6 real assembly modes" in page and "certify=True" in page
    assert modes == list(modes) and isinstance(modes[1:], list)


def test_cli_prints_rounded_boxes_and_the_surface_name_once(tmp_path):
    out = io.StringIO()
    assert main(["mesh", "--resolution", "8", "-o", str(tmp_path / "s.ply")], stream=out) == 0
    text = out.getvalue()
    name = isp.examples.stigger_husty().name
    assert text.count(name) == 1
    box = re.search(r"box (\[\[.*?\]\])", text).group(1)
    assert all(len(re.sub(r"[-.]", "", v).lstrip("0")) <= 6 for v in re.findall(r"[-0-9.]+", box))


_ARTISTS = {"legend", "set_xlabel", "set_ylabel", "set_zlabel", "set_title", "text", "annotate", "colorbar",
            "suptitle", "set_xlim", "set_ylim", "plot", "scatter", "imshow"}


@pytest.mark.parametrize("notebook", sorted((ROOT / "notebooks").glob("*.ipynb")), ids=lambda p: p.stem)
def test_notebook_cells_do_not_end_in_a_stray_artist(notebook):
    """A cell whose last line is ``ax.legend(...)`` shows ``<matplotlib.legend.Legend at 0x...>``."""
    for cell in json.loads(notebook.read_text())["cells"]:
        if cell["cell_type"] != "code":
            continue
        src = "".join(cell["source"]).rstrip()
        if not src or src.endswith(";"):
            continue
        try:
            body = ast.parse(src).body
        except SyntaxError:                     # IPython magics; none end a cell here
            continue
        last = body[-1] if body else None
        if isinstance(last, ast.Expr) and isinstance(last.value, ast.Call):
            f = last.value.func
            name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
            assert name not in _ARTISTS, f"{notebook.name}: a cell ends in {name}(...) and shows its return value"
