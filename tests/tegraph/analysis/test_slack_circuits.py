"""Lightest circuit through a node (the slack kernel of ``analyze``) against brute force."""

from __future__ import annotations

from unittest import mock

import networkx as nx
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph.analysis import slack
from tegraph.analysis.slack import shortest_circuits_through


@st.composite
def weighted_graphs(draw):
    n = draw(st.integers(1, 6))
    node = st.integers(0, n - 1)
    arcs = draw(st.lists(st.tuples(node, node, st.integers(0, 9)), min_size=1, max_size=14))
    sources = draw(st.lists(node, min_size=1, max_size=n, unique=True))
    return n, arcs, sources


def brute_force(n, arcs, source):
    """Every elementary circuit through ``source``, each parallel place tried."""
    g = nx.MultiDiGraph()
    g.add_nodes_from(range(n))
    for a, b, w in arcs:
        g.add_edge(a, b, weight=w)
    best = None
    for cycle in nx.simple_cycles(nx.DiGraph([(a, b) for a, b, _ in arcs])):
        if source not in cycle:
            continue
        hops = zip(cycle, cycle[1:] + cycle[:1])
        length = sum(min(w for a, b, w in arcs if (a, b) == hop) for hop in hops)
        best = length if best is None else min(best, length)
    return best


@settings(max_examples=150, deadline=None)
@given(weighted_graphs())
def test_both_kernels_equal_circuit_enumeration(graph):
    n, arcs, sources = graph
    events = np.arange(10, 10 + n)  # global event numbers differ from local indices
    s = np.array([events[a] for a, _, _ in arcs])
    d = np.array([events[b] for _, b, _ in arcs])
    weights = [w for _, _, w in arcs]
    expected = [brute_force(n, arcs, c) for c in sources]
    heads = [int(events[c]) for c in sources]
    # A bound at least the answer (here: the answer plus up to 3) changes nothing.
    upper = [None if e is None or k % 3 == 0 else e + k % 4 for k, e in enumerate(expected)]
    assert shortest_circuits_through(events, s, d, weights, heads) == expected
    # The whole graph at once (above: it is small), or component by component: by
    # blocks of sources, or in rounds of one source of each: the same.
    for rounds in (0, 1, 32):
        with mock.patch.object(slack, "_DENSE", 0), mock.patch.object(slack, "_ROUNDS", rounds):
            assert shortest_circuits_through(events, s, d, weights, heads) == expected
            assert shortest_circuits_through(events, s, d, weights, heads, upper) == expected
    assert shortest_circuits_through(events, s, d, weights, heads, upper) == expected
    # Weights beyond 2**53 take the exact Python path: the same circuits, scaled.
    big = 2**60
    scaled = shortest_circuits_through(events, s, d, [w * big for w in weights], heads)
    assert scaled == [None if e is None else e * big for e in expected]
