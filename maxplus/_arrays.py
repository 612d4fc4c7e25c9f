"""Integer-array helpers shared by the solver and by its independent checker.

This module imports nothing of :mod:`maxplus`, so the certificate checker
(:mod:`maxplus.certificate`) can use it without trusting any code of the
solver (:mod:`maxplus.cycle_ratio`, :mod:`maxplus.policy_iteration`).
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

__all__ = ["INT64_SAFE", "gcd_arrays", "int_array", "find_circuit", "argmax_ratio"]

INT64_SAFE = 2**62
"""Integers of absolute value below this may be added in pairs in int64 without overflow."""


def gcd_arrays(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Elementwise gcd of two integer arrays (int64 or object).

    >>> gcd_arrays(np.array([4, 9]), np.array([6, 3])).tolist()
    [2, 3]
    """
    if a.dtype == object or b.dtype == object:
        return np.frompyfunc(math.gcd, 2, 1)(a, b)
    return np.gcd(a, b)


def int_array(values: list[int]) -> np.ndarray:
    """int64 when every value stays below ``INT64_SAFE`` in magnitude, else object (Python ints).

    >>> int_array([1, 2]).dtype, int_array([2**70]).dtype
    (dtype('int64'), dtype('O'))
    """
    if all(-INT64_SAFE < v < INT64_SAFE for v in values):
        return np.array(values, dtype=np.int64)
    out = np.empty(len(values), dtype=object)
    out[:] = values
    return out


def find_circuit(src: np.ndarray, dst: np.ndarray, n: int, arcs: np.ndarray | None = None) -> list[int]:
    """One circuit (list of arc indices in order) among ``arcs``, or [] if acyclic.

    Parameters
    ----------
    src, dst : numpy.ndarray
        Arc endpoints.
    n : int
        Number of nodes.
    arcs : numpy.ndarray, optional
        Indices of the arcs to consider (default: all).

    Returns
    -------
    list of int

    Examples
    --------
    >>> find_circuit(np.array([0, 1, 2]), np.array([1, 2, 1]), 3)
    [1, 2]
    """
    if arcs is None:
        arcs = np.arange(len(src))
    arcs = np.asarray(arcs, dtype=np.int64)
    if len(arcs) == 0:
        return []
    s, d = src[arcs], dst[arcs]
    self_loops = np.flatnonzero(s == d)
    if len(self_loops):
        return [int(arcs[self_loops[0]])]
    graph = sp.csr_matrix((np.ones(len(arcs)), (s, d)), shape=(n, n))
    n_comp, labels = connected_components(graph, directed=True, connection="strong")
    sizes = np.bincount(labels, minlength=n_comp)
    big = np.flatnonzero(sizes > 1)
    if len(big) == 0:
        return []
    comp = big[0]
    inside = (labels[s] == comp) & (labels[d] == comp)
    sub = arcs[inside]
    # Walk forward inside one strongly connected class until a node repeats:
    # every node of the class has an out-arc inside it, so the walk never stops.
    out_arc: dict[int, int] = {}
    for a in sub.tolist():
        out_arc.setdefault(int(src[a]), a)
    start = int(src[sub[0]])
    seen: dict[int, int] = {}
    walk: list[int] = []
    node = start
    while node not in seen:
        seen[node] = len(walk)
        a = out_arc[node]
        walk.append(a)
        node = int(dst[a])
    return walk[seen[node]:]


def argmax_ratio(num: np.ndarray, den: np.ndarray) -> int:
    """Index of the largest ``num/den`` (all ``den > 0``), compared exactly.

    >>> argmax_ratio(np.array([7, 5, 9]), np.array([3, 2, 4]))  # 7/3, 5/2, 9/4
    1
    """
    if num.dtype == object or den.dtype == object:
        values = [Fraction(int(a), int(b)) for a, b in zip(num.tolist(), den.tolist())]
        return max(range(len(values)), key=values.__getitem__)
    approx = num.astype(float) / den.astype(float)
    best = int(np.argmax(approx))
    # Floats only shortlist; the winner is settled by exact cross-multiplication.
    for k in np.flatnonzero(approx >= approx[best] - abs(approx[best]) * 1e-9 - 1e-300).tolist():
        if int(num[k]) * int(den[best]) > int(num[best]) * int(den[k]):
            best = k
    return best
