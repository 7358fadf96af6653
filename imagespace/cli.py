"""The ``imagespace`` command."""

from __future__ import annotations

import argparse
import math
import os
import re
import sys
from pathlib import Path

import numpy as np
import sympy as sp

from .exceptions import InputError

__all__ = ["main", "demo", "mesh_command", "plot_command", "default_box", "EXAMPLES"]

EXAMPLES = {"stigger-husty": "stigger_husty", "general-3rpr": "general_3rpr",
            "collinear-3rpr": "collinear_3rpr", "choi-3ppr": "choi_3ppr"}


class _Parser(argparse.ArgumentParser):
    """An argument parser that reads ``-1e-3``, ``-2.5E+1``, ``-inf`` and ``-nan`` as (negative)
    numbers, not as options; argparse's own rule only knows ``-1`` and ``-0.5``."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = re.compile(
            r"^-(?:\d+\.?\d*(?:[eE][-+]?\d+)?|\.\d+(?:[eE][-+]?\d+)?|inf|infinity|nan)$", re.IGNORECASE)


class _CommandError(InputError):
    """A one-line error of the command line (exit status 2): an output path that cannot be
    written, or an option that would be ignored or is not finite."""


def _reason(exc):
    """The reason of an ``OSError`` in words, without the path."""
    return exc.strerror or str(exc) or type(exc).__name__


def _write_error(path, exc):
    """A :class:`_CommandError` naming ``path`` and why it could not be written."""
    return _CommandError(f"cannot write {os.fspath(path)}: {_reason(exc)}")


def _blocking_ancestor(path):
    """The first existing ancestor of ``path`` that is not a folder, or None."""
    for parent in Path(path).parents:
        if parent.exists():
            return None if parent.is_dir() else parent
    return None


def _check_output_file(path):
    """Refuse, before any computation, an output file that cannot be written: an existing
    folder, a path under a file, a missing or read-only folder.

    Raises
    ------
    InputError
        Naming the path and the reason.
    """
    path = Path(path)
    if path.is_dir():
        raise _CommandError(f"cannot write {path}: it is an existing folder; give a file name")
    blocker = _blocking_ancestor(path)
    if blocker is not None:
        raise _CommandError(f"cannot write {path}: {blocker} is a file, not a folder")
    parent = path.parent
    if not parent.exists():
        raise _CommandError(f"cannot write {path}: the folder {parent} does not exist")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise _CommandError(f"cannot write {path}: permission denied on the folder {parent}")


def _check_output_dir(path):
    """Refuse, before any computation, an output folder that is a file or lies under one."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise _CommandError(f"cannot write to {path}: it is a file, not a folder")
    blocker = _blocking_ancestor(path)
    if blocker is not None:
        raise _CommandError(f"cannot write to {path}: {blocker} is a file, not a folder")


def _save_figure(fig, path, dpi=110):
    """Save a matplotlib figure atomically and return the path written.

    The figure goes to a temporary file made by :func:`tempfile.mkstemp` in the target's folder
    (format from the suffix, as ``savefig`` would choose it; no suffix: ``savefig.format`` and
    that suffix appended), which is flushed, synced and renamed over the target with
    :func:`os.replace`. On any error, or an interrupt, the temporary file is removed and an
    existing file at ``path`` is left unchanged.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> from imagespace.cli import _save_figure
    >>> fig = plt.figure()
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _save_figure(fig, folder / "f.png").name, sorted(p.name for p in folder.iterdir())
    ('f.png', ['f.png'])
    >>> plt.close(fig)
    """
    import matplotlib

    path = Path(path)
    fmt = path.suffix[1:].lower()
    if not fmt:
        fmt = matplotlib.rcParams["savefig.format"]
        path = path.with_name(path.name.rstrip(".") + "." + fmt)
    from ._files import atomic_write

    try:
        atomic_write(path, lambda fh: fig.savefig(fh, format=fmt, dpi=dpi), name="-o/--output")
    except OSError as exc:
        raise _write_error(path, exc) from exc
    return path


