"""The exact preemptive fixed-priority timeline, its text rendering and its drawing.

The computed-torque timeline is compared with the order of execution that
section 6 of the ORCCAD paper describes for Figure 17 (times from the
durations in examples/computed_torque.yaml); other expectations are the
daters derived by hand in the examples' comments, or hand schedules.
"""

from __future__ import annotations

import subprocess
import sys
from fractions import Fraction as F

import pytest
from typer.testing import CliRunner

from tegraph import analyze, load_skeleton
from tegraph.cli import app
from tegraph.design.timeline import simulate_timeline
from tegraph.errors import InputError, ModelError
from tegraph.model.skeleton import Skeleton
from tegraph.report.plot import (
    INSTALL_HINT,
    PlotUnavailableError,
    draw_timeline,
    matplotlib_available,
)
from tegraph.report.timeline_text import render_timeline
from tests.paths import REPO

EXAMPLES = REPO / "examples"


def order(timeline, processor=None) -> list[tuple[str, F, F]]:
    return timeline.order_of_execution(processor)


def test_computed_torque_follows_figure_17():
    # Section 6: OBS.JL (high) runs at the first tick, then TG.JS, TF.TT.JS, CO.JS
    # (medium) in sequence, then MOD.DYN (low), "temporarily suspended by the next
    # execution of the higher priority OBS.JL" at 1, finishing in the second basic cycle.
    # Durations 0.1, 0.1, 0.2, 0.3, 1.2; clocks 1, 2, 6 ms.
    tl = simulate_timeline(load_skeleton(EXAMPLES / "computed_torque.yaml"))
    d = F(1, 10)

    def chain(t0):
        return [("TG.JS", t0 + d, t0 + 2 * d), ("TF.TT.JS", t0 + 2 * d, t0 + 4 * d),
                ("CO.JS", t0 + 4 * d, t0 + 7 * d)]

    assert order(tl) == [
        ("OBS.JL", 0, d), *chain(0), ("MOD.DYN", 7 * d, 1), ("OBS.JL", 1, 1 + d),
        ("MOD.DYN", 1 + d, 2), ("OBS.JL", 2, 2 + d), *chain(2), ("OBS.JL", 3, 3 + d),
        ("OBS.JL", 4, 4 + d), *chain(4), ("OBS.JL", 5, 5 + d)]
    assert tl.horizon == 6 and tl.late_jobs == []
    (mod,) = [j for j in tl.jobs if j.task == "MOD.DYN"]
    assert (mod.release, mod.finish, mod.preemptions, mod.deadline) == (0, 2, 1, 6)
    assert tl.ticks["obs"] == [0, 1, 2, 3, 4, 5] and tl.ticks["dyn"] == [0]
    assert tl.tasks == ["OBS.JL", "TG.JS", "TF.TT.JS", "CO.JS", "MOD.DYN"]


def test_reversed_pipeline_of_figure_4():
    # Figure 4 (bottom): the same four 10 ms tasks with the last stage most urgent run
    # in reverse: MT4 0-1, MT3 1-3, MT2 3-5, MT1 5-6.
    data = load_skeleton(EXAMPLES / "fig4_pipeline_unsynchronized.yaml").to_dict()
    for i, name in enumerate(["MT1", "MT2", "MT3", "MT4"]):
        data["tasks"][name]["priority"] = i + 1
    tl = simulate_timeline(Skeleton.from_dict(data))
    assert order(tl) == [("MT4", 0, 1), ("MT3", 1, 3), ("MT2", 3, 5), ("MT1", 5, 6)]
    # Synchronized (examples/fig4_pipeline_synchronized.yaml): the data order.
    tl = simulate_timeline(load_skeleton(EXAMPLES / "fig4_pipeline_synchronized.yaml"))
    assert order(tl) == [("MT1", 0, 1), ("MT2", 1, 3), ("MT3", 3, 5), ("MT4", 5, 6)]


def test_overrun_of_figure_12_matches_the_analysis():
    # MT2 (clock 4) waits for MT1's message (every 10): activation 2, released at 4,
    # reads y at 11 and ends (writes u) at 13 > tick 3 at 8. Spec §4 (v1.1): MT2 has an
    # output, so end(k) = x_write:u(k) = 3, 13, 23 and the ticks are 0, 4, 8, 12:
    # k = 2: 3 > 4 no; k = 3: 13 > 8 yes => overrun_at = 3 (the example file's derivation).
    # The timeline used to say "activation 2 ends at 13 ms, after the next tick at 8 ms",
    # the late job's number: one fact, two numberings. The one numbering is the spec's:
    # MT2 overruns at activation 3, tick 3 finding activation 2 unfinished.
    sk = load_skeleton(EXAMPLES / "fig12_double_sync.yaml")
    tl = simulate_timeline(sk)
    late = [(j.task, j.index, j.finish, j.deadline, j.overrun_at) for j in tl.late_jobs]
    assert late[0] == ("MT2", 2, 13, 8, 3)
    assert analyze(sk).tasks["MT2"].overrun_at == tl.overrun_at["MT2"] == 3
    assert tl.overrun_at["MT1"] is None
    assert ("OVERRUN: MT2 overruns at activation 3: its clock MT2.clock ticks at 8 ms while "
            "activation 2 runs until 13 ms") in render_timeline(tl)


