"""The advice's shortcuts answer what the general paths answer.

Each shortcut of :mod:`tegraph.design.rules` (a Rule 1 finding's first
candidate told at once, a task's synchronizations counted from its links as
they are, ...) is compared here with the general path it stands in for, on
random skeletons (hypothesis), the corpus, generated chains and groups, and
cases by hand where the shortcut must step aside.
"""

from __future__ import annotations

import importlib.util
import itertools
import random

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tegraph.design.rules import check_rules
from tegraph.design.rules.advice import Advisor
from tegraph.design.rules.candidates import CANDIDATE_LIMIT, Edits
from tegraph.design.rules.findings import FindingKind
from tegraph.model.skeleton import Protocol, Skeleton
from tests.paths import REPO
from tests.tegraph.skeleton_corpus import random_skeleton

_spec = importlib.util.spec_from_file_location(
    "generate_skeleton", REPO / "benchmarks" / "generate_skeleton.py")
assert _spec is not None and _spec.loader is not None
generate_skeleton = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(generate_skeleton)


def same(a: Edits, b: Edits) -> bool:
    """The same edits: the same links (objects) and protocols in order, drops, adds, words."""
    return (len(a.protocol) == len(b.protocol)
            and all(x is y and p is q for (x, p), (y, q) in zip(a.protocol, b.protocol))
            and (a.drop, a.add, a.kept, a.size()) == (b.drop, b.add, b.kept, b.size()))


def advisor_of(sk: Skeleton) -> tuple[Advisor, list]:
    findings = [f for f in check_rules(sk) if f.rule < 4]
    return Advisor(sk, findings), findings


def first_kept_agrees(sk: Skeleton) -> int:
    """Each Rule 1 finding's first candidate told at once equals the search's first.
    Returns how many were told at once."""
    advisor, findings = advisor_of(sk)
    told = 0
    for f in findings:
        if f.kind is not FindingKind.RULE1_SEVERAL_SYNCS:
            continue
        fast = advisor._first_kept(f.key)
        searched = advisor._freeing().first(advisor._runs(f), CANDIDATE_LIMIT)
        if fast is not None:
            assert searched is not None and same(fast, searched), f.key
            told += 1
    return told


def counts_agree(sk: Skeleton, per_finding: int = 8) -> int:
    """A task's synchronizations counted equal those listed, under each candidate's edits
    (and the edits of each step: every prefix of a candidate's links)."""
    advisor, findings = advisor_of(sk)
    compared = 0
    for f in findings:
        for edits in itertools.islice(advisor.candidates(f), per_finding):
            for n in range(len(edits.protocol) + 1):
                part = Edits(edits.protocol[:n], edits.drop, edits.add)
                for t in sk.tasks:
                    assert advisor.sync_count(t, part) == len(advisor.syncs(t, part)), (t, n)
                    compared += 1
    return compared


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.randoms(use_true_random=False), st.integers(2, 9), st.integers(1, 3))
def test_first_kept_equals_the_search_on_random_skeletons(rng, tasks, ports):
    first_kept_agrees(Skeleton.from_dict(random_skeleton(rng, max_tasks=tasks, max_ports=ports)))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.randoms(use_true_random=False), st.integers(2, 9), st.integers(1, 3))
def test_sync_count_equals_the_list_on_random_skeletons(rng, tasks, ports):
    counts_agree(Skeleton.from_dict(random_skeleton(rng, max_tasks=tasks, max_ports=ports)))


def test_the_shortcuts_on_the_corpus_and_generated_skeletons():
    told = compared = 0
    for seed in range(120):
        sk = Skeleton.from_dict(random_skeleton(random.Random(seed), 8, 3))
        told += first_kept_agrees(sk)
        compared += counts_agree(sk)
    for shape, n, seed in [("chain-clocks", 40, 0), ("groups", 200, 3)]:
        sk = Skeleton.from_dict(generate_skeleton.SHAPES[shape](n, seed=seed))
        told += first_kept_agrees(sk)
        compared += counts_agree(sk, per_finding=2)
    # Not vacuous: many first candidates are told at once, many counts compared.
    assert told >= 100 and compared >= 5000, (told, compared)


def _middle() -> Skeleton:
    # M has a clock, reads A's message SYN/SYN and posts to B SYN/SYN: three synchronizations.
    return Skeleton.from_dict({"tasks": {
        "A": {"duration": 1, "outputs": ["x"]},
        "M": {"duration": 1, "period": 4, "inputs": ["x"], "outputs": ["y"]},
        "B": {"duration": 1, "inputs": ["y"]}},
        "links": [{"from": "A:x", "to": "M:x", "protocol": "SYN/SYN"},
                  {"from": "M:y", "to": "B:y", "protocol": "SYN/SYN"}]})


def test_first_kept_by_hand():
    # Footnote 6: M keeps its first input; its clock goes; the rendezvous it posts on
    # keeps B blocking (ASYN/SYN), the first way, not cut.
    sk = _middle()
    advisor, _ = advisor_of(sk)
    edits = advisor._first_kept("M")
    assert edits is not None
    assert [(link.label, p) for link, p in edits.protocol] == [
        (sk.links[1].label, Protocol.ASYN_SYN)]
    assert (edits.drop, edits.add, edits.kept, edits.size()) == (
        frozenset({"M"}), frozenset(), "input M:x", 2)


def test_a_link_edited_twice_counts_by_its_last_edit():
    sk = _middle()
    advisor, _ = advisor_of(sk)
    x, y = sk.links
    assert advisor.sync_count("M", Edits()) == 3
    edits = Edits().set(y, Protocol.ASYN_ASYN).set(x, Protocol.ASYN_ASYN).set(y, Protocol.SYN_ASYN)
    assert advisor.sync_count("M", edits) == len(advisor.syncs("M", edits)) == 2
    assert advisor.sync_count("B", edits) == len(advisor.syncs("B", edits)) == 0
    assert advisor.sync_count("A", edits.with_clock("A", True)) == 1
    assert advisor.sync_count("M", edits.with_clock("M", False)) == 1


def test_a_rule2_finding_on_groups_that_stay_is_still_found():
    # A and B run at one rate and A -> B does not synchronize them (Rule 2). Edits that
    # leave both groups as they were (A2, which reads A, gives up its share of A's
    # clock) leave the finding: Rule 2 is not read again on groups that stay, but the
    # finding judged is.
    sk = Skeleton.from_dict({
        "clocks": {"c": {"period": 4}},
        "tasks": {"A": {"duration": 1, "clock": "c", "outputs": ["x", "z"]},
                  "A2": {"duration": 1, "clock": "c", "inputs": ["z"]},
                  "B": {"duration": 1, "period": 4, "inputs": ["y"]}},
        "links": [{"from": "A:x", "to": "B:y", "protocol": "ASYN/ASYN"},
                  {"from": "A:z", "to": "A2:z", "protocol": "ASYN/SYN"}]})
    advisor, findings = advisor_of(sk)
    (finding,) = [f for f in findings if f.kind is FindingKind.RULE2_UNSYNCHRONIZED]
    edits = Edits().with_clock("A2", False)
    assert advisor.brings(finding.identity, edits) == {finding.identity}
    groups, part, root_of = advisor._groups_after(edits)
    assert advisor._kept_groups(groups, part, root_of) == {advisor.group_of["A"]}
