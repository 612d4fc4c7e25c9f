"""regime_bounds.autonomous_from: K* derived by hand, in integer units of 1/D."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from tegraph.analysis.regime_bounds import autonomous_from


@pytest.mark.parametrize("scale", [1, 3, 10])
def test_k_star_by_hand_with_a_cycle_time_finer_than_the_scale(scale):
    # Event F (0): a self-loop of 2 tokens and holding 3, so mu = 3/2, whose
    # denominator 2 divides no scale here: the bounds' unit 1/D is finer than
    # the daters' 1/scale. Event S (1): a clock-like self-loop (1 token, 2), P = 2;
    # the crossing place F -> S holds 1.
    #   x_F = 0, 0, 3, 3, 6, ... ; potentials V_F = 0 (weight 3 - 2·3/2 = 0);
    #   beta = max(0 - 1·3/2, 0 - 2·3/2) = -3/2; y_S(k) = 2(k-1): regime from
    #   k = 1, L_S = 0 - 2 = -2; need = (V_F - 0 + beta + 1 - L_S) / (P - mu)
    #   = (-3/2 + 1 + 2) / (1/2) = 3, so K* = 3 (indeed x_F(k) + 1 > y_S(k) at k = 1 only).
    # Times are given scaled by `scale`: the answer must not depend on it.
    src, dst = np.array([0, 1, 0]), np.array([0, 1, 1])
    tokens = np.array([2, 1, 0])
    holding = np.array([3, 2, 1]) * scale
    initial = np.zeros(3, dtype=np.int64)
    found = autonomous_from(np.array([0, 1]), [Fraction(3, 2), Fraction(2)], Fraction(2),
                            src, dst, tokens, holding, initial, scale, 2, 1000)
    assert found is not None
    slow, k_star = found
    assert slow.tolist() == [1] and k_star == 3


def test_no_crossing_place_gives_the_slow_events_from_the_first_firing():
    # The same S alone, and F downstream of nothing of S: no place from F into S.
    src, dst = np.array([0, 1]), np.array([0, 1])
    found = autonomous_from(np.array([0, 1]), [Fraction(3, 2), Fraction(2)], Fraction(2),
                            src, dst, np.array([2, 1]), np.array([3, 2]), np.zeros(2, np.int64),
                            1, 2, 1000)
    assert found is not None and found[0].tolist() == [1] and found[1] == 1
