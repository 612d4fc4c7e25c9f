"""Tasks on different processors that never execute at the same time, against the
schedule unrolled by brute force."""

from __future__ import annotations

import math
from fractions import Fraction as F

from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from tegraph.analysis.analyze import analyze_skeleton
from tegraph.analysis.processors import schedule_on_processors
from tegraph.analysis.processors.overlap import MAX_PAIRS, never_together
from tegraph.model.build import build_teg
from tegraph.model.skeleton import Skeleton
from tests.tegraph.skeleton_corpus import random_skeleton


def schedule_of(data: dict):
    sk = Skeleton.from_dict(data)
    return schedule_on_processors(sk, build_teg(sk), analyze_skeleton(sk).groups)


def unrolled_pairs(s) -> set[tuple[str, str]]:
    """The pairs found by writing out every stretch until both regimes have repeated
    together: from the later start, one common multiple of the two lengths."""
    stretches: dict[str, list[tuple[F, F]]] = {}
    for i in s.intervals:
        stretches.setdefault(i.task, []).append((i.start, i.end))
    regime_of = {t: r for r in s.regimes for t in r["tasks"]}
    where = s.platform.processor_of
    names = [t for t in s.tasks if t in stretches]

    def busy(task: str, until: F) -> list[tuple[F, F]]:
        r = regime_of[task]
        start, length = r["start"], r["length"]
        out = [(a, min(b, start)) for a, b in stretches[task] if a < start]
        if length is None:
            return out
        pattern = [(max(a, start), b) for a, b in stretches[task] if b > start]
        m = 0
        while start + m * length < until:
            out += [(a + m * length, b + m * length) for a, b in pattern]
            m += 1
        return out

    together = set()
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            if where[a] == where[b]:
                continue
            ra, rb = regime_of[a], regime_of[b]
            la = ra["length"] or F(1)
            lb = rb["length"] or F(1)
            common = F(math.lcm(la.numerator * lb.denominator, lb.numerator * la.denominator),
                       la.denominator * lb.denominator)
            until = max(ra["start"], rb["start"]) + common
            if any(x0 < y1 and y0 < x1 for x0, x1 in busy(a, until)
                   for y0, y1 in busy(b, until)):
                together.add((a, b))
    return {(a, b) for i, a in enumerate(names) for b in names[i + 1:]
            if where[a] != where[b]} - together


def test_two_phased_tasks_alternate_and_are_found():
    # A runs 0-1, 4-5, ...; B 2-3, 6-7, ... (its phase 2): never at once. With B's
    # period 6 instead, B runs 2-3, 8-9 (against A's 8-9): together at 8.
    base = {"A": {"duration": 1, "period": 4, "processor": "p"},
            "B": {"duration": 1, "period": 4, "phase": 2, "processor": "q"}}
    assert never_together(schedule_of({"tasks": base})).pairs == [("A", "B")]
    base["B"]["period"] = 6
    assert never_together(schedule_of({"tasks": base})).pairs == []


def test_a_synchronized_pipeline_never_overlaps_its_stages():
    # MT2 reads MT1 through ASYN/SYN on another processor: MT1 0-1, MT2 1-3 every 5;
    # MT3 on a third processor runs free from 0 for 2 every 5: it overlaps both.
    data = {"tasks": {"MT1": {"duration": 1, "period": 5, "outputs": ["x"], "processor": "p"},
                      "MT2": {"duration": 2, "inputs": ["x"], "processor": "q"},
                      "MT3": {"duration": 2, "period": 5, "processor": "r"}},
            "links": [{"from": "MT1:x", "to": "MT2:x", "protocol": "ASYN/SYN"}]}
    result = never_together(schedule_of(data))
    assert result.pairs == [("MT1", "MT2")]
    assert result.examined == 3


def test_no_pair_is_claimed_on_a_schedule_not_proven():
    # 3 ms of work every 2 ms on p: it overruns, no processor time is known for ever.
    data = {"tasks": {"A": {"duration": 3, "period": 2, "processor": "p"},
                      "B": {"duration": 1, "period": 2, "processor": "q"}}}
    result = never_together(schedule_of(data))
    assert result.pairs is None and "not proven schedulable" in result.why


def test_a_task_that_never_occupies_its_processor_is_left_out_with_why():
    data = {"tasks": {"A": {"duration": 0, "period": 2, "processor": "p"},
                      "B": {"duration": 1, "period": 2, "processor": "q"}}}
    result = never_together(schedule_of(data))
    assert result.pairs == []
    assert result.left_out == {"A": "it never occupies its processor"}