@pytest.mark.parametrize("example", ["fig7a_circular_wait.yaml", "fig7b_wrong_order.yaml"])
def test_a_dead_design_reports_its_deadlock(example):
    # Figure 7a: nobody can read first, no job ever starts. Figure 7b: MT1 computes 0-2 and
    # then waits for ever at its rendezvous with MT2, which waits for MT3, which waits for
    # MT1's second write (the circuits derived by hand in the examples). The diagram used
    # to say "every job ends by the next tick of its clock" and exit 0.
    sk = load_skeleton(EXAMPLES / example)
    tl = simulate_timeline(sk)
    assert [d.events for d in tl.deadlocks] == [d.events for d in analyze(sk).deadlocks]
    assert tl.dead_tasks == ["MT1", "MT2", "MT3"] and tl.late_jobs == [] and tl.exit_status == 1
    ran = [(t, a, b) for t, a, b in order(tl)]
    assert ran == ([] if example.startswith("fig7a") else [("MT1", 0, 2)])
    text = render_timeline(tl)
    assert "DEADLOCK: token-free circuit " + " -> ".join(
        [*tl.deadlocks[0].events, tl.deadlocks[0].events[0]]) in text
    assert "every job ends" not in text and text.rstrip().endswith(
        "verdict: DEADLOCK (1 token-free circuit; 3 tasks in groups that are not live) "
        "(exit status 1)")
    out = run("timeline", str(EXAMPLES / example))
    assert out.returncode == 1 and "DEADLOCK" in out.stdout


def test_overrun_in_step_on_one_processor():
    # MT1 0-6 posts y; MT2 (same priority, later in the file) reads it at 6, runs 6-12,
    # past its next tick at 10 (spec example: overrun_at(MT2) = 2).
    tl = simulate_timeline(load_skeleton(EXAMPLES / "overrun_in_step.yaml"), horizon=10)
    assert order(tl) == [("MT1", 0, 6), ("MT2", 6, 10)]
    (late,) = tl.late_jobs
    assert (late.task, late.index, late.finish, late.deadline) == ("MT2", 1, None, 10)


def test_rendezvous_waits_for_the_partner():
    # Example daters: P computes 0-1 then waits at the rendezvous until Q's tick at 5/2;
    # Q computes 5/2-9/2; P's second activation at 5 computes 5-6.
    tl = simulate_timeline(load_skeleton(EXAMPLES / "rendezvous_two_clocks.yaml"))
    assert order(tl) == [("P", 0, 1), ("Q", F(5, 2), F(9, 2)), ("P", 5, 6)]
    p1 = next(j for j in tl.jobs if j.task == "P")
    assert (p1.release, p1.finish) == (0, F(5, 2))


def test_thread_runs_its_tasks_in_turn():
    # threads.yaml group 0 (clock 2): TG.JS 0-3/10, TF.TT.JS 3/10-7/10, CO.JS 7/10-6/5
    # (the example's daters); [LOG, DIAG] free-running below them: LOG 6/5-23/15,
    # DIAG from 23/15 (still running at the horizon 2).
    tl = simulate_timeline(load_skeleton(EXAMPLES / "threads.yaml"))
    assert order(tl) == [("TG.JS", 0, F(3, 10)), ("TF.TT.JS", F(3, 10), F(7, 10)),
                         ("CO.JS", F(7, 10), F(6, 5)), ("LOG", F(6, 5), F(23, 15)),
                         ("DIAG", F(23, 15), 2)]


