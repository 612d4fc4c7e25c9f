"""The compiled Howard kernel against the numpy kernel, result for result.

:mod:`maxplus._howard_kernel` claims to run the numpy kernel's iteration step
for step, so both must give the same ratio, cycle times, policy, potentials,
critical circuit and iteration count (the outputs of tegraph are built on
them). Each kernel is chosen by the switch ``maxplus._kernels`` (``kernel``
here), so both run at every size. Data past the compiled kernel's bound, or
potentials that reach ``2**62`` on the way, fall back to the numpy kernel:
also tested.
"""
from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from maxplus import _kernels
from maxplus.cycle_ratio import max_cycle_ratio
from maxplus.errors import ZeroTokenCircuitError
from tests.maxplus.kernels import COMPILED, NUMPY, assert_same, kernel
from tests.maxplus.test_howard_brute_force import (
    circuits_with_chains,
    dag_of_blocks,
    small_multigraphs,
)

compiled = pytest.importorskip("maxplus._howard_kernel")


def numpy_kernel(use_compiled):
    """max_cycle_ratio on the compiled kernel or on the numpy kernel, whatever the size."""
    return kernel(COMPILED if use_compiled else NUMPY)


def solve(use_compiled, *args, **kwargs):
    """max_cycle_ratio on the numpy kernel, compiled or not; or the error it raised."""
    with numpy_kernel(use_compiled):
        try:
            return max_cycle_ratio(*args, **kwargs)
        except ZeroTokenCircuitError as e:
            return e


def same_result(*args, **kwargs):
    got, ref = solve(True, *args, **kwargs), solve(False, *args, **kwargs)
    assert_same(got, ref)
    return got


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
    compiled kernel must visit them in that order too. Arcs from the layer into a
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


@st.composite
def scaled_graphs(draw):
    """random_graphs with weights and tokens scaled up: some runs leave int64 on the way.

    Weights up to ``50 * 2**55`` and tokens up to ``3 * 2**40``: the compiled
    kernel's bound (``2 n max(|w|, t) < 2**62``) refuses some graphs outright,
    and on others the potentials, sums of ``w T - W t``, reach ``2**62``
    during the iteration, where the compiled kernel hands over to numpy.
    """
    n, arcs = draw(random_graphs())
    w_scale = draw(st.sampled_from([1, 2**20, 2**40, 2**55]))
    t_scale = draw(st.sampled_from([1, 2**30, 2**40]))
    return n, [(a, b, w * w_scale if isinstance(w, int) and abs(w) < 2**63 else w,
                t * t_scale) for a, b, w, t in arcs]


@settings(deadline=None, suppress_health_check=list(HealthCheck), max_examples=300)
@given(random_graphs())
def test_random_graphs_same_result(g):
    n, arcs = g
    same_result(*arc_lists(arcs), n_nodes=n)


@settings(deadline=None, suppress_health_check=list(HealthCheck), max_examples=100)
@given(fanned_layers())
def test_wide_sweeps_same_result(g):
    n, arcs = g
    same_result(*arc_lists(arcs), n_nodes=n)


@settings(deadline=None, suppress_health_check=list(HealthCheck), max_examples=150)
@given(st.one_of(small_multigraphs(), circuits_with_chains(), dag_of_blocks()))
def test_brute_force_families_same_result(g):
    n, arcs = g
    same_result(*arc_lists(arcs), n_nodes=n)


@settings(deadline=None, suppress_health_check=list(HealthCheck), max_examples=150)
@given(scaled_graphs())
def test_large_numbers_same_result(g):
    n, arcs = g
    same_result(*arc_lists(arcs), n_nodes=n)


@settings(deadline=None, suppress_health_check=list(HealthCheck), max_examples=60)
@given(random_graphs(), st.sampled_from(["3/7", "0.25"]))
def test_fractional_weights_same_result(g, factor):
    from fractions import Fraction
    n, arcs = g
    src, dst, w, t = arc_lists(arcs)
    same_result(src, dst, [str(x * Fraction(factor)) for x in w], t, n_nodes=n)


@pytest.mark.parametrize("n", [10, 100, 1000, 5000])
@pytest.mark.parametrize("seed", [1, 2])
def test_sprand_same_result(n, seed):
    import sys
    from pathlib import Path
    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
    from sprand import sprand

    same_result(*sprand(n, seed=seed))


