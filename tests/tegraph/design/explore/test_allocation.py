"""`explore --processors`: where the tasks run as one more choice of the design space.

The front is checked against a brute force that knows nothing of the canonical
numbering: every allocation (renamings included) is rebuilt as a skeleton by hand
and judged by the analysis on processors (spec §4b), its objectives read off the
report; the counts of canonical allocations are derived by hand in the comments.
"""

from __future__ import annotations

import itertools
import json
from dataclasses import replace
from fractions import Fraction

import pytest
from typer.testing import CliRunner

from tegraph import InputError, Skeleton
from tegraph.analysis.analyze import analyze_skeleton
from tegraph.cli import app
from tegraph.design.explore import explore_design
from tegraph.design.explore.allocation import Allocation, allocation_of
from tegraph.design.explore.evaluate import evaluate_variant
from tegraph.design.explore.objectives import DEFINITIONS
from tegraph.design.explore.results import ResultsTable
from tegraph.design.explore.search import ParetoLocalSearch, dominates
from tegraph.design.explore.space import design_space
from tegraph.model.platform import crosses

F = Fraction


def three(network: str | None = "1/2") -> Skeleton:
    """A (1 every 4) writes B (2, ASYN/SYN: runs after each A), C (1 every 2) reads A
    ASYN/ASYN: three units under --allocate tasks, two groups (A+B, C) under groups."""
    data = {"tasks": {
        "A": {"duration": 1, "period": 4, "outputs": ["x", "y"], "processor": "p"},
        "B": {"duration": 2, "inputs": ["x"], "processor": "p"},
        "C": {"duration": 1, "period": 2, "inputs": ["y"], "processor": "q"}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"},
                  {"from": "A:y", "to": "C:y", "protocol": "ASYN/ASYN"}]}
    if network is not None:
        data["network"] = {"delay": network}
    return Skeleton.from_dict(data)


OBJECTIVES = ["processors", "traffic", "busiest", "load", "latency"]


def brute_force(sk: Skeleton, offered: list[str], chain: list[str]) -> dict[tuple, tuple]:
    """Every allocation of the tasks to ``offered`` (renamings included), judged from
    scratch: processor -> objective vector, for the kept ones."""
    out = {}
    for on in itertools.product(offered, repeat=len(sk.tasks)):
        tasks = {n: replace(t, processor=p) for (n, t), p in zip(sk.tasks.items(), on)}
        variant = replace(sk, tasks=tasks)
        report = analyze_skeleton(variant, processors=True, chains=[chain])
        s = report.schedule
        if not (report.live and report.consistent and s.schedulable is True):
            continue
        figures = report.chains[0].on_processors
        if not figures.decided:
            continue
        demand = {p: F(0) for p in set(on)}
        load = {p: F(0) for p in set(on)}
        clocked = {n for g in report.groups if g.clocks for n in g.tasks}
        for (n, t), p in zip(variant.tasks.items(), on):
            if n in clocked:  # a free-running group asks nothing (there is none here)
                demand[p] += t.duration / report.tasks[n].period
            load[p] += t.duration / s.tasks[n].period
        out[on] = (F(len(set(on))), F(sum(crosses(variant, k) for k in variant.links)),
                   max(demand.values()), max(load.values()), figures.first_use)
    return out


def front_of(vectors: dict[tuple, tuple]) -> set[tuple]:
    names = range(5)
    as_dicts = {k: dict(zip(names, v)) for k, v in vectors.items()}
    return {k for k, v in as_dicts.items()
            if not any(dominates(w, v, list(names)) for w in as_dicts.values())}


def test_the_front_equals_the_brute_force_over_every_allocation_renamings_included():
    sk = three()
    chain = ["A", "C"]
    space = design_space(sk, offer="p,q,r", allocate="tasks", chains=[chain],
                         objectives=OBJECTIVES)
    assert space.objectives[-1] == "latency:A,C"
    # 3 tasks on 3 alike processors: S(3,1) + S(3,2) + S(3,3) = 1 + 3 + 1 = 5 of 27.
    assert space.size == 5
    found = explore_design(space, workers=0)
    assert found.method == "exhaustive"
    brute = brute_force(sk, ["p", "q", "r"], chain)
    best = front_of(brute)
    a = space.allocation
    # A renaming changes nothing: each allocation is kept with its canonical form's
    # figures, or neither is kept (27 allocations, 5 canonical).
    for on in itertools.product("pqr", repeat=3):
        assert brute.get(on) == brute.get(a.canonical(on)), on
    # The front holds one canonical member of each renaming class of the brute force's.
    assert {space.allocation.processors_of(space.allocation_index(r.variant))
            for r in found.front} == {a.canonical(on) for on in best}
    for r in found.front:
        on = a.processors_of(space.allocation_index(r.variant))
        assert tuple(r.objectives[n] for n in space.objectives) == brute[on]
    # Every kept variant's vector is one of the brute force's (no allocation missed).
    kept = {tuple(r.objectives[n] for n in space.objectives) for r in found.results.values()
            if r.kept}
    assert kept == set(brute.values())


