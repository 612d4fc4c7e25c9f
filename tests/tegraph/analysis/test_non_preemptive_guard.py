"""A processor declared ``preemptive: false`` (spec §4d) never gets a preemptive answer.

The schedule engine is preemptive (§4b); until it schedules non-preemptively, a
part with such a processor is not decided: its figures are null and the verdict
is null with the reason. Every preemption-only theorem declines it: the critical
instant and Lehoczky-Sha-Ding (and the sensitivity's parts built on them), the
response-time cross-check (Joseph and Pandya, no blocking term), and Rule 4's
rate-monotonic order (optimal under preemption only).
"""

from __future__ import annotations

import json

from typer.testing import CliRunner

from tegraph import analyze
from tegraph.analysis.processors import schedule_on_processors
from tegraph.analysis.processors.critical_instant import independent_tasks
from tegraph.analysis.processors.schedule import NON_PREEMPTIVE
from tegraph.analysis.sensitivity import sensitivity
from tegraph.cli import app
from tegraph.design.rules import FindingKind, check_rules
from tegraph.design.schedulability import NOT_PREEMPTIVE
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


def test_the_schedule_is_not_computed_and_says_why():
    r = analyze(frames(False), design=False)
    s = r.schedule
    assert s is not None and s.schedulable is None and r.exit_status == 1
    assert NON_PREEMPTIVE in s.why_undecided and "can0" in s.why_undecided
    for t in ("F1", "F2", "F3"):  # no figure claimed for the frames
        assert r.on_processors(t) == {"period": None, "overrun_at": None, "response": None,
                                      "response_from_tick": None, "starved": False,
                                      "stopped_after": None, "waits_for": [],
                                      "decided": False}
    # The part on the preemptive cpu is decided as always: X alone, response 1.
    assert r.on_processors("X")["response"] == "1" and s.tasks["X"].decided
    doc = r.to_dict()
    assert [(p["name"], p["preemptive"]) for p in doc["processors"]] == [
        ("can0", False), ("cpu", True)]
    text = render_text(r)
    assert "UNDECIDED" in text and NON_PREEMPTIVE in text


def test_preemptive_frames_are_decided():
    # The same frames on a preemptive processor (§4b): F1 0-1, F2 1-2, F3 from 2, preempted
    # by F1 at 2.5 (to 3.5) and by F2's second job at 3.5 (to 4.5): F3's clock ticks at
    # 3.5 while its first job runs, an overrun at activation 2. Without preemption F3
    # would run 2-3 and meet its period (Davis et al. 2007): the answer a bus must not get.
    r = analyze(frames(True), design=False)
    assert r.schedule.schedulable is False and r.schedule.tasks["F3"].overrun_at == 2
    assert all(p["preemptive"] for p in r.to_dict()["processors"])


def test_a_proven_overrun_elsewhere_still_decides():
    # X alone on cpu, 5 every 4: its clock ticks at 4 while job 1 runs to 5.
    r = analyze(frames(False, x_duration=5), design=False)
    assert r.schedule.schedulable is False
    assert r.schedule.tasks["X"].overrun_at == 2


def test_the_critical_instant_declines_a_non_preemptive_processor():
    for preemptive, decided in ((True, True), (False, False)):
        sk = frames(preemptive)
        plat = platform_of(sk)
        verdict = independent_tasks(sk, ["F1", "F2", "F3"], plat)
        assert (verdict is not None) is decided
    sk = frames(False)
    s = schedule_on_processors(sk, build_teg(sk), analyze(sk, design=False).groups)
    assert not any(r.get("by") == "critical instant" for r in s.regimes)


def test_the_response_time_test_is_not_applied():
    r = analyze(frames(False), margins_max_tasks=0)
    sched = r.design.schedulability
    can0 = next(p for p in sched.processors if p.processor == "can0")
    assert not can0.preemptive and can0.schedulable is None
    assert all(u.schedulable is None and u.response_time is None and NOT_PREEMPTIVE in u.note
               for u in can0.units)
    # Never "schedulable" by a test that does not apply.
    assert sched.schedulable is None and sched.not_applied == [can0]
    cpu = next(p for p in sched.processors if p.processor == "cpu")
    assert cpu.preemptive and cpu.schedulable is True
    assert r.to_dict()["design"]["schedulability"]["processors"][0]["preemptive"] is False


def test_rule4_does_not_call_rate_monotonic_optimal_there():
    # F1 (2.5 ms) below F2 (3.5 ms): not rate-monotonic, a warning on a preemptive
    # processor only.
    def kinds(preemptive):
        data = frames(preemptive).to_dict()
        data["tasks"]["F1"]["priority"], data["tasks"]["F2"]["priority"] = 2, 3
        return [f.kind for f in check_rules(Skeleton.from_dict(data), processors=False)]
    assert FindingKind.RULE4_NOT_RATE_MONOTONIC in kinds(True)
    assert FindingKind.RULE4_NOT_RATE_MONOTONIC not in kinds(False)


def test_the_sensitivity_on_processors_says_undecided():
    result = sensitivity(frames(False), ["F1.duration"], formulas=False, verify=False)
    assert result.processors and result.schedulable is None
    text = json.dumps(result.to_dict())
    assert NON_PREEMPTIVE in text


def test_the_timeline_draws_nothing_it_did_not_compute(tmp_path):
    tl = simulate_timeline(frames(False))
    assert tl.schedulable is None
    assert not [i for i in tl.intervals if i.processor == "can0"]
    assert [i.task for i in tl.intervals if i.processor == "cpu"]
    text = render_text(tl)
    assert f"not computed ({NON_PREEMPTIVE})" in text and "raise `max_events`" not in text
    assert "hyperperiod" not in text.splitlines()[-1]  # no budget is to blame


def test_the_command_line_exits_1_with_the_reason(tmp_path):
    f = tmp_path / "can.yaml"
    f.write_text("tasks:\n  F1: {duration: 1, period: 2.5, processor: can0}\n"
                 "  F2: {duration: 1, period: 3.5, processor: can0}\n"
                 "processors:\n  can0: {preemptive: false}\n")
    result = CliRunner().invoke(app, ["analyze", str(f), "--json"])
    assert result.exit_code == 1, result.output
    doc = json.loads(result.output)
    assert doc["schedulable"] is None and NON_PREEMPTIVE in doc["schedule"]["why_undecided"]
    assert doc["processors"][0]["preemptive"] is False
