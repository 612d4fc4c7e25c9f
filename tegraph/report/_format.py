"""Number formatting shared by every text rendering: exact, as the input said it.

A time prints as the input would write it, exactly: its decimal when it
terminates (``5.43 ms``, ``1038412611.331 ms``, ``119.95 ms``), and its fraction
only when the decimal does not terminate, with a rounded decimal beside it:
``7/3 ms (≈2.33333)``. The rounded decimal is marked ``≈`` and given as many
significant digits as it takes not to look like an integer (``≈119.99999999``,
never ``120``), so that a slack of 11999999999/100000001 ms can never be read as
120 ms. The exact text is :func:`maxplus.scalar.display_text`, the one formatter
that messages of lower floors (design advice, analysis notes) use too; JSON keeps
its documented exact strings (``"543/100"``, :func:`maxplus.scalar.exact_text`).
The rounded decimals are computed with :mod:`decimal`, exact for numbers of any
size (no float overflow).
"""

from __future__ import annotations

from decimal import Context, Decimal
from fractions import Fraction

from maxplus.scalar import display_text

__all__ = ["count", "decimal_text", "human", "number", "time_text"]

_EXACT_DIGITS = 15
"""A terminating decimal with at most this many significant digits is printed exactly."""
_ROUNDED_DIGITS = 6
"""Significant digits of a rounded decimal (more when that would look like an integer)."""
_LONG_INTEGER = 16
"""Integers with more digits than this get a rounded decimal beside them (10^400 ≈ 1e+400)."""


def decimal_text(value: Fraction) -> str | None:
    """The rounded decimal shown beside an exact value, or None when the exact text says it all.

    Parameters
    ----------
    value : Fraction

    Returns
    -------
    str or None
        None for a terminating decimal (it is printed exactly) and for a short
        integer; ``≈`` and a rounded decimal beside a fraction or a long integer.

    Examples
    --------
    >>> decimal_text(Fraction(2399, 20)), decimal_text(Fraction(7, 3)), decimal_text(Fraction(4))
    (None, '≈2.33333', None)
    >>> decimal_text(Fraction(11999999999, 100000001))
    '≈119.999999'
    >>> decimal_text(Fraction(10**400 + 1, 1))
    '≈1.00000e+400'
    """
    if value.denominator == 1:
        if abs(value.numerator) < 10**_LONG_INTEGER:  # no str(): it refuses 4,301 digits
            return None
        return "≈" + format(Context(prec=_ROUNDED_DIGITS).create_decimal(value.numerator), ".5e")
    if "/" not in str(display_text(value)):
        return None  # a terminating decimal, printed exactly
    digits = _ROUNDED_DIGITS
    rounded = Context(prec=digits).divide(Decimal(value.numerator), Decimal(value.denominator))
    if abs(rounded.adjusted()) >= _EXACT_DIGITS:  # far from 1: scientific notation says it
        return "≈" + format(rounded, f".{_ROUNDED_DIGITS - 1}e")
    if rounded == rounded.to_integral_value():  # never let a fraction look whole
        # The fewest digits that do not look whole, found by doubling then bisecting:
        # 10 - 1e-4299 needs 4,301, and one division per digit took seconds. Looking
        # whole is monotone in the digits (a rounding to p digits is whole when p is at
        # most the integer digits, or the value is within half a unit of the p-th digit
        # of an integer; both hold for every smaller p), so the bisection is exact.
        def whole(p: int) -> bool:
            r = Context(prec=p).divide(Decimal(value.numerator), Decimal(value.denominator))
            return r == r.to_integral_value()

        low, high = digits, 2 * digits
        while whole(high):
            low, high = high, 2 * high
        while high - low > 1:
            middle = (low + high) // 2
            low, high = (middle, high) if whole(middle) else (low, middle)
        rounded = Context(prec=high).divide(Decimal(value.numerator), Decimal(value.denominator))
    return "≈" + format(rounded, "f")


def number(value: Fraction | int | None) -> str:
    """An exact number as the input said it, a rounded decimal beside a fraction; ``-`` for None.

    >>> number(Fraction(7, 3)), number(Fraction(6)), number(Fraction(543, 100)), number(None)
    ('7/3 (≈2.33333)', '6', '5.43', '-')
    """
    if value is None:
        return "-"
    value = Fraction(value)
    text = str(display_text(value))
    dec = decimal_text(value)
    return text if dec is None else f"{text} ({dec})"


def time_text(value: Fraction | int | None, unit: str) -> str:
    """A time, exact as the input said it, with its unit and nothing beside: ``5.43 ms``.

    For tables and sentences where a rounded decimal beside would be noise.

    >>> time_text(Fraction(543, 100), "ms"), time_text(Fraction(7, 3), "ms"), time_text(None, "ms")
    ('5.43 ms', '7/3 ms', '-')
    """
    return "-" if value is None else f"{display_text(Fraction(value))} {unit}"


def human(value: Fraction | int | None, unit: str) -> str:
    """A time: exact as the input said it, its unit, a rounded decimal beside a fraction.

    >>> human(Fraction(7, 3), "ms"), human(Fraction(2399, 20), "ms"), human(Fraction(3), "ms")
    ('7/3 ms (≈2.33333)', '119.95 ms', '3 ms')
    >>> human(Fraction(1038412611331, 1000), "ms")
    '1038412611.331 ms'
    """
    if value is None:
        return "-"
    value = Fraction(value)
    text = f"{display_text(value)} {unit}"
    dec = decimal_text(value)
    return text if dec is None else f"{text} ({dec})"


def count(n: int, noun: str) -> str:
    """``1 state``, ``1,501 states``.

    >>> count(1, "state"), count(1501, "state")
    ('1 state', '1,501 states')
    """
    return f"{n:,} {noun}{'s' * (n != 1)}"
