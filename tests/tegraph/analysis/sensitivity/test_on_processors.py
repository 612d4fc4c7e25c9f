"""`tegraph sensitivity` on the processors (spec §4b): values derived by hand or by
another algorithm (the exact schedule of the scaled skeleton, Lehoczky-Sha-Ding)."""

from __future__ import annotations

import json
from fractions import Fraction as F
from pathlib import Path
from unittest import mock

import jsonschema
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from tegraph import Skeleton, load_skeleton, sensitivity
from tegraph.analysis.processors.scaling import critical_scaling_factor
from tegraph.analysis.sensitivity.parts import ProcessorLine
from tegraph.cli import app
from tegraph.errors import InputError
from tegraph.report import render_text, to_json
from tests.tegraph.analysis.sensitivity.exact_schedule import on_schedule

REPO = Path(__file__).resolve().parents[4]
TORQUE = REPO / "examples" / "computed_torque.yaml"
SCHEMA = json.loads((REPO / "docs" / "report.schema.json").read_text())
NUDGE = F(1, 10**9)




def scaled(sk: Skeleton, a: F) -> Skeleton:
    data = sk.to_dict()
    for task in data["tasks"].values():
        task["duration"] = str(F(task["duration"]) * a)
    return Skeleton.from_dict(data)


# ------------------------------------------------------------------ computed torque


def test_computed_torque_on_its_one_cpu():
    # One CPU, rate-monotonic: OBS.JL (1 ms) > the control chain TG.JS -> TF.TT.JS -> CO.JS
    # (2 ms, one group, run back to back: each is released when the previous ends,
    # so the CPU never idles between them) > MOD.DYN (6 ms). For MOD.DYN the chain
    # is one unit of 0.6a every 2 ms, so by Lehoczky-Sha-Ding's scheduling points
    # (W(t) = 1.2a + 0.1a ceil(t) + 0.6a ceil(t/2) <= t for some t in {1..6}):
    #   t=1: 1.9a <= 1; t=2: 2a <= 2; t=3: 2.7a <= 3; t=4: 2.8a <= 4;
    #   t=5: 3.5a <= 5; t=6: 3.6a <= 6 -> a <= 5/3 (the largest).
    # The chain (CO.JS ends by 2): 0.6a + 0.1a ceil(t) <= t: t=2: 0.8a <= 2 -> 5/2.
    # OBS.JL: 0.1a <= 1 -> 10. a* = min(5/3, 5/2, 10) = 5/3 < 2 (utilization 0.6 x 5/3 = 1).
    sk = load_skeleton(TORQUE)
    r = sensitivity(sk, formulas=False)
    s = r.scaling
    assert r.processors and r.schedulable is True and r.exit_status == 0
    assert s.semantics == "processors" and s.exact and s.factor == F(5, 3) and s.attained
    assert s.limits[0].task == "MOD.DYN"
    # The chain is one periodic unit at its own priority (its tasks released by ctl,
    # each when the one before ends): decided by the theorem; the walk on affine
    # times, the theorem switched off, finds the same factor.
    assert "Lehoczky" in s.method and "affine" not in s.method
    with mock.patch.object(ProcessorLine, "__post_init__", _no_theorem):
        walked = sensitivity(sk, formulas=False, margins=False, verify=False).scaling
    assert walked.exact and walked.factor == F(5, 3) and "affine" in walked.method
    assert s.per_task.factor == 5
    assert all(c.agrees for c in r.checks)
    # Another algorithm: the exact schedule of the scaled skeleton.
    assert on_schedule(scaled(sk, F(5, 3))) is True
    assert on_schedule(scaled(sk, F(5, 3) + NUDGE)) is False
    assert on_schedule(scaled(sk, F(2))) is False
    # Margins, each alone (same points, one unknown): MOD.DYN: C + 0.6 + 1.8 <= 6 at
    # t=6 -> 3.6; OBS.JL: 1.2 + 6C + 1.8 <= 6 -> 1/2 (t=4 gives 2/5, smaller).
    assert r.margins["MOD.DYN.duration"].high == F(18, 5)
    assert r.margins["OBS.JL.duration"].high == F(1, 2)
    assert r.margins["MOD.DYN.duration"].per_task.high == 6


def test_computed_torque_with_a_processor_per_task_is_the_old_answer():
    r = sensitivity(load_skeleton(TORQUE), formulas=False, processors=False)
    assert not r.processors and r.scaling.factor == 5
    assert r.scaling.semantics == "processor per task"
    assert r.margins["MOD.DYN.duration"].high == 6


