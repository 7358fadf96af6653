"""An interactive explorer for Jupyter: drag the joint values, watch the assembly modes move.

``isp.widgets.explore(m)`` returns an :class:`Explorer`, an ipywidgets layout with

- one slider per actuated joint (ranges from the design, :func:`joint_ranges`) and a text box that
  takes an exact value (``27/2``, ``-3*pi/4``; parsed by :func:`parse_joint_value`, never evaluated);
- a **pose view**: the mechanism in every real assembly mode, coloured by aspect (red: det J > 0,
  blue: det J < 0), each mode numbered, prismatic guides drawn;
- an **image-space view**: the singularity surface meshed once (re-meshed when it depends on the
  joint values, coarsely while dragging and finer once the slider rests) as a rotatable 3D mesh in
  the chart ``(x2/x0, x3/x0, x1/x0)``, with the current modes as points;
- a **section view**: the fixed-orientation conic at the orientation of a chosen mode, with the two
  aspect regions;
- a status line: the certified number of real modes (certified on the float joint values shown, or
  on the exact value typed), a "near singular" badge where :class:`~imagespace.NearSingularWarning`
  applies, and the time the update took;
- "change mode": two modes of equal aspect are joined by a certified singularity-free path
  (:func:`imagespace.paths.modechange.plan_mode_change`), animated in both views with its joint
  loop; for opposite aspects the reason no such path exists is shown.

The 3D widget library is plotly (``FigureWidget``): it is on PyPI with no compiled parts, renders in
JupyterLab, Notebook 7 and Voilà, and writes a standalone HTML page of the same figures
(:meth:`Explorer.save_html`) that opens without a kernel. Needs the ``imagespace[jupyter]`` extra.
"""

from __future__ import annotations

import html
import re
import threading
import time
import warnings
from fractions import Fraction

import numpy as np

import ipywidgets as W
import plotly.graph_objects as go

from ._files import atomic_write
from ._validate import as_box, as_count, as_exact, as_joint_vector
from .core.mechanism import check_mechanism
from .drawing import ASPECT_COLOURS, CHART_LABELS, chart_coordinates, mechanism_lines
from .exceptions import ImageSpaceError, InputError, NearSingularWarning

__all__ = ["explore", "Explorer", "joint_ranges", "parse_joint_value", "REST_DELAY", "DRAG_RESOLUTION",
           "REST_RESOLUTION", "SECTION_GRID", "SLIDER_STEPS"]

REST_DELAY = 0.4
"""Seconds without slider motion after which a joint-dependent surface is meshed finely."""
DRAG_RESOLUTION = 20
"""Grid points per axis of a joint-dependent surface re-meshed while a slider moves."""
REST_RESOLUTION = 48
"""Grid points per axis of the surface mesh at rest (and of a joint-free surface, meshed once)."""
SECTION_GRID = 100
"""Grid points per axis of the section view's aspect regions."""
SLIDER_STEPS = 2000
"""Steps across a joint slider's range (keyboard arrows move one step, PageUp/PageDown several)."""
_PHI_CHART = 3.0                 # default |x1/x0| = |tan(phi/2)| range of the image-space view


# -- inputs ----------------------------------------------------------------------------------------
_PI_FORM = re.compile(r"^\s*([-+]?)\s*([0-9]*\.?[0-9]*(?:[eE][-+]?[0-9]+)?)\s*\*?\s*pi\s*(?:/\s*([0-9]+))?\s*$")


def parse_joint_value(text, name="q"):
    """An exact joint value from text: a decimal or fraction (``13.25``, ``27/2``) or a rational
    multiple of pi (``pi/2``, ``-3/4*pi`` is not accepted; write ``-0.75*pi`` or ``-3*pi/4``).

    The text is parsed with :class:`fractions.Fraction` (never evaluated as Python).

    Parameters
    ----------
    text : str
    name : str
        The parameter name used in error messages.

    Returns
    -------
    sympy.Rational or sympy expression
        The exact value (``sympy.pi`` times a rational for the pi forms).

    Raises
    ------
    TypeError
        ``text`` is not a string.
    InputError
        The text is not a number, a fraction or a rational multiple of pi.

    Examples
    --------
    >>> from imagespace.widgets import parse_joint_value
    >>> parse_joint_value("27/2"), parse_joint_value("-3*pi/4")
    (27/2, -3*pi/4)
    """
    import sympy as sp

    if not isinstance(text, str):
        raise TypeError(f"{name} must be text such as '27/2' or 'pi/3', got {type(text).__name__}")
    if len(text) > 100 or re.search(r"[eE][-+]?[0-9]{4,}", text):
        raise InputError(f"{name} must be a number of float size (at most 100 characters, exponent "
                         f"below 1000), got {text[:40]!r}")
    m = _PI_FORM.match(text)
    try:
        if m:
            sign, coef, den = m.groups()
            c = Fraction(coef) if coef else Fraction(1)
            c = c / int(den) if den else c
            c = -c if sign == "-" else c
            return sp.Rational(c.numerator, c.denominator) * sp.pi
        f = Fraction(text.strip())
    except (ValueError, ZeroDivisionError):
        raise InputError(f"{name} must be a number, a fraction such as 27/2 or a rational multiple of pi "
                         f"such as 3*pi/4; got {text!r}") from None
    if not abs(f) < Fraction(10) ** 300:
        raise InputError(f"{name} must be within the float range (|value| < 1e300), got {text!r}")
    return sp.Rational(f.numerator, f.denominator)


