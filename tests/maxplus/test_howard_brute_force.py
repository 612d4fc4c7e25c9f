"""Howard's policy iteration (with its downstream sweep) against circuit enumeration.

The expected values come from enumerating every elementary circuit
(networkx.simple_cycles), every choice of parallel arc on it, and, for the
cycle time of a node, the largest ratio among the circuits it is reachable
from (Baccelli et al. 1992, Thm 3.112). The chain-shaped generators are what
reach the sweep: random small multigraphs almost never do.
"""
from __future__ import annotations

import itertools
from fractions import Fraction

import networkx as nx
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import maxplus.policy_iteration as pi
from maxplus.cycle_ratio import max_cycle_ratio
from maxplus.errors import ZeroTokenCircuitError
from tests.maxplus.kernels import KERNELS, NUMPY, kernel


def _arc(src, dst, w, t, tail, head, weight, tokens):
    """Append one arc to the four parallel lists."""
    src.append(tail)
    dst.append(head)
    w.append(weight)
    t.append(tokens)

def brute_force(n, arcs):
    """(max ratio, per-node cycle time, has zero-token circuit) by enumeration."""
    g = nx.DiGraph()
    g.add_nodes_from(range(n))
    par = {}
    for a, b, w, t in arcs:
        g.add_edge(a, b)
        par.setdefault((a, b), []).append((w, t))
    ratios = []  # (ratio, node set)
    zero = False
    for cyc in nx.simple_cycles(g):
        hops = list(zip(cyc, cyc[1:] + cyc[:1]))
        best = None
        for choice in itertools.product(*(par[h] for h in hops)):
            W = sum(w for w, _ in choice)
            T = sum(t for _, t in choice)
            if T == 0:
                zero = True
                continue
            r = Fraction(W, T)
            best = r if best is None else max(best, r)
        if best is not None:
            ratios.append((best, set(cyc)))
    if zero:
        return None, None, True
    ct = [None] * n
    for r, nodes in ratios:
        reach = set(nodes)
        for v in nodes:
            reach |= nx.descendants(g, v)
        for v in reach:
            if ct[v] is None or r > ct[v]:
                ct[v] = r
    top = max((r for r, _ in ratios), default=None)
    return top, ct, False


def check(n, arcs):
    """The brute-force oracle against every kernel built here."""
    for name in KERNELS:
        with kernel(name):
            check_kernel(n, arcs)


def check_kernel(n, arcs):
    src = [a for a, _, _, _ in arcs]
    dst = [b for _, b, _, _ in arcs]
    w = [x for _, _, x, _ in arcs]
    t = [x for _, _, _, x in arcs]
    top, ct, zero = brute_force(n, arcs)
    if zero:
        with pytest.raises(ZeroTokenCircuitError):
            max_cycle_ratio(src, dst, w, t, n)
        return
    r = max_cycle_ratio(src, dst, w, t, n)
    assert r.ratio == top
    assert r.cycle_times == ct
    assert r.verify()
    # The cycle-time arrays themselves in lowest terms (Fraction would hide a
    # common factor), 0/0 where there is none: integer weights take no gcd pass.
    for v, (a, b) in enumerate(zip(r.cycle_time_num.tolist(), r.cycle_time_den.tolist())):
        assert (a, b) == ((0, 0) if ct[v] is None else (ct[v].numerator, ct[v].denominator))
    if top is not None:
        c = r.circuit.tolist()
        assert Fraction(sum(w[k] for k in c), sum(t[k] for k in c)) == top
    # every node's policy circuit attains its cycle time
    for v in range(n):
        if ct[v] is not None:
            c = r.policy_circuit(v).tolist()
            assert Fraction(sum(w[k] for k in c), sum(t[k] for k in c)) == ct[v]
    # same answer on the object (Python int) path: huge offset on nothing -> scale weights
    big = 2**70
    r2 = max_cycle_ratio(src, dst, [x * big for x in w], t, n)
    assert r2.cycle_times == [None if c is None else c * big for c in ct]
    assert r2.verify()
    # the strategies for long circuits and wide sweeps (in C) on every graph
    with large_graph_paths():
        for scale in (1, big):
            r3 = max_cycle_ratio(src, dst, [x * scale for x in w], t, n)
            assert r3.cycle_times == [None if c is None else c * scale for c in ct]
            assert r3.verify()


