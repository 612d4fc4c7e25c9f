"""The dater simulation of a small graph in Python lists against the numpy steps.

``DaterSimulation`` steps a graph of at most ``_SMALL`` places in Python lists (a
group's upstream closure, hundreds of them at 10,000 tasks); with ``_SMALL = -1``
the same graph takes the numpy steps. Both must give the same daters, step by
step, of the same dtype: int64 until a dater passes 2**60, Python ints after.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tegraph.analysis import dynamics
from tegraph.analysis.dynamics import DaterSimulation, Regime, explore


@st.composite
def graphs(draw):
    """Places with tokens anywhere, 0-token places forward only (no token-free
    circuit); holding times small or near 2**61 (the steps then leave int64)."""
    n = draw(st.integers(1, 8))
    m = draw(st.integers(0, 20))
    src, dst, tokens = [], [], []
    for _ in range(m):
        a, b = draw(st.integers(0, n - 1)), draw(st.integers(0, n - 1))
        t = draw(st.integers(0, 3))
        if t == 0 and a >= b:
            if a == b:
                t = 1
            else:
                a, b = b, a
        src.append(a)
        dst.append(b)
        tokens.append(t)
    big = draw(st.booleans())
    holding = [draw(st.integers(0, 10)) + (2**61 if big and draw(st.booleans()) else 0)
               for _ in range(m)]
    initial = [draw(st.integers(0, 5)) for _ in range(m)]
    active = np.array([draw(st.integers(0, 5)) > 0 for _ in range(n)], dtype=bool)
    arrays = [np.array(v, dtype=np.int64) for v in (src, dst, tokens, holding, initial)]
    return (*arrays, n, active)


def run(graph, steps, small, monkeypatch):
    monkeypatch.setattr(dynamics, "_SMALL", 128 if small else -1)
    sim = DaterSimulation(*graph)
    assert (sim._small is not None) == small
    return [sim.step() for _ in range(steps)]


@settings(max_examples=300, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(graphs(), st.integers(1, 9))
def test_small_graphs_step_as_numpy_does(monkeypatch, graph, steps):
    lists = run(graph, steps, True, monkeypatch)
    arrays = run(graph, steps, False, monkeypatch)
    for a, b in zip(lists, arrays):
        assert a.dtype == b.dtype
        assert a.tolist() == b.tolist()


def test_a_small_ring_leaves_int64_and_keeps_its_daters(monkeypatch):
    # One event, a self-loop of 1 token holding 2**60 + 1: x(k) = (k - 1)(2**60 + 1);
    # x(2) passes 2**60, so x(3) on is made in Python ints.
    h = 2**60 + 1
    graph = (np.array([0]), np.array([0]), np.array([1]), np.array([h]), np.array([0]), 1,
             np.ones(1, dtype=bool))
    for small in (True, False):
        xs = run(graph, 4, small, monkeypatch)
        assert [x.tolist() for x in xs] == [[0], [h], [2 * h], [3 * h]]
        assert [x.dtype for x in xs] == [np.int64, np.int64, object, object]


@pytest.mark.parametrize("small", [True, False])
def test_explore_finds_the_regime_of_a_small_graph(monkeypatch, small):
    # a -> b (0 tokens, 2), b -> a (1 token, 3): period 5 from the first firing.
    graph = (np.array([0, 1]), np.array([1, 0]), np.array([0, 1]), np.array([2, 3]),
             np.array([0, 0]), 2, np.ones(2, dtype=bool))
    monkeypatch.setattr(dynamics, "_SMALL", 128 if small else -1)
    regime = Regime(np.array([0, 1]), 5, 1)
    explore(DaterSimulation(*graph), 1, [regime], [], 100)
    assert (regime.transient, regime.cyclicity) == (1, 1)
