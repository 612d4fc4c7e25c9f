"""The structure of a skeleton: groups (spec §4), clocks, design periods, links by port."""

from __future__ import annotations

import random
from fractions import Fraction as F

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph import load_skeleton
from tegraph.model.build import build_teg
from tegraph.model.skeleton import Skeleton
from tegraph.model.structure import Structure, design_period
from tests.paths import REPO
from tests.tegraph.skeleton_corpus import random_skeleton

EXAMPLES = REPO / "examples"


def _weak_parts_of_the_teg(sk: Skeleton) -> tuple[list[tuple[str, ...]], list[int]]:
    """The groups by another algorithm on another graph: union-find over the places of
    the timed event graph (spec §4's own definition: weakly connected parts), numbered
    by their first task in the file; and each event's group (-1: a part with no task)."""
    teg = build_teg(sk)
    parent = list(range(teg.n_transitions))

    def find(e: int) -> int:
        while parent[e] != e:
            e = parent[e]
        return e

    for place in teg.places:
        parent[find(place.src)] = find(place.dst)
    chains = teg.attrs["chains"]
    number: dict[int, int] = {}
    groups: list[list[str]] = []
    for task in sk.tasks:
        root = find(chains[task][0])
        if root not in number:
            number[root] = len(groups)
            groups.append([])
        groups[number[root]].append(task)
    return [tuple(g) for g in groups], [number.get(find(e), -1) for e in range(teg.n_transitions)]


@settings(max_examples=150, deadline=None)
@given(st.randoms(use_true_random=False))
def test_groups_are_the_weak_parts_of_the_timed_event_graph(rng: random.Random) -> None:
    sk = Skeleton.from_dict(random_skeleton(rng))
    groups, event_group = _weak_parts_of_the_teg(sk)
    s = Structure.of(sk)
    assert list(s.groups) == groups
    assert s.group_of_event(build_teg(sk)).tolist() == event_group
    assert all(s.group_of[t] == g for g, ts in enumerate(s.groups) for t in ts)


def test_the_fixed_corpus_agrees_too() -> None:
    for seed in range(200):
        sk = Skeleton.from_dict(random_skeleton(random.Random(seed)))
        groups, event_group = _weak_parts_of_the_teg(sk)
        s = Structure.of(sk)
        assert list(s.groups) == groups, seed
        assert s.group_of_event(build_teg(sk)).tolist() == event_group, seed


@pytest.mark.parametrize("name", sorted(p.name for p in EXAMPLES.glob("*.yaml")))
def test_the_examples_agree_too(name: str) -> None:
    sk = load_skeleton(EXAMPLES / name)
    groups, event_group = _weak_parts_of_the_teg(sk)
    s = Structure.of(sk)
    assert list(s.groups) == groups
    assert s.group_of_event(build_teg(sk)).tolist() == event_group


def test_what_joins_tasks_and_what_does_not() -> None:
    # A-B: ASYN/SYN (joins); B-C: ASYN/ASYN (does not); C-D: SYN/SYN (joins);
    # E and G share the clock k (joins); F and H a thread (joins); "spare" drives nothing.
    sk = Skeleton.from_dict({
        "clocks": {"k": {"period": 6}, "spare": {"period": 1}},
        "tasks": {
            "A": {"duration": 1, "period": 4, "outputs": ["x"]},
            "B": {"duration": 1, "inputs": ["x"], "outputs": ["y"]},
            "C": {"duration": 1, "period": 2, "inputs": ["y"], "outputs": ["z"]},
            "D": {"duration": 1, "inputs": ["z"]},
            "E": {"duration": 1, "clock": "k"},
            "F": {"duration": 1},
            "G": {"duration": 1, "clock": "k"},
            "H": {"duration": 1}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"},
                  {"from": "B:y", "to": "C:y", "protocol": "ASYN/ASYN"},
                  {"from": "C:z", "to": "D:z", "protocol": "SYN/SYN"}],
        "threads": [["F", "H"]]})
    s = Structure.of(sk)
    assert s.groups == (("A", "B"), ("C", "D"), ("E", "G"), ("F", "H"))
    assert dict(s.group_of) == {"A": 0, "B": 0, "C": 1, "D": 1, "E": 2, "G": 2, "F": 3, "H": 3}
    assert s.clocks == (("A.clock",), ("C.clock",), ("k",), ())
    assert dict(s.group_of_clock) == {"A.clock": 0, "C.clock": 1, "k": 2}
    assert s.periods == (F(4), F(2), F(6), None)


def test_design_period_is_the_fastest_clock() -> None:
    # Two clocks in one group (a Rule 3 finding): the faster one, 3/2, sets the design period.
    sk = Skeleton.from_dict({"tasks": {
        "A": {"duration": 1, "period": 5, "outputs": ["x"]},
        "B": {"duration": 1, "period": "3/2", "inputs": ["x"]}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]})
    assert Structure.of(sk).periods == (F(3, 2),)
    assert design_period(sk, ["A"]) == F(5)


def test_clocks_of_a_group_in_the_order_their_tasks_come() -> None:
    # The clocks section lists a before b, but X (on b) comes before Y (on a): b first,
    # as the report's groups list them.
    sk = Skeleton.from_dict({"clocks": {"a": {"period": 2}, "b": {"period": 3}}, "tasks": {
        "X": {"duration": 1, "clock": "b", "outputs": ["o"]},
        "Y": {"duration": 1, "clock": "a", "inputs": ["i"]}},
        "links": [{"from": "X:o", "to": "Y:i", "protocol": "ASYN/SYN"}]})
    s = Structure.of(sk)
    assert s.clocks == (("b", "a"),) and s.periods == (F(2),)


def test_links_by_port_keep_file_order() -> None:
    # One output read by two tasks: both links under the writer's port, in file order.
    sk = Skeleton.from_dict({"tasks": {
        "W": {"duration": 1, "period": 2, "outputs": ["o"]},
        "R1": {"duration": 1, "inputs": ["i"]}, "R2": {"duration": 1, "inputs": ["i"]}},
        "links": [{"from": "W:o", "to": "R2:i", "protocol": "ASYN/ASYN"},
                  {"from": "W:o", "to": "R1:i", "protocol": "ASYN/SYN"}]})
    s = Structure.of(sk)
    assert [x.reader for x in s.by_writer["W", "o"]] == [("R2", "i"), ("R1", "i")]
    assert [x.writer for x in s.by_reader["R1", "i"]] == [("W", "o")]
    assert ("W", "o") not in s.by_reader
    assert s.groups == (("W", "R1"), ("R2",))


def test_a_skeleton_without_tasks_has_no_group() -> None:
    s = Structure.of(Skeleton("empty", {}))
    assert s.groups == () and s.periods == () and dict(s.group_of) == {}