def large_graph_paths():
    """The numpy kernel's strategies for long circuits and wide sweeps, at every size."""
    return kernel(walk_min_circuit_nodes=0, sweep_few=0, rows_min_level=0)


@st.composite
def small_multigraphs(draw):
    n = draw(st.integers(1, 7))
    node = st.integers(0, n - 1)
    arcs = draw(st.lists(st.tuples(node, node, st.integers(-4, 9), st.integers(0, 3)),
                         min_size=0, max_size=16))
    return n, arcs


@st.composite
def circuits_with_chains(draw):
    """A few circuits (distinct ratios), chains hanging off them, cross links, joins."""
    arcs = []
    n = 0
    heads = []
    for _ in range(draw(st.integers(1, 4))):
        k = draw(st.integers(1, 4))
        nodes = list(range(n, n + k))
        n += k
        for a, b in zip(nodes, nodes[1:] + nodes[:1]):
            arcs.append((a, b, draw(st.integers(0, 9)), draw(st.integers(1, 2))))
        heads.append(nodes)
    # chains from random existing nodes, possibly long, possibly merging into others
    for _ in range(draw(st.integers(0, 5))):
        start = draw(st.integers(0, n - 1))
        length = draw(st.integers(1, 12))
        prev = start
        for _ in range(length):
            arcs.append((prev, n, draw(st.integers(-3, 9)), draw(st.integers(0, 2))))
            prev = n
            n += 1
        # optionally join the chain end into an existing node (possibly a circuit)
        if draw(st.booleans()):
            arcs.append((prev, draw(st.integers(0, n - 1)), draw(st.integers(-3, 9)),
                         draw(st.integers(1, 2))))
    # extra random arcs (parallel arcs, cross links), with tokens >= 1 to keep things finite-ish
    node = st.integers(0, n - 1)
    arcs += draw(st.lists(st.tuples(node, node, st.integers(-3, 9), st.integers(0, 2)),
                          max_size=4))
    perm = draw(st.permutations(range(n)))
    arcs = [(perm[a], perm[b], w, t) for a, b, w, t in arcs]
    arcs = draw(st.permutations(arcs))
    return n, list(arcs)


@settings(deadline=None, suppress_health_check=list(HealthCheck))
@given(small_multigraphs())
def test_small_multigraphs(g):
    check(*g)


@settings(deadline=None, suppress_health_check=list(HealthCheck))
@given(circuits_with_chains())
def test_circuits_with_chains(g):
    n, arcs = g
    if n > 60:
        return
    check(n, arcs)


def count_iterations(src, dst, w, t, n):
    calls = [0]
    orig = pi._value_determination

    def counted(*a, **k):
        calls[0] += 1
        return orig(*a, **k)

    pi._value_determination = counted
    try:
        with kernel(NUMPY):  # the numpy kernel's determinations are what is counted
            r = max_cycle_ratio(src, dst, w, t, n)
    finally:
        pi._value_determination = orig
    return r, calls[0]


@pytest.mark.parametrize("L", [10, 100, 1000, 10000])
def test_iterations_long_chain_below_fast_circuit(L):
    # slow circuit (self loop weight 1) at node 0, fast circuit (self loop 100) at node 1,
    # both feeding a chain 2..L+1; initial policy (heaviest in-arc) prefers the slow one
    src = [0, 1, 0, 1]
    dst = [0, 1, 2, 2]
    w = [1, 100, 1000, 0]
    t = [1, 1, 0, 0]
    for k in range(2, L + 1):
        _arc(src, dst, w, t, k, k + 1, 0, 0)
    r, it = count_iterations(src, dst, w, t, L + 2)
    assert r.iterations == it
    assert r.verify()
    assert set(r.cycle_times[2:]) == {100}
    assert it <= 6  # one hop per iteration would take L


