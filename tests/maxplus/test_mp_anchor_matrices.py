"""Every ``kind == "matrix"`` case of shared/anchors/maxplus/cases.json through the
public API of maxplus.dense / spectral / implicit.

The anchors share our convention (``x(k+1) = A ⊗ x(k)``, ``A[i][j]`` = arc
j -> i, null = ε, 0-based). Eigenvectors are unique only up to an additive
constant (and up to the eigenspace): we check ``A ⊗ v = λ ⊗ v`` with a naive
product, that the anchor's vector is an eigenvector too, and proportionality
when the critical graph has a single class. The anchors are read-only.
"""

from __future__ import annotations

import json
import re
from fractions import Fraction

import numpy as np
import pytest

from maxplus import ReducibleMatrixError
from maxplus.dense import oplus, otimes, solve, star
from maxplus.implicit import simulate, to_explicit
from maxplus.scalar import EPS
from maxplus.spectral import (
    critical_graph,
    cycle_time_vector,
    cyclicity,
    eigenspace,
    eigenvalue,
    eigenvector,
    howard,
    karp,
)
from maxplus.transient import trajectory_transient, transient
from tests.paths import ANCHORS  # noqa: E402

CASES = json.loads((ANCHORS / "maxplus" / "cases.json").read_text())
MATRIX_CASES = [case for case in CASES if case["kind"] == "matrix"]
BY_ID = {case["id"]: case for case in CASES}

F = Fraction


def fr(v):
    """Anchor number -> exact value (floats by their decimal text: 4.4 is 22/5)."""
    return EPS if v is None else F(str(v))


def parse(A):
    return [[fr(v) for v in row] for row in A]


def naive_apply(A, x):
    return [max(A[i][j] + x[j] for j in range(len(x))) for i in range(len(A))]


def is_eigenvector(A, v, lam):
    return any(x != EPS for x in v) and naive_apply(A, v) == [x + lam for x in v]


def proportional(u, v):
    if [x == EPS for x in u] != [x == EPS for x in v]:
        return False
    return len({a - b for a, b in zip(u, v) if a != EPS}) == 1


def anchor_eigenvalue(case):
    return F(case["eigenvalue_exact"]) if "eigenvalue_exact" in case else fr(case["eigenvalue"])


def by_id(*ids):
    return [pytest.param(BY_ID[i], id=i) for i in ids]


ALL = [pytest.param(case, id=case["id"]) for case in MATRIX_CASES]


def test_the_anchor_file_has_the_expected_matrix_cases():
    assert len(MATRIX_CASES) == 16
    for case in MATRIX_CASES:
        # maxpluslib_mcm_graph1 states its matrix in the DP/Howard orientation
        # (edge i->j is matrix[i][j]) and notes that this is the same cycle-time
        # vector as x(k+1) = A x(k) with that very A: our convention too.
        assert case["convention"].startswith("x(k+1) = A (x) x(k)") or (
            case["id"] == "maxpluslib_mcm_graph1"
            and "equals x(k+1)=A x(k) cycle time with this A" in case["convention"]
        )


# --------------------------------------------------------------------------- every case


@pytest.mark.parametrize("case", ALL)
def test_eigenvalue_howard_and_karp(case):
    lam = anchor_eigenvalue(case)
    assert eigenvalue(case["matrix"]) == lam
    assert karp(case["matrix"]) == lam
    assert howard(case["matrix"]).eigenvalue == lam


@pytest.mark.parametrize("case", ALL)
def test_cycle_time_vector(case):
    expected = [fr(v) for v in case["cycle_time_vector"]]
    assert cycle_time_vector(case["matrix"]) == expected
    assert howard(case["matrix"]).cycle_time_vector == expected


@pytest.mark.parametrize("case", ALL)
def test_eigenvector(case):
    A = parse(case["matrix"])
    lam = anchor_eigenvalue(case)
    v = eigenvector(case["matrix"]).tolist()
    assert is_eigenvector(A, v, lam)
    if "eigenvector" in case:
        theirs = [fr(x) for x in case["eigenvector"]]
        assert is_eigenvector(A, theirs, lam)
        if len(critical_graph(case["matrix"]).components) == 1:
            assert proportional(v, theirs)
    for other in case.get("other_eigenvectors", []):
        assert is_eigenvector(A, [fr(x) for x in other], lam)


@pytest.mark.parametrize("case", [c for c in ALL if "other_eigenpairs" in c.values[0]])
def test_other_eigenpairs_of_reducible_matrices(case):
    # Reducible matrices have more eigenvalues; ours is the largest one.
    A = parse(case["matrix"])
    for pair in case["other_eigenpairs"]:
        mu = fr(pair["eigenvalue"])
        assert is_eigenvector(A, [fr(x) for x in pair["eigenvector"]], mu)
        assert mu < eigenvalue(case["matrix"])


