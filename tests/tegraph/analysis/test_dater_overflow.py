"""Daters past int64: a step that would pass it runs on Python ints from the start, and a
state is keyed by its values alone on either side of the boundary.

Found by review: daters are checked against 2**60 after each step, but one step adds a
whole token-free path's holding times, so three places of holding time 2**62 - 1 in a
row wrapped to a negative dater (the numpy path) or raised OverflowError (the list path).
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given

from tegraph import Skeleton, analyze
from tegraph.analysis.dynamics import DaterSimulation
from tests.tegraph.analysis.test_analysis_properties import SETTINGS, any_skeleton

H = 2**62 - 1


@pytest.mark.parametrize("readers", [0, 300])  # 0: the list path; 300: the numpy path
def test_a_step_past_int64_gives_the_exact_daters(readers):
    # Event 0 has a self-loop (one token, available at 0, holding H) and feeds the
    # token-free chain 0 -> 1 -> 2 -> 3 (holding H each) and `readers` events (holding 1).
    # x0(1) = 0 (the initial token), then each event of the chain H later:
    # x(1) = [0, H, 2H, 3H]; x0(2) = x0(1) + H = H, so x(2) = [H, 2H, 3H, 4H].
    src = [0, 0, 1, 2] + [0] * readers
    dst = [0, 1, 2, 3] + list(range(4, 4 + readers))
    hold = [H, H, H, H] + [1] * readers
    tokens = np.zeros(len(src), dtype=np.int64)
    tokens[0] = 1
    sim = DaterSimulation(np.array(src), np.array(dst), tokens, np.array(hold, dtype=np.int64),
                          np.zeros(len(src), dtype=np.int64), 4 + readers)
    assert [int(v) for v in sim.step()[:4]] == [0, H, 2 * H, 3 * H]
    assert [int(v) for v in sim.step()[:4]] == [H, 2 * H, 3 * H, 4 * H]


def test_small_times_keep_int64():
    # The same graph with holding time 5: the room of one step is 5 * 4, far from int64.
    src, dst = np.array([0, 0, 1, 2]), np.array([0, 1, 2, 3])
    sim = DaterSimulation(src, dst, np.array([1, 0, 0, 0]), np.full(4, 5, dtype=np.int64),
                          np.zeros(4, dtype=np.int64), 4)
    assert sim.dtype is np.int64
    assert sim.step().tolist() == [0, 5, 10, 15]


# ------------------------------------------- one state key across the int64 boundary

@pytest.mark.parametrize("period", [2**61, 3 * 2**59, 3 * 2**60 - 1])
def test_a_transient_across_the_int64_boundary_is_the_exact_one(period):
    # One task on its own clock of period P, duration 1 (< P). By §3,
    # x_tick(k) = (k - 1)·P, and x_activate(k) = x_compute(k) = x_tick(k): the
    # return place adds 1 < P, so the tick always comes last. Hence
    # x_e(k + 1) = x_e(k) + P for every event from k = 1: transient K = 1, c = 1.
    # The daters pass 2**62 between the states compared (2**61 -> 2**62 for
    # P = 2**61): the key of a state must not depend on the type that held it.
    sk = Skeleton.from_dict({"tasks": {"T0": {"period": period, "duration": 1}}})
    (group,) = analyze(sk).groups
    assert group.period == period
    assert group.transient == (1, 1)


def _times_scaled(data: dict, factor: int) -> dict:
    """The skeleton dictionary with every duration, period and phase times ``factor``."""
    def times(value):
        v = Fraction(str(value)) * factor
        return str(v.numerator) if v.denominator == 1 else f"{v.numerator}/{v.denominator}"

    out = {**data, "clocks": {c: {k: times(v) for k, v in spec.items()}
                              for c, spec in data.get("clocks", {}).items()}}
    out["tasks"] = {t: {k: (times(v) if k in ("duration", "period", "phase") else v)
                        for k, v in spec.items()} for t, spec in data["tasks"].items()}
    return out


@SETTINGS
@given(any_skeleton)
def test_scaling_every_time_by_2_56_keeps_every_transient(data):
    # Multiplying every time by a constant multiplies every dater by it (§3 is
    # homogeneous of degree one in the holding times and the availabilities), so
    # each group's period is multiplied by it and its transient and cyclicity
    # stay the same. At 2**56 the daters of these small skeletons (periods and
    # durations up to 10, a few dozen firings) cross 2**62 as the search runs.
    small = analyze(Skeleton.from_dict(data, name="random"), max_steps=20_000)
    big = analyze(Skeleton.from_dict(_times_scaled(data, 2**56), name="random"),
                  max_steps=20_000)
    assert [g.tasks for g in big.groups] == [g.tasks for g in small.groups]
    for g, h in zip(small.groups, big.groups):
        assert h.period == (None if g.period is None else g.period * 2**56)
        assert h.transient == g.transient, g.tasks
