"""The certificate checker on its own: arc arrays and a claim in, no solver involved.

The claims here are derived by hand (comments), so the checker is tested
apart from the solver whose results it checks; that it imports nothing of
the solver, type-only imports included, is an import-linter contract of
``pyproject.toml`` (run by ``tests/test_architecture.py``).
"""

from __future__ import annotations

import re
from dataclasses import replace
from fractions import Fraction

import numpy as np
import pytest

from maxplus import CertificateError, CycleRatioCertificate, max_cycle_ratio
from maxplus.certificate import CycleRatioClaim, verify_cycle_ratio

# Both kernels: on graphs this small max_cycle_ratio would run the list one only.
pytestmark = pytest.mark.usefixtures("every_kernel")

# Arcs 0: 0 -> 1 (weight 3), 1: 1 -> 0 (weight 5), 2: 2 -> 0 (weight 10, no token).
# The circuit 0 -> 1 -> 0 has ratio (3 + 5) / 2 = 4; node 2 is on no circuit and
# no circuit reaches it, so it has no cycle time (den 0, policy -1).
# Potentials X0 = 0, X1 = -1 make both circuit arcs tight (W/T = 4/1):
#   arc 0: X1 = X0 + 3*1 - 4*1 = -1;  arc 1: X0 = X1 + 5*1 - 4*1 = 0.
SRC, DST, WEIGHT, TOKENS = [0, 1, 2], [1, 0, 0], [3, 5, 10], [1, 1, 0]


def _claim(**proof) -> CycleRatioClaim:
    fields = dict(scale=1, ratio_num=np.array([4, 4, 0]), ratio_den=np.array([1, 1, 0]),
                  potential=np.array([0, -1, 0]), policy=np.array([1, 0, -1]),
                  circuit=np.array([0, 1]))
    fields.update(proof)
    return CycleRatioClaim(Fraction(4), np.array([0, 1]), np.array([4, 4, 0]),
                           np.array([1, 1, 0]), CycleRatioCertificate(**fields))


def test_a_claim_derived_by_hand_is_proven_from_arrays_alone():
    assert verify_cycle_ratio(SRC, DST, WEIGHT, TOKENS, _claim()) is None


def test_the_solver_result_is_the_same_claim():
    # The solver, given the same arcs, claims what was derived by hand above.
    r = max_cycle_ratio(SRC, DST, WEIGHT, TOKENS)
    assert (r.ratio, r.circuit_nodes, r.cycle_times) == (Fraction(4), [0, 1], [4, 4, None])
    assert r.verify()


@pytest.mark.parametrize("arcs, proof, message", [
    # X1 = 0: arc 1 would need X0 >= 0 + 5 - 4 = 1.
    ((SRC, DST, WEIGHT, TOKENS), dict(potential=np.array([0, 0, 0])),
     "arc 1 (1 -> 0) violates the potential inequality"),
    # A heavier arc 1 (6): the circuit's ratio is 9/2 > 4.
    ((SRC, DST, [3, 6, 10], TOKENS), {}, "arc 1 (1 -> 0) violates the potential inequality"),
    # Node 1's policy arc is arc 2 (2 -> 0), which ends at node 0.
    ((SRC, DST, WEIGHT, TOKENS), dict(policy=np.array([1, 2, -1])),
     "a policy arc does not end at its node"),
])
def test_a_wrong_claim_is_refused_naming_where(arcs, proof, message):
    with pytest.raises(CertificateError, match=re.escape(message)):
        verify_cycle_ratio(*arcs, _claim(**proof))


@pytest.mark.parametrize("arcs, claim, message", [
    # Before, short tokens and potentials were accepted (only live arcs and nodes were
    # read), the bad circuit raised IndexError and the zero scale ZeroDivisionError.
    ((SRC, DST, WEIGHT, [1, 1]), _claim(), "src, dst, weight and tokens of one length"),
    ((SRC, DST, WEIGHT, TOKENS), _claim(potential=np.array([0, -1])),
     "the claim's potential has shape"),
    (([0, 1, 5], DST, WEIGHT, TOKENS), _claim(), "arc 2 has src 5, not a node of the claim"),
    ((SRC, DST, WEIGHT, TOKENS), replace(_claim(), circuit=np.array([0, 7])),
     "names an arc that does not exist"),
    ((SRC, DST, WEIGHT, TOKENS), _claim(scale=0), "scale is 0; expected an integer > 0"),
])
def test_a_malformed_claim_is_a_certificate_error(arcs, claim, message):
    with pytest.raises(CertificateError, match=re.escape(message)):
        verify_cycle_ratio(*arcs, claim)
