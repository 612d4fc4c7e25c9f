"""Integer-array helpers shared by the solver and by its independent checker.

This module imports nothing of :mod:`maxplus`, so the certificate checker
(:mod:`maxplus.certificate`) can use it without trusting any code of the
solver (:mod:`maxplus.cycle_ratio`, :mod:`maxplus.policy_iteration`).
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

__all__ = [
    "INT64_SAFE",
    "abs_max",
    "argmax_ratio",
    "compare_ratios",
    "exact_ints",
    "find_circuit",
    "float_ratios",
    "gcd_arrays",
    "int_array",
    "products_fit",
]

INT64_SAFE = 2**62
"""Integers of absolute value below this may be added in pairs in int64 without overflow."""


def gcd_arrays(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Elementwise gcd of two integer arrays (int64 or object).

    >>> gcd_arrays(np.array([4, 9]), np.array([6, 3])).tolist()
    [2, 3]
    """
    if a.dtype == object or b.dtype == object:
        # A ufunc made by frompyfunc is typed as returning Any: the result is an object array.
        out: np.ndarray = np.frompyfunc(math.gcd, 2, 1)(a, b)
    else:
        out = np.gcd(a, b)  # Any in the stubs, for arrays of unknown dtype
    return out


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


def find_circuit(src: np.ndarray, dst: np.ndarray, n: int,
                 arcs: np.ndarray | None = None) -> list[int]:
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


def abs_max(a: np.ndarray) -> int:
    """Largest absolute value of an integer array, as a Python int (0 when empty).

    Never overflows: ``np.abs`` of int64's smallest value would stay negative.

    >>> abs_max(np.array([-2**63, 5])) == 2**63
    True
    """
    if len(a) == 0:
        return 0
    return max(int(a.max()), -int(a.min()))


def exact_ints(a: np.ndarray) -> np.ndarray:
    """An integer array as int64, or as object (Python ints) when int64 cannot hold it.

    uint64 values from 2**63 would wrap to negative numbers in int64.

    >>> exact_ints(np.array([2**64 - 1], dtype=np.uint64)).tolist() == [2**64 - 1]
    True
    """
    if a.dtype == object:
        return a
    if a.dtype.kind == "u" and len(a) and int(a.max()) > np.iinfo(np.int64).max:
        out = np.empty(len(a), dtype=object)
        out[:] = a.tolist()
        return out
    return a.astype(np.int64, copy=False)


def products_fit(*pairs: tuple[np.ndarray, np.ndarray]) -> bool:
    """True when, for each pair ``(a, b)``, every ``a[i] * b[j]`` and a sum of two fit int64."""
    for a, b in pairs:
        if a.dtype == object or b.dtype == object or abs_max(a) * abs_max(b) >= INT64_SAFE:
            return False
    return True


def _as_object(a: np.ndarray) -> np.ndarray:
    if a.dtype == object:
        return a
    out = np.empty(len(a), dtype=object)
    out[:] = a.tolist()
    return out


def compare_ratios(a_num: np.ndarray, a_den: np.ndarray, b_num: np.ndarray,
                   b_den: np.ndarray) -> npt.NDArray[np.int8]:
    """Elementwise sign of ``a_num/a_den - b_num/b_den`` (denominators > 0), exact.

    int64 cross-multiplication when the products cannot overflow, Python ints otherwise.

    >>> compare_ratios(np.array([1, 2**70]), np.array([3, 1]), np.array([1, 2**70]),
    ...                np.array([2, 1])).tolist()
    [-1, 0]
    """
    if not products_fit((a_num, b_den), (b_num, a_den)):
        a_num, a_den, b_num, b_den = (_as_object(x) for x in (a_num, a_den, b_num, b_den))
    left, right = a_num * b_den, b_num * a_den
    # Object arrays compare to Any in numpy's stubs; the comparisons are boolean arrays.
    above: npt.NDArray[np.bool_] = left > right
    below: npt.NDArray[np.bool_] = left < right
    return above.astype(np.int8) - below.astype(np.int8)


def float_ratios(num: np.ndarray, den: np.ndarray) -> npt.NDArray[np.float64]:
    """Nearest floats of ``num/den`` (den > 0), ``±inf`` beyond float range.

    Only an accelerator: callers settle every decision exactly.

    >>> float_ratios(np.array([10**400, 1], dtype=object), np.array([1, 3], dtype=object)).tolist()
    [inf, 0.3333333333333333]
    """
    if num.dtype != object and den.dtype != object:
        return num.astype(np.float64) / den.astype(np.float64)
    ratios: np.ndarray = np.frompyfunc(_float_ratio, 2, 1)(num, den)  # objects (floats)
    return ratios.astype(np.float64)


def _float_ratio(a: int, b: int) -> float:
    try:
        return int(a) / int(b)  # correctly rounded for Python ints of any size
    except OverflowError:
        return math.inf if (a > 0) == (b > 0) else -math.inf


def argmax_ratio(num: np.ndarray, den: np.ndarray) -> int:
    """Index of the (first) largest ``num/den`` (all ``den > 0``), compared exactly.

    Floats shortlist the candidates (every ratio within float error of the
    float maximum); an exact knockout tournament among them, vectorized,
    settles the winner. Infinite floats (huge ratios) shortlist everything
    that could be the maximum.

    >>> argmax_ratio(np.array([7, 5, 9]), np.array([3, 2, 4]))  # 7/3, 5/2, 9/4
    1
    >>> argmax_ratio(np.array([10**400, 10**400 + 1], dtype=object), np.array([3, 3]))
    1
    """
    approx = float_ratios(num, den)
    top = approx.max()
    if math.isinf(top) and top > 0:
        cand = np.flatnonzero(approx == top)
    else:
        # Float division of exact ints errs by a few ulps; 1e-9 relative is ample.
        cand = np.flatnonzero(approx >= top - abs(top) * 1e-9 - 1e-300)
    if len(cand) > 1:
        # Most graphs give most nodes one cycle time: one exact comparison of
        # every candidate with the first settles that case (nothing above it:
        # it is the first of the largest), where the tournament took log2 of
        # the candidates' count in rounds (0.3 ms of a 12 ms solve at 10^4 nodes).
        # Otherwise the largest lie among those strictly above it, in order.
        head = cand[:1]
        above = compare_ratios(num[cand], den[cand], num[head], den[head]) > 0
        if not above.any():
            return int(cand[0])
        cand = cand[above]
    while len(cand) > 1:
        # Pair neighbours; the left one (lower index) wins ties, an odd one out passes.
        left, right = cand[0:len(cand) - 1:2], cand[1::2]
        sign = compare_ratios(num[right], den[right], num[left], den[left])
        winners = np.where(sign > 0, right, left)
        cand = np.concatenate([winners, cand[len(cand) - 1:]]) if len(cand) % 2 else winners
    return int(cand[0])
