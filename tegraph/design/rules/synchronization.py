"""What a task waits for, and the synchronized groups it forms (spec §6).

A task's *synchronizations* are its clock, each input it reads ASYN/SYN or
SYN/SYN (the reader blocks) and each output it posts SYN/ASYN or SYN/SYN (the
writer blocks). A *synchronized group* is a weakly connected part of the timed
event graph (spec §4 ``groups``): tasks joined by a synchronizing link, a
thread or a shared clock. The design rules (:mod:`.rules`) and their advice
(:mod:`.advice`) read a skeleton through these.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from fractions import Fraction
from typing import Literal

from ...model.skeleton import Link, Protocol, Skeleton

__all__ = ["READER_BLOCKS", "WRITER_BLOCKS", "Synchronization", "group_period", "link_index",
           "synchronizations", "synchronized_groups"]

# Which side of a link blocks (spec §1): the reader of ASYN/SYN, the writer of SYN/ASYN.
READER_BLOCKS = (Protocol.ASYN_SYN, Protocol.SYN_SYN)
WRITER_BLOCKS = (Protocol.SYN_ASYN, Protocol.SYN_SYN)


@dataclass(frozen=True)
class Synchronization:
    """One thing a task waits for: its clock, or a blocking side of a link."""

    kind: Literal["clock", "input", "output"]
    clock: str | None = None
    port: str | None = None
    """``TASK:PORT``."""
    link: Link | None = None

    @property
    def label(self) -> str:
        if self.kind == "clock":
            return f"clock {self.clock}"
        # Type: an input or output synchronization always has its link (only a clock has none).
        return f"{self.kind} {self.port} ({self.link.label})"  # type: ignore[union-attr]


def link_index(sk: Skeleton) -> tuple[dict, dict]:
    """Links by reader port and by writer port (one pass, so checks stay linear)."""
    by_reader: dict[tuple[str, str], list[Link]] = {}
    by_writer: dict[tuple[str, str], list[Link]] = {}
    for link in sk.links:
        by_reader.setdefault(link.reader, []).append(link)
        by_writer.setdefault(link.writer, []).append(link)
    return by_reader, by_writer


def synchronizations(sk: Skeleton, task: str,
                     index: tuple[dict, dict] | None = None) -> list[Synchronization]:
    """What ``task`` waits for at each activation, in chain order (Rule 1).

    Examples
    --------
    Figure 12: MT2 has a clock and also waits for MT1's message.

    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "MT1": {"duration": 1, "period": 10, "outputs": ["y"]},
    ...     "MT2": {"duration": 2, "period": 4, "inputs": ["y"]}},
    ...   "links": [{"from": "MT1:y", "to": "MT2:y", "protocol": "ASYN/SYN"}]})
    >>> [s.label for s in synchronizations(sk, "MT2")]
    ['clock MT2.clock', 'input MT2:y (MT1:y -> MT2:y (ASYN/SYN))']
    """
    by_reader, by_writer = index if index is not None else link_index(sk)
    t = sk.tasks[task]
    out = [Synchronization("clock", clock=t.clock)] if t.clock else []
    for port in t.inputs:
        for link in by_reader.get((task, port), ()):
            if link.protocol in READER_BLOCKS:
                out.append(Synchronization("input", port=f"{task}:{port}", link=link))
    for port in t.outputs:
        for link in by_writer.get((task, port), ()):
            if link.protocol in WRITER_BLOCKS:
                out.append(Synchronization("output", port=f"{task}:{port}", link=link))
    return out


def synchronized_groups(sk: Skeleton) -> list[tuple[str, ...]]:
    """The synchronized groups: tasks joined by synchronizing links, threads, clocks.

    These are the weakly connected parts of the timed event graph (spec §4),
    found here by union-find on the skeleton; listed in the order of their
    first task in the file, tasks in file order.

    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "A": {"duration": 1, "period": 2, "outputs": ["x"]},
    ...     "B": {"duration": 1, "inputs": ["x"]}, "C": {"duration": 1, "period": 2}},
    ...   "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]})
    >>> synchronized_groups(sk)
    [('A', 'B'), ('C',)]
    """
    parent = {t: t for t in sk.tasks}

    def find(t: str) -> str:
        while parent[t] != t:
            parent[t] = parent[parent[t]]
            t = parent[t]
        return t

    def union(a: str, b: str) -> None:
        parent[find(a)] = find(b)

    for link in sk.links:
        if link.protocol.synchronizing:
            union(link.writer[0], link.reader[0])
    for thread in sk.threads:
        for a, b in itertools.pairwise(thread):
            union(a, b)
    first_of_clock: dict[str, str] = {}
    for name, task in sk.tasks.items():
        if task.clock:
            union(name, first_of_clock.setdefault(task.clock, name))
    groups: dict[str, list[str]] = {}
    for name in sk.tasks:
        groups.setdefault(find(name), []).append(name)
    return [tuple(g) for g in groups.values()]


def group_period(sk: Skeleton, tasks: tuple[str, ...] | list[str]) -> Fraction | None:
    """The design period of a group: its fastest clock's period (None without a clock).

    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": "5/2"}}})
    >>> group_period(sk, ["A"])
    Fraction(5, 2)
    """
    periods = [sk.clocks[c].period for t in tasks if (c := sk.tasks[t].clock)]
    return min(periods) if periods else None
