"""Benchmark of ``tegraph.sensitivity`` against the naive alternative, a grid of analyses.

Three measurements:

1. **Period formula and keep-pace region** for 2 and 4 parameters (durations
   of the largest group, plus one clock period with 4), on the examples and
   on a generated skeleton of 1,000 tasks: ``sensitivity(sk, vary,
   margins=False)`` (exact formula over the box, and the scaling factor when
   durations are varied), against a grid of ``analyze_skeleton`` calls on
   the group alone (5 points per axis with 2 parameters, 3 with 4), which
   only samples the cycle time and never gives a breakpoint exactly.
2. **Scaling factor** of generated skeletons of 10,000 tasks (every duration
   varied), ``sensitivity(sk, formulas=False, margins=False)``, against the
   cost of the analyses a bisection on the factor needs (one whole-skeleton
   analysis is timed; a bisection to a relative 10^-9 over [0, 2^k] needs
   about 30 + k of them, and still is not exact).
3. **All margins** on 1,000 tasks (every end cross-checked with the
   analysis, ``verify=True``) and 10,000 tasks (``verify=False``: the
   cross-checks are two group analyses per finite end, measured at 1,000):
   ``sensitivity(sk, formulas=False)`` and, for ``tegraph analyze``'s column,
   ``duration_margins``.

The generated skeleton (``generate_skeleton.py``) is mostly inconsistent at
its nominal values (its free-running SYN/ASYN readers are faster than their
clocked writers, a few groups have two clocks); a *consistent variant*
(every SYN/ASYN or SYN/SYN link made ASYN/SYN, the second clocks removed)
is measured too, since its scaling factor is finite and every margin is a
real search.

"Oracle calls" are batched evaluations of the exact oracle (Howard cycle
ratios and overrun certificates for every group asked at once); "points" the
(group, parameter point) pairs they evaluated; "analyses" the cross-checks
with ``analyze_skeleton`` (``verify=True``, the default).

4. **On one CPU** (spec §4b): the scaling factor and every margin of
   ``examples/quadrotor.yaml`` (each group one periodic unit, a logger without
   clock), of the same without its logger, of ``computed_torque.yaml`` and of
   ``schedulable_skeleton.py 100`` (ten processors, two groups each):
   ``sensitivity(sk, formulas=False)`` with the checks and without, decided level
   by level by the exact test of units, against the same with that test switched
   off (the walk on affine times, as before it existed), once (``--walk-runs``;
   0 leaves it out: minutes).

Usage::

    python benchmarks/bench_sensitivity.py [--runs 3] [--margin-runs 1] [--big 10000]
                                           [--parts 1 2 3 4] [--walk-runs 1]
"""

from __future__ import annotations

import argparse
import itertools
import statistics
import sys
import time
from collections.abc import Callable
from fractions import Fraction
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent


def timed(runs: int, fn: Callable[..., Any], *args: Any,
          **kwargs: Any) -> tuple[float, float, float, Any]:
    """Median, min and max wall time of ``runs`` calls ``fn(*args, **kwargs)``, and the result."""
    times, out = [], None
    for _ in range(runs):
        start = time.perf_counter()
        out = fn(*args, **kwargs)
        times.append(time.perf_counter() - start)
    return statistics.median(times), min(times), max(times), out


def spread(med: float, low: float, high: float) -> str:
    return f"{med:.3g} s [{low:.3g}, {high:.3g}]"


def consistent_variant(doc: dict) -> dict:
    """Every SYN/ASYN and SYN/SYN link ASYN/SYN; only the first task of a group keeps a clock."""
    for link in doc["links"]:
        if link["protocol"] in ("SYN/ASYN", "SYN/SYN"):
            link["protocol"] = "ASYN/SYN"
    for name, task in doc["tasks"].items():
        if "period" in task and not name.endswith(".T0"):
            del task["period"]
    return doc


def pick(sk, k: int) -> list[str]:
    """k parameters of the largest group: durations, and with k >= 4 one clock period."""
    from tegraph.model.structure import Structure

    structure = Structure.of(sk)
    g = max(range(len(structure.groups)), key=lambda i: len(structure.groups[i]))
    group, clocks = structure.groups[g], list(structure.clocks[g])
    durations = [t for t in group][: k - (1 if k >= 4 and clocks else 0)]
    out = []
    for t in durations:
        d = sk.tasks[t].duration
        out.append(f"{t}.duration=0..{3 * d if d else 1}")
    if len(out) < k and clocks:
        p = sk.clocks[clocks[0]].period
        out.append(f"{clocks[0]}.period={p / 2}..{2 * p}")
    return out


