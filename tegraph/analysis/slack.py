"""Slack kernel: the lightest circuit through each of a set of events.

The slack of a task is how much its duration can grow before the period of
its group does; with Johnson's reduced weights [1]_ (Howard's potentials [2]_
make them non-negative, 0 on critical circuits) it is the lightest circuit
through the task's compute event, found by Dijkstra's algorithm [3]_. Arrays
in, arrays out, as :mod:`scipy.sparse.csgraph`: the caller validates.

References
----------
.. [1] D. B. Johnson, "Efficient algorithms for shortest paths in sparse
   networks", Journal of the ACM 24(1), 1–13, 1977.
.. [2] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
   J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
   algebra", IFAC Conference on System Structure and Control, 1998.
.. [3] E. W. Dijkstra, "A note on two problems in connexion with graphs",
   Numerische Mathematik 1, 269–271, 1959.
"""

from __future__ import annotations

import heapq
from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components, dijkstra

__all__ = ["shortest_circuits_through"]


def shortest_circuits_through(events: np.ndarray, s: np.ndarray, d: np.ndarray,
                               weights: list[int] | np.ndarray, sources: list[int],
                               upper: Sequence[int | None] | None = None) -> list[int | None]:
    """Length of the lightest circuit through each source (non-negative integer weights).

    Parameters
    ----------
    events : numpy.ndarray of int
        The nodes (event numbers, any integers) of the graph.
    s, d : numpy.ndarray of int
        Tail and head event of every arc (place).
    weights : list of int or numpy.ndarray of int
        Non-negative integer weight of every arc.
    sources : list of int
        Events whose lightest circuit is wanted.
    upper : sequence of int or None, optional
        ``upper[i]``: the length of some circuit through ``sources[i]`` (None:
        unknown); no search goes further.

    Returns
    -------
    list of int or None
        ``min over arcs k into c of dist(c, s[k]) + weights[k]`` for each
        source c, None when no circuit passes through c.

    See Also
    --------
    scipy.sparse.csgraph.dijkstra : the float kernel used below 2**53.
    maxplus.max_cycle_ratio : the potentials that make the weights non-negative.

    Notes
    -----
    Dijkstra's algorithm [1]_ from each source, restricted to the source's strongly
    connected component (a circuit cannot leave it) and to distances up to
    ``upper``. scipy's Dijkstra runs (one source of each component at a time,
    or blocks of sources of a large component) when every distance stays below
    2**53, where float64 is exact; otherwise an exact heap Dijkstra in Python
    stops once no shorter circuit can be found. The cost is each component's
    size times its sources (linear in a chain of small groups).
    The analysis (:mod:`tegraph.analysis.analyze`) calls it with Johnson's reduced weights
    [2]_ (Howard's potentials [3]_ make every weight non-negative), so that the
    lightest circuit is the slack of a task's compute event.

    References
    ----------
    .. [1] E. W. Dijkstra, "A note on two problems in connexion with graphs",
       Numerische Mathematik 1, 269–271, 1959.
    .. [2] D. B. Johnson, "Efficient algorithms for shortest paths in sparse
       networks", Journal of the ACM 24(1), 1–13, 1977.
    .. [3] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
       J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
       algebra", IFAC Conference on System Structure and Control, 1998.

    Examples
    --------
    Circuits 1 -> 2 -> 1 (weight 3 + 4) and 1 -> 1 (weight 9); node 3 is on none:

    >>> shortest_circuits_through(np.array([1, 2, 3]), np.array([1, 2, 1, 2]),
    ...                           np.array([2, 1, 1, 3]), [3, 4, 9, 0], [1, 2, 3])
    [7, 7, None]
    """
    n = len(events)
    ls, ld, heads = (_positions(events, x) for x in (s, d, np.asarray(sources, dtype=np.int64)))
    # The places into each source: (source index, place) pairs, by source.
    order = np.argsort(ld, kind="stable")
    first = np.searchsorted(ld[order], heads)
    last = np.searchsorted(ld[order], heads, side="right")
    pair_source = np.repeat(np.arange(len(sources)), last - first)
    pair_place = order[_ranges(first, last)]
    result: list[int | None] = [None] * len(sources)
    top = (int(weights.max()) if isinstance(weights, np.ndarray) else max(weights)) \
        if len(weights) else 0
    if len(weights) and top * max(n, 1) < 2**53:
        bound = np.array([np.inf if u is None else float(u)
                          for u in (upper if upper is not None else [None] * len(heads))])
        best = _circuits_by_component(n, ls, ld, np.array(weights, dtype=np.float64), heads,
                                      pair_source, pair_place, bound)
        # (A ufunc per element would cost more than the whole search.)
        return [int(v) if finite else None
                for v, finite in zip(best.tolist(), np.isfinite(best).tolist())]
    if isinstance(weights, np.ndarray):
        weights = weights.tolist()  # Python ints: sums of any size
    adjacency: list[list[tuple[int, int]]] = [[] for _ in range(n)]
    for a, b, wt in zip(ls.tolist(), ld.tolist(), weights):
        adjacency[a].append((b, wt))
    closing: dict[int, dict[int, int]] = {}  # source -> {tail of a place into it: weight}
    for i, k in zip(pair_source.tolist(), pair_place.tolist()):
        tails = closing.setdefault(i, {})
        u = int(ls[k])
        tails[u] = min(weights[k], tails.get(u, weights[k]))
    for i, c in enumerate(heads.tolist()):
        into = closing.get(i, {})
        shortest = None
        dist = {c: 0}
        heap = [(0, c)]
        while heap:
            dv, v = heapq.heappop(heap)
            if dv > dist[v]:
                continue
            if shortest is not None and dv >= shortest:
                break  # every later circuit is at least this long
            if v in into:
                cand = dv + into[v]
                shortest = cand if shortest is None else min(shortest, cand)
            for b, wt in adjacency[v]:
                if b not in dist or dv + wt < dist[b]:
                    dist[b] = dv + wt
                    heapq.heappush(heap, (dv + wt, b))
        result[i] = shortest
    return result


