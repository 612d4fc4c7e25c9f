"""Minimal p-semiflows: against circuit enumeration and hand-computed nets."""

from __future__ import annotations

import itertools

import networkx as nx
import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph.analysis import semiflow_tables
from tegraph.analysis.invariants import _combine_open_rows, minimal_semiflows, semiflow_census


@st.composite
def marked_graphs(draw):
    n = draw(st.integers(1, 6))
    m = draw(st.integers(1, 10))
    node = st.integers(0, n - 1)
    return n, draw(st.lists(st.tuples(node, node), min_size=m, max_size=m))


@settings(max_examples=200, deadline=None)
@given(marked_graphs())
def test_marked_graph_semiflows_are_its_elementary_circuits(graph):
    # In a marked graph the supports of the minimal p-semiflows are exactly
    # the elementary circuits (as sets of places), each with coefficients 1.
    n, arcs = graph
    C = np.zeros((len(arcs), n), dtype=int)
    for p, (a, b) in enumerate(arcs):
        C[p, a] += 1
        C[p, b] -= 1
    expected = set()
    for cycle in nx.simple_cycles(nx.DiGraph(arcs)):
        pairs = list(zip(cycle, cycle[1:] + cycle[:1]))
        choices = [[p for p, arc in enumerate(arcs) if arc == pair] for pair in pairs]
        expected.update(tuple(sorted(c)) for c in itertools.product(*choices))
    for method in ("dense", "sparse"):
        result = minimal_semiflows(C, method=method)
        assert result.computed
        got = sorted(tuple(np.flatnonzero(y).tolist()) for y in result.semiflows)
        assert got == sorted(expected), method
        assert all(set(y.tolist()) <= {0, 1} for y in result.semiflows)


def test_weighted_net_semiflow_by_hand():
    # t0 takes 2 tokens from p0 and puts 1 in p1; t1 takes 1 from p1 and puts
    # 2 in p0. y = (1, 2): y.C = (−2 + 2, 2 − 2) = 0, and it is the only
    # minimal one (the kernel of C^T is one-dimensional).
    C = np.array([[-2, 2], [1, -1]])
    result = minimal_semiflows(C)
    assert [y.tolist() for y in result.semiflows] == [[1, 2]]


def test_budget_is_reported():
    # Two transitions joined by 6 parallel places each way: 36 circuits of 2
    # places; a budget of 10 rows cannot hold them.
    C = np.array([[1, -1]] * 6 + [[-1, 1]] * 6)
    for method in ("dense", "sparse"):
        assert len(minimal_semiflows(C, method=method).semiflows) == 36
        assert minimal_semiflows(C, budget=10, method=method).computed is False


def _minimal_semiflows_by_kernels(C: np.ndarray) -> set[tuple[int, ...]]:
    """Minimal supports by brute force over place subsets, smallest first.

    A support S is that of a minimal p-semiflow exactly when no smaller one
    lies inside it and the kernel of C[S]ᵀ is one-dimensional, spanned by a
    vector with every entry non-zero and of one sign (if the kernel were
    larger, a combination of two semiflows on S would zero an entry while
    staying >= 0, giving a smaller support).
    """
    import sympy

    found: list[frozenset[int]] = []
    result = set()
    for size in range(1, C.shape[0] + 1):
        for S in itertools.combinations(range(C.shape[0]), size):
            if any(f <= set(S) for f in found):
                continue
            kernel = sympy.Matrix(C[list(S)].tolist()).T.nullspace()
            if len(kernel) != 1:
                continue
            v = list(kernel[0])
            if all(x > 0 for x in v) or all(x < 0 for x in v):
                found.append(frozenset(S))
                result.add(S)
    return result


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 6).flatmap(lambda p: st.integers(1, 4).flatmap(
    lambda t: st.lists(st.lists(st.integers(-2, 2), min_size=t, max_size=t),
                       min_size=p, max_size=p))))
def test_weighted_net_semiflows_equal_brute_force(rows):
    # Any P/T net (weights up to 2, places both input and output of a
    # transition folded into one entry): Farkas against the kernel test.
    C = np.array(rows, dtype=np.int64)
    expected = _minimal_semiflows_by_kernels(C)
    for method in ("dense", "sparse"):
        result = minimal_semiflows(C, method=method)
        assert result.computed
        assert {tuple(np.flatnonzero(y).tolist()) for y in result.semiflows} == expected, method
        for y in result.semiflows:
            assert not (y @ C).any() and (y >= 0).all() and np.gcd.reduce(y) == 1


@settings(max_examples=60, deadline=None)
@given(marked_graphs(), st.integers(1, 12))
def test_both_tables_run_out_of_budget_alike(graph, budget):
    n, arcs = graph
    C = np.zeros((len(arcs), n), dtype=int)
    for p, (a, b) in enumerate(arcs):
        C[p, a] += 1
        C[p, b] -= 1
    dense = minimal_semiflows(C, budget, method="dense")
    sparse = minimal_semiflows(C, budget, method="sparse")
    assert dense.computed == sparse.computed
    assert dense.count == sparse.count


# Dense and sparse tables: same rows and budget verdict on any net, and edge cases.

