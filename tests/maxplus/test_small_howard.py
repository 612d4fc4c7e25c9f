"""The small-graph kernel (Python lists) against the numpy kernel, result for result.

:mod:`maxplus._small_howard` claims to run the numpy kernel's iteration step
for step, so both must give not only the same ratio and cycle times (which
test_howard_brute_force checks against circuit enumeration for both) but the
same policy, potentials, critical circuit and iteration count: the outputs of
tegraph are built on those. Each path is forced by setting the crossover
``SMALL_GRAPH_ARCS`` (read at each call), so both run at every size.
"""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import maxplus._small_howard as small
from maxplus.cycle_ratio import max_cycle_ratio
from maxplus.errors import ZeroTokenCircuitError
from tests.maxplus.kernels import LISTS, NUMPY, assert_same, kernel
from tests.maxplus.test_howard_brute_force import (
    circuits_with_chains,
    dag_of_blocks,
    small_multigraphs,
)


def solve(limit, *args, **kwargs):
    """The result of max_cycle_ratio on one path, or the ZeroTokenCircuitError it raised."""
    with kernel(limit):
        try:
            return max_cycle_ratio(*args, **kwargs)
        except ZeroTokenCircuitError as e:
            return e


def same_result(*args, **kwargs):
    """Solve on both paths; assert everything the result carries is equal; return it."""
    ref = solve(NUMPY, *args, **kwargs)
    got = solve(LISTS, *args, **kwargs)
    assert_same(got, ref)
    return None if isinstance(ref, ZeroTokenCircuitError) else got


def arc_lists(arcs):
    return ([a for a, _, _, _ in arcs], [b for _, b, _, _ in arcs],
            [w for _, _, w, _ in arcs], [t for _, _, _, t in arcs])


@st.composite
def random_graphs(draw):
    """Several strongly connected blocks, arcs between them and chains below them.

    Zero-token arcs (a token-free circuit is possible, and must be refused
    alike), self-loops, parallel arcs, negative weights and, on request,
    weights beyond int64. Fans of many out-arcs reach the sweep's rounds of
    many nodes (the scan of all arcs, above 16 nodes and a sixteenth of them).
    """
    n = draw(st.integers(1, 80))
    node = st.integers(0, n - 1)
    big = draw(st.sampled_from([1, 1, 2**64 + 1]))
    weight = st.integers(-20, 50).map(lambda x: x * big)
    arcs = []
    blocks = draw(st.integers(1, 4))
    cut = sorted(draw(st.lists(st.integers(1, n), min_size=blocks - 1, max_size=blocks - 1)))
    bounds = [0, *cut, n]
    for lo, hi in zip(bounds, bounds[1:]):
        members = list(range(lo, hi))
        if not members or draw(st.booleans()) is False and len(members) > 1:
            continue  # no circuit here: nodes downstream only, or none
        for a, b in zip(members, members[1:] + members[:1]):
            arcs.append((a, b, draw(weight), draw(st.integers(1, 3))))
    if draw(st.booleans()):  # a fan: one node feeding many
        hub = draw(node)
        arcs += [(hub, v, draw(weight), draw(st.integers(0, 2))) for v in range(n)]
    arcs += draw(st.lists(st.tuples(node, node, weight, st.integers(0, 3)), max_size=3 * n))
    perm = draw(st.permutations(range(n)))
    arcs = [(perm[a], perm[b], w, t) for a, b, w, t in arcs]
    return n, list(draw(st.permutations(arcs)))


@st.composite
def fanned_layers(draw):
    """Self-loops of distinct ratios feeding a layer of 17-40 nodes, then a second layer.

    The first policy (heaviest in-arc) hangs the layer on a slow circuit; the
    ratio step moves it at once, a round of more than 16 nodes that are a large
    share of the graph: the numpy sweep scans all arcs (by head) there, so the
    list kernel must visit them in that order too. Arcs from the layer into a
    second one give several writers per head ("last write wins").
    """
    k = draw(st.integers(2, 4))  # circuits 0..k-1, ratio r_i on a self-loop
    ratios = sorted(draw(st.lists(st.integers(0, 30), min_size=k, max_size=k, unique=True)))
    width = draw(st.integers(20, 40))
    second = draw(st.integers(0, 30))
    n = k + width + second
    arcs = [(i, i, r, 1) for i, r in enumerate(ratios)]
    layer = range(k, k + width)
    for v in layer:  # heavy arcs from the slowest circuit, most nodes fed by the fastest
        arcs.append((0, v, draw(st.integers(10**3, 10**4)), draw(st.integers(0, 1))))
        for i in range(1, k):
            if draw(st.integers(0, 9)) < (8 if i == k - 1 else 4):
                arcs.append((i, v, draw(st.integers(-5, 10)), draw(st.integers(0, 1))))
    for v in range(k + width, n):
        for _ in range(draw(st.integers(1, 3))):
            arcs.append((draw(st.sampled_from(layer)), v, draw(st.integers(-5, 50)), 0))
    node = st.integers(0, n - 1)
    arcs += draw(st.lists(st.tuples(node, node, st.integers(-5, 50), st.integers(1, 2)),
                          max_size=5))
    perm = draw(st.permutations(range(n)))
    arcs = [(perm[a], perm[b], w, t) for a, b, w, t in arcs]
    return n, list(draw(st.permutations(arcs)))


@settings(deadline=None, suppress_health_check=list(HealthCheck), max_examples=100)
@given(fanned_layers())
def test_wide_sweeps_same_result(g):
    n, arcs = g
    same_result(*arc_lists(arcs), n_nodes=n)


