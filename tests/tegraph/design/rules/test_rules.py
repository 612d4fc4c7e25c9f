"""Design rules 1-4 of ORCCAD section 6, and the spec §6 keys they read.

Every expected finding is derived by hand from the skeleton in the test (the
synchronizations of each task are listed in a comment); the groups are
cross-checked against the weakly connected parts that ``analyze`` computes
on the timed event graph (a different algorithm).
"""

from __future__ import annotations

import json
import subprocess
import sys
from fractions import Fraction as F

import pytest

from tegraph import SkeletonError, analyze, load_skeleton
from tegraph.design.rules import (
    Change,
    FindingKind,
    apply_change,
    check_rules,
    is_automaton,
    proposed_priorities,
    synchronizations,
)
from tegraph.io import dump_skeleton
from tegraph.model.skeleton import Skeleton
from tegraph.report.design_text import render_rules
from tests.paths import REPO

EXAMPLES = REPO / "examples"


def sk(data: dict) -> Skeleton:
    return Skeleton.from_dict(data)


def of_rule(findings, rule: int, severity: str | None = None):
    return [f for f in findings if f.rule == rule and (severity is None or f.severity == severity)]


# Computed torque (Figure 15): OBS.JL {clock obs}, TG.JS {clock ctl}, TF.TT.JS {input qd},
# CO.JS {input e; M, N are ASYN/ASYN}, MOD.DYN {clock dyn}: one synchronization each;
# groups {OBS.JL} (1 ms), {TG.JS, TF.TT.JS, CO.JS} (2 ms), {MOD.DYN} (6 ms), one clock each.
def computed_torque(**priorities: int) -> Skeleton:
    data = load_skeleton(EXAMPLES / "computed_torque.yaml").to_dict()
    for task, p in priorities.items():
        data["tasks"][task.replace("_", ".")]["priority"] = p
    return Skeleton.from_dict(data)


# ------------------------------------------------------------------ Rule 1

def test_rule1_passes_when_each_task_has_one_synchronization():
    findings = check_rules(load_skeleton(EXAMPLES / "fig4_pipeline_synchronized.yaml"))
    # MT1 {clock rtc}, MT2..MT4 {their ASYN/SYN input}: exactly one each.
    assert of_rule(findings, 1) == []


def test_rule1_double_synchronization_of_figure_12():
    s = load_skeleton(EXAMPLES / "fig12_double_sync.yaml")
    # MT2 has its private clock MT2.clock AND reads y ASYN/SYN from MT1: two.
    assert [x.label for x in synchronizations(s, "MT2")] == [
        "clock MT2.clock", "input MT2:y (MT1:y -> MT2:y (ASYN/SYN))"]
    (f,) = of_rule(check_rules(s), 1)
    assert (f.severity, f.tasks, f.ports, f.links) == (
        "error", ("MT2",), ("MT2:y",), ("MT1:y -> MT2:y (ASYN/SYN)",))
    assert "2 synchronizations" in f.message
    # Two one-edit changes remove it with nothing new: keep the input read first (footnote
    # 6) and drop MT2's 4 ms clock, which makes MT2 run at MT1's 10 ms; or keep the clock
    # and read y ASYN/ASYN, which keeps both sampling periods: preferred.
    assert f.advice.startswith("keep only its clock")
    assert "make MT1:y -> MT2:y ASYN/ASYN" in f.advice
    # Before, MT2 waits for MT1's 10 ms message: it runs every 10 ms while its 4 ms clock
    # ticks on (the ticks queue): the group runs at two rates (the advice states the
    # periods the skeleton runs at, not the fastest clock's).
    assert ("{MT1, MT2} not rate-consistent (clock rtc 10 ms, clock MT2.clock 4 ms) -> "
            "{MT1} 10 ms, {MT2} 4 ms") in f.advice
    assert f.change == Change((("MT1:y", "MT2:y", "ASYN/ASYN"),))


