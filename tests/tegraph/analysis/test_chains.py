"""The latency of a chain (spec §4c), on hand-derived cases.

Each expected value is traced by hand in the comment above it: the schedule
(§4b on processors, §3 with a processor per task), which message each read sees,
and the figures' definitions (first use, age, age_min, reaction).
"""

from __future__ import annotations

from fractions import Fraction as F

import pytest

from tegraph import SkeletonError, analyze, load_skeleton
from tegraph.analysis import dynamics
from tegraph.analysis.analyze import analyze_skeleton
from tegraph.analysis.chains import ChainFigures, chain_paths
from tegraph.model.build import build_teg
from tegraph.model.skeleton import Skeleton
from tests.paths import REPO

EXAMPLES = REPO / "examples"
FIG4 = ["MT1", "MT2", "MT3", "MT4"]


def figures(f: ChainFigures) -> tuple:
    return f.first_use, f.age, f.age_min, f.reaction


def fig4(priorities: list[int] | None = None) -> Skeleton:
    data = load_skeleton(EXAMPLES / "fig4_pipeline_unsynchronized.yaml").to_dict()
    for task, p in zip(FIG4, priorities or []):
        data["tasks"][task]["priority"] = p
    return Skeleton.from_dict(data)


@pytest.mark.parametrize("priorities", [None, [4, 3, 2, 1]])
def test_figure_4_in_the_designers_order(priorities):
    # One processor, MT1 the most urgent (rate-monotonic: equal periods, file order; or
    # declared): 0-1 MT1, 1-3 MT2, 3-5 MT3, 5-6 MT4 each period. MT2 starts at 1, when
    # MT1 (same processor) has written x1: seen; likewise at 3 and 5. The sample read at
    # 0 is posted at 6: first use = age = age_min = 6; a change just after 0 is sampled
    # at 10 and posted at 16: reaction 16.
    report = analyze(fig4(priorities), chains=[FIG4])
    assert report.chains[0].on_processors.first_use == 6
    (c,) = report.chains
    assert figures(c.on_processors) == (6, 6, 6, 16)
    assert c.on_processors.why_undecided is None


def test_figure_4_reversed():
    # MT4 the most urgent: 0-1 MT4, 1-3 MT3, 3-5 MT2, 5-6 MT1. Each read comes before its
    # writer's write of the period: MT2 (start 13) sees MT1's write at 6 (sample at 5),
    # MT3 (start 21) sees MT2's at 15, MT4 (start 30) MT3's at 23, posted at 31:
    # 31 - 5 = 26 for every output; reaction 26 + 10 = 36.
    report = analyze(fig4([1, 2, 3, 4]), chains=[FIG4])
    assert report.chains[0].on_processors.first_use == 26
    (c,) = report.chains
    assert figures(c.on_processors) == (26, 26, 26, 36)
    steps = [(s.task, s.k, s.at) for s in c.on_processors.worst]
    assert steps[0] == ("MT1", 1, 5) and steps[-1] == ("MT4", 4, 31)


@pytest.mark.parametrize("priorities", [None, [1, 2, 3, 4]])
def test_figure_4_with_a_processor_per_task(priorities):
    # Every task starts at its tick, 10(k-1); a non-blocking read sees only messages
    # written strictly before (another processor): MT2 at 10 sees MT1's write at 1,
    # MT3 at 20 MT2's at 12, MT4 at 30 MT3's at 22, posted at 31: 31 - 0 = 31, whatever
    # the priorities; reaction 41. --no-processors reports the same on_processors.
    sk = fig4(priorities)
    (c,) = analyze(sk, chains=[FIG4]).chains
    assert figures(c.processor_per_task) == (31, 31, 31, 41)
    (alone,) = analyze(sk, chains=[FIG4], processors=False).chains
    assert figures(alone.on_processors) == figures(alone.processor_per_task) == (31, 31, 31, 41)


def test_figure_4_with_a_processor_per_task_without_the_daters(monkeypatch):
    # The figures with a processor per task are read off §3's daters where the dater
    # simulation proved the groups' regimes; with no dater recorded they come from the
    # schedule with a processor per task instead: the same 31, 31, 31, 41 (derived in
    # test_figure_4_with_a_processor_per_task).
    monkeypatch.setattr(dynamics, "RECORD_LIMIT", 0)
    (c,) = analyze(fig4(), chains=[FIG4], processors=False).chains
    assert figures(c.processor_per_task) == (31, 31, 31, 41)


