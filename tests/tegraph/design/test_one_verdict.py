"""One verdict on schedulability: every command ends with analyze's (spec §4b), exactly.

``tegraph rules`` took the response-time/utilization test of ORCCAD §6 as its verdict:
on the examples and the generated skeletons below, 14 of 43 files got another
verdict from ``rules`` than from ``analyze`` (measured on the code before this
test). The test is now a cross-check beside the exact verdict, a task without a
clock is no periodic load in it, and the problems of every command come in one
order, earliest in time first.
"""

from __future__ import annotations

import importlib.util
from fractions import Fraction as F

import pytest
from typer.testing import CliRunner

import tegraph
from tegraph import Skeleton, load_skeleton
from tegraph.cli import app
from tegraph.design.timeline import simulate_timeline
from tegraph.report import render_text
from tests.paths import REPO

_spec = importlib.util.spec_from_file_location(
    "generate_skeleton", REPO / "benchmarks" / "generate_skeleton.py")
assert _spec is not None and _spec.loader is not None
generate_skeleton = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(generate_skeleton)

EXAMPLES = sorted((REPO / "examples").glob("*.yaml"))
GENERATED = [(n, seed, processors) for n in (4, 8, 12, 20, 30) for seed in range(3)
             for processors in (0, 2)]


def _generated(n: int, seed: int, processors: int) -> Skeleton:
    doc = generate_skeleton.generate(n, seed)
    return Skeleton.from_dict(generate_skeleton.spread(doc, processors) if processors else doc)


CORPUS = ([pytest.param(lambda p=p: load_skeleton(p), id=p.name) for p in EXAMPLES]
          + [pytest.param(lambda g=g: _generated(*g), id="generated-{}-s{}-p{}".format(*g))
             for g in GENERATED])


@pytest.mark.parametrize("make", CORPUS)
def test_rules_ends_with_the_verdict_of_analyze(make):
    sk = make()
    report = tegraph.analyze(sk, design=False)
    section = tegraph.rules(sk)
    # The same verdict, True, False or None (undecided within the same budget).
    assert section.schedulable == report.schedulable
    broken = any(f.severity != "info" for f in section.rules)
    assert section.exit_status == (1 if broken or report.exit_status else 0)
    last = render_text(section).splitlines()[-1]
    assert last.endswith(f"(exit status {section.exit_status})")
    if report.schedulable:
        assert last.startswith("verdict: schedulable on its processors (spec §4b, exact)")
    elif report.schedulable is None:
        assert "UNDECIDED" in last
    else:
        assert "NOT" in last
    # The response-time test is compared with it, never taken for it.
    cross = section.cross_check
    # On non-preemptive processors the design section gives bounds, no verdict: the
    # test's verdict is then that of the preemptive processors alone.
    tested = [p.schedulable for p in section.schedulability.processors if not p.cross_check]
    says = (section.schedulability.schedulable if not cross.preemptive_only
            else False if False in tested else None if None in tested or not tested
            else True)
    assert (cross.says, cross.exact) == (says, report.schedulable)
    if cross.says is not None and report.schedulable is not None:
        assert cross.agrees == (cross.says == report.schedulable and not cross.disagreements)


def test_the_corpus_is_the_one_measured():
    # 13 examples (more may come) and 30 generated skeletons: the 43 files of the count.
    assert len(EXAMPLES) >= 13 and len(GENERATED) == 30