def test_rule1_counts_blocking_outputs_and_rendezvous():
    # W: clock c + output a posted SYN/ASYN (W blocks) = 2; R reads a SYN/ASYN (never
    # blocks) = 0 and is in no thread -> warning.
    s = sk({"clocks": {"c": {"period": 5}},
            "tasks": {"W": {"duration": 1, "clock": "c", "outputs": ["a"]},
                      "R": {"duration": 1, "inputs": ["a"]}},
            "links": [{"from": "W:a", "to": "R:a", "protocol": "SYN/ASYN"}]})
    errors = of_rule(check_rules(s), 1, "error")
    assert [(f.tasks, f.ports) for f in errors] == [(("W",), ("W:a",))]
    # W keeps its clock (no input: the clock comes first). Cutting a (ASYN/ASYN) would
    # leave R alone in a group without a clock (a new Rule 3 error); ASYN/SYN hands the
    # wait over to R, which then has its one synchronization (R's warning goes too).
    assert errors[0].change == Change((("W:a", "R:a", "ASYN/SYN"),))
    # Before, R waits for nothing (it reads SYN/ASYN, no clock): it runs every 1 ms (its
    # duration) beside W's 5 ms. After, R waits for W's message: {W, R} runs at 5 ms.
    # On their one processor (one group, one priority): before, R runs whenever W does not
    # (4 ms of every 5) and posts 4 requests per 5 ms that W takes once: the place of
    # requests R.read:a -> W.write:a grows. After, W [0,1], R [1,2], again every 5 ms.
    assert errors[0].advice == ("keep only its clock: make W:a -> R:a ASYN/SYN (R waits for "
                                "W's message) [periods (max cycle ratio), "
                                "before -> after: {W, R} not rate-consistent (clock c 5 ms, "
                                "R 1 ms) -> {W, R} 5 ms; every clocked task keeps its "
                                "clock's period; on its processors (§4b), before -> after: "
                                "NOT SCHEDULABLE (the place R.read:a -> W.write:a grows "
                                "(requests-overwritten)) -> schedulable ({W, R} 5 ms)]")
    warnings = of_rule(check_rules(s), 1, "warning")
    assert [f.tasks for f in warnings] == [("R",)]
    assert "no synchronization" in warnings[0].message


def test_rule1_task_in_a_thread_needs_no_synchronization_of_its_own():
    # DIAG has no clock and no port, but its thread runs it after LOG.
    s = sk({"clocks": {"c": {"period": 5}},
            "tasks": {"LOG": {"duration": 1, "clock": "c"}, "DIAG": {"duration": 1}},
            "threads": [["LOG", "DIAG"]]})
    assert of_rule(check_rules(s), 1) == []


# ------------------------------------------------------------------ Rule 2

def test_rule2_passes_for_the_computed_torque_law():
    # The only ASYN/ASYN links join MOD.DYN (6 ms) and CO.JS (2 ms): different rates.
    assert of_rule(check_rules(computed_torque()), 2) == []


def test_rule2_rendezvous_is_flagged():
    (f,) = of_rule(check_rules(load_skeleton(EXAMPLES / "fig11_fixed_order.yaml")), 2)
    assert (f.severity, f.tasks, f.ports, f.links) == (
        "warning", ("MT1", "MT2"), ("MT1:a", "MT2:a"), ("MT1:a -> MT2:a (SYN/SYN)",))
    assert "ASYN/SYN" in f.advice


