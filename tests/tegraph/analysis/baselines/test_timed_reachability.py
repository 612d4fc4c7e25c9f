"""The timed baseline (:mod:`tegraph.timed_reachability`) against hand derivations and
against the (max,+) figures of :func:`tegraph.analyze`, the other algorithm.

The agreement contract: wherever the baseline concludes, its period,
transient (K, c) and first overrun equal the (max,+) ones; and it concludes on
every rate-consistent group (a bounded timed state space must repeat).
``analyze(..., design=False)``: the design section compares with nothing here.
"""

from __future__ import annotations

import json
import random
from fractions import Fraction as F
from functools import cache
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from tegraph import Skeleton, analyze, load_skeleton, render_text
from tegraph.analysis.baselines.timed_reachability import timed_reachability
from tegraph.cli import app
from tests.paths import REPO
from tests.tegraph.skeleton_corpus import random_skeleton, write_corpus

SETTINGS = settings(max_examples=60, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow])
CORPUS_SIZE = 300
BUDGET = 3000
EXAMPLES = REPO / "examples"

# The ORCCAD double synchronization: A and B share a clock (period 4, phase 1)
# and B also waits for A's message. By hand: A computes at 4k-3 and writes at
# 4k; B activates at 1, then at max(4k-3, 4(k-1)+3) = 4k-1, reads and computes
# at 4k, writes at 4k+3 > 4k+1 = the next tick: period 4, transient K=2 (B's
# activation daters 1, 7, 11, 15... are periodic from k=2), c=1, overrun at 2.
DOUBLE_SYNC = {"clocks": {"c": {"period": 4, "phase": 1}}, "tasks": {
    "A": {"duration": 3, "clock": "c", "outputs": ["x"]},
    "B": {"duration": 3, "clock": "c", "inputs": ["x"], "outputs": ["y"]}},
    "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]}


# ------------------------------------------------------------------ hand derivations

def test_one_clocked_task() -> None:
    # compute fires at 1, 5, 9...: periodic from k=1, and done at 4k-3+3 < 4k+1.
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 3, "period": 4, "phase": 1}}})
    r = timed_reachability(sk)
    assert (r.complete, r.ended_by) == (True, "repeat")
    assert (r.groups[0].period, r.groups[0].transient) == (F(4), (1, 1))
    a = r.tasks["A"]
    assert (a.period, a.overrun_at, a.decided) == (F(4), None, True)
    assert r.exit_status == 0


def test_double_synchronization_overruns_in_step() -> None:
    r = timed_reachability(Skeleton.from_dict(DOUBLE_SYNC))
    g = r.groups[0]
    assert (g.period, g.transient, r.tasks["B"].overrun_at, r.tasks["A"].overrun_at) == (
        F(4), (2, 1), 2, None)
    assert r.exit_status == 1


@pytest.mark.parametrize("periods, lcm", [([2, 3], 6), ([2, 3, 5], 30)])
def test_the_whole_state_repeats_at_the_lcm_of_independent_periods(periods, lcm) -> None:
    """Tasks of duration 1, phase 0: every token is back in place exactly at the lcm."""
    sk = Skeleton.from_dict({"tasks": {f"T{p}": {"duration": 1, "period": p} for p in periods}})
    r = timed_reachability(sk)
    assert r.ended_by == "repeat" and r.time_reached == lcm
    assert [(g.period, g.transient) for g in r.groups] == [(F(p), (1, 1)) for p in periods]


def test_zero_duration_circuits() -> None:
    # An unclocked task of duration 0 fires at 0 forever: period 0 from k=1.
    r = timed_reachability(Skeleton.from_dict({"tasks": {"Z": {"duration": 0}}}))
    assert (r.complete, r.groups[0].period, r.groups[0].transient) == (True, F(0), (1, 1))
    # One that floods a reader of duration 1 never lets time move: that group is
    # set aside as stalled at 0, and the independent clocked task is still found.
    sk = Skeleton.from_dict({
        "tasks": {"W": {"duration": 0, "outputs": ["x"]}, "R": {"duration": 1, "inputs": ["x"]},
                  "C": {"duration": 1, "period": 2}},
        "links": [{"from": "W:x", "to": "R:x", "protocol": "ASYN/SYN"}]})
    r = timed_reachability(sk)
    assert (r.groups[0].stalled_at, r.groups[0].period) == (F(0), None)
    assert (r.groups[1].period, r.groups[1].transient, r.tasks["C"].decided) == (F(2), (1, 1), True)


