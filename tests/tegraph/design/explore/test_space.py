"""The design space of `explore`: choices, numbering, refusals; the pruning rules against
reorder's own test, on random skeletons."""

from __future__ import annotations

import itertools
from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph import InputError, Protocol, Skeleton, load_skeleton
from tegraph.analysis.reorder import reorder_ports
from tegraph.design.explore.choices import parse_clock_choice, parse_link_choice
from tegraph.design.explore.prune import DeadlockOracle, protocol_ranges
from tegraph.design.explore.space import design_space
from tests.paths import REPO
from tests.tegraph.skeleton_corpus import random_skeleton

F = Fraction
EXAMPLES = REPO / "examples"
ORDER = [Protocol.ASYN_ASYN, Protocol.ASYN_SYN, Protocol.SYN_ASYN, Protocol.SYN_SYN]


@pytest.fixture(scope="module")
def torque():
    return load_skeleton(EXAMPLES / "computed_torque.yaml")


def test_numbering_is_mixed_radix_links_first(torque):
    space = design_space(torque, {"TG.JS:qd -> TF.TT.JS:qd": ["ASYN/SYN", "SYN/SYN"],
                                  "MOD.DYN:M -> CO.JS:M": None},
                         clocks={"ctl": ["1", "2", "5/2"]})
    assert space.size == 2 * 4 * 3 and space.n_clock_variants == 3
    # Variant 7 = protocol index 2, clock index 1: first link ASYN/SYN (2 // 4 = 0),
    # second the third of all four (2 % 4 = 2: SYN/ASYN), ctl the second period.
    assert space.protocols(7) == (Protocol.ASYN_SYN, Protocol.SYN_ASYN)
    assert space.periods(7) == (F(2),)
    for v in range(space.size):
        assert space.variant_of(space.protocols(v), space.periods(v)) == v
    built = space.build(7)
    assert built.links[0].protocol is Protocol.ASYN_SYN
    assert built.links[2].protocol is Protocol.SYN_ASYN
    assert built.clocks["ctl"].period == 2 and built.clocks["obs"].period == 1
    assert space.describe(7) == ({"TG.JS:qd -> TF.TT.JS:qd": "ASYN/SYN",
                                  "MOD.DYN:M -> CO.JS:M": "SYN/ASYN"}, {"ctl": "2"})


def test_the_input_design_is_where_the_local_search_starts(torque):
    space = design_space(torque, all_links=True, clocks={"ctl": [1, 2]})
    start = space.starting_variant()
    assert space.protocols(start) == tuple(link.protocol for link in torque.links)
    assert space.periods(start) == (F(2),)


def test_reference_periods_are_the_input_groups_fastest_clock(torque):
    space = design_space(torque, all_links=True)
    # Groups of the input (examples/computed_torque.yaml): OBS.JL at 1 ms, the
    # control path at 2 ms, MOD.DYN at 6 ms.
    assert space.reference_periods == {"OBS.JL": 1, "TG.JS": 2, "TF.TT.JS": 2, "CO.JS": 2,
                                       "MOD.DYN": 6}


def test_fingerprint_changes_with_the_space(torque):
    a = design_space(torque, all_links=True)
    b = design_space(torque, all_links=True, objectives=["load"])
    c = design_space(torque, all_links=True, clocks={"ctl": [2]})
    assert len({a.fingerprint, b.fingerprint, c.fingerprint}) == 3
    assert a.fingerprint == design_space(torque, all_links=True).fingerprint


def test_parsers():
    assert parse_link_choice("A:x->B:y=ASYN/SYN, syn-syn") == ("A:x -> B:y",
                                                                ("ASYN/SYN", "syn-syn"))
    assert parse_clock_choice("T.clock=1, 7/3") == ("T.clock", ("1", "7/3"))
    assert parse_clock_choice("rtc") == ("rtc", ())


@pytest.mark.parametrize("kwargs, where, words", [
    ({"links": {"A:x -> B:y": None}}, "links[0]", "no link 'A:x -> B:y'"),
    ({"links": {"TG.JS:qd -> TF.TT.JS:qd": ["ASYN/FOO"]}}, "links[0]", "unknown protocol"),
    ({"links": {"TG.JS:qd -> TF.TT.JS:qd": []}}, "links[0]", "no protocol allowed"),
    ({"links": ["TG.JS:qd -> TF.TT.JS:qd", "TG.JS:qd->TF.TT.JS:qd"]}, "links[1]",
     "chosen twice"),
    ({"clocks": {"nope": [1]}}, "clocks.nope", "no clock 'nope'"),
    ({"clocks": {"ctl": []}}, "clocks.ctl", "no period given"),
    ({"clocks": {"ctl": [0]}}, "clocks.ctl[0]", "a period > 0"),
    ({"clocks": {"ctl": ["x"]}}, "clocks.ctl[0]", "a period > 0"),
    ({}, "links", "nothing to explore"),
    ({"all_links": True, "objectives": ["latency"]}, "objectives[0]", "needs a chain"),
    ({"all_links": True, "objectives": ["speed"]}, "objectives[0]", "unknown objective"),
    ({"all_links": True, "objectives": []}, "objectives", "no objective"),
    ({"all_links": True, "chains": [["TG.JS", "CO.JS"]]}, "chain[0][1]", "no link from"),
])
def test_refusals_name_the_parameter(torque, kwargs, where, words):
    with pytest.raises(InputError) as err:
        design_space(torque, **kwargs)
    assert err.value.where == where and words in err.value.reason


