"""Spectral theory: eigenvalue (Howard kernel) vs Karp vs brute force, eigenvectors,
critical graph, cyclicity, transients, Howard's certificate, bad input.

Independent references: the elementary circuits enumerated by networkx
(``simple_cycles``), naive triple-loop products and powers, and hand
computations in comments.
"""

from __future__ import annotations

import math
from fractions import Fraction

import networkx as nx
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from maxplus import MaxPlusError, MaxPlusValueError, ReducibleMatrixError
from maxplus.scalar import EPS
from maxplus.spectral import (
    critical_graph,
    cycle_time_vector,
    cyclicity,
    eigenspace,
    eigenvalue,
    eigenvector,
    howard,
    is_irreducible,
    karp,
)
from maxplus.transient import trajectory_transient, transient

# Both kernels: on matrices this small max_cycle_ratio would run the list one only.
pytestmark = pytest.mark.usefixtures("every_kernel")

F = Fraction


# --------------------------------------------------------------------------- independent helpers


def fr(v):
    return EPS if v is None else F(v)


def parse(A):
    return [[fr(v) for v in row] for row in A]


def naive_otimes(A, B):
    return [[max((A[i][j] + B[j][k] for j in range(len(B))), default=EPS)
             for k in range(len(B[0]))] for i in range(len(A))]


def naive_apply(A, x):
    return [max(A[i][j] + x[j] for j in range(len(x))) for i in range(len(A))]


def naive_powers(A, up_to):
    """[A^0, A^1, ..., A^up_to] by repeated naive products."""
    n = len(A)
    out = [[[F(0) if i == j else EPS for j in range(n)] for i in range(n)]]
    for _ in range(up_to):
        out.append(naive_otimes(out[-1], A))
    return out


def shifted(M, s):
    return [[v + s for v in row] for row in M]


def digraph(A):
    g = nx.DiGraph()
    g.add_nodes_from(range(len(A)))
    for i, row in enumerate(A):
        for j, v in enumerate(row):
            if v != EPS:
                g.add_edge(j, i, weight=v)  # A[i][j] is the arc j -> i
    return g


def circuits(A):
    """(node list, mean) of every elementary circuit."""
    g = digraph(A)
    out = []
    for cycle in nx.simple_cycles(g):
        arcs = list(zip(cycle, cycle[1:] + cycle[:1]))
        out.append((cycle, F(sum(g[a][b]["weight"] for a, b in arcs), len(cycle))))
    return out


def brute_force_eigenvalue(A):
    return max((mean for _, mean in circuits(A)), default=None)


def brute_force_cycle_times(A):
    """χ_i = max mean of the circuits from which i can be reached."""
    g = digraph(A)
    found = circuits(A)
    out = []
    for i in range(len(A)):
        upstream = nx.ancestors(g, i) | {i}
        means = [mean for cycle, mean in found if upstream & set(cycle)]
        out.append(max(means, default=None))
    return out


def brute_force_critical(A):
    """Nodes and arcs of the circuits of maximum mean."""
    lam = brute_force_eigenvalue(A)
    nodes, arcs = set(), set()
    for cycle, mean in circuits(A):
        if mean == lam:
            nodes |= set(cycle)
            arcs |= set(zip(cycle, cycle[1:] + cycle[:1]))
    return lam, nodes, arcs


def brute_force_cyclicity(A):
    """lcm over critical components of the gcd of their elementary circuit lengths."""
    _, nodes, arcs = brute_force_critical(A)
    g = nx.DiGraph()
    g.add_nodes_from(nodes)
    g.add_edges_from(arcs)
    c = 1
    for comp in nx.strongly_connected_components(g):
        lengths = [len(cycle) for cycle in nx.simple_cycles(g.subgraph(comp))]
        c = math.lcm(c, math.gcd(*lengths))
    return c


entry = st.one_of(
    st.none(), st.none(), st.integers(-5, 5),
    st.fractions(min_value=-3, max_value=3, max_denominator=2),
)


@st.composite
def square_matrices(draw, max_n=4, entries=entry):
    n = draw(st.integers(1, max_n))
    return [[draw(entries) for _ in range(n)] for _ in range(n)]


@st.composite
def irreducible_matrices(draw, max_n=4):
    """A Hamiltonian circuit 0 -> 1 -> ... -> 0 of finite weights plus random entries."""
    A = draw(square_matrices(max_n))
    n = len(A)
    for j in range(n):
        i = (j + 1) % n
        if A[i][j] is None:
            A[i][j] = draw(st.integers(-5, 5))
    return A


# --------------------------------------------------------------------------- regressions


