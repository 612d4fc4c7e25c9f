"""One overrun definition and one activation numbering in `analyze`, `reach --timed`, `timeline`.

Spec §4 (v1.1): T overruns at activation k when tick k of its clock comes while
activation k-1 has not ended, ``end_T(k-1) > x_C.tick(k)``, the end being the
last write, or, for a task without outputs, ``x_T.compute + duration(T)``.

The three commands compute it three ways: the dater simulation with its
periodic-regime proof (:func:`tegraph.analyze`), the ORCCAD §5 timed state
search (:func:`~tegraph.analysis.baselines.timed_reachability.timed_reachability`) and the
schedule on processors that the timeline draws
(:func:`~tegraph.design.timeline.simulate_timeline`, spec §4b, each task on a
processor of its own so that it is §3 exactly). Expected values are derived by
hand below; the sweeps confront the three algorithms on random skeletons, the
corpus and the examples.
"""

from __future__ import annotations

import random

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from tegraph import Skeleton, analyze, build_teg, load_skeleton
from tegraph.analysis.baselines.timed_reachability import timed_reachability
from tegraph.cli import app
from tegraph.design.timeline import simulate_timeline
from tegraph.report.timeline_text import render_timeline
from tests.paths import REPO
from tests.tegraph.skeleton_corpus import random_skeleton

EXAMPLES = REPO / "examples"
SETTINGS = settings(max_examples=80, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])

# W (private clock, period 4, phase 0, duration 2) posts x; R (private clock, period 4,
# duration 3, NO outputs) reads x ASYN/SYN. By hand (spec §2-§3):
#   W.tick(k) = 4k-4; W.activate(k) = max(4k-4, W.write(k-1)) = 4k-4; W.compute = W.activate;
#   W.write(k) = 4k-2.
#   R.tick(k) = 4k-4; R.activate(k) = max(R.tick(k), R.compute(k-1) + 3)  (the return place
#   leaves R.compute: it holds 3) = 0, then max(4k-4, 4(k-1)-2+3) = 4k-3 for k >= 2;
#   R.read:x(k) = max(R.activate(k), W.write(k)) = 4k-2 = R.compute(k).
#   end_R(k) = R.compute(k) + 3 = 4k+1 > R.tick(k+1) = 4k: overrun at k = 2 (end_R(1) = 5 > 4),
#   by 1 ms, less than R's duration: the start of R's computation, 4k-6 at k-1, never
#   passes the tick 4k-4, so v1 (x_last = x_R.compute) said "never".
#   Every event runs at 4 from k = 2 on (R.activate(1) = 0, not 5 - 4): period 4,
#   transient K = 2, cyclicity 1, rate-consistent: a task that keeps pace but ends late.
KEEPS_PACE = {"tasks": {
    "W": {"duration": 2, "period": 4, "outputs": ["x"], "processor": "p0"},
    "R": {"duration": 3, "period": 4, "inputs": ["x"], "processor": "p1"}},
    "links": [{"from": "W:x", "to": "R:x", "protocol": "ASYN/SYN"}]}

# The same with R of duration 5 (above its period) and W of duration 3:
#   W.write(k) = 4k-1; R.activate(k) = max(4k-4, R.compute(k-1) + 5);
#   R.compute(1) = max(0, 3) = 3, R.compute(k) = max(4k-4, R.compute(k-1) + 5, 4k-1):
#   3, 8, 13, 18: 5k-2 (R is slower than its clock: period 5, not rate-consistent).
#   end_R(k) = 5k+3; overrun at the smallest k >= 2 with 5(k-1)+3 > 4k-4: k = 2 (8 > 4),
#   by 4 < 5 ms. v1 compared R.compute(k-1) = 5k-7 > 4k-4: k = 4.
SLOWER = {"tasks": {
    "W": {"duration": 3, "period": 4, "outputs": ["x"], "processor": "p0"},
    "R": {"duration": 5, "period": 4, "inputs": ["x"], "processor": "p1"}},
    "links": [{"from": "W:x", "to": "R:x", "protocol": "ASYN/SYN"}]}


def test_end_of_a_task_without_outputs_is_the_end_of_its_computation():
    sk = Skeleton.from_dict(KEEPS_PACE)
    r = analyze(sk, design=False)
    assert (r.groups[0].period, r.groups[0].transient) == (4, (2, 1))
    assert (r.tasks["R"].overrun_at, r.tasks["W"].overrun_at) == (2, None)
    assert r.tasks["R"].overrun_decided and r.consistent is False
    daters = build_teg(sk).simulate(4)
    assert daters["R.compute"] == [2, 6, 10, 14] and daters["R.activate"] == [0, 5, 9, 13]
    timed = timed_reachability(sk)
    assert (timed.tasks["R"].overrun_at, timed.tasks["W"].overrun_at) == (2, None)
    assert timed.groups[0].transient == (2, 1)
    tl = simulate_timeline(sk)
    # Drawn until the proof: tick 2 at 4 finds job 1 of R running until 5.
    (late,) = tl.late_jobs
    assert (late.task, late.index, late.finish, tl.overrun_ticks["R"]) == ("R", 1, 5, 4)
    tl = simulate_timeline(sk, horizon=12)
    assert [(j.index, j.finish) for j in tl.jobs if j.task == "R"] == [(1, 5), (2, 9), (3, None)]
    assert tl.overrun_at["R"] == 2 and tl.overrun_at["W"] is None
    assert ("OVERRUN: R overruns at activation 2: its clock R.clock ticks at 4 ms while "
            "activation 1 runs until 5 ms") in render_timeline(tl)


