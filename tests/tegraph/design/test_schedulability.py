"""Threads, the ORCCAD §6 condition and Joseph-Pandya response times.

Response times are checked against task sets computed by hand (the
iterations are written out) and against a different algorithm: the first
job's finish time in the exact preemptive simulation of
:mod:`tegraph.timeline`, which equals the response time at the critical
instant when every task is released at 0.
"""

from __future__ import annotations

import json
import time
from fractions import Fraction as F

import jsonschema
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

import tegraph
from tegraph import InputError, load_skeleton
from tegraph.cli import app
from tegraph.design import schedulability as sched_module
from tegraph.design.schedulability import (
    UndecidedError,
    effective_priorities,
    hyperperiod,
    response_time,
    response_time_bounds,
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
        "B": {"duration": 1, "period": 2}}})) == ({"A": 1, "B": 2}, {"default": "rate-monotonic"})


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
    # Drawn to 12 (every period divides it): a first job that meets its period ends
    # in the drawing, also past an overrun of another task (where it stops by default).
    timeline = simulate_timeline(sk, horizon=12)
    first = {j.task: j for j in timeline.jobs if j.index == 1}
    for name in sk.tasks:
        u = s.unit_of(name)
        if u.schedulable:
            assert first[name].finish == u.response_time, (name, data)


# --- a nearly full processor: the start and the budget ---------

NEARLY_FULL = {"tasks": {"H": {"duration": 9999999, "period": 10000000},
                         "L": {"duration": 10000000, "period": 10**16}}}


def plain_iteration(cost, pairs):
    """Joseph and Pandya as published: from C, until the fixed point (None: no time)."""
    if cost == 0:
        return F(0)
    if pairs and sum(c / t for c, t in pairs) >= 1:
        return None
    r = F(cost)
    while True:
        nxt = cost + sum(-(-r // t) * c for c, t in pairs)  # ceil(r/t) of Fractions
        if nxt == r:
            return r
        r = nxt


def test_a_unit_under_a_nearly_full_processor_is_schedulable():
    # U_H = 9999999/10^7 = 1 - 10^-7 < 1. R_L = 10^7 + ceil(R/10^7)*9999999: at
    # R = 10^14, ceil = 10^7 and 10^7 + 10^7*9999999 = 10^7*10^7 = 10^14: a fixed point,
    # and the least (any fixed point is >= C/(1-U) = 10^7/10^-7 = 10^14). 10^14 <= 10^16.
    s = schedulability(Skeleton.from_dict(NEARLY_FULL))
    u = s.unit_of("L")
    assert (u.response_time, u.schedulable, u.margin) == (10**14, True, 10**16 - 10**14)
    assert "no time" not in u.note and s.schedulable is True
    # The start C/(1-U) is the fixed point: one evaluation of one term.
    r = response_time_bounds(F(10**7), [(F(9999999), F(10**7))])
    assert (r.status, r.value, r.terms) == ("exact", 10**14, 1)


def test_rules_and_analyze_answer_at_once_on_nearly_full_processors(tmp_path):
    path = tmp_path / "full.yaml"
    path.write_text(yaml.safe_dump(NEARLY_FULL))
    start = time.monotonic()
    out = CliRunner().invoke(app, ["rules", str(path)])
    assert out.exit_code == 0, out.output
    assert "no time" not in out.output
    assert "schedulable on its processors (spec §4b, exact); design rules followed" in out.output
    # H and 8 units of 125000 every 10^14 + i (rate-monotonic: L0 first).
    # L0 under H: C/(1-U) = 125000/10^-6 = 1.25*10^11, and 125000 +
    # ceil(1.25*10^11/10^6)*999999 = 125000*(1 + 999999) = 1.25*10^11: R = 1.25*10^11.
    many = {"tasks": {"H": {"duration": 999999, "period": 10**6},
                      **{f"L{i}": {"duration": 125000, "period": 10**14 + i} for i in range(8)}}}
    path.write_text(yaml.safe_dump(many))
    for command in (["rules", str(path)], ["analyze", str(path), "--design"]):
        out = CliRunner().invoke(app, command)
        assert out.exit_code == 0, (command, out.output)
        assert "no time" not in out.output
    assert time.monotonic() - start < 30
    s = schedulability(Skeleton.from_dict(many))
    assert s.unit_of("L0").response_time == F(125 * 10**9) and s.schedulable is True


def test_three_tasks_start_from_the_proven_lower_bound():
    # H1 (1 every 2), H2 (2 every 10): U = 1/2 + 1/5 = 7/10. L: C = 3000.
    # Lower bounds: C + 1 + 2 = 3003 and C/(1 - U) = 3000/(3/10) = 10000: start 10000.
    # W(10000) = 3000 + ceil(10000/2)*1 + ceil(10000/10)*2 = 3000 + 5000 + 2000 = 10000:
    # the fixed point, in one iteration (two terms); upper bound (3003)/(3/10) = 10010.
    pairs = [(F(1), F(2)), (F(2), F(10))]
    r = response_time_bounds(F(3000), pairs)
    assert (r.status, r.value, r.lower, r.upper, r.terms) == ("exact", 10000, 10000, 10000, 2)
    assert plain_iteration(F(3000), pairs) == 10000
    s = schedulability(Skeleton.from_dict({"tasks": {
        "H1": {"duration": 1, "period": 2}, "H2": {"duration": 2, "period": 10},
        "L": {"duration": 3000, "period": 20000}}}))
    assert (s.unit_of("L").response_time, s.unit_of("L").schedulable) == (10000, True)


def textbook(period_c):
    return Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 4},
                                         "B": {"duration": 2, "period": 6},
                                         "C": {"duration": 3, "period": period_c}}})


