// imagespace explorer panels: several plotly plots driven by one anywidget model.
//
// The kernel sends only what changed (a trace's arrays as binary buffers, a title) in custom
// messages; the pose panel is redrawn at once and the heavier panels (3D scene, contour) after the
// browser has painted it. A planned path arrives once as frames and is played here, in the browser
// (requestAnimationFrame), not one kernel round trip a frame.

const TYPED = { f8: Float64Array, f4: Float32Array, i4: Int32Array, u4: Uint32Array, i2: Int16Array,
                u2: Uint16Array, i1: Int8Array, u1: Uint8Array };

function plotlyLib() {
  if (!globalThis.__imagespacePlotly) {
    globalThis.__imagespacePlotly = (function () {
      const module = { exports: {} };
      /*__PLOTLY_SOURCE__*/
      return module.exports;
    })();
  }
  return globalThis.__imagespacePlotly;
}

function typed(view, code, shape) {
  let buf;
  if (view instanceof ArrayBuffer) buf = view;
  else buf = view.buffer.slice(view.byteOffset, view.byteOffset + view.byteLength);
  const arr = new TYPED[code](buf);
  if (shape && shape.length === 2) {
    const rows = new Array(shape[0]);
    for (let r = 0; r < shape[0]; r++) rows[r] = arr.subarray(r * shape[1], (r + 1) * shape[1]);
    return rows;
  }
  return arr;
}

function decode(obj, buffers) {
  if (Array.isArray(obj)) return obj.map((o) => decode(o, buffers));
  if (obj && typeof obj === "object") {
    if (obj instanceof DataView || obj instanceof ArrayBuffer || ArrayBuffer.isView(obj)) return obj;
    if (obj.$t !== undefined) {
      const raw = obj.$v !== undefined ? obj.$v : buffers[obj.$b];
      return typed(raw, obj.$t, obj.$s);
    }
    const out = {};
    for (const k of Object.keys(obj)) out[k] = decode(obj[k], buffers);
    return out;
  }
  return obj;
}

function setPath(target, path, value) {
  const parts = path.split(".");
  let o = target;
  for (let i = 0; i < parts.length - 1; i++) {
    const key = /^\d+$/.test(parts[i]) ? Number(parts[i]) : parts[i];
    if (o[key] === undefined || o[key] === null) o[key] = /^\d+$/.test(parts[i + 1]) ? [] : {};
    o = o[key];
  }
  const last = /^\d+$/.test(parts[parts.length - 1]) ? Number(parts[parts.length - 1]) : parts[parts.length - 1];
  o[last] = value;
}

