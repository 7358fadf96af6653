"""The explorers' plot panels: plotly figures held as plain data in Python, drawn in the browser by
one small anywidget (``panels.js``, with plotly.js from the installed ``plotly`` package).

Why not plotly's ``FigureWidget``: it redraws the whole figure (3D mesh included) on every change,
its import pulls in nbformat and jsonschema (about 2-3 s at start-up), and it cannot play frames.
Here the kernel sends only what changed (a trace's arrays as binary buffers, a title) per panel;
the browser redraws the pose panel first and the heavier ones after that paint; a planned path is
sent once and played in the browser.
"""

from __future__ import annotations

import contextlib
import copy
import functools
import html
import json
import pathlib
import threading

import numpy as np

import anywidget
import traitlets

from .._files import atomic_write
from ..exceptions import InputError

__all__ = ["PanelView", "TraceView"]

_HERE = pathlib.Path(__file__).parent
_CODES = {np.dtype(np.float64): "f8", np.dtype(np.float32): "f4", np.dtype(np.int32): "i4",
          np.dtype(np.uint32): "u4", np.dtype(np.int16): "i2", np.dtype(np.uint16): "u2",
          np.dtype(np.int8): "i1", np.dtype(np.uint8): "u1"}


@functools.lru_cache(maxsize=1)
def _plotly_js():
    import importlib.util

    spec = importlib.util.find_spec("plotly")
    if spec is None or spec.origin is None:            # pragma: no cover  (plotly is a dependency of the extra)
        raise ImportError("the explorer needs plotly: pip install 'imagespace[jupyter]'")
    return (pathlib.Path(spec.origin).parent / "package_data" / "plotly.min.js").read_text(encoding="utf-8")


@functools.lru_cache(maxsize=1)
def _esm():
    return (_HERE / "panels.js").read_text(encoding="utf-8").replace("/*__PLOTLY_SOURCE__*/", _plotly_js())


def _array(value):
    """``value`` as a contiguous numeric array for binary transfer (float64, or its integer type),
    or None: only numpy arrays travel as binary (plain lists, e.g. axis ranges, stay JSON)."""
    if not isinstance(value, np.ndarray):
        return None
    if value.dtype.kind in "iu":
        return np.ascontiguousarray(value if value.dtype in _CODES else value.astype(np.int32))
    if value.dtype.kind in "fb":
        return np.ascontiguousarray(value, dtype=np.float64)
    return None


def _pack(obj, buffers=None):
    """JSON-able copy of ``obj`` with numeric arrays as binary buffers.

    ``buffers`` a list: arrays go there and are referenced by index (custom messages); None: the
    array's memoryview stays in place (widget state; ipywidgets moves it to a binary buffer)."""
    a = _array(obj)
    if a is not None and a.ndim <= 2:
        out = {"$t": _CODES[a.dtype]}
        if a.ndim == 2:
            out["$s"] = list(a.shape)
        if buffers is None:
            out["$v"] = memoryview(a.reshape(-1)).cast("B")
        else:
            out["$b"] = len(buffers)
            buffers.append(memoryview(a.reshape(-1)).cast("B"))
        return out
    if isinstance(obj, np.ndarray):              # text arrays and the like
        return obj.tolist()
    if isinstance(obj, dict):
        return {str(k): _pack(v, buffers) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_pack(v, buffers) for v in obj]
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, float) and not np.isfinite(obj):
        return None
    return obj


