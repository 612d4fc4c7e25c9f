"""The processor-wide busy-period analysis against the reference, unit by unit.

:class:`tegraph.design._busy_levels.Levels` answers for every unit of a processor at
once, on one integer scale, with numpy sums; the reference
(:func:`~tegraph.design.busy_period.busy_period_response`) builds, checks and scales
each unit's interferers on its own, in Python integers. They must agree on every
field (the terms counted too), on small and large denominators, with budgets that
stop them anywhere; and :func:`~tegraph.design.nonpreemptive.judge_non_preemptive`
must leave every unit as the direct per-unit reading of the analysis does
(``judge_directly`` below: every unit's interferers and blockers listed from all the
units).
"""

from __future__ import annotations

from fractions import Fraction as F
from types import SimpleNamespace

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from maxplus.scalar import display_text
from tegraph.design import _busy_levels
from tegraph.design._busy_levels import Levels
from tegraph.design.busy_period import busy_period_response
from tegraph.design.nonpreemptive import REVISED_TEST, _add_note, _judge, judge_non_preemptive

DENOMINATORS = st.sampled_from([1, 2, 3, 7, 10, 1000, 999_983, 10**9 + 7, 2**61 - 1])


@st.composite
def times(draw, low=0, high=12):
    return F(draw(st.integers(low, high)), draw(DENOMINATORS))


@st.composite
def unit_sets(draw):
    """Periodic units (cost, period, priority), with the blockings and last parts a
    query may use."""
    n = draw(st.integers(1, 7))
    units = []
    for _ in range(n):
        period = draw(times(1, 40))
        # Mostly light units (so that levels end), sometimes heavy ones.
        share = F(draw(st.integers(0, 10)), draw(st.sampled_from([10, 30, 100])))
        cost = period * share if draw(st.booleans()) else draw(times(0, 6))
        units.append((cost, period, draw(st.integers(1, 4))))
    extra = [draw(times(0, 6)) for _ in range(3)]
    return units, extra


def reference(units, n, blocking, last, budget):
    c, t, p = units[n]
    hp = [(cv, tv) for m, (cv, tv, pv) in enumerate(units) if m != n and pv >= p]
    return busy_period_response(c, t, hp, preemptive=False, blocking=blocking, last=last,
                                budget=budget)


def check_levels(units, extra, budget):
    levels = Levels(units, extra)
    for n, (c, _, _) in enumerate(units):
        lasts = [None, *(x for x in extra if 0 < x <= c)]
        for blocking in (0, *extra):
            for last in lasts:
                assert (levels.response(n, blocking=blocking, last=last, budget=budget)
                        == reference(units, n, blocking, last, budget)), (n, blocking, last)


# Small budgets: an endless level (or a huge hyperperiod) stops at them, anywhere.
BUDGETS = st.integers(1, 300)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(unit_sets(), BUDGETS)
def test_every_unit_answers_as_the_reference(case, budget):
    check_levels(*case, budget)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(unit_sets(), BUDGETS, st.sampled_from([2**8, 2**20, 2**40]))
def test_the_int64_guard_switches_to_exact_integers_anywhere(case, budget, limit):
    # A low guard sends some iterations (or whole processors) to Python integers
    # mid-way: the answer must not change.
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_busy_levels, "_LIMIT", limit)
        check_levels(*case, budget)


def test_the_can_frames_with_a_large_common_scale():
    # Davis et al.'s frames (R = 2, 3, 7/2 ms) on a processor where some other time has
    # a large prime denominator: the common scale exceeds int64, the answers stay.
    units = [(F(1), F(5, 2), 3), (F(1), F(7, 2), 2), (F(1), F(7, 2), 1)]
    levels = Levels(units, [F(1), F(1, 2**61 - 1), F(1, 10**9 + 7)])
    assert levels.scale > 2**62
    # F1 and F2 are blocked by a 1 ms frame below them, F3 by none.
    assert ([levels.response(n, blocking=b).value for n, b in enumerate([1, 1, 0])]
            == [F(2), F(3), F(7, 2)])


# -- judge_non_preemptive against the direct reading --------------------------------

