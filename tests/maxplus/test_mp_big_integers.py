"""Exact answers for entries far beyond int64 and float range.

Regression: with ε kept as float('-inf') among Python ints, ``int + -inf``
converts the int to a float, so an entry of 10**400 next to an ε raised
OverflowError in otimes, power, transient, karp, eigenvalue (and more).

Every expected value is derived by hand below for A = B + [[0, 3], [-5, ε]]:
the circuits are the self-loop on 0 (mean B) and 0 -> 1 -> 0 (weights B − 5
and B + 3, mean B − 1), so λ = B.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from maxplus import (
    cycle_time_vector,
    cyclicity,
    eigenvalue,
    eigenvector,
    karp,
    left_residual,
    otimes,
    power,
    simulate,
    star,
    trajectory_transient,
    transient,
)
from maxplus.scalar import EPS

# Both kernels: on graphs this small max_cycle_ratio would run the list one only.
pytestmark = pytest.mark.usefixtures("every_kernel")

BIGS = [pytest.param(2**63 + 1, id="2**63+1"), pytest.param(10**400, id="10**400")]


def matrix(B):
    return [[B, B + 3], [B - 5, None]]


@pytest.mark.parametrize("B", BIGS)
def test_eigenvalue_karp_and_cycle_times(B):
    A = matrix(B)
    assert eigenvalue(A) == B
    assert karp(A) == B
    assert cycle_time_vector(A) == [B, B]
    # As an array of Python ints, and with a common denominator 3.
    assert eigenvalue(np.array(A, dtype=object)) == B
    assert eigenvalue([[Fraction(B, 3), None], [1, 0]]) == Fraction(B, 3)


@pytest.mark.parametrize("B", BIGS)
def test_products_and_powers(B):
    A = matrix(B)
    # A²: [0][0] max(2B, (B+3)+(B−5)) = 2B; [0][1] B + B+3; [1][0] (B−5)+B;
    # [1][1] (B−5)+(B+3) = 2B−2.
    assert otimes(A, A).tolist() == [[2 * B, 2 * B + 3], [2 * B - 5, 2 * B - 2]]
    # A³ = A ⊗ A²: [0][0] max(3B, (B+3)+(2B−5)); [0][1] max(3B+3, (B+3)+(2B−2));
    # [1][0] (B−5)+2B; [1][1] (B−5)+(2B+3).
    assert power(A, 3).tolist() == [[3 * B, 3 * B + 3], [3 * B - 5, 3 * B - 2]]
    assert otimes(B, A).tolist() == [[2 * B, 2 * B + 3], [2 * B - 5, EPS]]
    assert otimes(A, [0, None]).tolist() == [B, B - 5]


@pytest.mark.parametrize("B", BIGS)
def test_star_and_residual(B):
    # One circuit 0 -> 1 -> 0 of weight (B − 1) + (−B) = −1: the star exists.
    assert star([[None, -B], [B - 1, None]]).tolist() == [[0, -B], [B - 1, 0]]
    # (A \ A)[j][k] = min_i (A[i][k] − A[i][j]): [0][1] meets ε − (B−5) = ε;
    # [1][0] = min(B − (B+3), (B−5) − ε = ⊤) = −3; the diagonal is 0.
    assert left_residual(matrix(B), matrix(B)).tolist() == [[0, EPS], [-3, 0]]


@pytest.mark.parametrize("B", BIGS)
def test_transients_and_eigenvector(B):
    A = matrix(B)
    # N = A − λ = [[0, 3], [−5, ε]]: N² = [[0, 3], [−5, −2]] = N³ ≠ N, so t = 2, c = 1.
    assert transient(A) == 2
    assert cyclicity(A) == 1
    # Column 0 of N+ = [0, −5]; A ⊗ v = [max(B, B − 2), B − 5] = B ⊗ v.
    assert eigenvector(A).tolist() == [0, -5]
    # x(1) − B = [3, −5], x(2) − 2B = [3, −2] = x(3) − 3B.
    assert trajectory_transient(A, [0, 0]) == (2, 1, B)


@pytest.mark.parametrize("B", BIGS)
def test_simulate(B):
    # x(k) = A0 x(k) ⊕ A1 x(k−1) with A0 = [[ε, ε], [B, ε]], A1 = diag(1, 1):
    # x1(k) = x1(k−1) + 1, x2(k) = max(x2(k−1) + 1, x1(k) + B).
    x = simulate([[None, None], [B, None]], [[1, None], [None, 1]], initial=[0, 0], steps=2)
    assert x.tolist() == [[0, 0], [1, B + 1], [2, B + 2]]
