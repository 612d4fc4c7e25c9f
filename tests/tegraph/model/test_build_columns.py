"""``build_teg`` builds its graph as columns; the oracle adds it event by event and
place by place (``_element_build``, the builder before the columns). Both must give
the same graph: events, attributes, places (ends, tokens, times, kinds, names,
origins), records, arrays, and the same error for a skeleton they refuse.
"""

from __future__ import annotations

import math
import pickle
import random
from fractions import Fraction as F

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tegraph.errors import ModelError
from tegraph.model.build import build_teg
from tegraph.model.skeleton import Clock, Link, Protocol, Skeleton, Task
from tegraph.model.teg import TimeCodes, TimedEventGraph
from tests.tegraph.model._element_build import element_build
from tests.tegraph.skeleton_corpus import random_skeleton, side_by_side

SETTINGS = settings(max_examples=150, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow])


def assert_same_graph(new: TimedEventGraph, old: TimedEventGraph) -> None:
    assert new.name == old.name
    assert new.transition_names == old.transition_names
    assert [new.index(n) for n in new.transition_names] == list(range(old.n_transitions))
    assert new.transition_attrs == old.transition_attrs
    assert [list(a) for a in new.transition_attrs] == [list(a) for a in old.transition_attrs]
    assert new.places == old.places  # ends, tokens, holding, initial, kind, name
    assert [p.origin for p in new.places] == [p.origin for p in old.places]
    assert [new.place(k) for k in range(new.n_places)] == list(old.places)
    assert new.attrs == old.attrs
    a, b = new.arrays(), old.arrays()
    assert a.scale == b.scale and a.n_transitions == b.n_transitions
    for field in ("src", "dst", "tokens", "holding", "initial"):
        x, y = getattr(a, field), getattr(b, field)
        assert x.dtype == y.dtype and x.tolist() == y.tolist(), field


@st.composite
def rendezvous_skeletons(draw) -> Skeleton:
    """Skeletons heavy in SYN/SYN links: readers before their writer in the file,
    several readers of one port, a task reading its own output, a reader reading one
    port twice; with clocks shared, private and unused, threads, and durations as
    Fractions or (from code) ints."""
    n = draw(st.integers(1, 5))
    names = [f"T{i}" for i in range(n)]
    clocks = {f"c{j}": Clock(f"c{j}", F(draw(st.integers(1, 9)), draw(st.integers(1, 4))),
                             F(draw(st.integers(0, 3)), draw(st.integers(1, 3))))
              for j in range(draw(st.integers(0, 2)))}
    as_int = draw(st.integers(0, 4)) == 0
    tasks = {}
    for t in names:
        num = draw(st.integers(0, 7))
        duration = num if as_int else F(num, draw(st.integers(1, 5)))
        clock = draw(st.sampled_from([None, *sorted(clocks)]))
        tasks[t] = Task(t, duration, clock, tuple(f"i{k}" for k in range(draw(st.integers(0, 3)))),
                        tuple(f"o{k}" for k in range(draw(st.integers(0, 3)))))
    links = []
    for t in names:
        for q in tasks[t].inputs:
            writers = [(w, p) for w in names for p in tasks[w].outputs]
            if not writers or draw(st.integers(0, 5)) == 0:
                continue
            protocol = draw(st.sampled_from([Protocol.SYN_SYN, Protocol.SYN_SYN, Protocol.ASYN_SYN,
                                             Protocol.SYN_ASYN, Protocol.ASYN_ASYN]))
            links.append(Link(draw(st.sampled_from(writers)), (t, q), protocol))
    threads = []
    if n > 1 and draw(st.booleans()):
        threads.append(tuple(draw(st.permutations(names))[:draw(st.integers(1, n))]))
    return Skeleton("rdv", tasks, clocks, links, threads)


@SETTINGS
@given(rendezvous_skeletons())
def test_columns_build_the_graph_of_the_element_path(sk):
    assert_same_graph(build_teg(sk), element_build(sk))


@SETTINGS
@given(st.randoms(use_true_random=False))
def test_columns_build_the_graph_of_the_element_path_on_the_corpus_generator(rng):
    sk = Skeleton.from_dict(random_skeleton(rng))
    assert_same_graph(build_teg(sk), element_build(sk))


def test_a_benchmark_shape_is_built_alike():
    """A thousand tasks of the corpus generator, one skeleton: many groups' numbering."""
    rng = random.Random(3)
    sk = Skeleton.from_dict(side_by_side([random_skeleton(rng) for _ in range(60)]))
    assert_same_graph(build_teg(sk), element_build(sk))


@pytest.mark.parametrize("duration", [F(-1), -2])
def test_a_negative_duration_is_refused_with_the_element_path_message(duration):
    sk = Skeleton("s", {"A": Task("A", F(1), outputs=("o",)),
                        "B": Task("B", duration, inputs=("i",))},
                  links=[Link(("A", "o"), ("B", "i"), Protocol.ASYN_SYN)])
    with pytest.raises(ModelError) as new:
        build_teg(sk)
    with pytest.raises(ModelError) as old:
        element_build(sk)
    assert str(new.value) == str(old.value) == "place B.compute -> B.read:i: " \
        f"holding must be >= 0, got {duration}"


def test_two_links_into_one_input_name_the_missing_event_as_before():
    """Invalid (validation refuses it), but built from code: the ASYN/SYN place's
    reader is the writer's rendezvous, its read event does not exist."""
    sk = Skeleton("s", {"A": Task("A", F(1), outputs=("o",)), "B": Task("B", F(1), inputs=("i",))},
                  links=[Link(("A", "o"), ("B", "i"), Protocol.SYN_SYN),
                         Link(("A", "o"), ("B", "i"), Protocol.ASYN_SYN)])
    with pytest.raises(ModelError) as new:
        build_teg(sk)
    with pytest.raises(ModelError) as old:
        element_build(sk)
    assert str(new.value) == str(old.value)


