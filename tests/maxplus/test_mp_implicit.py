"""Implicit systems x(k) = A0 x(k) ⊕ A1 x(k-1) ⊕ ... ⊕ B u(k): explicit form and simulation.

The reference is a direct simulation that never forms A0*: at each k it
iterates ``y <- A0 ⊗ y ⊕ r`` (r = delayed and input terms) until it stops
changing, which takes at most n rounds when A0 has no circuit.
"""

from __future__ import annotations

import itertools
from fractions import Fraction

import networkx as nx
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from maxplus import MaxPlusValueError, ZeroTokenCircuitError
from maxplus.implicit import simulate, to_explicit
from maxplus.scalar import EPS

F = Fraction


def fr(v):
    return EPS if v is None else F(v)


def parse(A):
    return [[fr(v) for v in row] for row in A]


def apply(A, x):
    return [max((A[i][j] + x[j] for j in range(len(x))), default=EPS) for i in range(len(A))]


def join(x, y):
    return [max(a, b) for a, b in zip(x, y)]


def direct_simulation(mats, B, initial, inputs, steps):
    """x(k) for k = 0..steps by fixed-point iteration of the implicit equation."""
    n, p = len(mats[0]), len(mats) - 1
    history = [list(v) for v in initial]  # x(0), x(-1), ...
    history += [[EPS] * n for _ in range(p - len(history))]
    out = [history[0]]
    for k in range(1, steps + 1):
        rest = [EPS] * n
        for lag in range(1, p + 1):
            rest = join(rest, apply(mats[lag], history[lag - 1]))
        if B is not None:
            rest = join(rest, apply(B, inputs[k - 1]))
        y = rest
        for _ in range(n + 1):
            y = join(apply(mats[0], y), rest)
        history = [y] + history[:-1]
        out.append(y)
    return out


entry = st.one_of(st.none(), st.none(), st.integers(-4, 6), st.fractions(0, 3, max_denominator=2))


@st.composite
def acyclic(draw, n):
    """A0 strictly lower triangular under a random relabelling (so: no circuit)."""
    order = draw(st.permutations(range(n)))
    rank = {v: r for r, v in enumerate(order)}
    return [[draw(entry) if rank[j] < rank[i] else None for j in range(n)] for i in range(n)]


@st.composite
def systems(draw):
    n = draw(st.integers(1, 4))
    p = draw(st.integers(1, 3))
    m = draw(st.integers(1, 2))
    mats = [draw(acyclic(n))] + [
        [[draw(entry) for _ in range(n)] for _ in range(n)] for _ in range(p)
    ]
    B = [[draw(entry) for _ in range(m)] for _ in range(n)]
    steps = draw(st.integers(0, 6))
    initial = [[draw(entry) for _ in range(n)] for _ in range(draw(st.integers(0, p)))]
    inputs = [[draw(st.integers(0, 9)) for _ in range(m)] for _ in range(steps)]
    return mats, B, initial, inputs, steps


def test_first_order_by_hand():
    # A0: arc 0 -> 1 (weight 1). A0* = [[0, ε], [1, 0]].
    # A0* ⊗ A1 with A1 = diag(2, 3): [[2, ε], [max(1+2, 0+ε), 3]] = [[2, ε], [3, 3]].
    s = to_explicit([[None, None], [1, None]], [[2, None], [None, 3]], B=[[0], [None]])
    assert s.A.tolist() == [[2, EPS], [3, 3]]
    assert s.B.tolist() == [[0], [1]]  # A0* ⊗ B = [0, max(1 + 0, ε)]
    assert (s.order, s.n_states) == (1, 2)


def test_second_order_companion_form_by_hand():
    # x(k) = 1 ⊗ x(k-1) ⊕ 5 ⊗ x(k-2) (scalar, A0 = ε): X(k) = [x(k); x(k-1)],
    # Â = [[1, 5], [0, ε]].
    s = to_explicit([[None]], [[1]], [[5]])
    assert s.A.tolist() == [[1, 5], [0, EPS]]
    assert s.B is None and s.order == 2
    # From x(0) = 0, x(-1) = 0: x(1) = max(1, 5) = 5, x(2) = max(6, 5) = 6, x(3) = max(7, 10) = 10.
    x = simulate([[None]], [[1]], [[5]], initial=[[0], [0]], steps=3)
    assert [row[0] for row in x.tolist()] == [0, 5, 6, 10]