def test_syn_asyn_writer_waits_for_the_request():
    # W (priority 2, clock 10) computes 0-1 then must post x SYN/ASYN: it waits for R's
    # request; R (priority 1, clock 10, phase 3) reads at 3 (request), so W posts at 3
    # and ends; R computes 3-5. Horizon: largest phase 3 + hyperperiod 10 = 13, so W's
    # second activation (10-11) is in it, waiting at the end for R's request at 13.
    sk = Skeleton.from_dict({
        "clocks": {"cw": {"period": 10}, "cr": {"period": 10, "phase": 3}},
        "tasks": {"W": {"duration": 1, "clock": "cw", "outputs": ["x"], "priority": 2},
                  "R": {"duration": 2, "clock": "cr", "inputs": ["x"], "priority": 1}},
        "links": [{"from": "W:x", "to": "R:x", "protocol": "SYN/ASYN"}]})
    tl = simulate_timeline(sk)
    assert tl.horizon == 13
    assert order(tl) == [("W", 0, 1), ("R", 3, 5), ("W", 10, 11)]
    assert [(j.task, j.index, j.finish) for j in tl.jobs] == [
        ("W", 1, 3), ("R", 1, 5), ("W", 2, None)]


def test_processors_run_in_parallel():
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 3, "period": 4, "processor": "p0"},
                                       "B": {"duration": 3, "period": 4, "processor": "p1"}}})
    tl = simulate_timeline(sk)
    assert order(tl, "p0") == [("A", 0, 3)] and order(tl, "p1") == [("B", 0, 3)]
    assert "processor p1:" in render_timeline(tl)


def test_text_rendering_is_exact():
    tl = simulate_timeline(load_skeleton(EXAMPLES / "computed_torque.yaml"))
    text = render_timeline(tl)
    lines = text.splitlines()
    # 60 columns of 1/10 ms: OBS.JL computes in columns 0, 10, 20, 30, 40, 50.
    assert lines[0] == "timeline computed-torque: 0 to 6 ms, one column = 0.1 ms"  # as a decimal
    obs = lines[1].split("|")[1]
    assert len(obs) == 60 and [i for i, c in enumerate(obs) if c == "#"] == [0, 10, 20, 30, 40, 50]
    mod = lines[5].split("|")[1]
    assert mod[:20] == "-------###-#########"
    assert lines[6].split("|")[1].count("^") == 6  # clock obs
    assert "     1.1 - 2        MOD.DYN" in text  # 11/10 ms, as the file writes it
    assert text.endswith("verdict: every job ends by the next tick of its pacing clock "
                         "(simulated up to 6 ms) (exit status 0)\n")


def test_long_horizons_are_drawn_approximately():
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": "1/7", "period": 1}}})
    text = render_timeline(simulate_timeline(sk, horizon=50), width=40)
    assert "(approximate drawing)" in text.splitlines()[0]


def test_refusals():
    sk = Skeleton.from_dict({"tasks": {"Z": {"duration": 0}}})
    with pytest.raises(ModelError, match="without time passing"):
        simulate_timeline(sk)
    with pytest.raises(ModelError, match="horizon must be > 0"):
        simulate_timeline(Skeleton.from_dict({"tasks": {"A": {"duration": 1}}}), horizon=0)


# ------------------------------------------------------------------ drawing

def test_drawing_or_how_to_install(tmp_path):
    tl = simulate_timeline(load_skeleton(EXAMPLES / "computed_torque.yaml"))
    out = tmp_path / "fig17.svg"
    if matplotlib_available():
        assert draw_timeline(tl, out) == out
        svg = out.read_text()
        assert svg.startswith("<?xml") and "<svg" in svg
        for task in tl.tasks:
            assert task in svg
        # Same timeline, same bytes; an existing file is never replaced silently.
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
    # Whatever is installed here: a None entry makes `import matplotlib` fail.
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    assert matplotlib_available() is False
    tl = simulate_timeline(Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 2}}}))
    with pytest.raises(PlotUnavailableError) as info:
        draw_timeline(tl, tmp_path / "a.svg")
    assert "pip install 'tegraph[plot]'" in str(info.value)
    src = tmp_path / "a.yaml"
    src.write_text("tasks:\n  A: {duration: 1, period: 2}\n")
    result = CliRunner().invoke(app, ["timeline", str(src), "-o", str(tmp_path / "a.svg")])
    assert result.exit_code == 2
    assert "pip install 'tegraph[plot]'" in result.output
    assert not (tmp_path / "a.svg").exists()


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "tegraph.cli", *args], check=False,
                          capture_output=True,
                          text=True, timeout=120)


def test_cli_timeline(tmp_path):
    ok = run("timeline", str(EXAMPLES / "computed_torque.yaml"))
    assert ok.returncode == 0, ok.stderr
    assert "order of execution (exact):" in ok.stdout
    late = run("timeline", str(EXAMPLES / "fig12_double_sync.yaml"), "--horizon", "14")
    assert late.returncode == 1 and "MT2 overruns at activation 3" in late.stdout
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


