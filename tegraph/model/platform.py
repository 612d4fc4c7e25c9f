"""The platform of a skeleton: where each task runs, how urgently, on what kind of processor.

One definition (``docs/skeleton.md`` §4b, §4d), read by everything that speaks of
processors: the exact schedule (:mod:`tegraph.analysis.processors`), its theorems
(the critical instant, the scaling factor), the sensitivity on processors, the
response-time cross-check (:mod:`tegraph.design.schedulability`) and Rule 4
(:mod:`tegraph.design.rules.priorities`). :func:`~tegraph.analysis.analyze.analyze_skeleton`
computes it once (``report.platform``) and the rest reads it there.

- **Processors.** Each task runs on its ``processor``; a task that declares none
  runs on :data:`DEFAULT_PROCESSOR` (``"default"``, :attr:`Task.runs_on
  <tegraph.model.elements.Task.runs_on>`). A processor is preemptive unless
  ``processors:`` declares it ``preemptive: false`` (§4d).
- **Priorities.** On a processor where every task declares ``priority``, those
  (larger is more urgent); otherwise, all or none, every task of that processor
  gets the rate-monotonic proposal (:func:`rate_monotonic`) and the declared ones
  are *replaced* (:attr:`ProcessorInfo.replaced`: the report says so).
- **The rate-monotonic proposal** (§4b). Take the groups (§4, whole groups,
  wherever their other tasks run) that have a task on the processor; a group's
  design period is its fastest clock's period. The shortest design period is the
  most urgent; equal design periods: the group whose first task comes earlier in
  the file; groups without a clock are the least urgent, in file order. Numbers run
  from 1 (least urgent) upward, every task of a group gets its group's number, and
  the Robot-task automaton (:func:`is_automaton`) one more than the largest number
  on its processor: several automata on one processor share that number.
- **Delays** (§4d). A link's delay is its own when it declares one, else the
  network's when its two tasks run on different (declared) processors, else 0
  (:func:`link_delay`).
- **The hyperperiod** of a set of clocks: the least common multiple of their
  periods (:func:`hyperperiod`, :func:`clock_hyperperiod`).

Rate-monotonic priorities are optimal among fixed priorities only under
preemption (Liu and Layland 1973): the proposal is still what a non-preemptive
processor gets (§4d), but nothing claims it is optimal there.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from functools import cached_property
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from ..errors import InputError
from .elements import DEFAULT_PROCESSOR, Link, Processor
from .skeleton import Skeleton
from .structure import Structure, design_period

__all__ = ["DEFAULT_PROCESSOR", "Platform", "Processor", "ProcessorInfo", "check_groups",
           "clock_hyperperiod", "crosses", "group_tasks", "hyperperiod", "is_automaton",
           "link_delay", "platform_of", "processor_of", "processor_parts", "processor_per_task",
           "rate_monotonic"]

_AUTOMATON = re.compile(r"(?:^|\.)(?:rta|automaton)$", re.IGNORECASE)

Groups = Structure | Sequence[Any]
"""The groups of spec §4: a :class:`~tegraph.model.structure.Structure`, or a sequence
of groups, each a sequence of task names or anything with ``tasks`` (a ``GroupReport``)."""


def is_automaton(name: str) -> bool:
    """Whether ``name`` names the Robot-task automaton (§4b): ``RTA`` or ``automaton``,
    or a name ending in ``.RTA`` or ``.automaton``, any case.

    Examples
    --------
    >>> is_automaton("RTA"), is_automaton("arm.Automaton"), is_automaton("PARTA")
    (True, True, False)
    """
    return bool(_AUTOMATON.search(name))


def processor_of(skeleton: Skeleton) -> dict[str, str]:
    """Each task's processor (§4b): the one it declares, else :data:`DEFAULT_PROCESSOR`.

    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "processor": "cpu1"},
    ...                                    "B": {"duration": 1}}})
    >>> processor_of(sk)
    {'A': 'cpu1', 'B': 'default'}
    """
    return {name: task.runs_on for name, task in skeleton.tasks.items()}


def crosses(skeleton: Skeleton, link: Link) -> bool:
    """Whether ``link`` joins two tasks on different processors, as declared (§4d): the
    same with a processor per task (``--no-processors``)."""
    tasks = skeleton.tasks
    return tasks[link.writer[0]].runs_on != tasks[link.reader[0]].runs_on


def link_delay(skeleton: Skeleton, link: Link) -> Fraction:
    """The delay of ``link`` (§4d): its own when declared (0 included), else
    ``network.delay`` when it crosses processors, else 0.

    Examples
    --------
    >>> sk = Skeleton.from_dict({"network": {"delay": "1/5"}, "tasks": {
    ...     "A": {"duration": 1, "outputs": ["x", "y"], "processor": "cpu1"},
    ...     "B": {"duration": 1, "inputs": ["x"], "processor": "cpu2"},
    ...     "C": {"duration": 1, "inputs": ["y"], "processor": "cpu1"}},
    ...   "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"},
    ...             {"from": "A:y", "to": "C:y", "protocol": "ASYN/SYN"}]})
    >>> [str(link_delay(sk, link)) for link in sk.links]
    ['1/5', '0']
    """
    return link.effective_delay(crosses(skeleton, link), skeleton.network_delay)


def hyperperiod(periods: Iterable[Fraction]) -> Fraction:
    """Least common multiple of positive rationals: ``lcm(numerators)/gcd(denominators)``.

    Parameters
    ----------
    periods : iterable of Fraction
        Positive periods (ints and Fractions alike).

    Returns
    -------
    Fraction
        The least positive rational that every period divides an integer
        number of times; 1 for no period.

    Examples
    --------
    >>> hyperperiod([Fraction(1), Fraction(2), Fraction(6)])
    Fraction(6, 1)
    >>> hyperperiod([Fraction(3, 2), Fraction(5, 4)])
    Fraction(15, 2)
    """
    num, den = 1, 0
    for p in periods:
        p = Fraction(p)
        num = math.lcm(num, p.numerator)
        den = math.gcd(den, p.denominator)
    return Fraction(num, den or 1)


def clock_hyperperiod(skeleton: Skeleton, tasks: Iterable[str]) -> tuple[Fraction | None, int]:
    """The hyperperiod of the clocks of ``tasks``, and how many times they tick over it.

    None and 0 when no task has a clock. A periodic regime of these tasks holds a
    whole number of periods of every clock: it cannot repeat before that many ticks.

    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 2},
    ...                                    "B": {"duration": 1, "period": 3},
    ...                                    "C": {"duration": 1}}})
    >>> clock_hyperperiod(sk, ["A", "B", "C"]), clock_hyperperiod(sk, ["C"])
    ((Fraction(6, 1), 5), (None, 0))
    """
    periods = {skeleton.clocks[c].period
               for c in {skeleton.tasks[t].clock for t in tasks} if c is not None}
    if not periods:
        return None, 0
    hyper = hyperperiod(periods)
    return hyper, sum(int(hyper / p) for p in periods)


@dataclass(frozen=True)
class ProcessorInfo:
    """One processor: its tasks in file order, their priorities and where those come from.

    Attributes
    ----------
    name : str
    tasks : tuple of str
    priorities : dict of str to int
        The priority each of its tasks runs at (larger is more urgent).
    priority_source : str
        ``"declared"`` (every task declares one) or ``"rate-monotonic"``.
    preemptive : bool
        Declared ``preemptive: false`` or not (§4d).
    replaced : dict of str to int
        The declared priorities that the rate-monotonic proposal replaced (the
        declaration is partial on this processor: all or none), task -> declared value;
        empty when every or no task declares one.
    """

    name: str
    tasks: tuple[str, ...]
    priorities: dict[str, int]
    priority_source: str
    preemptive: bool = True
    replaced: dict[str, int] = field(default_factory=dict)


@dataclass(frozen=True)
class Platform:
    """Where and how urgently each task runs, on what kind of processor.

    Attributes
    ----------
    processors : tuple of ProcessorInfo
        In the order of each processor's first task in the file.
    processor_of : dict of str to str
        Task -> processor name.
    priority : dict of str to int
        Task -> priority (larger is more urgent), in file order.
    """

    processors: tuple[ProcessorInfo, ...]
    processor_of: dict[str, str]
    priority: dict[str, int]

    @cached_property
    def by_name(self) -> dict[str, ProcessorInfo]:
        """Processor name -> its :class:`ProcessorInfo`."""
        return {p.name: p for p in self.processors}

    def preemptive(self, processor: str) -> bool:
        """Whether ``processor`` is preemptive (§4b; False where declared, §4d)."""
        return self.by_name[processor].preemptive

    def all_preemptive(self, tasks: Iterable[str]) -> bool:
        """Whether every processor that ``tasks`` run on is preemptive: the hypothesis of
        every preemption-only theorem (Lehoczky-Sha-Ding, Joseph-Pandya without blocking,
        the optimality of rate-monotonic priorities)."""
        by_name, where = self.by_name, self.processor_of
        return all(by_name[where[t]].preemptive for t in tasks)

    @property
    def replaced(self) -> list[ProcessorInfo]:
        """The processors whose partial declaration of priorities was replaced."""
        return [p for p in self.processors if p.replaced]


def group_tasks(groups: Groups) -> list[Sequence[str]]:
    """The task names of each group, whatever form ``groups`` has."""
    if isinstance(groups, Structure):
        return list(groups.groups)
    return [g.tasks if hasattr(g, "tasks") else g for g in groups]


def platform_of(skeleton: Skeleton, groups: Groups | None = None) -> Platform:
    """The processors, their kinds and the priorities of ``skeleton`` (§4b, §4d).

    Parameters
    ----------
    skeleton : Skeleton
    groups : Structure or sequence of groups, optional
        The groups of spec §4 (``report.structure`` or ``report.groups`` of
        :func:`~tegraph.analysis.analyze.analyze_skeleton`), in the order of their
        first task in the file; ``Structure.of(skeleton)`` when not given.

    Returns
    -------
    Platform

    Raises
    ------
    InputError
        ``groups`` do not hold every task of ``skeleton`` exactly once.

    Examples
    --------
    The example of §4b: A and B with period 10, C with period 5, D without a
    clock, in this file order, on one processor:

    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "A": {"duration": 1, "period": 10}, "B": {"duration": 1, "period": 10},
    ...     "C": {"duration": 1, "period": 5}, "D": {"duration": 1}}})
    >>> platform_of(sk).priority
    {'A': 3, 'B': 2, 'C': 4, 'D': 1}

    A partial declaration is replaced, and says so:

    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 10, "priority": 1},
    ...                                    "B": {"duration": 1, "period": 5}}})
    >>> p = platform_of(sk).processors[0]
    >>> p.priorities, p.priority_source, p.replaced, p.preemptive
    ({'A': 1, 'B': 2}, 'rate-monotonic', {'A': 1}, True)
    """
    structure = Structure.of(skeleton) if groups is None else groups
    tasks_of = group_tasks(structure)
    check_groups(skeleton, tasks_of)
    processors = processor_of(skeleton)
    on: dict[str, list[str]] = {}
    for name, proc in processors.items():
        on.setdefault(proc, []).append(name)
    proposal: dict[str, int] | None = None
    priority: dict[str, int] = {}
    infos = []
    for proc, tasks in on.items():
        declared = {t: p for t in tasks if (p := skeleton.tasks[t].priority) is not None}
        replaced: dict[str, int] = {}
        if len(declared) == len(tasks):
            chosen = {t: int(p) for t, p in declared.items()}
            source = "declared"
        else:
            if proposal is None:  # one proposal for all the processors that need it
                proposal = rate_monotonic(skeleton, structure)
            chosen = {t: proposal[t] for t in tasks}
            source = "rate-monotonic"
            replaced = {t: int(p) for t, p in declared.items()}
        priority.update(chosen)
        declared_kind = skeleton.processors.get(proc)
        infos.append(ProcessorInfo(proc, tuple(tasks), chosen, source,
                                   True if declared_kind is None else declared_kind.preemptive,
                                   replaced))
    return Platform(tuple(infos), processors, {t: priority[t] for t in skeleton.tasks})


def processor_per_task(skeleton: Skeleton) -> Platform:
    """Every task alone on a processor named after it: the schedule is then §3's daters
    (§4b: ``f_T(k) = x_T.compute(k) + duration(T)``, every job starts at its release).

    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1}, "B": {"duration": 1}}})
    >>> processor_per_task(sk).processor_of
    {'A': 'A', 'B': 'B'}
    """
    infos = tuple(ProcessorInfo(t, (t,), {t: 1}, "alone") for t in skeleton.tasks)
    return Platform(infos, {t: t for t in skeleton.tasks}, {t: 1 for t in skeleton.tasks})


def rate_monotonic(skeleton: Skeleton, groups: Groups | None = None) -> dict[str, int]:
    """The rate-monotonic proposal of §4b for every task, processor by processor.

    Parameters
    ----------
    skeleton : Skeleton
    groups : Structure or sequence of groups, optional
        As for :func:`platform_of`.

    Returns
    -------
    dict of str to int
        Task -> proposed priority (larger is more urgent), in file order.

    Examples
    --------
    Two automata on one processor share the number above the rest:

    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "SLOW": {"duration": 1, "period": 6}, "FAST": {"duration": 1, "period": 1},
    ...     "RTA": {"duration": 0}, "arm.automaton": {"duration": 0}}})
    >>> rate_monotonic(sk)
    {'SLOW': 3, 'FAST': 4, 'RTA': 5, 'arm.automaton': 5}
    """
    structure = Structure.of(skeleton) if groups is None else groups
    tasks_of = group_tasks(structure)
    periods = (list(structure.periods) if isinstance(structure, Structure)
               else [design_period(skeleton, tasks) for tasks in tasks_of])
    index = {t: i for i, t in enumerate(skeleton.tasks)}
    # Each group's rank key, most urgent first: clocked before clockless, shorter
    # design period, then its first task in the file.
    keys = [(period is None, period if period is not None else 0, min(index[t] for t in tasks))
            for tasks, period in zip(tasks_of, periods)]
    group_of = {t: g for g, tasks in enumerate(tasks_of) for t in tasks}
    on: dict[str, list[str]] = {}
    for name, task in skeleton.tasks.items():
        on.setdefault(task.runs_on, []).append(name)
    out: dict[str, int] = {}
    for tasks in on.values():
        here = sorted(dict.fromkeys(group_of[t] for t in tasks), key=lambda g: keys[g])
        number = {g: len(here) - rank for rank, g in enumerate(here)}
        mine = {t: number[group_of[t]] for t in tasks}
        top = max(mine.values(), default=0)
        for t in mine:
            if is_automaton(t):
                mine[t] = top + 1
        out.update(mine)
    return {t: out[t] for t in skeleton.tasks}


def check_groups(skeleton: Skeleton, groups: Groups) -> None:
    """Refuse groups that do not hold every task of ``skeleton`` exactly once.

    Raises
    ------
    InputError
        Naming ``groups`` and the first task missing, repeated or unknown.
    """
    seen: set[str] = set()
    for tasks in group_tasks(groups):
        for t in tasks:
            if t in seen or t not in skeleton.tasks:
                why = "twice" if t in seen else "but the skeleton has no such task"
                raise InputError(f"task {t!r} is in the groups {why}; expected the groups "
                                 "of analyze_skeleton(skeleton)", "groups")
            seen.add(t)
    missing = [t for t in skeleton.tasks if t not in seen]
    if missing:
        raise InputError(f"task {missing[0]!r} is in no group; expected the groups of "
                         "analyze_skeleton(skeleton)", "groups")


def processor_parts(groups: Sequence[Sequence[str]], processor_of: Mapping[str, str]
                    ) -> list[int]:
    """The part of each group on the processors (§4b): groups joined, transitively, by
    sharing a processor; numbered in the order of their first group.

    A part's schedule depends on nothing outside it (no link crosses groups, no
    processor crosses parts), so each is decided alone.

    Parameters
    ----------
    groups : sequence of sequences of str
        The tasks of each group (spec §4).
    processor_of : mapping of str to str
        Each task's processor.

    Examples
    --------
    >>> processor_parts([("A",), ("B", "C"), ("D",)],
    ...                 {"A": "cpu0", "B": "cpu1", "C": "cpu2", "D": "cpu2"})
    [0, 1, 1]
    """
    index: dict[str, int] = {}
    rows: list[int] = []
    cols: list[int] = []
    for g, tasks in enumerate(groups):
        for t in tasks:
            rows.append(g)
            cols.append(len(groups) + index.setdefault(processor_of[t], len(index)))
    n = len(groups) + len(index)
    graph = sp.csr_array((np.ones(len(rows), dtype=np.int8), (rows, cols)), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    first: dict[int, int] = {}
    return [first.setdefault(int(label[g]), len(first)) for g in range(len(groups))]
