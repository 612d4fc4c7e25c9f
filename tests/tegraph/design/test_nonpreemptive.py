"""The revised analysis on non-preemptive processors (Davis, Burns, Bril, Lukkien 2007).

Expected values are derived by hand (the iterations are written out), taken from
Davis et al.'s CAN example, or measured by the brute-force simulator of
``brute_force.py`` (written apart from tegraph, over every job of a long run, with
random phases): the bound must hold for every job, whatever the phases.
"""

from __future__ import annotations

import itertools
import math
from fractions import Fraction as F

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from tegraph import InputError, analyze
from tegraph.design.busy_period import busy_period_response
from tegraph.design.nonpreemptive import REVISED_TEST
from tegraph.design.schedulability import RTA_TEST, schedulability
from tegraph.model.skeleton import Skeleton
from tests.tegraph.design.brute_force import SimTask, simulate


def frames_skeleton(preemptive: bool = False) -> Skeleton:
    """Davis et al.'s three CAN frames: 1 ms each, periods 2.5, 3.5, 3.5 ms, the first the
    most urgent, on one bus."""
    tasks = {"F1": {"duration": 1, "period": 2.5, "priority": 3, "processor": "can0"},
             "F2": {"duration": 1, "period": 3.5, "priority": 2, "processor": "can0"},
             "F3": {"duration": 1, "period": 3.5, "priority": 1, "processor": "can0"}}
    return Skeleton.from_dict({"tasks": tasks, "processors": {"can0": {"preemptive": preemptive}}})


def responses(sk: Skeleton) -> dict[str, F | None]:
    s = schedulability(sk, analyze(sk, design=False))
    return {t: s.unit_of(t).response_time for t in sk.tasks}


def test_the_can_example_of_davis_et_al():
    """Davis, Burns, Bril and Lukkien, "Controller Area Network (CAN) schedulability
    analysis: refuted, revisited and revised", Real-Time Systems 35(3), 2007, section 3:
    three frames of 1 ms, periods 2.5, 3.5 and 3.5 ms, most urgent first; the revised
    analysis gives 2, 3 and 3.5 ms."""
    # F1: B = 1 (a frame already on the bus), nothing more urgent: w = 1, R = 1 + 1 = 2.
    # F2: B = 1; w = 1 + (floor(w/2.5) + 1)*1: 2 -> 1 + 1 = 2: R(0) = 3; its busy period
    #     t = 1 + ceil(t/2.5) + ceil(t/3.5): 3, 4, 5, 5 holds Q = ceil(5/3.5) = 2 instances;
    #     w(1) = 1 + 1 + (floor(w/2.5) + 1): 3 -> 4 -> 4, R(1) = 4 - 3.5 + 1 = 1.5: R = 3.
    # F3: B = 0; w(0) = (floor(w/2.5)+1) + (floor(w/3.5)+1) = 2, R(0) = 3; busy period
    #     t = ceil(t/2.5) + 2 ceil(t/3.5): 1, 3, 4, 6, 7, 7: Q = 2; w(1) = 1 + ...: 3 -> 4
    #     -> 5 -> 6 -> 6, R(1) = 6 - 3.5 + 1 = 3.5: R = 3.5 (the original analysis, q = 0
    #     alone, would claim 3 and miss the second instance, sent 6-7).
    sk = frames_skeleton()
    sched = schedulability(sk, analyze(sk, design=False))
    (can0,) = sched.processors
    assert not can0.preemptive and can0.test == REVISED_TEST
    got = {u.tasks[0]: (u.response_time, u.schedulable, u.margin) for u in can0.units}
    assert got == {"F1": (2, True, F(1, 2)), "F2": (3, True, F(1, 2)), "F3": (F(7, 2), True, 0)}
    assert all(u.test == REVISED_TEST for u in can0.units)
    f3 = sched.unit_of("F3")
    assert "instance 2 of 2" in f3.note
    # A cross-check over all phases, never the verdict: the section decides nothing here.
    assert can0.bounds_within_periods is True and can0.cross_check
    assert can0.schedulable is None and sched.schedulable is None
    # The exact schedule from a common release: F3's second instance, queued at 3.5, is
    # sent 6-7 (a frame queued at the instant the bus frees takes part in the choice).
    run = simulate([SimTask("F1", "can0", 3, F(1), F(5, 2)),
                    SimTask("F2", "can0", 2, F(1), F(7, 2)),
                    SimTask("F3", "can0", 1, F(1), F(7, 2))], {"can0": False}, F(35))
    worst = {t: max(j.finish - j.release for j in jobs if j.finish is not None)
             for t, jobs in run.jobs.items()}
    assert worst == {"F1": F(3, 2), "F2": 2, "F3": F(7, 2)}
    assert [(j.release, j.start) for j in run.jobs["F3"][:2]] == [(0, 2), (F(7, 2), 6)]


