"""Generated skeletons with latency chains (spec §4c), for the chains benchmark.

On a skeleton of ``generate_skeleton.py`` (groups of 3 to 30 tasks):

- ``many``: ``count`` chains of 5 to 20 tasks, each a random walk along the links
  (a task reads the one before); where a walk finds no link to a task it has not
  visited, an ASYN/ASYN link to a random one is added (new ports: no place, so
  the groups and their figures stay those of the skeleton without the link);
- ``through``: one chain through every group, in file order: from each group's
  first task down its links (the group's tree of readers) to a task without
  reader, then an ASYN/ASYN link to the first task of the next group.

Both skeletons are written twice, with and without their ``chains:`` (the
added links in both), so that the cost of the chains alone is compared.

Usage::

    python benchmarks/chain_skeletons.py 1000 --shape many -o /tmp/many.json
        [--count 100] [--seed 0] [--processors N]
    (writes /tmp/many.json and /tmp/many.nochains.json)
"""

from __future__ import annotations

import argparse
import json
import random
from pathlib import Path

from generate_skeleton import generate, spread


def _readers(doc: dict) -> dict[str, list[str]]:
    out: dict[str, list[str]] = {t: [] for t in doc["tasks"]}
    for link in doc["links"]:
        out[link["from"].split(":")[0]].append(link["to"].split(":")[0])
    return out


def _link(doc: dict, a: str, b: str, port: str) -> None:
    doc["tasks"][a].setdefault("outputs", []).append(port)
    doc["tasks"][b].setdefault("inputs", []).append(port)
    doc["links"].append({"from": f"{a}:{port}", "to": f"{b}:{port}", "protocol": "ASYN/ASYN"})


def many(doc: dict, count: int, rng: random.Random) -> list[list[str]]:
    """``count`` chains of 5 to 20 tasks along the links, adding ASYN/ASYN ones."""
    names = list(doc["tasks"])
    readers = _readers(doc)
    chains = []
    for c in range(count):
        length = rng.randint(5, 20)
        chain = [rng.choice(names)]
        while len(chain) < length:
            here = chain[-1]
            options = [t for t in readers[here] if t not in chain]
            if options:
                chain.append(rng.choice(options))
                continue
            nxt = rng.choice([t for t in names if t not in chain])
            _link(doc, here, nxt, f"c{c}_{len(chain)}")
            readers[here].append(nxt)
            chain.append(nxt)
        chains.append(chain)
    return chains


def through(doc: dict, rng: random.Random) -> list[list[str]]:
    """One chain through every group: down each group's readers, then to the next group."""
    readers = _readers(doc)
    firsts = [t for t in doc["tasks"] if t.endswith(".T0")]
    group_of = {t: t.split(".")[0] for t in doc["tasks"]}
    chain: list[str] = []
    for g, first in enumerate(firsts):
        here = first
        if chain:
            _link(doc, chain[-1], first, f"through{g}")
        chain.append(here)
        while True:
            inside = [t for t in readers[here] if group_of[t] == group_of[first]
                      and t not in chain]
            if not inside:
                break
            here = rng.choice(inside)
            chain.append(here)
    return [chain]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("n_tasks", type=int)
    parser.add_argument("--shape", choices=["many", "through"], required=True)
    parser.add_argument("--count", type=int, default=100)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--processors", type=int)
    parser.add_argument("-o", "--output", type=Path, required=True)
    args = parser.parse_args()
    doc = generate(args.n_tasks, args.seed)
    if args.processors:
        doc = spread(doc, args.processors)
    rng = random.Random(args.seed + 1)
    chains = many(doc, args.count, rng) if args.shape == "many" else through(doc, rng)
    args.output.with_suffix(".nochains.json").write_text(json.dumps(doc, indent=1))
    doc["chains"] = chains
    args.output.write_text(json.dumps(doc, indent=1))


if __name__ == "__main__":
    main()
