"""The planar explorer: drag the joint values, watch the assembly modes move.

``isp.widgets.explore(m)`` returns an :class:`Explorer`, an ipywidgets layout with

- one slider per actuated joint (ranges from the design, :func:`joint_ranges`) and a text box that
  takes an exact value (``27/2``, ``-3*pi/4``; parsed by :func:`parse_joint_value`, never evaluated);
  the exact value stays the state until a slider is moved by the user (the slider showing it at its
  nearest grid step is not a move);
- a **pose view**: the mechanism in every real assembly mode, coloured by aspect (red: det J > 0,
  blue: det J < 0), each mode numbered, prismatic guides drawn. A mode keeps its number while it
  lives (modes are tracked from one joint vector to the next by the nearest image point of the same
  aspect; :class:`~imagespace.widgets.tracking.ModeTracker`); modes that merge are named in the
  status line. With no real mode the last drawing stays, greyed, and the view says why;
- an **image-space view**: the singularity surface meshed once (re-meshed when it depends on the
  joint values, coarsely while dragging and finer once the slider rests) as a rotatable 3D mesh in
  the chart ``(x2/x0, x3/x0, x1/x0)``, with the current modes as points;
- a **section view**: the fixed-orientation conic at the orientation of a chosen mode, with the two
  aspect regions;
- a status line: the certified number of real modes (certified on the float joint values shown, or
  on the exact value typed), a "near singular" badge where :class:`~imagespace.NearSingularWarning`
  applies, and the kernel's time for the update (solving and drawing; the browser's round trip and
  repaint come on top, measured in ``benchmarks/README.md``);
- "change mode": two modes of equal aspect are joined by a certified singularity-free path
  (:func:`imagespace.paths.modechange.plan_mode_change`); the path is sent to the browser once and
  played there (pose view, image space and joint loop); for opposite aspects the reason no such
  path exists is shown;
- with ``atlas=`` (a :class:`~imagespace.atlas.JointAtlas`, or True to compute one in the
  background), an **atlas panel**: the joint-space atlas in 3D (the count-change surface, one colour
  per pair of counts it separates, the cusp curves, the joint box) with a marker at ``q`` that
  follows the sliders and carries the certified count at ``q``; the status line names the atlas
  region (:mod:`~imagespace.widgets.planar_atlas`). A mode change's joint loop is drawn there too.

The panels are plotly figures drawn by one small widget (:mod:`imagespace.widgets.view`): each
update sends only the changed traces' data. :meth:`Explorer.save_html` writes a standalone page of
the same panels that opens without a kernel. Needs the ``imagespace[jupyter]`` extra.
"""

from __future__ import annotations

import html
import threading
import time
import warnings

import numpy as np

import ipywidgets as W

from .._validate import as_box, as_count, as_exact, as_joint_vector, as_seconds
from ..core.mechanism import check_mechanism
from ..drawing import CHART_LABELS, chart_coordinates, mechanism_lines
from ..exceptions import ImageSpaceError, InputError, NearSingularWarning
from .inputs import joint_ranges, parse_joint_value
from .planar_panels import joined_polylines, merged_labels, planar_panels, section_regions, status_html
from .tracking import ModeTracker
from .view import PanelView
from ..solve import front

__all__ = ["explore_planar", "Explorer", "REST_DELAY", "DRAG_RESOLUTION", "REST_RESOLUTION", "SECTION_GRID",
           "SLIDER_STEPS", "FRAME_RATE"]

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
FRAME_RATE = 30
"""Frames per second of a mode change played in the browser."""
_PHI_CHART = 3.0                 # default |x1/x0| = |tan(phi/2)| range of the image-space view
_LABEL_MERGE = 0.04              # mode labels closer than this fraction of the view are written once
_LABEL_MERGE_3D = 0.08           # the same in the image-space view's unit cube


def explore_planar(manipulator, q=None, box=None, resolution=REST_RESOLUTION, atlas=None):
    """The planar explorer (see :func:`imagespace.widgets.explore`)."""
    return Explorer(manipulator, q=q, box=box, resolution=resolution, atlas=atlas)


