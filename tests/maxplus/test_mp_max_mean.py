"""The dense certified Howard behind eigenvalue and cycle_time_vector.

Small matrices are compared with brute force in test_mp_spectral.py; here
the larger ones (the numpy path, above SMALL nodes) are cross-checked
against two independent algorithms: Karp's theorem (maxplus.karp) and the
sparse Howard kernel (maxplus.cycle_ratio.max_cycle_ratio, its own
certificate checked). The certificate checker is fed wrong claims, and the
fast input paths must read every input form as the general validator does.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from maxplus import (
    CertificateError,
    MaxPlusValueError,
    cycle_time_vector,
    eigenvalue,
    howard,
    karp,
)
from maxplus._integer_matrix import integer_matrix
from maxplus._kernels import current
from maxplus._max_mean import _single_mean
from maxplus._mean_certificate import check_mean_certificate, check_mean_certificate_lists
from maxplus.cycle_ratio import max_cycle_ratio


def random_matrix(seed, n, density, low=-50, high=50, blocks=1):
    """Random integer matrix (None = ε); with blocks > 1, arcs only go from a
    block to itself or to a later block, so the matrix is reducible."""
    rng = np.random.default_rng(seed)
    A = rng.integers(low, high + 1, size=(n, n)).astype(object)
    A[rng.random((n, n)) > density] = None
    if blocks > 1:
        block = np.sort(rng.integers(0, blocks, size=n))
        A[block[:, None] < block[None, :]] = None  # A[i][j] is j -> i: no arc back
    return A.tolist()


def sparse_ratio(A):
    rows, cols = np.nonzero(np.array([[v is not None for v in row] for row in A]))
    weights = [A[i][j] for i, j in zip(rows.tolist(), cols.tolist())]
    result = max_cycle_ratio(cols, rows, weights, n_nodes=len(A))
    result.verify()
    return result


SMALL = current().dense_lists_max_nodes  # the dense Howard's lists up to it, numpy above


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(SMALL + 1, 45), st.floats(0.05, 1.0),
       st.integers(1, 4))
def test_numpy_path_agrees_with_karp_and_the_sparse_kernel(seed, n, density, blocks):
    A = random_matrix(seed, n, density, blocks=blocks)
    lam = eigenvalue(A)
    assert lam == karp(A) == sparse_ratio(A).ratio
    assert cycle_time_vector(A) == sparse_ratio(A).cycle_times


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, SMALL), st.floats(0.05, 1.0),
       st.integers(1, 3))
def test_list_path_agrees_with_karp_and_the_sparse_kernel(seed, n, density, blocks):
    A = random_matrix(seed, n, density, blocks=blocks)
    assert eigenvalue(A) == karp(A) == sparse_ratio(A).ratio
    assert cycle_time_vector(A) == howard(A).cycle_time_vector


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(2, 30))
def test_lists_and_arrays_give_the_same_certified_mean(seed, n):
    # The two implementations of the improvement step must agree (both are certified).
    A = random_matrix(seed, n, 1.0)  # complete: every node has an in-arc
    m = integer_matrix(A)
    assert _single_mean(None, None, A) == _single_mean(m.values, m.finite, None)


def test_ring_with_chords_by_hand():
    # Arcs j -> j+1 of weight 3 and chords j -> j−2 of weight 5 (mod 60). No
    # arc weighs more than 5, and the chords alone close the circuit
    # 0 -> 58 -> 56 -> ... -> 2 -> 0 of 30 arcs of weight 5: λ = 5.
    n = 60
    A = [[None] * n for _ in range(n)]
    for j in range(n):
        A[(j + 1) % n][j] = 3
        A[(j - 2) % n][j] = 5
    assert eigenvalue(A) == 5 == karp(A) == sparse_ratio(A).ratio
    assert cycle_time_vector(A) == [5] * n


def test_every_input_form_reads_the_same_numbers():
    # Circuits: loops 1, 3, 1; 0 -> 1 -> 2 -> 0 of mean (0 + 4 + 2)/3 = 2;
    # 1 -> 2 -> 1 of mean (A[2][1] + A[1][2])/2 = (4 + 3)/2 = 7/2, the largest.
    ints = [[1, None, 2], [0, 3, 3], [None, 4, 1]]
    lam = karp(ints)
    assert lam == Fraction(7, 2)
    as_float = np.array([[1, -np.inf, 2], [0, 3, 3], [-np.inf, 4, 1]])
    assert eigenvalue(ints) == eigenvalue(np.array(ints, dtype=object)) == lam
    assert eigenvalue(as_float) == eigenvalue(as_float.astype(np.float32)) == lam
    assert eigenvalue(np.array([[1, 2], [3, 4]], dtype=np.uint8)) == 4
    # 0.1 is read as 1/10 (its decimal text), not as the binary float.
    assert eigenvalue([[0.1]]) == eigenvalue(np.array([[0.1]])) == Fraction(1, 10)
    assert eigenvalue([["7/3", None], [None, "eps"]]) == Fraction(7, 3)
    assert eigenvalue(np.array([[2**64 - 1]], dtype=np.uint64)) == 2**64 - 1


@pytest.mark.parametrize(("A", "where"), [
    ([[1, True], [0, 0]], "A[0][1]"),
    (np.array([[1.0, np.nan], [0.0, 0.0]]), "A[0][1]"),
    (np.array([[1.0, np.inf], [0.0, 0.0]]), "A[0][1]"),
    ([[1, 2], [3]], "A[1]"),
    ([[1, "x"], [0, 0]], "A[0][1]"),
])
def test_bad_entries_are_named(A, where):
    with pytest.raises(MaxPlusValueError) as info:
        eigenvalue(A)
    assert info.value.where == where


def test_the_checker_refuses_wrong_claims():
    W = [[1, 5], [3, 2]]  # λ = 4, circuit 0 -> 1 -> 0 (see test_mp_karp_pitfall.py)
    arr = np.array(W)
    full = np.ones(arr.shape, dtype=bool)
    for check in (lambda p, q, x, walk: check_mean_certificate_lists(W, p, q, x, walk),
                  lambda p, q, x, walk: check_mean_certificate(arr, full, p, q, np.array(x), walk)):
        check(4, 1, [0, -1], [0, 1])  # x_0 >= 5 − 4 + x_1 and x_1 >= 3 − 4 + x_0: tight
        with pytest.raises(CertificateError, match="potential"):
            check(2, 1, [0, 0], [1])  # the loop on 1 has mean 2, but 0 -> 1 -> 0 beats it
        with pytest.raises(CertificateError, match="mean"):
            check(5, 1, [0, -1], [0, 1])  # 5 is not the mean of 0 -> 1 -> 0
        with pytest.raises(CertificateError, match="denominator"):
            check(4, 0, [0, -1], [0, 1])
    no_loop = np.array([[0, 5], [3, 0]])
    with pytest.raises(CertificateError, match="no arc"):
        check_mean_certificate(no_loop, no_loop != 0, 0, 1, np.array([0, 0]), [0])