@pytest.mark.parametrize(
    "A0, nodes",
    [
        ([[0]], [0]),  # a self-loop, even of weight 0
        ([[None, -3], [-2, None]], [0, 1]),  # negative circuit: still a deadlock
        ([[None, None, 1], [2, None, None], [None, 0, None]], [0, 1, 2]),
    ],
)
def test_circuit_in_A0_is_refused_and_named(A0, nodes):
    n = len(A0)
    with pytest.raises(ZeroTokenCircuitError) as info:
        to_explicit(A0, [[None] * n for _ in range(n)])
    assert sorted(info.value.nodes) == nodes
    circuit = info.value.nodes
    # It is a real circuit of A0: each consecutive pair is an arc (A0[b][a] finite).
    assert all(A0[b][a] is not None for a, b in zip(circuit, circuit[1:] + circuit[:1]))
    assert "A0[" in str(info.value)
    with pytest.raises(ZeroTokenCircuitError):
        simulate(A0, [[None] * n for _ in range(n)], steps=1)


@settings(max_examples=60, deadline=None)
@given(systems())
def test_simulation_matches_direct_fixed_point_iteration(system):
    mats, B, initial, inputs, steps = system
    got = simulate(*mats, B=B, initial=initial or None, inputs=inputs if steps else None,
                   steps=steps).tolist()
    expected = direct_simulation([parse(M) for M in mats], parse(B),
                                 [[fr(v) for v in x] for x in initial],
                                 [[fr(v) for v in u] for u in inputs], steps)
    assert got == expected


@settings(max_examples=40, deadline=None)
@given(systems())
def test_explicit_matrix_of_order_one_is_A0_star_A1(system):
    mats, B, _, _, _ = system
    s = to_explicit(mats[0], mats[1], B=B)
    n = len(mats[0])
    # Independent A0*: sum of the paths of A0 (no circuit, so at most n-1 arcs), via networkx.
    g = nx.DiGraph()
    g.add_nodes_from(range(n))
    A0 = parse(mats[0])
    for i in range(n):
        for j in range(n):
            if A0[i][j] != EPS:
                g.add_edge(j, i, weight=A0[i][j])
    star = [[F(0) if i == j else EPS for j in range(n)] for i in range(n)]
    for j in range(n):
        for i in range(n):
            for path in nx.all_simple_paths(g, j, i):
                w = sum(g[a][b]["weight"] for a, b in itertools.pairwise(path))
                star[i][j] = max(star[i][j], w)
    A1 = parse(mats[1])
    expected = [[max(star[i][k] + A1[k][j] for k in range(n)) for j in range(n)]
                for i in range(n)]
    assert s.A.tolist() == expected


def test_constant_input_and_defaults():
    A0 = [[None, None, None], [None, None, None], [6, 6, None]]
    A1 = [[5, None, None], [None, 6, None], [None, None, 3]]
    B = [[2], [0], [None]]
    constant = simulate(A0, A1, B=B, inputs=[0], steps=4).tolist()
    rows = simulate(A0, A1, B=B, inputs=[[0]] * 4).tolist()
    assert constant == rows
    assert constant[0] == [EPS, EPS, EPS]  # default initial state ε
    # x(1) = A0* B0 u(1) = [2, 0, max(6+2, 6+0)] = [2, 0, 8] (De Schutter's example)
    assert constant[1] == [2, 0, 8]
    # Without input the ε initial state stays ε.
    assert simulate(A0, A1, steps=2).tolist() == [[EPS] * 3] * 3


def test_bad_systems_are_refused():
    with pytest.raises(MaxPlusValueError) as info:
        to_explicit([[None]], [[1, 2]])
    assert info.value.where == "A1"
    with pytest.raises(MaxPlusValueError) as info:
        to_explicit([[None, None], [None, None]], [[1]])
    assert info.value.where == "A1"
    with pytest.raises(MaxPlusValueError) as info:
        to_explicit([[None]], [[1]], B=[[0], [1]])
    assert info.value.where == "B"
    with pytest.raises(MaxPlusValueError) as info:
        to_explicit([[float("nan")]], [[1]])
    assert info.value.where == "A0[0][0]"
    with pytest.raises(MaxPlusValueError) as info:
        simulate([[None]], [[1]], inputs=[0], steps=2)
    assert info.value.where == "B"
    with pytest.raises(MaxPlusValueError) as info:
        simulate([[None]], [[1]], B=[[0]], inputs=[0])
    assert info.value.where == "steps"
    with pytest.raises(MaxPlusValueError) as info:
        simulate([[None]], [[1]], steps=-1)
    assert info.value.where == "steps"
    with pytest.raises(MaxPlusValueError) as info:
        simulate([[None]], [[1]], initial=[[0], [1]], steps=1)
    assert info.value.where == "initial"
    with pytest.raises(MaxPlusValueError) as info:
        simulate([[None]], [[1]], initial=[0, 1], steps=1)
    assert info.value.where == "initial[0]"
    with pytest.raises(MaxPlusValueError) as info:
        simulate([[None]], [[1]], B=[[0]], inputs=[[0]], steps=3)
    assert info.value.where == "inputs"
