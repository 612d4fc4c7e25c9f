"""The slack kernel on graphs of thousands of small components (searched by rounds, one
source of each at a time) and a few large ones (searched by blocks of sources).

Reference: scipy's Dijkstra from every source over the whole graph (no
component restriction, no bound, no batching), zero weights lifted
lexicographically (w·(n+1) + 1) so that the arc count breaks ties.
"""
from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.csgraph import dijkstra

from tegraph.analysis.slack import shortest_circuits_through


def random_graph(rng, n_target, big_sizes=()):
    arcs = []
    comps = []
    n = 0
    sizes = list(big_sizes)
    while n + sum(sizes) < n_target:
        sizes.append(int(rng.integers(1, 7)))
    rng.shuffle(sizes)
    for size in sizes:
        nodes = np.arange(n, n + size)
        n += size
        comps.append(nodes)
        if size == 1:
            if rng.random() < 0.5:  # self loop (maybe parallel)
                for _ in range(rng.integers(1, 3)):
                    arcs.append((nodes[0], nodes[0], int(rng.integers(0, 10))))
            continue
        order = rng.permutation(nodes)
        for a, b in zip(order, np.roll(order, -1)):
            arcs.append((a, b, int(rng.integers(0, 10))))
        for _ in range(int(rng.integers(0, size + 1))):
            arcs.append((rng.choice(nodes), rng.choice(nodes), int(rng.integers(0, 10))))
    # forward arcs between components (keeps them separate SCCs)
    for _ in range(n):
        i, j = sorted(rng.integers(0, len(comps), 2))
        if i < j:
            arcs.append((rng.choice(comps[i]), rng.choice(comps[j]), int(rng.integers(0, 10))))
    perm = rng.permutation(n)
    arcs = [(int(perm[a]), int(perm[b]), w) for a, b, w in arcs]
    rng.shuffle(arcs)
    return n, arcs


def reference(n, arcs, sources):
    """Per-source Dijkstra over the whole graph; a lexicographic lift makes 0 weights positive."""
    big = n + 1
    s = np.array([a for a, _, _ in arcs])
    d = np.array([b for _, b, _ in arcs])
    w = np.array([x for _, _, x in arcs], dtype=np.float64)
    lifted = w * big + 1
    g = sp.coo_matrix((lifted, (s, d)), shape=(n, n))
    # keep the lightest parallel arc
    m = {}
    for a, b, x in zip(s.tolist(), d.tolist(), lifted.tolist()):
        m[a, b] = min(x, m.get((a, b), x))
    keys = list(m)
    g = sp.csr_matrix(([m[k] for k in keys], ([k[0] for k in keys], [k[1] for k in keys])),
                      shape=(n, n))
    dist = dijkstra(g, directed=True, indices=sources)
    w_int = np.array([x for _, _, x in arcs], dtype=np.int64)
    out = []
    for row, c in zip(dist, sources):
        into = np.flatnonzero(d == c)
        reach = into[np.isfinite(row[s[into]])]
        out.append(None if len(reach) == 0 else
                   int((row[s[reach]].astype(np.int64) // big + w_int[reach]).min()))
    return out


@pytest.mark.parametrize("seed", range(2))
@pytest.mark.parametrize("big_sizes", [(), (5000, 40), (700,) * 8])
def test_large_against_whole_graph_dijkstra(seed, big_sizes):
    rng = np.random.default_rng(seed)
    n, arcs = random_graph(rng, 9000, big_sizes)
    events = np.sort(rng.choice(10 * n, n, replace=False))  # global numbers
    k = min(n, 1500)
    sources_local = rng.choice(n, k, replace=False).tolist()
    expected = reference(n, arcs, sources_local)
    s = events[[a for a, _, _ in arcs]]
    d = events[[b for _, b, _ in arcs]]
    weights = [x for _, _, x in arcs]
    heads = [int(events[c]) for c in sources_local]
    got = shortest_circuits_through(events, s, d, weights, heads)
    assert got == expected
    # bounds: exact answers (tightest), answers + slack, or None
    upper = [None if e is None else
             (e if i % 3 == 0 else (None if i % 3 == 1 else e + int(rng.integers(0, 5))))
             for i, e in enumerate(expected)]
    assert shortest_circuits_through(events, s, d, weights, heads, upper) == expected
    tight = [e for e in expected]
    assert shortest_circuits_through(events, s, d, weights, heads, tight) == expected


@pytest.mark.parametrize("seed", range(3))
def test_exact_path_equals_float_path(seed):
    rng = np.random.default_rng(100 + seed)
    n, arcs = random_graph(rng, 300, (40,))
    events = np.arange(n) + 7
    sources_local = rng.choice(n, 120, replace=False).tolist()
    s = events[[a for a, _, _ in arcs]]
    d = events[[b for _, b, _ in arcs]]
    weights = [x for _, _, x in arcs]
    heads = [int(events[c]) for c in sources_local]
    f = shortest_circuits_through(events, s, d, weights, heads)
    assert f == reference(n, arcs, sources_local)
    big = 2**60
    e = shortest_circuits_through(events, s, d, [x * big for x in weights], heads)
    assert e == [None if v is None else v * big for v in f]
