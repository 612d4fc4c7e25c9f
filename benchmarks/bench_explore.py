"""Benchmark of ``tegraph explore``: variants per second, engines, batch size, model transfer.

Skeletons come from ``generate_skeleton.py`` (20 and 1,000 tasks); the design
space chooses the first links of the skeleton with all four protocols. Each
table is measured in rounds, every configuration once per round (A B C A B C),
and reports the median and the spread (min-max) over the rounds.

1. **Engines, one shot**: the wall time of a whole exploration, start-up
   included: in this process; a ``distributed.LocalCluster`` of 2 workers
   started for it; Dask's local process scheduler (``scheduler="processes"``,
   a process pool per call, the batches as delayed tasks).
2. **Throughput, warm**: variants per second once the workers are up (a
   LocalCluster started beforehand, ``scheduler=ADDRESS``), 1 and 2 workers.
3. **Batch size**: 2 warm workers, fixed batch sizes and the adaptive one.
4. **Model transfer**: the design space shipped once per worker (the worker
   plugin ``explore`` uses) against the space sent with every batch.
5. **Extrapolation**: the cost of one variant of a 10,000-task skeleton.

``--crossover`` measures where a local cluster starts to pay: whole explorations
of growing work, each in a fresh process (cold, as a new ``tegraph explore``), in
this process (``workers=0``), on a ``LocalCluster`` of 2 workers started for it
(``workers=2``, its start-up included) and with the default (``workers=None``: the
rule of ``explore/run.py``), interleaved (A B C A B C); it prints the wall times,
the engine the default chose, and the crossover of the first two (interpolated
on the in-process work).

``--ab OTHER_ROOT`` measures instead this tree (A) against another checkout (B) of
tegraph, each exploration in a fresh process (A B A B, the workers of a Dask
run importing the same tree): variants per second of a whole exploration, in
process and on a LocalCluster of 1 and 2 warm workers. Each exploration starts
cold: a design space judged incrementally (``explore/incremental.py``) keeps its
groups' figures only for that space.

Usage (Dask's local process scheduler, compared here, is the ``bench`` extra)::

    pip install '.[bench]'
    python benchmarks/bench_explore.py [--rounds 3] [--skip-10k]
    python benchmarks/bench_explore.py --ab ../base [--rounds 3]
    python benchmarks/bench_explore.py --crossover [--rounds 3]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import logging
import os
import pickle
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))

from generate_skeleton import generate  # noqa: E402

from tegraph import Skeleton  # noqa: E402
from tegraph.design.explore import explore_design  # noqa: E402
from tegraph.design.explore.evaluate import evaluate_batch, evaluate_variant  # noqa: E402
from tegraph.design.explore.space import design_space  # noqa: E402
from tegraph.model.elements import link_name  # noqa: E402


def space_of(n_tasks: int, n_links: int):
    sk = Skeleton.from_dict(generate(n_tasks, seed=0))
    links = [link_name(k.writer, k.reader) for k in sk.links[:n_links]]
    return design_space(sk, links, objectives=["period", "load"])


def cluster(workers: int):
    from distributed import LocalCluster

    return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                        host="127.0.0.1", dashboard_address="127.0.0.1:0",
                        silence_logs=logging.ERROR)


def spread(values: list[float], digits: int = 1) -> str:
    m = statistics.median(values)
    return f"{m:.{digits}f} ({min(values):.{digits}f}-{max(values):.{digits}f})"


def fresh(space):
    """A copy of ``space``: an incremental judge keeps its cache per space object, so
    every measured exploration starts cold, as a new ``tegraph explore`` does."""
    return dataclasses.replace(space)


def one_shot(space, how: str) -> float:
    space = fresh(space)
    start = time.perf_counter()
    if how == "in-process":
        explore_design(space, workers=0)
    elif how == "LocalCluster(2)":
        explore_design(space, workers=2)
    else:  # Dask's local process scheduler: a pool per call, the space in every task
        import dask

        size = max(1, space.size // 8)
        batches = [list(range(a, min(a + size, space.size))) for a in range(0, space.size, size)]
        dask.compute(*[dask.delayed(evaluate_batch)(space, b) for b in batches],
                     scheduler="processes", num_workers=2)
    return time.perf_counter() - start


def rate(space, address: str, batch_size: int | None = None) -> float:
    space = fresh(space)
    start = time.perf_counter()
    found = explore_design(space, scheduler=address, batch_size=batch_size)
    return len(found.results) / (time.perf_counter() - start)


def rate_space_per_batch(space, client, batch_size: int) -> float:
    """The space as an argument of every batch (what the plugin avoids)."""
    from distributed import wait

    start = time.perf_counter()
    batches = [list(range(a, min(a + batch_size, space.size)))
               for a in range(0, space.size, batch_size)]
    futures = [client.submit(evaluate_batch, space, b, pure=False) for b in batches]
    wait(futures)
    return space.size / (time.perf_counter() - start)


# One exploration in a fresh process, on the tegraph of ROOT (argv: ROOT, tasks, links,
# "in-process" or a number of warm LocalCluster workers); prints variants and seconds.
_CHILD = r"""
import json, logging, sys, time
root, n, k, how = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
sys.path[:0] = [root, root + "/benchmarks"]
from generate_skeleton import generate
import tegraph
assert tegraph.__file__.startswith(root), tegraph.__file__
from tegraph import Skeleton
from tegraph.design.explore import explore_design
from tegraph.design.explore.space import design_space
sk = Skeleton.from_dict(generate(n, seed=0))
# The links named as the input names them (W:p -> R:q), which every checkout reads alike.
space = design_space(sk, [f"{x.writer[0]}:{x.writer[1]} -> {x.reader[0]}:{x.reader[1]}"
                          for x in sk.links[:k]],
                     objectives=["period", "load"])
