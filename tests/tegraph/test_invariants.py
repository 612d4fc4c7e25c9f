"""Minimal p-semiflows: against circuit enumeration and hand-computed nets."""

from __future__ import annotations

import itertools

import networkx as nx
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph.invariants import minimal_semiflows


@st.composite
def marked_graphs(draw):
    n = draw(st.integers(1, 6))
    m = draw(st.integers(1, 10))
    node = st.integers(0, n - 1)
    return n, draw(st.lists(st.tuples(node, node), min_size=m, max_size=m))


@settings(max_examples=200, deadline=None)
@given(marked_graphs())
def test_marked_graph_semiflows_are_its_elementary_circuits(graph):
    # In a marked graph the supports of the minimal p-semiflows are exactly
    # the elementary circuits (as sets of places), each with coefficients 1.
    n, arcs = graph
    C = np.zeros((len(arcs), n), dtype=int)
    for p, (a, b) in enumerate(arcs):
        C[p, a] += 1
        C[p, b] -= 1
    expected = set()
    for cycle in nx.simple_cycles(nx.DiGraph(arcs)):
        pairs = list(zip(cycle, cycle[1:] + cycle[:1]))
        choices = [[p for p, arc in enumerate(arcs) if arc == pair] for pair in pairs]
        expected.update(tuple(sorted(c)) for c in itertools.product(*choices))
    result = minimal_semiflows(C)
    assert result.computed
    assert sorted(tuple(np.flatnonzero(y).tolist()) for y in result.semiflows) == sorted(expected)
    assert all(set(y.tolist()) <= {0, 1} for y in result.semiflows)


def test_weighted_net_semiflow_by_hand():
    # t0 takes 2 tokens from p0 and puts 1 in p1; t1 takes 1 from p1 and puts
    # 2 in p0. y = (1, 2): y.C = (−2 + 2, 2 − 2) = 0, and it is the only
    # minimal one (the kernel of C^T is one-dimensional).
    C = np.array([[-2, 2], [1, -1]])
    result = minimal_semiflows(C)
    assert [y.tolist() for y in result.semiflows] == [[1, 2]]


def test_budget_is_reported():
    # Two transitions joined by 6 parallel places each way: 36 circuits of 2
    # places; a budget of 10 rows cannot hold them.
    C = np.array([[1, -1]] * 6 + [[-1, 1]] * 6)
    assert len(minimal_semiflows(C).semiflows) == 36
    assert minimal_semiflows(C, budget=10).computed is False
