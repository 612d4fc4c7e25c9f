"""Exact pruning of the design space: protocol assignments that deadlock whatever the port
order (rules A and B), and processors loaded beyond their time (rule C).

``explore`` judges a variant without analyzing it when a theorem settles its
verdict. Rules A and B, proven here and cross-checked against
:func:`tegraph.analysis.reorder.reorder_ports` by the tests, settle it without any
analysis; rule C settles a live and consistent variant as not schedulable on its
processors (spec §4b) without running the schedule:

**Rule A (time does not matter).** Whether a skeleton is live, and whether
some port order makes it live, depends only on its token-free places and
merged events, never on durations or periods (Commoner's theorem [1]_ on the
0-token graph; the precedence graph of :mod:`tegraph.analysis.reorder` holds
no time). So a protocol assignment that deadlocks for every port order does so
for every choice of clock periods: its ``n_clock_variants`` variants are judged
at once, and the repair (the port orders) found for a live-able assignment is
computed once for all its periods.

**Rule B (synchronization only adds obligations).** In the precedence graph,
ASYN/ASYN adds nothing, ASYN/SYN adds the edge ``write -> read``, SYN/ASYN the
edge ``read -> write``, and SYN/SYN merges the two events. Adding an edge, or
merging two nodes, maps every circuit to a closed walk, which contains a
circuit. Hence, in the order ASYN/ASYN < ASYN/SYN, SYN/ASYN < SYN/SYN (and
ASYN/SYN < SYN/SYN, SYN/ASYN < SYN/SYN, since a merge also closes the walk an
edge would), "deadlocks for every port order" is upward closed: when the
links chosen so far, with every other chosen link ASYN/ASYN, already close a
circuit of obligations, every completion does. The exhaustive enumeration
walks the links in order and drops such a subtree in one check.

**The check itself** runs on a graph of a few nodes. Let ``G`` be the
precedence graph of the skeleton with every chosen link ASYN/ASYN. If ``G`` has a
circuit, every variant is dead. Otherwise call *terminals* the write and read
events of the chosen links, and join terminal ``a`` to terminal ``b`` when ``G``
has a path from ``a`` to ``b`` through no other terminal. A variant adds its
link edges between terminals and merges the SYN/SYN pairs; every circuit of
its precedence graph leaves ``G`` only at terminals, so it is a circuit of the
terminal graph (with the merges contracted), and conversely. Two more
circuits come from merges: a merged class holding two events of one task's
chain (a task reading two SYN/SYN inputs of one writer port sees one event
twice, reorder's self-loop), and a class whose members are joined by a path of
``G`` (the path closes on the merged event).

**Rule C (more work than time).** Let P be a processor, and for each group g
(spec §4) with a clock let ``p_g`` be its clocks' period (in a consistent
variant every clock of a group has one period: the ticks are events of the
group, and a rate-consistent group has one cycle time). If

    U_P = Σ over the tasks T on P whose group has a clock of duration(T) / p_g(T) > 1,

the variant is not schedulable on its processors. Proof: suppose it is. Then
(§4b) every group is live and has no unbounded place on processors, so (§4,
applied to the daters on processors) all the events of a group share one cycle
time, and a group with a clock runs at its clock's period ``p_g`` (the tick's
self-loop fires every ``p_g``); the schedule reached a periodic regime, of some
length L, in which each task T of such a group on P releases ``L/p_g`` jobs and
every job ends (no task is starved). So P gives those tasks
``Σ duration(T) L/p_g = U_P L`` of its time in each regime, which is at most L:
``U_P <= 1``, a contradiction. When the tasks *with a clock* alone already need
more than P (``Σ duration(T)/period(clock(T)) > 1``), a task with a clock
overruns: otherwise each activation k-1 of each such T ends by its tick k
(``end_T(k-1) <= x_tick(k)``), so by time t the processor has given them at
least ``Σ duration(T) floor((t - phase)/period)`` > t for t large enough,
more than the t units of time it had. Rule C says which of the two it proved.
``U_P = 1`` proves nothing (harmonic periods fill a processor exactly), and
tasks in groups without a clock are left out (they slow down to the time left).

What is **not** a proof, and is not used to prune: the response-time test of
:mod:`tegraph.design.schedulability` saying "not schedulable". It assumes the
critical instant (every unit released together) and one release per period of
each group; on processors a job is released when its reads are done, clocks
may have phases that never line up, and synchronization spreads a group's jobs
over its period. Example (``tests/tegraph/design/test_explore_processors.py``):
A, 3 every 6, and B, 4 every 9 with phase 3/2, on one processor: the test says
R_B = 10 > 9, the exact schedule is periodic with B's response at most 17/2.
Nor is its "schedulable" a proof of §4b (it does not model the blocking of a
read on a slower writer on another processor, nor a group whose tasks run at
different rates), so every variant that rule C does not settle runs the exact
schedule.

References
----------
.. [1] F. Commoner, A. W. Holt, S. Even, A. Pnueli, "Marked directed
   graphs", Journal of Computer and System Sciences 5(5), 511–523, 1971.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import replace
from fractions import Fraction

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import breadth_first_order

from maxplus.scalar import exact_text

from ...analysis.processors import processor_of
from ...analysis.reorder import PrecedenceGraph
from ...analysis.results import Report
from ...model.skeleton import Protocol, Skeleton
from .demand import processor_shares
from .space import DesignSpace

__all__ = ["DeadlockOracle", "overloaded", "protocol_ranges"]

DEAD_REASON = ("dead whatever the port order: its synchronizations close a circuit of "
               "obligations (pruned without analysis)")


class DeadlockOracle:
    """Decides, for a protocol assignment of the chosen links, whether no port order makes
    the skeleton live (Rule B's terminal graph; see the module docstring).

    Parameters
    ----------
    space : DesignSpace

    Examples
    --------
    Figure 7a of the ORCCAD paper: three tasks in a ring of links, no clock.
    ASYN/SYN on all three links closes the circuit; one ASYN/ASYN breaks it.

    >>> from tegraph.model.skeleton import Skeleton
    >>> from tegraph.design.explore.space import design_space
    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "MT1": {"duration": 1, "inputs": ["c"], "outputs": ["a"]},
    ...     "MT2": {"duration": 1, "inputs": ["a"], "outputs": ["b"]},
    ...     "MT3": {"duration": 1, "inputs": ["b"], "outputs": ["c"]}}, "links": [
    ...     {"from": "MT1:a", "to": "MT2:a", "protocol": "ASYN/SYN"},
    ...     {"from": "MT2:b", "to": "MT3:b", "protocol": "ASYN/SYN"},
    ...     {"from": "MT3:c", "to": "MT1:c", "protocol": "ASYN/SYN"}]})
    >>> oracle = DeadlockOracle(design_space(sk, all_links=True))
    >>> S, A = Protocol.ASYN_SYN, Protocol.ASYN_ASYN
    >>> oracle.dead((S, S, S)), oracle.dead((S, S, A))
    (True, False)
    """

    def __init__(self, space: DesignSpace) -> None:
        self.n_links = len(space.links)
        links = list(space.skeleton.links)
        for choice in space.links:
            links[choice.index] = replace(links[choice.index], protocol=Protocol.ASYN_ASYN)
        graph = PrecedenceGraph(replace(space.skeleton, links=links))
        self.base_dead = graph.topological_order() is None
        ends = [(graph.write[links[c.index].writer], graph.read[links[c.index].reader])
                for c in space.links]
        nodes = sorted({v for pair in ends for v in pair})
        local = {v: i for i, v in enumerate(nodes)}
        self._writer = [local[w] for w, _ in ends]
        self._reader = [local[r] for _, r in ends]
        # The tasks whose chain holds each terminal (a merged SYN/SYN event holds two).
        holders: dict[int, set[str]] = {v: set() for v in nodes}
        for name, task in space.skeleton.tasks.items():
            for port in task.inputs:
                v = graph.read[name, port]
                if v in holders:
                    holders[v].add(name)
            for port in task.outputs:
                v = graph.write[name, port]
                if v in holders:
                    holders[v].add(name)
        self._tasks = [sorted(holders[v]) for v in nodes]
        self._direct = [] if self.base_dead else _direct_paths(graph, nodes)

    def dead(self, protocols: Sequence[Protocol]) -> bool:
        """True when the chosen links with these protocols (the links not given:
        ASYN/ASYN) close a circuit of obligations: dead for every port order."""
        if self.base_dead:
            return True
        n = len(self._tasks)
        parent = list(range(n))

        def find(x: int) -> int:
            while parent[x] != x:
                parent[x] = parent[parent[x]]
                x = parent[x]
            return x

        edges: list[tuple[int, int]] = []
        for i, protocol in enumerate(protocols):
            w, r = self._writer[i], self._reader[i]
            if protocol is Protocol.SYN_SYN:
                parent[find(w)] = find(r)
            elif protocol is Protocol.ASYN_SYN:
                edges.append((w, r))
            elif protocol is Protocol.SYN_ASYN:
                edges.append((r, w))
        cls = [find(x) for x in range(n)]
        holder: dict[tuple[int, str], int] = {}
        for x in range(n):
            for task in self._tasks[x]:
                if holder.setdefault((cls[x], task), x) != x:
                    return True  # one event twice in a task's chain
        succ: dict[int, set[int]] = {}
        for a, b in [*edges, *((x, y) for x in range(n) for y in self._direct[x])]:
            ca, cb = cls[a], cls[b]
            if ca == cb:
                return True
            succ.setdefault(ca, set()).add(cb)
        return _has_circuit(succ)


def _direct_paths(graph: PrecedenceGraph, nodes: list[int]) -> list[list[int]]:
    """For each terminal, the terminals reached by a path of ``graph`` through no other
    terminal (one breadth-first search per terminal, in scipy)."""
    n, t = len(graph.names), len(nodes)
    terminal = np.zeros(n + t, dtype=bool)
    terminal[nodes] = True
    src, dst = [], []
    for a, outs in enumerate(graph.succ):
        for b in outs:
            # A terminal keeps no out-edge: searches stop there. Its out-edges go to a
            # copy of it (node n + k), the start of the k-th search.
            if terminal[a]:
                src.append(n + nodes.index(a))
            else:
                src.append(a)
            dst.append(b)
    adjacency = sp.csr_matrix((np.ones(len(src), dtype=np.int8), (src, dst)), shape=(n + t,) * 2)
    local = {v: i for i, v in enumerate(nodes)}
    out = []
    for k in range(t):
        reached = breadth_first_order(adjacency, n + k, directed=True, return_predecessors=False)
        out.append(sorted(local[int(v)] for v in reached[terminal[reached]]))
    return out


def _has_circuit(succ: dict[int, set[int]]) -> bool:
    """Kahn's algorithm on a small graph given as successor sets."""
    indegree: dict[int, int] = {}
    for a, outs in succ.items():
        indegree.setdefault(a, 0)
        for b in outs:
            indegree[b] = indegree.get(b, 0) + 1
    ready = [v for v, d in indegree.items() if d == 0]
    removed = 0
    while ready:
        v = ready.pop()
        removed += 1
        for b in succ.get(v, ()):
            indegree[b] -= 1
            if indegree[b] == 0:
                ready.append(b)
    return removed < len(indegree)