@settings(deadline=None, suppress_health_check=list(HealthCheck), max_examples=300)
@given(random_graphs())
def test_random_graphs_same_result(g):
    n, arcs = g
    same_result(*arc_lists(arcs), n_nodes=n)


@settings(deadline=None, suppress_health_check=list(HealthCheck), max_examples=150)
@given(st.one_of(small_multigraphs(), circuits_with_chains(), dag_of_blocks()))
def test_brute_force_families_same_result(g):
    n, arcs = g
    same_result(*arc_lists(arcs), n_nodes=n)


@settings(deadline=None, suppress_health_check=list(HealthCheck), max_examples=60)
@given(random_graphs(), st.sampled_from(["3/7", "0.25"]))
def test_fractional_weights_same_result(g, factor):
    # Weights as exact strings: the scale (common denominator) is folded the same way.
    from fractions import Fraction
    n, arcs = g
    src, dst, w, t = arc_lists(arcs)
    same_result(src, dst, [str(x * Fraction(factor)) for x in w], t, n_nodes=n)


def test_numpy_arrays_in_and_object_weights():
    # A circuit 0 -> 1 -> 0 of ratio (2**70 + 2) / 2, node 2 downstream of it,
    # node 3 upstream of nothing: its cycle time is None.
    src, dst = np.array([0, 1, 1, 3]), np.array([1, 0, 2, 2])
    w = np.array([2**70, 2, 5, 7], dtype=object)
    r = same_result(src, dst, w, np.array([1, 1, 0, 0]), n_nodes=4)
    assert r.cycle_times == [2**69 + 1, 2**69 + 1, 2**69 + 1, None]
    assert r.certificate.potential.dtype == object


def test_token_free_circuit_refused_alike():
    # 1 -> 2 -> 1 carries no token, beside a circuit that does; named from the tail of
    # its first arc (arc 1, 1 -> 2), walking forward, on both paths.
    with pytest.raises(ZeroTokenCircuitError, match=r"circuit 1 -> 2 -> 1 \(arcs \[1, 2\]\)"):
        max_cycle_ratio([0, 1, 2, 0], [0, 2, 1, 1], [1, 1, 1, 1], [1, 0, 0, 1])
    same_result([0, 1, 2, 0], [0, 2, 1, 1], [1, 1, 1, 1], [1, 0, 0, 1])


def test_no_circuit_and_no_arc():
    for args, n in ((([], [], []), 4), (([], [], []), 0), (([0, 1], [1, 2], [3, 4]), 4)):
        r = same_result(*args, n_nodes=n)
        assert r.ratio is None and r.circuit.tolist() == [] and r.iterations == 0
        assert r.cycle_times == [None] * n


def test_token_counts_beyond_int64():
    # Circuit 0 -> 1 -> 0 with 2**64 + 1 tokens and weight 2 * (2**64 + 1): ratio 2;
    # the self-loop on 1 (weight 1, 1 token): ratio 1; both nodes see the circuit of ratio 2.
    big = 2**64 + 1
    r = same_result([0, 1, 1], [1, 0, 1], [2 * big, 0, 1], [big, 0, 1])
    assert r.cycle_times == [2, 2]


def test_small_graphs_skip_the_numpy_kernel(monkeypatch):
    # The point of the small path: no per-iteration numpy call. Before it
    # existed, every graph went through howard_arrays.
    def refuse(*args, **kwargs):
        raise AssertionError("the numpy kernel ran on a small graph")

    monkeypatch.setattr("maxplus.cycle_ratio.howard_arrays", refuse)
    r = max_cycle_ratio([0, 1, 1], [1, 0, 1], [5, 3, 3])
    assert r.cycle_times == [4, 4] and r.verify()
    with kernel(NUMPY), pytest.raises(AssertionError, match="numpy kernel ran"):
        max_cycle_ratio([0, 1, 1], [1, 0, 1], [5, 3, 3])


def test_long_chain_and_wide_sweep_same_result():
    # The sweep's rounds of many nodes (scan of all arcs) and a chain of 1,000 nodes
    # below a slow and a fast circuit: both kernels switch the same arcs.
    L = 1000
    src, dst, w, t = [0, 1, 0, 1], [0, 1, 2, 2], [1, 100, 1000, 0], [1, 1, 0, 0]
    for k in range(2, L + 1):
        src.append(k), dst.append(k + 1), w.append(k % 7), t.append(0)
    for k in range(2, L + 1, 3):  # fans out of the chain
        src.append(0), dst.append(k), w.append(5000), t.append(1)
        src.append(1), dst.append(k), w.append(0), t.append(1)
    same_result(src, dst, w, t, n_nodes=L + 2)


@pytest.mark.parametrize("n", [10, 100, 1000])
def test_sprand_same_result(n):
    import sys
    from pathlib import Path
    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
    from sprand import sprand

    same_result(*sprand(n, seed=n))



def test_list_kernel_never_revisits_a_policy(monkeypatch):
    # As the numpy kernel (test_mp_kernel_termination): a broken improvement step
    # that keeps "improving" without changing anything ends in an error, not a hang.
    original = small._Iteration.improve

    def stuck(self, pol, cur, todo):
        original(self, pol, cur, todo)
        return "bias"

    monkeypatch.setattr(small._Iteration, "improve", stuck)
    with kernel(LISTS), pytest.raises(RuntimeError, match="revisited a policy"):
        max_cycle_ratio([0, 0, 1], [0, 1, 1], [5, 0, 1], [1, 0, 1])