def _table(rows, headers):
    widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(headers)]
    line = "  ".join(h.rjust(w) for h, w in zip(headers, widths))
    out = [line, "-" * len(line)]
    out += ["  ".join(c.rjust(w) for c, w in zip(r, widths)) for r in rows]
    return "\n".join(out)


def demo(out_dir="imagespace-demo", stream=None):
    """Run the seed-002 example end to end and write a picture of the six assembly modes.

    Parameters
    ----------
    out_dir : str or Path
        Folder for ``assembly_modes.png`` (created if needed).
    stream : file-like, optional
        Where to print (default ``sys.stdout``).

    Returns
    -------
    Path
        The PNG written (atomically: an existing picture is replaced whole or left unchanged).

    Raises
    ------
    InputError
        If ``out_dir`` is a file, lies under one, or the picture cannot be written; the message
        names the path and the reason.

    Examples
    --------
    >>> import io, tempfile
    >>> from imagespace.cli import demo
    >>> path = demo(tempfile.mkdtemp(), stream=io.StringIO())
    >>> path.name
    'assembly_modes.png'
    """
    import matplotlib

    matplotlib.use("Agg")
    from . import examples
    from .core.quadrics import image_symbols
    from .plotting import plot_assembly_modes

    stream = stream or sys.stdout
    _check_output_dir(out_dir)
    m = examples.stigger_husty()
    q = m.q_example
    x0 = image_symbols()[0]
    p = lambda *a: print(*a, file=stream)
    p(f"imagespace demo: {m.name}")
    p(f"joint values q = ({', '.join(str(v) for v in q)})  = {np.round(m.q_example_float, 6).tolist()}")
    p("\nConstraint quadrics in the kinematic image space (x0 = 1 as in eqs. (5)-(7)):")
    for k, e in enumerate(m.constraint_equations(q), 1):
        p(f"  H{k}: {sp.expand(e.subs(x0, 1))} = 0")
    P = m.kinematic_polynomial(q)
    p(f"\nKinematic polynomial: a binary form of degree {P.total_degree()} in (x0 : x1), x0 = 1:")
    p("  " + str(sp.N(P.as_expr().subs(x0, 1), 10)) + " = 0")
    modes = m.direct_kinematics(q, certify=True)
    cert = modes.certificate
    p(f"\nCertified: {cert.count} distinct real roots on the projective line ({cert.method}).")
    rows = []
    for k, mm in enumerate(modes, 1):
        X = mm.image_point / mm.image_point[0] if abs(mm.image_point[0]) > m.tolerances.chart_x0 else mm.image_point
        rows.append([str(k), f"{X[1]:.8f}", f"{X[2]:.8f}", f"{X[3]:.8f}", f"{mm.pose[0]:.6f}",
                     f"{mm.pose[1]:.6f}", f"{mm.pose[2]:.6f}", f"{mm.aspect:+d}", f"{mm.residual:.1e}"])
    p(f"\n{len(modes)} real assembly modes (image point with x0 = 1; pose; sign of det J; joint residual):")
    p(_table(rows, ["mode", "x1", "x2", "x3", "x", "y", "phi [rad]", "aspect", "residual"]))
    out = Path(out_dir)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise _CommandError(f"cannot create the folder {out}: {_reason(exc)}") from exc
    path = out / "assembly_modes.png"
    fig = plot_assembly_modes(m, q, modes)
    import matplotlib.pyplot as plt

    try:
        path = _save_figure(fig, path, dpi=110)
    finally:
        plt.close(fig)
    p(f"\npicture of the assembly modes: {path}")
    return path


def _example(name):
    from . import examples

    if name not in EXAMPLES:
        raise SystemExit(f"imagespace: unknown example {name!r}; choose one of {', '.join(EXAMPLES)}")
    return getattr(examples, EXAMPLES[name])()


