"""`tegraph timeline`: the §4b schedule on processors (one semantics with analyze), drawn
until its proof, its text rendering and its drawing.

Expected schedules are derived by hand in the comments (from the durations, periods
and priorities of the files); the drawing past a proven regime is checked against
the tick-by-tick oracle of tests/tegraph/analysis/processors/test_schedule_oracle.py,
written apart from the engine.
"""

from __future__ import annotations

import subprocess
import sys
import time
from fractions import Fraction as F

import pytest
from hypothesis import HealthCheck, given, settings
from typer.testing import CliRunner

from tegraph import analyze, load_skeleton
from tegraph.analysis.analyze import analyze_skeleton
from tegraph.analysis.processors import platform_of
from tegraph.cli import app
from tegraph.design.timeline import simulate_timeline
from tegraph.errors import InputError
from tegraph.model.skeleton import Skeleton
from tegraph.report.plot import (
    INSTALL_HINT,
    PlotUnavailableError,
    draw_timeline,
    matplotlib_available,
)
from tegraph.report.timeline_text import render_timeline
from tests.paths import REPO
from tests.tegraph.analysis.processors.test_schedule_oracle import oracle, skeletons

EXAMPLES = REPO / "examples"


def runs(tl, processor="default"):
    """(task#k, start, end) of every drawn interval on ``processor``, times as text."""
    return [(f"{i.task}#{i.k}", str(i.start), str(i.end)) for i in tl.intervals
            if i.processor == processor]


def run(*args: str, timeout: float = 120) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "tegraph.cli", *args], check=False,
                          capture_output=True, text=True, timeout=timeout)


# ------------------------------------------------------------------ (1) Figure 17

def test_computed_torque_on_one_cpu_is_figure_17():
    # examples/computed_torque.yaml, one processor, rate-monotonic (§4b): groups
    # [OBS.JL] (1 ms), [TG.JS, TF.TT.JS, CO.JS] (2 ms), [MOD.DYN] (6 ms) -> priorities
    # 3, 2, 1. Durations 0.1, 0.1, 0.2, 0.3, 1.2. Every clock ticks at 0; q is an
    # unlinked input, so OBS.JL, TG.JS and MOD.DYN are released at 0; TF.TT.JS waits
    # for qd (TG.JS's write), CO.JS for e (TF.TT.JS's write):
    #   OBS.JL#1 0-0.1; TG.JS#1 0.1-0.2; TF.TT.JS#1 0.2-0.4; CO.JS#1 0.4-0.7;
    #   MOD.DYN#1 0.7-1 (0.3 of 1.2), preempted by OBS.JL#2 at its tick 1: 1-1.1;
    #   MOD.DYN#1 resumes 1.1-2 (0.9 more): it ends in the second basic cycle, at 2.
    #   Tick 2: OBS.JL#3 2-2.1, then the chain 2.1-2.2, 2.2-2.4, 2.4-2.7; OBS.JL#4 3-3.1;
    #   tick 4: OBS.JL#5 4-4.1, chain 4.1-4.7; OBS.JL#6 5-5.1.
    # Every job has ended by 5.1 and the three clocks tick together at 6 as at 0: the
    # state at 6 is the state at 0, the regime is [0, 6): the drawing ends at 6.
    tl = simulate_timeline(load_skeleton(EXAMPLES / "computed_torque.yaml"))
    assert tl.priorities == {"OBS.JL": 3, "TG.JS": 2, "TF.TT.JS": 2, "CO.JS": 2, "MOD.DYN": 1}

    assert runs(tl) == [
        ("OBS.JL#1", "0", "1/10"), ("TG.JS#1", "1/10", "1/5"), ("TF.TT.JS#1", "1/5", "2/5"),
        ("CO.JS#1", "2/5", "7/10"), ("MOD.DYN#1", "7/10", "1"), ("OBS.JL#2", "1", "11/10"),
        ("MOD.DYN#1", "11/10", "2"), ("OBS.JL#3", "2", "21/10"),
        ("TG.JS#2", "21/10", "11/5"), ("TF.TT.JS#2", "11/5", "12/5"), ("CO.JS#2", "12/5", "27/10"),
        ("OBS.JL#4", "3", "31/10"), ("OBS.JL#5", "4", "41/10"),
        ("TG.JS#3", "41/10", "21/5"), ("TF.TT.JS#3", "21/5", "22/5"), ("CO.JS#3", "22/5", "47/10"),
        ("OBS.JL#6", "5", "51/10")]
    assert tl.horizon == 6 and tl.proof_end == 6 and tl.schedulable is True
    (mod,) = [j for j in tl.jobs if j.task == "MOD.DYN"]
    assert (mod.finish, mod.preemptions, mod.segments) == (2, 1, [(F(7, 10), 1), (F(11, 10), 2)])
    assert tl.schedule.tasks["MOD.DYN"].response == 2
    text = render_timeline(tl)
    lines = text.splitlines()
    assert lines[0] == "timeline computed-torque on its processors: 0 to 6 ms, one column = 0.1 ms"
    lane = lines[1].split("|")[1]  # A OBS.JL, B TG.JS, C TF.TT.JS, D CO.JS, E MOD.DYN
    assert lane[:20] == "ABCCDDDEEEAEEEEEEEEE" and len(lane) == 60
    assert "     1.1 - 2        MOD.DYN#1  resumes; ends" in text
    assert "       0.7 - 1        MOD.DYN#1  preempted" in text
    assert "method: exact event-driven simulation" in text
    assert lines[-1] == ("verdict: schedulable on its processors (proven): no overrun, no "
                         "starved job, no growing place (exit status 0)")


