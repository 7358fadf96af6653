"""Design figures: mode-count maps, workspaces, design maps."""

from __future__ import annotations

import numpy as np

from ..exceptions import InputError
from .common import pyplot, legend_once, joint_unit, joint_label, LENGTH_UNIT, UNSOLVED_COLOUR

__all__ = ['plot_mode_count_map', 'plot_workspaces', 'plot_design_map']


def plot_mode_count_map(count_map, cusps=(), loops=(), ax=None, manipulator=None):
    """Real assembly modes over a joint-space section, the discriminant curve as the region
    boundaries, cusps and loops around them.

    The counts are whole numbers, so the colour map is discrete: one colour per count that occurs
    (grey for ``-1``, a row that could not be solved), and the colour bar's ticks are the counts.

    Parameters
    ----------
    count_map : ModeCountMap
        From :func:`imagespace.singular.cusps.mode_count_map`.
    cusps : sequence of Cusp
    loops : sequence of CuspLoop
    ax : matplotlib Axes, optional
    manipulator : PlanarParallel, optional
        Names the joint axes' units (``rad`` or length units); without it the axes say
        ``[length units or rad]``.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.singular.cusps import mode_count_map
    >>> from imagespace.plotting import plot_mode_count_map
    >>> m = isp.examples.general_3rpr()
    >>> fig = plot_mode_count_map(mode_count_map(m, 2, 10.0, [(6, 16), (1, 9)], 30), manipulator=m)
    >>> len(fig.axes), fig.axes[0].get_xlabel()
    (2, 'q1 [length units]')
    """
    plt = pyplot()
    from matplotlib.colors import BoundaryNorm, ListedColormap

    if ax is None:
        fig, ax = plt.subplots(figsize=(6.5, 5))
    else:
        fig = ax.figure
    a, b = count_map.axes
    C = np.asarray(count_map.counts)
    values = np.unique(C).astype(int)
    solved = values[values >= 0]
    shades = plt.get_cmap("Blues")(np.linspace(0.15, 0.85, max(1, len(solved))))[: len(solved)]
    colours = ([UNSOLVED_COLOUR] if (values < 0).any() else []) + [tuple(c) for c in shades]
    mids = (values[1:] + values[:-1]) / 2.0
    bounds = np.concatenate([[values[0] - 0.5], mids, [values[-1] + 0.5]])
    cmap = ListedColormap(colours)
    norm = BoundaryNorm(bounds, cmap.N)
    mesh = ax.pcolormesh(a, b, C.T, shading="nearest", cmap=cmap, norm=norm)
    unsolved = " (-1: not solved)" if (values < 0).any() else ""
    fig.colorbar(mesh, ax=ax, ticks=values, format="%d", label=f"real assembly modes{unsolved}")
    fa, fb = count_map.free
    if len(cusps):
        Cq = np.array([c.q for c in cusps])
        ax.plot(Cq[:, fa], Cq[:, fb], "r*", ms=12, label="cusps")
    for lp in loops:
        ax.plot(lp.q[:, fa], lp.q[:, fb], color="tab:green" if lp.changed else "0.4", lw=1.5,
                label="loop that changes the mode" if lp.changed else "loop, mode unchanged")
    ax.set_xlabel(joint_label(manipulator, fa))
    ax.set_ylabel(joint_label(manipulator, fb))
    unit = "" if manipulator is None else f" {joint_unit(manipulator, count_map.fixed)}"
    ax.set_title(f"section q{count_map.fixed + 1} = {count_map.value:g}{unit}", fontsize=10)
    if len(cusps) or len(loops):
        legend_once(ax)
    return fig


