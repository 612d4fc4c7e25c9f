"""The topological levels of the dater simulation: numpy passes against Kahn in Python.

``_breadth_levels`` (one numpy pass per level) and ``_kahn_levels`` (Python)
must give the same level to every event: the longest path from a source, in
0-token places. The breadth pass hands a thin DAG to Kahn; these tests check
that it does so for a broad head followed by a long thin tail (a clock per
task), and that the two agree wherever the breadth pass answers.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph.analysis.dynamics import _THIN, _breadth_levels, _kahn_levels


def _both(n, src, dst):
    src, dst = np.asarray(src, dtype=np.int64), np.asarray(dst, dtype=np.int64)
    active = np.ones(n, dtype=bool)
    order = np.argsort(src, kind="stable")
    args = (n, src[order], dst[order], dst, active)
    return _breadth_levels(*args), _kahn_levels(*args)


def _broad_head_thin_tail(width, length):
    # Events 0..width-1 are sources (ticks), all feeding event `width`, the head of a
    # chain width -> width+1 -> ... of `length` events: level of width + i is 1 + i.
    src = list(range(width)) + list(range(width, width + length - 1))
    dst = [width] * width + list(range(width + 1, width + length))
    return width + length, src, dst


def test_a_broad_head_then_a_long_thin_tail_goes_to_kahn():
    # 3 * 2 * _THIN * _THIN sources pass the first checkpoint (2 * _THIN levels
    # holding 3 * _THIN places each on average), then the tail holds one place per
    # level: the next checkpoint (4 * _THIN levels) sees 2 * _THIN places in
    # 2 * _THIN levels and hands over. Before the doubling checkpoints, every level
    # of the tail cost a numpy pass.
    width = 3 * 2 * _THIN * _THIN
    n, src, dst = _broad_head_thin_tail(width, 50 * _THIN)
    breadth, kahn = _both(n, src, dst)
    assert breadth is None
    assert kahn[:width].tolist() == [0] * width
    assert kahn[width:].tolist() == list(range(1, 50 * _THIN + 1))


def test_a_broad_dag_stays_with_numpy():
    # A grid of width 4 * _THIN: each level holds 4 * _THIN places, never thin.
    width, depth = 4 * _THIN, 8 * _THIN
    src, dst = [], []
    for lev in range(depth - 1):
        for i in range(width):
            src.append(lev * width + i)
            dst.append((lev + 1) * width + (i + 1) % width)
    breadth, kahn = _both(width * depth, src, dst)
    assert breadth is not None
    assert breadth.tolist() == kahn.tolist() == [e // width for e in range(width * depth)]


@st.composite
def _dags(draw):
    n = draw(st.integers(1, 300))
    m = draw(st.integers(0, 3 * n))
    pairs = draw(st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)),
                          min_size=m, max_size=m))
    # Forward places only (a < b): a DAG; some events are sources, some isolated.
    src = [min(a, b) for a, b in pairs if a != b]
    dst = [max(a, b) for a, b in pairs if a != b]
    return n, src, dst


@settings(max_examples=200, deadline=None)
@given(_dags())
def test_breadth_levels_equal_kahn_levels(dag):
    breadth, kahn = _both(*dag)
    if breadth is not None:
        assert breadth.tolist() == kahn.tolist()


@settings(max_examples=30, deadline=None)
@given(st.integers(2 * _THIN, 12 * _THIN), st.integers(1, 300))
def test_broad_heads_and_thin_tails_of_any_size_agree(width, length):
    n, src, dst = _broad_head_thin_tail(width, length)
    breadth, kahn = _both(n, src, dst)
    expected = [0] * width + list(range(1, length + 1))
    assert kahn.tolist() == expected
    if breadth is not None:
        assert breadth.tolist() == expected
