"""The one number parser (maxplus.scalar.exact): its grammar and its digit bound.

Every reader, command-line option and library call converts through ``exact``; these
tests pin what it accepts and refuses, value by value, with the expected values derived
by hand in the comments.
"""

import time
from decimal import Decimal
from fractions import Fraction as F

import numpy as np
import pytest

from maxplus.errors import MaxPlusValueError
from maxplus.scalar import EPS, MAX_DIGITS, exact, exact_time, size_problem


@pytest.mark.parametrize("text, value", [
    ("7/3", F(7, 3)), ("-7/3", F(-7, 3)), ("+5", F(5)), ("  5\t", F(5)),  # blanks around
    ("1_000", F(1000)), ("1_000.000_1", F(10000001, 10000)),  # "_" between digits (Python)
    ("5.", F(5)), (".5", F(1, 2)), ("25e-2", F(1, 4)), ("1E3", F(1000)), ("-2.5e+1", F(-25)),
    ("0e999999999", F(0)),  # zero whatever its exponent: nothing to expand
    ("1e4299", F(10**4299)),  # 4300 digits: exactly the bound
    ("1e-4299", F(1, 10**4299)),  # a denominator of 4300 digits
    ("eps", EPS), ("-inf", EPS), ("ε", EPS),
])
def test_the_grammar_accepts(text, value):
    assert exact(text) == value


@pytest.mark.parametrize("text", [
    "5/2/3",   # before: 15/2 (5 divided by 2/3)
    "1.5/2",   # before: 3/4; a fraction is of two integers
    "1e3/7",   # before: 1000/7
    "7/-3", "7 / 3", "1 000", "1__000", "_1", "1_", "--5", "+-5", "1e", "e5", ".", "",
    "0x1A", "1,5", "１２",  # full-width digits are not [0-9]
])
def test_nonsense_is_refused_as_not_a_number(text):
    with pytest.raises(MaxPlusValueError, match="expected a number such as") as info:
        exact_time(text, "tasks.A.duration")
    assert info.value.where == "tasks.A.duration"


@pytest.mark.parametrize("value, words", [
    ("nan", "NaN"), ("NaN", "NaN"), (Decimal("NaN"), "NaN"), (float("nan"), "NaN"),
    ("inf", r"\+inf"), ("+Infinity", r"\+inf"), (Decimal("Infinity"), r"\+inf"),
    (True, "boolean"), (np.bool_(False), "boolean"), (1 + 2j, "complex"),
    (np.complex128(1), "complex"), (b"1", "bytes"), ([1], "list"), ("7/0", "zero denominator"),
])
def test_other_values_are_refused_by_name(value, words):
    with pytest.raises(MaxPlusValueError, match=words):
        exact(value, "x")


def test_numpy_scalars():
    # numpy integers are integers; numpy floats are read by their own shortest decimal
    # text, as Python floats are: float32(0.1) is 1/10, not 0.100000001490116119384765625
    # (before: 13421773/134217728 read through float64's text 0.10000000149011612)
    assert exact(np.int64(-5)) == -5 and exact(np.uint8(200)) == 200
    assert exact(np.float32(0.1)) == F(1, 10) and exact(np.float16(0.5)) == F(1, 2)
    assert exact(np.float64(0.1)) == F(1, 10) and exact(0.1) == F(1, 10)
    assert exact(Decimal("2.50")) == F(5, 2)


@pytest.mark.parametrize("value, message", [
    ("1e999999999", "'1e999999999' has 1,000,000,000 digits; at most 4,300 are accepted"),
    (Decimal("1E+999999999"), "has 1,000,000,000 digits; at most 4,300 are accepted"),
    ("1e4300", "'1e4300' has 4,301 digits"),
    ("1e-8599", "'1e-8599' has a denominator of 8,600 digits"),  # 10**8599 over 1
    ("1e-999999999", "has a denominator of more than 4,300 digits"),
    ("1e" + "9" * 50, "has more than 1,000,000,000,000 digits"),
    ("9" * 5000, "has 5,000 digits; at most 4,300 are accepted"),
    ("1/" + "9" * 4301, "has 4,301 digits"),
    ("0." + "0" * 4299 + "1", "has 4,301 digits"),  # the digits of the text are bounded
    (10**4300, "the int has 4,301 digits"),  # library values too: str() could not print it
    (F(1, 10**4300), "has a denominator of 4,301 digits"),
], ids=["exponent", "decimal-exponent", "4301", "denominator", "negative-exponent",
        "exponent-digits", "5000-digits", "long-denominator", "long-decimal", "int",
        "fraction"])
def test_a_number_beyond_the_bound_is_refused_by_its_size(value, message):
    # before: "1e999999999" ran for hours (a billion-digit integer) and 5000 digits were
    # called "not a number" and echoed in full
    start = time.perf_counter()
    with pytest.raises(MaxPlusValueError) as info:
        exact_time(value, "horizon")
    assert time.perf_counter() - start < 1
    text = str(info.value)
    assert message in text and "at most 4,300 are accepted" in text
    assert "expected a number such as" not in text and len(text) < 200  # never in full
    assert info.value.where == "horizon"
    assert size_problem(value) is not None


def test_the_bound_is_python_s_own():
    import sys

    assert MAX_DIGITS == 4300 == sys.int_info.default_max_str_digits
    assert size_problem("7/3") is None and size_problem(5) is None and size_problem("x") is None
