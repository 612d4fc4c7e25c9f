"""`explore` judges each variant on its processors (spec v1.2 §4b).

A variant is kept only when `schedulable` is True on its processors; undecided
within the per-variant budget (`max_events`) is a rejection of its own; the
response-time test prunes nothing (a "no" from it is no proof of a §4b overrun),
and the only pruning before the exact schedule is the load argument proven in
docs/explore.md. Every expected value is derived by hand in the comments.
"""

from __future__ import annotations

import csv
import hashlib
import json
from fractions import Fraction

import pytest

import tegraph
from tegraph import InputError, Skeleton, load_skeleton
from tegraph.analysis.analyze import analyze_skeleton
from tegraph.design.explore import explore_design
from tegraph.design.explore.results import columns
from tegraph.design.explore.space import design_space
from tegraph.design.schedulability import schedulability
from tegraph.report.explore_text import render_exploration
from tests.paths import REPO

F = Fraction
FIG4 = REPO / "examples" / "fig4_pipeline_synchronized.yaml"


def pair(a: dict, b: dict, protocol: str = "ASYN/ASYN") -> Skeleton:
    """A writes x to B; both on the processor `default` (no `processor` key)."""
    return Skeleton.from_dict({
        "tasks": {"A": {"outputs": ["x"], **a}, "B": {"inputs": ["x"], **b}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": protocol}]})


def test_two_tasks_of_6_every_10_overrun_on_one_cpu_and_are_rejected_for_it():
    # A and B, 6 ms every 10 ms each, on one processor. With ASYN/ASYN they are two
    # groups, each alone fits its clock: live and consistent with a processor per task
    # (§4: each ends 6 after its tick). On the one CPU they need 6/10 + 6/10 = 6/5 of
    # it: by hand, A (more urgent, earlier in the file at equal periods) runs [0, 6],
    # B [6, 10], A [10, 16], B [16, 18]: B's first activation ends at 18 > its tick 10,
    # an overrun at activation 2. With SYN/SYN, B reads at A's write (6) and ends at
    # 12 > 10 even with a processor per task: an overrun of §4.
    sk = pair({"duration": 6, "period": 10}, {"duration": 6, "period": 10})
    space = design_space(sk, {"A:x -> B:x": ["ASYN/ASYN", "SYN/SYN"]})
    found = explore_design(space, workers=0)
    free, rendezvous = found.results[0], found.results[1]
    assert free.live and free.consistent and free.schedulable is False and not free.kept
    assert free.reason.startswith("overrun on processors")
    assert "6/5" in free.reason and "default" in free.reason
    assert not rendezvous.consistent and rendezvous.reason.startswith("overrun: B")
    assert found.rejected == {"an overrun": 1, "not schedulable on processors": 1}
    assert found.front == []
    # The load argument agrees with the exact schedule that `analyze` runs.
    report = tegraph.analyze(space.build(0))
    assert report.schedulable is False and report.schedule.tasks["B"].overrun_at == 2
    text = render_exploration(found)
    assert "1 not schedulable on processors, e.g. variant 0: overrun on processors" in text


def test_an_overrun_below_full_load_is_found_by_the_exact_schedule():
    # A: 3 every 6, B: 4 every 9 (load 1/2 + 4/9 = 17/18 <= 1, so no load argument).
    # By hand (rate-monotonic: A more urgent): A [0, 3], B [3, 6], A [6, 9], B [9, 10]:
    # B's first job ends at 10 > its tick at 9: overrun at activation 2. At 12 instead:
    # A [0,3], B [3,6], A [6,9], B [9,10] ends 10 <= 12; A [12,15], B [15,18], A [18,21],
    # B [21,22] ends 22 <= 24; at 24 both are released again with nothing pending, as at
    # 0: the schedule repeats every 12, schedulable.
    sk = pair({"duration": 3, "period": 6}, {"duration": 4, "period": 9})
    space = design_space(sk, clocks={"B.clock": [9, 12]}, objectives=["period", "load"])
    found = explore_design(space, workers=0)
    at9, at12 = found.results[0], found.results[1]
    assert at9.consistent and at9.schedulable is False
    assert at9.reason == "overrun on processors: B at activation 2 (on default)"
    assert at12.kept
    # On processors every task runs at its clock's period: the load is 3/6 + 4/12 = 5/6;
    # B runs every 12 where the input designed 9: period ratio 12/9 = 4/3.
    assert at12.objectives == {"period": F(4, 3), "load": F(5, 6)}


def test_the_response_time_test_prunes_nothing_it_has_not_proven():
    # B's clock a phase of 3/2 later: its releases fall at 3/2 and 3/2 + 9k, i.e. at
    # 3/2 or 9/2 modulo A's 6, never with A's. By hand: B at 3/2 waits for A (ends 3),
    # runs [3, 6], A [6, 9], B [9, 10]: ends 10 <= 21/2; B at 21/2: [21/2, 12], A [12,
    # 15], B [15, 35/2]: response 7; the schedule repeats every 18: schedulable. The
    # response-time test assumes the critical instant (both released together) and
    # says no (R = 4 + 2*3 = 10 > 9): it is no proof here, and the variant is kept.
    sk = pair({"duration": 3, "period": 6}, {"duration": 4, "period": 9, "phase": "3/2"})
    assert schedulability(sk).schedulable is False
    assert analyze_skeleton(sk, processors=True).schedulable is True
    space = design_space(sk, clocks={"B.clock": [9]}, objectives=["load"])
    found = explore_design(space, workers=0)
    assert found.results[0].kept and found.results[0].schedulable is True
    assert [r.variant for r in found.front] == [0]
    # The disagreement is reported, as a cross-check, not as a verdict.
    assert any("response-time test" in n and "1 variant" in n for n in found.notes)


def test_figure_4_pipeline_front_is_unchanged_on_one_processor():
    # The synchronized pipe-line (one group: MT1 on rtc, MT2..MT4 each reading the
    # stage before ASYN/SYN), durations 1, 2, 2, 1 on the one processor `default`.
    # Each stage is released when the previous one has written, which is when that
    # job has received its duration: at most one job is ready at any instant, nothing
    # is preempted, f = r + d and the schedule on processors is §3's daters exactly.
    # At rtc = 10 and 20 it is schedulable with every period on processors 10 (20):
    # period ratio 1 (2), load 6/10 (6/20), latency 1+2+2+1 = 6, as before §4b. At
    # rtc = 5 the group needs 6/5 of the processor: rejected, by the load argument.
    sk = load_skeleton(FIG4)
    chain = ["MT1", "MT2", "MT3", "MT4"]
    space = design_space(sk, clocks={"rtc": [5, 10, 20]}, chains=[chain])
    found = explore_design(space, workers=0)
    name = "latency:MT1,MT2,MT3,MT4"
    assert {space.periods(r.variant)[0]: r.objectives for r in found.front} == {
        F(10): {name: F(6), "period": F(1), "load": F(3, 5)},
        F(20): {name: F(6), "period": F(2), "load": F(3, 10)}}
    at5 = found.results[0]
    assert at5.consistent and at5.schedulable is False
    assert at5.reason.startswith("not schedulable on processors") and "6/5" in at5.reason


def test_a_variant_undecided_within_a_tiny_budget_is_rejected_as_undecided(tmp_path):
    # 5 event firings cannot reach the periodic regime of the pipe-line (its first
    # period alone fires 14 events: the tick and 4 + 3 * 3 task events): undecided.
    sk = load_skeleton(FIG4)
    found = tegraph.explore(sk, clocks={"rtc": [10]}, objectives=["load"], workers=0,
                            max_events=5, output=tmp_path / "r.csv")
    r = found.results[0]
    assert r.consistent and r.schedulable is None and not r.kept
    assert r.reason.startswith("undecided within max_events (5 event firings)")
    assert found.rejected == {"undecided within max_events": 1}
    assert found.front == []
    # The row says it: schedulable empty, kept false; and it is resumed as such.
    row = next(csv.DictReader(open(tmp_path / "r.csv", encoding="utf-8")))
    assert row["schedulable"] == "" and row["kept"] == "false"
    again = tegraph.explore(sk, clocks={"rtc": [10]}, objectives=["load"], workers=0,
                            max_events=5, output=tmp_path / "r.csv", resume=True)
    assert again.resumed == 1 and again.results[0].reason == r.reason
    # Another budget is another exploration: its verdicts are not resumed.
    with pytest.raises(InputError) as err:
        tegraph.explore(sk, clocks={"rtc": [10]}, objectives=["load"], workers=0,
                        output=tmp_path / "r.csv", resume=True)
    assert "max_events" in str(err.value)
    with pytest.raises(InputError) as err:
        design_space(sk, clocks={"rtc": [10]}, max_events=0)
    assert err.value.where == "max_events"


@pytest.mark.parametrize("version, words", [
    (2, "a processor per task"),
    (3, "designs kept where a task runs free that the input design runs on a clock")])
def test_resume_refuses_a_file_judged_with_a_processor_per_task(tmp_path, version, words):
    # A results file of definitions version 2 (before §4b: every variant judged with
    # a processor per task and the response-time test), or 3 (free-running designs
    # kept). Its fingerprint, computed as that version computed it (no `free_running`
    # in the constraints; version 3 with the budget), is no longer this exploration's:
    # refused, naming the version and what it judged differently, left as it was.
    sk = load_skeleton(FIG4)
    space = design_space(sk, clocks={"rtc": [10]}, objectives=["load"])
    constraints = {k: v for k, v in space.constraints.to_dict().items() if k != "free_running"}
    data = {"skeleton": sk.to_dict(), "links": [], "clocks": [["rtc", ["10"]]], "chains": [],
            "objectives": ["load"], "constraints": constraints, "definitions": version}
    if version == 3:
        data["max_events"] = space.max_events
    old = hashlib.sha256(json.dumps(data, sort_keys=True,
                                    default=str).encode()).hexdigest()[:16]
    header = columns(space)
    row = dict.fromkeys(header, "")
    row.update({"variant": "0", "space": old, "clock:rtc": "10", "judged": "analyzed",
                "live": "true", "repaired": "false", "consistent": "true",
                "schedulable": "true", "kept": "true", "load": "3/5", "rule2": "0",
                "seconds": "0.001"})
    target = tmp_path / "old.csv"
    with open(target, "w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f)
        writer.writerow(header)
        writer.writerow([row[c] for c in header])
    before = target.read_bytes()
    with pytest.raises(InputError) as err:
        tegraph.explore(sk, clocks={"rtc": [10]}, objectives=["load"], workers=0,
                        output=target, resume=True)
    message = str(err.value)
    assert words in message and f"version {version}" in message
    assert target.read_bytes() == before