def test_the_json_names_the_test_of_each_processor():
    sk = Skeleton.from_dict({"tasks": {
        "F1": {"duration": 1, "period": 2.5, "processor": "can0"},
        "X": {"duration": 1, "period": 4, "processor": "cpu"}},
        "processors": {"can0": {"preemptive": False}}})
    doc = analyze(sk, margins_max_tasks=0).to_dict()["design"]["schedulability"]
    assert [(p["processor"], p["preemptive"], p["test"]) for p in doc["processors"]] == [
        ("can0", False, REVISED_TEST), ("cpu", True, RTA_TEST)]
    assert doc["processors"][0]["units"][0]["test"] == REVISED_TEST
    assert "Tindell" not in REVISED_TEST


def test_a_long_low_priority_job_blocks_a_high_priority_one():
    # H: 1 every 10, most urgent; L: 5 every 20. Without preemption L may have started
    # just before H's release: H waits up to 5, R_H = B + C = 5 + 1 = 6 (with preemption 1).
    # L: w = (floor(w/10) + 1)*1 = 1, R_L = 1 + 5 = 6; busy period t = ceil(t/10) +
    # 5 ceil(t/20): 6, 6: one instance.
    sk = Skeleton.from_dict({"tasks": {
        "H": {"duration": 1, "period": 10, "priority": 2, "processor": "p"},
        "L": {"duration": 5, "period": 20, "priority": 1, "processor": "p"}},
        "processors": {"p": {"preemptive": False}}})
    assert responses(sk) == {"H": 6, "L": 6}
    assert "blocked by up to 5 ms (L)" in schedulability(sk).unit_of("H").note
    preemptive = Skeleton.from_dict({**sk.to_dict(), "processors": {"p": {"preemptive": True}}})
    assert responses(preemptive) == {"H": 1, "L": 6}
    # The simulator: L at 0, H at 1/2: H is released while L is on the processor and ends
    # at 6, responding 11/2 (the bound's 6 is approached as H's phase falls to 0+).
    run = simulate([SimTask("H", "p", 2, F(1), F(10), F(1, 2)),
                    SimTask("L", "p", 1, F(5), F(20))], {"p": False}, F(40))
    assert run.jobs["H"][0].finish - run.jobs["H"][0].activation == F(11, 2)


def test_a_job_released_as_the_processor_frees_takes_part():
    # H2 (1 every 2) and H1 (2 every 10) above B (1 every 100), released together: H2 0-1,
    # H1 1-3, H2 3-4, and at 4 H2's third job is released as the processor frees: it wins,
    # 4-5, and B runs 5-6. The continuous form counts the jobs released in [0, w]:
    # w = (floor(w/2) + 1) + 2 (floor(w/10) + 1): 3 -> 4 -> 5 -> 5, R = 5 + 1 = 6, the
    # simulated response. ceil((w + J)/T) without bit time would stop at w = 4 (R = 5:
    # optimistic).
    r = busy_period_response(1, 100, [(1, 2), (2, 10)], preemptive=False)
    assert (r.status, r.value) == ("exact", 6)
    run = simulate([SimTask("H2", "p", 3, F(1), F(2)), SimTask("H1", "p", 2, F(2), F(10)),
                    SimTask("B", "p", 1, F(1), F(100))], {"p": False}, F(20))
    b = run.jobs["B"][0]
    assert (b.start, b.finish) == (5, 6)
    w = 0  # the optimistic form's fixed point, written out for contrast
    while (nxt := math.ceil(F(w, 2)) + 2 * math.ceil(F(w, 10))) != w or w == 0:
        w = max(nxt, 1)
    assert w + 1 == 5


