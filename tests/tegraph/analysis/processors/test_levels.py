"""When a part's groups are periodic units (``processors/levels.py``), and the exact
test along a line (``scaling.level_limits``) against the single-task theorems."""

from __future__ import annotations

from fractions import Fraction as F

from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph import Skeleton
from tegraph.analysis.analyze import analyze_skeleton
from tegraph.analysis.processors.levels import Levels, processor_levels
from tegraph.analysis.processors.scaling import (
    critical_scaling_factor,
    duration_margin,
    level_limits,
)
from tegraph.model.build import build_teg
from tegraph.model.platform import platform_of


def levels_of(data: dict) -> Levels | str:
    """The levels of the skeleton's one part (every task on ``default``)."""
    sk = Skeleton.from_dict(data)
    groups = analyze_skeleton(sk).groups
    [found] = processor_levels(sk, build_teg(sk), [[g.tasks for g in groups]],
                               platform_of(sk, groups))
    return found


def chain(*extra_tasks: tuple[str, dict], links=()) -> dict:
    """A (clock c, 10 ms) -> B (ASYN/SYN), plus the tasks and links given."""
    tasks = {"A": {"duration": 1, "clock": "c", "outputs": ["o"]},
             "B": {"duration": 2, "inputs": ["i"], "outputs": ["o"]}}
    tasks.update(dict(extra_tasks))
    return {"clocks": {"c": {"period": 10}}, "tasks": tasks,
            "links": [{"from": "A:o", "to": "B:i", "protocol": "ASYN/SYN"}, *links]}


def test_a_chain_is_a_unit_and_a_clocked_reader_closes_it():
    # A -> B: every event waits for c's tick; B (no clock) ends last: not closed.
    found = levels_of(chain())
    assert isinstance(found, Levels)
    [unit] = found.levels
    assert (unit.tasks, unit.clock, unit.period, unit.closing) == (("A", "B"), "c", 10, None)
    # Z on the same clock reads B: its activation ends after every job: closed by Z.
    closed = levels_of(chain(("Z", {"duration": 0, "clock": "c", "inputs": ["i"]}),
                             links=[{"from": "B:o", "to": "Z:i", "protocol": "ASYN/SYN"}]))
    assert isinstance(closed, Levels) and closed.levels[0].closing == "Z"
    assert closed.levels[0].tasks.index("Z") > closed.levels[0].tasks.index("B")
    # A single clocked task closes its own group.
    single = levels_of({"tasks": {"A": {"duration": 1, "period": 4}}})
    assert isinstance(single, Levels) and single.levels[0].closing == "A"


def test_background_tasks_are_the_least_urgent_levels():
    found = levels_of(chain(("L", {"duration": 5})))
    assert isinstance(found, Levels)
    assert [(lv.tasks, lv.clock) for lv in found.levels] == [(("A", "B"), "c"), (("L",), None)]


def test_what_has_no_levels_says_why():
    # A free-running reader of a SYN/ASYN link does not wait for the clock.
    pull = levels_of({"clocks": {"c": {"period": 10}}, "tasks": {
        "A": {"duration": 1, "clock": "c", "outputs": ["o"]},
        "R": {"duration": 1, "inputs": ["i"]}},
        "links": [{"from": "A:o", "to": "R:i", "protocol": "SYN/ASYN"}]})
    assert isinstance(pull, str) and "R.read:i does not wait for a tick of c" in pull
    two_clocks = levels_of({"tasks": {
        "A": {"duration": 1, "period": 10, "outputs": ["o"]},
        "B": {"duration": 1, "period": 10, "inputs": ["i"]}},
        "links": [{"from": "A:o", "to": "B:i", "protocol": "ASYN/SYN"}]})
    assert isinstance(two_clocks, str) and "2 clocks" in two_clocks
    phase = levels_of({"tasks": {"A": {"duration": 1, "period": 10, "phase": 1}}})
    assert isinstance(phase, str) and "phase 1" in phase
    split = levels_of({**chain(), "tasks": {
        **chain()["tasks"], "B": {"duration": 2, "inputs": ["i"], "outputs": ["o"],
                                  "priority": 1},
        "A": {"duration": 1, "clock": "c", "outputs": ["o"], "priority": 2}}})
    assert isinstance(split, str) and "2 priorities" in split
    shared = levels_of({"tasks": {"A": {"duration": 1, "period": 10, "priority": 1},
                                  "B": {"duration": 1, "period": 5, "priority": 1}}})
    assert isinstance(shared, str) and "share the priority 1" in shared
    free = levels_of({"tasks": {"L": {"duration": 1, "outputs": ["o"]},
                                "M": {"duration": 1, "inputs": ["i"]}},
                      "links": [{"from": "L:o", "to": "M:i", "protocol": "ASYN/SYN"}]})
    assert isinstance(free, str) and "no clock and 2 tasks" in free
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 10},
                                       "B": {"duration": 1, "period": 5,
                                             "processor": "cpu1"}}})
    groups = analyze_skeleton(sk).groups
    [two] = processor_levels(sk, build_teg(sk), [[g.tasks for g in groups]],
                             platform_of(sk, groups))
    assert two == "its tasks run on 2 processors"