# A quadrotor on one CPU: IMU at 1 ms with its attitude estimator (ASYN/SYN), a 2.5 ms
# rate loop with its mixer, a 20 ms position loop, a 100 ms GPS, and a logger without
# any clock (it reads both ASYN/ASYN). Rate-monotonic: imu/att_est 5, rate_ctrl/mixer 4,
# pos_ctrl 3, gps 2, logger 1.
QUAD = {
    "name": "quad", "unit": "ms",
    "clocks": {"imu_clk": {"period": 1}, "rate_clk": {"period": "5/2"},
               "pos_clk": {"period": 20}, "gps_clk": {"period": 100}},
    "tasks": {
        "imu": {"duration": "1/10", "clock": "imu_clk", "inputs": ["raw"], "outputs": ["m"]},
        "att_est": {"duration": "1/5", "inputs": ["m"], "outputs": ["q"]},
        "rate_ctrl": {"duration": "3/10", "clock": "rate_clk", "inputs": ["q"],
                      "outputs": ["u"]},
        "mixer": {"duration": "1/10", "inputs": ["u"], "outputs": ["pwm"]},
        "gps": {"duration": 5, "clock": "gps_clk", "inputs": ["nmea"], "outputs": ["fix"]},
        "pos_ctrl": {"duration": 2, "clock": "pos_clk", "inputs": ["fix", "q"],
                     "outputs": ["sp"]},
        "logger": {"duration": "1/2", "inputs": ["q", "fix"]}},
    "links": [
        {"from": "imu:m", "to": "att_est:m", "protocol": "ASYN/SYN"},
        {"from": "att_est:q", "to": "rate_ctrl:q", "protocol": "ASYN/ASYN"},
        {"from": "rate_ctrl:u", "to": "mixer:u", "protocol": "ASYN/SYN"},
        {"from": "gps:fix", "to": "pos_ctrl:fix", "protocol": "ASYN/ASYN"},
        {"from": "att_est:q", "to": "pos_ctrl:q", "protocol": "ASYN/ASYN"},
        {"from": "att_est:q", "to": "logger:q", "protocol": "ASYN/ASYN"},
        {"from": "gps:fix", "to": "logger:fix", "protocol": "ASYN/ASYN"}],
}


def test_a_clockless_logger_is_no_periodic_load(tmp_path):
    sk = Skeleton.from_dict(QUAD)
    section = tegraph.rules(sk)
    (proc,) = section.schedulability.processors
    # The periodic work of one hyperperiod (100 ms): 0.3 * 100 + 0.4 * 40 + 2 * 5 + 5 * 1
    # = 30 + 16 + 10 + 5 = 61 ms; the logger, which nothing paces, is not charged (it was
    # counted at its own 0.5 ms cycle time: 0.5 * 200 = 100 ms more, 161 ms: "FAILS").
    assert (proc.hyperperiod, proc.demand, proc.condition_holds) == (100, 61, True)
    logger = section.schedulability.unit_of("logger")
    assert logger.free_running and logger.period is None and logger.schedulable is True
    # It gets what the periodic units leave: 1 - 61/100 = 39/100 of the processor, so
    # it runs once every 1/2 / (39/100) = 50/39 ms, which the exact schedule confirms.
    assert "39/100" in logger.note or "0.39" in logger.note
    assert section.analysis.schedule.tasks["logger"].period == F(50, 39)
    assert section.schedulability.schedulable is True and section.cross_check.agrees is True
    # The verdict is the exact one (schedulable); Rules 1 and 3 still make `rules` exit 1.
    path = tmp_path / "quad.yaml"
    path.write_text(__import__("yaml").safe_dump(QUAD))
    out = CliRunner().invoke(app, ["rules", str(path)])
    assert out.exit_code == 1
    assert out.output.splitlines()[-1] == (
        "verdict: schedulable on its processors (spec §4b, exact); 1 design-rule error, "
        "1 design-rule warning (exit status 1)")
    assert "they agree" in out.output and "FAILS" not in out.output
    assert CliRunner().invoke(app, ["analyze", str(path)]).exit_code == 0


