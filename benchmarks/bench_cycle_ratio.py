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

Prints a Markdown table (the one in the README).

``--crossover`` measures instead, in this process, the time per solve of the
two kernels (numpy arrays, Python lists: ``maxplus._small_howard``) on small
graphs of several families, to place ``SMALL_GRAPH_ARCS``::

    python benchmarks/bench_cycle_ratio.py --crossover --runs 5
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


def crossover_families(m: int, seed: int) -> dict:
    """Graphs of about ``m`` arcs: the shapes max_cycle_ratio meets."""
    import numpy as np
    from sprand import sprand

    rng = np.random.default_rng(seed)
    n = max(2, m // 4)
    ring_n = max(2, m // 2)  # ring i -> i+1 and chords i -> i+2: 2 arcs per node
    ring = np.arange(ring_n)
    ring_src = np.concatenate([ring, ring])
    ring_dst = np.concatenate([(ring + 1) % ring_n, (ring + 2) % ring_n])
    src, dst, w, t = sprand(n, seed=seed, layout="canonical")
    # Controller-like: per task a circuit of 2 events (1 token), chains of
    # token-free links between tasks, a few feedbacks, one slow clock per 10 tasks.
    tasks = max(1, m // 4)
    c_src, c_dst, c_w, c_t = [], [], [], []
    for k in range(tasks):
        a, b = 2 * k, 2 * k + 1
        c_src += [a, b]
        c_dst += [b, a]
        c_w += [int(rng.integers(1, 100)), 0]
        c_t += [0, 1]
        if k:
            c_src.append(2 * int(rng.integers(0, k)) + 1)
            c_dst.append(a)
            c_w.append(0)
            c_t.append(int(rng.integers(0, 2)))
        if k % 10 == 0:
            c_src.append(a)
            c_dst.append(a)
            c_w.append(int(rng.integers(100, 1000)))
            c_t.append(1)
    return {
        "sprand": (src, dst, w, t),
        "sprand equal weights": (src, dst, np.full(len(src), 7), t),
        "ring with chords": (ring_src, ring_dst, rng.integers(1, 10**4, 2 * ring_n),
                             np.ones(2 * ring_n, dtype=np.int64)),
        "controller-like": tuple(np.array(x) for x in (c_src, c_dst, c_w, c_t)),
    }


def crossover(runs: int, seed: int) -> None:
    """Median time per solve of each kernel, by family and size (in arcs)."""
    sys.path.insert(0, str(HERE))
    sys.path.insert(0, str(HERE.parent))
    import maxplus._small_howard as small
    from maxplus.cycle_ratio import max_cycle_ratio

    def per_solve(graph, limit: int) -> float:
        small.SMALL_GRAPH_ARCS = limit
        max_cycle_ratio(*graph)
        repeat = max(1, int(0.05 / max(1e-6, _once(max_cycle_ratio, graph))))
        times = []
        for _ in range(runs):
            start = time.perf_counter()
            for _ in range(repeat):
                max_cycle_ratio(*graph)
            times.append((time.perf_counter() - start) / repeat)
        return statistics.median(times)

    print("| family | arcs | numpy kernel (ms) | list kernel (ms) | lists / numpy |")
    print("|---|---:|---:|---:|---:|")
    for m in (10, 30, 100, 300, 500, 700, 1000, 2000, 5000):
        for name, graph in crossover_families(m, seed).items():
            arrays, lists = per_solve(graph, -1), per_solve(graph, 10**9)
            print(f"| {name} | {len(graph[0]):,} | {arrays * 1e3:.3f} | {lists * 1e3:.3f} | "
                  f"{lists / arrays:.2f} |", flush=True)


def _once(solve, graph) -> float:
    start = time.perf_counter()
    solve(*graph)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10**4, 10**5, 10**6])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--child", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--crossover", action="store_true",
                        help="time both kernels on small graphs (SMALL_GRAPH_ARCS)")
    args = parser.parse_args()
    if args.crossover:
        crossover(args.runs, args.seed)
        return
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
