"""Dense (max,+) operations: products, powers, Kleene star, solve, residuals.

Every expected value is derived independently: by hand (comments), by the
naive triple-loop product below, by Kleene iteration, or by enumerating the
elementary circuits with networkx.
"""

from __future__ import annotations

import copy
from fractions import Fraction

import networkx as nx
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from maxplus import MaxPlusValueError, PositiveCircuitError
from maxplus.dense import (
    identity,
    left_residual,
    oplus,
    otimes,
    plus,
    power,
    right_residual,
    solve,
    star,
)
from maxplus.scalar import EPS, TOP

F = Fraction


# --------------------------------------------------------------------------- independent helpers


def fr(v):
    """Parse a test entry without the library: None is ε."""
    return EPS if v is None else F(v)


def parse(A):
    return [[fr(v) for v in row] for row in A]


def add(a, b):
    """a ⊗ b with ε absorbing, also against ⊤ (ε ⊗ ⊤ = ε)."""
    if a == EPS or b == EPS:
        return EPS
    return a + b


def naive_otimes(A, B):
    return [[max((add(A[i][j], B[j][k]) for j in range(len(B))), default=EPS)
             for k in range(len(B[0]))] for i in range(len(A))]


def naive_oplus(A, B):
    return [[max(a, b) for a, b in zip(ra, rb)] for ra, rb in zip(A, B)]


def naive_identity(n):
    return [[F(0) if i == j else EPS for j in range(n)] for i in range(n)]


def naive_power(A, k):
    out = naive_identity(len(A))
    for _ in range(k):
        out = naive_otimes(out, A)
    return out


def as_lists(M):
    return np.asarray(M, dtype=object).tolist()


def digraph(A):
    g = nx.DiGraph()
    g.add_nodes_from(range(len(A)))
    for i, row in enumerate(A):
        for j, v in enumerate(row):
            if v != EPS:
                g.add_edge(j, i, weight=v)  # A[i][j] is the arc j -> i
    return g


def circuit_weights(A):
    g = digraph(A)
    for cycle in nx.simple_cycles(g):
        yield cycle, sum(g[a][b]["weight"] for a, b in zip(cycle, cycle[1:] + cycle[:1]))


entry = st.one_of(
    st.none(), st.integers(-6, 6), st.fractions(min_value=-4, max_value=4, max_denominator=3)
)


@st.composite
def square_matrices(draw, max_n=4, entries=entry):
    n = draw(st.integers(1, max_n))
    return [[draw(entries) for _ in range(n)] for _ in range(n)]


@st.composite
def non_positive_circuit_matrices(draw, max_n=4):
    """Random matrices made star-convergent by shifting every entry by −λ."""
    A = parse(draw(square_matrices(max_n)))
    lam = max((w / len(c) for c, w in circuit_weights(A)), default=F(0))
    return [[v if v == EPS else v - lam for v in row] for row in A]


# --------------------------------------------------------------------------- basic operations


def test_identity_is_neutral_for_otimes():
    A = [[1, None], ["1/2", -3]]
    assert identity(2).tolist() == [[0, EPS], [EPS, 0]]
    assert otimes(identity(2), A).tolist() == parse(A)
    assert otimes(A, identity(2)).tolist() == parse(A)


def test_oplus_by_hand():
    # entrywise max, ε neutral: max(1, 0) = 1, max(ε, 3) = 3, max(0, ε) = 0, max(2, 5/2) = 5/2
    assert oplus([[1, None], [0, 2]], [[0, 3], [None, "5/2"]]).tolist() == [[1, 3], [0, F(5, 2)]]
    assert oplus(None, None) == EPS
    assert oplus([1, None], [None, None]).tolist() == [1, EPS]


def test_otimes_shapes_by_hand():
    A = [[3, 7], [2, 4]]
    # matrix-vector: [max(3+0, 7+1), max(2+0, 4+1)] = [8, 5]
    assert otimes(A, [0, 1]).tolist() == [8, 5]
    # row vector-matrix: [max(0+3, 1+2), max(0+7, 1+4)] = [3, 7]
    assert otimes([0, 1], A).tolist() == [3, 7]
    # vector-vector (inner product): max(1+0, ε+5) = 1
    assert otimes([1, None], [0, 5]) == 1
    # scalar ⊗ matrix: add 1/2 to every finite entry
    assert otimes(F(1, 2), [[1, None]]).tolist() == [[F(3, 2), EPS]]
    assert otimes([[1, None]], "1/2").tolist() == [[F(3, 2), EPS]]
    # non-square: (1x2) ⊗ (2x3)
    assert otimes([[0, 1]], [[1, None, 2], [0, 0, None]]).tolist() == [[1, 1, 2]]
    assert otimes(2, 3) == 5 and otimes(None, 3) == EPS