def joint_ranges(manipulator, q):
    """Slider ranges ``(3, 2)`` for the actuated joints, from the design and the joint values ``q``.

    Angles get ``[-pi, pi]``. An RPR leg length gets ``[0, L]`` and a slider travel
    ``[q - L/2, q + L/2]``, where ``L`` is twice the larger of ``|q_i|`` and the design's size (the
    spread of its base anchors plus that of its platform anchors).

    Parameters
    ----------
    manipulator : PlanarParallel
    q : (3,) float

    Returns
    -------
    (3, 2) float

    Raises
    ------
    InputError
        ``q`` is not three finite numbers.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.widgets import joint_ranges
    >>> m = isp.examples.stigger_husty()
    >>> joint_ranges(m, m.q_example_float).round(3).tolist()
    [[0.0, 40.0], [0.0, 40.0], [-6.75, 33.25]]
    """
    check_mechanism(manipulator)
    qv = as_joint_vector(q)
    geo = [leg.geometry(exact=False) for leg in manipulator.legs]
    base = np.array([g["base"] for g in geo], dtype=float)
    plat = np.array([g["platform"] for g in geo], dtype=float)
    size = float(np.max(np.ptp(base, axis=0)) + np.max(np.ptp(plat, axis=0)))
    out = np.empty((3, 2))
    for i, leg in enumerate(manipulator.legs):
        L = 2 * max(abs(qv[i]), size, 1.0)
        if leg.actuated_is_angle:
            out[i] = (-np.pi, np.pi)
        elif leg.joints == "RPR":
            out[i] = (0.0, L)
        else:
            out[i] = (qv[i] - L / 2, qv[i] + L / 2)
    return out


def _joined(polys):
    """Polylines as one ``(n, 2)`` array with NaN rows between them (gaps in a plotly line)."""
    if not polys:
        return np.zeros((0, 2))
    gap = np.full((1, 2), np.nan)
    return np.concatenate([part for P in polys for part in (np.asarray(P, dtype=float), gap)])


# -- the explorer ----------------------------------------------------------------------------------
def explore(manipulator, q=None, box=None, resolution=REST_RESOLUTION):
    """Open the interactive explorer on a manipulator (see the module docstring).

    Parameters
    ----------
    manipulator : PlanarParallel
    q : (3,) float, optional
        Starting joint values; default the design's ``q_example``.
    box : (3, 2) float, optional
        The image-space view's box in the chart ``(x2/x0, x3/x0, x1/x0)``; default: around the
        starting modes, with ``|x1/x0| <= 3`` (``|phi| <= 143 deg``).
    resolution : int
        Grid points per axis of the surface mesh at rest.

    Returns
    -------
    Explorer
        An ``ipywidgets.VBox``; display it (last expression of a cell).

    Raises
    ------
    InputError
        No ``q`` given for a design without ``q_example``; a bad ``q``, ``box`` or ``resolution``.

    Examples
    --------
    >>> import imagespace as isp
    >>> ex = isp.widgets.explore(isp.examples.stigger_husty())
    >>> ex.status["count"], ex.status["certified"]
    (6, True)
    """
    return Explorer(manipulator, q=q, box=box, resolution=resolution)


