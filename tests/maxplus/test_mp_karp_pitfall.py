"""A warning kept as a test: Karp's formula is max over nodes of the MIN over k.

mplusa 0.0.5's ``karp_algorithm`` takes the maximum over (node, k) instead,
which overestimates λ. On ``A = [[1, 5], [3, 2]]`` the elementary circuits
are (by hand):

* the self-loop on node 0, weight 1, mean 1;
* the self-loop on node 1, weight 2, mean 2;
* 0 -> 1 -> 0, arcs A[1][0] = 3 and A[0][1] = 5, mean (5 + 3)/2 = 4;

so λ = 4. Karp with D_k(v) the best walk of k arcs ending in v, started
everywhere at 0: D_1 = (5, 3), D_2 = (8, 8); node 0: min((8−0)/2, (8−5)/1)
= 3; node 1: min((8−0)/2, (8−3)/1) = 4; max over nodes = 4. The maximum over
k instead gives max(4, 3, 4, 5) = 5 at node 1, k = 1.
"""

from __future__ import annotations

from fractions import Fraction

import pytest

from maxplus import eigenvalue, howard, karp

# Both kernels: on graphs this small max_cycle_ratio would run the list one only.
pytestmark = pytest.mark.usefixtures("every_kernel")

A = [[1, 5], [3, 2]]


def _max_over_k(matrix):
    """The flawed formula (mplusa 0.0.5's ``karp_algorithm``): max over (v, k) of
    (D_n(v) - D_k(v)) / (n - k), with D_k(v) the best k-arc walk ending in v."""
    n = len(matrix)
    walks = [[Fraction(0)] * n]
    for _ in range(n):
        last = walks[-1]
        walks.append([max(last[u] + matrix[v][u] for u in range(n)) for v in range(n)])
    return max((walks[n][v] - walks[k][v]) / (n - k) for v in range(n) for k in range(n))


def test_our_eigenvalue_is_the_hand_derived_4():
    assert eigenvalue(A) == Fraction(4)
    assert karp(A) == Fraction(4)
    assert howard(A).circuit in ([0, 1], [1, 0])


def test_the_max_over_k_pitfall_gets_5_where_karp_gets_4():
    # By hand (module docstring): the maximum over k is 5 at node 1, k = 1; Karp's
    # min over k then max over nodes is 4. The peer itself is compared with ours in
    # benchmarks/peers/dense_peers.py (its "mplusa agrees" column), where it is installed.
    assert _max_over_k(A) == 5
    assert karp(A) == 4 != _max_over_k(A)
