"""analyze(): figures checked against hand derivations and a long exact simulation."""

from __future__ import annotations

import gc
from fractions import Fraction

import pytest

import tegraph.analysis.analyze as analyze_module
from tegraph import analyze
from tegraph.model.build import build_teg, last_event
from tegraph.model.skeleton import Skeleton


def _overruns_by_definition(sk: Skeleton, task: str, n: int) -> int | None:
    """Spec §4 (v1.1) literally: smallest k >= 2 with end(k-1) > x_tick(k), over n firings,
    end = x_last, plus the duration when the task has no outputs (its last event is compute)."""
    teg = build_teg(sk)
    daters = teg.simulate(n)
    extra = 0 if sk.tasks[task].outputs else sk.tasks[task].duration
    end = [x + extra for x in daters[last_event(teg, task)]]
    tick = daters[teg.attrs["clocks"][sk.tasks[task].clock]]
    for k in range(2, n + 1):
        if end[k - 2] > tick[k - 1]:
            return k
    return None


FAST_WRITER = {
    "tasks": {
        "W": {"duration": 1, "period": 2, "outputs": ["o"]},
        "T": {"duration": 4, "period": 5, "inputs": ["i"]},
    },
    "links": [{"from": "W:o", "to": "T:i", "protocol": "ASYN/SYN"}],
}


def test_faster_writer_upstream_never_overrun_is_proven():
    # W posts its k-th message at 2(k-1) + 1; T's clock ticks at 5(k-1).
    # T.read(k) = max(T.activate(k), 2k - 1), T.activate(k) = max(5(k-1),
    # T.compute(k-1) + 4): T.compute(1) = 1, then 5(k-1) for k >= 2 (W's
    # message is always there in time). T has no outputs, so activation k-1 ends
    # at T.compute(k-1) + 4 <= 5(k-2) + 4 < 5(k-1) (spec §4, v1.1): never an
    # overrun. W's place into T.read is unbounded (W is faster), so the group is
    # not rate-consistent and no full state repeats: the proof needs the bounds
    # of regime_bounds.
    sk = Skeleton.from_dict(FAST_WRITER)
    report = analyze(sk)
    t = report.tasks["T"]
    assert t.period == 5 and t.overrun_at is None and t.overrun_decided
    assert report.groups[0].rate_consistent is False
    assert [u.kind for u in report.unbounded_places] == ["messages-overwritten"]
    assert _overruns_by_definition(sk, "T", 300) is None


def test_late_fast_writer_overruns_at_2():
    # W starts at 13: its k-th message comes at 13 + 2(k-1) + 1 = 2k + 12, so
    # T.read(1) = 14 = T.compute(1) > T's second tick at 5: overrun at k = 2.
    data = {**FAST_WRITER, "tasks": {**FAST_WRITER["tasks"],
                                     "W": {"duration": 1, "period": 2, "phase": 13,
                                           "outputs": ["o"]}}}
    sk = Skeleton.from_dict(data)
    assert analyze(sk).tasks["T"].overrun_at == 2
    assert _overruns_by_definition(sk, "T", 50) == 2


def test_fractional_period_and_slack_are_exact():
    # One task of duration 1/3 on a clock of period 7/3: period 7/3, slack 2.
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": "1/3", "period": "7/3"}}})
    report = analyze(sk)
    assert report.tasks["A"].period == Fraction(7, 3)
    assert report.tasks["A"].slack == 2
    assert report.to_dict()["groups"][0]["period"] == "7/3"


def test_thread_period_is_the_sum_of_its_tasks():
    # Thread [A, B], no clocks, no outputs: the thread circuit is A.compute ->
    # B.compute -> A.compute holding 3 + 4 with 1 token (the thread-return
    # place): both tasks run every 7. Each chain alone (3 or 4 per token)
    # is faster, so the thread circuit is critical: slack 0 for both.
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 3}, "B": {"duration": 4}},
                             "threads": [["A", "B"]]})
    report = analyze(sk)
    assert report.groups[0].period == 7
    assert report.tasks["A"].slack == 0 and report.tasks["B"].critical is True


def test_transient_and_cyclicity_of_a_two_token_circuit():
    # SYN/SYN rendezvous between A (clock 4, duration 1) and B (no clock,
    # duration 6): B's chain (read/rendezvous -> compute -> return, holding 6,
    # 1 token) is slower than the clock, so A waits: the group runs at 6, the
    # clock place is unbounded, not rate-consistent.
    sk = Skeleton.from_dict({
        "tasks": {"A": {"duration": 1, "period": 4, "outputs": ["x"]},
                  "B": {"duration": 6, "inputs": ["x"]}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "SYN/SYN"}]})
    report = analyze(sk)
    assert report.tasks["A"].period == 6 and report.tasks["B"].period == 6
    assert [u.kind for u in report.unbounded_places] == ["clock-overrun"]
    # A's last event is the rendezvous A.write:x: x(1) = 1, x(2) = 7 (B's
    # compute ends at 1 + 6), ticks at 0, 4, 8: x_last(2) = 7 <= 8, x_last(3)
    # = 13 > 12: overrun at k = 4.
    assert report.tasks["A"].overrun_at == 4
    assert _overruns_by_definition(sk, "A", 20) == 4


