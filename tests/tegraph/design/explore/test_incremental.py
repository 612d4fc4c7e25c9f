"""Incremental judgement: on random walks through design spaces, a variant
judged from its groups' cached figures equals the variant judged afresh: verdict,
reason, periods and objectives, and the Pareto front of the walk."""

from __future__ import annotations

import importlib.util
import random
from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph import Skeleton, load_skeleton
from tegraph.analysis.analyze import analyze_skeleton
from tegraph.design.explore.evaluate import evaluate_variant
from tegraph.design.explore.incremental import IncrementalJudge, judge_of
from tegraph.design.explore.search import ParetoFront
from tegraph.design.explore.space import design_space
from tegraph.model.elements import link_name
from tegraph.model.structure import Structure
from tests.paths import REPO
from tests.tegraph.skeleton_corpus import random_skeleton

_spec = importlib.util.spec_from_file_location(
    "generate_skeleton", REPO / "benchmarks" / "generate_skeleton.py")
assert _spec is not None and _spec.loader is not None
generate_skeleton = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(generate_skeleton)

EXAMPLES = sorted(p.name for p in (REPO / "examples").glob("*.yaml"))


def _space(sk: Skeleton, rng: random.Random, max_links: int = 4, **kwargs):
    """Some of the skeleton's links with all four protocols, each clock (of a task) with
    its period and two others (faster and slower: consistency and overruns change)."""
    links = [link_name(k.writer, k.reader) for k in sk.links]
    rng.shuffle(links)
    used = {t.clock for t in sk.tasks.values() if t.clock}
    clocks = {c: sorted({sk.clocks[c].period, sk.clocks[c].period * rng.choice([2, 3]),
                         sk.clocks[c].period / rng.choice([2, 3])})
              for c in sorted(used)[:3]}
    if sk.links and rng.random() < 0.5:  # a chain's latency, and constraints
        link = rng.choice(sk.links)
        chain = [link.writer[0], link.reader[0]]
        task = rng.choice(sorted(sk.tasks))
        kwargs = {"chains": [chain], "requires": [f"{task}.period<={rng.choice([2, 5, 10])}"],
                  "max_latency": [f"{','.join(chain)}={rng.choice([3, 10, 30])}"], **kwargs}
    return design_space(sk, links[:max_links], clocks=clocks, **kwargs)


def _neighbour(space, variant: int, rng: random.Random) -> int:
    """``variant`` with one choice changed (a step of the local search)."""
    protocols, periods = list(space.protocols(variant)), list(space.periods(variant))
    moves = [("l", k) for k, c in enumerate(space.links) if len(c.protocols) > 1]
    moves += [("c", k) for k, c in enumerate(space.clocks) if len(c.periods) > 1]
    if not moves:
        return variant
    what, k = rng.choice(moves)
    if what == "l":
        protocols[k] = rng.choice([p for p in space.links[k].protocols if p != protocols[k]])
    else:
        periods[k] = rng.choice([p for p in space.clocks[k].periods if p != periods[k]])
    return space.variant_of(protocols, periods)


def _walk_agrees(space, rng: random.Random, steps: int) -> int:
    """Walk ``steps`` neighbours from a random variant; every incremental judgement
    equals the fresh one, and so does the front of the walk. Returns the number of
    variants the incremental judgement composed (not judged afresh)."""
    judge = judge_of(space)
    fresh_front, front = ParetoFront(space.objectives), ParetoFront(space.objectives)
    variant, composed = rng.randrange(space.size), 0
    for _ in range(steps):
        # The groups of a known pattern of synchronizing links, with this variant's own
        # links and periods, are Structure.of's; a group's first stage from its template
        # graph (group_graph) is that of the group's graph built afresh.
        sk = space.build(variant, validate=False)
        structure = Structure.of(sk)
        assert judge.structure(sk, variant) == structure
        for g in structure.groups:
            assert judge._compute_rates(sk, g) == judge._compute_rates(sk, g, template=False)
        found = judge.judge(variant)
        composed += found is not None
        if found is not None and found.report is not None:
            # The periods, transients and overruns of every group and task, as the
            # whole analysis finds them (what the judgement on processors reads).
            whole = analyze_skeleton(space.build(variant))
            assert (found.report.groups, found.report.tasks) == (whole.groups, whole.tasks)
        fast = evaluate_variant(space, variant)
        fresh = evaluate_variant(space, variant, incremental=False)
        assert fast == fresh, (variant, space.describe(variant))
        assert fast.rta == fresh.rta
        front.add(fast)
        fresh_front.add(fresh)
        variant = _neighbour(space, variant, rng)
    assert front.sorted() == fresh_front.sorted()
    return composed