def test_doubled_durations_overrun_on_one_cpu_as_analyze_says():
    # Every duration x2 (0.2, 0.2, 0.4, 0.6, 2.4): with one processor per task the
    # skeleton is consistent, and MOD.DYN's overrun at activation 2 is the one CPU's.
    # By hand, one CPU, the same priorities: OBS.JL#1 0-0.2, TG.JS 0.2-0.4, TF.TT.JS
    # 0.4-0.8, CO.JS 0.8-1 (0.2 of 0.6), preempted by OBS.JL#2 1-1.2, CO.JS 1.2-1.6,
    # MOD.DYN 1.6-2 (0.4 of 2.4). Each 2 ms cycle repeats this: MOD.DYN also gets
    # 3.6-4 and 5.6-6, so at dyn's tick 2 (6 ms) activation 1 has had 1.2 of its 2.4:
    # MOD.DYN overruns at activation 2 (a utilization of 1.2 > 1).
    data = load_skeleton(EXAMPLES / "computed_torque.yaml").to_dict()
    for spec in data["tasks"].values():
        spec["duration"] = 2 * F(str(spec["duration"]))
    sk = Skeleton.from_dict(data)
    tl = simulate_timeline(sk)
    assert tl.overrun_at["MOD.DYN"] == 2 and tl.overrun_ticks["MOD.DYN"] == 6
    assert [(s, e) for t, s, e in runs(tl) if t == "MOD.DYN#1"][:3] == [
        ("8/5", "2"), ("18/5", "4"), ("28/5", "6")]
    assert tl.exit_status == 1


# ------------------------------------------------------------------ (2) SYN/SYN 4 / 6

SYN_PAIR = {"tasks": {"A": {"duration": 1, "period": 4, "outputs": ["x"]},
                      "B": {"duration": 1, "period": 6, "inputs": ["x"]}},
            "links": [{"from": "A:x", "to": "B:x", "protocol": "SYN/SYN"}]}


