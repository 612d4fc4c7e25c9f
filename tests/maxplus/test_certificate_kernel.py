"""The compiled arc and policy checks of ``verify_cycle_ratio`` against its numpy checks.

The compiled pass (:mod:`maxplus._certificate_kernel`) only says "every check
holds" or declines; the numpy checks then run and name what fails. What must
never happen is a "holds" where the numpy checks refuse: the property test
corrupts solver claims in the ways a wrong solver would and compares the
outcome of ``verify_cycle_ratio`` with and without the compiled pass.
"""

from __future__ import annotations

from dataclasses import replace
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import maxplus.certificate as certificate
from maxplus import CertificateError, CycleRatioCertificate, _kernels, max_cycle_ratio
from maxplus.certificate import CycleRatioClaim, verify_cycle_ratio

kernel = pytest.importorskip("maxplus._certificate_kernel",
                             reason="the compiled checks are not built (no C compiler)")


def _claim_of(r) -> CycleRatioClaim:
    return CycleRatioClaim(r.ratio, r.circuit, r.cycle_time_num, r.cycle_time_den,
                           r.certificate)


def _outcome(arcs, claim, compiled: bool) -> str | None:
    """None when the claim is proven, else the checker's message."""
    with _kernels.use("compiled" if compiled else "numpy"):
        try:
            verify_cycle_ratio(*arcs, claim)
        except CertificateError as exc:
            return str(exc)
    return None


@st.composite
def strongly_connected(draw):
    """A circuit through every node, then random arcs: every node has a cycle time."""
    n = draw(st.integers(1, 12))
    order = draw(st.permutations(range(n)))
    src = [order[k] for k in range(n)]
    dst = [order[(k + 1) % n] for k in range(n)]
    extra = draw(st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)), max_size=3 * n))
    src += [a for a, _ in extra]
    dst += [b for _, b in extra]
    m = len(src)
    big = draw(st.sampled_from([5, 10**4, 2**40]))
    w = draw(st.lists(st.integers(-big, big), min_size=m, max_size=m))
    t = draw(st.lists(st.integers(1, 4), min_size=m, max_size=m))
    return src, dst, w, t


CORRUPTIONS = ["none", "potential", "weight", "policy", "ratio", "unreduced", "negative",
               "circuit-weight"]


@settings(max_examples=300, deadline=None)
@given(graph=strongly_connected(), corruption=st.sampled_from(CORRUPTIONS),
       pick=st.integers(0, 10**6), delta=st.sampled_from([-1, 1, 7]))
def test_the_compiled_checks_never_prove_what_the_numpy_checks_refuse(
        graph, corruption, pick, delta):
    src, dst, w, t = graph
    r = max_cycle_ratio(src, dst, w, t)
    c = r.certificate
    arcs = [np.asarray(r.src), np.asarray(r.dst), np.array(r.weight), np.asarray(r.tokens)]
    n, m = len(c.potential), len(arcs[0])
    k, a = pick % n, pick % m
    if corruption == "potential":
        c = replace(c, potential=_bumped(c.potential, k, delta))
    elif corruption == "weight":
        arcs[2] = _bumped(arcs[2], a, delta)
    elif corruption == "policy":
        c = replace(c, policy=_set(c.policy, k, a))
    elif corruption == "ratio":
        c = replace(c, ratio_num=_bumped(c.ratio_num, k, delta))
    elif corruption == "unreduced":
        c = replace(c, ratio_num=_bumped(c.ratio_num, k, 0, times=2),
                    ratio_den=_bumped(c.ratio_den, k, 0, times=2))
    elif corruption == "negative":
        c = replace(c, ratio_num=_bumped(c.ratio_num, k, 0, times=-1),
                    ratio_den=_bumped(c.ratio_den, k, 0, times=-1))
    elif corruption == "circuit-weight":
        arcs[2] = _bumped(arcs[2], int(np.asarray(r.circuit)[0]), delta)
    claim = replace(_claim_of(r), certificate=c)
    compiled = _outcome(arcs, claim, True)
    assert compiled == _outcome(arcs, claim, False)
    if corruption == "none":
        assert compiled is None
        # The solver's own claim on small numbers: the compiled pass proved it.
        held = kernel.arc_checks(*(np.ascontiguousarray(x, dtype=np.int64) for x in (
            *arcs, c.ratio_num, c.ratio_den, c.potential, c.policy)))
        assert held in (kernel.ALL_HOLD, kernel.ONE_RATIO)


def _bumped(values, k: int, delta: int, times: int = 1) -> np.ndarray:
    out = np.array(values, dtype=np.int64)
    out[k] = out[k] * times + delta
    return out


