"""Threads, the ORCCAD §6 condition and Joseph-Pandya response times.

Response times are checked against task sets computed by hand (the
iterations are written out) and against a different algorithm: the first
job's finish time in the exact preemptive simulation of
:mod:`tegraph.timeline`, which equals the response time at the critical
instant when every task is released at 0.
"""

from __future__ import annotations

from fractions import Fraction as F

from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph import load_skeleton
from tegraph.design.schedulability import (
    effective_priorities,
    hyperperiod,
    response_time,
    schedulability,
)
from tegraph.design.timeline import simulate_timeline
from tegraph.model.skeleton import Skeleton
from tests.paths import REPO

EXAMPLES = REPO / "examples"


def test_response_time_of_a_textbook_task_set():
    # (C, T) = (1, 4), (2, 6), (3, 12), rate-monotonic.
    # tau2: R = 2 + 1*ceil(3/4) = 3 -> 3.
    # tau3: R0 = 3 + 1 + 2 = 6; 3 + ceil(6/4)*1 + ceil(6/6)*2 = 7;
    #       3 + ceil(7/4)*1 + ceil(7/6)*2 = 9; 3 + 3 + 2*2 = 10; 3 + 3 + 2*2 = 10: R = 10.
    assert response_time(F(1), []) == 1
    assert response_time(F(2), [(F(1), F(4))]) == 3
    assert response_time(F(3), [(F(1), F(4)), (F(2), F(6))]) == 10


def test_response_time_with_fractions():
    # C = 3/2 under (1/2, 2): R0 = 2; 3/2 + ceil(2/2)*1/2 = 2: R = 2.
    # C = 7/3 under (1, 3): R0 = 10/3; 7/3 + ceil(10/9)*1 = 13/3; 7/3 + ceil(13/9)*1 = 13/3:
    # R = 13/3 (beyond one period of the interferer).
    assert response_time(F(3, 2), [(F(1, 2), F(2))]) == 2
    assert response_time(F(7, 3), [(F(1), F(3))]) == F(13, 3)


def test_response_time_when_nothing_is_left():
    # The interferers use the whole processor (1/2 + 1/2): no fixed point.
    assert response_time(F(1), [(F(1), F(2)), (F(2), F(4))]) is None
    # A response above the period is still the first job's response: C = 3 under
    # (1, 2): R0 = 4; 3 + ceil(4/2) = 5; 3 + ceil(5/2) = 6; 3 + 3 = 6: R = 6.
    assert response_time(F(3), [(F(1), F(2))]) == 6


def test_hyperperiod_of_rationals():
    # lcm(3/2, 5/4): multiples of 3/2 are 3k/2, of 5/4 are 5m/4; 15/2 = 5*(3/2) = 6*(5/4),
    # and 3k/2 = 5m/4 <=> 6k = 5m <=> k a multiple of 5: the first is 15/2.
    assert hyperperiod([F(3, 2), F(5, 4)]) == F(15, 2)
    assert hyperperiod([F(1), F(2), F(6)]) == 6


def test_computed_torque_on_one_processor():
    s = schedulability(load_skeleton(EXAMPLES / "computed_torque.yaml"))
    (p,) = s.processors
    # The example's comment: T = 6, sum D_i*T/tau_i = 0.1*6 + 0.6*3 + 1.2*1 = 3.6 <= 6.
    assert (p.hyperperiod, p.demand, p.condition_holds, p.condition_margin) == (
        6, F(18, 5), True, F(12, 5))
    assert p.priority_source == "rate-monotonic"
    rows = [(u.tasks, u.priority, u.period, u.cost, u.response_time, u.margin, u.schedulable)
            for u in p.units]
    # OBS.JL: 1/10. Control group (0.6) under OBS.JL: 0.6 + ceil(0.7/1)*0.1 = 0.7.
    # MOD.DYN (1.2): 1.2 + ceil(1.9/1)*0.1 + ceil(1.9/2)*0.6 = 2.0; at 2.0: 1.2+0.2+0.6 = 2.
    assert rows == [
        (["OBS.JL"], 3, 1, F(1, 10), F(1, 10), F(9, 10), True),
        (["TG.JS", "TF.TT.JS", "CO.JS"], 2, 2, F(3, 5), F(7, 10), F(13, 10), True),
        (["MOD.DYN"], 1, 6, F(6, 5), 2, 4, True),
    ]
    assert s.schedulable is True


