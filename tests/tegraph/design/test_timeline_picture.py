"""The timing diagram as a reader sees it: its default window, its colours, what the jobs
wait for, a deadlock, and the marks at the edges.

Each expected value is derived by hand in a comment (spec §3-§4b). What is drawn is read
from the matplotlib Figure's artists and legend, not from pixels.
"""

from __future__ import annotations

from fractions import Fraction as F

import pytest
from hypothesis import HealthCheck, assume, given, settings
from typer.testing import CliRunner

from tegraph import Skeleton, analyze
from tegraph.cli import app
from tegraph.design.timeline import simulate_timeline
from tegraph.design.timeline_waits import replay_daters
from tegraph.io import load_skeleton
from tegraph.model.build import build_teg, task_chain
from tegraph.report.plot import _LATE, matplotlib_available, timeline_figure
from tests.paths import REPO
from tests.tegraph.analysis.test_analysis_properties import skeleton_data

EXAMPLES = REPO / "examples"
needs_matplotlib = pytest.mark.skipif(not matplotlib_available(), reason="matplotlib")

# A fast loop beside a slow task: A (1/4 every 1 ms, the more urgent) and B (5 every
# 50 ms). B's job runs in A's idle time, 3/4 of each ms: 5 / (3/4) = 6.67 ms, done long
# before 50; at 50 the state of 0 repeats: the proof is the regime [0, 50).
FAST_AND_SLOW = {"tasks": {"A": {"duration": "1/4", "period": 1},
                           "B": {"duration": 5, "period": 50}}}

# A (1/2 every 1 ms) leaves B (21 every 40 ms) half of each ms: B's job 1 needs 42 ms and
# ends at 42 > its tick 2 at 40, so B overruns at activation 2, at 40 ms.
LATE = {"tasks": {"A": {"duration": "1/2", "period": 1}, "B": {"duration": 21, "period": 40}}}


def _legend(fig) -> list[str]:
    return [t.get_text() for t in fig.legends[0].get_texts()]


# ------------------------------------------------------------------ the default window

def test_the_default_window_is_ten_periods_of_the_fastest_clock():
    # before: the whole proof, 0-50 ms (50 periods of A in the same width)
    tl = simulate_timeline(Skeleton.from_dict(FAST_AND_SLOW))
    assert (tl.start, tl.horizon) == (0, 10)  # 10 x 1 ms, from the regime's start at 0
    assert "10 periods of A.clock (1 ms), the fastest clock" in tl.window
    assert "the proof runs to 50 ms: `horizon` 50 draws all of it" in tl.window
    assert tl.notes[0] == tl.window  # the text report prints it
    whole = simulate_timeline(Skeleton.from_dict(FAST_AND_SLOW), 50)
    assert (whole.start, whole.horizon, whole.window) == (0, 50, None)


def test_the_window_ends_two_periods_past_the_first_overrun():
    # The overrun's tick is at 40; two periods of A (the fastest, 1 ms) past it: 42; ten
    # periods back from there: 32, a tick of A. B's late job 1 ends at 42, in the window.
    tl = simulate_timeline(Skeleton.from_dict(LATE))
    assert tl.overrun_at["B"] == 2 and tl.overrun_ticks["B"] == 40
    assert (tl.start, tl.horizon) == (32, 42)
    assert "past the first overrun (B at 40 ms)" in tl.window
    assert [j.index for j in tl.late_jobs] == [1] and tl.late_jobs[0].finish == 42
    # the lanes start at the window: A's job 33 (released at tick 33, at 32 ms) comes first
    assert tl.visible[0].task == "A" and tl.visible[0].k == 33 and tl.visible[0].start == 32


def test_the_whole_proof_is_drawn_when_it_fits():
    # B alone, 2 every 4: the regime is [0, 4) (B's job ends at 2, the state repeats at 4),
    # within 10 periods: drawn whole, from 0, no window note.
    tl = simulate_timeline(Skeleton.from_dict({"tasks": {"B": {"duration": 2, "period": 4}}}))
    assert (tl.start, tl.horizon, tl.window) == (0, 4, None)


