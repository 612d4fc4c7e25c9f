"""The sweep's small rounds, walked in Python, against its vectorized rounds.

``_sweep_downstream`` passes a larger ratio down the graph round by round; a
round of at most ``SWEEP_FEW`` nodes is walked element by element
(``_sweep_few``), a larger one with numpy. Both must switch the same policies
in the same order, so that Howard's iteration is the same whichever walks.
Deep chains below a circuit (each round one node: the shape of a skeleton's
ASYN/SYN chain) and fans (rounds that grow past ``SWEEP_FEW`` and come back)
make the two disagree if either changes the order of its visits.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import maxplus.policy_iteration as pi


def solve(src, dst, w, t, n, few):
    saved = pi.SWEEP_FEW
    pi.SWEEP_FEW = few
    try:
        return pi.howard_arrays(np.array(src), np.array(dst), np.array(w, dtype=np.int64),
                                np.array(t, dtype=np.int64), n)
    finally:
        pi.SWEEP_FEW = saved


def same(a, b):
    return (a.ratio_num.tolist() == b.ratio_num.tolist()
            and a.ratio_den.tolist() == b.ratio_den.tolist()
            and a.potential.tolist() == b.potential.tolist()
            and a.policy.tolist() == b.policy.tolist() and a.iterations == b.iterations)


@st.composite
def circuits_with_tails(draw):
    # Two circuits (nodes 0-1 and 2-3) and a tail of nodes, each fed by one or more
    # earlier nodes: the tail's nodes reach a circuit's ratio only by the sweep.
    length = draw(st.integers(1, 60))
    src, dst, w, t = [0, 1, 2, 3], [1, 0, 3, 2], [5, 3, 1, 1], [1, 1, 1, 1]
    for v in range(4, 4 + length):
        for _ in range(draw(st.integers(1, 3))):
            src.append(draw(st.integers(0, v - 1)))
            dst.append(v)
            w.append(draw(st.integers(-5, 20)))
            t.append(draw(st.integers(0, 2)))
    return src, dst, w, t, 4 + length


@given(circuits_with_tails())
@settings(max_examples=150, deadline=None)
def test_small_rounds_in_python_switch_as_the_vectorized_ones(graph):
    src, dst, w, t, n = graph
    walked, vectorized = solve(*graph, few=pi.SWEEP_FEW), solve(*graph, few=0)
    assert same(walked, vectorized)
    # Both are Howard's answer: the circuit 0 -> 1 -> 0 has ratio (5 + 3)/2 = 4, the
    # other 1; every tail node is reached from node 0, 1, 2 or 3 by its feeders.
    assert walked.ratio_num[0] * 1 == 4 * walked.ratio_den[0]


@pytest.mark.parametrize("length", [1, 17, 5000])
def test_a_deep_chain_takes_its_circuit_ratio_all_the_way_down(length):
    # Node 0 on a self-loop of ratio 7/2, then a chain 0 -> 1 -> ... -> length, each
    # node also on a self-loop of ratio 1: every chain node runs at 7/2 (the
    # largest ratio upstream, Baccelli et al. Thm 3.112), as both walks find.
    n = length + 1
    src = [0] + list(range(length)) + list(range(1, n))
    dst = [0] + list(range(1, n)) + list(range(1, n))
    w = [7] + [1] * length + [1] * length
    t = [2] + [1] * length + [1] * length
    walked, vectorized = solve(src, dst, w, t, n, pi.SWEEP_FEW), solve(src, dst, w, t, n, 0)
    assert same(walked, vectorized)
    assert set(zip(walked.ratio_num.tolist(), walked.ratio_den.tolist())) == {(7, 2)}
