"""End-to-end benchmark of ``tegraph analyze --json`` on generated skeletons.

Skeletons of 1,000, 10,000 and 100,000 tasks in synchronized groups of 3 to 30
tasks with mixed protocols, clocks, a few threads and a few double
synchronizations (``generate_skeleton.py``). Each run is a fresh process (so
the time includes start-up, reading the file and writing the JSON), and its
peak resident memory is measured from inside that process.

Usage::

    python benchmarks/bench_analyze.py [--sizes 1000 10000 100000] [--runs 3]
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent

CHILD = """
import resource, sys
from tegraph.cli import main
sys.argv = ["tegraph", "analyze", sys.argv[1], "--json"]
try:
    main()
except SystemExit as exc:
    code = exc.code
with open({rss!r}, "w") as fh:
    fh.write(str(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss))
sys.exit(code)
"""


def measure(path: Path, rss_file: Path) -> tuple[float, float, dict]:
    start = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", CHILD.format(rss=str(rss_file)), str(path)],
                         capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    if out.returncode not in (0, 1):
        raise RuntimeError(out.stderr)
    return elapsed, int(rss_file.read_text()) / 1024, json.loads(out.stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10_000, 100_000])
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    sys.path.insert(0, str(HERE))
    from generate_skeleton import generate

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in args.sizes:
            path = Path(tmp) / f"sk{n}.json"
            path.write_text(json.dumps(generate(n, seed=0)))
            runs = args.runs if n <= 10_000 else 1
            results = [measure(path, Path(tmp) / "rss") for _ in range(runs)]
            times = [r[0] for r in results]
            report = results[-1][2]
            rows.append((n, statistics.median(times), max(r[1] for r in results), report))
    print("| tasks | groups | time, median (s) | peak memory (MiB) | live | unbounded places | "
          "overruns | semiflow cross-check |")
    print("|---:|---:|---:|---:|---|---:|---:|---|")
    for n, t, mem, rep in rows:
        overruns = sum(1 for task in rep["tasks"].values() if task["overrun_at"] is not None)
        inv = rep["invariants"]
        cross = (f"{inv['count']} semiflows, agrees" if inv["computed"] and inv["liveness_agrees"]
                 else "not run (budget)" if not inv["computed"] else "DISAGREES")
        print(f"| {n:,} | {len(rep['groups']):,} | {t:.2f} | {mem:.0f} | {rep['live']} | "
              f"{len(rep['unbounded_places']):,} | {overruns} | {cross} |")


if __name__ == "__main__":
    main()
