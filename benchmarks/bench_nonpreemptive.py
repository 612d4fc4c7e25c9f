"""Benchmark: what non-preemptive processors (spec §4d) cost ``analyze``, A/B.

The target: non-preemptive processors cost at most 20 % over preemptive ones in
``analyze`` on the generated skeletons. For each size, ``generate_skeleton.py N
--processors P`` writes the skeleton twice from the same seed: A with every processor
preemptive (the default), B the same file with every processor declared
``preemptive: false`` (``--non-preemptive P``); ``--delay D`` gives both the same
network delay. ``tegraph.analyze`` (the call of ``tegraph analyze``, design section
included, the cyclic collector off as the command has it) runs in this process on the
loaded skeletons, alternating A, B, A, B, ... so that load from elsewhere falls on both
alike; the table gives medians with their spread (min-max), wall and CPU seconds, the
ratio B/A of the wall medians and whether it meets the target.

A non-preemptive schedule is another schedule: it may need more or fewer event firings
before a regime is proven (or an overrun shown), so the table says for both whether the
schedule on processors was decided (``schedulable`` true or false, exactly), in how many
of its independent parts a periodic regime was proven (an overrun decides "not
schedulable" without one) and how many firings it simulated
(``report.schedule.events``); a ratio far from 1 with
firings far apart is the schedule's length, not the engine's cost per firing. The
engine's own time is measured too: every call of the §4b engine's ``simulate_part``
(from the schedule and from the sensitivity parts) is timed, and the last column gives
B/A of the engine's seconds per firing. So is the design section's revised analysis of
the non-preemptive processors (Davis et al.'s busy-period bound, ``judge_non_preemptive``,
which only B runs): the column "B bound (s)".

Usage::

    python benchmarks/bench_nonpreemptive.py [--runs 3] [--cases 1000:2 10000:4:1/10]
        [--output benchmarks/results/nonpreemptive.table.md]
"""

from __future__ import annotations

import argparse
import gc
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
TARGET = 1.20
"""B/A at most this: non-preemptive at most 20 % over preemptive."""

CASES = [(100, 2, None), (1_000, 2, None), (1_000, 4, None), (1_000, 4, "1/10"),
         (3_000, 4, None)]
"""(tasks, processors, network delay or None)."""


def write(tmp: Path, n: int, processors: int, delay: str | None, non_preemptive: int) -> Path:
    """One generated file (in a child process: the generator is a script)."""
    path = tmp / f"groups-{n}-{processors}-{delay or 0}-{non_preemptive}.json".replace("/", "_")
    path = tmp / path.name
    cmd = [sys.executable, str(HERE / "generate_skeleton.py"), str(n), "-o", str(path),
           "--processors", str(processors)]
    if non_preemptive:
        cmd += ["--non-preemptive", str(non_preemptive)]
    if delay is not None:
        cmd += ["--delay", delay]
    subprocess.run(cmd, check=True)
    return path


SPENT = {"engine": 0.0, "bound": 0.0}
"""Wall seconds since the last reset in the §4b engine's ``simulate_part`` and in the
design section's revised analysis of non-preemptive processors."""


def time_the_phases() -> None:
    """Wrap the two functions where the analysis looks them up, adding to SPENT."""
    import tegraph.analysis.processors.schedule as schedule
    import tegraph.analysis.sensitivity.simulation as simulation
    import tegraph.design.schedulability as schedulability

    for module, name, what in ((schedule, "simulate_part", "engine"),
                               (simulation, "simulate_part", "engine"),
                               (schedulability, "judge_non_preemptive", "bound")):
        inner = getattr(module, name)

        def timed(*args: Any, _inner: Any = inner, _what: str = what, **kwargs: Any) -> Any:
            start = time.perf_counter()
            try:
                return _inner(*args, **kwargs)
            finally:
                SPENT[_what] += time.perf_counter() - start

        setattr(module, name, timed)


def run(skeleton: Any) -> dict:
    """One ``analyze``: wall and CPU seconds, the verdict on processors, the firings."""
    from tegraph import analyze

    gc.collect()
    gc.disable()  # as `tegraph analyze` runs it
    try:
        SPENT.update(engine=0.0, bound=0.0)
        start, cpu = time.perf_counter(), time.process_time()
        report = analyze(skeleton)
        wall, cpu = time.perf_counter() - start, time.process_time() - cpu
    finally:
        gc.enable()
    schedule = report.schedule
    return {"time": wall, "cpu": cpu, "engine": SPENT["engine"],
            "bound": SPENT["bound"], "exit": report.exit_status,
            "schedulable": None if schedule is None else schedule.schedulable,
            "events": None if schedule is None else schedule.events,
            "why": None if schedule is None else schedule.why_undecided,
            "regimes": None if schedule is None else (
                sum(part["start"] is not None for part in schedule.regimes),
                len(schedule.regimes))}