def test_undecided_is_a_bound_never_a_guess():
    # 10 event firings cannot cover one hyperperiod (6 ms: 6 + 3 + 1 ticks): the
    # nominal verdict and the factor are undecided, with the budget named (the
    # schedule simulated: the theorem, which decides it, switched off).
    with mock.patch.object(ProcessorLine, "__post_init__", _no_theorem):
        r = sensitivity(load_skeleton(TORQUE), formulas=False, margins=False, max_events=10,
                        verify=False)
    assert r.schedulable is None and r.exit_status == 1
    assert r.scaling.factor is None and not r.scaling.exact
    assert r.scaling.why_undecided and "max_events" in " ".join(r.scaling.why_undecided)


def test_max_events_is_checked():
    try:
        sensitivity(load_skeleton(TORQUE), max_events=0)
    except InputError as exc:
        assert exc.where == "max_events"
    else:
        raise AssertionError("max_events=0 accepted")


# ------------------------------------------------------------------ independent tasks


def task_sets():
    periods = st.sampled_from([F(2), F(3), F(4), F(5), F(6), F(10), F(12)])
    durations = st.fractions(min_value=F(1, 4), max_value=F(3), max_denominator=4)
    return st.lists(st.tuples(durations, periods), min_size=1, max_size=3)


def skeleton_of(tasks) -> Skeleton:
    return Skeleton.from_dict({"tasks": {
        f"T{i}": {"duration": str(c), "period": str(p)} for i, (c, p) in enumerate(tasks)}})


def _no_theorem(self):
    ProcessorLine_post_init(self)
    self.use_theorem = False


ProcessorLine_post_init = ProcessorLine.__post_init__


@settings(max_examples=15, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(task_sets())
def test_theorem_walk_and_schedule_agree_on_independent_tasks(tasks):
    sk = skeleton_of(tasks)
    r = sensitivity(sk, formulas=False, margins=False, verify=False)
    s = r.scaling
    # Most urgent first: rate-monotonic, equal periods in file order (§4b).
    order = sorted(range(len(tasks)), key=lambda i: (tasks[i][1], i))
    lsd = critical_scaling_factor([tasks[i] for i in order]).value
    per_task = min(p / c for c, p in tasks)  # each task alone: C a <= T
    assert s.per_task.intervals[0] == (0, per_task)
    if lsd < 1:  # also when per_task < 1: then some task alone misses, so lsd < 1
        assert not s.nominal_consistent and s.factor is None
        return
    assert s.per_task.factor == per_task
    assert s.factor == min(lsd, per_task) <= per_task  # never above the relaxation
    assert "Lehoczky" in s.method
    # The walk on affine times, the theorem switched off, finds the same factor.
    with mock.patch.object(ProcessorLine, "__post_init__", _no_theorem):
        walked = sensitivity(sk, formulas=False, margins=False, verify=False).scaling
    assert walked.exact and walked.factor == s.factor and "affine" in walked.method
    # Brute force on rationals with the exact schedule: bisection brackets the end.
    assert on_schedule(scaled(sk, s.factor)) is True
    assert on_schedule(scaled(sk, s.factor + NUDGE)) is False
    low, high = F(1), per_task + 1
    for _ in range(6):
        mid = (low + high) / 2
        low, high = (mid, high) if on_schedule(scaled(sk, mid)) else (low, mid)
    assert low <= s.factor < high


# ------------------------------------------------------------------ the command line


def test_cli_labels_and_no_processors():
    runner = CliRunner()
    on = runner.invoke(app, ["sensitivity", str(TORQUE), "--no-formulas"])
    assert on.exit_code == 0, on.output
    assert "scaling factor 5/3 (≈1.66667) on its processors" in on.output
    assert "scaling factor 5 with a processor per task" in on.output
    off = runner.invoke(app, ["sensitivity", str(TORQUE), "--no-formulas", "--no-processors"])
    assert off.exit_code == 0, off.output
    assert "scaling factor 5 with a processor per task" in off.output
    assert "on its processors" not in off.output
    doc = json.loads(runner.invoke(app, ["sensitivity", str(TORQUE), "--json",
                                         "--no-processors"]).output)
    assert doc["scaling_factor"] == "5" and doc["processors"] is False
    doc = json.loads(runner.invoke(app, ["sensitivity", str(TORQUE), "--json"]).output)
    jsonschema.validate(doc, SCHEMA)
    assert doc["scaling_factor"] == "5/3" and doc["processors"] is True
    assert doc["scaling"]["semantics"] == "processors" and doc["scaling"]["exact"]
    assert doc["scaling"]["per_task"]["factor"] == "5"


def test_cli_bad_input_exits_2_with_one_message():
    bad = CliRunner().invoke(app, ["sensitivity", str(TORQUE), "--vary", "NOPE.duration"])
    assert bad.exit_code == 2
    lines = [line for line in bad.output.strip().splitlines() if line]
    assert len(lines) == 1 and "NOPE" in lines[0] and "Traceback" not in bad.output


def test_text_of_an_independent_set_names_the_theorem():
    sk = skeleton_of([(F(1), F(3)), (F(1), F(5)), (F(2), F(10))])
    text = render_text(sensitivity(sk, formulas=False))
    assert "scaling factor 9/7" in text and "Lehoczky, Sha and Ding" in text
    assert json.loads(to_json(sensitivity(sk, formulas=False)))["scaling_factor"] == "9/7"


# ------------------------------------------------------------------ cost: no search where
# no figure can exist, locality, budgets


def _no_search(*args, **kwargs):
    raise AssertionError("a search on processors was started")


def test_not_schedulable_nominal_gives_no_figure_and_no_search():
    # A pair on one processor at one priority (so no levels: the schedule itself
    # decides): A, first in the file, runs [0, 6); B is released at 0, runs [6, 10),
    # has 2 of its 6 left when A's next job and B's own tick come at 10: B's
    # activation 1 has not ended at tick 2 -> not schedulable. With a processor per
    # task each alone is consistent (6 <= 10).
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 6, "period": 10, "priority": 1},
                                       "B": {"duration": 6, "period": 10, "priority": 1}}})
    with mock.patch("tegraph.analysis.sensitivity.on_processors.solve_line", _no_search), \
            mock.patch.object(ProcessorLine, "evaluate", _no_search):
        r = sensitivity(sk, formulas=False)
    assert r.consistent and r.schedulable is False and r.exit_status == 1
    s = r.scaling
    assert s.factor is None and s.exact and s.nearest_above is None
    assert s.not_searched.startswith("none: not schedulable as it is")
    assert "B overruns at activation 2" in s.not_searched
    assert s.per_task.factor == F(10, 6)  # the per-task answer is still given beside
    for m in r.margins.values():
        assert m.high is None and m.exact
        assert m.not_searched.startswith("none: not schedulable as it is")
    doc = json.loads(to_json(r))
    jsonschema.validate(doc, SCHEMA)
    assert doc["scaling"]["not_searched"].startswith("none")
    text = render_text(r)
    assert "scaling factor on its processors: none: not schedulable as it is" in text
    assert "no scaling factor on its processors: not schedulable as it is" in text


