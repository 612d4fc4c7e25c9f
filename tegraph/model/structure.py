"""The structure of a skeleton: its groups (spec §4), their clocks and periods, its links by port.

A *group* is a weakly connected part of the timed event graph of a skeleton:
tasks joined by a synchronizing link (any protocol but ASYN/ASYN), a thread or
a shared clock. Spec §2 builds no place between two groups, so the parts of
the graph are exactly the connected components of the small undirected graph
on the tasks and clocks with those joins as edges; :meth:`Structure.of` finds
them once, vectorized (scipy), without building the timed event graph.

Groups are listed in the order of their first task in the file, tasks in file
order (spec §4 ``groups``); every figure of a group, every design rule and
every margin is numbered this way, so they all read one :class:`Structure`,
computed once per analysis and passed down.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from .skeleton import Link, Skeleton

if TYPE_CHECKING:
    from .teg import TimedEventGraph

__all__ = ["Structure", "design_period", "label_events"]

Port = tuple[str, str]


def design_period(skeleton: Skeleton, tasks: Sequence[str]) -> Fraction | None:
    """The design period of ``tasks``: their fastest clock's period (None without a clock).

    The design period of a group (ORCCAD §6, Rules 2 and 4); Rule 4 also
    applies it to the tasks of a group on one processor.

    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": "5/2"},
    ...                                    "B": {"duration": 1}}})
    >>> design_period(sk, ["A", "B"]), design_period(sk, ["B"])
    (Fraction(5, 2), None)
    """
    periods = [skeleton.clocks[c].period for t in tasks if (c := skeleton.tasks[t].clock)]
    return min(periods) if periods else None


@dataclass(frozen=True)
class Structure:
    """The groups of one skeleton, their clocks and design periods, its links by port.

    Attributes
    ----------
    groups : tuple of tuple of str
        The tasks of each group; groups by their first task in the file, tasks
        in file order (spec §4).
    group_of : mapping
        Task -> index of its group in ``groups``.
    clocks : tuple of tuple of str
        The clocks of each group, in the order of their first task in the file.
    group_of_clock : mapping
        Clock -> index of its group; a clock that activates no task is in none.
    periods : tuple of Fraction or None
        The design period of each group (:func:`design_period`).
    by_reader, by_writer : mapping
        ``(task, port)`` -> the links that port reads (writes), in file order.

    Examples
    --------
    A and B joined by an ASYN/SYN link, C alone on its clock, ``idle`` a
    clock that activates nothing:

    >>> sk = Skeleton.from_dict({"clocks": {"idle": {"period": 1}}, "tasks": {
    ...     "A": {"duration": 1, "period": 4, "outputs": ["x"]},
    ...     "B": {"duration": 1, "inputs": ["x"]}, "C": {"duration": 1, "period": 3}},
    ...   "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]})
    >>> s = Structure.of(sk)
    >>> s.groups, s.clocks, s.periods
    ((('A', 'B'), ('C',)), (('A.clock',), ('C.clock',)), (Fraction(4, 1), Fraction(3, 1)))
    >>> s.group_of["B"], "idle" in s.group_of_clock, [x.label for x in s.by_reader["B", "x"]]
    (0, False, ['A:x -> B:x (ASYN/SYN)'])
    """

    groups: tuple[tuple[str, ...], ...]
    group_of: Mapping[str, int]
    clocks: tuple[tuple[str, ...], ...]
    group_of_clock: Mapping[str, int]
    periods: tuple[Fraction | None, ...]
    by_reader: Mapping[Port, tuple[Link, ...]]
    by_writer: Mapping[Port, tuple[Link, ...]]

    @classmethod
    def of(cls, skeleton: Skeleton) -> Structure:
        """The structure of ``skeleton`` (assumed valid: every name it uses exists)."""
        groups = _groups(skeleton)
        group_of = {t: g for g, ts in enumerate(groups) for t in ts}
        # A clock is in the group of the tasks it activates (one group: they are joined).
        group_of_clock: dict[str, int] = {}
        clocks: list[list[str]] = [[] for _ in groups]
        for t, task in skeleton.tasks.items():
            if task.clock is not None and task.clock not in group_of_clock:
                group_of_clock[task.clock] = group_of[t]
                clocks[group_of[t]].append(task.clock)
        by_reader: dict[Port, list[Link]] = {}
        by_writer: dict[Port, list[Link]] = {}
        for link in skeleton.links:
            by_reader.setdefault(link.reader, []).append(link)
            by_writer.setdefault(link.writer, []).append(link)
        return cls(
            groups=tuple(tuple(g) for g in groups),
            group_of=group_of,
            clocks=tuple(tuple(c) for c in clocks),
            group_of_clock=group_of_clock,
            periods=tuple(design_period(skeleton, g) for g in groups),
            by_reader={p: tuple(x) for p, x in by_reader.items()},
            by_writer={p: tuple(x) for p, x in by_writer.items()})

    def group_of_event(self, teg: TimedEventGraph) -> np.ndarray:
        """The group of each event of ``build_teg(skeleton)``: its task's or its clock's.

        -1 for the tick of a clock that activates no task (it is in no group).

        >>> from tegraph.model.build import build_teg
        >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 2},
        ...                                    "B": {"duration": 1}}})
        >>> Structure.of(sk).group_of_event(build_teg(sk)).tolist()
        [0, 0, 0, 1]
        """
        return label_events(teg, self.group_of, self.group_of_clock)


def label_events(teg: TimedEventGraph, group_of: Mapping[str, int],
                 group_of_clock: Mapping[str, int]) -> np.ndarray:
    """The group of each event of ``teg``: its task's (``group_of``), or its clock's
    (``group_of_clock``; -1 for a clock in none).

    :meth:`Structure.group_of_event` for groups known otherwise (the design
    advice re-forms those of an edited skeleton without re-computing them).

    >>> from tegraph.model.build import build_teg
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 2},
    ...                                    "B": {"duration": 1}}})
    >>> g = build_teg(sk)  # events: A's clock tick, A.activate, A.compute, B.compute
    >>> label_events(g, {"A": 7, "B": 3}, {"A.clock": 7}).tolist()
    [7, 7, 7, 3]
    >>> label_events(g, {"A": 7, "B": 3}, {}).tolist()  # a clock in no group
    [-1, 7, 7, 3]
    """
    out = np.full(teg.n_transitions, -1, dtype=np.int64)
    for task, chain in teg.attrs["chains"].items():
        out[list(chain)] = group_of[task]
    for clock, tick in teg.attrs["clocks"].items():
        out[tick] = group_of_clock.get(clock, -1)
    return out


def _joins(skeleton: Skeleton, index: Mapping[str, int]) -> tuple[list[int], list[int]]:
    """The edges of the graph whose connected parts are the groups: task-clock for
    each clocked task (clocks numbered after the tasks), writer-reader for each
    synchronizing link, neighbours in each thread."""
    clock_index = {c: len(index) + i for i, c in enumerate(skeleton.clocks)}
    rows: list[int] = []
    cols: list[int] = []
    for t, task in skeleton.tasks.items():
        if task.clock is not None:
            rows.append(index[t])
            cols.append(clock_index[task.clock])
    for link in skeleton.links:
        if link.protocol.synchronizing:
            rows.append(index[link.writer[0]])
            cols.append(index[link.reader[0]])
    for thread in skeleton.threads:
        for a, b in zip(thread, thread[1:]):
            rows.append(index[a])
            cols.append(index[b])
    return rows, cols


def _groups(skeleton: Skeleton) -> list[list[str]]:
    """The tasks of each group (spec §4), groups and tasks in file order."""
    names = list(skeleton.tasks)
    index = {t: i for i, t in enumerate(names)}
    rows, cols = _joins(skeleton, index)
    n = len(names) + len(skeleton.clocks)
    graph = sp.csr_array((np.ones(len(rows), dtype=np.int8), (rows, cols)), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    # Renumber the components by their first task in the file (spec §4 order).
    number: dict[int, int] = {}
    groups: list[list[str]] = []
    for t in names:
        g = number.setdefault(int(label[index[t]]), len(number))
        if g == len(groups):
            groups.append([])
        groups[g].append(t)
    return groups