def plot_workspaces(workspaces, labels=None, ax=None):
    """Workspace regions drawn over each other (seed 004, Fig. 5).

    Parameters
    ----------
    workspaces : sequence of Workspace
    labels : sequence of str, optional
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.design.workspace import reachable_workspace, dexterous_workspace
    >>> from imagespace.plotting import plot_workspaces
    >>> m = isp.examples.choi_3ppr()
    >>> lim = [[-np.sqrt(3), np.sqrt(3)]] * 3
    >>> fig = plot_workspaces([reachable_workspace(m, (-1, 1), lim), dexterous_workspace(m, (-1, 1), lim)])
    >>> len(fig.axes)
    1
    """
    plt = pyplot()
    own = ax is None
    if own:
        fig, ax = plt.subplots(figsize=(5.5, 6))
    else:
        fig = ax.figure
    cmap = plt.get_cmap("tab10")
    for k, ws in enumerate(workspaces):
        lab = labels[k] if labels is not None else f"{ws.kind} (area {ws.area:.3g} {LENGTH_UNIT}^2)"
        col = cmap(k % 10)
        for j, curve in enumerate(ws.boundary):
            ax.plot(curve[:, 0], curve[:, 1], color=col, lw=1.8, label=lab if j == 0 else None)
            if ws.polygon is not None:
                ax.fill(curve[:, 0], curve[:, 1], color=col, alpha=0.12)
    ax.set_aspect("equal")
    ax.set_xlabel(f"x [{LENGTH_UNIT}]")
    ax.set_ylabel(f"y [{LENGTH_UNIT}]")
    ax.grid(True, alpha=0.3)
    if own:
        ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.12), frameon=False)
        fig.tight_layout()
    else:
        ax.legend(fontsize=8, loc="best")
    return fig


def plot_design_map(table, value, x, y, best=None, ax=None, title=None, units=None):
    """A design index (or the composite) over a two-parameter grid (seed 004, Figs. 7-9).

    Parameters
    ----------
    table : DesignTable
    value : str or (n,) float
        An index of the table, or values per row (e.g. ``FuzzyResult.composite``).
    x, y : str
        The two grid parameters (in the table's grid order: ``x`` first).
    best : sequence of int, optional
        Rows to mark (e.g. ``FuzzyResult.best``).
    ax : matplotlib Axes, optional
    title : str, optional
    units : dict of str, optional
        Unit of each parameter (and of the value, under the key ``value`` if it is a name, or
        ``"value"``), e.g. ``{"alpha": "rad", "r_over_R": "-"}``; a name without one is labelled
        ``[sweep units]``.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    InputError
        ``x, y`` not the table's two grid parameters in order; ``units`` not a dict.

    Examples
    --------
    >>> from imagespace.design.sweep import sweep
    >>> from imagespace.plotting import plot_design_map
    >>> def index(a, b):
    ...     return {"sum": float(a + b)}
    >>> t = sweep(index, {"a": [1.0, 2.0, 3.0], "b": [0.0, 1.0]}, processes=0)
    >>> fig = plot_design_map(t, "sum", "a", "b", units={"a": "mm", "b": "mm", "sum": "mm"})
    >>> len(fig.axes), fig.axes[0].get_xlabel()
    (2, 'a [mm]')
    """
    plt = pyplot()
    if units is None:
        units = {}
    if not isinstance(units, dict):
        raise InputError(f"units must be a dict of parameter name -> unit, got {type(units).__name__}")
    names = list(table.params)
    if [x, y] != names[:2] or len(names) != 2:
        raise InputError(f"x, y must be the table's two grid parameters in order {names}, got {[x, y]}")
    Z = table.grid(value) if isinstance(value, str) else np.asarray(value, float).reshape(table.shape)
    xs = table.params[x].reshape(table.shape)[:, 0]
    ys = table.params[y].reshape(table.shape)[0, :]
    if ax is None:
        fig, ax = plt.subplots(figsize=(6, 4.5))
    else:
        fig = ax.figure
    def label(name):
        return f"{name} [{units.get(name, 'sweep units')}]"

    mesh = ax.pcolormesh(xs, ys, Z.T, shading="nearest", cmap="viridis")
    fig.colorbar(mesh, ax=ax, label=label(value if isinstance(value, str) else "value"))
    if best is not None:
        ax.plot(table.params[x][list(best)], table.params[y][list(best)], "r*", ms=14, label="optimum")
        ax.legend(fontsize=8)
    ax.set_xlabel(label(x))
    ax.set_ylabel(label(y))
    if title:
        ax.set_title(title, fontsize=10)
    return fig