def protocol_ranges(space: DesignSpace, oracle: DeadlockOracle
                    ) -> Iterator[tuple[int, int, bool]]:
    """Protocol indices in increasing order as ``(first, count, dead)`` runs (Rule B).

    A dead prefix (the links chosen so far as given, the others ASYN/ASYN) yields
    the whole run of its completions with one check.

    >>> from tegraph.model.skeleton import Skeleton
    >>> from tegraph.design.explore.space import design_space
    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "A": {"duration": 1, "inputs": ["y"], "outputs": ["x", "z"]},
    ...     "B": {"duration": 1, "inputs": ["x", "z"], "outputs": ["y"]}}, "links": [
    ...     {"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"},
    ...     {"from": "A:z", "to": "B:z", "protocol": "ASYN/SYN"},
    ...     {"from": "B:y", "to": "A:y", "protocol": "ASYN/SYN"}]})
    >>> space = design_space(sk, {"A:x -> B:x": ["SYN/SYN", "ASYN/ASYN"],
    ...                           "A:z -> B:z": ["ASYN/SYN", "ASYN/ASYN"]})
    >>> list(protocol_ranges(space, DeadlockOracle(space)))
    [(0, 3, True), (3, 1, False)]
    """
    choices = [c.protocols for c in space.links]
    spans = [1] * (len(choices) + 1)
    for k in range(len(choices) - 1, -1, -1):
        spans[k] = spans[k + 1] * len(choices[k])
    rest = Protocol.ASYN_ASYN

    def walk(k: int, prefix: tuple[Protocol, ...], first: int) -> Iterator[tuple[int, int, bool]]:
        if oracle.dead(prefix + (rest,) * (len(choices) - k)):
            yield first, spans[k], True
            return
        if k == len(choices):
            yield first, 1, False
            return
        for d, protocol in enumerate(choices[k]):
            yield from walk(k + 1, (*prefix, protocol), first + d * spans[k + 1])

    pending: tuple[int, int, bool] | None = None
    for run in walk(0, (), 0):
        # Consecutive runs of one verdict are merged: fewer, longer runs.
        if pending is not None and pending[2] == run[2] and pending[0] + pending[1] == run[0]:
            pending = (pending[0], pending[1] + run[1], run[2])
            continue
        if pending is not None:
            yield pending
        pending = run
    if pending is not None:
        yield pending


