"""Number formatting shared by every text rendering: exact first, a decimal beside it.

A time prints as its exact value, its unit, and, when the exact text is not
already a short integer, a decimal: ``7/3 ms (≈2.33333)``, ``2399/20 ms
(119.95)``. A decimal that terminates within 15 significant digits is printed
exactly; any other is rounded, marked ``≈``, and given as many significant
digits as it takes not to look like an integer (``≈119.99999999``, never
``120``), so that a slack of 2399/20 ms can never be read as a period of
120 ms. The decimals are computed with :mod:`decimal`, exact for numbers of
any size (no float overflow).
"""

from __future__ import annotations

from decimal import Context, Decimal
from fractions import Fraction

from maxplus.scalar import exact_text

__all__ = ["count", "decimal_text", "human", "number"]

_EXACT_DIGITS = 15
"""A terminating decimal with at most this many significant digits is printed exactly."""
_MAX_PLACES = 4_000
"""An exact decimal is computed up to this many places after the point (cost: its digits)."""
_ROUNDED_DIGITS = 6
"""Significant digits of a rounded decimal (more when that would look like an integer)."""
_LONG_INTEGER = 16
"""Integers with more digits than this get a rounded decimal beside them (10^400 ≈ 1e+400)."""


def _decimal_places(value: Fraction) -> int | None:
    """Places after the point of the exact decimal of ``value``; None if it has none."""
    d, places = value.denominator, 0
    for p in (2, 5):
        count = 0
        while d % p == 0:
            d //= p
            count += 1
        places = max(places, count)
    return places if d == 1 else None


def decimal_text(value: Fraction) -> str | None:
    """The decimal shown beside an exact value, or None when the exact text says it all.

    Parameters
    ----------
    value : Fraction

    Returns
    -------
    str or None

    Examples
    --------
    >>> decimal_text(Fraction(2399, 20)), decimal_text(Fraction(7, 3)), decimal_text(Fraction(4))
    ('119.95', '≈2.33333', None)
    >>> decimal_text(Fraction(11999999999, 100000001))
    '≈119.999999'
    >>> decimal_text(Fraction(10**400 + 1, 1))
    '≈1.00000e+400'
    """
    if value.denominator == 1:
        if len(str(abs(value.numerator))) <= _LONG_INTEGER:
            return None
        return "≈" + format(Context(prec=_ROUNDED_DIGITS).create_decimal(value.numerator), ".5e")
    places = _decimal_places(value)
    if places is not None and places <= _MAX_PLACES:
        # p/q with q = 2^a 5^b is (p * 10^n / q) / 10^n for n = max(a, b), exactly.
        scaled = value.numerator * 10**places // value.denominator
        exact = Decimal(scaled).scaleb(-places).normalize()
        if len(exact.as_tuple().digits) <= _EXACT_DIGITS:
            # Few significant digits but far from 1 (3/10^17): exact scientific notation.
            return format(exact, "f" if places <= _EXACT_DIGITS else "e")
    digits = _ROUNDED_DIGITS
    rounded = Context(prec=digits).divide(Decimal(value.numerator), Decimal(value.denominator))
    if abs(rounded.adjusted()) >= _EXACT_DIGITS:  # far from 1: scientific notation says it
        return "≈" + format(rounded, f".{_ROUNDED_DIGITS - 1}e")
    while rounded == rounded.to_integral_value():  # never let a fraction look whole
        digits += 1
        rounded = Context(prec=digits).divide(Decimal(value.numerator), Decimal(value.denominator))
    return "≈" + format(rounded, "f")


def number(value: Fraction | int | None) -> str:
    """An exact number with its decimal beside it: ``7/3 (≈2.33333)``; ``-`` for None.

    >>> number(Fraction(7, 3)), number(Fraction(6)), number(None)
    ('7/3 (≈2.33333)', '6', '-')
    """
    if value is None:
        return "-"
    value = Fraction(value)
    text = str(exact_text(value))
    dec = decimal_text(value)
    return text if dec is None else f"{text} ({dec})"


def human(value: Fraction | int | None, unit: str) -> str:
    """A time: exact, its unit, and a decimal beside it when useful; ``-`` for None.

    >>> human(Fraction(7, 3), "ms"), human(Fraction(2399, 20), "ms"), human(Fraction(3), "ms")
    ('7/3 ms (≈2.33333)', '2399/20 ms (119.95)', '3 ms')
    """
    if value is None:
        return "-"
    value = Fraction(value)
    text = f"{exact_text(value)} {unit}"
    dec = decimal_text(value)
    return text if dec is None else f"{text} ({dec})"


def count(n: int, noun: str) -> str:
    """``1 state``, ``1,501 states``.

    >>> count(1, "state"), count(1501, "state")
    ('1 state', '1,501 states')
    """
    return f"{n:,} {noun}{'s' * (n != 1)}"
