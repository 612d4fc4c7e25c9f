"""max_cycle_ratio is exact for integers of any size (fuzzing found int64 wrap-arounds).

Every expected value below is worked out by hand in a comment; the property
tests compare huge-weight graphs with the same graph at small weights, whose
answer is known from circuit enumeration, through an exact affine map.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from maxplus import CertificateError
from maxplus._arrays import argmax_ratio, compare_ratios, float_ratios
from maxplus.cycle_ratio import CycleRatioCertificate, max_cycle_ratio
from tests.maxplus.test_mp_cycle_ratio import brute_force, graphs

# Both kernels: on graphs this small max_cycle_ratio would run the list one only.
pytestmark = pytest.mark.usefixtures("every_kernel")

BIG = 2**70


@pytest.mark.parametrize(
    "src, dst, weight, tokens, expected",
    [
        # 0 -> 1 -> 0, both arcs 2**63-1, one token each: (2*(2**63-1))/2 = 2**63-1
        # (int64 sums wrapped to -2, reported ratio -1).
        ([0, 1], [1, 0], np.array([2**63 - 1] * 2), [1, 1], Fraction(2**63 - 1)),
        # a triangle of 2**62 arcs: 3*2**62/3 = 2**62 (reported -2**62/3).
        ([0, 1, 2], [1, 2, 0], np.array([2**62] * 3, dtype=np.int64), [1, 1, 1], Fraction(2**62)),
        # plain Python ints that fit int64 one by one but not summed.
        ([0, 1], [1, 0], [2**62, 2**62], [1, 1], Fraction(2**62)),
        # a uint64 self-loop of 2**64-1 (astype(int64) made it -1).
        ([0], [0], np.array([2**64 - 1], dtype=np.uint64), [1], Fraction(2**64 - 1)),
        # 10**400 over 2 tokens on the circuit with 1: (10**400 + 1)/2 (float() overflowed).
        ([0, 1], [1, 0], [10**400, 1], [1, 1], Fraction(10**400 + 1, 2)),
        # a negative weight of int64's smallest value: np.abs leaves it negative.
        ([0, 1], [1, 0], np.array([-(2**63), -(2**63)]), [1, 1], Fraction(-(2**63))),
        # token counts past int64: 3 / (2**64 + 1).
        ([0, 1], [1, 0], [1, 2], [2**64, 1], Fraction(3, 2**64 + 1)),
        # uint64 tokens past int64 (wrapped to a negative count before).
        ([0], [0], [5], np.array([2**63 + 1], dtype=np.uint64), Fraction(5, 2**63 + 1)),
        # a weight scale past int64: 1/2**70 on a self-loop (den * scale overflowed).
        ([0], [0], [Fraction(1, 2**70)], [1], Fraction(1, 2**70)),
        # tokens of 2**62 times weights of 2**62: ratio products leave int64.
        # circuit 0<->1: (2**62 + 2**62)/(2**63) = 1; loop on 1: (2**62-1)/2**62 < 1.
        ([0, 1, 1], [1, 0, 1], [2**62, 2**62, 2**62 - 1], [2**62, 2**62, 2**62], Fraction(1)),
    ],
)
def test_near_and_past_int64(src, dst, weight, tokens, expected):
    result = max_cycle_ratio(src, dst, weight, tokens)
    assert result.ratio == expected
    assert set(result.cycle_times) == {expected}  # every node is on the critical circuit
    assert result.verify()


def test_two_huge_circuits_one_apart():
    # 0 <-> 1 has ratio (10**400 + 10**400)/2, the loop on 2 has 10**400 + 1,
    # and 1 -> 2 makes node 2 see both: chi_2 = 10**400 + 1, chi_0 = chi_1 = 10**400.
    r = max_cycle_ratio([0, 1, 2, 1], [1, 0, 2, 2], [10**400, 10**400, 10**400 + 1, 0],
                        [1, 1, 1, 1])
    assert r.cycle_times == [Fraction(10**400), Fraction(10**400), Fraction(10**400 + 1)]
    assert r.ratio == 10**400 + 1 and r.circuit.tolist() == [2]
    assert r.verify()


def test_verify_catches_an_off_by_one_past_float_precision():
    # 2**64 + 1 and 2**64 are the same float: the checker must not be fooled.
    r = max_cycle_ratio([0], [0], [2**64 + 1], [1])
    num = np.array([2**64], dtype=object)
    fields = {k: getattr(r.certificate, k) for k in CycleRatioCertificate.__dataclass_fields__}
    fields["ratio_num"] = num
    r.certificate = CycleRatioCertificate(**fields)
    with pytest.raises(CertificateError):
        r.verify()


def test_argmax_ratio_huge_values():
    # floats see 2**80/3 and (2**80+1)/3 as equal; the second is larger.
    num = np.array([2**80, 2**80 + 1, 5], dtype=object)
    den = np.array([3, 3, 1], dtype=object)
    assert argmax_ratio(num, den) == 1
    # past float range: 10**400/7 beats 10**399
    assert argmax_ratio(np.array([10**399, 10**400], dtype=object), np.array([1, 7])) == 1
    # int64 values whose cross products leave int64: (2**62-1)/(2**62-2) > (2**62)/(2**62-1)?
    # a/b > c/d  <=>  ad > bc: (2**62-1)**2 = 2**124 - 2**63 + 1 > 2**62 (2**62-2) = 2**124 - 2**63.
    num = np.array([2**62, 2**62 - 1], dtype=np.int64)
    den = np.array([2**62 - 1, 2**62 - 2], dtype=np.int64)
    assert argmax_ratio(num, den) == 1
    # ties go to the first index
    assert argmax_ratio(np.array([2, 4, 4]), np.array([1, 2, 2])) == 0


def test_compare_and_float_ratios():
    assert compare_ratios(np.array([2**62]), np.array([2**62 - 1]), np.array([2**62 - 1]),
                          np.array([2**62 - 2])).tolist() == [-1]
    assert float_ratios(np.array([-(10**400)], dtype=object), np.array([1])).tolist() == [-np.inf]


def affine_expected(small, k_w, shift, k_t):
    """Ratio of the graph with w' = k_w*w + shift*t' and t' = k_t*t: (k_w*r)/k_t + shift."""
    return None if small is None else Fraction(k_w) * small / k_t + shift


