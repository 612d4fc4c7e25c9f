"""Operands and scaled-integer arithmetic shared by the dense (max,+) modules.

Every dense function validates its operands here (scalars, vectors, matrices
as exact ``Fraction`` / ``EPS`` values), scales them by one common
denominator, and works on integers: float64 while the caller's growth bound
keeps every sum below 2**52 (see :func:`maxplus.scalar.to_scaled`), Python
ints in object arrays otherwise.

In object arrays ε is :data:`BOTTOM`, not ``float('-inf')``: ``int + float``
converts the int to a float, which overflows beyond about 1.8e308, so a
Python int of 400 digits plus ``-inf`` raises instead of giving ε.
:data:`BOTTOM` orders and compares like ``-inf`` (it is ``== -inf``) but
absorbs every sum without converting anything.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from fractions import Fraction
from typing import Any

import numpy as np

from ._params import unmasked
from .errors import MaxPlusValueError
from .scalar import (
    EPS,
    TOP,
    Scalar,
    common_denominator,
    exact,
    exact_matrix,
    exact_vector,
    is_eps,
    to_scaled,
)

__all__ = [
    "BOTTOM",
    "as_exact",
    "bottom",
    "identity_scaled",
    "operand",
    "product_scaled",
    "rank_of",
    "scale_together",
    "scaled",
    "square_matrix",
    "times",
]


class _Bottom:
    """ε among Python ints: below every number, absorbing for ``+``.

    Differences follow the residuation conventions (``a − ε = ⊤``,
    ``ε − a = ε``, ``ε − ε = ⊤``).
    """

    __slots__ = ()

    def __add__(self, other: Any) -> _Bottom:
        return self

    __radd__ = __add__

    def __sub__(self, other: Any) -> Any:
        return TOP if self.__eq__(other) else self

    def __rsub__(self, other: Any) -> float:
        return TOP

    def __neg__(self) -> float:
        return TOP

    def __eq__(self, other: object) -> bool:
        return other is self or (isinstance(other, float) and other == -math.inf)

    def __ne__(self, other: object) -> bool:
        return not self.__eq__(other)

    def __lt__(self, other: Any) -> bool:
        return not self.__eq__(other)

    def __le__(self, other: Any) -> bool:
        return True

    def __gt__(self, other: Any) -> bool:
        return False

    def __ge__(self, other: Any) -> bool:
        return self.__eq__(other)

    def __hash__(self) -> int:
        return hash(-math.inf)

    def __float__(self) -> float:
        return -math.inf

    def __repr__(self) -> str:
        return "BOTTOM"


BOTTOM = _Bottom()
"""ε in object arrays of scaled integers."""


def bottom(dtype: Any) -> Any:
    """ε of a scaled array of this dtype: ``-inf`` for float64, :data:`BOTTOM` for object.

    >>> bottom(float), bottom(object)
    (-inf, BOTTOM)
    """
    return BOTTOM if np.dtype(dtype) == object else -np.inf


def times(a: Scalar, b: Scalar) -> Scalar:
    """Exact ``a ⊗ b`` of two scalars (ε absorbing; no float conversion of a huge Fraction).

    >>> times(Fraction(10**400), EPS), times(Fraction(1, 2), Fraction(1, 3))
    (-inf, Fraction(5, 6))
    """
    return EPS if is_eps(a) or is_eps(b) else a + b


# --------------------------------------------------------------------------- operands


def rank_of(value: Any) -> int:
    """0 for a scalar, 1 for a vector, 2 for a matrix, without building an array.

    (``np.asarray`` of a ragged list would fail before we can name the row.)

    >>> rank_of(3), rank_of([1, 2]), rank_of([[1], [2, 3]])
    (0, 1, 2)
    """
    if isinstance(value, np.ndarray):
        return value.ndim
    if isinstance(value, (list, tuple)):
        return 2 if any(isinstance(e, (list, tuple, np.ndarray)) for e in value) else 1
    return 0


def operand(value: Any, name: str, square: bool = False) -> tuple[Any, int]:
    """Validate a scalar, vector or matrix; return (exact value, rank).

    >>> operand([1, None], "x")[0].tolist()
    [Fraction(1, 1), -inf]
    """
    value = unmasked(value, name)
    rank = rank_of(value)
    if rank == 0:
        item = value.item() if isinstance(value, np.ndarray) else value
        return exact(item, name), 0
    if rank == 1:
        entries = exact_vector(value, name)
        if not entries:
            raise MaxPlusValueError("the vector is empty", name)
        vec = np.empty(len(entries), dtype=object)
        vec[:] = entries
        return vec, 1
    if rank == 2:
        return exact_matrix(value, name, square=square), 2
    raise MaxPlusValueError(f"expected a scalar, vector or matrix, got {rank} dimensions", name)


def square_matrix(value: Any, name: str = "A") -> np.ndarray:
    """A validated square matrix (a fresh object array: the input is never touched).

    >>> square_matrix([[1]]).tolist()
    [[Fraction(1, 1)]]
    """
    value = unmasked(value, name)
    if rank_of(value) != 2:
        raise MaxPlusValueError("expected a square matrix (list of rows)", name)
    return exact_matrix(value, name, square=True)


# --------------------------------------------------------------------------- scaled integers


def _with_bottom(array: np.ndarray) -> np.ndarray:
    """An object array with every ε (``-inf``) replaced by :data:`BOTTOM` (in place)."""
    flat = array.reshape(-1)
    for k, v in enumerate(flat.tolist()):
        if isinstance(v, float) and v == -math.inf:
            flat[k] = BOTTOM
    return array


def scaled(matrix: np.ndarray, scale: int | None = None, growth: int = 1) -> tuple[np.ndarray, int]:
    """:func:`maxplus.scalar.to_scaled`, with :data:`BOTTOM` for ε in object arrays.

    >>> a, s = scaled(np.array([[Fraction(10**400), EPS]], dtype=object))
    >>> a.dtype, a[0, 1]
    (dtype('O'), BOTTOM)
    """
    array, scale = to_scaled(matrix, scale, growth)
    if array.dtype == object:
        _with_bottom(array)
    return array, scale


def _object_ints(array: np.ndarray) -> np.ndarray:
    """Scaled float64 array -> object array of Python ints (and BOTTOM)."""
    if array.dtype == object:
        return array
    out = np.empty(array.shape, dtype=object)
    flat = out.reshape(-1)
    for k, v in enumerate(array.ravel().tolist()):
        flat[k] = BOTTOM if v == -math.inf else int(v)
    return out


def scale_together(arrays: Sequence[np.ndarray], growth: int = 2) -> tuple[list[np.ndarray], int]:
    """Scale exact object arrays by one common denominator, in one dtype.

    float64 is used only when every array qualifies; mixing float64 with
    Python ints would silently round, so one object array turns them all
    into object arrays.

    >>> (a, b), s = scale_together([np.array([Fraction(1, 2)], dtype=object),
    ...                             np.array([Fraction(1, 3)], dtype=object)])
    >>> s, a.tolist(), b.tolist()
    (6, [3.0], [2.0])
    """
    scale = common_denominator(v for a in arrays for v in a.ravel().tolist())
    out = [scaled(a, scale, growth)[0] for a in arrays]
    if any(s.dtype == object for s in out):
        out = [_object_ints(s) for s in out]
    return out, scale


def as_exact(array: np.ndarray, scale: int) -> np.ndarray:
    """Scaled integers back to exact values: an object array of Fraction / EPS / TOP.

    >>> as_exact(np.array([[1.0, -np.inf]]), 2).tolist()
    [[Fraction(1, 2), -inf]]
    """
    out = np.empty(array.shape, dtype=object)
    flat = out.reshape(-1)
    for k, v in enumerate(array.ravel().tolist()):
        if v is BOTTOM or (isinstance(v, float) and v == -math.inf):
            flat[k] = EPS
        elif isinstance(v, float) and v == math.inf:
            flat[k] = TOP
        else:
            flat[k] = Fraction(int(v), scale)
    return out


def identity_scaled(n: int, dtype: Any = float) -> np.ndarray:
    """The (max,+) identity E on scaled integers (0 on the diagonal, ε elsewhere).

    >>> identity_scaled(2).tolist()
    [[0.0, -inf], [-inf, 0.0]]
    """
    out = np.full((n, n), bottom(dtype), dtype=dtype)
    zero = 0 if np.dtype(dtype) == object else 0.0  # a Python int keeps object sums exact
    for i in range(n):
        out[i, i] = zero
    return out


def product_scaled(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """``X ⊗ Y`` of two scaled 2-D arrays of one dtype.

    The loop runs over the inner dimension so memory stays O(rows × cols)
    (the broadcast ``X[:, :, None] + Y[None]`` would need rows × inner × cols).

    >>> product_scaled(np.array([[1.0, 2.0]]), np.array([[0.0], [5.0]])).tolist()
    [[7.0]]
    """
    out = np.full((X.shape[0], Y.shape[1]), bottom(X.dtype), dtype=X.dtype)
    for j in range(X.shape[1]):
        np.maximum(out, X[:, j, None] + Y[None, j, :], out=out)
    return out
