"""The advice's solves: folding single-input events away changes no cycle time."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from maxplus import ZeroTokenCircuitError, max_cycle_ratio
from tegraph.design.rules.rates import folded


@st.composite
def graphs(draw):
    """A small graph where every node has an in-arc (as every event of a skeleton): many
    single-input nodes, chains and rings of them, loops, parallel arcs, 0-token arcs."""
    n = draw(st.integers(1, 9))
    arcs = [(draw(st.integers(0, n - 1)), v) for v in range(n)]  # an in-arc each
    arcs += draw(st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)),
                          max_size=2 * n))
    weights = draw(st.lists(st.integers(-5, 40), min_size=len(arcs), max_size=len(arcs)))
    tokens = draw(st.lists(st.integers(0, 2), min_size=len(arcs), max_size=len(arcs)))
    return [a for a, _ in arcs], [b for _, b in arcs], weights, tokens, n


def _cycle_times(src, dst, weights, tokens, n):
    """Each node's cycle time as a (num, den) pair in lowest terms, or the error's type."""
    try:
        r = max_cycle_ratio(src, dst, weights, tokens, n_nodes=n)
    except ZeroTokenCircuitError:
        return ZeroTokenCircuitError
    return list(zip(r.cycle_time_num.tolist(), r.cycle_time_den.tolist()))


@settings(max_examples=400, deadline=None)
@given(graphs())
def test_folding_changes_no_cycle_time_nor_a_token_free_circuit(graph):
    # The folded graph solved, each node read at the node it was folded into: the same
    # cycle times as the graph solved whole, and a token-free circuit refused in both.
    src, dst, weights, tokens, n = graph
    whole = _cycle_times(src, dst, weights, tokens, n)
    f = folded(src, dst, weights, tokens, n)
    assert f.n_nodes <= n
    small = _cycle_times(f.src, f.dst, f.weight, f.tokens, f.n_nodes)
    if whole is ZeroTokenCircuitError:
        assert small is ZeroTokenCircuitError
    else:
        assert small is not ZeroTokenCircuitError
        assert [small[v] for v in f.node.tolist()] == whole


@pytest.mark.parametrize(("graph", "nodes_left"), [
    # A ring of single-input nodes keeps one node, its arc the ring's sum.
    (([0, 1, 2], [1, 2, 0], [1, 2, 3], [0, 1, 0], 3), 1),
    # A loop as the only in-arc is no fold: the node keeps its loop.
    (([0], [0], [5], [1], 1), 1),
    # Node 2 has two in-arcs: it stays; 1 folds into 0, which has one in-arc from 2.
    (([0, 1, 2, 0], [1, 2, 0, 2], [1, 1, 1, 7], [0, 0, 1, 0], 3), 1),
])
def test_folding_by_hand(graph, nodes_left):
    # Worked by hand: in the last graph, 0 folds into 2 (its only in-arc 2 -> 0) and 1
    # into 0, so into 2: the circuits 2 -> 0 -> 1 -> 2 (weight 3, 1 token) and
    # 2 -> 0 -> 2 (weight 8, 1 token) become loops on 2 of those weights.
    f = folded(*graph)
    assert f.n_nodes == nodes_left
    assert f.node.tolist() == [0] * graph[4]
    if graph[0] == [0, 1, 2, 0]:
        assert sorted(zip(f.weight.tolist(), f.tokens.tolist())) == [(3, 1), (8, 1)]