# ------------------------------------------------------------------ how each verdict was obtained

# B and C wait for each other's message: a token-free circuit (a dead group); A is a task of
# duration 1 on its own clock of period 4 (a live, rate-consistent group).
ONE_DEAD_ONE_LIVE = {"tasks": {
    "A": {"duration": 1, "period": 4},
    "B": {"duration": 1, "inputs": ["b"], "outputs": ["a"]},
    "C": {"duration": 1, "inputs": ["a"], "outputs": ["b"]}},
    "links": [{"from": "B:a", "to": "C:a", "protocol": "ASYN/SYN"},
              {"from": "C:b", "to": "B:b", "protocol": "ASYN/SYN"}]}


def test_methods_of_a_skeleton_whose_every_group_is_dead():
    # Figure 7a: no group is live, so nothing was simulated and no period computed; the
    # header used to say "dater simulation over 0 activations; each periodic regime proven
    # by a repeated state" and "certificate verified".
    from tegraph import load_skeleton
    from tests.paths import REPO
    m = analyze(load_skeleton(REPO / "examples" / "fig7a_circular_wait.yaml")).methods
    assert m["timing"] == "no dater simulation: every group is dead"
    assert m["periods"] == "no live group: no period computed"
    assert m["slack"] == "no slack computed: no group is rate-consistent"
    assert m["liveness"].startswith("token-free circuits: 1 found")


def test_methods_of_a_skeleton_with_a_dead_and_a_live_group():
    m = analyze(Skeleton.from_dict(ONE_DEAD_ONE_LIVE), design=False).methods
    assert m["periods"].startswith("periods of the 1 live group(s) only (1 dead): maximum cycle "
                                   "ratio by exact Howard policy iteration; certificate verified")
    # A: compute at 4(k-1), periodic from k = 1; the state repeats at k = 2.
    assert m["timing"] == (
        "exact dater simulation over 2 activations; the periodic regime of 1 rate-consistent "
        "group(s) proven by a repeated state (homogeneity of the (max,+) recurrence); the "
        "overrun of 1 clocked task(s) decided (the first one seen, or none up to a proven "
        "periodic regime); 1 dead group(s) not simulated")


def test_methods_when_nothing_is_clocked():
    # W (duration 1) posts to R (duration 2) ASYN/SYN, no clock: W runs every 1, R every 2,
    # the place between them is unbounded: no rate-consistent group, no clocked task, so
    # the dater simulation has nothing to find and does not run.
    sk = Skeleton.from_dict({"tasks": {"W": {"duration": 1, "outputs": ["x"]},
                                       "R": {"duration": 2, "inputs": ["x"]}},
                             "links": [{"from": "W:x", "to": "R:x", "protocol": "ASYN/SYN"}]})
    m = analyze(sk, design=False).methods
    assert m["timing"] == ("no dater simulation: no rate-consistent group (no transient to "
                           "find) and no clocked task in a live group (no overrun to watch)")
    assert m["periods"].endswith("certificate verified")
    # One free-running task (period 3): its regime is found, there is no overrun to watch.
    m = analyze(Skeleton.from_dict({"tasks": {"A": {"duration": 3}}}), design=False).methods
    assert "the periodic regime of 1 rate-consistent group(s) proven" in m["timing"]
    assert "overrun" not in m["timing"]


def test_methods_when_overruns_stay_undecided():
    # FAST_WRITER with a budget of 2 firings: T's proof needs the regime of regime_bounds,
    # which 2 firings do not reach; W's own regime (period 2 from k = 1) is found.
    r = analyze(Skeleton.from_dict(FAST_WRITER), design=False, max_steps=2)
    assert not r.tasks["T"].overrun_decided and r.tasks["W"].overrun_decided
    assert r.methods["timing"].endswith(
        "the overrun of 1 clocked task(s) decided (the first one seen, or none up to a proven "
        "periodic regime); 1 overrun(s) undecided within the budget")


def test_the_cyclic_collector_is_paused_during_the_analysis_and_restored(monkeypatch):
    # analyze_skeleton pauses the cyclic garbage collector while it runs (a speed-up
    # only): it must be off inside, and left as found after, even on an error.
    seen = []
    real = analyze_module._slack

    def spy(*args):
        seen.append(gc.isenabled())
        return real(*args)

    monkeypatch.setattr(analyze_module, "_slack", spy)
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 2, "period": 10}}})
    was = gc.isenabled()
    try:
        for state in (True, False):
            (gc.enable if state else gc.disable)()
            assert analyze_module.analyze_skeleton(sk).live
            assert gc.isenabled() is state
        monkeypatch.setattr(analyze_module, "_slack", lambda *a: 1 / 0)
        gc.enable()
        with pytest.raises(ZeroDivisionError):
            analyze_module.analyze_skeleton(sk)
        assert gc.isenabled()
    finally:
        (gc.enable if was else gc.disable)()
    assert seen == [False, False]