def test_syn_syn_pair_overruns_at_activation_5_as_analyze_proves():
    # A (clock 4, duration 1) writes x, B (clock 6, duration 1) reads it SYN/SYN: the
    # write W = A.write:x = B.read:x is one event. One group (design period 4): both
    # priority 1, one processor; at equal priority and release, file order (A first).
    #   A.activate(k) = max(4(k-1), W(k-1)); B.activate(k) = max(6(k-1), f_B(k-1));
    #   W(k) = max(f_A(k), B.activate(k)); B's job is released at W(k).
    #   k=1: A#1 0-1, W = max(1, 0) = 1, B#1 1-2.
    #   k=2: A.act = 4, A#2 4-5; B.act = max(6, 2) = 6; W = 6; B#2 6-7.
    #   k=3: A.act = max(8, 6) = 8, A#3 8-9; B.act = 12; W = 12; B#3 released at 12.
    #   k=4: A.act = max(12, W(3) = 12) = 12, released with B#3: A#4 12-13 (file order),
    #        B#3 13-14; B.act(4) = max(18, 14) = 18; W(4) = max(13, 18) = 18.
    #   end_A(4) = W(4) = 18 > tick 5 of A at 16: A overruns at activation 5.
    # (With a processor per task, §4 gives the same end_A: 1, 6, 12, 18, hence 5.)
    sk = Skeleton.from_dict(SYN_PAIR)
    tl = simulate_timeline(sk, 16)  # until the proof: the overrun's tick
    assert runs(tl) == [("A#1", "0", "1"), ("B#1", "1", "2"), ("A#2", "4", "5"),
                        ("B#2", "6", "7"), ("A#3", "8", "9"), ("A#4", "12", "13"),
                        ("B#3", "13", "14")]
    assert tl.overrun_at == {"A": 5, "B": None} and tl.overrun_ticks["A"] == 16
    # By default: two periods of the fastest clock (A's, 4) past the overrun's tick,
    # which is then inside the frame: 16 + 8 = 24 (the whole fits in 10 periods).
    assert simulate_timeline(sk).horizon == 24
    report = analyze(sk, design=False)
    assert report.tasks["A"].overrun_at == tl.overrun_at["A"] == 5
    assert report.exit_status == tl.exit_status == 1
    text = render_timeline(tl)
    assert ("OVERRUN: A overruns at activation 5: its clock A.clock ticks at 16 ms while "
            "activation 4 has not ended (computed by 13 ms; a write still waits)") in text
    assert text.splitlines()[-1] == (
        "verdict: NOT schedulable on its processors: A overruns first, at activation 5 "
        "(16 ms); 1 growing place (exit status 1)")


def test_a_short_horizon_limits_the_drawing_never_the_verdict(tmp_path):
    # The old timeline stopped at the hyperperiod 12 and exited 0 on this pair.
    f = tmp_path / "pair.yaml"
    f.write_text("tasks:\n  A: {duration: 1, period: 4, outputs: [x]}\n"
                 "  B: {duration: 1, period: 6, inputs: [x]}\n"
                 "links:\n  - {from: 'A:x', to: 'B:x', protocol: SYN/SYN}\n")
    out = CliRunner().invoke(app, ["timeline", str(f), "--horizon", "12"])
    assert out.exit_code == 1, out.output
    assert "0 to 12 ms" in out.output.splitlines()[0]
    assert "A overruns at activation 5" in out.output


# ------------------------------------------------------------------ (3) drifting clocks

DRIFT = [997, 1009, 1013, 1019]  # primes: the hyperperiod is their product / 1000 ms


def test_drifting_clocks_end_at_once_naming_the_hyperperiod(tmp_path):
    # Four sensors of 0.997, 1.009, 1.013 and 1.019 ms (duration 0.1), phases 0, 0.1,
    # 0.2, 0.3 (not released together): a regime holds a whole number of each period,
    # so it cannot repeat before lcm = 997*1009*1013*1019/1000 = 1038412611.331 ms,
    # billions of ticks: undecided within --max-events, at once, naming both. The old
    # timeline printed nothing and grew to 2.8 GB.
    assert 997 * 1009 * 1013 * 1019 == 1038412611331
    f = tmp_path / "sensors.yaml"
    f.write_text("tasks:\n" + "".join(
        f"  S{i}: {{duration: 0.1, period: {p / 1000}, phase: {i / 10}}}\n"
        for i, p in enumerate(DRIFT)))
    start = time.monotonic()
    out = run("timeline", str(f), timeout=60)
    assert time.monotonic() - start < 30
    assert out.returncode == 1, out.stderr
    last = out.stdout.splitlines()[-1]
    assert last.startswith("verdict: UNDECIDED within the budget of 1,000,000 ")
    assert last.endswith("(exit status 1)")
    assert "hyperperiod is 1038412611.331 ms" in last and "--max-events" in last
    assert "`" not in last  # the CLI names its option, not the library's parameter


