"""A skeleton that IS schedulable on its processors, for the sensitivity benchmark.

``generate_skeleton.py``'s groups overrun on purpose (double synchronization,
free-running circuits), so none of its skeletons is schedulable on its
processors. Here each of ``n_tasks / 10`` processors runs two synchronized
groups of five tasks: an ASYN/SYN chain on a 10 ms clock and one on a 20 ms
clock (rate-monotonic: the first is more urgent), durations between 0.1 and
0.4 ms, so each processor is loaded about 20 % and each part (one processor,
its two groups) repeats after one hyperperiod of 20 ms.

Usage::

    python benchmarks/schedulable_skeleton.py 100 -o /tmp/s100.yaml [--seed 0]
"""

from __future__ import annotations

import argparse
import json
import random
from pathlib import Path


def generate(n_tasks: int, seed: int = 0) -> dict:
    rng = random.Random(seed)
    tasks: dict[str, dict] = {}
    links: list[dict] = []
    for p in range(max(1, n_tasks // 10)):
        for g, period in enumerate((10, 20)):
            names = [f"P{p}.G{g}.T{k}" for k in range(5)]
            for k, name in enumerate(names):
                task: dict = {"duration": f"{rng.randint(10, 40)}/100", "processor": f"cpu{p}"}
                if k == 0:
                    task["period"] = period
                if k > 0:
                    task["inputs"] = ["i"]
                    links.append({"from": f"{names[k - 1]}:o", "to": f"{name}:i",
                                  "protocol": "ASYN/SYN"})
                if k < 4:
                    task["outputs"] = ["o"]
                tasks[name] = task
    return {"name": f"schedulable-{len(tasks)}", "tasks": tasks, "links": links}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("n_tasks", type=int)
    parser.add_argument("-o", "--output", type=Path, required=True)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    args.output.write_text(json.dumps(generate(args.n_tasks, args.seed), indent=1))


if __name__ == "__main__":
    main()
