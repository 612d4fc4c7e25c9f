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
                               weights: list[int], sources: list[int],
                               upper: Sequence[int | None] | None = None) -> list[int | None]:
    """Length of the lightest circuit through each source (non-negative integer weights).

    Parameters
    ----------
    events : numpy.ndarray of int
        The nodes (event numbers, any integers) of the graph.
    s, d : numpy.ndarray of int
        Tail and head event of every arc (place).
    weights : list of int
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
    ``upper``. scipy's Dijkstra runs on blocks of sources when every distance
    stays below 2**53, where float64 is exact; otherwise an exact heap
    Dijkstra in Python stops once no shorter circuit can be found.
    :meth:`tegraph.analysis.Analysis` calls it with Johnson's reduced weights
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
    local = {int(e): i for i, e in enumerate(events.tolist())}
    n = len(local)
    ls = np.array([local[int(a)] for a in s.tolist()], dtype=np.int64)
    ld = np.array([local[int(b)] for b in d.tolist()], dtype=np.int64)
    heads = np.array([local[c] for c in sources], dtype=np.int64)
    # The places into each source: (source index, place) pairs.
    order = np.argsort(ld, kind="stable")
    first = np.searchsorted(ld[order], heads)
    last = np.searchsorted(ld[order], heads, side="right")
    pair_source = np.repeat(np.arange(len(sources)), last - first)
    pair_place = order[np.concatenate([np.arange(a, b) for a, b in zip(first, last)]
                                      or [np.zeros(0, dtype=np.int64)])]
    result: list[int | None] = [None] * len(sources)
    if len(weights) and max(weights) * max(n, 1) < 2**53:
        bound = np.array([np.inf if u is None else float(u)
                          for u in (upper if upper is not None else [None] * len(heads))])
        best = _circuits_by_component(n, ls, ld, np.array(weights, dtype=np.float64), heads,
                                      pair_source, pair_place, bound)
        return [None if not np.isfinite(v) else int(v) for v in best.tolist()]
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


def _circuits_by_component(n: int, ls: np.ndarray, ld: np.ndarray, wf: np.ndarray,
                           heads: np.ndarray, pair_source: np.ndarray, pair_place: np.ndarray,
                           bound: np.ndarray) -> np.ndarray:
    """Float kernel of :func:`_shortest_circuits_through` (exact below 2**53).

    A circuit stays inside one strongly connected component, so each source
    is searched in its own component only, with scipy's Dijkstra on a few
    small components at a time: a chain of many small components costs in
    proportion to its size, not to sources × events.
    """
    arcs = sp.csr_matrix((np.ones(len(ls)), (ls, ld)), shape=(n, n))
    _, label = connected_components(arcs, directed=True, connection="strong")
    inside = label[ls] == label[ld]
    # Number the events component by component, so that each is a contiguous range.
    by_label = np.argsort(label, kind="stable")
    new = np.empty(n, dtype=np.int64)
    new[by_label] = np.arange(n)
    best = np.full(len(heads), np.inf)
    if not inside.any():
        return best  # no circuit at all
    a, b, w = new[ls[inside]], new[ld[inside]], wf[inside]
    key = np.lexsort((w, b, a))
    keep = key[np.r_[True, (a[key][1:] != a[key][:-1]) | (b[key][1:] != b[key][:-1])]]
    graph = sp.csr_matrix((w[keep], (a[keep], b[keep])), shape=(n, n))
    comp_start = np.searchsorted(label[by_label], label[by_label], side="left")
    comp_end = np.searchsorted(label[by_label], label[by_label], side="right")
    valid = inside[pair_place]
    pair_source, pair_place = pair_source[valid], pair_place[valid]
    head_new = new[heads]
    # Batches: the components whose first event falls in the same window of events.
    window = 4096
    batch = comp_start[head_new] // window
    for key_batch in np.unique(batch).tolist():
        mine = np.flatnonzero(batch == key_batch)
        lo = int(comp_start[head_new[mine]].min())
        hi = int(comp_end[head_new[mine]].max())
        sub = graph[lo:hi, lo:hi]
        block = max(1, 2_000_000 // (hi - lo))
        mine = mine[np.argsort(bound[mine], kind="stable")]  # similar bounds share a search
        for k in range(0, len(mine), block):
            chunk = mine[k:k + block]
            dist = dijkstra(sub, directed=True, indices=head_new[chunk] - lo,
                            limit=float(bound[chunk].max()))
            row = np.full(len(heads), -1, dtype=np.int64)
            row[chunk] = np.arange(len(chunk))
            take = row[pair_source] >= 0
            ps, pp = pair_source[take], pair_place[take]
            np.minimum.at(best, ps, dist[row[ps], new[ls[pp]] - lo] + wf[pp])
    return best