class Explorer(W.VBox):
    """The planar explorer's layout and state; made by :func:`imagespace.widgets.explore`.

    Attributes
    ----------
    manipulator : PlanarParallel
    q : (3,) float
        The joint values shown.
    modes : list of AssemblyMode
        The real assembly modes at ``q``, in the order of their numbers.
    mode_numbers : list of int
        The number shown for each mode (kept while the mode lives, so not always ``1..n``).
    status : dict
        ``count`` (real modes), ``certified`` (bool), ``near_singular`` (bool), ``exact`` (the
        count was certified on exact joint values typed in), ``seconds`` (the kernel's time for the
        last update: solving and drawing), ``error`` (a message, or None), ``events`` (modes that
        merged or appeared in the last update, or ""), ``atlas`` (None without the atlas panel, else
        a dict: ``state`` ("computing", "ready", "failed: ..."), ``inside`` (q in the atlas box),
        ``count`` (the certified count at q shown on the marker, None if not certified),
        ``certified``, ``region`` and ``region_count`` (the atlas region of the grid node nearest
        to q and that node's count)).
    plan : ModeChangePlan or None
        The last mode change planned.
    view : PanelView
        The four panels (pose, image space, section, joint loop), and the atlas panel when asked
        for; :meth:`trace` finds a trace.
    atlas : JointAtlas or None
        The atlas shown (None without the panel, or while it is computed).
    sliders : list of ipywidgets.FloatSlider
    exact_boxes : list of ipywidgets.Text
    """

    def __init__(self, manipulator, q=None, box=None, resolution=REST_RESOLUTION, atlas=None):
        check_mechanism(manipulator)
        if q is None:
            if manipulator.q_example_float is None:
                raise InputError("q is needed: this design has no q_example; pass the starting joint "
                                 "values, e.g. explore(m, q=m.inverse_kinematics(pose))")
            q = manipulator.q_example_float
        self.manipulator = manipulator
        self.q = as_joint_vector(q).copy()
        self.resolution = as_count(resolution, "resolution", minimum=8)
        if box is not None:
            box = as_box(box, dim=3)
        self._atlas_panel = None
        self._atlas_thread = None
        self._closed = False
        if atlas is not None:
            from .planar_atlas import AtlasPanel, check_atlas_option, default_atlas_box

            given, compute = check_atlas_option(atlas, manipulator)
            if given is not None:
                self._atlas_panel = AtlasPanel(manipulator, given.box, given)
            elif compute:
                self._atlas_panel = AtlasPanel(manipulator, default_atlas_box(manipulator, self.q))
        self.modes = []
        self.mode_numbers = []
        self.tracker = ModeTracker()
        self.plan = None
        self.status = {"count": 0, "certified": False, "near_singular": False, "exact": False,
                       "seconds": 0.0, "error": None, "events": "", "atlas": None}
        self._text_error = None           # the error a refused exact-value entry left, if any
        self._surface = None
        self._surface_q = None
        self._timer = None
        self._lock = threading.Lock()
        self._want = None
        self._working = False
        self._generation = 0             # bumped by every set_q: a background mesh of older q is dropped
        self._draw = threading.RLock()   # one thread draws at a time
        self._stale = False              # the surface shown belongs to earlier joint values
        self._mesh_resolution = 0
        self._muted = False
        self._last_drawing = np.zeros((0, 2))
        self._old_numbers = []
        self._warm = False                       # the batch path's kernel is loaded (background)
        ranges = joint_ranges(manipulator, self.q)
        self.sliders = []
        self.exact_boxes = []
        # a value set from Python comes back once from the browser, snapped to the slider's grid
        self._echo = [True, True, True]
        rows = []
        for i, leg in enumerate(manipulator.legs):
            lo, hi = ranges[i]
            # the slider snaps to min + k * step in the browser: align its grid with q so that the
            # starting joint values are shown (and solved) as given
            step = float(hi - lo) / SLIDER_STEPS
            lo = self.q[i] - np.floor((self.q[i] - lo) / step) * step
            hi = lo + SLIDER_STEPS * step
            unit = "rad" if leg.actuated_is_angle else "length units"
            s = W.FloatSlider(value=float(self.q[i]), min=float(lo), max=float(hi), step=step,
                              description=f"q{i + 1} {leg.actuated_name} [{unit}]",
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
        self.section_mode.observe(self._on_section_mode, "value")
        self.change_button = W.Button(description="change mode", button_style="primary",
                                      tooltip="plan a certified singularity-free path between mode A and mode B")
        self.change_button.on_click(lambda b: self.change_mode())
        self.plan_message = W.HTML()

        panels, order = planar_panels(), ["pose", "space", "section", "loop"]
        if self._atlas_panel is not None:
            from .planar_atlas import atlas_panel

            panels["atlas"] = atlas_panel(manipulator, self._atlas_panel.box)
            order.append("atlas")
        self.view = PanelView(panels, order=order, columns=[540, 610], urgent=["pose"], controls="loop")
        with self.view.quiet():                # the first state goes out once, as the widget's state
            self._solve(self.q, first=True)
            self._box = box if box is not None else self._initial_box()
            self.view.relayout("space", "scene", {**self.view.layout("space")["scene"], **self._scene()})
            self._title("space", "image space (meshing the singularity surface ...)")
            if self._atlas_panel is not None:
                if self._atlas_panel.atlas is not None:
                    self._atlas_panel.show_atlas(self.view, self._atlas_panel.atlas)
                else:
                    self._title("atlas", "joint-space atlas (computing in the background ...)")
            self._draw_all()
        # the surface is meshed in the background: the panels show first (wait() blocks until it is in)
        self._queue(self.resolution)
        if self._atlas_panel is not None and self._atlas_panel.atlas is None:
            self._atlas_thread = threading.Thread(target=self._compute_atlas, daemon=True)
            self._atlas_thread.start()
        controls = W.HBox([self.section_mode, self.mode_a, self.mode_b, self.change_button])
        super().__init__([W.VBox(rows), self.status_line, controls, self.plan_message, self.view])

    # -- figures --------------------------------------------------------------------------------
    def trace(self, name):
        """The trace called ``name`` (a read-only :class:`~imagespace.widgets.view.TraceView`).

        Names: ``guides``, ``last drawing``, ``legs+1``, ``legs-1``, ``platform+1``, ``platform-1``,
        ``base``, ``numbers``, ``moving`` (pose view); ``surface``, ``points+1``, ``points-1``,
        ``path``, ``position`` (image space); ``regions`` (the conic and its aspect regions),
        ``section+1``, ``section-1`` (section view); ``loop1``..``loop3``, ``now`` (joint loop);
        with the atlas panel ``atlas sheet 0``..``atlas sheet 5`` (the count-change surface, one
        sheet per pair of counts), ``atlas cusps``, ``atlas box``, ``atlas q`` (the marker at q),
        ``atlas loop`` and ``atlas position`` (a mode change's joint loop).

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
        return self.view.trace(name)

    def figures(self):
        """The panels as ``plotly.graph_objects.Figure`` objects, by panel name (``pose``,
        ``space``, ``section``, ``loop``, and ``atlas`` with the atlas panel).

        Examples
        --------
        >>> import imagespace as isp
        >>> ex = isp.widgets.explore(isp.examples.collinear_3rpr(), resolution=16)
        >>> sorted(ex.figures())
        ['loop', 'pose', 'section', 'space']
        """
        return self.view.figures()

    def _title(self, panel, text):
        self.view.relayout(panel, "title.text", text)

    def _initial_box(self):
        C = chart_coordinates(np.array([mm.image_point for mm in self.modes])) if self.modes else np.zeros((1, 3))
        C = C[np.all(np.isfinite(C), axis=1)]
        half = max(2.0 * float(np.max(np.abs(C[:, :2]))) if len(C) else 1.0, 1.0)
        return np.array([[-half, half], [-half, half], [-_PHI_CHART, _PHI_CHART]])

    def _scene(self):
        b = self._box
        return {"xaxis": {"title": {"text": CHART_LABELS[0]}, "range": list(map(float, b[0]))},
                "yaxis": {"title": {"text": CHART_LABELS[1]}, "range": list(map(float, b[1]))},
                "zaxis": {"title": {"text": CHART_LABELS[2]}, "range": list(map(float, b[2]))},
                "aspectmode": "cube"}

    # -- computation ----------------------------------------------------------------------------
    def _solve(self, q, exact=None, first=False):
        """Certified real modes at ``q`` (float batch path), or at the exact values ``exact``.

        ``first``: the per-call certified path (no compiled kernel to load: the page shows sooner);
        the batch path's kernel is loaded in the background afterwards (:meth:`_work`)."""
        t0 = time.perf_counter()
        m = self.manipulator
        err = None
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                if exact is not None or first:
                    cm = front.direct_kinematics(m, exact if exact is not None else np.asarray(q, dtype=float), certify=True)
                    modes, certified, near = list(cm), bool(cm.certificate.certified), False
                else:
                    res = front.direct_kinematics_batch(m, np.asarray(q, dtype=float)[None], certify=True)
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
        numbers = self.tracker.update(np.array([mm.image_point for mm in modes]).reshape(len(modes), -1)
                                      if modes else np.zeros((0, 4)), [mm.aspect for mm in modes])
        order = np.argsort(numbers, kind="stable")
        self.modes = [modes[k] for k in order]
        self.mode_numbers = [numbers[k] for k in order]
        self.status = {"count": len(modes), "certified": certified and err is None, "near_singular": near,
                       "exact": exact is not None, "seconds": time.perf_counter() - t0, "error": err,
                       "events": self.tracker.message, "atlas": self.status.get("atlas")}

    def _mesh_for(self, q, resolution, quiet=True):
        """``(surface, mesh)`` at joint values ``q``; raises ImageSpaceError (the caller reports it).

        ``quiet``: the mesher's warnings are silenced (main thread only: ``warnings.catch_warnings``
        changes process-wide state, so the background thread never uses it)."""
        from ..singular.meshing import mesh_surface

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
        V, F = np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces).astype(np.int32)
        self.view.set("surface", x=V[:, 0].copy(), y=V[:, 1].copy(), z=V[:, 2].copy(), i=F[:, 0].copy(),
                      j=F[:, 1].copy(), k=F[:, 2].copy(), opacity=0.3 if self._plan_shown() else 0.5,
                      name=f"singularity surface ({S.kind}, {resolution}^3 grid)")

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
    def _labels(self):
        return [f"{n} ({mm.aspect:+d})" for n, mm in zip(self.mode_numbers, self.modes)]

    def _draw_all(self):
        self._update_dropdowns()
        with self.view.batch():
            self._draw_pose()
            self._draw_space()
            self._draw_section()
            self._draw_atlas()
        self._draw_status()

    def _draw_atlas(self):
        """The atlas marker at q with the count just certified (only the marker's trace changes)."""
        if self._atlas_panel is not None:
            self.status["atlas"] = dict(self._atlas_panel.marker(self.view, self.q, self.status))

    def _compute_atlas(self):
        """The atlas of ``atlas=True``, in the background (the panels show first)."""
        from ..atlas import joint_atlas
        from .planar_atlas import ATLAS_RESOLUTION

        panel = self._atlas_panel
        try:
            atlas = joint_atlas(self.manipulator, panel.box, ATLAS_RESOLUTION)
        except Exception as e:                 # noqa: BLE001  (shown in the status line)
            with self._draw:
                panel.failed(self.view, str(e))
                self.status["error"] = self.status["error"] or f"computing the atlas failed: {e}"
                self._draw_atlas()
                self._draw_status()
            return
        if self._closed:
            return
        with self._draw:
            with self.view.batch():
                panel.show_atlas(self.view, atlas)
                self._draw_atlas()
            self._draw_status()

    @property
    def atlas(self):
        return None if self._atlas_panel is None else self._atlas_panel.atlas

    def _update_dropdowns(self):
        options = list(zip(self._labels(), range(len(self.modes))))
        if self.section_mode.options == tuple(options) or list(self.section_mode.options) == options:
            return
        chosen = {}
        for key, dd in (("a", self.mode_a), ("b", self.mode_b), ("s", self.section_mode)):
            v = dd.value
            chosen[key] = self._old_numbers[v] if v is not None and v < len(getattr(self, "_old_numbers", [])) else None
        self._muted = True
        try:
            for key, dd, default in (("a", self.mode_a, 0), ("b", self.mode_b, 1), ("s", self.section_mode, 0)):
                dd.options = options
                if not options:
                    continue
                n = chosen[key]
                dd.value = self.mode_numbers.index(n) if n in self.mode_numbers else min(default, len(options) - 1)
        finally:
            self._muted = False
        self._old_numbers = list(self.mode_numbers)

    def _draw_pose(self):
        m = self.manipulator
        guides, legs, plats, base, centres = [], {1: [], -1: []}, {1: [], -1: []}, [], []
        for mm in self.modes:
            lines = mechanism_lines(m, mm.pose, self.q)
            a = 1 if mm.aspect >= 0 else -1
            guides += list(lines.guides)
            for L in lines.legs:
                legs[a].append(L)
                base.append(L[0])
            plats[a].append(lines.platform)
            centres.append(lines.platform[:3].mean(axis=0))
        B = np.array(base) if base else np.zeros((0, 2))
        C = np.array(centres) if centres else np.zeros((0, 2))
        size = float(np.ptp(B, axis=0).max()) if len(B) > 1 else 1.0
        q_text = ", ".join(f"{v:.4g}" for v in self.q)
        v = self.view
        if self.modes:
            for name, polys in (("guides", guides), ("legs+1", legs[1]), ("legs-1", legs[-1]),
                                ("platform+1", plats[1]), ("platform-1", plats[-1])):
                xy = joined_polylines(polys)
                v.set(name, x=xy[:, 0], y=xy[:, 1])
            self._last_drawing = joined_polylines(guides + legs[1] + legs[-1] + plats[1] + plats[-1])
            v.set("last drawing", x=np.zeros(0), y=np.zeros(0))
            v.set("base", x=B[:, 0], y=B[:, 1])
            v.set("numbers", x=C[:, 0], y=C[:, 1], text=merged_labels(C, self.mode_numbers, _LABEL_MERGE * size))
            v.relayout("pose", "annotations", [])
            n = len(self.modes)
            self._title("pose", f"pose view: {n} real assembly mode{'' if n == 1 else 's'} at q = ({q_text})")
        else:
            for name in ("guides", "legs+1", "legs-1", "platform+1", "platform-1", "base"):
                v.set(name, x=np.zeros(0), y=np.zeros(0))
            v.set("numbers", x=np.zeros(0), y=np.zeros(0), text=[])
            v.set("last drawing", x=self._last_drawing[:, 0], y=self._last_drawing[:, 1])
            why = ("no real assembly mode for these joint values: the legs cannot be assembled"
                   if not self.status["error"] else "no modes: " + self.status["error"][:80])
            v.relayout("pose", "annotations", [{"text": why + "<br>(the last drawing, greyed)", "xref": "paper",
                                                "yref": "paper", "x": 0.5, "y": 0.98, "showarrow": False,
                                                "font": {"size": 12, "color": "#b00"}, "bgcolor": "rgba(255,255,255,0.8)"}])
            self._title("pose", f"pose view: no real assembly mode at q = ({q_text})")
        v.set("moving", x=np.zeros(0), y=np.zeros(0))

    def _draw_space(self):
        C = chart_coordinates(np.array([mm.image_point for mm in self.modes])) if self.modes else np.zeros((0, 3))
        # labels of points close together on screen are written once ("1, 3"): the chart's axes have
        # different spans, so closeness is judged in the box's unit cube
        unit = (C - self._box[:, 0]) / (self._box[:, 1] - self._box[:, 0])
        labels = merged_labels(unit, self.mode_numbers, _LABEL_MERGE_3D)
        for a in (1, -1):
            ks = [k for k, mm in enumerate(self.modes) if (1 if mm.aspect >= 0 else -1) == a]
            self.view.set(f"points{a:+d}", x=C[ks, 0], y=C[ks, 1], z=C[ks, 2], text=[labels[k] for k in ks])
        if self.plan is None:
            for name in ("path", "position"):
                self.view.set(name, x=np.zeros(0), y=np.zeros(0), z=np.zeros(0))

    def _on_section_mode(self, change):
        if not self._muted:
            with self._draw:
                self._draw_section()

    def _draw_section(self):
        v = self.view
        if not self.modes or self._surface is None or self.section_mode.value is None:
            with v.batch():
                v.set("regions", x=np.zeros(0), y=np.zeros(0), z=np.zeros((0, 0)))
                for a in (1, -1):
                    v.set(f"section{a:+d}", x=np.zeros(0), y=np.zeros(0), text=[])
                self._title("section", "section view (no mode)" if not self.modes else "section view (surface not meshed yet)")
            return
        k = min(int(self.section_mode.value), len(self.modes) - 1)
        mode = self.modes[k]
        phi = float(mode.pose[2])
        xs, ys, Z = section_regions(self._surface.section_coefficients(phi), self.modes, k, SECTION_GRID)
        same = [j for j, mm in enumerate(self.modes) if abs(np.remainder(mm.pose[2] - phi + np.pi, 2 * np.pi) - np.pi)
                <= self.manipulator.tolerances.plot_orientation]
        with v.batch():
            v.set("regions", x=xs, y=ys, z=Z)
            for a in (1, -1):
                js = [j for j in same if (1 if self.modes[j].aspect >= 0 else -1) == a]
                v.set(f"section{a:+d}", x=np.array([self.modes[j].pose[0] for j in js]),
                      y=np.array([self.modes[j].pose[1] for j in js]), text=[str(self.mode_numbers[j]) for j in js])
            # the ranges are the grid's: the shading fills the panel (no white bands)
            v.relayout("section", "xaxis.range", [float(xs[0]), float(xs[-1])])
            v.relayout("section", "yaxis.range", [float(ys[0]), float(ys[-1])])
            self._title("section", f"section at phi = {np.degrees(phi):.3f} deg (mode {self.mode_numbers[k]}): "
                                   "red det J > 0, blue det J < 0"
                                   + (" [surface of earlier joint values, updating]" if self._stale else ""))

    def _draw_status(self):
        atlas = None if self._atlas_panel is None else self._atlas_panel.status_html()
        self.status_line.value = status_html(self.status, self.q, self.modes, self.mode_numbers, atlas)

    # -- events ---------------------------------------------------------------------------------
    def _on_slider(self, change):
        if self._muted:
            return
        i = next((k for k, s in enumerate(self.sliders) if s is change["owner"]), None)
        if i is not None and self._echo[i]:
            self._echo[i] = False
            if abs(change["new"] - self.q[i]) <= 0.5 * self.sliders[i].step * (1 + 1e-9):
                # the browser shows a value set from here at its nearest grid step and reports that
                # back once: not a move by the user (an exact value typed stays the state)
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
        if self._muted:
            return
        if not change["new"].strip():
            # an emptied box: its refused entry no longer stands, so neither does its error
            if self.status.get("error") and self.status["error"] == self._text_error:
                self.status["error"] = None
                self._draw_status()
            return
        exact = []
        try:
            for j, box in enumerate(self.exact_boxes):
                text = box.value.strip()
                exact.append(parse_joint_value(text, f"q{j + 1}") if text else self.q[j])
            self.set_q(exact=exact)
        except InputError as e:
            self.status["error"] = self._text_error = str(e)
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
                for i, (s, v) in enumerate(zip(self.sliders, qv)):
                    if not s.min <= v <= s.max:
                        s.min, s.max = min(s.min, v), max(s.max, v)
                    if s.value != float(v):
                        s.value = float(v)
                        self._echo[i] = True
            finally:
                self._muted = False
            self._solve(qv, exact=exact)
            t0 = time.perf_counter()
            self._update_dropdowns()
            with self.view.batch():
                if self._surface is None and self._working:
                    pass                               # the first surface is still being meshed
                elif self._surface is None or self._surface.kind != "joint-free":
                    if _dragging:
                        self._schedule_refine()
                    else:
                        self._remesh(self.resolution)
                self._hide_plan()
                self._draw_pose()
                self._draw_space()
                self._draw_section()
                self._draw_atlas()
            self.status["seconds"] += time.perf_counter() - t0
            self._draw_status()

    def _schedule_refine(self):
        """A joint-dependent surface while a slider moves: the shown mesh is dimmed (it belongs to
        earlier joint values), a coarse mesh for the latest values is made in the background, and a
        fine one once the sliders rest for :data:`REST_DELAY` seconds."""
        self._stale = True
        self.view.set("surface", opacity=0.15)
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
        if not self._warm:
            self._warm = True
            try:                                   # load the batch path's compiled kernel once, off the page's way
                front.direct_kinematics_batch(self.manipulator, self.q[None], certify=True)
            except ImageSpaceError:
                pass
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
                    if generation == self._generation or S.kind == "joint-free":
                        first = self._surface is None
                        # the first surface goes out as the whole state (also what a page saved later holds)
                        with (self.view.quiet() if first else self.view.batch()):
                            self._show_mesh(S, mesh, q, resolution)
                            self._title("space", "image space")
                            self._draw_section()
        finally:
            with self._lock:
                self._working = False
                pending = self._want is not None
            if pending:
                self._queue(self._want[1])

    def wait(self, timeout=60.0):
        """Wait until background work (re-meshing the surface, computing the atlas of
        ``atlas=True``) is done.

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
        end = time.monotonic() + as_seconds(timeout, "timeout")
        while time.monotonic() < end:
            with self._lock:
                timer_pending = self._timer is not None and self._timer.is_alive()
                idle = not self._working and self._want is None
                if self._atlas_thread is not None and self._atlas_thread.is_alive():
                    idle = False
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
        with self._draw:
            self._remesh(self.resolution)

    def _plan_shown(self):
        return self.plan is not None and self.plan.found

    def _hide_plan(self):
        self.plan_message.value = ""
        self.view.set_frames(None)
        with self.view.batch():
            for name in ("loop1", "loop2", "loop3", "now", "moving"):
                self.view.set(name, x=np.zeros(0), y=np.zeros(0))
            for name in ("path", "position"):
                self.view.set(name, x=np.zeros(0), y=np.zeros(0), z=np.zeros(0))
            self.view.set("surface", opacity=0.15 if self._stale else 0.5)
            self._title("loop", "joint loop")
            if self._atlas_panel is not None:
                self._atlas_panel.hide_loop(self.view)

    # -- mode change ----------------------------------------------------------------------------
    def change_mode(self, a=None, b=None):
        """Plan a certified singularity-free path from mode ``a`` to mode ``b`` (0-based indices into
        :attr:`modes`, shown with the numbers ``mode_numbers[a]``, ``mode_numbers[b]``; default the
        two dropdowns) and show it; returns the :class:`ModeChangePlan` (or None with a message if no
        plan can be made for this design). The path is sent to the browser once and played there.

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
        from .._validate import as_index
        from ..paths.modechange import plan_mode_change

        a = self.mode_a.value if a is None else a
        b = self.mode_b.value if b is None else b
        if a is None or b is None:
            self.plan_message.value = "<i>pick two modes first</i>"
            return None
        a, b = as_index(a, "a", len(self.modes)), as_index(b, "b", len(self.modes))
        if a == b:
            self.plan_message.value = "<i>pick two different modes</i>"
            return None
        na, nb = self.mode_numbers[a], self.mode_numbers[b]
        try:
            plan = plan_mode_change(self.manipulator, self.q, self.modes[a], self.modes[b])
        except ImageSpaceError as e:
            self.plan = None
            self._hide_plan()
            self.plan_message.value = f'<span class="isp-plan">no plan: {html.escape(str(e))}</span>'
            return None
        if not plan.found:
            self.plan = None
            self._hide_plan()
            self.plan = plan
            self.plan_message.value = (f'<span class="isp-plan">mode {na} &rarr; mode {nb}: '
                                       f'{html.escape(plan.reason)}</span>')
            return plan
        self.plan = plan
        n = len(plan.poses)
        self.plan_message.value = (f'<span class="isp-plan">mode {na} &rarr; mode {nb}: certified '
                                   f'singularity-free path found ({n} samples); press play below the '
                                   f'image space (played in the browser at {FRAME_RATE} frames/s)</span>')
        from ..core.kinematic_map import image_point

        C = chart_coordinates(image_point(plan.poses))
        J = plan.joint_loop - plan.joint_loop[0]
        with self.view.batch():
            self.view.set("path", x=C[:, 0], y=C[:, 1], z=C[:, 2])
            self.view.set("surface", opacity=0.3)
            for i in range(3):
                self.view.set(f"loop{i + 1}", x=np.arange(n, dtype=float), y=J[:, i])
            if self._atlas_panel is not None:
                self._atlas_panel.show_loop(self.view, plan.joint_loop)
            self._title("loop", f"joint loop of the mode change {na} -> {nb} (starts and ends at q)")
        self.view.set_frames(self._frames(plan, C, J), interval=1.0 / FRAME_RATE)
        self.show_frame(0)
        return plan

    def _frames(self, plan, C, J):
        """Every sample of the plan as frames: the moving drawing, the image point, the joint loop."""
        moving = [joined_polylines(list(mechanism_lines(self.manipulator, p, jq).legs)
                          + [mechanism_lines(self.manipulator, p, jq).platform])
                  for p, jq in zip(plan.poses, plan.joint_loop)]
        width = max(len(xy) for xy in moving)
        mx = np.full((len(moving), width), np.nan)
        my = np.full((len(moving), width), np.nan)
        for k, xy in enumerate(moving):
            mx[k, :len(xy)], my[k, :len(xy)] = xy[:, 0], xy[:, 1]
        n = len(plan.poses)
        frames = {"moving": {"x": mx, "y": my},
                  "position": {"x": C[:, :1], "y": C[:, 1:2], "z": C[:, 2:3]},
                  "now": {"x": np.repeat(np.arange(n, dtype=float)[:, None], 3, axis=1), "y": J}}
        if self._atlas_panel is not None:
            frames.update(self._atlas_panel.frames(plan.joint_loop))
        return frames

    def show_frame(self, k):
        """Show sample ``k`` of the planned mode change (as the browser's play control does).

        Examples
        --------
        >>> import imagespace as isp
        >>> ex = isp.widgets.explore(isp.examples.stigger_husty())
        >>> neg = [k for k, mm in enumerate(ex.modes) if mm.aspect < 0]
        >>> ex.change_mode(neg[0], neg[1]).found and ex.show_frame(5) is None
        True
        """
        with self._draw:
            if self.plan is None or not self.plan.found:
                return
            self.view.show_frame(int(min(max(k, 0), len(self.plan.poses) - 1)))

    def close(self):
        """Stop the background re-meshing and close the explorer's widgets.

        Examples
        --------
        >>> import imagespace as isp
        >>> ex = isp.widgets.explore(isp.examples.collinear_3rpr(), resolution=16); ex.close(); ex.wait()
        True
        """
        self._closed = True                     # an atlas still being computed is dropped
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
        joint-loop views; plotly.js inlined) that opens in a browser without a kernel. Waits for the
        background meshing first (:meth:`wait`).

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
        self.wait()                            # the surface meshed in the background belongs on the page
        q = ", ".join(f"{v:.10g}" for v in self.q)
        name = html.escape(self.manipulator.name)
        header = f"<h2>{name} at q = ({q})</h2>{self.status_line.value}{self.plan_message.value}"
        return self.view.save(path, f"imagespace explorer: {self.manipulator.name}", header)
