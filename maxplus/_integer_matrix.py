"""A square (max,+) matrix as exact scaled integers, validated once, cheaply.

The spectral functions only need integers: every entry times the common
denominator ``scale``, and a mask of the finite entries (the arcs). The
general validator :func:`maxplus.scalar.exact_matrix` builds one Fraction per
entry, which costs more than the whole eigenvalue computation on a dense
matrix. Here the two common inputs skip it: nested lists of plain Python ints
and ``None`` (one type test per entry, then one numpy conversion), and numpy
arrays of integers or of integral floats (with ``-inf`` for ε). Everything
else (fractions, decimals, text, bad entries) goes through ``exact_matrix``,
which names the offending entry.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from ._arrays import INT64_SAFE
from ._params import unmasked
from .scalar import common_denominator, exact_matrix, is_eps

__all__ = ["IntegerMatrix", "from_exact", "integer_matrix", "plain_int_rows", "rows_of"]

_FLOAT_EXACT = 2**53
_PLAIN = {int, type(None)}


class IntegerMatrix(NamedTuple):
    """``values[i, j] / scale`` is ``A[i][j]`` where ``finite[i, j]`` (0 elsewhere)."""

    values: np.ndarray  # int64, or object (Python ints) beyond the int64-safe range
    finite: np.ndarray  # bool
    scale: int


def plain_int_rows(A: Any) -> list[list[int | None]] | None:
    """``A`` itself when it is a non-empty square list of lists of ints and None.

    Returns None for anything else (the caller then validates the general way).

    Examples
    --------
    >>> plain_int_rows([[1, None], [2, 3]])
    [[1, None], [2, 3]]
    >>> plain_int_rows([[1, 0.5], [2, 3]]) is None, plain_int_rows([[True]]) is None
    (True, True)
    """
    if type(A) is not list or not A:
        return None
    n = len(A)
    for row in A:
        if type(row) is not list or len(row) != n or not _PLAIN.issuperset(map(type, row)):
            return None
    return A


def integer_matrix(A: Any, name: str = "A") -> IntegerMatrix:
    """Validate a square matrix and return it as scaled integers.

    Parameters
    ----------
    A : nested lists or 2-D array
        Entries as accepted by :func:`maxplus.scalar.exact`.
    name : str
        Name used in error messages.

    Returns
    -------
    IntegerMatrix

    Raises
    ------
    MaxPlusValueError
        A bad entry (named), a ragged or non-square matrix.

    Examples
    --------
    >>> m = integer_matrix([["1/2", None], [1, 0]])
    >>> m.values.tolist(), m.finite.tolist(), m.scale
    ([[1, 0], [2, 0]], [[True, False], [True, True]], 2)
    """
    A = unmasked(A, name)  # the fast path would read what lies under a mask
    if isinstance(A, np.ndarray) and A.ndim == 2 and A.size and A.shape[0] == A.shape[1]:
        fast = _from_array(A)
        if fast is not None:
            return fast
    rows = plain_int_rows(A)
    if rows is not None:
        return _from_int_rows(rows)
    return from_exact(exact_matrix(A, name, square=True))


def _from_array(A: np.ndarray) -> IntegerMatrix | None:
    kind = A.dtype.kind
    if kind in "iu":
        if kind == "u" and int(A.max()) >= INT64_SAFE:
            return None
        values = A.astype(np.int64)
        if _abs_max(values) >= INT64_SAFE:
            return None
        return IntegerMatrix(values, np.ones(A.shape, dtype=bool), 1)
    if kind == "f":
        with np.errstate(invalid="ignore"):
            finite = A != -np.inf
            inner = np.where(finite, A, 0.0)
            # NaN, +inf, fractions and floats beyond 2**53 (read by their
            # decimal text) are the general validator's job.
            if not (np.all(np.abs(inner) < _FLOAT_EXACT) and np.all(inner == np.round(inner))):
                return None
        return IntegerMatrix(inner.astype(np.int64), finite, 1)
    return None


def _from_int_rows(rows: list[list[int | None]]) -> IntegerMatrix:
    try:
        floats = np.array(rows, dtype=float)  # None -> nan
    except OverflowError:  # an int beyond float range: Python ints it is
        floats = None
    if floats is not None:
        finite = ~np.isnan(floats)
        if np.all(np.abs(floats[finite]) < _FLOAT_EXACT):
            # Below 2**53 every int converts exactly (and rounding can only move a
            # larger one up to 2**53, so the test cannot pass wrongly).
            return IntegerMatrix(np.where(finite, floats, 0.0).astype(np.int64), finite, 1)
    n = len(rows)
    values = np.zeros((n, n), dtype=object)
    finite = np.zeros((n, n), dtype=bool)
    for i, row in enumerate(rows):
        for j, v in enumerate(row):
            if v is not None:
                values[i, j] = v
                finite[i, j] = True
    return _narrow(values, finite, 1)


def from_exact(M: np.ndarray) -> IntegerMatrix:
    """An already validated exact matrix (Fraction / EPS entries) as scaled integers.

    >>> from fractions import Fraction
    >>> from_exact(np.array([[Fraction(1, 3), float("-inf")]], dtype=object)).values.tolist()
    [[1, 0]]
    """
    flat = M.ravel().tolist()
    scale = common_denominator(flat)
    finite = np.array([not is_eps(v) for v in flat], dtype=bool).reshape(M.shape)
    values = np.zeros(M.shape, dtype=object)
    values.reshape(-1)[:] = [0 if is_eps(v) else int(v * scale) for v in flat]
    return _narrow(values, finite, scale)


def _narrow(values: np.ndarray, finite: np.ndarray, scale: int) -> IntegerMatrix:
    """int64 when every value is safely inside its range, else keep Python ints."""
    if _abs_max(values) < INT64_SAFE:
        values = values.astype(np.int64)
    return IntegerMatrix(values, finite, scale)


def _abs_max(a: np.ndarray) -> int:
    if a.size == 0:
        return 0
    return max(abs(int(a.max())), abs(int(a.min())))


def rows_of(matrix: IntegerMatrix) -> list[list[int | None]]:
    """The matrix as lists of Python ints, ``None`` where there is no arc."""
    values = matrix.values.tolist()
    mask = matrix.finite.tolist()
    return [[int(v) if f else None for v, f in zip(vr, fr)] for vr, fr in zip(values, mask)]
