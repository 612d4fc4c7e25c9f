"""Howard's policy iteration on Python lists: the kernel for small graphs.

:func:`maxplus.policy_iteration.howard_arrays` makes some 170 numpy calls per
solve whatever the graph's size, each with a fixed cost; on a small graph (one
group of a skeleton) plain Python walks the arcs in less. Up to
:data:`SMALL_GRAPH_ARCS` arcs,
:func:`maxplus.cycle_ratio.max_cycle_ratio` runs this module instead.

It is the *same* iteration, step for step, not merely another exact
algorithm: the same first policy (each node's first heaviest in-arc), the
same value determination (a policy circuit is rooted at its smallest node,
whose potential is kept when its ratio is unchanged), the same improvement
(a ratio step to the first in-arc of largest ratio, passed downstream level
by level with the numpy sweep's order of visits and its "last write wins"
choice; else a bias step to the first in-arc of largest value). So it
returns the same policy, potentials, circuit and iteration count as the
numpy kernel, and every output built on them is unchanged; the property tests
of ``tests/maxplus/test_small_howard.py`` check that equality on random graphs.
The termination proof of :func:`~maxplus.policy_iteration.howard_arrays`
therefore holds here too; as there, a repeated policy raises RuntimeError
rather than looping.

All numbers are Python ints: exact at any size, no int64 bound to watch.
"""

from __future__ import annotations

from math import gcd
from typing import Literal, NamedTuple, TypeAlias

from . import policy_iteration

__all__ = ["SMALL_GRAPH_ARCS", "downstream_of_circuits", "has_circuit", "howard_lists"]


SMALL_GRAPH_ARCS = 350
"""Up to this many arcs, :func:`maxplus.cycle_ratio.max_cycle_ratio` runs this module.

Set by ``python benchmarks/bench_cycle_ratio.py --crossover`` on four families
(SPRAND, equal weights, a ring with chords, a controller-like graph): Python's
cost grows with the arcs and iterations, numpy's is nearly fixed per solve, and
the constant sits below where the first family crosses
(``benchmarks/results/constants.md`` has the figures).
"""



class ListSolution(NamedTuple):
    """Per node (all ``n``): reduced ratio ``num/den`` (0/0 off the live nodes),
    potential, policy arc (-1 off the live nodes); value determinations run."""

    num: list[int]
    den: list[int]
    potential: list[int]
    policy: list[int]
    iterations: int


def has_circuit(n: int, src: list[int], dst: list[int], arcs: list[int]) -> bool:
    """Whether the arcs ``arcs`` (indices into ``src``/``dst``) contain a circuit.

    Kahn's algorithm: repeatedly drop nodes without in-arc; a circuit is what
    never drops.

    >>> src, dst = [0, 1, 2], [1, 2, 1]
    >>> has_circuit(3, src, dst, [0, 1, 2]), has_circuit(3, src, dst, [0, 1])
    (True, False)
    """
    return len(_acyclic_part(n, src, dst, arcs)) < n


def downstream_of_circuits(n: int, src: list[int], dst: list[int]) -> list[bool]:
    """Per node, whether some circuit reaches it (a node of a circuit included).

    A node drops out of Kahn's algorithm exactly when every backward walk
    from it ends, i.e. when no circuit lies upstream of it.

    >>> downstream_of_circuits(4, [0, 1, 1, 3], [1, 1, 2, 0])
    [False, True, True, False]
    """
    live = [True] * n
    for v in _acyclic_part(n, src, dst, range(len(src))):
        live[v] = False
    return live


def _acyclic_part(n: int, src: list[int], dst: list[int], arcs: list[int] | range) -> list[int]:
    """The nodes that Kahn's algorithm drops: those no circuit of ``arcs`` reaches."""
    indegree = [0] * n
    out: list[list[int]] = [[] for _ in range(n)]
    for a in arcs:
        indegree[dst[a]] += 1
        out[src[a]].append(dst[a])
    dropped = [v for v in range(n) if indegree[v] == 0]
    for u in dropped:  # grows while it is walked
        for v in out[u]:
            indegree[v] -= 1
            if indegree[v] == 0:
                dropped.append(v)
    return dropped


