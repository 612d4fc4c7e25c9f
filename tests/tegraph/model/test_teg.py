"""Tests of tegraph.teg: the general timed event graph, its matrices and dynamics.

Every expected value is derived by hand (in comments) or by an independent
brute-force implementation of spec §3 written here with plain Fractions.
"""

from __future__ import annotations

import itertools
from fractions import Fraction as F
from functools import cache

import networkx as nx
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from maxplus.scalar import EPS
from tegraph.errors import ModelError, NotLiveError
from tegraph.model.teg import Place, TimedEventGraph


def make(names, places):
    """A TEG from event names and (src, dst, tokens, holding, initial) tuples."""
    g = TimedEventGraph()
    for n in names:
        g.add_transition(n)
    for s, d, m, h, a in places:
        g.add_place(s, d, tokens=m, holding=h, initial=a)
    return g


# --------------------------------------------------------------------------- incidence
# The paper's Figure 8 (section 4), written as the paper numbers it. Reading
# the rows of its W (+1: the place is an output of the transition, -1: an input):
#   p1 = t2 -> t1 (marked),  p2 = t1 -> t2        the real-time clock's circuit
#   p3 = t1 -> t3                                  clock activates the task
#   p4 = t6 -> t3 (marked)                         return place of the task
#   p5 = t3 -> t4, p6 = t4 -> t5, p7 = t5 -> t6    activate, read, compute, write
PAPER_W = [
    [-1, 1, 0, 0, 0, 0],
    [1, -1, 0, 0, 0, 0],
    [1, 0, -1, 0, 0, 0],
    [0, 0, -1, 0, 0, 1],
    [0, 0, 1, -1, 0, 0],
    [0, 0, 0, 1, -1, 0],
    [0, 0, 0, 0, 1, -1],
]
PAPER_M0 = [1, 0, 0, 1, 0, 0, 0]
FIG8_PLACES = [("t2", "t1", 1), ("t1", "t2", 0), ("t1", "t3", 0), ("t6", "t3", 1),
               ("t3", "t4", 0), ("t4", "t5", 0), ("t5", "t6", 0)]


def test_incidence_matrix_is_the_papers_w_for_figure_8():
    g = make([f"t{i}" for i in range(1, 7)], [(s, d, m, 0, 0) for s, d, m in FIG8_PLACES])
    W = g.incidence_matrix()
    assert W.shape == (7, 6)
    assert W.toarray().tolist() == PAPER_W
    assert g.arrays().tokens.tolist() == PAPER_M0
    # Every directed circuit is a p-invariant: its indicator v satisfies W^T v = 0
    # (the paper's equation (1)); s1 = {p1, p2} and s2 = {p4, p5, p6, p7}.
    for circuit in ([0, 1], [3, 4, 5, 6]):
        v = np.zeros(7, dtype=int)
        v[circuit] = 1
        assert (W.T @ v).tolist() == [0] * 6


def test_incidence_self_loop_row_is_zero_and_parallel_places_have_own_rows():
    g = make(["a", "b"], [("a", "a", 1, 2, 0), ("a", "b", 0, 0, 0), ("a", "b", 1, 0, 0)])
    assert g.incidence_matrix().toarray().tolist() == [[0, 0], [1, -1], [1, -1]]
    assert g.incidence_matrix().nnz == 4  # the self-loop stores no explicit zero


# --------------------------------------------------------------------------- validation
@pytest.mark.parametrize("kwargs, words", [
    ({"src": "a", "dst": "zz"}, ["unknown event 'zz'", "a -> zz"]),
    ({"src": 5, "dst": "a"}, ["out of range"]),
    ({"src": "a", "dst": "b", "tokens": -1}, ["tokens", "-1", "a -> b"]),
    ({"src": "a", "dst": "b", "tokens": 1.5}, ["tokens", "1.5"]),
    ({"src": "a", "dst": "b", "tokens": True}, ["tokens"]),
    ({"src": "a", "dst": "b", "holding": -2}, ["holding", ">= 0", "a -> b"]),
    ({"src": "a", "dst": "b", "initial": "-1/3"}, ["initial", "-1/3"]),
    ({"src": "a", "dst": "b", "holding": "ten", "name": "P9"}, ["P9", "ten"]),
    ({"src": "a", "dst": "b", "holding": float("nan")}, ["NaN"]),
])
def test_add_place_refuses_bad_input_naming_the_place(kwargs, words):
    g = make(["a", "b"], [])
    with pytest.raises(ModelError) as info:
        g.add_place(**kwargs)
    for w in words:
        assert w in str(info.value)
    assert g.n_places == 0