function render({ model, el }) {
  const Plotly = plotlyLib();
  const root = document.createElement("div");
  root.className = "isp-panels";
  el.appendChild(root);
  const divs = {};
  let state = {};            // panel -> {data, layout, config}
  let frames = null;         // {n, interval, panels: {panel: {trace: {prop: rows}}}}
  let playing = false, frameNo = 0, raf = null;
  const pending = {};        // panel -> true: a deferred redraw is queued
  // a panel's content revision (the kernel's count of its changes; -1: changed here, by a frame)
  // and the revision last drawn: a new state redraws only the panels whose content changed
  const knownRev = {}, drawnRev = {};
  let flushQueued = false;
  const controls = document.createElement("div");
  controls.className = "isp-animation";
  const playButton = document.createElement("button");
  playButton.className = "isp-play";
  playButton.textContent = "\u25B6 play";
  playButton.disabled = true;
  const slider = document.createElement("input");
  slider.type = "range"; slider.className = "isp-frame"; slider.min = 0; slider.max = 0; slider.value = 0;
  slider.disabled = true;
  const readout = document.createElement("span");
  readout.className = "isp-frame-readout";
  controls.append(playButton, slider, readout);

  function draw(panel) {
    const s = state[panel];
    if (!s || !divs[panel]) return Promise.resolve();
    const rev = knownRev[panel];
    drawnRev[panel] = rev;
    return Plotly.react(divs[panel], s.data, s.layout, s.config || { displaylogo: false });
  }

  function build(spec) {
    state = {};
    const same = Object.keys(divs).length === spec.order.length && spec.order.every((n) => divs[n]);
    if (!same) {                 // first build: the grid of panels (a new state reuses them: react)
      root.innerHTML = "";
      root.style.display = "grid";
      root.style.gridTemplateColumns = (spec.columns || []).map((w) => w + "px").join(" ");
      root.style.gap = "4px";
      for (const name of spec.order) {
        const div = document.createElement("div");
        div.className = "isp-panel isp-panel-" + name;
        div.dataset.panel = name;
        divs[name] = div;
        if (spec.controls === name) {
          const wrap = document.createElement("div");
          wrap.append(controls, div);
          root.appendChild(wrap);
        } else {
          root.appendChild(div);
        }
      }
    }
    // the urgent panels (the pose) now; the others after the browser has painted them (a first
    // WebGL scene costs about a second in a software renderer); unchanged panels are not redrawn
    const revs = spec.revs || {}, urgent = spec.urgent || [];
    let later = false;
    for (const name of spec.order) {
      state[name] = spec.panels[name];
      knownRev[name] = revs[name] === undefined ? -1 : revs[name];
      if (same && knownRev[name] !== -1 && drawnRev[name] === knownRev[name]) continue;
      if (urgent.includes(name)) draw(name);
      else { pending[name] = true; later = true; }
    }
    if (later) scheduleOthers(true);
    el.dataset.version = String(spec.version);
  }

  // a heavy panel (the 3D scene redraws its whole mesh) is redrawn at most a quarter of the time, so
  // that it never holds up the pose panel; while a path plays it follows only if it is fast (a GPU)
  const cost = {}, lastDone = {};
  let flushTimer = null;
  function flushPending() {
    flushQueued = false;
    flushTimer = null;
    const now = performance.now();
    let wait = 0;
    for (const p of Object.keys(pending)) {
      const c = cost[p] || 0;
      // while a path plays, a panel slower than a frame waits for the end (or a pause)
      if (playing && c > 40) { wait = Math.max(wait, 250); continue; }
      const gap = 3 * c - (now - (lastDone[p] || -1e9));
      if (gap > 0) { wait = Math.max(wait, gap); continue; }
      delete pending[p];
      const t = performance.now();
      const first = lastDone[p] === undefined;
      // a panel's first draw (a WebGL scene's context and shaders) does not predict its redraws
      draw(p).then(() => { lastDone[p] = performance.now(); if (!first) cost[p] = lastDone[p] - t; });
    }
    if (Object.keys(pending).length) {
      flushQueued = true;
      flushTimer = setTimeout(() => requestAnimationFrame(() => setTimeout(flushPending, 0)), wait);
    }
  }

  function scheduleOthers(now) {
    if (now && flushTimer !== null) { clearTimeout(flushTimer); flushTimer = null; flushQueued = false; }
    if (flushQueued) return;
    flushQueued = true;
    // after the next paint: the pose panel shows first, the heavier panels follow
    requestAnimationFrame(() => setTimeout(flushPending, 0));
  }

  function applyUpdate(panels, urgent, revs) {
    for (const [panel, change] of Object.entries(panels)) {
      const s = state[panel];
      if (!s) continue;
      knownRev[panel] = revs && revs[panel] !== undefined ? revs[panel] : -1;
      for (const [idx, props] of Object.entries(change.traces || {})) {
        s.data[Number(idx)] = Object.assign({}, s.data[Number(idx)], props);
      }
      if (change.layout) {
        s.layout = Object.assign({}, s.layout);
        for (const [path, value] of Object.entries(change.layout)) setPath(s.layout, path, value);
        s.layout.datarevision = (s.layout.datarevision || 0) + 1;
      }
      if (urgent.includes(panel)) draw(panel);
      else { pending[panel] = true; scheduleOthers(); }
    }
  }

  // during playback a 2D panel moves its traces with plotly's animate (no replot of axes, legend
  // and the other traces); the 3D panel is redrawn when its turn comes (flushPending)
  function showFrame(k, fast) {
    if (!frames) return;
    frameNo = Math.max(0, Math.min(frames.n - 1, k));
    const changed = {};
    for (const [panel, traces] of Object.entries(frames.panels)) {
      const s = state[panel];
      const idxs = Object.keys(traces).map(Number);
      const upd = idxs.map((idx) => {
        const u = {};
        for (const [prop, rows] of Object.entries(traces[idx])) u[prop] = rows[frameNo];
        return u;
      });
      const flat = idxs.every((idx) => (s.data[idx].type || "scatter") === "scatter");
      if (fast && flat) {
        idxs.forEach((idx, j) => { s.data[idx] = Object.assign({}, s.data[idx], upd[j]); });
        knownRev[panel] = -1;
        Plotly.animate(divs[panel], { data: upd, traces: idxs },
                       { mode: "immediate", transition: { duration: 0 }, frame: { duration: 0, redraw: false } });
      } else {
        changed[panel] = { traces: {} };
        idxs.forEach((idx, j) => { changed[panel].traces[idx] = upd[j]; });
      }
    }
    applyUpdate(changed, fast ? [] : (frames.urgent || []));
    slider.value = frameNo;
    readout.textContent = " frame " + frameNo + " / " + (frames.n - 1);
  }

  let startTime = 0, startFrame = 0;
  function tick(now) {
    if (!playing || !frames) { raf = null; return; }
    // the sample shown follows the clock: a slow repaint skips samples, never slows the motion
    const k = Math.min(frames.n - 1, startFrame + Math.floor((now - startTime) / frames.interval));
    if (k !== frameNo) showFrame(k, true);
    if (k >= frames.n - 1) {
      playing = false; playButton.textContent = "\u25B6 play"; raf = null;
      scheduleOthers(true);                // the last sample in every panel, now
      return;
    }
    raf = requestAnimationFrame(tick);
  }

  playButton.addEventListener("click", () => {
    if (!frames) return;
    playing = !playing;
    playButton.textContent = playing ? "\u23F8 pause" : "\u25B6 play";
    if (!playing) stopped();
    if (playing) {
      if (frameNo >= frames.n - 1) showFrame(0);
      startTime = performance.now();
      startFrame = frameNo;
      if (raf === null) raf = requestAnimationFrame(tick);
    }
  });
  slider.addEventListener("input", () => { playing = false; playButton.textContent = "\u25B6 play"; showFrame(Number(slider.value)); });
  function stopped() { scheduleOthers(true); }

  function setFrames(f) {
    frames = f;
    playing = false;
    playButton.textContent = "\u25B6 play";
    if (!f) {
      playButton.disabled = slider.disabled = true;
      slider.max = 0; slider.value = 0; readout.textContent = "";
      return;
    }
    playButton.disabled = slider.disabled = false;
    slider.max = f.n - 1;
    showFrame(0);
  }

  function onMessage(msg, buffers) {
    const m = decode(msg, buffers || []);
    if (m.type === "update") applyUpdate(m.panels, m.urgent || [], m.revs);
    else if (m.type === "full") { build(m.spec); setFrames(null); }
    else if (m.type === "frames") setFrames(m.frames);
    else if (m.type === "frame") {
      playing = false; showFrame(m.k);
      if (frames) for (const [p, r] of Object.entries(m.revs || {})) if (p in frames.panels) knownRev[p] = r;
    }
    else if (m.type === "play") { if (frames && !playing) playButton.click(); }
  }

  build(decode(model.get("spec"), []));
  const onSpec = () => { build(decode(model.get("spec"), [])); setFrames(null); };
  model.on("change:spec", onSpec);
  model.on("msg:custom", onMessage);
  // a view opened after updates (a re-displayed widget) asks for the current state
  model.send({ type: "hello", version: model.get("spec").version });
  return () => {
    playing = false;
    model.off("change:spec", onSpec);
    model.off("msg:custom", onMessage);
    for (const div of Object.values(divs)) Plotly.purge(div);
  };
}

// the plotly library is compiled when the model is created, before its view is rendered
export default { initialize() { plotlyLib(); }, render };