def grid(sk, vary: list[str], per_axis: int) -> tuple[int, float]:
    """The naive alternative: analyze the group at every point of a grid; (analyses, seconds)."""
    import dataclasses

    from tegraph.analysis.analyze import analyze_skeleton
    from tegraph.analysis.sensitivity.parameters import parse_vary
    from tegraph.model.structure import Structure

    params = parse_vary(sk, vary)
    owners = {p.owner for p in params if p.kind == "duration"}
    group = next(g for g in Structure.of(sk).groups if owners & set(g))
    local = sk.restricted_to(group)
    axes = []
    for p in params:
        assert p.high is not None
        axes.append([p.low + (p.high - p.low) * Fraction(i, per_axis - 1)
                     for i in range(per_axis)])
    n, start = 0, time.perf_counter()
    for point in itertools.product(*axes):
        tasks, clocks = dict(local.tasks), dict(local.clocks)
        for p, v in zip(params, point):
            if p.kind == "duration":
                tasks[p.owner] = dataclasses.replace(tasks[p.owner], duration=v)
            else:
                clocks[p.owner] = dataclasses.replace(clocks[p.owner], period=v)
        analyze_skeleton(dataclasses.replace(local, tasks=tasks, clocks=clocks),
                         max_steps=1_000, semiflow_max_places=0)
        n += 1
    return n, time.perf_counter() - start


def effort_text(effort: dict, part: str) -> str:
    e = effort.get(part)
    if not e:
        return "-"
    return f"{e['rounds']} calls, {e['points']} points, {e['analyses']} analyses"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--margin-runs", type=int, default=1)
    parser.add_argument("--big", type=int, default=10_000)
    parser.add_argument("--mid", type=int, default=1_000)
    parser.add_argument("--parts", type=int, nargs="+", default=[1, 2, 3, 4],
                        help="which measurements (1 formulas, 2 scaling factor, 3 margins, "
                             "4 on one CPU)")
    parser.add_argument("--walk-runs", type=int, default=1,
                        help="runs of part 4 with the exact test of units switched off")
    args = parser.parse_args()
    # The checkout's tegraph, not an installed copy.
    sys.path[:0] = [str(ROOT), str(HERE)]
    from generate_skeleton import generate

    from tegraph import Skeleton, load_skeleton

    print(f"# bench_sensitivity: runs={args.runs}, margin runs={args.margin_runs}")
    cases = [(name, load_skeleton(ROOT / "examples" / name)) for name in (
        "computed_torque.yaml", "threads.yaml", "rendezvous_two_clocks.yaml",
        "ring_two_tokens.yaml")]
    cases.append((f"generated {args.mid}", Skeleton.from_dict(generate(args.mid))))
    cases.append((f"generated {args.mid}, consistent",
                  Skeleton.from_dict(consistent_variant(generate(args.mid)))))
    bigs = [(f"generated {args.big}", Skeleton.from_dict(generate(args.big))),
            (f"generated {args.big}, consistent",
             Skeleton.from_dict(consistent_variant(generate(args.big))))]
    if 1 in args.parts:
        formulas(cases, args.runs)
    if 2 in args.parts:
        scaling(bigs, args.runs, args.big)
    if 3 in args.parts:
        margins(cases[-2:], bigs, args)
    if 4 in args.parts:
        one_cpu(args)


def formulas(cases, runs: int) -> None:
    from tegraph import sensitivity

    print("\n## 1. Period formula and keep-pace region (exact) vs a grid of analyses\n")
    print("| skeleton | parameters | exact: time (median [min, max]) | formula terms | "
          "oracle calls (formulas) | grid | grid time | time per grid analysis |")
    print("|---|---|---|---|---|---|---|---|")
    for label, sk in cases:
        for k, per_axis in ((2, 5), (4, 3)):
            vary = pick(sk, k)
            med, low, high, r = timed(runs, sensitivity, sk, vary, margins=False)
            terms = max((len(f.terms) for f in r.formulas), default=0)
            n, seconds = grid(sk, vary, per_axis)
            names = ", ".join(v.split("=")[0] for v in vary)
            print(f"| {label} | {k}: {names} | {spread(med, low, high)} | {terms} | "
                  f"{effort_text(r.effort, 'formulas')} | {per_axis}^{k} = {n} | "
                  f"{seconds:.3g} s | {seconds / n * 1000:.3g} ms |", flush=True)



