"""Benchmark of the chains' latency (spec §4c): what chains cost ``analyze``, and explore.

1. **analyze**: ``tegraph analyze FILE --json``, a fresh process per run, on the files
   of ``chain_skeletons.py`` with and without their ``chains:`` (the same skeleton, the
   same links): 100 chains of 5 to 20 tasks on a 1,000-task generated skeleton (on its
   one processor, and spread over 100 processors), one chain through every group of the
   10,000-task one. The runs alternate (without, with, without, with, ...), so that load
   from elsewhere falls on both alike; medians with their spread (min-max), wall and CPU.
2. **explore**: variants per second of ``explore`` in this process on the 20-task
   benchmark of ``bench_explore.py`` (its first 3 links, all four protocols: 64
   variants) with a chain objective (``latency``, plus ``period`` and ``load``), this
   tree against another checkout (``--base``, e.g. main: the latency then was a bound),
   a fresh process per exploration, alternating.

Usage::

    git worktree add --detach /tmp/perf-base main
    python benchmarks/bench_chains.py --base /tmp/perf-base [--runs 5]
        [--output benchmarks/results/chains.md]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from bench_analyze import measure, spread  # noqa: E402

CASES = [("many", 1000, None, "100 chains of 5-20 tasks, 1,000 tasks on one processor"),
         ("many", 1000, 100, "100 chains of 5-20 tasks, 1,000 tasks on 100 processors"),
         ("through", 10000, None, "one chain through every group, 10,000 tasks")]

_EXPLORE = r"""
import json, sys, time
root = sys.argv[1]
sys.path[:0] = [root, root + "/benchmarks"]
from generate_skeleton import generate
import tegraph
assert tegraph.__file__.startswith(root), tegraph.__file__
from tegraph import Skeleton
from tegraph.design.explore import explore_design
from tegraph.design.explore.space import design_space
sk = Skeleton.from_dict(generate(20, seed=0))
# The links named as the input names them (W:p -> R:q), which every checkout reads alike.
links = [f"{x.writer[0]}:{x.writer[1]} -> {x.reader[0]}:{x.reader[1]}" for x in sk.links[:3]]
readers = {}
for x in sk.links:
    readers.setdefault(x.writer[0], []).append(x.reader[0])
def longest(t, seen):
    best = [t]
    for r in readers.get(t, []):
        if r not in seen:
            path = [t] + longest(r, seen | {r})
            best = max(best, path, key=len)
    return best
chain = max((longest(t, {t}) for t in sk.tasks), key=len)
space = design_space(sk, links, chains=[chain], objectives=["latency", "period", "load"])
start = time.perf_counter()
found = explore_design(space, workers=0)
print(json.dumps({"variants": len(found.results), "seconds": time.perf_counter() - start,
                  "chain": chain}))
"""


def analyze_rows(runs: int, tmp: Path) -> list[str]:
    rows = []
    for shape, n, processors, what in CASES:
        path = tmp / f"{shape}-{n}-{processors}.json"
        cmd = [sys.executable, str(HERE / "chain_skeletons.py"), str(n), "--shape", shape,
               "-o", str(path)]
        if processors:
            cmd += ["--processors", str(processors)]
        subprocess.run(cmd, check=True, cwd=HERE)
        files = {"without": path.with_suffix(".nochains.json"), "with": path}
        got: dict[str, list[dict]] = {k: [] for k in files}
        for _ in range(runs):
            for name, f in files.items():
                r = measure(HERE.parent, f, (), tmp / "rss", 600.0)
                got[name].append(r)
                print(f"{what} {name}: {r['time']:.2f} s cpu {r['cpu']:.2f} s rc {r['rc']}",
                      file=sys.stderr, flush=True)
        w = [r["time"] for r in got["without"]]
        c = [r["time"] for r in got["with"]]
        wc = [r["cpu"] for r in got["without"]]
        cc = [r["cpu"] for r in got["with"]]
        decided = _decided(got["with"][0]["stdout"])
        rows.append(f"| {what} | {spread(w)} | {spread(c)} | "
                    f"{statistics.median(c) / statistics.median(w):.3f} | {spread(wc)} | "
                    f"{spread(cc)} | {statistics.median(cc) / statistics.median(wc):.3f} | "
                    f"{decided} |")
    return rows


def _decided(stdout: bytes) -> str:
    """How many chains were decided, on processors and with a processor per task."""
    doc = json.loads(stdout)
    chains = doc["chains"]
    on = sum(c["on_processors"]["first_use"] is not None for c in chains)
    alone = sum(c["first_use"] is not None for c in chains)
    return f"{on}/{len(chains)} on processors, {alone}/{len(chains)} per task"


def explore_rows(base: Path | None, runs: int) -> list[str]:
    roots = {"B (this tree)": HERE.parent}
    if base is not None:
        roots = {"A (base)": base.resolve(), **roots}
    rates: dict[str, list[float]] = {k: [] for k in roots}
    chain = None
    for _ in range(runs):
        for name, root in roots.items():
            env = dict(os.environ, PYTHONPATH=str(root))
            out = subprocess.run([sys.executable, "-c", _EXPLORE, str(root)], cwd=root,
                                 env=env, capture_output=True, text=True, timeout=3600,
                                 check=True)
            row = json.loads(out.stdout.strip().splitlines()[-1])
            chain = row["chain"]
            rates[name].append(row["variants"] / row["seconds"])
            print(f"explore {name}: {row['variants']} variants in {row['seconds']:.2f} s",
                  file=sys.stderr, flush=True)
    lines = [f"chain {','.join(chain or [])}; variants/s, median (min-max) of {runs}", "",
             "| tree | variants/s |", "|---|---:|"]
    lines += [f"| {name} | {spread(v)} |" for name, v in rates.items()]
    if len(rates) == 2:
        a, b = (statistics.median(v) for v in rates.values())
        lines.append(f"| B/A | {b / a:.2f} |")
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", type=Path, help="checkout to compare explore with (A)")
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--output", type=Path)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        rows = analyze_rows(args.runs, Path(tmp))
    head = ["# Chains (spec §4c): their cost in `tegraph analyze`, and explore", "",
            f"Machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f} at the "
            f"end; measured {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}. "
            f"Median (min-max) of {args.runs} runs, fresh process each, alternating.", "",
            "## analyze FILE --json, without and with the file's chains", "",
            "| skeleton | without (s) | with (s) | with/without | CPU without (s) | "
            "CPU with (s) | CPU with/without | chains decided |",
            "|---|---|---|---:|---|---|---:|---|"]
    text = head + rows + ["", "## explore, 20 tasks, 3 links (64 variants), a chain "
                                 "objective, in process", ""] + explore_rows(args.base,
                                                                            args.runs)
    out = "\n".join(text) + "\n"
    print(out)
    if args.output:
        args.output.write_text(out)


if __name__ == "__main__":
    main()
