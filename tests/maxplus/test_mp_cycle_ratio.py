"""Sparse maximum cycle ratio: brute force, reference graphs, certificates, bad input."""

from __future__ import annotations

import itertools
import json
from fractions import Fraction

import networkx as nx
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from maxplus import CertificateError, MaxPlusValueError, ZeroTokenCircuitError
from maxplus.cycle_ratio import CycleRatioCertificate, max_cycle_ratio

# Both kernels: on graphs this small max_cycle_ratio would run the list one only.
pytestmark = pytest.mark.usefixtures("every_kernel")


def brute_force(n, src, dst, w, t):
    """(ratio per elementary circuit with its node set, zero-token circuit found?)."""
    simple = nx.DiGraph()
    simple.add_nodes_from(range(n))
    simple.add_edges_from(zip(src, dst))
    found, zero = [], False
    for cycle in nx.simple_cycles(simple):
        pairs = list(zip(cycle, cycle[1:] + cycle[:1]))
        choices = [[a for a in range(len(src)) if (src[a], dst[a]) == p] for p in pairs]
        for arcs in itertools.product(*choices):
            tokens = sum(t[a] for a in arcs)
            if tokens == 0:
                zero = True
            else:
                found.append((Fraction(sum(w[a] for a in arcs), tokens), set(cycle)))
    return found, zero, simple


@st.composite
def graphs(draw, max_nodes=6, max_arcs=12):
    n = draw(st.integers(1, max_nodes))
    m = draw(st.integers(0, max_arcs))
    node = st.integers(0, n - 1)
    src = draw(st.lists(node, min_size=m, max_size=m))
    dst = draw(st.lists(node, min_size=m, max_size=m))
    w = draw(st.lists(st.integers(-6, 12), min_size=m, max_size=m))
    t = draw(st.lists(st.integers(0, 3), min_size=m, max_size=m))
    return n, src, dst, w, t


@settings(max_examples=300, deadline=None)
@given(graphs())
def test_ratio_and_cycle_times_equal_brute_force(graph):
    n, src, dst, w, t = graph
    found, zero, simple = brute_force(n, src, dst, w, t)
    if zero:
        with pytest.raises(ZeroTokenCircuitError) as info:
            max_cycle_ratio(src, dst, w, t, n_nodes=n)
        # The named circuit really is a closed walk without tokens.
        arcs = info.value.circuit
        assert all(t[a] == 0 for a in arcs)
        assert [dst[a] for a in arcs] == [src[a] for a in arcs[1:] + arcs[:1]]
        return
    result = max_cycle_ratio(src, dst, w, t, n_nodes=n)
    assert result.ratio == max((r for r, _ in found), default=None)
    for i in range(n):
        upstream = nx.ancestors(simple, i) | {i}
        expected = max((r for r, nodes in found if nodes & upstream), default=None)
        assert result.cycle_times[i] == expected
    assert result.verify()
    if result.ratio is not None:
        arcs = result.circuit.tolist()
        assert Fraction(sum(w[a] for a in arcs), sum(t[a] for a in arcs)) == result.ratio


def test_exact_weights_fractions_and_decimals():
    # Circuit 0 -> 1 -> 0 with weights 1/3 and 0.5 over 2 tokens: (1/3 + 1/2)/2 = 5/12.
    result = max_cycle_ratio([0, 1], [1, 0], ["1/3", 0.5], [1, 1])
    assert result.ratio == Fraction(5, 12)
    assert result.verify()


def test_matrix_case_karp_regression():
    # [[3,7],[2,4]]: arcs j->i weight A[i][j]; circuits 3, 4 and (7+2)/2 = 9/2.
    result = max_cycle_ratio([0, 1, 1, 0], [0, 0, 1, 1], [3, 7, 4, 2])
    assert result.ratio == Fraction(9, 2)


def _tampered(result, **changes):
    fields = {k: getattr(result.certificate, k) for k in CycleRatioCertificate.__dataclass_fields__}
    fields.update(changes)
    result.certificate = CycleRatioCertificate(**fields)
    return result


def test_tampered_ratio_fails():
    result = max_cycle_ratio([0, 1, 1], [1, 0, 1], [5, 3, 3], [1, 1, 1])
    result.ratio = Fraction(7, 2)
    with pytest.raises(CertificateError):
        result.verify()


def test_tampered_potential_fails():
    result = max_cycle_ratio([0, 1, 1, 2], [1, 0, 1, 0], [5, 3, 3, 1], [1, 1, 1, 1], n_nodes=3)
    potential = result.certificate.potential.copy()
    potential[1] -= 1
    with pytest.raises(CertificateError):
        _tampered(result, potential=potential).verify()


def test_tampered_cycle_time_fails():
    # Lowering every claimed cycle time to 3 breaks the potential inequality
    # on the circuit 0 -> 1 -> 0 of ratio 4.
    result = max_cycle_ratio([0, 1, 1], [1, 0, 1], [5, 3, 3], [1, 1, 1])
    num = np.array([3, 3])
    den = np.array([1, 1])
    result.cycle_time_num, result.cycle_time_den = num, den
    result.ratio = Fraction(3)
    with pytest.raises(CertificateError):
        _tampered(result, ratio_num=num, ratio_den=den).verify()