def test_otimes_dimension_mismatch_names_operand():
    with pytest.raises(MaxPlusValueError, match="inner dimensions") as info:
        otimes([[1, 2]], [[1, 2]])
    assert info.value.where == "B"
    with pytest.raises(MaxPlusValueError, match="shapes"):
        oplus([[1, 2]], [1, 2])


def test_power_by_hand():
    A = [[3, 7], [2, 4]]
    # A^2[0][0] = max(3+3, 7+2) = 9, A^2[0][1] = max(3+7, 7+4) = 11,
    # A^2[1][0] = max(2+3, 4+2) = 6, A^2[1][1] = max(2+7, 4+4) = 9
    assert power(A, 2).tolist() == [[9, 11], [6, 9]]
    assert power(A, 0).tolist() == [[0, EPS], [EPS, 0]]
    assert power(A, 1).tolist() == [[3, 7], [2, 4]]


@settings(max_examples=60, deadline=None)
@given(square_matrices(), st.integers(0, 9))
def test_power_equals_repeated_naive_product(A, k):
    assert power(A, k).tolist() == naive_power(parse(A), k)


@settings(max_examples=40, deadline=None)
@given(square_matrices(max_n=3), square_matrices(max_n=3))
def test_otimes_matches_naive_and_is_associative(A, B):
    n = min(len(A), len(B))
    A = [row[:n] for row in A[:n]]
    B = [row[:n] for row in B[:n]]
    assert otimes(A, B).tolist() == naive_otimes(parse(A), parse(B))
    assert otimes(otimes(A, B), A).tolist() == otimes(A, otimes(B, A)).tolist()


def test_large_entries_fall_back_to_exact_python_ints():
    big = 2**60
    # (2^60 + 2^60) is beyond float64's exact integers: the object path must be used.
    assert otimes([[big]], [[big]]).tolist() == [[2 * big]]
    assert power([[big + 1]], 3).tolist() == [[3 * big + 3]]
    assert star([[-big, 1], [-1, None]]).tolist() == [[0, 1], [-1, 0]]


# --------------------------------------------------------------------------- Kleene star


def test_star_anchor_like_example_by_hand():
    # Arcs: 1->0 (2), 2->0 (3), 0->1 (-2), 2->1 (-1), 0->2 (-5), 1->2 (-2), loops 1 (-10), 2 (0).
    # Best paths: 2->0 directly 3; 0->1 -2; 0->2 -5 vs 0->1->2 = -4; 1->2 -2;
    # 2->1 -1 vs 2->0->1 = 1.
    S = star([[None, 2, 3], [-2, -10, -1], [-5, -2, 0]])
    assert S.tolist() == [[0, 2, 3], [-2, 0, 1], [-4, -2, 0]]


def test_star_positive_circuit_is_named():
    # 0 -> 1 (weight 0) -> 0 (weight 1): total 1 > 0.
    with pytest.raises(PositiveCircuitError) as info:
        star([[0, 1], [0, None]])
    assert info.value.circuit == [0, 1] and info.value.weight == 1


def test_star_does_not_modify_input():
    as_list = [[None, -1], [-2, "1/2"]]
    as_list_copy = copy.deepcopy(as_list)
    as_float = np.array([[-np.inf, -1.0], [-2.0, -0.5]])
    as_float_copy = as_float.copy()
    as_object = np.array([[EPS, F(-1)], [F(-2), F(-1, 2)]], dtype=object)
    as_object_copy = as_object.copy()
    star(as_float)
    star(as_object)
    plus(as_object)
    with pytest.raises(PositiveCircuitError):
        star(as_list)
    assert as_list == as_list_copy
    assert np.array_equal(as_float, as_float_copy)
    assert as_object.tolist() == as_object_copy.tolist()


