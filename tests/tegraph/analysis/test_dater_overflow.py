"""A step of the dater simulation that would pass int64 runs on Python ints from the start.

Found by review: daters are checked against 2**60 after each step, but one step adds a
whole token-free path's holding times, so three places of holding time 2**62 - 1 in a
row wrapped to a negative dater (the numpy path) or raised OverflowError (the list path).
"""

from __future__ import annotations

import numpy as np
import pytest

from tegraph.analysis.dynamics import DaterSimulation

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
