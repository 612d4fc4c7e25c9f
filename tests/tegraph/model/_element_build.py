"""The event-graph build of a skeleton place by place, as ``build_teg`` did before it
built columns: the oracle of ``test_build_columns``.

Each event is added by ``add_transition`` and each place by ``add_places``'s checked,
one-at-a-time path, every name resolved through the graph's own index: slow, and
obviously what the module docstring of :mod:`tegraph.model.build` says.
"""

from __future__ import annotations

import itertools
from fractions import Fraction
from typing import Any

from tegraph.model.build import ActivationEnd, HoldingSource
from tegraph.model.skeleton import Protocol, Skeleton, Task
from tegraph.model.teg import TimedEventGraph

_ZERO = Fraction(0)
_NO_PARAMETER = HoldingSource("none")


def element_build(skeleton: Skeleton) -> TimedEventGraph:
    """``build_teg(skeleton)`` place by place, for a skeleton whose references resolve."""
    tasks, clocks = skeleton.tasks, skeleton.clocks
    merged = {link.reader: f"{link.writer[0]}.write:{link.writer[1]}"
              for link in skeleton.links if link.protocol is Protocol.SYN_SYN}
    chains = {name: _chain(t, merged) for name, t in tasks.items()}
    teg = TimedEventGraph(skeleton.name)
    teg.attrs["unit"] = skeleton.unit
    _add_events(teg, skeleton, chains, merged)
    places = _Places(teg, skeleton)
    for c, clock in clocks.items():
        places.add(f"{c}.tick", f"{c}.tick", HoldingSource("period", c), tokens=1,
                   initial=clock.phase, kind="clock", origin={"clock": c})
    for name, chain in chains.items():
        _add_chain(places, tasks[name], [ev for ev, _ in chain])
    _add_links(places, skeleton)
    _add_threads(places, skeleton, chains)
    teg.add_places(places.rows)
    idx = teg.index
    teg.attrs["chains"] = {t: tuple(idx(ev) for ev, _ in chain) for t, chain in chains.items()}
    teg.attrs["compute"] = {t: idx(f"{t}.compute") for t in tasks}
    teg.attrs["clocks"] = {c: idx(f"{c}.tick") for c in clocks}
    teg.attrs["holding_source"] = tuple(places.sources)
    teg.attrs["activation_end"] = {
        t: ActivationEnd(idx(chain[-1][0]), not tasks[t].outputs,
                         Fraction(0) if tasks[t].outputs else tasks[t].duration)
        for t, chain in chains.items()}
    return teg


class _Places:
    def __init__(self, teg: TimedEventGraph, skeleton: Skeleton) -> None:
        self.teg, self.skeleton = teg, skeleton
        self.rows: list[tuple[Any, ...]] = []
        self.sources: list[HoldingSource] = []

    def add(self, src: str, dst: str, source: HoldingSource = _NO_PARAMETER, *,
            tokens: int = 0, initial: Fraction = _ZERO, kind: str, origin: dict) -> None:
        self.rows.append((src, dst, tokens, source.value(self.skeleton), initial, kind, origin))
        self.sources.append(source)


def _add_events(teg, skeleton, chains, merged) -> None:
    tasks = skeleton.tasks
    ports: dict[str, list[tuple[str, str]]] = {}
    for t in tasks.values():
        for p in t.outputs:
            ports[f"{t.name}.write:{p}"] = [(t.name, p)]
    for t in tasks.values():
        for q in t.inputs:
            ports.setdefault(merged.get((t.name, q), f"{t.name}.read:{q}"), []).append((t.name, q))
    owners: dict[str, list[str]] = {}
    for name, chain in chains.items():
        for ev, _ in chain:
            if name not in owners.setdefault(ev, []):
                owners[ev].append(name)
    for c in skeleton.clocks:
        teg.add_transition(f"{c}.tick", role="tick", tasks=(), ports=(), clock=c)
    made: set[str] = set()
    for name, chain in chains.items():
        for ev, role in chain:
            if ev in made:
                continue
            made.add(ev)
            if len(ports.get(ev, ())) > 1:
                role = "rendezvous"
            teg.add_transition(ev, role=role, tasks=tuple(owners[ev]),
                               ports=tuple(ports.get(ev, ())),
                               clock=tasks[name].clock if role == "activate" else None)


def _add_links(places: _Places, skeleton: Skeleton) -> None:
    for i, link in enumerate(skeleton.links):
        w = f"{link.writer[0]}.write:{link.writer[1]}"
        r = f"{link.reader[0]}.read:{link.reader[1]}"
        origin = {"link": link.label, "link_index": i}
        if link.protocol is Protocol.ASYN_SYN:
            places.add(w, r, kind="asyn-syn", origin=origin)
        elif link.protocol is Protocol.SYN_ASYN:
            places.add(r, w, kind="syn-asyn", origin=origin)


def _add_threads(places: _Places, skeleton: Skeleton, chains) -> None:
    ends = {name: (chain[0][0], chain[-1][0]) for name, chain in chains.items()}
    for i, thread in enumerate(skeleton.threads):
        for j, name in enumerate(thread):
            nxt, last = thread[(j + 1) % len(thread)], j == len(thread) - 1
            places.add(ends[name][1], ends[nxt][0], _leaving(name, ends[name][1]),
                       tokens=1 if last else 0, kind="thread-return" if last else "thread",
                       origin={"thread": i, "from": name, "to": nxt})


def _chain(task: Task, merged) -> list[tuple[str, str]]:
    t = task.name
    chain = [(f"{t}.activate", "activate")] if task.clock is not None else []
    chain += [(merged.get((t, q), f"{t}.read:{q}"), "read") for q in task.inputs]
    chain.append((f"{t}.compute", "compute"))
    chain += [(f"{t}.write:{p}", "write") for p in task.outputs]
    return chain


def _leaving(task: str, event: str) -> HoldingSource:
    return HoldingSource("duration", task) if event == f"{task}.compute" else _NO_PARAMETER


def _add_chain(places: _Places, task: Task, chain: list[str]) -> None:
    t = task.name
    if task.clock is not None:
        places.add(f"{task.clock}.tick", chain[0], kind="activation",
                   origin={"clock": task.clock, "task": t})
    origin = {"task": t}
    for a, b in itertools.pairwise(chain):
        places.add(a, b, _leaving(t, a), kind="chain", origin=origin)
    places.add(chain[-1], chain[0], _leaving(t, chain[-1]), tokens=1, kind="return",
               origin=origin)