def howard_lists(src: list[int], dst: list[int], w: list[int], t: list[int], n: int,
                 live: list[bool]) -> ListSolution:
    """Howard's iteration on the arcs between live nodes (every live node has such an in-arc).

    Parameters
    ----------
    src, dst, w, t : list of int
        Arcs, integer weights and token counts, with no circuit of zero tokens.
    n : int
        Number of nodes.
    live : list of bool
        The nodes some circuit reaches (:func:`downstream_of_circuits`).

    Returns
    -------
    ListSolution
        What :func:`maxplus.policy_iteration.howard_arrays` returns for the live
        nodes relabelled in increasing order, mapped back to all ``n`` nodes.

    Examples
    --------
    Circuit 0 -> 1 -> 0 of ratio (5+3)/2 and a self-loop of ratio 3 on node 1:

    >>> s = howard_lists([0, 1, 1], [1, 0, 1], [5, 3, 3], [1, 1, 1], 2, [True, True])
    >>> s.num, s.den, s.policy
    ([4, 4], [1, 1], [1, 0])
    """
    nodes = [v for v in range(n) if live[v]]
    # In-arcs in arc order: the numpy kernel's arcs sorted stably by head.
    in_arcs: list[list[int]] = [[] for _ in range(n)]
    for a, (s, d) in enumerate(zip(src, dst)):
        if live[s] and live[d]:
            in_arcs[d].append(a)
    pol = [-1] * n
    for v in nodes:  # the first heaviest in-arc
        arcs = in_arcs[v]
        best = arcs[0]
        for a in arcs:
            if w[a] > w[best]:
                best = a
        pol[v] = best
    out_arcs: list[list[int]] = [[] for _ in range(n)]
    for v in nodes:  # by tail, then in the order by head (the numpy kernel's out_arcs)
        for a in in_arcs[v]:
            out_arcs[src[a]].append(a)
    iteration = _Iteration(src, dst, w, t, nodes, in_arcs, out_arcs)
    seen = {tuple(pol)}
    prev: _Values | None = None
    iterations = 0
    check_all = True
    # The policy's children of each node: the nodes whose policy arc leaves it.
    children: list[set[int]] = [set() for _ in range(n)]
    for v in nodes:
        children[src[pol[v]]].add(v)
    affected: list[int] | None = None  # all nodes
    while True:
        cur = iteration.values(pol, prev, affected)
        iterations += 1
        to_improve = None
        if not check_all:
            assert prev is not None  # check_all holds in the first iteration
            to_improve = iteration.touched(prev, cur, affected)
        prev = cur
        before = pol[:]
        step = iteration.improve(pol, cur, to_improve)
        if step is None and to_improve is not None:
            step = iteration.improve(pol, cur, None)  # the last word checks every node
        if step is None:
            num = [0] * n
            den = [0] * n
            for v in nodes:
                num[v], den[v] = cur.ratio[v]
            return ListSolution(num, den, cur.X, pol, iterations)
        key = tuple(pol)
        if key in seen:  # impossible by the proof in howard_arrays: a bug
            raise RuntimeError("internal error: policy iteration revisited a policy "
                               "(it would loop for ever); please report it")
        seen.add(key)
        # After a ratio step, gains were not examined: check every node next.
        check_all = step == "ratio"
        # Only the nodes whose policy walk passes a switched node get new values:
        # the others reach the same circuit by the same path, and that circuit
        # keeps its ratio and its root's potential.
        affected = [v for v in nodes if pol[v] != before[v]]
        for v in affected:
            children[src[before[v]]].discard(v)
            children[src[pol[v]]].add(v)
        reached = set(affected)
        for u in affected:  # grows while it is walked
            for c in children[u]:
                if c not in reached:
                    reached.add(c)
                    affected.append(c)


_Step: TypeAlias = Literal["ratio", "bias"]
"""A policy improvement: to an arc of larger ratio, or of the same ratio and larger bias."""


