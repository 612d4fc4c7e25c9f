"""The one platform of a skeleton (model/platform.py): processors, kinds, priorities, delays."""

from __future__ import annotations

from fractions import Fraction as F

import pytest

from tegraph.errors import InputError
from tegraph.model.platform import (
    DEFAULT_PROCESSOR,
    clock_hyperperiod,
    crosses,
    hyperperiod,
    is_automaton,
    link_delay,
    platform_of,
    processor_of,
    rate_monotonic,
)
from tegraph.model.skeleton import Skeleton
from tegraph.model.structure import Structure


def sk(tasks: dict, **extra) -> Skeleton:
    return Skeleton.from_dict({"tasks": tasks, **extra})


def test_the_default_processor_is_one_name():
    s = sk({"A": {"duration": 1}, "B": {"duration": 1, "processor": "default"}})
    # A declares nothing, B declares "default": one processor, one entry.
    assert DEFAULT_PROCESSOR == "default"
    assert processor_of(s) == {"A": "default", "B": "default"}
    (p,) = platform_of(s).processors
    assert (p.name, p.tasks) == ("default", ("A", "B"))


def test_the_example_of_4b():
    # A, B period 10; C period 5; D no clock (file order): C 4, A 3, B 2, D 1.
    s = sk({"A": {"duration": 1, "period": 10}, "B": {"duration": 1, "period": 10},
            "C": {"duration": 1, "period": 5}, "D": {"duration": 1}})
    assert platform_of(s).priority == {"A": 3, "B": 2, "C": 4, "D": 1}
    assert rate_monotonic(s) == {"A": 3, "B": 2, "C": 4, "D": 1}


def test_two_automata_on_one_processor_share_the_number_above_the_rest():
    # Groups FAST (1), SLOW (6), RTA, arm.automaton (no clock): FAST 4, SLOW 3, the
    # clockless ones 2 and 1; then each automaton gets 4 + 1 (§4b: one more than the
    # largest number on its processor).
    s = sk({"SLOW": {"duration": 1, "period": 6}, "FAST": {"duration": 1, "period": 1},
            "RTA": {"duration": 0}, "arm.automaton": {"duration": 0}})
    assert rate_monotonic(s) == {"SLOW": 3, "FAST": 4, "RTA": 5, "arm.automaton": 5}
    assert is_automaton("x.RTA") and not is_automaton("RTAx")


def test_each_processor_numbers_its_own_groups():
    # A group spanning two processors counts on both; numbers restart on each.
    s = Skeleton.from_dict({"tasks": {
        "A": {"duration": 1, "period": 4, "outputs": ["x"], "processor": "p"},
        "B": {"duration": 1, "inputs": ["x"], "processor": "q"},
        "C": {"duration": 1, "period": 2, "processor": "p"},
        "D": {"duration": 1, "period": 8, "processor": "q"}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]})
    # p: C (2) 2, group {A, B} (4) 1; q: group {A, B} (4) 2, D (8) 1.
    assert platform_of(s).priority == {"A": 1, "B": 2, "C": 2, "D": 1}


def test_declared_partial_and_none():
    s = sk({"A": {"duration": 1, "period": 10, "priority": 7, "processor": "p"},
            "B": {"duration": 1, "period": 5, "priority": 1, "processor": "p"},
            "C": {"duration": 1, "period": 10, "priority": 9, "processor": "q"},
            "D": {"duration": 1, "period": 5, "processor": "q"},
            "E": {"duration": 1, "processor": "r"}})
    p, q, r = platform_of(s).processors
    assert (p.priority_source, p.priorities, p.replaced) == ("declared", {"A": 7, "B": 1}, {})
    # q: only C declares; all or none: the proposal (D 2, C 1), C's 9 replaced.
    assert (q.priority_source, q.priorities, q.replaced) == (
        "rate-monotonic", {"C": 1, "D": 2}, {"C": 9})
    assert (r.priority_source, r.replaced) == ("rate-monotonic", {})
    assert [x.name for x in platform_of(s).replaced] == ["q"]


def test_processor_kinds():
    s = sk({"A": {"duration": 1, "processor": "can0"}, "B": {"duration": 1}},
           processors={"can0": {"preemptive": False}, "default": {}})
    plat = platform_of(s)
    assert [(p.name, p.preemptive) for p in plat.processors] == [("can0", False),
                                                                 ("default", True)]
    assert not plat.preemptive("can0") and plat.preemptive("default")
    assert plat.all_preemptive(["B"]) and not plat.all_preemptive(["A", "B"])


def test_groups_in_any_form_give_one_platform():
    s = sk({"A": {"duration": 1, "period": 3}, "B": {"duration": 1, "period": 2}})
    structure = Structure.of(s)
    assert platform_of(s) == platform_of(s, structure) == platform_of(s, structure.groups)
    with pytest.raises(InputError, match="in no group"):
        platform_of(s, [("A",)])


def test_hyperperiod_and_the_ticks_over_it():
    assert hyperperiod([F(3, 2), F(5, 4)]) == F(15, 2) and hyperperiod([]) == 1
    s = sk({"A": {"duration": 1, "period": "3/2"}, "B": {"duration": 1, "period": "5/4"},
            "C": {"duration": 1}})
    # lcm 15/2: A ticks 5 times, B 6 times over it.
    assert clock_hyperperiod(s, ["A", "B", "C"]) == (F(15, 2), 11)
    assert clock_hyperperiod(s, ["C"]) == (None, 0)


def test_a_link_delay_own_first_then_the_network_across_processors():
    s = Skeleton.from_dict({"network": {"delay": 3}, "tasks": {
        "W": {"duration": 1, "outputs": ["a", "b", "c"], "processor": "p"},
        "R": {"duration": 1, "inputs": ["a", "b"], "processor": "q"},
        "S": {"duration": 1, "inputs": ["c"]}},
        "links": [{"from": "W:a", "to": "R:a", "protocol": "ASYN/SYN"},
                  {"from": "W:b", "to": "R:b", "protocol": "ASYN/SYN", "delay": 0},
                  {"from": "W:c", "to": "S:c", "protocol": "SYN/ASYN", "delay": "1/2"}]})
    a, b, c = s.links
    assert crosses(s, a) and crosses(s, b) and crosses(s, c)
    # a: none of its own, across: the network's 3; b: its own 0 wins; c: its own 1/2.
    assert [link_delay(s, x) for x in s.links] == [3, 0, F(1, 2)]
    same = Skeleton.from_dict({"network": {"delay": 3}, "tasks": {
        "W": {"duration": 1, "outputs": ["a"]}, "R": {"duration": 1, "inputs": ["a"]}},
        "links": [{"from": "W:a", "to": "R:a", "protocol": "ASYN/SYN"}]})
    assert not crosses(same, same.links[0]) and link_delay(same, same.links[0]) == 0