if how == "in-process":
    start = time.perf_counter()
    found = explore_design(space, workers=0)
else:
    from distributed import Client, LocalCluster
    w = int(how)
    with LocalCluster(n_workers=w, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address="127.0.0.1:0", silence_logs=logging.ERROR) as c, \
            Client(c) as client:
        client.wait_for_workers(w)
        client.run(lambda: __import__("tegraph.design.explore.evaluate"))
        start = time.perf_counter()
        found = explore_design(space, scheduler=c.scheduler_address)
print(json.dumps({"variants": len(found.results), "seconds": time.perf_counter() - start}))
"""


# One exploration in a fresh process (argv: tasks, links, workers: "0", "2" or "auto");
# prints its variants, seconds (the exploration alone: the cluster's start included,
# the interpreter's imports not) and the engine used.
_CROSSOVER_CHILD = r"""
import json, sys, time
root, n, k, how = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
sys.path[:0] = [root, root + "/benchmarks"]
from generate_skeleton import generate
from tegraph import Skeleton
from tegraph.design.explore import explore_design
from tegraph.model.elements import link_name
from tegraph.design.explore.space import design_space
sk = Skeleton.from_dict(generate(n, seed=0))
space = design_space(sk, [link_name(x.writer, x.reader) for x in sk.links[:k]],
                     objectives=["period", "load"])
start = time.perf_counter()
found = explore_design(space, workers=None if how == "auto" else int(how))
print(json.dumps({"variants": len(found.results), "seconds": time.perf_counter() - start,
                  "engine": found.log.engine, "workers": found.log.workers}))
