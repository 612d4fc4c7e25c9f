"""A task slower than its clock overruns for certain: located exactly.

Expected activations are derived by hand from spec §3-§4 (end of activation
k-1 against tick k), next to each assertion; docs/analysis.md has the proof
of the method ("A certain overrun, located exactly").
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph import Skeleton, analyze, reach


def test_duration_past_the_period_overruns_at_activation_2():
    # Duration 11 on a clock of 10: activation 1 runs 0-11, tick 2 comes at 10 < 11.
    r = analyze(Skeleton.from_dict({"tasks": {"A": {"duration": 11, "period": 10}}}))
    assert r.tasks["A"].overrun_at == 2 and r.tasks["A"].overrun_decided


def _late(writer_period, max_steps=100_000):
    # W (duration 1, clock P_W > 10) feeds A (duration 1, clock 10, no output) ASYN/SYN.
    # While A keeps up, it starts at its tick 10(k-1), waits for W's write k at
    # (k-1)·P_W + 1, and ends 1 later: end_A(k-1) = (k-2)·P_W + 2. Tick k is at 10(k-1),
    # so A overruns at the first k with (k-2)·(P_W - 10) > 8 (strictly).
    sk = Skeleton.from_dict({
        "tasks": {"W": {"duration": 1, "period": writer_period, "outputs": ["m"]},
                  "A": {"duration": 1, "period": 10, "inputs": ["m"]}},
        "links": [{"from": "W:m", "to": "A:m", "protocol": "ASYN/SYN"}]})
    return analyze(sk, max_steps=max_steps)


@pytest.mark.parametrize(("writer_period", "expected"), [
    ("10001/1000", 8003),         # (k-2)/1000 > 8: k - 2 = 8001
    ("10000001/1000000", 8000003),  # (k-2)/10^6 > 8: k - 2 = 8000001, far past the budget
    ("11", 11),                   # (k-2)·1 > 8: k - 2 = 9
    ("12", 7),                    # (k-2)·2 > 8: k - 2 = 5 (4·2 = 8 is not > 8)
])
def test_a_slow_writer_makes_the_overrun_come_late(writer_period, expected):
    r = _late(writer_period)
    assert r.tasks["A"].overrun_at == expected and r.tasks["A"].overrun_decided
    assert r.tasks["W"].overrun_at is None


def test_a_late_overrun_is_not_left_to_the_budget():
    # It used to read "overrun undecided (budget)" when the budget ended first.
    r = _late("10001/1000", max_steps=100)
    assert r.tasks["A"].overrun_at == 8003 and r.tasks["A"].overrun_decided


def test_the_report_says_how_the_overrun_was_found():
    r = _late("10001/1000")
    assert any("overrun of A located exactly by (max,+) matrix powers" in n for n in r.notes)


@settings(max_examples=40, deadline=None)
@given(st.integers(101, 160), st.integers(1, 9), st.integers(1, 9), st.integers(0, 9),
       st.sampled_from(["ASYN/SYN", "SYN/SYN"]))
def test_powers_agree_with_the_timed_exploration(writer_tenths, writer_duration,
                                                 reader_duration, reader_phase, protocol):
    # A writer slower than the reader's clock drags the reader below its clock, so the
    # reader's overrun is certain and located by (max,+) powers; the ORCCAD timed
    # exploration (a different algorithm: earliest firing, one event at a time, until
    # the timed state repeats or the overrun is seen) must find the same activation.
    sk = Skeleton.from_dict({
        "clocks": {"r": {"period": 10, "phase": reader_phase}},
        "tasks": {"W": {"duration": writer_duration, "period": f"{writer_tenths}/10",
                        "outputs": ["m"]},
                  "A": {"duration": reader_duration, "clock": "r", "inputs": ["m"]}},
        "links": [{"from": "W:m", "to": "A:m", "protocol": protocol}]})
    report = analyze(sk, max_steps=50)
    assert any("overrun of A located exactly by (max,+) matrix powers" in n
               for n in report.notes)
    found = report.tasks["A"]
    timed = reach(sk, timed=True, max_states=200_000).tasks["A"]
    assert timed.decided and found.overrun_decided
    assert found.overrun_at == timed.overrun_at


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 7), st.data())
def test_a_power_squared_matches_the_definition(n, data):
    # (A ⊗ A)[i, j] = max over k of A[i, k] + A[k, j] among finite entries: checked
    # by the definition in Python ints, with entries small (the int64 cube) and near
    # or past 2**62 (the sums then leave int64: Python ints, exact).
    from tegraph.analysis.dynamics import _square

    size = data.draw(st.sampled_from([10, 2**61, 2**62, 2**70]))
    cells = data.draw(st.lists(st.one_of(st.none(), st.integers(-size, size)),
                               min_size=n * n, max_size=n * n))
    values = np.zeros((n, n), dtype=object)
    finite = np.zeros((n, n), dtype=bool)
    for c, v in enumerate(cells):
        if v is not None:
            values[c // n, c % n], finite[c // n, c % n] = v, True
    out, out_finite = _square((values, finite))
    for i in range(n):
        for j in range(n):
            terms = [cells[i * n + k] + cells[k * n + j] for k in range(n)
                     if cells[i * n + k] is not None and cells[k * n + j] is not None]
            assert bool(out_finite[i, j]) == bool(terms)
            if terms:
                assert out[i, j] == max(terms) and type(out[i, j]) is int
