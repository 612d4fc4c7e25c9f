"""Each task's processor and priority (``docs/skeleton.md`` v1.2 §4b, *Platform*).

Tasks without ``processor`` share the processor ``"default"``. On a processor
where every task declares ``priority``, those priorities are used; otherwise
every task of that processor gets the rate-monotonic proposal of §4b:

- take the groups (§4: whole groups, wherever their other tasks run) that
  have a task on the processor; a group's *design period* is the smallest
  period among its clocks;
- the shortest design period is the most urgent; equal design periods: the
  group whose first task comes earlier in the file is the more urgent;
  groups without a clock are the least urgent, in file order;
- numbers run from 1 (least urgent) upward, every task of a group gets its
  group's number, and the Robot-task automaton (a task named ``RTA`` or
  ``automaton``, or ending in ``.RTA`` or ``.automaton``, any case) gets one
  more than the largest number on its processor.

The groups are not recomputed here: they are a parameter, the ``groups`` of
the :class:`~tegraph.analysis.results.Report` that
:func:`~tegraph.analysis.analyze.analyze_skeleton` returns (one definition of
groups for every command).
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Protocol as _Protocol

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from ...errors import InputError
from ...model.skeleton import Skeleton
from ...model.structure import design_period

__all__ = ["DEFAULT_PROCESSOR", "Platform", "ProcessorInfo", "check_groups", "is_automaton",
           "platform_of", "processor_of", "processor_parts", "processor_per_task"]

DEFAULT_PROCESSOR = "default"
"""The processor of every task that declares none (§4b)."""

_AUTOMATON = re.compile(r"(?:^|\.)(?:rta|automaton)$", re.IGNORECASE)


class _Group(_Protocol):
    """What is read of a group: a ``GroupReport`` has it."""

    tasks: list[str]


def is_automaton(name: str) -> bool:
    """Whether ``name`` names the Robot-task automaton (§4b).

    Examples
    --------
    >>> is_automaton("RTA"), is_automaton("arm.Automaton"), is_automaton("PARTA")
    (True, True, False)
    """
    return bool(_AUTOMATON.search(name))


@dataclass(frozen=True)
class ProcessorInfo:
    """One processor: its tasks in file order, their priorities and where those come from."""

    name: str
    tasks: tuple[str, ...]
    priorities: dict[str, int]
    priority_source: str
    """``"declared"`` or ``"rate-monotonic"``."""


@dataclass(frozen=True)
class Platform:
    """Where and how urgently each task runs.

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


def platform_of(skeleton: Skeleton, groups: Sequence[_Group]) -> Platform:
    """The processors and priorities of ``skeleton`` (§4b).

    Parameters
    ----------
    skeleton : Skeleton
    groups : sequence of GroupReport
        The groups of :func:`~tegraph.analysis.analyze.analyze_skeleton`
        (``report.groups``), in the order of their first task in the file;
        only ``tasks`` is read.

    Returns
    -------
    Platform

    Examples
    --------
    The example of §4b: A and B with period 10, C with period 5, D without a
    clock, in this file order, on one processor:

    >>> from tegraph.analysis.analyze import analyze_skeleton
    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "A": {"duration": 1, "period": 10}, "B": {"duration": 1, "period": 10},
    ...     "C": {"duration": 1, "period": 5}, "D": {"duration": 1}}})
    >>> platform_of(sk, analyze_skeleton(sk).groups).priority
    {'A': 3, 'B': 2, 'C': 4, 'D': 1}
    """
    check_groups(skeleton, groups)
    processors = processor_of(skeleton)
    on: dict[str, list[str]] = {}
    for name, proc in processors.items():
        on.setdefault(proc, []).append(name)
    priority: dict[str, int] = {}
    infos = []
    keys = _group_keys(skeleton, groups)
    group_of = {t: g for g, group in enumerate(groups) for t in group.tasks}
    for proc, tasks in on.items():
        declared = [skeleton.tasks[t].priority for t in tasks]
        if all(p is not None for p in declared):
            chosen = {t: int(p) for t, p in zip(tasks, declared) if p is not None}  # all are
            source = "declared"
        else:
            chosen = _rate_monotonic(tasks, group_of, keys)
            source = "rate-monotonic"
        priority.update(chosen)
        infos.append(ProcessorInfo(proc, tuple(tasks), {t: chosen[t] for t in tasks}, source))
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


def check_groups(skeleton: Skeleton, groups: Sequence[_Group]) -> None:
    """Refuse groups that do not hold every task of ``skeleton`` exactly once.

    Raises
    ------
    InputError
        Naming ``groups`` and the first task missing, repeated or unknown.
    """
    seen: set[str] = set()
    for group in groups:
        for t in group.tasks:
            if t in seen or t not in skeleton.tasks:
                why = "twice" if t in seen else "but the skeleton has no such task"
                raise InputError(f"task {t!r} is in the groups {why}; expected the groups "
                                 "of analyze_skeleton(skeleton)", "groups")
            seen.add(t)
    missing = [t for t in skeleton.tasks if t not in seen]
    if missing:
        raise InputError(f"task {missing[0]!r} is in no group; expected the groups of "
                         "analyze_skeleton(skeleton)", "groups")


def _group_keys(skeleton: Skeleton, groups: Sequence[_Group]) -> list[tuple]:
    """Each group's rank key, most urgent first: clocked before clockless, shorter
    design period (:func:`~tegraph.model.structure.design_period`), then its first task
    in the file."""
    index = {t: i for i, t in enumerate(skeleton.tasks)}
    keys = []
    for group in groups:
        design = design_period(skeleton, group.tasks)
        first = min(index[t] for t in group.tasks)
        keys.append((design is None, design if design is not None else 0, first))
    return keys


def _rate_monotonic(tasks: list[str], group_of: dict[str, int],
                    keys: list[tuple]) -> dict[str, int]:
    """The §4b proposal for the ``tasks`` of one processor."""
    here = sorted(dict.fromkeys(group_of[t] for t in tasks), key=lambda g: keys[g])
    number = {g: len(here) - rank for rank, g in enumerate(here)}
    out = {t: number[group_of[t]] for t in tasks}
    top = max(out.values(), default=0)
    for t in out:
        if is_automaton(t):
            out[t] = top + 1
    return out


def processor_of(skeleton: Skeleton) -> dict[str, str]:
    """Each task's processor (§4b): the one it declares, else :data:`DEFAULT_PROCESSOR`.

    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "processor": "cpu1"},
    ...                                    "B": {"duration": 1}}})
    >>> processor_of(sk)
    {'A': 'cpu1', 'B': 'default'}
    """
    return {name: task.processor or DEFAULT_PROCESSOR for name, task in skeleton.tasks.items()}


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
