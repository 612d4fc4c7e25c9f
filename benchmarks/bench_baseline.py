"""(max,+) analysis against the state-space baselines of the ORCCAD paper.

Three families of skeletons, each grown in size:

1. ``pipeline``: n tasks under one clock (period 10), each reading its
   predecessor's message (ASYN/SYN), as in the paper's Figure 4;
2. ``coprime``: m independent 3-task pipelines whose clock periods are the
   first m primes, n = 3m tasks; their timed state space grows with the least
   common multiple of the periods, the (max,+) analysis does not;
3. ``random``: the generated skeletons of ``generate_skeleton.py`` (seed 0).

For every size, ``tegraph.analyze``, the untimed baseline
(:func:`tegraph.reachability.skeleton_reachability`) and the timed one
(:func:`tegraph.timed_reachability.timed_reachability`) each run in a fresh
process: the time is that of the library call alone (building the timed event
graph included, interpreter start-up and skeleton generation excluded; for
``analyze`` the median of up to 5 calls, as many as fit in two seconds), the
memory the process's peak resident set. A baseline stops at the time budget
(``--budget`` seconds, 60 by default; :data:`MAX_STATES` is a memory guard set high enough
that the time budget is what binds) and then says so (``>``); in families 1 and 3 it is not
run again at larger sizes once it has, in family 2 it always runs (the target
is measured at 30 tasks). ``agree`` compares every answer a baseline
concluded with the (max,+) one: the deadlock verdict, and the period,
transient and first overrun of every group or task.

Usage::

    python benchmarks/bench_baseline.py [--budget 60] [--families 1 2 3] [--max-tasks N]

writes ``benchmarks/results/baseline.{json,md}`` and, when matplotlib is
installed (the ``plot`` extra), ``benchmarks/results/baseline.png``.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"
PRIMES = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37]
SIZES = {
    1: [2, 4, 6, 8, 10, 12, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096, 8192, 16384],
    2: [3, 6, 9, 12, 15, 18, 21, 24, 27, 30],
    3: [3, 4, 5, 6, 7, 8, 10, 12, 15, 20, 30, 50, 100, 200, 500, 1000],
}
NAMES = {1: "pipeline", 2: "coprime", 3: "random"}
MAX_STATES = 40_000_000
"""State budget of every baseline run: a memory guard (a few hundred bytes per
untimed state, more per timed one); at the default budget the time binds first."""


def pipeline(n: int, period: int = 10, prefix: str = "T") -> tuple[dict, list[dict]]:
    """n tasks, the first on clock ``<prefix>.rtc``, each reading its predecessor (ASYN/SYN).

    Durations cycle through 1/20, 2/20, 3/20 of the period: every task keeps pace.
    """
    tasks = {}
    links = []
    for i in range(n):
        task: dict = {"duration": f"{(i % 3 + 1) * period}/20"}
        if i == 0:
            task["clock"] = f"{prefix}.rtc"
        else:
            task["inputs"] = ["i"]
            links.append({"from": f"{prefix}{i - 1}:o", "to": f"{prefix}{i}:i",
                          "protocol": "ASYN/SYN"})
        if i < n - 1:
            task["outputs"] = ["o"]
        tasks[f"{prefix}{i}"] = task
    return tasks, links


def skeleton(family: int, n: int) -> dict:
    if family == 1:
        tasks, links = pipeline(n)
        return {"name": f"pipeline-{n}", "clocks": {"T.rtc": {"period": 10}},
                "tasks": tasks, "links": links}
    if family == 2:
        doc: dict = {"name": f"coprime-{n}", "clocks": {}, "tasks": {}, "links": []}
        for g, p in enumerate(PRIMES[:n // 3]):
            tasks, links = pipeline(3, p, prefix=f"G{g}T")
            doc["clocks"][f"G{g}T.rtc"] = {"period": p}
            doc["tasks"].update(tasks)
            doc["links"] += links
        return doc
    sys.path.insert(0, str(HERE))
    from generate_skeleton import generate

    return generate(n, seed=0)


CHILD = """
import json, resource, sys, time
sys.path.insert(0, {here!r})
from bench_baseline import MAX_STATES, skeleton
from tegraph import Skeleton, analyze, build_teg
from tegraph.analysis.baselines.reachability import skeleton_reachability
from tegraph.analysis.baselines.timed_reachability import timed_reachability