@settings(max_examples=150, deadline=None, suppress_health_check=list(HealthCheck))
@given(graphs(), st.sampled_from([1, BIG, 3 * BIG + 1]),
       st.sampled_from([0, 2**65 + 3, -(2**90)]), st.sampled_from([1, 2**64]))
def test_huge_weights_are_small_weights_scaled(graph, k_w, shift, k_t):
    # Sum along a circuit: (k_w*Σw + shift*k_t*Σt) / (k_t*Σt) = k_w/k_t * ratio + shift.
    n, src, dst, w, t = graph
    found, zero, _ = brute_force(n, src, dst, w, t)
    if zero:
        return
    small = max_cycle_ratio(src, dst, w, t, n_nodes=n)
    assert small.ratio == max((r for r, _ in found), default=None)
    big_t = [k_t * x for x in t]
    big_w = [k_w * x + shift * y for x, y in zip(w, big_t)]
    big = max_cycle_ratio(src, dst, big_w, big_t, n_nodes=n)
    assert big.ratio == affine_expected(small.ratio, k_w, shift, k_t)
    assert big.cycle_times == [affine_expected(c, k_w, shift, k_t) for c in small.cycle_times]
    assert big.verify()
    if big.ratio is not None:
        arcs = big.circuit.tolist()
        assert Fraction(sum(big_w[a] for a in arcs), sum(big_t[a] for a in arcs)) == big.ratio


@settings(max_examples=60, deadline=None)
@given(st.integers(2**62, 2**63 - 1), st.integers(1, 5), st.integers(1, 3))
def test_int64_edge_circuits(value, length, tokens):
    # One circuit of `length` arcs of weight `value`: ratio value/tokens, as given.
    nodes = list(range(length))
    r = max_cycle_ratio(nodes, nodes[1:] + nodes[:1], np.array([value] * length, dtype=np.int64),
                        [tokens] * length)
    assert r.ratio == Fraction(value, tokens)
    assert r.verify()