"""

CROSSOVER_CASES = [(20, 5), (1000, 5), (1000, 6), (1000, 7)]


def crossover(rounds: int) -> None:
    """Wall time of whole explorations in process, on a LocalCluster(2) and by default."""
    root = str(HERE.parent)
    ways = ["0", "2", "auto"]
    got: dict[tuple, list[dict]] = {(c, w): [] for c in CROSSOVER_CASES for w in ways}
    for _ in range(rounds):
        for case in CROSSOVER_CASES:
            for how in ways:
                out = subprocess.run([sys.executable, "-c", _CROSSOVER_CHILD, root,
                                      *map(str, case), how], cwd=root, capture_output=True,
                                     text=True, timeout=3600, check=True)
                row = json.loads(out.stdout.strip().splitlines()[-1])
                got[case, how].append(row)
                print(f"  {case} workers={how}: {row}", file=sys.stderr, flush=True)
    print(f"seconds of a whole exploration, median (min-max) of {rounds}; os.cpu_count() = "
          f"{os.cpu_count()}\n")
    print("| tasks | links | variants judged | in process | LocalCluster(2), start included "
          "| cluster / in process | default | default's engine |")
    print("|---:|---:|---:|---:|---:|---:|---:|---|")
    points = []
    for case in CROSSOVER_CASES:
        inp = [r["seconds"] for r in got[case, "0"]]
        two = [r["seconds"] for r in got[case, "2"]]
        auto = [r["seconds"] for r in got[case, "auto"]]
        engines = sorted({f"{r['engine']} ({r['workers']})" for r in got[case, "auto"]})
        points.append((statistics.median(inp), statistics.median(two)))
        print(f"| {case[0]:,} | {case[1]} | {got[case, '0'][0]['variants']:,} | {spread(inp, 2)} "
              f"| {spread(two, 2)} | {statistics.median(two) / statistics.median(inp):.2f} "
              f"| {spread(auto, 2)} | {', '.join(engines)} |")
    # The crossover: the in-process work W where the cluster's time equals W, linear
    # between the two measured points that bracket it.
    points.sort()
    for (w1, c1), (w2, c2) in zip(points, points[1:]):
        if c1 >= w1 and c2 < w2:
            # c(w) = c1 + (w - w1) (c2 - c1) / (w2 - w1) = w
            slope = (c2 - c1) / (w2 - w1)
            w = (c1 - slope * w1) / (1 - slope)
            print(f"\ncrossover: a LocalCluster(2) pays from about {w:.1f} s of in-process "
                  "work (interpolated between the measured points)")
            break
    else:
        side = "never" if all(c >= w for w, c in points) else "always"
        print(f"\ncrossover: not bracketed by the measured points (the cluster {side} pays "
              "over this range)")


def ab(other: str, rounds: int) -> None:
    """This tree (A) against ``other`` (B): variants/s of whole explorations, cold."""
    roots = {"A": str(HERE.parent), "B": str(Path(other).resolve())}
    # The published spaces on both trees; larger ones (where two workers can pay) on A
    # only: B, judging every variant afresh, would take too long on them.
    both, only_a = ("A", "B"), ("A",)
    cases = [(20, 3, "in-process", both), (1000, 2, "in-process", both),
             (20, 3, "1", both), (20, 3, "2", both), (1000, 2, "1", both),
             (1000, 2, "2", both), (20, 5, "in-process", only_a), (20, 5, "1", only_a),
             (20, 5, "2", only_a), (1000, 5, "in-process", only_a),
             (1000, 5, "1", only_a), (1000, 5, "2", only_a)]
    got: dict[tuple, list[float]] = {(c[:3], r): [] for c in cases for r in roots}
    for _ in range(rounds):
        for *case, names in cases:
            for name in names:
                root = roots[name]
                env = dict(os.environ, PYTHONPATH=root)
                out = subprocess.run([sys.executable, "-c", _CHILD, root, *map(str, case)],
                                     cwd=root, env=env, capture_output=True, text=True,
                                     timeout=3600, check=True)
                row = json.loads(out.stdout.strip().splitlines()[-1])
                got[tuple(case), name].append(row["variants"] / row["seconds"])
                print(f"  {name} {case}: {row['variants']} variants, {row['seconds']:.2f} s",
                      file=sys.stderr, flush=True)
    print(f"A = {roots['A']}, B = {roots['B']}; variants/s, median (min-max) of {rounds}\n")
    print("| tasks | links | variants | engine | A | B | A/B |")
    print("|---:|---:|---:|---|---:|---:|---:|")
    for n, k, how, _ in cases:
        a, b = got[(n, k, how), "A"], got[(n, k, how), "B"]
        engine = "in process" if how == "in-process" else f"{how} warm worker(s)"
        ratio = f"{statistics.median(a) / statistics.median(b):.1f}x" if b else "-"
        print(f"| {n:,} | {k} | {4 ** k} | {engine} | {spread(a, 1)} | "
              f"{spread(b, 2) if b else '-'} | {ratio} |")
    for n, k in sorted({(n, k) for n, k, how, _ in cases if how == "2"}):
        for name in roots:
            one, two = got[(n, k, "1"), name], got[(n, k, "2"), name]
            if one and two:
                print(f"{name}: {n:,} tasks, {4 ** k} variants: 2 workers / 1 worker = "
                      f"{statistics.median(two) / statistics.median(one):.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--skip-10k", action="store_true")
    parser.add_argument("--ab", metavar="OTHER_ROOT",
                        help="compare this tree with another checkout (see the docstring)")
    parser.add_argument("--crossover", action="store_true",
                        help="where a local cluster starts to pay (see the docstring)")
    args = parser.parse_args()
    if args.crossover:
        crossover(args.rounds)
        return
    if args.ab:
        ab(args.ab, args.rounds)
        return
    from distributed import Client

    spaces = {20: space_of(20, 3), 1000: space_of(1000, 2)}
    for n, s in spaces.items():
        print(f"# {n} tasks: {len(s.skeleton.links)} links, {s.size} variants; pickled space "
              f"{len(pickle.dumps(s)) / 1024:.0f} KiB", flush=True)

    print("\n## 1. One exploration, start-up included (s)\n")
    ways = ["in-process", "LocalCluster(2)", "process scheduler(2)"]
    times = {(n, w): [] for n in spaces for w in ways}
    for _ in range(args.rounds):
        for n, s in spaces.items():
            for w in ways:
                times[n, w].append(one_shot(s, w))
    print("| tasks | variants | " + " | ".join(ways) + " |")
    print("|---:|---:|" + "---:|" * len(ways))
    for n, s in spaces.items():
        print(f"| {n:,} | {s.size} | " + " | ".join(spread(times[n, w], 2) for w in ways)
              + " |", flush=True)
    start = time.perf_counter()
    with cluster(2) as c, Client(c) as client:
        client.wait_for_workers(2)
        started = time.perf_counter() - start
    print(f"\nLocalCluster(2) start and stop alone: {started:.2f} s")

    print("\n## 2. Throughput with warm workers (variants/s)\n")
    one, two = cluster(1), cluster(2)
    try:
        warm = {"1 worker": one.scheduler_address, "2 workers": two.scheduler_address}
        for address in warm.values():
            with Client(address) as client:
                client.wait_for_workers(1)
        rates = {(n, w): [] for n in spaces for w in [*warm, "in-process"]}
        for _ in range(args.rounds):
            for n, s in spaces.items():
                for w, address in warm.items():
                    rates[n, w].append(rate(s, address))
                cold = fresh(s)
                start = time.perf_counter()
                explore_design(cold, workers=0)
                rates[n, "in-process"].append(s.size / (time.perf_counter() - start))
        print("| tasks | in-process | LocalCluster 1 worker | LocalCluster 2 workers | "
              "speed-up 2 vs 1 |")
        print("|---:|---:|---:|---:|---:|")
        for n in spaces:
            r1, r2 = rates[n, "1 worker"], rates[n, "2 workers"]
            print(f"| {n:,} | {spread(rates[n, 'in-process'], 2)} | {spread(r1, 2)} | "
                  f"{spread(r2, 2)} | {statistics.median(r2) / statistics.median(r1):.2f} |",
                  flush=True)

        print("\n## 3. Batch size, 2 warm workers, 20 tasks (variants/s)\n")
        sizes: list[int | None] = [1, 4, 16, 64, None]
        by_size = {b: [] for b in sizes}
        for _ in range(args.rounds):
            for b in sizes:
                by_size[b].append(rate(spaces[20], two.scheduler_address, b))
        print("| batch | " + " | ".join("adaptive" if b is None else str(b) for b in sizes)
              + " |")
        print("|---|" + "---:|" * len(sizes))
        print("| variants/s | " + " | ".join(spread(by_size[b]) for b in sizes) + " |",
              flush=True)

        print("\n## 4. Model transfer, 2 warm workers, 1,000 tasks (variants/s)\n")
        s = spaces[1000]
        blob = pickle.dumps(s)
        t0 = time.perf_counter()
        for _ in range(10):
            pickle.loads(pickle.dumps(s))
        codec = (time.perf_counter() - t0) / 10
        ship = {("plugin", b): [] for b in (1, 8)} | {("per batch", b): [] for b in (1, 8)}
        with Client(two.scheduler_address) as client:
            for _ in range(args.rounds):
                for b in (1, 8):
                    ship["plugin", b].append(rate(s, two.scheduler_address, b))
                    ship["per batch", b].append(rate_space_per_batch(s, client, b))
        print(f"space: {len(blob) / 1024:.0f} KiB pickled, {codec * 1000:.1f} ms to pickle and "
              "unpickle\n")
        print("| batch | space once per worker (plugin) | space with every batch |")
        print("|---:|---:|---:|")
        for b in (1, 8):
            print(f"| {b} | {spread(ship['plugin', b], 2)} | {spread(ship['per batch', b], 2)} |",
                  flush=True)
    finally:
        one.close()
        two.close()

    if not args.skip_10k:
        print("\n## 5. One variant of a 10,000-task skeleton\n")
        s = space_of(10_000, 2)
        costs = []
        for v in range(3):
            start = time.perf_counter()
            evaluate_variant(s, v)
            costs.append(time.perf_counter() - start)
        per = statistics.median(costs)
        total = 4 ** 10 * per
        print(f"judging one variant: {spread(costs, 2)} s; pickled space "
              f"{len(pickle.dumps(s)) / 2**20:.1f} MiB")
        print(f"4^10 = {4 ** 10:,} variants: {total / 3600:,.0f} h on one worker, "
              f"{total / 64 / 3600:,.1f} h on 64 workers (cost alone, no pruning)")


if __name__ == "__main__":
    main()