def _positions(events: np.ndarray, x: np.ndarray) -> np.ndarray:
    """The index of each of ``x`` in ``events`` (each one of them, ``events`` distinct)."""
    if not len(x):
        return np.zeros(0, dtype=np.int64)
    order = np.argsort(events, kind="stable")
    at = order[np.minimum(np.searchsorted(events[order], x), len(events) - 1)] \
        if len(events) else np.zeros(0, dtype=np.int64)
    if len(at) != len(x) or not np.array_equal(events[at], x):
        raise KeyError("an arc or a source is not among the events")
    return at.astype(np.int64)


def _ranges(first: np.ndarray, last: np.ndarray) -> np.ndarray:
    """``first[0]..last[0]-1, first[1]..last[1]-1, ...`` concatenated (no loop per range)."""
    count = last - first
    total = int(count.sum())
    starts = np.repeat(first - (np.cumsum(count) - count), count)
    return (starts + np.arange(total)).astype(np.int64)


def _lightest(a: np.ndarray, b: np.ndarray, w: np.ndarray, n: int) -> sp.csr_matrix:
    """The graph of arcs ``a -> b`` of weights ``w``, the lightest of parallel arcs only
    (a sparse matrix would add them up)."""
    key = np.lexsort((w, b, a))
    keep = key[np.r_[True, (a[key][1:] != a[key][:-1]) | (b[key][1:] != b[key][:-1])]]
    return sp.csr_matrix((w[keep], (a[keep], b[keep])), shape=(n, n))


_DENSE = 2_000_000
"""Distances in one dense search (sources x events): a graph this small is searched
at once, a larger one component by component."""

_ROUNDS = 32
"""Components with at most this many sources are searched by rounds (one source of
each per search); the others by blocks of sources (:func:`_circuits_by_component`)."""