@pytest.mark.parametrize("case", [c for c in ALL if "cyclicity" in c.values[0]])
def test_cyclicity(case):
    assert cyclicity(case["matrix"]) == case["cyclicity"]


@pytest.mark.parametrize("case", [c for c in ALL if "transient" in c.values[0]])
def test_transient(case):
    assert transient(case["matrix"]) == case["transient"]


# Reducible cases without a matrix transient: some class has only circuits slower
# than λ and no critical circuit on its own walks (read from each case's matrix):
SLOW_CLASSES = {
    "mpjl_howard_upper_triangular_two_eigenvalues": [[0]],  # loop 1 < λ = 2
    "mpjl_2x2_lower_triangular_chi_not_constant": [[0]],  # loop 3 < 4
    "mpa_ex2_39_triangular_two_eigenvalues": [[0]],  # loop 0 < 1
    "olsder_roos_vanegmond_6x6_two_critical_circuits": [[1]],  # notes: A^k[1][1] = 5k
    "deschutter_production_open_loop": [[0]],  # machine 1 rate 5 < 6
    "cmlib_mpm_matrix_example2_reducible_generalized_eigenmode": [[0, 1], [3, 4]],  # 1, 3 < 5
    "maxpluslib_mcm_graph1": [[4]],  # loop 1 < 5/2
}


@pytest.mark.parametrize("case", [c for c in ALL if "transient" not in c.values[0]])
def test_no_matrix_transient_for_reducible_cases(case):
    with pytest.raises(ReducibleMatrixError) as info:
        transient(case["matrix"])
    named = re.search(r"class (\[[0-9, ]+\])", str(info.value)).group(1)
    assert json.loads(named) in SLOW_CLASSES[case["id"]]


@pytest.mark.parametrize("case", ALL)
def test_howard_policy_and_bias(case):
    A = parse(case["matrix"])
    h = howard(case["matrix"])
    for i, j in enumerate(h.policy):
        chi = h.cycle_time_vector[i]
        assert A[i][j] != EPS
        assert h.bias[i] == h.bias[j] + A[i][j] - chi
    circuit = h.circuit
    arcs = list(zip(circuit, circuit[1:] + circuit[:1]))
    assert F(sum(A[b][a] for a, b in arcs), len(arcs)) == anchor_eigenvalue(case)


# --------------------------------------------------------------------------- case-specific data


@pytest.mark.parametrize("case", by_id("mpjl_howard_2x2_irreducible"))
def test_mpjl_howard_2x2(case):
    # Critical graph = self-loop on node 1 (notes).
    g = critical_graph(case["matrix"])
    assert g.nodes == [1] and g.arcs == [(1, 1)]


@pytest.mark.parametrize("case", by_id("mpjl_2x2_lower_triangular_chi_not_constant"))
def test_reducible_bias_is_not_an_eigenvector(case):
    # Notes: "the test asserts S*v != lambda*v (bias is not an eigenvector)".
    A = parse(case["matrix"])
    h = howard(case["matrix"])
    assert naive_apply(A, h.bias) != [b + 4 for b in h.bias]
    # The only eigenpair is (4, [ε, 0]) (notes): ours is exactly that column.
    assert eigenvector(case["matrix"]).tolist() == [EPS, 0]


@pytest.mark.parametrize("case", by_id("scicos_eigenspace_two_critical_loops"))
def test_scicos_eigenspace(case):
    basis = eigenspace(case["matrix"]).tolist()
    components = len(critical_graph(case["matrix"]).components)
    assert len(basis[0]) == case["critical_components"] == components
    theirs = [[fr(x) for x in vec] for vec in case["eigenspace_basis"]]
    ours = [[row[k] for row in basis] for k in range(len(basis[0]))]
    for vec in ours:
        assert any(proportional(vec, t) for t in theirs)


@pytest.mark.parametrize("case", by_id("bcoq_2x2_cyclicity2"))
def test_bcoq_2x2_trajectory(case):
    traj = case["trajectory"]
    x = [fr(v) for v in traj["x0"]]
    for expected in traj["states"]:
        assert x == [fr(v) for v in expected]
        x = otimes(case["matrix"], x).tolist()
    # x(p) = c ⊗ x(q) with p = 3, q = 1, c = 9: periodic from K = 1 with period 2, 9 = 2 · 9/2.
    K, period, rate = trajectory_transient(case["matrix"], traj["x0"])
    assert (K, period, period * rate) == (traj["q"], traj["p"] - traj["q"], traj["c"])


@pytest.mark.parametrize("case", by_id("olsder_roos_vanegmond_6x6_two_critical_circuits"))
def test_olsder_critical_circuits(case):
    # critical_circuits_1based [[4,3,4],[1,5,6,1]] -> 0-based classes {2, 3} and {0, 4, 5}.
    expected = sorted(sorted({v - 1 for v in c}) for c in case["critical_circuits_1based"])
    assert critical_graph(case["matrix"]).components == expected