def test_rule2_unsynchronized_pipeline_of_figure_4():
    # Four groups, each one private 10 ms clock; the three ASYN/ASYN links join
    # groups of the same period: three findings, one per link.
    pipeline = load_skeleton(EXAMPLES / "fig4_pipeline_unsynchronized.yaml")
    findings = of_rule(check_rules(pipeline), 2)
    assert [f.links for f in findings] == [("MT1:x1 -> MT2:x1 (ASYN/ASYN)",),
                                           ("MT2:x2 -> MT3:x2 (ASYN/ASYN)",),
                                           ("MT3:x3 -> MT4:x3 (ASYN/ASYN)",)]
    # MT1 and MT2 join one group paced by MT1's 10 ms clock; MT2's own clock was 10 ms too.
    # On their one processor all four tasks need 1 + 2 + 2 + 1 = 6 ms of every 10, each
    # released at a 10 ms tick (or, after, at MT1's end): every job ends before the next.
    assert ("make MT1:x1 -> MT2:x1 ASYN/SYN (MT2 waits for MT1's message); remove the clock "
            "MT2.clock of MT2 [periods (max cycle ratio), before -> after: "
            "{MT1} 10 ms, {MT2} 10 ms -> {MT1, MT2} 10 ms; every clocked task keeps its "
            "clock's period; on its processors (§4b), before -> after: schedulable ({MT1} "
            "10 ms, {MT2} 10 ms, {MT3} 10 ms, {MT4} 10 ms) -> schedulable ({MT1, MT2} 10 ms, "
            "{MT3} 10 ms, {MT4} 10 ms)]") == findings[0].advice
    assert findings[0].change == Change((("MT1:x1", "MT2:x1", "ASYN/SYN"),), ("MT2",))
    assert all("Figure 4" in f.message for f in findings)


# ------------------------------------------------------------------ Rule 3

def test_rule3_passes_with_one_clock_per_group():
    assert of_rule(check_rules(computed_torque()), 3) == []


def test_rule3_group_without_clock_figure_7a():
    (f,) = of_rule(check_rules(load_skeleton(EXAMPLES / "fig7a_circular_wait.yaml")), 3)
    assert (f.severity, f.tasks) == ("error", ("MT1", "MT2", "MT3"))
    # Every task waits for an input: the advice also breaks the wait.
    # No clock anywhere and a dead group: the period proposed is a multiple of its longest
    # duration (1 ms), the shortest first, judged on its one processor (one priority;
    # release, then file order). The circular wait through MT2:b -> MT1:b is cut, so the
    # skeleton (dead, Figure 7a) becomes live. At 1 ms, three jobs of 1 ms each per 1 ms
    # cannot fit: MT1 [0,1]; at 1 MT1#2 and MT2#1 are released, MT1 first [1,2]; at 2 MT2#1
    # (released 1) [2,3]; at 3 MT1#3 (released 2) before MT3#1 (released 3) [3,4]: MT1's
    # tick 4 at 3 finds activation 3 not ended: MT1 overruns at activation 4. At 2 ms, 3
    # ms of work every 2 ms cannot fit either. At 3 ms: MT1 [0,1], MT2 reads a at 1 [1,2],
    # MT3 reads b at 2 [2,3], and again from each tick: schedulable, the processor full.
    assert f.change == Change((("MT2:b", "MT1:b", "ASYN/ASYN"),), add_clock=("MT1",),
                              period=F(3))
    assert f.advice == ("make MT2:b -> MT1:b ASYN/ASYN (neither side waits); give MT1 a clock "
                        "of its own, of period 3 ms (one clock for the whole group; a multiple "
                        "of its longest duration (no clock around it); the first of 3 periods "
                        "tried that is schedulable on its processors) [periods (max cycle "
                        "ratio), before -> after: {MT1, MT2, MT3} dead -> {MT1, MT2, MT3} 3 ms; "
                        "on its processors (§4b), before -> after: NOT SCHEDULABLE (dead: a "
                        "token-free circuit) -> schedulable ({MT1, MT2, MT3} 3 ms) (the new "
                        "clock at 3 ms, the period proposed)] This also makes the skeleton "
                        "live.")
    # With the period the check assumes (1 ms, no period being known), it overruns.
    one = analyze(apply_change(load_skeleton(EXAMPLES / "fig7a_circular_wait.yaml"),
                               f.change, F(1)), design=False)
    assert one.schedule.tasks["MT1"].overrun_at == 4


