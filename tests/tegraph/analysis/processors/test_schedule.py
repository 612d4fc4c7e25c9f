"""The §4b schedule on processors: hand-derived cases and properties.

Every expected value is derived by hand in the comments (or by an
independent oracle: the §4 figures of ``analyze_skeleton``, and the exact
test of Lehoczky, Sha and Ding implemented below).
"""

from __future__ import annotations

import math
import random
from fractions import Fraction as F
from pathlib import Path

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from tegraph.analysis.analyze import analyze_skeleton
from tegraph.analysis.processors import schedule_on_processors
from tegraph.errors import InputError
from tegraph.io.skeleton_file import load_skeleton
from tegraph.model.build import build_teg
from tegraph.model.skeleton import Skeleton
from tests.tegraph.skeleton_corpus import random_skeleton

EXAMPLES = Path(__file__).resolve().parents[4] / "examples"


def schedule(sk: Skeleton, **kw):
    return schedule_on_processors(sk, build_teg(sk), analyze_skeleton(sk).groups, **kw)


def of(data: dict):
    sk = Skeleton.from_dict(data)
    return sk, schedule(sk)


def runs(s, processor: str = "default", until: F | None = None):
    """(task, start, end) on one processor, as text, up to ``until``."""
    return [(i.task, str(i.start), str(i.end)) for i in s.intervals
            if i.processor == processor and (until is None or i.start < until)]


# ---------------------------------------------------------------- Figure 17

def test_figure_17_computed_torque_on_one_cpu():
    # Rate-monotonic (§4b): groups [OBS.JL] 1 ms, [TG.JS, TF.TT.JS, CO.JS] 2 ms,
    # [MOD.DYN] 6 ms -> 3, 2, 2, 2, 1. All released at 0 (ticks at 0; the chain
    # tasks when their ASYN/SYN input is written):
    #   OBS.JL 0-0.1; TG.JS 0.1-0.2 (writes qd); TF.TT.JS 0.2-0.4; CO.JS 0.4-0.7;
    #   MOD.DYN 0.7-1.0, preempted by OBS.JL 1.0-1.1, resumes 1.1-2.0
    #   (0.3 + 0.9 = 1.2): it finishes in the second basic cycle, at 2.
    sk = load_skeleton(EXAMPLES / "computed_torque.yaml")
    s = schedule(sk)
    assert s.platform.priority == {"OBS.JL": 3, "TG.JS": 2, "TF.TT.JS": 2, "CO.JS": 2,
                                   "MOD.DYN": 1}
    assert runs(s, until=F(2)) == [
        ("OBS.JL", "0", "1/10"), ("TG.JS", "1/10", "1/5"), ("TF.TT.JS", "1/5", "2/5"),
        ("CO.JS", "2/5", "7/10"), ("MOD.DYN", "7/10", "1"), ("OBS.JL", "1", "11/10"),
        ("MOD.DYN", "11/10", "2")]
    # Responses over the regime (the pattern repeats every 6 ms from 0):
    # OBS.JL 0.1; TG.JS released 0 ends 0.2; TF.TT.JS 0.2 -> 0.4; CO.JS 0.4 -> 0.7;
    # MOD.DYN 0 -> 2. At 2 the control chain runs again 2.1-2.7 (OBS.JL 2-2.1).
    r = {t: (f.period, f.response, f.overrun_at) for t, f in s.tasks.items()}
    assert r == {"OBS.JL": (1, F(1, 10), None), "TG.JS": (2, F(1, 5), None),
                 "TF.TT.JS": (2, F(1, 5), None), "CO.JS": (2, F(3, 10), None),
                 "MOD.DYN": (6, 2, None)}
    assert s.schedulable is True and s.exact and s.why_undecided is None
    assert s.group_periods == [1, 2, 6]
    assert s.regimes[0]["start"] == 0 and s.regimes[0]["length"] == 6