@settings(max_examples=60, deadline=None)
@given(square_matrices())
def test_star_converges_iff_no_positive_circuit(A):
    parsed = parse(A)
    positive = [(c, w) for c, w in circuit_weights(parsed) if w > 0]
    if positive:
        with pytest.raises(PositiveCircuitError) as info:
            star(A)
        circuit, weight = info.value.circuit, info.value.weight
        # The named circuit is elementary, made of real arcs, and weighs what it says.
        assert len(set(circuit)) == len(circuit)
        arcs = list(zip(circuit, circuit[1:] + circuit[:1]))
        assert all(parsed[b][a] != EPS for a, b in arcs)
        assert weight == sum(parsed[b][a] for a, b in arcs) > 0
    else:
        S = star(A).tolist()
        n = len(A)
        # A* = E ⊕ A ⊕ ... ⊕ A^(n-1) when no circuit is positive (BCOQ §3.2.3).
        expected = naive_identity(n)
        for k in range(1, n):
            expected = naive_oplus(expected, naive_power(parsed, k))
        assert S == expected


@settings(max_examples=60, deadline=None)
@given(non_positive_circuit_matrices())
def test_star_identities(A):
    n = len(A)
    S = star(A).tolist()
    # A* = E ⊕ A ⊗ A*  and  A* ⊗ A* = A*  (closure properties, BCOQ §3.2.3 / §4.3)
    assert S == naive_oplus(naive_identity(n), naive_otimes(A, S))
    assert naive_otimes(S, S) == S
    # A+ = A ⊗ A*
    assert plus(A).tolist() == naive_otimes(A, S)


@settings(max_examples=60, deadline=None)
@given(non_positive_circuit_matrices(), st.data())
def test_solve_gives_the_least_solution(A, data):
    n = len(A)
    b = [data.draw(entry) for _ in range(n)]
    x = solve(A, b).tolist()
    col = [[fr(v)] for v in b]
    # It solves x = A ⊗ x ⊕ b ...
    assert [[v] for v in x] == naive_oplus(naive_otimes(A, [[v] for v in x]), col)
    # ... and is the least solution: Kleene iteration from ε stays below every
    # solution and reaches x within n steps.
    y = [[EPS] for _ in range(n)]
    for _ in range(n + 1):
        y = naive_oplus(naive_otimes(A, y), col)
    assert [v[0] for v in y] == x


def test_solve_ignores_unreachable_positive_circuit_and_refuses_reachable_one():
    A = [[1, None], [None, None]]  # positive self-loop on node 0 only
    assert solve(A, [None, 0]).tolist() == [EPS, 0]  # node 1 never reaches node 0
    with pytest.raises(PositiveCircuitError) as info:
        solve(A, [0, None])
    assert info.value.circuit == [0] and info.value.weight == 1
    # Matrix right-hand side: one system per column.
    assert solve([[None, None], [2, None]], [[0, None], [None, 1]]).tolist() == [[0, EPS], [2, 1]]


def test_solve_reports_circuit_with_original_indices():
    # Nodes 1 and 2 form the positive circuit 1 -> 2 -> 1 (weights 1 and 1), reached
    # from node 0 (arc 0 -> 1) where b is supported: solve works on the sub-matrix of
    # nodes {0, 1, 2} and must report the circuit in the caller's numbering.
    A = [[None, None, None], [0, None, 1], [None, 1, None]]
    with pytest.raises(PositiveCircuitError) as info:
        solve(A, [0, None, None])
    assert info.value.circuit == [1, 2] and info.value.weight == 2


# --------------------------------------------------------------------------- residuation


def test_residuals_by_hand():
    A = [[1, 2], [3, None]]
    # (A \ b)_0 = min(5-1, 6-3) = 3; (A \ b)_1 = min(5-2, 6-ε = ⊤) = 3
    assert left_residual(A, [5, 6]).tolist() == [3, 3]
    # ε \ ε = ⊤ ; finite \ ε = ε
    assert left_residual([[None]], [[None]]).tolist() == [[TOP]]
    assert left_residual([[0]], [[None]]).tolist() == [[EPS]]
    # (b / A)_i = min_j (b_j - A[i][j]): i=0 min(5-1, 6-2)=4, i=1 min(5-3, ⊤)=2
    assert right_residual([5, 6], A).tolist() == [4, 2]
    with pytest.raises(MaxPlusValueError, match="rows"):
        left_residual(A, [1, 2, 3])


