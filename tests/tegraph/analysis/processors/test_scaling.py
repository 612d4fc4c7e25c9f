"""Lehoczky, Sha and Ding's critical scaling factor, on a task set worked by hand.

The anchor of the sensitivity on processors: the values below are derived by
hand from the exact test (scheduling points), then checked with a different
algorithm, the exact §4b schedule (``schedule_on_processors``) of the scaled
skeleton: schedulable at the end, not just beyond.
"""

from __future__ import annotations

from fractions import Fraction as F

from tegraph import Skeleton
from tegraph.analysis.analyze import analyze_skeleton
from tegraph.analysis.processors import schedule_on_processors
from tegraph.analysis.processors.scaling import critical_scaling_factor, duration_margin
from tegraph.model.build import build_teg

# A (C 1, T 3), B (C 1, T 5), C (C 2, T 10); rate-monotonic: A, B, C most urgent first.
# W_i(t) = sum over j at least as urgent as i of C_j ceil(t / T_j), all times a:
#   A: S = {3}:            W = a                        -> a <= 3
#   B: S = {3, 5}:         t=3: 2a <= 3 (3/2); t=5: 3a <= 5 (5/3)          -> max 5/3
#   C: S = {3, 5, 6, 9, 10}: t=3: 4a (3/4); t=5: 5a (1); t=6: 6a (1);
#                          t=9: (3+2+2)a = 7a <= 9 (9/7); t=10: 8a <= 10 (5/4) -> max 9/7
# a* = min(3, 5/3, 9/7) = 9/7, set by C. At 9/7 the work released before 9 is
# 3·9/7 + 2·9/7 + 18/7 = 9: C ends exactly at 9 <= 10.
SET = [(F(1), F(3)), (F(1), F(5)), (F(2), F(10))]


def scaled(a: F, durations=None) -> Skeleton:
    durations = durations or [c * a for c, _ in SET]
    return Skeleton.from_dict({"tasks": {
        name: {"duration": str(d), "period": str(t)}
        for name, d, (_, t) in zip("ABC", durations, SET)}})


def schedulable(sk: Skeleton) -> bool | None:
    report = analyze_skeleton(sk, processors=False, semiflow_max_places=0)
    return schedule_on_processors(sk, build_teg(sk), report.groups,
                                  intervals=False).schedulable


def test_critical_scaling_factor_of_a_textbook_set():
    limit = critical_scaling_factor(SET)
    assert limit.value == F(9, 7) and limit.task == 2
    # A different algorithm: the exact schedule of the scaled task set.
    assert schedulable(scaled(F(9, 7))) is True
    assert schedulable(scaled(F(9, 7) + F(1, 10**9))) is False


def test_duration_margin_of_each_task():
    # C alone (A, B at 1): C <= max_t (t - rest(t)) / 1 with rest(t) = ceil(t/3) + ceil(t/5):
    # t=3: 1, t=5: 2, t=6: 2, t=9: 9-5 = 4, t=10: 10-6 = 4 -> 4.
    assert duration_margin(SET, 2).value == 4
    # A alone (B 1, C 2): A's own test C_A <= 3; B: max(t=3: (3-1)/1, t=5: (5-1)/2) = 2;
    # C: t=3: (3-1-2)/1 = 0, t=5: (5-1-2)/2 = 1, t=6: (6-2-2)/2 = 1,
    #    t=9: (9-2-2)/3 = 5/3, t=10: (10-2-2)/4 = 3/2 -> 5/3; min(3, 2, 5/3) = 5/3.
    m = duration_margin(SET, 0)
    assert m.value == F(5, 3) and m.task == 2
    assert schedulable(scaled(F(1), [F(5, 3), F(1), F(2)])) is True
    assert schedulable(scaled(F(1), [F(5, 3) + F(1, 10**9), F(1), F(2)])) is False


def test_no_work_is_any_factor_and_a_hopeless_task_is_negative():
    assert critical_scaling_factor([(F(0), F(2)), (F(0), F(3))]).value is None
    # A takes all of every 2: B (T 4) cannot fit any work, even of its own at 0.
    m = duration_margin([(F(2), F(2)), (F(1), F(4)), (F(1), F(8))], 2)
    assert m.value is not None and m.value < 0 and m.task == 1


def test_budget_of_scheduling_points_gives_none():
    assert critical_scaling_factor(SET, max_points=2) is None