def test_figure_17_doubled_durations_overrun():
    # Durations x2: OBS.JL 0.2, TG.JS 0.2, TF.TT.JS 0.4, CO.JS 0.6, MOD.DYN 2.4;
    # utilization 0.2 + 1.2/2 + 2.4/6 = 1.2 > 1.
    # Each 2 ms: OBS.JL 0-0.2, TG 0.2-0.4, TF 0.4-0.8, CO 0.8-1.0, OBS 1.0-1.2,
    # CO 1.2-1.6, MOD.DYN 1.6-2.0: MOD.DYN gets 0.4 per 2 ms, 1.2 by the tick at 6
    # -> activation 1 has not ended at tick 2: overrun_at 2. It ends at 12 (2.4 =
    # 6 x 0.4), the next at 24: one activation per 12 ms while its clock ticks
    # every 6: the place dyn.tick -> MOD.DYN.activate grows (clock-overrun).
    # CO.JS released 0.8 ends 1.6: response 0.8; TG.JS 0 -> 0.4; TF 0.4 -> 0.8.
    data = load_skeleton(EXAMPLES / "computed_torque.yaml").to_dict()
    for t in data["tasks"].values():
        t["duration"] = str(F(t["duration"]) * 2)
    sk, s = of(data)
    assert s.schedulable is False
    first = min((f.overrun_at, t) for t, f in s.tasks.items() if f.overrun_at is not None)
    assert first == (2, "MOD.DYN")
    assert [(u.src, u.dst, u.kind) for u in s.unbounded] == [
        ("dyn.tick", "MOD.DYN.activate", "clock-overrun")]
    assert s.tasks["MOD.DYN"].period == 12 and s.tasks["MOD.DYN"].response == 12
    assert [s.tasks[t].response for t in ("OBS.JL", "TG.JS", "TF.TT.JS", "CO.JS")] == [
        F(1, 5), F(2, 5), F(2, 5), F(4, 5)]
    assert s.group_periods == [1, 2, None]


# ---------------------------------------------------------------- two tasks

def test_two_tasks_above_full_load():
    # A 6/10 prio 2, B 6/10 prio 1: A 0-6, B 6-10 (4 of 6), A 10-16, B 16-18:
    # B's first job ends at 18 > tick 2 at 10 -> overrun_at 2. B then gets 4 per
    # 10 ms for 6 per job: jobs (release, end) (0,18) (18,30) (30,48) (48,60)...
    # period 15, response max(18, 12) = 18; its activation place grows.
    sk, s = of({"tasks": {"A": {"duration": 6, "period": 10, "priority": 2},
                          "B": {"duration": 6, "period": 10, "priority": 1}}})
    assert s.platform.processors[0].priority_source == "declared"
    # (one interval per job: job 1 of B ends at 18, job 2 starts there)
    assert runs(s, until=F(30)) == [("A", "0", "6"), ("B", "6", "10"), ("A", "10", "16"),
                                   ("B", "16", "18"), ("B", "18", "20"), ("A", "20", "26"),
                                   ("B", "26", "30")]
    b = s.tasks["B"]
    assert (b.overrun_at, b.period, b.response) == (2, 15, 18)
    assert (s.tasks["A"].period, s.tasks["A"].response, s.tasks["A"].overrun_at) == (10, 6, None)
    assert [(u.dst, u.kind) for u in s.unbounded] == [("B.activate", "clock-overrun")]
    assert s.schedulable is False


def test_two_tasks_at_full_load_exactly():
    # A 4/10 prio 2, B 6/10 prio 1: A 0-4, B 4-10: B ends at its next tick, 10,
    # which is in time (end > tick overruns, end = tick does not).
    sk, s = of({"tasks": {"A": {"duration": 4, "period": 10, "priority": 2},
                          "B": {"duration": 6, "period": 10, "priority": 1}}})
    assert runs(s, until=F(10)) == [("A", "0", "4"), ("B", "4", "10")]
    # The state at 10 (B's job ending as the clocks tick) was not that of 0: the
    # regime starts at 10 and lasts 10.
    assert s.regimes[0]["start"] == 10 and s.regimes[0]["length"] == 10
    assert s.schedulable is True
    assert (s.tasks["B"].response, s.tasks["B"].period, s.tasks["B"].overrun_at) == (10, 10, None)