def default_box(m, chart):
    """The default meshing box of a chart, scaled by the design: image ``+-0.8 L`` and
    ``x1/x0 in [-3, 3]``; pose ``+-L`` and ``phi in [-pi, pi]``
    (:func:`imagespace.singular.boxes.default_box`, also :func:`~imagespace.mesh_surface`'s default).

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.cli import default_box
    >>> default_box(isp.examples.stigger_husty(), "pose")[2]
    (-3.141592653589793, 3.141592653589793)
    """
    from .singular.boxes import default_box as box_of

    return box_of(m, chart)


def _check_finite(values, option):
    if values is not None and not all(math.isfinite(v) for v in values):
        raise _CommandError(f"{option} must be finite numbers, got {' '.join(map(repr, values))}")


def _surface(m, args, q_draws_modes=False):
    """The singularity surface the options ask for. ``--q`` or ``--working-modes`` for a surface
    that does not depend on the joint values is refused rather than ignored, except ``--q`` where
    it also places the drawn assembly modes (``q_draws_modes``; there ``--working-modes``, when
    given, chooses the surface and ``--q`` only the modes)."""
    q, wm = args.q, args.working_modes
    if q_draws_modes and wm is not None:
        q = None
    if q is None and wm is None:
        return m.singularity_surface()
    S = m.singularity_surface(q=q, working_modes=wm)
    if S.kind == "joint-free":
        given = [o for o, v in (("--q", q), ("--working-modes", wm)) if v is not None]
        if q_draws_modes:
            given = [o for o in given if o != "--q"]
        if given:
            given = " and ".join(given)
            raise _CommandError(f"{given}: the singularity surface of {m.name} does not depend on the "
                                f"joint values (joint-free), so {given} would be ignored; leave it out")
    return S


def _box_text(box):
    """A box for people: six significant digits (``[[-12.1852, 12.1852], ...]``)."""
    return "[" + ", ".join("[" + ", ".join(f"{float(v):.6g}" for v in b) + "]" for b in box) + "]"


def _box(m, args):
    if args.box is None:
        return default_box(m, args.chart)
    b = args.box
    return ((b[0], b[1]), (b[2], b[3]), (b[4], b[5]))