def test_a_budget_that_runs_out_is_undecided_never_no_time():
    # C = 3 under (1, 4), (2, 6): U = 7/12; start max(3+1+2, 3/(5/12)) = 36/5;
    # W(36/5) = 3 + 2*1 + 2*2 = 9, then 10, then 10 (R = 10, three iterations of two
    # terms). Upper bound (3 + 1 + 2)/(5/12) = 72/5. A budget of 2 terms stops at 9.
    r = response_time_bounds(F(3), [(F(1), F(4)), (F(2), F(6))], budget=2)
    assert (r.status, r.value, r.lower, r.upper, r.terms) == ("budget", None, 9, F(72, 5), 2)
    with pytest.raises(UndecidedError):
        response_time(F(3), [(F(1), F(4)), (F(2), F(6))], budget=2)
    assert response_time_bounds(F(3), [(F(1), F(4)), (F(2), F(6))], budget=6).value == 10
    # Period 12: 9 <= 12 < 72/5, undecided. B under A: start max(3, 8/3) = 3 = W(3), exact.
    s = schedulability(textbook(12), budget=2)
    c = s.unit_of("C")
    assert (c.response_time, c.bounds, c.schedulable, c.undecided) == (None, (9, F(72, 5)),
                                                                      None, True)
    assert c.note.startswith("undecided (budget)") and "no time" not in c.note
    assert s.unit_of("B").response_time == 3
    assert s.processors[0].schedulable is None and s.schedulable is None
    assert s.undecided == [c]
    assert s.to_dict()["processors"][0]["units"][2]["response_time_bounds"] == ["9", "72/5"]
    # The bounds settle it when they can: period 8 < 9 (no), period 15 >= 72/5 (yes).
    assert schedulability(textbook(8), budget=2).unit_of("C").schedulable is False
    assert schedulability(textbook(15), budget=2).unit_of("C").schedulable is True
    with pytest.raises(InputError, match="budget"):
        schedulability(textbook(12), budget=0)


def test_rules_say_undecided_when_the_budget_runs_out(tmp_path, monkeypatch):
    monkeypatch.setattr(sched_module, "RTA_BUDGET", 2)
    path = tmp_path / "textbook.yaml"
    path.write_text(yaml.safe_dump({"tasks": {"A": {"duration": 1, "period": 4},
                                              "B": {"duration": 2, "period": 6},
                                              "C": {"duration": 3, "period": 12}}}))
    out = CliRunner().invoke(app, ["rules", str(path)])
    assert "undecided (budget)" in out.output and "no time" not in out.output
    assert "NO" not in out.output and "not schedulable" not in out.output
    # The test undecided decides nothing: the exact schedule does (by hand in
    # test_explore_keeps_a_variant_whose_test_is_undecided: schedulable), as for analyze.
    assert ("cross-check: the response-time test says undecided; the exact schedule (spec "
            "§4b, the verdict) says schedulable: not compared") in out.output
    assert out.output.splitlines()[-1] == ("verdict: schedulable on its processors (spec §4b, "
                                           "exact); design rules followed (exit status 0)")
    assert out.exit_code == 0


def test_explore_keeps_a_variant_whose_test_is_undecided(monkeypatch):
    monkeypatch.setattr(sched_module, "RTA_BUDGET", 2)
    found = tegraph.explore(textbook(12), clocks={"C.clock": [12]}, workers=0)
    (result,) = found.results.values()
    # The response-time test runs out of budget (undecided, rta None) but only
    # cross-checks: the exact schedule on the one processor decides. By hand, A 1/4,
    # B 2/6, C 3/12 released together, rate-monotonic: A 0-1, B 1-3, C 3-4, A 4-5,
    # C 5-6, B 6-8, A 8-9, C 9-10 (done, 10 <= 12); at 12 the state of 0 repeats,
    # every job done before its next release: schedulable.
    assert result.rta is None
    assert result.kept and result.schedulable is True and found.front == [result]


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 30), st.lists(st.tuples(st.integers(1, 12), st.integers(1, 12),
                                               st.integers(1, 3)), max_size=4),
       st.integers(1, 3))
def test_the_lower_bound_start_reaches_the_plain_fixed_point(c, interferers, den):
    # Random small task sets (costs and periods in quarters, halves...): the accelerated
    # recurrence equals Joseph and Pandya's plain iteration from C.
    cost = F(c, den)
    pairs = [(F(ci, d), F(ti, d)) for ci, ti, d in interferers]
    expected = plain_iteration(cost, pairs)
    r = response_time_bounds(cost, pairs)
    if expected is None:
        assert r.status == "no time"
    else:
        assert (r.status, r.value) == ("exact", expected)
        assert r.lower == r.upper == expected


def test_the_bounds_of_an_undecided_unit_follow_the_report_schema():
    schema = json.loads((REPO / "docs" / "report.schema.json").read_text())
    check = {"$ref": "#/$defs/schedulability", "$defs": schema["$defs"]}
    for period in (8, 12, 15):  # decided no, undecided, decided yes by the bounds
        jsonschema.validate(schedulability(textbook(period), budget=2).to_dict(), check)
    jsonschema.validate(schedulability(textbook(12)).to_dict(), check)
