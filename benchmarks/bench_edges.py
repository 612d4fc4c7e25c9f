"""Benchmark of the arc-list (``.edges``) reader and writer at 4 million lines.

An SPRAND-style graph (``sprand.py``: n = 10^6 nodes, m = 4n arcs, weights
1..10^4, tokens 1..10, seed 1) is written with ``tegraph.io.edges.write_edges``
and read back with ``read_edges``, in a temporary directory. Prints the median
wall time of each over the runs, the file size, the peak resident memory of
the process, and checks that the arrays read back equal the ones written.
A second pass uses exact non-integer holding times (``k/4``), which take the
slower vectorized path.

Usage::

    python benchmarks/bench_edges.py              # 4,000,000 lines, 3 runs
    python benchmarks/bench_edges.py --lines 400000 --runs 1
"""

from __future__ import annotations

import argparse
import resource
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent


def bench(lines: int, runs: int, scale: int) -> dict:
    sys.path.insert(0, str(HERE))
    from sprand import sprand

    from tegraph.io.edges import ArcList, read_edges, write_edges

    src, dst, weight, tokens = sprand(lines // 4, seed=1)
    graph = ArcList(src, dst, weight, tokens, scale, None, lines // 4, "sprand")
    write_times, read_times = [], []
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "g.edges"
        for _ in range(runs):
            path.unlink(missing_ok=True)
            t0 = time.perf_counter()
            write_edges(graph, path)
            write_times.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            back = read_edges(path)
            read_times.append(time.perf_counter() - t0)
        size = path.stat().st_size
    same = (np.array_equal(back.src, src) and np.array_equal(back.dst, dst)
            and np.array_equal(back.tokens, tokens) and back.scale == scale
            and np.array_equal(back.holding, weight))
    return {"write": statistics.median(write_times), "read": statistics.median(read_times),
            "size": size, "same": same}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lines", type=int, default=4_000_000)
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    print("| lines | holding times | file (MB) | write, median (s) | read, median (s) "
          "| round trip equal |")
    print("|---:|---|---:|---:|---:|---|")
    for scale, what in ((1, "integers"), (4, "quarters (k/4)")):
        r = bench(args.lines, args.runs, scale)
        print(f"| {args.lines:,} | {what} | {r['size'] / 1e6:.0f} | {r['write']:.2f} "
              f"| {r['read']:.2f} | {r['same']} |")
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"\npeak resident memory of the process: {peak:.0f} MiB")


if __name__ == "__main__":
    main()
