"""The explorer's page-ready time in a real browser, taken apart against Voilà's own floor.

Run: ``python benchmarks/page_ready.py [runs]`` (needs the ``browser`` extra and Debian's
``chromium``, as the browser tests). Voilà serves, in turn and ``runs`` times each:

* the **floor**: a notebook showing one trivial anywidget and one HTML widget (what any widget page
  costs: the kernel's start-up, Voilà's page and widget manager);
* the **planar explorer** (``notebooks/00_explore.ipynb``).

Each is timed from the line "Kernel started" in Voilà's log to the page being ready (floor: both
widgets shown; explorer: the status line and the four panels drawn, the browser test's condition).
Then, in a blank page of the same browser, the two browser-side costs no widget code can avoid:
evaluating plotly.min.js (the one the installed ``plotly`` package ships) and plotly's first 3D plot
(a WebGL context and its shaders; software WebGL here, as in CI).
"""

import os
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "browser"))
os.environ.setdefault("IMAGESPACE_BROWSER", "1")

import browser_harness as bh  # noqa: E402
from test_explorer_browser import READY as EXPLORER_READY  # noqa: E402  (the browser test's condition)

FLOOR_CELL = (
    "import anywidget, traitlets, ipywidgets as W\n"
    "class Tiny(anywidget.AnyWidget):\n"
    "    _esm = traitlets.Unicode('export default { render({ model, el }) { const d = document.createElement(\"div\");"
    " d.className = \"tiny-ready\"; el.appendChild(d); } }').tag(sync=True)\n"
    "W.VBox([W.HTML('<span class=\"tiny-status\">ready</span>'), Tiny()])")
FLOOR_READY = "() => document.querySelector('.tiny-ready') && document.querySelector('.tiny-status')"

EVAL_PLOTLY = """(src) => { const t0 = performance.now(); (new Function("module", src))({exports: {}});
    return performance.now() - t0; }"""
FIRST_3D = """async () => { const d = document.createElement('div'); d.style.width = '500px'; d.style.height = '400px';
    document.body.appendChild(d); const t0 = performance.now();
    await window.Plotly.newPlot(d, [{type: 'scatter3d', x: [0, 1], y: [0, 1], z: [0, 1]},
        {type: 'mesh3d', x: [0, 1, 0], y: [0, 0, 1], z: [0, 0, 0], i: [0], j: [1], k: [2]}]);
    return performance.now() - t0; }"""


def _page_ready(notebook, ready_js, label, folder):
    """Seconds from "Kernel started" to ``ready_js`` (the browser tests' own measurement:
    :func:`browser_harness.served_page`, which also fails on any page error)."""
    timings = bh.Timings(folder / f"timings_{label}.json")
    with bh.served_page(notebook, f"voila_{label}.log", label, timings, ready_js):
        pass
    return timings.data[f"{label}.page_ready_after_kernel_start_s"]


def _in_blank_page():
    import importlib.util

    from playwright.sync_api import sync_playwright

    origin = Path(importlib.util.find_spec("plotly").origin).parent
    src = (origin / "package_data" / "plotly.min.js").read_text(encoding="utf-8")
    pw = sync_playwright().start()
    browser = pw.chromium.launch(executable_path=bh.CHROMIUM, args=bh.CHROMIUM_ARGS)
    try:
        pg = browser.new_page()
        pg.set_content("<html><body></body></html>")
        ev = pg.evaluate(EVAL_PLOTLY, src)
        first = pg.evaluate(FIRST_3D)
        return ev / 1000, first / 1000, len(src)
    finally:
        browser.close()
        pw.stop()


def main(runs=2):
    tmp = ROOT / "artifacts" / "page_ready"
    tmp.mkdir(parents=True, exist_ok=True)
    bh.ARTIFACTS.mkdir(parents=True, exist_ok=True)          # the Voila logs go there
    floor_nb = bh.one_cell_notebook(tmp / "floor.ipynb", FLOOR_CELL, "floor")
    floor, explorer, plotly_eval, first_3d = [], [], [], []
    for _ in range(runs):                                    # alternating: the same load for both
        floor.append(_page_ready(floor_nb, FLOOR_READY, "floor", tmp))
        explorer.append(_page_ready(ROOT / "notebooks" / "00_explore.ipynb", EXPLORER_READY, "explorer", tmp))
        e, f, size = _in_blank_page()
        plotly_eval.append(e)
        first_3d.append(f)
    med = statistics.median
    print(f"page ready after the kernel started, {runs} runs each (median; all):")
    print(f"  floor (one trivial anywidget)  {med(floor):6.2f} s  {[round(v, 2) for v in floor]}")
    print(f"  planar explorer                {med(explorer):6.2f} s  {[round(v, 2) for v in explorer]}")
    print(f"  explorer / floor               {med(explorer) / med(floor):6.2f}x")
    print(f"  the explorer's own share       {med(explorer) - med(floor):6.2f} s")
    print(f"in a blank page: plotly.min.js ({size / 1e6:.1f} MB) evaluated in {med(plotly_eval):.2f} s "
          f"{[round(v, 2) for v in plotly_eval]}; first 3D plot {med(first_3d):.2f} s "
          f"{[round(v, 2) for v in first_3d]}")
    print(f"floor + plotly evaluation + first 3D plot = {med(floor) + med(plotly_eval) + med(first_3d):.2f} s "
          "(target: < 5 s)")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 2)
