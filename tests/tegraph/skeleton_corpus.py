"""Small random skeletons for the tests: the generator and its shared pieces.

:func:`random_skeleton` draws a valid skeleton dictionary (spec §1) from a
``random.Random``: 1 to 5 tasks, shared, private or no clocks, up to two
inputs and outputs per task, links with the four protocols, an occasional
thread; or a ring of 2 to 5 tasks with circuits of several tokens. The tests
feed it hypothesis' ``st.randoms()`` (so failures shrink and replay) and, for
the fixed corpus, ``random.Random(seed)`` for the seeds ``0 .. n-1``:
:func:`write_corpus` writes those files at test time, so the corpus is the same
on every machine and nothing is committed but this code.

The wiring is shared with the hypothesis strategies of
``test_analysis_properties`` (which draw with ``draw`` instead of a
``random.Random``): :func:`link_inputs` links the input ports,
:func:`ring_links` closes a ring, :func:`add_follower` hangs a reader on R0.
They take the random choices as arguments (or as the ``pick``/``skip``
callables), so each caller's skeleton for a given seed stays what it was.

>>> import random
>>> a, b = random_skeleton(random.Random(7)), random_skeleton(random.Random(7))
>>> a == b and 1 <= len(a["tasks"]) <= 6
True
"""

from __future__ import annotations

import json
import random
from collections.abc import Callable
from pathlib import Path
from typing import Any

PROTOCOLS = ["ASYN/ASYN", "ASYN/SYN", "SYN/ASYN", "SYN/SYN"]
DURATIONS = [0, 1, 1, 2, 3, "1/2", "1/3", "3/2", "5/2", "7/3"]
PERIODS = [1, 2, 3, 4, 5, 6, 10, "1/2", "5/2", "7/3"]
PHASES = [0, 0, 1, "1/2", "5/3"]


def random_skeleton(rng: random.Random, max_tasks: int = 5, max_ports: int = 2) -> dict:
    """A valid skeleton dictionary; the same ``rng`` state gives the same skeleton.

    One in four is a ring (:func:`random_ring`): random wiring seldom closes
    a circuit with two tokens, which is what gives cyclicities above 1.
    """
    if rng.random() < 0.25:
        return random_ring(rng, max_tasks)
    n = rng.randint(1, max_tasks)
    names = [f"T{i}" for i in range(n)]
    clocks = {}
    for j in range(rng.randint(0, 2)):
        clocks[f"c{j}"] = {"period": rng.choice(PERIODS), "phase": rng.choice(PHASES)}
    tasks: dict[str, dict] = {}
    for t in names:
        spec: dict = {"duration": rng.choice(DURATIONS)}
        kind = rng.choice(["none", "private", "shared", "shared"])
        if kind == "private":
            spec["period"] = rng.choice(PERIODS)
            spec["phase"] = rng.choice(PHASES)
        elif kind == "shared" and clocks:
            spec["clock"] = rng.choice(sorted(clocks))
        spec["inputs"] = [f"i{j}" for j in range(rng.randint(0, max_ports))]
        spec["outputs"] = [f"o{j}" for j in range(rng.randint(0, max_ports))]
        tasks[t] = spec
    links = link_inputs(names, tasks, pick=rng.choice, skip=lambda: rng.random() < 0.2)
    data: dict = {"clocks": clocks, "tasks": tasks, "links": links}
    if n > 1 and rng.random() < 0.2:
        data["threads"] = [rng.sample(names, rng.randint(2, n))]
    return data


def random_ring(rng: random.Random, max_tasks: int = 5) -> dict:
    """Tasks R0 -> R1 -> ... -> R0 joined by ASYN/SYN or SYN/ASYN links in random port orders.

    Link i either carries R(i)'s message to R(i+1) (ASYN/SYN) or R(i)'s
    request to R(i+1) (SYN/ASYN, R(i+1) writes when R(i) has read), so the
    ring circuit holds 0, 1, 2... tokens (examples/ring_two_tokens.yaml is
    one of them); R0 may have a clock and a follower may read R0.
    """
    n = rng.randint(2, max_tasks)
    # Equal durations make a circuit of several tokens the critical one.
    same = rng.choice(DURATIONS[1:]) if rng.random() < 0.5 else None
    tasks: dict[str, dict] = {f"R{i}": {"duration": same or rng.choice(DURATIONS),
                                        "inputs": [], "outputs": []} for i in range(n)}
    links = ring_links(tasks, [rng.random() < 0.5 for _ in range(n)])
    for spec in tasks.values():
        for side in ("inputs", "outputs"):
            rng.shuffle(spec[side])
    clocks = {}
    if rng.random() < 0.3:
        clocks["rtc"] = {"period": rng.choice(PERIODS), "phase": rng.choice(PHASES)}
        tasks["R0"]["clock"] = "rtc"
    if rng.random() < 0.5:
        add_follower(tasks, links, rng.choice(DURATIONS))
    return {"clocks": clocks, "tasks": tasks, "links": links}


