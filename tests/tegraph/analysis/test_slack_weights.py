"""The slack's circuit weights in int64 arrays against the exact Python path.

``_circuit_weights_int64`` must give the same reduced weights and chain bounds
as ``_circuit_weights_exact`` whenever it answers, and refuse (None) when a
value could leave int64; the analysis must not change with the threshold
``_SLACK_ARRAYS`` that picks between them.
"""
from __future__ import annotations

import random
from unittest import mock

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph.analysis import analyze as analysis
from tegraph.analysis.analyze import _circuit_weights_exact, _circuit_weights_int64
from tegraph.model.skeleton import Skeleton
from tests.tegraph.skeleton_corpus import random_skeleton


def both(s, d, holding, tokens, X, W, T, chains):
    arrays = [np.array(v, dtype=object if any(abs(x) >= 2**62 for x in v) else np.int64)
              for v in (s, d, holding, tokens, X)]
    return (_circuit_weights_int64(*arrays, W, T, chains),
            _circuit_weights_exact(*arrays, W, T, chains))


def test_by_hand():
    # Circuit 0 -> 1 (holding 3) -> 0 (holding 2, one token) of cycle time W/T = 5/1,
    # and a parallel 0 -> 1 of holding 1; potentials X = [0, 3] (X[b] - X[a] >= h*T - W*m).
    # reduced = -(h*T - W*m + X[a] - X[b]): 0 -> 1: -(3 - 3) = 0; 1 -> 0: -(2 - 5 + 3) = 0;
    # the parallel one: -(1 - 3) = 2. Chain [0, 1] closes by its lightest hops 0 + 0 = 0;
    # chain [1] needs a place 1 -> 1, which there is not: None.
    fast, exact = both([0, 1, 0], [1, 0, 1], [3, 2, 1], [0, 1, 0], [0, 3], 5, 1, [[0, 1], [1]])
    assert fast is not None
    assert fast[0].tolist() == exact[0] == [0, 0, 2]
    assert fast[1] == exact[1] == [0, None]


def test_potentials_past_int64_but_close_together():
    # The same circuit as by hand, every potential shifted by 2**70: only their
    # differences enter a reduced weight, so the answer is the same and the int64
    # path must give it (it once cast the potentials themselves and overflowed).
    shift = 2**70
    fast, exact = both([0, 1, 0], [1, 0, 1], [3, 2, 1], [0, 1, 0], [shift, shift + 3], 5, 1,
                       [[0, 1], [1]])
    assert fast is not None
    assert fast[0].tolist() == exact[0] == [0, 0, 2]
    assert fast[1] == exact[1] == [0, None]


def test_tokens_past_int64_refused_even_when_they_weigh_nothing():
    # W = 0: a place's tokens count for nothing in its reduced weight, so the bound
    # on the weights holds, yet 2**63 tokens cannot be read as int64 (hypothesis
    # found this one): the int64 path refuses, the exact one answers.
    fast, exact = both([0], [0], [0], [2**63], [0], 0, 1, [[0]])
    assert fast is None
    assert exact == ([0], [0])


@st.composite
def weight_problems(draw):
    n = draw(st.integers(1, 6))
    node = st.integers(0, n - 1)
    places = draw(st.lists(st.tuples(node, node), min_size=1, max_size=14))
    # Magnitudes around int64's limit too, so that the refusal is exercised.
    big = draw(st.sampled_from([10, 2**20, 2**61, 2**70]))
    value = st.integers(-big, big)
    holding = draw(st.lists(value, min_size=len(places), max_size=len(places)))
    tokens = draw(st.lists(st.integers(0, big), min_size=len(places), max_size=len(places)))
    X = draw(st.lists(value, min_size=n, max_size=n))
    W, T = draw(value), draw(st.integers(1, big))
    chains = draw(st.lists(st.lists(node, min_size=1, max_size=4), min_size=1, max_size=5))
    return ([a for a, _ in places], [b for _, b in places], holding, tokens, X, W, T, chains)


@given(weight_problems())
@settings(max_examples=300, deadline=None)
def test_int64_weights_equal_exact_or_refuse(problem):
    fast, exact = both(*problem)
    s, d, holding, tokens, X, W, T, _ = problem
    used = [X[e] for e in s + d]  # the potentials the places read
    # Every term of a reduced weight small (not only their sums, which may cancel):
    terms = ([abs(h) * T for h in holding] + [abs(W) * m for m in tokens] + tokens
             + [max(used) - min(used), abs(W), T])
    if max(terms) < 2**40:
        assert fast is not None  # small terms always take the arrays
    if fast is not None:
        assert fast[0].dtype == np.int64
        assert fast[0].tolist() == exact[0]
        assert fast[1] == exact[1]


@given(st.randoms(use_true_random=False))
@settings(max_examples=60, deadline=None)
def test_analysis_same_with_either_weights(rng: random.Random):
    sk = Skeleton.from_dict(random_skeleton(rng, max_tasks=8))
    with mock.patch.object(analysis, "_SLACK_ARRAYS", 0):
        arrays = analysis.analyze_skeleton(sk, max_steps=2000)
    with mock.patch.object(analysis, "_SLACK_ARRAYS", 10**9):
        exact = analysis.analyze_skeleton(sk, max_steps=2000)
    assert {t: (r.slack, r.critical) for t, r in arrays.tasks.items()} == \
        {t: (r.slack, r.critical) for t, r in exact.tasks.items()}