def test_karp_regression_bcoq_2x2():
    # Circuits: loop 0 (3), loop 1 (4), 0 -> 1 -> 0 of weight 2 + 7 = 9, mean 9/2 (wins).
    # (Some libraries return 4 here, ignoring the 2-circuit.)
    A = [[3, 7], [2, 4]]
    assert karp(A) == F(9, 2)
    assert eigenvalue(A) == F(9, 2)


def test_block_diagonal_matrix_is_reducible():
    # Two independent blocks: no arc between {0, 1} and {2}.
    A = [[1, 2, None], [3, 4, None], [None, None, 7]]
    assert not is_irreducible(A)
    assert is_irreducible([[1, 2], [3, 4]])
    assert not is_irreducible([[None]])  # no circuit
    with pytest.raises(ReducibleMatrixError):
        eigenspace(A)
    # Means: block {0,1}: loops 1, 4, circuit (2+3)/2; block {2}: 7.
    assert karp(A) == eigenvalue(A) == 7
    assert cycle_time_vector(A) == [4, 4, 7]


def test_large_entries_stay_exact():
    # 2^60 + 1 does not survive float64. Loops 2^60 + 1 on both nodes, 2-circuit of
    # mean 2^60: λ = 2^60 + 1, A − λ = [[0, -1], [-1, 0]] = (A − λ)^k for k >= 1.
    big = 2**60
    A = [[big + 1, big], [big, big + 1]]
    assert eigenvalue(A) == karp(A) == big + 1
    assert critical_graph(A).components == [[0], [1]]
    assert eigenvector(A).tolist() == [0, -1]
    assert transient(A) == 1
    powers = naive_powers(parse(A), 2)
    assert powers[2] == shifted(powers[1], big + 1) and powers[1] != shifted(powers[0], big + 1)
    # Loops 2^60 and 2^60 + 1 joined by arcs of weight 0: A^k[0][0] =
    # max(k·2^60, (k−2)(2^60 + 1)) switches only after k = 2^61 + 2, far beyond any budget.
    with pytest.raises(MaxPlusError, match="max_power=50"):
        transient([[big, 0], [0, big + 1]], max_power=50)


def test_no_circuit():
    A = [[None, None], [3, None]]
    assert eigenvalue(A) is None and karp(A) is None
    assert cycle_time_vector(A) == [None, None]
    assert critical_graph(A).nodes == [] and cyclicity(A) == 1
    # A^1 = A != ε, A^2 = ε: so t = 1 is the least with A^(t+1) = ε.
    assert transient(A) == 1
    assert transient([[None]]) == 0
    with pytest.raises(ReducibleMatrixError, match="no circuit"):
        eigenvector(A)
    h = howard(A)
    assert h.eigenvalue is None and h.policy == [None, None] and h.circuit == []


def test_two_critical_classes_eigenspace_by_hand():
    # A = [[1, 0], [0, 1]]: λ = 1, two critical loops; (A − 1)^+ = [[0, -1], [-1, 0]].
    g = critical_graph([[1, 0], [0, 1]])
    assert g.components == [[0], [1]] and g.arcs == [(0, 0), (1, 1)]
    assert eigenspace([[1, 0], [0, 1]]).tolist() == [[0, -1], [-1, 0]]


def test_transient_budget_is_enforced():
    # A^(k)[1][1] = max(9k, 10(k-2)): the transient is 20 (hand computation in the anchors).
    with pytest.raises(MaxPlusError, match="max_power"):
        transient([[10, 0], [0, 9]], max_power=10)
    assert transient([[10, 0], [0, 9]], max_power=30) == 20


def test_reducible_transient_names_the_slow_class():
    # Node 0 has its own loop (mean 1) and feeds node 1 (loop 2): A^k[0][0] = k grows
    # slower than 2k, so A^(t+1) = 2 ⊗ A^t never holds.
    with pytest.raises(ReducibleMatrixError, match=r"class \[0\]"):
        transient([[1, None], [0, 2]])
    # Node 0 only feeds the critical loop (no circuit of its own): the identity holds.
    # A = [[ε, ε], [0, 2]]: A^1 = [[ε, ε], [0, 2]], A^2 = [[ε, ε], [2, 4]] = 2 ⊗ A^1,
    # A^1 != 2 ⊗ A^0.
    assert transient([[None, None], [0, 2]]) == 1


