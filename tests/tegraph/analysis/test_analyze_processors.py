"""analyze on the processors (spec v1.2 §4b, §5): the verdict a control engineer asks for.

Expected figures are derived by hand in the comments from the files' durations.
"""

from __future__ import annotations

import json
from fractions import Fraction as F

from typer.testing import CliRunner

from tegraph import analyze, load_skeleton
from tegraph.analysis.processors import MAX_EVENTS
from tegraph.cli import MAX_EVENTS as CLI_MAX_EVENTS
from tegraph.cli import app
from tegraph.model.skeleton import Skeleton
from tegraph.report import render_text
from tests.paths import REPO

TORQUE = REPO / "examples" / "computed_torque.yaml"


def _doubled(tmp_path):
    data = load_skeleton(TORQUE).to_dict()
    for task in data["tasks"].values():
        task["duration"] = str(F(task["duration"]) * 2)
    path = tmp_path / "doubled.yaml"
    path.write_text(json.dumps(data), encoding="utf-8")
    return path


def test_figure_17_on_one_cpu():
    # Rate-monotonic: OBS.JL (1 ms) 3, the 2 ms group 2, MOD.DYN (6 ms) 1. From 0: OBS.JL
    # 0-0.1; TG.JS 0.1-0.2 (released 0: response 0.2); TF.TT.JS reads TG's qd, released
    # 0.2, runs 0.2-0.4 (0.2); CO.JS 0.4-0.7 (0.3); MOD.DYN 0.7-1.0, preempted by OBS.JL
    # 1.0-1.1, then 1.1-2.0: 0.3 + 0.9 = 1.2 at 2.0, in the second basic cycle: response
    # 2. Every job ends before its next tick: schedulable, the periods are the clocks'.
    r = analyze(load_skeleton(TORQUE))
    s = r.schedule
    assert r.schedulable is True and r.exit_status == 0 and s.exact
    assert {t: s.tasks[t].response for t in s.tasks} == {
        "OBS.JL": F(1, 10), "TG.JS": F(2, 10), "TF.TT.JS": F(2, 10), "CO.JS": F(3, 10),
        "MOD.DYN": F(2)}
    assert s.platform.priority == {"OBS.JL": 3, "TG.JS": 2, "TF.TT.JS": 2, "CO.JS": 2,
                                   "MOD.DYN": 1}
    assert s.group_periods == [F(1), F(2), F(6)]


def test_doubled_durations_overrun_on_one_cpu_though_each_task_alone_keeps_pace(tmp_path):
    # Durations x2: utilization 0.2 + 1.2/2 + 2.4/6 = 1.2 > 1. In every 2 ms window the
    # CPU gives OBS.JL 0.4 and the 2 ms chain 1.2, MOD.DYN the last 0.4: its 2.4 ms end
    # at 12 > its tick 2 at 6: overrun at activation 2 (and its clock's place grows).
    # With a processor per task (§4) it keeps its 6 ms pace: exit 0 there.
    path = _doubled(tmp_path)
    result = CliRunner().invoke(app, ["analyze", str(path)])
    assert result.exit_code == 1
    last = result.output.rstrip().splitlines()[-1]
    assert last == ("verdict: live and consistent with a processor per task, but NOT "
                    "SCHEDULABLE on its processors: MOD.DYN overruns at activation 2 (6 ms), "
                    "1 growing place (exit status 1)")
    doc = json.loads(CliRunner().invoke(app, ["analyze", str(path), "--json"]).output)
    assert doc["schedulable"] is False and doc["consistent"] is True
    assert doc["tasks"]["MOD.DYN"]["on_processors"]["overrun_at"] == 2
    assert doc["tasks"]["MOD.DYN"]["overrun_at"] is None
    assert doc["schedule"]["unbounded_places"][0]["from"] == "dyn.tick"
    old = CliRunner().invoke(app, ["analyze", str(path), "--no-processors"])
    assert old.exit_code == 0
    # The v1.1 verdict, with the response-time test's failure as advice beside it.
    assert old.output.rstrip().splitlines()[-1].startswith(
        "verdict: live and consistent (exit status 0); the design section lists a processor "
        "that fails its schedulability test")


def test_two_tasks_of_one_rate_that_do_not_fit_fail_the_verdict():
    # A (6 ms, priority 2) runs 0-6 and 10-16; B gets 6-10 and 16-18: B's first job
    # ends at 18 > its tick 2 at 10: overrun at activation 2; before v1.2, exit 0.
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 6, "period": 10, "priority": 2},
                                       "B": {"duration": 6, "period": 10, "priority": 1}}})
    r = analyze(sk)
    assert r.exit_status == 1 and r.schedule.tasks["B"].overrun_at == 2
    assert "NOT SCHEDULABLE on its processors: B overruns at activation 2" in render_text(r)
    assert analyze(sk, processors=False).exit_status == 0


def test_a_dead_skeleton_keeps_its_live_groups_on_processors():
    # fig7b's three tasks are dead; a lone 5 ms task beside them runs (its group lives).
    data = load_skeleton(REPO / "examples" / "fig7b_wrong_order.yaml").to_dict()
    data["tasks"]["Z"] = {"duration": 1, "period": 5}
    r = analyze(Skeleton.from_dict(data))
    assert r.schedulable is False and not r.live
    assert r.schedule.tasks["Z"].period == 5 and r.schedule.tasks["Z"].response >= 1
    assert r.schedule.tasks["MT1"].period is None


def test_the_response_time_test_is_only_a_cross_check():
    # Example 19 of the issue in JSON: processors listed in file order, their source.
    r = analyze(load_skeleton(TORQUE))
    doc = r.to_dict()
    assert doc["processors"] == [{"name": "default", "tasks": list(r.tasks),
                                  "priorities": dict(r.schedule.platform.priority),
                                  "priority_source": "rate-monotonic", "preemptive": True,
                                  "replaced_priorities": {}}]
    assert [g["period_on_processors"] for g in doc["groups"]] == ["1", "2", "6"]
    # CO.JS has no clock of its own: no time from a tick (spec v1.3 §4b).
    assert doc["tasks"]["CO.JS"]["on_processors"] == {
        "period": "2", "overrun_at": None, "response": "3/10", "response_from_tick": None,
        "starved": False, "stopped_after": None, "waits_for": [], "decided": True}
    # Figure 17 (by hand in the example's header): MOD.DYN released at its tick 0 runs
    # 0.7-1.0 and 1.1-2.0, every 6 ms alike: 2 from release and from its tick; TG.JS,
    # released at its tick 0, waits for OBS.JL (0-0.1) and runs 0.1-0.2: 1/5 both.
    for task, value in (("MOD.DYN", "2"), ("TG.JS", "1/5")):
        figures = doc["tasks"][task]["on_processors"]
        assert (figures["response"], figures["response_from_tick"]) == (value, value)


def test_the_command_line_default_is_the_library_constant():
    assert CLI_MAX_EVENTS == MAX_EVENTS
