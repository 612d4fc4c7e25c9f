"""The exact schedule, the response-time cross-check and Rule 4 read one platform.

Every priority a task runs at in the exact schedule (§4b) is the one the design
section's response-time test charges it at, and, where nothing is declared, the
rate-monotonic proposal Rule 4 advises: on every processor, for random skeletons
with automata, shared and private processors, and declarations all, none or partial.
"""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph import analyze
from tegraph.design.rules import proposed_priorities
from tegraph.model.skeleton import Skeleton

NAMES = ["A", "B", "RTA", "arm.automaton", "C", "D"]


def priorities_of_both(sk: Skeleton) -> tuple[dict, dict]:
    report = analyze(sk, semiflow_max_places=0, margins_max_tasks=0, max_events=20_000)
    assert report.schedule is not None and report.design is not None
    return dict(report.schedule.platform.priority), dict(report.design.schedulability.priorities)


def test_two_automata_on_one_processor():
    # FAST (1), SLOW (6) and two clockless automata on one processor. §4b: FAST 4, SLOW 3,
    # the automata's groups 2 and 1, then each automaton one more than the largest: 5.
    sk = Skeleton.from_dict({"tasks": {
        "SLOW": {"duration": 1, "period": 6}, "FAST": {"duration": 1, "period": 1},
        "RTA": {"duration": 0}, "arm.automaton": {"duration": 0}}})
    schedule, cross_check = priorities_of_both(sk)
    assert schedule == {"SLOW": 3, "FAST": 4, "RTA": 5, "arm.automaton": 5}
    assert cross_check == schedule
    assert proposed_priorities(sk) == schedule


@st.composite
def skeletons(draw) -> Skeleton:
    n = draw(st.integers(2, len(NAMES)))
    names = NAMES[:n]
    tasks: dict[str, dict] = {}
    for name in names:
        body: dict = {"duration": draw(st.integers(0, 2))}
        period = draw(st.none() | st.sampled_from([2, 3, 4, 6, 12]))
        if period is not None:
            body["period"] = period
        where = draw(st.sampled_from([None, "p", "q"]))
        if where is not None:
            body["processor"] = where
        tasks[name] = body
    # Join some neighbours into groups (ASYN/SYN), the reader without a clock.
    links = []
    for a, b in zip(names, names[1:]):
        if draw(st.booleans()):
            tasks[a].setdefault("outputs", []).append("o")
            tasks[b].setdefault("inputs", []).append("i")
            tasks[b].pop("period", None)
            links.append({"from": f"{a}:o", "to": f"{b}:i", "protocol": "ASYN/SYN"})
    declare = draw(st.sampled_from(["none", "all", "some"]))
    for name in names:
        if declare == "all" or (declare == "some" and draw(st.booleans())):
            tasks[name]["priority"] = draw(st.integers(-2, 5))
    return Skeleton.from_dict({"tasks": tasks, "links": links})


@settings(max_examples=60, deadline=None)
@given(skeletons())
def test_the_schedule_and_the_cross_check_use_the_same_priorities(sk):
    schedule, cross_check = priorities_of_both(sk)
    assert cross_check == schedule
    if all(t.priority is None for t in sk.tasks.values()):
        assert proposed_priorities(sk) == schedule