def test_rule3_group_without_clock_names_its_source():
    # C reads nothing: the clock goes there. C already waits to post z (SYN/ASYN to B):
    # a clock as well would be two synchronizations (Rule 1), so z is cut (ASYN/ASYN);
    # the group stays one through C:y -> A:y and A:x -> B:x, D:x.
    # No clock around it: the period is a multiple of the group's cycle time, 7/3 ms. On
    # the one processor the group needs 1 + 2 + 5/3 + 1 = 17/3 ms of work per period: 7/3
    # and 14/3 ms are too short, 7 ms the first that is schedulable.
    (f,) = of_rule(check_rules(load_skeleton(EXAMPLES / "ring_two_tokens.yaml")), 3)
    assert f.change == Change((("C:z", "B:z", "ASYN/ASYN"),), add_clock=("C",), period=F(7))


def test_rule3_two_clocks_in_one_group():
    (f,) = of_rule(check_rules(load_skeleton(EXAMPLES / "overrun_in_step.yaml")), 3)
    assert (f.severity, f.tasks) == ("error", ("MT1", "MT2"))
    assert "2 clocks (MT1.clock on MT1, MT2.clock on MT2)" in f.message
    # Both clocks are 10 ms: MT2 keeps its sampling period on MT1's clock.
    # On their one processor (12 ms of work every 10 ms, one priority; a job runs by its
    # release, then file order): before, MT1 [0,6], MT2 [6,12] past MT2's tick at 10:
    # MT2 overruns at activation 2. After, MT2#k is released at max(MT1's k-th end,
    # MT2#(k-1)'s end): MT1 [0,6], MT2 [6,12], MT1 [12,18], MT2 [18,24], MT1 [24,30],
    # MT1 [30,36] (released 30, before MT2#3 released 30), MT2 [36,42], MT1 [42,48],
    # MT2 [48,54] (released 42), MT1 [54,60], MT2#5 (released 54) [60,66] before MT1#7
    # (released 60) [66,72], past MT1's tick at 70: MT1 overruns at activation 8.
    assert f.advice == ("keep one clock (MT1.clock): remove the clock MT2.clock of MT2 "
                        "[periods (max cycle ratio), before -> after: "
                        "{MT1, MT2} 10 ms, unchanged; every clocked task keeps its clock's "
                        "period; on its processors (§4b), before -> after: NOT SCHEDULABLE "
                        "(MT2 overruns at activation 2) -> NOT SCHEDULABLE (MT1 overruns at "
                        "activation 8)]")


# ------------------------------------------------------------------ Rule 4

def test_rule4_proposal_when_nothing_is_declared():
    (f,) = of_rule(check_rules(computed_torque()), 4)
    # Rate-monotonic by hand: 1 ms group first, then 2 ms, then 6 ms: 3, 2, 1.
    assert f.severity == "info"
    assert "OBS.JL: 3, TG.JS: 2, TF.TT.JS: 2, CO.JS: 2, MOD.DYN: 1" in f.advice
    assert proposed_priorities(computed_torque()) == {
        "OBS.JL": 3, "TG.JS": 2, "TF.TT.JS": 2, "CO.JS": 2, "MOD.DYN": 1}


def test_rule4_passes_with_rate_monotonic_priorities():
    s = computed_torque(OBS_JL=30, TG_JS=20, TF_TT_JS=20, CO_JS=20, MOD_DYN=10)
    findings = check_rules(s)
    assert findings == []
    assert render_rules(findings).startswith("design rules (ORCCAD section 6): all followed")


def test_rule4_one_group_two_priorities():
    s = computed_torque(OBS_JL=30, TG_JS=20, TF_TT_JS=21, CO_JS=20, MOD_DYN=10)
    (f,) = of_rule(check_rules(s), 4)
    assert (f.severity, f.tasks) == ("error", ("TG.JS", "TF.TT.JS", "CO.JS"))
    assert "TF.TT.JS: 21" in f.message and "e.g. 21" in f.advice


def test_rule4_two_groups_one_priority():
    s = computed_torque(OBS_JL=20, TG_JS=20, TF_TT_JS=20, CO_JS=20, MOD_DYN=10)
    (f,) = of_rule(check_rules(s), 4)
    assert (f.severity, f.tasks) == ("error", ("OBS.JL", "TG.JS", "TF.TT.JS", "CO.JS"))
    assert "share priority 20" in f.message


