"""Bad arguments to the public maxplus API end in the library's own errors.

Every mistake raises :class:`maxplus.MaxPlusError` (for bad values its
subclass :class:`maxplus.MaxPlusValueError`, which names the parameter), never
a MemoryError, IndexError, TypeError or a silently truncated value.
"""
from __future__ import annotations

import math
import re
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import maxplus
from maxplus import MaxPlusError, MaxPlusValueError
from maxplus.scalar import exact_matrix, exact_vector

# --------------------------------------------------------------------------- max_cycle_ratio


def refused(where: str, *args, **kwargs) -> MaxPlusValueError:
    with pytest.raises(MaxPlusValueError) as caught:
        maxplus.max_cycle_ratio(*args, **kwargs)
    assert caught.value.where.startswith(where), caught.value
    return caught.value


def test_a_huge_node_index_is_refused_before_any_allocation():
    # Before: numpy tried to allocate 10**12 entries per node array (7 TiB).
    error = refused("src[1]", [0, 10**12], [0, 0], [1, 1])
    assert "1000000000000" in str(error)
    refused("n_nodes", [0], [0], [1], n_nodes=10**12)


def test_spare_nodes_up_to_the_stated_bound_are_accepted():
    # The bound is 2 per arc plus maxplus.cycle_ratio.MAX_SPARE_NODES nodes no arc touches.
    from maxplus.cycle_ratio import MAX_SPARE_NODES
    r = maxplus.max_cycle_ratio([0], [0], [3], n_nodes=2 + MAX_SPARE_NODES)
    assert r.cycle_times[:2] == [3, None]
    refused("n_nodes", [0], [0], [3], n_nodes=3 + MAX_SPARE_NODES)


@pytest.mark.parametrize("n_nodes", [math.nan, 2.5, True, "2", -1, 1.0])
def test_n_nodes_must_be_a_whole_number(n_nodes):
    # Before: nan gave a bare ValueError, 2.5 was silently taken as 2.
    error = refused("n_nodes", [0, 1], [1, 0], [1, 1], n_nodes=n_nodes)
    assert "n_nodes" in str(error)


def test_n_nodes_may_be_a_numpy_integer():
    assert maxplus.max_cycle_ratio([0], [0], [2], n_nodes=np.int64(1)).ratio == 2


@pytest.mark.parametrize("name, position", [("src", 0), ("dst", 1), ("weight", 2),
                                            ("tokens", 3)])
def test_masked_entries_are_refused_by_name(name, position):
    # Before: IndexError or TypeError, or the masked value silently used.
    args = [[0, 1], [1, 0], [1, 1], [1, 1]]
    args[position] = np.ma.masked_array(args[position], mask=[False, True])
    error = refused(f"{name}[1]", *args)
    assert "masked" in str(error)


def test_masked_arrays_without_masked_entries_are_plain_data():
    unmasked = np.ma.masked_array([0, 1], mask=False)
    r = maxplus.max_cycle_ratio(unmasked, [1, 0], np.ma.masked_array([3, 5]), [1, 1])
    assert r.ratio == 4


def test_python_ints_past_int64_in_a_list_are_kept_exact():
    # numpy 2 turns a list mixing 0 and 2**63 into float64 (9223372036854775808.0,
    # then read back as 9223372036854776000): a silent rounding, before.
    r = maxplus.max_cycle_ratio([0, 0], [0, 0], [0, 2**63], [1, 1])
    assert r.ratio == 2**63
    r = maxplus.max_cycle_ratio([0], [0], [2**64 + 1], [2**63 + 1])
    assert r.ratio == Fraction(2**64 + 1, 2**63 + 1)


def test_a_node_index_past_int64_in_a_list_is_refused_by_name():
    refused("src[1]", [0, 2**64], [0, 0], [1, 1])


@pytest.mark.parametrize("node", [5, -1, 2, 1.5, None, "0"])
def test_policy_circuit_of_a_node_that_has_none(node):
    # Nodes 0 and 1 form a circuit, node 2 has no cycle time (no circuit reaches it).
    # Before: 5 gave an IndexError and -1 the circuit of node 2 (counted from the end).
    r = maxplus.max_cycle_ratio([0, 1], [1, 0], [1, 1], n_nodes=3)
    with pytest.raises(MaxPlusValueError) as caught:
        r.policy_circuit(node)
    assert caught.value.where == "node"


def test_policy_circuit_of_a_numpy_integer():
    r = maxplus.max_cycle_ratio([0, 1], [1, 0], [1, 3])
    assert sorted(r.policy_circuit(np.int32(1)).tolist()) == [0, 1]  # the circuit 0 -> 1 -> 0