def link_inputs(names: list[str], tasks: dict[str, dict], pick: Callable[[list], Any],
                skip: Callable[[], bool], guard_all_links: bool = True) -> list[dict]:
    """Link the input ports of ``tasks`` (each with at most one writer, none of its own task).

    For each input port in task order, ``skip()`` leaves it unlinked (a device),
    otherwise ``pick`` chooses a writer ``(task, output)`` among the other tasks'
    outputs, then a protocol. A reader is never given two SYN/SYN links to
    one write event (two rendezvous with one write: a library limitation,
    ``test_double_rendezvous_with_one_write``): such a link becomes ASYN/SYN
    when the reader already has a SYN/SYN link to that event, or, with
    ``guard_all_links`` (:func:`random_skeleton`), any link to it.
    ``skip`` is not called when no other task writes.
    """
    outputs = [(t, p) for t in names for p in tasks[t]["outputs"]]
    links = []
    for t in names:
        met: set[tuple[str, str]] = set()
        for q in tasks[t]["inputs"]:
            writers = [(w, p) for (w, p) in outputs if w != t]
            if not writers or skip():
                continue  # unlinked: a device
            w, p = pick(writers)
            proto = pick(PROTOCOLS)
            if guard_all_links or proto == "SYN/SYN":
                if proto == "SYN/SYN" and (w, p) in met:
                    proto = "ASYN/SYN"
                met.add((w, p))
            links.append({"from": f"{w}:{p}", "to": f"{t}:{q}", "protocol": proto})
    return links


def ring_links(tasks: dict[str, dict], forward: list[bool]) -> list[dict]:
    """Join R0 -> R1 -> ... -> R(n-1) -> R0 (n = ``len(forward)``); return the links.

    Link i is ASYN/SYN when ``forward[i]`` (R(i) writes x_i that R(i+1) reads),
    else SYN/ASYN (R(i+1) writes z_i that R(i) reads); the ports are appended
    to the tasks' ``inputs`` and ``outputs`` lists in link order.
    """
    n = len(forward)
    links = []
    for i, fwd in enumerate(forward):
        a, b = f"R{i}", f"R{(i + 1) % n}"
        if fwd:
            tasks[a]["outputs"].append(f"x{i}")
            tasks[b]["inputs"].append(f"x{i}")
            links.append({"from": f"{a}:x{i}", "to": f"{b}:x{i}", "protocol": "ASYN/SYN"})
        else:
            tasks[b]["outputs"].append(f"z{i}")
            tasks[a]["inputs"].append(f"z{i}")
            links.append({"from": f"{b}:z{i}", "to": f"{a}:z{i}", "protocol": "SYN/ASYN"})
    return links


def add_follower(tasks: dict[str, dict], links: list[dict], duration) -> None:
    """Add task F reading R0's new output f (ASYN/SYN): it reads the ring without feeding it."""
    tasks["F"] = {"duration": duration, "inputs": ["f"]}
    tasks["R0"]["outputs"].append("f")
    links.append({"from": "R0:f", "to": "F:f", "protocol": "ASYN/SYN"})


def write_corpus(directory: Path, count: int) -> list[Path]:
    """Write ``corpus-<seed>.json`` for the seeds ``0 .. count-1``; return the paths."""
    paths = []
    for seed in range(count):
        data = random_skeleton(random.Random(seed))
        data["name"] = f"corpus-{seed}"
        path = Path(directory) / f"corpus-{seed}.json"
        path.write_text(json.dumps(data, indent=1))
        paths.append(path)
    return paths


def side_by_side(parts: list[dict]) -> dict:
    """Several corpus skeletons as one (each part's clocks and tasks renamed ``g<k>...``),
    so one analysis sees many groups."""
    data: dict = {"clocks": {}, "tasks": {}, "links": [], "threads": []}
    for k, part in enumerate(parts):
        rename = {t: f"g{k}{t}" for t in part["tasks"]}
        for c, clock in part["clocks"].items():
            data["clocks"][f"g{k}{c}"] = clock
        for t, spec in part["tasks"].items():
            spec = dict(spec)
            if "clock" in spec:
                spec["clock"] = f"g{k}{spec['clock']}"
            data["tasks"][rename[t]] = spec
        for link in part["links"]:
            link = dict(link)
            for end in ("from", "to"):
                task, port = link[end].split(":")
                link[end] = f"{rename[task]}:{port}"
            data["links"].append(link)
        data["threads"] += [[rename[t] for t in thread] for thread in part.get("threads", [])]
    return data