def test_equal_weights_and_long_chain_same_result():
    # All weights equal (every circuit critical, one iteration), then a chain of
    # 2,000 nodes below a slow and a fast circuit with fans out of it (deep sweeps).
    rng = np.random.default_rng(5)
    n = 3000
    src = np.concatenate([np.arange(n), rng.integers(0, n, 3 * n)])
    dst = np.concatenate([(np.arange(n) + 1) % n, rng.integers(0, n, 3 * n)])
    same_result(src, dst, np.full(len(src), 7), np.ones(len(src), dtype=np.int64))
    L = 2000
    src, dst, w, t = [0, 1, 0, 1], [0, 1, 2, 2], [1, 100, 1000, 0], [1, 1, 0, 0]
    for k in range(2, L + 1):
        src.append(k), dst.append(k + 1), w.append(k % 7), t.append(0)
    for k in range(2, L + 1, 3):
        src.append(0), dst.append(k), w.append(5000), t.append(1)
        src.append(1), dst.append(k), w.append(0), t.append(1)
    same_result(src, dst, w, t, n_nodes=L + 2)


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


def howard_direct(src, dst, w, t, n):
    return compiled.howard(np.array(src), np.array(dst), np.array(w, dtype=np.int64),
                           np.array(t, dtype=np.int64), n, _kernels.current().sweep_few,
                           _kernels.current().scan_min_share)


def test_compiled_kernel_runs_on_int64_data(monkeypatch):
    # The handle is used whenever the data are int64: a kernel that refuses to run is noticed.
    def refuse(*args):
        raise AssertionError("compiled kernel ran")

    monkeypatch.setattr(compiled, "howard", refuse)
    with numpy_kernel(True), pytest.raises(AssertionError, match="compiled kernel ran"):
        max_cycle_ratio([0, 1, 1], [1, 0, 1], [5, 3, 3])
    with pytest.raises(AssertionError, match="compiled kernel ran"):  # the default, any size
        max_cycle_ratio([0, 1, 1], [1, 0, 1], [5, 3, 3])
    with numpy_kernel(True):  # Python ints never reach it
        r = max_cycle_ratio([0, 1, 1], [1, 0, 1], [2**64, 3, 3])
    assert r.ratio == Fraction(2**64 + 3, 2)


