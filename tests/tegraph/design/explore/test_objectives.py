"""explore's objectives as a designer reads them: the period ratio
judges a task against its own designed rate, total utilization shows what a faster
loop costs off the busiest processor, columns say what they hold, the text says why
variants were rejected, Rule 2 findings break ties, and constraints restrict the space.

Every expected figure is derived by hand in the comments.
"""

from __future__ import annotations

from fractions import Fraction

import pytest
from typer.testing import CliRunner

from tegraph import InputError, Skeleton, load_skeleton
from tegraph.api import explore
from tegraph.cli import app
from tegraph.design.explore.evaluate import rule2_findings
from tegraph.design.rules import check_rules
from tegraph.report.explore_text import render_exploration
from tests.paths import REPO

F = Fraction
FIG4 = str(REPO / "examples" / "fig4_pipeline_synchronized.yaml")
CHAIN = ["MT1", "MT2", "MT3", "MT4"]

# SENS samples on its own 5 ms clock, CTRL on its own 2 ms clock; as drawn, CTRL's
# read of y blocks (ASYN/SYN), which joins them in one group whose fastest clock is
# ctl (2 ms). The correct decoupling reads y ASYN/ASYN.
DECOUPLING = {"clocks": {"ctl": {"period": 2}, "sens": {"period": 5}}, "tasks": {
    "SENS": {"duration": 1, "clock": "sens", "outputs": ["y"]},
    "CTRL": {"duration": 1, "clock": "ctl", "inputs": ["y"]}},
    "links": [{"from": "SENS:y", "to": "CTRL:y", "protocol": "ASYN/SYN"}]}


def test_a_task_on_its_own_slower_clock_is_judged_against_its_own_rate():
    sk = Skeleton.from_dict(DECOUPLING)
    found = explore(sk, {"SENS:y -> CTRL:y": ["ASYN/SYN", "ASYN/ASYN"]},
                    objectives=["period"], workers=0)
    decoupled = found.space.variant_of([found.space.links[0].protocols[1]], [])
    r = found.results[decoupled]
    # ASYN/ASYN: SENS runs every 5 ms on sens, CTRL every 2 ms on ctl, each at its own
    # clock's period: ratios 5/5 and 2/2, so 1. Before: SENS was charged against the
    # group it left, 5/2.
    assert r.kept and r.objectives["period"] == 1
    assert found.space.reference_periods == {"SENS": 5, "CTRL": 2}


TWO_CPUS = {"tasks": {"A": {"duration": 1, "period": 10, "processor": "P1"},
                      "B": {"duration": 2, "period": 4, "processor": "P2"}}}


def test_total_utilization_shows_what_a_faster_loop_costs_elsewhere():
    sk = Skeleton.from_dict(TWO_CPUS)
    clocks = {"A.clock": [10, 5]}
    # A at 10: loads 1/10 (P1) and 2/4 (P2): busiest 1/2, total 3/5. A at 5: 1/5 and
    # 1/2: busiest still 1/2, total 7/10. Both run every task at its designed rate or
    # faster: period ratios max(10/10, 4/4) = 1 and max(5/10, 4/4) = 1.
    only_load = explore(sk, clocks=clocks, objectives=["period", "load"], workers=0)
    assert {r.objectives["load"] for r in only_load.front} == {F(1, 2)}
    assert len(only_load.front) == 2  # the cost of doubling A is invisible
    found = explore(sk, clocks=clocks, workers=0)  # default: utilization with 2 CPUs
    assert found.space.objectives == ("period", "load", "utilization")
    assert [(found.entry(r)["clocks"]["A.clock"], r.objectives["utilization"])
            for r in found.front] == [("10", F(3, 5))]
    assert found.results[1].objectives["utilization"] == F(7, 10)


def test_columns_say_what_they_hold_with_units_and_rejections_are_counted():
    found = explore(load_skeleton(FIG4), ["MT1:x1 -> MT2:x1"], clocks={"rtc": [5, 10, 20]},
                    chains=[CHAIN], workers=0)
    text = render_exploration(found)
    header = next(line for line in text.splitlines() if line.strip().startswith("variant"))
    # Each column says where its figure comes from: every one on processors, the
    # chain's latency too (spec §4c).
    assert "rtc (ms)" in header and "period ratio on processors" in header
    assert "latency MT1,MT2,MT3,MT4 (ms, on processors)" in header
    assert "busiest load on processors" in header
    # By hand, the 12 variants (4 protocols of MT1 -> MT2, rtc 5, 10 or 20):
    # - ASYN/ASYN (3): MT2 -> MT3 -> MT4 lose their only synchronization and run
    #   unclocked, one every 2 ms with a processor per task. The response-time test
    #   rejected them (5 ms of work every 2 ms); on the one processor (spec §4b)
    #   they run below MT1 in the time it leaves, slower than 2 ms but never
    #   starved and with no place growing: schedulable, but they run free where the
    #   input design runs them on rtc: not kept (kept with `free_running`);
    # - SYN/ASYN (3): MT1 blocks on MT2's request while MT2 reads freely every 2 ms,
    #   faster than rtc: requests pile up, an unbounded place;
    # - ASYN/SYN and SYN/SYN at rtc = 5 (2): one group of 6 ms of work every 5 ms:
    #   6/5 of the processor, not schedulable on processors (rule C);
    # - the other 4 are kept.
    assert found.rejected == {"an unbounded place": 3, "not schedulable on processors": 2,
                              "a free-running task": 3}
    assert found.kept == 4
    assert "rejected: 8 variant(s), by the first reason met" in text
    assert "\n  3 a free-running task, e.g. variant 0: free-running: MT2, MT3, MT4" in text
    assert "\n  3 an unbounded place, e.g. variant 6: requests-overwritten" in text
    assert ("\n  2 not schedulable on processors, e.g. variant 3: not schedulable on "
            "processors: default runs groups with a clock needing 6/5 of its time") in text