def test_a_deadlocked_group_stops_firing() -> None:
    sk = load_skeleton(EXAMPLES / "fig7a_circular_wait.yaml")  # every task waits to read
    r = timed_reachability(sk)
    assert (r.complete, r.ended_by, r.firings, r.groups[0].stuck_after) == (
        True, "quiescence", 0, F(0))
    # Each of the nine events waits on an empty place fed by the next one round the
    # circle (the example's derivation): all of them are stuck from the first state.
    assert r.groups[0].stuck_events == [
        "MT1.read:b", "MT1.compute", "MT1.write:a", "MT2.read:c", "MT2.compute",
        "MT2.write:b", "MT3.read:a", "MT3.compute", "MT3.write:c"]
    assert r.deadlock and r.exit_status == 1 and "deadlock" in render_text(r)


def test_a_clock_ticking_at_a_dead_group_is_the_deadlock_not_an_overrun() -> None:
    # Figure 7b (hand derivation in the example): at 0, rtc ticks and MT1 activates, reads q
    # and starts computing (4 firings); its rendezvous MT1.write:a then waits for MT2.read:c,
    # which waits for MT3.write:c, which waits (MT3.compute, MT3.read:d) for MT1.write:d,
    # which comes after MT1.write:a: the token-free circuit. MT2.compute and MT2.write:tau
    # wait on it, and MT1.activate on MT1.write:d (its return place is empty after the first
    # activation), MT1.read:q and MT1.compute on MT1.activate: every event but rtc.tick is
    # stuck after those 4 firings, all at time 0. A search that went on ticking (a
    # million states) would call MT1 overrun at activation 2; analyze reports the
    # deadlock and no overrun (spec §4), and so does this search now.
    sk = load_skeleton(EXAMPLES / "fig7b_wrong_order.yaml")
    r = timed_reachability(sk)
    g = r.groups[0]
    assert (r.complete, r.firings, r.states) == (True, 4, 5)
    assert (g.stuck_after, g.period) == (F(0), None)
    assert g.stuck_events == [
        "MT1.activate", "MT1.read:q", "MT1.compute", "MT1.write:a", "MT1.write:d",
        "MT2.read:c", "MT2.compute", "MT2.write:tau", "MT3.read:d", "MT3.compute", "MT3.write:c"]
    assert {t: (x.overrun_at, x.decided) for t, x in r.tasks.items()} == {
        "MT1": (None, True), "MT2": (None, True), "MT3": (None, True)}
    assert r.exit_status == 1 and "overrun" not in render_text(r)
    out = CliRunner().invoke(app, ["reach", str(EXAMPLES / "fig7b_wrong_order.yaml"), "--timed"])
    assert out.exit_code == 1 and "deadlock" in out.stdout


def test_part_of_a_group_runs_on_beside_a_deadlock() -> None:
    # A and B wait for each other's message: A.read:b -> A.compute -> A.write:a -> B.read:a
    # -> B.compute -> B.write:b -> A.read:b holds no token. W (clock 2, duration 1) posts w to
    # A ASYN/SYN and never waits: it writes at 1, 3, 5... A.read:w comes first in A's chain;
    # its return place (A.write:a -> A.read:w, 1 token) lets it fire once, at 1 (W's first
    # post); then that place is empty and fed by the stuck A.write:a. So the stuck events are
    # all of A and B (the last to fire: A.read:w at 1), while W and its clock run for ever:
    # W's messages pile up in the place into A.read:w only, which the dead group's state
    # leaves out, so that state repeats after one period of W and the search ends.
    sk = Skeleton.from_dict({"tasks": {
        "W": {"duration": 1, "period": 2, "outputs": ["w"]},
        "A": {"duration": 1, "inputs": ["w", "b"], "outputs": ["a"]},
        "B": {"duration": 1, "inputs": ["a"], "outputs": ["b"]}},
        "links": [{"from": "W:w", "to": "A:w", "protocol": "ASYN/SYN"},
                  {"from": "A:a", "to": "B:a", "protocol": "ASYN/SYN"},
                  {"from": "B:b", "to": "A:b", "protocol": "ASYN/SYN"}]})
    r = timed_reachability(sk)
    assert r.complete and r.groups[0].stuck_events == [
        "A.read:w", "A.read:b", "A.compute", "A.write:a", "B.read:a", "B.compute", "B.write:b"]
    assert r.groups[0].stuck_after == 1  # A.read:w fired once, at W's first post
    assert r.tasks["W"].overrun_at is None and r.exit_status == 1