# ---------------------------------------------------------------- pipeline, idle time

def test_pipeline_group_on_one_cpu():
    # H (5 ms, 1) is more urgent (2) than the group P1 -> P2 -> P3 (10 ms, all 1).
    # H 0-1, P1 1-3 (writes a), P2 released 3 runs 3-5, H 5-6, P2 6-7, P3 7-8.
    sk, s = of({"tasks": {
        "H": {"duration": 1, "period": 5},
        "P1": {"duration": 2, "period": 10, "outputs": ["a"]},
        "P2": {"duration": 3, "inputs": ["a"], "outputs": ["b"]},
        "P3": {"duration": 1, "inputs": ["b"]}},
        "links": [{"from": "P1:a", "to": "P2:a", "protocol": "ASYN/SYN"},
                  {"from": "P2:b", "to": "P3:b", "protocol": "ASYN/SYN"}]})
    assert s.platform.priority == {"H": 2, "P1": 1, "P2": 1, "P3": 1}
    assert runs(s, until=F(10)) == [("H", "0", "1"), ("P1", "1", "3"), ("P2", "3", "5"),
                                   ("H", "5", "6"), ("P2", "6", "7"), ("P3", "7", "8")]
    got = {t: (f.period, f.response) for t, f in s.tasks.items()}
    assert got == {"H": (5, 1), "P1": (10, 3), "P2": (10, 4), "P3": (10, 1)}
    assert s.schedulable is True and s.group_periods == [5, 10]


def test_free_running_task_uses_idle_time():
    # A (10 ms, 4) prio 2, B clockless (3) prio 1: A 0-4, B 4-7, B 7-10, then each
    # 10 ms: A 10-14, B (released 10) 14-17, B (released 17) 17-20: two B per 10 ms,
    # period 5, responses 7 and 3 -> 7.
    sk, s = of({"tasks": {"A": {"duration": 4, "period": 10}, "B": {"duration": 3}}})
    assert runs(s, until=F(20)) == [("A", "0", "4"), ("B", "4", "7"), ("B", "7", "10"),
                                   ("A", "10", "14"), ("B", "14", "17"), ("B", "17", "20")]
    assert (s.tasks["B"].period, s.tasks["B"].response) == (5, 7)
    assert s.group_periods == [10, 5] and s.schedulable is True


def test_two_processors_joined_by_a_link():
    # cpu0: S (10 ms, 2) writes to R on cpu1 (ASYN/SYN, 3); cpu1 also runs H
    # (4 ms, 2), more urgent (design period 4 < 10). S 0-2 on cpu0; cpu1: H 0-2,
    # R 2-4, H 4-6, R 6-7 (response 5); R released 12: H 12-14, R 14-16, H 16-18,
    # R 18-19 (response 7); then 22 -> 27 (5), 32 -> 39 (7): regime of 20 ms.
    sk, s = of({"tasks": {
        "S": {"duration": 2, "period": 10, "outputs": ["x"], "processor": "cpu0"},
        "R": {"duration": 3, "inputs": ["x"], "processor": "cpu1"},
        "H": {"duration": 2, "period": 4, "processor": "cpu1"}},
        "links": [{"from": "S:x", "to": "R:x", "protocol": "ASYN/SYN"}]})
    assert [p.name for p in s.platform.processors] == ["cpu0", "cpu1"]
    assert runs(s, "cpu0", F(20)) == [("S", "0", "2"), ("S", "10", "12")]
    assert runs(s, "cpu1", F(20)) == [
        ("H", "0", "2"), ("R", "2", "4"), ("H", "4", "6"), ("R", "6", "7"), ("H", "8", "10"),
        ("H", "12", "14"), ("R", "14", "16"), ("H", "16", "18"), ("R", "18", "19")]
    assert (s.tasks["R"].period, s.tasks["R"].response) == (10, 7)
    assert s.regimes == [{"tasks": ["S", "R", "H"], "start": 0, "length": 20}]
    assert s.schedulable is True


