"""The critical instant against the exact simulation of the schedule on processors.

`independent_tasks` is used only where a hyperperiod is too long to simulate; on
small hyperperiods the simulation (`schedule_on_processors`, its own tests and
oracle) decides, and the theorem must agree with it task by task.
"""

from __future__ import annotations

from fractions import Fraction as F

from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph.analysis.analyze import analyze_skeleton
from tegraph.analysis.processors import platform_of, schedule_on_processors
from tegraph.analysis.processors.critical_instant import independent_tasks
from tegraph.model.build import build_teg
from tegraph.model.skeleton import Skeleton


def _verdicts(data: dict):
    sk = Skeleton.from_dict(data)
    groups = analyze_skeleton(sk, semiflow_max_places=0).groups
    theorem = independent_tasks(sk, list(sk.tasks), platform_of(sk, groups))
    return theorem, schedule_on_processors(sk, build_teg(sk), groups)


@settings(max_examples=150, deadline=None)
@given(st.lists(st.tuples(st.integers(2, 12), st.integers(1, 8)), min_size=1, max_size=5),
       st.booleans())
def test_the_theorem_agrees_with_the_simulation(tasks, declared):
    # Durations in tenths of the period at most 0.8; declared priorities distinct (file
    # order reversed) or rate-monotonic (distinct only when the periods are).
    data = {"tasks": {f"T{i}": {"duration": str(F(d, 10) * p), "period": p,
                                **({"priority": len(tasks) - i} if declared else {})}
                      for i, (p, d) in enumerate(tasks)}}
    theorem, simulated = _verdicts(data)
    if theorem is None:  # equal rate-monotonic priorities: outside the theorem
        assert not declared and len({p for p, _ in tasks}) < len(tasks)
        return
    if theorem.late is None:
        assert simulated.schedulable is True
        for t, r in theorem.response.items():
            assert (simulated.tasks[t].response, simulated.tasks[t].period) == (
                r, theorem.period[t])
    else:
        assert simulated.schedulable is False
        assert simulated.tasks[theorem.late].overrun_at == 2
        for t in theorem.period:  # the more urgent tasks meet their periods
            assert simulated.tasks[t].overrun_at is None
            # After an overrun the simulation runs on for a bounded number of firings
            # only (AFTER_OVERRUN): within a long hyperperiod (periods 2, 5, 7, 9, 11:
            # 6,930) it ends before it proves their regime and leaves them undecided.
            if simulated.tasks[t].decided:
                assert simulated.tasks[t].response == theorem.response[t]


def test_outside_its_hypotheses_it_says_nothing():
    base = {"A": {"duration": 1, "period": 4, "outputs": ["m"]},
            "B": {"duration": 1, "period": 6, "inputs": ["m"]}}
    for protocol, applies in (("ASYN/ASYN", True), ("ASYN/SYN", False)):
        data = {"tasks": base, "links": [{"from": "A:m", "to": "B:m", "protocol": protocol}]}
        assert (_verdicts(data)[0] is not None) == applies
    two_processors = {"tasks": {"A": {"duration": 1, "period": 4, "processor": "p"},
                                "B": {"duration": 1, "period": 6}}}
    assert _verdicts(two_processors)[0] is None
    shared_clock = {"clocks": {"c": {"period": 4}},
                    "tasks": {"A": {"duration": 1, "clock": "c"},
                              "B": {"duration": 1, "clock": "c"}}}
    assert _verdicts(shared_clock)[0] is None
    phase = {"clocks": {"c": {"period": 4, "phase": 1}},
             "tasks": {"A": {"duration": 1, "clock": "c"}}}
    assert _verdicts(phase)[0] is None