class Explorer(W.VBox):
    """The explorer's layout and state; made by :func:`explore`.

    Attributes
    ----------
    manipulator : PlanarParallel
    q : (3,) float
        The joint values shown.
    modes : list of AssemblyMode
        The real assembly modes at ``q``, numbered from 1 in the views.
    status : dict
        ``count`` (real modes), ``certified`` (bool), ``near_singular`` (bool), ``exact`` (the
        count was certified on exact joint values typed in), ``seconds`` (the last update),
        ``error`` (a message, or None).
    plan : ModeChangePlan or None
        The last mode change planned.
    figure : plotly.graph_objects.FigureWidget
        The four panels (pose view, image space, section view, joint loop); :meth:`trace` finds a
        trace by name.
    sliders : list of ipywidgets.FloatSlider
    exact_boxes : list of ipywidgets.Text
    """

    def __init__(self, manipulator, q=None, box=None, resolution=REST_RESOLUTION):
        check_mechanism(manipulator)
        if q is None:
            if manipulator.q_example_float is None:
                raise InputError("q is needed: this design has no q_example; pass the starting joint "
                                 "values, e.g. explore(m, q=m.inverse_kinematics(pose))")
            q = manipulator.q_example_float
        self.manipulator = manipulator
        self.q = as_joint_vector(q).copy()
        self.resolution = as_count(resolution, "resolution", minimum=8)
        self.modes = []
        self.plan = None
        self.status = {"count": 0, "certified": False, "near_singular": False, "exact": False,
                       "seconds": 0.0, "error": None}
        self._surface = None
        self._surface_q = None
        self._timer = None
        self._lock = threading.Lock()
        self._want = None
        self._working = False
        self._generation = 0             # bumped by every set_q: a background mesh of older q is dropped
        self._draw = threading.RLock()   # one thread draws at a time (the figure is not thread-safe)
        self._stale = False              # the surface shown belongs to earlier joint values
        self._mesh_resolution = 0
        self._muted = False
        ranges = joint_ranges(manipulator, self.q)
        self.sliders = []
        self.exact_boxes = []
        rows = []
        for i, leg in enumerate(manipulator.legs):
            lo, hi = ranges[i]
            # the slider snaps to min + k * step in the browser: align its grid with q so that the
            # starting joint values are shown (and solved) as given
            step = float(hi - lo) / SLIDER_STEPS
            lo = self.q[i] - np.floor((self.q[i] - lo) / step) * step
            hi = lo + SLIDER_STEPS * step
            unit = "rad" if leg.actuated_is_angle else "length units"
            s = W.FloatSlider(value=float(self.q[i]), min=float(lo), max=float(hi), step=step, description=f"q{i + 1} {leg.actuated_name} [{unit}]",
                              continuous_update=True, readout_format=".4f",
                              style={"description_width": "170px"}, layout=W.Layout(width="480px"))
            t = W.Text(placeholder="exact value, e.g. 27/2", continuous_update=False,
                       layout=W.Layout(width="180px"))
            s.observe(self._on_slider, "value")
            t.observe(self._on_text, "value")
            self.sliders.append(s)
            self.exact_boxes.append(t)
            rows.append(W.HBox([s, t]))
        self.status_line = W.HTML()
        self.mode_a = W.Dropdown(description="mode A", layout=W.Layout(width="160px"))
        self.mode_b = W.Dropdown(description="mode B", layout=W.Layout(width="160px"))
        self.section_mode = W.Dropdown(description="section at", layout=W.Layout(width="170px"))
        self.section_mode.observe(lambda ch: self._draw_section(), "value")
        self.change_button = W.Button(description="change mode", button_style="primary",
                                      tooltip="plan a certified singularity-free path between mode A and mode B")
        self.change_button.on_click(lambda b: self.change_mode())
        self.plan_message = W.HTML()
        self.play = W.Play(interval=60, min=0, max=0, disabled=True, description="animate")
        self.frame = W.IntSlider(min=0, max=0, description="frame", disabled=True)
        W.jslink((self.play, "value"), (self.frame, "value"))
        self.frame.observe(lambda ch: self._draw_frame(ch["new"]), "value")

        self.figure = self._build_figure()
        self._solve(self.q)
        self._box = self._initial_box(box)
        self.figure.layout.scene.update(self._scene())
        self._remesh(self.resolution)
        self._draw_all()
        # a FigureWidget's front end starts from the figure it was constructed with (later edits
        # travel as messages to a live view), so the first state is drawn into plain figures
        self.figure = go.FigureWidget(self.figure)
        controls = W.HBox([self.section_mode, self.mode_a, self.mode_b, self.change_button, self.play, self.frame])
        super().__init__([W.VBox(rows), self.status_line, controls, self.plan_message, self.figure])

    # -- figures --------------------------------------------------------------------------------
    def _build_figure(self):
        """One plotly figure with four panels (pose, image space, section, joint loop).

        One figure, not four: each plotly ``FigureWidget`` is an anywidget model that loads the
        5 MB plotly.js bundle, and anywidget gives a model 2 s to start.
        """
        from plotly.subplots import make_subplots

        fig = make_subplots(rows=2, cols=2, specs=[[{"type": "xy"}, {"type": "scene"}], [{"type": "xy"}, {"type": "xy"}]],
                            column_widths=[0.47, 0.53], row_heights=[0.58, 0.42], horizontal_spacing=0.08,
                            vertical_spacing=0.09,
                            subplot_titles=("pose view", "image space", "section view", "joint loop"))
        self._trace = {}

        def add(name, trace, row, col):
            self._trace[name] = len(fig.data)
            fig.add_trace(trace, row=row, col=col)

        # pose view
        add("guides", go.Scatter(x=[], y=[], mode="lines", name="prismatic guides", hoverinfo="skip",
                                 line=dict(color="#999999", dash="dash", width=2)), 1, 1)
        for a in (1, -1):
            add(f"legs{a:+d}", go.Scatter(x=[], y=[], mode="lines", name=f"legs, aspect {a:+d}", hoverinfo="skip",
                                          legendgroup=f"aspect{a:+d}", line=dict(color=ASPECT_COLOURS[a], width=2)), 1, 1)
            add(f"platform{a:+d}", go.Scatter(x=[], y=[], mode="lines", fill="toself", name=f"platform, aspect {a:+d}",
                                              legendgroup=f"aspect{a:+d}", hoverinfo="skip", opacity=0.35,
                                              line=dict(color=ASPECT_COLOURS[a], width=1)), 1, 1)
        add("base", go.Scatter(x=[], y=[], mode="markers", name="base joints",
                               marker=dict(symbol="square", color="black", size=8)), 1, 1)
        add("numbers", go.Scatter(x=[], y=[], mode="text", name="mode numbers", textfont=dict(size=14),
                                  showlegend=False), 1, 1)
        add("moving", go.Scatter(x=[], y=[], mode="lines+markers", name="along the planned path",
                                 line=dict(color="#2ca02c", width=4)), 1, 1)
        # image space
        add("surface", go.Mesh3d(x=[], y=[], z=[], i=[], j=[], k=[], color="#bbbbbb", opacity=0.5,
                                 name="singularity surface", flatshading=True, showlegend=True, hoverinfo="skip"), 1, 2)
        for a in (1, -1):
            add(f"points{a:+d}", go.Scatter3d(x=[], y=[], z=[], mode="markers+text", name=f"modes, aspect {a:+d}",
                                              legendgroup=f"aspect{a:+d}", showlegend=False, textposition="top center",
                                              marker=dict(color=ASPECT_COLOURS[a], size=6)), 1, 2)
        add("path", go.Scatter3d(x=[], y=[], z=[], mode="lines", name="certified path",
                                 line=dict(color="#2ca02c", width=6)), 1, 2)
        add("position", go.Scatter3d(x=[], y=[], z=[], mode="markers", name="position on the path", showlegend=False,
                                     marker=dict(color="#2ca02c", size=8, symbol="diamond")), 1, 2)
        # section view
        # one contour trace draws both the conic (its zero line) and the two aspect regions (fills):
        # its values are the conic's, signed so that positive means aspect +1
        add("regions", go.Contour(x=[], y=[], z=[], showscale=False, name="singular conic (det J = 0)",
                                  hoverinfo="skip", contours=dict(start=0, end=0, size=1, coloring="fill"),
                                  showlegend=True, opacity=0.45, line=dict(color="black", width=2),
                                  colorscale=[[0, ASPECT_COLOURS[-1]], [1, ASPECT_COLOURS[1]]]), 2, 1)
        for a in (1, -1):
            add(f"section{a:+d}", go.Scatter(x=[], y=[], mode="markers+text", name=f"modes, aspect {a:+d}",
                                             legendgroup=f"aspect{a:+d}", showlegend=False, textposition="top center",
                                             marker=dict(color=ASPECT_COLOURS[a], size=10,
                                                         line=dict(color="black", width=1))), 2, 1)
        # joint loop
        for i in range(3):
            add(f"loop{i + 1}", go.Scatter(x=[], y=[], mode="lines", name=f"q{i + 1} - q{i + 1} at the start"), 2, 2)
        add("now", go.Scatter(x=[], y=[], mode="markers", name="now", showlegend=False,
                              marker=dict(color="black", size=8)), 2, 2)
        fig.update_layout(width=1150, height=1000, margin=dict(l=50, r=10, t=60, b=40),
                          legend=dict(font=dict(size=10), orientation="h", y=-0.06))
        fig.update_xaxes(title_text="x [length units]", row=1, col=1)
        fig.update_yaxes(title_text="y [length units]", scaleanchor="x", scaleratio=1, row=1, col=1)
        fig.update_xaxes(title_text="x [length units]", row=2, col=1)
        fig.update_yaxes(title_text="y [length units]", scaleanchor="x3", scaleratio=1, row=2, col=1)
        fig.update_xaxes(title_text="path sample", row=2, col=2)
        fig.update_yaxes(title_text="joint change [rad or length units]", row=2, col=2)
        return fig

    def trace(self, name):
        """The plotly trace called ``name`` in the explorer's figure.

        Names: ``guides``, ``legs+1``, ``legs-1``, ``platform+1``, ``platform-1``, ``base``, ``numbers``,
        ``moving`` (pose view); ``surface``, ``points+1``, ``points-1``, ``path``, ``position``
        (image space); ``regions`` (the conic and its aspect regions), ``section+1``, ``section-1`` (section view);
        ``loop1``..``loop3``, ``now`` (joint loop).

        Raises
        ------
        InputError
            An unknown name.

        Examples
        --------
        >>> import imagespace as isp
        >>> ex = isp.widgets.explore(isp.examples.stigger_husty())
        >>> len(ex.trace("numbers").text)
        6
        """
        if name not in self._trace:
            raise InputError(f"name must be one of {sorted(self._trace)}, got {name!r}")
        return self.figure.data[self._trace[name]]

    def _title(self, panel, text):
        self.figure.layout.annotations[panel].text = text

    def _initial_box(self, box):
        if box is not None:
            return as_box(box, dim=3)
        C = chart_coordinates(np.array([mm.image_point for mm in self.modes])) if self.modes else np.zeros((1, 3))
        C = C[np.all(np.isfinite(C), axis=1)]
        half = max(2.0 * float(np.max(np.abs(C[:, :2]))) if len(C) else 1.0, 1.0)
        return np.array([[-half, half], [-half, half], [-_PHI_CHART, _PHI_CHART]])

    def _scene(self):
        b = self._box
        return dict(xaxis=dict(title=CHART_LABELS[0], range=list(b[0])),
                    yaxis=dict(title=CHART_LABELS[1], range=list(b[1])),
                    zaxis=dict(title=CHART_LABELS[2], range=list(b[2])), aspectmode="cube")

    # -- computation ----------------------------------------------------------------------------
    def _solve(self, q, exact=None):
        """Certified real modes at ``q`` (float batch path), or at the exact values ``exact``."""
        t0 = time.perf_counter()
        m = self.manipulator
        err = None
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                if exact is not None:
                    cm = m.direct_kinematics(exact, certify=True)
                    modes, certified, near = list(cm), bool(cm.certificate.certified), False
                else:
                    res = m.direct_kinematics_batch(np.asarray(q, dtype=float)[None], certify=True)
                    if not res.row_ok[0]:
                        err = "; ".join(str(e) for e in res.errors.values()) or "no solution for this row"
                        modes, certified, near = [], False, False
                    else:
                        modes = res.modes(0)
                        certified = bool(res.consistent[0]) if res.consistent is not None else False
                        near = bool(res.near_singular[0]) if res.near_singular is not None else False
            except ImageSpaceError as e:
                err, modes, certified, near = str(e), [], False, False
        near = near or any(issubclass(w.category, NearSingularWarning) for w in caught)
        self.modes = modes
        self.status = {"count": len(modes), "certified": certified and err is None, "near_singular": near,
                       "exact": exact is not None, "seconds": time.perf_counter() - t0, "error": err}

    def _mesh_for(self, q, resolution, quiet=True):
        """``(surface, mesh)`` at joint values ``q``; raises ImageSpaceError (the caller reports it).

        ``quiet``: the mesher's warnings are silenced (main thread only: ``warnings.catch_warnings``
        changes process-wide state, so the background thread never uses it)."""
        from .singular.meshing import mesh_surface

        S = self._surface
        if S is None or S.kind != "joint-free":
            S = self.manipulator.singularity_surface(q=q)
        box = [tuple(r) for r in self._box]
        if not quiet:
            return S, mesh_surface(S, box, chart="image", resolution=resolution)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return S, mesh_surface(S, box, chart="image", resolution=resolution)

    def _show_mesh(self, S, mesh, q, resolution):
        self._surface, self._surface_q, self._mesh_resolution = S, q, resolution
        self._stale = False
        V, F = np.asarray(mesh.vertices), np.asarray(mesh.faces).astype(np.int32)
        with self.figure.batch_update():
            self.trace("surface").update(x=V[:, 0], y=V[:, 1], z=V[:, 2], i=F[:, 0], j=F[:, 1], k=F[:, 2],
                                         opacity=0.5, name=f"singularity surface ({S.kind}, {resolution}^3 grid)")

    def _remesh(self, resolution):
        """Mesh the surface for the current joint values now (skipped for a joint-free surface
        already meshed at least this finely)."""
        S = self._surface
        if S is not None and S.kind == "joint-free" and resolution <= self._mesh_resolution:
            return
        q = self.q.copy()
        try:
            S, mesh = self._mesh_for(q, resolution)
        except ImageSpaceError as e:
            self.status["error"] = self.status["error"] or f"singularity surface: {e}"
            return
        self._show_mesh(S, mesh, q, resolution)

    # -- drawing --------------------------------------------------------------------------------
    def _draw_all(self):
        labels = [f"{k + 1} ({mm.aspect:+d})" for k, mm in enumerate(self.modes)]
        for dd in (self.mode_a, self.mode_b):
            dd.options = list(zip(labels, range(len(labels))))
        if len(labels) > 1:
            self.mode_b.value = 1
        self.section_mode.options = list(zip(labels, range(len(labels))))
        if labels:
            self.mode_a.value = 0
            self.section_mode.value = 0
        self._draw_pose()
        self._draw_space()
        self._draw_section()
        self._draw_status()

    def _draw_pose(self):
        m = self.manipulator
        guides, legs, plats, base, text = [], {1: [], -1: []}, {1: [], -1: []}, [], ([], [], [])
        for k, mm in enumerate(self.modes):
            lines = mechanism_lines(m, mm.pose, self.q)
            a = 1 if mm.aspect >= 0 else -1
            for seg in lines.guides:
                guides.append(seg)
            for L in lines.legs:
                legs[a].append(L)
                base.append(L[0])
            plats[a].append(lines.platform)
            c = lines.platform[:3].mean(axis=0)
            text[0].append(c[0])
            text[1].append(c[1])
            text[2].append(str(k + 1))

        B = np.array(base) if base else np.zeros((0, 2))
        with self.figure.batch_update():
            for name, polys in (("guides", guides), ("legs+1", legs[1]), ("legs-1", legs[-1]),
                                ("platform+1", plats[1]), ("platform-1", plats[-1])):
                xy = _joined(polys)
                self.trace(name).update(x=xy[:, 0], y=xy[:, 1])
            self.trace("base").update(x=B[:, 0], y=B[:, 1])
            self.trace("numbers").update(x=np.array(text[0]), y=np.array(text[1]), text=text[2])
            self.trace("moving").update(x=[], y=[])
            self._title(0, f"pose view: {len(self.modes)} real assembly mode{'' if len(self.modes) == 1 else 's'} "
                           f"at q = ({', '.join(f'{v:.4g}' for v in self.q)})")

    def _draw_space(self):
        with self.figure.batch_update():
            for a in (1, -1):
                ks = [k for k, mm in enumerate(self.modes) if (1 if mm.aspect >= 0 else -1) == a]
                C = chart_coordinates(np.array([self.modes[k].image_point for k in ks])) if ks else np.zeros((0, 3))
                self.trace(f"points{a:+d}").update(x=C[:, 0], y=C[:, 1], z=C[:, 2], text=[str(k + 1) for k in ks])
            if self.plan is None:
                for name in ("path", "position"):
                    self.trace(name).update(x=[], y=[], z=[])

    def _draw_section(self):
        fig = self.figure
        if not self.modes or self._surface is None or self.section_mode.value is None:
            with fig.batch_update():
                self.trace("regions").update(x=[], y=[], z=[])
                for a in (1, -1):
                    self.trace(f"section{a:+d}").update(x=[], y=[], text=[])
                self._title(2, "section view (no mode)")
            return
        k = int(self.section_mode.value)
        mode = self.modes[k]
        phi = float(mode.pose[2])
        c = np.asarray(self._surface.section_coefficients(phi), dtype=float).reshape(-1)
        P = np.array([mm.pose for mm in self.modes])
        lo, hi = P[:, :2].min(axis=0), P[:, :2].max(axis=0)
        half = 0.75 * max(float(np.max(hi - lo)), 1.0)
        mid = (lo + hi) / 2
        xs = np.linspace(mid[0] - half, mid[0] + half, SECTION_GRID)
        ys = np.linspace(mid[1] - half, mid[1] + half, SECTION_GRID)
        X, Y = np.meshgrid(xs, ys)
        def conic(x, y):                       # A x^2 + B xy + C y^2 + D x + E y + F
            return c[0] * x * x + c[1] * x * y + c[2] * y * y + c[3] * x + c[4] * y + c[5]

        Z = conic(X, Y)
        s0 = conic(mode.pose[0], mode.pose[1])
        # the sign of the conic times the chosen mode's (aspect * sign) is the aspect of a region
        flip = float(np.sign(s0)) * (1 if mode.aspect >= 0 else -1) if s0 != 0 and mode.aspect != 0 else 1.0
        same = [j for j, mm in enumerate(self.modes) if abs(np.remainder(mm.pose[2] - phi + np.pi, 2 * np.pi) - np.pi)
                <= self.manipulator.tolerances.plot_orientation]
        with fig.batch_update():
            self.trace("regions").update(x=xs, y=ys, z=flip * Z)
            for a in (1, -1):
                js = [j for j in same if (1 if self.modes[j].aspect >= 0 else -1) == a]
                self.trace(f"section{a:+d}").update(x=[self.modes[j].pose[0] for j in js],
                                                    y=[self.modes[j].pose[1] for j in js],
                                                    text=[str(j + 1) for j in js])
            self._title(2, f"section at phi = {np.degrees(phi):.3f} deg (mode {k + 1}): "
                           "red det J > 0, blue det J < 0"
                           + (" [surface of the earlier joint values, updating]" if self._stale else ""))

    def _draw_status(self):
        st = self.status
        badge = ('<span style="background:#f0ad4e;color:white;padding:1px 6px;border-radius:8px" '
                 'class="isp-near-singular">near singular</span> ') if st["near_singular"] else ""
        if st["error"]:
            body = f'<b class="isp-error" style="color:#b00">{html.escape(st["error"])}</b>'
        else:
            if not st["certified"]:
                how = "NOT certified"
            else:
                how = "certified on the exact joint values" if st["exact"] else "certified on the float joint values"
            body = (f'<b><span class="isp-count">{st["count"]}</span> real assembly mode'
                    f'{"" if st["count"] == 1 else "s"}</b> ({how})')
        q = ",".join(repr(float(v)) for v in self.q)
        self.status_line.value = (f'<div class="isp-status" data-q="{q}">{badge}{body} &middot; updated in '
                                  f'<span class="isp-seconds">{1000 * st["seconds"]:.0f}</span> ms</div>')

    # -- events ---------------------------------------------------------------------------------
    def _on_slider(self, change):
        if self._muted:
            return
        self._muted = True
        try:                                  # the typed exact values no longer describe the state
            for box in self.exact_boxes:
                box.value = ""
        finally:
            self._muted = False
        q = np.array([s.value for s in self.sliders])
        self.set_q(q, _dragging=True)

    def _on_text(self, change):
        if self._muted or not change["new"].strip():
            return
        exact = []
        try:
            for j, box in enumerate(self.exact_boxes):
                text = box.value.strip()
                exact.append(parse_joint_value(text, f"q{j + 1}") if text else self.q[j])
            self.set_q(exact=exact)
        except InputError as e:
            self.status["error"] = str(e)
            self._draw_status()

    def set_q(self, q=None, exact=None, _dragging=False):
        """Show the joint values ``q`` (floats), or the exact values ``exact``: give one of the two.

        Parameters
        ----------
        q : (3,) float, optional
        exact : sequence of three numbers or sympy numbers, optional
            The status count is then certified on these exact values (slower: the exact path); the
            views show ``float(exact)``.

        Raises
        ------
        InputError
            ``q`` is not three finite numbers, ``exact`` not three finite values, or both or
            neither are given.
        TypeError
            Non-numeric values.

        Examples
        --------
        >>> import imagespace as isp
        >>> ex = isp.widgets.explore(isp.examples.stigger_husty())
        >>> ex.set_q([10.0, 15.0, 13.25]); ex.status["count"], ex.status["certified"]
        (4, True)
        """
        if (q is None) == (exact is None):
            raise InputError("give either q (three floats) or exact (three exact values), "
                             f"got q={q!r} and exact={exact!r}")
        if exact is not None:
            if isinstance(exact, (str, bytes)) or not hasattr(exact, "__len__") or len(exact) != 3:
                raise InputError(f"exact must be three exact joint values, got {exact!r}")
            exact = [as_exact(v, f"exact[{i}]") for i, v in enumerate(exact)]
            if any(v.free_symbols for v in exact):
                raise InputError(f"exact must hold numbers, not symbols, got {exact}")
            q = [float(v) for v in exact]
        qv = as_joint_vector(q)
        with self._draw:
            with self._lock:
                self._generation += 1
            self.q = qv.copy()
            self.plan = None
            self._muted = True
            try:
                for s, v in zip(self.sliders, qv):
                    if not s.min <= v <= s.max:
                        s.min, s.max = min(s.min, v), max(s.max, v)
                    s.value = float(v)
            finally:
                self._muted = False
            self._solve(qv, exact=exact)
            t0 = time.perf_counter()
            if self._surface is None or self._surface.kind != "joint-free":
                if _dragging:
                    self._schedule_refine()
                else:
                    self._remesh(self.resolution)
            self._hide_plan()
            self._draw_all()
            self.status["seconds"] += time.perf_counter() - t0
            self._draw_status()

    def _schedule_refine(self):
        """A joint-dependent surface while a slider moves: the shown mesh is dimmed (it belongs to
        earlier joint values), a coarse mesh for the latest values is made in the background, and a
        fine one once the sliders rest for :data:`REST_DELAY` seconds."""
        self._stale = True
        with self.figure.batch_update():
            self.trace("surface").update(opacity=0.15)
        self._queue(min(DRAG_RESOLUTION, self.resolution))
        if self._timer is not None:
            self._timer.cancel()
        self._timer = threading.Timer(REST_DELAY, self._queue, args=(self.resolution,))
        self._timer.daemon = True
        self._timer.start()

    def _queue(self, resolution):
        with self._lock:
            self._want = (self.q.copy(), resolution, self._generation)
            if self._working:
                return
            self._working = True
        threading.Thread(target=self._work, daemon=True).start()

    def _work(self):
        try:
            while True:
                with self._lock:
                    job, self._want = self._want, None
                    if job is None:
                        return
                q, resolution, generation = job
                try:
                    S, mesh = self._mesh_for(q, resolution, quiet=False)
                except Exception as e:                 # noqa: BLE001  (shown in the status line)
                    with self._draw:
                        self.status["error"] = f"re-meshing the singularity surface failed: {e}"
                        self._draw_status()
                    continue
                with self._draw:                       # the main thread may have moved on meanwhile
                    if generation == self._generation:
                        self._show_mesh(S, mesh, q, resolution)
                        self._draw_section()
        finally:
            with self._lock:
                self._working = False
                pending = self._want is not None
            if pending:
                self._queue(self._want[1])

    def wait(self, timeout=60.0):
        """Wait until background re-meshing (joint-dependent surfaces, after dragging) is done.

        Parameters
        ----------
        timeout : float
            Seconds at most.

        Returns
        -------
        bool
            True if nothing is left to do.

        Examples
        --------
        >>> import imagespace as isp
        >>> ex = isp.widgets.explore(isp.examples.collinear_3rpr(), resolution=16)   # joint-free: meshed once
        >>> ex.wait(), ex.trace("surface").name
        (True, 'singularity surface (joint-free, 16^3 grid)')
        """
        end = time.monotonic() + float(timeout)
        while time.monotonic() < end:
            with self._lock:
                timer_pending = self._timer is not None and self._timer.is_alive()
                idle = not self._working and self._want is None
            if idle and not timer_pending:
                return True
            time.sleep(0.02)
        return False

    def refine(self):
        """Mesh the surface at the rest resolution for the current joint values, now.

        Examples
        --------
        >>> import imagespace as isp
        >>> ex = isp.widgets.explore(isp.examples.collinear_3rpr(), resolution=16); ex.refine()
        >>> ex.trace("surface").name
        'singularity surface (joint-free, 16^3 grid)'
        """
        self._remesh(self.resolution)

    def _hide_plan(self):
        self.play.disabled = self.frame.disabled = True
        self.play.max = self.frame.max = 0
        self.plan_message.value = ""
        with self.figure.batch_update():
            for name in ("loop1", "loop2", "loop3", "now", "moving"):
                self.trace(name).update(x=[], y=[])
            for name in ("path", "position"):
                self.trace(name).update(x=[], y=[], z=[])
            self._title(3, "joint loop")

    # -- mode change ----------------------------------------------------------------------------
    def change_mode(self, a=None, b=None):
        """Plan a certified singularity-free path from mode ``a`` to mode ``b`` (0-based; default the
        two dropdowns) and show it; returns the :class:`ModeChangePlan` (or None with a message if no
        plan can be made for this design).

        Raises
        ------
        InputError
            ``a`` or ``b`` is not the index of a current mode.

        Examples
        --------
        >>> import imagespace as isp
        >>> ex = isp.widgets.explore(isp.examples.stigger_husty())
        >>> ex.change_mode(0, 1).found        # modes 1 and 2 have opposite aspects
        False
        """
        with self._draw:
            return self._change_mode(a, b)

    def _change_mode(self, a, b):
        from ._validate import as_index
        from .paths.modechange import plan_mode_change

        a = self.mode_a.value if a is None else a
        b = self.mode_b.value if b is None else b
        if a is None or b is None:
            self.plan_message.value = "<i>pick two modes first</i>"
            return None
        a, b = as_index(a, "a", len(self.modes)), as_index(b, "b", len(self.modes))
        if a == b:
            self.plan_message.value = "<i>pick two different modes</i>"
            return None
        try:
            plan = plan_mode_change(self.manipulator, self.q, self.modes[a], self.modes[b])
        except ImageSpaceError as e:
            self.plan = None
            self.play.playing = False
            self._hide_plan()
            self.plan_message.value = f'<span class="isp-plan">no plan: {html.escape(str(e))}</span>'
            return None
        self.plan = plan
        if not plan.found:
            self.play.playing = False
            self._hide_plan()
            self.plan_message.value = (f'<span class="isp-plan">mode {a + 1} &rarr; mode {b + 1}: '
                                       f'{html.escape(plan.reason)}</span>')
            return plan
        n = len(plan.poses)
        self.plan_message.value = (f'<span class="isp-plan">mode {a + 1} &rarr; mode {b + 1}: certified '
                                   f'singularity-free path found ({n} samples); press play</span>')
        from .core.kinematic_map import image_point

        C = chart_coordinates(image_point(plan.poses))
        J = plan.joint_loop - plan.joint_loop[0]
        with self.figure.batch_update():
            self.trace("path").update(x=C[:, 0], y=C[:, 1], z=C[:, 2])
            for i in range(3):
                self.trace(f"loop{i + 1}").update(x=np.arange(n), y=J[:, i])
            self._title(3, f"joint loop of the mode change {a + 1} -> {b + 1} (starts and ends at q)")
        self.play.max = self.frame.max = n - 1
        self.play.disabled = self.frame.disabled = False
        self._draw_frame(0)
        return plan

    def _draw_frame(self, k):
        with self._draw:
            self._draw_frame_locked(k)

    def _draw_frame_locked(self, k):
        plan = self.plan
        if plan is None or not plan.found:
            return
        k = int(min(max(k, 0), len(plan.poses) - 1))
        from .core.kinematic_map import image_point

        lines = mechanism_lines(self.manipulator, plan.poses[k], plan.joint_loop[k])
        xy = _joined(lines.legs + [lines.platform])
        C = chart_coordinates(image_point(plan.poses[k]))
        J = plan.joint_loop - plan.joint_loop[0]
        with self.figure.batch_update():
            self.trace("moving").update(x=xy[:, 0], y=xy[:, 1])
            self.trace("position").update(x=C[:, 0], y=C[:, 1], z=C[:, 2])
            self.trace("now").update(x=[k, k, k], y=J[k].tolist())

    def close(self):
        """Stop the background re-meshing and close the explorer's widgets (the figure included).

        Examples
        --------
        >>> import imagespace as isp
        >>> ex = isp.widgets.explore(isp.examples.collinear_3rpr(), resolution=16); ex.close(); ex.wait()
        True
        """
        lock = getattr(self, "_lock", None)     # also called by __del__ when __init__ refused its input
        if lock is not None:
            with lock:
                self._want = None
        if getattr(self, "_timer", None) is not None:
            self._timer.cancel()

        def close_tree(w):
            for child in getattr(w, "children", ()):
                close_tree(child)
            if w is not self:
                w.close()

        close_tree(self)
        super().close()

    # -- export ---------------------------------------------------------------------------------
    def save_html(self, path):
        """Write a standalone HTML page of the current state (status, pose, image-space, section and
        joint-loop views; plotly.js inlined) that opens in a browser without a kernel.

        Parameters
        ----------
        path : str or os.PathLike

        Returns
        -------
        pathlib.Path

        Raises
        ------
        OSError
            The file cannot be written (the folder is missing or not writable).

        Examples
        --------
        >>> import tempfile, pathlib, imagespace as isp
        >>> ex = isp.widgets.explore(isp.examples.collinear_3rpr(), resolution=16)
        >>> p = ex.save_html(pathlib.Path(tempfile.mkdtemp()) / "explorer.html")
        >>> "plotly" in p.read_text()
        True
        """
        import pathlib

        import plotly.io as pio

        parts = [pio.to_html(go.Figure(self.figure), include_plotlyjs=True, full_html=False)]
        q = ", ".join(f"{v:.10g}" for v in self.q)
        page = ("<!DOCTYPE html><html><head><meta charset='utf-8'><title>imagespace explorer: "
                f"{html.escape(self.manipulator.name)}</title></head><body style='font-family:sans-serif'>"
                f"<h2>{html.escape(self.manipulator.name)} at q = ({q})</h2>{self.status_line.value}"
                f"{self.plan_message.value}<div style='display:flex;flex-wrap:wrap'>"
                + "".join(f"<div>{p}</div>" for p in parts) + "</div></body></html>")
        path = pathlib.Path(path)
        atomic_write(path, lambda f: f.write(page.encode("utf-8")))
        return path
