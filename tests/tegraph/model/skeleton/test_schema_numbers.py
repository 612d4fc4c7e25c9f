"""Time values of a skeleton go through the one number parser."""

import time
from fractions import Fraction as F

import pytest

from tegraph.errors import SkeletonError
from tegraph.io import load_skeleton


def _load(tmp_path, duration: str):
    path = tmp_path / "s.yaml"
    path.write_text(f"tasks:\n  A: {{duration: {duration}, period: 10}}\n", encoding="utf-8")
    return load_skeleton(path)


@pytest.mark.parametrize("written", ['"5/2/3"', '"1.5/2"', '"7 / 3"', '"1 000"', "'nan'"])
def test_nonsense_durations_are_refused_naming_the_key_path(tmp_path, written):
    # before: "5/2/3" was read as 15/2 (5 divided by 2/3), "1.5/2" as 3/4
    with pytest.raises(SkeletonError) as info:
        _load(tmp_path, written)
    assert info.value.where == "tasks.A.duration"
    assert "expected a duration >= 0" in info.value.reason


@pytest.mark.parametrize("written, value", [
    ("1_000", F(1000)), ('"1_000"', F(1000)), ("+5", F(5)), ('" 7/3 "', F(7, 3)),
    ("1e-18", F(1, 10**18)), ('"1e4299"', F(10**4299)), ("0e999999999", F(0)),
])
def test_the_grammar_s_numbers_are_read_exactly(tmp_path, written, value):
    assert _load(tmp_path, written).tasks["A"].duration == value


@pytest.mark.parametrize("written, size", [
    ('"1/' + "9" * 4301 + '"', "4,301 digits"),
    ("1e4300", "4,301 digits"),
    ('"1' + "0" * 5000 + '"', "5,001 digits"),
    ("1" + "0" * 5000, "5,001 digits"),  # plain: YAML's own int() refused it, in its words
])
def test_a_duration_beyond_the_bound_is_refused_by_its_size(tmp_path, written, size):
    start = time.perf_counter()
    with pytest.raises(SkeletonError) as info:
        _load(tmp_path, written)
    assert time.perf_counter() - start < 5
    reason = info.value.reason
    assert info.value.where == "tasks.A.duration"
    assert f"has {size}; at most 4,300 are accepted" in reason and len(reason) < 200
    assert "a finite number such as" not in reason  # not called "not a number"