def test_drifting_clocks_released_together_end_at_once(tmp_path):
    # The same four sensors in phase: whatever decides them (the
    # exact simulation's budget, or a theorem), the answer comes in seconds, its
    # verdict line carries the exit status and the report says how it was obtained.
    f = tmp_path / "sensors.yaml"
    f.write_text("tasks:\n" + "".join(f"  S{i}: {{duration: 0.1, period: {p / 1000}}}\n"
                                      for i, p in enumerate(DRIFT)))
    start = time.monotonic()
    out = run("timeline", str(f), timeout=60)
    assert time.monotonic() - start < 30
    lines = out.stdout.splitlines()
    assert lines[-1].endswith(f"(exit status {out.returncode})")
    assert any(line.startswith("method: ") for line in lines)
    if out.returncode:
        assert "hyperperiod is 1038412611.331 ms" in lines[-1]


def test_a_small_budget_is_undecided_with_its_reason():
    # Clocks 7 and 11 ms: the state cannot repeat before 77 ms; 20 firings do not get
    # there. Exit 1, and the budget is named.
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 7},
                                       "B": {"duration": 1, "period": 11}}})
    tl = simulate_timeline(sk, max_events=20)
    assert tl.schedulable is None and tl.exit_status == 1 and tl.proof_end is None
    last = render_timeline(tl).splitlines()[-1]
    assert "`max_events`" in last and "hyperperiod is 77 ms" in last
    assert simulate_timeline(sk).schedulable is True


# ------------------------------------------------------------------ (4) starvation / overrun

def test_two_tasks_over_full_load_on_one_processor():
    # A {6, period 10, priority 2} and B {6, period 10, priority 1}: load 12/10.
    #   A#1 0-6; B#1 6-10 (4 of 6), preempted by A#2 at 10: 10-16; B#1 resumes 16-18.
    #   Tick 2 of B at 10 finds activation 1 unfinished: B overruns at activation 2.
    # The old analyze exited 0 here ("a processor fails its schedulability test ...
    # which does not change the verdict").
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 6, "period": 10, "priority": 2},
                                       "B": {"duration": 6, "period": 10, "priority": 1}}})
    tl = simulate_timeline(sk, 18)  # the overrun's tick 10, and the late job's end 18
    assert runs(tl) == [("A#1", "0", "6"), ("B#1", "6", "10"), ("A#2", "10", "16"),
                        ("B#1", "16", "18")]
    assert tl.overrun_at == {"A": None, "B": 2} and tl.exit_status == 1
    # By default two periods (10) past the overrun's tick: 10 + 20 = 30, after the late
    # job's end 18 (the whole fits in 10 periods, from 0).
    assert simulate_timeline(sk).horizon == 30
    assert [(j.task, j.index) for j in tl.late_jobs] == [("B", 1)]
    assert ("OVERRUN: B overruns at activation 2: its clock B.clock ticks at 10 ms while "
            "activation 1 runs until 18 ms") in render_timeline(tl)


def test_a_starved_task_is_not_schedulable():
    # H (no clock, 1, priority 2) is released again as soon as it ends: it holds the
    # processor for ever; L (10 ms, priority 1) never runs: starved, overrun at 2.
    sk = Skeleton.from_dict({"tasks": {"H": {"duration": 1, "priority": 2},
                                       "L": {"duration": 1, "period": 10, "priority": 1}}})
    tl = simulate_timeline(sk)
    assert tl.overrun_at["L"] == 2 and tl.exit_status == 1
    assert all(i.task == "H" for i in tl.intervals)
    text = render_timeline(tl)
    assert ("STARVED: a job of L (released at 0 ms) never receives its duration on processor "
            "default") in text
    assert "1 starved task" in text.splitlines()[-1]


# ------------------------------------------------------------------ (5) processors

