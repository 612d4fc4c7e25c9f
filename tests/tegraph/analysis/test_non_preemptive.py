"""A processor declared ``preemptive: false`` (spec §4d): the exact schedule, every command.

The engine never interrupts a running job there and, when the processor becomes free,
chooses among every job released up to that instant, those released at it included.
Every preemption-only theorem declines such a processor: the critical instant and
Lehoczky-Sha-Ding, the response-time cross-check of Joseph and Pandya (replaced by the
revised analysis of Davis et al. 2007, a bound, never the verdict), and Rule 4's
rate-monotonic order (optimal under preemption only).
"""

from __future__ import annotations

import json
from fractions import Fraction as F

from typer.testing import CliRunner

from tegraph import analyze
from tegraph.analysis.processors import schedule_on_processors
from tegraph.analysis.processors.critical_instant import independent_tasks
from tegraph.analysis.sensitivity import sensitivity
from tegraph.cli import app
from tegraph.design.nonpreemptive import REVISED_TEST
from tegraph.design.rules import FindingKind, check_rules
from tegraph.design.timeline import simulate_timeline
from tegraph.model.build import build_teg
from tegraph.model.platform import platform_of
from tegraph.model.skeleton import Skeleton
from tegraph.report import render_text


def frames(preemptive: bool, **more) -> Skeleton:
    """The three CAN frames of Davis et al. 2007 (1 ms; periods 2.5, 3.5, 3.5 ms, in that
    order of priority) on can0; on cpu, X (``x_duration`` every 4)."""
    tasks = {"F1": {"duration": 1, "period": 2.5, "priority": 3, "processor": "can0"},
             "F2": {"duration": 1, "period": 3.5, "priority": 2, "processor": "can0"},
             "F3": {"duration": 1, "period": 3.5, "priority": 1, "processor": "can0"},
             "X": {"duration": more.pop("x_duration", 1), "period": 4, "processor": "cpu"}}
    return Skeleton.from_dict({"tasks": tasks,
                               "processors": {"can0": {"preemptive": preemptive}}})


def drawn(sk: Skeleton):
    """The processor time of each job (analyze keeps none)."""
    return schedule_on_processors(sk, build_teg(sk), analyze(sk, design=False).groups).intervals


def bus(intervals, processor="can0", until=F(35, 2)):
    return [(i.task, i.start, i.end) for i in intervals
            if i.processor == processor and i.start < until]


def test_the_can_frames_of_davis_et_al():
    # By hand, from the common release at 0 (one hyperperiod, 17.5 ms): F1 0-1, F2 1-2,
    # F3 2-3; F1 (2.5) waits for F3's frame, 3-4; F2 and F3 (3.5): F2 4-5; at 5 F1's
    # third frame is released as the bus becomes free and wins the arbitration, 5-6;
    # F3 6-7 (response 3.5; a simulator that chose before the release would send it
    # 5-6, 2.5); F2 (7) 7-8; F1 (7.5) 8-9; F3 (7) 9-10; F1 (10) 10-11; F2 (10.5)
    # 11-12; ... Responses over the regime: F1 1.5 (at 2.5), F2 2 (released 14, sent
    # 15-16 after F1), F3 3.5.
    r = analyze(frames(False), design=False)
    s = r.schedule
    assert s.schedulable is True and r.exit_status == 0
    assert bus(drawn(frames(False)), until=F(12)) == [
        ("F1", 0, 1), ("F2", 1, 2), ("F3", 2, 3), ("F1", 3, 4), ("F2", 4, 5), ("F1", 5, 6),
        ("F3", 6, 7), ("F2", 7, 8), ("F1", 8, 9), ("F3", 9, 10), ("F1", 10, 11),
        ("F2", 11, 12)]
    assert [s.tasks[t].response for t in ("F1", "F2", "F3")] == [F(3, 2), F(2), F(7, 2)]
    assert [s.tasks[t].period for t in ("F1", "F2", "F3")] == [F(5, 2), F(7, 2), F(7, 2)]
    assert "non-preemptive on can0" in s.method
    doc = r.to_dict()
    assert [(p["name"], p["preemptive"]) for p in doc["processors"]] == [
        ("can0", False), ("cpu", True)]
    assert r.on_processors("F3")["response"] == "7/2"


def test_the_revised_analysis_bounds_the_exact_responses():
    # Davis et al. 2007, Table 2: the revised analysis gives 2, 3 and 3.5 ms; the
    # original analysis of Tindell et al. (3 ms for F3) is below the exact 3.5.
    r = analyze(frames(False), margins_max_tasks=0)
    can0 = next(p for p in r.design.schedulability.processors if p.processor == "can0")
    assert not can0.preemptive and can0.cross_check and can0.test == REVISED_TEST
    assert [u.response_time for u in can0.units] == [F(2), F(3), F(7, 2)]
    exact = [r.schedule.tasks[t].response for t in ("F1", "F2", "F3")]
    assert all(e <= u.response_time for e, u in zip(exact, can0.units))
    # A cross-check never decides: the processor and the section say "not decided".
    assert can0.schedulable is None and r.design.schedulability.schedulable is None
    assert r.exit_status == 0  # the exact schedule decides
    # Each frame's bound is within its period, and the exact schedule meets every period:
    # the three bounds are compared and agree; the Joseph-Pandya test covers only cpu.
    cross = r.to_dict()["design"]["schedulability"]["cross_check"]
    assert (cross["bounds_compared"], cross["bounds_agree"], cross["test_says"]) == (3, True, True)
    text = render_text(r)
    assert "response-time test on the preemptive processors says schedulable" in text
    assert "3 unit(s) on non-preemptive processors whose bound is within the period" in text


