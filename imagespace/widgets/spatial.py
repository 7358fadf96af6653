"""The Gough-Stewart explorer: six leg-length sliders, the platform in every real assembly mode.

``isp.widgets.explore(gs)`` (a :class:`~imagespace.spatial.gough_stewart.GoughStewart`) returns a
:class:`SpatialExplorer`:

- six leg-length sliders (ranges from the design: each length +- half the design's size);
- a status line with the **fast** count (the parameter homotopy, ~20 ms, with its reliability flag:
  every float check passed or not) at once, then the **certified** count (Krawczyk boxes in arb on
  the exact quadrics, msolve where they do not settle it; computed in the background, 0.1-0.4 s);
- a **3D view** of the platform in every real mode: base grey, legs and platform red where
  ``det J > 0`` and blue where ``det J < 0``, each mode numbered (a mode keeps its number while it
  lives: :class:`~imagespace.widgets.tracking.ModeTracker` on the Study points);
- a **constant-orientation singularity section** through the chosen mode: the exact cubic
  ``det J(x, y, z) = 0`` of the mode's orientation
  (:func:`~imagespace.spatial.singularities.constant_orientation_singularity`) in the horizontal
  plane through the mode's position, with the two aspect regions and the mode's position.

Needs the ``imagespace[jupyter]`` extra.
"""

from __future__ import annotations

import html
import json
import threading
import time
import warnings

import numpy as np

import ipywidgets as W

from .._validate import as_box, as_seconds
from ..drawing import ASPECT_COLOURS
from ..exceptions import ImageSpaceError, InputError, InputTypeError, NearSingularWarning
from .planar_panels import merged_labels
from .tracking import ModeTracker
from .view import PanelView

__all__ = ["SpatialExplorer", "default_lengths", "length_ranges", "SPATIAL_SECTION_GRID", "LENGTH_STEPS",
           "MAX_LENGTH_RATIO"]

SPATIAL_SECTION_GRID = 120
"""Grid points per axis of the singularity section."""
LENGTH_STEPS = 1000
"""Steps across a leg-length slider's range."""
MAX_LENGTH_RATIO = 1e6
"""Leg lengths beyond this many times the design's size are refused (an absurd input, answered at
once rather than by a homotopy that overflows)."""
_LABEL_MERGE = 0.05


def _size(gs):
    """The design's size: the spread of the base anchors plus that of the platform anchors."""
    return float(np.max(np.ptp(gs.base_points, axis=0)) + np.max(np.ptp(gs.platform_points, axis=0)))


def default_lengths(gs):
    """Leg lengths of the platform parallel to the base, centred above it at the design's size.

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.widgets.spatial import default_lengths
    >>> gs = isp.GoughStewart(np.eye(3).tolist() + (-np.eye(3)).tolist(), (0.5 * np.eye(3)).tolist() + (-0.5 * np.eye(3)).tolist())
    >>> default_lengths(gs).shape
    (6,)
    """
    from ..spatial.study import study_point

    centre = gs.base_points.mean(axis=0) - gs.platform_points.mean(axis=0)
    return gs.inverse_kinematics(study_point([1.0, 0.0, 0.0, 0.0], centre + [0.0, 0.0, _size(gs)]))


def length_ranges(gs, lengths):
    """Slider ranges ``(6, 2)``: each length +- half the design's size, at least 2 % of it above 0.

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.widgets.spatial import length_ranges
    >>> gs, L = isp.examples.dietmaier_1998()
    >>> r = length_ranges(gs, L)
    >>> bool(np.all((r[:, 0] < L) & (L < r[:, 1]) & (r[:, 0] > 0)))
    True
    """
    half = 0.5 * _size(gs)
    L = np.asarray(lengths, dtype=float)
    return np.column_stack([np.maximum(L - half, 0.02 * 2 * half), L + half])