def test_tampered_one_ratio_certificates_fail():
    # Circuit 0 -> 1 -> 2 -> 0 (weights 5, 3, 4, one token each: ratio 4) with
    # the chord 0 -> 2 (weight 1): every node has cycle time 4, the checker's
    # one-ratio path. Each tampering below breaks one step of the proof.
    def solve():
        return max_cycle_ratio([0, 1, 2, 0], [1, 2, 0, 2], [5, 3, 4, 1], [1, 1, 1, 1])

    assert solve().verify() and set(solve().cycle_times) == {Fraction(4)}
    result = solve()
    result.cycle_time_num = result.cycle_time_num.copy()
    result.cycle_time_num[2] += 1  # node 2 claims 5
    with pytest.raises(CertificateError, match="node 2"):
        result.verify()
    result = solve()
    potential = result.certificate.potential.copy()
    potential[1] += 1  # the policy arc 1 -> 2 is no longer tight (or 0 -> 1 fails)
    with pytest.raises(CertificateError):
        _tampered(result, potential=potential).verify()
    result = solve()
    result.ratio = Fraction(9, 2)
    with pytest.raises(CertificateError):
        result.verify()


def test_nodes_without_upstream_circuit():
    # 0 -> 1 -> 2 is a path; only node 2 has a self-loop (ratio 5/1).
    result = max_cycle_ratio([0, 1, 2], [1, 2, 2], [1, 1, 5], [1, 1, 1])
    assert result.cycle_times == [None, None, Fraction(5)]
    assert result.verify()


def test_acyclic_graph_has_no_ratio():
    result = max_cycle_ratio([0, 1], [1, 2], [1, 2], [0, 0])
    assert result.ratio is None and len(result.circuit) == 0
    assert result.cycle_times == [None, None, None]


@pytest.mark.parametrize(
    "args, where",
    [
        (([0, 1], [1], [1, 2]), "dst"),
        (([0, 1], [1, 0], [1, float("nan")]), "weight[1]"),
        (([0, 1], [1, 0], [1, float("inf")]), "weight[1]"),
        (([0, 1], [1, 0], [1, "abc"]), "weight[1]"),
        (([0, 1], [1, 0], [1, 2], [1, -1]), "tokens[1]"),
        (([0, 1], [1, 0], [1, 2], [1, 0.5]), "tokens[1]"),
        (([0, -1], [1, 0], [1, 2]), "src[1]"),
    ],
)
def test_bad_input_names_the_entry(args, where):
    with pytest.raises(MaxPlusValueError) as info:
        max_cycle_ratio(*args)
    assert info.value.where == where
    assert isinstance(info.value, ValueError)


def test_zero_token_circuit_is_named():
    # 0 -> 1 -> 2 -> 0 with no token on any arc; the arc 2 -> 3 is elsewhere.
    with pytest.raises(ZeroTokenCircuitError) as info:
        max_cycle_ratio([0, 1, 2, 2], [1, 2, 0, 3], [1, 1, 1, 1], [0, 0, 0, 1])
    assert sorted(info.value.circuit) == [0, 1, 2]


def _read_edges(path):
    data = np.loadtxt(path, comments="#", dtype=np.int64, ndmin=2)
    return data[:, 0], data[:, 1], data[:, 2], data[:, 3]


def test_sdf3_hsdf_periods(anchors):
    cases = json.loads((anchors / "sdf" / "cases.json").read_text())["cases"]
    assert len(cases) >= 5
    for case in cases:
        src, dst, w, t = _read_edges(anchors / "sdf" / case["hsdf_edge_list"])
        result = max_cycle_ratio(src, dst, w, t)
        assert result.ratio == Fraction(case["period_fraction"]), case["name"]
        critical = case["critical_cycle"]
        assert int(w[result.circuit].sum()) * critical["sum_tokens"] == (
            critical["sum_weight"] * int(t[result.circuit].sum())
        )
        assert result.verify()


def _read_teg(path):
    lines = [ln for ln in path.read_text().splitlines()[1:] if ln.strip()]
    arcs = [ln.replace(":", " ").split() for ln in lines]
    return [[int(a[k]) for a in arcs] for k in range(4)]


def test_timed_petri_net_editor_teg_files(anchors):
    # tests/HowardTests.cpp of TimedPetriNetEditor: SemiNetherlands has cycle
    # time 143/3 everywhere. The editor reads line "i j" as the arc i -> j.
    src, dst, w, t = _read_teg(anchors / "teg" / "SemiNetherlands.teg")
    result = max_cycle_ratio(src, dst, w, t)
    assert result.ratio == Fraction(143, 3)
    assert set(result.cycle_times) == {Fraction(143, 3)}
    # SemiHoward: the editor reports chi = [1, 1, 2] with two components. Its
    # line "i j: h m" is the semi-Howard entry T[i][j] (x_i waits for x_j), so
    # the dater arc is j -> i. By hand: circuit 0 <-> 1 has ratio (0+1)/(1+0) = 1,
    # the self-loop on 2 has 2/1; node 2 waits for 0 and 1, not the reverse.
    i, j, w, t = _read_teg(anchors / "teg" / "SemiHoward.teg")
    result = max_cycle_ratio(j, i, w, t)
    assert result.cycle_times == [Fraction(1), Fraction(1), Fraction(2)]
    assert result.verify()