def test_thread_on_one_cpu():
    # Thread [A, B]: B (no clock, 3) runs once A (10 ms, 2) has finished, A again
    # once B has. H (4 ms, 1) is more urgent (4 < 10): H 0-1, A 1-3, B 3-4, H 4-5,
    # B 5-7, H 8-9, A 10-12, H 12-13, B 13-16, H 16-17, H 20-21, A 21-23, B 23-24,
    # H 24-25, B 25-27: the state of 0 comes back at 20.
    # Responses: A 0->3, 10->12: 3; B 3->7, 12->16: 4.
    sk, s = of({"tasks": {"H": {"duration": 1, "period": 4},
                          "A": {"duration": 2, "period": 10}, "B": {"duration": 3}},
                "threads": [["A", "B"]]})
    assert runs(s, until=F(20)) == [
        ("H", "0", "1"), ("A", "1", "3"), ("B", "3", "4"), ("H", "4", "5"), ("B", "5", "7"),
        ("H", "8", "9"), ("A", "10", "12"), ("H", "12", "13"), ("B", "13", "16"),
        ("H", "16", "17")]
    got = {t: (f.period, f.response) for t, f in s.tasks.items()}
    assert got == {"H": (4, 1), "A": (10, 3), "B": (10, 4)}
    assert s.regimes[0]["start"] == 0 and s.regimes[0]["length"] == 20
    assert s.schedulable is True


# ---------------------------------------------------------------- zero durations, starvation

def test_zero_durations():
    # A (5 ms, 0): each job ends at its release, response 0, period 5. Z (no
    # clock, 0): its chain is a circuit of zero durations: period 0, response 0.
    sk, s = of({"tasks": {"A": {"duration": 0, "period": 5}, "Z": {"duration": 0}}})
    assert (s.tasks["A"].period, s.tasks["A"].response) == (5, 0)
    assert (s.tasks["Z"].period, s.tasks["Z"].response) == (0, 0)
    assert s.group_periods == [5, 0] and s.schedulable is True and s.intervals == []


def test_zero_period_writer_floods_its_reader():
    # Z (no clock, 0) writes at time 0 infinitely often; C (4 ms, 1) reads it
    # ASYN/SYN: the place Z.write:x -> C.read:x holds infinitely many tokens.
    sk, s = of({"tasks": {"Z": {"duration": 0, "outputs": ["x"]},
                          "C": {"duration": 1, "period": 4, "inputs": ["x"]}},
                "links": [{"from": "Z:x", "to": "C:x", "protocol": "ASYN/SYN"}]})
    assert [(u.src, u.dst, u.kind, u.per_regime) for u in s.unbounded] == [
        ("Z.write:x", "C.read:x", "messages-overwritten", None)]
    assert (s.tasks["C"].period, s.tasks["C"].response) == (4, 1)
    assert s.schedulable is False


def test_starvation():
    # H (no clock, 1) prio 2 runs back to back for ever (its next job is released
    # when the last ends); L (10 ms, 1) prio 1 never gets the processor: starved,
    # overrun at 2 (tick 10 while activation 1 has not ended), no period.
    sk, s = of({"tasks": {"H": {"duration": 1, "priority": 2},
                          "L": {"duration": 1, "period": 10, "priority": 1}}})
    low = s.tasks["L"]
    assert low.starved and low.period is None and low.response is None
    assert low.overrun_at == 2 and s.starved == ["L"]
    assert (s.tasks["H"].period, s.tasks["H"].response) == (1, 1)
    assert s.schedulable is False


