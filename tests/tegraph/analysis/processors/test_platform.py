"""Processors and priorities of §4b (declared, or the rate-monotonic proposal)."""

from __future__ import annotations

import pytest

from tegraph.analysis.analyze import analyze_skeleton
from tegraph.analysis.processors import is_automaton, platform_of
from tegraph.model.skeleton import Skeleton


def platform(data: dict):
    sk = Skeleton.from_dict(data)
    return platform_of(sk, analyze_skeleton(sk).groups)


def test_section_4b_example():
    # A and B period 10, C period 5, D no clock, in this file order: C is the
    # most urgent (5), then A (10, earlier in the file), B (10), D (no clock):
    # numbers from 1 (least urgent): C 4, A 3, B 2, D 1.
    p = platform({"tasks": {"A": {"duration": 1, "period": 10},
                            "B": {"duration": 1, "period": 10},
                            "C": {"duration": 1, "period": 5},
                            "D": {"duration": 1}}})
    assert p.priority == {"A": 3, "B": 2, "C": 4, "D": 1}
    assert [(i.name, i.tasks, i.priority_source) for i in p.processors] == [
        ("default", ("A", "B", "C", "D"), "rate-monotonic")]


@pytest.mark.parametrize("name", ["RTA", "automaton", "arm.rta", "X.Automaton", "a.b.RTA"])
def test_automaton_gets_one_more_than_the_largest(name):
    # Groups: F (1 ms) 3, S (6 ms) 2, and the automaton's own clockless group 1;
    # the automaton then gets 3 + 1 = 4.
    p = platform({"tasks": {"S": {"duration": 1, "period": 6}, "F": {"duration": 1, "period": 1},
                            name: {"duration": 0}}})
    assert p.priority == {"S": 2, "F": 3, name: 4}


@pytest.mark.parametrize("name", ["PARTA", "rta2", "automatons", "RTA.x"])
def test_not_the_automaton(name):
    assert not is_automaton(name)


def test_group_shares_its_number_and_design_period_is_its_smallest_clock():
    # Group 1: P (10 ms) -> Q (ASYN/SYN) and R with a 4 ms clock reading P too:
    # design period min(10, 4) = 4. Group 2: T (5 ms). So group 1 (4) is more
    # urgent than T (5): P, Q, R get 2, T gets 1.
    p = platform({"tasks": {"T": {"duration": 1, "period": 5},
                            "P": {"duration": 1, "period": 10, "outputs": ["a", "b"]},
                            "Q": {"duration": 1, "inputs": ["a"]},
                            "R": {"duration": 1, "period": 4, "inputs": ["b"]}},
                  "links": [{"from": "P:a", "to": "Q:a", "protocol": "ASYN/SYN"},
                            {"from": "P:b", "to": "R:b", "protocol": "ASYN/SYN"}]})
    assert p.priority == {"T": 1, "P": 2, "Q": 2, "R": 2}


def test_groups_counted_per_processor_whole_groups_wherever_they_run():
    # Group P (10 ms) -> Q spans cpu0 (P) and cpu1 (Q). On cpu1, Q's group (design
    # period 10, its clock being on cpu0) is ranked against U (20 ms): Q 2, U 1.
    # On cpu0, P alone: 1. Processors in the order of their first task.
    p = platform({"tasks": {"P": {"duration": 1, "period": 10, "outputs": ["a"],
                                  "processor": "cpu0"},
                            "U": {"duration": 1, "period": 20, "processor": "cpu1"},
                            "Q": {"duration": 1, "inputs": ["a"], "processor": "cpu1"}},
                  "links": [{"from": "P:a", "to": "Q:a", "protocol": "ASYN/SYN"}]})
    assert p.priority == {"P": 1, "U": 1, "Q": 2}
    assert [i.name for i in p.processors] == ["cpu0", "cpu1"]


def test_declared_only_when_every_task_of_the_processor_declares():
    # cpu0: both declare -> declared (even against rate-monotonic order);
    # default: one of two declares -> the proposal for both.
    p = platform({"tasks": {"A": {"duration": 1, "period": 10, "priority": 7, "processor": "cpu0"},
                            "B": {"duration": 1, "period": 5, "priority": 3, "processor": "cpu0"},
                            "C": {"duration": 1, "period": 10, "priority": 9},
                            "D": {"duration": 1, "period": 5}}})
    assert p.priority == {"A": 7, "B": 3, "C": 1, "D": 2}
    assert {i.name: i.priority_source for i in p.processors} == {
        "cpu0": "declared", "default": "rate-monotonic"}