def test_not_consistent_nominal_gives_no_figure_and_no_search():
    # A alone overruns with a processor per task (12 > 10): nothing on processors
    # (the theorem switched off: the schedule would have to be walked).
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 12, "period": 10}}})
    with mock.patch("tegraph.analysis.sensitivity.on_processors.solve_line", _no_search), \
            mock.patch.object(ProcessorLine, "__post_init__", _no_theorem):
        r = sensitivity(sk, formulas=False)
    m = r.margins["A.duration"]
    assert not r.consistent and m.high is None
    assert m.not_searched.startswith("none: not consistent as it is")
    assert "`vary`" in m.not_searched  # how to have it searched


def test_undecided_nominal_is_undecided_at_once_naming_max_events():
    # 10 firings cannot cover computed_torque's hyperperiod (6 ms: 6 + 3 + 1 ticks).
    with mock.patch("tegraph.analysis.sensitivity.on_processors.solve_line", _no_search), \
            mock.patch.object(ProcessorLine, "evaluate", _no_search), \
            mock.patch.object(ProcessorLine, "__post_init__", _no_theorem):
        r = sensitivity(load_skeleton(TORQUE), formulas=False, max_events=10)
    assert r.schedulable is None
    figures = [r.scaling, *r.margins.values()]
    for f in figures:
        assert not f.exact and f.not_searched.startswith("undecided")
        assert "`max_events`" in f.not_searched and "--max-events" not in f.not_searched
    assert "undecided at the nominal values" in render_text(r)


def _with_second_part(sk: Skeleton) -> Skeleton:
    """computed_torque (its one CPU ``default``) and a second part on ``cpu9``."""
    data = sk.to_dict()
    data["tasks"]["X"] = {"duration": "3", "period": "7", "outputs": ["o"],
                          "processor": "cpu9"}
    data["tasks"]["Y"] = {"duration": "2", "inputs": ["i"], "processor": "cpu9"}
    data["links"] = list(data.get("links", [])) + [
        {"from": "X:o", "to": "Y:i", "protocol": "ASYN/SYN"}]
    return Skeleton.from_dict(data)


