"""Exact (max,+) scalars and the validation of user input.

The semiring is ``R_max = (Q ∪ {ε}, ⊕ = max, ⊗ = +)`` [1]_ with ``ε = -inf``. Every
finite value is held as a :class:`fractions.Fraction`; ε is the float ``-inf``,
so Python's own ``max`` and ``+`` already implement ⊕ and ⊗ on these values
(``Fraction(3) + float('-inf') == float('-inf')``).

Inputs may be ints, Fractions, decimal or fraction strings (``"0.1"``,
``"7/3"``), floats (taken by their shortest decimal text, so ``0.1`` is exactly
``1/10``), and ``None`` / ``"eps"`` / ``-inf`` for ε. Everything is validated
once, here, with messages that name the offending entry: :func:`exact` is the one
number parser of the project (every file reader, command-line option and library
call converts through it), so one grammar and one bound hold everywhere.

The text of a number, after surrounding blanks are stripped, is exactly one of::

    number   := sign? ( digits "/" digits              one fraction p/q
                      | mantissa exponent? )           an integer or a decimal
    mantissa := digits ( "." digits? )? | "." digits
    exponent := ("e" | "E") sign? digits
    digits   := [0-9] ( "_"? [0-9] )*                  1_000: as Python and YAML 1.1
    sign     := "+" | "-"

Nothing else: no blank inside (``"1 000"``), no second slash (``"5/2/3"``), no
decimal in a fraction (``"1.5/2"``), no hexadecimal. The words ``nan`` and
``inf`` are refused by name; ``-inf``, ``eps``, ``ε`` mean ε where ε is allowed.
Booleans, complex numbers and other objects are refused; numpy integers are
integers and numpy floats are read, like floats, by their own shortest decimal
text (``np.float32(0.1)`` is ``1/10``); a :class:`~decimal.Decimal` by its text.

**The bound** (:data:`MAX_DIGITS`, 4,300: Python's own limit on converting a
text to an int): each integer of the text (``p``, ``q``, the digits of a
decimal) and the numerator and the denominator of the exact value have at most
4,300 digits. So ``1e4299`` is held exactly while ``1e999999999`` is refused
from its text, by its size ("has 1,000,000,000 digits; at most 4,300 are
accepted"), without being expanded; a refused text is shown by its first 40
characters and its length.

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
import re
from collections.abc import Iterable
from decimal import Decimal
from fractions import Fraction
from numbers import Integral, Rational
from typing import Any, Literal, overload

import numpy as np

from ._arrays import INT64_SAFE, int_array
from ._params import unmasked
from .errors import MaxPlusValueError

__all__ = [
    "EPS",
    "FLOAT_EXACT_BOUND",
    "INT64_SAFE",
    "MAX_DIGITS",
    "TOP",
    "Scalar",
    "DISPLAY_DIGITS",
    "common_denominator",
    "display_text",
    "exact",
    "exact_matrix",
    "exact_text",
    "exact_time",
    "exact_vector",
    "from_scaled",
    "int_array",
    "is_eps",
    "size_problem",
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


@overload
def exact(value: Any, where: str = ..., *, allow_eps: Literal[False]) -> Fraction: ...
@overload
def exact(value: Any, where: str = ..., allow_eps: bool = ...) -> Scalar: ...
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
        NaN, +inf, booleans, complex numbers, text outside the grammar of the
        module docstring (``"5/2/3"``), a zero denominator, or a number beyond
        :data:`MAX_DIGITS` digits (refused by its size, never expanded).

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


MAX_DIGITS = 4300
"""Most digits of a number: of each integer in its text, and of the numerator and the
denominator of its exact value (Python's own limit on converting text to an int)."""

# The grammar of a number's text (docs/skeleton.md, "Time values"): one sign, then ONE
# fraction of two integers or one decimal with an optional exponent. An underscore may
# stand between two digits, as in Python and YAML 1.1 (1_000). Nothing else: no space
# inside, no second slash ("5/2/3"), no decimal in a fraction ("1.5/2").
_DIGITS = r"[0-9](?:_?[0-9])*"
_NUMBER = re.compile(
    rf"(?P<sign>[+-]?)(?:(?P<p>{_DIGITS})/(?P<q>{_DIGITS})"
    rf"|(?P<int>{_DIGITS})?(?:\.(?P<frac>{_DIGITS})?)?(?:[eE](?P<exp>[+-]?{_DIGITS}))?)")
_NAN_WORDS = {"nan", "+nan", "-nan", "snan"}
_INF_WORDS = {"inf", "+inf", "infinity", "+infinity"}
_TEN_TO_LIMIT = 10**MAX_DIGITS
_SAFE_BITS = 14_000  # 2**14000 has 4,215 digits: fewer bits are always within the bound
_SHOWN = 40


def _shown(text: str) -> str:
    """A text for a message: quoted, cut to 40 characters with its length when longer."""
    if len(text) <= _SHOWN:
        return repr(text)
    return f"{text[:_SHOWN]!r}"[:-1] + f"...' ({len(text):,} characters)"


def _too_many(shown: str, digits: int | str, part: str = "") -> str:
    count = f"{digits:,}" if isinstance(digits, int) else digits
    return f"{shown} has {part}{count} digits; at most {MAX_DIGITS:,} are accepted"


def _int_problem(n: int, shown: str, what: str = "") -> str | None:
    """Why the integer ``n`` (a numerator or a denominator) is refused, or None."""
    n = abs(n)
    if n < _TEN_TO_LIMIT:
        return None
    bits = n.bit_length()
    # log10(2) = 0.30103: this count is exact or one too small; 10**d settles it (cheap
    # up to millions of digits; beyond, the count is given as "more than").
    if bits < 10**7:
        d = int((bits - 1) * 0.30102999566398120) + 1
        count: int | str = d + 1 if n >= 10**d else d
    else:
        count = f"more than {MAX_DIGITS:,}"
    return _too_many(shown, count, what)


def size_problem(value: Any) -> str | None:
    """Why a number is refused by its size, or None; the digit bound of every reader.

    A number is accepted when each integer of its text (``p`` and ``q`` of
    ``p/q``, the digits of a decimal) and the numerator and the denominator of
    its exact value have at most :data:`MAX_DIGITS` digits. The exponent of a
    decimal is bounded by that: ``1e999999999`` is refused from its text, never
    expanded. Values that are not numbers pass (the parser names them).

    Parameters
    ----------
    value : any

    Returns
    -------
    str or None

    Examples
    --------
    >>> size_problem("1e4299") is None, size_problem("7/3") is None
    (True, True)
    >>> size_problem("1e999999999")
    "'1e999999999' has 1,000,000,000 digits; at most 4,300 are accepted"
    >>> print(size_problem("9" * 5000))  # doctest: +ELLIPSIS
    '999...' (5,000 characters) has 5,000 digits; at most 4,300 are accepted
    """
    if isinstance(value, str) and len(value) < 40 and "e" not in value.lower():
        return None  # fewer than 40 digits and no exponent: nothing to bound (the fast path)
    try:
        _parse(value, "value")
    except _SizeError as err:
        return err.problem
    except MaxPlusValueError:
        return None
    return None


class _SizeError(MaxPlusValueError):
    """A number refused by its size (a MaxPlusValueError like every refusal)."""

    def __init__(self, problem: str, where: str) -> None:
        self.problem = problem
        super().__init__(problem, where)


def _text_value(text: str, where: str, original: Any) -> Scalar:
    """The exact value of a number's text, by the grammar above, within MAX_DIGITS."""
    stripped = text.strip()
    word = stripped.lower()
    if word in _EPS_WORDS:
        return EPS
    if word in _NAN_WORDS:
        raise MaxPlusValueError("expected a number, got NaN", where)
    if word in _INF_WORDS:
        raise MaxPlusValueError("+inf is not a (max,+) value (did you mean ε = -inf?)", where)
    shown = _shown(stripped)
    m = _NUMBER.fullmatch(stripped)
    if m is None or not (m["p"] or m["int"] or m["frac"]):
        raise MaxPlusValueError(
            f"expected a number such as 3, 0.5, 1e-3 or '7/3' (an integer, a decimal or one "
            f"fraction of two integers), got {shown}", where)
    sign = -1 if m["sign"] == "-" else 1
    if m["p"] is not None:
        p, q = m["p"].replace("_", ""), m["q"].replace("_", "")
        for part in (p, q):
            if len(part) > MAX_DIGITS:
                raise _SizeError(_too_many(shown, len(part)), where)
        if int(q) == 0:
            raise MaxPlusValueError(f"{shown} has a zero denominator", where)
        return Fraction(sign * int(p), int(q))
    whole, frac = (m["int"] or "").replace("_", ""), (m["frac"] or "").replace("_", "")
    mantissa = (whole + frac).lstrip("0")
    if len(whole) + len(frac) > MAX_DIGITS:
        raise _SizeError(_too_many(shown, len(whole) + len(frac)), where)
    exp_text = (m["exp"] or "0").replace("_", "")
    if not mantissa:
        return Fraction(0)  # 0e999999999 is zero, whatever its exponent
    exp_digits = exp_text.lstrip("+-").lstrip("0")
    # The value is M * 10**shift, M the mantissa's integer (1 to MAX_DIGITS digits).
    if len(exp_digits) > 12:  # |shift| > 10**12 - MAX_DIGITS: refused without int()
        if exp_text.startswith("-"):
            raise _SizeError(_too_many(shown, f"more than {MAX_DIGITS:,}",
                                       "a denominator of "), where)
        raise _SizeError(_too_many(shown, f"more than {10**12:,}"), where)
    shift = int(exp_text) - len(frac)
    if shift > 0 and len(mantissa) + shift > MAX_DIGITS:
        raise _SizeError(_too_many(shown, len(mantissa) + shift), where)
    # A denominator 10**k over a numerator M < 10**MAX_DIGITS keeps more than
    # k - MAX_DIGITS digits after reduction: k >= 2 * MAX_DIGITS is refused unexpanded.
    if shift <= -2 * MAX_DIGITS:
        raise _SizeError(_too_many(shown, f"more than {MAX_DIGITS:,}", "a denominator of "),
                         where)
    value = Fraction(sign * int(mantissa) * 10**max(shift, 0), 10**max(-shift, 0))
    why = _int_problem(value.denominator, shown, "a denominator of ")
    if why is not None:
        raise _SizeError(why, where)
    return value


# The numbers a skeleton file mostly holds: "98/3750", "12", "0.5", no blank, no "_",
# no exponent. Under _PLAIN_LENGTH characters no integer of them nears MAX_DIGITS, so
# their value is read without the general grammar's size accounting (same value: the
# test of the grammar compares both paths).
_PLAIN = re.compile(r"([+-]?)([0-9]+)(?:/([0-9]+)|\.([0-9]+))?")
_PLAIN_LENGTH = 100


def _plain_value(text: str) -> Fraction | None:
    """The value of a short plain text (see ``_PLAIN``), or None: the general grammar reads it."""
    if len(text) > _PLAIN_LENGTH:
        return None
    m = _PLAIN.fullmatch(text)
    if m is None:
        return None
    sign, whole, q, frac = m.groups()
    if q is not None:
        if q.strip("0") == "":
            return None  # a zero denominator: the general path words the refusal
        return Fraction(-int(whole) if sign == "-" else int(whole), int(q))
    if frac is not None:
        n = int(whole + frac)
        return Fraction(-n if sign == "-" else n, 10 ** len(frac))
    n = int(whole)
    return Fraction(-n if sign == "-" else n)


def _parse(value: Any, where: str) -> Scalar:
    """THE conversion of one user value (every reader, option and call goes through it)."""
    kind = type(value)
    if kind is int and value.bit_length() < _SAFE_BITS:
        return Fraction(value)  # the common case, within the bound for sure
    if kind is str:
        plain = _plain_value(value)
        if plain is not None:
            return plain
    if value is None:
        return EPS
    if isinstance(value, (bool, np.bool_)):
        raise MaxPlusValueError(f"expected a number, got the boolean {value!r}", where)
    if isinstance(value, str):
        return _text_value(value, where, value)
    if type(value) is Fraction and (value.numerator.bit_length() < _SAFE_BITS
                                    and value.denominator.bit_length() < _SAFE_BITS):
        return value  # the common case, within the bound for sure: no copy, no count
    if isinstance(value, (Integral, Rational)):
        result = (Fraction(int(value)) if isinstance(value, Integral)
                  else Fraction(int(value.numerator), int(value.denominator)))
        for part, what in ((result.numerator, ""), (result.denominator, "a denominator of ")):
            why = _int_problem(part, f"the {type(value).__name__}", what)
            if why is not None:
                raise _SizeError(why, where)
        return result
    if isinstance(value, (float, np.floating)):
        f = float(value)
        if math.isnan(f):
            raise MaxPlusValueError("expected a number, got NaN", where)
        if math.isinf(f):
            if f < 0:
                return EPS
            raise MaxPlusValueError("+inf is not a (max,+) value (did you mean ε = -inf?)", where)
        # The shortest decimal text that round-trips in the value's own precision:
        # 0.1 -> "0.1" -> 1/10, and np.float32(0.1) -> "0.1" too (not 0.10000000149...).
        return _text_value(repr(f) if isinstance(value, float) else str(value), where, value)
    if isinstance(value, Decimal):
        if value.is_nan():
            raise MaxPlusValueError("expected a number, got NaN", where)
        if value.is_infinite():
            if value < 0:
                return EPS
            raise MaxPlusValueError("+inf is not a (max,+) value (did you mean ε = -inf?)", where)
        return _text_value(str(value), where, value)  # its exponent bounded before expansion
    raise MaxPlusValueError(
        f"expected a number, got {type(value).__name__} {_shown(repr(value))}", where)


def _exact(value: Any, where: str) -> Scalar:
    return _parse(value, where)


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
    return exact(value, where, allow_eps=False)


@overload
def exact_text(value: Fraction | int) -> str: ...
@overload
def exact_text(value: None) -> None: ...
@overload
def exact_text(value: Fraction | int | None) -> str | None: ...
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
    if type(value) is not Fraction:  # a Fraction is read as it is (no copy: reports write
        value = Fraction(value)      # tens of thousands of them)
    n, d = value.numerator, value.denominator
    if n.bit_length() < _SAFE_BITS and d.bit_length() < _SAFE_BITS:  # str() takes them
        return str(n) if d == 1 else f"{n}/{d}"
    if d == 1:
        return _int_text(n)
    return f"{_int_text(n)}/{_int_text(d)}"


_CHUNK_DIGITS = 1000
_CHUNK = 10**_CHUNK_DIGITS


def _int_text(n: int) -> str:
    """``str(n)`` for an int of any size.

    Inputs are bounded (:data:`MAX_DIGITS`), but what is computed from them is not:
    the demand of a task of duration 1e-4299 over a hyperperiod has a denominator of
    4,301 digits, and ``str`` refuses more than 4,300 (Python's default guard).

    >>> _int_text(-(10**5000))[:4], len(_int_text(10**5000))
    ('-100', 5001)
    """
    if n.bit_length() < _SAFE_BITS:
        return str(n)
    sign, n = "-" if n < 0 else "", abs(n)
    chunks = []
    while n:
        n, r = divmod(n, _CHUNK)
        chunks.append(r)
    return sign + str(chunks[-1]) + "".join(f"{c:0{_CHUNK_DIGITS}d}" for c in chunks[-2::-1])

DISPLAY_DIGITS = 30
"""Most significant digits of a decimal that text reports print instead of a fraction."""


@overload
def display_text(value: Fraction | int) -> str: ...
@overload
def display_text(value: None) -> None: ...
@overload
def display_text(value: Fraction | int | None) -> str | None: ...
def display_text(value: Fraction | int | None) -> str | None:
    """An exact number as text reports print it: its decimal when it terminates.

    Inputs are written in decimal (``5.43``, ``1038412611.331``); a report
    prints them back the same way, exactly, and a fraction only when the
    decimal does not terminate (``7/3``) or would need more than
    :data:`DISPLAY_DIGITS` significant digits (``1/2**50``). Far from 1 the
    exact decimal is written in scientific notation (``3e-17``). JSON keeps
    :func:`exact_text` (``"543/100"``), its documented format.

    Parameters
    ----------
    value : Fraction, int or None

    Returns
    -------
    str or None

    See Also
    --------
    exact_text : the exact text of files and JSON.

    Examples
    --------
    >>> display_text(Fraction(543, 100)), display_text(Fraction(1038412611331, 1000))
    ('5.43', '1038412611.331')
    >>> display_text(Fraction(7, 3)), display_text(Fraction(-4)), display_text(Fraction(3, 10**17))
    ('7/3', '-4', '3e-17')
    >>> display_text(10 - Fraction(1, 10**18)), display_text(Fraction(1, 2**50))
    ('9.999999999999999999', '1/1125899906842624')
    """
    if value is None:
        return None
    if type(value) is not Fraction:  # a Fraction is read as it is (no copy)
        value = Fraction(value)
    if value.denominator == 1:
        return _int_text(value.numerator)
    d, places = value.denominator, 0
    for p in (2, 5):  # p/q terminates iff q = 2^a 5^b; it has max(a, b) places
        count = 0
        while d % p == 0:
            d //= p
            count += 1
        places = max(places, count)
    if d != 1 or places > DISPLAY_DIGITS + 4 * MAX_DIGITS:
        return exact_text(value)
    scaled = abs(value.numerator) * 10**places // value.denominator
    while places and scaled % 10 == 0:  # 2.50 -> 2.5
        scaled, places = scaled // 10, places - 1
    if scaled >= 10**DISPLAY_DIGITS:  # more digits than shown (and maybe than str takes)
        return exact_text(value)
    digits = str(scaled)
    if len(digits) > DISPLAY_DIGITS:
        return exact_text(value)
    # Built from its digits: no decimal context, so nothing is rounded.
    exact = Decimal((int(value < 0), tuple(map(int, digits)), -places))
    # Positional while that stays short (0.000123, 1234.5); scientific far from 1.
    return format(exact, "f" if -7 <= exact.adjusted() < DISPLAY_DIGITS else "e")


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
    values = unmasked(values, name)  # a masked entry would be read as what lies under it
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
    values = unmasked(values, name)
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
            # A float here is EPS or TOP, skipped above: the types (Fraction | float)
            # cannot say that the only floats are those two.
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
    arr: np.ndarray
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