def test_a_clock_that_activates_no_task_is_refused():
    sk = Skeleton.from_dict({"clocks": {"idle": {"period": 3}},
                             "tasks": {"A": {"duration": 1, "period": 4}}})
    with pytest.raises(InputError, match="activates no task"):
        design_space(sk, clocks={"idle": [1, 2]})
    with pytest.raises(InputError, match="the clock of task 'A' is 'A.clock'"):
        design_space(sk, clocks={"A": [1, 2]})


def _assignments(space):
    return itertools.product(*(c.protocols for c in space.links))


@settings(max_examples=80, deadline=None)
@given(st.randoms(use_true_random=False))
def test_the_oracle_agrees_with_reorder_on_every_assignment(rng):
    """Rule B's terminal graph decides 'dead whatever the port order' exactly."""
    sk = Skeleton.from_dict(random_skeleton(rng, max_tasks=5))
    if not sk.links:
        return
    space = design_space(sk, all_links=True)
    oracle = DeadlockOracle(space)
    links = list(sk.links)
    verdicts = {}
    for protocols in itertools.islice(_assignments(space), 200):
        for choice, p in zip(space.links, protocols):
            links[choice.index] = links[choice.index].__class__(
                links[choice.index].writer, links[choice.index].reader, p)
        variant = Skeleton(sk.name, sk.tasks, sk.clocks, list(links), sk.threads)
        dead = not reorder_ports(variant).possible
        assert oracle.dead(protocols) == dead, protocols
        verdicts[protocols] = dead
    # Rule B: more synchronization never makes a dead assignment live.
    rank = {Protocol.ASYN_ASYN: 0, Protocol.ASYN_SYN: 1, Protocol.SYN_ASYN: 1,
            Protocol.SYN_SYN: 2}
    for a, dead_a in verdicts.items():
        if not dead_a:
            continue
        for b, dead_b in verdicts.items():
            above = all(x == y or x is Protocol.ASYN_ASYN or y is Protocol.SYN_SYN
                        for x, y in zip(a, b)) and all(rank[x] <= rank[y] for x, y in zip(a, b))
            if above:
                assert dead_b, (a, b)


@settings(max_examples=60, deadline=None)
@given(st.randoms(use_true_random=False))
def test_ranges_cover_the_space_in_order_with_the_oracle_verdict(rng):
    sk = Skeleton.from_dict(random_skeleton(rng, max_tasks=4))
    if not sk.links or len(sk.links) > 5:
        return
    space = design_space(sk, {f"{k.writer[0]}:{k.writer[1]} -> {k.reader[0]}:{k.reader[1]}":
                              rng.sample(ORDER, rng.randint(1, 4)) for k in sk.links})
    oracle = DeadlockOracle(space)
    covered = 0
    for first, count, dead in protocol_ranges(space, oracle):
        assert first == covered
        for index in range(first, first + count):
            protocols = space.protocols(index * space.n_clock_variants)
            assert oracle.dead(protocols) == dead
        covered += count
    assert covered == space.n_protocol_variants


def test_a_link_with_a_delay_is_never_made_a_rendezvous():
    # W:a -> R:a crosses processors and takes the network's 1/5; W:b -> S:b is on one
    # processor, no delay: only the first loses SYN/SYN (spec §4d: a rendezvous is one
    # event), and the report says why.
    sk = Skeleton.from_dict({"network": {"delay": "1/5"}, "tasks": {
        "W": {"duration": 1, "period": 10, "outputs": ["a", "b"], "processor": "p"},
        "R": {"duration": 1, "inputs": ["a"], "processor": "q"},
        "S": {"duration": 1, "inputs": ["b"], "processor": "p"}},
        "links": [{"from": "W:a", "to": "R:a", "protocol": "ASYN/SYN"},
                  {"from": "W:b", "to": "S:b", "protocol": "ASYN/SYN"}]})
    space = design_space(sk, all_links=True)
    a, b = space.links
    assert Protocol.SYN_SYN not in a.protocols and a.delay == Fraction(1, 5)
    assert Protocol.SYN_SYN in b.protocols and b.delay == 0
    assert space.size == 3 * 4
    for variant in range(space.size):
        space.build(variant)  # every variant is a skeleton the format accepts
    with pytest.raises(InputError, match="has a delay of 1/5 ms .* a protocol besides SYN/SYN"):
        design_space(sk, {"W:a -> R:a": ["SYN/SYN"]})