def test_task_slower_than_its_clock_overruns_by_less_than_its_duration():
    sk = Skeleton.from_dict(SLOWER)
    r = analyze(sk, design=False)
    assert r.tasks["R"].period == 5 and r.groups[0].rate_consistent is False
    assert r.tasks["R"].overrun_at == 2 and r.tasks["W"].overrun_at is None
    assert build_teg(sk).simulate(4)["R.compute"] == [3, 8, 13, 18]
    timed = timed_reachability(sk, max_states=2000)
    assert timed.tasks["R"].overrun_at == 2
    assert simulate_timeline(sk, horizon=20).overrun_at["R"] == 2


def test_figure_12_one_numbering_in_three_commands(tmp_path):
    # Hand derivation in examples/fig12_double_sync.yaml (MT2 has an output, so v1.1
    # changes nothing there): end_MT2 = x_write:u = 3, 13, 23; ticks 0, 4, 8, 12: the first
    # k >= 2 with end(k-1) > tick(k) is k = 3. analyze said "overrun at activation 3" and the
    # timeline "activation 2 ends at 13 ms, after the next tick at 8 ms": the late job's
    # number. Both now say activation 3.
    path = str(EXAMPLES / "fig12_double_sync.yaml")
    runner = CliRunner()
    analyzed = runner.invoke(app, ["analyze", path, "--no-design"])
    timed = runner.invoke(app, ["reach", path, "--timed", "--max-states", "200"])
    drawn = runner.invoke(app, ["timeline", path])
    assert "at activation 3" in analyzed.stdout
    assert "MT2 overruns at activation 3" in timed.stdout
    assert "MT2 overruns at activation 3: its clock MT2.clock ticks at 8 ms" in drawn.stdout
    assert (analyzed.exit_code, timed.exit_code, drawn.exit_code) == (1, 1, 1)


# ------------------------------------------------------------------ the sweeps

def check_three_agree(data: dict) -> int | None:
    """analyze, reach --timed and timeline agree on the first overrun of every clocked task.

    Returns how many overruns the timeline confirmed.
    """
    # Each task alone on its processor: no interference. A thread is one OS thread,
    # so its tasks share one processor; its places already serialize them (each
    # starts once the one before has finished), so they never compete for it.
    data.pop("processors", None)  # their kinds (§4d) name processors no task keeps
    for name, spec in data["tasks"].items():
        spec["processor"] = f"cpu.{name}"
    for thread in data.get("threads", ()):
        for name in thread:
            data["tasks"][name]["processor"] = f"cpu.{thread[0]}"
    sk = Skeleton.from_dict(data)
    report = analyze(sk, design=False, max_steps=20_000)
    timed = timed_reachability(sk, max_states=3000)
    for g, b in zip(report.groups, timed.groups):
        # Both say which groups are dead; the timed search names what is stuck.
        assert (b.stuck_events is not None) == (not g.live), g.tasks
        if not g.live:
            circuit = {e for d in report.deadlocks if set(d.tasks) <= set(g.tasks)
                       for e in d.events}
            assert circuit <= set(b.stuck_events)
    clocked = [t for t, task in sk.tasks.items() if task.clock]
    for t in clocked:
        mine, other = report.tasks[t], timed.tasks[t]
        if not report.groups[mine.group].live:
            assert mine.overrun_at is None and other.overrun_at is None and other.decided
            continue
        if other.overrun_at is not None or (other.decided and mine.overrun_decided):
            assert other.overrun_at == mine.overrun_at, t
    # The timeline draws the §4b schedule, which with a processor per task
    # is §3 exactly: its first overruns are the engine's, whatever it draws.
    tl = simulate_timeline(sk)
    assert bool(tl.deadlocks) == (not report.live)
    assert not any(j.late for j in tl.jobs if j.task in tl.dead_tasks)
    confirmed = 0
    for t in clocked:
        rep, mine = report.tasks[t], tl.schedule.tasks[t]
        if not rep.overrun_decided or (mine.overrun_at is None and not mine.decided):
            continue  # a budget on either side: nothing to compare
        assert tl.overrun_at[t] == rep.overrun_at, (t, rep.overrun_at)
        confirmed += rep.overrun_at is not None
    return confirmed


@SETTINGS
@given(st.randoms(use_true_random=False))
def test_three_commands_agree_on_random_skeletons(rng: random.Random) -> None:
    assume(check_three_agree(random_skeleton(rng)) is not None)


def test_three_commands_agree_on_the_corpus() -> None:
    """Not vacuous: most of the corpus reaches the timeline, with overruns among them."""
    outcomes = [check_three_agree(random_skeleton(random.Random(seed))) for seed in range(150)]
    compared = [c for c in outcomes if c is not None]
    assert len(compared) >= 60 and sum(compared) >= 20, (len(compared), sum(compared))


@pytest.mark.parametrize("example", sorted(p.name for p in EXAMPLES.glob("*.yaml")))
def test_three_commands_agree_on_the_examples(example: str) -> None:
    check_three_agree(load_skeleton(EXAMPLES / example).to_dict())
