"""Benchmark of ``tegraph explore`` choosing where tasks run (``offer``, ``allocate``).

The skeletons are built here (:func:`grouped`): ``G`` groups of ``S`` tasks, each
group an ASYN/SYN chain driven by the clock of its first task (10 ms or 20 ms,
alternating), its durations summing to ``share`` of the period; the last task of
each group writes to the first task of the next one through an ASYN/ASYN link (no
place: the groups stay apart until a chosen protocol joins them). The input design
puts group ``g`` on processor ``g mod P``; ``network.delay`` is 1/10 ms.

1. **(a) exhaustive**: 5 groups of 4 tasks (20 tasks, share 7/20: three groups on one
   processor are over its time), the 4 links between the groups chosen among the four
   protocols, the groups' processors among 3 offered (``allocate="groups"``), every
   variant judged in this process. Three platforms: ``cpu1,cpu2,cpu3`` alike (the
   target row: a placement and its renamings are one variant), ``cpu3`` declared
   ``preemptive: false`` (``cpu1`` and ``cpu2`` alike), and that platform with ``G0``
   pinned to ``cpu1`` (a processor holding a pinned unit is like no other, so none is
   interchangeable: ``3^4`` placements of the other four groups).
2. **Incremental against from scratch**: a uniform sample of the target space's
   variants, each judged on a fresh copy of the space (cold caches, as a new ``tegraph
   explore`` starts), ``evaluate_variant(..., incremental=True)`` and ``False``
   interleaved (A B A B); the whole space judged incrementally is row (a). The same on a
   sample of the (b) space (``--sample-b``).
3. **(b) local search**: 20 groups of 50 tasks (1,000 tasks, share 3/20), only the
   groups' processors chosen among 4 alike ones, Pareto local search of 1,000 variants
   (``max_variants=1000``), on a ``distributed.LocalCluster`` of 2 workers bound to
   127.0.0.1 started and stopped here (its start counted apart), and in this process,
   interleaved (A B A B).
4. **How the allocation space grows**: canonical placements against ``k^n``
   (:class:`tegraph.design.explore.allocation.Allocation`, counted, not judged).

Medians of the rounds, spread as min-max; a target is "met" when the median is under it.

Usage::

    pip install '.[bench]'
    python benchmarks/bench_explore_allocation.py [--rounds 3] [--sample 300]
        [--sample-b 10] [--only a,incremental,b,growth,incremental-b]
"""

from __future__ import annotations

import argparse
import dataclasses
import logging
import os
import random
import statistics
import sys
import time
from fractions import Fraction
from math import comb
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from tegraph import Skeleton  # noqa: E402
from tegraph.design.explore import explore_design  # noqa: E402
from tegraph.design.explore.allocation import Allocation  # noqa: E402
from tegraph.design.explore.evaluate import evaluate_variant  # noqa: E402
from tegraph.design.explore.space import design_space  # noqa: E402

TARGET_A = 10.0
TARGET_B = 60.0


def grouped(n_groups: int, size: int, processors: int, share: Fraction,
            non_preemptive: tuple[str, ...] = (), delay: str = "1/10", seed: int = 0) -> dict:
    """``n_groups`` ASYN/SYN chains of ``size`` tasks joined by ASYN/ASYN links (see the
    module docstring); processors ``cpu1`` ... ``cpuP``."""
    rng = random.Random(seed)
    tasks: dict[str, dict] = {}
    links: list[dict] = []
    for g in range(n_groups):
        period = 10 if g % 2 == 0 else 20
        # Integer weights, exact durations: the group's sum is share * period.
        weights = [rng.randint(1, 9) for _ in range(size)]
        for k, w in enumerate(weights):
            d = share * period * w / sum(weights)
            task: dict = {"duration": f"{d.numerator}/{d.denominator}",
                          "processor": f"cpu{g % processors + 1}"}
            if k == 0:
                task["period"] = period
            if k > 0:
                task["inputs"] = ["i"]
                links.append({"from": f"G{g}.T{k - 1}:o", "to": f"G{g}.T{k}:i",
                              "protocol": "ASYN/SYN"})
            if k < size - 1:
                task["outputs"] = ["o"]
            tasks[f"G{g}.T{k}"] = task
    between = []
    for g in range(n_groups - 1):
        last, first = f"G{g}.T{size - 1}", f"G{g + 1}.T0"
        tasks[last].setdefault("outputs", []).append("x")
        tasks[first].setdefault("inputs", []).append("x")
        links.append({"from": f"{last}:x", "to": f"{first}:x", "protocol": "ASYN/ASYN"})
        between.append(f"{last}:x -> {first}:x")
    doc = {"name": f"grouped-{n_groups}x{size}", "unit": "ms", "tasks": tasks,
           "links": links, "network": {"delay": delay}, "between": between}
    if non_preemptive:
        doc["processors"] = {p: {"preemptive": False} for p in non_preemptive}
    return doc