def test_budget_stop_and_progress() -> None:
    sk = load_skeleton(EXAMPLES / "fig12_double_sync.yaml")  # not rate-consistent: no repeat
    report = analyze(sk, design=False)
    r = timed_reachability(sk, max_states=500)
    assert (r.states, r.complete, r.stopped_by) == (500, False, "states")
    assert r.groups[0].period is None
    # The overrun is seen on the way; the task that never overruns stays undecided.
    for name, task in report.tasks.items():
        if task.overrun_at is not None:
            assert (r.tasks[name].overrun_at, r.tasks[name].decided) == (task.overrun_at, True)
        elif sk.tasks[name].clock is not None:
            assert (r.tasks[name].overrun_at, r.tasks[name].decided) == (None, False)
    calls: list[int] = []
    r = timed_reachability(sk, progress=lambda s, f, sec: calls.append(f),
                           stop=lambda: len(calls) >= 2)
    assert r.stopped_by == "interrupted" and calls == sorted(calls) and calls[-1] == r.firings
    r = timed_reachability(sk, max_seconds=0)
    assert r.stopped_by == "time"


# ------------------------------------------------------------------ agreement

def check_agreement(sk: Skeleton) -> None:
    report = analyze(sk, design=False)
    r = timed_reachability(sk, max_states=BUDGET)
    assert [g.tasks for g in r.groups] == [g.tasks for g in report.groups]
    for g, b in zip(report.groups, r.groups):
        # A group is dead in one exactly when it is in the other, and what the
        # timed search finds stuck holds the token-free circuits analyze reports.
        assert (b.stuck_events is not None) == (not g.live)
        if not g.live:
            circuits = {e for d in report.deadlocks if set(d.tasks) <= set(g.tasks)
                        for e in d.events}
            assert circuits <= set(b.stuck_events)
        if g.rate_consistent:
            assert b.period is not None, f"group {g.index} did not repeat"
        if b.period is not None:
            assert (b.period, b.transient) == (g.period, g.transient)
    for name, t in report.tasks.items():
        b = r.tasks[name]
        group = report.groups[t.group]
        if not group.live:  # both report the deadlock there, not overruns
            assert b.overrun_at is None and t.overrun_at is None and b.decided
            continue
        if group.rate_consistent:
            assert b.decided and b.period == t.period
        if b.decided and t.overrun_decided:
            assert b.overrun_at == t.overrun_at
        if b.overrun_at is not None:  # the first overrun seen is the first there is
            assert b.overrun_at == t.overrun_at


@SETTINGS
@given(st.randoms(use_true_random=False))
def test_figures_equal_the_maxplus_ones(rng: random.Random) -> None:
    check_agreement(Skeleton.from_dict(random_skeleton(rng)))


@pytest.fixture(scope="session")
def corpus(tmp_path_factory: pytest.TempPathFactory) -> list[Path]:
    return write_corpus(tmp_path_factory.mktemp("timed-corpus"), CORPUS_SIZE)


@cache
def _load(path: Path) -> Skeleton:
    return load_skeleton(path)


@pytest.mark.parametrize("seed", range(CORPUS_SIZE))
def test_corpus_figures(corpus: list[Path], seed: int) -> None:
    check_agreement(_load(corpus[seed]))