def test_two_processors_give_two_lanes(tmp_path):
    # A on p0, B on p1, each 3 of 4 ms: both run 0-3 in parallel; the regime is [0, 4).
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 3, "period": 4, "processor": "p0"},
                                       "B": {"duration": 3, "period": 4, "processor": "p1"}}})
    tl = simulate_timeline(sk)
    assert tl.processors == ["p0", "p1"]
    assert runs(tl, "p0") == [("A#1", "0", "3")] and runs(tl, "p1") == [("B#1", "0", "3")]
    lines = render_timeline(tl).splitlines()
    assert lines[1].startswith("p0      |AAA.|") and lines[2].startswith("p1      |BBB.|")
    if matplotlib_available():
        svg = draw_timeline(tl, tmp_path / "two.svg").read_text()
        assert "processor p0" in svg and "processor p1" in svg and "A#1" in svg


def test_a_longer_horizon_repeats_the_proven_regime():
    # Figure 17 again, drawn to 18 ms: three regimes of 6 ms; activation numbers go on
    # (OBS.JL +6, the chain +3, MOD.DYN +1 per regime).
    tl = simulate_timeline(load_skeleton(EXAMPLES / "computed_torque.yaml"), horizon=18)
    first = runs(tl)[:17]
    for m in (1, 2):
        shifted = [(t, str(F(a) - 6 * m), str(F(b) - 6 * m))
                   for t, a, b in runs(tl) if 6 * m <= F(a) < 6 * m + 6]
        per = {"OBS.JL": 6, "TG.JS": 3, "TF.TT.JS": 3, "CO.JS": 3, "MOD.DYN": 1}
        back = [(f"{t.split('#')[0]}#{int(t.split('#')[1]) - m * per[t.split('#')[0]]}", a, b)
                for t, a, b in shifted]
        assert back == first
    assert tl.schedulable is True


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(skeletons())
def test_the_drawing_past_the_proof_is_what_a_tick_by_tick_oracle_sees(data):
    # The oracle (written apart from the engine) gives each unit [t, t+1) of each
    # processor to a job; the timeline drawn to 3 regimes past each proof (the regime
    # repeated, activations renumbered) must give the same job to every unit.
    sk = Skeleton.from_dict(data)
    report = analyze_skeleton(sk)
    tl = simulate_timeline(sk)
    regimes = [r for r in tl.schedule.regimes if r["length"] is not None]
    end = max([int(r["start"] + 4 * r["length"]) for r in regimes] + [30])
    tl = simulate_timeline(sk, horizon=end)
    plat = platform_of(sk, report.groups)
    lazy = frozenset(p.name for p in plat.processors if not p.preemptive)
    units = oracle(sk, end, plat.priority, plat.processor_of, lazy)[0]
    for r in tl.schedule.regimes:
        if r["start"] is None:
            continue  # undecided: drawn only as far as simulated
        part = set(r["tasks"])
        mine = {(t, i.processor): (i.task, i.k) for i in tl.intervals if i.task in part
                for t in range(int(i.start), int(i.end))}
        assert mine == {key: v for key, v in units.items() if v[0] in part}


# ------------------------------------------------------------------ dead designs

@pytest.mark.parametrize("example", ["fig7a_circular_wait.yaml", "fig7b_wrong_order.yaml"])
def test_a_dead_design_reports_its_deadlock(example):
    # Figure 7a: nobody can read first, no job ever starts. Figure 7b: MT1 computes 0-2
    # and then waits for ever at its rendezvous (the circuits derived in the examples).
    sk = load_skeleton(EXAMPLES / example)
    tl = simulate_timeline(sk)
    assert [d.events for d in tl.deadlocks] == [d.events for d in analyze(sk).deadlocks]
    assert tl.dead_tasks == ["MT1", "MT2", "MT3"] and tl.exit_status == 1
    assert runs(tl) == ([] if example.startswith("fig7a") else [("MT1#1", "0", "2")])
    text = render_timeline(tl)
    assert "DEADLOCK: token-free circuit " + " -> ".join(
        [*tl.deadlocks[0].events, tl.deadlocks[0].events[0]]) in text
    assert text.rstrip().endswith(
        "DEADLOCK (1 token-free circuit; 3 tasks in groups that are not live) (exit status 1)")