def test_rule4_groups_on_different_processors_may_share_a_priority():
    data = computed_torque(OBS_JL=20, TG_JS=20, TF_TT_JS=20, CO_JS=20, MOD_DYN=10).to_dict()
    data["tasks"]["OBS.JL"]["processor"] = "cpu1"
    assert of_rule(check_rules(Skeleton.from_dict(data)), 4) == []


def test_rule4_not_rate_monotonic():
    # MOD.DYN (6 ms) above the 2 ms group.
    s = computed_torque(OBS_JL=30, TG_JS=10, TF_TT_JS=10, CO_JS=10, MOD_DYN=20)
    (f,) = of_rule(check_rules(s), 4)
    assert f.severity == "warning" and "not rate-monotonic" in f.message
    assert f.tasks == ("TG.JS", "TF.TT.JS", "CO.JS", "MOD.DYN")


def test_rule4_every_inverted_slower_group_is_reported():
    # Periods 1 (prio 10), 2 (prio 30), 6 (prio 20). Pairs (faster, slower): (1, 2) and
    # (1, 6) are inverted (10 < 30, 10 < 20); (2, 6) is not (30 > 20). Two warnings, each
    # naming OBS.JL as the faster group left below.
    s = computed_torque(OBS_JL=10, TG_JS=30, TF_TT_JS=30, CO_JS=30, MOD_DYN=20)
    findings = of_rule(check_rules(s), 4)
    assert [(f.severity, f.tasks) for f in findings] == [
        ("warning", ("OBS.JL", "TG.JS", "TF.TT.JS", "CO.JS")),
        ("warning", ("OBS.JL", "MOD.DYN"))]


def test_rule4_some_priorities_missing():
    # Four of five tasks on the one processor declare: all or none (spec §4b), so all
    # five run rate-monotonic (3, 2, 2, 2, 1) and the four declared are replaced. An
    # error, whose change keeps them: MOD.DYN (6 ms, the slowest) goes below the 2 ms
    # group's 20, at 19.
    s = computed_torque(OBS_JL=30, TG_JS=20, TF_TT_JS=20, CO_JS=20)
    (f,) = of_rule(check_rules(s), 4)
    assert (f.severity, f.tasks) == ("error", ("MOD.DYN",))
    assert f.change is not None and f.change.priorities == (("MOD.DYN", 19),)
    assert "OBS.JL 30 -> 3" in f.message and "MOD.DYN: 19" in f.advice
    assert of_rule(check_rules(apply_change(s, f.change)), 4) == []


def test_rule4_automaton_highest():
    assert is_automaton("RTA") and is_automaton("arm.Automaton") and not is_automaton("PARTA")
    base = {"tasks": {"OBS": {"duration": 1, "period": 1, "priority": 5, "outputs": ["ev"]},
                      "RTA": {"duration": 0, "inputs": ["ev"], "priority": 4}},
            "links": [{"from": "OBS:ev", "to": "RTA:ev", "protocol": "ASYN/SYN"}]}
    (f,) = of_rule(check_rules(sk(base)), 4)
    assert (f.severity, f.tasks) == ("error", ("RTA", "OBS"))
    assert "give RTA a priority above 5" in f.advice
    base["tasks"]["RTA"]["priority"] = 6
    assert of_rule(check_rules(sk(base)), 4) == []
    # The proposal puts the automaton on top though it shares OBS's group.
    del base["tasks"]["RTA"]["priority"], base["tasks"]["OBS"]["priority"]
    assert proposed_priorities(sk(base)) == {"OBS": 1, "RTA": 2}


# ------------------------------------------------------------------ spec §6 keys

