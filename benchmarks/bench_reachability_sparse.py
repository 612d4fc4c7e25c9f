"""The untimed reachability search before and after sparse arc weights, side by side.

Runs each case in a fresh process, alternating the two checkouts (A B A B ...),
and prints medians and spread. The "before" checkout is a git worktree of the
commit preceding the change (``--before``), "after" is this one.

Usage::

    python benchmarks/bench_reachability_sparse.py --before /tmp/before --runs 3
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
from pathlib import Path

CASES = {
    # name: (file relative to the anchors, max_states)
    "CircularTrains-PT-024 (86,515 states)": ("pnml/CircularTrains-PT-024.pnml", 1_000_000),
    "HouseConstruction-PT-00005 (300,000 of 1,187,984)":
        ("pnml/HouseConstruction-PT-00005.pnml", 300_000),
    "ring of 2 places, 10**9 tokens (100,000 levels)": ("ring", 100_000),
}

PROGRAM = """
import json, sys, time
import numpy as np
from tegraph.io import read
from tegraph.model.petri import PetriNet
from tegraph.analysis.baselines.reachability import reachability_graph
name, budget = sys.argv[1], int(sys.argv[2])
if name == "ring":
    net = PetriNet("ring", ["ab", "ba"], ["a", "b"], np.array([[0, 1], [1, 0]]),
                   np.array([[1, 0], [0, 1]]), np.array([0, 10**9]))
else:
    net = read(name)
t = time.perf_counter()
r = reachability_graph(net, max_states=budget)
print(json.dumps({"seconds": time.perf_counter() - t, "states": r.states, "edges": r.edges}))
"""


def run(checkout: Path, anchors: Path, case: tuple[str, int]) -> dict:
    name, budget = case
    target = name if name == "ring" else str(anchors / name)
    out = subprocess.run([sys.executable, "-c", PROGRAM, target, str(budget)], cwd=checkout,
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", type=Path, required=True)
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    after = Path(__file__).resolve().parents[1]
    anchors = after / "tests" / "data" / "anchors"
    print("| case | states | before (s), median [min-max] | after (s), median [min-max] |")
    print("|---|---|---|---|")
    for label, case in CASES.items():
        times: dict[str, list[float]] = {"before": [], "after": []}
        seen = set()
        for _ in range(args.runs):
            for side, checkout in (("before", args.before), ("after", after)):
                r = run(checkout, anchors, case)
                times[side].append(r["seconds"])
                seen.add((r["states"], r["edges"]))
        assert len(seen) == 1, f"the two checkouts disagree: {seen}"
        states = next(iter(seen))[0]
        cells = [f"{statistics.median(t):.2f} [{min(t):.2f}-{max(t):.2f}]"
                 for t in times.values()]
        print(f"| {label} | {states:,} | {cells[0]} | {cells[1]} |")


if __name__ == "__main__":
    main()
