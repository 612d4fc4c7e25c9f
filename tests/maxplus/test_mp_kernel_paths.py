"""The kernel's alternative paths give the answers of its main ones.

Speed work added paths taken only on large inputs (a policy walk finished in
C past ``walk_in_python`` steps, ...). Each is forced here on a small graph
whose answer is derived by hand, so the path is tested without a large input.
"""
from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import maxplus
import maxplus.policy_iteration as pi
from tests.maxplus.kernels import kernel

from .test_howard_brute_force import check, circuits_with_chains, small_multigraphs

# These tests reach the numpy kernel's own strategies (thresholds, caches, fallbacks):
# where it is built, max_cycle_ratio would run the compiled kernel instead.
pytestmark = pytest.mark.usefixtures("numpy_kernel")


def ring(n: int, chord_weight: int = 1):
    """Ring 0 -> 1 -> ... -> n-1 -> 0 of weight 3 per arc (arcs 0..n-1), plus chords i -> i+2.

    A chord (arc n + i) skips one node for ``chord_weight``; with weight 1
    (against 3 + 3 = 6 along the ring) every chord is worse, so the critical
    circuit is the whole ring: ratio 3n / n = 3, arcs 0..n-1.
    """
    nodes = np.arange(n)
    src = np.concatenate([nodes, nodes])
    dst = np.concatenate([(nodes + 1) % n, (nodes + 2) % n])
    w = np.concatenate([np.full(n, 3), np.full(n, chord_weight)])
    return src, dst, w


@pytest.mark.parametrize("walk_in_python", [2, 5, 4096])
def test_a_long_policy_circuit_is_walked_in_c(walk_in_python):
    n = 40
    src, dst, w = ring(n)
    with kernel(walk_in_python=walk_in_python):
        r = maxplus.max_cycle_ratio(src, dst, w)
    assert r.ratio == 3
    # The circuit starts wherever the solver's best node is; as a rotation of
    # the ring's arcs it is 0, 1, ..., n-1 read from some arc k.
    k = int(r.circuit[0])
    assert r.circuit.tolist() == [(k + i) % n for i in range(n)]
    # policy_circuit(v): the walk v, v-1, ... closes on v, so the circuit
    # read forward starts with v's out-arc on the ring, arc v (by hand above).
    with kernel(walk_in_python=walk_in_python):
        for v in (0, 7, n - 1):
            assert r.policy_circuit(v).tolist() == [(v + i) % n for i in range(n)]
        assert r.verify()


def test_a_walk_in_c_from_a_node_below_the_circuit():
    """Node 3 hangs below the 2-circuit 0 <-> 1 by the path 1 -> 2 -> 3."""
    with kernel(walk_in_python=1):
        # arcs: 0: 0->1 (w 5), 1: 1->0 (w 3), 2: 1->2, 3: 2->3; ratio (5 + 3) / 2 = 4
        r = maxplus.max_cycle_ratio([0, 1, 1, 2], [1, 0, 2, 3], [5, 3, 1, 1])
        assert r.ratio == Fraction(4)
        # The walk 3, 2, 1, 0 closes on 1 (pred of 0): circuit nodes 1, 0, forward arcs
        # 1->0, 0->1.
        assert r.policy_circuit(3).tolist() == [1, 0]
        assert r.policy_circuit(0).tolist() == [0, 1]


# --------------------------------------------------------------------------- fallbacks

def fallback_paths(scan: bool):
    """The paths large or unusual graphs take: the bias step's segmented maximum by
    ``reduceat`` (many distinct in-degrees), circuits by pointer jumping (more than
    256 circuit nodes), the policy walk in C, and every sweep round either by a scan
    of all arcs (``scan``) or by gathering the out-arcs of its nodes; the counting
    sort by scipy's public sparse conversion (a scipy without the private routine),
    and int32 indices (graphs of more than ``intp_max_arcs`` arcs)."""
    return kernel(max_degree_blocks=0, python_max_circuit_nodes=0, sweep_few=0,
                  scan_min_share=10**9 if scan else 0, rows_min_level=0,
                  scipy_coo_tocsr=False, intp_max_arcs=0, walk_in_python=1)


@pytest.mark.parametrize("scan", [True, False])
@settings(deadline=None, suppress_health_check=list(HealthCheck), max_examples=40)
@given(g=small_multigraphs())
def test_fallbacks_on_small_multigraphs(scan, g):
    with fallback_paths(scan):
        check(*g)  # against circuit enumeration (test_howard_brute_force)


@pytest.mark.parametrize("scan", [True, False])
@settings(deadline=None, suppress_health_check=list(HealthCheck), max_examples=40)
@given(g=circuits_with_chains())
def test_fallbacks_on_circuits_with_chains(scan, g):
    n, arcs = g
    if n > 60:
        return
    with fallback_paths(scan):
        check(n, arcs)


