"""Every figure of ``sensitivity`` checked against the analysis at points.

The reference is :func:`~tegraph.analysis.analyze.analyze_skeleton` on the
whole skeleton with the values set here (``dataclasses.replace`` on the
tasks and clocks, not the sensitivity model's own ``skeleton_at``): a
different algorithm (dater simulation, Howard on the whole graph) than the
certificates and line searches ``sensitivity`` reads its intervals from.

- the scaling factor: consistent at it, not at ``factor·(1 + 1/10^9)``;
- each margin's finite ends: consistent at the end, not just beyond;
- random rational points inside each reported interval consistent, outside not;
- the period formulas: at random rational points of the box, each group's
  cycle time is the maximum of its terms, and the keep-pace inequalities hold
  exactly where the group keeps pace with the clock (both directions).

On the examples (computed torque, Figure 12, the others) and on random
skeletons (``tests/tegraph/skeleton_corpus.py``). Heavy properties run a few
examples only: the whole suite stays within its time budget.
"""

from __future__ import annotations

import dataclasses
import random
from fractions import Fraction as F
from pathlib import Path

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from tegraph import Skeleton, load_skeleton
from tegraph import sensitivity as _sensitivity
from tegraph.analysis.analyze import analyze_skeleton
from tests.tegraph.skeleton_corpus import random_skeleton


def sensitivity(*args, **kwargs):
    """The (max,+) answers (a processor per task), checked here against the analysis
    with a processor per task; on processors: ``test_sensitivity_processors``."""
    kwargs.setdefault("processors", False)
    return _sensitivity(*args, **kwargs)


EXAMPLES = Path(__file__).resolve().parents[4] / "examples"
NUDGE = F(1, 10**9)
SETTINGS = dict(deadline=None, derandomize=True,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])


# ------------------------------------------------------------------ the reference


def at(sk: Skeleton, durations: dict[str, F] | None = None,
       periods: dict[str, F] | None = None) -> Skeleton:
    """``sk`` with some durations (by task) and clock periods (by clock) replaced."""
    tasks = {t: dataclasses.replace(task, duration=durations[t])
             if durations and t in durations else task for t, task in sk.tasks.items()}
    clocks = {c: dataclasses.replace(clock, period=periods[c])
              if periods and c in periods else clock for c, clock in sk.clocks.items()}
    return dataclasses.replace(sk, tasks=tasks, clocks=clocks)


def analysis(sk: Skeleton):
    """The analysis; a short dater simulation first (a group slower than its
    clock is inconsistent whatever the simulation would find)."""
    report = analyze_skeleton(sk, max_steps=1_000, semiflow_max_places=0)
    if all(t.overrun_decided for t in report.tasks.values()):
        return report
    if not all(g.live and g.rate_consistent for g in report.groups):
        return report
    return analyze_skeleton(sk, semiflow_max_places=0)


def verdict(sk: Skeleton, groups: list[int] | None = None) -> bool | None:
    """Consistent (spec §4) — of the whole skeleton, or of ``groups`` only;
    None when an overrun stays undecided within the budget."""
    report = analysis(sk)
    chosen = range(len(report.groups)) if groups is None else groups
    fine = True
    for i in chosen:
        g = report.groups[i]
        if not (g.live and g.rate_consistent):
            return False
        for t in g.tasks:
            if report.tasks[t].overrun_at is not None:
                return False
            if not report.tasks[t].overrun_decided:
                # Type: None: undecided, beside True and False.
                fine = None  # type: ignore[assignment]
    return fine


def scaled(sk: Skeleton, names: list[str], alpha: F) -> Skeleton:
    owners = [n.removesuffix(".duration") for n in names]
    return at(sk, {t: sk.tasks[t].duration * alpha for t in owners})


def moved(sk: Skeleton, parameter, value: F) -> Skeleton:
    if parameter.kind == "duration":
        return at(sk, {parameter.owner: value})
    return at(sk, periods={parameter.owner: value})


def inside(rng: random.Random, low: F, high: F | None) -> F:
    """A random rational point of [low, high] (of [low, 2·low + 10] when unbounded)."""
    top = high if high is not None else 2 * low + 10
    return low + (top - low) * F(rng.randint(0, 997), 997)


def gaps(intervals, low: F, high: F | None):
    """The parts of [low, high] that no interval covers, as open pairs (a, b)."""
    out, start = [], low
    for a, b in intervals:
        if a > start:
            out.append((start, a))
        if b is None:
            return out
        start = b
    if high is None or start < high:
        out.append((start, high))
    return out


def outside(rng: random.Random, a: F, b: F | None) -> F:
    """A random rational point strictly inside the open gap (a, b)."""
    if b is None:
        return a + (a + 1) * F(rng.randint(1, 997), 997)
    return a + (b - a) * F(rng.randint(1, 996), 997)