def test_text_diagram_explains_its_symbols():
    # Figure 12: MT2's late activation is drawn X; every symbol drawn is in the legend.
    from tegraph.report.timeline_text import render_timeline

    text = render_timeline(simulate_timeline(load_skeleton(EXAMPLES / "fig12_double_sync.yaml")))
    rows = text.splitlines()[1:5]
    legend = next(line for line in text.splitlines() if line.startswith("legend: "))
    drawn = {ch for row in rows for ch in row.split("|")[1]} - {" "}
    assert drawn == {"#", "-", "X", "^"}
    assert all(f"{ch} " in legend for ch in drawn)


def test_verdict_names_a_few_late_tasks_and_counts_the_rest():
    # A chain T0 -> ... -> T7 read ASYN/SYN; T0 on a 10 ms clock, each other task also
    # on its own 7 ms clock: T1..T7 are bound to two rates, so all 7 run late (Figure 12).
    n = 8
    tasks = {f"T{i}": {"duration": 1, "period": 7 if i else 10,
                       "inputs": ["i"] if i else [], "outputs": ["o"] if i < n - 1 else []}
             for i in range(n)}
    links = [{"from": f"T{i}:o", "to": f"T{i + 1}:i", "protocol": "ASYN/SYN"}
             for i in range(n - 1)]
    from tegraph import Skeleton
    from tegraph.report.timeline_text import render_timeline

    tl = simulate_timeline(Skeleton.from_dict({"tasks": tasks, "links": links}))
    late = list(dict.fromkeys(j.task for j in tl.late_jobs))
    assert sorted(late) == [f"T{i}" for i in range(1, n)]
    verdict = render_timeline(tl).splitlines()[-1]
    assert verdict.startswith(f"verdict: {len(tl.late_jobs)} overruns before ")
    assert verdict.endswith(f"by {', '.join(late[:5])} and 2 more (exit status 1)")


def test_overrun_at_is_an_attribute_as_in_the_analysis_report():
    # Issue 21: Timeline.overrun_at was a method where Report.tasks[T].overrun_at is an
    # attribute. Duration 11 on a clock of 10: activation 1 runs 0-11, tick 2 comes at 10
    # while it runs, so the overrun is at activation 2 (spec §4); B (2 on 10) never overruns.
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 11, "period": 10},
                                       "B": {"duration": 2, "period": 10, "processor": "p2"}}})
    tl = simulate_timeline(sk, horizon=30)
    assert tl.overrun_at == {"A": 2, "B": None}
    assert tl.overrun_at["A"] == analyze(sk).tasks["A"].overrun_at == 2
    with pytest.warns(DeprecationWarning, match=r"overrun_at\[task\]"):
        assert tl.overrun_at("A") == 2  # the 0.x call still answers


def _writer_feeding(duration):
    # A clockless writer of the given duration runs freely; the clocked reader (period 1)
    # waits ASYN/SYN for its messages: up to 1/duration + 1 writer jobs in the hyperperiod 1.
    return Skeleton.from_dict({
        "tasks": {"W": {"duration": duration, "outputs": ["m"]},
                  "R": {"duration": 1, "period": 1, "inputs": ["m"]}},
        "links": [{"from": "W:m", "to": "R:m", "protocol": "ASYN/SYN"}]})


def _refused_at_once(call):
    """``call()`` raises InputError within 10 s (it used to run for ever: a hang is a failure)."""
    import signal
    import time

    def too_long(*_):
        raise AssertionError("still simulating after 10 s")

    old = signal.signal(signal.SIGALRM, too_long)
    signal.alarm(10)
    start = time.monotonic()
    try:
        with pytest.raises(InputError) as info:
            call()
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
    assert time.monotonic() - start < 5
    return info.value


@pytest.mark.parametrize("duration", ["1e-400", "1/" + "9" * 4000])
def test_a_tiny_duration_is_refused_before_simulating(duration):
    # Issue 21 (items 5 and 7): both ran past 60 s. Hyperperiod 1 ms; W may run
    # 1/duration + 1 > 10^399 jobs, R one per tick (1): far past the default max_jobs.
    err = _refused_at_once(lambda: simulate_timeline(_writer_feeding(duration)))
    assert err.where == "max_jobs"
    assert "hyperperiod 1 ms" in err.reason and "`horizon`" in err.reason
    assert "W more than 10^399" in err.reason