# ------------------------------------------------------------------ level_limits


def task_sets():
    periods = st.sampled_from([F(2), F(3), F(4), F(5), F(5, 2), F(6), F(10)])
    durations = st.fractions(min_value=F(0), max_value=F(3), max_denominator=4)
    return st.lists(st.tuples(durations, periods), min_size=1, max_size=4)


@settings(max_examples=60, deadline=None, derandomize=True)
@given(task_sets(), st.data())
def test_level_limits_are_the_single_task_theorems_on_their_lines(tasks, data):
    # Every duration times t: the critical scaling factor is the least limit.
    limits = level_limits([(F(0), c, p) for c, p in tasks])
    assert limits is not None
    highs = [x.high for x in limits if x.high is not None]
    factor = critical_scaling_factor(tasks).value
    assert (min(highs) if highs else None) == factor
    # One duration t alone: its margin is the least limit from it down.
    m = data.draw(st.integers(0, len(tasks) - 1))
    line = [(F(0), F(1), p) if i == m else (c, F(0), p) for i, (c, p) in enumerate(tasks)]
    limits = level_limits(line)
    assert limits is not None
    margin = duration_margin([(F(0) if i == m else c, p) for i, (c, p) in enumerate(tasks)], m)
    if margin.value is not None and margin.value < 0 and margin.task < m:
        assert any(x.never for x in limits[:m])  # a more urgent task fails as it is
    else:
        assert not any(x.never for x in limits[:m])
        assert min(x.high for x in limits[m:] if x.high is not None) == margin.value


def test_level_limits_by_hand():
    # Units (0.25, 1), (0.5 + t, 2.5): the second at its points s = 1, 2, 2.5:
    # 0.75 + t <= 1, 1 + t <= 2, 1.25 + t <= 2.5 -> t <= 5/4 (s = 2.5); never for 0 work
    # left: the first alone, 0.25 <= 1 for every t.
    first, second = level_limits([(F(1, 4), F(0), F(1)), (F(1, 2), F(1), F(5, 2))])
    assert first.high is None and not first.never
    assert second.high == F(5, 4)
    # A unit whose own points all fail whatever t >= 0: 3 <= 2 never (the more urgent
    # unit alone fills (0, 2] and more).
    _, late = level_limits([(F(3), F(0), F(3)), (F(0), F(0), F(2))])
    assert late.never


def test_a_non_preemptive_processor_has_no_levels():
    # Lehoczky, Sha and Ding's test assumes preemption: a processor declared
    # preemptive: false (spec §4d) is declined by name, whatever its groups.
    data = chain()
    assert isinstance(levels_of(data), Levels)
    data["processors"] = {"default": {"preemptive": False}}
    assert levels_of(data) == "the processor default does not preempt"


def test_a_delayed_link_in_a_group_declines_the_levels():
    # A -> B (ASYN/SYN, delay 8) on one processor, every 10, one priority: A 0-1, B
    # (visible at 9) 9-11, so A#2 (released 10) waits for it: 11-12, its message visible
    # at 20 with A#3: A 20-21 first (file order), B 21-23 (response 3). One unit of
    # summed work (3 every 10, from the tick) would say the group ends by 3: the levels
    # decline; the exact schedule answers.
    sk = Skeleton.from_dict({"tasks": {
        "A": {"duration": 1, "period": 10, "outputs": ["x"]},
        "B": {"duration": 2, "inputs": ["x"]}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN", "delay": 8}]})
    report = analyze_skeleton(sk, processors=True)
    [levels] = processor_levels(sk, build_teg(sk), [[g.tasks for g in report.groups]],
                                platform_of(sk, report.groups))
    assert levels == "a link into B holds a delay (§4d)"
    b = report.schedule.tasks["B"]
    assert (b.period, b.response) == (10, 3)