def test_add_transition_refuses_duplicates_and_non_strings():
    g = make(["a"], [])
    with pytest.raises(ModelError, match="duplicate event name"):
        g.add_transition("a")
    with pytest.raises(ModelError):
        g.add_transition("")
    with pytest.raises(ModelError, match="unknown event"):
        g.index("b")
    assert g.index("a") == 0 and g.n_transitions == 1


def test_place_fields_accessors_and_exact_parsing():
    g = make(["a", "b"], [])
    i = g.add_place(1, "a", tokens=2, holding=0.1, initial="7/3", kind="k", origin={"x": 1})
    assert i == 0 and g.n_places == 1 and g.transition_names == ("a", "b")
    assert g.places[0] == Place(1, 0, 2, F(1, 10), F(7, 3), "k", "b -> a", {"x": 1})
    hash(g.places[0])  # the dict origin stays out of the hash


def test_arrays_scale_and_object_fallback():
    g = make(["a", "b"], [("a", "b", 0, "1/4", 0), ("b", "a", 3, "2/3", "1/2")])
    a = g.arrays()
    # lcm(4, 3, 2) = 12: 1/4 -> 3, 2/3 -> 8, 1/2 -> 6.
    assert a.scale == 12 and a.holding.tolist() == [3, 8] and a.initial.tolist() == [0, 6]
    assert a.holding.dtype == np.int64 and a.tokens.tolist() == [0, 3]
    assert a.src.tolist() == [0, 1] and a.dst.tolist() == [1, 0] and a.n_transitions == 2
    big = make(["a"], [("a", "a", 1, 2**70, 0)]).arrays()
    assert big.holding.dtype == object and big.holding.tolist() == [2**70]
    g.add_place("a", "a", 1, 1)  # the cache is refreshed after a change
    assert g.arrays().holding.tolist() == [3, 8, 12]


times = st.fractions(min_value=0, max_value=2**70, max_denominator=50)


@given(st.lists(st.tuples(times, times, st.booleans()), max_size=12))
def test_arrays_scale_each_place_exactly_shared_objects_or_not(rows):
    # arrays() scales each distinct time object once: places sharing one object
    # (`share`: the previous place's holding object) or holding equal values in
    # distinct objects all get t * scale, checked place by place against the Place.
    g = make(["a"], [])
    previous = None
    for holding, initial, share in rows:
        g.add_place("a", "a", 1, previous if share and previous is not None else holding, initial)
        previous = g.places[-1].holding
    a = g.arrays()
    assert a.holding.tolist() == [p.holding * a.scale for p in g.places]
    assert a.initial.tolist() == [p.initial * a.scale for p in g.places]
    assert all(p.holding * a.scale % 1 == 0 for p in g.places)
    wide = max([abs(v) for v in a.holding.tolist() + a.initial.tolist()], default=0) >= 2**62
    assert (a.holding.dtype == object) == (max(map(abs, a.holding.tolist()), default=0) >= 2**62)
    assert wide or (a.holding.dtype == a.initial.dtype == np.int64)


# --------------------------------------------------------------------------- state equations
def test_state_equations_hand_example():
    # Places: a->b (0 tok, 2), a->b (0 tok, 5: the max wins), b->c (1 tok, 1),
    # c->a (2 tok, 3/2), c->a (2 tok, 1/2). So A0[b][a] = 5, A1[c][b] = 1,
    # A2[a][c] = 3/2, everything else EPS.
    g = make(["a", "b", "c"], [("a", "b", 0, 2, 0), ("a", "b", 0, 5, 0), ("b", "c", 1, 1, 0),
                               ("c", "a", 2, "3/2", 0), ("c", "a", 2, "1/2", 0)])
    A = g.state_equations()
    assert len(A) == 3
    e = EPS
    assert A[0].tolist() == [[e, e, e], [F(5), e, e], [e, e, e]]
    assert A[1].tolist() == [[e, e, e], [e, e, e], [e, F(1), e]]
    assert A[2].tolist() == [[e, e, F(3, 2)], [e, e, e], [e, e, e]]
    # For k > 2 they reproduce the simulation: x(3) = A0 x(3) + A1 x(2) + A2 x(1).
    x = g.simulate(3).fractions()
    for i in range(3):
        terms = [A[m][i][j] + x[2 - m][j] for m in range(3) for j in range(3)]
        assert x[2][i] == max(terms)


def test_state_equations_without_places():
    A = make(["a"], []).state_equations()
    assert len(A) == 1 and A[0].tolist() == [[EPS]]