def test_a_window_asked_for_on_the_command_line(tmp_path):
    path = tmp_path / "late.yaml"
    path.write_text("tasks:\n  A: {duration: 0.5, period: 1}\n  B: {duration: 21, period: 40}\n")
    out = CliRunner().invoke(app, ["timeline", str(path), "--horizon", "36..40"])
    assert out.exit_code == 1, out.output
    assert out.output.startswith("timeline late on its processors: 36 to 40 ms")
    # the note says how to see more, with the option's own name
    default = CliRunner().invoke(app, ["timeline", str(path)]).output
    assert "--horizon 42 draws all of it, --horizon A..B any window" in default
    for bad in ("40..36", "-1..3", "3..x"):
        refused = CliRunner().invoke(app, ["timeline", str(path), "--horizon", bad])
        assert refused.exit_code == 2
        (line,) = refused.output.strip().splitlines()
        assert line.startswith("tegraph: error: --horizon: expected a time > 0")


# ------------------------------------------------------------------ colours

@needs_matplotlib
def test_no_task_is_painted_in_the_overrun_red():
    # 20 tasks: before, the 7th took tab20's red (#d62728, the late activation's colour)
    # and the 8th its light red.
    from matplotlib.colors import to_hex

    sk = Skeleton.from_dict({"tasks": {f"T{i:02}": {"duration": "1/100", "period": 10}
                                       for i in range(20)}})
    fig = timeline_figure(simulate_timeline(sk))
    bars = [to_hex(c) for coll in fig.axes[0].collections for c in coll.get_facecolors()]
    assert bars and _LATE not in bars and "#ff9896" not in bars
    assert not {"#7f7f7f", "#c7c7c7"} & set(bars)  # nor the greys of waits and regimes


# ------------------------------------------------------------------ waiting

def test_a_read_that_waits_for_its_writer():
    # Figure 12: MT2 (clock 4, duration 2) reads MT1:x ASYN/SYN; MT1 (rtc 10, duration 1)
    # writes at 1, then at 11. MT2's activation 1 is due at 0 and released at 1; its
    # activation 2 is due at its tick 4 (activation 1 ended at 3) and released at 11.
    tl = simulate_timeline(load_skeleton(EXAMPLES / "fig12_double_sync.yaml"))
    waits = [(w.task, w.k, w.start, w.end, w.kind) for w in tl.waits]
    assert ("MT2", 1, 0, 1, "start") in waits and ("MT2", 2, 4, 11, "start") in waits
    assert not [w for w in tl.waits if w.task == "MT1"]  # its reads are its sensors'


def test_a_rendezvous_writer_waits_to_end():
    # P (clock 5, duration 1) and Q (clock 5, phase 2.5) meet at P.write:x = Q.read:x:
    # P's job ends at 1, the rendezvous fires when Q is activated, at 2.5: P waits [1, 2.5).
    tl = simulate_timeline(load_skeleton(EXAMPLES / "rendezvous_two_clocks.yaml"))
    assert [(w.task, w.k, w.start, w.end, w.kind) for w in tl.waits] == [
        ("P", 1, 1, F(5, 2), "end")]


@needs_matplotlib
def test_waits_are_drawn_and_keyed():
    fig = timeline_figure(simulate_timeline(load_skeleton(EXAMPLES / "rendezvous_two_clocks.yaml")))
    assert "done, waits to end (a write for its reader)" in _legend(fig)
    assert "P waits" in [t.get_text() for t in fig.axes[0].get_yticklabels()]


# ------------------------------------------------------------------ a deadlock

# W (clock 10, duration 2) writes x that B reads SYN/ASYN (the write waits for the read);
# B and C wait for each other (B reads c from C, C reads b from B, ASYN/SYN): a token-free
# circuit. W's job 1 runs 0-2, then W.write:x waits for B.read:x for ever; B is stuck at
# its first read, B.read:c, and C at C.read:b, from 0.
DEAD = {"tasks": {"W": {"duration": 2, "period": 10, "outputs": ["x"]},
                  "B": {"duration": 1, "inputs": ["c", "x"], "outputs": ["b"]},
                  "C": {"duration": 1, "inputs": ["b"], "outputs": ["c"]}},
        "links": [{"from": "W:x", "to": "B:x", "protocol": "SYN/ASYN"},
                  {"from": "B:b", "to": "C:b", "protocol": "ASYN/SYN"},
                  {"from": "C:c", "to": "B:c", "protocol": "ASYN/SYN"}]}