def test_the_pair_limit_is_a_stated_refusal():
    tasks = {f"T{i}": {"duration": 0.01, "period": 1000, "processor": f"p{i}"}
             for i in range(202)}  # 202 * 201 / 2 = 20301 pairs
    assert 202 * 201 // 2 > MAX_PAIRS
    result = never_together(schedule_of({"tasks": tasks}))
    assert result.pairs is None and "20301 pairs" in result.why


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.randoms(use_true_random=False), st.integers(2, 3))
def test_random_skeletons_agree_with_the_unrolled_schedule(rng, processors):
    data = random_skeleton(rng)
    data.pop("threads", None)
    for i, spec in enumerate(data["tasks"].values()):
        spec["processor"] = f"cpu{i % processors}"
    s = schedule_of(data)
    assume(s.schedulable is True)
    assume(all("by" not in r for r in s.regimes))
    result = never_together(s)
    assert set(result.pairs) == unrolled_pairs(s)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.integers(1, 3), st.integers(2, 7), st.integers(0, 6)),
                min_size=2, max_size=4), st.sampled_from([1, 2**70]))
def test_free_tasks_of_several_periods_agree_with_the_unrolled_schedule(specs, unit):
    # Independent tasks each on its own processor: the regimes of different lengths
    # meet only through the common start (Bézout on the gcd of the lengths); times
    # multiplied by 2**70 take the exact wide path.
    tasks = {f"T{i}": {"duration": F(d, 2) * unit, "period": p * unit,
                       "phase": F(ph, 3) * unit, "processor": f"p{i}"}
             for i, (d, p, ph) in enumerate(specs)}
    for spec in tasks.values():
        spec.update({k: str(v) for k, v in spec.items() if k != "processor"})
    s = schedule_of({"tasks": tasks})
    assume(s.schedulable is True)
    assert set(never_together(s).pairs) == unrolled_pairs(s)


def busy_set(draw, wide: int):
    """A task's processor time drawn directly: disjoint stretches before ``start``,
    then a pattern of disjoint stretches inside ``[0, length)`` (or nothing after)."""
    start = draw(st.integers(0, 12))
    length = draw(st.one_of(st.none(), st.integers(1, 9)))
    cuts = sorted(set(draw(st.lists(st.integers(0, start), max_size=6))))
    trans = [(a, b) for a, b in zip(cuts[::2], cuts[1::2]) if a < b]
    pattern = []
    if length is not None:
        cuts = sorted(set(draw(st.lists(st.integers(0, length), max_size=6))))
        pattern = [(a, b) for a, b in zip(cuts[::2], cuts[1::2]) if a < b]
    stretches = trans + [(start + a, start + b) for a, b in pattern]
    return [(a * wide, b * wide) for a, b in stretches], start * wide, (
        None if length is None else length * wide)


@st.composite
def two_busy_sets(draw):
    wide = draw(st.sampled_from([1, 2**70]))
    return busy_set(draw, wide), busy_set(draw, wide)


@settings(max_examples=400, deadline=None)
@given(two_busy_sets())
def test_the_modular_test_is_the_unrolled_one(sets):
    # The algorithm alone, on busy sets drawn directly (no engine): both orders, the
    # transient of each against the other's regime, regimes of coprime lengths.
    from tegraph.analysis.processors import overlap

    def unrolled(stretches, start, length, until):
        out = [(a, b) for a, b in stretches if a < start]
        if length is not None:
            pattern = [(a, b) for a, b in stretches if a >= start]
            m = 0
            while start + m * length < until:
                out += [(a + m * length, b + m * length) for a, b in pattern]
                m += 1
        return out

    (sx, x0, lx), (sy, y0, ly) = sets
    until = max(x0, y0) + math.lcm(lx or 1, ly or 1)
    expected = any(a < d and c < b for a, b in unrolled(sx, x0, lx, until)
                   for c, d in unrolled(sy, y0, ly, until))
    dtype = object if max([x0, y0, lx or 0, ly or 0]) > 2**40 else int
    bx = overlap._split(sx, {"start": F(x0), "length": None if lx is None else F(lx)}, 1,
                        dtype)
    by = overlap._split(sy, {"start": F(y0), "length": None if ly is None else F(ly)}, 1,
                        dtype)
    assert overlap._overlap(bx, by) == expected
    assert overlap._overlap(by, bx) == expected
