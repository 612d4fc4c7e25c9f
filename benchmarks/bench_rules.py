"""Cost of the design rules (with their checked advice) and of the timed search, A/B.

Each measurement runs in a fresh process on the checkout given (``--a`` and
``--b``, default: this checkout for both), interleaved A B A B, and reports
the median and the spread (min-max) of the wall and CPU time of the library
call alone (skeleton generation and start-up excluded):

* ``check_rules`` on the generated skeletons of ``generate_skeleton.py``
  (seed 0) of 1,000, 10,000 and 100,000 tasks;
* ``timed_reachability`` on the examples, with a budget of 200,000 states:
  Figure 12 (its group never repeats) runs to the budget, which gives the cost
  per state of a live group; Figure 7b is the dead design.

Usage::

    python benchmarks/bench_rules.py --a /path/to/base --b . [--runs 3] [--sizes 1000 10000]

writes ``benchmarks/results/rules.md``.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent

RULES = """
import json, sys, time
sys.path.insert(0, {root!r})
from tegraph import Skeleton
from tegraph.design.rules import check_rules
sk = Skeleton.from_dict(json.load(open({path!r})))
wall, cpu = time.perf_counter(), time.process_time()
findings = check_rules(sk)
print(json.dumps([time.perf_counter() - wall, time.process_time() - cpu, len(findings)]))
"""

TIMED = """
import json, sys, time
sys.path.insert(0, {root!r})
from tegraph import load_skeleton
from tegraph.analysis.baselines.timed_reachability import timed_reachability
sk = load_skeleton({path!r})
wall, cpu = time.perf_counter(), time.process_time()
r = timed_reachability(sk, max_states=200_000)
print(json.dumps([time.perf_counter() - wall, time.process_time() - cpu, r.states]))
"""


def run(code: str, root: Path, path: Path) -> list[float]:
    out = subprocess.run([sys.executable, "-c", code.format(root=str(root), path=str(path))],
                         capture_output=True, text=True, cwd=root, check=True)
    return json.loads(out.stdout)


def spread(values: list[float]) -> str:
    return f"{statistics.median(values):.3f} ({min(values):.3f}-{max(values):.3f})"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--a", type=Path, default=HERE.parent)
    parser.add_argument("--b", type=Path, default=HERE.parent)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--sizes", type=int, nargs="*", default=[1000, 10_000, 100_000])
    args = parser.parse_args()
    sys.path.insert(0, str(HERE))
    from generate_skeleton import generate

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        cases = []
        for n in args.sizes:
            path = Path(tmp) / f"generated-{n}.json"
            path.write_text(json.dumps(generate(n)))
            cases.append((f"check_rules, {n:,} tasks", RULES, path))
        for example in sorted((HERE.parent / "examples").glob("*.yaml")):
            if (args.a / "examples" / example.name).exists():  # both checkouts have it
                cases.append((f"timed_reachability, {example.stem}", TIMED, example))
        for label, code, path in cases:
            got: dict[str, list[list[float]]] = {"A": [], "B": []}
            for _ in range(args.runs):  # A B A B
                got["A"].append(run(code, args.a.resolve(), path))
                got["B"].append(run(code, args.b.resolve(), path))
            rows.append((label, *(spread([r[i] for r in got[s]]) for s in "AB" for i in (0, 1)),
                         got["A"][0][2], got["B"][0][2]))
            print(rows[-1], flush=True)
    lines = [f"A = `{args.a}`, B = `{args.b}`; {args.runs} runs each, interleaved A B A B; "
             "seconds, median (min-max); the last two columns: findings (rules) or states "
             "(timed search) of A and B.", "",
             "| what | A wall | A CPU | B wall | B CPU | A count | B count |",
             "|---|---:|---:|---:|---:|---:|---:|"]
    lines += ["| " + " | ".join(str(x) for x in row) + " |" for row in rows]
    out = HERE / "results" / "rules.md"
    out.write_text("# Design rules and timed search, A/B\n\n" + "\n".join(lines) + "\n")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