def _set(values, k: int, value: int) -> np.ndarray:
    out = np.array(values, dtype=np.int64)
    out[k] = value
    return out


def _arrays(*lists):
    return [np.array(x, dtype=np.int64) for x in lists]


def test_one_cycle_time_everywhere_by_hand():
    # The circuit 0 -> 1 -> 0 (weights 3, 5, one token each) has ratio 8/2 = 4/1 at
    # both nodes; potentials 0, -1 make both arcs tight: X1 = 0 + 3 - 4, X0 = -1 + 5 - 4.
    held = kernel.arc_checks(*_arrays([0, 1], [1, 0], [3, 5], [1, 1], [4, 4], [1, 1],
                                      [0, -1], [1, 0]))
    assert held == kernel.ONE_RATIO
    # X1 = 0: arc 1 would need X0 >= 0 + 5 - 4 = 1 > 0: declined.
    assert kernel.arc_checks(*_arrays([0, 1], [1, 0], [3, 5], [1, 1], [4, 4], [1, 1],
                                      [0, 0], [1, 0])) == 0


def test_two_cycle_times_by_hand():
    # Node 0's self-loop (arc 0, weight 2) has ratio 2, node 1's (arc 1, weight 5) ratio
    # 5; arc 2 (0 -> 1, weight 0, no token) goes from the smaller cycle time to the
    # larger, as it must. Each policy arc is the node's self-loop, tight with X = 0.
    arcs = ([0, 1, 0], [0, 1, 1], [2, 5, 0], [1, 1, 0])
    held = kernel.arc_checks(*_arrays(*arcs, [2, 5], [1, 1], [0, 0], [0, 1]))
    assert held == kernel.ALL_HOLD
    # Reversed, 1 -> 0 goes from 5 to 2: a circuit through it could not be proven.
    assert kernel.arc_checks(*_arrays([0, 1, 1], [0, 1, 0], [2, 5, 0], [1, 1, 0],
                                      [2, 5], [1, 1], [0, 0], [0, 1])) == 0
    # The same claim through verify_cycle_ratio, circuit = node 1's self-loop.
    proof = CycleRatioCertificate(scale=1, ratio_num=np.array([2, 5]),
                                  ratio_den=np.array([1, 1]), potential=np.array([0, 0]),
                                  policy=np.array([0, 1]), circuit=np.array([1]))
    claim = CycleRatioClaim(Fraction(5), np.array([1]), np.array([2, 5]), np.array([1, 1]),
                            proof)
    assert verify_cycle_ratio(*arcs, claim) is None


def test_products_that_may_leave_int64_are_left_to_the_numpy_checks():
    # 2 * |w| |T| = 2 * 2**61 * 1 reaches the bound 2**62: declined, though the claim
    # (one self-loop of weight 2**61, ratio 2**61) holds and numpy proves it.
    big = 2**61
    assert kernel.arc_checks(*_arrays([0], [0], [big], [1], [big], [1], [0], [0])) == 0
    proof = CycleRatioCertificate(scale=1, ratio_num=np.array([big]), ratio_den=np.array([1]),
                                  potential=np.array([0]), policy=np.array([0]),
                                  circuit=np.array([0]))
    claim = CycleRatioClaim(Fraction(big), np.array([0]), np.array([big]), np.array([1]), proof)
    assert verify_cycle_ratio([0], [0], [big], [1], claim) is None
    # One below: 2 * (2**60 - 1) < 2**62, proven by the compiled pass.
    small = 2**60 - 1
    assert kernel.arc_checks(*_arrays([0], [0], [small], [1], [small], [1], [0],
                                      [0])) == kernel.ONE_RATIO


def test_a_node_without_cycle_time_or_arrays_of_other_lengths_are_declined():
    # Node 1 has den 0 (no cycle time): the numpy checks handle such nodes.
    assert kernel.arc_checks(*_arrays([0, 0], [0, 1], [1, 0], [1, 0], [1, 0], [1, 0],
                                      [0, 0], [0, -1])) == 0
    assert kernel.arc_checks(*_arrays([0], [0], [1], [1], [1, 1], [1], [0], [0])) == 0
    assert kernel.arc_checks(*_arrays([], [], [], [], [], [], [], [])) == 0