def test_block_maxima_find_the_first_best_in_arc():
    """Nodes of in-degrees 2, 1 and 3 (three blocks), the best in-arcs found by hand.

    Arcs into node 0: from 1 (w 1) and 2 (w 5); into 1: from 0 (w 2); into 2:
    from 0 (w 1), 1 (w 0), 2 (w 3). With X = 0 everywhere and W/T = 0/1, the
    term of an arc is its weight: node 0's best is 5 (its 2nd in-arc), node 1's
    2 (its only one), node 2's 3 (its 3rd), all beating X = 0.
    """
    src = np.array([1, 2, 0, 0, 1, 2])
    dst = np.array([0, 0, 1, 2, 2, 2])
    w = np.array([1, 5, 2, 1, 0, 3])
    t = np.ones(6, dtype=np.int64)
    arcs = pi._InArcs(src, dst, w, t, 3)
    terms = pi._ArcTerms(arcs, pi._Bounds(arcs))
    nodes, best = terms.best_values(np.zeros(3, dtype=np.int64), 0, 1, 0)
    assert len(terms.blocks) == 3
    order = np.argsort(nodes)
    assert nodes[order].tolist() == [0, 1, 2]
    assert (best[order] >> terms.bits).tolist() == [5, 2, 3]
    # The low bits rank the arc from the last possible in-arc: offset = (D - 1) - rank.
    offset = (terms.degree_max - 1) - (best[order] & ((1 << terms.bits) - 1))
    assert offset.tolist() == [1, 0, 2]
    assert terms.terms(0, 1, None).tolist() == [1, 5, 2, 1, 0, 3]  # sorted by head: w
    assert terms.terms(0, 1, np.array([1, 5])).tolist() == [5, 3]


@settings(deadline=None, max_examples=60)
@given(st.lists(st.integers(0, 9), max_size=40))
def test_stable_order_with_and_without_the_private_conversion(keys):
    """Both counting sorts give numpy's stable argsort and the segment offsets."""
    keys = np.array(keys, dtype=np.int64)
    expected = np.argsort(keys, kind="stable").tolist()
    offsets = np.searchsorted(np.sort(keys), np.arange(11)).tolist()  # 10 keys: 11 offsets
    for private, intp_max in ((True, 10**9), (False, 10**9), (True, 0), (False, 0)):
        with kernel(scipy_coo_tocsr=private, intp_max_arcs=intp_max):
            order, starts = pi.stable_order(keys, 10)
        assert order.tolist() == expected and starts.tolist() == offsets
        assert order.dtype == (np.intp if intp_max else np.int32)


@settings(deadline=None, max_examples=80)
@given(st.integers(1, 8).flatmap(lambda n: st.tuples(
    st.just(n),
    st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1), st.integers(-3, 3)),
             min_size=0, max_size=30))))
def test_initial_policy_by_blocks_is_the_first_heaviest_in_arc(g):
    """The policy found by blocks of equal in-degree is, per node, its first in-arc
    (in head order) of largest weight, found here by a loop over the arcs."""
    n, extra = g
    # Every node gets an in-arc (a ring), then the drawn arcs: degrees vary, ties abound.
    arcs = [(v, (v + 1) % n, 0) for v in range(n)] + extra
    src, dst, w = (np.array(c, dtype=np.int64) for c in zip(*arcs))
    t = np.ones(len(arcs), dtype=np.int64)
    sorted_arcs = pi._InArcs(src, dst, w, t, n)
    found = pi._ArcTerms(sorted_arcs, pi._Bounds(sorted_arcs)).initial_policy()
    expected = []
    for v in range(n):  # sorted by head, then by input order (a stable sort)
        ins = [k for k in range(len(arcs)) if dst[k] == v]
        best = max(w[k] for k in ins)
        expected.append(next(k for k in ins if w[k] == best))
    assert sorted_arcs.order[found].tolist() == expected
    assert found.tolist() == sorted_arcs.initial_policy().tolist()


def test_policy_digests_tell_policies_apart():
    digest = pi._PolicyDigest(5)
    a = np.array([0, 1, 2, 3, 4], dtype=np.int32)
    b = a.copy()
    b[3] = 7
    assert digest(a) == digest(a.copy())
    assert digest(a) != digest(b)
    assert len(digest(a)) == 16


@settings(deadline=None, max_examples=60)
@given(st.permutations(range(12)), st.lists(st.integers(-2**70, 2**70), min_size=12,
                                            max_size=12))
def test_circuits_walked_in_python_as_by_pointer_jumping(back, weights):
    """Roots, circuits and sums from the root: the same by both walks (int64 and Python ints)."""
    back = np.array(back, dtype=np.int32)
    tokens = np.arange(1, 13, dtype=np.int64)
    for w in (np.array([x % 1000 for x in weights], dtype=np.int64),
              np.array(weights, dtype=object)):
        jumped = pi._jump_circuits(back, w, tokens)
        walked = pi._python_circuits(back, w, tokens)
        for a, b in zip(jumped, walked):
            assert a.tolist() == b.tolist()
        assert walked[2].dtype == w.dtype