# --------------------------------------------------------------------------- networkx
def test_networkx_round_trip_keeps_everything():
    g = make(["x", "y", "z"], [("x", "y", 0, "1/3", 0), ("y", "x", 1, 2, "1/2"),
                               ("x", "y", 2, 0, 0), ("z", "z", 1, 4, 1)])
    g.add_place("z", "x", kind="chain", name="P", origin={"task": "T", "n": (1, 2)})
    g.transition_attrs[0]["role"] = "read"
    g.attrs["unit"] = "ms"
    G = g.to_networkx()
    assert isinstance(G, nx.MultiDiGraph) and G.number_of_edges() == 5
    assert G.edges["y", "x", 1] == {"tokens": 1, "holding": F(2), "initial": F(1, 2), "kind": "",
                                        "name": "y -> x", "origin": None}
    h = TimedEventGraph.from_networkx(G)
    assert h.transition_names == g.transition_names
    assert h.places == g.places
    assert h.transition_attrs == g.transition_attrs and h.attrs == g.attrs
    assert h.name == g.name


def test_from_networkx_defaults_and_lenient_numbers():
    G = nx.MultiDiGraph()
    G.add_edge("a", "b", holding=0.1)
    G.add_edge("b", "a", tokens=1, holding="7/3", initial=2)
    G.add_edge(3, "a", holding=F(1, 2), tokens=1.0)
    g = TimedEventGraph.from_networkx(G)
    assert g.transition_names == ("a", "b", "3")
    by_name = {p.name: p for p in g.places}
    assert by_name["a -> b"] == Place(0, 1, 0, F(1, 10), F(0), "", "a -> b")
    assert by_name["b -> a"].holding == F(7, 3) and by_name["b -> a"].initial == 2
    assert by_name["3 -> a"].tokens == 1
    bad = nx.DiGraph()
    bad.add_edge("a", "b", tokens=-1)
    with pytest.raises(ModelError, match="tokens"):
        TimedEventGraph.from_networkx(bad)


# --------------------------------------------------------------------------- simulate by hand
def test_simulate_clock_and_task_by_hand():
    # tick: self-loop 1 token, holding 4, available at 1 -> x_tick(k) = 1 + 4(k-1).
    # run: x_run(k) = max(x_tick(k), x_run(k-1) + 3) (k > 1), x_run(1) = max(x_tick(1), 0) = 1.
    # As 3 < 4 the task keeps pace: x_run(k) = 1 + 4(k-1).
    g = make(["tick", "run"], [("tick", "tick", 1, 4, 1), ("tick", "run", 0, 0, 0),
                               ("run", "run", 1, 3, 0)])
    d = g.simulate(5)
    assert d["tick"] == [F(1 + 4 * (k - 1)) for k in range(1, 6)]
    assert d["run"] == [F(1 + 4 * (k - 1)) for k in range(1, 6)]
    # With duration 5 > 4: x_run(k) = 1 + 5(k-1) (1, 6, 11, 16, 21).
    g2 = make(["tick", "run"], [("tick", "tick", 1, 4, 1), ("tick", "run", 0, 0, 0),
                                ("run", "run", 1, 5, 0)])
    assert g2.simulate(5)["run"] == [F(1), F(6), F(11), F(16), F(21)]


def test_simulate_two_tokens_initial_times_and_sources():
    # src has no input place: fires at 0 always. a <- b place with 2 tokens,
    # holding 1, available at 3/2; b <- a with 0 tokens, holding 1/2; a <- src (0, 0).
    # x_a(1) = max(0, 3/2) = 3/2, x_b(1) = 2, x_a(2) = max(0, 3/2) = 3/2, x_b(2) = 2,
    # x_a(3) = x_b(1) + 1 = 3, x_b(3) = 7/2, x_a(4) = x_b(2) + 1 = 3, x_a(5) = 9/2.
    g = make(["a", "b", "src"], [("b", "a", 2, 1, "3/2"), ("a", "b", 0, "1/2", 0),
                                 ("src", "a", 0, 0, 0)])
    d = g.simulate(5)
    assert d["src"] == [F(0)] * 5
    assert d["a"] == [F(3, 2), F(3, 2), F(3), F(3), F(9, 2)]
    assert d["b"] == [F(2), F(2), F(7, 2), F(7, 2), F(5)]
    assert d.to_dict()["a"] == d[0] and d.fractions()[2, 1] == F(7, 2)
    assert d.times.shape == (5, 3) and g.simulate(0).times.shape == (0, 3)