def test_dead_group_gets_null_figures_and_live_groups_as_usual():
    # fig7a: a circular wait; add a live task A on the processor.
    data = load_skeleton(EXAMPLES / "fig7a_circular_wait.yaml").to_dict()
    data["tasks"]["A"] = {"duration": 1, "period": 10}
    sk, s = of(data)
    assert s.schedulable is False
    assert (s.tasks["A"].period, s.tasks["A"].response) == (10, 1)
    dead = [t for t in sk.tasks if t != "A"]
    assert all(s.tasks[t].period is None and s.tasks[t].response is None for t in dead)


def test_budget_gives_null_with_reason():
    # Drifting clocks 7 and 11 ms: the state first repeats after 77 ms; 20 firings
    # are not enough.
    sk, s = of({"tasks": {"A": {"duration": 1, "period": 7}, "B": {"duration": 1, "period": 11}}})
    assert s.schedulable is True
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 7},
                                       "B": {"duration": 1, "period": 11}}})
    small = schedule(sk, max_events=20)
    assert small.schedulable is None and not small.exact
    # A budget of 20 firings fires 20, not one more to see that work is left.
    assert small.events == 20 and "20 event firings" in small.method
    assert "max_events" in small.why_undecided and "20" in small.why_undecided
    assert small.tasks["A"].period is None and not small.tasks["A"].decided


def test_an_overrun_found_before_the_budget_runs_out_claims_no_regime():
    # test_two_tasks_above_full_load's pair: B's first job ends at 18 > its tick at 10
    # (overrun at 2, within the first 10 firings), but the regime (B's period 15) needs
    # 48 firings. With 20 the verdict is proven by the overrun alone: the method must
    # not claim a repeated state, nor give B a period.
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 6, "period": 10, "priority": 2},
                                       "B": {"duration": 6, "period": 10, "priority": 1}}})
    s = schedule(sk, max_events=20)
    assert (s.schedulable, s.exact, s.tasks["B"].overrun_at) == (False, True, 2)
    assert s.tasks["B"].period is None
    assert "proven by a repeated state" not in s.method
    assert s.method.endswith("no periodic regime within the budget: only what the "
                             "simulation exhibited (an overrun, a growing place, a job "
                             "that never ends) is proven")
    # Two independent parts, one repeating (C alone on cpu1) and one not: the method
    # counts each.
    sk = Skeleton.from_dict({"tasks": {
        "A": {"duration": 6, "period": 10, "priority": 2},
        "B": {"duration": 6, "period": 10, "priority": 1},
        "C": {"duration": 1, "period": 10, "processor": "cpu1"}}})
    s = schedule(sk, max_events=40)  # about half each: C repeats after 3, B needs 48
    assert s.tasks["C"].period == 10 and s.tasks["B"].period is None
    assert "regime proven by a repeated state (up to places that only gain tokens, " \
        "never taken last) in 1 of them; in the other 1, none within as many firings " \
        "again as its first overrun took" in s.method


def test_past_an_overrun_the_search_for_a_regime_is_bounded():
    # The pair above: events tick, activate, compute of A and of B. At 0 the six
    # fire; at 10 A.tick, B.tick, A.activate, A.compute (4 more) but not
    # B.activate, whose job (started at 6 after A's) ends at 12: B overruns at
    # activation 2, seen at the 10th firing. The search for a regime then goes
    # on for as many firings again (10), or a tenth of the share if more: with
    # 100 firings that is 20 in all, short of the 48 the regime needs; with
    # 1,000 it is 10 + 100 and the regime (B's period 15) is proven.
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 6, "period": 10, "priority": 2},
                                       "B": {"duration": 6, "period": 10, "priority": 1}}})
    s = schedule(sk, max_events=100)
    assert (s.schedulable, s.exact, s.events, s.tasks["B"].overrun_at) == (False, True, 20, 2)
    assert s.tasks["B"].period is None
    assert s.method.endswith("no periodic regime within as many firings again as its first "
                             "overrun took (at least 1/10 of its share; the overrun decides "
                             "the verdict): only what the simulation exhibited (an overrun, "
                             "a growing place, a job that never ends) is proven")
    s = schedule(sk, max_events=1000)
    assert (s.events, s.tasks["B"].period) == (48, 15)
    assert s.method.endswith("each part's periodic regime proven by a repeated state (up to "
                             "places that only gain tokens, never taken last)")