def test_a_margin_is_its_part_alone():
    torque = load_skeleton(TORQUE)
    both = _with_second_part(torque)
    calls: list[int] = []
    evaluate = ProcessorLine.evaluate
    nominal_part = ProcessorLine._nominal_part
    nominal_calls: list[str] = []

    def counting(self, i, *args, **kwargs):
        calls.append(self.parts[i].names[0])
        return evaluate(self, i, *args, **kwargs)

    def counting_nominal(self, part):
        nominal_calls.append(part.names[0])
        return nominal_part(self, part)

    with mock.patch.object(ProcessorLine, "evaluate", counting), \
            mock.patch.object(ProcessorLine, "_nominal_part", counting_nominal):
        r = sensitivity(both, formulas=False, vary=["MOD.DYN.duration", "Y.duration"])
    # Each part decided once at the nominal values, never again per margin; the
    # margin of MOD.DYN simulates only the computed-torque part, Y's only X and Y's.
    assert sorted(nominal_calls) == ["OBS.JL", "X"]
    assert set(calls) <= {"OBS.JL", "X"} and calls
    # The same margins computed on each part alone (another skeleton, other parts):
    # MOD.DYN on its CPU: 18/5 by hand (test_computed_torque_on_its_one_cpu).
    # Y alone on cpu9 after X (ASYN/SYN: released when X ends at 3): it ends by
    # X's next tick at 7 -> Y.duration <= 4; by the per-task answer also 4.
    alone = sensitivity(torque, formulas=False, vary=["MOD.DYN.duration"])
    pair = Skeleton.from_dict({"tasks": {
        "X": {"duration": 3, "period": 7, "outputs": ["o"], "processor": "cpu9"},
        "Y": {"duration": 2, "inputs": ["i"], "processor": "cpu9"}},
        "links": [{"from": "X:o", "to": "Y:i", "protocol": "ASYN/SYN"}]})
    pair_alone = sensitivity(pair, formulas=False, vary=["Y.duration"])
    m, y = r.margins["MOD.DYN.duration"], r.margins["Y.duration"]
    assert m.exact and m.high == alone.margins["MOD.DYN.duration"].high == F(18, 5)
    assert y.exact and y.high == pair_alone.margins["Y.duration"].high == 4
    assert all(c.agrees for c in r.checks)


def test_a_tiny_budget_gives_undecided_never_a_wrong_number():
    # 1,000 firings per figure: the nominal (about 50 firings per simulation) is
    # decided, but no walk of computed_torque's scaling line ends within it.
    exact = sensitivity(load_skeleton(TORQUE), formulas=False, verify=False)
    with mock.patch.object(ProcessorLine, "__post_init__", _no_theorem):  # simulate it
        r = sensitivity(load_skeleton(TORQUE), formulas=False, verify=False, max_events=1000)
    assert r.schedulable is True
    s = r.scaling
    assert s.factor is None and not s.exact
    assert "this figure's budget of 1,000 event firings (`max_events`)" in s.why_undecided[0]
    proven, most = s.bounds
    assert 1 <= proven <= exact.scaling.factor <= most  # a bound around the true 5/3
    for name, m in r.margins.items():
        true = exact.margins[name]
        if m.exact:
            assert (m.low, m.high) == (true.low, true.high)
        else:
            lo, hi = m.bounds
            assert hi <= true.high and (lo is None or lo >= true.low)
    # The run's budget: 2 x max_events in all, spent after the first figures; the
    # rest are undecided at once, naming it.
    with mock.patch("tegraph.analysis.sensitivity.simulation.RUN_BUDGETS", 2), \
            mock.patch.object(ProcessorLine, "__post_init__", _no_theorem):
        r = sensitivity(load_skeleton(TORQUE), formulas=False, verify=False, max_events=5000)
    assert r.schedulable is True
    spent = [f for f in [r.scaling, *r.margins.values()]
             if "run's budget" in " ".join([f.not_searched or "", *f.why_undecided])]
    assert spent and all(not f.exact for f in spent)
    assert all("(2 × `max_events`)" in " ".join([f.not_searched or "", *f.why_undecided])
               for f in spent)
    for name, m in r.margins.items():
        assert m.high is None or m.high == exact.margins[name].high
    fired = int(r.notes[-1].split(" event firings")[0].split()[-1].replace(",", ""))
    assert fired <= 10_000 and "budget of 10,000" in r.notes[-1]


def test_a_period_walked_down_is_never_taken_at_zero_or_below():
    # obs.period of computed_torque on its one CPU: the walk down from the nominal 1 ms
    # asks for the schedule just below the end of an interval that had no lower end;
    # the point taken there was at - 1 = 0 ms, a period the model refuses, and the
    # schedule crashed (KeyError) on a clock of period 0. Per task the group of OBS.JL
    # (alone, 0.1 ms) keeps pace for every period >= 0.1 ms (by hand); on the CPU the
    # nominal 1 ms is schedulable (test_computed_torque_on_its_one_cpu), so whatever
    # the budget leaves undecided, the interval found holds 1.
    s = sensitivity(load_skeleton(TORQUE), ["obs.period"], formulas=False, verify=False,
                    max_events=20_000)
    m = s.margins["obs.period"]
    assert m.per_task.intervals == [(F(1, 10), None)]
    low, high = m.bounds if m.bounds is not None else (m.low, m.high)
    assert low <= 1 and (high is None or 1 <= high)
