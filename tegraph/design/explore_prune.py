"""Exact pruning of the design space: protocol assignments that deadlock whatever the port order.

``explore`` judges a variant without analyzing it when a theorem settles its
verdict. Two rules, both proven here and cross-checked against
:func:`tegraph.analysis.reorder.reorder_ports` by the tests:

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

References
----------
.. [1] F. Commoner, A. W. Holt, S. Even, A. Pnueli, "Marked directed
   graphs", Journal of Computer and System Sciences 5(5), 511–523, 1971.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import replace

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import breadth_first_order

from ..analysis.reorder import PrecedenceGraph
from ..model.skeleton import Protocol
from .explore_space import DesignSpace

__all__ = ["DeadlockOracle", "protocol_ranges"]

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
    >>> from tegraph.design.explore_space import design_space
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
    >>> from tegraph.design.explore_space import design_space
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
