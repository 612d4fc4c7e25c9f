"""Howard's policy iteration ends, whatever the size of the integers.

Holdings between about 2**57 and 2**60 made the int64 path pack the arc terms
(``term * 2**bits + arc rank``) while the potentials were too large for packed
keys; the bias test then read the packed keys as if they were the terms, found
gains that do not exist and switched between two policies for ever.

Every run here is bounded (:func:`bounded`: at most ``MAX_ITERATIONS`` value
determinations, then a failure instead of a hang) and checked against an
independent answer: elementary circuits enumerated by networkx, ratios taken
exactly with Fractions (``brute_force`` of test_howard_brute_force.py).
"""
from __future__ import annotations

import subprocess
import sys
import textwrap
from contextlib import contextmanager
from fractions import Fraction

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import maxplus
import maxplus.policy_iteration as pi

from .test_howard_brute_force import brute_force

# The numpy kernel, whose int64 bounds these holdings probe (bounded() counts its
# determinations); the compiled kernel is compared to it in test_howard_kernel.
pytestmark = pytest.mark.usefixtures("numpy_kernel")

MAX_ITERATIONS = 200
"""Far above what graphs of a few nodes need (a handful), far below a hang."""


@contextmanager
def bounded(limit: int = MAX_ITERATIONS):
    """Fail (instead of hanging) after ``limit`` value determinations."""
    original = pi._value_determination
    calls = [0]

    def counted(*args, **kwargs):
        calls[0] += 1
        assert calls[0] <= limit, f"policy iteration still running after {limit} iterations"
        return original(*args, **kwargs)

    pi._value_determination = counted
    try:
        yield calls
    finally:
        pi._value_determination = original


def solve_and_check(n, arcs):
    """max_cycle_ratio (bounded) against circuit enumeration, exactly."""
    src, dst, w, t = (list(column) for column in zip(*arcs))
    top, cycle_times, zero = brute_force(n, arcs)
    assert not zero
    with bounded():
        r = maxplus.max_cycle_ratio(src, dst, w, t, n_nodes=n)
    assert r.ratio == top
    assert r.cycle_times == cycle_times
    assert r.verify()
    return r


# --------------------------------------------------------------------------- the reported cases

@pytest.mark.parametrize("holding", [2**58, 2**58 + 1, 2**59 - 1, 3 * 2**57,
                                     2**53, 2**54, 2**60, 2**62])
def test_reported_holdings_end_with_the_exact_ratio(holding):
    # Node 0: self-loop of `holding` with 1 token; 0 -> 1 of 0 and no token;
    # node 1: self-loop of 1 with 1 token. Circuits: {0} of ratio holding/1,
    # {1} of ratio 1; node 1 is reached from node 0, so both cycle times are
    # max(holding, 1) = holding. (Before: the first four never returned.)
    with bounded():
        r = maxplus.max_cycle_ratio([0, 0, 1], [0, 1, 1], [holding, 0, 1], [1, 0, 1])
    assert r.ratio == holding
    assert r.cycle_times == [holding, holding]
    assert r.verify()


def test_policy_iteration_never_revisits_a_policy():
    # The guarantee that does not rest on the proof alone: a run that came
    # back to a policy it had left would loop, so it is caught. Here a broken
    # improvement step (it keeps "improving" without changing anything) must
    # end in an error, not a hang.
    original = pi._improve

    def stuck(pol, cur, cand, arcs, terms):
        original(pol, cur, cand, arcs, terms)
        return "bias"

    pi._improve = stuck
    try:
        with bounded(10), pytest.raises(RuntimeError, match="revisited a policy"):
            maxplus.max_cycle_ratio([0, 0, 1], [0, 1, 1], [5, 0, 1], [1, 0, 1])
    finally:
        pi._improve = original


# --------------------------------------------------------------------------- sweeps