def plan_and_motor(processors: str) -> Skeleton:
    # A plan made every 200 ms (P) drives a 10 ms motor loop (M), ASYN/ASYN.
    return Skeleton.from_dict({
        "tasks": {
            "P": {"duration": 1, "period": 200, "inputs": ["s"], "outputs": ["plan"],
                  "processor": "cpu0"},
            "M": {"duration": 1, "period": 10, "inputs": ["plan"], "outputs": ["u"],
                  "processor": "cpu0" if processors == "one" else "cpu1"}},
        "links": [{"from": "P:plan", "to": "M:plan", "protocol": "ASYN/ASYN"}]})


def test_a_slow_plan_driving_a_fast_motor_loop():
    # Processor per task: P samples at 0, writes at 1; M reads at 10k. M at 10 uses the
    # plan of 0 first (output 11: first use 11), and every M up to the one at 200 (P's
    # next plan is written at 201, not yet): its output at 201 is 201 ms old: age 201,
    # 190 more than the first use; age_min 11; reaction: the plan of 200 is first used
    # at 210, posted at 211: 211.
    (c,) = analyze(plan_and_motor("two"), chains=[["P", "M"]]).chains
    assert figures(c.processor_per_task) == (11, 201, 11, 211)
    assert c.processor_per_task.age - c.processor_per_task.first_use == 190
    # One processor (M the more urgent, rate-monotonic): M 0-1, P 1-2 (samples at 1,
    # writes at 2). M at 10 posts at 11 the plan sampled at 1: first use 10; M at 200
    # runs before P's next plan (written at 202): output 201, age 200; reaction: the
    # sample at 201 first reaches the output at 211: 210.
    (c,) = analyze(plan_and_motor("one"), chains=[["P", "M"]]).chains
    assert figures(c.on_processors) == (10, 200, 10, 210)
    assert c.on_processors.age - c.on_processors.first_use == 190


def test_computed_torque_chain_on_its_one_cpu():
    # computed_torque.yaml on the default processor, rate-monotonic: OBS.JL (1 ms) 0-0.1,
    # then the ctl group: TG.JS starts at 0.1 (no input: its start is its sample) and
    # writes qd at 0.2, TF.TT.JS (blocking read of qd) runs 0.2-0.4 and writes e, CO.JS
    # (blocking read of e) 0.4-0.7 and writes tau at 0.7; MOD.DYN runs after, preempted
    # by OBS.JL at 1, and ends at 2.0, before the next period. Every 2 ms the same:
    # first use = age = age_min = 0.7 - 0.1 = 3/5; reaction 2.7 - 0.1 = 13/5.
    # With a processor per task TG.JS starts at 0 and tau is written at 0.6: the same.
    sk = load_skeleton(EXAMPLES / "computed_torque.yaml")
    control, model = analyze(sk, chains=[["TG.JS", "TF.TT.JS", "CO.JS"],
                                         ["MOD.DYN", "CO.JS"]]).chains
    assert figures(control.on_processors) == (F(3, 5), F(3, 5), F(3, 5), F(13, 5))
    assert figures(control.processor_per_task) == (F(3, 5), F(3, 5), F(3, 5), F(13, 5))
    # MOD.DYN samples q at its start, 0.7, and writes M, N when it ends, at 2.0; CO.JS
    # reads M at its job's start (after its blocking read of e): 2.4 sees it, tau at 2.7:
    # first use 2; CO.JS at 6.4 still uses it (MOD.DYN's next job starts at 6.7), tau at
    # 6.7: age 6; age_min 2; the next sample (6.7) first reaches tau at 8.7: reaction 8.
    assert figures(model.on_processors) == (2, 6, 2, 8)