def test_drifting_independent_sensors_are_decided_by_the_critical_instant():
    # Four sensors of 0.997, 1.009, 1.013 and 1.019 ms (997, 1009, 1013, 1019 are
    # primes): hyperperiod 997*1009*1013*1019/1000 ms, about 4e9 ticks: no simulation
    # crosses it. They are independent, released together at 0, on one processor:
    # rate-monotonic S0 > S1 > S2 > S3 and the critical instant gives each response
    # by Joseph-Pandya: R0 = 0.1; R1 = 0.1 + ceil(R/0.997)*0.1 = 0.2 (one S0 job
    # within 0.2); R2 = 0.3; R3 = 0.4, each below its period: schedulable.
    periods = [997, 1009, 1013, 1019]
    sk = Skeleton.from_dict({"tasks": {f"S{i}": {"duration": "0.1", "period": f"{p}/1000"}
                                       for i, p in enumerate(periods)}})
    s = schedule(sk)
    # Decided without crossing the hyperperiod: only a quick look at the start is
    # simulated, for the timeline (job 1 of each, in priority order from 0).
    assert s.schedulable is True and s.events <= 10_001
    assert [(i.task, i.start, i.end) for i in s.intervals[:4]] == [
        ("S0", 0, F(1, 10)), ("S1", F(1, 10), F(2, 10)), ("S2", F(2, 10), F(3, 10)),
        ("S3", F(3, 10), F(4, 10))]
    assert s.regimes[0]["by"] == "critical instant"
    assert [s.tasks[f"S{i}"].response for i in range(4)] == [
        F(k, 10) for k in (1, 2, 3, 4)]
    assert [s.tasks[f"S{i}"].period for i in range(4)] == [F(p, 1000) for p in periods]
    assert s.group_periods == [F(p, 1000) for p in periods]
    assert "critical instant" in s.method
    assert s.regimes[0]["length"] == F(math.prod(periods), 1000)


def test_drifting_independent_sensors_that_miss_overrun_at_activation_2():
    # S3 (least urgent, 1.019 ms) needs 0.8 ms: R3 = 0.8 + ceil(R/0.997)*0.1 +
    # ceil(R/1.009)*0.1 + ceil(R/1.013)*0.1: from 0.8, 1.1 (one job of each), then with
    # R = 1.1 two jobs of each more urgent sensor: 1.4 > 1.019: job 1 still runs at
    # tick 2 (1.019): overrun at activation 2, proven; the others meet their periods.
    periods = [997, 1009, 1013, 1019]
    sk = Skeleton.from_dict({"tasks": {
        f"S{i}": {"duration": "0.8" if i == 3 else "0.1", "period": f"{p}/1000"}
        for i, p in enumerate(periods)}})
    s = schedule(sk)
    assert s.schedulable is False
    assert s.tasks["S3"].overrun_at == 2
    assert [s.tasks[f"S{i}"].overrun_at for i in range(3)] == [None] * 3


def test_drifting_clocks_bound_together_are_refused_at_once_naming_the_hyperperiod():
    # The same four clocks, but S1 also waits for S0's message (ASYN/SYN): not
    # independent, no theorem applies; a regime cannot repeat before H/period ticks of
    # each clock, about 4e9 > the budget of 1e6.
    periods = [997, 1009, 1013, 1019]
    sk = Skeleton.from_dict({
        "tasks": {f"S{i}": {"duration": "0.1", "period": f"{p}/1000",
                            "inputs": ["m"] if i == 1 else [], "outputs": ["m"] if i == 0 else []}
                  for i, p in enumerate(periods)},
        "links": [{"from": "S0:m", "to": "S1:m", "protocol": "ASYN/SYN"}]})
    s = schedule(sk)
    ticks = sum(math.prod(periods) // p for p in periods)
    assert math.prod(periods) == 1038412611331
    assert s.schedulable is None and s.events <= 10_001  # a quick look for an early overrun
    assert "hyperperiod is 1038412611.331 ms" in s.why_undecided
    assert f"at least {ticks:,} clock ticks" in s.why_undecided


def test_groups_of_another_skeleton_are_refused():
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 7},
                                       "B": {"duration": 1, "period": 7}}})
    other = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 7}}})
    with pytest.raises(InputError, match=r"groups: task 'B' is in no group"):
        schedule_on_processors(sk, build_teg(sk), analyze_skeleton(other).groups)


