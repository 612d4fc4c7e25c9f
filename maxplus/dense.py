"""Dense (max,+) matrix algebra: sums, products, powers; and the namespace of
the dense functions (closures and residuals live in private modules, one idea
each, and are re-exported here).

Convention (the whole package): ``x(k+1) = A ⊗ x(k)``, i.e.
``x_i(k+1) = max_j (A[i][j] + x_j(k))``, so ``A[i][j]`` is the weight of the
arc ``j -> i`` and ε = -inf. ``(A ⊗ B)[i][k] = max_j (A[i][j] + B[j][k])`` is
then the best weight of a path ``k -> j -> i``; ``A^k[i][j]`` the best weight of
a path of ``k`` arcs from ``j`` to ``i``, and ``A*[i][j]`` the best weight of any
path from ``j`` to ``i`` [1]_.

Every function accepts nested lists or arrays (validated by
:func:`maxplus.scalar.exact_matrix` / :func:`~maxplus.scalar.exact_vector`, so
a bad entry raises :class:`~maxplus.errors.MaxPlusValueError` naming it) and
returns exact values: object ndarrays of ``Fraction`` / ``EPS`` (and ``TOP`` =
+inf for residuals only), scalars as ``Fraction`` / ``EPS``. Inside, the work
is done on scaled integers (float64 when exact, Python ints of any size
otherwise), see :mod:`maxplus._scaled`.

References
----------
.. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
   and Linearity*, Wiley, 1992, §2.3 and §3.2.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ._closure import plus, solve, star
from ._residuation import left_residual, right_residual
from ._scaled import (
    as_exact,
    identity_scaled,
    operand,
    product_scaled,
    scale_together,
    scaled,
    square_matrix,
    times,
)
from .errors import MaxPlusValueError

__all__ = [
    "identity",
    "left_residual",
    "oplus",
    "otimes",
    "plus",
    "power",
    "right_residual",
    "solve",
    "star",
]


# --------------------------------------------------------------------------- basic operations


def identity(n: int) -> np.ndarray:
    """The (max,+) identity matrix E: 0 on the diagonal, ε elsewhere.

    Parameters
    ----------
    n : int
        Size, at least 1.

    Returns
    -------
    numpy.ndarray of dtype object

    Raises
    ------
    MaxPlusValueError
        ``n`` is not a positive integer, or exceeds ``MAX_IDENTITY_SIZE`` (8192).

    See Also
    --------
    power : ``A^0 = E``.
    otimes : E is its neutral element.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, §3.2.

    Examples
    --------
    >>> identity(2).tolist()
    [[Fraction(0, 1), -inf], [-inf, Fraction(0, 1)]]
    """
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise MaxPlusValueError(f"expected a positive integer size, got {n!r}", "n")
    if n > MAX_IDENTITY_SIZE:  # n*n Python objects: 10**12 would ask numpy for 7 TiB
        raise MaxPlusValueError(f"expected a size of at most {MAX_IDENTITY_SIZE} (a dense "
                                f"matrix of n*n exact entries), got {n}", "n")
    return as_exact(identity_scaled(int(n)), 1)


MAX_IDENTITY_SIZE = 2**13
"""The largest :func:`identity`: 2**26 entries, about a minute and gigabytes of Fractions."""


def oplus(A: Any, B: Any) -> Any:
    """(max,+) sum ``A ⊕ B``: the entrywise maximum of two operands of one shape.

    Parameters
    ----------
    A, B : scalar, vector or matrix (nested lists or arrays)
        Same shape.

    Returns
    -------
    Fraction, EPS, or numpy.ndarray of dtype object

    Raises
    ------
    MaxPlusValueError
        A bad entry (named), or shapes that differ.

    See Also
    --------
    otimes : the (max,+) product.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, §3.2 (the semiring R_max and its matrices).

    Examples
    --------
    >>> oplus([[1, None], [0, 2]], [[0, 3], [None, "5/2"]]).tolist()
    [[Fraction(1, 1), Fraction(3, 1)], [Fraction(0, 1), Fraction(5, 2)]]
    >>> oplus(3, None)
    Fraction(3, 1)
    """
    a, rank_a = operand(A, "A")
    b, rank_b = operand(B, "B")
    if rank_a == 0 and rank_b == 0:
        return max(a, b)
    if rank_a != rank_b or a.shape != b.shape:
        raise MaxPlusValueError(
            f"cannot add operands of shapes {np.shape(a)} and {np.shape(b)}", "B"
        )
    out = np.empty(a.shape, dtype=object)
    out.reshape(-1)[:] = [max(x, y) for x, y in zip(a.ravel().tolist(), b.ravel().tolist())]
    return out


def otimes(A: Any, B: Any) -> Any:
    """(max,+) product ``A ⊗ B``.

    Matrix-matrix ``(A ⊗ B)[i][k] = max_j (A[i][j] + B[j][k])``; a vector on the
    right is a column (``A ⊗ x`` is one step of ``x(k+1) = A ⊗ x(k)``), a vector
    on the left a row; vector ⊗ vector is the scalar ``max_i (x_i + y_i)``; a
    scalar on either side adds itself to every entry.

    Parameters
    ----------
    A, B : scalar, vector or matrix (nested lists or arrays)
        Conformable operands; matrices need not be square.

    Returns
    -------
    Fraction, EPS, or numpy.ndarray of dtype object

    Raises
    ------
    MaxPlusValueError
        A bad entry (named), or inner dimensions that differ.

    See Also
    --------
    oplus : the (max,+) sum.
    power : repeated products of a square matrix.
    maxplus.dense.left_residual : the greatest X with ``A ⊗ X <= B``.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, §3.2 (matrix product, path interpretation).

    Examples
    --------
    >>> A = [[3, 7], [2, 4]]
    >>> otimes(A, [0, 0]).tolist()
    [Fraction(7, 1), Fraction(4, 1)]
    >>> otimes(A, A).tolist()
    [[Fraction(9, 1), Fraction(11, 1)], [Fraction(6, 1), Fraction(9, 1)]]
    >>> otimes("1/2", [[1, None]]).tolist()
    [[Fraction(3, 2), -inf]]
    """
    a, rank_a = operand(A, "A")
    b, rank_b = operand(B, "B")
    if rank_a == 0 or rank_b == 0:
        scalar, other = (a, b) if rank_a == 0 else (b, a)
        if rank_a == 0 and rank_b == 0:
            return times(scalar, other)
        out = np.empty(other.shape, dtype=object)
        out.reshape(-1)[:] = [times(scalar, v) for v in other.ravel().tolist()]
        return out
    left = a if rank_a == 2 else a.reshape(1, -1)
    right = b if rank_b == 2 else b.reshape(-1, 1)
    if left.shape[1] != right.shape[0]:
        raise MaxPlusValueError(
            f"cannot multiply {'x'.join(map(str, a.shape))} by "
            f"{'x'.join(map(str, b.shape))}: inner dimensions differ", "B"
        )
    (ls, rs), scale = scale_together([left, right], growth=2)
    result = as_exact(product_scaled(ls, rs), scale)
    if rank_a == 1 and rank_b == 1:
        return result[0, 0]
    if rank_b == 1:
        return result[:, 0]
    if rank_a == 1:
        return result[0, :]
    return result


def power(A: Any, k: int) -> np.ndarray:
    """The k-th (max,+) power ``A^k = A ⊗ ... ⊗ A``; ``A^0 = E``.

    ``A^k[i][j]`` is the best weight of a path of exactly ``k`` arcs from ``j``
    to ``i``. Computed by repeated squaring (O(n³ log k)).

    Parameters
    ----------
    A : square matrix (nested lists or 2-D array)
    k : int
        Non-negative exponent.

    Returns
    -------
    numpy.ndarray of dtype object

    Raises
    ------
    MaxPlusValueError
        A bad entry (named), a non-square matrix, or ``k`` not a non-negative
        integer.

    See Also
    --------
    otimes : one product.
    maxplus.dense.star : ``E ⊕ A ⊕ A² ⊕ ...``.
    maxplus.transient.transient : when ``A^(t+c) = λ^c ⊗ A^t`` starts.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, §3.2 (path interpretation of powers).

    Examples
    --------
    >>> power([[3, 7], [2, 4]], 3).tolist()
    [[Fraction(13, 1), Fraction(16, 1)], [Fraction(11, 1), Fraction(13, 1)]]
    >>> power([[5]], 0).tolist()
    [[Fraction(0, 1)]]
    """
    M = square_matrix(A)
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 0:
        raise MaxPlusValueError(f"expected a non-negative integer exponent, got {k!r}", "k")
    k = int(k)
    # Entries of A^k are sums of k entries of A: growth k keeps float64 exact.
    base, scale = scaled(M, growth=max(k, 1) + 1)
    result = identity_scaled(len(M), base.dtype)
    while k:
        if k & 1:
            result = product_scaled(result, base)
        k >>= 1
        if k:
            base = product_scaled(base, base)
    return as_exact(result, scale)
