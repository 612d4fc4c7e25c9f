"""Sensitivity on one CPU decided level by level: each group one periodic unit of its
summed work (docs/sensitivity.md, "One periodic unit per group"), a task without clock
in the idle time. Expected values by hand in the comments, and by other algorithms:
the exact schedule of the skeleton at the point (``schedule_on_processors``), the
walk on affine times with the theorem switched off, and the critical scaling factor
of single tasks (``scaling.critical_scaling_factor``)."""

from __future__ import annotations

import json
from fractions import Fraction as F
from pathlib import Path
from unittest import mock

import jsonschema
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tegraph import Skeleton, load_skeleton, sensitivity
from tegraph.analysis.analyze import analyze_skeleton
from tegraph.analysis.processors import schedule_on_processors
from tegraph.analysis.processors.scaling import critical_scaling_factor
from tegraph.analysis.sensitivity.parts import ProcessorLine
from tegraph.model.build import build_teg
from tegraph.report import render_text, to_json
from tests.tegraph.analysis.sensitivity.exact_schedule import on_schedule

REPO = Path(__file__).resolve().parents[4]
QUADROTOR = REPO / "examples" / "quadrotor.yaml"
LIDAR = REPO / "examples" / "lidar_fusion_two_clocks.yaml"
SCHEMA = json.loads((REPO / "docs" / "report.schema.json").read_text())
NUDGE = F(1, 10**6)




def with_durations(sk: Skeleton, scale: F = F(1), **durations: F) -> Skeleton:
    data = sk.to_dict()
    for name, task in data["tasks"].items():
        task["duration"] = str(durations.get(name, F(task["duration"]) * scale))
    return Skeleton.from_dict(data)


_post_init = ProcessorLine.__post_init__


def _no_theorem(self):
    _post_init(self)
    self.use_theorem = False


def _no_simulation(*args, **kwargs):
    raise AssertionError("the schedule was simulated")


# ------------------------------------------------------------------ the quadrotor

# Units (examples/quadrotor.yaml): {imu, att_est} 0.25 every 1 ms, {rate_ctrl, mixer}
# 0.5 every 2.5, {pos_ctrl} 2 every 20, {gps} 9 every 100: utilization 0.64; the
# logger (no clock) runs in the idle time. Every duration times a: a <= 4 (imu),
# 2 (rate, at t = 2: a + a <= 2), 20/11 (pos, t = 20: 5a + 4a + 2a <= 20), 25/16
# (gps, t = 100: 25a + 20a + 10a + 9a <= 100). At 25/16 the units use the whole CPU:
# the logger starves; below, it gets a positive share.
QUADROTOR_HIGH = {  # each alone, the others nominal: where 0.64 + growth/period = 1
    "imu.duration": F(46, 100), "att_est.duration": F(51, 100),
    "rate_ctrl.duration": F(12, 10), "mixer.duration": F(11, 10),
    "pos_ctrl.duration": F(92, 10), "gps.duration": F(45)}


def test_quadrotor_scaling_factor_is_a_supremum_not_attained():
    r = sensitivity(load_skeleton(QUADROTOR), formulas=False)
    s = r.scaling
    assert r.schedulable is True and r.exit_status == 0
    assert s.exact and s.factor == F(25, 16) and not s.attained
    assert s.intervals == [(0, F(25, 16))]
    assert s.limits[0].task == "logger" and "starved" in s.limits[0].detail
    assert "at the end itself" in s.limits[0].detail
    # Why, in words: 1/4 + 1/5 + 1/10 + 9/100 = 0.64, times 25/16 is exactly 1.
    assert s.limits[0].detail.endswith("the units above it use the whole processor "
                                       "(their utilization is 1)")
    assert "Lehoczky" in s.method and "affine" not in s.method
    assert all(c.agrees for c in r.checks) and r.checks
    # The exact schedule, another algorithm: the logger starved at 25/16, every task
    # served just below it (a point halfway: just below, the logger's share is too
    # small for a schedule within a budget to end its job).
    sk = load_skeleton(QUADROTOR)
    assert on_schedule(with_durations(sk, F(25, 16))) is False
    assert on_schedule(with_durations(sk, (1 + F(25, 16)) / 2)) is True