def test_rule2_findings_break_ties():
    # A then B, 1 + 2 ms at 10 ms: ASYN/SYN and SYN/SYN both give latency 3, ratio 1,
    # load 3/10; SYN/SYN is a rendezvous (one Rule 2 finding): ASYN/SYN alone wins.
    sk = Skeleton.from_dict({"clocks": {"rtc": {"period": 10}}, "tasks": {
        "A": {"duration": 1, "clock": "rtc", "inputs": ["s"], "outputs": ["x"]},
        "B": {"duration": 2, "inputs": ["x"], "outputs": ["u"]}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/ASYN"}]})
    found = explore(sk, {"A:x -> B:x": ["ASYN/SYN", "SYN/SYN"]}, chains=[["A", "B"]],
                    workers=0)
    both = list(found.results.values())
    assert [r.objectives for r in both][0] == [r.objectives for r in both][1]
    assert [(found.entry(r)["links"]["A:x -> B:x"], r.rule2) for r in found.front] == \
        [("ASYN/SYN", 0)]


@pytest.mark.parametrize("path", sorted((REPO / "examples").glob("*.yaml")))
def test_rule2_count_is_what_check_rules_reports(path):
    sk = load_skeleton(path)
    assert rule2_findings(sk) == sum(1 for f in check_rules(sk) if f.rule == 2)


def test_require_a_period_keeps_only_the_designs_that_meet_it():
    # MT1's period is rtc's: with rtc in 10, 20 and MT1.period = 10 required, only the
    # rtc = 10 variants can be kept; the rtc = 20 ones are rejected by the constraint.
    found = explore(load_skeleton(FIG4), clocks={"rtc": [10, 20]}, requires=["MT1.period=10"],
                    workers=0)
    assert [found.entry(r)["clocks"]["rtc"] for r in found.front] == ["10"]
    assert found.rejected == {"against a constraint": 1}
    # The period is read on processors, and the reason says so.
    assert "MT1.period on processors is 20 ms, required = 10 ms" in found.results[1].reason


def test_max_latency_keeps_only_the_chains_fast_enough():
    # Figure 4 unsynchronized run in the wrong order (priorities declared 1, 2, 3, 4: MT4
    # the most urgent, the lower half of the paper's Figure 4): as drawn each hop waits a
    # period, exactly 26 ms on its processor (spec §4c's example). Synchronized ASYN/SYN
    # every stage waits for the one before: 6 ms whatever the priorities. With
    # "<= 20 ms", the design as drawn is rejected by the constraint, never by a bound.
    data = load_skeleton(REPO / "examples" / "fig4_pipeline_unsynchronized.yaml").to_dict()
    for p, task in enumerate(CHAIN, 1):
        data["tasks"][task]["priority"] = p
    found = explore(Skeleton.from_dict(data), all_links=True, chains=[CHAIN],
                    max_latency=["MT1,MT2,MT3,MT4=20"], workers=0)
    name = f"latency:{','.join(CHAIN)}"
    asis = found.results[found.space.starting_variant()]
    assert asis.live and asis.consistent and asis.schedulable and not asis.kept
    assert asis.objectives[name] == 26 and asis.kinds[name] == "exact"
    assert asis.reason == ("against a constraint: latency MT1,MT2,MT3,MT4 on processors is "
                           "26 ms, required <= 20 ms")
    assert found.front and all(r.objectives[name] <= 20 for r in found.front)
    assert all(r.objectives[name] <= 20 for r in found.results.values() if r.kept)


def test_age_and_reaction_objectives_and_an_undecided_chain_is_rejected():
    # A slow plan P (200 ms) drives a motor loop M (10 ms), on two processors; a choice of
    # M's period. By hand (tests/tegraph/analysis/test_chains.py): at 10 ms, first use 11,
    # age 201, reaction 211; at 20 ms M reads at 20k: first use 21, age 201 (M at 200
    # still uses the plan of 0), reaction 221.
    sk = Skeleton.from_dict({
        "tasks": {
            "P": {"duration": 1, "period": 200, "inputs": ["s"], "outputs": ["plan"],
                  "processor": "cpu0"},
            "M": {"duration": 1, "period": 10, "inputs": ["plan"], "outputs": ["u"],
                  "processor": "cpu1"}},
        "links": [{"from": "P:plan", "to": "M:plan", "protocol": "ASYN/ASYN"}]})
    found = explore(sk, clocks={"M.clock": [10, 20]}, chains=[["P", "M"]],
                    objectives=["latency", "age", "reaction"], workers=0)
    assert found.space.objectives == ("latency:P,M", "age:P,M", "reaction:P,M")
    got = {found.entry(r)["clocks"]["M.clock"]: r.objectives for r in found.results.values()}
    assert got == {"10": {"latency:P,M": 11, "age:P,M": 201, "reaction:P,M": 211},
                   "20": {"latency:P,M": 21, "age:P,M": 201, "reaction:P,M": 221}}



def test_a_variant_whose_chain_is_undecided_is_rejected_with_the_reason():
    # A every 1 ms and B every 97 ms on two processors: each part repeats within a few
    # firings (the schedule is decided in 60), but the chain's parts repeat together only
    # every 97 ms: 97 samples and 1 output, more than the 60 allowed: the latency is
    # undecided, and the variant rejected for it, never ranked.
    sk = Skeleton.from_dict({
        "tasks": {"A": {"duration": "1/2", "period": 1, "outputs": ["x"], "processor": "c0"},
                  "B": {"duration": 1, "period": 97, "inputs": ["x"], "processor": "c1"}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/ASYN"}]})
    found = explore(sk, clocks={"B.clock": [97]}, chains=[["A", "B"]], max_events=60,
                    workers=0)
    (r,) = found.results.values()
    assert r.schedulable is True and not r.kept and r.kinds == {"latency:A,B": "undecided"}
    assert r.reason == ("the latency of A,B on processors is undecided: the chain's parts "
                        "repeat together every 97 ms, 98 outputs and samples, more than "
                        "`max_events`")
    assert found.rejected == {"a chain's latency undecided": 1} and not found.front


def test_forbid_takes_a_protocol_out_of_the_space():
    found = explore(load_skeleton(FIG4), all_links=True, forbid=["syn-syn"], workers=0)
    assert found.space.size == 3 ** 3
    assert all("SYN/SYN" not in found.space.describe(v)[0].values()
               for v in range(found.space.size))
    # A link not chosen keeps its protocol: when that is the forbidden one, refused.
    sk = Skeleton.from_dict({"clocks": {"rtc": {"period": 10}}, "tasks": {
        "A": {"duration": 1, "clock": "rtc", "outputs": ["x", "y"]},
        "B": {"duration": 2, "inputs": ["x", "y"]}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"},
                  {"from": "A:y", "to": "B:y", "protocol": "SYN/SYN"}]})
    with pytest.raises(InputError, match="'A:y -> B:y' is SYN/SYN in the skeleton and not "
                                         "chosen") as err:
        explore(sk, ["A:x -> B:x"], forbid=["SYN/SYN"], workers=0)
    assert err.value.where == "forbid"


@pytest.mark.parametrize("args, words", [
    (["--require", "MT9.period=2"], "--require[0]: no task 'MT9'"),
    (["--require", "MT1.duration=2"], "--require[0]: cannot read 'MT1.duration=2'"),
    (["--require", "MT1.period=0"], "--require[0]: expected a period > 0"),
    (["--max-latency", "MT1,MT3=5"], "--max-latency[0][1]: no link from MT1 to MT3"),
    (["--max-latency", "MT1,MT2"], "--max-latency[0]: cannot read 'MT1,MT2'"),
    (["--forbid", "SYN"], "--forbid[0]: unknown protocol 'SYN'"),
])
def test_constraint_refusals_name_their_option(args, words):
    out = CliRunner().invoke(app, ["explore", FIG4, "--all-links", "--workers", "0", *args])
    assert out.exit_code == 2, out.stdout
    assert words in out.stderr and len(out.stderr.strip().splitlines()) == 1, out.stderr


def test_the_command_line_constraints_restrict_the_front():
    out = CliRunner().invoke(app, ["explore", FIG4, "--clock", "rtc=10,20", "--require",
                                   "MT1.period=20", "--workers", "0"])
    assert out.exit_code == 0, out.stderr
    assert "constraints: MT1.period = 20 ms" in out.stdout
    assert "\n  1 against a constraint, e.g. variant 0: against a constraint: MT1.period " \
        "on processors is 10 ms, required = 20 ms" in out.stdout  # on processors
    assert out.stdout.strip().splitlines()[-1].startswith("verdict: 1 design(s)")
