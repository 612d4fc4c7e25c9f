"""The groups some tasks form once a candidate's edits are made (spec §4 ``groups``).

The advisor (:mod:`.advice`) re-forms the groups a candidate touches, and only
those, to read Rules 2 and 3 on them afterwards: tasks joined by a shared
clock, a synchronizing link or a thread. What joins each group as it is, is
kept once per group; a candidate changes only its edited links and the clocks
of its edited tasks. Small groups are re-formed by a union-find in Python, a
large one by scipy's connected components over arrays kept per group (a
Python loop over a group of 10,000 tasks would be paid once per candidate, since its
Rule 3 finding re-forms the group for each).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from fractions import Fraction

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from ...model.skeleton import Link, Skeleton
from .freeing import Edits

__all__ = ["ARRAYS_FROM", "Regrouping"]

ARRAYS_FROM = 500
"""A single group of this many tasks and more is re-formed by scipy's connected
components (a fixed set-up cost a call), a smaller one by a union-find (a cost per
task): the two cross near this size."""

Part = tuple[list[str], int, Fraction | None]
"""A re-formed group: its tasks in file order, how many clocks, its design period."""


class Regrouping:
    """The groups of one skeleton, re-formed after edits.

    Parameters
    ----------
    skeleton : Skeleton
    groups : sequence of tuple of str
        Its groups, tasks in file order (``Structure.groups``).
    links_from : sequence of list of Link
        The links whose writer is in each group.
    threads_of : mapping of int to list of tuple of str
        The threads of each group.
    order : mapping of str to int
        Each task's place in the file.
    fresh : Fraction
        The period of a clock added by the edits (no other clock has it).
    """

    def __init__(self, skeleton: Skeleton, groups: Sequence[tuple[str, ...]],
                 links_from: Sequence[list[Link]], threads_of: Mapping[int, list[tuple[str, ...]]],
                 order: Mapping[str, int], fresh: Fraction) -> None:
        self.sk, self.groups, self.links_from = skeleton, groups, links_from
        self.threads_of, self.order, self.fresh = threads_of, order, fresh
        # The clocks' periods, slowest last, and each clock's rank among them: the
        # fastest of many clocks is the least of their ranks (ints, not Fractions).
        self.by_rank = sorted({c.period for c in skeleton.clocks.values()})
        rank_of = {period: i for i, period in enumerate(self.by_rank)}
        self.clock_rank = {c: rank_of[k.period] for c, k in skeleton.clocks.items()}
        self._joins: dict[int, tuple[list[tuple[str, str, int]], list[tuple[str, list[str]]],
                                     list[tuple[str, str]]]] = {}
        self._arrays: dict[int, _GroupArrays] = {}
        self._task_clocks: dict[int, dict[str, str | None]] = {}

    def after(self, groups: list[int], edits: Edits) -> tuple[dict[str, Part], dict[str, str]]:
        """The groups that the tasks of ``groups`` form once ``edits`` are made.

        Returns ``{root: (tasks in file order, how many clocks, design period)}``
        (by their first task in the file) and the root of each of those tasks.
        """
        if len(groups) == 1 and len(self.groups[groups[0]]) >= ARRAYS_FROM:
            return self._by_arrays(groups[0], edits)
        tasks = [t for g in groups for t in self.groups[g]]
        if len(groups) > 1:  # each group is in file order already, not their union
            tasks.sort(key=self.order.__getitem__)
        clock_of, root_of = self._joined_after(tasks, groups, edits)
        return self._counted(tasks, root_of, clock_of), root_of

    # ------------------------------------------------------------ by a union-find
    def _joined_after(self, tasks: list[str], groups: list[int], edits: Edits
                      ) -> tuple[dict[str, str | None], dict[str, str]]:
        """Each task's clock once ``edits`` are made, and the root of its group then.

        A union-find over the tasks of ``groups``, whose joins are those of the
        groups as they are (cached per group) but for what the edits touch: the
        edited links, and the clocks of the edited tasks.
        """
        parent = dict(zip(tasks, tasks))
        edited = edits.by_id()  # the last edit of each link
        changed = edits.drop | edits.add
        # A task whose clock is dropped has one (and one given a clock may have had one).
        moved = {self.sk.tasks[t].clock for t in changed} - {None}
        # Each task's clock as it is, copied from each group's (kept once per group).
        clock_of: dict[str, str | None] = {}
        for g in groups:
            clock_of.update(self._clocks_of_tasks(g))
        for t in edits.drop:
            clock_of[t] = None
        for t in edits.add:
            clock_of[t] = f"{t}\0new"  # a clock of its own: it joins nothing
        pairs: list[tuple[str, str]] = []
        for g in groups:
            links, clocks, threads = self._joins_of_group(g)
            # The synchronizing links, unless edited.
            pairs += [(w, r) for w, r, key in links if key not in edited]
            for clock, users in clocks:
                if clock in moved:
                    users = [t for t in users if t not in changed]
                pairs += [(users[0], t) for t in users[1:]]
            pairs += threads
        pairs += [(link.writer[0], link.reader[0]) for link, p in edits.protocol
                  if p.synchronizing and edited[id(link)] is p]
        # A union-find, its finds written out (halving the path): a call per find
        # cost as much as the rest of the loop.
        for a, b in pairs:
            while (up := parent[a]) != a:
                parent[a] = parent[up]
                a = parent[a]
            while (up := parent[b]) != b:
                parent[b] = parent[up]
                b = parent[b]
            if a != b:
                parent[a] = b
        root_of = {}
        for t in tasks:
            a = t
            while (up := parent[a]) != a:
                parent[a] = parent[up]
                a = parent[a]
            root_of[t] = a
        return clock_of, root_of

    def _clocks_of_tasks(self, g: int) -> dict[str, str | None]:
        """Each task of group ``g`` and its clock, as they are (cached)."""
        known = self._task_clocks.get(g)
        if known is None:
            tasks = self.sk.tasks
            known = self._task_clocks[g] = {t: tasks[t].clock for t in self.groups[g]}
        return known

    def _joins_of_group(self, g: int) -> tuple[list[tuple[str, str, int]],
                                                list[tuple[str, list[str]]],
                                                list[tuple[str, str]]]:
        """What joins the tasks of group ``g`` as it is (cached): its synchronizing
        links (writer, reader, the link's ``id``), the users of each of its clocks (in
        file order), its threads' pairs."""
        known = self._joins.get(g)
        if known is None:
            links = [(link.writer[0], link.reader[0], id(link)) for link in self.links_from[g]
                     if link.protocol.synchronizing]
            users: dict[str, list[str]] = {}
            for t in self.groups[g]:
                clock = self.sk.tasks[t].clock
                if clock:
                    users.setdefault(clock, []).append(t)
            threads = [(thread[0], t) for thread in self.threads_of.get(g, ())
                       for t in thread[1:]]
            known = self._joins[g] = (links, list(users.items()), threads)
        return known

    def _counted(self, tasks: list[str], root_of: dict[str, str],
                 clock_of: dict[str, str | None]) -> dict[str, Part]:
        """Each re-formed group by its root: its tasks in file order, how many clocks,
        and its design period (the fastest of its clocks, a new clock's included).

        ``tasks`` are in file order. The fastest clock is found by its rank among the
        periods (:attr:`clock_rank`), not by comparing Fractions.
        """
        part: dict[str, tuple[list[str], set[str]]] = {}
        for t in tasks:
            entry = part.get(root_of[t])
            if entry is None:
                entry = part[root_of[t]] = ([], set())
            entry[0].append(t)
            if clock := clock_of[t]:
                entry[1].add(clock)
        rank, fresh = self.clock_rank, len(self.by_rank)
        counted: dict[str, Part] = {}
        for root, (members, clocks) in part.items():
            fastest = min((rank.get(c, fresh) for c in clocks), default=None)
            counted[root] = (members, len(clocks), self._period(fastest))
        return counted

    def _period(self, rank: int | None) -> Fraction | None:
        """The period of a clock's rank (the new clock's: one past the last)."""
        if rank is None:
            return None
        return self.fresh if rank == len(self.by_rank) else self.by_rank[rank]

    # ------------------------------------------------------------ by arrays
    def _by_arrays(self, g: int, edits: Edits) -> tuple[dict[str, Part], dict[str, str]]:
        """:meth:`after` for the one group ``g``, by scipy's connected components over
        a graph of its tasks and clocks (a task joins the node of its clock)."""
        a = self._arrays.get(g)
        if a is None:
            a = self._arrays[g] = _GroupArrays(self, g)
        n = len(a.names)
        keep = np.ones(len(a.links), dtype=bool)
        rows, cols = [], []
        edited = {id(link): p for link, p in edits.protocol}
        for link, p in edits.protocol:
            at = a.link_at.get(id(link))
            if at is not None:
                keep[at] = False  # re-added below if it still synchronizes
            if p.synchronizing and edited[id(link)] is p:
                rows.append(a.index[link.writer[0]])
                cols.append(a.index[link.reader[0]])
        clock = a.clock.copy()  # each task's clock node (-1: none)
        for t in edits.drop:
            clock[a.index[t]] = -1
        added = sorted(a.index[t] for t in edits.add)
        for k, i in enumerate(added):  # a clock of its own, on a node of its own
            clock[i] = a.n_clocks + k
        clocked = np.flatnonzero(clock >= 0)
        src = np.concatenate([a.writer[keep], np.asarray(rows, dtype=np.int64),
                              a.thread_a, clocked])
        dst = np.concatenate([a.reader[keep], np.asarray(cols, dtype=np.int64),
                              a.thread_b, n + clock[clocked]])
        size = n + a.n_clocks + len(added)
        graph = sp.csr_array((np.ones(len(src), dtype=np.int8), (src, dst)), shape=(size, size))
        label = connected_components(graph, directed=False)[1][:n]
        # Number the parts by their first task (the names are in file order).
        _, first = np.unique(label, return_index=True)
        first.sort()
        number = np.empty(label.max() + 1, dtype=np.int64)
        number[label[first]] = np.arange(len(first))
        part = number[label]
        order = np.argsort(part, kind="stable")
        ends = np.cumsum(np.bincount(part, minlength=len(first))).tolist()
        # Distinct clocks and the fastest rank of each part.
        rank = np.concatenate([a.rank, np.full(len(added), len(self.by_rank))])
        with_clock = part[clocked]
        pairs = np.unique(with_clock * (size + 1) + clock[clocked])
        n_clocks = np.bincount(pairs // (size + 1), minlength=len(first)).tolist()
        fastest = np.full(len(first), len(self.by_rank) + 1, dtype=np.int64)
        np.minimum.at(fastest, with_clock, rank[clock[clocked]])
        names = a.names
        roots = [names[i] for i in first.tolist()]
        counted: dict[str, Part] = {}
        start = 0
        for k, (end, root) in enumerate(zip(ends, roots)):
            members = [names[i] for i in order[start:end].tolist()]
            best = int(fastest[k])
            counted[root] = (members, n_clocks[k],
                             None if best > len(self.by_rank) else self._period(best))
            start = end
        root_of = dict(zip(names, (roots[i] for i in part.tolist())))
        return counted, root_of


class _GroupArrays:
    """What joins the tasks of one group, as arrays over its tasks (file order) and
    its clocks: the synchronizing links, the threads' pairs, each task's clock."""

    def __init__(self, owner: Regrouping, g: int) -> None:
        sk = owner.sk
        self.names = list(owner.groups[g])
        self.index = {t: i for i, t in enumerate(self.names)}
        self.links = [link for link in owner.links_from[g] if link.protocol.synchronizing]
        self.link_at = {id(link): i for i, link in enumerate(self.links)}
        self.writer = np.array([self.index[x.writer[0]] for x in self.links], dtype=np.int64)
        self.reader = np.array([self.index[x.reader[0]] for x in self.links], dtype=np.int64)
        pairs = [(self.index[th[0]], self.index[t]) for th in owner.threads_of.get(g, ())
                 for t in th[1:]]
        self.thread_a = np.array([p[0] for p in pairs], dtype=np.int64)
        self.thread_b = np.array([p[1] for p in pairs], dtype=np.int64)
        clocks: dict[str, int] = {}
        node = [clocks.setdefault(c, len(clocks)) if (c := sk.tasks[t].clock) else -1
                for t in self.names]
        self.clock = np.array(node, dtype=np.int64)
        self.n_clocks = len(clocks)
        ranks = [owner.clock_rank[c] for c in clocks]
        self.rank = np.array(ranks, dtype=np.int64)