def test_all_durations_zero():
    # Jobs of duration 0 end at their release: every bound is 0, no blocking, no time used.
    sk = Skeleton.from_dict({"tasks": {
        "A": {"duration": 0, "period": 2, "processor": "p"},
        "B": {"duration": 0, "period": 3, "processor": "p"}},
        "processors": {"p": {"preemptive": False}}})
    assert responses(sk) == {"A": 0, "B": 0}
    assert busy_period_response(0, 1, [(1, 1)], preemptive=False, jitter=F(1, 3)).value == F(1, 3)


@pytest.mark.parametrize("duration, period", [(1, 4), (F(7, 3), 3), (3, 3)])
def test_one_task_alone_answers_as_with_preemption(duration, period):
    # Alone, nothing blocks or overtakes it: C, whatever the processor's kind.
    def sk(kind):
        return Skeleton.from_dict({"tasks": {"A": {"duration": duration, "period": period,
                                                   "processor": "p"}},
                                   "processors": {"p": {"preemptive": kind}}})
    assert responses(sk(False)) == responses(sk(True)) == {"A": F(duration)}


def test_a_group_of_several_tasks_is_a_job_of_several_parts():
    # A (2) then B (1), one group of period 10 on the bus, above L (3 every 20). Between A
    # and B a more urgent frame may pass; the last part is the shortest, F = 1:
    # w = B + C - F = 3 + 3 - 1 = 5, R = 5 + 1 = 6 (one instance).
    # L: w = 0 + (floor(w/10) + 1)*3 = 3, R = 3 + 3 = 6.
    sk = Skeleton.from_dict({"tasks": {
        "A": {"duration": 2, "period": 10, "outputs": ["x"], "processor": "p"},
        "B": {"duration": 1, "inputs": ["x"], "processor": "p"},
        "L": {"duration": 3, "period": 20, "processor": "p"}},
        "processors": {"p": {"preemptive": False}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]})
    s = schedulability(sk)
    u = s.unit_of("A")
    assert u.tasks == ["A", "B"] and u.response_time == 6
    assert "2 non-preemptive parts, the last taken as the shortest (1 ms)" in u.note
    assert s.unit_of("L").response_time == 6


def test_a_free_running_task_blocks_but_is_no_periodic_load():
    # Z has no clock: never charged as periodic load to A, but on a bus its frame (4) may
    # have just started when A's is queued: R_A = 4 + 1 = 5. A free-running frame above
    # a periodic one may take every instant: no time for it.
    base = {"A": {"duration": 1, "period": 10, "processor": "p"},
            "Z": {"duration": 4, "processor": "p"}}
    sk = Skeleton.from_dict({"tasks": base, "processors": {"p": {"preemptive": False}}})
    s = schedulability(sk)
    assert s.unit_of("A").response_time == 5 and s.unit_of("A").schedulable
    assert s.unit_of("Z").response_time is None
    above = Skeleton.from_dict({"tasks": {"A": {**base["A"], "priority": 1},
                                          "Z": {**base["Z"], "priority": 2}},
                                "processors": {"p": {"preemptive": False}}})
    a = schedulability(above).unit_of("A")
    assert a.schedulable is False and "free-running Z" in a.note


def test_overloaded_levels_and_endless_busy_periods():
    # Level load above 1: unbounded; more urgent load 1: no time; level load exactly 1
    # with blocking: the busy period never ends, proven bounds only:
    # upper = J + F + (B + C - F + S)/(1 - U) = 0 + 1 + (1 + 1 - 1 + 1)/(1/2) = 5.
    assert busy_period_response(2, 3, [(1, 2)], preemptive=False).status == "unbounded"
    assert busy_period_response(1, 3, [(1, 1)], preemptive=False).status == "no time"
    r = busy_period_response(1, 2, [(1, 2)], preemptive=False, blocking=1)
    assert (r.status, r.upper) == ("endless", 5) and r.lower <= r.upper
    # With preemption and nothing that delays the end of its busy period, load 1 is exact:
    # 1 every 2 under 1 every 2: R = 2.
    assert busy_period_response(1, 2, [(1, 2)], preemptive=True).value == 2


