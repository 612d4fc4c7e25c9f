"""P/T nets hold sparse arc weights: built from arrays, checked once, compared with the
dense definition on random nets."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph.errors import ModelError
from tegraph.io.edges import parse_edges
from tegraph.model.convert import from_networkx, to_networkx
from tegraph.model.petri import ArcWeights, PetriNet


def dense_violation(pre: np.ndarray, post: np.ndarray, places: list[str],
                    transitions: list[str]) -> str | None:
    """The marked-graph test written from the definition, on dense matrices."""
    for p in range(pre.shape[0]):
        for t in range(pre.shape[1]):
            if pre[p, t] > 1 or post[p, t] > 1:
                return (f"the arc between place {places[p]!r} and transition "
                        f"{transitions[t]!r} has weight {max(pre[p, t], post[p, t])}; a marked "
                        "graph has weights 1")
    for p in range(pre.shape[0]):
        ins, outs = int((post[p] > 0).sum()), int((pre[p] > 0).sum())
        if ins != 1 or outs != 1:
            return (f"place {places[p]!r} has {ins} input transitions and {outs} output "
                    "transitions; a marked graph has one of each")
    return None


@st.composite
def dense_nets(draw):
    n_p, n_t = draw(st.integers(0, 5)), draw(st.integers(0, 5))
    cell = st.sampled_from([0, 0, 0, 1, 1, 2])
    pre = np.array(draw(st.lists(st.lists(cell, min_size=n_t, max_size=n_t),
                                 min_size=n_p, max_size=n_p)), dtype=np.int64).reshape(n_p, n_t)
    post = np.array(draw(st.lists(st.lists(cell, min_size=n_t, max_size=n_t),
                                  min_size=n_p, max_size=n_p)), dtype=np.int64).reshape(n_p, n_t)
    return pre, post


@settings(max_examples=150, deadline=None)
@given(dense_nets(), st.sampled_from(["dense", "list", "coo", "csc"]))
def test_any_input_form_gives_the_same_sparse_net(mats, form):
    pre, post = mats
    n_p, n_t = pre.shape
    convert = {"dense": lambda m: m, "list": lambda m: m.tolist(), "coo": sp.coo_matrix,
               "csc": sp.csc_array}[form]
    places, transitions = [f"p{i}" for i in range(n_p)], [f"t{i}" for i in range(n_t)]
    net = PetriNet("n", places, transitions, convert(pre), convert(post), [1] * n_p)
    assert isinstance(net.pre, ArcWeights) and net.pre.dtype == np.int64
    assert net.pre.shape == net.post.shape == (n_p, n_t)
    assert net.pre.tolist() == pre.tolist() and net.post.tolist() == post.tolist()
    assert (net.incidence.toarray() == post - pre).all()
    assert net.marked_graph_violation() == dense_violation(pre, post, places, transitions)


def test_shapes_and_values_are_checked_once():
    with pytest.raises(ModelError, match=r"pre has shape \(1, 2\), expected"):
        PetriNet("n", ["p"], ["t"], [[1, 0]], [[1]], [0])
    with pytest.raises(ModelError, match="the marking has 2 entries"):
        PetriNet("n", ["p"], ["t"], [[1]], [[1]], [0, 1])
    with pytest.raises(ModelError, match="arc weight must be >= 0"):
        PetriNet("n", ["p"], ["t"], [[-1]], [[1]], [0])
    with pytest.raises(ModelError, match="2\\*\\*63 - 1"):
        PetriNet("n", ["p"], ["t"], [[1]], [[1]], [2**63])
    for big in (np.array([[2**64 - 1]], dtype=np.uint64),
                sp.csr_array(np.array([[2**64 - 1]], dtype=np.uint64))):  # before: -1, wrapped
        with pytest.raises(ModelError, match="2\\*\\*63 - 1"):
            PetriNet("n", ["p"], ["t"], big, [[1]], [0])


def test_a_net_from_an_arc_list_equals_the_net_from_its_teg():
    # ring 0 -> 1 -> 0 and a self-loop on 1; the arc list goes to the net without a TEG
    arcs = parse_edges("0 1 7/3 0\n1 0 2 1\n1 1 5 1\n")
    a, b = PetriNet.from_teg(arcs), PetriNet.from_teg(arcs.to_teg())
    assert a.pre.tolist() == b.pre.tolist() == [[0, 1], [1, 0], [0, 1]]
    assert a.post.tolist() == b.post.tolist() == [[1, 0], [0, 1], [0, 1]]
    assert a.holding == b.holding and a.marking.tolist() == b.marking.tolist() == [0, 1, 1]
    assert a.places == b.places == ["0 -> 1", "1 -> 0", "1 -> 1"]
    assert a.to_teg().places[0].holding == arcs.holding_time(0)


def test_networkx_round_trip_keeps_weights():
    net = PetriNet("n", ["p", "q"], ["a", "b"], [[2, 0], [0, 1]], [[0, 1], [3, 0]], [4, 0])
    back = from_networkx(to_networkx(net))
    assert back.pre.tolist() == net.pre.tolist() and back.post.tolist() == net.post.tolist()
    assert back.marking.tolist() == [4, 0]