def test_corpus_exercises_every_figure(corpus: list[Path]) -> None:
    """Not vacuous: repeats with K > 1 and c > 1, and overruns, are all compared."""
    transients, overruns = set(), 0
    for path in corpus:
        report = analyze(_load(path), design=False)
        transients |= {g.transient for g in report.groups if g.transient}
        overruns += sum(t.overrun_at is not None for t in report.tasks.values())
    assert any(k > 1 for k, _ in transients) and any(c > 1 for _, c in transients)
    assert overruns >= 50


@pytest.mark.parametrize("example", sorted(p.name for p in EXAMPLES.glob("*.yaml")))
def test_examples(example: str) -> None:
    check_agreement(load_skeleton(EXAMPLES / example))


# ------------------------------------------------------------------ command line

def test_cli_timed_json(tmp_path: Path) -> None:
    f = tmp_path / "double.json"
    f.write_text(json.dumps(DOUBLE_SYNC))
    out = CliRunner().invoke(app, ["reach", str(f), "--timed", "--json"])
    assert out.exit_code == 1, out.output
    d = json.loads(out.stdout)
    assert d["complete"] is True and d["states"] > 0
    assert d["tasks"]["B"]["period"] == "4" and d["tasks"]["B"]["overrun_at"] == 2
    assert d["tasks"]["A"]["overrun_at"] is None
    assert [(g["tasks"], g["period"], g["transient"]) for g in d["groups"]] == [
        (["A", "B"], "4", {"k": 2, "cyclicity": 1})]


def test_cli_timed_agrees_with_analyze_json() -> None:
    f = str(EXAMPLES / "ring_two_tokens.yaml")
    runner = CliRunner()
    timed = json.loads(runner.invoke(app, ["reach", f, "--timed", "--json"]).stdout)
    maxplus = json.loads(runner.invoke(app, ["analyze", f, "--json"]).stdout)
    assert [(g["period"], g["transient"]) for g in timed["groups"]] == [
        (g["period"], g["transient"]) for g in maxplus["groups"]]
    out = runner.invoke(app, ["reach", f, "--timed", "--max-states", "3"])
    assert out.exit_code == 0 and "inconclusive (budget 3 states reached)" in out.stdout


def test_cli_timed_progress_on_a_terminal() -> None:
    # A search longer than a second (400,000 states: a few seconds) shows its progress on a
    # terminal (stderr a tty), as the untimed one does; the bar is erased before the result
    # is printed on stdout.
    import os
    import pty
    import subprocess
    import sys

    main, child = pty.openpty()
    proc = subprocess.Popen(
        [sys.executable, "-m", "tegraph.cli", "reach", "--timed", "--max-states", "400000",
         str(EXAMPLES / "fig12_double_sync.yaml")],
        stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=child)
    os.close(child)
    seen = b""
    while True:  # read as it comes: a full terminal buffer would block the search
        try:
            chunk = os.read(main, 65536)
        except OSError:  # the other end is closed: the process has ended
            break
        if not chunk:
            break
        seen += chunk
    os.close(main)
    # Type: stdout=PIPE: the stream is there.
    out = proc.stdout.read()  # type: ignore[union-attr]
    assert proc.wait(timeout=300) == 1 and b"MT2 overruns at activation 3" in out
    assert b" states, " in seen and b"/s" in seen, seen[:200]


def test_a_group_firing_without_end_is_in_the_verdict():
    # A and B, both of duration 0, pass one token round a circuit: they fire at time 0
    # without end (a zero-duration circuit); C runs alone on its 5 ms clock.
    sk = Skeleton.from_dict({
        "tasks": {"A": {"duration": 0, "inputs": ["y"], "outputs": ["x"]},
                  "B": {"duration": 0, "inputs": ["x"], "outputs": ["y"]},
                  "C": {"duration": 1, "period": 5}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"},
                  {"from": "B:y", "to": "A:y", "protocol": "SYN/ASYN"}]})
    r = timed_reachability(sk)
    assert [g.stalled_at for g in r.groups] == [0, None]
    assert render_text(r).splitlines()[-1] == (
        "verdict: group 0 fires without end at time 0 ms (zero-duration tasks) (exit status 0)")