def test_bad_budget_is_refused():
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 7}}})
    with pytest.raises(InputError, match="max_events"):
        schedule(sk, max_events=0)


# ---------------------------------------------------------------- properties

PROPS = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _own_processors(data: dict) -> Skeleton:
    data = dict(data)
    data.pop("threads", None)  # a thread is one OS thread: one processor
    for i, spec in enumerate(data["tasks"].values()):
        spec["processor"] = f"cpu{i}"
    return Skeleton.from_dict(data)


@PROPS
@given(st.randoms(use_true_random=False))
def test_one_processor_per_task_is_section_4(rng):
    sk = _own_processors(random_skeleton(rng))
    report = analyze_skeleton(sk)
    s = schedule_on_processors(sk, build_teg(sk), report.groups)
    assume(all(t.decided for t in s.tasks.values()))
    for name, t in report.tasks.items():
        if not report.groups[t.group].live:
            continue
        mine = s.tasks[name]
        assert mine.period == t.period, name
        if t.overrun_decided:
            assert mine.overrun_at == t.overrun_at, name
        if mine.period:
            assert mine.response == sk.tasks[name].duration, name
    for g, group in enumerate(report.groups):
        assert s.group_periods[g] == group.period, g
    assert {(u.src, u.dst) for u in s.unbounded} == {
        (u.src, u.dst) for u in report.unbounded_places}
    if all(t.overrun_decided for t in report.tasks.values()):
        assert s.schedulable is report.consistent


def lsd_schedulable(tasks: list[tuple[F, F]]) -> bool:
    """Lehoczky, Sha and Ding (1989): tasks (C, T) in priority order, most urgent first.

    Task i meets its deadlines iff some t in S_i = {k*T_j : j <= i, 1 <= k <= T_i/T_j}
    has sum_{j <= i} C_j * ceil(t / T_j) <= t.
    """
    for i, (_, ti) in enumerate(tasks):
        points = {k * tj for _, tj in tasks[:i + 1] for k in range(1, math.floor(ti / tj) + 1)}
        if not any(sum(c * math.ceil(t / tj) for c, tj in tasks[:i + 1]) <= t for t in points):
            return False
    return True


@PROPS
@given(st.lists(st.tuples(st.sampled_from([1, 2, 3, 4, 5, 6, F(5, 2)]),
                          st.sampled_from([0, F(1, 4), F(1, 2), 1, F(3, 2), 2])),
                min_size=1, max_size=4))
def test_independent_tasks_match_lehoczky_sha_ding(spec):
    # Synchronous release (phase 0), rate-monotonic: shortest period first, ties in file order.
    data = {"tasks": {f"T{i}": {"duration": str(c), "period": str(p)}
                      for i, (p, c) in enumerate(spec)}}
    sk, s = of(data)
    order = sorted(range(len(spec)), key=lambda i: (F(spec[i][0]), i))
    expected = lsd_schedulable([(F(spec[i][1]), F(spec[i][0])) for i in order])
    assert s.schedulable is expected


def test_corpus_seeds_one_processor_each():
    # The fixed corpus too (seeds 0..39), as in the other corpus tests.
    for seed in range(40):
        sk = _own_processors(random_skeleton(random.Random(seed)))
        report = analyze_skeleton(sk)
        s = schedule_on_processors(sk, build_teg(sk), report.groups)
        for name, t in report.tasks.items():
            if report.groups[t.group].live and s.tasks[name].decided:
                assert s.tasks[name].period == t.period, (seed, name)
