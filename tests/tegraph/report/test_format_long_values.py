"""A value a hair from an integer is formatted in a few divisions (issue 21 review, item 4).

``analyze`` of a task of duration 1e-4299 on a 10 ms clock took 9 to 15 s, all of it in
the rounded decimal beside the slack 10 - 1e-4299: one division per digit, 4,301 of
them, each longer than the last. The answer is unchanged; the divisions are counted.
"""

from __future__ import annotations

from decimal import Context, Decimal
from fractions import Fraction as F

import pytest

from tegraph.report import _format


def _reference(value: F) -> str:
    """The rounded decimal by its definition: add digits one by one until not whole."""
    digits = 6
    while True:
        r = Context(prec=digits).divide(Decimal(value.numerator), Decimal(value.denominator))
        if r != r.to_integral_value():
            return "≈" + format(r, "f")
        digits += 1


class _Counting:
    calls = 0

    def __init__(self, prec: int) -> None:
        self.context = Context(prec=prec)

    def divide(self, a, b):
        _Counting.calls += 1
        return self.context.divide(a, b)

    def create_decimal(self, n):
        return self.context.create_decimal(n)


@pytest.mark.parametrize("value", [
    10 - F(1, 10**4299),            # the slack of the issue: 4,301 digits to look not whole
    F(12, 1) + F(1, 3 * 10**2000),  # just above an integer, never terminating
    F(11999999999, 100000001), F(7, 3), 5 - F(19, 3 * 10**12),
    F(999999, 1000000) + F(1, 3 * 10**7),
])
def test_the_rounded_decimal_is_the_fewest_digits_that_do_not_look_whole(value, monkeypatch):
    monkeypatch.setattr(_format, "Context", _Counting)
    _Counting.calls = 0
    text = _format.decimal_text(value)
    assert _Counting.calls <= 40, _Counting.calls  # was one per digit: 4,296 for the first
    assert text == _reference(value)


def test_the_slack_beside_a_tiny_duration_stays_exact_and_quick():
    text = _format.decimal_text(10 - F(1, 10**4299))
    assert text == "≈9." + "9" * 4299  # 4,300 significant digits: the first not to look whole
