"""Residuation of the (max,+) product: the greatest solutions of ``A ⊗ X <= B``
and ``X ⊗ A <= B``.

``(A \\ B)[j][k] = min_i (B[i][k] − A[i][j])`` with ``x − ε = ⊤`` (+inf,
:data:`maxplus.scalar.TOP`, also ``ε − ε = ⊤``) and ``ε − a = ε`` for finite
a [1]_. The public functions are importable from :mod:`maxplus.dense` and
:mod:`maxplus`.

References
----------
.. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
   and Linearity*, Wiley, 1992, §4.4 (residuation) and §4.5.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ._scaled import as_exact, operand, scale_together
from .errors import MaxPlusValueError

__all__ = ["left_residual", "right_residual"]


def _left_residual_scaled(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """``(A \\ B)[j][k] = min_i (B[i][k] - A[i][j])`` with ``x - ε = ⊤`` (+inf)."""
    m, p = A.shape[1], B.shape[1]
    out = np.full((m, p), np.inf, dtype=A.dtype)
    with np.errstate(invalid="ignore"):
        for i in range(A.shape[0]):
            row_a = A[i][:, None]
            # ε in A constrains nothing (⊤); ε in B against a finite A forces ε.
            diff = np.where(np.asarray(row_a == -np.inf, dtype=bool), np.inf, B[i][None, :] - row_a)
            np.minimum(out, diff, out=out)
    return out


def left_residual(A: Any, B: Any) -> np.ndarray:
    """Left residual ``A \\ B``: the greatest X with ``A ⊗ X ≤ B``.

    ``(A \\ B)[j][k] = min_i (B[i][k] − A[i][j])`` with the conventions
    ``x − ε = ⊤`` (+inf, ``maxplus.scalar.TOP``; also ``ε − ε = ⊤``) and
    ``ε − a = ε`` for finite a. A column of A that is all ε gives a row of ⊤.

    Parameters
    ----------
    A : matrix (n × m)
    B : matrix (n × p) or vector (n)

    Returns
    -------
    numpy.ndarray of dtype object
        m × p (a vector of length m for a vector B); entries Fraction, EPS or TOP.

    Raises
    ------
    MaxPlusValueError
        A bad entry (named), or A and B with different numbers of rows.

    See Also
    --------
    right_residual : the greatest X with ``X ⊗ A ≤ B``.
    maxplus.dense.otimes : the product being residuated.
    maxplus.dense.solve : the least solution of ``x = A x ⊕ b``.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, §4.4 (residuation of ⊗, in matrix form).

    Examples
    --------
    >>> left_residual([[1, 2], [3, None]], [5, 6]).tolist()
    [Fraction(3, 1), Fraction(3, 1)]
    >>> left_residual([[None]], [[None]]).tolist()
    [[inf]]
    """
    a, rank_a = operand(A, "A")
    b, rank_b = operand(B, "B")
    if rank_a != 2 or rank_b == 0:
        raise MaxPlusValueError("expected a matrix A and a matrix or vector B",
                                "A" if rank_a != 2 else "B")
    right = b.reshape(-1, 1) if rank_b == 1 else b
    if a.shape[0] != right.shape[0]:
        raise MaxPlusValueError(f"A has {a.shape[0]} rows but B has {right.shape[0]}", "B")
    (sa, sb), scale = scale_together([a, right], growth=2)
    result = as_exact(_left_residual_scaled(sa, sb), scale)
    return result[:, 0] if rank_b == 1 else result


def right_residual(B: Any, A: Any) -> np.ndarray:
    """Right residual ``B / A``: the greatest X with ``X ⊗ A ≤ B``.

    ``(B / A)[k][i] = min_j (B[k][j] − A[i][j])``, same ⊤ conventions as
    :func:`left_residual`; ``B / A = (Aᵀ \\ Bᵀ)ᵀ``.

    Parameters
    ----------
    B : matrix (p × m) or vector (m, a row)
    A : matrix (n × m)

    Returns
    -------
    numpy.ndarray of dtype object
        p × n (a vector of length n for a vector B).

    Raises
    ------
    MaxPlusValueError
        A bad entry (named), or A and B with different numbers of columns.

    See Also
    --------
    left_residual : the greatest X with ``A ⊗ X ≤ B``.
    maxplus.dense.otimes : the product being residuated.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, §4.4.

    Examples
    --------
    >>> right_residual([[5, 6]], [[1, 2], [3, None]]).tolist()
    [[Fraction(4, 1), Fraction(2, 1)]]
    """
    b, rank_b = operand(B, "B")
    a, rank_a = operand(A, "A")
    if rank_a != 2 or rank_b == 0:
        raise MaxPlusValueError("expected a matrix or vector B and a matrix A",
                                "A" if rank_a != 2 else "B")
    left = b.reshape(1, -1) if rank_b == 1 else b
    if a.shape[1] != left.shape[1]:
        raise MaxPlusValueError(f"A has {a.shape[1]} columns but B has {left.shape[1]}", "B")
    (sa, sb), scale = scale_together([a, left], growth=2)
    result = as_exact(_left_residual_scaled(sa.T.copy(), sb.T.copy()).T, scale)
    return result[0, :] if rank_b == 1 else result
