"""Maximum cycle mean of a dense integer matrix, by Howard's policy iteration, certified.

The dense counterpart of :func:`maxplus.cycle_ratio.max_cycle_ratio` for
matrices (every arc carries one token). A *policy* picks one in-arc per node
(``policy[i] = j``: the arc ``j -> i``); following it backwards from any node
ends on a policy circuit. *Value determination* gives every node the mean
``W/T`` of the circuit it reaches (a reduced fraction of scaled integers) and
a potential ``X`` (bias times T) that is tight along the policy; *policy
improvement* switches a node to an in-arc from a node of larger mean, or,
failing that, to one of the same mean and larger potential. A circuit that
survives an iteration keeps its root's potential, which rules out cycling [1]_.

Everything is an integer: Python ints in value determination (one pass over
the nodes), int64 arrays (or object arrays beyond the int64-safe range) in the
improvement step, a Python double loop below :data:`SMALL` nodes, where numpy's
per-call cost would dominate. No float is used, so no tolerance either.

When the optimal policy has one mean λ on every node (always for an
irreducible matrix), its potentials prove λ (see
:mod:`maxplus._mean_certificate`, checked before λ is returned). Otherwise
the matrix is split into strongly connected classes and each class is solved
on its own (its maximum cycle mean is the eigenvalue of the class [2]_).

References
----------
.. [1] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
   J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
   algebra", IFAC Conference on System Structure and Control, 1998.
.. [2] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
   and Linearity*, Wiley, 1992, Thm 3.23 and Thm 3.112.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from fractions import Fraction
from operator import add, itemgetter
from typing import NamedTuple

import numpy as np

from ._arrays import INT64_SAFE
from ._graphs import strong_classes
from ._integer_matrix import IntegerMatrix, integer_matrix, rows_of
from ._mean_certificate import check_mean_certificate, check_mean_certificate_lists
from .errors import MaxPlusError

__all__ = ["SMALL", "ClassMeans", "class_means", "cycle_times", "max_cycle_mean", "max_cycle_mean_rows"]

SMALL = 16
"""Up to this many nodes the improvement step is a Python loop (faster than numpy there)."""

Ratio = tuple[int, int]


class _Policy(NamedTuple):
    ratio: list[Ratio]  # (W, T) per node, reduced, T > 0
    potential: list[int]
    policy: list[int]


# --------------------------------------------------------------------------- Howard


def _value_determination(pol: list[int], wpol: list[int], old: _Policy | None
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
            # potentials never decrease between iterations of one mean [1].
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
            W, T = ratio[pol[u]]  # type: ignore[misc]
            ratio[u] = (W, T)
            X[u] = X[pol[u]] + wpol[u] * T - W
    return ratio, X  # type: ignore[return-value]


class _Arcs(NamedTuple):
    """A small matrix as flat in-arc lists, for the Python loops.

    The in-arcs of node i are ``flat[bounds[i]:bounds[i + 1]]``; one
    ``itemgetter`` gathers ``X[j]`` for every arc at once, in C.
    """

    sources: list[list[int]]  # predecessors j of each node i
    weights: list[list[int]]  # A[i][j], in the same order
    flat_weights: list[int]
    bounds: list[tuple[int, int]]
    gather: Callable[[list[int]], tuple[int, ...]]


def _arcs(rows: list[list[int | None]]) -> _Arcs:
    sources, weights, bounds, flat_sources = [], [], [], []
    for row in rows:
        js = [j for j, w in enumerate(row) if w is not None]
        sources.append(js)
        weights.append([row[j] for j in js])
        bounds.append((len(flat_sources), len(flat_sources) + len(js)))
        flat_sources += js
    flat_weights = [w for ws in weights for w in ws]
    gather = itemgetter(*flat_sources) if len(flat_sources) > 1 else \
        (lambda X, j=flat_sources[0]: (X[j],))
    return _Arcs(sources, weights, flat_weights, bounds, gather)


def _successors(arcs: _Arcs) -> list[list[int]]:
    out: list[list[int]] = [[] for _ in arcs.sources]
    for i, js in enumerate(arcs.sources):
        for j in js:
            out[j].append(i)
    return out


def _improve_lists(arcs: _Arcs, state: _Policy, times_T: dict[int, list[list[int]]]
                   ) -> list[int] | None:
    """One policy improvement on in-arc lists; None when the policy is optimal.

    ``times_T`` caches the weights multiplied by a mean's denominator T.
    """
    ratio, X, pol = state
    new: list[int] | None = None
    distinct = set(ratio)
    if len(distinct) > 1:
        new = _sweep_lists(_successors(arcs), ratio, pol, distinct)
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
    for i, (start, end) in enumerate(arcs.bounds):
        row = values[start:end]
        top = max(row)
        if top - W > X[i]:
            if new is None:
                new = list(pol)
            new[i] = arcs.sources[i][row.index(top)]
    return new


def _sweep_lists(succs: list[list[int]], ratio: list[Ratio], pol: list[int],
                 distinct: set[Ratio]) -> list[int] | None:
    """Ratio improvement, passed downstream at once (None when no ratio improves).

    The largest mean goes first, breadth first: a node whose predecessor holds
    a strictly larger mean switches to it and takes that mean, so one
    iteration carries a mean as far as it reaches instead of one arc (each
    switch is a strict gain, so no new policy circuit forms) [1]_.
    """
    order = sorted(distinct, key=lambda r: Fraction(*r), reverse=True)
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


def _improve_arrays(values: np.ndarray, finite: np.ndarray, state: _Policy) -> list[int] | None:
    ratio, X, pol = state
    n = len(pol)
    distinct = sorted(set(ratio), key=lambda r: Fraction(*r))
    pol_a = np.array(pol)
    if len(distinct) > 1:
        rank_of = {r: k for k, r in enumerate(distinct)}
        rank = np.array([rank_of[r] for r in ratio])
        ranks = np.where(finite, rank[None, :], -1)
        up = ranks.max(axis=1) > rank
        if up.any():
            pol_a[up] = ranks.argmax(axis=1)[up]
            return pol_a.tolist()
        same = finite & (rank[None, :] == rank[:, None])
    else:
        same = finite
    W = [r[0] for r in ratio]
    T = [r[1] for r in ratio]
    big = (max(map(abs, X)) + max(map(abs, W)) + max(T) * _abs_max(values))
    if big < INT64_SAFE and values.dtype != object:
        Xa, Wa, Ta = (np.array(a, dtype=np.int64) for a in (X, W, T))
        low: object = np.iinfo(np.int64).min
    else:
        Xa, Wa, Ta = (_objects(a) for a in (X, W, T))
        low = -math.inf  # only compared, never added
    value = np.where(same, Xa[None, :] + values * Ta[:, None] - Wa[:, None], low)
    best = value.argmax(axis=1)
    gain = value[np.arange(n), best] > Xa
    if not gain.any():
        return None
    pol_a[gain] = best[gain]
    return pol_a.tolist()


def _objects(values: list[int]) -> np.ndarray:
    out = np.empty(len(values), dtype=object)
    out[:] = values
    return out


def _abs_max(a: np.ndarray) -> int:
    return max(abs(int(a.max())), abs(int(a.min()))) if a.size else 0


def _howard(values: np.ndarray | None, finite: np.ndarray | None,
            rows: list[list[int | None]] | None) -> _Policy:
    """Optimal policy of a matrix whose every node has an in-arc (as lists or as arrays)."""
    if rows is not None:
        n = len(rows)
        arcs = _arcs(rows)
        times_T: dict[int, list[int]] = {}
        # First policy: the best two-arc walk into each node, i.e. the best
        # in-arc after one step of x(k+1) = A x(k) from x = 0 (saves about one
        # iteration over the plain heaviest in-arc).
        heaviest = [max(ws) for ws in arcs.weights]
        values = list(map(add, arcs.gather(heaviest), arcs.flat_weights))
        pol = []
        for js, (start, end) in zip(arcs.sources, arcs.bounds):
            row = values[start:end]
            pol.append(js[row.index(max(row))])
    else:
        assert values is not None and finite is not None
        n = len(finite)
        low = -math.inf if values.dtype == object else np.iinfo(np.int64).min
        pol = np.where(finite, values, low).argmax(axis=1).tolist()
        nodes = np.arange(n)
    state: _Policy | None = None
    # Howard terminates (each iteration strictly improves); the bound only
    # turns a defect into an error instead of a hang.
    for _ in range(100 * (n + 1) ** 2):
        if rows is not None:
            wpol = [row[j] for row, j in zip(rows, pol)]
        else:
            wpol = values[nodes, pol].tolist()
        ratio, X = _value_determination(pol, wpol, state)  # type: ignore[arg-type]
        state = _Policy(ratio, X, pol)
        if rows is not None:
            new = _improve_lists(arcs, state, times_T)
        else:
            new = _improve_arrays(values, finite, state)
        if new is None:
            return state
        pol = new
    raise MaxPlusError("Howard's policy iteration did not converge (a defect: please report)")


def _policy_walk(pol: list[int], start: int) -> list[int]:
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


# --------------------------------------------------------------------------- means


def _single_mean(values: np.ndarray | None, finite: np.ndarray | None,
                 rows: list[list[int | None]] | None) -> Ratio | None:
    """The certified mean when the optimal policy has one mean on every node, else None.

    Give ``rows`` (lists) for a small matrix, ``values`` and ``finite`` otherwise.
    """
    state = _howard(values, finite, rows)
    if len(set(state.ratio)) > 1:
        return None
    p, q = state.ratio[0]
    walk = _policy_walk(state.policy, 0)
    if rows is not None:
        check_mean_certificate_lists(rows, p, q, state.potential, walk)
    else:
        assert values is not None and finite is not None
        x = _objects(state.potential)
        if values.dtype != object and max(map(abs, state.potential)) < INT64_SAFE:
            x = x.astype(np.int64)
        check_mean_certificate(values, finite, p, q, x, walk)
    return p, q


def _solve(values: np.ndarray, finite: np.ndarray) -> Ratio | None:
    if len(finite) <= SMALL:
        return _single_mean(None, None, rows_of(IntegerMatrix(values, finite, 1)))
    return _single_mean(values, finite, None)


class ClassMeans(NamedTuple):
    """Strongly connected classes and the maximum cycle mean of each (scaled)."""

    labels: np.ndarray  # class of every node
    means: list[Ratio | None]  # per class; None for a class without circuit


def class_means(matrix: IntegerMatrix) -> ClassMeans:
    """The maximum cycle mean of every strongly connected class, each certified.

    Examples
    --------
    >>> from maxplus._integer_matrix import integer_matrix
    >>> cm = class_means(integer_matrix([[3, None], [2, 4]]))
    >>> cm.labels.tolist() == [0, 1] or cm.labels.tolist() == [1, 0], sorted(cm.means)
    (True, [(3, 1), (4, 1)])
    """
    values, finite = matrix.values, matrix.finite
    n_classes, labels = strong_classes(finite)
    means: list[Ratio | None] = []
    for c in range(n_classes):
        nodes = np.flatnonzero(labels == c)
        if len(nodes) == 1 and not finite[nodes[0], nodes[0]]:
            means.append(None)
            continue
        sub = np.ix_(nodes, nodes)
        mean = _solve(values[sub], finite[sub])
        if mean is None:  # an irreducible matrix has one mean everywhere
            raise MaxPlusError("a strongly connected class has two cycle means (a defect)")
        means.append(mean)
    return ClassMeans(labels, means)


def max_cycle_mean(matrix: IntegerMatrix) -> Fraction | None:
    """Maximum cycle mean of the matrix (None without circuit), certified exactly.

    Parameters
    ----------
    matrix : IntegerMatrix

    Returns
    -------
    Fraction or None

    Raises
    ------
    CertificateError
        The potentials do not prove the mean (a defect of the solver).

    Examples
    --------
    >>> from maxplus._integer_matrix import integer_matrix
    >>> max_cycle_mean(integer_matrix([[1, 5], [3, 2]]))  # circuit 0 -> 1 -> 0: (5+3)/2
    Fraction(4, 1)
    """
    values, finite = matrix.values, matrix.finite
    if finite.any(axis=1).all():  # every node has an in-arc: Howard on the whole matrix
        mean = _solve(values, finite)
        if mean is not None:
            return Fraction(mean[0], mean[1] * matrix.scale)
    return _best_class_mean(matrix)


def max_cycle_mean_rows(rows: list[list[int | None]]) -> Fraction | None:
    """:func:`max_cycle_mean` of a small matrix given as lists of ints and None.

    Examples
    --------
    >>> max_cycle_mean_rows([[1, 5], [3, 2]])
    Fraction(4, 1)
    """
    n = len(rows)
    if n <= 2:  # every elementary circuit, enumerated: the maximum of their means
        means = [Fraction(rows[i][i]) for i in range(n) if rows[i][i] is not None]
        if n == 2 and rows[0][1] is not None and rows[1][0] is not None:
            means.append(Fraction(rows[0][1] + rows[1][0], 2))
        return max(means, default=None)
    if all(row.count(None) < n for row in rows):  # every node has an in-arc
        mean = _single_mean(None, None, rows)
        if mean is not None:
            return Fraction(mean[0], mean[1])
    return _best_class_mean(integer_matrix(rows))


def _best_class_mean(matrix: IntegerMatrix) -> Fraction | None:
    best = max((Fraction(*m) for m in class_means(matrix).means if m is not None), default=None)
    return None if best is None else best / matrix.scale


def cycle_times(matrix: IntegerMatrix) -> list[Fraction | None]:
    """Cycle time ``χ_i`` of every node: the largest maximum cycle mean among the
    strongly connected classes from which i can be reached (None without any) [2]_.

    Each class mean is certified; the maximum is then passed down the acyclic
    graph of the classes in topological order.

    Examples
    --------
    >>> from maxplus._integer_matrix import integer_matrix
    >>> cycle_times(integer_matrix([[3, None, None], [2, 4, None], [None, 0, None]]))
    [Fraction(3, 1), Fraction(4, 1), Fraction(4, 1)]
    """
    labels, means = class_means(matrix)
    best = [None if m is None else Fraction(m[0], m[1] * matrix.scale) for m in means]
    if len(means) > 1:
        rows, cols = np.nonzero(matrix.finite)
        tail, head = labels[cols], labels[rows]  # class arcs tail -> head
        across = tail != head
        pairs = np.unique(np.stack([tail[across], head[across]], axis=1), axis=0).tolist()
        successors: list[list[int]] = [[] for _ in means]
        waiting = [0] * len(means)
        for a, b in pairs:
            successors[a].append(b)
            waiting[b] += 1
        ready = [c for c in range(len(means)) if waiting[c] == 0]
        while ready:  # Kahn's topological order of the classes
            c = ready.pop()
            for d in successors[c]:
                if best[c] is not None and (best[d] is None or best[c] > best[d]):
                    best[d] = best[c]
                waiting[d] -= 1
                if waiting[d] == 0:
                    ready.append(d)
    return [best[c] for c in labels.tolist()]