def race(same_processor: bool) -> Skeleton:
    return Skeleton.from_dict({
        "tasks": {
            "A": {"duration": 1, "period": 10, "outputs": ["x"], "processor": "cpu0"},
            "B": {"duration": 1, "period": 10, "phase": 1, "inputs": ["x"], "outputs": ["u"],
                  "processor": "cpu0" if same_processor else "cpu1"}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/ASYN"}]})


def test_a_write_and_a_read_at_one_instant_across_two_processors():
    # A writes x at 1 (its job 0-1); B's tick is at 1 and its job starts at 1 on its own
    # processor: a race, not seen. B at 1 reads A's message of the period before (its
    # sample at -10, in the regime), posted at 2: 12; B at 11 uses A's sample of 0: first
    # use 12 = age; reaction: the sample at 10 reaches the output at 22: 22.
    (c,) = analyze(race(False), chains=[["A", "B"]]).chains
    assert figures(c.on_processors) == (12, 12, 12, 22)
    # On one processor A's job ended before B's started: seen. 2 - 0 = 2; reaction 12.
    (c,) = analyze(race(True), chains=[["A", "B"]]).chains
    assert figures(c.on_processors) == (2, 2, 2, 12)
    # With a processor per task, both are a race.
    assert figures(c.processor_per_task) == (12, 12, 12, 22)


def reader_of_two(order: list[str]) -> Skeleton:
    # R (no clock) reads a from W1 (ASYN/ASYN) and b from W2 (ASYN/SYN: R waits for it).
    return Skeleton.from_dict({
        "tasks": {
            "W1": {"duration": 1, "period": 10, "outputs": ["a"]},
            "W2": {"duration": 3, "period": 10, "outputs": ["b"]},
            "R": {"duration": 1, "inputs": order, "outputs": ["u"]}},
        "links": [{"from": "W1:a", "to": "R:a", "protocol": "ASYN/ASYN"},
                  {"from": "W2:b", "to": "R:b", "protocol": "ASYN/SYN"}]})


def test_a_non_blocking_read_declared_before_a_blocking_read():
    # inputs [a, b]: R reads a at its event, then waits for b. With a processor per task,
    # R.read:a fires when R's previous activation ends: read:a(2) at 4 sees W1's write
    # at 1 (sample 0), then R waits for W2's message of 13 and writes u at 14: 14 - 0;
    # read:a(3) at 14 sees W1's write at 11: again 14. Reaction: the sample at 10 is
    # first posted at 24: 24.
    (c,) = analyze(reader_of_two(["a", "b"]), chains=[["W1", "R"]]).chains
    assert figures(c.processor_per_task) == (14, 14, 14, 24)
    # inputs [b, a]: a is read at the job's start, after b: at 3 it sees W1's write at 1,
    # u at 4: 4 - 0 = 4; reaction 14.
    (c,) = analyze(reader_of_two(["b", "a"]), chains=[["W1", "R"]]).chains
    assert figures(c.processor_per_task) == (4, 4, 4, 14)
    (p,) = chain_paths(c_sk := reader_of_two(["a", "b"]), build_teg(c_sk), [["W1", "R"]])
    assert (p.hops[0].read.kind, p.hops[0].read.name, p.hops[0].blocking) == (
        "event", "R.read:a", False)


def test_a_sample_overwritten_before_it_is_used():
    # W samples every 2 ms (at 2i, written at 2i + 1), R reads every 10 (at 10k, its own
    # processor): R at 10 sees W's write at 9, the sample of 8: output 11, 3 ms old, and
    # every output alike: first use = age = age_min = 3. The samples of 0, 2, 4, 6 are
    # overwritten before any read: no output uses them (age does not count them), but a
    # change just after 8 is sampled at 10 and overwritten too, and first reaches the
    # output with the sample of 18, at 21: reaction 21 - 8 = 13.
    sk = Skeleton.from_dict({
        "tasks": {"W": {"duration": 1, "period": 2, "outputs": ["x"]},
                  "R": {"duration": 1, "period": 10, "inputs": ["x"], "outputs": ["u"]}},
        "links": [{"from": "W:x", "to": "R:x", "protocol": "ASYN/ASYN"}]})
    (c,) = analyze(sk, chains=[["W", "R"]]).chains
    assert figures(c.processor_per_task) == (3, 3, 3, 13)


def test_a_starved_task_has_no_figure_and_says_why():
    # A (period 2, duration 2) takes all of the one processor: B never runs.
    sk = Skeleton.from_dict({
        "tasks": {"A": {"duration": 2, "period": 2, "outputs": ["x"], "priority": 2},
                  "B": {"duration": 1, "period": 10, "inputs": ["x"], "priority": 1}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/ASYN"}]})
    (c,) = analyze(sk, chains=[["A", "B"]]).chains
    assert figures(c.on_processors) == (None, None, None, None)
    assert c.on_processors.why_undecided == "B is starved: its job never ends"
    # With a processor per task B runs at 10k, reads A's write of 10k (A writes every 2,
    # at 2i + 2: the one at 10k is a race, the one before at 10k - 2, A's job started at
    # 10k - 4): output at 10k + 1, 5 ms after the sample.
    assert c.processor_per_task.first_use == 5


def test_a_dead_group_has_no_figure():
    # Figure 7a: MT2 -> MT1 is a link, and the three tasks wait for each other for ever.
    data = load_skeleton(EXAMPLES / "fig7a_circular_wait.yaml").to_dict()
    data["chains"] = [["MT2", "MT1"]]
    (c,) = analyze(Skeleton.from_dict(data)).chains
    for f in (c.on_processors, c.processor_per_task):
        assert figures(f) == (None, None, None, None)
        assert f.why_undecided == "the group of MT2 is not live (a deadlock)"


def test_the_file_chains_come_first_then_those_asked_for(tmp_path):
    f = tmp_path / "ct.yaml"
    f.write_text((EXAMPLES / "computed_torque.yaml").read_text()
                 + "chains:\n  - [TG.JS, TF.TT.JS, CO.JS]\n")
    r = analyze_skeleton(load_skeleton(f), processors=True, chains=[["MOD.DYN", "CO.JS"]])
    assert [c.tasks for c in r.chains] == [("TG.JS", "TF.TT.JS", "CO.JS"), ("MOD.DYN", "CO.JS")]
    doc = r.to_dict()["chains"]
    assert doc[0] == {"tasks": ["TG.JS", "TF.TT.JS", "CO.JS"], "first_use": "3/5",
                      "age": "3/5", "age_min": "3/5", "reaction": "13/5",
                      "why_undecided": None,
                      "on_processors": {"first_use": "3/5", "age": "3/5", "age_min": "3/5",
                                        "reaction": "13/5", "why_undecided": None}}


@pytest.mark.parametrize("chain, key_path, wording", [
    (["TG.JS", "CO.JS"], "chain[0][1]", "no link from TG.JS to CO.JS"),
    (["TG.JS", "NOPE"], "chain[0][1]", "no task 'NOPE'"),
    ([], "chain[0]", "an empty chain"),
])
def test_refused_chains_are_named(chain, key_path, wording):
    sk = load_skeleton(EXAMPLES / "computed_torque.yaml")
    with pytest.raises(SkeletonError) as info:
        analyze_skeleton(sk, chains=[chain])
    assert info.value.where == key_path and wording in info.value.reason


def test_times_past_int64_on_the_schedule_s_scale():
    # Durations of denominators 1000000007 and 998244353 on clocks of 1/3 and 1/7: the
    # common scale passes 2**62, and the window is computed on Python integers. A (alone
    # on c0) samples at k/3 and writes at k/3 + dA; B (alone on c1) reads at j/7 the
    # newest write strictly before (another processor) and posts at j/7 + dB. Over one
    # common period (1 ms, 7 outputs of B), brute force:
    dA, dB = F(1, 1000000007), F(1, 998244353)
    sk = Skeleton.from_dict({
        "tasks": {"A": {"duration": str(dA), "period": "1/3", "outputs": ["x"],
                        "processor": "c0"},
                  "B": {"duration": str(dB), "period": "1/7", "inputs": ["x"], "outputs": ["u"],
                        "processor": "c1"}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/ASYN"}]})
    r = analyze(sk, chains=[["A", "B"]], design=False)
    assert r.schedule.scale > 2**62
    ages = []
    for j in range(7, 14):
        k = max(k for k in range(40) if F(k, 3) + dA < F(j, 7))
        ages.append(F(j, 7) + dB - F(k, 3))
    (c,) = r.chains
    assert (c.on_processors.age, c.on_processors.age_min) == (max(ages), min(ages))
    assert figures(c.on_processors) == figures(c.processor_per_task)