def spread(values: list[float]) -> str:
    return f"{statistics.median(values):.2f} ({min(values):.2f}-{max(values):.2f})"


def verdict(rs: list[dict]) -> str:
    """The schedule's verdict and firings; every run of one file must give the same."""
    seen = {(r["schedulable"], r["events"], r["regimes"]) for r in rs}
    if len(seen) != 1:
        return "DIFFERS between runs: " + ", ".join(map(str, sorted(seen, key=str)))
    schedulable, events, regimes = seen.pop()
    word = {True: "schedulable", False: "not schedulable", None: "undecided"}[schedulable]
    if events is None:
        return word
    proven = f"a regime proven in {regimes[0]} of {regimes[1]} part(s)" if regimes else ""
    return f"{word}, {events:,} firings, {proven}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--cases", nargs="*",
                        help="TASKS:PROCESSORS[:DELAY], e.g. 1000:2 10000:4:1/10")
    parser.add_argument("--output", type=Path, help="write the Markdown table here too")
    args = parser.parse_args()
    cases = CASES
    if args.cases:
        cases = [(int(c.split(":")[0]), int(c.split(":")[1]),
                  c.split(":")[2] if c.count(":") > 1 else None) for c in args.cases]
    from tegraph import Skeleton, analyze
    from tegraph.io import load_skeleton

    time_the_phases()
    # Warm up: the first analysis pays lazy imports and the kernels' first calls.
    analyze(Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 4,
                                                "processor": "p"}},
                                "processors": {"p": {"preemptive": False}}}))
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n, processors, delay in cases:
            files = {"A": write(Path(tmp), n, processors, delay, 0),
                     "B": write(Path(tmp), n, processors, delay, processors)}
            skeletons = {name: load_skeleton(path) for name, path in files.items()}
            assert all(not p.preemptive for p in skeletons["B"].processors.values())
            results: dict[str, list[dict]] = {"A": [], "B": []}
            for _ in range(args.runs):
                for name in ("A", "B"):  # interleaved: A, B, A, B, ...
                    r = run(skeletons[name])
                    results[name].append(r)
                    print(f"{n} tasks, {processors} processors, delay {delay or 0}, {name}: "
                          f"{r['time']:.2f} s, cpu {r['cpu']:.2f} s, engine {r['engine']:.2f} s, "
                          f"bound {r['bound']:.2f} s, exit {r['exit']}, "
                          f"schedulable {r['schedulable']}, {r['events']} firings, "
                          f"regimes {r['regimes']}"
                          + (f" ({r['why']})" if r["why"] else ""),
                          file=sys.stderr, flush=True)
            rows.append((n, processors, delay, results))
    text = "\n".join(table(rows, args.runs)) + "\n"
    print(text)
    if args.output:
        args.output.write_text(text)


def table(rows: list, runs: int) -> list[str]:
    head = ["# `tegraph.analyze`, every processor preemptive (A) or non-preemptive (B)", "",
            f"Machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f} at the "
            "end; A and B runs alternate in one process, so any load falls on both alike. "
            f"Median of {runs} runs (min-max), seconds; CPU is this process's user + system "
            "time; engine: the wall time of the §4b engine's `simulate_part` calls within "
            "it; bound: the wall time of the design section's revised analysis of the "
            "non-preemptive processors (`judge_non_preemptive`); "
            "`generate_skeleton.py N --processors P` (seed 0), B with "
            "`--non-preemptive P`. Target: B/A at most "
            f"{TARGET:.2f}.", ""]
    cols = ["tasks", "processors", "delay", "A time (s)", "A CPU (s)", "A engine (s)",
            "A schedule", "B time (s)", "B CPU (s)", "B engine (s)", "B bound (s)",
            "B schedule", "B/A", "target", "B/A engine per firing"]
    out = head + ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for n, processors, delay, results in rows:
        a, b = results["A"], results["B"]
        ma = statistics.median(r["time"] for r in a)
        mb = statistics.median(r["time"] for r in b)
        ratio = mb / ma
        ga = statistics.median(r["engine"] for r in a)
        gb = statistics.median(r["engine"] for r in b)
        ea, eb = a[0]["events"], b[0]["events"]
        per_firing = f"{(gb / eb) / (ga / ea):.2f}" if ea and eb and ga else "-"
        out.append("| " + " | ".join([
            f"{n:,}", str(processors), delay or "0",
            spread([r["time"] for r in a]), spread([r["cpu"] for r in a]),
            spread([r["engine"] for r in a]), verdict(a),
            spread([r["time"] for r in b]), spread([r["cpu"] for r in b]),
            spread([r["engine"] for r in b]), spread([r["bound"] for r in b]), verdict(b),
            f"{ratio:.2f}", "met" if ratio <= TARGET else "not met", per_firing]) + " |")
    return out


if __name__ == "__main__":
    main()