def test_two_interchangeable_processors_judge_each_renaming_class_once():
    # 3 tasks on {p, q}, p and q alike and nothing pinned: 2^3 = 8 allocations, in
    # renaming pairs (ppp/qqq, ppq/qqp, pqp/qpq, pqq/qpp): 4 variants judged.
    space = design_space(three(), offer="p,q", allocate="tasks", objectives=["traffic"])
    assert space.allocation.classes == (("p", "q"),)
    assert space.size == 4
    found = explore_design(space, workers=0)
    assert len(found.results) == 4
    # With q declared non-preemptive they are not alike: all 8 are judged.
    sk = replace(three(), processors={"q": replace(
        Skeleton.from_dict({"processors": {"q": {"preemptive": False}},
                            "tasks": {"T": {"duration": 1, "processor": "q"}}}).processors["q"])})
    assert design_space(sk, offer="p,q", allocate="tasks", objectives=["traffic"]).size == 8
    # Pinning A on p makes p unlike q: B, C free over {p, q}, 2^2 = 4, no renaming.
    pinned = design_space(three(), offer="p,q", allocate="tasks", pin=["A=p"],
                          objectives=["traffic"])
    assert pinned.allocation.classes == () and pinned.size == 4


def test_canonical_counts_are_the_stirling_sums():
    # n free units on k alike processors: Σ_{i<=k} S(n, i). n = 4, k = 3:
    # S(4,1) + S(4,2) + S(4,3) = 1 + 7 + 6 = 14 (against 3^4 = 81).
    units = tuple((t,) for t in "ABCD")
    assert Allocation(("a", "b", "c"), units, {}, (("a", "b", "c"),)).size == 14
    # One processor x unlike two alike ones a, b, 3 units: choose the j units not on x
    # (C(3, j)), those spread over a, b up to renaming (S(j,1) + S(j,2)):
    # j=0: 1; j=1: 3*1; j=2: 3*(1+1); j=3: 1*(1+3) -> 1 + 3 + 6 + 4 = 14.
    a = Allocation(("x", "a", "b"), units[:3], {}, (("a", "b"),))
    assert a.size == 14
    # Unranking and ranking are inverse, and every allocation's renaming is one of them.
    listed = [a.processors_of(i) for i in range(a.size)]
    assert [a.index_of(on) for on in listed] == list(range(a.size))
    every = {a.canonical(on) for on in itertools.product("xab", repeat=3)}
    assert every == set(listed)


def test_groups_move_whole_and_a_pinned_task_never_moves():
    # Under groups: units A+B and C. Pinning C on q: only A+B moves, over p, q, r.
    space = design_space(three(), offer="p,q,r", pin=["C=q"], objectives=["traffic"])
    assert space.allocation.units == (("A", "B"), ("C",))
    assert space.size == 2  # p and r alike (nothing pinned): A+B on p or on q (r ~ p)
    for v in range(space.size):
        on = space.processors_of(v)
        assert on["C"] == "q" and on["A"] == on["B"]
    found = explore_design(space, workers=0)
    assert all(space.processors_of(v)["C"] == "q" for v in found.results)
    # Pinning B pins its group A+B.
    space = design_space(three(), offer="p,q", pin=["B=q"], objectives=["traffic"])
    assert all(space.processors_of(v)["A"] == "q" for v in range(space.size))