@pytest.mark.parametrize("case", by_id("star_irreducible_cyclicity2"))
def test_star_and_solve(case):
    assert star(case["matrix"]).tolist() == parse(case["kleene_star"])
    x = solve(case["matrix"], case["astarb"]["b"]).tolist()
    assert x == [fr(v) for v in case["astarb"]["x"]]
    # Notes: eigenvector = critical column 0 of A* (λ = 0, so (A − λ)^+ column 0).
    assert eigenvector(case["matrix"]).tolist() == [fr(v) for v in case["eigenvector"]]


@pytest.mark.parametrize("case", by_id("cmlib_mpm_matrix_example2_reducible_generalized_eigenmode"))
def test_generalized_eigenmode(case):
    mode = case["generalized_eigenmode"]
    v, eta = [fr(x) for x in mode["v"]], [fr(x) for x in mode["eta"]]
    assert cycle_time_vector(case["matrix"]) == eta
    for k in range(6):
        image = otimes(case["matrix"], [a + k * e for a, e in zip(v, eta)]).tolist()
        assert image == [a + (k + 1) * e for a, e in zip(v, eta)]


@pytest.mark.parametrize("case", by_id("maxpluslib_mcm_graph1"))
def test_maxpluslib_howard_policy(case):
    # Forced: nodes 0, 1, 2 have a single in-arc, node 3 must follow the 2.5 circuit
    # 0 -> 1 -> 2 -> 3 -> 0, node 4 only its own loop.
    assert howard(case["matrix"]).policy == case["howard_policy"]


def _parse_entries(text, value_of):
    """'A0(2,1)=d1,A0(4,1)=d1' or 'B0(1,1)=B0(1,5)=0' -> {(i, j): value}, 0-based."""
    entries = [(m.start(), int(m.group(2)) - 1, int(m.group(3)) - 1)
               for m in re.finditer(r"(A0|A1|B0|C)\((\d+),(\d+)\)", text)]
    values = [(m.start(), value_of(m.group(1))) for m in re.finditer(r"=(d\d+|0)(?=,|$)", text)]
    return {(i, j): next(val for pos, val in values if pos > start) for start, i, j in entries}


def _assemble(text, rows, cols, value_of):
    M = [[None] * cols for _ in range(rows)]
    for (i, j), v in _parse_entries(text, value_of).items():
        M[i][j] = v
    return M


@pytest.mark.parametrize("case", by_id("bcoq_multiproduct_7x7"))
def test_bcoq_multiproduct_assembly_and_trajectory(case):
    teg = case["teg"]
    d = teg["d"]

    def value_of(token):
        return d[int(token[1:]) - 1] if token.startswith("d") else 0

    A0 = _assemble(teg["A0_entries_1based"], 7, 7, value_of)
    A1 = _assemble(teg["A1_entries_1based"], 7, 7, value_of)
    B0 = _assemble(teg["B0_entries_1based"], 7, 6, value_of)
    C = _assemble(teg["C_entries_1based"], 6, 7, value_of)
    system = to_explicit(A0, A1, B=B0)
    # M = A0* A1 ⊕ A0* B0 K C with K = identity.
    M = oplus(system.A, otimes(system.B, C))
    assert M.tolist() == parse(case["matrix"])
    rows = case["trajectory"]["x_rows_k1_to_10"]
    x = [fr(row[0]) for row in rows]
    for k in range(1, 10):
        x = otimes(case["matrix"], x).tolist()
        assert x == [fr(row[k]) for row in rows]
    lam = anchor_eigenvalue(case)
    steady = [fr(v) for v in case["trajectory"]["steady_state_x0"]]
    assert is_eigenvector(parse(case["matrix"]), steady, lam)
    assert proportional(eigenvector(case["matrix"]).tolist(), steady)


@pytest.mark.parametrize("case", by_id("deschutter_production_open_loop"))
def test_deschutter_implicit_system(case):
    teg = case["teg"]
    system = to_explicit(teg["A0"], teg["A1"], B=teg["B0"])
    assert system.A.tolist() == parse(case["matrix"])  # A = A0* A1
    assert system.B.tolist() == parse(teg["B"])  # B = A0* B0
    traj = case["trajectory"]
    x = simulate(teg["A0"], teg["A1"], B=teg["B0"], initial=traj["x0"], inputs=[0], steps=10)
    assert x[1:].tolist() == parse(traj["x_1_to_10"])
    y = [otimes(teg["C"], row)[0] for row in x[1:].tolist()]
    assert y == [fr(v) for v in traj["y_1_to_10"]]
    assert np.all(x[0] == EPS)