def leq(X, Y):
    return all(x <= y for rx, ry in zip(X, Y) for x, y in zip(rx, ry))


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 3), st.integers(1, 3), st.integers(1, 3), st.data())
def test_left_residual_is_the_greatest_subsolution(n, m, p, data):
    A = [[data.draw(entry) for _ in range(m)] for _ in range(n)]
    B = [[data.draw(entry) for _ in range(p)] for _ in range(n)]
    X = left_residual(A, B).tolist()
    PA, PB = parse(A), parse(B)
    assert len(X) == m and len(X[0]) == p
    assert leq(naive_otimes(PA, X), PB)  # A ⊗ (A \ B) <= B
    # Greatest: no entry can grow. Each finite or ε entry is pinned by a row
    # i with A[i][j] finite and A[i][j] + X[j][k] = B[i][k]; ⊤ only when
    # column j of A is all ε (it constrains nothing).
    for j in range(m):
        for k in range(p):
            if X[j][k] == TOP:
                assert all(PA[i][j] == EPS for i in range(n))
            else:
                assert any(PA[i][j] != EPS and add(PA[i][j], X[j][k]) == PB[i][k] for i in range(n))


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 3), st.integers(1, 3), st.integers(1, 3), st.data())
def test_right_residual_is_the_greatest_subsolution(n, m, p, data):
    A = [[data.draw(entry) for _ in range(m)] for _ in range(n)]
    B = [[data.draw(entry) for _ in range(m)] for _ in range(p)]
    X = right_residual(B, A).tolist()
    PA, PB = parse(A), parse(B)
    assert len(X) == p and len(X[0]) == n
    assert leq(naive_otimes(X, PA), PB)  # (B / A) ⊗ A <= B
    for k in range(p):
        for i in range(n):
            if X[k][i] == TOP:
                assert all(PA[i][j] == EPS for j in range(m))
            else:
                assert any(PA[i][j] != EPS and add(X[k][i], PA[i][j]) == PB[k][j] for j in range(m))


# --------------------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    "bad, where",
    [
        ([[1, 2, 3], [4, 5, 6]], "A"),  # not square
        ([[1, 2], [3]], "A[1]"),  # ragged
        ([[1, float("nan")], [0, 0]], "A[0][1]"),
        ([[1, 0], [float("inf"), 0]], "A[1][0]"),
        ([[1, 0], [0, "seven"]], "A[1][1]"),
    ],
)
def test_bad_matrices_are_refused_naming_the_entry(bad, where):
    for function in (star, plus, lambda A: power(A, 2)):
        with pytest.raises(MaxPlusValueError) as info:
            function(bad)
        assert info.value.where == where
        assert isinstance(info.value, ValueError)


def test_bad_operands_and_exponents():
    with pytest.raises(MaxPlusValueError) as info:
        otimes([[1, "x"]], [[1], [2]])
    assert info.value.where == "A[0][1]"
    with pytest.raises(MaxPlusValueError) as info:
        oplus([1, 2], [1, float("nan")])
    assert info.value.where == "B[1]"
    for k in (-1, 1.5, True):
        with pytest.raises(MaxPlusValueError) as info:
            power([[1]], k)
        assert info.value.where == "k"
    with pytest.raises(MaxPlusValueError):
        identity(0)
    with pytest.raises(MaxPlusValueError, match="rows"):
        solve([[0]], [1, 2])


def test_positive_circuit_fallback_when_pointers_are_useless():
    # The predecessor walk is backed by an exact search: feed it meaningless
    # pointers (every node "comes from" node 0) and it must still name a real
    # positive circuit, here the only one: 0 -> 1 -> 0 of weight 2 + (-1) = 1.
    from maxplus._closure import raise_positive_circuit

    M = np.array([[EPS, F(-1)], [F(2), EPS]], dtype=object)
    with pytest.raises(PositiveCircuitError) as info:
        raise_positive_circuit(np.zeros((2, 2), dtype=int), 0, M, None)
    assert info.value.circuit == [0, 1] and info.value.weight == 1
