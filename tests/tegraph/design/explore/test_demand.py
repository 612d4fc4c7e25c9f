"""The processor shares on a common denominator against a plain sum of Fractions."""

from __future__ import annotations

from fractions import Fraction as F

from hypothesis import given
from hypothesis import strategies as st

from tegraph.design.explore.demand import processor_shares

TIMES = st.builds(F, st.integers(0, 50), st.sampled_from([1, 2, 3, 7, 10, 999_983]))
ENTRIES = st.lists(st.tuples(st.sampled_from(["a", "b", "c"]), TIMES, TIMES), max_size=30)


@given(ENTRIES)
def test_the_shares_are_the_sums_of_the_quotients(entries):
    expected: dict[str, F] = {"c": F(0)}
    for processor, duration, period in entries:
        share = duration / period if period else F(0)
        expected[processor] = expected.get(processor, F(0)) + share
    got = processor_shares(entries, every=["c"])
    # A processor named only by entries of period 0 (no time asked) is not listed
    # unless ``every`` names it.
    assert got == {
        p: v for p, v in expected.items()
        if p == "c" or any(e[0] == p and e[2] for e in entries)}
