"""The ``imagespace`` command line (issue 14): filesystem errors as one-line messages with exit
status 2, negative numbers in scientific notation, refused NaN and ignored joint options, and
atomic PNG writes for ``demo`` and ``plot``."""

import errno
import io
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")

import matplotlib.figure  # noqa: E402
import pytest  # noqa: E402

import imagespace.singular.meshing  # noqa: E402
import imagespace.plotting  # noqa: E402
from imagespace.cli import main  # noqa: E402

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def _run(argv, capsys):
    out = io.StringIO()
    rc = main(argv, stream=out)
    return rc, out.getvalue(), capsys.readouterr().err


def _assert_one_line_error(rc, err, *needles):
    assert rc == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    for needle in needles:
        assert str(needle) in lines[0], (needle, err)


@pytest.fixture
def a_file(tmp_path):
    f = tmp_path / "file.txt"
    f.write_text("not a folder")
    return f


# -- 1. filesystem errors -------------------------------------------------------------------

@pytest.mark.parametrize("command", [["mesh", "--resolution", "8"], ["plot", "modes"]])
def test_cli_output_under_a_file_is_a_one_line_error(command, a_file, capsys):
    target = a_file / ("out.ply" if command[0] == "mesh" else "out.png")
    rc, _, err = _run(command + ["-o", str(target)], capsys)
    _assert_one_line_error(rc, err, target, "is a file")


@pytest.mark.parametrize("command", [["mesh", "--resolution", "8"], ["plot", "modes"]])
def test_cli_output_in_a_missing_folder_is_a_one_line_error(command, tmp_path, capsys):
    target = tmp_path / "missing" / ("out.ply" if command[0] == "mesh" else "out.png")
    rc, _, err = _run(command + ["-o", str(target)], capsys)
    _assert_one_line_error(rc, err, target, "does not exist")
    assert not target.parent.exists()


@pytest.mark.parametrize("command", [["mesh", "--resolution", "8"], ["plot", "modes"]])
def test_cli_existing_folder_as_output_is_a_one_line_error(command, tmp_path, capsys):
    target = tmp_path / ("d.ply" if command[0] == "mesh" else "d.png")
    target.mkdir()
    rc, _, err = _run(command + ["-o", str(target)], capsys)
    _assert_one_line_error(rc, err, target, "folder")
    assert target.is_dir() and not any(target.iterdir())


def test_cli_demo_onto_a_file_is_a_one_line_error(a_file, capsys):
    rc, _, err = _run(["demo", "-o", str(a_file)], capsys)
    _assert_one_line_error(rc, err, a_file, "is a file")
    assert a_file.read_text() == "not a folder"
    rc, _, err = _run(["demo", "-o", str(a_file / "sub")], capsys)
    _assert_one_line_error(rc, err, a_file / "sub", "is a file")


def test_cli_mesh_write_failure_names_the_path(tmp_path, capsys, monkeypatch):
    """An unwritable folder (permission bits do not stop root, so the export is made to fail the
    way it would): exit 2, the path and the reason on one line."""
    def refuse(mesh, path, *a, **k):
        raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), str(tmp_path / ".tmpXYZ"))

    monkeypatch.setattr(imagespace.singular.meshing, "export_mesh", refuse)
    target = tmp_path / "s.ply"
    rc, _, err = _run(["mesh", "--resolution", "8", "-o", str(target)], capsys)
    _assert_one_line_error(rc, err, target, "Permission denied")


@pytest.mark.slow
@pytest.mark.parametrize("command", [["demo"], ["plot", "modes"]])
def test_cli_png_write_failure_names_the_path(command, tmp_path, capsys, monkeypatch):
    import tempfile

    def refuse(*a, **k):
        raise PermissionError(errno.EACCES, os.strerror(errno.EACCES))

    monkeypatch.setattr(tempfile, "mkstemp", refuse)
    target = tmp_path / "assembly_modes.png" if command == ["demo"] else tmp_path / "f.png"
    rc, _, err = _run(command + ["-o", str(tmp_path if command == ["demo"] else target)], capsys)
    _assert_one_line_error(rc, err, target, "Permission denied")
    assert not target.exists()