def test_trajectory_parity_trap_is_detected():
    # x0 lives on nodes 0 and 5. 5 -> 3 enters the critical 2-circuit 3 <-> 4 (mean 1),
    # 3 -> 1 leaves it towards the slow 2-circuit 1 <-> 2 (mean 0), which 0 -> 1 also
    # enters. Every node reached through a circuit has cycle time 1, yet the walks
    # from 5 reach node 1 only at even k and those from 0 at odd k: along one parity
    # x_1(k) grows like 0·k, so no (K, c) exists.
    A = [[None] * 6 for _ in range(6)]
    for j, i, w in [(0, 1, 0), (1, 2, 0), (2, 1, 0), (5, 3, 0), (3, 4, 1), (4, 3, 1), (3, 1, 0)]:
        A[i][j] = w
    x0 = [0, None, None, None, None, 0]
    xs = [[fr(v) for v in x0]]
    for _ in range(30):
        xs.append(naive_apply(parse(A), xs[-1]))
    # Independent evidence: x_1 alternates between growth 2 per 2 steps and 0.
    assert xs[29][1] - xs[27][1] == 0 and xs[28][1] - xs[26][1] == 2
    with pytest.raises(ReducibleMatrixError, match="never becomes periodic"):
        trajectory_transient(A, x0)
    # From node 5 alone, only the fast circuit feeds everything: periodic.
    K, c, rate = trajectory_transient(A, [None, None, None, None, None, 0])
    assert rate == 1 and c == 2
    xs = [[EPS] * 5 + [F(0)]]
    for _ in range(K + c):
        xs.append(naive_apply(parse(A), xs[-1]))
    assert xs[K + c] == [v + c * rate for v in xs[K]]


def test_trajectory_that_dies_out():
    # 0 -> 1 -> 2, no circuit: x(1) = [ε, 1, ε], x(2) = [ε, ε, 3], x(3) = ε.
    A = [[None, None, None], [1, None, None], [None, 2, None]]
    assert tuple(trajectory_transient(A, [0, None, None])) == (3, 1, None)
    with pytest.raises(MaxPlusValueError):
        trajectory_transient(A, [None, None, None])


# --------------------------------------------------------------------------- properties


@settings(max_examples=80, deadline=None)
@given(square_matrices())
def test_eigenvalue_equals_karp_equals_brute_force(A):
    expected = brute_force_eigenvalue(parse(A))
    assert karp(A) == expected
    assert eigenvalue(A) == expected


@settings(max_examples=60, deadline=None)
@given(square_matrices())
def test_cycle_time_vector_equals_brute_force(A):
    assert cycle_time_vector(A) == brute_force_cycle_times(parse(A))


@settings(max_examples=60, deadline=None)
@given(square_matrices())
def test_eigenvector_and_critical_graph(A):
    P = parse(A)
    lam, nodes, arcs = brute_force_critical(P)
    if lam is None:
        with pytest.raises(ReducibleMatrixError):
            eigenvector(A)
        return
    v = eigenvector(A).tolist()
    assert any(x != EPS for x in v)
    assert naive_apply(P, v) == [x + lam for x in v]  # A ⊗ v = λ ⊗ v
    g = critical_graph(A)
    assert g.eigenvalue == lam
    assert set(g.nodes) == nodes and set(g.arcs) == arcs
    assert sorted(v for comp in g.components for v in comp) == sorted(nodes)
    assert cyclicity(A) == brute_force_cyclicity(P)


@settings(max_examples=40, deadline=None)
@given(irreducible_matrices())
def test_eigenspace_basis_of_irreducible_matrices(A):
    P = parse(A)
    lam, nodes, arcs = brute_force_critical(P)
    V = eigenspace(A).tolist()
    g = nx.DiGraph()
    g.add_nodes_from(nodes)
    g.add_edges_from(arcs)
    assert len(V[0]) == nx.number_strongly_connected_components(g)
    for k in range(len(V[0])):
        column = [row[k] for row in V]
        assert all(x != EPS for x in column)  # irreducible: eigenvectors are finite
        assert naive_apply(P, column) == [x + lam for x in column]


@settings(max_examples=60, deadline=None)
@given(square_matrices(max_n=3))
def test_transient_is_the_least_t(A):
    P = parse(A)
    lam = brute_force_eigenvalue(P)
    c = brute_force_cyclicity(P) if lam is not None else 1
    try:
        t = transient(A)
    except ReducibleMatrixError:
        # Independently: some pair (j, i) is joined through a circuit but through no
        # circuit of mean λ, so A^k[i][j] grows slower than kλ (networkx paths).
        g = digraph(P)
        found = circuits(P)
        reach = {j: nx.descendants(g, j) | {j} for j in g}
        slow = any(
            any(c_ in reach[j] and i in reach[c_] for cyc, _ in found for c_ in cyc)
            and not any(c_ in reach[j] and i in reach[c_]
                        for cyc, mean in found if mean == lam for c_ in cyc)
            for j in g for i in g
        )
        assert slow
        return
    powers = naive_powers(P, t + c)
    if lam is None:
        assert all(v == EPS for row in powers[t + 1] for v in row)
        assert t == 0 or any(v != EPS for row in powers[t] for v in row)
        return
    assert powers[t + c] == shifted(powers[t], c * lam)
    if t > 0:
        assert powers[t - 1 + c] != shifted(powers[t - 1], c * lam)


