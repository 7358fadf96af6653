"""The ``imagespace`` command."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import sympy as sp

__all__ = ["main", "demo"]


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
        The PNG written.

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
    from .constraints import image_symbols
    from .plotting import plot_assembly_modes

    stream = stream or sys.stdout
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
        X = mm.image_point / mm.image_point[0] if abs(mm.image_point[0]) > 1e-12 else mm.image_point
        rows.append([str(k), f"{X[1]:.8f}", f"{X[2]:.8f}", f"{X[3]:.8f}", f"{mm.pose[0]:.6f}",
                     f"{mm.pose[1]:.6f}", f"{mm.pose[2]:.6f}", f"{mm.aspect:+d}", f"{mm.residual:.1e}"])
    p(f"\n{len(modes)} real assembly modes (image point with x0 = 1; pose; sign of det J; joint residual):")
    p(_table(rows, ["mode", "x1", "x2", "x3", "x", "y", "phi [rad]", "aspect", "residual"]))
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    path = out / "assembly_modes.png"
    fig = plot_assembly_modes(m, q, modes)
    fig.savefig(path, dpi=110)
    import matplotlib.pyplot as plt

    plt.close(fig)
    p(f"\npicture of the assembly modes: {path}")
    return path


def main(argv=None):
    """Entry point of the ``imagespace`` command.

    Examples
    --------
    >>> from imagespace.cli import main
    >>> main(["--version"])  # doctest: +SKIP
    """
    from . import __version__

    parser = argparse.ArgumentParser(prog="imagespace",
                                     description="Kinematics of planar parallel manipulators in the kinematic image space.")
    parser.add_argument("--version", action="version", version=f"imagespace {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    d = sub.add_parser("demo", help="the six-solution 2RPR-PPR example of Stigger & Husty, end to end")
    d.add_argument("-o", "--out", default="imagespace-demo", help="folder for the picture (default: %(default)s)")
    args = parser.parse_args(argv)
    if args.command == "demo":
        demo(args.out)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