def test_rules_speaks_of_an_overrun_on_processors_that_the_test_does_not_see():
    # Figure 12: MT2 is bound to its 4 ms clock and to MT1's 10 ms message; on its
    # processor it overruns at activation 3 (by hand in the example). The response-time
    # test, which sees processor time only, says schedulable: the verdict is not its.
    section = tegraph.rules(REPO / "examples" / "fig12_double_sync.yaml")
    assert section.schedulability.schedulable is True
    assert section.schedulable is False and section.exit_status == 1
    assert section.analysis.schedule.tasks["MT2"].overrun_at == 3
    text = render_text(section)
    assert "they DISAGREE" in text
    # Tick 3 of MT2's 4 ms clock comes at 8 ms; with a processor per task too (spec §4).
    assert text.splitlines()[-1] == (
        "verdict: NOT CONSISTENT: 1 unbounded place, MT2 overruns at activation 3 (8 ms); "
        "NOT SCHEDULABLE on its processors: MT2 overruns at activation 3 (8 ms), 1 growing "
        "place; 2 design-rule errors (exit status 1)")


# A (100 ms, 101 of work) is first in the file, B (2 ms, 5/2 of work) second, each on
# a processor of its own: each job waits for the one before, so job 1 ends after tick
# 2 for both: A overruns at activation 2, at 100 ms; B at activation 2, at 2 ms.
LATE = {"tasks": {"A": {"duration": 101, "period": 100, "processor": "p0"},
                  "B": {"duration": "5/2", "period": 2, "processor": "p1"}}}


def test_every_command_names_the_earliest_problem_first():
    sk = Skeleton.from_dict(LATE)
    report = tegraph.analyze(sk)
    s = report.schedule
    assert [(p.task, p.k, p.at) for p in s.problems] == [("B", 2, 2), ("A", 2, 100)]
    last = render_text(report).splitlines()[-1]
    # With a processor per task (spec §4) and on processors (§4b) alike: B first. (Each
    # clock's place grows: the tasks are slower than their clocks.)
    assert last == (
        "verdict: NOT CONSISTENT: 2 unbounded places, B overruns at activation 2 (2 ms), A "
        "overruns at activation 2 (100 ms); NOT SCHEDULABLE on its processors: B overruns at "
        "activation 2 (2 ms), A overruns at activation 2 (100 ms), 2 growing places "
        "(exit status 1)")
    timeline = render_text(simulate_timeline(sk)).splitlines()
    overruns = [line.split(":")[1].split()[0] for line in timeline
                if line.startswith("OVERRUN")]
    assert overruns == ["B", "A"]
    assert "B overruns first" in timeline[-1]
    no_processors = render_text(tegraph.analyze(sk, processors=False)).splitlines()[-1]
    assert "B overruns at activation 2 (2 ms), A overruns" in no_processors


def test_the_timeline_names_a_starved_job_before_a_later_overrun():
    # A holds the processor all the time (2 ms every 2 ms, the more urgent): B's job,
    # released at 0, never runs (starved at 0 ms); B's tick 2 comes at 4 ms with it
    # unfinished (an overrun at 4 ms); C reads B's message ASYN/SYN: no job at all.
    # Earliest first, as analyze says it: the starved job, then the overrun.
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 2, "period": 2},
                                       "B": {"duration": 1, "period": 4, "outputs": ["y"]},
                                       "C": {"duration": 1, "inputs": ["y"]}},
                             "links": [{"from": "B:y", "to": "C:y", "protocol": "ASYN/SYN"}]})
    report = tegraph.analyze(sk)
    assert [(p.kind, p.task, p.at) for p in report.schedule.problems] == [
        ("starved", "B", 0), ("overrun", "B", 4)]
    lines = render_text(simulate_timeline(sk)).splitlines()
    named = [line.split(":")[0] for line in lines if line.startswith(("STARVED", "OVERRUN"))]
    assert named == ["STARVED", "OVERRUN"]
    assert ("STOPPED: C never runs again from the start (no job at all): it waits for B, "
            "starved") in lines
    assert lines[-1] == ("verdict: NOT schedulable on its processors: 1 starved task (B "
                         "first, its job released at 0 ms); B overruns first, at activation "
                         "2 (4 ms); 1 growing place (exit status 1)")
    last = render_text(report).splitlines()[-1]
    assert last.index("B starved") < last.index("B overruns")
