"""The fast path of the number parser (``_plain_value``) against the general grammar.

Plain texts ("98/3750", "12", "-0.50") skip the general grammar's size accounting;
every text the fast path takes must get the value the general path
(``_text_value``) gives, and every other text must be left to it.
"""

from fractions import Fraction as F

import pytest
from hypothesis import given
from hypothesis import strategies as st

from maxplus.errors import MaxPlusValueError
from maxplus.scalar import _parse, _plain_value, _text_value, exact_time

_digits = st.text("0123456789", min_size=1, max_size=30)
_plain_texts = st.one_of(
    st.builds(lambda s, p, q: f"{s}{p}/{q}", st.sampled_from(["", "+", "-"]), _digits, _digits),
    st.builds(lambda s, w, f: f"{s}{w}.{f}", st.sampled_from(["", "+", "-"]), _digits, _digits),
    st.builds(lambda s, w: f"{s}{w}", st.sampled_from(["", "+", "-"]), _digits),
)


def _general(text):
    try:
        return _text_value(text, "v", text)
    except MaxPlusValueError as err:
        return ("refused", str(err))


@given(_plain_texts)
def test_plain_texts_read_as_the_general_grammar_reads_them(text):
    fast = _plain_value(text)
    if fast is None:  # only a zero denominator is handed back
        assert isinstance(_general(text), tuple)
    else:
        assert fast == _general(text)


@given(st.text("0123456789+-./_eE \t", max_size=12))
def test_any_short_text_parses_as_before(text):
    # _parse takes the fast path where it can; the result or the refusal is the same.
    try:
        got = _parse(text, "v")
    except MaxPlusValueError as err:
        got = ("refused", str(err))
    assert got == _general(text)


@given(st.integers(min_value=-(10**60), max_value=10**60))
def test_ints_read_as_fractions(n):
    assert _parse(n, "v") == F(n) and type(_parse(n, "v")) is F


@pytest.mark.parametrize("text, value", [
    ("010", F(10)),  # leading zeros: ten, not eight
    ("-0.50", F(-1, 2)), ("98/3750", F(49, 1875)), ("+7", F(7)), ("0/5", F(0)),
])
def test_plain_values_by_hand(text, value):
    assert _plain_value(text) == value


@pytest.mark.parametrize("text", ["7/0", "7/00", " 5", "1_000", "1e3", "5.", ".5", "１２",
                                  "1" * 101])
def test_other_texts_go_the_general_way(text):
    assert _plain_value(text) is None


def test_a_zero_denominator_keeps_its_message():
    with pytest.raises(MaxPlusValueError, match="zero denominator"):
        exact_time("7/000", "x")