def _panels():
    def s3(meta, name, **kw):
        return {"type": "scatter3d", "meta": meta, "name": name, "x": np.zeros(0), "y": np.zeros(0),
                "z": np.zeros(0), **kw}

    plat = [s3("base", "base", mode="lines+markers", line={"color": "#555555", "width": 5},
               marker={"color": "black", "size": 3})]
    for a in (1, -1):
        # every mode thin and faint; the chosen one bold (below)
        plat.append(s3(f"legs{a:+d}", f"legs, aspect {a:+d}", mode="lines", showlegend=False,
                       line={"color": ASPECT_COLOURS[a], "width": 1.5}, opacity=0.3, legendgroup=f"aspect{a:+d}"))
        plat.append(s3(f"platform{a:+d}", f"platform, aspect {a:+d} ({'det J > 0' if a > 0 else 'det J < 0'})",
                       mode="lines", line={"color": ASPECT_COLOURS[a], "width": 3}, opacity=0.5,
                       legendgroup=f"aspect{a:+d}"))
    plat += [{"type": "mesh3d", "meta": "chosen platform", "name": "the chosen mode", "x": np.zeros(0),
              "y": np.zeros(0), "z": np.zeros(0), "i": np.zeros(0, np.int32), "j": np.zeros(0, np.int32),
              "k": np.zeros(0, np.int32), "color": ASPECT_COLOURS[1], "opacity": 0.75, "flatshading": True,
              "showlegend": True, "hoverinfo": "skip"},
             s3("chosen", "the chosen mode's legs", mode="lines", line={"color": "black", "width": 7},
                showlegend=False),
             s3("numbers", "mode numbers", mode="text", text=[], showlegend=False,
                textfont={"size": 11, "color": "#333333"})]
    plat_layout = {"width": 620, "height": 600, "margin": {"l": 0, "r": 0, "t": 50, "b": 0}, "uirevision": "keep",
                   "title": {"text": "platform", "font": {"size": 13}},
                   "legend": {"font": {"size": 10}, "orientation": "h", "y": 0.02, "x": 0.02},
                   "scene": {"aspectmode": "data", "domain": {"x": [0.02, 0.98], "y": [0.08, 1.0]},
                             "xaxis": {"title": {"text": "x [length units]"}},
                             "yaxis": {"title": {"text": "y [length units]"}},
                             "zaxis": {"title": {"text": "z [length units]"}},
                             "camera": {"eye": {"x": 1.6, "y": -1.6, "z": 0.9}}}}
    section = [{"type": "contour", "meta": "regions", "name": "det J = 0 (orientation of the chosen mode)",
                "x": np.zeros(0), "y": np.zeros(0), "z": np.zeros((0, 0)), "showscale": False, "hoverinfo": "skip",
                "contours": {"start": 0, "end": 0, "size": 1, "coloring": "fill"}, "showlegend": True,
                "opacity": 0.45, "line": {"color": "black", "width": 2},
                "colorscale": [[0, ASPECT_COLOURS[-1]], [1, ASPECT_COLOURS[1]]]},
               {"type": "scatter", "meta": "position", "name": "the chosen mode's position", "x": np.zeros(0),
                "y": np.zeros(0), "mode": "markers+text", "textposition": "top center", "text": [],
                "marker": {"color": "black", "size": 11, "symbol": "x"}}]
    section_layout = {"width": 520, "height": 600, "margin": {"l": 60, "r": 10, "t": 50, "b": 45},
                      "uirevision": "keep", "title": {"text": "singularity section", "font": {"size": 13}},
                      "xaxis": {"title": {"text": "x [length units]"}, "constrain": "domain"},
                      "yaxis": {"title": {"text": "y [length units]"}, "scaleanchor": "x", "scaleratio": 1,
                                "constrain": "domain"},
                      "legend": {"font": {"size": 10}, "orientation": "h", "y": -0.12}}
    return {"platform": {"data": plat, "layout": plat_layout}, "section": {"data": section, "layout": section_layout}}


def _checked(gs, L):
    """Six positive finite leg lengths, not absurdly long for the design (:data:`MAX_LENGTH_RATIO`)."""
    from ..spatial.platform import check_lengths

    L = check_lengths(L, "L").astype(float).copy()
    limit = MAX_LENGTH_RATIO * _size(gs)
    if np.any(L > limit):
        raise InputError(f"L must be at most {MAX_LENGTH_RATIO:g} times the design's size ({limit:.4g}), got "
                         f"{float(L.max()):.4g}")
    return L


def _joined3(polys):
    if not polys:
        return np.zeros((0, 3))
    gap = np.full((1, 3), np.nan)
    return np.concatenate([part for P in polys for part in (np.asarray(P, dtype=float), gap)])


