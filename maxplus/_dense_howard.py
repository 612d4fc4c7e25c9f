"""Howard's policy iteration for the maximum cycle mean of a dense integer matrix.

A *policy* picks one in-arc per node (``policy[i] = j``: the arc ``j -> i``);
following it backwards from any node ends on a policy circuit. *Value
determination* gives every node the mean ``W/T`` of the circuit it reaches (a
reduced fraction of scaled integers) and a potential ``X`` (bias times T)
that is tight along the policy; *policy improvement* switches a node to an
in-arc from a node of larger mean, or, failing that, to one of the same mean
and larger potential. A circuit that survives an iteration keeps its root's
potential, which rules out cycling [1]_.

Everything is an integer: Python ints in value determination (one pass over
the nodes), int64 arrays (or object arrays beyond the int64-safe range) in
the improvement step for larger matrices, flat Python lists for small ones,
where numpy's per-call cost would dominate. No float is used, so no
tolerance either. Nothing here proves the result: :mod:`maxplus._max_mean`
has it checked by :mod:`maxplus._mean_certificate`.

References
----------
.. [1] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
   J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
   algebra", IFAC Conference on System Structure and Control, 1998.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from fractions import Fraction
from itertools import pairwise
from operator import add, itemgetter
from typing import NamedTuple, cast

import numpy as np

from ._arrays import INT64_SAFE
from .errors import MaxPlusError

__all__ = ["Policy", "Ratio", "optimal_policy", "policy_walk"]

Ratio = tuple[int, int]


class Policy(NamedTuple):
    """Per node: the mean (W, T) of its policy circuit, its potential, its policy arc."""

    ratio: list[Ratio]  # (W, T) per node, reduced, T > 0
    potential: list[int]
    policy: list[int]


def _value_determination(pol: list[int], wpol: list[int], old: Policy | None
                         ) -> tuple[list[Ratio], list[int]]:
    n = len(pol)
    ratio: list[Ratio | None] = [None] * n
    X = [0] * n
    walked = [-1] * n  # the start of the walk that last visited a node
    for s in range(n):
        if ratio[s] is not None:
            continue
        path: list[int] = []
        v = s
        while ratio[v] is None and walked[v] != s:
            walked[v] = s
            path.append(v)
            v = pol[v]
        if ratio[v] is None:  # v closes a new policy circuit: path[k:]
            k = path.index(v)
            cycle = path[k:]
            path = path[:k]
            total = sum(wpol[u] for u in cycle)
            g = math.gcd(total, len(cycle))
            W, T = total // g, len(cycle) // g
            root = min(cycle)
            # A circuit that keeps its mean keeps its root's potential: then
            # potentials never decrease between iterations of one mean [1]_.
            X[root] = old.potential[root] if old is not None and old.ratio[root] == (W, T) else 0
            ratio[root] = (W, T)
            back = [root]
            u = pol[root]
            while u != root:
                back.append(u)
                u = pol[u]
            for u in reversed(back[1:]):
                X[u] = X[pol[u]] + wpol[u] * T - W
                ratio[u] = (W, T)
        for u in reversed(path):
            # pol[u] is past u on the path, or on a circuit: its ratio is set (an
            # assert here would cost a check per node of every determination).
            W, T = ratio[pol[u]]  # type: ignore[misc]
            ratio[u] = (W, T)
            X[u] = X[pol[u]] + wpol[u] * T - W
    # Every node reaches a policy circuit, so the loop gave every node its ratio.
    return cast(list[Ratio], ratio), X


class _Arcs:
    """A small matrix as flat in-arc lists, for the Python loops.

    The in-arcs of node i are ``flat_weights[rows[i]]`` (``rows[i]`` a slice);
    one ``itemgetter`` gathers ``X[j]`` for every arc at once, and
    ``map(max, map(values.__getitem__, rows))`` takes every row's maximum, both
    in C: per arc, no Python bytecode runs.
    """

    __slots__ = ("_successors", "flat_weights", "gather", "rows", "sources", "weights")

    def __init__(self, sources: list[list[int]], weights: list[list[int]],
                 flat_weights: list[int], rows: list[slice],
                 gather: Callable[[list[int]], tuple[int, ...]]) -> None:
        self.sources = sources  # predecessors j of each node i
        self.weights = weights  # A[i][j], in the same order
        self.flat_weights = flat_weights
        self.rows = rows
        self.gather = gather
        self._successors: list[list[int]] | None = None

    def successors(self) -> list[list[int]]:
        """Successors of every node (built on first use: only ratio sweeps need them)."""
        if self._successors is None:
            out: list[list[int]] = [[] for _ in self.sources]
            for i, js in enumerate(self.sources):
                for j in js:
                    out[j].append(i)
            self._successors = out
        return self._successors


def _arcs(rows: list[list[int | None]]) -> _Arcs:
    sources: list[list[int]] = []
    weights: list[list[int]] = []
    bounds: list[slice] = []
    flat_sources: list[int] = []
    columns = range(len(rows))
    for row in rows:
        js = [j for j, w in zip(columns, row) if w is not None]
        sources.append(js)
        weights.append([w for w in row if w is not None])
        bounds.append(slice(len(flat_sources), len(flat_sources) + len(js)))
        flat_sources += js
    flat_weights = [w for ws in weights for w in ws]
    gather = itemgetter(*flat_sources) if len(flat_sources) > 1 else \
        (lambda X, j=flat_sources[0]: (X[j],))
    return _Arcs(sources, weights, flat_weights, bounds, gather)


def _improve_lists(arcs: _Arcs, state: Policy, times_T: dict[int, list[int]]
                   ) -> list[int] | None:
    """One policy improvement on in-arc lists; None when the policy is optimal.

    ``times_T`` caches the weights multiplied by a mean's denominator T.
    """
    ratio, X, pol = state
    new: list[int] | None = None
    distinct = set(ratio)
    if len(distinct) > 1:
        new = _sweep_lists(arcs.successors(), ratio, pol, distinct)
        if new is not None:
            return new
        for i, (js, ws) in enumerate(zip(arcs.sources, arcs.weights)):
            r = ratio[i]
            W, T = r
            values = [X[j] + w * T if ratio[j] == r else X[i] + W for j, w in zip(js, ws)]
            top = max(values)
            if top - W > X[i]:
                if new is None:
                    new = list(pol)
                new[i] = js[values.index(top)]
        return new
    # One mean everywhere (the usual case after the first iteration): every
    # predecessor has the same mean, so only potentials compare.
    W, T = ratio[0]
    weights_T = times_T.get(T)
    if weights_T is None:
        weights_T = times_T[T] = [w * T for w in arcs.flat_weights]
    values = list(map(add, arcs.gather(X), weights_T))
    tops = list(map(max, map(values.__getitem__, arcs.rows)))
    for i in [i for i, (top, x) in enumerate(zip(tops, X)) if top - W > x]:
        if new is None:
            new = list(pol)
        new[i] = arcs.sources[i][values[arcs.rows[i]].index(tops[i])]
    return new


def sorted_ratios(ratios: set[Ratio]) -> list[Ratio]:
    """Distinct reduced fractions (W, T), T > 0, in increasing order, exactly.

    Floats sort; cross-multiplication then checks every adjacent pair (and
    Fractions redo the order if floats could not separate two of them).

    >>> sorted_ratios({(7, 2), (10**400, 1), (-1, 3)})[:2]
    [(-1, 3), (7, 2)]
    """
    try:
        order = sorted(ratios, key=lambda r: r[0] / r[1])
    except OverflowError:  # a ratio beyond float range
        return sorted(ratios, key=lambda r: Fraction(*r))
    if all(a[0] * b[1] < b[0] * a[1] for a, b in pairwise(order)):
        return order
    return sorted(ratios, key=lambda r: Fraction(*r))


def _sweep_lists(succs: list[list[int]], ratio: list[Ratio], pol: list[int],
                 distinct: set[Ratio]) -> list[int] | None:
    """Ratio improvement, passed downstream at once (None when no ratio improves).

    The largest mean goes first, breadth first: a node whose predecessor holds
    a strictly larger mean switches to it and takes that mean, so one
    iteration carries a mean as far as it reaches instead of one arc (each
    switch is a strict gain, so no new policy circuit forms) [1]_.
    """
    order = sorted_ratios(distinct)[::-1]
    level_of = {r: k for k, r in enumerate(order)}  # 0 = the largest mean
    level = [level_of[r] for r in ratio]
    new: list[int] | None = None
    by_level: list[list[int]] = [[] for _ in order]
    for v, k in enumerate(level):
        by_level[k].append(v)
    for top, members in enumerate(by_level):
        frontier = [v for v in members if level[v] == top]
        while frontier:
            reached = []
            for u in frontier:
                for v in succs[u]:
                    if level[v] > top:
                        level[v] = top
                        if new is None:
                            new = list(pol)
                        new[v] = u
                        reached.append(v)
            frontier = reached
    return new


def _improve_arrays(values: np.ndarray, finite: np.ndarray, state: Policy) -> list[int] | None:
    ratio, X, pol = state
    n = len(pol)
    distinct = sorted_ratios(set(ratio))
    pol_a = np.array(pol)
    if len(distinct) > 1:
        rank_of = {r: k for k, r in enumerate(distinct)}
        rank = np.array([rank_of[r] for r in ratio])
        ranks = np.where(finite, rank[None, :], -1)
        up = ranks.max(axis=1) > rank
        if up.any():
            pol_a[up] = ranks.argmax(axis=1)[up]
            improved: list[int] = pol_a.tolist()
            return improved
        same = finite & (rank[None, :] == rank[:, None])
    else:
        same = finite
    W = [r[0] for r in ratio]
    T = [r[1] for r in ratio]
    big = (max(map(abs, X)) + max(map(abs, W)) + max(T) * _abs_max(values))
    if big < INT64_SAFE and values.dtype != object:
        Xa, Wa, Ta = (np.array(a, dtype=np.int64) for a in (X, W, T))
        low: int | float = np.iinfo(np.int64).min
    else:
        Xa, Wa, Ta = (_objects(a) for a in (X, W, T))
        low = -math.inf  # only compared, never added
    value = np.where(same, Xa[None, :] + values * Ta[:, None] - Wa[:, None], low)
    best = value.argmax(axis=1)
    gain = value[np.arange(n), best] > Xa
    if not gain.any():
        return None
    pol_a[gain] = best[gain]
    improved = pol_a.tolist()
    return improved


def _objects(values: list[int]) -> np.ndarray:
    out = np.empty(len(values), dtype=object)
    out[:] = values
    return out


def _abs_max(a: np.ndarray) -> int:
    return max(abs(int(a.max())), abs(int(a.min()))) if a.size else 0


def optimal_policy(values: np.ndarray | None, finite: np.ndarray | None,
                   rows: list[list[int | None]] | None) -> Policy:
    """Optimal policy of a matrix whose every node has an in-arc (as lists or as arrays)."""
    if rows is not None:
        n = len(rows)
        arcs = _arcs(rows)
        times_T: dict[int, list[int]] = {}
        # First policy: the best two-arc walk into each node, i.e. the best
        # in-arc after one step of x(k+1) = A x(k) from x = 0 (saves about one
        # iteration over the plain heaviest in-arc).
        heaviest = [max(ws) for ws in arcs.weights]
        two_arcs = list(map(add, arcs.gather(heaviest), arcs.flat_weights))
        pol = [js[row.index(max(row))] for js, row in
               zip(arcs.sources, map(two_arcs.__getitem__, arcs.rows))]
    else:
        assert values is not None and finite is not None
        matrix, mask = values, finite
        n = len(mask)
        low = -math.inf if matrix.dtype == object else np.iinfo(np.int64).min
        pol = np.where(mask, matrix, low).argmax(axis=1).tolist()
        nodes = np.arange(n)
    state: Policy | None = None
    # Howard terminates (each iteration strictly improves); the bound only
    # turns a defect into an error instead of a hang.
    for _ in range(100 * (n + 1) ** 2):
        if rows is not None:
            # A policy arc is an arc: its entry is finite, never None.
            wpol = cast(list[int], [row[j] for row, j in zip(rows, pol)])
        else:
            wpol = matrix[nodes, pol].tolist()
        ratio, X = _value_determination(pol, wpol, state)
        state = Policy(ratio, X, pol)
        if rows is not None:
            new = _improve_lists(arcs, state, times_T)
        else:
            new = _improve_arrays(matrix, mask, state)
        if new is None:
            return state
        pol = new
    raise MaxPlusError("Howard's policy iteration did not converge (a defect: please report)")


def policy_walk(pol: list[int], start: int) -> list[int]:
    """Nodes of the policy circuit reached backwards from ``start``, in forward order."""
    seen: set[int] = set()
    v = start
    while v not in seen:
        seen.add(v)
        v = pol[v]
    back = [v]
    u = pol[v]
    while u != v:
        back.append(u)
        u = pol[u]
    return back[::-1]