@settings(max_examples=60, deadline=None)
@given(st.randoms(use_true_random=False))
def test_incremental_equals_fresh_on_random_skeletons(rng):
    sk = Skeleton.from_dict(random_skeleton(rng, max_tasks=6))
    if not sk.links and not any(t.clock for t in sk.tasks.values()):
        return  # nothing to choose
    _walk_agrees(_space(sk, rng), rng, steps=12)


@settings(max_examples=len(EXAMPLES) * 2, deadline=None)
@given(st.sampled_from(EXAMPLES), st.randoms(use_true_random=False))
def test_incremental_equals_fresh_on_the_examples(name, rng):
    sk = load_skeleton(REPO / "examples" / name)
    _walk_agrees(_space(sk, rng, max_links=5), rng, steps=10)


@settings(max_examples=6, deadline=None)
@given(st.integers(30, 80), st.integers(0, 10**6), st.randoms(use_true_random=False))
def test_incremental_equals_fresh_on_generated_skeletons(n, seed, rng):
    """Several groups, threads and clocks: most groups untouched by the choices."""
    sk = Skeleton.from_dict(generate_skeleton.generate(n, seed=seed))
    _walk_agrees(_space(sk, rng, max_links=3), rng, steps=8)


def test_untouched_groups_are_analysed_once_and_a_return_pays_nothing():
    """Two groups: the chosen link lies in the first; the second is analysed once for
    the whole space, the first once per protocol; judging again analyses nothing."""
    sk = Skeleton.from_dict({"tasks": {
        "A": {"duration": 1, "period": 4, "outputs": ["x"]},
        "B": {"duration": 3, "inputs": ["x"]},
        # C overruns its clock: every variant is inconsistent, so composed.
        "C": {"duration": 3, "period": 2}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]})
    space = design_space(sk, ["A:x -> B:x"])
    judge = IncrementalJudge(space)
    reasons = [judge.judge(v) for v in range(space.size)]
    assert all(r is not None and r.report is None for r in reasons)
    # ASYN/ASYN splits A and B: groups (A), (B), (C); otherwise (A, B), (C).
    # Keys: (A) and (B) once, (A, B) with each of the three synchronizing protocols,
    # (C) once: 6 analyses for 4 variants.
    assert len(judge.rates) == 6
    before = dict(judge.rates)
    again = [judge.judge(v) for v in reversed(range(space.size))]
    assert judge.rates == before
    assert [r.reason for r in again] == [r.reason for r in reversed(reasons)]
    # C (3 every 2) is the only unbounded place of the ASYN/ASYN variant: its
    # clock-overrun place is the clock tick to C's activation.
    assert reasons[0].reason == "clock-overrun at C.clock.tick -> C.activate"


def test_the_first_unbounded_place_is_the_whole_graph_s_first():
    """Two groups, each with an unbounded place: the reason names the place the whole
    graph lists first (the task earlier in the file), and counts both."""
    sk = Skeleton.from_dict({"tasks": {
        "D": {"duration": 5, "period": 2},
        "A": {"duration": 1, "period": 2, "outputs": ["x"]},
        "B": {"duration": 3, "period": 6, "inputs": ["x"]}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/ASYN"}]})
    space = design_space(sk, ["A:x -> B:x"], clocks={"D.clock": [2, 10]})
    for v in range(space.size):
        assert evaluate_variant(space, v) == evaluate_variant(space, v, incremental=False)
    # ASYN/SYN, D at 2: A posts every 2, B reads every 6 (A:x overwritten) and D
    # overruns (5 every 2): two unbounded places; D is first in the file.
    v = space.variant_of([space.links[0].protocols[1]], [Fraction(2)])
    assert evaluate_variant(space, v).reason == \
        "clock-overrun at D.clock.tick -> D.activate (and 1 more)"


@pytest.mark.parametrize("name", ["fig4_pipeline_synchronized.yaml", "threads.yaml"])
def test_a_consistent_variant_carries_the_report_composed_from_its_groups(name):
    sk = load_skeleton(REPO / "examples" / name)
    space = design_space(sk, all_links=True)
    v = space.starting_variant()
    composed = IncrementalJudge(space).judge(v)
    assert composed is not None and composed.report is not None and not composed.reason
    fresh = analyze_skeleton(space.build(v))
    assert fresh.consistent
    assert composed.report.groups == fresh.groups and composed.report.tasks == fresh.tasks
