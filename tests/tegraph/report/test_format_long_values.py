"""A value a hair from an integer is formatted in a few divisions.

The rounded decimal beside the slack 10 - 1e-4299 (a task of duration 1e-4299 on a
10 ms clock) would take one division per digit, 4,301 of them, each longer than the
last. The answer is the same; the divisions are counted.
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


def test_a_computed_number_past_python_str_limit_is_written_exactly(tmp_path):
    from typer.testing import CliRunner

    from maxplus.scalar import display_text, exact_text
    from tegraph.cli import app

    # Inputs hold at most 4,300 digits, sums of them more: the utilization demand over
    # the hyperperiod T = lcm(10, 20) = 20 is 2·1e-4299 + 2·2.5 + 7/3 = 1/(5·10^4298) +
    # 22/3 = (110·10^4298 + 3)/(15·10^4298): a numerator of 4,301 digits, which `str`
    # refused (ValueError: Exceeds the limit (4300 digits)), a traceback out of `analyze`.
    value = 2 * F(1, 10**4299) + 5 + F(7, 3)
    assert value == F(110 * 10**4298 + 3, 15 * 10**4298)
    text = exact_text(value)
    num, den = text.split("/")
    assert num == "110" + "0" * 4297 + "3" and den == "15" + "0" * 4298
    assert display_text(value) == text and exact_text(-(10**5000)) == "-1" + "0" * 5000
    path = tmp_path / "tiny.yaml"
    path.write_text('tasks:\n  A: {duration: 1e-4299, period: 10, outputs: [x]}\n'
                    '  B: {duration: 2.5, inputs: [x], outputs: [y]}\n'
                    '  C: {duration: "7/3", period: 20, inputs: [y]}\n'
                    'links:\n  - {from: "A:x", to: "B:x", protocol: ASYN/SYN}\n'
                    '  - {from: "B:y", to: "C:y", protocol: ASYN/ASYN}\n')
    result = CliRunner().invoke(app, ["analyze", str(path)])
    assert result.exit_code == 0, result.output[-500:]
    assert result.output.rstrip().endswith(
        "verdict: live, consistent and schedulable on its processors (exit status 0)")


def test_a_long_integer_gets_its_rounded_decimal_without_str():
    # 10^5000 has 5,001 digits: str() refuses it; the text is exact, ≈1.00000e+5000 beside.
    text = _format.human(F(10**5000), "ms")
    assert text == "1" + "0" * 5000 + " ms (≈1.00000e+5000)"
    # 16 digits or fewer: no rounded decimal beside (_LONG_INTEGER).
    assert _format.decimal_text(F(10**16 - 1)) is None
    assert _format.decimal_text(F(10**16)) == "≈1.00000e+16"