def test_a_budget_that_runs_out_gives_proven_bounds():
    r = busy_period_response(F(1, 1000), 1, [(F(999, 1000) - F(1, 10**6), 1)],
                             preemptive=False, blocking=F(1, 1000), budget=3)
    assert r.status == "budget" and r.lower <= r.upper
    full = busy_period_response(F(1, 1000), 1, [(F(999, 1000) - F(1, 10**6), 1)],
                                preemptive=False, blocking=F(1, 1000))
    assert full.status == "exact" and r.lower <= full.value <= r.upper


@pytest.mark.parametrize("kwargs, where", [
    ({"blocking": 1, "preemptive": True}, "blocking"),
    ({"last": 1, "preemptive": True}, "last"),
    ({"last": 2, "preemptive": False}, "last"),
    ({"jitter": -1, "preemptive": False}, "jitter"),
    ({"budget": 0, "preemptive": False}, "budget"),
])
def test_refusals_name_the_parameter(kwargs, where):
    with pytest.raises(InputError) as e:
        busy_period_response(1, 2, [], **kwargs)
    assert e.value.where == where


# -- properties: the bound holds for every job of the brute-force schedule, any phases --

@st.composite
def task_sets(draw):
    n = draw(st.integers(2, 4))
    den = draw(st.sampled_from([1, 2, 3]))
    periods = [F(draw(st.integers(2, 12)), den) for _ in range(n)]
    durations = [F(draw(st.integers(0, 6)), den * 2) for _ in range(n)]
    phases = [F(draw(st.integers(0, 11)), den * draw(st.sampled_from([1, 2, 5])))
              for _ in range(n)]
    priorities = [draw(st.integers(1, n)) for _ in range(n)]
    return list(zip(periods, durations, phases, priorities, strict=True))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(task_sets(), st.booleans())
def test_every_simulated_response_is_within_the_revised_bound(tasks, common_release):
    # A task longer than its own clock overruns it: its period is then its cycle time
    # (spec §4b), not the clock the simulator paces it by.
    assume(all(C <= T for T, C, _, _ in tasks))
    if common_release:
        tasks = [(T, C, F(0), p) for T, C, _, p in tasks]
    sk = Skeleton.from_dict({"tasks": {
        f"T{i}": {"duration": C, "period": T, "phase": phase, "priority": p, "processor": "bus"}
        for i, (T, C, phase, p) in enumerate(tasks)}, "processors": {"bus": {"preemptive": False}}})
    sched = schedulability(sk, analyze(sk, design=False))
    hyper = math.lcm(*(T.numerator for T, *_ in tasks)) / math.gcd(
        *(T.denominator for T, *_ in tasks))
    horizon = max(phase for _, _, phase, _ in tasks) + 3 * F(hyper)
    run = simulate([SimTask(f"T{i}", "bus", p, C, T, phase)
                    for i, (T, C, phase, p) in enumerate(tasks)], {"bus": False}, horizon)
    for i in range(len(tasks)):
        u = sched.unit_of(f"T{i}")
        bound = u.response_time if u.bounds is None else u.bounds[1]
        if bound is None:  # no time or unbounded: nothing is claimed
            assert u.schedulable is False
            continue
        for job in run.jobs[f"T{i}"]:
            end = job.finish if job.finish is not None else horizon
            # From the tick (the activation), hence from the release too.
            assert end - job.activation <= bound, (f"T{i}", job)
        if u.schedulable:  # within its period: no job of the run overran
            assert all(j.release == j.activation for j in run.jobs[f"T{i}"])


def original_can_analysis(cost, blocking, interferers):
    """Tindell, Burns and Wellings's CAN analysis as Davis et al. state it (their eq. 1-3,
    no bit time, no jitter): the first instance only, ``R = w + C`` with
    ``w = B + Σ_hp (floor(w/T_j) + 1)·C_j``. Written here for contrast only."""
    w = blocking
    while (nxt := blocking + sum((math.floor(w / t) + 1) * c for c, t in interferers)) != w:
        w = nxt
    return w + cost