def test_quadrotor_margins_are_exact_and_open():
    r = sensitivity(load_skeleton(QUADROTOR), formulas=False)
    for name, high in QUADROTOR_HIGH.items():
        m = r.margins[name]
        assert m.exact and (m.low, m.high) == (0, high), name
        assert not m.high_attained and m.low_attained, name
        assert [x.task for x in m.limits_high] == ["logger"], name
    logger = r.margins["logger.duration"]  # the idle time stays 36 %: any duration
    assert logger.exact and logger.high is None and logger.high_attained
    assert r.margins["gps.duration"].high - 9 == 36  # +36 exactly, not attained
    assert all(c.agrees for c in r.checks)
    doc = json.loads(to_json(r))
    jsonschema.validate(doc, SCHEMA)
    assert doc["scaling_factor"] == "25/16" and doc["scaling"]["attained"] is False
    gps = doc["margins"]["gps.duration"]
    assert gps["high"] == "45" and gps["high_attained"] is False
    assert gps["intervals_open"] == [[False, True]]
    text = render_text(r)
    assert "schedulable for α in [0, 1.5625)" in text
    assert "a supremum NOT attained" in text and "any factor below 1.5625" in text
    assert "[0, 45)" in text and "less than +36" in text


def test_quadrotor_figures_need_no_simulation_and_without_logger_are_attained():
    sk = load_skeleton(QUADROTOR)
    with mock.patch.object(ProcessorLine, "_simulate", _no_simulation):
        fast = sensitivity(sk, formulas=False, verify=False)
    assert fast.schedulable is True and fast.scaling.factor == F(25, 16)
    # Without the logger every figure is attained, and the walk on affine times (the
    # theorem off) reaches the same ends: gps overruns at activation 2 just beyond.
    clocked = sk.restricted_to([t for t in sk.tasks if t != "logger"])
    r = sensitivity(clocked, formulas=False)
    s = r.scaling
    assert s.exact and s.factor == F(25, 16) and s.attained
    assert s.limits[0].task == "gps" and s.limits[0].activation == 2
    units = [(F(1, 4), F(1)), (F(1, 2), F(5, 2)), (F(2), F(20)), (F(9), F(100))]
    assert critical_scaling_factor(units).value == F(25, 16)  # the units as single tasks
    for name, high in QUADROTOR_HIGH.items():
        m = r.margins[name]
        assert m.exact and m.high == high and m.high_attained, name
    assert all(c.agrees for c in r.checks)
    # (The walk on affine times reaches pos_ctrl's 46/5 and mixer's 11/10 too, in a
    # minute each, and stops at its 400 intervals on gps's: benchmarks/results/
    # sensitivity.md. The random parts below compare the two on smaller skeletons.)


# ------------------------------------------------------------------ starved tasks


def test_a_duration_whose_growth_starves_its_task_has_no_unbounded_margin():
    # T0 runs freely (no clock, 4 ms) and comes first in the file: the more urgent of
    # the two groups without clock (§4b), it always has a job. T2 (duration 0) has its
    # events at time 0 only: schedulable; with any positive duration its job never
    # runs: starved. Its margin is {0}; T0's is unbounded (nothing above it).
    sk = Skeleton.from_dict({"tasks": {"T0": {"duration": 4}, "T2": {"duration": 0}}})
    r = sensitivity(sk, formulas=False)
    m = r.margins["T2.duration"]
    assert m.exact and (m.low, m.high) == (0, 0) and m.high_attained
    assert m.limits_high[0].task == "T2" and "starved" in m.limits_high[0].detail
    assert m.limits_high[0].detail.endswith("T0, more urgent and without clock, always "
                                            "has a job")
    assert r.margins["T0.duration"].high is None
    assert all(c.agrees for c in r.checks)
    starved = schedule_on_processors(with_durations(sk, T2=F(1, 1000)),
                                     build_teg(with_durations(sk, T2=F(1, 1000))),
                                     analyze_skeleton(sk).groups)
    assert starved.schedulable is False and starved.starved == ["T2"]