nets = st.integers(1, 8).flatmap(lambda p: st.integers(0, 5).flatmap(
    lambda t: st.lists(st.lists(st.integers(-2, 2), min_size=t, max_size=t),
                       min_size=p, max_size=p)))


def rows_of(res):
    return sorted(tuple(y.tolist()) for y in res.semiflows)


@settings(deadline=None)
@given(nets, st.integers(0, 15))
def test_dense_sparse_same_rows_and_budget_on_weighted_nets(rows, budget):
    C = np.array(rows, dtype=np.int64).reshape(len(rows), -1)
    d = minimal_semiflows(C, budget, method="dense")
    s = minimal_semiflows(C, budget, method="sparse")
    assert d.computed == s.computed
    assert rows_of(d) == rows_of(s)
    full = minimal_semiflows(C, 10**6, method="dense")
    for y in full.semiflows:
        assert not (y @ C).any() and (y >= 0).all() and y.any() and np.gcd.reduce(y) == 1
    if d.computed:
        assert rows_of(d) == rows_of(full)


@pytest.mark.parametrize("method", ["dense", "sparse", "auto"])
@pytest.mark.parametrize("shape", [(0, 0), (0, 3), (3, 0), (1, 1), (4, 2)])
def test_all_zero_and_empty(method, shape):
    C = np.zeros(shape, dtype=int)
    r = minimal_semiflows(C, method=method)
    assert r.computed
    assert r.matrix.shape == (shape[0], shape[0])
    assert sorted(map(tuple, (y.tolist() for y in r.semiflows))) == sorted(
        tuple(int(i == k) for i in range(shape[0])) for k in range(shape[0]))


@pytest.mark.parametrize("method", ["dense", "sparse"])
def test_explicit_zeros_and_self_loops_in_sparse_input(method):
    # places 0, 1: circuit t0 <-> t1; place 2: self-loop of t0 (a zero row), stored explicitly
    rows, cols = np.array([0, 0, 1, 1, 2]), np.array([0, 1, 0, 1, 0])
    C = sp.csr_matrix((np.array([-1, 1, 1, -1, 0]), (rows, cols)), shape=(3, 2))
    r = minimal_semiflows(C, method=method)
    assert [y.tolist() for y in r.semiflows] == [[1, 1, 0], [0, 0, 1]]


@pytest.mark.parametrize("method", ["dense", "sparse"])
def test_transition_without_places_and_source_sink(method):
    # t0 -> p0 -> t1 (t0 source, t1 sink): no semiflow; t2 touches nothing
    C = np.array([[1, -1, 0]])
    assert minimal_semiflows(C, method=method).count == 0
    # weighted: 2 p0 = p1 around t0/t1
    C = np.array([[2, -2], [-1, 1]])
    assert [y.tolist() for y in minimal_semiflows(C, method=method).semiflows] == [[1, 2]]


def _farkas_over_all_places(C: np.ndarray, budget: int):
    """The dense Farkas table as it was before the open-rows table: every row,
    over every place (kept here as the reference the faster table must equal
    row for row, in order, and in its budget verdict)."""
    from tegraph.analysis.invariants import _contract_series_transitions

    C = sp.csr_matrix(C, dtype=np.int64)
    C.eliminate_zeros()
    Y, R = (m.toarray() for m in _contract_series_transitions(C))
    done = ~R.any(axis=0)
    for _ in range(int((~done).sum())):
        cost = (R > 0).sum(axis=0) * (R < 0).sum(axis=0)
        cost[done] = np.iinfo(np.int64).max
        j = int(np.argmin(cost))
        done[j] = True
        col = R[:, j]
        pos, neg, zero = np.flatnonzero(col > 0), np.flatnonzero(col < 0), np.flatnonzero(col == 0)
        if len(zero) - int((~R[zero].any(axis=1)).sum()) + len(pos) * len(neg) > budget:
            return None
        if len(pos) == 0 or len(neg) == 0:
            Y, R = Y[zero], R[zero]
            continue
        a, b = np.repeat(pos, len(neg)), np.tile(neg, len(pos))
        fa, fb = -col[b][:, None], col[a][:, None]
        new_Y, new_R = fa * Y[a] + fb * Y[b], fa * R[a] + fb * R[b]
        g = np.gcd.reduce(new_Y, axis=1)
        g = np.where(g == 0, 1, g)[:, None]
        new_Y, new_R = new_Y // g, new_R // g
        S_old, S_new = (Y[zero] > 0).astype(int), (new_Y > 0).astype(int)
        size = S_new.sum(axis=1)
        bad = ((S_new @ S_old.T) == S_old.sum(axis=1)[None, :]).any(axis=1)
        contains = (S_new @ S_new.T) == size[None, :]
        np.fill_diagonal(contains, False)
        strict = (contains & (size[None, :] < size[:, None])).any(axis=1)
        earlier_equal = np.triu((contains & (size[None, :] == size[:, None])).T, k=1).any(axis=0)
        keep = ~bad & ~strict & ~earlier_equal
        Y, R = np.vstack([Y[zero], new_Y[keep]]), np.vstack([R[zero], new_R[keep]])
    return Y


