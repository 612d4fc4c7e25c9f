"""Benchmark of maxplus.max_cycle_ratio on SPRAND-style graphs (issue: maxplus foundation).

Random strongly connected graphs with n nodes and m = 4n arcs, integer
weights 1..10^4 and tokens 1..10, fixed seeds. For each n: median wall time of
``max_cycle_ratio`` over the runs, the time of the independent certificate
check, the number of Howard iterations, and the peak resident memory of a
fresh process that builds the graph and solves it (each size runs in its own
process so that peaks do not mix).

Usage::

    python benchmarks/bench_cycle_ratio.py            # 10^4, 10^5, 10^6, 5 runs each
    python benchmarks/bench_cycle_ratio.py --sizes 10000 --runs 3

Prints a Markdown table (the one in the README). The kernels side by side on
small graphs: ``bench_small_graphs.py``.
"""

from __future__ import annotations

import argparse
import json
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def run_one(n: int, runs: int, seed: int) -> dict:
    sys.path.insert(0, str(HERE))
    sys.path.insert(0, str(HERE.parent))  # the checkout, not an installed copy
    from sprand import sprand

    from maxplus.cycle_ratio import max_cycle_ratio

    graph = sprand(n, seed=seed)
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        result = max_cycle_ratio(*graph)
        times.append(time.perf_counter() - start)
    start = time.perf_counter()
    result.verify()
    verify_time = time.perf_counter() - start
    peak_kib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return {
        "n": n, "m": len(graph[0]), "median_s": statistics.median(times),
        "min_s": min(times), "verify_s": verify_time, "iterations": result.iterations,
        "peak_mib": peak_kib / 1024, "ratio": str(result.ratio),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10**4, 10**5, 10**6])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--child", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(run_one(args.child, args.runs, args.seed)))
        return
    rows = []
    for n in args.sizes:
        out = subprocess.run([sys.executable, __file__, "--child", str(n), "--runs", str(args.runs),
                              "--seed", str(args.seed)], check=True, capture_output=True, text=True)
        rows.append(json.loads(out.stdout))
    print("| n | m | median time (s) | certificate check (s) | Howard iterations "
          "| peak memory (MiB) | max cycle ratio |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r['n']:,} | {r['m']:,} | {r['median_s']:.2f} | {r['verify_s']:.2f} | "
              f"{r['iterations']} | {r['peak_mib']:.0f} | {r['ratio']} |")


if __name__ == "__main__":
    main()