@pytest.mark.parametrize("L", [10, 100, 1000])
def test_iterations_ladder(L):
    # a ladder: circuits of increasing ratio each feeding the next rung of a chain,
    # and the chain feeding back, so the ranks go up step by step
    src, dst, w, t = [], [], [], []
    n = 2 * L
    for k in range(L):
        c, v = 2 * k, 2 * k + 1
        _arc(src, dst, w, t, c, c, k, 1)          # circuit of ratio k
        _arc(src, dst, w, t, c, v, 0, 0)
        if k:
            _arc(src, dst, w, t, 2 * k - 1, v, 10**6, 0)  # heavy chain arc
    r, _ = count_iterations(src, dst, w, t, n)
    assert r.verify()
    exp = []
    for k in range(L):
        exp += [Fraction(k), Fraction(k)]
    assert r.cycle_times == exp


@st.composite
def dag_of_blocks(draw):
    """Blocks (each a circuit plus chords) joined forward by chains of 0-token arcs."""
    arcs, blocks, n = [], [], 0
    for _ in range(draw(st.integers(2, 5))):
        k = draw(st.integers(1, 3))
        nodes = list(range(n, n + k))
        n += k
        ratio_w = draw(st.integers(0, 6))
        for a, b in zip(nodes, nodes[1:] + nodes[:1]):
            arcs.append((a, b, ratio_w, 1))
        for _ in range(draw(st.integers(0, 2))):
            arcs.append((draw(st.sampled_from(nodes)), draw(st.sampled_from(nodes)),
                         draw(st.integers(0, 6)), draw(st.integers(1, 2))))
        blocks.append(nodes)
    for _ in range(draw(st.integers(1, 6))):
        i = draw(st.integers(0, len(blocks) - 2))
        j = draw(st.integers(i + 1, len(blocks) - 1))
        prev = draw(st.sampled_from(blocks[i]))
        for _ in range(draw(st.integers(0, 6))):
            arcs.append((prev, n, draw(st.integers(-2, 20)), draw(st.integers(0, 1))))
            prev, n = n, n + 1
        arcs.append((prev, draw(st.sampled_from(blocks[j])), draw(st.integers(-2, 20)),
                     draw(st.integers(0, 1))))
    # tails hanging below random nodes
    for _ in range(draw(st.integers(0, 3))):
        prev = draw(st.integers(0, n - 1))
        for _ in range(draw(st.integers(1, 8))):
            arcs.append((prev, n, draw(st.integers(-2, 20)), 0))
            prev, n = n, n + 1
    perm = draw(st.permutations(range(n)))
    arcs = [(perm[a], perm[b], w, t) for a, b, w, t in arcs]
    return n, list(draw(st.permutations(arcs)))


@settings(deadline=None, suppress_health_check=list(HealthCheck))
@given(dag_of_blocks())
def test_dag_of_blocks(g):
    check(*g)


def reverse_ladder(L):
    # node 2k: self-loop of ratio k; node 2k+1 (v_k): heavy arc from 2k, light arc from v_{k+1}.
    # chi(v_k) = L-1. Initial policy (heaviest in-arc) takes the self-loop side; one ratio
    # improvement switches every v_k to v_{k+1} at once.
    src, dst, w, t = [], [], [], []
    for k in range(L):
        _arc(src, dst, w, t, 2 * k, 2 * k, k, 1)
        _arc(src, dst, w, t, 2 * k, 2 * k + 1, 10**6, 0)
        if k + 1 < L:
            _arc(src, dst, w, t, 2 * k + 3, 2 * k + 1, 0, 0)
    return src, dst, w, t, 2 * L


def test_sweep_switches_linear_in_nodes():
    L = 2000
    switched = [0]
    best, raise_ = pi._best_per_node, pi._raise

    def counting(arcs, key, s_dst):
        chosen, nodes = best(arcs, key, s_dst)
        switched[0] += len(nodes)
        return chosen, nodes

    def counting_sweep(pol, rank, done, heads, arcs, top):
        switched[0] += len(heads)
        return raise_(pol, rank, done, heads, arcs, top)

    pi._best_per_node, pi._raise = counting, counting_sweep
    try:
        with kernel(NUMPY):  # the numpy kernel's switches are what is counted
            r = max_cycle_ratio(*reverse_ladder(L))
    finally:
        pi._best_per_node, pi._raise = best, raise_
    assert r.verify()
    assert all(r.cycle_times[2 * k + 1] == L - 1 for k in range(L))
    assert switched[0] <= 4 * 2 * L, switched[0]   # HEAD: about L*L/2 = 2,000,000