@st.composite
def small_claims(draw):
    """A solver's claim on a strongly connected graph of weights 0..3, then one entry of
    one of its eight arrays moved by one: ties and tight arcs are common at this size, so
    a check off by one in the compiled pass shows."""
    n = draw(st.integers(1, 6))
    src = list(range(n)) + draw(st.lists(st.integers(0, n - 1), max_size=2 * n))
    dst = [(k + 1) % n for k in range(n)] + draw(
        st.lists(st.integers(0, n - 1), min_size=len(src) - n, max_size=len(src) - n))
    w = draw(st.lists(st.integers(0, 3), min_size=len(src), max_size=len(src)))
    t = draw(st.lists(st.integers(1, 2), min_size=len(src), max_size=len(src)))
    r = max_cycle_ratio(src, dst, w, t)
    c = r.certificate
    arrays = [np.array(x, dtype=np.int64) for x in (r.src, r.dst, r.weight, r.tokens,
                                                     c.ratio_num, c.ratio_den, c.potential,
                                                     c.policy)]
    which = draw(st.integers(2, 7))  # not the arcs' ends: those are checked before
    k = draw(st.integers(0, len(arrays[which]) - 1))
    arrays[which][k] += draw(st.sampled_from([-1, 0, 1]))
    if draw(st.booleans()):  # the ends as the solver keeps them: int32 (the fused type)
        arrays[0], arrays[1] = arrays[0].astype(np.int32), arrays[1].astype(np.int32)
    return arrays


@settings(max_examples=500, deadline=None)
@given(arrays=small_claims())
def test_the_compiled_pass_holds_exactly_when_the_numpy_arc_and_policy_checks_hold(arrays):
    src, dst, w, t, W, T, X, policy = arrays
    held = kernel.arc_checks(*arrays)
    proof = CycleRatioCertificate(scale=1, ratio_num=W, ratio_den=T, potential=X,
                                  policy=policy, circuit=np.array([0]))
    claim = CycleRatioClaim(Fraction(0), np.array([0]), W, T, proof)
    with pytest.MonkeyPatch.context() as m, _kernels.use("numpy"):
        m.setattr(certificate, "_verify_circuit", lambda *args: None)  # the arcs and policy only
        try:
            verify_cycle_ratio(src, dst, w, t, claim)
            numpy_holds = True
        except CertificateError:
            numpy_holds = False
    if (T > 0).all():  # every node has a cycle time: the compiled pass decides alone
        assert bool(held) == numpy_holds
        if held:
            one = bool((W == W[0]).all() and (T == T[0]).all())
            assert held == (kernel.ONE_RATIO if one else kernel.ALL_HOLD)
    else:
        assert held == 0


def test_a_policy_arc_into_another_node_is_declined_though_it_would_be_tight():
    # Self-loops 0 -> 0 and 1 -> 1 (weight 1, one token: ratio 1 at both nodes), X = 0.
    # Node 1's policy arc is arc 0, which ends at node 0; its tightness would hold
    # (X0 + 1 - 1 = 0 = X1), so only the check of where it ends refuses it.
    arrays = _arrays([0, 1], [0, 1], [1, 1], [1, 1], [1, 1], [1, 1], [0, 0], [0, 0])
    assert kernel.arc_checks(*arrays) == 0
    proof = CycleRatioCertificate(scale=1, ratio_num=arrays[4], ratio_den=arrays[5],
                                  potential=arrays[6], policy=arrays[7], circuit=np.array([0]))
    claim = CycleRatioClaim(Fraction(1), np.array([0]), arrays[4], arrays[5], proof)
    with pytest.raises(CertificateError, match="a policy arc does not end at its node"):
        verify_cycle_ratio(*arrays[:4], claim)


def test_the_bound_itself_cannot_wrap_around():
    # Found by review: w, W and X at -2**63 and T at 2**63 - 1 with a token count of
    # -2**63 make |X| + |w| |T| + |W| |t| exactly 2**127, whose double wraps to 0 in
    # 128 bits. The numpy checks refuse the claim: arc 2 (1 -> 0) would need
    # X0 >= X1 + 0 * T - W * 2 = -2**63 + 2**64 > X0 = -2**63.
    low, high = -2**63, 2**63 - 1
    arrays = _arrays([0, 0, 1], [0, 1, 0], [low, 0, 0], [high, low, 2], [low, low],
                     [high, high], [low, low], [0, 1])
    assert kernel.arc_checks(*arrays) == 0
    proof = CycleRatioCertificate(scale=1, ratio_num=arrays[4], ratio_den=arrays[5],
                                  potential=arrays[6], policy=arrays[7], circuit=np.array([0]))
    claim = CycleRatioClaim(Fraction(low, high), np.array([0]), arrays[4], arrays[5], proof)
    with pytest.raises(CertificateError, match="arc 2 .* violates the potential inequality"):
        verify_cycle_ratio(*arrays[:4], claim)