family, n, which, budget = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3], float(sys.argv[4])
sk = Skeleton.from_dict(skeleton(family, n))
start = time.perf_counter()
if which == "analyze":
    # Milliseconds are at the mercy of the other core: the median of up to 5 calls.
    times = []
    while len(times) < 5 and sum(times) < 2:
        t0 = time.perf_counter()
        r = analyze(sk)
        times.append(time.perf_counter() - t0)
    seconds = sorted(times)[len(times) // 2]
    out = {{"live": r.live, "dead": [g.index for g in r.groups if not g.live],
           "groups": [[str(g.period) if g.rate_consistent else None, g.transient]
                      for g in r.groups],
           "overruns": {{t: [x.overrun_at, x.overrun_decided] for t, x in r.tasks.items()
                        if r.groups[x.group].live}}}}
elif which == "untimed":
    r = skeleton_reachability(build_teg(sk), max_states=MAX_STATES, max_seconds=budget)
    seconds = time.perf_counter() - start
    out = {{"states": r.states, "complete": r.complete, "deadlock": r.deadlock,
           "dead": sorted({{d.group for d in r.dead}})}}
else:
    r = timed_reachability(sk, max_states=MAX_STATES, max_seconds=budget)
    seconds = time.perf_counter() - start
    out = {{"states": r.states, "complete": r.complete,
           "groups": [[None if g.period is None else str(g.period), g.transient]
                      for g in r.groups],
           "overruns": {{t: [x.overrun_at, x.decided] for t, x in r.tasks.items()}}}}
out["seconds"] = seconds
out["mib"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
out["tasks"] = len(sk.tasks)
print(json.dumps(out))
"""


def measure(family: int, n: int, which: str, budget: float) -> dict:
    out = subprocess.run([sys.executable, "-c", CHILD.format(here=str(HERE)), str(family),
                          str(n), which, str(budget)], capture_output=True, text=True,
                         check=False)
    if out.returncode != 0:
        raise RuntimeError(out.stderr)
    return json.loads(out.stdout)


def agreement(ref: dict, untimed: dict | None, timed: dict | None) -> str:
    """'yes', 'NO', or what could not be compared."""
    verdicts = []
    if untimed is not None:
        if untimed["complete"]:
            verdicts.append(untimed["deadlock"] == (not ref["live"])
                            and untimed["dead"] == ref["dead"])
        elif untimed["dead"]:  # a deadlock found before the budget is conclusive
            verdicts.append(set(untimed["dead"]) <= set(ref["dead"]))
    if timed is not None:
        for (period, transient), (bp, bt) in zip(ref["groups"], timed["groups"]):
            if bp is not None:
                verdicts.append((bp, bt) == (period, transient))
            elif period is not None and timed["complete"]:
                verdicts.append(False)  # a bounded group must repeat
        for task, (at, decided) in ref["overruns"].items():
            b_at, b_decided = timed["overruns"][task]
            if (b_decided and decided) or b_at is not None:
                verdicts.append(b_at == at)
    if not verdicts:
        return "n/a"
    if not all(verdicts):
        return "NO"
    concluded = (untimed is None or untimed["complete"]) and (timed is None or timed["complete"])
    return "yes" if concluded else f"yes ({len(verdicts)} answers)"


def run(families: list[int], budget: float, max_tasks: int) -> list[dict]:
    rows = []
    for family in families:
        exhausted: set[str] = set()
        for n in SIZES[family]:
            if n > max_tasks:
                break
            row: dict = {"family": NAMES[family], "n": n,
                         "analyze": measure(family, n, "analyze", budget)}
            for which in ("untimed", "timed"):
                if which in exhausted:
                    row[which] = None
                    continue
                row[which] = measure(family, n, which, budget)
                if not row[which]["complete"] and family != 2:
                    exhausted.add(which)
            row["agree"] = agreement(row["analyze"], row["untimed"], row["timed"])
            rows.append(row)
            print(line(row), flush=True)
            if {"untimed", "timed"} <= exhausted:
                break
    return rows


HEADER = ("| family | tasks | analyze (s) | MiB | untimed (s) | MiB | states | ratio | "
          "timed (s) | MiB | states | ratio | agree |\n"
          "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")


def line(row: dict) -> str:
    a = row["analyze"]
    cells = [row["family"], f"{row['n']:,}", f"{a['seconds']:.3f}", f"{a['mib']:.0f}"]
    for which in ("untimed", "timed"):
        b = row[which]
        if b is None:
            cells += ["not run"] + [""] * 3
            continue
        over = "" if b["complete"] else ">"
        ratio = b["seconds"] / a["seconds"]
        cells += [f"{over}{b['seconds']:.2f}", f"{b['mib']:.0f}", f"{over}{b['states']:,}",
                  f"{over}{ratio:,.0f}" if ratio >= 10 else f"{over}{ratio:.2f}"]
    return "| " + " | ".join(cells + [row["agree"]]) + " |"


def plot(rows: list[dict], path: Path) -> bool:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import matplotlib.ticker
    except ImportError:
        return False
    families = list(dict.fromkeys(r["family"] for r in rows))
    fig, axes = plt.subplots(1, len(families), figsize=(5 * len(families), 4), squeeze=False)
    for ax, fam in zip(axes[0], families):
        mine = [r for r in rows if r["family"] == fam]
        for which, style in (("analyze", "o-"), ("untimed", "s--"), ("timed", "^--")):
            pts = [(r["n"], r[which]["seconds"], r[which].get("complete", True))
                   for r in mine if r[which] is not None]
            if not pts:
                continue
            label = {"analyze": "(max,+) analyze", "untimed": "untimed reachability",
                     "timed": "timed exploration"}[which]
            line_, = ax.plot([p[0] for p in pts], [p[1] for p in pts], style, label=label)
            capped = [p for p in pts if not p[2]]
            if capped:  # stopped by the budget: the true time is larger
                ax.plot([p[0] for p in capped], [p[1] for p in capped], "x", ms=10,
                        color=line_.get_color())
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.xaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_title(f"family: {fam}")
        ax.set_xlabel("tasks")
        ax.set_ylabel("seconds (x: stopped by the budget)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    return True


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--budget", type=float, default=60.0, help="seconds per baseline run")
    parser.add_argument("--families", type=int, nargs="+", default=[1, 2, 3], choices=[1, 2, 3])
    parser.add_argument("--max-tasks", type=int, default=10**9, help="largest size to try")
    args = parser.parse_args()
    print(HEADER, flush=True)
    rows = run(args.families, args.budget, args.max_tasks)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "baseline.json").write_text(json.dumps(rows, indent=1))
    (RESULTS / "baseline.md").write_text(HEADER + "\n" + "\n".join(line(r) for r in rows) + "\n")
    if plot(rows, RESULTS / "baseline.png"):
        print(f"plot: {RESULTS / 'baseline.png'}")


if __name__ == "__main__":
    main()