def test_objectives_hand_derived_on_a_tiny_skeleton():
    # A on p, B on p (after A: period 4), C on q; the network delay 1/2 on A:y -> C:y,
    # which crosses. processors: 2. traffic: 1 link across. busiest: p asks
    # 1/4 + 2/4 = 3/4, q asks 1/2. On processors p runs A then B in each period of 4
    # (3 of its 4 units), so load 3/4 too.
    space = design_space(three(), offer="p,q", allocate="tasks",
                         objectives=["processors", "traffic", "busiest", "load"])
    a = space.allocation
    v = space.variant_of([], [], a.index_of(("p", "p", "q")))
    assert space.crossing(v) == [("A:y -> C:y", F(1, 2))]
    r = evaluate_variant(space, v)
    assert r.kept
    assert r.objectives == {"processors": 2, "traffic": 1, "busiest": F(3, 4),
                            "load": F(3, 4)}
    # All on p: one processor, nothing crosses, p asks 3/4 + 1/2 = 5/4 > 1: rule C.
    r = evaluate_variant(space, space.variant_of([], [], a.index_of(("p", "p", "p"))))
    assert not r.kept and r.objectives["processors"] == 1 and r.objectives["traffic"] == 0
    assert r.objectives["busiest"] == F(5, 4)


def test_a_rendezvous_across_processors_is_rejected_not_failed():
    sk = Skeleton.from_dict({"network": {"delay": 1}, "tasks": {
        "A": {"duration": 1, "period": 4, "outputs": ["x"]},
        "B": {"duration": 1, "inputs": ["x"]}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "SYN/SYN"}]})
    space = design_space(sk, offer="p,q", allocate="tasks", objectives=["traffic"])
    a = space.allocation
    r = evaluate_variant(space, space.variant_of([], [], a.index_of(("p", "q"))))
    assert r.judged == "pruned" and r.reason.startswith("a rendezvous across processors")
    assert evaluate_variant(space, space.variant_of([], [], a.index_of(("p", "p")))).kept


def test_local_search_moves_units_and_starts_from_never_together_pairs():
    # A and B (1 every 4, B's phase 2) never run at once on p and q: the start puts
    # them together (both on p), besides the input design (A on p, B on q).
    sk = Skeleton.from_dict({"tasks": {
        "A": {"duration": 1, "period": 4, "processor": "p"},
        "B": {"duration": 1, "period": 4, "phase": 2, "processor": "q"},
        "C": {"duration": 1, "period": 4, "processor": "q"}}})
    space = design_space(sk, offer="p,q", allocate="tasks", pin=["C=q"],
                         objectives=["processors"])
    a = space.allocation
    search = ParetoLocalSearch(space, _NoDeath(), _front(), budget=10)
    starts = [a.processors_of(space.allocation_index(v)) for v in search._generation]
    assert ("p", "q") in starts and ("p", "p") in starts


class _NoDeath:
    def dead(self, protocols):
        return False


def _front():
    from tegraph.design.explore.search import ParetoFront
    return ParetoFront(["processors"])


def test_results_file_has_the_units_and_a_new_definitions_version(tmp_path):
    assert DEFINITIONS == 6
    space = design_space(three(), offer="p,q", objectives=["traffic"])
    table = ResultsTable(tmp_path / "r.csv", space)
    assert "on:A+B" in table.columns and "on:C" in table.columns
    table.close()
    # Without processors offered, the fingerprint of version 6 differs from 5's: a file of
    # version 5 is refused, never read as this one.
    plain = design_space(three(), clocks={"A.clock": [4, 8]}, objectives=["load"])
    assert plain.fingerprint_of(5) != plain.fingerprint


@pytest.mark.parametrize(("args", "where", "expected"), [
    (["--processors", ""], "--processors", "cannot be read"),
    (["--processors", "p,p"], "--processors", "offered twice"),
    (["--processors", "p,q", "--pin", "Z=p"], "--pin", "no task 'Z'"),
    (["--processors", "p,q", "--pin", "A=cpu9"], "--pin", "unknown processor 'cpu9'"),
    (["--processors", "p,q", "--pin", "A"], "--pin", "expected TASK=PROCESSOR"),
    (["--processors", "p,q", "--allocate", "cores"], "--allocate", "expected one of"),
    (["--pin", "A=p", "--clock", "A.clock=4"], "--pin", "no processor is offered"),
    (["--allocate", "tasks", "--clock", "A.clock=4"], "--allocate", "without processors"),
    (["--processors", "p,q", "--pin", "A=p", "--pin", "A=q"], "--pin", "pinned to both"),
])
def test_bad_allocation_options_exit_2_with_one_message(tmp_path, args, where, expected):
    f = tmp_path / "s.yaml"
    f.write_text("tasks:\n  A: {duration: 1, period: 4}\n  B: {duration: 1, period: 4}\n")
    result = CliRunner().invoke(app, ["explore", str(f), *args])
    assert result.exit_code == 2, result.output
    text = result.stderr if hasattr(result, "stderr") else result.output
    assert where in text and expected in text and "Traceback" not in text