def test_priority_processor_chains_round_trip(tmp_path):
    text = ("tasks:\n"
            "  A: {duration: 1, period: 2, priority: 010, processor: 1, outputs: [x]}\n"
            "  B: {duration: 1, inputs: [x], priority: -3, processor: cpu.b}\n"
            "links:\n  - {from: 'A:x', to: 'B:x', protocol: ASYN/SYN}\n"
            "chains:\n  - [A, B]\n")
    f = tmp_path / "s.yaml"
    f.write_text(text)
    s = load_skeleton(f)
    # 010 is ten as written (not YAML 1.1's octal eight); the processor 1 is a name.
    assert (s.tasks["A"].priority, s.tasks["A"].processor) == (10, "1")
    assert (s.tasks["B"].priority, s.tasks["B"].processor) == (-3, "cpu.b")
    assert s.chains == [("A", "B")]
    for suffix in (".yaml", ".json"):
        assert load_skeleton(dump_skeleton(s, tmp_path / f"copy{suffix}")) == s


@pytest.mark.parametrize("task_line, key_path, wording", [
    ("priority: high", "tasks.A.priority", "expected a priority (an integer"),
    ("priority: 1.5", "tasks.A.priority", "got float 1.5"),
    ("priority: true", "tasks.A.priority", "got the boolean true"),
    ("priority: null", "tasks.A.priority", "got nothing (null)"),
    ("processor: ''", "tasks.A.processor", "expected a non-empty processor name"),
    ("processor: [a]", "tasks.A.processor", "expected a processor name (a text), got a list"),
    ("processor: 'a:b'", "tasks.A.processor", "contains ':'"),
])
def test_task_key_refusals(tmp_path, task_line, key_path, wording):
    f = tmp_path / "s.yaml"
    f.write_text(f"tasks:\n  A:\n    duration: 1\n    {task_line}\n")
    with pytest.raises(SkeletonError) as info:
        load_skeleton(f)
    assert info.value.where == key_path and info.value.line == 4
    assert wording in info.value.reason and "expected" in info.value.reason


@pytest.mark.parametrize("chains, key_path, wording", [
    ("[[A, C]]", "chains[0][1]", "no task 'C'"),
    ("[[A, B, A]]", "chains[0][2]", "the task 'A' is already at chains[0][0]"),
    ("[[B, A]]", "chains[0][1]", "no link from B to A"),
    ("[[]]", "chains[0]", "an empty chain"),
    ("[A, B]", "chains[0]", "expected a list of task names, sensor first"),
    ("5", "chains", "expected a list of chains"),
])
def test_chain_refusals(tmp_path, chains, key_path, wording):
    f = tmp_path / "s.yaml"
    f.write_text("tasks:\n  A: {duration: 1, outputs: [x]}\n  B: {duration: 1, inputs: [x]}\n"
                 "links:\n  - {from: 'A:x', to: 'B:x', protocol: ASYN/ASYN}\n"
                 f"chains: {chains}\n")
    with pytest.raises(SkeletonError) as info:
        load_skeleton(f)
    assert info.value.where == key_path and wording in info.value.reason


def test_priority_built_in_code_is_checked():
    from dataclasses import replace
    s = sk({"tasks": {"A": {"duration": 1}}})
    s.tasks["A"] = replace(s.tasks["A"], priority=F(3, 2))
    with pytest.raises(SkeletonError, match=r"tasks\.A\.priority: expected a priority"):
        s.validate()


# ------------------------------------------------------------------ command line

def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "tegraph.cli", *args], check=False,
                          capture_output=True, text=True, timeout=120)


def test_cli_rules_exit_statuses(tmp_path):
    ok = run("rules", str(EXAMPLES / "computed_torque.yaml"))
    assert ok.returncode == 0, ok.stderr
    assert "all followed" in ok.stdout and "Joseph and Pandya" in ok.stdout
    bad = run("rules", str(EXAMPLES / "fig4_pipeline_unsynchronized.yaml"), "--json")
    assert bad.returncode == 1
    data = json.loads(bad.stdout)
    assert [f["rule"] for f in data["rules"]] == [2, 2, 2, 4]
    refused = run("rules", str(EXAMPLES / "computed_torque.yaml"), "--chain", "TG.JS,CO.JS")
    assert refused.returncode == 2 and refused.stdout == ""
    assert "--chain[0][1]: no link from TG.JS to CO.JS" in refused.stderr
    assert refused.stderr.count("\n") == 1


