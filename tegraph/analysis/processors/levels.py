"""A processor's groups as levels of priority: periodic units and background tasks.

Under preemptive fixed priorities a job never waits for a less urgent one, and
no place joins two groups (spec §2, §4): the schedule of a level (the jobs of
one priority) depends only on the levels above it. When a part of the
schedule (groups joined by a processor) has the shape of the ORCCAD rules
(each group released by one clock, its tasks at one priority on one
processor), each group runs as **one periodic unit of its summed work**, and
the part is decided by Lehoczky, Sha and Ding's exact test, level by level
from the most urgent down, without simulating (``scaling.level_limits``).

A part has **levels** (:func:`processor_levels`) when

- all its tasks run on one processor, which preempts (§4b);
- the tasks of each group share one priority, and no two groups share one;
- each group is either

  - a **unit**: one clock, of phase 0, and every event of the group waits,
    through places without token, for a tick of that clock (nothing of it runs
    ahead of its clock); its unit has the clock's period and the sum of the
    group's durations as its work; or
  - a **background task**: a group of one task without a clock (it runs
    freely, whenever its processor has nothing more urgent to do).

The theorem (``docs/sensitivity.md``, *One periodic unit per group*, with its
proof): take the levels most urgent first; while every unit above meets its
deadline (its work of activation k done by tick k+1) and no background task
above has work,

1. a unit that meets its deadline by the exact test is schedulable: each
   activation's jobs end by the next tick, the last exactly when the unit's
   job ends (the group's jobs keep the processor busy at their level exactly
   when the unit would be: each is released when those it waits for end);
2. a unit that misses its first deadline leaves work of activation 1 at tick
   2; when a task of its clock ends each activation after every job of it
   (the unit's **closing** task), that task overruns at activation 2, proven;
   without one, the lateness of a task without clock is no overrun (§4b), and
   the theorem does not decide;
3. a background task of positive duration gets the processor's idle time: it
   is starved exactly when the units above use all of it (their utilization
   is 1); once it runs, it always has a job, so every less urgent job of
   positive duration is starved.

References
----------
.. [1] J. Lehoczky, L. Sha, Y. Ding, "The rate monotonic scheduling algorithm:
   exact characterization and average case behavior", IEEE Real-Time Systems
   Symposium, 166–171, 1989.
.. [2] C. L. Liu, J. W. Layland, "Scheduling algorithms for multiprogramming in
   a hard-real-time environment", Journal of the ACM 20(1), 46–61, 1973.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction

from ...model.build import activation_end, holding_sources
from ...model.platform import Platform
from ...model.skeleton import Skeleton
from ...model.teg import TimedEventGraph

__all__ = ["Level", "Levels", "processor_levels"]


@dataclass(frozen=True)
class Level:
    """One group at its priority: a periodic unit (``clock`` set) or a background task."""

    tasks: tuple[str, ...]
    """In an order where each task comes after those it waits for in an activation."""
    priority: int
    clock: str | None
    """The unit's clock; None: a background task (one task without a clock)."""
    period: Fraction | None
    closing: str | None = None
    """A task of the unit's clock whose activation ends after every job of the same
    activation (None: none, or a background task)."""


@dataclass(frozen=True)
class Levels:
    """The levels of one part, most urgent first, on its one processor."""

    processor: str
    levels: tuple[Level, ...]


def processor_levels(skeleton: Skeleton, teg: TimedEventGraph,
                     parts: Sequence[Sequence[Sequence[str]]], platform: Platform
                     ) -> list[Levels | str]:
    """The levels of each part, or why it has none.

    Parameters
    ----------
    skeleton : Skeleton
    teg : TimedEventGraph
        ``build_teg(skeleton)``.
    parts : sequence of sequences of sequences of str
        For each part (spec §4 groups joined by a processor), the tasks of each
        of its groups, each group live.
    platform : Platform

    Returns
    -------
    list of Levels or str
        Per part: its levels, or the reason, in words, why it has none.

    Examples
    --------
    A chain ``imu -> est`` (ASYN/SYN) on a 1 ms clock above a logger without clock:

    >>> from tegraph.analysis.analyze import analyze_skeleton
    >>> from tegraph.model.platform import platform_of
    >>> from tegraph.model.build import build_teg
    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "imu": {"duration": "0.1", "period": 1, "outputs": ["x"]},
    ...     "est": {"duration": "0.2", "inputs": ["x"]}, "log": {"duration": 5}},
    ...     "links": [{"from": "imu:x", "to": "est:x", "protocol": "ASYN/SYN"}]})
    >>> groups = analyze_skeleton(sk).groups
    >>> [levels] = processor_levels(sk, build_teg(sk), [[g.tasks for g in groups]],
    ...                             platform_of(sk, groups))
    >>> [(lv.tasks, lv.clock, lv.closing) for lv in levels.levels]
    [(('imu', 'est'), 'imu.clock', None), (('log',), None, None)]
    """
    waits = _Waits(teg)
    # A link's delay (§4d) leaves its reader idle while the message travels: a group is
    # then no unit of its summed work at one priority, and the levels do not apply.
    owners = teg.transition_attrs
    delayed = {t for p, source in zip(teg.places, holding_sources(teg))
               if source.kind in ("delay", "network-delay") and p.holding > 0
               for t in owners[p.dst].get("tasks", ())}
    return [_part_levels(skeleton, teg, groups, platform, waits, delayed) for groups in parts]