def test_paper_condition_fails_and_rta_agrees():
    # A: 3 every 4, B: 3 every 8 -> T = 8, demand 3*2 + 3*1 = 9 > 8: fails.
    # RTA of B: R0 = 6; 3 + ceil(6/4)*3 = 9; 3 + ceil(9/4)*3 = 12; 3 + 3*3 = 12 > 8.
    s = schedulability(Skeleton.from_dict({"tasks": {"A": {"duration": 3, "period": 4},
                                                     "B": {"duration": 3, "period": 8}}}))
    (p,) = s.processors
    assert (p.hyperperiod, p.demand, p.condition_holds, p.condition_margin) == (8, 9, False, -1)
    b = s.unit_of("B")
    assert (b.response_time, b.schedulable, b.margin) == (12, False, -4)
    assert s.schedulable is False


def test_declared_priorities_and_ties():
    # Declared priorities reverse rate-monotonic: B (period 8) is now more urgent.
    # A: 1 + ceil(R/8)*2 -> R0 = 3 -> 1 + 2 = 3. Ties (two groups with priority 5)
    # count both ways: C (1 every 4) and D (1 every 4) each get R = 2.
    s = schedulability(Skeleton.from_dict({"tasks": {
        "A": {"duration": 1, "period": 4, "priority": 1, "processor": "p"},
        "B": {"duration": 2, "period": 8, "priority": 9, "processor": "p"},
        "C": {"duration": 1, "period": 4, "priority": 5, "processor": "q"},
        "D": {"duration": 1, "period": 4, "priority": 5, "processor": "q"}}}))
    assert [p.processor for p in s.processors] == ["p", "q"]
    assert {p.processor: p.priority_source for p in s.processors} == {"p": "declared",
                                                                      "q": "declared"}
    assert s.unit_of("A").response_time == 3 and s.unit_of("B").response_time == 2
    assert s.unit_of("C").response_time == 2
    assert "shares priority 5 with 1 other unit(s)" in s.unit_of("C").note


def test_processors_do_not_interfere():
    s = schedulability(Skeleton.from_dict({"tasks": {
        "A": {"duration": 3, "period": 4, "processor": "cpu0"},
        "B": {"duration": 3, "period": 4, "processor": "cpu1"}}}))
    assert [u.response_time for p in s.processors for u in p.units] == [3, 3]
    assert effective_priorities(Skeleton.from_dict({"tasks": {
        "A": {"duration": 1, "period": 4, "priority": 7},
        "B": {"duration": 1, "period": 2}}})) == ({"A": 1, "B": 2}, {None: "rate-monotonic"})


def test_threads_of_the_example():
    s = schedulability(load_skeleton(EXAMPLES / "threads.yaml"))
    t0, t1 = s.threads
    # Example comment: the control thread has load 3/10 + 2/5 + 1/2 = 6/5, period 2
    # (clock ctl): fits, margin 4/5. [LOG, DIAG]: load 5/6, period 5/6, free-running.
    assert (t0.tasks, t0.load, t0.period, t0.pace, t0.fits, t0.margin) == (
        ["TG.JS", "TF.TT.JS", "CO.JS"], F(6, 5), 2, 2, True, F(4, 5))
    assert (t1.load, t1.period, t1.pace, t1.fits, t1.margin) == (F(5, 6), F(5, 6), None, True, 0)


def test_thread_that_does_not_fit():
    # Load 2 + 1 = 3 on a 2 ms clock: the thread circuit (1 token, holding 3) makes
    # the cycle time 3 > 2 (the clock's activations pile up).
    s = schedulability(Skeleton.from_dict({
        "tasks": {"A": {"duration": 2, "period": 2, "outputs": ["x"]},
                  "B": {"duration": 1, "inputs": ["x"]}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}],
        "threads": [["A", "B"]]}))
    (t,) = s.threads
    assert (t.load, t.period, t.pace, t.fits, t.margin) == (3, 3, 2, False, -1)
    assert t.period >= t.load


def test_dead_group_is_not_analyzed():
    s = schedulability(load_skeleton(EXAMPLES / "fig7a_circular_wait.yaml"))
    (u,) = s.processors[0].units
    assert (u.period, u.response_time, u.schedulable) == (None, None, None)
    assert "deadlock" in u.note and s.schedulable is None


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.sampled_from([2, 3, 4, 6, 12]), st.integers(1, 6)),
                min_size=1, max_size=4))
def test_response_times_match_the_simulation(tasks):
    # Independent tasks released together at 0 (the critical instant), rate-monotonic,
    # duration c/4 of a period p: the first job of each task ends at its response time.
    data = {"tasks": {f"T{i}": {"duration": F(c, 4), "period": p}
                      for i, (p, c) in enumerate(tasks)}}
    sk = Skeleton.from_dict(data)
    s = schedulability(sk)
    timeline = simulate_timeline(sk)
    first = {j.task: j for j in timeline.jobs if j.index == 1}
    for name in sk.tasks:
        u = s.unit_of(name)
        if u.schedulable:
            assert first[name].finish == u.response_time, (name, data)