# ------------------------------------------------------------------ the checks


def check_scaling(sk: Skeleton, r, rng: random.Random, points: int = 3) -> int:
    """The scaling factor and intervals against the analysis; the number of points checked."""
    s = r.scaling
    if s is None:
        return 0
    names, n = s.parameters, 0
    if s.factor is not None:
        assert verdict(scaled(sk, names, s.factor)) is True, s.factor
        beyond = verdict(scaled(sk, names, s.factor * (1 + NUDGE)))
        assert beyond in (False, None), s.factor
        n += 2
    for a, b in s.intervals:
        for t in [a, *(inside(rng, a, b) for _ in range(points))] + ([b] if b else []):
            assert verdict(scaled(sk, names, t)) in (True, None), (t, s.intervals)
            n += 1
        if b is not None and b > 0:
            assert verdict(scaled(sk, names, b * (1 + NUDGE))) in (False, None) or any(
                x <= b * (1 + NUDGE) for x, _ in s.intervals if x > b), (b, s.intervals)
    for a, b in gaps(s.intervals, F(0), None):
        for _ in range(points):
            t = outside(rng, a, b)
            assert verdict(scaled(sk, names, t)) in (False, None), (t, s.intervals)
            n += 1
    return n


def check_margins(sk: Skeleton, r, rng: random.Random, points: int = 2) -> int:
    """Each margin's ends and intervals against the analysis of its groups."""
    n = 0
    for name, m in r.margins.items():
        p = m.parameter
        groups = m.groups

        def ok(value: F) -> bool | None:
            return verdict(moved(sk, p, value), groups)  # noqa: B023

        for a, b in m.intervals:
            for end, step in ((a, -1), (b, 1)):
                if end is None:
                    continue
                assert ok(end) in (True, None), (name, end, m.intervals)
                past = end + step * max(end, F(1)) * NUDGE
                in_range = p.contains(past)
                if in_range and not any(x <= past and (y is None or past <= y)
                                        for x, y in m.intervals):
                    assert ok(past) in (False, None), (name, past, m.intervals)
                n += 2
            for _ in range(points):
                t = inside(rng, a, b)
                if p.contains(t):
                    assert ok(t) in (True, None), (name, t, m.intervals)
                    n += 1
        for a, b in gaps(m.intervals, p.low, p.high):
            for _ in range(points):
                t = outside(rng, a, b)
                if p.contains(t):
                    assert ok(t) in (False, None), (name, t, m.intervals)
                    n += 1
        if m.nominal_consistent:
            assert m.low is not None and m.low <= p.nominal
            assert m.high is None or p.nominal <= m.high
    return n


def formula_value(f, values: dict[str, F]) -> F:
    return max((t.constant + sum((c * values[q] for q, c in t.coefficients.items()), F(0)))
               / t.tokens for t in f.terms)


def check_formulas(sk: Skeleton, r, rng: random.Random, points: int = 4) -> int:
    """Each exact formula and keep-pace region against the analysis at random box points."""
    params = {p.name: p for p in r.parameters}
    n = 0
    for _ in range(points):
        values = {name: inside(rng, p.low if not p.low_open else p.low + F(1, 7),
                               p.high) for name, p in params.items()}
        durations = {p.owner: values[q] for q, p in params.items() if p.kind == "duration"}
        periods = {p.owner: values[q] for q, p in params.items() if p.kind == "period"}
        point = at(sk, durations, periods)
        report = analyze_skeleton(point, max_steps=0, semiflow_max_places=0)
        for f in r.formulas:
            if not f.exact:
                continue
            g = report.groups[f.group]
            assert g.tasks == f.tasks and g.live
            cycle_time = max(g.cycle_times.values())
            assert formula_value(f, values) == cycle_time, (f.group, values)
            for pace in f.pace:
                period = point.clocks[pace.clock].period
                keeps = cycle_time == period
                holds = not pace.empty and all(
                    sum((c * values[q] for q, c in co.items()), F(0)) <= bound
                    for co, bound, _ in pace.inequalities)
                assert holds == keeps, (f.group, pace.clock, values, cycle_time, period)
            n += 1
    return n


# ------------------------------------------------------------------ examples


def example(name: str) -> Skeleton:
    return load_skeleton(EXAMPLES / name)


@pytest.mark.parametrize("name", ["computed_torque.yaml", "fig12_double_sync.yaml",
                                  "overrun_in_step.yaml", "rendezvous_two_clocks.yaml",
                                  "threads.yaml", "ring_two_tokens.yaml",
                                  "fig7a_circular_wait.yaml"])
def test_examples_against_the_analysis(name):
    sk = example(name)
    r = sensitivity(sk, verify=False)
    rng = random.Random(name)
    assert check_scaling(sk, r, rng) + check_margins(sk, r, rng) >= 0
    if r.formulas:
        check_formulas(sk, r, rng)


