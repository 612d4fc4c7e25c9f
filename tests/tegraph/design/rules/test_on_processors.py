"""The advice says what its change does to the skeleton on its processors (spec §4b).

Every expectation is derived by hand below, from the durations and periods of the
skeletons, not read from the tool.
"""

from __future__ import annotations

import json

from tegraph import analyze, load_skeleton
from tegraph.api import rules
from tegraph.design.rules import Change, FindingKind, check_rules, on_processors
from tegraph.model.skeleton import Skeleton
from tegraph.report import to_json
from tests.paths import REPO

FIG12 = REPO / "examples" / "fig12_double_sync.yaml"

# Figure 12 on its one (default) processor. MT1: duration 1, clock rtc 10 ms, writes y;
# MT2: duration 2, its own 4 ms clock, reads y ASYN/SYN (it waits for MT1's message).
# Before: one group {MT1, MT2}, so one rate-monotonic priority for both; MT1 and MT2 never
# compete (MT2 waits for MT1's write), so the schedule is §3's:
#   MT1 runs [0,1], [10,11], [20,21] ...   (released at each rtc tick)
#   MT2 job 1 released at 1 (MT1.write:y(1) = 1), runs [1,3];
#   MT2 job 2: activated at 4 (its tick), released at MT1.write:y(2) = 11, runs [11,13];
#   MT2's tick 3 comes at 8 while job 2 has not ended (13 > 8): overrun at activation 3.
# After (MT1:y -> MT2:y ASYN/ASYN): groups {MT1} (10 ms) and {MT2} (4 ms); rate-monotonic:
# MT2 more urgent. Over the hyperperiod 20, MT2 runs [0,2] [4,6] [8,10] [12,14] [16,18],
# MT1 runs [2,3] (released 0, waits for MT2) and [10,11]: every job ends before its next
# tick, the schedule repeats every 20 ms: schedulable, MT1 every 10 ms, MT2 every 4 ms.
FIG12_EFFECT = ("on its processors (§4b), before -> after: NOT SCHEDULABLE (MT2 overruns at "
                "activation 3) -> schedulable ({MT1} 10 ms, {MT2} 4 ms)")


def _advised(findings):
    return [f for f in findings if f.change is not None]


def test_fig12_on_its_one_processor():
    findings = _advised(check_rules(load_skeleton(FIG12)))
    # Rule 1 (MT2's two synchronizations) and Rule 3 (two clocks): both cut the link.
    assert [f.kind for f in findings] == [FindingKind.RULE1_SEVERAL_SYNCS,
                                          FindingKind.RULE3_SEVERAL_CLOCKS]
    for f in findings:
        assert f.change == Change((("MT1:y", "MT2:y", "ASYN/ASYN"),))
        assert f.advice.endswith("every clocked task keeps its clock's period; "
                                 + FIG12_EFFECT + "]"), f.advice
        assert (f.schedule.tasks, f.schedule.processors) == (("MT1", "MT2"), ("default",))
        assert (f.schedule.before, f.schedule.after, f.schedule.why_undecided) == (
            False, True, None)


def test_fig12_json_carries_the_effect():
    data = json.loads(to_json(rules(FIG12)))
    first = data["rules"][0]
    assert first["schedule"] == {"part": 0, "schedulable_before": False,
                                 "schedulable_after": True, "why_undecided": None}
    # Both findings (Rules 1 and 3) touch the one part: it is written once.
    assert data["schedule_parts"] == [{"tasks": ["MT1", "MT2"], "processors": ["default"]}]
    assert [f["schedule"]["part"] for f in data["rules"] if f["schedule"]] == [0, 0]
    assert data["rules"][-1]["schedule"] is None  # Rule 4: no change


def _fig12_with_c(processor_of_c: str, c_duration: int) -> Skeleton:
    data = load_skeleton(FIG12).to_dict()
    for t in ("MT1", "MT2"):
        data["tasks"][t]["processor"] = "cpu1"
    data["tasks"]["C"] = {"duration": c_duration, "period": 5, "processor": processor_of_c}
    return Skeleton.from_dict(data)


def test_a_change_on_one_processor_leaves_the_other_alone():
    # C runs alone on cpu2 (its own group, no link): the change touches {MT1, MT2} on cpu1
    # only, and so does the part decided again; C (duration 3 of 5 ms, schedulable or not
    # alike) is not in it. On cpu1 the schedule is Figure 12's above.
    sk = _fig12_with_c("cpu2", 3)
    for f in _advised(check_rules(sk)):
        assert (f.schedule.tasks, f.schedule.processors) == (("MT1", "MT2"), ("cpu1",))
        assert f.advice.endswith(FIG12_EFFECT + "]"), f.advice