@pytest.mark.slow
def test_cli_filesystem_error_in_a_real_process_has_no_traceback(a_file):
    target = a_file / "out.ply"
    r = subprocess.run([sys.executable, "-m", "imagespace.cli", "mesh", "--resolution", "8", "-o", str(target)],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 2, r.stderr
    assert "Traceback" not in r.stderr and len(r.stderr.strip().splitlines()) == 1
    assert str(target) in r.stderr


# -- 2. negative numbers in scientific notation -------------------------------------------------

def test_cli_box_accepts_negative_scientific_notation(tmp_path, capsys):
    target = tmp_path / "s.ply"
    rc, out, err = _run(["mesh", "--resolution", "8", "--box", "-1.2e1", "1.2E+1", "-12e0", "12", "-3e0", "-.5e-1",
                         "-o", str(target)], capsys)
    assert rc == 0, err
    assert "box [[-12, 12], [-12, 12], [-3, -0.05]]" in out
    assert target.exists()


@pytest.mark.slow
def test_cli_phi_accepts_negative_scientific_notation(tmp_path, capsys, monkeypatch):
    seen = {}
    real = imagespace.plotting.plot_conic_section

    def spy(surface, phi, *a, **k):
        seen["phi"] = phi
        return real(surface, phi, *a, **k)

    monkeypatch.setattr(imagespace.plotting, "plot_conic_section", spy)
    target = tmp_path / "c.png"
    rc, _, err = _run(["plot", "conic", "--phi", "-1e-1", "-o", str(target)], capsys)
    assert rc == 0, err
    assert seen["phi"] == -0.1
    assert target.read_bytes().startswith(PNG_MAGIC)


def test_cli_non_numbers_with_a_dash_are_still_options(capsys):
    """Widening the number rule must not turn what is not a number into a value."""
    with pytest.raises(SystemExit) as exc:
        main(["plot", "conic", "--phi", "-e1"])
    assert exc.value.code == 2
    capsys.readouterr()


# -- 3. refused input -----------------------------------------------------------------------

@pytest.mark.parametrize("command", [["mesh", "--resolution", "8", "-o", "{}/s.ply"],
                                     ["plot", "modes", "-o", "{}/m.png"]])
@pytest.mark.parametrize("q", [["nan", "nan", "nan"], ["1", "inf", "2"], ["-nan", "1", "2"]])
def test_cli_non_finite_q_is_refused(command, q, tmp_path, capsys):
    argv = [a.format(tmp_path) for a in command] + ["--q", *q]
    rc, _, err = _run(argv, capsys)
    _assert_one_line_error(rc, err, "--q", "finite")
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize("argv", [["mesh", "--box", "nan", "1", "-1", "1", "-1", "1"],
                                  ["plot", "conic", "--phi", "nan"]])
def test_cli_non_finite_box_and_phi_are_refused(argv, tmp_path, capsys):
    rc, _, err = _run(argv + ["-o", str(tmp_path / ("s.ply" if argv[0] == "mesh" else "c.png"))], capsys)
    _assert_one_line_error(rc, err, "--box" if argv[0] == "mesh" else "--phi", "finite")


@pytest.mark.slow
@pytest.mark.parametrize("option", [["--q", "10", "11", "12"], ["--working-modes", "0", "1", "0"]])
def test_cli_mesh_refuses_joint_options_for_a_joint_free_surface(option, tmp_path, capsys):
    target = tmp_path / "s.ply"
    rc, _, err = _run(["mesh", "--example", "general-3rpr", "--resolution", "8", *option, "-o", str(target)], capsys)
    _assert_one_line_error(rc, err, option[0], "does not depend on the joint values")
    assert not target.exists()


@pytest.mark.parametrize("figure", ["surface", "conic", "modes", "quadrics"])
def test_cli_plot_refuses_working_modes_it_would_ignore(figure, tmp_path, capsys):
    target = tmp_path / "f.png"
    rc, _, err = _run(["plot", figure, "--example", "general-3rpr", "--working-modes", "0", "0", "0",
                       "-o", str(target)], capsys)
    _assert_one_line_error(rc, err, "--working-modes")
    if figure in ("surface", "conic"):
        assert "does not depend on the joint values" in err
    assert not target.exists()


@pytest.mark.slow
def test_cli_plot_q_still_places_the_drawn_modes(tmp_path, capsys):
    """In ``plot``, ``--q`` chooses the assembly modes drawn, so it is not refused."""
    target = tmp_path / "s.png"
    rc, _, err = _run(["plot", "surface", "--resolution", "12", "--q", "10", "15.2315", "13.2529",
                       "-o", str(target)], capsys)
    assert rc == 0, err
    assert target.read_bytes().startswith(PNG_MAGIC)


# -- 4. atomic PNG writes ---------------------------------------------------------------------

@pytest.fixture
def failing_savefig(monkeypatch):
    """``Figure.savefig`` writes a little, then fails with the given exception."""
    def install(exc):
        def broken(self, fname, *a, **k):
            fname.write(b"partial")
            raise exc

        monkeypatch.setattr(matplotlib.figure.Figure, "savefig", broken)
    return install


@pytest.mark.slow
@pytest.mark.parametrize("exc, rc_expected", [(OSError(errno.ENOSPC, os.strerror(errno.ENOSPC)), 2),
                                              (KeyboardInterrupt(), None)])
@pytest.mark.parametrize("command", ["demo", "plot"])
def test_cli_png_is_left_unchanged_when_saving_fails(command, exc, rc_expected, tmp_path, capsys,
                                                     failing_savefig):
    target = tmp_path / ("assembly_modes.png" if command == "demo" else "m.png")
    target.write_bytes(PNG_MAGIC + b"the old picture")
    argv = ["demo", "-o", str(tmp_path)] if command == "demo" else ["plot", "modes", "-o", str(target)]
    failing_savefig(exc)
    if rc_expected is None:
        with pytest.raises(KeyboardInterrupt):
            main(argv, stream=io.StringIO())
    else:
        rc, _, err = _run(argv, capsys)
        _assert_one_line_error(rc, err, target, "No space left")
    assert target.read_bytes() == PNG_MAGIC + b"the old picture"
    assert sorted(p.name for p in tmp_path.iterdir()) == [target.name]      # no temporary file left


@pytest.mark.slow
@pytest.mark.parametrize("command", ["demo", "plot"])
def test_cli_png_goes_through_a_temporary_file_and_os_replace(command, tmp_path, capsys, monkeypatch):
    import tempfile

    made, replaced, formats = [], [], []
    real_mkstemp, real_replace, real_savefig = tempfile.mkstemp, os.replace, matplotlib.figure.Figure.savefig

    def mkstemp(*a, **k):
        fd, name = real_mkstemp(*a, **k)
        made.append((k.get("dir"), name))
        return fd, name

    def replace(src, dst):
        replaced.append((src, dst))
        return real_replace(src, dst)

    def savefig(self, fname, *a, **k):
        formats.append((fname, k.get("format")))
        return real_savefig(self, fname, *a, **k)

    monkeypatch.setattr(tempfile, "mkstemp", mkstemp)
    monkeypatch.setattr(os, "replace", replace)
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", savefig)
    target = tmp_path / ("assembly_modes.png" if command == "demo" else "m.png")
    target.write_bytes(b"old")
    os.chmod(target, 0o640)
    argv = ["demo", "-o", str(tmp_path)] if command == "demo" else ["plot", "modes", "-o", str(target)]
    rc, out, err = _run(argv, capsys)
    assert rc == 0, err
    assert len(made) == 1 and os.path.samefile(made[0][0], tmp_path)
    assert replaced == [(made[0][1], target)]
    assert len(formats) == 1 and not isinstance(formats[0][0], (str, os.PathLike)) and formats[0][1] == "png"
    assert target.read_bytes().startswith(PNG_MAGIC)
    assert os.stat(target).st_mode & 0o777 == 0o640                         # the old file's permissions
    assert sorted(p.name for p in tmp_path.iterdir()) == [target.name]
    assert str(target) in out


@pytest.mark.slow
def test_cli_plot_without_suffix_writes_png_as_savefig_did(tmp_path, capsys):
    rc, out, err = _run(["plot", "modes", "-o", str(tmp_path / "figure")], capsys)
    assert rc == 0, err
    assert (tmp_path / "figure.png").read_bytes().startswith(PNG_MAGIC)
    assert str(tmp_path / "figure.png") in out


# -- 5. thresholds from Tolerances ------------------------------------------------------------

def _demo_x1_column(out):
    lines = out.splitlines()
    head = next(i for i, line in enumerate(lines) if line.split()[:2] == ["mode", "x1"])
    rows = []
    for line in lines[head + 2:]:
        if not line.strip():
            break
        rows.append(float(line.split()[1]))
    return rows


@pytest.mark.slow
def test_cli_demo_reads_chart_x0_from_the_tolerances(tmp_path, capsys, monkeypatch):
    """The demo prints image points in the chart x0 = 1 where |x0| exceeds ``chart_x0``; with a
    threshold above every |x0| (at most 1) the normalised points are printed as they are."""
    import imagespace as isp
    from imagespace import examples

    rc, out, err = _run(["demo", "-o", str(tmp_path / "a")], capsys)
    assert rc == 0, err
    charted = _demo_x1_column(out)
    assert len(charted) == 6 and max(abs(v) for v in charted) > 1

    original = examples.stigger_husty

    def loose():
        base = original()
        m = isp.PlanarParallel(base.legs, name=base.name, tolerances=isp.Tolerances(chart_x0=10.0))
        m.q_example = base.q_example
        return m

    monkeypatch.setattr(examples, "stigger_husty", loose)
    rc, out, err = _run(["demo", "-o", str(tmp_path / "b")], capsys)
    assert rc == 0, err
    raw = _demo_x1_column(out)
    assert len(raw) == 6 and max(abs(v) for v in raw) <= 1 and raw != charted