@settings(max_examples=300, deadline=None)
@given(st.one_of(nets.map(lambda rows: np.array(rows, dtype=np.int64).reshape(len(rows), -1)),
                 marked_graphs().map(lambda graph: np.array(
                     [[(k == a) - (k == b) for k in range(graph[0])] for a, b in graph[1]]))),
       st.integers(0, 40))
def test_dense_table_equals_the_table_over_all_places(C, budget):
    # The dense table keeps only open rows, as coefficients over them; its rows,
    # their order and its budget verdict are those of the full table.
    expected = _farkas_over_all_places(C, budget)
    got = minimal_semiflows(C, budget, method="dense")
    assert got.computed == (expected is not None)
    if expected is not None:
        assert got.matrix.toarray().tolist() == expected.tolist()


@settings(max_examples=150, deadline=None)
@given(st.lists(st.one_of(
    nets.map(lambda rows: np.array(rows, dtype=np.int64).reshape(len(rows), -1)),
    marked_graphs().map(lambda graph: np.array(
        [[(k == a) - (k == b) for k in range(graph[0])] for a, b in graph[1]]))),
    min_size=1, max_size=4), st.integers(0, 12), st.randoms(use_true_random=False))
def test_census_equals_each_blocks_own_semiflows(parts, budget, random):
    # Several nets side by side (rows and columns shuffled), as the blocks of one
    # net: the census must count what minimal_semiflows finds block by block, and
    # stop at the same block when the budget runs out.
    n_rows = sum(len(p) for p in parts)
    n_cols = sum(p.shape[1] for p in parts)
    row_at, col_at = list(range(n_rows)), list(range(n_cols))
    random.shuffle(row_at)
    random.shuffle(col_at)
    C = np.zeros((n_rows, n_cols), dtype=np.int64)
    marking = np.array([random.randint(0, 1) for _ in range(n_rows)])
    blocks, r0, c0 = [], 0, 0
    for p in parts:
        rows = np.array(row_at[r0:r0 + len(p)], dtype=np.int64)
        cols = np.sort(np.array(col_at[c0:c0 + p.shape[1]], dtype=np.int64))
        C[np.ix_(rows, cols)] = p
        blocks.append((rows, cols))
        r0, c0 = r0 + len(p), c0 + p.shape[1]
    count = unmarked = 0
    failed = None
    for b, (rows, cols) in enumerate(blocks):
        result = minimal_semiflows(C[np.ix_(rows, cols)], budget)
        if not result.computed:
            failed = b
            break
        count += result.count
        unmarked += len(result.unmarked(marking[rows]))
    census = semiflow_census(sp.csr_matrix(C), blocks, marking, budget)
    assert census.failed == failed and census.computed == (failed is None)
    if failed is None:
        assert (census.count, census.unmarked) == (count, unmarked)


@pytest.mark.parametrize("budget", [35, 36])
def test_census_budget_at_the_edge(budget):
    # Block 0: a circuit of one place; block 1: two transitions joined by 6 places
    # each way (36 circuits, 36 candidate rows at the first step: within a budget
    # of 36, not of 35), as minimal_semiflows decides.
    C = sp.block_diag([np.array([[0]]), np.array([[1, -1]] * 6 + [[-1, 1]] * 6)], format="csr")
    blocks = [(np.array([0]), np.array([0])), (np.arange(1, 13), np.array([1, 2]))]
    census = semiflow_census(C, blocks, np.zeros(13, dtype=np.int64), budget)
    alone = minimal_semiflows(C[1:, 1:], budget)
    assert census.computed == alone.computed == (budget == 36)
    assert census.failed == (None if budget == 36 else 1)
    if census.computed:
        assert census.count == census.unmarked == 37


@settings(max_examples=150, deadline=None)
@given(st.lists(st.integers(1, 5).flatmap(lambda t: st.lists(
    st.lists(st.integers(-2, 2), min_size=t, max_size=t), min_size=1, max_size=8)),
    min_size=1, max_size=6), st.integers(-1, 40), st.sampled_from([(2, 8), (6, 64), (64, 1 << 22)]))
def test_tables_combined_together_equal_each_alone(tables, budget, limits):
    # combine_tables takes one step of every table at once, in chunks, and leaves
    # the tables that grow past MAX_ROWS (small limits here force both): each
    # result must be the one-table routine's, rows, order and budget verdict.
    tables = [np.array(t, dtype=np.int64) for t in tables]
    saved = semiflow_tables.MAX_ROWS, semiflow_tables.CHUNK_ENTRIES
    semiflow_tables.MAX_ROWS, semiflow_tables.CHUNK_ENTRIES = limits
    try:
        results, left = semiflow_tables.combine_tables(tables, budget)
    finally:
        semiflow_tables.MAX_ROWS, semiflow_tables.CHUNK_ENTRIES = saved
    for k, table in enumerate(tables):
        alone = _combine_open_rows(table, budget)
        if k in left:
            assert results[k] is None
            continue
        assert (results[k] is None) == (alone is None)
        if alone is not None:
            assert results[k].tolist() == alone.tolist()