def skeleton_and_links(doc: dict) -> tuple[Skeleton, list[str]]:
    doc = dict(doc)
    between = doc.pop("between")
    return Skeleton.from_dict(doc), between


OFFER3 = ["cpu1", "cpu2", "cpu3"]
PLATFORMS_A = {  # name -> (non-preemptive processors, pins)
    "3 alike": ((), ()),
    "cpu1, cpu2 alike; cpu3 non-preemptive": (("cpu3",), ()),
    "G0 pinned to cpu1, cpu3 non-preemptive: none alike": (("cpu3",), ("G0.T0=cpu1",)),
}


def space_a(platform: str):
    non_preemptive, pin = PLATFORMS_A[platform]
    sk, between = skeleton_and_links(grouped(5, 4, 3, Fraction(7, 20), non_preemptive))
    return design_space(sk, between, offer=OFFER3, allocate="groups", pin=pin)


def space_b():
    sk, _ = skeleton_and_links(grouped(20, 50, 4, Fraction(3, 20)))
    return design_space(sk, offer=["cpu1", "cpu2", "cpu3", "cpu4"], allocate="groups")


def fresh(space):
    """A copy of ``space``: an incremental judge keeps its caches per space object, so
    a measured exploration on a copy starts cold, as a new ``tegraph explore`` does."""
    return dataclasses.replace(space)


def spread(values: list[float], digits: int = 2) -> str:
    m = statistics.median(values)
    return f"{m:,.{digits}f} ({min(values):,.{digits}f}-{max(values):,.{digits}f})"


def verdict(median: float, target: float) -> str:
    return "met" if median < target else "**not met**"


def counts(found) -> str:
    judged = {}
    for r in found.results.values():
        judged[r.judged] = judged.get(r.judged, 0) + 1
    kept = sum(1 for r in found.results.values() if r.kept)
    return ", ".join(f"{n:,} {k}" for k, n in sorted(judged.items())) + f"; {kept:,} kept"


def run_a(rounds: int) -> None:
    spaces = {p: space_a(p) for p in PLATFORMS_A}
    seconds: dict[str, list[float]] = {p: [] for p in spaces}
    last = {}
    for _ in range(rounds):
        for p, s in spaces.items():
            start = time.perf_counter()
            found = explore_design(fresh(s), workers=0, max_variants=s.size)
            seconds[p].append(time.perf_counter() - start)
            last[p] = found
            print(f"  (a) {p}: {seconds[p][-1]:.2f} s", file=sys.stderr, flush=True)
    print("\n## (a) 5 groups of 4 tasks, 4 links' protocols, 3 offered processors, "
          "exhaustive, in process\n")
    print("| platform | placements (of 3^5 = 243) | variants | judged | front | seconds "
          "| variants/s | target 10 s |")
    print("|---|---:|---:|---|---:|---:|---:|---|")
    for p, s in spaces.items():
        found, m = last[p], statistics.median(seconds[p])
        target = verdict(m, TARGET_A) if p == "3 alike" else "(growth)"
        print(f"| {p} | {s.allocation.size:,} | {s.size:,} | {counts(found)} | "
              f"{len(found.front)} | {spread(seconds[p])} | {len(found.results) / m:,.0f} "
              f"| {target} |", flush=True)


def run_incremental(rounds: int, sample: int, s=None, label: str = "(a) space (3 alike)"
                    ) -> None:
    s = space_a("3 alike") if s is None else s
    rng = random.Random(1)
    variants = sorted(rng.sample(range(s.size), min(sample, s.size)))
    ways = {"incremental": True, "from scratch": False}
    seconds: dict[str, list[float]] = {w: [] for w in ways}
    verdicts: dict[str, list] = {}
    for _ in range(rounds):
        for w, flag in ways.items():
            cold = fresh(s)
            start = time.perf_counter()
            got = [evaluate_variant(cold, v, {}, incremental=flag) for v in variants]
            seconds[w].append(time.perf_counter() - start)
            verdicts[w] = [(r.kept, r.live, r.consistent, r.schedulable, r.objectives)
                           for r in got]
            print(f"  incremental={flag}: {seconds[w][-1]:.2f} s", file=sys.stderr, flush=True)
    same = verdicts["incremental"] == verdicts["from scratch"]
    print(f"\n## Incremental against from-scratch judgement: {len(variants)} variants of "
          f"the {label}, a uniform sample, cold caches\n")
    print("| judgement | seconds | ms per variant | variants/s |")
    print("|---|---:|---:|---:|")
    for w in ways:
        m = statistics.median(seconds[w])
        print(f"| {w} | {spread(seconds[w])} | {1000 * m / len(variants):.2f} | "
              f"{len(variants) / m:,.0f} |")
    ratio = statistics.median(seconds["from scratch"]) / statistics.median(seconds["incremental"])
    print(f"\nfrom scratch / incremental = {ratio:.2f}; the same verdicts and objectives: "
          f"{'yes' if same else 'NO'}", flush=True)