def overloaded(skeleton: Skeleton, report: Report) -> str | None:
    """Rule C (module docstring): why the variant is proven not schedulable on its
    processors by their load, or None when the load proves nothing.

    Parameters
    ----------
    skeleton : Skeleton
    report : Report
        ``analyze_skeleton(skeleton)``, live and consistent (its groups are read).

    Returns
    -------
    str or None
        The reason, naming the processor, its load and the tasks counted.

    Examples
    --------
    Two tasks of 6 ms every 10 ms on one processor (6/5 of it), then 5 every 10:

    >>> from tegraph.analysis.analyze import analyze_skeleton
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 6, "period": 10},
    ...                                    "B": {"duration": 6, "period": 10}}})
    >>> print(overloaded(sk, analyze_skeleton(sk)))
    overrun on processors: default runs tasks with a clock needing 6/5 of its time (A 6 every \
10, B 6 every 10), more than all of it, so one of them overruns (proven by the load, rule C)
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 5, "period": 10},
    ...                                    "B": {"duration": 5, "period": 10}}})
    >>> overloaded(sk, analyze_skeleton(sk)) is None
    True
    """
    # processor -> (task, duration, period of its group's clock, has a clock of its own)
    grouped: dict[str, list[tuple[str, Fraction, Fraction, bool]]] = {}
    runs_on = processor_of(skeleton)
    for g in report.groups:
        periods = {skeleton.clocks[c].period for c in g.clocks}
        if len(periods) != 1:  # no clock (or, not in a consistent variant, clocks that differ)
            continue
        (period,) = periods
        for name in g.tasks:
            task = skeleton.tasks[name]
            grouped.setdefault(runs_on[name], []).append(
                (name, task.duration, period, task.clock is not None))
    for where, tasks in grouped.items():
        load = processor_shares(((where, d, p) for _, d, p, _ in tasks), every=[where])[where]
        if load <= 1:
            continue
        own = [t for t in tasks if t[3]]
        clocked = processor_shares(((where, d, p) for _, d, p, _ in own), every=[where])[where]
        counted = own if clocked > 1 else tasks
        shown = ", ".join(f"{name} {exact_text(d)} every {exact_text(p)}"
                          for name, d, p, _ in counted[:6] if d)
        shown += ", ..." if len(counted) > 6 else ""
        if clocked > 1:
            return (f"overrun on processors: {where} runs tasks with a clock needing "
                    f"{exact_text(clocked)} of its time ({shown}), more than all of it, so "
                    "one of them overruns (proven by the load, rule C)")
        return (f"not schedulable on processors: {where} runs groups with a clock needing "
                f"{exact_text(load)} of its time ({shown}), more than all of it, so a task "
                "overruns or a place grows (proven by the load, rule C)")
    return None
