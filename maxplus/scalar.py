"""Exact (max,+) scalars and the validation of user input.

The semiring is ``R_max = (Q ∪ {ε}, ⊕ = max, ⊗ = +)`` [1]_ with ``ε = -inf``. Every
finite value is held as a :class:`fractions.Fraction`; ε is the float ``-inf``,
so Python's own ``max`` and ``+`` already implement ⊕ and ⊗ on these values
(``Fraction(3) + float('-inf') == float('-inf')``).

Inputs may be ints, Fractions, decimal or fraction strings (``"0.1"``,
``"7/3"``), floats (taken by their shortest decimal text, so ``0.1`` is exactly
``1/10``), and ``None`` / ``"eps"`` / ``-inf`` for ε. Everything is validated
once, here, with messages that name the offending entry.

Internally the algorithms work on *scaled integers*: all entries of a matrix
multiplied by the least common multiple of their denominators. Integers below
2**53 are exact in binary floating point, so a float64 array of scaled
integers (with ``-inf`` for ε) gives exact (max,+) arithmetic at numpy speed;
above that bound the same code runs on object arrays of Python ints.

References
----------
.. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
   and Linearity*, Wiley, 1992, §3.2 (the semiring R_max = (R ∪ {ε}, max, +)).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from decimal import Decimal
from fractions import Fraction
from numbers import Integral, Rational
from typing import Any

import numpy as np

from ._arrays import INT64_SAFE, int_array
from .errors import MaxPlusValueError

__all__ = [
    "EPS",
    "FLOAT_EXACT_BOUND",
    "INT64_SAFE",
    "TOP",
    "Scalar",
    "common_denominator",
    "exact",
    "exact_matrix",
    "exact_text",
    "exact_time",
    "exact_vector",
    "from_scaled",
    "int_array",
    "is_eps",
    "to_scaled",
]

EPS: float = float("-inf")
"""The (max,+) zero ε (neutral for ⊕, absorbing for ⊗)."""

TOP: float = float("inf")
"""The top element ⊤, only produced by residuation (``ε \\ ε``)."""

Scalar = Fraction | float
"""An exact (max,+) scalar: a Fraction, or ``EPS`` (``-inf``)."""

FLOAT_EXACT_BOUND = 2**52
"""Scaled integers of absolute value below this stay exact in float64 sums of two."""

_EPS_WORDS = {"eps", "ε", "-inf", "-infinity", "epsilon", "e"}


def is_eps(value: Any) -> bool:
    """Return True when ``value`` is ε (``-inf``).

    Parameters
    ----------
    value : any

    Returns
    -------
    bool

    See Also
    --------
    exact : reads ``None``, ``"eps"`` and ``-inf`` as ε.

    Examples
    --------
    >>> is_eps(EPS), is_eps(Fraction(0))
    (True, False)
    """
    return isinstance(value, float) and value == EPS


def exact(value: Any, where: str = "value", allow_eps: bool = True) -> Scalar:
    """Convert one user value to an exact (max,+) scalar.

    Parameters
    ----------
    value : int, Fraction, str, float, Decimal, None
        The value. Floats are read by their shortest decimal text (``0.1`` is
        ``1/10``); ``None``, ``"eps"`` and ``-inf`` mean ε.
    where : str
        Name of the entry, used in error messages (e.g. ``"A[0][1]"``).
    allow_eps : bool
        When False, ε is refused (for durations, token counts, ...).

    Returns
    -------
    Fraction or EPS

    Raises
    ------
    MaxPlusValueError
        NaN, +inf, booleans, text that is not a number, a zero denominator.

    See Also
    --------
    exact_time : a finite value (no ε).
    exact_vector, exact_matrix : whole vectors and matrices, entries named.

    Examples
    --------
    >>> exact("7/3"), exact(0.1), exact(None), exact("2.5")
    (Fraction(7, 3), Fraction(1, 10), -inf, Fraction(5, 2))
    """
    result = _exact(value, where)
    if not allow_eps and is_eps(result):
        raise MaxPlusValueError("expected a finite number, got ε (-inf)", where)
    return result


def _exact(value: Any, where: str) -> Scalar:
    if value is None:
        return EPS
    if isinstance(value, (bool, np.bool_)):
        raise MaxPlusValueError(f"expected a number, got the boolean {value!r}", where)
    if isinstance(value, Fraction):
        return value
    if isinstance(value, Integral):
        return Fraction(int(value))
    if isinstance(value, Rational):
        return Fraction(value.numerator, value.denominator)
    if isinstance(value, (float, np.floating)):
        f = float(value)
        if math.isnan(f):
            raise MaxPlusValueError("expected a number, got NaN", where)
        if f == EPS:
            return EPS
        if math.isinf(f):
            raise MaxPlusValueError("+inf is not a (max,+) value (did you mean ε = -inf?)", where)
        # repr gives the shortest decimal text that round-trips: 0.1 -> "0.1" -> 1/10.
        return Fraction(repr(f))
    if isinstance(value, Decimal):
        if not value.is_finite():
            if value.is_infinite() and value < 0:
                return EPS
            raise MaxPlusValueError(f"expected a finite number, got {value}", where)
        return Fraction(value)
    if isinstance(value, str):
        text = value.strip()
        if text.lower() in _EPS_WORDS:
            return EPS
        try:
            if "/" in text:
                num, den = text.split("/", 1)
                if Fraction(den.strip()) == 0:
                    raise MaxPlusValueError(f"{value!r} has a zero denominator", where)
                return Fraction(num.strip()) / Fraction(den.strip())
            return Fraction(text)
        except MaxPlusValueError:
            raise
        except (ValueError, ZeroDivisionError):
            raise MaxPlusValueError(
                f"expected a number such as 3, 0.5 or '7/3', got the text {value!r}", where
            ) from None
    raise MaxPlusValueError(
        f"expected a number, got {type(value).__name__} {value!r}", where
    )


def exact_time(value: Any, where: str = "value") -> Fraction:
    """Convert a finite time value (no ε) to a Fraction.

    Parameters
    ----------
    value : int, Fraction, str, float, Decimal
        As accepted by :func:`exact`.
    where : str
        Name of the entry, used in error messages.

    Returns
    -------
    Fraction

    Raises
    ------
    MaxPlusValueError
        ε, NaN, ±inf, or anything :func:`exact` refuses.

    See Also
    --------
    exact : the same, ε allowed.
    exact_text : writes such a value back.

    Examples
    --------
    >>> exact_time("0.25")
    Fraction(1, 4)
    """
    return exact(value, where, allow_eps=False)  # type: ignore[return-value]


def exact_text(value: Fraction | int | None) -> str | None:
    """An exact number as reports write it: ``"7/3"``, ``"2"``; None stays None.

    Parameters
    ----------
    value : Fraction, int or None

    Returns
    -------
    str or None

    See Also
    --------
    exact_time : reads such a text back.

    Examples
    --------
    >>> exact_text(Fraction(7, 3)), exact_text(Fraction(4, 2)), exact_text(None)
    ('7/3', '2', None)
    """
    if value is None:
        return None
    value = Fraction(value)
    if value.denominator == 1:
        return str(value.numerator)
    return f"{value.numerator}/{value.denominator}"

def exact_vector(values: Any, name: str = "x", allow_eps: bool = True) -> list[Scalar]:
    """Validate a vector of (max,+) scalars.

    Parameters
    ----------
    values : list or 1-D array
        Entries as accepted by :func:`exact`.
    name : str
        Name used in error messages (an entry is named ``x[i]``).
    allow_eps : bool
        When False, ε is refused.

    Returns
    -------
    list of Fraction or EPS

    Raises
    ------
    MaxPlusValueError
        Not a list, a nested list, or a bad entry (named).

    See Also
    --------
    exact_matrix : the same for a matrix.
    exact : one entry.

    Examples
    --------
    >>> exact_vector([1, None, "1/2"])
    [Fraction(1, 1), -inf, Fraction(1, 2)]
    """
    if isinstance(values, np.ndarray):
        if values.ndim != 1:
            raise MaxPlusValueError(f"expected a vector, got an array of shape {values.shape}",
                                    name)
        values = values.tolist()
    if isinstance(values, (str, bytes)) or not isinstance(values, Iterable):
        raise MaxPlusValueError(f"expected a list of numbers, got {type(values).__name__}", name)
    out = []
    for i, v in enumerate(values):
        if isinstance(v, (list, tuple, np.ndarray)):
            raise MaxPlusValueError("expected a number, got a nested list", f"{name}[{i}]")
        out.append(exact(v, f"{name}[{i}]", allow_eps))
    return out


def exact_matrix(values: Any, name: str = "A", square: bool = True) -> np.ndarray:
    """Validate a matrix and return it as an object array of exact scalars.

    Parameters
    ----------
    values : nested lists or 2-D array
        Entries as accepted by :func:`exact`.
    name : str
        Name used in error messages.
    square : bool
        Refuse non-square matrices.

    Returns
    -------
    numpy.ndarray of dtype object
        Entries are ``Fraction`` or ``EPS``.

    Raises
    ------
    MaxPlusValueError
        Ragged rows, wrong shape, or a bad entry (named as ``A[i][j]``).

    See Also
    --------
    exact_vector : the same for a vector.
    to_scaled : the matrix as scaled integers.

    Examples
    --------
    >>> exact_matrix([[1, None], ["1/2", 0.25]]).tolist()
    [[Fraction(1, 1), -inf], [Fraction(1, 2), Fraction(1, 4)]]
    """
    if isinstance(values, np.ndarray):
        if values.ndim != 2:
            raise MaxPlusValueError(
                f"expected a 2-D matrix, got an array of shape {values.shape}", name
            )
        rows = values.tolist()
    else:
        if isinstance(values, (str, bytes)) or not isinstance(values, Iterable):
            raise MaxPlusValueError(
                f"expected a matrix (list of rows), got {type(values).__name__}", name
            )
        rows = list(values)
    n_rows = len(rows)
    if n_rows == 0:
        raise MaxPlusValueError("the matrix is empty", name)
    width = None
    out = np.empty((n_rows, 0), dtype=object)
    parsed: list[list[Scalar]] = []
    for i, row in enumerate(rows):
        if isinstance(row, (str, bytes)) or not isinstance(row, (Iterable, np.ndarray)):
            raise MaxPlusValueError(
                f"expected a row (list of numbers), got {type(row).__name__} {row!r}",
                f"{name}[{i}]",
            )
        row = list(row)
        if width is None:
            width = len(row)
        elif len(row) != width:
            raise MaxPlusValueError(
                f"ragged matrix: row {i} has {len(row)} entries, row 0 has {width}", f"{name}[{i}]"
            )
        parsed.append([_exact_entry(v, f"{name}[{i}][{j}]") for j, v in enumerate(row)])
    assert width is not None
    if width == 0:
        raise MaxPlusValueError("the matrix has no columns", name)
    if square and width != n_rows:
        raise MaxPlusValueError(f"expected a square matrix, got {n_rows}x{width}", name)
    out = np.empty((n_rows, width), dtype=object)
    for i, row in enumerate(parsed):
        for j, v in enumerate(row):
            out[i, j] = v
    return out


def _exact_entry(value: Any, where: str) -> Scalar:
    if isinstance(value, (list, tuple, np.ndarray)):
        raise MaxPlusValueError("expected a number, got a nested list", where)
    return exact(value, where)


def common_denominator(values: Iterable[Scalar]) -> int:
    """Least common multiple of the denominators of the finite values.

    Parameters
    ----------
    values : iterable of Fraction or EPS (TOP is skipped too)

    Returns
    -------
    int

    See Also
    --------
    to_scaled : scales a matrix by it.

    Examples
    --------
    >>> common_denominator([Fraction(1, 2), Fraction(2, 3), EPS])
    6
    """
    scale = 1
    for v in values:
        if not is_eps(v) and not (isinstance(v, float) and v == TOP):
            scale = math.lcm(scale, v.denominator)  # type: ignore[union-attr]
    return scale


def to_scaled(matrix: np.ndarray, scale: int | None = None,
              growth: int = 1) -> tuple[np.ndarray, int]:
    """Scale an exact object array to integers, in float64 when that stays exact.

    Parameters
    ----------
    matrix : numpy.ndarray of dtype object
        Entries Fraction or EPS (as returned by :func:`exact_matrix`).
    scale : int, optional
        Common denominator to use (default: the least one).
    growth : int
        How many times the largest magnitude may be added up by the caller's
        algorithm (e.g. ``n`` for a closure, ``k`` for a k-th power). float64 is
        used only when ``growth * max|entry| * scale`` stays below 2**52.

    Returns
    -------
    (array, scale)
        ``array`` holds ``entry * scale`` as integers (float64 with ``-inf``
        for ε, or object dtype holding Python ints and ``-inf``).

    See Also
    --------
    from_scaled : the inverse.
    common_denominator : the default scale.

    Examples
    --------
    >>> a, s = to_scaled(exact_matrix([["1/2", None], [1, 0]]))
    >>> s, a.tolist()
    (2, [[1.0, -inf], [2.0, 0.0]])
    """
    flat = matrix.ravel().tolist()
    if scale is None:
        scale = common_denominator(flat)
    ints: list[Any] = [v if is_eps(v) else int(v * scale) for v in flat]
    largest = max((abs(v) for v in ints if not is_eps(v)), default=0)
    if (largest + 1) * max(growth, 1) < FLOAT_EXACT_BOUND:
        arr = np.array(ints, dtype=float).reshape(matrix.shape)
    else:
        arr = np.empty(len(ints), dtype=object)
        arr[:] = ints
        arr = arr.reshape(matrix.shape)
    return arr, scale


def from_scaled(array: np.ndarray, scale: int) -> np.ndarray:
    """Inverse of :func:`to_scaled`: an object array of Fraction / EPS / TOP.

    Parameters
    ----------
    array : numpy.ndarray
        Scaled integers (float64 or object), ``-inf`` for ε, ``+inf`` for ⊤.
    scale : int
        The common denominator the values were multiplied by.

    Returns
    -------
    numpy.ndarray of dtype object

    See Also
    --------
    to_scaled : the forward conversion.

    Examples
    --------
    >>> from_scaled(np.array([[1.0, -np.inf]]), 2).tolist()
    [[Fraction(1, 2), -inf]]
    """
    out = np.empty(array.shape, dtype=object)
    flat = out.reshape(-1)
    for k, v in enumerate(array.ravel().tolist()):
        if isinstance(v, float) and math.isinf(v):
            flat[k] = EPS if v < 0 else TOP
        else:
            flat[k] = Fraction(int(v), scale)
    return out