def test_a_background_task_above_clocked_work_starves_it():
    # Declared priorities put the logger L (no clock, 1 ms) above A (10 ms clock):
    # L always has a job, A's first job never runs: not schedulable. A.duration = 0
    # (its job ends at its release) is schedulable, any positive value is not: {0};
    # L.duration = 0 too ({0}: A alone then meets its deadline).
    sk = Skeleton.from_dict({"tasks": {"L": {"duration": 1, "priority": 2},
                                       "A": {"duration": 1, "period": 10, "priority": 1}}})
    assert on_schedule(sk) is False
    assert on_schedule(with_durations(sk, A=F(0))) is True
    assert on_schedule(with_durations(sk, L=F(0))) is True
    r = sensitivity(sk, formulas=False)
    assert r.schedulable is False
    for name in ("A.duration", "L.duration"):
        m = r.margins[name]
        assert not m.nominal_consistent and m.exact and m.intervals == [(0, 0)], name
        assert m.not_searched is None
    assert all(c.agrees for c in r.checks)
    assert "NOT at nominal; schedulable on {0}" in render_text(r)


# ------------------------------------------------------------------ the guard: closing tasks


def _pair(closing: bool) -> Skeleton:
    """H (7 ms clock, 3.5) above the group A (10 ms clock, 0.5) -> B (4), optionally
    closed by Z (the same clock, reading B, 0)."""
    tasks = {"H": {"duration": "3.5", "period": 7},
             "A": {"duration": "0.5", "clock": "c", "outputs": ["o"]},
             "B": {"duration": 4, "inputs": ["i"], "outputs": ["o"]}}
    links = [{"from": "A:o", "to": "B:i", "protocol": "ASYN/SYN"}]
    if closing:
        tasks["Z"] = {"duration": 0, "clock": "c", "inputs": ["i"]}
        links.append({"from": "B:o", "to": "Z:i", "protocol": "ASYN/SYN"})
    return Skeleton.from_dict({"clocks": {"c": {"period": 10}}, "tasks": tasks,
                               "links": links})


def test_a_unit_missing_its_deadline_overruns_only_when_closed():
    # The unit {A, B} (4.5 every 10) under H (3.5 every 7): Lehoczky-Sha-Ding at its
    # points, t = 7: 3.5 + 4.5 = 8 > 7; t = 10: 7 + 4.5 = 11.5 > 10: its first job ends
    # after tick 2 (at 11.5: H 0-3.5, A 3.5-4, B 4-7, H 7-10.5, B 10.5-11.5). B has no
    # clock: its lateness is no overrun (§4b), A's activations end at 4, 12, ... and the
    # utilization is 0.95: the exact schedule finds it schedulable, and so must the
    # sensitivity (the theorem, which would call it an overrun, must not decide).
    # With Z (clock c) reading B, Z's activation 1 ends with B's job, at 11.5 > 10:
    # overrun at activation 2, which the theorem decides without simulating.
    open_pair, closed_pair = _pair(False), _pair(True)
    assert on_schedule(open_pair) is True
    r = sensitivity(open_pair, formulas=False, margins=False, verify=False)
    assert r.schedulable is True
    assert on_schedule(closed_pair) is False
    with mock.patch.object(ProcessorLine, "_simulate", _no_simulation):
        closed = sensitivity(closed_pair, formulas=False, margins=False, verify=False)
    assert closed.schedulable is False
    assert closed.scaling.not_searched.startswith("none: not schedulable as it is")
    assert "Z overruns at activation 2" in closed.scaling.not_searched


# ------------------------------------------------------------------ a period searched


def _two_lidar_clocks() -> Skeleton:
    """examples/lidar_fusion_two_clocks.yaml with the rear lidar on a 200 ms clock: the
    fusion is bound to two clocks, consistent only where they are equal."""
    data = load_skeleton(LIDAR).to_dict()
    data["clocks"] = {"lidar_clk": {"period": "100"}, "rear_clk": {"period": "200"}}
    for name, clock in (("FrontLidarDriver", "lidar_clk"), ("RearLidarDriver", "rear_clk")):
        data["tasks"][name].pop("period", None)
        data["tasks"][name]["clock"] = clock
    return Skeleton.from_dict(data)