def mesh_command(args, stream=None):
    """``imagespace mesh``: mesh the singularity surface of an example and export it.

    Prints how many vertices are certified within ``tol`` of the box size (a sign change between
    points of proven sign, see :mod:`imagespace.singular.meshing`), how many could not be certified and
    were removed (or kept, ``--keep-uncertified``), and the precision the export format stores
    (PLY/OBJ float64; STL/GLB float32 by format). Returns 1 with ``--strict`` when any vertex
    was removed or left uncertified, else 0.

    The output path is checked before any computation (an existing folder, a path under a file or
    a missing folder is refused), and ``--q`` or ``--working-modes`` for a surface that does not
    depend on the joint values is refused rather than ignored; both raise :class:`InputError`
    (``main`` turns it into a one-line message and exit status 2).

    Raises
    ------
    InputError
        An output path that cannot be written or has an unknown suffix; ``--q`` or
        ``--working-modes`` for a surface that does not use them (``main`` reports these
        with exit status 2).

    Examples
    --------
    >>> import io, tempfile, pathlib
    >>> from imagespace.cli import main
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "s.ply"
    >>> main(["mesh", "--resolution", "24", "--strict", "-o", str(out)], stream=io.StringIO())
    0
    >>> out.exists()
    True
    """
    import time

    from .singular.meshing import EXPORT_FORMATS, EXPORT_PRECISION, export_mesh, mesh_surface

    stream = stream or sys.stdout
    suffix = Path(args.output).suffix.lower()
    if suffix not in EXPORT_FORMATS:
        raise InputError(f"-o/--output must end in one of {', '.join(EXPORT_FORMATS)} (the format is "
                         f"taken from the suffix), got {args.output!r}")
    _check_output_file(args.output)
    m = _example(args.example)
    S = _surface(m, args)
    box = _box(m, args)
    t = time.perf_counter()
    keep = getattr(args, "keep_uncertified", False)
    mesh = mesh_surface(S, box, chart=args.chart, resolution=args.resolution, tol=getattr(args, "tol", 1e-9),
                        on_uncertified="keep" if keep else "remove")
    try:
        path = export_mesh(mesh, args.output)
    except OSError as exc:
        raise _write_error(args.output, exc) from exc
    t = time.perf_counter() - t
    md = mesh.metadata["imagespace"]
    n_uncert, n_removed = md["uncertified"], md["removed"]
    n_cert = len(mesh.vertices) - n_uncert
    within = (f"within {md['max_distance']:.2e} of the surface ({md['max_distance'] / md['size']:.1e} of the box "
              f"size; certified by a sign change or an exact zero; signs: {md['sign_test']})")
    print(f"{m.name}: singularity surface ({S.kind})", file=stream)
    print(f"chart {args.chart}, box {_box_text(box)}, resolution {args.resolution}", file=stream)
    if n_uncert == 0 and n_removed == 0:
        print(f"{len(mesh.faces)} triangles, {len(mesh.vertices)} vertices; every vertex {within}; {t:.2f} s",
              file=stream)
    else:
        print(f"{len(mesh.faces)} triangles, {len(mesh.vertices)} vertices; {n_cert} certified {within}; "
              f"{t:.2f} s", file=stream)
        if n_removed:
            print(f"{n_removed} vertices could not be certified and were removed with their "
                  f"{md['removed_faces']} triangles", file=stream)
        if n_uncert:
            print(f"{n_uncert} vertices could not be certified and were kept (--keep-uncertified); "
                  "their distance to the surface is unknown", file=stream)
    if EXPORT_PRECISION[suffix] == "float64":
        print(f"written: {path} (float64 vertices, exactly the certified ones)", file=stream)
    else:
        print(f"written: {path} (float32 vertices: {suffix[1:].upper()} stores single precision, so each "
              "coordinate is rounded by up to 6e-8 of its size, more than the certified bound; "
              "use .ply or .obj for float64)", file=stream)
    if getattr(args, "strict", False) and (n_uncert or n_removed):
        print(f"imagespace mesh: --strict: {n_removed + n_uncert} vertices without a certificate "
              f"({n_removed} removed, {n_uncert} kept)", file=sys.stderr)
        return 1
    return 0