def cluster(workers: int):
    from distributed import LocalCluster

    return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                        host="127.0.0.1", dashboard_address="127.0.0.1:0",
                        silence_logs=logging.ERROR)


def run_b(rounds: int, in_process: bool) -> None:
    from distributed import Client

    s = space_b()
    ways = ["LocalCluster(2), warm", *(["in process"] if in_process else [])]
    seconds: dict[str, list[float]] = {w: [] for w in ways}
    starts: list[float] = []
    found_of = {}
    for _ in range(rounds):
        for w in ways:
            if w == "in process":
                start = time.perf_counter()
                found = explore_design(fresh(s), workers=0, max_variants=1000)
                seconds[w].append(time.perf_counter() - start)
            else:
                t0 = time.perf_counter()
                with cluster(2) as c, Client(c) as client:
                    client.wait_for_workers(2)
                    client.run(lambda: __import__("tegraph.design.explore.evaluate"))
                    starts.append(time.perf_counter() - t0)
                    start = time.perf_counter()
                    found = explore_design(fresh(s), scheduler=c.scheduler_address,
                                           max_variants=1000)
                    seconds[w].append(time.perf_counter() - start)
            found_of[w] = found
            print(f"  (b) {w}: {seconds[w][-1]:.2f} s, {len(found.results)} variants, "
                  f"{found.method}, {found.stopped}", file=sys.stderr, flush=True)
    print("\n## (b) 1,000 tasks in 20 groups, 4 alike offered processors, Pareto local "
          "search of 1,000 variants\n")
    print(f"space: {s.allocation.size:,} canonical placements (4^20 = {4 ** 20:,} with the "
          f"renamings); LocalCluster(2) start, workers' imports included: "
          f"{spread(starts)} s (not in the seconds below)\n")
    print("| engine | judged | front | seconds | variants/s | target 60 s (2 workers) |")
    print("|---|---|---:|---:|---:|---|")
    for w in ways:
        found, m = found_of[w], statistics.median(seconds[w])
        target = verdict(m, TARGET_B) if w.startswith("LocalCluster") else "-"
        print(f"| {w} | {counts(found)} | {len(found.front)} | {spread(seconds[w])} | "
              f"{len(found.results) / m:,.1f} | {target} |", flush=True)


def stirling2(n: int, k: int) -> int:
    """Stirling number of the second kind S(n, k), by its recurrence."""
    row = [1] + [0] * k  # S(0, j)
    for _ in range(n):
        row = [0] + [j * row[j] + row[j - 1] for j in range(1, k + 1)]
    return row[k]


def big(n: int) -> str:
    """An integer as the table shows it: in full up to 10^15, else in powers of ten."""
    return f"{n:,}" if n < 10 ** 15 else f"{n:.2e}"


def run_growth() -> None:
    print("\n## How the allocation space grows (placements counted, not judged)\n")
    print("| free units n | processors | k^n | canonical (judged once each) | ratio |")
    print("|---:|---|---:|---:|---:|")
    for n, k, alike in [(5, 3, 3), (5, 3, 2), (10, 3, 3), (10, 4, 4), (20, 4, 4),
                        (20, 4, 2), (50, 4, 4), (60, 8, 8)]:
        offered = tuple(f"p{i}" for i in range(k))
        classes = (offered[:alike],) if alike > 1 else ()
        a = Allocation(offered, tuple((f"U{u}",) for u in range(n)), {}, classes)
        # By the formula of allocation.py, independently of its counting table.
        m = k - alike
        formula = sum(comb(n, j) * m ** (n - j) * sum(stirling2(j, i) for i in range(alike + 1))
                      for j in range(n + 1))
        assert a.size == formula, (n, k, alike, a.size, formula)
        what = f"{k} alike" if alike == k else f"{k}, {alike} alike"
        print(f"| {n} | {what} | {big(k ** n)} | {big(a.size)} | {k ** n / a.size:,.1f} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--rounds-b", type=int, default=2)
    parser.add_argument("--sample", type=int, default=300)
    parser.add_argument("--sample-b", type=int, default=10)
    parser.add_argument("--only", default="a,incremental,b,growth,incremental-b")
    parser.add_argument("--no-in-process-b", action="store_true")
    args = parser.parse_args()
    only = set(args.only.split(","))
    print(f"os.cpu_count() = {os.cpu_count()}; load average before: "
          f"{', '.join(f'{x:.2f}' for x in os.getloadavg())}", flush=True)
    if "growth" in only:
        run_growth()
    if "a" in only:
        run_a(args.rounds)
    if "incremental" in only:
        run_incremental(args.rounds, args.sample)
    if "incremental-b" in only:
        run_incremental(args.rounds_b, args.sample_b, space_b(), "(b) space (1,000 tasks)")
    if "b" in only:
        run_b(args.rounds_b, not args.no_in_process_b)
    print(f"\nload average after: {', '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