@settings(deadline=None, max_examples=80)
@given(st.permutations(range(12)), st.lists(st.integers(-2**70, 2**70), min_size=12,
                                            max_size=12))
def test_one_circuit_is_walked_as_by_pointer_jumping(back, weights):
    """_one_circuit gives what both general walks give when the positions form one
    circuit, and declines (None) when they form several."""
    back = np.array(back, dtype=np.int32)
    # Count the circuits of the permutation by hand: follow each unseen position.
    seen, circuits = set(), 0
    for p in range(12):
        if p not in seen:
            circuits += 1
            while p not in seen:
                seen.add(p)
                p = int(back[p])
    tokens = np.arange(1, 13, dtype=np.int64)
    for w in (np.array([x % 1000 for x in weights], dtype=np.int64),
              np.array(weights, dtype=object)):
        one = pi._one_circuit(back, w, tokens)
        if circuits > 1:
            assert one is None
            continue
        assert one is not None
        for general in (pi._jump_circuits(back, w, tokens), pi._walk_circuits(back, w, tokens)):
            for a, b in zip(one, general):
                assert a.tolist() == b.tolist()
        assert one[2].dtype == w.dtype


def test_one_long_circuit_by_hand():
    """Positions 0 -> 2 -> 1 -> 3 -> 0 (back maps each to its predecessor): one circuit,
    rooted at 0; the sums from the root along 2, 1, 3 are 20, 20 + 10, 20 + 10 + 30."""
    back = np.array([3, 2, 0, 1], dtype=np.int32)
    w = np.array([40, 10, 20, 30], dtype=np.int64)
    t = np.array([1, 2, 3, 4], dtype=np.int64)
    roots, circuit_of, sum_w, sum_t = pi._one_circuit(back, w, t)
    assert roots.tolist() == [0] and circuit_of.tolist() == [0, 0, 0, 0]
    assert sum_w.tolist() == [0, 30, 20, 60] and sum_t.tolist() == [0, 5, 3, 9]
    assert pi._one_circuit(np.array([1, 0, 3, 2], dtype=np.int32), w, t) is None


def _solve_without_circuit_cache(src, dst, w, t, n):
    """max_cycle_ratio with every value determination recomputing its circuits."""
    original = pi._value_determination

    def fresh(pol, arcs, prev, bounds):
        bounds.circuits = None
        return original(pol, arcs, prev, bounds)

    pi._value_determination = fresh
    try:
        return maxplus.max_cycle_ratio(src, dst, w, t, n_nodes=n)
    finally:
        pi._value_determination = original


@settings(deadline=None, suppress_health_check=list(HealthCheck), max_examples=60)
@given(g=circuits_with_chains())
def test_unchanged_circuits_reused_give_the_same_run(g):
    """Reusing the previous circuits is what recomputing them gives: the same
    policies, potentials and iteration count, on every graph."""
    n, arcs = g
    if not arcs:
        return
    src, dst, w, t = (list(column) for column in zip(*arcs))
    try:
        cached = maxplus.max_cycle_ratio(src, dst, w, t, n_nodes=n)
    except maxplus.ZeroTokenCircuitError:
        return
    fresh = _solve_without_circuit_cache(src, dst, w, t, n)
    assert cached.iterations == fresh.iterations
    for a, b in [(cached.certificate.potential, fresh.certificate.potential),
                 (cached.certificate.policy, fresh.certificate.policy),
                 (cached.cycle_time_num, fresh.cycle_time_num),
                 (cached.cycle_time_den, fresh.cycle_time_den)]:
        assert a.tolist() == b.tolist()


def test_a_long_circuit_is_reused_on_the_ring(monkeypatch):
    """A ring of 500 nodes with chords i -> i+5 (the benchmark's ring, smaller): its
    long critical circuit survives some iterations; the answer matches the run
    that recomputes it every time, and the reuse did happen."""
    n, skip = 500, 5
    rng = np.random.default_rng(0)
    nodes = np.arange(n)
    src = np.concatenate([nodes, nodes])
    dst = np.concatenate([(nodes + 1) % n, (nodes + skip) % n])
    w = np.concatenate([rng.integers(1, 10_001, n), rng.integers(1, skip * 10_000 + 1, n)])
    t = rng.integers(1, 11, 2 * n)
    fresh = _solve_without_circuit_cache(src, dst, w, t, n)
    computed = []
    original = pi._circuits
    monkeypatch.setattr(pi, "_circuits", lambda *a: computed.append(1) or original(*a))
    cached = maxplus.max_cycle_ratio(src, dst, w, t)
    assert len(computed) < cached.iterations  # some determination reused its circuits
    assert cached.ratio == fresh.ratio and cached.iterations == fresh.iterations
    assert cached.certificate.potential.tolist() == fresh.certificate.potential.tolist()
    assert cached.verify()