def test_a_named_period_is_searched_where_the_nominal_is_not_schedulable():
    # With a processor per task the group keeps pace only at lidar_clk.period = 200
    # (both clocks equal); on the one CPU the work per 200 ms is 39 ms: schedulable
    # there, which analyze confirms; nowhere else in 50..400.
    sk = _two_lidar_clocks()
    r = sensitivity(sk, ["lidar_clk.period=50..400"], formulas=False)
    m = r.margins["lidar_clk.period"]
    assert m.per_task.intervals == [(200, 200)]
    assert not m.nominal_consistent and m.not_searched is None
    assert m.exact and m.intervals == [(200, 200)]
    assert all(c.agrees for c in m.checks) and m.checks
    moved = Skeleton.from_dict({**sk.to_dict(), "clocks": {
        "lidar_clk": {"period": "200"}, "rear_clk": {"period": "200"}}})
    assert analyze_skeleton(moved, processors=True).schedulable is True
    assert "NOT at nominal; schedulable on {200}" in render_text(r)
    jsonschema.validate(json.loads(to_json(r)), SCHEMA)


def test_a_bound_says_why_its_part_was_simulated():
    # The lidar fusion's one group has two clocks (100 ms each): not one periodic unit,
    # so its schedule is walked, and 1,000 firings per figure do not reach the end.
    sk = load_skeleton(LIDAR)
    r = sensitivity(sk, ["NDTLocalizer.duration"], formulas=False, verify=False,
                    max_events=1000)
    for figure in (r.scaling, r.margins["NDTLocalizer.duration"]):
        assert not figure.exact
        why = " ".join(figure.why_undecided)
        assert "`max_events`" in why
        assert "not decided by the exact test of periodic units" in why and "2 clocks" in why


# ------------------------------------------------------------------ random parts with levels


@st.composite
def level_parts(draw):
    """One CPU: up to three clocked groups (a root on its clock, a chain of readers,
    sometimes a closing task on the same clock), maybe a task without clock;
    rate-monotonic, or declared priorities one per group in a random order."""
    durations = st.integers(0, 8).map(lambda n: F(n, 4))
    tasks: dict = {}
    links: list = []
    clocks: dict = {}
    for u in range(draw(st.integers(1, 3))):
        clocks[f"c{u}"] = {"period": draw(st.sampled_from([2, 3, 4, 5, 6, 10, 12]))}
        prev = f"U{u}r"
        tasks[prev] = {"duration": str(draw(durations)), "clock": f"c{u}", "outputs": ["o"]}
        for k in range(draw(st.integers(0, 2))):
            name = f"U{u}t{k}"
            tasks[name] = {"duration": str(draw(durations)), "inputs": ["i"],
                           "outputs": ["o"]}
            links.append({"from": f"{prev}:o", "to": f"{name}:i", "protocol": "ASYN/SYN"})
            prev = name
        if draw(st.booleans()) and prev != f"U{u}r":
            tasks[f"U{u}z"] = {"duration": str(draw(durations) / 2), "clock": f"c{u}",
                               "inputs": ["i"]}
            links.append({"from": f"{prev}:o", "to": f"U{u}z:i", "protocol": "ASYN/SYN"})
    if draw(st.booleans()):
        tasks["B"] = {"duration": str(draw(durations))}
    if draw(st.booleans()):
        groups = draw(st.permutations(sorted({t[:2] for t in tasks})))
        for t in tasks:
            tasks[t]["priority"] = groups.index(t[:2]) + 1
    return Skeleton.from_dict({"clocks": clocks, "tasks": tasks, "links": links})


@settings(max_examples=20, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(level_parts())
def test_levels_agree_with_the_schedule_and_the_walk(sk):
    fast = sensitivity(sk, formulas=False, verify=True, max_events=20_000)
    engine = on_schedule(sk)
    if engine is not None:  # the nominal verdict, against the exact schedule
        assert fast.schedulable is engine
    # Every exact end, at it and beside it, against the exact schedule (the checks).
    assert all(c.agrees or c.found is None for c in fast.checks)
    # The walk on affine times, the theorem off, where it decides.
    with mock.patch.object(ProcessorLine, "__post_init__", _no_theorem):
        walked = sensitivity(sk, formulas=False, verify=False, max_events=20_000)
    if walked.schedulable is not None and fast.schedulable is not None:
        assert walked.schedulable is fast.schedulable
    s, w = fast.scaling, walked.scaling
    if s.exact and w.exact and w.not_searched is None and s.not_searched is None:
        assert (s.factor, s.attained) == (w.factor, w.attained)
    for name, m in fast.margins.items():
        mw = walked.margins[name]
        if m.exact and mw.exact and mw.not_searched is None and m.nominal_consistent:
            assert (m.low, m.high, m.high_attained) == (mw.low, mw.high, mw.high_attained)