def _plain(obj):
    """``obj`` as JSON (arrays as lists, NaN as null): for the standalone page."""
    if isinstance(obj, np.ndarray):
        return [_plain(v) for v in obj.tolist()] if obj.dtype.kind == "f" else obj.tolist()
    if isinstance(obj, dict):
        return {k: _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if isinstance(obj, float) and not np.isfinite(obj):
        return None
    if isinstance(obj, np.generic):
        return obj.item()
    return obj


class TraceView:
    """A read-only view of one trace of a panel: its plotly properties as attributes (``x``, ``y``,
    ``z``, ``text``, ``name``, ``opacity``, ``i`` ...; an unset property is None).

    Examples
    --------
    >>> from imagespace.widgets.view import TraceView
    >>> t = TraceView({"type": "scatter", "name": "legs", "x": [0.0, 1.0]})
    >>> t.name, list(t.x), t.opacity
    ('legs', [0.0, 1.0], None)
    """

    def __init__(self, props):
        object.__setattr__(self, "_props", props)

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        value = self._props.get(name)
        if isinstance(value, np.ndarray):
            return value.copy()
        return copy.deepcopy(value)

    def __setattr__(self, name, value):
        raise AttributeError("a TraceView is read-only; the explorer draws its traces itself")

    def __repr__(self):
        return f"TraceView({self._props.get('type', 'trace')}, name={self._props.get('name')!r})"


class PanelView(anywidget.AnyWidget):
    """Plotly panels in one widget. ``panels``: name -> ``{"data": [trace dicts], "layout": dict}``;
    ``names``: trace name -> ``(panel, index)``; ``order``: panels in display order; ``columns``:
    the grid's column widths in pixels; ``urgent``: panels redrawn before the browser paints (the
    others follow the paint); ``controls``: the panel above which the play controls sit.

    Examples
    --------
    >>> from imagespace.widgets.view import PanelView
    >>> v = PanelView({"a": {"data": [{"type": "scatter", "name": "line", "x": [], "y": []}], "layout": {}}},
    ...               order=["a"], columns=[400])
    >>> with v.batch():
    ...     v.set("line", x=[0.0, 1.0], y=[1.0, 2.0])
    >>> list(v.trace("line").y)
    [1.0, 2.0]
    """

    _esm = traitlets.Unicode().tag(sync=True)
    spec = traitlets.Dict().tag(sync=True)

    def __init__(self, panels, order, columns, urgent=(), controls=None):
        self.panels = panels
        self.order = list(order)
        self.columns = list(columns)
        self.urgent = list(urgent)
        self.controls = controls
        self.names = {}
        for p in self.order:
            for k, tr in enumerate(panels[p]["data"]):
                self.names[tr.get("meta", tr["name"])] = (p, k)
        self._pending = {}
        self._depth = 0
        self._lock = threading.RLock()
        self._version = 0
        self._revs = {p: 0 for p in self.order}   # per panel: bumped by each change of its content
        self._frames = None
        self._hold = False
        super().__init__(_esm=_esm())
        self.on_msg(self._on_front)
        self.publish()

    # -- state ----------------------------------------------------------------------------------
    def trace(self, name):
        """The trace called ``name`` (a :class:`TraceView`); InputError names the known ones."""
        if name not in self.names:
            raise InputError(f"name must be one of {sorted(self.names)}, got {name!r}")
        p, k = self.names[name]
        return TraceView(self.panels[p]["data"][k])

    def layout(self, panel):
        return copy.deepcopy(self.panels[panel]["layout"])

    def _spec(self):
        return {"order": self.order, "columns": self.columns, "controls": self.controls,
                "version": self._version, "revs": dict(self._revs), "urgent": self.urgent,
                "panels": self.panels}

    def publish(self):
        """Send the whole state (on construction, and after a big change such as a new mesh)."""
        with self._lock:
            self._version += 1
            self._pending = {}
            self.spec = _pack(self._spec())

    # -- updates --------------------------------------------------------------------------------
    @contextlib.contextmanager
    def quiet(self):
        """Changes inside update the state only; on exit the whole state is sent once."""
        with self._lock:
            self._hold = True
            try:
                yield self
            finally:
                self._hold = False
                self.publish()

    @contextlib.contextmanager
    def batch(self):
        """Collect :meth:`set` and :meth:`relayout` calls; send them as one message on exit."""
        with self._lock:
            self._depth += 1
            try:
                yield self
            finally:
                self._depth -= 1
                if self._depth == 0:
                    self.flush()

    def set(self, trace, /, **props):
        """Change properties of the trace called ``trace`` (sent on the batch's exit, or now outside one)."""
        with self._lock:
            p, k = self.names[trace]
            self.panels[p]["data"][k].update(props)
            self._revs[p] += 1
            self._pending.setdefault(p, {"traces": {}, "layout": {}})["traces"].setdefault(k, {}).update(props)
            if self._depth == 0:
                self.flush()

    def relayout(self, panel, path, value):
        """Set a layout property of ``panel`` by a dotted path (``"annotations.0.text"``)."""
        with self._lock:
            target = self.panels[panel]["layout"]
            parts = path.split(".")
            for part in parts[:-1]:
                target = target[int(part)] if part.isdigit() else target.setdefault(part, {})
            last = parts[-1]
            if last.isdigit():
                target[int(last)] = value
            else:
                target[last] = value
            self._revs[panel] += 1
            self._pending.setdefault(panel, {"traces": {}, "layout": {}})["layout"][path] = value
            if self._depth == 0:
                self.flush()

    def flush(self):
        with self._lock:
            if not self._pending:
                return
            pending, self._pending = self._pending, {}
            if self._hold:
                return
            self._version += 1
            # the urgent panels first in the message: the browser draws them before painting
            ordered = {p: pending[p] for p in sorted(pending, key=lambda p: p not in self.urgent)}
            buffers = []
            content = {"type": "update", "urgent": self.urgent, "panels": _pack(ordered, buffers),
                       "revs": {p: self._revs[p] for p in ordered}}
            if self.comm is not None:
                self.send(content, buffers)

    # -- animation ------------------------------------------------------------------------------
    def set_frames(self, frames, interval=1 / 30):
        """Frames to play in the browser: ``frames`` maps trace name -> {prop: (n, k) array}; the
        ``interval`` between frames in seconds. None removes them."""
        with self._lock:
            if frames is None:
                if self._frames is None:
                    return
                self._frames = None
                if self.comm is not None and not self._hold:
                    self.send({"type": "frames", "frames": None})
                return
            n = None
            panels = {}
            for name, props in frames.items():
                p, k = self.names[name]
                for prop, rows in props.items():
                    rows = np.asarray(rows, dtype=float)
                    n = rows.shape[0] if n is None else n
                    if rows.ndim != 2 or rows.shape[0] != n:
                        raise InputError(f"frames[{name!r}][{prop!r}] must be (n, k) with one n, got {rows.shape}")
                    panels.setdefault(p, {}).setdefault(k, {})[prop] = rows
            self._frames = {"n": int(n), "interval": 1000.0 * float(interval), "panels": panels,
                            "urgent": self.urgent}
            if self._hold:
                return
            buffers = []
            content = {"type": "frames", "frames": _pack(self._frames, buffers)}
            if self.comm is not None:
                self.send(content, buffers)

    @property
    def frame_count(self):
        """How many frames the browser can play (0: none)."""
        return 0 if self._frames is None else self._frames["n"]

    def show_frame(self, k):
        """Draw frame ``k`` in Python's state and in the browser."""
        with self._lock:
            if self._frames is None:
                return
            for p, traces in self._frames["panels"].items():
                for idx, props in traces.items():
                    self.panels[p]["data"][idx].update({prop: rows[k] for prop, rows in props.items()})
                self._revs[p] += 1
            self._version += 1
            if self.comm is not None:
                self.send({"type": "frame", "k": int(k), "revs": dict(self._revs)})

    def _on_front(self, widget, content, buffers):
        if isinstance(content, dict) and content.get("type") == "hello":
            with self._lock:
                if content.get("version") != self._version:
                    buffers = []
                    self.send({"type": "full", "spec": _pack(self._spec(), buffers)}, buffers)
                    if self._frames is not None:
                        fb = []
                        self.send({"type": "frames", "frames": _pack(self._frames, fb)}, fb)

    # -- export ---------------------------------------------------------------------------------
    def figures(self):
        """The panels as ``plotly.graph_objects.Figure`` objects (built on demand), by panel name."""
        import plotly.graph_objects as go

        return {p: go.Figure({"data": _plain(self.panels[p]["data"]), "layout": _plain(self.panels[p]["layout"])})
                for p in self.order}

    def page(self, title, header_html=""):
        """A standalone HTML page of the panels (plotly.js inlined; opens without a kernel)."""
        divs, calls = [], []
        for k, p in enumerate(self.order):
            divs.append(f"<div id='isp-panel-{k}' class='isp-panel'></div>")
            data = json.dumps(_plain(self.panels[p]["data"]))
            layout = json.dumps(_plain(self.panels[p]["layout"]))
            calls.append(f"Plotly.newPlot('isp-panel-{k}', {data}, {layout}, {{displaylogo: false}});")
        cols = " ".join(f"{w}px" for w in self.columns)
        return ("<!DOCTYPE html><html><head><meta charset='utf-8'>"
                f"<title>{html.escape(title)}</title><script type='text/javascript'>{_plotly_js()}</script>"
                "</head><body style='font-family:sans-serif'>" + header_html
                + f"<div class='plotly-graph-div' style='display:grid;grid-template-columns:{cols};gap:4px'>"
                + "".join(divs) + "</div><script>" + "\n".join(calls) + "</script></body></html>")

    def save(self, path, title, header_html=""):
        path = pathlib.Path(path)
        text = self.page(title, header_html)
        atomic_write(path, lambda f: f.write(text.encode("utf-8")))
        return path