# ------------------------------------------------------------------ the columns alone

def test_add_transitions_refuses_what_add_transition_refuses():
    g = TimedEventGraph()
    g.add_transition("a")
    for names in (["b", "a"], ["b", "b"], ["b", ""], ["b", 3]):
        with pytest.raises(ModelError):
            TimedEventGraph().add_transitions(["a"], [{}]) or g.add_transitions(
                names, [{}] * len(names))
        assert g.transition_names[0] == "a"


def test_add_place_columns_checks_like_add_place():
    for src, dst, tokens, holding in [([0], [2], [0], F(1)), ([0], [0], [-1], F(1)),
                                      ([0], [0], [0], F(-1)), ([-1], [0], [0], F(0))]:
        g, h = TimedEventGraph(), TimedEventGraph()
        for x in (g, h):
            x.add_transitions(["a", "b"], [{}, {}])
        with pytest.raises(ModelError) as one:
            g.add_place_columns(src, dst, tokens, TimeCodes([holding], [0]),
                                TimeCodes([F(0)], [0]), [""], [None])
        with pytest.raises(ModelError) as other:
            h.add_place(src[0], dst[0], tokens[0], holding)
        assert str(one.value) == str(other.value)


def test_places_added_one_by_one_after_columns_share_the_time_table():
    g = TimedEventGraph()
    g.add_transitions(["a", "b"], [{}, {}])
    g.add_place_columns(np.array([0, 1]), np.array([1, 0]), np.array([0, 1]),
                        TimeCodes([F(1, 2), F(1, 2)], [0, 1]), TimeCodes([F(0)], [0, 0]),
                        ["x", "y"], [None, None])
    g.add_place("a", "a", 1, "1/3")
    g.add_place("b", "b", 1, F(1, 2))
    copy = pickle.loads(pickle.dumps(g))
    copy.add_place("a", "b", 0, "1/3")
    for x in (g, copy):
        a = x.arrays()
        assert a.scale == 6
    assert g.arrays().holding.tolist() == [3, 3, 2, 3]
    assert copy.arrays().holding.tolist() == [3, 3, 2, 3, 2]
    assert [str(p.holding) for p in copy.places] == ["1/2", "1/2", "1/3", "1/2", "1/3"]


def test_columns_added_twice_read_as_places_added_one_by_one():
    g, h = TimedEventGraph(), TimedEventGraph()
    for x in (g, h):
        x.add_transitions(["a", "b"], [{}, {}])
    rows = [(0, 1, 0, F(1, 2), F(0)), (1, 0, 1, F(3), F(1)), (0, 0, 2, F(2, 3), F(0))]
    g.add_place_columns([0, 1], [1, 0], [0, 1], TimeCodes([F(1, 2), F(3)], [0, 1]),
                        TimeCodes([F(0), F(1)], [0, 1]), ["", ""], [None, None])
    g.add_place_columns([0], [0], [2], TimeCodes([F(2, 3)], [0]), TimeCodes([F(0)], [0]),
                        [""], [None])
    for s, d, m, hold, init in rows:
        h.add_place(s, d, m, hold, init)
    assert g.places == h.places
    assert g.arrays().holding.tolist() == h.arrays().holding.tolist() == [3, 18, 4]
    assert g.arrays().initial.tolist() == [0, 6, 0]


times = st.fractions(min_value=0, max_denominator=10**6) | st.builds(
    F, st.integers(0, 2**80), st.integers(1, 2**70))


@SETTINGS
@given(st.lists(st.tuples(times, times, st.integers(0, 3)), min_size=1, max_size=12))
def test_scaled_times_are_the_exact_products(rows):
    """arrays() and scaled_by_part() scale in int64 when every product fits, else in
    Python ints: either way each value is ``time * scale`` exactly, and the dtype is
    int64 exactly when every value of the column lies below 2**62."""
    g = TimedEventGraph()
    g.add_transition("a")
    for holding, initial, _ in rows:
        g.add_place("a", "a", 1, holding, initial)
    a = g.arrays()
    for column, k in ((a.holding, 0), (a.initial, 1)):
        exact = [row[k] * a.scale for row in rows]
        assert all(v.denominator == 1 for v in exact)
        assert column.tolist() == [int(v) for v in exact]
        assert (column.dtype == np.int64) == all(abs(v) < 2**62 for v in exact)
    part = np.array([row[2] for row in rows])
    holding, initial, scales = g.scaled_by_part(part, 4)
    for column, k in ((holding, 0), (initial, 1)):
        exact = [row[k] * scales[row[2]] for row in rows]
        assert column.tolist() == [int(v) for v in exact]
        assert (column.dtype == np.int64) == all(abs(v) < 2**62 for v in exact)
    for p in range(4):
        mine = [t for row in rows if row[2] == p for t in row[:2]]
        # math.lcm in Python ints: numpy's lcm reads a denominator of 2**63 + 1 as a float.
        assert scales[p] == math.lcm(*(t.denominator for t in mine))


def test_columns_of_different_lengths_are_refused():
    g = TimedEventGraph()
    with pytest.raises(ModelError, match="2 event names but 1 attribute dicts"):
        g.add_transitions(["a", "b"], [{}])
    g.add_transitions(["a", "b"], [{}, {}])
    with pytest.raises(ModelError, match="different lengths"):
        g.add_place_columns([0, 1], [1], [0, 0], TimeCodes([F(0)], [0, 0]),
                            TimeCodes([F(0)], [0, 0]), ["", ""], [None, None])
    assert g.n_transitions == 2 and g.n_places == 0