def test_figure_12_overrun_in_every_command_alike():
    # fig12_double_sync.yaml, one CPU: MT1#1 0-1, MT2#1 1-3; MT2's activation 2 waits for
    # MT1's message of 10: MT1#2 10-11, MT2#2 11-13, after its tick 3 at 8: overrun at
    # activation 3, as analyze says (the example's derivation, §4).
    sk = load_skeleton(EXAMPLES / "fig12_double_sync.yaml")
    tl = simulate_timeline(sk)
    assert runs(tl) == [("MT1#1", "0", "1"), ("MT2#1", "1", "3"), ("MT1#2", "10", "11"),
                        ("MT2#2", "11", "13")]
    assert analyze(sk).tasks["MT2"].overrun_at == tl.overrun_at["MT2"] == 3
    assert ("OVERRUN: MT2 overruns at activation 3: its clock MT2.clock ticks at 8 ms while "
            "activation 2 computes until 13 ms") in render_timeline(tl)


# ------------------------------------------------------------------ refusals and drawing

def test_refusals():
    sk = Skeleton.from_dict({"unit": "us", "tasks": {"A": {"duration": 1, "period": 10}}})
    with pytest.raises(InputError, match=r"expected a time > 0, got -2.5 us") as info:
        simulate_timeline(sk, horizon="-2.5")
    assert info.value.where == "horizon"
    for bad in (0, -1, True, 1.5):
        with pytest.raises(InputError, match=r"expected an integer from 1 to 2\*\*63 - 1") as info:
            simulate_timeline(sk, max_events=bad)
        assert info.value.where == "max_events"


@pytest.mark.parametrize("value", ["0", "-3"])
def test_cli_refuses_a_budget_of_nothing_in_one_line(tmp_path, value):
    path = tmp_path / "a.yaml"
    path.write_text("tasks:\n  A: {duration: 1, period: 10}\n")
    out = CliRunner().invoke(app, ["timeline", str(path), "--max-events", value])
    assert out.exit_code == 2
    (line,) = out.output.strip().splitlines()
    assert line.startswith("tegraph: error: --max-events")
    assert "expected an integer from 1 to 2**63 - 1" in line


def test_drawing_or_how_to_install(tmp_path):
    tl = simulate_timeline(load_skeleton(EXAMPLES / "computed_torque.yaml"))
    out = tmp_path / "fig17.svg"
    if matplotlib_available():
        assert draw_timeline(tl, out) == out
        svg = out.read_text()
        assert svg.startswith("<?xml") and "<svg" in svg
        assert "processor default" in svg and "MOD.DYN#1" in svg
        for task in tl.tasks:
            assert task in svg
        again = tmp_path / "again.svg"
        draw_timeline(tl, again)
        assert again.read_bytes() == out.read_bytes()
        with pytest.raises(FileExistsError):
            draw_timeline(tl, out)
        png = draw_timeline(tl, tmp_path / "fig17.png")
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    else:
        with pytest.raises(PlotUnavailableError, match=INSTALL_HINT.replace("[", r"\[")):
            draw_timeline(tl, out)
        assert not out.exists()
    with pytest.raises(InputError, match="expected a file name ending in .svg or .png"):
        draw_timeline(tl, tmp_path / "fig17.pdf")


def test_without_matplotlib_the_message_says_how_to_install(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    assert matplotlib_available() is False
    tl = simulate_timeline(Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 2}}}))
    with pytest.raises(PlotUnavailableError) as info:
        draw_timeline(tl, tmp_path / "a.svg")
    assert "pip install '.[plot]'" in str(info.value)
    src = tmp_path / "a.yaml"
    src.write_text("tasks:\n  A: {duration: 1, period: 2}\n")
    result = CliRunner().invoke(app, ["timeline", str(src), "-o", str(tmp_path / "a.svg")])
    assert result.exit_code == 2
    assert "pip install '.[plot]'" in result.output
    assert not (tmp_path / "a.svg").exists()