def scaling(bigs, runs: int, big: int) -> None:
    from tegraph import sensitivity
    from tegraph.analysis.analyze import analyze_skeleton

    print(f"\n## 2. Scaling factor, {big} tasks, every duration varied\n")
    print("| skeleton | time (median [min, max]) | factor | oracle calls | one analysis "
          "(whole skeleton) | bisection to 10^-9 (about 35 analyses) |")
    print("|---|---|---|---|---|---|")
    for label, sk in bigs:
        med, low, high, r = timed(runs, sensitivity, sk, formulas=False,
                                  margins=False)
        s = r.scaling
        factor = (str(s.factor) if s.factor is not None else
                  f"none ({'nominal inconsistent' if not s.nominal_consistent else 'unbounded'}"
                  f", {len(s.intervals)} interval(s))")
        a_med, _, _, _ = timed(1, analyze_skeleton, sk, semiflow_max_places=0)
        setup = r.effort["setup"]["seconds"]
        print(f"| {label} | {spread(med, low, high)} (setup {setup:.3g} s) | {factor} | "
              f"{effort_text(r.effort, 'scaling')} | {a_med:.3g} s | "
              f"about {35 * a_med:.0f} s |", flush=True)



def margins(mids, bigs, args) -> None:
    from tegraph import duration_margins, sensitivity
    from tegraph.analysis.analyze import analyze_skeleton

    print(f"\n## 3. All margins, {args.mid} and {args.big} tasks\n")
    print("| skeleton | sensitivity, every duration's margin | verified | oracle calls | "
          "duration_margins (analyze's column) | one analysis |")
    print("|---|---|---|---|---|---|")
    for (label, sk), verify in [*((c, True) for c in mids), *((c, False) for c in bigs)]:
        med, low, high, r = timed(args.margin_runs, sensitivity, sk, formulas=False,
                                  verify=verify)
        report = analyze_skeleton(sk, semiflow_max_places=0)
        d_med, d_low, d_high, m = timed(args.runs, duration_margins, sk, report)
        a_med, _, _, _ = timed(1, analyze_skeleton, sk, semiflow_max_places=0)
        margins = r.effort["margins"]["seconds"]
        print(f"| {label} | {spread(med, low, high)} in all, margins part {margins:.3g} s "
              f"({args.margin_runs} run(s)) | {'yes' if verify else 'no'} | "
              f"{effort_text(r.effort, 'margins')} | "
              f"{spread(d_med, d_low, d_high)} ({len(m)} tasks of consistent groups) | "
              f"{a_med:.3g} s |", flush=True)


def one_cpu(args) -> None:
    from unittest import mock

    from schedulable_skeleton import generate as schedulable

    from tegraph import Skeleton, load_skeleton, sensitivity
    from tegraph.analysis.sensitivity.parts import ProcessorLine

    quadrotor = load_skeleton(ROOT / "examples" / "quadrotor.yaml")
    cases = [("quadrotor.yaml", quadrotor),
             ("quadrotor.yaml without its logger",
              quadrotor.restricted_to([t for t in quadrotor.tasks if t != "logger"])),
             ("computed_torque.yaml", load_skeleton(ROOT / "examples" / "computed_torque.yaml")),
             ("schedulable_skeleton.py 100", Skeleton.from_dict(schedulable(100)))]
    post_init = ProcessorLine.__post_init__

    def without_theorem(self):
        post_init(self)
        self.use_theorem = False

    print("\n## 4. On one CPU: the scaling factor and every margin, exact\n")
    print("| skeleton | figures | levels, checked (median [min, max]) | levels, unchecked | "
          "answer | the walk alone (theorem off), unchecked | its answer |")
    print("|---|---|---|---|---|---|---|")
    for label, sk in cases:
        on = timed(args.runs, sensitivity, sk, formulas=False)
        off = timed(args.runs, sensitivity, sk, formulas=False, verify=False)
        r = on[3]
        figures = 1 + len(r.margins)
        walk_text = answer_walk = "not run"
        if args.walk_runs:
            with mock.patch.object(ProcessorLine, "__post_init__", without_theorem):
                w = timed(args.walk_runs, sensitivity, sk, formulas=False, verify=False)
            walk_text, answer_walk = spread(*w[:3]), answer_text(w[3])
        print(f"| {label} | {figures} | {spread(*on[:3])} | {spread(*off[:3])} | "
              f"{answer_text(r)} | {walk_text} | {answer_walk} |", flush=True)


def answer_text(r) -> str:
    """The factor (a supremum marked <) and how many figures are exact."""
    s = r.scaling
    figures = [s, *r.margins.values()]
    exact = sum(f.exact for f in figures)
    factor = ("bounded" if not s.exact else "none" if s.factor is None
              else f"{'< ' if not s.attained else ''}{s.factor}")
    agree = all(c.agrees for c in r.checks)
    return (f"factor {factor}, {exact}/{len(figures)} exact"
            + ("" if not r.checks else ", checks agree" if agree else ", checks DISAGREE"))


if __name__ == "__main__":
    main()