def test_a_change_includes_the_groups_sharing_its_processor():
    # C (duration 1, period 5) on cpu1 beside MT1 and MT2: the part is all three.
    # Before: {MT1, MT2} (design period 4) above {C} (5). MT1 [0,1], MT2 released at 1,
    # runs [1,3], C [3,4]; MT2's job 2 is released at 11 (MT1's second write), so its
    # tick 3 at 8 finds it not ended: MT2 overruns at activation 3, as without C.
    # After: MT2 (4) above C (5) above MT1 (10). MT2 [0,2], C [2,3], MT1 [3,4]; MT2 [4,6],
    # C [6,7] (released 5), MT2 [8,10], C [10,11], MT1 [11,12] (released 10), MT2 [12,14],
    # C [15,16], MT2 [16,18]; at 20 all three are released again with nothing pending:
    # schedulable, periods MT1 10, MT2 4, C 5 (groups in file order).
    sk = _fig12_with_c("cpu1", 1)
    (f, _) = _advised(check_rules(sk))
    assert (f.schedule.tasks, f.schedule.processors) == (("MT1", "MT2", "C"), ("cpu1",))
    assert f.advice.endswith(
        "on its processors (§4b), before -> after: NOT SCHEDULABLE (MT2 overruns at "
        "activation 3) -> schedulable ({MT1} 10 ms, {MT2} 4 ms, {C} 5 ms)]"), f.advice


def test_the_budget_in_all_spent_is_said(monkeypatch):
    monkeypatch.setattr(on_processors, "ADVICE_EVENTS", 1)
    for f in _advised(check_rules(load_skeleton(FIG12))):
        why = ("not decided: the advice's budget of 1 event firings in all is spent "
               "(tegraph analyze on the changed file decides it)")
        assert f.advice.endswith(f"; on its processors (§4b), before -> after: {why}]")
        assert (f.schedule.before, f.schedule.after, f.schedule.why_undecided) == (
            None, None, why)


def test_the_budget_per_simulation_spent_is_said(monkeypatch):
    # 5 firings cannot reach MT2's third tick (at 8 ms; both clocks tick, both tasks
    # activate, read and compute before): the verdict before is not reached. After, MT1
    # and MT2 are independent periodic tasks on one processor whose hyperperiod (20 ms,
    # 2 + 5 = 7 ticks) is more than 5 firings: the critical instant decides them without
    # simulating (spec §4b): MT2 responds in 2 <= 4, MT1 in 1 + 2 = 3 <= 10: schedulable.
    monkeypatch.setattr(on_processors, "CHANGE_EVENTS", 5)
    for f in _advised(check_rules(load_skeleton(FIG12))):
        assert f.advice.endswith("; on its processors (§4b), before -> after: undecided "
                                 "within 5 event firings -> schedulable ({MT1} 10 ms, "
                                 "{MT2} 4 ms)]"), f.advice
        assert (f.schedule.before, f.schedule.after) == (None, True)
        assert f.schedule.why_undecided == "undecided within 5 event firings per simulation"


def test_a_part_too_large_is_not_simulated(monkeypatch):
    monkeypatch.setattr(on_processors, "PART_TASKS", 1)
    # Both findings touch the one part: the second's words are the first's, kept.
    for f in _advised(check_rules(load_skeleton(FIG12))):
        assert f.advice.endswith("before -> after: not simulated: the processors it touches "
                                 "run 2 tasks, more than the advice simulates per change (1; "
                                 "tegraph analyze on the changed file decides it)]"), f.advice
        assert f.schedule.tasks == ("MT1", "MT2") and f.schedule.before is None


def test_without_processors_the_advice_leaves_it_out():
    sk = load_skeleton(FIG12)
    for findings in (check_rules(sk, processors=False),
                     analyze(sk, processors=False).design.rules,
                     rules(sk, processors=False).rules):
        for f in _advised(findings):
            assert "§4b" not in f.advice and f.schedule is None
            assert f.advice.endswith("every clocked task keeps its clock's period]")
    # ... and with them (the defaults of analyze and rules), it is said.
    assert all(f.advice.endswith(FIG12_EFFECT + "]")
               for f in _advised(analyze(sk).design.rules))


def test_each_change_states_the_first_use_of_the_chains_it_touches():
    # Figure 4 unsynchronized with MT4 the most urgent (priorities 1, 2, 3, 4): as it is,
    # 26 ms (spec §4c's example). Rule 2 advises synchronizing each hop:
    # - MT1:x1 -> MT2:x1 ASYN/SYN (MT2 loses its clock): MT4 0-1, MT3 1-3, MT1 (the least
    #   urgent) 3-4, sampling at 3 and writing at 4, MT2 released at 4 runs 4-6; MT3 at 11
    #   reads MT2's write of 6, writes 13; MT4 at 20 reads it, posts at 21: 21 - 3 = 18;
    # - MT2:x2 -> MT3:x2 ASYN/SYN: MT4 0-1, MT2 1-3, MT3 (released at 3) 3-5, MT1 5-6; the
    #   sample of 5 is read by MT2 at 11, by MT3 at 13, by MT4 at 20, posted at 21: 16.
    data = load_skeleton(REPO / "examples" / "fig4_pipeline_unsynchronized.yaml").to_dict()
    for p, task in enumerate(["MT1", "MT2", "MT3", "MT4"], 1):
        data["tasks"][task]["priority"] = p
    data["chains"] = [["MT1", "MT2", "MT3", "MT4"]]
    section = rules(Skeleton.from_dict(data))
    said = [f.advice.split("first use on its processors (§4c), before -> after: ")[1]
            for f in section.rules if f.rule == 2]
    assert said[:2] == ["MT1 -> MT2 -> MT3 -> MT4 26 ms -> 18 ms]",
                        "MT1 -> MT2 -> MT3 -> MT4 26 ms -> 16 ms]"]
    # Without a chain, no such clause.
    data.pop("chains")
    assert not any("first use" in f.advice for f in rules(Skeleton.from_dict(data)).rules)
