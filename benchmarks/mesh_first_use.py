"""The first mesh of a design, the warm mesh, and a re-mesh at new joint values.

Every figure comes from a fresh Python process (``subprocess``), as a new user would meet it:

* **fresh process**: ``import imagespace`` and the meshing imports (trimesh, scikit-image), the
  derivation of the seed-002 quartic (``stigger_husty()``) and its first 128³ mesh in the image
  chart (box ``x2, x3 in [-12, 12], x1 in [-3, 3]``);
* **first mesh of a new design in a running session**: the same after the imports and one small
  mesh of another design (``general_3rpr``) - what a second design costs once the libraries are
  loaded: derivation + table + 128³ mesh;
* **warm mesh**: median of 5 more 128³ meshes of the same surface (image and pose chart), with
  plain marching cubes on the same grid (no projection, no certificate) as the baseline;
* **re-mesh at a new q** of a design whose surface depends on the joint values (an RRR leg with
  an actuated base revolute): ``singularity_surface(q=)`` + ``mesh_surface`` at the explorer's
  drag (20³) and rest (48³) resolutions + ``section_coefficients``, median over 6 new q after the
  first one.

The mesher uses no numba, so the numba cache (warm or cold) does not enter these figures.

Baseline code: ``--baseline SRC`` runs the same workers on another checkout of the package (e.g.
``git archive ed71793 | tar -x -C /tmp/old``), so old and new code are measured in one run.

    python benchmarks/mesh_first_use.py [--baseline SRC] [--repeat N] [--cpu]

``--cpu`` times with each process's CPU time instead of the wall clock.
"""

import json
import os
import subprocess
import sys
import time

import numpy as np

IMAGE_BOX = [(-12, 12), (-12, 12), (-3, 3)]
# wall-clock time, or with MESH_BENCH_CLOCK=cpu the process's CPU time (on a machine shared with
# other jobs, CPU time is closer to what the wall clock shows on an idle one: everything measured
# here runs in one thread)
now = time.process_time if os.environ.get("MESH_BENCH_CLOCK") == "cpu" else time.perf_counter
if os.environ.get("MESH_BENCH_CLOCK") == "cpu" and __name__ == "__main__" and "--worker" in sys.argv:
    time.perf_counter = time.process_time   # the mesher's stage times too (a worker process only)
POSE_BOX = [(-15, 15), (-15, 15), (-np.pi, np.pi)]


def rrr_design(isp):
    return isp.PlanarParallel([isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3, 2), actuated=0),
                               isp.RPR(base=(6, 0), platform=(1, 0)), isp.RPR(base=(2, 5), platform=(0, 1))])


def worker_fresh():
    t0 = now()
    import imagespace as isp
    from imagespace.singular.meshing import mesh_surface
    import trimesh  # noqa: F401  (what the first mesh imports anyway)
    from skimage.measure import marching_cubes  # noqa: F401
    t1 = now()
    m = isp.examples.stigger_husty()
    S = m.singularity_surface()
    t2 = now()
    mesh = mesh_surface(S, IMAGE_BOX, resolution=128, progress=False)
    t3 = now()
    return {"import": t1 - t0, "derive": t2 - t1, "mesh": t3 - t2, "total": t3 - t0,
            "faces": len(mesh.faces), "uncertified": mesh.metadata["imagespace"]["uncertified"]}