def test_simulate_huge_times_stay_exact():
    # x(k) = (k-1) * (2**70 + 1/3), far beyond int64 after scaling by 3.
    h = F(2**70) + F(1, 3)
    d = make(["a"], [("a", "a", 1, h, 0)]).simulate(4)
    assert d.times.dtype == object and d["a"] == [(k - 1) * h for k in range(1, 5)]


def test_simulate_refuses_a_token_free_circuit_naming_it():
    g = make(["a", "b", "c", "d"], [("a", "b", 0, 1, 0), ("b", "c", 0, 1, 0),
                                    ("c", "b", 0, 1, 0), ("d", "a", 1, 0, 0),
                                    ("c", "d", 0, 0, 0)])
    with pytest.raises(NotLiveError) as info:
        g.simulate(2)
    assert sorted(info.value.circuit) == ["b", "c"]
    loop = make(["a", "b"], [("a", "a", 0, 1, 0), ("a", "b", 0, 0, 0)])
    with pytest.raises(NotLiveError) as info:
        loop.simulate(1)
    assert info.value.circuit == ["a"]
    with pytest.raises(ValueError):
        loop.simulate(-1)


# --------------------------------------------------------------------------- brute force
def brute_force(n, places, n_firings):
    """Spec §3 verbatim: recursion with memoization, plain Fractions."""
    into = [[p for p in places if p[1] == e] for e in range(n)]

    @cache
    def x(e, k):
        vals = [x(s, k - m) + h if k > m else a for s, _, m, h, a in into[e]]
        return max(vals, default=F(0))

    return [[x(e, k) for e in range(n)] for k in range(1, n_firings + 1)]


times = st.fractions(min_value=0, max_value=6, max_denominator=4)


@st.composite
def live_tegs(draw):
    """Random small TEGs where every circuit carries a token.

    0-token places go forward in a random order of the events, so the 0-token
    subgraph is acyclic; every other place has 1 to 3 tokens and any ends.
    """
    n = draw(st.integers(1, 7))
    order = draw(st.permutations(range(n)))  # order[r]: the event of rank r
    places = []
    for _ in range(draw(st.integers(0, 14))):
        if n > 1 and draw(st.booleans()):
            r = sorted(draw(st.lists(st.integers(0, n - 1), min_size=2, max_size=2, unique=True)))
            s, d, m = order[r[0]], order[r[1]], 0
        else:
            s, d, m = draw(st.integers(0, n - 1)), draw(st.integers(0, n - 1)), draw(
                st.integers(1, 3))
        places.append((s, d, m, draw(times), draw(times)))
    return n, places


@given(live_tegs(), st.integers(0, 7), st.sampled_from([1, 1, 2**61 + 1]))
def test_simulate_equals_brute_force(case, n_firings, factor):
    # factor 2**61 + 1 pushes the scaled times past int64: the object-dtype path.
    n, places = case
    places = [(s, d, m, h * factor, a * factor) for s, d, m, h, a in places]
    g = make([f"e{i}" for i in range(n)], places)
    assert g.simulate(n_firings).fractions().tolist() == brute_force(n, places, n_firings)


@given(st.integers(1, 5), st.lists(st.tuples(st.integers(0, 4), st.integers(0, 4),
                                             st.integers(0, 1)), max_size=10))
def test_not_live_exactly_when_a_token_free_circuit_exists(n, raw):
    places = [(s % n, d % n, m, 1, 0) for s, d, m in raw]
    g = make([f"e{i}" for i in range(n)], places)
    zero = nx.DiGraph()
    zero.add_nodes_from(range(n))
    zero.add_edges_from((s, d) for s, d, m, _, _ in places if m == 0)
    if nx.is_directed_acyclic_graph(zero):
        assert len(g.simulate(3).times) == 3
    else:
        with pytest.raises(NotLiveError) as info:
            g.simulate(3)
        c = [g.index(e) for e in info.value.circuit]
        # The named events form a circuit of 0-token places, each event once.
        assert len(set(c)) == len(c)
        assert all(zero.has_edge(c[i], c[(i + 1) % len(c)]) for i in range(len(c)))


@given(live_tegs())
def test_circuits_are_p_invariants(case):
    n, places = case
    g = make([f"e{i}" for i in range(n)], places)
    W = g.incidence_matrix().toarray()
    first = {}
    for i, (s, d, *_) in enumerate(places):
        first.setdefault((s, d), i)
    for cycle in itertools.islice(nx.simple_cycles(nx.DiGraph(list(first))), 10):
        v = np.zeros(len(places), dtype=int)
        for j, u in enumerate(cycle):
            v[first[(u, cycle[(j + 1) % len(cycle)])]] = 1
        assert not (W.T @ v).any()