@settings(max_examples=40, deadline=None)
@given(irreducible_matrices(max_n=3))
def test_irreducible_transient_always_exists(A):
    P = parse(A)
    lam = brute_force_eigenvalue(P)
    c = brute_force_cyclicity(P)
    t = transient(A)
    powers = naive_powers(P, t + c)
    assert powers[t + c] == shifted(powers[t], c * lam)
    if t > 0:
        assert powers[t - 1 + c] != shifted(powers[t - 1], c * lam)


@settings(max_examples=60, deadline=None)
@given(square_matrices(max_n=4), st.data())
def test_trajectory_transient(A, data):
    P = parse(A)
    x0 = [data.draw(st.one_of(st.none(), st.integers(-3, 3))) for _ in A]
    if all(v is None for v in x0):
        x0[0] = 0
    xs = [[fr(v) for v in x0]]
    for _ in range(80):
        xs.append(naive_apply(P, xs[-1]))
    try:
        K, c, rate = trajectory_transient(A, x0)
    except ReducibleMatrixError:
        # Evidence from the simulation: no period c <= 12 brings x(80) back to a
        # shifted x(80 − c) (with n <= 4 and these weights, transients are short).
        for c in range(1, 13):
            diffs = {a - b for a, b in zip(xs[80], xs[80 - c]) if a != EPS or b != EPS}
            supports_match = all((a == EPS) == (b == EPS) for a, b in zip(xs[80], xs[80 - c]))
            assert not (supports_match and len(diffs) == 1 and EPS not in diffs)
        return
    assert K + c <= 60
    shift = 0 if rate is None else c * rate
    assert xs[K + c] == [v + shift for v in xs[K]]
    if K > 0:  # least K (a period from K−1 would also be a multiple of c)
        assert xs[K - 1 + c] != [v + shift for v in xs[K - 1]]
    for smaller in range(1, c):  # least c for this K
        assert xs[K + smaller] != [v + (0 if rate is None else smaller * rate) for v in xs[K]]
    if rate is not None and is_irreducible(A):
        assert rate == brute_force_eigenvalue(P)


@settings(max_examples=60, deadline=None)
@given(square_matrices())
def test_howard_certificate(A):
    P = parse(A)
    h = howard(A)
    chi = h.cycle_time_vector
    assert chi == brute_force_cycle_times(P)
    assert h.eigenvalue == brute_force_eigenvalue(P)
    for i in range(len(P)):
        for j in range(len(P)):
            if P[i][j] != EPS and chi[i] is not None and chi[j] == chi[i]:
                assert h.bias[i] >= h.bias[j] + P[i][j] - chi[i]
        if chi[i] is not None:
            j = h.policy[i]
            assert P[i][j] != EPS and chi[j] == chi[i]
            assert h.bias[i] == h.bias[j] + P[i][j] - chi[i]
        else:
            assert h.policy[i] is None and h.bias[i] is None
    if h.circuit:
        arcs = list(zip(h.circuit, h.circuit[1:] + h.circuit[:1]))
        assert F(sum(P[b][a] for a, b in arcs), len(arcs)) == h.eigenvalue


@pytest.mark.slow
@settings(max_examples=200, deadline=None)
@given(square_matrices(max_n=7, entries=st.one_of(st.none(), st.integers(-20, 20))))
def test_larger_sweep_karp_howard_brute_force(A):
    expected = brute_force_eigenvalue(parse(A))
    assert karp(A) == eigenvalue(A) == expected
    assert cycle_time_vector(A) == brute_force_cycle_times(parse(A))


# --------------------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    "bad, where",
    [
        ([[1, 2, 3], [4, 5, 6]], "A"),
        ([[1, 2], [3]], "A[1]"),
        ([[1, float("nan")], [0, 0]], "A[0][1]"),
        ([[1, 0], [float("inf"), 0]], "A[1][0]"),
        ([[1, 0], [0, "seven"]], "A[1][1]"),
    ],
)
def test_bad_matrices_are_refused_naming_the_entry(bad, where):
    for function in (eigenvalue, karp, cycle_time_vector, eigenvector, critical_graph,
                     cyclicity, transient, howard, is_irreducible):
        with pytest.raises(MaxPlusValueError) as info:
            function(bad)
        assert info.value.where == where


def test_bad_initial_state():
    with pytest.raises(MaxPlusValueError) as info:
        trajectory_transient([[1]], [0, 1])
    assert info.value.where == "x0"
    with pytest.raises(MaxPlusValueError) as info:
        trajectory_transient([[1]], ["x"])
    assert info.value.where == "x0[0]"