def worker_session():
    import imagespace as isp
    from imagespace.singular.meshing import mesh_surface, surface_implicit
    from skimage.measure import marching_cubes

    other = isp.examples.general_3rpr()
    mesh_surface(other.singularity_surface(), IMAGE_BOX, resolution=16, progress=False)
    t0 = now()
    m = isp.examples.stigger_husty()
    S = m.singularity_surface()
    t1 = now()
    mesh = mesh_surface(S, IMAGE_BOX, resolution=128, progress=False)
    t2 = now()
    out = {"derive": t1 - t0, "first_mesh": t2 - t1, "first_total": t2 - t0, "faces": len(mesh.faces)}
    for chart, box in (("image", IMAGE_BOX), ("pose", POSE_BOX)):
        mesh_surface(S, box, chart=chart, resolution=128, progress=False)
        ts, parts = [], []
        for _ in range(5):
            t = now()
            mesh = mesh_surface(S, box, chart=chart, resolution=128, progress=False)
            ts.append(now() - t)
            parts.append(mesh.metadata["imagespace"]["times"])
        k = int(np.argsort(ts)[len(ts) // 2])
        f = surface_implicit(S, chart)
        b = np.asarray(box, float)
        axes = [np.linspace(*b[i], 128) for i in range(3)]
        tp = []
        for _ in range(5):
            t = now()
            G = f.grid(axes)
            marching_cubes(G, 0.0, spacing=tuple((b[:, 1] - b[:, 0]) / 127))
            tp.append(now() - t)
        out[chart] = {"warm": float(np.median(ts)), "parts": parts[k], "plain_mc": float(np.median(tp)),
                      "faces": len(mesh.faces), "max_distance": mesh.metadata["imagespace"]["max_distance"]}
    return out


def worker_joints():
    import imagespace as isp
    from imagespace.singular.meshing import mesh_surface

    mesh_surface(isp.examples.general_3rpr().singularity_surface(), IMAGE_BOX, resolution=16, progress=False)
    m = rrr_design(isp)
    rng = np.random.default_rng(20261202)
    qs = [(float(rng.uniform(-2, 2)), float(rng.uniform(4, 6)), float(rng.uniform(4, 6))) for _ in range(7)]
    rows = []
    for q in qs:
        t0 = now()
        S = m.singularity_surface(q=q)
        t1 = now()
        m20 = mesh_surface(S, IMAGE_BOX, resolution=20, progress=False)
        t2 = now()
        m48 = mesh_surface(S, IMAGE_BOX, resolution=48, progress=False)
        t3 = now()
        S.section_coefficients([0.3])
        t4 = now()
        rows.append({"surface": t1 - t0, "mesh20": t2 - t1, "mesh48": t3 - t2, "section": t4 - t3,
                     "drag": t2 - t0, "rest": (t1 - t0) + (t3 - t2) + (t4 - t3),
                     "faces48": len(m48.faces), "faces20": len(m20.faces)})
    later = {k: float(np.median([r[k] for r in rows[1:]])) for k in rows[0] if not k.startswith("faces")}
    return {"first": rows[0], "later": later, "faces48": [r["faces48"] for r in rows]}


WORKERS = {"fresh": worker_fresh, "session": worker_session, "joints": worker_joints}


def run(task, src, clock):
    env = dict(os.environ, PYTHONPATH=src, MESH_BENCH_CLOCK=clock)
    out = subprocess.run([sys.executable, os.path.abspath(__file__), "--worker", task], env=env,
                         capture_output=True, text=True, check=True, cwd=src)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv):
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    repeat = int(argv[argv.index("--repeat") + 1]) if "--repeat" in argv else 3
    trees = [("new", here)]
    if "--baseline" in argv:
        trees.append(("old", argv[argv.index("--baseline") + 1]))
    clock = "cpu" if "--cpu" in argv else "wall"
    print(f"clock: {clock} time" + (" (process CPU time)" if clock == "cpu" else ""))
    res = {}
    for name, src in trees:
        fresh = [run("fresh", src, clock) for _ in range(repeat)]
        res[name] = {"fresh": {k: float(np.median([f[k] for f in fresh])) for k in fresh[0]},
                     "session": run("session", src, clock), "joints": run("joints", src, clock)}
    for name, r in res.items():
        f, s, j = r["fresh"], r["session"], r["joints"]
        print(f"[{name}] fresh process (median of {repeat}): import {f['import']:.2f} s, derivation "
              f"{f['derive']:.2f} s, first 128^3 mesh {f['mesh']:.2f} s, total {f['total']:.2f} s "
              f"({int(f['faces'])} faces, {int(f['uncertified'])} uncertified)")
        print(f"[{name}] first mesh of a new design in a session: derivation {s['derive']:.3f} s + 128^3 mesh "
              f"{s['first_mesh']:.3f} s = {s['first_total']:.3f} s")
        for chart in ("image", "pose"):
            c = s[chart]
            parts = ", ".join(f"{k} {1e3 * v:.0f}" for k, v in c["parts"].items())
            print(f"[{name}] warm 128^3 {chart}: {1e3 * c['warm']:.0f} ms ({parts} ms); plain marching cubes "
                  f"{1e3 * c['plain_mc']:.0f} ms; ratio {c['warm'] / c['plain_mc']:.2f}x; {c['faces']} faces, "
                  f"certified distance <= {c['max_distance']:.1e}")
        jf, jl = j["first"], j["later"]
        print(f"[{name}] joint-dependent RRR design, first q: surface {jf['surface']:.3f} s, 20^3 mesh "
              f"{jf['mesh20']:.3f} s, 48^3 mesh {jf['mesh48']:.3f} s, section {jf['section']:.3f} s")
        print(f"[{name}]   new q (median of 6): surface {1e3 * jl['surface']:.0f} ms, 20^3 mesh "
              f"{1e3 * jl['mesh20']:.0f} ms, 48^3 mesh {1e3 * jl['mesh48']:.0f} ms, section "
              f"{1e3 * jl['section']:.0f} ms; drag update {1e3 * jl['drag']:.0f} ms, rest update "
              f"{1e3 * jl['rest']:.0f} ms; faces at 48^3 {j['faces48']}")
    if "old" in res:
        n, o = res["new"], res["old"]
        print(f"ratios old/new: fresh total {o['fresh']['total'] / n['fresh']['total']:.2f}x, new design in a "
              f"session {o['session']['first_total'] / n['session']['first_total']:.2f}x, warm image "
              f"{o['session']['image']['warm'] / n['session']['image']['warm']:.2f}x, warm pose "
              f"{o['session']['pose']['warm'] / n['session']['pose']['warm']:.2f}x, new-q rest update "
              f"{o['joints']['later']['rest'] / n['joints']['later']['rest']:.1f}x, drag update "
              f"{o['joints']['later']['drag'] / n['joints']['later']['drag']:.1f}x")


if __name__ == "__main__":
    if len(sys.argv) > 2 and sys.argv[1] == "--worker":
        print(json.dumps(WORKERS[sys.argv[2]]()))
    else:
        main(sys.argv[1:])