def test_the_library_refuses_the_same():
    with pytest.raises(InputError, match="no task 'Z'"):
        allocation_of(three(), ["p"], pin=["Z=p"])


def test_incremental_judgement_equals_the_judgement_from_scratch_on_every_allocation():
    # Under tasks, A:x -> B:x lies inside the group A+B: split over two processors it
    # holds the network's 1/2 (spec §4d), so the group is built anew, not edited.
    space = design_space(three(), offer="p,q,r", allocate="tasks", chains=[["A", "C"]],
                         objectives=OBJECTIVES)
    for v in range(space.size):
        a, b = evaluate_variant(space, v), evaluate_variant(space, v, incremental=False)
        a.seconds = b.seconds = 0.0
        assert a == b, v


def test_a_results_file_of_an_allocation_is_resumed_cell_for_cell(tmp_path):
    from tegraph.api import explore
    out = tmp_path / "r.csv"
    first = explore(three(), offer="p,q,r", allocate="tasks", objectives=["traffic"],
                    output=out)
    rows = out.read_text().splitlines()
    assert len(rows) == 1 + 5 and rows[0].count("on:") == 3
    again = explore(three(), offer="p,q,r", allocate="tasks", objectives=["traffic"],
                    output=out, resume=True)
    assert again.resumed == 5
    assert [r.variant for r in again.front] == [r.variant for r in first.front]
    # Another offer is another space: the file is refused, not misread.
    with pytest.raises(InputError, match="another exploration"):
        explore(three(), offer="p,q,s", allocate="tasks", objectives=["traffic"],
                output=out, resume=True)


def test_syn_syn_stays_a_choice_where_the_allocation_may_join_the_two_tasks():
    # A on p, B on q, network delay 1: in the input A:x -> B:x crosses, so without
    # --processors SYN/SYN is no choice (a rendezvous holds no delay). With A and B
    # free over {p, q} it is one: judged where both share a processor, pruned across.
    sk = Skeleton.from_dict({"network": {"delay": 1}, "tasks": {
        "A": {"duration": 1, "period": 4, "outputs": ["x"], "processor": "p"},
        "B": {"duration": 1, "inputs": ["x"], "processor": "q"}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]})
    fixed = design_space(sk, ["A:x -> B:x=ASYN/SYN,SYN/SYN"], objectives=["load"])
    assert [p.value for p in fixed.links[0].protocols] == ["ASYN/SYN"]
    space = design_space(sk, ["A:x -> B:x=ASYN/SYN,SYN/SYN"], offer="p,q",
                         allocate="tasks", objectives=["traffic"])
    assert space.size == 2 * 2  # two protocols, two allocations (p p, p q; q ~ p)
    syn = [p.value for p in space.links[0].protocols].index("SYN/SYN")
    a = space.allocation
    together = space.variant_of([space.links[0].protocols[syn]], [], a.index_of(("p", "p")))
    apart = space.variant_of([space.links[0].protocols[syn]], [], a.index_of(("p", "q")))
    assert evaluate_variant(space, together).kept
    assert evaluate_variant(space, apart).judged == "pruned"


def test_busiest_counts_only_the_groups_with_a_clock():
    # A: 1 every 4; D: duration 1, no clock, no link: a group of its own that runs free
    # (as often as its processor lets it, at the lowest priority). Both on p: D asks
    # nothing, so busiest = 1/4; on processors D fills the 3/4 A leaves: load 1.
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 4},
                                       "D": {"duration": 1}}})
    space = design_space(sk, offer="p,q", allocate="tasks", free_running=True,
                         objectives=["processors", "busiest", "load"])
    r = evaluate_variant(space, space.variant_of([], [], space.allocation.index_of("pp")))
    assert r.kept, r.reason
    assert r.objectives == {"processors": 1, "busiest": F(1, 4), "load": 1}