def test_computed_torque_by_hand_at_the_ends():
    # By hand (test_sensitivity): every duration scaled by α keeps the design
    # consistent iff α·d <= P for each task of a clocked group and the control
    # group's sum-free chains: α <= min(1/(1/10), 2/(3/10), 6/(6/5)) = 5.
    sk = example("computed_torque.yaml")
    names = [f"{t}.duration" for t in sk.tasks]
    assert verdict(scaled(sk, names, F(5))) is True
    assert verdict(scaled(sk, names, F(5) * (1 + NUDGE))) is False
    # Each duration alone: consistent up to its clock's period, not beyond.
    for task, period in {"OBS.JL": 1, "TG.JS": 2, "TF.TT.JS": 2, "CO.JS": 2,
                         "MOD.DYN": 6}.items():
        assert verdict(at(sk, {task: F(period)})) is True, task
        assert verdict(at(sk, {task: F(period) * (1 + NUDGE)})) is False, task
    r = sensitivity(sk, verify=False)
    assert r.scaling.factor == 5
    assert {m.parameter.owner: m.high for m in r.margins.values()} == {
        "OBS.JL": 1, "TG.JS": 2, "TF.TT.JS": 2, "CO.JS": 2, "MOD.DYN": 6}


def test_fig12_no_factor_and_no_duration_helps():
    # MT2's group is paced by rtc (10 ms) and MT2.clock (4 ms): a place between
    # them is unbounded for every duration, so every factor is inconsistent.
    sk = example("fig12_double_sync.yaml")
    names = [f"{t}.duration" for t in sk.tasks]
    for alpha in (F(0), F(1, 1000), F(1, 2), F(1), F(3), F(100)):
        assert verdict(scaled(sk, names, alpha)) is False, alpha
    r = sensitivity(sk, verify=False)
    assert r.scaling.intervals == [] and r.scaling.factor is None


# ------------------------------------------------------------------ random skeletons


def vary_of(sk: Skeleton, rng: random.Random, k: int) -> list[str]:
    """Up to k parameters: durations and periods, with bounded exact ranges."""
    names = [f"{t}.duration" for t in sk.tasks] + [f"{c}.period" for c in sk.clocks]
    chosen = rng.sample(names, min(k, len(names)))
    out = []
    for name in chosen:
        if name.endswith(".duration"):
            d = sk.tasks[name.removesuffix(".duration")].duration
            out.append(f"{name}=0..{2 * d + 2}")
        else:
            p = sk.clocks[name.removesuffix(".period")].period
            out.append(f"{name}={p / 2}..{2 * p}")
    return out


@settings(max_examples=25, **SETTINGS)
@given(st.randoms(use_true_random=False))
def test_random_scaling_and_margins_against_the_analysis(rng):
    sk = Skeleton.from_dict(random_skeleton(rng, max_tasks=4))
    r = sensitivity(sk, formulas=False, verify=False)
    check_scaling(sk, r, rng, points=2)
    check_margins(sk, r, rng, points=1)


@settings(max_examples=20, **SETTINGS)
@given(st.randoms(use_true_random=False))
def test_random_formulas_against_the_analysis(rng):
    sk = Skeleton.from_dict(random_skeleton(rng, max_tasks=4))
    vary = vary_of(sk, rng, 3)
    r = sensitivity(sk, vary, verify=False)
    assume(r.formulas)
    check_formulas(sk, r, rng, points=4)


@settings(max_examples=10, **SETTINGS)
@given(st.randoms(use_true_random=False))
def test_random_ranged_margins_against_the_analysis(rng):
    # Periods too, within ranges: consistency need not be monotone (a slower
    # producer can repair a design), so intervals may be several.
    sk = Skeleton.from_dict(random_skeleton(rng, max_tasks=4))
    r = sensitivity(sk, vary_of(sk, rng, 3), formulas=False, verify=False)
    check_margins(sk, r, rng, points=2)


@settings(max_examples=30, **SETTINGS)
@given(st.randoms(use_true_random=False))
def test_random_duration_margins_agree_with_the_line_search(rng):
    # analyze's "can grow by" (one nominal analysis: slack and longest paths)
    # against the exact line search of sensitivity, and the analysis at its end.
    from tegraph import duration_margins

    sk = Skeleton.from_dict(random_skeleton(rng, max_tasks=4))
    fast = duration_margins(sk)
    r = sensitivity(sk, formulas=False, verify=False)
    for task, grow in fast.items():
        m = r.margins[f"{task}.duration"]
        assert m.nominal_consistent, task
        d = sk.tasks[task].duration
        assert (None if m.high is None else m.high - d) == grow, (task, m.intervals, grow)
        if grow is not None:
            assert verdict(at(sk, {task: d + grow}), m.groups) in (True, None)
