"""A warning kept as a test: Karp's formula is max over nodes of the MIN over k.

mplusa 0.0.5's ``karp_algorithm`` takes the maximum over (node, k) instead,
which overestimates λ. On ``A = [[1, 5], [3, 2]]`` the elementary circuits
are (by hand):

* the self-loop on node 0, weight 1, mean 1;
* the self-loop on node 1, weight 2, mean 2;
* 0 -> 1 -> 0, arcs A[1][0] = 3 and A[0][1] = 5, mean (5 + 3)/2 = 4;

so λ = 4. Karp with D_k(v) the best walk of k arcs ending in v, started
everywhere at 0: D_1 = (5, 3), D_2 = (8, 8); node 0: min((8−0)/2, (8−5)/1)
= 3; node 1: min((8−0)/2, (8−3)/1) = 4; max over nodes = 4. The maximum over
k instead gives max(4, 3, 4, 5) = 5 at node 1, k = 1.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
import types
from fractions import Fraction

import numpy as np
import pytest

from maxplus import eigenvalue, howard, karp

A = [[1, 5], [3, 2]]


def _mplusa_karp():
    """mplusa's karp_algorithm, or None when mplusa is not installed.

    mplusa 0.0.5's package ``__init__`` imports its plotting module, which
    fails (it needs matplotlib, and annotates with an undefined name); the
    algebra module does not need it, so it is loaded under bare parent
    packages, and sys.modules is restored afterwards.
    """
    spec = importlib.util.find_spec("mplusa")
    if spec is None or not spec.submodule_search_locations:
        return None
    saved = {k: v for k, v in sys.modules.items() if k == "mplusa" or k.startswith("mplusa.")}
    try:
        for k in saved:
            del sys.modules[k]
        root = spec.submodule_search_locations[0]
        for name, path in (("mplusa", root), ("mplusa.maxplus", f"{root}/maxplus")):
            package = types.ModuleType(name)
            package.__path__ = [path]
            sys.modules[name] = package
        return importlib.import_module("mplusa.maxplus.maxplus").karp_algorithm
    finally:
        for k in [k for k in sys.modules if k == "mplusa" or k.startswith("mplusa.")]:
            del sys.modules[k]
        sys.modules.update(saved)


def test_our_eigenvalue_is_the_hand_derived_4():
    assert eigenvalue(A) == Fraction(4)
    assert karp(A) == Fraction(4)
    assert howard(A).circuit in ([0, 1], [1, 0])


def test_mplusa_karp_takes_the_max_over_k_and_gets_5():
    karp_algorithm = _mplusa_karp()
    if karp_algorithm is None:
        pytest.skip("mplusa is not installed")
    # mplusa reads A[k, j] as the arc k -> j: its graph is the transpose of
    # ours, which has the same circuits and the same means.
    wrong = karp_algorithm(np.array(A, dtype=float))
    assert wrong == 5.0  # a documented defect of the peer: λ is 4
    assert eigenvalue(A) == 4 != wrong