class SpatialExplorer(W.VBox):
    """The Gough-Stewart explorer's layout and state; made by :func:`imagespace.widgets.explore`.

    Attributes
    ----------
    gs : GoughStewart
    lengths : (6,) float
        The leg lengths shown.
    result : SpatialDKResult
        The fast path's result at ``lengths`` (modes in the order of their numbers).
    certified : SpatialDKResult or None
        The certified result (None while it is computed in the background, or if it failed).
    mode_numbers : list of int
        The number shown for each mode of ``result``.
    status : dict
        ``fast_count``, ``reliable``, ``certified_count`` (None until known), ``certified``
        (bool), ``seconds`` (the kernel's time for the fast update), ``error``, ``events``.
    view : PanelView
        The panels ``platform`` (3D) and ``section``; :meth:`trace` finds a trace.
    sliders : list of ipywidgets.FloatSlider
    """

    def __init__(self, gs, L=None, box=None):
        from ..spatial.gough_stewart import GoughStewart

        if not isinstance(gs, GoughStewart):
            raise InputTypeError(f"gs must be a GoughStewart platform, got {type(gs).__name__}")
        gs.check_design()
        self.gs = gs
        self.lengths = _checked(gs, default_lengths(gs) if L is None else L)
        self.box = None if box is None else as_box(box, dim=3)
        self.tracker = ModeTracker()
        self.mode_numbers = []
        self.result = None
        self.certified = None
        self.status = {"fast_count": 0, "reliable": False, "certified_count": None, "certified": False,
                       "seconds": 0.0, "error": None, "events": ""}
        self._lock = threading.Lock()
        self._draw = threading.RLock()
        self._generation = 0
        self._working = False
        self._want = None
        self._muted = False
        self._echo = [True] * 6
        self._section_generation = -1
        ranges = length_ranges(gs, self.lengths)
        self.sliders = []
        for i in range(6):
            lo, hi = ranges[i]
            step = float(hi - lo) / LENGTH_STEPS
            lo = self.lengths[i] - np.floor((self.lengths[i] - lo) / step) * step
            s = W.FloatSlider(value=float(self.lengths[i]), min=float(lo), max=float(lo + LENGTH_STEPS * step),
                              step=step, description=f"L{i + 1} [length units]", continuous_update=True,
                              readout_format=".4f", style={"description_width": "120px"},
                              layout=W.Layout(width="440px"))
            s.observe(self._on_slider, "value")
            self.sliders.append(s)
        self.status_line = W.HTML()
        self.section_mode = W.Dropdown(description="section at", layout=W.Layout(width="190px"))
        self.section_mode.observe(self._on_section_mode, "value")
        self.view = PanelView(_panels(), order=["platform", "section"], columns=[620, 520], urgent=["platform"])
        self.show_all = W.Checkbox(value=True, description="all modes (else the chosen one only)",
                                   style={"description_width": "initial"})
        self.show_all.observe(self._on_section_mode, "value")
        with self.view.quiet():
            self._solve()
            self._update_dropdown()
            self._draw_platform()
            self._draw_section()
            self._draw_status()
        self._queue()
        sliders = W.HBox([W.VBox(self.sliders[:3]), W.VBox(self.sliders[3:])])
        super().__init__([sliders, self.status_line, W.HBox([self.section_mode, self.show_all]), self.view])

    # -- state ----------------------------------------------------------------------------------
    def trace(self, name):
        """The trace called ``name`` (a read-only :class:`~imagespace.widgets.view.TraceView`): ``base``,
        ``legs+1``, ``legs-1``, ``platform+1``, ``platform-1``, ``chosen platform``, ``chosen``, ``numbers``
        (3D view);
        ``regions``, ``position`` (section).

        Examples
        --------
        >>> import imagespace as isp
        >>> gs, L = isp.examples.dietmaier_1998()
        >>> ex = isp.widgets.explore(gs, L)
        >>> ex.wait() and ex.status["certified_count"]
        40
        """
        return self.view.trace(name)

    def set_lengths(self, L):
        """Show the leg lengths ``L`` (six positive numbers): the fast count now, the certified count
        and the section in the background (:meth:`wait` waits for them).

        Raises
        ------
        InputError
            ``L`` not six positive finite numbers.

        Examples
        --------
        >>> import imagespace as isp
        >>> gs, L = isp.examples.dietmaier_1998()
        >>> ex = isp.widgets.explore(gs, L)
        >>> ex.set_lengths(L * 1.001); ex.wait(), ex.status["certified_count"]
        (True, 28)
        """
        L = _checked(self.gs, L)
        with self._draw:
            with self._lock:
                self._generation += 1
            self.lengths = L.copy()
            self._muted = True
            try:
                for i, (s, v) in enumerate(zip(self.sliders, L)):
                    if not s.min <= v <= s.max:
                        s.min, s.max = min(s.min, v), max(s.max, v)
                    if s.value != float(v):
                        s.value = float(v)
                        self._echo[i] = True
            finally:
                self._muted = False
            self._solve()
            t0 = time.perf_counter()
            self._update_dropdown()
            self._draw_platform()
            self.status["seconds"] += time.perf_counter() - t0
            self._draw_status()
        self._queue()

    def wait(self, timeout=60.0):
        """Wait for the background work (certified count, section); True when done.

        Examples
        --------
        >>> import imagespace as isp
        >>> gs, L = isp.examples.dietmaier_1998()
        >>> isp.widgets.explore(gs, L).wait()
        True
        """
        end = time.monotonic() + as_seconds(timeout, "timeout")
        while time.monotonic() < end:
            with self._lock:
                if not self._working and self._want is None:
                    return True
            time.sleep(0.02)
        return False

    # -- computation ----------------------------------------------------------------------------
    def _solve(self):
        t0 = time.perf_counter()
        err = None
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NearSingularWarning)     # the reliability flag says it
            try:
                res = self.gs.direct_kinematics(self.lengths)
            except ImageSpaceError as e:
                res, err = None, str(e)
        if res is None:
            S, asp, reliable, ncx = np.zeros((0, 8)), np.zeros(0, np.int8), False, 0
        else:
            S, asp, reliable, ncx = res.study_points, res.aspects, bool(res.reliable), int(res.complex_count)
        numbers = self.tracker.update(S, [1 if a >= 0 else -1 for a in asp])
        order = np.argsort(numbers, kind="stable")
        if res is not None:
            from ..spatial.results import SpatialDKResult

            res = SpatialDKResult(S[order], res.residuals[order], asp[order], ncx, False, reliable, res.method)
        self.result = res
        self.mode_numbers = [numbers[k] for k in order]
        self.certified = None
        self.status = {"fast_count": len(S), "reliable": reliable, "complex_count": ncx, "certified_count": None,
                       "certified": False, "seconds": time.perf_counter() - t0, "error": err,
                       "events": self.tracker.message}

    def _queue(self):
        with self._lock:
            self._want = (self.lengths.copy(), self._generation)
            if self._working:
                return
            self._working = True
        threading.Thread(target=self._work, daemon=True).start()

    def _work(self):
        import importlib

        importlib.import_module("scipy.optimize")   # the tracker's assignment of many modes, off the first move

        try:
            while True:
                with self._lock:
                    job, self._want = self._want, None
                    if job is None:
                        return
                L, generation = job
                try:
                    cert = self.gs.direct_kinematics(L, certify=True)
                    error = None
                except ImageSpaceError as e:        # shown in the status line
                    cert, error = None, f"certification failed: {e}"
                with self._draw:
                    if generation != self._generation:
                        continue
                    self.certified = cert
                    self.status["certified_count"] = None if cert is None else cert.count
                    self.status["certified"] = cert is not None and bool(cert.certified)
                    if error:
                        self.status["error"] = error
                    if self._section_generation != generation:
                        self._draw_section()
                    self._draw_status()
        finally:
            with self._lock:
                self._working = False
                pending = self._want is not None
            if pending:
                self._queue()

    # -- drawing --------------------------------------------------------------------------------
    def _update_dropdown(self):
        labels = [f"mode {n} ({int(a):+d})" for n, a in zip(self.mode_numbers, self._aspects())]
        options = list(zip(labels, range(len(labels))))
        if list(self.section_mode.options) == options:
            return
        old = getattr(self, "_old_numbers", [])
        v = self.section_mode.value
        keep = old[v] if v is not None and v < len(old) else None
        self._muted = True
        try:
            self.section_mode.options = options
            if options:
                self.section_mode.value = self.mode_numbers.index(keep) if keep in self.mode_numbers else 0
        finally:
            self._muted = False
        self._old_numbers = list(self.mode_numbers)

    def _aspects(self):
        return [] if self.result is None else list(self.result.aspects)

    def _chosen(self):
        k = self.section_mode.value
        return None if k is None or self.result is None or k >= self.result.count else int(k)

    def _draw_platform(self):
        from ..plotting.common import polygon_order
        from ..spatial.study import transform_points

        gs, v = self.gs, self.view
        A = gs.base_points
        ring = A[polygon_order(A)]
        legs, plats, centres = {1: [], -1: []}, {1: [], -1: []}, []
        order = polygon_order(gs.platform_points)
        S = np.zeros((0, 8)) if self.result is None else self.result.study_points
        shown = range(len(S)) if self.show_all.value else [k for k in [self._chosen()] if k is not None]
        for s, a in ((S[k], self._aspects()[k]) for k in shown):
            X = transform_points(s, gs.platform_points)
            side = 1 if a >= 0 else -1
            legs[side] += [np.stack([A[i], X[i]]) for i in range(6)]
            plats[side].append(np.vstack([X[order], X[order][:1]]))
            centres.append(X.mean(axis=0))
        with v.batch():
            base = np.vstack([ring, ring[:1]])
            v.set("base", x=base[:, 0], y=base[:, 1], z=base[:, 2])
            for side in (1, -1):
                P = _joined3(legs[side])
                v.set(f"legs{side:+d}", x=P[:, 0], y=P[:, 1], z=P[:, 2])
                P = _joined3(plats[side])
                v.set(f"platform{side:+d}", x=P[:, 0], y=P[:, 1], z=P[:, 2])
            C = np.array(centres) if centres else np.zeros((0, 3))
            scale = _LABEL_MERGE * _size(gs)
            numbers = [self.mode_numbers[k] for k in shown]
            v.set("numbers", x=C[:, 0], y=C[:, 1], z=C[:, 2] + 0.04 * _size(gs),
                  text=merged_labels(C, numbers, scale))
            k = self._chosen()
            if k is not None:
                X = transform_points(S[k], gs.platform_points)
                P = _joined3([np.vstack([X[order], X[order][:1]])] + [np.stack([A[i], X[i]]) for i in range(6)])
                F = np.vstack([X[order], X.mean(axis=0)])          # a fan about the centroid: the plate
                fan = np.array([[6, j, (j + 1) % 6] for j in range(6)], dtype=np.int32)
                side = 1 if self._aspects()[k] >= 0 else -1
                v.set("chosen platform", x=F[:, 0], y=F[:, 1], z=F[:, 2], i=fan[:, 0], j=fan[:, 1], k=fan[:, 2],
                      color=ASPECT_COLOURS[side], name=f"the chosen mode {self.mode_numbers[k]}")
            else:
                P = np.zeros((0, 3))
                v.set("chosen platform", x=np.zeros(0), y=np.zeros(0), z=np.zeros(0), i=np.zeros(0, np.int32),
                      j=np.zeros(0, np.int32), k=np.zeros(0, np.int32))
            v.set("chosen", x=P[:, 0], y=P[:, 1], z=P[:, 2])
            n = len(S)
            v.relayout("platform", "title.text", (f"platform: {n} real assembly mode{'' if n == 1 else 's'} "
                                                   "(red det J > 0, blue det J < 0; the chosen mode black)")
                       if n else "platform: no real assembly mode for these leg lengths")

    def _on_section_mode(self, change):
        if self._muted:
            return
        with self._draw:
            self._draw_platform()
            self._draw_section()

    def _draw_section(self):
        from ..spatial.singularities import constant_orientation_singularity

        self._section_generation = self._generation
        v = self.view
        k = self._chosen()
        if k is None:
            with v.batch():
                v.set("regions", x=np.zeros(0), y=np.zeros(0), z=np.zeros((0, 0)))
                v.set("position", x=np.zeros(0), y=np.zeros(0), text=[])
                v.relayout("section", "title.text", "singularity section (no mode)")
            return
        R, t = self.result.rotations[k], self.result.translations[k]
        try:
            locus = constant_orientation_singularity(self.gs, R)
        except ImageSpaceError as e:
            v.relayout("section", "title.text", f"singularity section: {html.escape(str(e))[:80]}")
            return
        if self.box is not None:
            xs = np.linspace(*self.box[0], SPATIAL_SECTION_GRID)
            ys = np.linspace(*self.box[1], SPATIAL_SECTION_GRID)
        else:
            half = 0.75 * _size(self.gs)
            xs = np.linspace(t[0] - half, t[0] + half, SPATIAL_SECTION_GRID)
            ys = np.linspace(t[1] - half, t[1] + half, SPATIAL_SECTION_GRID)
        X, Y = np.meshgrid(xs, ys)
        Z = locus.value(np.column_stack([X.ravel(), Y.ravel(), np.full(X.size, t[2])])).reshape(X.shape)
        angle = np.degrees(2 * np.arccos(min(1.0, abs(float(self.result.study_points[k][0])) /
                                             float(np.linalg.norm(self.result.study_points[k][:4])))))
        with v.batch():
            v.set("regions", x=xs, y=ys, z=Z)
            v.set("position", x=np.array([t[0]]), y=np.array([t[1]]), text=[f"mode {self.mode_numbers[k]}"])
            v.relayout("section", "xaxis.range", [float(xs[0]), float(xs[-1])])
            v.relayout("section", "yaxis.range", [float(ys[0]), float(ys[-1])])
            v.relayout("section", "title.text", f"det J = 0 at the orientation of mode {self.mode_numbers[k]} "
                                                f"(turned {angle:.1f} deg), plane z = {t[2]:.4g}")

    def _draw_status(self):
        st = self.status
        if st["error"] and st["fast_count"] == 0:
            body = f'<b class="isp-error" style="color:#b00">{html.escape(st["error"])}</b>'
        else:
            if st["certified_count"] is None:
                cert = '<span class="isp-certifying">certifying ...</span>'
            else:
                cert = (f'<b><span class="isp-count">{st["certified_count"]}</span> real assembly mode'
                        f'{"" if st["certified_count"] == 1 else "s"}</b> '
                        f'({"certified" if st["certified"] else "NOT certified"})')
            fast = (f'fast path: <span class="isp-fast-count">{st["fast_count"]}</span> real of '
                    f'{st.get("complex_count", 0)} complex, '
                    + ('<span class="isp-reliable">reliable</span>' if st["reliable"] else
                       '<span class="isp-unreliable" style="color:#b00">NOT reliable</span>'))
            body = f"{cert} &middot; {fast}"
            if st["fast_count"] == 0:
                body += ' &middot; <span class="isp-none">no real assembly mode for these leg lengths</span>'
            if st["error"]:
                body += f' &middot; <span class="isp-error" style="color:#b00">{html.escape(st["error"])}</span>'
        if st.get("events"):
            body += f' &middot; <span class="isp-events">{html.escape(st["events"])}</span>'
        T = np.zeros((0, 3)) if self.result is None else self.result.translations
        modes = json.dumps([[int(n), int(a)] + [float(c) for c in t]
                            for n, a, t in zip(self.mode_numbers, self._aspects(), T)])
        L = ",".join(repr(float(x)) for x in self.lengths)
        self.status_line.value = (f'<div class="isp-status" data-lengths="{L}" data-modes="{html.escape(modes)}">'
                                  f'{body} &middot; <span title="time in the kernel for the fast direct kinematics '
                                  f'and the drawing data; the certified count follows from the background">kernel '
                                  f'time <span class="isp-seconds">{1000 * st["seconds"]:.0f}</span> ms</span></div>')

    # -- events ---------------------------------------------------------------------------------
    def _on_slider(self, change):
        if self._muted:
            return
        i = next((k for k, s in enumerate(self.sliders) if s is change["owner"]), None)
        if i is not None and self._echo[i]:
            self._echo[i] = False
            if abs(change["new"] - self.lengths[i]) <= 0.5 * self.sliders[i].step * (1 + 1e-9):
                return                  # the browser's snap of a value set here, not a user move
        try:
            self.set_lengths([s.value for s in self.sliders])
        except InputError as e:
            self.status["error"] = str(e)
            self._draw_status()

    def close(self):
        """Stop the background work and close the widgets.

        Examples
        --------
        >>> import imagespace as isp
        >>> gs, L = isp.examples.dietmaier_1998()
        >>> ex = isp.widgets.explore(gs, L); ex.close(); ex.wait()
        True
        """
        lock = getattr(self, "_lock", None)     # also called by __del__ when __init__ refused its input
        if lock is not None:
            with lock:
                self._want = None
        for name in ("status_line", "section_mode", "show_all", "view"):
            if getattr(self, name, None) is not None:
                getattr(self, name).close()
        for w in getattr(self, "sliders", []):
            w.close()
        super().close()