def judge_directly(units, durations, free_running, unit="ms", *, budget=None):
    """Each unit's interferers and blockers listed from all the units, the analysis of
    each by the reference."""
    periodic = [u for u in units if u.period and u.group not in free_running]
    counted = {id(u) for u in periodic}
    for u in periodic:
        u.test = REVISED_TEST
        hog = next((v for v in units if v.group in free_running and v.cost > 0
                    and v.priority > u.priority), None)
        if hog is not None:
            u.schedulable = False
            _add_note(u, f"the free-running {', '.join(hog.tasks)} (priority {hog.priority}) "
                         "leaves it no time")
            continue
        interferers = [(v.cost, v.period) for v in periodic
                       if v is not u and v.priority >= u.priority]
        blockers = [(durations[t], t) for v in units if v is not u
                    and (v.priority < u.priority
                         or (v.priority == u.priority and id(v) not in counted))
                    for t in v.tasks]
        blocking, blocker = max(blockers, key=lambda b: b[0], default=(F(0), None))
        parts = [durations[t] for t in u.tasks if durations[t] > 0]
        last = min(parts, default=None)
        result = busy_period_response(u.cost, u.period, interferers, preemptive=False,
                                      blocking=blocking, last=last, budget=budget)
        _judge(u, result, unit)
        if blocker is not None and blocking > 0:
            _add_note(u, f"blocked by up to {display_text(blocking)} {unit} ({blocker})")
        if len(parts) > 1:
            _add_note(u, f"{len(parts)} non-preemptive parts, the last taken as the shortest "
                         f"({display_text(last)} {unit})")
        ties = sum(1 for v in periodic if v is not u and v.priority == u.priority)
        if ties:
            _add_note(u, f"shares priority {u.priority} with {ties} other unit(s), counted "
                         "as interference")


@st.composite
def processors(draw):
    """Units of one processor: groups of one or more tasks, some free-running, some
    without a period, priorities shared."""
    n = draw(st.integers(1, 7))
    durations, units, free = {}, [], set()
    for g in range(n):
        tasks = [f"t{g}_{k}" for k in range(draw(st.integers(1, 3)))]
        for t in tasks:
            durations[t] = draw(times(0, 4))
        kind = draw(st.sampled_from(["periodic"] * 4 + ["free", "dead"]))
        if kind == "free":
            free.add(g)
        period = None if kind == "dead" else draw(times(1, 60))
        cost = sum((durations[t] for t in tasks), F(0))
        units.append(dict(group=g, tasks=tasks, priority=draw(st.integers(1, 4)),
                          period=period, cost=cost))
    return units, durations, free


def fresh(units):
    return [SimpleNamespace(**u, response_time=None, schedulable=None, margin=None, test="",
                            note="", bounds=None) for u in units]


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(processors(), BUDGETS)
def test_every_unit_is_judged_as_directly(case, budget):
    units, durations, free = case
    fast, direct = fresh(units), fresh(units)
    judge_non_preemptive(fast, durations, free, budget=budget)
    judge_directly(direct, durations, free, budget=budget)
    assert [vars(u) for u in fast] == [vars(u) for u in direct]


def test_a_unit_without_interferers_stops_at_its_budget():
    # C = 1, T = 2 alone on its processor, blocked for b = 10^12: the level-i busy
    # period solves x = b + ceil(x / 2), x = 2b, so 10^12 instances q lie in it, each
    # w(q) = b + q (no term of a more urgent task). Each instance counts one term: a
    # budget of 1,000 stops the examination there, the bound R(0) = b + 1 the largest
    # found (R(q) = w(q) + 1 - 2q falls with q), the status "budget", not an answer.
    b = F(10**12)
    for answer in (Levels([(F(1), F(2), 1)], [b]).response(0, blocking=b, budget=1000),
                   busy_period_response(1, 2, [], preemptive=False, blocking=b, budget=1000)):
        assert answer.status == "budget" and answer.terms <= 1000
        assert answer.lower == b + 1 and answer.upper >= answer.lower
        assert 900 < answer.instances < 1000