class _Values(NamedTuple):
    """One value determination: per node its reduced ratio ``(W, T)``, rank and potential."""

    ratio: list[tuple[int, int]]
    rank: list[int]
    X: list[int]
    n_ranks: int


class _Iteration:
    """The graph, and the two steps of the iteration on it."""

    def __init__(self, src: list[int], dst: list[int], w: list[int], t: list[int],
                 nodes: list[int], in_arcs: list[list[int]], out_arcs: list[list[int]]) -> None:
        self.src, self.dst, self.w, self.t = src, dst, w, t
        self.nodes, self.in_arcs, self.out_arcs = nodes, in_arcs, out_arcs
        self.n = len(in_arcs)
        # Per node its in-arcs as (arc, tail, weight, tokens): the improvement's inner loop.
        self.in_lists = [[(a, src[a], w[a], t[a]) for a in arcs] for arcs in in_arcs]

    def values(self, pol: list[int], prev: _Values | None, affected: list[int] | None
               ) -> _Values:
        """Ratio and potential of every live node under ``pol`` (tight on policy arcs).

        Only the nodes ``affected`` (None: all) are valued again; the others
        keep their values of ``prev``.
        """
        src, w, t = self.src, self.w, self.t
        if affected is None or prev is None:
            state = [0] * self.n  # 0: not seen, 1: on the current walk, 2: valued
            ratio: list[tuple[int, int]] = [(0, 0)] * self.n
            X = [0] * self.n
            affected = self.nodes
        else:
            state = [2] * self.n
            for v in affected:
                state[v] = 0
            ratio, X = prev.ratio[:], prev.X[:]
        for v in affected:
            if state[v]:
                continue
            path = []
            u = v
            while not state[u]:  # backwards along the policy
                state[u] = 1
                path.append(u)
                u = src[pol[u]]
            if state[u] == 1:  # the walk closed a circuit: path[k:], backwards from u
                k = path.index(u)
                self._circuit(path[k:], pol, prev, ratio, X)
                for x in path[k:]:
                    state[x] = 2
                del path[k:]
            # The rest of the walk reaches the circuit of u: its ratio, and potentials
            # tight along the policy from u's.
            WT = ratio[u]
            W, T = WT
            x_u = X[u]
            for x in reversed(path):
                a = pol[x]
                x_u += w[a] * T - W * t[a]
                X[x] = x_u
                ratio[x] = WT
                state[x] = 2
        distinct = set(ratio[v] for v in self.nodes)
        rank = [0] * self.n
        if len(distinct) > 1:
            rank_of = {r: i for i, r in enumerate(sorted(distinct, key=_as_key))}
            for v in self.nodes:
                rank[v] = rank_of[ratio[v]]
        return _Values(ratio, rank, X, len(distinct))

    def _circuit(self, cycle: list[int], pol: list[int], prev: _Values | None,
                 ratio: list[tuple[int, int]], X: list[int]) -> None:
        """Ratio and potentials of a policy circuit (its nodes listed backwards)."""
        w, t = self.w, self.t
        W = T = 0
        for x in cycle:
            a = pol[x]
            W += w[a]
            T += t[a]
        g = gcd(W, T)  # T > 0: no circuit without tokens
        W, T = W // g, T // g
        WT = (W, T)
        root = min(cycle)
        r = cycle.index(root)
        # Its potential is kept when its ratio is (Cochet-Terrasson et al.): as numpy's _circuits.
        x_root = prev.X[root] if prev is not None and prev.ratio[root] == WT else 0
        ratio[root], X[root] = WT, x_root
        for x in cycle[:r][::-1] + cycle[r + 1:][::-1]:  # forwards from the root
            a = pol[x]
            x_root += w[a] * T - W * t[a]
            X[x] = x_root
            ratio[x] = WT

    def touched(self, prev: _Values, cur: _Values, affected: list[int] | None
                ) -> list[int] | None:
        """The nodes whose in-arcs may improve after a bias step; None for all nodes.

        As the numpy kernel's candidate arcs: an arc between two nodes whose
        ratio and potential did not change was not improving at the last check
        and still is not, so only the nodes that changed and the heads of their
        out-arcs need a look (all nodes when many changed).
        """
        changed = [v for v in (self.nodes if affected is None else affected)
                   if cur.X[v] != prev.X[v] or cur.ratio[v] != prev.ratio[v]]
        if 8 * len(changed) >= len(self.nodes):
            return None
        dst, out_arcs = self.dst, self.out_arcs
        to_improve = set(changed)
        for u in changed:
            to_improve.update(dst[a] for a in out_arcs[u])
        return sorted(to_improve)

    def improve(self, pol: list[int], cur: _Values, to_improve: list[int] | None) -> _Step | None:
        """One policy improvement at the nodes ``to_improve`` (None: all); its kind, or None."""
        rank, in_lists = cur.rank, self.in_lists
        nodes = self.nodes if to_improve is None else to_improve
        if cur.n_ranks > 1:
            frontier = []
            raised = []
            for v in nodes:  # the first in-arc of largest strictly better ratio
                best_rank, best = rank[v], -1
                for a, s, _, _ in in_lists[v]:
                    r = rank[s]
                    if r > best_rank:
                        best_rank, best = r, a
                if best >= 0:
                    frontier.append(v)
                    raised.append((best, best_rank))
            if frontier:
                for v, (a, r) in zip(frontier, raised):
                    pol[v], rank[v] = a, r
                self._sweep(pol, rank, frontier)
                return "ratio"
        X, ratio = cur.X, cur.ratio
        switched = False
        for v in nodes:  # the first in-arc of largest value, of the same ratio
            W, T = ratio[v]
            rv, best_value, best = rank[v], X[v], -1
            for a, s, wa, ta in in_lists[v]:
                if rank[s] == rv:
                    value = X[s] + wa * T - W * ta
                    if value > best_value:
                        best_value, best = value, a
            if best >= 0:
                pol[v] = best
                switched = True
        return "bias" if switched else None

    def _sweep(self, pol: list[int], rank: list[int], frontier: list[int]) -> None:
        """numpy's ``_sweep_downstream``: larger ranks passed downstream, breadth first.

        The arcs of a round are visited in the order numpy gathers them (by
        tail in the round's order, or, for a round of many nodes, by head), and
        of several arcs into one node the last visited wins, as numpy's
        assignment does; the next round lists the raised nodes in the order of
        their winning arcs.
        """
        src, dst, out_arcs = self.src, self.dst, self.out_arcs
        n_live = len(self.nodes)
        done = [False] * self.n
        pending = sorted(frontier, key=lambda v: -rank[v])  # stable, as numpy's argsort
        groups: list[list[int]] = []  # by rank, cut before the sweep raises any of them
        for v in pending:
            if groups and rank[groups[-1][0]] == rank[v]:
                groups[-1].append(v)
            else:
                groups.append([v])
        for group in groups:
            level = [v for v in group if not done[v]]
            if not level:
                continue
            top = rank[level[0]]
            for v in level:
                done[v] = True
            while level:
                # The numpy sweep's thresholds decide the order of its visits, hence
                # which of several equal choices it keeps: read from it, at each call.
                if (len(level) > policy_iteration.SWEEP_FEW
                        and len(level) * policy_iteration.SCAN_MIN_SHARE > n_live):
                    in_level = set(level)
                    gathered = [a for v in self.nodes for a in self.in_arcs[v]
                                if src[a] in in_level]
                else:
                    gathered = [a for u in level for a in out_arcs[u]]
                kept = [a for a in gathered if rank[dst[a]] < top]
                for a in kept:
                    pol[dst[a]] = a
                level = [dst[a] for a in kept if pol[dst[a]] == a]
                for v in level:
                    rank[v] = top
                    done[v] = True


def _as_key(ratio: tuple[int, int]) -> _Ratio:
    return _Ratio(*ratio)


class _Ratio:
    """A reduced fraction ``W/T`` (``T > 0``) ordered by value, by cross-multiplication."""

    __slots__ = ("W", "T")

    def __init__(self, W: int, T: int) -> None:
        self.W, self.T = W, T

    def __lt__(self, other: _Ratio) -> bool:
        return self.W * other.T < other.W * self.T