def test_the_original_analysis_is_optimistic_on_the_can_example():
    # Davis et al. 2007, section 3 (the three frames of 1 ms, periods 2.5, 3.5, 3.5 ms):
    # the original analysis gives F3 w = 1 + 1 = 2, R = 3 ms. From a common release the
    # bus sends F1 0-1, F2 1-2, F3 2-3, F1 (queued 2.5) 3-4, F2 (3.5) 4-5, F1 (5, queued as
    # the bus frees) 5-6, and F3's second frame, queued at 3.5, only 6-7: 3.5 ms. The
    # revised analysis, over every instance of the busy period, gives the 3.5 ms the
    # schedule reaches.
    original = original_can_analysis(F(1), F(0), [(F(1), F(5, 2)), (F(1), F(7, 2))])
    assert original == 3
    run = simulate([SimTask("F1", "can0", 3, F(1), F(5, 2)),
                    SimTask("F2", "can0", 2, F(1), F(7, 2)),
                    SimTask("F3", "can0", 1, F(1), F(7, 2))], {"can0": False}, F(35))
    observed = max(j.finish - j.activation for j in run.jobs["F3"] if j.finish is not None)
    assert original < observed == F(7, 2)
    revised = schedulability(frames_skeleton()).unit_of("F3").response_time
    assert revised == observed
    # F1 and F2: the original analysis agrees there (2 and 3 ms).
    assert original_can_analysis(F(1), F(1), []) == 2
    assert original_can_analysis(F(1), F(1), [(F(1), F(5, 2))]) == 3


@st.composite
def integer_task_sets(draw):
    n = draw(st.integers(2, 3))
    periods = [draw(st.integers(2, 6)) for _ in range(n)]
    durations = [draw(st.integers(1, t)) for t in periods]
    priorities = [draw(st.integers(1, n)) for _ in range(n)]
    return list(zip(periods, durations, priorities, strict=True))


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(integer_task_sets())
def test_the_bound_covers_every_release_offset_of_a_small_integer_task_set(tasks):
    # Every integer offset of every task but the first (a common shift changes nothing),
    # each simulated non-preemptively over two hyperperiods past the last offset: the
    # revised bound must be at least every response observed, whatever the offsets.
    sk = Skeleton.from_dict({"tasks": {
        f"T{i}": {"duration": c, "period": t, "priority": p, "processor": "bus"}
        for i, (t, c, p) in enumerate(tasks)}, "processors": {"bus": {"preemptive": False}}})
    sched = schedulability(sk, analyze(sk, design=False))
    hyper = math.lcm(*(t for t, _, _ in tasks))
    worst = dict.fromkeys(range(len(tasks)), F(0))
    for offsets in itertools.product(*(range(t) for t, _, _ in tasks[1:])):
        phases = (0, *offsets)
        horizon = F(max(phases) + 2 * hyper)
        run = simulate([SimTask(f"T{i}", "bus", p, F(c), F(t), F(phases[i]))
                        for i, (t, c, p) in enumerate(tasks)], {"bus": False}, horizon)
        for i in worst:
            for job in run.jobs[f"T{i}"]:
                end = job.finish if job.finish is not None else horizon
                worst[i] = max(worst[i], end - job.activation)
    for i, observed in worst.items():
        u = sched.unit_of(f"T{i}")
        bound = u.response_time if u.bounds is None else u.bounds[1]
        if bound is None:  # no time or unbounded: nothing is claimed, and it says so
            assert u.schedulable is False
            continue
        assert observed <= bound, (f"T{i}", observed, bound)


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(task_sets())
def test_every_exact_response_is_within_the_revised_bound(tasks):
    # The §4b engine's exact schedule (§4d) for the declared phases, against the revised
    # analysis over every phase: each exact response from the tick is at most the bound.
    assume(all(C <= T for T, C, _, _ in tasks))
    sk = Skeleton.from_dict({"tasks": {
        f"T{i}": {"duration": C, "period": T, "phase": phase, "priority": p, "processor": "bus"}
        for i, (T, C, phase, p) in enumerate(tasks)}, "processors": {"bus": {"preemptive": False}}})
    report = analyze(sk, design=False)
    sched = schedulability(sk, report)
    for i in range(len(tasks)):
        fig = report.schedule.tasks[f"T{i}"]
        u = sched.unit_of(f"T{i}")
        bound = u.response_time if u.bounds is None else u.bounds[1]
        if bound is None or not fig.decided or fig.response_from_tick is None:
            continue
        assert fig.response_from_tick <= bound, (f"T{i}", fig.response_from_tick, bound)
        if u.schedulable:  # the bounds say every job ends within its period: so it does
            assert fig.overrun_at is None