# Holdings across the int64 boundaries that matter: 2**53 (float), the packed
# arc terms and keys (a few bits below 2**62), 2**62 and 2**63 (int64 itself),
# and beyond int64, where Python ints take another path.
holdings = st.one_of(
    st.integers(2**50, 2**63).flatmap(lambda h: st.sampled_from([h, 2**63 - h + 2**50])),
    st.builds(lambda k, d: 2**k + d, st.integers(50, 66), st.integers(-3, 3)),
    st.integers(2**63, 2**70),
)


@settings(max_examples=150, deadline=None, suppress_health_check=list(HealthCheck))
@given(holdings, st.integers(1, 3), st.integers(0, 5), st.integers(1, 2))
@example(2**58, 1, 0, 1)
@example(3 * 2**57, 1, 0, 1)
@example(2**63 - 1, 2, 1, 1)
def test_huge_holdings_in_small_graphs(holding, tokens, small, small_tokens):
    # The reported shape, with token counts and the slow loop varied, plus a
    # circuit through both nodes.
    arcs = [(0, 0, holding, tokens), (0, 1, 0, 0), (1, 1, small, small_tokens),
            (1, 0, holding // 3, 1)]
    solve_and_check(2, arcs)
    solve_and_check(2, arcs[:3])


@st.composite
def graphs_with_huge_weights(draw):
    """Multigraphs of up to 5 nodes whose weights mix small values and ones near 2**50..2**64."""
    n = draw(st.integers(1, 5))
    node = st.integers(0, n - 1)
    weight = st.one_of(st.integers(-5, 5), holdings, holdings.map(lambda h: -h))
    arcs = draw(st.lists(st.tuples(node, node, weight, st.integers(1, 3)), min_size=1,
                         max_size=9))
    # zero-token arcs only forward (lower to higher node), so no circuit lacks tokens
    arcs += draw(st.lists(st.tuples(node, node, weight, st.just(0)), max_size=3).map(
        lambda extra: [(min(a, b), max(a, b), w, t) for a, b, w, t in extra if a != b]))
    return n, arcs


@settings(max_examples=150, deadline=None, suppress_health_check=list(HealthCheck))
@given(graphs_with_huge_weights())
def test_graphs_with_huge_weights(g):
    solve_and_check(*g)


@settings(max_examples=100, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.integers(1, 10**20), st.integers(1, 10**20), st.integers(1, 100))
@example(1, 25 * 10**15, 10)            # duration 1/25000000000000000, period 10
@example(2500000037252903, 25 * 10**15, 10)  # float(np.float32(0.1)) read as a decimal
def test_tiny_rationals_next_to_a_period(num, den, period):
    # A task's shape in tegraph: a clock of `period` (self-loop of one token)
    # feeding a task of duration num/den that also loops on itself. Circuits:
    # the clock (period/1) and the task (num/den per token); the task is
    # reached from the clock, so its cycle time is the larger of the two.
    duration = Fraction(num, den)
    arcs = [(0, 0, Fraction(period), 1), (0, 1, Fraction(0), 0), (1, 1, duration, 1)]
    r = solve_and_check(2, arcs)
    assert r.cycle_times == [period, max(Fraction(period), duration)]


# --------------------------------------------------------------------------- through tegraph

@pytest.mark.parametrize("duration", ['"1/25000000000000000"', "np.float32(0.1)"])
def test_tegraph_period_of_a_tiny_duration(duration):
    # A clocked task of period 10 whose duration is far below it: its period is
    # the clock's, 10 ms. Run in a subprocess under a timeout: before the fix
    # the analysis never returned.
    code = textwrap.dedent(f"""
        import numpy as np
        import tegraph
        skeleton = tegraph.Skeleton.from_dict(
            {{"tasks": {{"A": {{"duration": {duration}, "period": 10}}}}}})
        report = tegraph.analyze(skeleton)
        print(report.groups[0].period)
    """)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split()[0] == "10"