def test_a_deadlock_says_which_events_are_stuck_and_from_when():
    tl = simulate_timeline(Skeleton.from_dict(DEAD))
    assert [(s.task, s.event, s.since) for s in tl.stuck] == [
        ("W", "W.write:x", 2), ("B", "B.read:c", 0), ("C", "C.read:b", 0)]


@needs_matplotlib
@pytest.mark.parametrize("data", [DEAD, "fig7a_circular_wait.yaml"])
def test_a_dead_picture_draws_the_deadlock_and_no_regime(data):
    # before: fig7a's picture was empty, and its legend listed "proven regime", "late
    # activation" and "overrun tick", none of which it drew
    sk = load_skeleton(EXAMPLES / data) if isinstance(data, str) else Skeleton.from_dict(data)
    fig = timeline_figure(simulate_timeline(sk))
    legend = _legend(fig)
    assert "stuck for ever (a deadlock)" in legend
    assert not {"proven regime", "late activation", "overrun tick"} & set(legend)
    texts = [t.get_text() for t in fig.axes[0].texts]
    assert any(t.startswith("stuck at ") for t in texts)
    assert "(deadlock)" in fig.axes[0].get_title()


# ------------------------------------------------------------------ the frame

@needs_matplotlib
def test_the_overrun_tick_at_the_end_of_the_drawing_is_inside_the_frame():
    # The SYN/SYN pair of test_timeline: A overruns at its tick 5, at 16; drawn to 16,
    # the red tick sits on the frame's edge: before, the axis ended at 16 and cut it.
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 4, "outputs": ["x"]},
                                       "B": {"duration": 1, "period": 6, "inputs": ["x"]}},
                             "links": [{"from": "A:x", "to": "B:x", "protocol": "SYN/SYN"}]})
    fig = timeline_figure(simulate_timeline(sk, 16))
    ax = fig.axes[0]
    left, right = ax.get_xlim()
    assert left < 0 and right > 16
    red = [line for line in ax.lines if line.get_color() == _LATE]
    assert [list(line.get_xdata()) for line in red if len(line.get_xdata())] == [[16.0]]
    assert all(not line.get_clip_on() for line in red)


# ------------------------------------------------------------------ the daters replayed

@settings(max_examples=40, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(skeleton_data(threads=False))  # a thread is one processor's
def test_the_replayed_daters_are_section_3_with_a_processor_per_task(data):
    # With every task alone on its processor, f_T(k) = x_T.compute(k) + duration(T) and
    # §4b is §3 (docs/skeleton.md §4b): the daters replayed from the drawn jobs' ends must
    # be the §3 daters of TimedEventGraph.simulate, a different algorithm (vectorized by
    # firing index), firing for firing.
    for name, spec in data["tasks"].items():
        spec["processor"] = f"P_{name}"
    sk = Skeleton.from_dict(data, name="random")
    assume(analyze(sk, design=False).live)
    horizon = F(30)
    tl = simulate_timeline(sk, horizon)
    teg = build_teg(sk)
    zero = [t for t, f in tl.schedule.tasks.items() if f.period == 0]
    skip = frozenset(e for t in zero for e in task_chain(teg, t))
    finish = {}
    for job in tl.jobs:
        if job.finish is not None:
            finish.setdefault(job.task, {})[job.index] = job.finish
    x, cut = replay_daters(teg, finish, tl.durations, horizon, skip)
    assert not cut
    n = max((len(v) for v in x), default=0)
    reference = teg.simulate(n)
    names = teg.transition_names
    for e, times in enumerate(x):
        if e not in skip:
            assert times == list(reference[names[e]][:len(times)]), names[e]
    for name, c in sk.clocks.items():  # a clock never waits: each tick up to the horizon
        if f"{name}.tick" in names:
            expected = [c.phase + j * c.period for j in range(int((horizon - c.phase) / c.period)
                                                                 + 1)] if c.phase <= horizon else []
            assert x[names.index(f"{name}.tick")] == expected