def _part_levels(skeleton: Skeleton, teg: TimedEventGraph, groups: Sequence[Sequence[str]],
                 platform: Platform, waits: _Waits, delayed: set[str]) -> Levels | str:
    processors = sorted({platform.processor_of[t] for g in groups for t in g})
    if len(processors) != 1:
        return f"its tasks run on {len(processors)} processors"
    processor = processors[0]
    if not platform.preemptive(processor):
        return f"the processor {processor} does not preempt"
    held = next((t for g in groups for t in g if t in delayed), None)
    if held is not None:
        return f"a link into {held} holds a delay (§4d)"
    owner: dict[int, str] = {}
    levels = []
    for group in groups:
        priorities = {platform.priority[t] for t in group}
        if len(priorities) != 1:
            return f"the tasks of the group of {_names(group)} have {len(priorities)} priorities"
        priority = priorities.pop()
        if priority in owner:
            return (f"the groups of {owner[priority]} and {group[0]} share the priority "
                    f"{priority}")
        owner[priority] = group[0]
        level = _level(skeleton, teg, waits, list(group), priority)
        if isinstance(level, str):
            return level
        levels.append(level)
    levels.sort(key=lambda level: -level.priority)
    return Levels(processor, tuple(levels))


def _level(skeleton: Skeleton, teg: TimedEventGraph, waits: _Waits, group: list[str],
           priority: int) -> Level | str:
    clocks = list(dict.fromkeys(c for t in group if (c := skeleton.tasks[t].clock) is not None))
    if not clocks:
        if len(group) != 1:
            return f"the group of {_names(group)} has no clock and {len(group)} tasks"
        return Level(tuple(group), priority, None, None)
    if len(clocks) > 1:
        return f"the group of {_names(group)} has {len(clocks)} clocks"
    name = clocks[0]
    clock = skeleton.clocks[name]
    if clock.phase != 0:
        return f"the clock {name} has phase {clock.phase}, not 0"
    tick = teg.attrs["clocks"][name]
    chains = teg.attrs["chains"]
    events = [e for t in group for e in chains[t]]
    order = waits.order(tick, events)
    if isinstance(order, int):
        return (f"in the group of {_names(group)}, {teg.transition_names[order]} does not "
                f"wait for a tick of {name}")
    compute = teg.attrs["compute"]
    rank = {e: i for i, e in enumerate(order)}
    ordered = tuple(sorted(group, key=lambda t: rank[compute[t]]))
    computes = {compute[t] for t in group}
    closing = next((t for t in group if skeleton.tasks[t].clock == name
                    and computes <= waits.before(activation_end(teg, t).event)), None)
    return Level(ordered, priority, name, clock.period, closing)


class _Waits:
    """The places without token of the graph, both ways."""

    def __init__(self, teg: TimedEventGraph) -> None:
        a = teg.arrays()
        empty = a.tokens == 0
        self.after: dict[int, list[int]] = {}
        self.before_of: dict[int, list[int]] = {}
        for s, d in zip(a.src[empty].tolist(), a.dst[empty].tolist()):
            self.after.setdefault(s, []).append(d)
            self.before_of.setdefault(d, []).append(s)

    def order(self, tick: int, events: list[int]) -> list[int] | int:
        """``events`` in an order of their places without token, each after those it
        waits for, when every one waits for ``tick``; else one that does not (it waits
        for nothing, or lies on or after a circuit without token)."""
        inside = dict.fromkeys(events)
        need = {e: sum(1 for s in self.before_of.get(e, ()) if s in inside or s == tick)
                for e in inside}
        free = next((e for e, n in need.items() if n == 0), None)
        if free is not None:
            return free
        ready = []
        for d in self.after.get(tick, ()):
            if d in inside:
                need[d] -= 1
                if need[d] == 0:
                    ready.append(d)
        out: list[int] = []
        while ready:
            e = ready.pop()
            out.append(e)
            for d in self.after.get(e, ()):
                if d in inside:
                    need[d] -= 1
                    if need[d] == 0:
                        ready.append(d)
        if len(out) < len(inside):
            done = set(out)
            return next(e for e in inside if e not in done)
        return out

    def before(self, event: int) -> set[int]:
        """The events from which ``event`` is reached through places without token
        (``event`` included)."""
        seen = {event}
        stack = [event]
        while stack:
            for s in self.before_of.get(stack.pop(), ()):
                if s not in seen:
                    seen.add(s)
                    stack.append(s)
        return seen


def _names(group: Sequence[str]) -> str:
    return ", ".join(group[:3]) + (" ..." if len(group) > 3 else "")