def plot_command(args, stream=None):
    """``imagespace plot``: the figures of seed 002 for an example, written to a file.

    The picture is written atomically (see :func:`_save_figure`). ``--q`` places the drawn
    assembly modes; ``--working-modes`` chooses the surface of the ``surface`` and ``conic``
    figures and is refused where it would be ignored (the other figures, or a surface that does
    not depend on the joint values).

    Raises
    ------
    InputError
        An output path that cannot be written; ``--working-modes`` where the figure would
        ignore it (``main`` reports these with exit status 2).

    Examples
    --------
    >>> import io, tempfile, pathlib
    >>> from imagespace.cli import main
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "conic.png"
    >>> main(["plot", "conic", "-o", str(out)], stream=io.StringIO())
    0
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from . import plotting

    stream = stream or sys.stdout
    if args.working_modes is not None and args.figure in ("modes", "quadrics"):
        raise _CommandError(f"--working-modes: the {args.figure} figure does not use it (only surface "
                            "and conic do); leave it out")
    _check_output_file(args.output)
    m = _example(args.example)
    q = m.q_example_float if args.q is None else np.array(args.q)
    if args.figure == "modes":
        fig = plotting.plot_assembly_modes(m, q)
    elif args.figure == "quadrics":
        fig = plotting.plot_constraint_quadrics(m, q, _box(m, argparse.Namespace(box=args.box, chart="image")),
                                                resolution=args.resolution)
    elif args.figure == "surface":
        S = _surface(m, args, q_draws_modes=True)
        fig = plotting.plot_singularity_surface(S, _box(m, args), chart=args.chart,
                                                resolution=args.resolution, q=q)
    else:
        S = _surface(m, args, q_draws_modes=True)
        modes = m.direct_kinematics(q)
        phi = args.phi if args.phi is not None else (modes[0].pose[2] if modes else 0.0)
        from .singular.boxes import design_scale

        L = design_scale(m)
        fig = plotting.plot_conic_section(S, phi, (-L, L), (-L, L), modes=modes)
    try:
        path = _save_figure(fig, args.output, dpi=110)
    finally:
        plt.close(fig)
    print(f"written: {path}", file=stream)
    return 0


def main(argv=None, stream=None):
    """Entry point of the ``imagespace`` command.

    Raises
    ------
    SystemExit
        From argparse: ``--help``, ``--version`` or unknown options (library errors are
        reported and return 2 instead).

    Examples
    --------
    >>> from imagespace.cli import main
    >>> main(["--version"])  # doctest: +SKIP
    """
    from . import __version__

    parser = _Parser(prog="imagespace",
                                     description="Kinematics of planar parallel manipulators in the kinematic image space.")
    parser.add_argument("--version", action="version", version=f"imagespace {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    d = sub.add_parser("demo", help="the six-solution 2RPR-PPR example of Stigger & Husty, end to end")
    d.add_argument("-o", "--out", default="imagespace-demo", help="folder for the picture (default: %(default)s)")

    def common(p, resolution):
        p.add_argument("--example", default="stigger-husty", choices=sorted(EXAMPLES),
                       help="the mechanism (default: %(default)s)")
        p.add_argument("--chart", default="image", choices=("image", "pose"),
                       help="image: (x2/x0, x3/x0, x1/x0); pose: (x, y, phi) (default: %(default)s)")
        p.add_argument("--resolution", type=int, default=resolution, help="grid points per axis (default: %(default)s)")
        p.add_argument("--box", type=float, nargs=6, metavar=("UMIN", "UMAX", "VMIN", "VMAX", "WMIN", "WMAX"),
                       help="box in chart coordinates (default: scaled to the design)")
        p.add_argument("--q", type=float, nargs=3, help="joint values (surface at given joints / modes to draw)")
        p.add_argument("--working-modes", type=int, nargs=3, dest="working_modes",
                       help="leg IK branches through which joint values are eliminated")

    me = sub.add_parser("mesh", help="mesh the singularity surface and export it (STL, PLY, OBJ, GLB)")
    common(me, 128)
    me.add_argument("-o", "--output", default="surface.stl",
                    help="output file; the format from the suffix (.ply/.obj: float64 vertices; "
                         ".stl/.glb: float32 by format)")
    me.add_argument("--tol", type=float, default=1e-9,
                    help="certified distance of every vertex to the surface, relative to the box size "
                         "(default: %(default)s)")
    me.add_argument("--keep-uncertified", action="store_true", dest="keep_uncertified",
                    help="keep vertices no sign change could be certified for (default: remove them)")
    me.add_argument("--strict", action="store_true",
                    help="exit with status 1 when any vertex is uncertified or was removed")
    pl = sub.add_parser("plot", help="figures: modes, quadrics (Abb. 2), surface (Abb. 4), conic")
    pl.add_argument("figure", choices=("modes", "quadrics", "surface", "conic"))
    common(pl, 40)
    pl.add_argument("--phi", type=float, help="orientation of the conic section (default: the first mode's)")
    pl.add_argument("-o", "--output", default="figure.png", help="image file (default: %(default)s)")
    args = parser.parse_args(argv)
    from .exceptions import ImageSpaceError

    try:
        opts = vars(args)
        _check_finite(opts.get("q"), "--q")
        _check_finite(opts.get("box"), "--box")
        _check_finite(None if opts.get("phi") is None else [opts["phi"]], "--phi")
        if args.command == "demo":
            demo(args.out, stream=stream)
        elif args.command == "mesh":
            return mesh_command(args, stream)
        elif args.command == "plot":
            return plot_command(args, stream)
    except (ImageSpaceError, ValueError) as exc:
        print(f"imagespace {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        where = f"{os.fsdecode(exc.filename)}: " if exc.filename is not None else ""
        print(f"imagespace {args.command}: error: {where}{_reason(exc)}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