@pytest.mark.parametrize("w, t", [(2**61, 1), (-(2**61), 1), (5, 2**61), (-(2**63), 1),
                                  (2**62 // 6 + 1, 1)])
def test_numbers_past_the_bound_left_to_numpy(w, t):
    # 2 n max(|w|, t) < 2**62 with n = 3 (the numpy kernel's first bound), checked by
    # the compiled kernel itself: past it (by one, the last case), None.
    args = ([0, 1, 1, 1], [1, 0, 1, 2], [w, 3, 3, 1], [t, 1, 1, 0])
    assert howard_direct(*args, 3) is None
    same_result(*args)
    w_in = 2**62 // 6 - 1 if w > 0 else -(2**62 // 6 - 1)
    assert howard_direct([0, 1, 1, 1], [1, 0, 1, 2], [w_in, 3, 3, 1], [1, 1, 1, 0], 3)


def test_potentials_past_2_62_hand_over_to_numpy():
    # Node 2 hangs below the self-loop on 1 (ratio 2**40 - 7) by an arc of 2**40
    # tokens: its potential is about -(2**40 - 7) * 2**40 = -2**80. The compiled
    # kernel stops (None); max_cycle_ratio then gives the numpy kernel's result
    # in Python ints.
    args = ([0, 1, 1, 1], [1, 0, 1, 2], [2**40, 1, 2**40 - 7, 5], [2**40, 0, 1, 2**40])
    assert howard_direct(*args, 3) is None
    r = same_result(*args)
    assert r.certificate.potential.dtype == object


def test_compiled_result_is_the_solution():
    # The tuple the kernel returns, field by field (policy as the caller's arc indices).
    W, T, X, policy, iterations = howard_direct([0, 1, 1], [1, 0, 1], [5, 3, 3], [1, 1, 1], 2)
    assert (W.tolist(), T.tolist(), policy.tolist(), iterations) == ([4, 4], [1, 1], [1, 0], 1)
    assert X.tolist() == [0, 1]


def test_numpy_path_when_the_kernel_gives_up(monkeypatch):
    # A compiled run that returns None (past 2**62, or a repeated policy) costs a
    # numpy run, never a wrong or missing answer.
    monkeypatch.setattr(compiled, "howard", lambda *args: None)
    with numpy_kernel(True):
        r = max_cycle_ratio([0, 1, 1], [1, 0, 1], [5, 3, 3])
    assert r.ratio == 4 and r.iterations == 1 and r.verify()


@settings(deadline=None, suppress_health_check=list(HealthCheck), max_examples=300)
@given(random_graphs(), st.sampled_from([np.int32, np.int64]))
def test_the_checks_around_howard_in_c_are_the_numpy_ones(g, index):
    # Kahn's algorithm in C against scipy's strong components: the nodes some circuit
    # reaches, and whether the token-free arcs hold a circuit.
    from maxplus._arrays import find_circuit
    from maxplus.cycle_ratio import _nodes_reached_by_circuits

    n, arcs = g
    src, dst, _, t = (np.array(x) for x in arc_lists(arcs))
    src, dst, t = src.astype(index), dst.astype(index), t.astype(np.int64)
    off, dropped = compiled.off_circuits(src, dst, n)
    with kernel(NUMPY):
        live = _nodes_reached_by_circuits(src, dst, n)
    assert (~off).tolist() == ([True] * n if live is None else live.tolist())
    assert dropped == int(off.sum())
    zero = np.flatnonzero(t == 0)
    assert (compiled.off_circuits(src, dst, n, t)[1] < n) == bool(find_circuit(src, dst, n, zero))


@settings(deadline=None, max_examples=300)
@given(st.lists(st.tuples(st.integers(-2**62, 2**62), st.integers(1, 2**62)), min_size=1,
                max_size=30))
def test_the_best_node_in_c_is_argmax_ratio(ratios):
    # The first largest num/den, exact in 128 bits, against the float shortlist and the
    # exact tournament of argmax_ratio.
    from maxplus._arrays import argmax_ratio

    num, den = (np.array(x, dtype=np.int64) for x in zip(*ratios))
    assert compiled.first_largest_ratio(num, den) == argmax_ratio(num, den)


def walk_both(start, policy, src):
    from maxplus.cycle_ratio import _policy_circuit

    got = _policy_circuit(start, policy, src)
    with kernel(NUMPY):
        ref = _policy_circuit(start, policy, src)
    assert got.tolist() == ref.tolist()
    return got


@settings(deadline=None, suppress_health_check=list(HealthCheck), max_examples=300)
@given(st.integers(1, 40).flatmap(lambda n: st.tuples(
    st.just(n), st.integers(0, n - 1),
    st.lists(st.integers(0, 2 * n - 1), min_size=n, max_size=n),
    st.lists(st.integers(0, n - 1), min_size=2 * n, max_size=2 * n),
    st.sampled_from([np.int32, np.int64]))))
def test_policy_circuit_walk_same(g):
    # Brent's walk in C against the walk in Python, from every node of random policies.
    n, start, policy, src, dtype = g
    for s in range(n):
        walk_both(s, np.array(policy, dtype=np.int64), np.array(src, dtype=dtype))


def test_policy_circuit_without_policy_arc():
    # A walk that meets a node without a policy arc: the compiled walk leaves it to Python.
    # Node 0's policy arc (0) comes from 2, node 2's (1) from 0; node 1 has none.
    policy, src = np.array([0, -1, 1], dtype=np.int64), np.array([2, 0], dtype=np.int64)
    assert compiled.policy_circuit(1, policy, src) is None
    assert compiled.policy_circuit(0, policy, src).tolist() == [1, 0]
    assert walk_both(2, policy, src).tolist() == [0, 1]


def test_policy_circuit_long_walk_same():
    # A walk of 20,000 steps into a circuit of 7,000 (the Python walk hands over to
    # its depth-first search in C past 4,096 steps).
    n = 27000
    src = np.arange(n, dtype=np.int32) - 1
    src[0] = 6999  # node k's policy arc comes from k - 1; 0 from 6,999: circuit 0..6,999
    policy = np.arange(n, dtype=np.int64)
    arcs = walk_both(n - 1, policy, src)
    assert len(arcs) == 7000 and arcs[0] == 0 and arcs.tolist() == sorted(arcs.tolist())