def test_preemptive_frames_overrun():
    # The same frames on a preemptive processor (§4b): F1 0-1, F2 1-2, F3 from 2, preempted
    # by F1 at 2.5 (to 3.5) and by F2's second job at 3.5 (to 4.5): F3's clock ticks at
    # 3.5 while its first job runs, an overrun at activation 2. Without preemption F3
    # runs 2-3 and meets its period: the answer a bus must get.
    r = analyze(frames(True), design=False)
    assert r.schedule.schedulable is False and r.schedule.tasks["F3"].overrun_at == 2


def test_a_long_less_urgent_job_blocks_an_urgent_one():
    # L (3 ms, released 0) and H (1 ms, released 1, more urgent), both every 10 ms. Non-
    # preemptive: L 0-3, H waits, 3-4: H's response 3, L's 3. Preemptive: L 0-1, H 1-2,
    # L 2-4: H 1, L 4.
    def sk(preemptive):
        return Skeleton.from_dict({
            "tasks": {"L": {"duration": 3, "period": 10, "priority": 1, "processor": "p"},
                      "H": {"duration": 1, "period": 10, "phase": 1, "priority": 2,
                            "processor": "p"}},
            "processors": {"p": {"preemptive": preemptive}}})
    lazy = analyze(sk(False), design=False).schedule
    assert bus(drawn(sk(False)), "p", F(10)) == [("L", 0, 3), ("H", 3, 4)]
    assert (lazy.tasks["H"].response, lazy.tasks["L"].response) == (3, 3)
    eager = analyze(sk(True), design=False).schedule
    assert bus(drawn(sk(True)), "p", F(10)) == [("L", 0, 1), ("H", 1, 2), ("L", 2, 4)]
    assert (eager.tasks["H"].response, eager.tasks["L"].response) == (1, 4)


def test_jobs_of_duration_zero_end_at_their_release():
    # Nothing holds the processor: every response is 0, each task runs at its period.
    data = {"tasks": {"A": {"duration": 0, "period": 2, "processor": "p"},
                      "B": {"duration": 0, "period": 3, "processor": "p"}},
            "processors": {"p": {"preemptive": False}}}
    s = analyze(Skeleton.from_dict(data), design=False).schedule
    assert s.schedulable is True and not drawn(Skeleton.from_dict(data))
    assert [(s.tasks[t].response, s.tasks[t].period) for t in "AB"] == [(0, 2), (0, 3)]


def test_one_task_on_a_non_preemptive_processor_is_the_preemptive_answer():
    def doc(preemptive):
        data = {"tasks": {"A": {"duration": 2, "period": 5, "processor": "p"},
                          "B": {"duration": 1, "period": 3, "processor": "q"}},
                "processors": {"p": {"preemptive": preemptive}}}
        out = analyze(Skeleton.from_dict(data), design=False).to_dict()
        out.pop("processors")  # says preemptive or not
        out["schedule"].pop("method")  # names the non-preemptive processor
        out["methods"].pop("schedule", None)
        return out
    assert doc(False) == doc(True)


def test_a_proven_overrun_elsewhere_decides():
    # X alone on cpu, 5 every 4: its clock ticks at 4 while job 1 runs to 5.
    r = analyze(frames(False, x_duration=5), design=False)
    assert r.schedule.schedulable is False
    assert r.schedule.tasks["X"].overrun_at == 2


def test_the_critical_instant_declines_a_non_preemptive_processor():
    for preemptive, decided in ((True, True), (False, False)):
        sk = frames(preemptive)
        verdict = independent_tasks(sk, ["F1", "F2", "F3"], platform_of(sk))
        assert (verdict is not None) is decided
    sk = frames(False)
    s = schedule_on_processors(sk, build_teg(sk), analyze(sk, design=False).groups)
    assert not any(r.get("by") == "critical instant" for r in s.regimes)


def test_rule4_does_not_call_rate_monotonic_optimal_there():
    # F1 (2.5 ms) below F2 (3.5 ms): not rate-monotonic, a warning on a preemptive
    # processor only.
    def kinds(preemptive):
        data = frames(preemptive).to_dict()
        data["tasks"]["F1"]["priority"], data["tasks"]["F2"]["priority"] = 2, 3
        return [f.kind for f in check_rules(Skeleton.from_dict(data), processors=False)]
    assert FindingKind.RULE4_NOT_RATE_MONOTONIC in kinds(True)
    assert FindingKind.RULE4_NOT_RATE_MONOTONIC not in kinds(False)


def test_the_sensitivity_decides_on_the_bus():
    # F3's response equals its period (3.5): any growth of F1's frame delays F3's past
    # its next release (F3 6-7 becomes later), so the margin of F1.duration is 0.
    result = sensitivity(frames(False), ["F1.duration"], formulas=False, verify=False)
    assert result.schedulable is True
    text = json.dumps(result.to_dict())
    assert "not implemented" not in text


def test_the_timeline_draws_the_bus():
    tl = simulate_timeline(frames(False))
    assert tl.schedulable is True
    assert bus(tl.intervals, until=F(6)) == [("F1", 0, 1), ("F2", 1, 2), ("F3", 2, 3),
                                             ("F1", 3, 4), ("F2", 4, 5), ("F1", 5, 6)]
    assert "schedulable" in render_text(tl).splitlines()[-1]


def test_the_command_line_exits_0_on_the_frames(tmp_path):
    f = tmp_path / "can.yaml"
    f.write_text("tasks:\n  F1: {duration: 1, period: 2.5, processor: can0}\n"
                 "  F2: {duration: 1, period: 3.5, processor: can0}\n"
                 "processors:\n  can0: {preemptive: false}\n")
    result = CliRunner().invoke(app, ["analyze", str(f), "--json"])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.output)
    assert doc["schedulable"] is True and doc["processors"][0]["preemptive"] is False