# --------------------------------------------------------------------------- the other entry points

@pytest.mark.parametrize("max_power", [None, math.nan, 2.5, True, -1, "10"])
def test_transient_budget_must_be_a_whole_number(max_power):
    # Before: None gave a TypeError.
    with pytest.raises(MaxPlusValueError) as caught:
        maxplus.transient([[3, 7], [2, 4]], max_power=max_power)
    assert caught.value.where == "max_power"


@pytest.mark.parametrize("max_steps", [None, math.nan, 2.5, True, -1])
def test_trajectory_budget_must_be_a_whole_number(max_steps):
    with pytest.raises(MaxPlusValueError) as caught:
        maxplus.trajectory_transient([[3, 7], [2, 4]], [0, 0], max_steps=max_steps)
    assert caught.value.where == "max_steps"


JUNK = [None, math.nan, math.inf, -1, 0, 2.5, True, "x", b"1", object(), {}, [], [[]],
        [[1, 2]], [[1], [2, 3]], [[[1]]], 10**12, complex(1, 1),
        np.ma.masked_array([[1, 2], [3, 4]], mask=[[False, True], [False, False]]),
        np.ma.masked_array([1, 2], mask=[True, False]), np.zeros((2, 3)),
        np.array([["a"]]), np.array([[np.nan]]), [[Fraction(1, 3), "1/0"]], [[1e999]]]

GOOD = [[[3, 7], [2, 4]], [[1]], [1, 2], 2, [[0, None], [None, 1]]]

ENTRY_POINTS = {
    "identity": lambda a, b: maxplus.identity(a),
    "oplus": maxplus.oplus,
    "otimes": maxplus.otimes,
    "plus": lambda a, b: maxplus.plus(a),
    "power": maxplus.power,
    "left_residual": maxplus.left_residual,
    "right_residual": maxplus.right_residual,
    "solve": maxplus.solve,
    "star": lambda a, b: maxplus.star(a),
    "critical_graph": lambda a, b: maxplus.critical_graph(a),
    "cycle_time_vector": lambda a, b: maxplus.cycle_time_vector(a),
    "cyclicity": lambda a, b: maxplus.cyclicity(a),
    "eigenspace": lambda a, b: maxplus.eigenspace(a),
    "eigenvalue": lambda a, b: maxplus.eigenvalue(a),
    "eigenvector": lambda a, b: maxplus.eigenvector(a),
    "howard": lambda a, b: maxplus.howard(a),
    "is_irreducible": lambda a, b: maxplus.is_irreducible(a),
    "karp": lambda a, b: maxplus.karp(a),
    "transient": lambda a, b: maxplus.transient(a, b),
    "trajectory_transient": maxplus.trajectory_transient,
    "trajectory_transient budget": lambda a, b: maxplus.trajectory_transient(
        [[3, 7], [2, 4]], [0, 0], a),
    "to_explicit": maxplus.to_explicit,
    "simulate": lambda a, b: maxplus.simulate(a, [[1, None], [None, 2]], initial=[0, 0],
                                              steps=b),
    "max_cycle_ratio": lambda a, b: maxplus.max_cycle_ratio(a, b, [1]),
    "max_cycle_ratio weight": lambda a, b: maxplus.max_cycle_ratio([0], [0], a, b),
    "max_cycle_ratio n_nodes": lambda a, b: maxplus.max_cycle_ratio([0], [0], [1], None, a),
    "exact": lambda a, b: maxplus.exact(a),
    "exact_vector": lambda a, b: maxplus.exact_vector(a),
    "exact_matrix": lambda a, b: maxplus.exact_matrix(a),
}

arguments = st.sampled_from(JUNK + GOOD)


@settings(max_examples=600, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.sampled_from(sorted(ENTRY_POINTS)), arguments, arguments)
def test_junk_meets_only_the_documented_errors(name, a, b):
    try:
        ENTRY_POINTS[name](a, b)
    except MaxPlusError:
        pass


@pytest.mark.parametrize("convert, values, where", [
    (exact_vector, np.ma.masked_array([1, 2], mask=[False, True]), "x[1]"),
    (exact_matrix, np.ma.masked_array([[1, 2], [3, 4]], mask=[[0, 0], [1, 0]]), "A[1][0]"),
])
def test_exact_conversions_refuse_a_masked_entry_by_index(convert, values, where):
    # .tolist() of a masked array gives None for a masked entry, which read as ε.
    with pytest.raises(MaxPlusValueError, match=re.escape(where) + ": the entry is masked"):
        convert(values)
