"""Generate large synchronization skeletons for the analysis benchmark.

Tasks come in synchronized groups of 3 to 30: the first task of a group has a
clock; every other task reads from an earlier task of its group through
ASYN/SYN (mostly), SYN/ASYN or SYN/SYN, so each group is one weakly connected
part of the timed event graph. A few tasks share a thread with the task they
read from, and ASYN/ASYN links join some groups (they add no place). Durations
are small against the clock period, so most groups are consistent; a few
groups get a second clock on one of their tasks (double synchronization, the
ORCCAD paper's Figure 12), which makes them overrun.

Two more shapes put every task in ONE synchronized group, to see how each
phase grows with the size of a group rather than with the number of groups:
``chain`` is an ASYN/SYN chain driven by the clock of its first task, and
``chain-clocks`` is the same chain where every task also has its own 7 ms
clock (one group bound by as many clocks as tasks).

``--processors N`` spreads the tasks over N processors ``cpu0`` ... (spec v1.2
§4b), round robin in file order, the tasks of one thread together (a thread is one
OS thread: it cannot cross processors); without it every task is on the one
processor ``default``.

``--non-preemptive K`` declares the first K processors (``cpu0`` ... in order, or
``default`` without ``--processors``) ``preemptive: false`` in a ``processors:``
mapping (spec v1.3 §4d); only a processor some task runs on may be declared, so K
is at most the number of processors that got a task. ``--delay D`` sets
``network.delay: D`` (exact, e.g. ``1/10``), the delay of every link across
processors; a rendezvous (SYN/SYN) across processors cannot be delayed (§4d), so
those links declare ``delay: 0``. Without these options the file is the same as
before they existed.

Usage::

    python benchmarks/generate_skeleton.py 10000 -o /tmp/sk10k.yaml [--seed 0]
        [--shape groups|chain|chain-clocks] [--processors N]
        [--non-preemptive K] [--delay D]
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
    threads: list[list[str]] = []
    in_thread: set[str] = set()
    group_first: list[str] = []
    made = 0
    g = 0
    while made < n_tasks:
        size = min(rng.randint(3, 30), n_tasks - made)
        period = rng.choice([1, 2, 5, 10, 20, 50])
        names = [f"G{g}.T{k}" for k in range(size)]
        budget = period * 0.8
        for k, name in enumerate(names):
            task: dict = {"duration": f"{rng.randint(1, 100)}/{int(1000 / budget * size) or 1}",
                          "inputs": [], "outputs": []}
            if k == 0:
                task["period"] = period
            tasks[name] = task
        for k in range(1, size):
            parent = names[rng.randrange(k)]
            child = names[k]
            roll = rng.random()
            protocol = "ASYN/SYN" if roll < 0.7 else ("SYN/ASYN" if roll < 0.85 else "SYN/SYN")
            port = f"d{k}"
            tasks[parent]["outputs"].append(port)
            tasks[child]["inputs"].append(port)
            links.append({"from": f"{parent}:{port}", "to": f"{child}:{port}",
                          "protocol": protocol})
            if (protocol == "ASYN/SYN" and rng.random() < 0.05
                    and parent not in in_thread and child not in in_thread):
                threads.append([parent, child])
                in_thread.update((parent, child))
        if rng.random() < 0.05 and size > 1:
            # Double synchronization: a synchronized task also gets a fast clock.
            victim = names[rng.randrange(1, size)]
            tasks[victim]["period"] = max(1, period // 2)
        if group_first and rng.random() < 0.5:
            other = rng.choice(group_first)
            tasks[other]["outputs"].append(f"x{g}")
            tasks[names[0]]["inputs"].append(f"x{g}")
            links.append({"from": f"{other}:x{g}", "to": f"{names[0]}:x{g}",
                          "protocol": "ASYN/ASYN"})
        group_first.append(names[0])
        made += size
        g += 1
    for task in tasks.values():
        if not task["inputs"]:
            del task["inputs"]
        if not task["outputs"]:
            del task["outputs"]
    doc = {"name": f"generated-{n_tasks}", "tasks": tasks, "links": links}
    if threads:
        doc["threads"] = threads
    return doc


def generate_chain(n_tasks: int, every_clock: bool = False, seed: int = 0) -> dict:
    """An ASYN/SYN chain ``C0 -> C1 -> ...`` of ``n_tasks`` tasks: one synchronized group.

    ``C0`` has a 10 ms clock; with ``every_clock`` every other task also has
    its own 7 ms clock, so the group is bound by ``n_tasks`` clocks.
    """
    rng = random.Random(seed)
    tasks: dict[str, dict] = {}
    links: list[dict] = []
    for k in range(n_tasks):
        task: dict = {"duration": f"{rng.randint(1, 100)}/{1000 * max(1, n_tasks // 100)}"}
        if k == 0:
            task["period"] = 10
        elif every_clock:
            task["period"] = 7
        if k > 0:
            task["inputs"] = ["i"]
            links.append({"from": f"C{k - 1}:o", "to": f"C{k}:i", "protocol": "ASYN/SYN"})
        if k < n_tasks - 1:
            task["outputs"] = ["o"]
        tasks[f"C{k}"] = task
    shape = "chain-clocks" if every_clock else "chain"
    return {"name": f"{shape}-{n_tasks}", "tasks": tasks, "links": links}


SHAPES = {"groups": generate,
          "chain": lambda n, seed=0: generate_chain(n, False, seed),
          "chain-clocks": lambda n, seed=0: generate_chain(n, True, seed)}


def spread(doc: dict, processors: int) -> dict:
    """``doc`` with its tasks on ``processors`` processors, round robin, threads kept whole."""
    home: dict[str, str] = {}
    for thread in doc.get("threads", []):
        owner = next((home[t] for t in thread if t in home), thread[0])
        for t in thread:
            home.setdefault(t, owner)
    slot: dict[str, int] = {}
    for name, task in doc["tasks"].items():
        owner = home.get(name, name)
        slot.setdefault(owner, len(slot) % processors)
        task["processor"] = f"cpu{slot[owner]}"
    return doc


def processors_used(doc: dict) -> list[str]:
    """The processors some task of ``doc`` runs on: ``cpu0``, ``cpu1`` ... or ``default``."""
    used = {task.get("processor", "default") for task in doc["tasks"].values()}
    return sorted(used, key=lambda p: (len(p), p))  # cpu2 before cpu10


def declare_platform(doc: dict, non_preemptive: int = 0, delay: str | None = None) -> dict:
    """``doc`` with its first ``non_preemptive`` processors non-preemptive and ``delay``
    the network's delay (spec §4d); SYN/SYN links across processors get ``delay: 0``.

    ``delay`` is a time as the skeleton reads it (``"1/10"``, ``"0.2"``, ``"3"``).
    """
    used = processors_used(doc)
    if not 0 <= non_preemptive <= len(used):
        raise ValueError(f"--non-preemptive {non_preemptive}: the tasks run on "
                         f"{len(used)} processor(s)")
    if non_preemptive:
        doc["processors"] = {p: {"preemptive": False} for p in used[:non_preemptive]}
    if delay is not None:
        doc["network"] = {"delay": delay}
        tasks = doc["tasks"]
        for link in doc["links"]:
            writer, reader = link["from"].split(":")[0], link["to"].split(":")[0]
            if (link["protocol"] == "SYN/SYN" and tasks[writer].get("processor", "default")
                    != tasks[reader].get("processor", "default")):
                link["delay"] = 0
    return doc


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("n_tasks", type=int)
    parser.add_argument("-o", "--output", type=Path, required=True)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--shape", choices=sorted(SHAPES), default="groups")
    parser.add_argument("--processors", type=int, default=0,
                        help="spread the tasks over this many processors (default: one)")
    parser.add_argument("--non-preemptive", type=int, default=0, metavar="K",
                        help="declare the first K processors `preemptive: false`")
    parser.add_argument("--delay", metavar="D",
                        help="network delay of the links across processors, e.g. 1/10")
    args = parser.parse_args()
    doc = SHAPES[args.shape](args.n_tasks, seed=args.seed)
    if args.processors > 0:
        doc = spread(doc, args.processors)
    if args.non_preemptive or args.delay is not None:
        try:
            doc = declare_platform(doc, args.non_preemptive, args.delay)
        except ValueError as exc:
            parser.error(str(exc))
    # JSON is a subset of YAML and loads much faster for large files.
    args.output.write_text(json.dumps(doc, indent=1))


if __name__ == "__main__":
    main()
