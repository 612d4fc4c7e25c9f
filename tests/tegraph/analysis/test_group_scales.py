"""Each group's times on its own scale give the analysis of the common scale.

``analyze_skeleton`` scales each group's times by the group's own least common
denominator (:meth:`TimedEventGraph.scaled_by_part`): integers that fit in int64
where the common scale of all groups would not. The same analysis on the common
scale (``_PER_GROUP_SCALE = False``, as before) must give the same report, field
by field, on skeletons of several groups with periods and durations of different
denominators, including one whose common scale is past int64.
"""

from __future__ import annotations

import random
from fractions import Fraction as F

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tegraph.analysis import analyze as analyze_module
from tegraph.analysis.analyze import analyze_skeleton
from tegraph.model.build import build_teg
from tegraph.model.skeleton import Skeleton
from tegraph.model.teg import TimedEventGraph
from tegraph.report.document import to_json
from tests.tegraph.skeleton_corpus import random_skeleton, side_by_side

SETTINGS = settings(max_examples=60, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow,
                                           HealthCheck.function_scoped_fixture])


def groups_of(parts: list[dict]) -> Skeleton:
    """One skeleton of several corpus skeletons side by side (each one group or more)."""
    return Skeleton.from_dict(side_by_side(parts))


def both_scales(sk: Skeleton, monkeypatch) -> tuple[str, str]:
    own = to_json(analyze_skeleton(sk))
    monkeypatch.setattr(analyze_module, "_PER_GROUP_SCALE", False)
    common = to_json(analyze_skeleton(sk))
    monkeypatch.setattr(analyze_module, "_PER_GROUP_SCALE", True)
    return own, common


@SETTINGS
@given(st.randoms(use_true_random=False), st.integers(1, 4))
def test_each_group_on_its_scale_gives_the_report_of_the_common_scale(monkeypatch, rng, n):
    own, common = both_scales(groups_of([random_skeleton(rng) for _ in range(n)]), monkeypatch)
    assert own == common


def test_groups_past_int64_together_give_the_report_of_the_common_scale(monkeypatch):
    """Periods of 1/p for the primes p up to 60 (their lcm has 22 digits) in groups
    of a clocked task each, with a follower: the common scale's arrays are objects."""
    primes = [p for p in range(2, 60) if all(p % q for q in range(2, p))]
    tasks = {}
    for p in primes:
        tasks[f"A{p}"] = {"duration": f"1/{3 * p}", "period": f"1/{p}", "outputs": ["o"]}
        tasks[f"B{p}"] = {"duration": f"1/{2 * p}", "inputs": ["i"]}
    links = [{"from": f"A{p}:o", "to": f"B{p}:i", "protocol": "SYN/SYN"} for p in primes]
    sk = Skeleton.from_dict({"tasks": tasks, "links": links})
    assert build_teg(sk).arrays().holding.dtype == object
    own, common = both_scales(sk, monkeypatch)
    assert own == common


def test_a_corpus_of_many_groups_gives_the_report_of_the_common_scale(monkeypatch):
    rng = random.Random(11)
    own, common = both_scales(groups_of([random_skeleton(rng) for _ in range(40)]), monkeypatch)
    assert own == common


@pytest.mark.parametrize("denominators", [[1, 1], [2, 3], [4, 6, 9]])
def test_scaled_by_part_scales_each_part_by_its_own_denominators(denominators):
    g = TimedEventGraph()
    for k, d in enumerate(denominators):
        g.add_transition(f"e{k}")
        g.add_place(k, k, 1, F(1, d), F(k, 2 * d))
    holding, initial, scales = g.scaled_by_part(np.arange(len(denominators)), len(denominators))
    assert scales == [d * (2 if k % 2 else 1) for k, d in enumerate(denominators)]
    for k, d in enumerate(denominators):
        assert F(int(holding[k]), scales[k]) == F(1, d)
        assert F(int(initial[k]), scales[k]) == F(k, 2 * d)
    one, _, (common, *_) = g.scaled_by_part(np.zeros(len(denominators), dtype=int), 1)
    assert common == g.arrays().scale and one.tolist() == g.arrays().holding.tolist()