def test_a_long_hyperperiod_is_refused_naming_it():
    # 999983 and 999979 are primes: hyperperiod = their product 999962000357 ms, with
    # 999979 ticks of A and 999983 of B before it: 1,999,962 jobs > 100,000.
    from tegraph.design.timeline import MAX_JOBS

    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 999983},
                                       "B": {"duration": 1, "period": 999979}}})
    err = _refused_at_once(lambda: simulate_timeline(sk))
    assert 999983 * 999979 == 999962000357
    assert "hyperperiod 999962000357 ms" in err.reason and "1,999,962 jobs" in err.reason
    assert f"`max_jobs` = {MAX_JOBS:,}" in err.reason
    with pytest.raises(InputError, match="expected an integer >= 1"):
        simulate_timeline(sk, max_jobs=0)
    # A horizon that cuts the simulation: it runs, and the verdict says up to when.
    tl = simulate_timeline(sk, horizon=2_000_000)
    # Ticks before 2000000: A at 0, 999983, 1999966; B at 0, 999979, 1999958.
    assert tl.full_horizon == 999962000357 and len(tl.jobs) == 6
    assert ("up to 2000000 ms only (the horizon cut the simulation; the default horizon is "
            "999962000357 ms: a later overrun is not excluded)") in render_timeline(tl)
    assert simulate_timeline(sk, horizon=2_000_000, max_jobs=6).full_horizon is not None
    with pytest.raises(InputError, match="may take 6 jobs"):
        simulate_timeline(sk, horizon=2_000_000, max_jobs=5)


def test_cli_refuses_a_long_simulation_naming_its_options(tmp_path):
    from tegraph.design.timeline import MAX_JOBS

    f = tmp_path / "p.yaml"
    f.write_text("tasks:\n  A: {duration: 1, period: 999983}\n  B: {duration: 1, period: 999979}\n")
    res = CliRunner().invoke(app, ["timeline", str(f)])
    assert res.exit_code == 2, res.output
    assert res.output.startswith("tegraph: error: --max-jobs: simulating up to 999962000357 ms")
    assert "give a shorter --horizon, or raise --max-jobs" in res.output
    assert "Traceback" not in res.output
    # The option's default is the library's constant.
    assert f"more than --max-jobs = {MAX_JOBS:,}" in res.output
    res = CliRunner().invoke(app, ["timeline", str(f), "--max-jobs", "1", "--horizon", "1"])
    assert res.exit_code == 2 and "may take 2 jobs" in res.output  # one tick each at 0


def test_a_refusal_states_the_hyperperiod_as_the_input_wrote_its_periods():
    # Periods 2.5 and 1.5 ms: hyperperiod lcm = 7.5 ms (3 x 2.5 = 5 x 1.5), so up
    # to 7.5 ms A has 3 jobs and B 5: 8 jobs, over a budget of 2. The input wrote
    # decimals: the message says 7.5 ms, not 15/2 ms.
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": "0.1", "period": "2.5"},
                                       "B": {"duration": "0.1", "period": "1.5"}}})
    with pytest.raises(InputError) as refused:
        simulate_timeline(sk, max_jobs=2)
    assert "hyperperiod 7.5 ms" in str(refused.value) and "8 jobs (B 5, A 3)" in str(refused.value)
    assert "15/2" not in str(refused.value)


@pytest.mark.parametrize("duration, characters", [
    # No clock: the horizon is 2 * (1 + duration). 2 + 2e-400 = (10^400 + 1)/(5 * 10^399):
    # 401 + 1 + 400 = 802 characters; 2 + 2/(10^4000 - 1) = 2 * 10^4000/(10^4000 - 1):
    # 4001 + 1 + 4000 = 8002 characters. Both terminate or not, but past 30 digits: fractions.
    ("1e-400", 802), ("1/" + "9" * 4000, 8002)])
def test_a_refusal_shortens_a_horizon_too_long_to_read(tmp_path, duration, characters):
    # Issue 21 review: the message printed the ~800-digit horizon (8.3 KB for 4000 nines).
    f = tmp_path / "w.yaml"
    f.write_text(f'tasks:\n  W: {{duration: "{duration}", outputs: [x]}}\n'
                 '  R: {duration: 1, inputs: [x]}\n'
                 'links:\n  - {from: "W:x", to: "R:x", protocol: ASYN/SYN}\n')
    res = CliRunner().invoke(app, ["timeline", str(f)])
    assert res.exit_code == 2 and "Traceback" not in res.output
    assert f"... ({characters} characters) ms (no clock" in res.output
    assert len(res.output) < 500, len(res.output)


def test_a_short_horizon_is_refused_with_its_unit():
    sk = Skeleton.from_dict({"unit": "us", "tasks": {"A": {"duration": 1, "period": 10}}})
    with pytest.raises(ModelError, match=r"the horizon must be > 0, got -2.5 us"):
        simulate_timeline(sk, horizon="-2.5")