def test_local_search_over_links_and_processors_never_moves_a_pinned_task():
    # The link A:x -> B:x among two protocols, tasks over p, q, r with A pinned on q:
    # B, C free, p and r alike: B, C each on p, q or r up to renaming of p/r:
    # (q q), (q p), (p q), (p p), (p r) -> 5 allocations, 10 variants; a budget of 4
    # analyses makes it a local search.
    space = design_space(three(), ["A:x -> B:x=ASYN/SYN,ASYN/ASYN"], offer="p,q,r",
                         allocate="tasks", pin=["A=q"], objectives=["traffic", "busiest"],
                         free_running=True)
    assert space.n_allocation_variants == 5 and space.size == 10
    found = explore_design(space, workers=0, max_variants=4)
    assert found.method == "pareto-local-search"
    assert found.results and all(space.processors_of(v)["A"] == "q" for v in found.results)
    assert len(found.results) <= 4 + found.count("pruned")
    exact = explore_design(space, workers=0)
    # A heuristic: what it judged is what the exhaustive search judged of those variants.
    for v, r in found.results.items():
        assert (r.kept, r.objectives) == (exact.results[v].kept, exact.results[v].objectives)


def test_the_reports_show_where_each_unit_of_the_front_runs():
    from tegraph.report import to_json
    from tegraph.report.explore_text import render_exploration
    from tegraph.report.html import render_html
    space = design_space(three(), offer="p,q", objectives=["traffic", "busiest"])
    found = explore_design(space, workers=0)
    text = render_exploration(found)
    assert "on A+B" in text and "across processors: A:y -> C:y (delay 1/2 ms)" in text
    assert "on A+B" in render_html(found)
    # All on p asks 3/4 + 1/2 > 1 (rule C): the one kept design splits A+B from C.
    (design,) = json.loads(to_json(found))["front"]
    assert design["processors"] == {"A+B": "p", "C": "q"}
    assert design["crossing"] == [{"link": "A:y -> C:y", "delay": "1/2"}]


def test_the_exhaustive_search_proposes_the_never_together_pairs_first_and_once():
    from tegraph.design.explore.prune import DeadlockOracle
    from tegraph.design.explore.search import ExhaustiveSearch
    sk = Skeleton.from_dict({"tasks": {
        "A": {"duration": 1, "period": 4, "processor": "p"},
        "B": {"duration": 1, "period": 4, "phase": 2, "processor": "q"},
        "C": {"duration": 1, "period": 4, "processor": "q"}}})
    # A, B, C free over p, q, r (alike): S(3,1) + S(3,2) + S(3,3) = 5 variants. A and B
    # never run at once in the input (A in [0, 1], B in [2, 3] of every 4; C runs with
    # A in [0, 1] on q): the pair is put on A's processor p, B moved: p p q, canonical
    # p p q, number 1 (after p p p), proposed first.
    space = design_space(sk, offer="p,q,r", allocate="tasks", objectives=["processors"])
    search = ExhaustiveSearch(space, DeadlockOracle(space))
    analyze, pruned = search.propose(100)
    a = space.allocation
    assert a.processors_of(analyze[0]) == ("p", "p", "q")
    assert sorted(analyze) == list(range(space.size)) == list(range(5)) and not pruned


def test_a_task_on_a_processor_not_offered_stays_there():
    # F on the bus (not offered) is in no unit; A and B move over p, q (alike): p p, p q.
    # Under groups, A's group holds F (A:x -> F:x is ASYN/SYN): that group stays whole.
    sk = Skeleton.from_dict({"processors": {"bus": {"preemptive": False}}, "tasks": {
        "A": {"duration": 1, "period": 4, "outputs": ["x"]},
        "F": {"duration": 1, "inputs": ["x"], "processor": "bus"},
        "B": {"duration": 1, "period": 4}},
        "links": [{"from": "A:x", "to": "F:x", "protocol": "ASYN/SYN"}]})
    space = design_space(sk, offer="p,q", allocate="tasks", objectives=["busiest"])
    assert space.allocation.units == (("A",), ("B",)) and space.size == 2
    assert all(space.build(v).tasks["F"].runs_on == "bus" for v in range(space.size))
    groups = design_space(sk, offer="p,q", objectives=["busiest"])
    assert groups.allocation.units == (("B",),)
    with pytest.raises(InputError, match="stays where the file puts it"):
        design_space(sk, offer="p,q", allocate="tasks", pin=["F=p"], objectives=["busiest"])
