"""Howard's kernels side by side on small graphs: does each one pay where it runs?

``max_cycle_ratio`` (validation, the zero-token check, Howard, the critical
circuit: the whole call a caller pays) on each kernel of the switch
``maxplus._kernels``, on graphs of 6 to 2,000 arcs of four families
(:func:`families`: SPRAND with m = 4n, the same with equal weights, a ring
with chords, a controller-like graph). The kernels run interleaved, A B C A B
C, each sample a batch of solves lasting about ``BATCH_SECONDS``; the table gives the median
time per solve and the spread (min-max) over the samples, and each kernel's
time over the compiled kernel's.

``--against DIR`` compares instead what a caller gets by default (no switch:
whatever ``max_cycle_ratio`` chooses) in this checkout and in the checkout
``DIR`` (an older commit, its kernels built in place), one process per
checkout and round, the checkouts alternated A B A B.

Usage::

    python benchmarks/bench_small_graphs.py                    # every kernel built here
    python benchmarks/bench_small_graphs.py --runs 9 --kernels compiled numpy
    python benchmarks/bench_small_graphs.py --against /tmp/main-checkout --runs 7

Prints a Markdown table with the commit, the machine's load before and after,
and the Python and numpy versions (``benchmarks/results/small_graphs.md``).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))


def _checkout(argv: list[str]) -> Path:
    """The checkout whose maxplus is measured: ``--checkout DIR``, else this one."""
    return Path(argv[argv.index("--checkout") + 1]) if "--checkout" in argv else HERE.parent


sys.path.insert(0, str(_checkout(sys.argv)))  # a checkout, not an installed copy

BATCH_SECONDS = 0.02
"""Each sample times a batch of solves this long: timer resolution and call
overhead stay small beside it."""

SIZES = (10, 30, 60, 100, 200, 350, 500, 1000, 2000)
"""About this many arcs per graph (each family rounds it its own way)."""


def families(m: int, seed: int) -> dict:
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


def _kernels_here() -> list[str]:
    from maxplus import _kernels

    kernels = [k for k in _kernels.KERNELS if k != "auto"]
    return [k for k in kernels if k != "compiled" or all(_kernels.compiled().values())]


def _batch(graph, kernel: str, repeat: int) -> float:
    """Seconds per solve of ``repeat`` solves of ``graph`` on ``kernel`` (``default``: no
    switch, as a caller runs it; a checkout without the switch knows only that one)."""
    from contextlib import nullcontext

    from maxplus.cycle_ratio import max_cycle_ratio

    if kernel == "default":
        chosen = nullcontext()
    else:
        from maxplus import _kernels

        chosen = _kernels.use(kernel)
    with chosen:
        start = time.perf_counter()
        for _ in range(repeat):
            max_cycle_ratio(*graph)
        return (time.perf_counter() - start) / repeat


def measure(graph, kernels: list[str], runs: int) -> dict[str, list[float]]:
    """Per kernel, ``runs`` samples of the time per solve, the kernels interleaved."""
    repeat = {}
    for kernel in kernels:  # warm up, and size each batch to BATCH_SECONDS
        once = max(_batch(graph, kernel, 1), _batch(graph, kernel, 1), 1e-6)
        repeat[kernel] = max(1, int(BATCH_SECONDS / once))
    samples: dict[str, list[float]] = {k: [] for k in kernels}
    for _ in range(runs):
        for kernel in kernels:
            samples[kernel].append(_batch(graph, kernel, repeat[kernel]))
    return samples


def _commit(where: Path) -> str:
    try:
        out = subprocess.run(["git", "-C", str(where), "log", "-1", "--format=%h %cI"],
                             capture_output=True, text=True, check=True)
        dirty = subprocess.run(["git", "-C", str(where), "status", "--porcelain", "--",
                                "maxplus"], capture_output=True, text=True, check=True)
        return out.stdout.strip() + (" (maxplus modified)" if dirty.stdout.strip() else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown (not a git checkout)"


def _one_round(checkout: Path, sizes: list[int], seed: int) -> dict[str, float]:
    """One sample per graph of the default kernel of ``checkout``, in a fresh process."""
    out = subprocess.run([sys.executable, __file__, "--checkout", str(checkout), "--child",
                          "--sizes", *map(str, sizes), "--seed", str(seed)],
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def against(other: Path, runs: int, sizes: list[int], seed: int) -> None:
    """The default kernel here and in ``other``, one process per round, A B A B."""
    here = HERE.parent
    print(f"this checkout: commit {_commit(here)}; against {other}: commit {_commit(other)}; "
          f"load {os.getloadavg()[0]:.1f} before", flush=True)
    samples: dict[Path, list[dict[str, float]]] = {here: [], other: []}
    for _ in range(runs):
        for checkout in (other, here):
            samples[checkout].append(_one_round(checkout, sizes, seed))
    print()
    print("| family | arcs | before (us) | after (us) | after / before |")
    print("|---|---:|---:|---:|---:|")
    for cell in samples[here][0]:
        before = [s[cell] for s in samples[other]]
        after = [s[cell] for s in samples[here]]
        b, a = statistics.median(before), statistics.median(after)
        name, arcs = cell.rsplit(" ", 1)
        print(f"| {name} | {int(arcs):,} | {b * 1e6:,.0f} ({min(before) * 1e6:,.0f}-"
              f"{max(before) * 1e6:,.0f}) | {a * 1e6:,.0f} ({min(after) * 1e6:,.0f}-"
              f"{max(after) * 1e6:,.0f}) | {a / b:.2f} |", flush=True)
    print()
    print(f"load {os.getloadavg()[0]:.1f} after; {runs} rounds, a process per checkout and "
          "round, alternated; median (min-max) time per solve of max_cycle_ratio by default.")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=7, help="samples per kernel and graph")
    parser.add_argument("--kernels", nargs="+", help="default: every kernel built here")
    parser.add_argument("--sizes", type=int, nargs="+", default=list(SIZES))
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--against", type=Path, help="compare the default kernel with DIR's")
    parser.add_argument("--checkout", type=Path, help=argparse.SUPPRESS)
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.against:
        against(args.against.resolve(), args.runs, args.sizes, args.seed)
        return
    if args.child:  # one sample per graph of the default kernel, as JSON
        cells = {}
        for m in args.sizes:
            for name, graph in families(m, args.seed).items():
                cells[f"{name} {len(graph[0])}"] = measure(graph, ["default"], 1)["default"][0]
        print(json.dumps(cells))
        return
    import numpy as np


    kernels = args.kernels or _kernels_here()
    base = "compiled" if "compiled" in kernels else kernels[0]
    load_before = os.getloadavg()
    print(f"commit {_commit(HERE.parent)}; Python {platform.python_version()}, "
          f"numpy {np.__version__}; {os.cpu_count()} cores, load {load_before[0]:.1f} before",
          flush=True)
    print()
    head = " | ".join(f"{k} (us)" for k in kernels)
    ratios = " | ".join(f"{k} / {base}" for k in kernels if k != base)
    print(f"| family | arcs | {head} | {ratios} |")
    print("|---|---:|" + "---:|" * (2 * len(kernels) - 1))
    for m in args.sizes:
        for name, graph in families(m, args.seed).items():
            samples = measure(graph, kernels, args.runs)
            medians = {k: statistics.median(v) for k, v in samples.items()}
            cells = " | ".join(f"{medians[k] * 1e6:,.0f} ({min(samples[k]) * 1e6:,.0f}-"
                               f"{max(samples[k]) * 1e6:,.0f})" for k in kernels)
            quotients = " | ".join(f"{medians[k] / medians[base]:.2f}" for k in kernels
                                   if k != base)
            print(f"| {name} | {len(graph[0]):,} | {cells} | {quotients} |", flush=True)
    print()
    print(f"load {os.getloadavg()[0]:.1f} after; {args.runs} samples per cell, kernels "
          "interleaved; median (min-max) time per solve of max_cycle_ratio.")


if __name__ == "__main__":
    main()