def test_findings_carry_their_kind_and_key():
    # Figure 12: MT2 waits for its clock MT2.clock and for MT1's message (Rule 1, key the
    # task); the group {MT1, MT2} has clocks rtc and MT2.clock (Rule 3, key the group).
    fig12 = check_rules(load_skeleton(EXAMPLES / "fig12_double_sync.yaml"))
    assert [(f.kind, f.key) for f in fig12 if f.rule < 4] == [
        (FindingKind.RULE1_SEVERAL_SYNCS, "MT2"),
        (FindingKind.RULE3_SEVERAL_CLOCKS, ("MT1", "MT2"))]
    # Figure 4, unsynchronized: three ASYN/ASYN links between groups of one period (Rule 2,
    # key the link's two ports); nothing declares a priority (Rule 4, key every task).
    fig4 = check_rules(load_skeleton(EXAMPLES / "fig4_pipeline_unsynchronized.yaml"))
    assert [(f.kind, f.key) for f in fig4] == [
        (FindingKind.RULE2_UNSYNCHRONIZED, (("MT1", "x1"), ("MT2", "x1"))),
        (FindingKind.RULE2_UNSYNCHRONIZED, (("MT2", "x2"), ("MT3", "x2"))),
        (FindingKind.RULE2_UNSYNCHRONIZED, (("MT3", "x3"), ("MT4", "x3"))),
        (FindingKind.RULE4_NONE_DECLARED, ("MT1", "MT2", "MT3", "MT4"))]
    # The rule and severity are the kind's.
    assert all((f.rule, f.severity) == f.kind.value[:2] for f in fig12 + fig4)


def test_the_rules_command_prints_what_the_library_call_returns():
    # `tegraph rules` parses, calls tegraph.rules and prints its document and status; the
    # section is the same one that `analyze` carries as its design.
    import tegraph
    from tegraph.report import to_document

    path = EXAMPLES / "fig4_pipeline_unsynchronized.yaml"
    section = tegraph.rules(str(path), chains=[["MT1", "MT2"]])
    out = run("rules", str(path), "--json", "--chain", "MT1,MT2")
    assert json.loads(out.stdout) == to_document(section)
    assert out.returncode == section.exit_status == 1  # three Rule 2 warnings
    doc = to_document(section)
    assert list(doc) == ["schema_version", "report", "name", "unit", "schedulable", "schedule",
                         "rules", "schedule_parts", "schedulability", "latency"]
    design = to_document(analyze(str(path), chains=[["MT1", "MT2"]]))["design"]
    assert design == {k: doc[k] for k in ("rules", "schedule_parts", "schedulability",
                                          "latency")}
    assert run("rules", str(path)).stdout.endswith("(exit status 1)\n")
    with pytest.raises(TypeError, match="skeleton: expected a Skeleton"):
        tegraph.rules(3)


# ------------------------------------------------------------------ threads and processors

def test_a_thread_across_two_processors_is_refused(tmp_path):
    # A thread is one OS thread (spec §2 serializes its tasks): A on cpu0 and B on the
    # default processor cannot be one thread. One message, key path of B, exit 2.
    from typer.testing import CliRunner

    from tegraph.cli import app

    path = tmp_path / "split.yaml"
    path.write_text("tasks:\n  A: {duration: 1, period: 10, processor: cpu0}\n"
                    "  B: {duration: 1, period: 10}\nthreads:\n  - [A, B]\n")
    done = CliRunner().invoke(app, ["rules", str(path)])
    assert done.exit_code == 2, done.output
    (line,) = done.output.strip().splitlines()
    assert "threads[0][1]" in line and "'cpu0'" in line and "default processor" in line
    assert "'A'" in line and "'B'" in line
    with pytest.raises(SkeletonError, match="one processor"):
        sk({"tasks": {"A": {"duration": 1, "processor": "x"},
                      "B": {"duration": 1, "processor": "y"}}, "threads": [["B", "A"]]})
    # One processor (named, or the default for all): accepted.
    sk({"tasks": {"A": {"duration": 1, "processor": "x"},
                  "B": {"duration": 1, "processor": "x"}}, "threads": [["A", "B"]]})