def _circuits_by_component(n: int, ls: np.ndarray, ld: np.ndarray, wf: np.ndarray,
                           heads: np.ndarray, pair_source: np.ndarray, pair_place: np.ndarray,
                           bound: np.ndarray) -> np.ndarray:
    """Float kernel of :func:`shortest_circuits_through` (exact below 2**53).

    A circuit stays inside one strongly connected component, so only the arcs
    inside components are kept, and each source is searched in its own
    component. Many components with few sources each (a chain of many small
    groups) are searched in rounds: round r takes the r-th source of each, all
    at once (scipy's ``min_only``: no arc joins two components, so each
    event's distance is from its own component's source), in at most
    :data:`_ROUNDS` calls; the cost is each component's size times its
    sources. The other components (one large group, or a few small ones,
    where rounds would merge nothing) are searched component by component, by
    blocks of sources, each a dense matrix of distances over its component.
    """
    best = np.full(len(heads), np.inf)
    if not len(heads):
        return best
    if n * len(heads) <= _DENSE:
        # One search of every source over the whole graph: an arc into a source from
        # an event it reaches closes a circuit, whichever component (a small group).
        dist = dijkstra(_lightest(ls, ld, wf, n), directed=True, indices=heads,
                        limit=float(bound.max(initial=0)))
        np.minimum.at(best, pair_source,
                      dist[pair_source, ls[pair_place]] + wf[pair_place])
        return best
    arcs = sp.csr_matrix((np.ones(len(ls)), (ls, ld)), shape=(n, n))
    _, label = connected_components(arcs, directed=True, connection="strong")
    inside = label[ls] == label[ld]
    if not inside.any():
        return best  # no circuit at all
    # Number the events component by component, so that each is a contiguous range.
    by_label = np.argsort(label, kind="stable")
    new = np.empty(n, dtype=np.int64)
    new[by_label] = np.arange(n)
    sorted_label = label[by_label]
    graph = _lightest(new[ls[inside]], new[ld[inside]], wf[inside], n)
    valid = inside[pair_place]
    pair_source = pair_source[valid]
    pair_tail, pair_weight = new[ls[pair_place[valid]]], wf[pair_place[valid]]
    # The pairs of each source, a contiguous range (pair_source is sorted).
    pair_first = np.searchsorted(pair_source, np.arange(len(heads)))
    pair_last = np.searchsorted(pair_source, np.arange(len(heads)), side="right")
    comp = label[heads]
    # Each source's rank among its component's sources, and how many those are.
    by_comp = np.argsort(comp, kind="stable")
    comp_first = np.searchsorted(comp[by_comp], comp[by_comp])
    rank = np.empty(len(heads), dtype=np.int64)
    rank[by_comp] = np.arange(len(heads)) - comp_first
    few = np.flatnonzero(np.bincount(comp, minlength=n)[comp] <= _ROUNDS)
    rounds = int(rank[few].max()) + 1 if len(few) else 0
    if len(np.unique(comp[few])) <= rounds:
        few = few[:0]  # as many searches either way: by components, fewer made
    head_new = new[heads]
    for r in range(rounds if len(few) else 0):
        mine = few[rank[few] == r]
        dist = dijkstra(graph, directed=True, indices=head_new[mine], min_only=True,
                        limit=float(bound[mine].max()))
        pairs = _ranges(pair_first[mine], pair_last[mine])
        np.minimum.at(best, pair_source[pairs], dist[pair_tail[pairs]] + pair_weight[pairs])
    rest = np.setdiff1d(np.arange(len(heads)), few)
    # Component by component, similar bounds together (they share a search).
    comp_start = np.searchsorted(sorted_label, comp, side="left")
    comp_end = np.searchsorted(sorted_label, comp, side="right")
    rest = rest[np.lexsort((bound[rest], comp_start[rest]))]
    for part in np.split(rest, np.flatnonzero(np.diff(comp_start[rest])) + 1):
        if not len(part):
            continue
        lo, hi = int(comp_start[part[0]]), int(comp_end[part[0]])
        sub = graph[lo:hi, lo:hi]
        block = max(1, _DENSE // (hi - lo))
        for k in range(0, len(part), block):
            chunk = part[k:k + block]
            dist = dijkstra(sub, directed=True, indices=head_new[chunk] - lo,
                            limit=float(bound[chunk].max()))
            pairs = _ranges(pair_first[chunk], pair_last[chunk])
            rows = np.repeat(np.arange(len(chunk)), pair_last[chunk] - pair_first[chunk])
            np.minimum.at(best, pair_source[pairs],
                          dist[rows, pair_tail[pairs] - lo] + pair_weight[pairs])
    return best