def test_cli_timeline(tmp_path):
    ok = run("timeline", str(EXAMPLES / "computed_torque.yaml"))
    assert ok.returncode == 0, ok.stderr
    assert "order of execution (exact; T#k: activation k of T):" in ok.stdout
    bad = run("timeline", str(EXAMPLES / "fig12_double_sync.yaml"), "--horizon", "-1")
    assert bad.returncode == 2 and "--horizon: expected a time > 0" in bad.stderr
    out = tmp_path / "d.svg"
    drawn = run("timeline", str(EXAMPLES / "computed_torque.yaml"), "-o", str(out))
    if matplotlib_available():
        assert drawn.returncode == 0 and out.exists() and f"wrote {out}" in drawn.stderr
        assert drawn.stdout.splitlines()[-1].startswith("verdict: ")  # the last line
        exists = run("timeline", str(EXAMPLES / "computed_torque.yaml"), "-o", str(out))
        assert exists.returncode == 2 and "--force" in exists.stderr
    else:
        assert drawn.returncode == 2 and INSTALL_HINT in drawn.stderr and not out.exists()


def test_a_part_decided_by_the_critical_instant_draws_the_start_of_its_schedule():
    # The drifting sensors, independent: the theorem decides (hyperperiod ~10^9 ms);
    # the start is drawn from a quick look: four periods of the slowest clock
    # (4 * 1.019 = 4.076 ms), job 1 of each in priority order from the common release.
    sk = Skeleton.from_dict({"tasks": {f"S{i}": {"duration": "0.1", "period": f"{p}/1000"}
                                       for i, p in enumerate(DRIFT)}})
    tl = simulate_timeline(sk)
    assert tl.schedulable is True and tl.horizon == F("4.076")
    assert runs(tl)[:4] == [("S0#1", "0", "1/10"), ("S1#1", "1/10", "1/5"),
                            ("S2#1", "1/5", "3/10"), ("S3#1", "3/10", "2/5")]
    assert "only the start of the schedule is drawn" in render_timeline(tl)


def test_the_worst_data_path_of_figure_4_reversed_is_drawn_and_its_figures_printed():
    # Figure 4 with MT4 the most urgent (priorities 1, 2, 3, 4 declared): each period
    # 0-1 MT4, 1-3 MT3, 3-5 MT2, 5-6 MT1. The largest first use (26 ms, spec §4c's
    # example) is the sample MT1 takes at 5, written at 6, read by MT2 at 13 (its second
    # job's start), written at 15, read by MT3 at 21, written at 23, read by MT4 at 30,
    # posted at 31. The drawing runs on to 40, the end of the period holding the path.
    data = load_skeleton(EXAMPLES / "fig4_pipeline_unsynchronized.yaml").to_dict()
    for p, task in enumerate(["MT1", "MT2", "MT3", "MT4"], 1):
        data["tasks"][task]["priority"] = p
    tl = simulate_timeline(Skeleton.from_dict(data), chains=[["MT1", "MT2", "MT3", "MT4"]])
    (c,) = tl.chains
    assert (c.figures.first_use, c.figures.reaction) == (26, 36)
    assert [(s.task, s.k, s.at) for s in c.figures.worst] == [
        ("MT1", 1, 5), ("MT1", 1, 6), ("MT2", 2, 13), ("MT2", 2, 15), ("MT3", 3, 21),
        ("MT3", 3, 23), ("MT4", 4, 30), ("MT4", 4, 31)]
    assert tl.horizon == 40 and tl.schedulable is True
    text = render_timeline(tl)
    row = next(line for line in text.splitlines() if line.startswith("chain 1  "))
    assert row.split("|")[1] == "     sw      r w     r w      ro        "
    assert ("chain 1, MT1 -> MT2 -> MT3 -> MT4, on its processors: first use 26 ms, age 26 ms "
            "(min 26 ms), reaction 36 ms") in text
    assert "MT4#4 posts at 31 ms (MT4.write:u)" in text


def test_timeline_takes_chains_on_the_command_line():
    out = CliRunner().invoke(app, ["timeline", str(EXAMPLES / "fig4_pipeline_unsynchronized.yaml"),
                                   "--chain", "MT1,MT2,MT3,MT4"])
    assert out.exit_code == 0, out.output
    # Rate-monotonic in file order: 0-1, 1-3, 3-5, 5-6; first use 6, reaction 16.
    assert "first use 6 ms, age 6 ms (min 6 ms), reaction 16 ms" in out.output
